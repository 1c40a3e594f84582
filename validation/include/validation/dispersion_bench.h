/* dispersion_bench.h -- `pencil bench dispersion`: the 1989 paper's Fig. 14 table (section 3.3:
 * a dispersive polyhedron of 120 polygons, 1.2 min by dispersive pencil tracing against 1.0 min
 * non-dispersive and 57.9 min by a conventional non-dispersive ray tracer), reproduced with what
 * is built: each method's time on scenes/fig14.json and its colour error against a converged
 * spectral reference, per pixel CIEDE2000 (mean, 99th percentile, largest).
 *
 * Methods (exact renderer options of docs/spectral.md):
 *  - pencil: the pencil renderer, the glass at its index at the d-line (non-dispersive pencil);
 *  - exact-nd: the exact renderer with --wavelengths off (the conventional non-dispersive tracer);
 *  - exact-takagi9: every primary ray traced at 9 wavelengths (Takagi et al., the paper's [9]:
 *    its conventional dispersive method);
 *  - exact-fan9, exact-fan40: the spectral fan with 9 and 40 bins;
 *  - exact-fanR/2: the fan with half the reference's bins (how far the reference has converged);
 *  - reference: the fan with R bins (default 400), timed once.
 *  - pencil-spectral, exact-spectral-pencil: spectral pencils (the 1989 paper's Eq. 13) in the
 *    pencil and exact renderers;
 *  - beam, beam-solids, beam-pencils: the beam renderer with the glass at n_d, with dispersion
 *    image solids (the paper's 3.2.2), and with spectral pencils from each cell share. */
#ifndef VALIDATION_DISPERSION_BENCH_H
#define VALIDATION_DISPERSION_BENCH_H

#include "validation/status.h"
#include <stdio.h>

typedef struct {
  int quick;          /**< 48 x 48, the reference at 100 bins, one run (tests) */
  int threads;        /**< OpenMP threads, 0 = all */
  int runs;           /**< timed runs per method (the median is reported), >= 1 */
  int size;           /**< image side in pixels (0: 256; quick: 48) */
  int ref_bins;       /**< the reference's bins (0: 400; quick: 100), RT_MIN_BINS..RT_MAX_BINS */
  int spp;            /**< every method's samples per pixel, a square (0: the scene's) */
  int ref_spp;        /**< the reference's, a square (0: as spp): above the methods', its pixel
                           approaches an area average, which beams compute and point samples
                           approach, so that methods can be compared at equal error */
  const char *json;   /**< summary path or NULL */
  const char *out;    /**< directory for the images (fig14-METHOD.exr and .png), or NULL */
  const char *scenes; /**< directory holding fig14.json, or NULL for the source tree's */
  FILE *report;       /**< table (stdout) or NULL */
} val_dispersion_bench_opts_t;

/** Run the benchmark; 0 on success, else VAL_ESCENE (a scene it reads), VAL_EOUTPUT (an
 *  output) or VAL_EFAIL (validation/status.h), each after a message on stderr. */
int val_bench_dispersion(const val_dispersion_bench_opts_t *o);

#endif
