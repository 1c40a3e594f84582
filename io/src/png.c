/* png.c -- the PNG preview of a render: R, G, B through the display transform (post/display.h),
 * 8-bit sRGB written with libpng, with the provenance every output records as text chunks
 * (Software, pencil:version, pencil:commit, pencil:date; pencil:command_line as UTF-8 iTXt, as
 * the EXR header has them); and io_render_write(), which replaces an EXR and its preview
 * together. */
#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "image_io_impl.h"
#include "io/json.h"
#include "io/output.h"
#include "post/display.h"

/* libpng's error callback: keep the message, then return to the setjmp of write_rgb8. */
static void png_error_fn(png_structp png, png_const_charp msg) {
  char *why = png_get_error_ptr(png);
  snprintf(why, 256, "%s", msg);
  png_longjmp(png, 1);
}

static void png_warning_fn(png_structp png, png_const_charp msg) {
  (void)png, (void)msg; /* nothing a preview's reader needs */
}

/* The RGB rows buf (w x h x 3 bytes) to the open file f with the provenance's text chunks; 1, or
 * 0 with libpng's reason in why[256]. */
static int write_rgb8(FILE *f, const unsigned char *buf, int w, int h, char *why) {
  const io_provenance_t *p = io_provenance();
  char software[256];
  snprintf(software, sizeof software, "pencil %s (%s)", p->version, p->commit);
  png_text text[5];
  memset(text, 0, sizeof text);
  const char *const keys[5] = {"Software", "pencil:version", "pencil:commit", "pencil:date",
                               "pencil:command_line"};
  const char *const values[5] = {software, p->version, p->commit, p->date, p->command_line};
  for (int k = 0; k < 5; k++) {
    /* the command line may hold any UTF-8 (main() refuses other arguments): iTXt; the rest is
     * ASCII, tEXt */
    text[k].compression = k == 4 ? PNG_ITXT_COMPRESSION_NONE : PNG_TEXT_COMPRESSION_NONE;
    text[k].key = (png_charp)keys[k];
    text[k].text = (png_charp)values[k];
    text[k].text_length = strlen(values[k]);
  }
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, why, png_error_fn, png_warning_fn);
  png_infop info = png ? png_create_info_struct(png) : NULL;
  if (!info) {
    snprintf(why, 256, "out of memory");
    png_destroy_write_struct(&png, NULL);
    return 0;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return 0;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL); /* as libpng's simplified API wrote it */
  png_set_text(png, info, text, 5);
  png_write_info(png, info);
  for (int y = 0; y < h; y++)
    png_write_row(png, buf + (size_t)y * (size_t)w * 3);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return 1;
}

int io_png_write_file(const char *file, const char *path, const rt_image_t *img, char *err,
                      size_t cap) {
  size_t n = (size_t)img->width * (size_t)img->height;
  unsigned char *buf = malloc(3 * n);
  if (!buf) {
    snprintf(err, cap, "%s: out of memory", path);
    return -1;
  }
  pp_display_srgb8(img->ch[RT_CH_R], img->ch[RT_CH_G], img->ch[RT_CH_B], n, buf);
  char why[256] = "";
  FILE *f = fopen(file, "wb");
  int ok = f && write_rgb8(f, buf, img->width, img->height, why);
  if (f && ok && (fflush(f) != 0 || ferror(f)))
    ok = 0, snprintf(why, sizeof why, "%s", strerror(errno));
  if (f && fclose(f) != 0 && ok)
    ok = 0, snprintf(why, sizeof why, "%s", strerror(errno));
  if (!f)
    snprintf(why, sizeof why, "%s", strerror(errno));
  free(buf);
  if (!ok) {
    snprintf(err, cap, "%s: cannot write PNG: %s", path, why);
    return -1;
  }
  return 0;
}

int io_png_write(const char *path, const rt_image_t *img, char *err, size_t cap) {
  io_atomic_t a;
  if (io_atomic_begin(&a, path, err, cap) != 0)
    return -1;
  if (io_png_write_file(a.tmp, path, img, err, cap) != 0) {
    io_atomic_abort(&a);
    return -1;
  }
  return io_atomic_commit(&a, err, cap);
}

int io_png_path_for(const char *exr_path, char *out, size_t cap) {
  size_t n = strlen(exr_path);
  int has_ext = n >= 4 && strcasecmp(exr_path + n - 4, ".exr") == 0;
  size_t stem = has_ext ? n - 4 : n;
  if (stem + 5 > cap)
    return 0;
  memcpy(out, exr_path, stem);
  memcpy(out + stem, ".png", 5);
  return 1;
}

int io_render_check(const char *exr_path, char *err, size_t cap) {
  char png[4096];
  size_t n = strlen(exr_path);
  if (n < 5 || strcasecmp(exr_path + n - 4, ".exr") != 0 || exr_path[n - 5] == '/') {
    snprintf(err, cap,
             "%s: the output is an OpenEXR file and must be named NAME.exr (its PNG preview is "
             "written beside it as NAME.png)",
             exr_path);
    return -1;
  }
  if (!io_png_path_for(exr_path, png, sizeof png))
    return snprintf(err, cap, "%s: the path is too long", exr_path), -1;
  return io_output_check(exr_path, err, cap) == 0 && io_output_check(png, err, cap) == 0 ? 0 : -1;
}

int io_render_write(const char *exr_path, const rt_image_t *img, const io_exr_channel_t *extra,
                    int nextra, const io_attr_t *attrs, int nattrs, char *err, size_t cap) {
  return io_render_write_preview(exr_path, img, extra, nextra, attrs, nattrs, img, err, cap);
}

int io_render_write_preview(const char *exr_path, const rt_image_t *img,
                            const io_exr_channel_t *extra, int nextra, const io_attr_t *attrs,
                            int nattrs, const rt_image_t *preview, char *err, size_t cap) {
  char png[4096];
  io_atomic_t ae, ap;
  if (io_render_check(exr_path, err, cap) != 0 || !io_png_path_for(exr_path, png, sizeof png))
    return -1;
  if (io_atomic_begin(&ae, exr_path, err, cap) != 0)
    return -1;
  if (io_atomic_begin(&ap, png, err, cap) != 0) {
    io_atomic_abort(&ae);
    return -1;
  }
  int ok = io_exr_write_file(ae.tmp, exr_path, img, extra, nextra, attrs, nattrs, err, cap) == 0 &&
           io_png_write_file(ap.tmp, png, preview, err, cap) == 0;
  ok = ok && io_atomic_commit(&ae, err, cap) == 0 && io_atomic_commit(&ap, err, cap) == 0;
  io_atomic_abort(&ae); /* no-ops after a commit */
  io_atomic_abort(&ap);
  return ok ? 0 : -1;
}

int io_map_preview(int width, int height, const float *e, rt_image_t *img) {
  if (rt_image_alloc(img, width, height) != RT_OK)
    return 0;
  float top = 0.0f;
  size_t n = (size_t)width * (size_t)height;
  for (size_t k = 0; k < n; k++)
    top = fmaxf(top, e[k]);
  for (int y = 0; y < height; y++)
    for (int x = 0; x < width; x++) { /* PNG rows from the top: the largest v first */
      size_t src = (size_t)(height - 1 - y) * width + x, dst = (size_t)y * width + x;
      float g = top > 0 ? e[src] / top : 0.0f;
      img->ch[RT_CH_R][dst] = img->ch[RT_CH_G][dst] = img->ch[RT_CH_B][dst] = g;
    }
  return 1;
}

int io_map_write(const char *exr_path, int width, int height, const io_exr_channel_t *ch, int n,
                 const rt_image_t *preview, const io_attr_t *attrs, int nattrs,
                 const char *json_path, struct json_t *summary, char *err, size_t cap) {
  char png[4096];
  io_atomic_t ae, ap, aj;
  if (io_render_check(exr_path, err, cap) != 0 || !io_png_path_for(exr_path, png, sizeof png) ||
      io_output_check(json_path, err, cap) != 0)
    return -1;
  if (json_is_object(summary) && !json_object_get(summary, "provenance"))
    json_object_set_new(summary, "provenance", io_json_provenance());
  if (io_atomic_begin(&ae, exr_path, err, cap) != 0)
    return -1;
  if (io_atomic_begin(&ap, png, err, cap) != 0) {
    io_atomic_abort(&ae);
    return -1;
  }
  if (io_atomic_open(&aj, json_path, err, cap) != 0) {
    io_atomic_abort(&ae);
    io_atomic_abort(&ap);
    return -1;
  }
  int ok = io_exr_write_channels_file(ae.tmp, exr_path, width, height, ch, n, attrs, nattrs, err,
                                      cap) == 0 &&
           (!preview || io_png_write_file(ap.tmp, png, preview, err, cap) == 0);
  if (ok && (json_dumpf(summary, aj.f, JSON_INDENT(2)) != 0 || fputc('\n', aj.f) == EOF)) {
    snprintf(err, cap, "%s: error writing JSON", json_path);
    ok = 0;
  }
  ok = ok && io_atomic_commit(&ae, err, cap) == 0 &&
       (!preview || io_atomic_commit(&ap, err, cap) == 0) && io_atomic_commit(&aj, err, cap) == 0;
  io_atomic_abort(&ae); /* no-ops after a commit */
  io_atomic_abort(&ap);
  io_atomic_abort(&aj);
  return ok ? 0 : -1;
}
