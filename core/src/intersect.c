/* intersect.c -- ray-primitive intersection (course notes 1.7.1.3 sphere, 1.7.1.4 plane) and a
 * point-in-polygon test that also holds for concave polygons: the exported wrappers of prim.h,
 * crossings for shadow rays, normals and bounds. */
#include "core/intersect.h"

#include <math.h>

#include "paraxial/vec3.h"
#include "prim.h"

int rt_prim_intersect(const rt_scene_t *s, int prim, const rt_ray_t *ray, double tmax, double *t) {
  return prim_hit(s, prim, ray, tmax, t);
}

int rt_prim_crossings(const rt_scene_t *s, int prim, const rt_ray_t *ray, double t[2]) {
  return prim_crossings(s, prim, ray, t);
}

px_vec3_t rt_prim_normal(const rt_scene_t *s, int prim, px_vec3_t p) {
  return rt_prim_normal_at(&s->prim[prim], p);
}

int rt_prim_bounds(const rt_scene_t *s, int prim, px_vec3_t *lo, px_vec3_t *hi) {
  const rt_prim_t *p = &s->prim[prim];
  if (p->kind == RT_PRIM_SPHERE) {
    px_vec3_t r = px_v3(p->sphere.r, p->sphere.r, p->sphere.r);
    *lo = px_v3_sub(p->sphere.c, r);
    *hi = px_v3_add(p->sphere.c, r);
    return 1;
  }
  if (p->kind != RT_PRIM_POLYGON)
    return 0;
  const px_vec3_t *v = s->vertex + p->polygon.first;
  *lo = *hi = v[0];
  for (int i = 1; i < p->polygon.count; i++) {
    *lo = px_v3(fmin(lo->x, v[i].x), fmin(lo->y, v[i].y), fmin(lo->z, v[i].z));
    *hi = px_v3(fmax(hi->x, v[i].x), fmax(hi->y, v[i].y), fmax(hi->z, v[i].z));
  }
  return 1;
}
