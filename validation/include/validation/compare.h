/* compare.h -- what the benchmark drivers share to compare renders and keep them: per-pixel
 * differences of two images and one case's image written as an EXR. */
#ifndef VALIDATION_COMPARE_H
#define VALIDATION_COMPARE_H

#include "core/image.h"

/** Per pixel the largest of |a - b| over R, G, B, summed up over the image. */
typedef struct {
  double mean, rms, p99, max; /**< p99: val_quantile()'s 99th percentile */
} val_diff_t;

/** The differences of a against b (same size). 0, or -1 out of memory (nothing printed). */
int val_image_diff(const rt_image_t *a, const rt_image_t *b, val_diff_t *d);

/** Write img as DIR/NAME-VARIANT.exr (and its PNG preview) with the attributes pencil:case and
 *  pencil:variant; 0, or -1 after printing "pencil CMD: why" on stderr (cmd: "bench beam"). */
int val_save_case(const char *cmd, const char *dir, const char *name, const char *variant,
                  const rt_image_t *img);

#endif
