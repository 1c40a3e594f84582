/* image_io.h -- rendered images: OpenEXR through OpenEXRCore's C API (all channels, float32,
 * with the provenance of io/output.h in the header) and an 8-bit sRGB PNG preview through
 * libpng.
 *
 * Functions return 0 on success, or -1 with a one-line reason in err[cap] (naming the file); on
 * failure no partial or temporary file is left behind (io/output.h). Not thread-safe with
 * respect to the same path.
 */
#ifndef IO_IMAGE_IO_H
#define IO_IMAGE_IO_H

#include <stddef.h>

#include "core/image.h"

struct json_t; /* jansson's json_t */

/** A named float32 channel of width x height values (caller-owned) beside an image's own. */
typedef struct {
  const char *name;
  const float *data;
} io_exr_channel_t;

/** A string attribute of an image file's header. */
typedef struct {
  const char *key;
  const char *value;
} io_attr_t;

/** The one OpenEXR writer: every channel of img (rt_channel_name() names) and the `nextra`
 *  extra channels (names must differ from the image's) as 32-bit float, ZIP-compressed
 *  scanlines, with the string attributes attrs[0 .. nattrs-1] and the provenance of
 *  io/output.h (pencil:version, pencil:commit, pencil:command_line, pencil:date). The file is
 *  replaced atomically. */
int io_exr_write(const char *path, const rt_image_t *img, const io_exr_channel_t *extra, int nextra,
                 const io_attr_t *attrs, int nattrs, char *err, size_t cap);

/** Read channel `name` of a scanline EXR written by io_exr_write() into out (width x height
 *  floats, caller-owned, sized by *width x *height from a first call with out = NULL).
 *  For tests and tools that check files independently of the writer. */
int io_exr_read_channel(const char *path, const char *name, float *out, int *width, int *height,
                        char *err, size_t cap);

/** Read the string attribute `key` of an EXR file into out[cap_out] (tests, tools). */
int io_exr_read_attr(const char *path, const char *key, char *out, size_t cap_out, char *err,
                     size_t cap);

/** The PNG preview of img: R, G, B through the display transform of post/display.h (clamped to
 *  [0, 1], sRGB-encoded), 8 bits per channel; replaced atomically. */
int io_png_write(const char *path, const rt_image_t *img, char *err, size_t cap);

/** "OUT.exr" -> "OUT.png" (any other name gets ".png" appended); 0 when it does not fit. */
int io_png_path_for(const char *exr_path, char *out, size_t cap);

/** Before a render: exr_path names an .exr file, and it and its PNG preview can be written
 *  (io_output_check()). */
int io_render_check(const char *exr_path, char *err, size_t cap);

/** A render's outputs: io_exr_write() to exr_path and io_png_write() to the preview beside it.
 *  Both are written to temporary files first and renamed only when both succeeded, so that a
 *  failure leaves the old files as they were. */
int io_render_write(const char *exr_path, const rt_image_t *img, const io_exr_channel_t *extra,
                    int nextra, const io_attr_t *attrs, int nattrs, char *err, size_t cap);
/** io_render_write() with the PNG preview made from `preview` (R, G, B, the same size) instead of
 *  img: an image whose display transform is not the plain clamp (the star filter's phi). */
int io_render_write_preview(const char *exr_path, const rt_image_t *img,
                            const io_exr_channel_t *extra, int nextra, const io_attr_t *attrs,
                            int nattrs, const rt_image_t *preview, char *err, size_t cap);

/** The grey preview of a map of width x height values e (row j of the map holds its v index j):
 *  each value over the largest, image rows from the top (the largest j first), in R = G = B.
 *  Allocates img (rt_image_free()); 0 when out of memory. */
int io_map_preview(int width, int height, const float *e, rt_image_t *img);

/** A map's outputs (illuminance maps): the float32 channels ch[0 .. n-1] of width x height
 *  values and nothing else to exr_path, with the attributes and provenance of io_exr_write();
 *  the PNG preview of `preview` (R, G, B; may be NULL for none) beside it; and the JSON summary
 *  `summary` (a "provenance" object is added) to json_path. All are written to temporary files
 *  and renamed only when every one succeeded. */
int io_map_write(const char *exr_path, int width, int height, const io_exr_channel_t *ch, int n,
                 const rt_image_t *preview, const io_attr_t *attrs, int nattrs,
                 const char *json_path, struct json_t *summary, char *err, size_t cap);

#endif
