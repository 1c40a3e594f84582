/* intersect.h -- ray-surface intersection: the primitive tests (course notes 1.7.1.3-1.7.1.4)
 * and the scene queries through the BVH (textbook 9.1 "Intersect(r)", 9.2 acceleration).
 *
 * All functions are thread-safe on a prepared scene and allocate nothing.
 */
#ifndef RENDER_INTERSECT_H
#define RENDER_INTERSECT_H

#include "core/scene.h"
#include "paraxial/vec3.h"

/** Nearest distance t in (ray->tmin, tmax) at which the ray meets primitive `prim`; returns 1
 *  and writes *t, or 0 when there is none. Spheres use the cancellation-free form of the
 *  quadratic; polygons an even-odd crossing test, so concave polygons are exact. */
int rt_prim_intersect(const rt_scene_t *s, int prim, const rt_ray_t *ray, double tmax, double *t);

/** Every distance in (ray->tmin, ray->tmax) at which the ray crosses primitive `prim` (at most
 *  2), ascending; returns how many. Used by shadow rays, which see all occluders. */
int rt_prim_crossings(const rt_scene_t *s, int prim, const rt_ray_t *ray, double t[2]);

/** Unit geometric normal of `prim` at p (a point on it): outward for spheres and polyhedra. */
px_vec3_t rt_prim_normal(const rt_scene_t *s, int prim, px_vec3_t p);

/** rt_prim_normal() of the primitive pr, inline: the body the scene queries and the pencil's
 *  exact walks along its paths inline (there the call costs about as much as the normal). */
static inline px_vec3_t rt_prim_normal_at(const rt_prim_t *pr, px_vec3_t p) {
  switch (pr->kind) {
  case RT_PRIM_SPHERE: { /* (p - c) / |p - c|: unit to rounding even when p is off by an ulp */
    px_vec3_t d = px_v3_sub(p, pr->sphere.c);
    return px_v3_scale(d, 1.0 / px_v3_norm(d));
  }
  case RT_PRIM_PLANE:
    return pr->plane.n;
  case RT_PRIM_POLYGON:
    return pr->polygon.n;
  }
  return px_v3(0, 0, 1);
}

/** Axis-aligned bounds of a bounded primitive (sphere, polygon); 0 for a plane. */
int rt_prim_bounds(const rt_scene_t *s, int prim, px_vec3_t *lo, px_vec3_t *hi);

/** Bounds of the scene's bounded primitives (the BVH's root box); 0 when it has none. */
int rt_scene_bounds(const rt_scene_t *s, double lo[3], double hi[3]);

/** Whether a primitive other than skip[0 .. nskip) may meet a segment from the box `from` to
 *  the box `to` (each lo x, y, z, hi x, y, z): such a segment lies in the box swept from `from`
 *  to `to`, (1 - t) from + t to for t in [0, 1], which is tested against a bounded primitive's
 *  own bounds and against a plane exactly. The other primitives of a listed primitive's object
 *  are skipped too when that object is alone (rt_object_t.alone: convex, nothing else enters
 *  its bounds), as a ray that leaves a convex body does not meet it again, and a ray inside it
 *  meets the face it leaves by first. 1 for boxes that are empty or not numbers. */
int rt_sweep_meets_others(const rt_scene_t *s, const double from[6], const double to[6],
                          const int *skip, int nskip);

/** Nearest hit of the ray with the scene (BVH plus unbounded planes). Returns 1 and fills *hit,
 *  or 0 on a miss. The scene must be prepared. */
int rt_intersect(const rt_scene_t *s, const rt_ray_t *ray, rt_hit_t *hit);

/** The closed object that holds point p: the one whose surface a ray from p meets first from
 *  inside (the innermost, when closed objects nest without crossing), or -1. A point on a surface
 *  counts on the side the probe ray leaves by. */
int rt_medium_object(const rt_scene_t *s, px_vec3_t p);

/** The refractive index of the medium at p: rt_medium_object()'s material's, or the scene's
 *  (settings.ior). A light's rays start in it. */
double rt_medium_ior(const rt_scene_t *s, px_vec3_t p);

/** The same by testing every primitive (no BVH); for tests of the BVH. */
int rt_intersect_brute(const rt_scene_t *s, const rt_ray_t *ray, rt_hit_t *hit);

/** Light transmitted along the shadow segment [ray->tmin, ray->tmax] (textbook 9.1): the
 *  product over the transparent objects it passes through of kt * transmittance, counted once
 *  per passage (an exit crossing of a closed object; any crossing of an open surface); black as
 *  soon as an opaque surface is met. White when nothing is in the way. */
rt_rgb_t rt_transmittance(const rt_scene_t *s, const rt_ray_t *ray);
/** rt_transmittance(), and in *blocker the object whose surface blocked the light, or -1 when
 *  none did: the first the search met, which need not be the nearest when several are in the
 *  way. */
rt_rgb_t rt_transmittance_blocker(const rt_scene_t *s, const rt_ray_t *ray, int *blocker);

#endif
