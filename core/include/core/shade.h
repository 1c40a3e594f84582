/* shade.h -- shading, shared by every renderer (textbook 9.1: Trace and AccLightSource).
 *
 * The illumination equation at a surface point is the same whether the point was found by
 * exact ray tracing or by a pencil (paper section 4). This module evaluates it and leaves to
 * the caller only what differs between renderers, "how rays find surfaces", through an
 * rt_tracer_t: a callback for the radiance arriving along a secondary ray and one for the
 * transmittance of a shadow segment. Directions of reflected and refracted rays come from
 * libparaxial's px_interface_outgoing(), so they agree with the exact tracer of reference/ and
 * the system matrices built on the same interface.
 *
 * Typical use by a renderer, for a ray that met a surface:
 *     rt_surface_t sf;
 *     rt_shade_surface(scene, &hit, &ray, &sf);
 *     rt_rgb_t c = rt_shade_hit(scene, plan, &sf, &ray, depth, &tracer);
 * rt_shade_hit() = rt_shade_direct() + sum over rt_shade_children() of weight * tracer child.
 * A renderer that traces children as pencils calls the parts itself; core/shade_paths.h has
 * the entry points for renderers that follow known paths of a ray tree.
 * All functions are thread-safe and allocate nothing.
 */
#ifndef RENDER_SHADE_H
#define RENDER_SHADE_H

#include "core/intersect.h"
#include "core/plan.h"
#include "core/scene.h"

/** Relative offset of secondary-ray origins off the surface, times (1 + |p|_inf): far above
 *  the rounding error of a double-precision hit point (~1e-16 |p|) and far below any feature
 *  of a scene (scene units). */
#define RT_SURFACE_OFFSET 1e-9

/** What shading needs to know about a hit: the point, oriented normals, the material after
 *  texture lookup and the two media. */
typedef struct {
  rt_hit_t hit;
  px_vec3_t nf;             /**< unit normal facing the incoming ray: nf . d < 0 */
  const rt_material_t *mat; /**< material at the point (checker square resolved) */
  int texel;                /**< checker square parity 0/1, or -1 without texture */
  int entering;             /**< 1 when the ray enters the object (hits the outward side) */
  double n1;                /**< index on the incoming side (the ray's medium) */
  double n2;                /**< index on the far side (object's ior entering, scene's leaving) */
} rt_surface_t;

/** A secondary ray spawned at a surface with the weight its radiance carries. */
typedef struct {
  rt_ray_t ray;       /**< origin offset off the surface, unit direction, medium */
  rt_rgb_t weight;    /**< kr, kt T, or the Fresnel-weighted split */
  rt_ray_kind_t kind; /**< RT_RAY_REFLECT or RT_RAY_REFRACT */
  int tir;            /**< 1 for a reflection that carries refracted weight after total
                           internal reflection */
} rt_child_t;

/** The light index of the shadow queries towards an area light's mesh points: beyond every
 *  per-light cache (a mesh point's visibility is not the light's, and no two points share one),
 *  so that a renderer that caches shadows per light index traces these every time. */
#define RT_AREA_SHADOW_INDEX(l) (1024 + (l))

/** Result of one shadow query, reported to the tracer for its ray tree. */
typedef struct {
  int light;        /**< light index (RT_AREA_SHADOW_INDEX(l) for an area light's points) */
  rt_ray_t ray;     /**< the shadow segment: from the point towards the light */
  rt_rgb_t through; /**< transmittance the tracer found (white = unoccluded) */
} rt_shadow_t;

/** What a tracer's occluded() callback computes for q by exact tracing: white when the segment
 *  meets nothing, black when it meets anything (opaque or not). */
static inline void rt_shadow_occluded(const rt_scene_t *s, rt_shadow_t *q) {
  rt_hit_t h;
  q->through = rt_intersect(s, &q->ray, &h) ? rt_rgb(0, 0, 0) : rt_rgb(1, 1, 1);
}
/** rt_shadow_occluded(), returning the object the segment meets (-1: none). */
static inline int rt_shadow_occluded_by(const rt_scene_t *s, rt_shadow_t *q) {
  rt_hit_t h;
  int hit = rt_intersect(s, &q->ray, &h);
  q->through = hit ? rt_rgb(0, 0, 0) : rt_rgb(1, 1, 1);
  return hit ? h.object : -1;
}
/** How a renderer finds surfaces. Both callbacks are called from the thread that shades. */
typedef struct {
  /** Radiance arriving at the surface along child->ray (a generation-`depth` secondary ray,
   *  depth >= 1). The exact tracer intersects the scene and shades recursively. */
  rt_rgb_t (*child)(void *ctx, const rt_child_t *child, int depth);
  /** Transmittance of the segment q->ray (fill q->through); the exact tracer calls
   *  rt_transmittance(). */
  void (*shadow)(void *ctx, rt_shadow_t *q);
  void *ctx; /**< passed through */
  /** Optional (NULL: every query goes to shadow()): 1 with *through filled when the tracer
   *  already knows the transmittance towards light `light` from the surface being shaded (a
   *  renderer that shares shadow queries among neighbouring samples, as the pencil renderer
   *  does per domain), so that the shadow segment is not built; 0 to be asked through
   *  shadow(). */
  int (*known)(void *ctx, int light, rt_rgb_t *through);
  /** Optional (NULL: shadow() is asked, the textbook's shadow): as shadow(), but anything the
   *  segment meets blocks the light, q->through white or black (rt_shadow_occluded()): the
   *  shadow ray of a caustic receiver, whose light through other objects comes from a map
   *  (core/caustics.h). A renderer that draws caustics provides it. */
  void (*occluded)(void *ctx, rt_shadow_t *q);
  /** Optional (NULL: not counted): told of each ray that shading traces itself, not through
   *  child() or shadow() (`what` an rt_ray_kind_t), and of the events of spectral pencils
   *  (RT_COUNT_*), for the caller's statistics (rt_stats_t; core/src/wpencil.c). */
  void (*count)(void *ctx, int what);
  /** 1: the caller keeps the shape of the ray tree and not the radiance (the pencil renderer's
   *  axial and corner rays): shading may skip what only makes radiance and records no node,
   *  the tracing of spectral pencils (their subtrees are not recorded); 0: the radiance. */
  int shape;
} rt_tracer_t;

/** rt_tracer_t.count()'s events of spectral pencils, beside the ray kinds: rt_stats_t.spectral[i]
 *  for RT_COUNT_SPECTRAL + i (a white ray drawn by them, a pencil, a narrow hit). */
#define RT_COUNT_SPECTRAL 16

/** Orient the hit for shading: facing normal, material and texel, media n1 (ray->ior) and n2. */
void rt_shade_surface(const rt_scene_t *s, const rt_hit_t *hit, const rt_ray_t *ray,
                      rt_surface_t *out);

/** Ambient plus, for each light the surface faces, diffuse and specular terms weighted by the
 *  shadow transmittance (textbook's AccLightSource). Shadow rays are cast only when the plan
 *  has RT_EFFECT_SHADOWS; specular terms only with RT_EFFECT_SPECULAR. On a caustic receiver
 *  of a light (plan->maps, core/caustics.h) the shadow ray is opaque and kd colour E of the
 *  light's map is added. */
rt_rgb_t rt_shade_direct(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                         const rt_ray_t *ray, const rt_tracer_t *tr);

/** The coherent children of the hit, at most 2, in out[]: returns how many. Reflection when the
 *  plan has RT_EFFECT_REFLECTION and the material reflects; refraction (or its total internal
 *  reflection) only when the plan has RT_EFFECT_REFRACTION and kt > 0. Children with zero
 *  weight are not returned. `depth` is the generation of the incoming ray; none when
 *  depth >= plan->max_depth. */
int rt_shade_children(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                      const rt_ray_t *ray, int depth, rt_child_t out[2]);

/** The full Whitted shading of a hit by a generation-`depth` ray: direct light plus the
 *  children's radiance from tr->child(). */
rt_rgb_t rt_shade_hit(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                      const rt_ray_t *ray, int depth, const rt_tracer_t *tr);

/** Unpolarised Fresnel reflectance for cosines ci (incident) and ct (transmitted), indices
 *  n1 -> n2; 1 for total internal reflection (ct < 0 is not allowed); exactly 0 when n1 == n2
 *  (an index-matched surface reflects nothing, and no reflected child is spawned). */
double rt_fresnel(double ci, double ct, double n1, double n2);

#endif
