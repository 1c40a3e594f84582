/* prim.h -- private: the ray-primitive tests (course notes 1.7.1.3 sphere, 1.7.1.4 plane; an
 * even-odd crossing test for polygons, exact for concave ones), as inline functions so that the
 * BVH traversal in query.c can inline them. intersect.c exports them. */
#ifndef RENDER_PRIM_H
#define RENDER_PRIM_H

#include <math.h>

#include "core/scene.h"
#include "paraxial/vec3.h"

/** The slab test's ordered min and max: a < b ? a : b and a > b ? a : b, the second operand
 *  when either is NaN. Unlike px_min and px_max (paraxial/vec3.h) they drop a NaN of the first
 *  operand; the slab test in query.c relies on that for rays parallel to a slab (0 * inf). */
static inline double ordered_min(double a, double b) {
  return a < b ? a : b;
}
static inline double ordered_max(double a, double b) {
  return a > b ? a : b;
}

/* Roots of |o + t d - c|^2 = r^2 for unit d, ascending; 0 on a miss. The discriminant is taken
 * as r^2 - |oc - (oc.d) d|^2 (squared distance of the line from the centre), which does not
 * cancel catastrophically for distant spheres, and the near root from the product of the roots,
 * (|oc| - r)(|oc| + r), which is accurate for origins on or near the surface. */
static inline int sphere_roots(const rt_sphere_t *sp, const rt_ray_t *ray, double t[2]) {
  px_vec3_t oc = px_v3_sub(ray->o, sp->c);
  double b = px_v3_dot(oc, ray->d);
  px_vec3_t perp = px_v3_axpy(-b, ray->d, oc);
  double disc = (sp->r - px_v3_norm(perp)) * (sp->r + px_v3_norm(perp));
  if (disc < 0.0)
    return 0;
  double q = -b - copysign(sqrt(disc), b); /* the root of larger magnitude */
  double len = px_v3_norm(oc);
  double prod = (len - sp->r) * (len + sp->r); /* t0 t1 */
  double t1 = q, t2 = q != 0.0 ? prod / q : 0.0;
  t[0] = ordered_min(t1, t2);
  t[1] = ordered_max(t1, t2);
  return 2;
}

/* Even-odd crossing test of (px, py) against the polygon's vertices projected on axes ia, ib.
 * A point on an edge shared by two faces is counted in exactly one of them (half-open rule in
 * y). Called with constant axes so that the component selection folds away. */
static inline int polygon_inside_2d(const px_vec3_t *v, int count, int ia, int ib, double px,
                                    double py) {
  int inside = 0;
  double xj = px_v3_at(v[count - 1], ia), yj = px_v3_at(v[count - 1], ib);
  for (int i = 0; i < count; i++) { /* edge from vertex j = i - 1 to vertex i */
    double xi = px_v3_at(v[i], ia), yi = px_v3_at(v[i], ib);
    if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi)
      inside = !inside;
    xj = xi;
    yj = yi;
  }
  return inside;
}

/* Even-odd test of p against the polygon projected along its dominant axis. */
static inline int polygon_inside(const rt_scene_t *s, const rt_polygon_t *pg, px_vec3_t p) {
  const px_vec3_t *v = s->vertex + pg->first;
  switch (pg->axis) {
  case 0:
    return polygon_inside_2d(v, pg->count, 1, 2, p.y, p.z);
  case 1:
    return polygon_inside_2d(v, pg->count, 0, 2, p.x, p.z);
  default:
    return polygon_inside_2d(v, pg->count, 0, 1, p.x, p.y);
  }
}

/* Distance to the plane n.x = d along the ray; 0 when parallel or outside (tmin, tmax). */
static inline int plane_t(px_vec3_t n, double d, const rt_ray_t *ray, double tmax, double *t) {
  double den = px_v3_dot(n, ray->d);
  if (den == 0.0)
    return 0;
  double tt = (d - px_v3_dot(n, ray->o)) / den;
  if (!(tt > ray->tmin && tt < tmax))
    return 0;
  *t = tt;
  return 1;
}

/* Nearest crossing in (ray->tmin, tmax); the body of rt_prim_intersect(), inlined into the BVH
 * traversal. */
static inline int prim_hit(const rt_scene_t *s, int prim, const rt_ray_t *ray, double tmax,
                           double *t) {
  const rt_prim_t *p = &s->prim[prim];
  switch (p->kind) {
  case RT_PRIM_SPHERE: {
    double r[2];
    if (!sphere_roots(&p->sphere, ray, r))
      return 0;
    if (r[0] > ray->tmin && r[0] < tmax) {
      *t = r[0];
      return 1;
    }
    if (r[1] > ray->tmin && r[1] < tmax) {
      *t = r[1];
      return 1;
    }
    return 0;
  }
  case RT_PRIM_PLANE:
    return plane_t(p->plane.n, px_v3_dot(p->plane.n, p->plane.p), ray, tmax, t);
  case RT_PRIM_POLYGON: {
    double tt;
    if (!plane_t(p->polygon.n, p->polygon.d, ray, tmax, &tt) ||
        !polygon_inside(s, &p->polygon, px_v3_axpy(tt, ray->d, ray->o)))
      return 0;
    *t = tt;
    return 1;
  }
  }
  return 0;
}

/* Every crossing in (ray->tmin, ray->tmax), ascending: the body of rt_prim_crossings(), inlined
 * into the shadow query. */
static inline int prim_crossings(const rt_scene_t *s, int prim, const rt_ray_t *ray, double t[2]) {
  const rt_prim_t *p = &s->prim[prim];
  if (p->kind != RT_PRIM_SPHERE)
    return prim_hit(s, prim, ray, ray->tmax, t);
  double r[2];
  int n = 0;
  if (!sphere_roots(&p->sphere, ray, r))
    return 0;
  for (int k = 0; k < 2; k++)
    if (r[k] > ray->tmin && r[k] < ray->tmax)
      t[n++] = r[k];
  return n;
}

#endif
