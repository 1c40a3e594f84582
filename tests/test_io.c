/* test_io.c -- io/: the OpenEXR writer read back through OpenEXRCore (exr_start_read), the PNG
 * preview read back through libpng, the scene files of scenes/ (fig8.json is the built-in
 * scene), and the JSON line locator behind the loader's error messages. */
#include <jansson.h>
#include <math.h>
#include <openexr.h>
#include <png.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../io/src/json_locate.h"
#include "cmocka_main.h"
#include "core/builtin.h"
#include "io/image_io.h"
#include "io/output.h"
#include "io/scene_json.h"
#include "render/render.h"

#ifndef PENCIL_SOURCE_DIR
#error "PENCIL_SOURCE_DIR must name the source tree (tests/CMakeLists.txt)"
#endif

/* A unique path in the temporary directory with the given suffix. */
static void temp_path(char *out, size_t cap, const char *suffix) {
  snprintf(out, cap, "%s/pencil_test_io_%ld_%s", P_tmpdir, (long)getpid(), suffix);
}

static void fill(rt_image_t *img) {
  for (int c = 0; c < RT_CH_COUNT; c++)
    for (int k = 0; k < img->width * img->height; k++)
      img->ch[c][k] = (float)(c * 1000 + k) * 0.37f - 50.0f;
  img->ch[RT_CH_Z][3] = INFINITY;
  img->ch[RT_CH_T_U][5] = NAN;
  img->ch[RT_CH_R][0] = -0.0f;
}

/* Float channels with ZIP compression are lossless: every value comes back bit for bit. The
 * file is also opened directly with OpenEXRCore to check its channel list and size. */
static void exr_round_trip(void **state) {
  (void)state;
  char path[512], err[512];
  temp_path(path, sizeof path, "rt.exr");
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, 7, 19), RT_OK); /* 19 rows: a partial ZIP chunk */
  fill(&img);
  const io_attr_t meta[] = {{"pencil:test", "yes"}};
  float extra[7 * 19];
  for (int k = 0; k < 7 * 19; k++)
    extra[k] = 0.5f * (float)k;
  const io_exr_channel_t ch[] = {{"extra.k", extra}};
  assert_int_equal(io_exr_write(path, &img, ch, 1, meta, 1, err, sizeof err), 0);
  exr_context_t ctx = NULL;
  assert_int_equal(exr_start_read(&ctx, path, NULL), EXR_ERR_SUCCESS);
  const exr_attr_chlist_t *chl;
  assert_int_equal(exr_get_channels(ctx, 0, &chl), EXR_ERR_SUCCESS);
  assert_int_equal(chl->num_channels, RT_CH_COUNT + 1);
  for (int c = 0; c < chl->num_channels; c++)
    assert_int_equal(chl->entries[c].pixel_type, EXR_PIXEL_FLOAT);
  const char *val = NULL;
  assert_int_equal(exr_attr_get_string(ctx, 0, "pencil:test", NULL, &val), EXR_ERR_SUCCESS);
  assert_string_equal(val, "yes");
  exr_finish(&ctx);
  float back[7 * 19];
  for (int c = 0; c < RT_CH_COUNT; c++) {
    int w = 0, h = 0;
    assert_int_equal(
        io_exr_read_channel(path, rt_channel_name((rt_channel_t)c), back, &w, &h, err, sizeof err),
        0);
    assert_int_equal(w, 7);
    assert_int_equal(h, 19);
    assert_memory_equal(back, img.ch[c], sizeof back);
  }
  int w, h;
  assert_int_equal(io_exr_read_channel(path, "extra.k", back, &w, &h, err, sizeof err), 0);
  assert_memory_equal(back, extra, sizeof back);
  char version[64];
  assert_int_equal(
      io_exr_read_attr(path, "pencil:version", version, sizeof version, err, sizeof err), 0);
  assert_int_equal(
      io_exr_read_attr(path, "pencil:command_line", version, sizeof version, err, sizeof err), 0);
  assert_int_equal(io_exr_read_channel(path, "nope", back, &w, &h, err, sizeof err), -1);
  assert_non_null(strstr(err, "no channel 'nope'"));
  remove(path);
  rt_image_free(&img);
}

/* Debian 12's OpenEXRCore stores a ZIP chunk whose zlib output is exactly as long as its input
 * as if it were uncompressed, and it reads back as garbage (upstream issue 2306). The 16 rows of
 * 128 floats in tests/data/zip_equal_chunk.f32 are such a chunk (from an illuminance map, the
 * first time it happened); the writer reads every file back and writes it again uncompressed
 * when it does not read back bit for bit. */
static void exr_zip_equal_size_chunk_reads_back(void **state) {
  (void)state;
  char src[600], path[512], jpath[512], err[512];
  snprintf(src, sizeof src, "%s/tests/data/zip_equal_chunk.f32", PENCIL_SOURCE_DIR);
  static float v[128 * 16], back[128 * 16];
  FILE *f = fopen(src, "rb");
  assert_non_null(f);
  assert_int_equal(fread(v, sizeof v[0], 128 * 16, f), 128 * 16);
  fclose(f);
  temp_path(path, sizeof path, "zip.exr");
  temp_path(jpath, sizeof jpath, "zip.json");
  const io_exr_channel_t ch = {"E", v};
  json_t *summary = json_object();
  assert_int_equal(
      io_map_write(path, 128, 16, &ch, 1, NULL, NULL, 0, jpath, summary, err, sizeof err), 0);
  json_decref(summary);
  int w = 0, h = 0;
  assert_int_equal(io_exr_read_channel(path, "E", back, &w, &h, err, sizeof err), 0);
  assert_int_equal(w * h, 128 * 16);
  assert_memory_equal(back, v, sizeof v);
  remove(path);
  remove(jpath);
}

static void exr_unwritable_path_reports_error(void **state) {
  (void)state;
  char err[512];
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, 2, 2), RT_OK);
  assert_int_equal(io_exr_write("/nonexistent-dir/x.exr", &img, NULL, 0, NULL, 0, err, sizeof err),
                   -1);
  assert_non_null(strstr(err, "/nonexistent-dir/x.exr"));
  rt_image_free(&img);
}

/* A write that fails while the header is written (the file size limit standing in for a full
 * disk) is reported, not hung: the library's error handler once asked the context for its user
 * data under the lock the library held, and waited for itself. In a child process, so that a
 * hang is an alarm and the limit stays there. */
static void exr_header_write_error_reported(void **state) {
  (void)state;
  char path[512];
  temp_path(path, sizeof path, ".exr");
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    signal(SIGXFSZ, SIG_IGN); /* the write fails with EFBIG instead */
    alarm(20);
    struct rlimit lim = {64, 64};
    if (setrlimit(RLIMIT_FSIZE, &lim) != 0)
      _exit(3);
    rt_image_t img;
    char err[512] = "";
    if (rt_image_alloc(&img, 4, 4) != RT_OK)
      _exit(3);
    int rc = io_exr_write(path, &img, NULL, 0, NULL, 0, err, sizeof err);
    _exit(rc == -1 && strstr(err, path) ? 0 : 1);
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  if (WIFSIGNALED(status))
    print_message("the writer was ended by signal %d (SIGALRM %d: it hung)\n", WTERMSIG(status),
                  SIGALRM);
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 0);
  remove(path);
}

/* PNG: clamped, sRGB-encoded 8-bit values (0 -> 0, 1 and above -> 255, 0.5 -> 188, 0.2 -> 124
 * by IEC 61966-2-1), read back with libpng. */
static void png_preview_is_srgb(void **state) {
  (void)state;
  char path[512], err[512];
  temp_path(path, sizeof path, "p.png");
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, 2, 1), RT_OK);
  const float v[2][3] = {{0.0f, 0.5f, 1.0f}, {7.0f, -1.0f, 0.2f}};
  for (int k = 0; k < 2; k++)
    for (int c = 0; c < 3; c++)
      img.ch[RT_CH_R + c][k] = v[k][c];
  assert_int_equal(io_png_write(path, &img, err, sizeof err), 0);
  png_image pi;
  memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  assert_true(png_image_begin_read_from_file(&pi, path));
  pi.format = PNG_FORMAT_RGB;
  unsigned char px[6];
  assert_int_equal(PNG_IMAGE_SIZE(pi), 6);
  assert_true(png_image_finish_read(&pi, NULL, px, 0, NULL));
  const unsigned char want[6] = {0, 188, 255, 255, 0, 124};
  assert_memory_equal(px, want, 6);
  remove(path);
  rt_image_free(&img);
  char p2[64];
  assert_true(io_png_path_for("out/a.exr", p2, sizeof p2));
  assert_string_equal(p2, "out/a.png");
  assert_true(io_png_path_for("b", p2, sizeof p2));
  assert_string_equal(p2, "b.png");
}

/* The PNG preview records the provenance the EXR header and JSON record: Software and
 * pencil:version, commit, date as tEXt, the command line (any UTF-8) as iTXt, read back with
 * libpng. */
static void png_preview_records_provenance(void **state) {
  (void)state;
  char path[512], err[512];
  temp_path(path, sizeof path, "prov.png");
  char *argv[] = {"pencil", "render", "-o", "sc\xc3\xa8ne 'x'.exr", NULL};
  io_provenance_set("9.8.7", "abc1234", 4, argv);
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, 3, 2), RT_OK);
  assert_int_equal(io_png_write(path, &img, err, sizeof err), 0);
  rt_image_free(&img);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
  png_infop info = png_create_info_struct(png);
  assert_non_null(info);
  png_init_io(png, f);
  png_read_png(png, info, PNG_TRANSFORM_IDENTITY, NULL);
  png_textp text = NULL;
  int n = png_get_text(png, info, &text, NULL);
  const char *const want[][2] = {
      {"Software", "pencil 9.8.7 (abc1234)"},
      {"pencil:version", "9.8.7"},
      {"pencil:commit", "abc1234"},
      {"pencil:date", io_provenance()->date},
      {"pencil:command_line", "pencil render -o 'sc\xc3\xa8ne '\\''x'\\''.exr'"}};
  for (int k = 0; k < 5; k++) {
    int found = 0;
    for (int j = 0; j < n; j++)
      if (strcmp(text[j].key, want[k][0]) == 0) {
        assert_string_equal(text[j].text, want[k][1]);
        found = 1;
      }
    assert_true(found);
  }
  png_destroy_read_struct(&png, &info, NULL);
  fclose(f);
  remove(path);
}

/* A UTF-8 byte order mark at the start of a scene is skipped, from a file and from memory, and a
 * later error keeps the file's line numbers. */
static void scene_bom_skipped(void **state) {
  (void)state;
  char path[512], err[512];
  temp_path(path, sizeof path, "bom.json");
  const char *json =
      "\xEF\xBB\xBF{\"camera\": {\"eye\": [0, 0, -5], \"look_at\": [0, 0, 0]},\n"
      " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1,\n"
      "               \"material\": \"m\"}],\n \"materials\": {\"m\": {\"kd\": 0.5}}}\n";
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs(json, f);
  fclose(f);
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(io_scene_load(path, &s, err, sizeof err), 0);
  assert_int_equal(s.nobject, 1);
  rt_scene_free(&s);
  assert_int_equal(io_scene_load_buffer("m.json", json, strlen(json), &s, err, sizeof err), 0);
  rt_scene_free(&s);
  const char *bad = "\xEF\xBB\xBF{\n \"camera\": 3}\n";
  assert_int_equal(io_scene_load_buffer("b.json", bad, strlen(bad), &s, err, sizeof err), -1);
  assert_non_null(strstr(err, "b.json:2: camera: expected an object"));
  remove(path);
}

/* The scene files load, from their path and from memory alike (io_scene_load_buffer: the same
 * objects, primitives, vertices, materials, lights and settings). */
static void scene_files_load(void **state) {
  (void)state;
  const char *names[] = {"fig8", "fig11", "balls", "mesh1000"};
  for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
    char path[1024], err[1024];
    snprintf(path, sizeof path, "%s/scenes/%s.json", PENCIL_SOURCE_DIR, names[k]);
    rt_scene_t s, m;
    rt_scene_init(&s);
    rt_scene_init(&m);
    if (io_scene_load(path, &s, err, sizeof err) != 0)
      fail_msg("%s", err);
    assert_non_null(s.bvh);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char data[1 << 20];
    size_t len = fread(data, 1, sizeof data, f);
    fclose(f);
    assert_true(len > 0 && len < sizeof data);
    if (io_scene_load_buffer(path, data, len, &m, err, sizeof err) != 0)
      fail_msg("%s", err);
    assert_int_equal(m.nobject, s.nobject);
    assert_int_equal(m.nprim, s.nprim);
    assert_int_equal(m.nvertex, s.nvertex);
    assert_int_equal(m.nmaterial, s.nmaterial);
    assert_int_equal(m.nlight, s.nlight);
    assert_memory_equal(&m.camera, &s.camera, sizeof s.camera);
    assert_int_equal(m.max_depth, s.max_depth);
    assert_int_equal(m.spp, s.spp);
    rt_scene_free(&s);
    rt_scene_free(&m);
  }
}

/* scenes/fig8.json and the built-in scene are the same scene: equal tiny renders. */
static void fig8_file_equals_builtin(void **state) {
  (void)state;
  char path[1024], err[1024];
  snprintf(path, sizeof path, "%s/scenes/fig8.json", PENCIL_SOURCE_DIR);
  rt_scene_t a, b;
  rt_scene_init(&a);
  rt_scene_init(&b);
  assert_int_equal(io_scene_load(path, &a, err, sizeof err), 0);
  assert_int_equal(rt_builtin_fig8(&b), RT_OK);
  assert_int_equal(a.spp, b.spp);
  assert_int_equal(a.max_depth, b.max_depth);
  assert_int_equal(a.caustics, RT_CAUSTICS_OFF); /* the paper's Whitted image keeps its shadow */
  assert_int_equal(b.caustics, RT_CAUSTICS_OFF);
  rt_image_t ia, ib;
  xr_options_t opt = XR_OPTIONS_DEFAULT;
  a.camera.width = b.camera.width = 12;
  a.camera.height = b.camera.height = 10;
  rt_plan_t pa = rt_plan_make(&a, 1), pb = rt_plan_make(&b, 1);
  assert_int_equal(pa.on, pb.on);
  assert_int_equal(rt_image_alloc(&ia, 12, 10), RT_OK);
  assert_int_equal(rt_image_alloc(&ib, 12, 10), RT_OK);
  assert_int_equal(xr_render(&a, &pa, &opt, &ia, NULL), RT_OK);
  assert_int_equal(xr_render(&b, &pb, &opt, &ib, NULL), RT_OK);
  for (int c = 0; c < RT_CH_COUNT; c++)
    assert_memory_equal(ia.ch[c], ib.ch[c], sizeof(float) * 120);
  rt_image_free(&ia);
  rt_image_free(&ib);
  rt_scene_free(&a);
  rt_scene_free(&b);
}

static void json_locator_finds_lines(void **state) {
  (void)state;
  const char *t = "{\n \"a\": [1,\n  {\"b\": \"x,]}\"},\n  {\"c\":\n   3}],\n \"d\": {}\n}\n";
  io_json_step_t p1[] = {{"a", 0}, {NULL, 2}, {"c", 0}};
  io_json_step_t p2[] = {{"d", 0}, {"missing", 0}};
  io_json_step_t p3[] = {{"a", 0}, {NULL, 1}, {"b", 0}};
  assert_int_equal(io_json_locate(t, strlen(t), p1, 3), 5);
  assert_int_equal(io_json_locate(t, strlen(t), p2, 2), 6); /* the enclosing object */
  assert_int_equal(io_json_locate(t, strlen(t), p3, 3), 3);
  assert_int_equal(io_json_locate(t, strlen(t), p1, 0), 1);
}

/* A point light's "falloff": absent or "none" is the textbook's model, "inverse-square" the
 * physical one (the refusals are in scenes_bad/). */
static void light_falloff_key(void **state) {
  (void)state;
  static const char json[] =
      "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
      " \"lights\": [{\"type\": \"point\", \"position\": [0, 5, 0]},"
      "  {\"type\": \"point\", \"position\": [0, 5, 0], \"falloff\": \"none\"},"
      "  {\"type\": \"point\", \"position\": [0, 5, 0], \"falloff\": \"inverse-square\"},"
      "  {\"type\": \"parallel\", \"direction\": [0, -1, 0]}],"
      " \"objects\": []}";
  rt_scene_t s;
  char err[512];
  rt_scene_init(&s);
  assert_int_equal(io_scene_load_buffer("f.json", json, strlen(json), &s, err, sizeof err), 0);
  assert_int_equal(s.nlight, 4);
  assert_int_equal(s.light[0].falloff, RT_FALLOFF_NONE);
  assert_int_equal(s.light[1].falloff, RT_FALLOFF_NONE);
  assert_int_equal(s.light[2].falloff, RT_FALLOFF_INVERSE_SQUARE);
  assert_int_equal(s.light[3].falloff, RT_FALLOFF_NONE);
  rt_scene_free(&s);
}

static void missing_scene_file_named(void **state) {
  (void)state;
  char err[512];
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(io_scene_load("/nonexistent/scene.json", &s, err, sizeof err), -1);
  assert_non_null(strstr(err, "/nonexistent/scene.json"));
  assert_int_equal(s.nobject, 0);
}

/* A scene path that is no regular file: a directory and a named pipe are refused by name, at
 * once (the pipe was once opened and waited on for ever: the alarm makes that a failure). */
static void scene_path_not_a_regular_file(void **state) {
  (void)state;
  char dir[512], fifo[600], err[512];
  temp_path(dir, sizeof dir, ".d");
  assert_int_equal(mkdir(dir, 0700), 0);
  snprintf(fifo, sizeof fifo, "%s/scene.json", dir);
  assert_int_equal(mkfifo(fifo, 0600), 0);
  rt_scene_t s;
  rt_scene_init(&s);
  alarm(20);
  assert_int_equal(io_scene_load(dir, &s, err, sizeof err), -1);
  assert_non_null(strstr(err, "not a regular file (a directory)"));
  assert_int_equal(io_scene_load(fifo, &s, err, sizeof err), -1);
  assert_non_null(strstr(err, fifo));
  assert_non_null(strstr(err, "not a regular file"));
  alarm(0);
  remove(fifo);
  rmdir(dir);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(exr_round_trip),
      cmocka_unit_test(exr_zip_equal_size_chunk_reads_back),
      cmocka_unit_test(light_falloff_key),
      cmocka_unit_test(exr_unwritable_path_reports_error),
      cmocka_unit_test(exr_header_write_error_reported),
      cmocka_unit_test(scene_path_not_a_regular_file),
      cmocka_unit_test(png_preview_is_srgb),
      cmocka_unit_test(png_preview_records_provenance),
      cmocka_unit_test(scene_bom_skipped),
      cmocka_unit_test(scene_files_load),
      cmocka_unit_test(fig8_file_equals_builtin),
      cmocka_unit_test(json_locator_finds_lines),
      cmocka_unit_test(missing_scene_file_named),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
