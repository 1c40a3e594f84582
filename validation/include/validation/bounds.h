/* bounds.h -- `pencil verify bounds`: the error estimation of section 3 and the Appendix (A-1,
 * general system (3), Eqs. 4-6) against exact tracing.
 *
 * Everything is made dimensionless with the system's length L (val_system_t.length): positions
 * are divided by L, so the pencil constants compare as (A L, B, C / L, D L^2, E L, F) and a
 * pencil is described by the angle phi with x0 = L cos(phi), xi0 = sin(phi). The true error is
 * the second-order Taylor term Delta psi = 1/2 t(2)[psi, psi] of the exact map (jets, cross-
 * checked by __float128 differences), maximised over all directions of x0 and xi0; the full
 * error is exact map minus system matrix (docs/bounds.md). */
#ifndef VALIDATION_BOUNDS_H
#define VALIDATION_BOUNDS_H

#include <stdio.h>

#include "validation/systems.h"

enum { VAL_NCOEF = 6 }; /**< A, B, C (e_x) and D, E, F (e_xi) */
enum { VAL_NPHI = 17 }; /**< pencil shapes phi = 0 .. pi/2 sampled */
/** A ratio bound / true below 1 - VAL_BOUND_SLACK is a failure: the true worst case is found
 *  to ~1e-12 relative (grid plus refinement on a smooth trigonometric quadratic), so 1e-9
 *  separates a violated bound from a bound attained exactly (ratio 1, e.g. a, b, f). */
#define VAL_BOUND_SLACK 1e-9
/** A scaled true coefficient below this fraction of the tensor's scale (max(1, max scaled
 *  |t(2)|)) is zero: the jets are exact to ~1e-14 of that scale. */
#define VAL_ZERO_TOL 1e-10
/** Largest spread probed for the third-order onset (radians). */
#define VAL_ONSET_MAX 0.5
/** Ceres envelope: agreement required with the exact worst case where it is attained. */
#define VAL_FIT_TOL 0.02

/** Worst cases of a second-order tensor t(2) (hess[i][j][k], unscaled) -- bounds_truth.c. */
typedef struct {
  double coef[VAL_NCOEF];     /**< true A..F (scaled): max over unit directions of each part */
  double ex[VAL_NPHI];        /**< max |Delta x| / L over directions at phi_k (amplitude 1) */
  double exi[VAL_NPHI];       /**< max |Delta xi| over directions at phi_k */
  double dir_x[VAL_NPHI][2];  /**< (alpha, beta) attaining ex[k] */
  double dir_xi[VAL_NPHI][2]; /**< (alpha, beta) attaining exi[k] */
  double scale;               /**< max(1, max scaled |t(2)_ijk|) */
} val_truth_t;

/** phi_k = k/(VAL_NPHI-1) * pi/2. */
double val_phi(int k);

/** True worst cases of the tensor (directions maximised numerically: grid plus refinement). */
void val_truth_from_tensor(double hess[4][4][4], double length, val_truth_t *t);

/** e_x and e_xi of scaled pencil constants k at shape phi (amplitude 1). */
double val_ex_scaled(const px_pencil_t *k, double phi);
double val_exi_scaled(const px_pencil_t *k, double phi);

/** Pencil constants scaled by L: (A L, B, C / L, D L^2, E L, F). */
px_pencil_t val_scale_pencil(const px_pencil_t *k, double length);

/** Largest full error |x_exact - (T psi)_x| / L of a pinhole pencil (x = 0, |xi| = xi0) over the
 *  direction of xi (double precision; grid plus refinement). Errors of ex_map (a ray missing a
 *  surface, TIR) are returned. */
px_status_t val_pinhole_error(const ex_system_t *sys, const ex_axial_t *ax, px_mat4_t t,
                              double length, double xi0, double *err);

/** Largest full error (part 0: |Delta x| / L, part 1: |Delta xi|) at amplitude eps and shape phi,
 *  divided by eps^2, at the directions (alpha, beta) and their 1-degree neighbours, in
 *  __float128: the sampled exact error that the Ceres envelope is fitted to. eps is lowered
 *  (down to 1e-12) until the sample is in the second-order regime; *eps_used (may be NULL)
 *  tells which amplitude was used. */
px_status_t val_sampled_error(const ex_system_t *sys, const ex_axial_t *ax, double length,
                              double eps, double phi, int part, const double dir[2], double *err,
                              double *eps_used);

/** Ceres fit of the tightest non-negative quadratic envelope e(phi) = c0 cos^2 + c1 cos sin +
 *  c2 sin^2 >= samples[k] (k = 0..VAL_NPHI-1, scaled) -- fit_envelope.c. coef holds a start
 *  and receives the fit; *worst_excess = max_k samples/e - 1 (<= 0: an envelope),
 *  *attained_dev = |e/samples - 1| at the sample where samples/e is largest. Returns 0 on a
 *  usable fit, -1 otherwise. */
int val_fit_envelope(const double samples[VAL_NPHI], double coef[3], double *worst_excess,
                     double *attained_dev);

/** One system's verification. */
typedef struct {
  px_status_t status;               /**< PX_OK or why it was skipped */
  double theta_deg;                 /**< incidence angle at the first surface */
  double tensor_diff;               /**< jets vs quad differences, scaled, / scale */
  val_truth_t truth;                /**< true worst cases */
  px_pencil_t bound[2];             /**< scaled pencil constants [variant] */
  double ratio[2][VAL_NCOEF];       /**< bound / true; +Inf: true 0, bound > 0; NaN: both 0 */
  double ratio_ex[2], ratio_exi[2]; /**< min over phi of e / true worst (Inf: nothing to bound) */
  double phi_ex[2], phi_exi[2];     /**< phi where those minima are attained */
  int pinhole;                      /**< the input plane is off every surface (a cascade) */
  int second_order_vanishes;        /**< pinhole with true C = 0 but a non-zero full error */
  double onset[2];                  /**< pinhole: spread where C xi^2 < full error first
                                         [variant]; Inf: not up to VAL_ONSET_MAX or a miss */
  double err_at_probe;              /**< pinhole: full error / L at xi0 = 1e-2 */
  double k3;                        /**< pinhole: third-order coefficient (scaled), from the
                                         full error beyond the second-order term */
  double tau;                       /**< pinhole: tolerance of Eq. (3), scaled, for rho = 1/2
                                         and a direction interval of 1e-3 rad */
  double spread[2];                 /**< spread limits: Eq. (6) alone (capped), with k3 */
  px_spread_regime_t regime[2];     /**< their regimes */
  double err_over_tau[2];           /**< full exact error at those spreads / tau (> 1: the
                                         limit lets through a pencil that is too wide) */
  int fitted;                       /**< the Ceres fit ran */
  px_pencil_t fit;                  /**< fitted scaled constants A-F */
  double fit_excess[2], fit_dev[2]; /**< e_x, e_xi: envelope excess and attained deviation */
  double sampled_vs_tensor;         /**< max |sampled / tensor worst - 1| where both > 0 */
} val_bounds_result_t;

/** Verify one system (both variants; the fit when with_fit). */
void val_verify_bounds_one(const val_system_t *v, int with_fit, val_bounds_result_t *r);

/** The sweep of `pencil verify bounds`: val_sweep_build() plus pinhole -> glass sphere -> plane
 *  at aims 0 .. 0.9 of the radius (0 = through the centre), with and without an internal
 *  reflection. Free with free(). */
val_system_t *val_bounds_sweep(int quick, size_t *count);

typedef struct {
  int quick;        /**< small sweep (tests) */
  int no_fit;       /**< skip the Ceres fit */
  const char *json; /**< summary JSON path or NULL */
  const char *csv;  /**< directory for the CSV tables or NULL */
  FILE *report;     /**< human-readable tables (stdout) or NULL */
  /** Called after each system with (done, total), or NULL. */
  void (*progress)(void *ctx, int done, int total);
  void *progress_ctx; /**< passed to progress */
  int threads;        /**< OpenMP threads for the systems (independent); <= 0: all cores. The
                           results do not depend on it */
} val_bounds_opts_t;

/** Run the verification; 0 when the corrected variant holds everywhere and the fit agrees, 1
 *  otherwise, -1 on an I/O error (message on stderr naming the file). */
int val_verify_bounds(const val_bounds_opts_t *opts);

#endif
