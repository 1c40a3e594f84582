/* png.c -- the PNG preview of a render: linear radiance clamped to [0, 1] and encoded with the
 * sRGB transfer curve (IEC 61966-2-1), written with libpng's simplified API. */
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"

static unsigned char srgb8(float x) {
  double c = isfinite(x) ? fmin(fmax(x, 0.0), 1.0) : 0.0;
  double e = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
  return (unsigned char)lrint(255.0 * e);
}

int io_png_write(const char *path, const rt_image_t *img, char *err, size_t cap) {
  size_t n = (size_t)img->width * (size_t)img->height;
  unsigned char *buf = malloc(3 * n);
  if (!buf) {
    snprintf(err, cap, "%s: out of memory", path);
    return -1;
  }
  for (size_t k = 0; k < n; k++)
    for (int c = 0; c < 3; c++)
      buf[3 * k + c] = srgb8(img->ch[RT_CH_R + c][k]);
  png_image pi;
  memset(&pi, 0, sizeof pi);
  pi.version = PNG_IMAGE_VERSION;
  pi.width = (png_uint_32)img->width;
  pi.height = (png_uint_32)img->height;
  pi.format = PNG_FORMAT_RGB;
  int ok = png_image_write_to_file(&pi, path, 0, buf, 0, NULL);
  free(buf);
  if (!ok) {
    snprintf(err, cap, "%s: cannot write PNG: %s", path, pi.message);
    remove(path);
    return -1;
  }
  return 0;
}

int io_png_path_for(const char *exr_path, char *out, size_t cap) {
  size_t n = strlen(exr_path);
  int has_ext = n >= 4 && strcmp(exr_path + n - 4, ".exr") == 0;
  size_t stem = has_ext ? n - 4 : n;
  if (stem + 5 > cap)
    return 0;
  memcpy(out, exr_path, stem);
  memcpy(out + stem, ".png", 5);
  return 1;
}
