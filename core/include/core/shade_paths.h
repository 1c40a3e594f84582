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

#endif
