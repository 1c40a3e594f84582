/* stability.h -- `pencil verify stability`: randomized hard configurations of the element
 * matrices (Eq. 2) and cascades through caustics, each either refused with a status or checked
 * against its stated accuracy (PX_ACCURACY, status.h): against the invariants on all, against
 * Eq. (2) evaluated in __float128 from the same inputs on all, and against the __float128
 * Jacobian of exact tracing on a sample (docs/verification.md, "Stability"). */
#ifndef VALIDATION_STABILITY_H
#define VALIDATION_STABILITY_H

#include <stdint.h>
#include <stdio.h>

#include "paraxial/paraxial.h"

/** The regimes the configurations are drawn from (one in VAL_STAB_REGIMES each). */
typedef enum {
  VAL_STAB_GRAZING,    /**< 1e-9 .. 1e-1 deg from grazing, any indices */
  VAL_STAB_CRIT_BELOW, /**< 1e-13 .. 1e-1 deg below the critical angle */
  VAL_STAB_CRIT_ABOVE, /**< 1e-13 .. 1e-1 deg above it: total internal reflection */
  VAL_STAB_TIR,        /**< anywhere beyond the critical angle */
  VAL_STAB_NORMAL,     /**< 0 or 1e-12 .. 1e-1 deg */
  VAL_STAB_EQUAL,      /**< n1 = n2 at any angle, grazing included */
  VAL_STAB_CLOSE,      /**< n2 = n1 (1 +- 1e-15 .. 1e-3) */
  VAL_STAB_REFLECT,    /**< mirrors at any angle, grazing included */
  VAL_STAB_GENERAL,    /**< any angle, indices 1 .. 2.5 */
  VAL_STAB_CASCADE,    /**< transfer, element, transfer near the caustic (det B ~ 0), element,
                            transfer */
  VAL_STAB_REGIMES
} val_stab_regime_t;

const char *val_stab_regime_name(val_stab_regime_t r);

/** What became of one configuration. */
typedef struct {
  val_stab_regime_t regime;
  px_status_t status;        /**< PX_OK (checked) or why it was refused */
  int nonfinite;             /**< PX_OK with a NaN or Inf entry or error bound: a silent failure */
  int invariant_fail;        /**< the symplectic form or the determinant is off by more than the
                                  stated accuracy allows */
  int reference_fail;        /**< off the __float128 Eq. (2) by more than its own error bound */
  int accuracy_fail;         /**< off by more than PX_ACCURACY (implies reference_fail) */
  int refusal_wrong;         /**< refused with a reason the exact values contradict (TIR where
                                  cos^2 theta' > 1e-12, grazing where both cosines > 2e-10, overflow
                                  below PX_CURVATURE_MAX / 10) */
  int returned_tir;          /**< a matrix where the exact ray is totally reflected */
  int bounds_disagree;       /**< px_element_coeffs() returned another status than the matrix */
  double err_bound;          /**< the bound the library stated (cascades: propagated) */
  double err;                /**< the scaled relative error against the __float128 reference */
  int sampled;               /**< also compared with the exact-tracing Jacobian */
  int sample_fail;           /**< that comparison failed (error > bound + the reference's own) */
  int sample_unresolved;     /**< the Jacobian's two step sizes disagree by more than 1e-9:
                                  the reference cannot judge this configuration */
  double sample_err;         /**< scaled relative error against the Jacobian */
  int sample_invariant_fail; /**< the invariants do not hold on the exact Jacobian itself */
  char label[160];           /**< the configuration, for reports */
} val_stab_case_t;

/** Draw and check configuration `index` of the run with `seed` (deterministic: the same case
 *  for any thread count). `sample` = 1 also compares with ex_jacobian_q(). */
void val_stability_case(uint64_t seed, uint64_t index, int sample, val_stab_case_t *out);

typedef struct {
  uint64_t samples;      /**< configurations (10^7 by default) */
  uint64_t seed;         /**< generator seed */
  uint64_t sample_every; /**< one in this many also against the exact Jacobian (1000) */
  int threads;           /**< OpenMP threads; <= 0: all cores. Counts do not depend on it */
  const char *json;      /**< summary JSON path or NULL */
  FILE *report;          /**< table (stdout) or NULL */
  void (*progress)(void *ctx, int done, int total); /**< per 1/1000 of the run, or NULL */
  void *progress_ctx;
} val_stability_opts_t;

/** Run; 0 when nothing failed, 1 when any failure or silent non-finite result was found, -1 on
 *  an I/O error (message on stderr naming the file). */
int val_verify_stability(const val_stability_opts_t *opts);

#endif
