/* builtin.h -- scenes built in C: the paper's Fig. 8 (a transparent sphere over a
 * checkerboard, section 5), a Fig. 11-like transparent polyhedron of 100 polygons over a
 * three-coloured rectangle, and a ~1,000-polygon benchmark scene. scenes/README.md documents
 * the choices (the paper does not give radius, index, camera or light). */
#ifndef RENDER_BUILTIN_H
#define RENDER_BUILTIN_H

#include "core/scene.h"

/** Fig. 8: glass sphere (radius 1, index 1.5) over a checkerboard, one point light, 256 x 256,
 *  9 samples per pixel. `s` must be freshly initialised; it is prepared on return. */
rt_status_t rt_builtin_fig8(rt_scene_t *s);

/** Faceted glass sphere of `stacks` x `slices` polygons (quads, triangles at the poles) over
 *  the Fig. 8 checkerboard; 25 x 40 gives 1,000 polygons. Prepared on return. */
rt_status_t rt_builtin_mesh(rt_scene_t *s, int stacks, int slices);

/** Add a closed faceted sphere (UV polyhedron) of stacks x slices faces. */
rt_status_t rt_scene_add_faceted_sphere(rt_scene_t *s, px_vec3_t c, double r, int stacks,
                                        int slices, int material, int *object);

/** Look a built-in scene up by name ("fig8", "mesh1000"); RT_EINVAL for an unknown name. */
rt_status_t rt_builtin(const char *name, rt_scene_t *s);

#endif
