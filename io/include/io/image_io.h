/* image_io.h -- writing rendered images: OpenEXR through OpenEXRCore's C API (all channels,
 * float32) and an 8-bit sRGB PNG preview through libpng.
 *
 * Both return 0 on success, or -1 with a one-line reason in err[cap] (naming the file); on
 * failure no partial file is left behind. Not thread-safe with respect to the same path.
 */
#ifndef IO_IMAGE_IO_H
#define IO_IMAGE_IO_H

#include <stddef.h>

#include "render/render.h"

/** Write every channel of img (rt_channel_name() names) as 32-bit float, ZIP-compressed
 *  scanlines. The file also carries the string attributes of `meta` (key, value pairs, nmeta
 *  of them; may be NULL). */
int io_exr_write(const char *path, const rt_image_t *img, const char *const (*meta)[2], int nmeta,
                 char *err, size_t cap);

/** Read channel `name` of a scanline EXR written by io_exr_write() into out (width x height
 *  floats, caller-owned, sized by *width x *height from a first call with out = NULL).
 *  For tests and tools that check files independently of the writer. */
int io_exr_read_channel(const char *path, const char *name, float *out, int *width, int *height,
                        char *err, size_t cap);

/** Write R, G, B clamped to [0, 1] and sRGB-encoded, 8 bits per channel. */
int io_png_write(const char *path, const rt_image_t *img, char *err, size_t cap);

/** "OUT.exr" -> "OUT.png" (any other name gets ".png" appended); 0 when it does not fit. */
int io_png_path_for(const char *exr_path, char *out, size_t cap);

#endif
