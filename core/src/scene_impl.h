/* scene_impl.h -- private helpers shared by the scene-building files. */
#ifndef RENDER_SCENE_IMPL_H
#define RENDER_SCENE_IMPL_H

#include "core/scene.h"

/** Append an object of `kind` with `nprim` zeroed primitives (owned by it) and invalidate the
 *  BVH; the caller fills the primitives. */
rt_status_t rt__scene_new_object(rt_scene_t *s, rt_object_kind_t kind, int material, int nprim,
                                 int *object);

/** Append `n` vertices; index of the first in *first. */
rt_status_t rt__scene_push_vertices(rt_scene_t *s, const px_vec3_t *v, int n, int *first);

/** Fill polygon `pr` over vertex[first .. first + n - 1]: Newell normal, offset, dropped axis.
 *  RT_EGEOMETRY when its area vanishes or a vertex is off its plane (the message in why). */
rt_status_t rt__polygon_setup(const rt_scene_t *s, int first, int n, rt_polygon_t *pr,
                              const char **why);

#endif
