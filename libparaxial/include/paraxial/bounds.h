/* bounds.h -- error estimation of pencil tracing (paper section 3 and Appendix): the element
 * error coefficients a-f (A-1), the general cascade form with the weights lambda, mu
 * (Appendix (3)), the pencil constants A-F of Eq. (4), the tolerance tau of Eq. (3), the
 * acceptance test of Eq. (5) and the maximum spread angle of Eq. (6).
 *
 * The error of a pencil is the second-order term of the exact map, Delta psi = (1/2) H[psi, psi]
 * (the Taylor term; section 3.2 prints t(2) = d2 psi / d psi d psi without the 1/2, but its
 * coefficients carry the 1/2 of a Taylor term, see docs/bounds.md). Eq. (4) bounds its parts:
 *     e_x  = A x0^2 + B x0 xi0 + C xi0^2 >= |Delta x|
 *     e_xi = D x0^2 + E x0 xi0 + F xi0^2 >= |Delta xi|     with x0 = |x|, xi0 = |xi|.
 *
 * Two variants (px_variant_t): PX_VARIANT_PRINTED evaluates A-1 verbatim, reading its "R" as
 * the smallest radius of curvature |R| = 1 / max|principal curvature| (the only reading with
 * the right physical dimension for a, e; docs/errata.md); PX_VARIANT_CORRECTED (default) uses
 * the coefficients the project derived from the exact second-order expansion (docs/bounds.md),
 * which are upper bounds for any surface with |Q|_2 <= 1/R and third derivatives <= d_3m.
 *
 * Conventions are those of system.h. Everything is pure arithmetic on values: no allocation,
 * no I/O, thread-safe.
 */
#ifndef PARAXIAL_BOUNDS_H
#define PARAXIAL_BOUNDS_H

#include "paraxial/cascade.h"
#include "paraxial/system.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Coefficients of one element's error functions (A-1): e_x = a x^2 + b x xi + c xi^2 and
 *  e_xi = d x^2 + e x xi + f xi^2. Units with a length L: a 1/L, b 1, c L, d 1/L^2, e 1/L,
 *  f 1. The printed variant may hold negative values (it is verbatim); corrected ones are >= 0. */
typedef struct {
  double a, b, c, d, e, f;
} px_coeffs_t;

/** The pencil constants A-F of Eq. (4) for a whole system, same layout and units as
 *  px_coeffs_t (A..F in the fields a..f). */
typedef px_coeffs_t px_pencil_t;

/** Geometry an element's coefficients depend on. */
typedef struct {
  px_event_t event; /**< refraction or reflection */
  double theta;     /**< incidence angle, radians, [0, pi/2) */
  double n1, n2;    /**< indices (n2 ignored for a reflection) */
  double radius;    /**< smallest radius of curvature, > 0; +Inf for a plane */
  double d3m;       /**< largest |third derivative| of the surface height, >= 0 (A-1) */
} px_element_geom_t;

/** Element error coefficients a-f of Eq. (A-1) for a refraction or reflection.
 *  Errors: PX_EINVAL (theta outside [0, pi/2), index <= 0, radius <= 0 or NaN, d3m < 0 or not
 *  finite), PX_ETIR, PX_EGRAZING (cos theta or |cos theta'| <= PX_COS_MIN), PX_ENONFINITE
 *  (1/radius > PX_CURVATURE_MAX, or overflow), PX_EILLCOND (px_element_cosines()).
 *  On error *out is untouched. */
px_status_t px_error_coeffs(const px_element_geom_t *g, px_variant_t variant, px_coeffs_t *out);

/** px_error_coeffs() for the incidence given by its cosine and sine (g->theta is ignored; e.g.
 *  from px_cos_sin_deg() for an angle in degrees). The cosines are px_element_cosines()'s, so
 *  the coefficients exist exactly where px_element_matrix_cs() gives a matrix: the same
 *  PX_EGRAZING, PX_ETIR, PX_ENONFINITE (1/R > PX_CURVATURE_MAX) and PX_EILLCOND. */
px_status_t px_error_coeffs_cs(const px_element_geom_t *g, double cos_theta, double sin_theta,
                               px_variant_t variant, px_coeffs_t *out);

/** The geometry of a cascade element for px_error_coeffs(): theta from nu . s, the radius
 *  1 / |Q|_2 (|Q|_2 = the largest |principal curvature|), and the given d3m. Transfers have no
 *  geometry: PX_EINVAL. */
px_status_t px_element_geom(const px_element_t *e, double d3m, px_element_geom_t *out);

/** The coefficients of a cascade element (px_error_coeffs_cs() with the geometry of
 *  px_element_geom()), its cosines taken from the interface's vectors by
 *  px_interface_cos_sin() as px_interface_matrix() takes them, not through an angle (which
 *  near grazing costs 1e-16 / cos theta relative): so an element has coefficients exactly
 *  where it has a matrix. Transfers: PX_EINVAL. */
px_status_t px_element_coeffs(const px_element_t *e, double d3m, px_variant_t variant,
                              px_coeffs_t *out);

/** Largest |c_ijk| of a symmetric third-derivative tensor given as (c111, c112, c122, c222):
 *  d_3m of A-1 (indices over the two tangent coordinates). */
double px_d3m(const double cubic[4]);

/** The exact second-order term Delta psi = (1/2) H[psi, psi] of one refraction or reflection
 *  whose reference planes pass through the hit point O (the element of Eq. 2), for a surface
 *  height w = 1/2 t^T Q t + 1/6 c[t,t,t] with c = (c111, c112, c122, c222) in the interface's
 *  (u1, u2) basis (NULL = 0). psi and *out are in the element's own frames e->in and e->out,
 *  which may be rotated about the rays. Derived in docs/bounds.md; it is the analytic third
 *  check of the exact tracer's second-order tensor. A transfer gives 0 (A-1 (1)). */
px_status_t px_element_second_order(const px_element_t *e, const double cubic[4], px_ray4_t psi,
                                    px_ray4_t *out);

/** Weights of the general system (Appendix (3)) for element i (1-based) of a cascade:
 *  lambda[k] = |A^a_(k+1) i|_2 of the 2x2 blocks of T_i^a and mu[k] = |A^b_(k+1) i|_2 of
 *  T_i^b, blocks in the order (1 1), (1 2), (2 1), (2 2); |.|_2 = sqrt of the larger
 *  eigenvalue of A A^t. PX_EINVAL when i is 0 or > n. */
px_status_t px_cascade_weights(const px_cascade_t *c, size_t i, double lambda[4], double mu[4]);

/** The pencil constants A-F of Eq. (4) for a cascade by the general form of Appendix (3):
 *  e_x(zeta) = zeta^t { sum_i M_i^t (lambda_1i P_i + lambda_2i Q_i) M_i } zeta, and e_xi with
 *  lambda_3i, lambda_4i, where zeta = (x0, xi0), P_i = [[a, b/2], [b/2, c]], Q_i = [[d, e/2],
 *  [e/2, f]]. `d3m` holds one value per element (ignored for transfers) or is NULL for all 0.
 *  Transfers contribute nothing (A-1 (1)). Errors of px_error_coeffs() for any element. */
px_status_t px_pencil_constants(const px_cascade_t *c, const double *d3m, px_variant_t variant,
                                px_pencil_t *out);

/** e_x(x0, xi0) = A x0^2 + B x0 xi0 + C xi0^2 of Eq. (4). */
double px_pencil_ex(const px_pencil_t *k, double x0, double xi0);
/** e_xi(x0, xi0) = D x0^2 + E x0 xi0 + F xi0^2 of Eq. (4). */
double px_pencil_exi(const px_pencil_t *k, double x0, double xi0);

/** Tolerance of Eq. (3): tau = rho |(t1 t2) delta|, (t1 t2) the upper two rows of the overall
 *  system matrix t (positions), delta the sampling interval as a ray vector, rho > 0 the
 *  accuracy (rho <= 1/2 for one-pixel resolution). PX_EINVAL for rho <= 0 or non-finite input. */
px_status_t px_tolerance(px_mat4_t t, px_ray4_t delta, double rho, double *tau);

/** The acceptance test of Eq. (5): 1 when e_x(x0, xi0) <= tau, else 0. */
int px_pencil_accept(const px_pencil_t *k, double x0, double xi0, double tau);

/** Which term limited the spread angle. */
typedef enum {
  PX_SPREAD_SECOND_ORDER = 0, /**< Eq. (6): C xi^2 = tau (the third-order term is minor) */
  PX_SPREAD_THIRD_ORDER = 1,  /**< the third-order term K3 xi^3 dominates (C ~ 0) */
  PX_SPREAD_CAP = 2           /**< neither term limits: the caller's cap was returned */
} px_spread_regime_t;

/** Maximum spread angle of a pinhole pencil (x0 = 0), Eq. (6) extended by a third-order term:
 *  the largest xi0 <= cap with C xi0^2 + k3 xi0^3 <= tau, where C is the pencil constant and
 *  k3 >= 0 bounds the third-order position error of the pencil (0 if unknown). Eq. (6) alone
 *  is infinite where C = 0 (e.g. an axial ray through the centre of a sphere, where every
 *  second-order term vanishes but the third-order error does not); this function never is:
 *  cap > 0 must be finite and is returned, with regime PX_SPREAD_CAP, when neither term
 *  limits. `regime` may be NULL. PX_EINVAL for tau <= 0, C or k3 < 0, cap <= 0 or non-finite
 *  input. */
px_status_t px_spread_limit(double c, double k3, double tau, double cap, double *xi_max,
                            px_spread_regime_t *regime);

#ifdef __cplusplus
}
#endif

#endif
