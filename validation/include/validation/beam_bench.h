/* beam_bench.h -- `pencil bench beam`: beam tracing of polyhedra against the exact and the pencil
 * renderers at equal image error (issue 24's targets; the 1987 paper, section 4.1 (3) and
 * Fig. 11: 74 s by beams against 49 min by ray tracing).
 *
 * Each case is the 1987 Fig. 11 set-up (three coloured rectangles, a point light, the camera of
 * scenes/fig11.json) with a glass polyhedron: the paper's torus of 100 faces (Fig. 11 itself), a
 * triangular prism, or a UV sphere of 100 to 10,000 faces. The reference is the exact renderer at
 * 16 x 16 samples a pixel. Against it, per pixel the largest of |R|, |G|, |B|: the mean, the 99th
 * percentile and the largest difference, and the median time of the runs, of
 *  - the beam renderer (Eq. (4) bounds; and with the probes only, the check without a bound),
 *  - the exact renderer at 1, 4, 16 and 64 samples a pixel (a ladder),
 *  - the pencil renderer at 16 samples a pixel.
 * "Equal error": the exact renderer's time at the beams' mean error, by log-log interpolation on
 * the ladder; outside the ladder the nearest rung's time is given with the side it lies on. */
#ifndef VALIDATION_BEAM_BENCH_H
#define VALIDATION_BEAM_BENCH_H

#include "validation/status.h"
#include <stddef.h>
#include <stdio.h>

typedef struct {
  int quick;          /**< small images, the reference at 12 x 12 samples, three cases (tests) */
  int threads;        /**< OpenMP threads, 0 = all */
  int runs;           /**< timed runs per render (the median is reported), >= 1 */
  int size;           /**< image side in pixels (0: 256; quick: 32) */
  double rho;         /**< the beam renderer's tolerance, > 0 */
  const char *json;   /**< summary path or NULL */
  const char *out;    /**< directory for the images (CASE-VARIANT.exr and .png), or NULL */
  const char *scenes; /**< directory holding fig11.json, or NULL for the source tree's */
  const char *cases;  /**< comma-separated case names, or NULL for all (quick: fig11, prism,
                           sphere100) */
  FILE *report;       /**< table (stdout) or NULL */
} val_beam_bench_opts_t;

/** The case names, comma-separated (for --help and errors). */
const char *val_bench_beam_case_names(void);

/** 1 when every name of the comma-separated list is a case; else 0 with the first unknown name in
 *  bad[cap]. */
int val_bench_beam_cases_ok(const char *list, char *bad, size_t cap);

/** Run the benchmark; 0 on success, else VAL_ESCENE (a scene it reads), VAL_EOUTPUT (an
 *  output) or VAL_EFAIL (validation/status.h), each after a message on stderr. */
int val_bench_beam(const val_beam_bench_opts_t *o);

#endif
