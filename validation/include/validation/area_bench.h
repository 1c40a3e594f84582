/* area_bench.h -- `pencil bench area`: area sources (the 1989 paper's section 2.3) against the
 * brute-force sum of many point sources, issue 25's target. For each case an area light's
 * illuminance map is made as M x M mesh points, M = 1, 2, 4, 8 (quick: 1, 2), as the plain sum of
 * the points' grid-pencil maps, and for M up to 4 with the space-variant filter of the 1989
 * Eqs. (9)-(12) in both forms (lt_area_filter_t: the displacement quadratic over the mesh cell,
 * and linear as the printed Eq. 10 has it), and compared with the reference: the sum of
 * ref_mesh x ref_mesh point sources (64 x 64; quick 16 x 16), whose own error is estimated from a
 * second sum with half the mesh side. The cases:
 *  - floor: a bare floor under a rectangle, where the exact illuminance is known in closed form
 *    (the configuration factor of a parallel rectangle) and Eq. (9) holds exactly (a point's
 *    pattern moves rigidly with it); the brute-force sum is checked against it too;
 *  - ball: a glass ball over a floor past its focus (strong spherical aberration: a ray's
 *    landing is far from linear in the source's position), light through it only.
 * The ball is also run with its light scaled by 1/4 .. 2 at M = 2 against 24 x 24 points, the
 * filter's error as the mesh cells outgrow the small-source assumption of Eq. (9). */
#ifndef VALIDATION_AREA_BENCH_H
#define VALIDATION_AREA_BENCH_H

#include "validation/status.h"
#include <stdio.h>

typedef struct {
  int quick;        /**< small maps, meshes and grids (tests) */
  int threads;      /**< OpenMP threads, 0 = all */
  int runs;         /**< timed runs of each variant (the median is reported), >= 1 */
  int ref_mesh;     /**< the reference's mesh side; 0: 64 (quick: 16) */
  const char *json; /**< summary path or NULL */
  const char *out;  /**< directory for the maps (CASE-VARIANT.exr, .png, .json) and the CSV
                         files area-curve.csv and area-size.csv, or NULL */
  FILE *report;     /**< table (stdout) or NULL */
} val_area_bench_opts_t;

/** Run the benchmark; 0 on success, else VAL_ESCENE (a scene it reads), VAL_EOUTPUT (an
 *  output) or VAL_EFAIL (validation/status.h), each after a message on stderr. */
int val_bench_area(const val_area_bench_opts_t *o);

#endif
