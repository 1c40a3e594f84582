/* display.h -- the display transform: linear HDR radiance to 8-bit sRGB for previews (the
 * "non-linear transform to the display's range" that the 1989 paper's section 4 applies after
 * its cross-screen filter). Values are clamped to [0, 1] and encoded with the sRGB transfer
 * curve of IEC 61966-2-1; NaN and infinities become 0, so that a preview never shows a value
 * the EXR does not hold as finite. Pure functions, thread-safe. */
#ifndef POST_DISPLAY_H
#define POST_DISPLAY_H

#include <stddef.h>
#include <stdint.h>

/** One linear value to an 8-bit sRGB code. */
uint8_t pp_srgb8(float linear);

/** n pixels of three planes r, g, b (linear) to interleaved 8-bit sRGB rgb[3 n]. */
void pp_display_srgb8(const float *r, const float *g, const float *b, size_t n, uint8_t *rgb);

#endif
