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

#endif
