/* display.c -- the display transform of display.h: clamp, then the sRGB transfer curve
 * (IEC 61966-2-1: linear below 0.0031308, a 1/2.4 power above). */
#include "post/display.h"

#include <math.h>

uint8_t pp_srgb8(float linear) {
  double c = isfinite(linear) ? fmin(fmax(linear, 0.0), 1.0) : 0.0;
  double e = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
  return (uint8_t)lrint(255.0 * e);
}

void pp_display_srgb8(const float *r, const float *g, const float *b, size_t n, uint8_t *rgb) {
  for (size_t k = 0; k < n; k++) {
    rgb[3 * k] = pp_srgb8(r[k]);
    rgb[3 * k + 1] = pp_srgb8(g[k]);
    rgb[3 * k + 2] = pp_srgb8(b[k]);
  }
}
