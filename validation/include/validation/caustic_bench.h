/* caustic_bench.h -- `pencil bench caustics`: renders with caustics (issue 25's targets). For each
 * scene (Fig. 8 with caustics, the 1987 Fig. 11 with its caustic, the 1989 Fig. 8 pool), the
 * exact renderer with a converged backward-ray-traced map is the reference; against it, per
 * pixel (the largest of R, G, B), the RMS, 99th percentile and largest difference of
 *  - the exact renderer with its default map (photons),
 *  - the pencil renderer with its default map (grid-pencils), and with illuminance polygons
 *    where the scene is polyhedral,
 *  - the textbook's image (caustics off: shadows through glass attenuated, not refracted),
 * with each render's time (median of runs; the maps' time included) and the time ratios. The
 * reference's own error is estimated from a second reference with half its rays. The exact
 * renderer with the grid-pencil map compares the two maps alone (the photons that would match
 * grid-pencils, by 1/sqrt(N)), and the pencil renderer without caustics against the textbook's
 * exact image gives its own error apart from the maps'. */
#ifndef VALIDATION_CAUSTIC_BENCH_H
#define VALIDATION_CAUSTIC_BENCH_H

#include "validation/status.h"
#include <stdio.h>

typedef struct {
  int quick;          /**< small images and maps (tests) */
  int threads;        /**< OpenMP threads, 0 = all */
  int runs;           /**< timed runs per render (the median is reported), >= 1 */
  const char *json;   /**< summary path or NULL */
  const char *out;    /**< directory for the images (CASE-VARIANT.exr and .png), or NULL */
  const char *scenes; /**< directory holding the scenes, or NULL for the source tree's */
  int ref_rays;       /**< rays a side of the reference's photon grids; 0: 8193 for Fig. 8,
                           16384 for Fig. 11, the pool and the glass (quick: 513) */
  const char *cases;  /**< comma-separated case names to run (fig8, fig11, pool, glass), or NULL
                           for all */
  FILE *report;       /**< table (stdout) or NULL */
} val_caustic_bench_opts_t;

/** 1 when every name of the comma-separated list is a case of the benchmark; else 0 with the
 *  first unknown name in bad[cap]. */
int val_bench_caustics_cases_ok(const char *list, char *bad, size_t cap);

/** Run the benchmark; 0 on success, else VAL_ESCENE (a scene it reads), VAL_EOUTPUT (an
 *  output) or VAL_EFAIL (validation/status.h), each after a message on stderr. */
int val_bench_caustics(const val_caustic_bench_opts_t *o);

#endif
