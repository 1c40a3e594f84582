/* intersect.c -- ray-primitive intersection (course notes 1.7.1.3 sphere, 1.7.1.4 plane) and a
 * point-in-polygon test that also holds for concave polygons. */
#include "render/intersect.h"

#include <math.h>

/* Roots of |o + t d - c|^2 = r^2 for unit d, ascending; 0 on a miss. The discriminant is taken
 * as r^2 - |oc - (oc.d) d|^2 (squared distance of the line from the centre), which does not
 * cancel catastrophically for distant spheres, and the near root from the product of the roots,
 * (|oc| - r)(|oc| + r), which is accurate for origins on or near the surface. */
static int sphere_roots(const rt_sphere_t *sp, const rt_ray_t *ray, double t[2]) {
  px_vec3_t oc = px_vec3_sub(ray->o, sp->c);
  double b = px_vec3_dot(oc, ray->d);
  px_vec3_t perp = px_vec3_axpy(-b, ray->d, oc);
  double disc = (sp->r - px_vec3_norm(perp)) * (sp->r + px_vec3_norm(perp));
  if (disc < 0.0)
    return 0;
  double q = -b - copysign(sqrt(disc), b); /* the root of larger magnitude */
  double len = px_vec3_norm(oc);
  double prod = (len - sp->r) * (len + sp->r); /* t0 t1 */
  double t1 = q, t2 = q != 0.0 ? prod / q : 0.0;
  t[0] = fmin(t1, t2);
  t[1] = fmax(t1, t2);
  return 2;
}

static double coord(px_vec3_t v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

/* Even-odd crossing test of p against the polygon projected along its dominant axis. A point on
 * an edge shared by two faces is counted in exactly one of them (half-open rule in y). */
static int polygon_inside(const rt_scene_t *s, const rt_polygon_t *pg, px_vec3_t p) {
  int ia = pg->axis == 0 ? 1 : 0, ib = pg->axis == 2 ? 1 : 2;
  double px = coord(p, ia), py = coord(p, ib);
  const px_vec3_t *v = s->vertex + pg->first;
  int inside = 0;
  for (int i = 0, j = pg->count - 1; i < pg->count; j = i++) {
    double xi = coord(v[i], ia), yi = coord(v[i], ib), xj = coord(v[j], ia), yj = coord(v[j], ib);
    if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi)
      inside = !inside;
  }
  return inside;
}

/* Distance to the plane n.x = d along the ray; 0 when parallel or outside (tmin, tmax). */
static int plane_t(px_vec3_t n, double d, const rt_ray_t *ray, double tmax, double *t) {
  double den = px_vec3_dot(n, ray->d);
  if (den == 0.0)
    return 0;
  double tt = (d - px_vec3_dot(n, ray->o)) / den;
  if (!(tt > ray->tmin && tt < tmax))
    return 0;
  *t = tt;
  return 1;
}

int rt_prim_intersect(const rt_scene_t *s, int prim, const rt_ray_t *ray, double tmax, double *t) {
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
    return plane_t(p->plane.n, px_vec3_dot(p->plane.n, p->plane.p), ray, tmax, t);
  case RT_PRIM_POLYGON: {
    double tt;
    if (!plane_t(p->polygon.n, p->polygon.d, ray, tmax, &tt) ||
        !polygon_inside(s, &p->polygon, px_vec3_axpy(tt, ray->d, ray->o)))
      return 0;
    *t = tt;
    return 1;
  }
  }
  return 0;
}

int rt_prim_crossings(const rt_scene_t *s, int prim, const rt_ray_t *ray, double t[2]) {
  const rt_prim_t *p = &s->prim[prim];
  if (p->kind != RT_PRIM_SPHERE)
    return rt_prim_intersect(s, prim, ray, ray->tmax, t);
  double r[2];
  int n = 0;
  if (!sphere_roots(&p->sphere, ray, r))
    return 0;
  for (int k = 0; k < 2; k++)
    if (r[k] > ray->tmin && r[k] < ray->tmax)
      t[n++] = r[k];
  return n;
}

px_vec3_t rt_prim_normal(const rt_scene_t *s, int prim, px_vec3_t p) {
  const rt_prim_t *pr = &s->prim[prim];
  switch (pr->kind) {
  case RT_PRIM_SPHERE:
    return px_vec3_scale(px_vec3_sub(p, pr->sphere.c), 1.0 / pr->sphere.r);
  case RT_PRIM_PLANE:
    return pr->plane.n;
  case RT_PRIM_POLYGON:
    return pr->polygon.n;
  }
  return px_vec3(0, 0, 1);
}

int rt_prim_bounds(const rt_scene_t *s, int prim, px_vec3_t *lo, px_vec3_t *hi) {
  const rt_prim_t *p = &s->prim[prim];
  if (p->kind == RT_PRIM_SPHERE) {
    px_vec3_t r = px_vec3(p->sphere.r, p->sphere.r, p->sphere.r);
    *lo = px_vec3_sub(p->sphere.c, r);
    *hi = px_vec3_add(p->sphere.c, r);
    return 1;
  }
  if (p->kind != RT_PRIM_POLYGON)
    return 0;
  const px_vec3_t *v = s->vertex + p->polygon.first;
  *lo = *hi = v[0];
  for (int i = 1; i < p->polygon.count; i++) {
    *lo = px_vec3(fmin(lo->x, v[i].x), fmin(lo->y, v[i].y), fmin(lo->z, v[i].z));
    *hi = px_vec3(fmax(hi->x, v[i].x), fmax(hi->y, v[i].y), fmax(hi->z, v[i].z));
  }
  return 1;
}
