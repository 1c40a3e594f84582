/* illum_bench.h -- `pencil bench illuminance`: the illuminance maps (light/) against references,
 * issue 21's targets:
 *  - rotationally symmetric cases (a glass ball under a parallel light and under a point light
 *    on its axis) whose exact illuminance is a one-dimensional integral over the rays'
 *    meridional trace (val_ring_map): the grid-pencil map within 1% of it where the exact field
 *    is smooth over a cell, and its total flux within 0.5%;
 *  - the scene of the 1987 paper's Fig. 11 (scenes/fig11.json): grid-pencil tracing with
 *    128 x 128 pencils against photon counting with 100 times as many rays, both against a
 *    converged reference, with the time each needs for equal error. */
#ifndef VALIDATION_ILLUM_BENCH_H
#define VALIDATION_ILLUM_BENCH_H

#include <stdio.h>

#include "light/illuminance.h"
#include "validation/status.h"

/** A glass ball (radius r, index n, transmitting everything: kt 1, kr 0) with its centre at height
 *  h above a floor, lit from above along the axis by a parallel light (source_height <= 0) or a
 *  point light at that height (above the ball or inside it), intensity 1: the exact cell averages
 * of the floor's illuminance over map m's cells (u = x, v = -z; m->e receives R = G = B), from
 * `rays` meridional rays traced exactly whose flux is spread over the annulus each pair of
 * neighbours bounds. The radial profile's smoothness per cell goes to smooth[] (1 where the exact E
 * varies by less than 10% over the cell's radii and has no jump), when not NULL. */
void val_ring_map(double r, double n, double h, double source_height, long rays, lt_map_t *m,
                  unsigned char *smooth);

typedef struct {
  int quick;                      /**< small maps and grids (tests) */
  int threads;                    /**< OpenMP threads, 0 = all */
  int max_split;                  /**< grid-pencil runs: lt_options_t.max_split */
  double linear_tol, uniform_tol; /**< ... and the two tolerances */
  const char *json;               /**< summary path or NULL */
  const char *maps;               /**< directory for the maps (CASE-METHOD.exr, .json), or NULL */
  const char *fig11;              /**< the Fig. 11 scene, or NULL for the source tree's
                                       scenes/fig11.json */
  FILE *report;                   /**< table (stdout) or NULL */
} val_illum_bench_opts_t;

/** Run the benchmark; 0 when the targets are met, 1 when not, VAL_ESCENE when the Fig. 11 scene
 *  cannot be read (before any work), VAL_EFAIL on another error (validation/status.h; messages on
 *  stderr). */
int val_bench_illuminance(const val_illum_bench_opts_t *o);

#endif
