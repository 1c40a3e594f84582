/* shade_impl.h -- private: the refraction part of shading lives in refract.c, so that a plan
 * without refraction never enters it. */
#ifndef RENDER_SHADE_IMPL_H
#define RENDER_SHADE_IMPL_H

#include "core/shade.h"
#include "core/shade_paths.h"

/** Offset origin for a secondary ray leaving the surface on the side `side` (+1: the side the
 *  incoming ray came from, -1: the far side). */
px_vec3_t rt__offset_origin(const rt_surface_t *sf, double side);

/** Build the refracted child of a transparent surface (kt > 0). Returns 1 and fills *child when
 *  a refracted ray exists (child NULL: only says whether); adds to *extra_reflect the weight
 *  that reflects instead (Fresnel share, or everything after total internal reflection, when
 *  *tir is set). */
/** The index of m's interior at lambda nm (its model; m->ior should the model fail, which the
 *  scene loader rules out over 380-780 nm). */
double rt__index_at(const rt_material_t *m, double lambda);

/** Spectral pencils (wpencil.c) for the white ray `ray` refracting at the dispersive surface sf
 *  under a plan with RT_SPECTRAL_PENCIL: the transmitted radiance; adds to *wr what reflects
 *  instead (Fresnel shares, total internal reflection) and clears *all_tir unless every
 *  wavelength reflects totally. With tr NULL only the latter, nothing traced. rec (with tr): what
 *  the pencils met (rt_shade_spectral_rec()), or NULL. */
rt_rgb_t rt__wp_refract(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                        const rt_ray_t *ray, int depth, const rt_tracer_t *tr, rt_rgb_t *wr,
                        int *all_tir, rt_spectral_rec_t *rec);

/** The object of face q when q is a face of a convex polyhedron (rt_object_t.alone) and the n
 *  points v lie on the outer side of its plane (touching at most), else -1: no other face of
 *  that object can meet a triangle of those points (wpencil.c's band between a pencil's rays). */
int rt__wp_beside_face(const rt_scene_t *s, int q, const px_vec3_t *v, int n);

/** The refracted ray of rt__shade_refract() alone (0 under total internal reflection). */
int rt__refract_ray(const rt_scene_t *s, const rt_surface_t *sf, const rt_ray_t *ray,
                    rt_ray_t *out);

int rt__shade_refract(const rt_scene_t *s, const rt_surface_t *sf, const rt_ray_t *ray,
                      rt_child_t *child, rt_rgb_t *extra_reflect, int *tir);

#endif
