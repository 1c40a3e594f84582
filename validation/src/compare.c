/* compare.c -- per-pixel differences of two renders and one case's image written, for the
 * benchmark drivers (beam_bench.c, caustic_bench.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "io/image_io.h"
#include "validation/compare.h"
#include "validation/timing.h"

int val_image_diff(const rt_image_t *a, const rt_image_t *b, val_diff_t *d) {
  size_t n = (size_t)a->width * a->height;
  double *e = malloc((n ? n : 1) * sizeof *e);
  if (!e)
    return -1;
  double sum = 0.0, s2 = 0.0, mx = 0.0;
  for (size_t k = 0; k < n; k++) {
    double v = 0.0;
    for (int c = RT_CH_R; c <= RT_CH_B; c++)
      v = fmax(v, fabs((double)a->ch[c][k] - b->ch[c][k]));
    e[k] = v;
    sum += v;
    s2 += v * v;
    mx = fmax(mx, v);
  }
  d->mean = n ? sum / n : 0.0;
  d->rms = n ? sqrt(s2 / n) : 0.0;
  d->max = mx;
  val_sort(e, n); /* for the 99th percentile; cheap at these sizes */
  d->p99 = val_quantile(e, n, 0.99);
  free(e);
  return 0;
}

int val_save_case(const char *cmd, const char *dir, const char *name, const char *variant,
                  const rt_image_t *img) {
  char path[4096], err[1024];
  snprintf(path, sizeof path, "%s/%s-%s.exr", dir, name, variant);
  io_attr_t a[2] = {{"pencil:case", name}, {"pencil:variant", variant}};
  if (io_render_write(path, img, NULL, 0, a, 2, err, sizeof err) != 0) {
    fprintf(stderr, "pencil %s: %s\n", cmd, err);
    return -1;
  }
  return 0;
}
