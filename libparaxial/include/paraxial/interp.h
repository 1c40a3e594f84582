/* interp.h -- ray interpolation (paper section 4.1 (2), Fig. 5).
 *
 * Two traced rays psi0 and psi0 + delta give intersections x'0 and x'1; the ray psi0 + a delta is
 * taken to meet the object at x' = a x'1 + (1 - a) x'0. With a third ray psi0 - delta (x'_-1) the
 * error of that linear guess is estimated by e_int = |second-order - linear interpolation|, which
 * simplifies to |a (a - 1) / 2| |x'_-1 - 2 x'0 + x'1| (the printed second-order formula expanded).
 * Vectors are caller-owned arrays of length n; nothing allocates.
 */
#ifndef PARAXIAL_INTERP_H
#define PARAXIAL_INTERP_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/** out = a x1 + (1 - a) x0. `out` may alias x0 or x1. */
void px_interp_linear(size_t n, const double *x0, const double *x1, double a, double *out);

/** Second-order interpolation through (-1, xm1), (0, x0), (1, x1) at a (section 4.1 (2)):
 *  a(a-1)/2 xm1 + (1-a)(1+a) x0 + a(1+a)/2 x1. `out` may alias an input. */
void px_interp_quadratic(size_t n, const double *xm1, const double *x0, const double *x1, double a,
                         double *out);

/** e_int at a: Euclidean norm of quadratic minus linear interpolation. */
double px_interp_error(size_t n, const double *xm1, const double *x0, const double *x1, double a);

/** The largest e_int over a in [0, 1]: |x'_-1 - 2 x'0 + x'1| / 8 (attained at a = 1/2). */
double px_interp_error_max(size_t n, const double *xm1, const double *x0, const double *x1);

/** Bilinear interpolation inside a cell with corners c00 (u=0,v=0), c10 (u=1), c01 (v=1), c11,
 *  each of length n, at (u, v) in [0, 1]^2. */
void px_interp_bilinear(size_t n, const double *c00, const double *c10, const double *c01,
                        const double *c11, double u, double v, double *out);

#ifdef __cplusplus
}
#endif

#endif
