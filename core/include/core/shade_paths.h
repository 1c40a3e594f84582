/* shade_paths.h -- shading entry points for renderers that follow known paths of a ray tree
 * (the pencil renderer of the 1987 paper's section 4.1, and beam tracing to come) rather than
 * spawning every child: each gives bit for bit what the corresponding part of shade.h gives,
 * and does less work. The exact renderer does not use them. Implemented in core/src/shade.c,
 * beside the functions they must agree with. Thread-safe, no allocation. */
#ifndef CORE_SHADE_PATHS_H
#define CORE_SHADE_PATHS_H

#include "core/shade.h"

/** rt_shade_direct() at one point for its own material (out[0]) and for `other` in its place
 *  (out[1]), each bit for bit as rt_shade_direct() gives it, with each light's direction and
 *  shadow transmittance found once for both: a checkerboard's two materials at a lattice point
 *  of the pencil tracer. */
void rt_shade_direct2(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                      const rt_material_t *other, const rt_ray_t *ray, const rt_tracer_t *tr,
                      rt_rgb_t out[2]);

/** The one child of rt_shade_children() of the given kind (RT_RAY_REFLECT, including a total
 *  internal reflection, or RT_RAY_REFRACT), bit for bit the same ray and weight, without building
 *  the other: for a renderer that follows a known path of the ray tree. Returns 0, as
 *  rt_shade_children() returns no such child, at the depth limit, when the plan or the material
 *  has no such effect, for a mirror child of zero weight and for refraction under total internal
 *  reflection. */
int rt_shade_child(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                   const rt_ray_t *ray, int depth, rt_ray_kind_t kind, rt_child_t *out);

/** rt_shade_child()'s ray alone, bit for bit, for walks that need only where a known path goes
 *  (the pencil's exact walks along its paths): its weight is not computed where it cannot decide
 *  whether the child exists (a refraction's Fresnel split; a mirror child with kr > 0 under a plan
 *  with reflection). Returns 0 exactly where rt_shade_child() does. */
int rt_shade_child_ray(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                       const rt_ray_t *ray, int depth, rt_ray_kind_t kind, rt_ray_t *out);

/** 1 when a white ray of generation `depth` meeting material m draws dispersion by spectral
 *  pencils under the plan (RT_SPECTRAL_PENCIL; m transparent and dispersive; children possible):
 *  where rt_shade_hit() calls rt_shade_spectral() instead of spawning the refracted child. */
int rt_shade_spectral_at(const rt_plan_t *plan, const rt_material_t *m, int depth);

/** At such a hit: the refracted light by spectral pencils (core/src/wpencil.c, docs/spectral.md
 *  section 3a), returned with its weights (kt T, Fresnel) applied; and the white mirror child in
 *  *mirror (*nmirror 1, or 0 when it has no weight), weighted by kr plus the shares that reflect
 *  instead of refracting. rt_shade_hit() adds the mirror child's radiance to the return value;
 *  a renderer that follows known paths does so itself. tr: its count() and occluded() only. */
rt_rgb_t rt_shade_spectral(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                           const rt_ray_t *ray, int depth, const rt_tracer_t *tr,
                           rt_child_t *mirror, int *nmirror);

/** rt_shade_spectral()'s mirror child alone (returned: 1, or 0 when it has no weight), bit for bit,
 *  without tracing the refracted light. */
int rt_shade_spectral_mirror(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                             const rt_ray_t *ray, int depth, rt_child_t *mirror);

#endif
