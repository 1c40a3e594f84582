/* shade_paths.h -- shading entry points for renderers that follow known paths of a ray tree
 * (the pencil renderer of the 1987 paper's section 4.1, and beam tracing to come) rather than
 * spawning every child: each gives bit for bit what the corresponding part of shade.h gives,
 * and does less work. The exact renderer does not use them. Implemented in core/src/shade.c,
 * beside the functions they must agree with. Thread-safe, no allocation. */
#ifndef CORE_SHADE_PATHS_H
#define CORE_SHADE_PATHS_H

#include <math.h>
#include <stdint.h>

#include "core/shade.h"
#include "paraxial/system.h"
#include "paraxial/vec3.h"

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

/** rt_shade_child_ray() for a white ray of index `ior` arriving along d at the point p of primitive
 *  `prim`, at the surface record rt_shade_surface() makes of that hit (its normal from
 *  rt_prim_normal()), bit for bit, without building the record: only what rt_shade_child_ray()
 *  reads of it (the normal facing the ray, the material's kr, kt, T and ior, the two indices, the
 *  point and the primitive), not the texel, the copy of the hit nor the call chain. For walks that
 *  take a child at every step of a known path (the pencil's exact walks, pencil/src/eval.c).
 *  Returns 1 with *out, or 0, as rt_shade_child_ray() does (on 0 *out may be partly written,
 *  where rt_shade_child_ray() leaves it alone); -1 where that needs the mirror child's
 *  weight (a plan without reflection, kr <= 0, or a negative share of the refraction): the caller
 *  then asks rt_shade_child_ray() with the whole record.
 *
 *  Inline, and apart from the exact renderer's code: its expressions are those of
 *  rt_shade_surface(), rt__refract_ray(), reflect_child() and rt__offset_origin() in shade.c and
 *  refract.c, in the same order, so they round alike (the build contracts no product into an
 *  FMA), with Snell's law and the mirror law from the same px_interface_outgoing(). Sharing them
 *  as helpers changes the exact renderer's register allocation and costs it instructions
 *  (refract.c), so they are copies that change together: tests/test_render_shade.c compares
 *  the two functions bit for bit. */
static inline int rt_shade_walk_ray(const rt_scene_t *s, const rt_plan_t *plan, int prim,
                                    px_vec3_t p, px_vec3_t d, double ior, int depth,
                                    rt_ray_kind_t kind, rt_ray_t *out) {
  if (depth >= plan->max_depth)
    return 0;
  const rt_material_t *m = rt_scene_material_at(s, prim, p, NULL);
  px_event_t ev;
  double side;
  if (kind == RT_RAY_REFRACT) {
    if (!(rt_plan_has(plan, RT_EFFECT_REFRACTION) && m->kt > 0.0))
      return 0;
    ev = PX_EVENT_REFRACT;
    side = -1.0;
  } else if (kind == RT_RAY_REFLECT) {
    /* rt_shade_child_ray()'s mirror child of weight kr > 0; the other cases need the weight */
    if (!(rt_plan_has(plan, RT_EFFECT_REFLECTION) && m->kr > 0.0 && m->kt >= 0.0 &&
          m->transmittance.r >= 0.0 && m->transmittance.g >= 0.0 && m->transmittance.b >= 0.0))
      return -1;
    ev = PX_EVENT_REFLECT;
    side = 1.0;
  } else {
    return 0;
  }
  px_vec3_t n = rt_prim_normal_at(&s->prim[prim], p);
  double dn = px_v3_dot(n, d); /* rt_shade_surface() */
  px_vec3_t nf = dn < 0.0 ? n : px_v3_scale(n, -1.0);
  double n2 = ev == PX_EVENT_REFLECT ? ior : dn < 0.0 ? m->ior : s->ior;
  px_interface_t ifc = {.s = d, .nu = px_v3_scale(nf, -1.0), .n1 = ior, .n2 = n2};
  double ax = fabs(p.x), ay = fabs(p.y), az = fabs(p.z); /* rt__offset_origin() */
  double scale = 1.0 + (ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az));
  out->o = px_v3_axpy(side * RT_SURFACE_OFFSET * scale, nf, p); /* first: less kept over the call */
  double co;
  if (px_interface_outgoing(&ifc, ev, &out->d, &co) != PX_OK)
    return 0;
  out->tmin = 0.0;
  out->tmax = INFINITY;
  out->ior = n2;
  out->skip_prim = s->prim[prim].kind != RT_PRIM_SPHERE ? prim : -1;
  out->lambda = 0.0f;
  return 1;
}

/** Four white rays along one known path, as structure of arrays; each lane's tmin is 0 and its
 *  tmax infinite, as for every ray rt_shade_walk_ray() makes. */
typedef struct {
  px_vec3x4_t o, d; /**< origins and unit directions */
  double ior[4];    /**< index of the medium each travels in */
  int skip_prim;    /**< as rt_ray_t.skip_prim, the same for the four */
} rt_ray4_t;

/** rt_shade_walk_ray() for four rays arriving along d at the points p of primitive `prim`, in
 *  media of indices ior, lane by lane bit for bit (core/src/walk4.c): got[i] is what
 *  rt_shade_walk_ray() returns for lane i (1, 0 or -1) and, where it is 1, out's lane i its ray.
 *  Lanes whose bit in `lanes` is clear get 0. Four lanes at a time where px_simd4_available()
 *  and the primitive has one material (no checkerboard), else lane by lane. */
void rt_shade_walk_ray4(const rt_scene_t *s, const rt_plan_t *plan, int prim, const px_vec3x4_t *p,
                        const px_vec3x4_t *d, const double ior[4], int depth, rt_ray_kind_t kind,
                        unsigned lanes, rt_ray4_t *out, int got[4]);

/** rt_prim_intersect() for four rays o + t d with tmin 0 and tmax infinite: bit i of the result
 *  is set, and t[i] and the point hit[i] = px_v3_axpy(t[i], d[i], o[i]) written, where lane i (its
 *  bit set in `lanes`) meets `prim`, lane by lane bit for bit. Four at a time where
 *  px_simd4_available() (a polygon's inside test lane by lane); other lanes of t and hit may be
 *  written too. */
unsigned rt_prim_intersect4(const rt_scene_t *s, int prim, const px_vec3x4_t *o,
                            const px_vec3x4_t *d, unsigned lanes, double t[4], px_vec3x4_t *hit);

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

/** Distinct events an rt_spectral_rec_t keeps, and primitives per event. */
#define RT_SPECTRAL_REC_EVENTS 48
#define RT_SPECTRAL_EVENT_PRIMS 4

/** What rt_shade_spectral_rec() saw of the spectral pencils it traced, for a renderer that
 *  interpolates their light between neighbouring white rays (the pencil renderer's lattice): two
 *  white rays whose records have the same `sig` met the same surfaces in the same ways (the same
 *  events); the light between them may still be met by an object that lies between their pencils,
 *  which the boxes of each event's segments bound (rt_sweep_meets_others()). */
typedef struct {
  uint64_t sig; /**< a hash of the set of events (a pencil's hit: its generation, the primitive,
                     the ray's kind, the side, the checker square, total internal reflection; a
                     miss; the white ray's refraction or its total internal reflection); 0 when
                     `unusable` */
  int nev;      /**< distinct events, in the order of their hashes once traced */
  uint64_t ev[RT_SPECTRAL_REC_EVENTS]; /**< their hashes */
  /** per event, the bounds of the segments that end there: their origins (lo x, y, z, hi x, y,
   *  z) and their ends (the hit; for a miss, where the ray leaves the bounds of the scene's
   *  bounded primitives: beyond them a plane can meet a ray between two that miss it only if
   *  their directions straddle its horizon, which they do not where they all miss), the rays the
   *  checks at the pencils' ends traced included */
  double from[RT_SPECTRAL_REC_EVENTS][6], to[RT_SPECTRAL_REC_EVENTS][6];
  /** per event, the primitive it hits (-1 for a miss) and those its segments leave, -1 after the
   *  last: what rt_sweep_meets_others() may skip for that event's segments */
  int prim[RT_SPECTRAL_REC_EVENTS][RT_SPECTRAL_EVENT_PRIMS];
  /** Why the light cannot be interpolated (0: it can): 1 more events, or more primitives to an
   *  event, than the record holds, 2 a hit shaded by a light (a shadow or highlight may lie
   *  between two white rays' pencils), 3 a concave polygon met, 4 the cut budget spent, 5 a point
   *  not finite. */
  int unusable;
} rt_spectral_rec_t;

/** rt_shade_spectral() recording in *rec what its pencils met (rec NULL: rt_shade_spectral();
 *  with tr NULL nothing is traced and rec->sig is 0). */
rt_rgb_t rt_shade_spectral_rec(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                               const rt_ray_t *ray, int depth, const rt_tracer_t *tr,
                               rt_child_t *mirror, int *nmirror, rt_spectral_rec_t *rec);

/** A spectral pencil that is already past the white ray's refraction: `ray` at the centre u_c of
 *  [ua, ub] on the plan's wavelength axis (its origin on the surface it leaves, ray->skip that
 *  primitive; its ior and lambda are set here), d_o and d_d the derivatives in u of its origin and
 *  unit direction (the wavelength column of [P89] Eq. 13 as world vectors), travelling in medium
 *  `inside` (NULL: the scene's); `glass` the material whose index the axis makes linear, `weight`
 *  the largest channel of the weights that carry its light to the eye. Traced as
 *  rt_shade_spectral()'s pencils below the refraction (cut where the spectrum parts), its
 *  radiance times the colour weights' integral over the interval. The beam renderer's solids
 *  trace what they cannot draw with it (beam/src/render.c). */
rt_rgb_t rt_shade_spectral_ray(const rt_scene_t *s, const rt_plan_t *plan, const rt_ray_t *ray,
                               px_vec3_t d_o, px_vec3_t d_d, double ua, double ub,
                               const rt_material_t *inside, const rt_material_t *glass,
                               double weight, int depth, const rt_tracer_t *tr);

/** rt_shade_spectral()'s mirror child alone (returned: 1, or 0 when it has no weight), bit for bit,
 *  without tracing the refracted light. */
int rt_shade_spectral_mirror(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                             const rt_ray_t *ray, int depth, rt_child_t *mirror);

#endif
