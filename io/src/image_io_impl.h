/* image_io_impl.h -- io's private image writers: write a given (temporary) file directly, so
 * that io_render_write() can replace an EXR and its PNG preview together. */
#ifndef IO_IMAGE_IO_IMPL_H
#define IO_IMAGE_IO_IMPL_H

#include "io/image_io.h"

/** io_exr_write() into `file` as it is (no temporary file); errors name `path`. */
int io_exr_write_file(const char *file, const char *path, const rt_image_t *img,
                      const io_exr_channel_t *extra, int nextra, const io_attr_t *attrs, int nattrs,
                      char *err, size_t cap);
/** The channels ch[0 .. n-1] alone (width x height floats each) into `file` as it is. */
int io_exr_write_channels_file(const char *file, const char *path, int width, int height,
                               const io_exr_channel_t *ch, int n, const io_attr_t *attrs,
                               int nattrs, char *err, size_t cap);
/** io_png_write() into `file` as it is; errors name `path`. */
int io_png_write_file(const char *file, const char *path, const rt_image_t *img, char *err,
                      size_t cap);

#endif
