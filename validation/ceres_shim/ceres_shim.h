/* ceres_shim.h -- the two things pencil needs from Ceres that its C API (ceres/c_api.h) lacks:
 * bounds on parameters and a quiet solve (no logging, no progress output). A thin extern "C"
 * layer over the C++ API; the only C++ in the project (ceres_shim.cc).
 *
 * One problem = one parameter block of np parameters and one residual block of nres residuals
 * computed by a C callback. Thread-safe as long as callbacks are. */
#ifndef VALIDATION_CERES_SHIM_H
#define VALIDATION_CERES_SHIM_H

#ifdef __cplusplus
extern "C" {
#endif

/** Residuals r[0..nres) at parameters p[0..np); when jac is not NULL also the Jacobian,
 *  row-major jac[i * np + j] = d r_i / d p_j. Return 1 on success, 0 when r cannot be evaluated
 *  at p (the solver then shortens its step). */
typedef int (*val_ceres_cost_t)(void *user, const double *p, double *r, double *jac);

typedef struct {
  int max_iterations;         /**< <= 0: Ceres' default (50) */
  double function_tolerance;  /**< <= 0: Ceres' default (1e-6) */
  double gradient_tolerance;  /**< <= 0: Ceres' default (1e-10) */
  double parameter_tolerance; /**< <= 0: Ceres' default (1e-8) */
} val_ceres_options_t;

typedef struct {
  int converged;       /**< Ceres reported CONVERGENCE */
  int usable;          /**< the solution is usable (converged or stopped at an iteration limit) */
  int iterations;      /**< iterations taken */
  double initial_cost; /**< 1/2 sum r^2 at the start */
  double final_cost;   /**< 1/2 sum r^2 at the solution */
  char message[160];   /**< Ceres' termination message, truncated */
} val_ceres_summary_t;

/** Minimise 1/2 sum_i r_i(p)^2 subject to lower[j] <= p[j] <= upper[j] (either array may be
 *  NULL: unbounded; +-HUGE_VAL entries: unbounded on that side). p holds the start (inside the
 *  bounds) and receives the solution. Dense QR, Levenberg-Marquardt, silent. Returns 0 when
 *  the solve ran (see summary->usable), -1 on invalid arguments. */
int val_ceres_solve_bounded(int np, double *p, const double *lower, const double *upper, int nres,
                            val_ceres_cost_t cost, void *user, const val_ceres_options_t *opt,
                            val_ceres_summary_t *summary);

#ifdef __cplusplus
}
#endif

#endif
