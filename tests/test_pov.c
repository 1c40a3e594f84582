/* test_pov.c -- io/pov.h, the POV-Ray 3.7 export (issue 26's peer): the camera written as the
 * exact renderer's pixel-centre rays, the depth and materials as docs/pencil.md maps them, and
 * refusals that name what cannot be mapped; and validation/povray.h's reading of POV-Ray's
 * statistics. Whether POV-Ray renders the file as we do is tests/cli_export_pov.sh's business
 * (it needs POV-Ray). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/builtin.h"
#include "core/camera.h"
#include "io/pov.h"
#include "validation/povray.h"

/* The file io_pov_write() makes of s, in a malloc'ed string; NULL (with err) when refused. */
static char *export_text(const rt_scene_t *s, int flat, char *notes, size_t ncap, char *err,
                         size_t cap) {
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  assert_non_null(f);
  io_pov_options_t o = IO_POV_OPTIONS_DEFAULT;
  o.flat = flat;
  int rc = io_pov_write(f, s, &o, notes, ncap, err, cap);
  fclose(f);
  if (rc != 0) {
    free(buf);
    return NULL;
  }
  return buf;
}

/* The vector after `key ` in text, parsed as <x, y, z>. */
static px_vec3_t vector_after(const char *text, const char *key) {
  const char *p = strstr(text, key);
  px_vec3_t v = {NAN, NAN, NAN};
  assert_non_null(p);
  assert_int_equal(sscanf(p + strlen(key), " <%lf, %lf, %lf>", &v.x, &v.y, &v.z), 3);
  return v;
}

/* POV-Ray's ray for pixel (i, j) of a W x H image is direction + x0 right + y0 up with
 * x0 = (i + 1/2) / W - 1/2, y0 = 1/2 - (j + 1/2) / H; it must point where rt_view_ray() does,
 * to rounding (17 digits written, a few operations: 1e-14). */
static void camera_rays_are_ours(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  s.camera.width = 40; /* not square: the aspect ratio is in right */
  s.camera.height = 30;
  char err[512];
  char *t = export_text(&s, 0, NULL, 0, err, sizeof err);
  assert_non_null(t);
  px_vec3_t dir = vector_after(t, "direction"), right = vector_after(t, "\n  right");
  px_vec3_t up = vector_after(t, "\n  up"), loc = vector_after(t, "location");
  rt_view_t v;
  assert_int_equal(rt_view_make(&s.camera, &v), RT_OK);
  int px[4][2] = {{0, 0}, {39, 0}, {0, 29}, {17, 11}};
  for (int k = 0; k < 4; k++) {
    int i = px[k][0], j = px[k][1];
    double x0 = (i + 0.5) / 40.0 - 0.5, y0 = 0.5 - (j + 0.5) / 30.0;
    px_vec3_t d =
        px_v3_unit(px_v3_add(dir, px_v3_add(px_v3_scale(right, x0), px_v3_scale(up, y0))));
    rt_ray_t r = rt_view_ray(&v, i + 0.5, j + 0.5, 1.0);
    assert_close(d.x, r.d.x, 0, 1e-14);
    assert_close(d.y, r.d.y, 0, 1e-14);
    assert_close(d.z, r.d.z, 0, 1e-14);
  }
  assert_close(loc.y, s.camera.eye.y, 0, 0);
  assert_non_null(strstr(t, "#version 3.7;"));
  assert_non_null(strstr(t, "assumed_gamma 1.0"));
  free(t);
  rt_scene_free(&s);
}

/* The depth (primary ray = level 1), the glass (transmit, interior, Phong, mirror) and the
 * board's checker with its two materials; the notes name the shadow difference. */
static void depth_and_materials_are_mapped(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  char err[512], notes[1024];
  char *t = export_text(&s, 0, notes, sizeof notes, err, sizeof err);
  assert_non_null(t);
  assert_non_null(strstr(t, "max_trace_level 7"));
  assert_non_null(strstr(t, "adc_bailout 0"));
  assert_non_null(strstr(t, "rgbt <1, 1, 1, 0.75>"));
  assert_non_null(strstr(t, "interior { ior 1.5 }"));
  assert_non_null(strstr(t, "phong 0.59999999999999998 phong_size 80"));
  assert_non_null(strstr(t, "reflection { 0.14999999999999999 }"));
  assert_non_null(strstr(t, "texture { checker"));
  assert_non_null(strstr(t, "light_source { <-5, 6, -2.5>, rgb <1, 1, 1> }"));
  assert_non_null(strstr(notes, "shadows through a transparent closed object"));
  assert_non_null(strstr(t, "// note: shadows through"));
  free(t);
  /* a transparent material that is lit too: POV-Ray scales ka and kd by 1 - kt */
  s.material[2].kd = 0.3;
  s.material[2].kt = 0.5;
  t = export_text(&s, 0, NULL, 0, err, sizeof err);
  assert_non_null(t);
  assert_non_null(strstr(t, "diffuse 0.59999999999999998"));
  free(t);
  rt_scene_free(&s);
}

/* Names go into // comments: a newline or carriage return in one cannot end the comment and
 * start scene code (a #debug line here would be run by POV-Ray). */
static void names_cannot_inject_code(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  snprintf(s.material[2].name, sizeof s.material[2].name, "glass\n#debug \"M\"\r#debug \"R\"");
  rt_scene_name_object(&s, 1, "ball\n#debug \"O\"\n");
  char err[512], notes[1024];
  char *t = export_text(&s, 0, notes, sizeof notes, err, sizeof err);
  assert_non_null(t);
  assert_null(strstr(t, "\n#debug"));
  assert_null(strstr(t, "\r"));
  assert_non_null(strstr(t, "// material 'glass #debug \"M\" #debug \"R\"'"));
  free(t);
  rt_scene_free(&s);
}

/* Flat files: codes object + 1, the odd squares' bit, no lights, black, one level. */
static void flat_file_encodes_objects(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  char err[512];
  char *t = export_text(&s, 1, NULL, 0, err, sizeof err);
  assert_non_null(t);
  assert_non_null(strstr(t, "max_trace_level 1"));
  assert_null(strstr(t, "light_source"));
  assert_non_null(strstr(t, "rgb <1/255, 0/255, 0/255>"));   /* board, even squares */
  assert_non_null(strstr(t, "rgb <1/255, 0/255, 128/255>")); /* board, odd squares */
  assert_non_null(strstr(t, "rgb <2/255, 0/255, 0/255>"));   /* the ball */
  assert_non_null(strstr(t, "background { rgb <0, 0, 0> }"));
  free(t);
  rt_scene_free(&s);
}

/* Lights are placed about the scene, not the origin: far from the origin, POV-Ray's fade of an
 * inverse-square light, 2 / (1 + (d / f)^2) times the written colour, is 1 / d^2 times the
 * light's intensity at the ball's nearest point (d = 4) to 1e-6; a parallel light's location lies
 * behind the ball and the eye along its direction. */
static void lights_are_placed_about_the_scene(void **state) {
  (void)state;
  rt_scene_t s;
  char err[512];
  rt_scene_init(&s);
  const px_vec3_t c = px_vec3(1e5, 2.0, 3.0), dir = px_v3_unit(px_vec3(1.0, -1.0, 0.5));
  rt_material_t m = rt_material_default("white");
  int mi;
  assert_int_equal(rt_scene_add_material(&s, &m, &mi), RT_OK);
  assert_int_equal(rt_scene_add_sphere(&s, c, 1.0, mi, NULL), RT_OK);
  s.camera.eye = px_v3_add(c, px_vec3(0, 0, -10));
  s.camera.look_at = c;
  rt_light_t point = {RT_LIGHT_POINT,
                      px_v3_add(c, px_vec3(0, 5, 0)),
                      {2, 2, 2},
                      RT_FALLOFF_INVERSE_SQUARE,
                      {0, 0, 0},
                      {0, 0, 0},
                      0};
  rt_light_t par = {RT_LIGHT_PARALLEL, dir, {1, 1, 1}, RT_FALLOFF_NONE, {0, 0, 0}, {0, 0, 0}, 0};
  assert_int_equal(rt_scene_add_light(&s, &point), RT_OK);
  assert_int_equal(rt_scene_add_light(&s, &par), RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  char *t = export_text(&s, 0, NULL, 0, err, sizeof err);
  assert_non_null(t);
  const char *l0 = strstr(t, "light_source {");
  assert_non_null(l0);
  const char *l1 = strstr(l0 + 1, "light_source {");
  assert_non_null(l1);
  px_vec3_t loc = vector_after(l0, "light_source {"), col = vector_after(l0, "rgb");
  const char *fd = strstr(l0, "fade_distance");
  double f = NAN, d = 4.0;
  assert_true(fd && fd < l1 && sscanf(fd, "fade_distance %lf fade_power 2", &f) == 1);
  assert_close(loc.y, point.v.y, 0, 0);
  double pov = col.x * 2.0 / (1.0 + (d / f) * (d / f)), ours = point.intensity.r / (d * d);
  assert_close(pov, ours, 1e-6, 0);
  px_vec3_t at = vector_after(l1, "light_source {");
  assert_non_null(strstr(l1, "parallel point_at"));
  assert_true(px_v3_dot(px_v3_sub(c, at), dir) > 1.0 + 10.0); /* beyond the ball and the eye */
  assert_true(px_v3_dot(px_v3_sub(s.camera.eye, at), dir) > 10.0);
  free(t);
  rt_scene_free(&s);
  /* planes alone: the parallel light far behind the view (eye 5 from what it looks at), not at
   * the eye (the box of the eye alone) */
  rt_scene_init(&s);
  assert_int_equal(rt_scene_add_material(&s, &m, &mi), RT_OK);
  assert_int_equal(
      rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi, -1, 1, NULL),
      RT_OK);
  s.camera.eye = px_vec3(0, 3, -4);
  s.camera.look_at = px_vec3(0, 0, 0);
  assert_int_equal(rt_scene_add_light(&s, &par), RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  t = export_text(&s, 0, NULL, 0, err, sizeof err);
  assert_non_null(t);
  at = vector_after(strstr(t, "light_source {"), "light_source {");
  assert_true(px_v3_dot(px_v3_sub(s.camera.eye, at), dir) > 100.0 * 5.0);
  free(t);
  rt_scene_free(&s);
}

/* What cannot be mapped is refused naming it; a flat file needs only the geometry. */
static void unmappable_scenes_are_refused(void **state) {
  (void)state;
  rt_scene_t s;
  char err[512];
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  rt_light_t area = {RT_LIGHT_AREA, {0, 5, 0}, {1, 1, 1}, RT_FALLOFF_INVERSE_SQUARE,
                     {1, 0, 0},     {0, 0, 1}, 4};
  assert_int_equal(rt_scene_add_light(&s, &area), RT_OK);
  assert_null(export_text(&s, 0, NULL, 0, err, sizeof err));
  assert_non_null(strstr(err, "lights[1]: an area light"));
  char *t = export_text(&s, 1, NULL, 0, err, sizeof err);
  assert_non_null(t);
  free(t);
  s.nlight = 1;
  s.material[2].fresnel = 1;
  assert_null(export_text(&s, 0, NULL, 0, err, sizeof err));
  assert_non_null(strstr(err, "material 'glass': \"fresnel\""));
  s.material[2].fresnel = 0;
  s.ior = 1.33;
  assert_null(export_text(&s, 0, NULL, 0, err, sizeof err));
  assert_non_null(strstr(err, "settings: the space between objects has index 1.33"));
  rt_scene_free(&s);
}

/* A polyhedron becomes a mesh2 of fans; a face a fan does not cover is refused. */
static void polyhedra_become_meshes(void **state) {
  (void)state;
  rt_scene_t s;
  char err[512];
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_mesh(&s, 4, 6), RT_OK);
  char *t = export_text(&s, 0, NULL, 0, err, sizeof err);
  assert_non_null(t);
  /* 4 stacks x 6 slices: 12 triangles at the poles, 12 quadrilaterals of 2 triangles each */
  assert_non_null(strstr(t, "face_indices { 36"));
  free(t);
  rt_scene_free(&s);
  /* an L-shaped prism: its two L faces are not convex */
  rt_scene_init(&s);
  static const double L[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  px_vec3_t v[12];
  for (int k = 0; k < 6; k++) {
    v[k] = px_v3(L[k][0], L[k][1], 0);
    v[k + 6] = px_v3(L[k][0], L[k][1], 1);
  }
  int idx[6 + 6 + 24], len[8], n = 0;
  for (int k = 5; k >= 0; k--)
    idx[n++] = k;
  for (int k = 0; k < 6; k++)
    idx[n++] = k + 6;
  for (int k = 0; k < 6; k++) {
    int a = k, b = (k + 1) % 6;
    idx[n++] = a, idx[n++] = b, idx[n++] = b + 6, idx[n++] = a + 6;
  }
  for (int k = 0; k < 8; k++)
    len[k] = k < 2 ? 6 : 4;
  rt_material_t m = rt_material_default("white");
  int mi;
  assert_int_equal(rt_scene_add_material(&s, &m, &mi), RT_OK);
  assert_int_equal(rt_scene_add_polyhedron(&s, v, 12, idx, len, 8, mi, NULL, NULL, 0), RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  assert_null(export_text(&s, 1, NULL, 0, err, sizeof err));
  assert_non_null(strstr(err, "object 0: face 0 of the polyhedron is not convex"));
  rt_scene_free(&s);
}

/* POV-Ray's console statistics (the layout of 3.7.0's "Render Statistics" and "Render Time"
 * blocks): the counts at the start of their lines, the render threads' CPU seconds of the Trace
 * Time, not the Parse Time's; a log without the Trace Time is refused naming it. */
static void povray_statistics_are_read(void **state) {
  (void)state;
  const char *log = "Persistence of Vision(tm) Ray Tracer Version 3.7.0.10.unofficial (g++ @\n"
                    "Parser Time\n"
                    "  Parse Time:       0 hours  0 minutes  0 seconds (0.012 seconds)\n"
                    "              using 1 thread(s) with 0.011 CPU-seconds total\n"
                    "Pixels:            65536   Samples:               0   Smpls/Pxl: 0.00\n"
                    "Rays:             213460   Saved:                 0   Max Level: 7/7\n"
                    "Shadow Ray Tests:            187571   Succeeded:                 55731\n"
                    "Reflected Rays:               73962\n"
                    "Render Time:\n"
                    "  Trace Time:       0 hours  0 minutes  0 seconds (0.117 seconds)\n"
                    "              using 1 thread(s) with 0.108 CPU-seconds total\n";
  val_povray_run_t r = {0};
  char version[64], err[256];
  assert_int_equal(val_povray_parse(log, &r, version, sizeof version, err, sizeof err), 0);
  assert_close(r.trace_s, 0.108, 0, 0);
  assert_true(r.rays == 213460 && r.shadow_tests == 187571);
  assert_string_equal(version, "3.7.0.10.unofficial");
  char *cut = strdup(log);
  *strstr(cut, "Render Time:") = '\0';
  assert_int_equal(val_povray_parse(cut, &r, version, sizeof version, err, sizeof err), -1);
  assert_non_null(strstr(err, "Trace Time"));
  free(cut);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(camera_rays_are_ours),
      cmocka_unit_test(depth_and_materials_are_mapped),
      cmocka_unit_test(flat_file_encodes_objects),
      cmocka_unit_test(unmappable_scenes_are_refused),
      cmocka_unit_test(polyhedra_become_meshes),
      cmocka_unit_test(povray_statistics_are_read),
      cmocka_unit_test(names_cannot_inject_code),
      cmocka_unit_test(lights_are_placed_about_the_scene),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
