/* quadric.h -- the real surfaces of the exact tracer: quadrics F(p) = p^t M p + 2 b.p + c = 0.
 *
 * Planes, spheres (both ways round), cylinders at any orientation and ellipsoids are all
 * quadrics, so one intersection routine serves them all. The curvature matrix Q that
 * libparaxial's Eq. (2) needs is read off the Hessian 2M (docs/conventions.md).
 */
#ifndef EXACT_QUADRIC_H
#define EXACT_QUADRIC_H

#include "paraxial/paraxial.h"

typedef struct {
  double m[9]; /**< symmetric 3x3 M, row-major */
  double b[3]; /**< linear part: F = p^t M p + 2 b.p + c */
  double c;    /**< constant part */
} ex_quadric_t;

/** Plane through `point` with normal `normal` (need not be unit). */
ex_quadric_t ex_quadric_plane(px_vec3_t point, px_vec3_t normal);
/** Sphere |p - centre| = r, r > 0. */
ex_quadric_t ex_quadric_sphere(px_vec3_t centre, double r);
/** Infinite circular cylinder of radius r about the line through `point` along `axis`. */
ex_quadric_t ex_quadric_cylinder(px_vec3_t point, px_vec3_t axis, double r);
/** Ellipsoid with centre, orthonormal axes e1, e2, e3 (rows of `axes`) and semi-axes a, b, c. */
ex_quadric_t ex_quadric_ellipsoid(px_vec3_t centre, const px_vec3_t axes[3], double a, double b,
                                  double c);

double ex_quadric_eval(const ex_quadric_t *q, px_vec3_t p);
/** Half the gradient: M p + b. */
px_vec3_t ex_quadric_half_gradient(const ex_quadric_t *q, px_vec3_t p);

/** The local geometry where a ray of direction s meets the quadric at p, as libparaxial's
 *  interface: nu = normalised gradient oriented along s, Q from the Hessian projected on the
 *  tangent plane, u2 = normal of the plane of incidence (hint at normal incidence). */
px_status_t ex_quadric_interface(const ex_quadric_t *q, px_vec3_t p, px_vec3_t s, px_vec3_t hint,
                                 double n1, double n2, px_interface_t *out);

/** Third derivatives of the surface height w(t1, t2) along ifc->nu at p (the cubic term of
 *  w = 1/2 t^T Q t + 1/6 c[t,t,t] + ...), as (c111, c112, c122, c222) in ifc's (u1, u2) basis;
 *  ifc must come from ex_quadric_interface() at p. d_3m of A-1 is their largest magnitude.
 *  Spheres and cylinders give 0 everywhere (M nu is parallel to nu); an ellipsoid away from
 *  its vertices does not. PX_ESINGULAR when the gradient vanishes. */
px_status_t ex_quadric_cubic(const ex_quadric_t *q, px_vec3_t p, const px_interface_t *ifc,
                             double cubic[4]);

#endif
