/* shade.c -- the illumination equation at a surface point, shared by all renderers (textbook
 * 9.1: Trace(r, d) and AccLightSource(q); course notes 1.7.1.1-1.7.1.2: ambient and diffuse
 * terms; Phong's specular term). Reflected directions come from px_interface_outgoing(), the
 * same vector law that libparaxial's system matrices and reference/'s exact tracer use. */
#include "core/shade.h"
#include "core/caustics.h"
#include "core/shade_paths.h"

#include <math.h>

#include "paraxial/vec3.h"

#include "shade_impl.h"

void rt_shade_surface(const rt_scene_t *s, const rt_hit_t *hit, const rt_ray_t *ray,
                      rt_surface_t *out) {
  double dn = px_v3_dot(hit->n, ray->d);
  out->hit = *hit;
  out->entering = dn < 0.0;
  out->nf = dn < 0.0 ? hit->n : px_v3_scale(hit->n, -1.0);
  out->mat = rt_scene_material_at(s, hit->prim, hit->p, &out->texel);
  out->n1 = ray->ior;
  out->n2 = out->entering ? out->mat->ior : s->ior; /* a monochromatic ray's: spectral() below */
}

double rt__index_at(const rt_material_t *m, double lambda) {
  double n;
  if (px_index_eval(&m->index, lambda, &n, NULL) != PX_OK || !(n > 0.0))
    return m->ior; /* the loader checked every model over 380-780 nm: not reached */
  return n;
}

px_vec3_t rt__offset_origin(const rt_surface_t *sf, double side) {
  px_vec3_t p = sf->hit.p;
  double ax = fabs(p.x), ay = fabs(p.y), az = fabs(p.z); /* p is finite: plain comparisons */
  double scale = 1.0 + (ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az));
  return px_v3_axpy(side * RT_SURFACE_OFFSET * scale, sf->nf, p);
}

static int planar_prim(const rt_scene_t *s, int prim) {
  return s->prim[prim].kind != RT_PRIM_SPHERE;
}

/* Unit direction to light l from p, and the distance (INFINITY for a parallel light). */
static px_vec3_t to_light(const rt_light_t *l, px_vec3_t p, double *dist) {
  if (l->kind == RT_LIGHT_PARALLEL) {
    *dist = INFINITY;
    return px_v3_scale(l->v, -1.0);
  }
  px_vec3_t d = px_v3_sub(l->v, p);
  *dist = px_v3_norm(d);
  if (!(*dist > 0.0) || !isfinite(*dist))
    return px_v3(0, 0, 0); /* light on the surface: contributes nothing (N.L = 0) */
  return px_v3_scale(d, 1.0 / *dist);
}

/* The intensity light l delivers at distance dist: I_l, or I_l / dist^2 with the inverse-square
 * fall-off (a point light only; dist > 0 wherever the light is not on the surface, which
 * contributes nothing). Without fall-off it is I_l itself, so that such scenes shade bit for bit
 * as before the option existed. */
static inline rt_rgb_t intensity_at(const rt_light_t *l, double dist) {
  if (l->falloff == RT_FALLOFF_NONE)
    return l->intensity;
  return rt_rgb_scale(l->intensity, 1.0 / (dist * dist));
}

/* x^n for Phong's (R.V)^n, 0 < x <= 1: by repeated squaring when n is a whole number up to 1024
 * (the usual case). Each squaring doubles the relative error it inherits and adds one rounding,
 * so x^n comes out within (n - 1) roundings, 1.2e-13 relative at n = 1024: far below the float
 * resolution of the image (6e-8) and far cheaper than pow(). pow() for other exponents. */
static double phong_pow(double x, double n) {
  if (!(n >= 0.0 && n <= 1024.0) || n != floor(n))
    return pow(x, n);
  double r = 1.0;
  for (unsigned k = (unsigned)n; k; k >>= 1, x *= x)
    if (k & 1u)
      r *= x;
  return r;
}

/* Transmittance towards a light (white without the shadow effect). Always inlined: it is on the
 * exact renderer's hot path, and with a second caller the compiler stopped inlining it, which
 * made that renderer measurably slower (docs/tuning.md). */
static inline __attribute__((always_inline)) rt_rgb_t
shadow(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf, const rt_ray_t *ray,
       int l, px_vec3_t pos, px_vec3_t dir, double dist, int opaque, const rt_tracer_t *tr) {
  if (!rt_plan_has(plan, RT_EFFECT_SHADOWS))
    return rt_rgb(1, 1, 1);
  rt_rgb_t known;
  if (tr->known && tr->known(tr->ctx, l, &known))
    return known;
  rt_shadow_t q;
  px_vec3_t o = rt__offset_origin(sf, 1.0);
  q.light = l;
  q.ray = (rt_ray_t){
      o, dir, 0.0, dist, ray->ior, planar_prim(s, sf->hit.prim) ? sf->hit.prim : -1, 0.0f};
  if (isfinite(dist))
    q.ray.tmax = px_v3_dot(px_v3_sub(pos, o), dir);
  q.through = rt_rgb(1, 1, 1);
  if (opaque && tr->occluded)
    tr->occluded(tr->ctx, &q);
  else
    tr->shadow(tr->ctx, &q);
  return q.through;
}

/* Light l's diffuse and specular term for material m, as rt_shade_direct() adds it. */
static inline __attribute__((always_inline)) rt_rgb_t light_term(const rt_material_t *m, int spec,
                                                                 const rt_surface_t *sf,
                                                                 const rt_ray_t *ray, px_vec3_t L,
                                                                 double ndl) {
  rt_rgb_t term = rt_rgb_scale(m->color, m->kd * ndl);
  if (spec) { /* Phong: (R.V)^n with R the mirror image of L, V = -d; R.V = L.reflect(d) */
    px_vec3_t rd = px_v3_axpy(-2.0 * px_v3_dot(ray->d, sf->nf), sf->nf, ray->d);
    double rv = px_v3_dot(rd, L);
    if (rv > 0.0)
      term = rt_rgb_add(term, rt_rgb_scale(rt_rgb(1, 1, 1), m->ks * phong_pow(rv, m->phong)));
  }
  return term;
}

/* The diffuse term of a caustic map's light at p: kd colour E (core/caustics.h; no specular term,
 * the map not knowing the light's direction). */
static rt_rgb_t caustic_term(const rt_material_t *m, const rt_caustic_map_t *cm, px_vec3_t p) {
  return rt_rgb_mul(rt_rgb_scale(m->color, m->kd), rt_caustic_at(cm, p));
}

/* Area light l's diffuse and specular terms for the materials m[0 .. nm-1] (those with lit[i])
 * added to out[i]: the sum over its N x N mesh points, the cells' centres (N = samples), each a
 * Lambertian point of intensity I0 / N^2 cos(theta) / r^2, theta from the light's normal (the
 * illuminance maps' model, light/), with its own shadow ray: soft shadows in N^2 steps. With a
 * caustic map (opaque) every point's shadow ray is opaque. Out of line: only scenes with area
 * lights call it. */
static __attribute__((noinline)) void area_light(const rt_scene_t *s, const rt_plan_t *plan,
                                                 const rt_surface_t *sf, const rt_ray_t *ray, int l,
                                                 int opaque, const rt_tracer_t *tr,
                                                 const rt_material_t *const *m, const int *spec,
                                                 const int *lit, int nm, rt_rgb_t *out) {
  const rt_light_t *li = &s->light[l];
  int n = li->samples > 0 ? li->samples : 1;
  px_vec3_t ne = px_v3_unit(px_v3_cross(li->eu, li->ev));
  rt_rgb_t each = rt_rgb_scale(li->intensity, 1.0 / ((double)n * n));
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double a = (i + 0.5) / n - 0.5, b = (j + 0.5) / n - 0.5, dist;
      px_vec3_t pos = px_v3_add(li->v, px_v3_add(px_v3_scale(li->eu, a), px_v3_scale(li->ev, b)));
      px_vec3_t d = px_v3_sub(pos, sf->hit.p);
      dist = px_v3_norm(d);
      if (!(dist > 0.0) || !isfinite(dist))
        continue;
      px_vec3_t L = px_v3_scale(d, 1.0 / dist);
      double ndl = px_v3_dot(sf->nf, L), emit = -px_v3_dot(L, ne);
      if (!(ndl > 0.0) || !(emit > 0.0))
        continue; /* the surface faces away, or the point is behind the light */
      rt_rgb_t through =
          shadow(s, plan, sf, ray, RT_AREA_SHADOW_INDEX(l), pos, L, dist, opaque, tr);
      if (!(rt_rgb_max(through) > 0.0))
        continue;
      rt_rgb_t e = rt_rgb_mul(through, rt_rgb_scale(each, emit / (dist * dist)));
      for (int k = 0; k < nm; k++)
        if (lit[k])
          out[k] = rt_rgb_add(out[k], rt_rgb_mul(e, light_term(m[k], spec[k], sf, ray, L, ndl)));
    }
}

/* rt_shade_direct()'s sum, with the caustic maps `maps` (NULL: none). Always inlined, so that
 * the call without maps compiles to the loop it was before maps existed (the exact renderer's
 * hot path: a scene without caustics costs nothing more). */
static inline __attribute__((always_inline)) rt_rgb_t
direct(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf, const rt_ray_t *ray,
       const rt_tracer_t *tr, const rt_caustic_maps_t *maps, int area) {
  const rt_material_t *m = sf->mat;
  rt_rgb_t c = rt_rgb_scale(rt_rgb_mul(s->ambient, m->color), m->ka);
  int spec = rt_plan_has(plan, RT_EFFECT_SPECULAR) && m->ks > 0.0;
  if (!(m->kd > 0.0) && !spec)
    return c;
  for (int l = 0; l < s->nlight; l++) {
    const rt_caustic_map_t *cm = maps ? rt_caustic_map_of(maps, sf->hit.object, l) : NULL;
    if (cm)
      c = rt_rgb_add(c, caustic_term(m, cm, sf->hit.p));
    if (area && s->light[l].kind == RT_LIGHT_AREA) {
      const int one = 1;
      area_light(s, plan, sf, ray, l, cm != NULL, tr, &m, &spec, &one, 1, &c);
      continue;
    }
    double dist;
    px_vec3_t L = to_light(&s->light[l], sf->hit.p, &dist);
    double ndl = px_v3_dot(sf->nf, L);
    if (!(ndl > 0.0))
      continue; /* the surface faces away from the light */
    rt_rgb_t through = shadow(s, plan, sf, ray, l, s->light[l].v, L, dist, cm != NULL, tr);
    if (!(rt_rgb_max(through) > 0.0))
      continue;
    rt_rgb_t term = light_term(m, spec, sf, ray, L, ndl);
    c = rt_rgb_add(c, rt_rgb_mul(rt_rgb_mul(through, intensity_at(&s->light[l], dist)), term));
  }
  return c;
}

/* rt_shade_direct() for a scene with area lights, out of line so that other scenes' code is as
 * it was. */
static __attribute__((noinline)) rt_rgb_t
direct_with_area(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                 const rt_ray_t *ray, const rt_tracer_t *tr) {
  return direct(s, plan, sf, ray, tr, plan->maps, 1);
}

rt_rgb_t rt_shade_direct(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                         const rt_ray_t *ray, const rt_tracer_t *tr) {
  if (__builtin_expect(plan->area_lights, 0))
    return direct_with_area(s, plan, sf, ray, tr);
  if (plan->maps)
    return direct(s, plan, sf, ray, tr, plan->maps, 0);
  return direct(s, plan, sf, ray, tr, NULL, 0);
}

/* As rt_shade_direct() for sf->mat and `other`, each light's direction and shadow found once:
 * each material's sum takes the same operations in the same order as there. */
void rt_shade_direct2(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                      const rt_material_t *other, const rt_ray_t *ray, const rt_tracer_t *tr,
                      rt_rgb_t out[2]) {
  const rt_material_t *m[2] = {sf->mat, other};
  int spec[2], lit[2];
  for (int i = 0; i < 2; i++) {
    out[i] = rt_rgb_scale(rt_rgb_mul(s->ambient, m[i]->color), m[i]->ka);
    spec[i] = rt_plan_has(plan, RT_EFFECT_SPECULAR) && m[i]->ks > 0.0;
    lit[i] = m[i]->kd > 0.0 || spec[i];
  }
  const rt_caustic_maps_t *maps = plan->maps;
  for (int l = 0; l < s->nlight && (lit[0] || lit[1]); l++) {
    const rt_caustic_map_t *cm = maps ? rt_caustic_map_of(maps, sf->hit.object, l) : NULL;
    if (cm) {
      rt_rgb_t e = rt_caustic_at(cm, sf->hit.p);
      for (int i = 0; i < 2; i++)
        out[i] = rt_rgb_add(out[i], rt_rgb_mul(rt_rgb_scale(m[i]->color, m[i]->kd), e));
    }
    if (plan->area_lights && s->light[l].kind == RT_LIGHT_AREA) {
      area_light(s, plan, sf, ray, l, cm != NULL, tr, m, spec, lit, 2, out);
      continue;
    }
    double dist;
    px_vec3_t L = to_light(&s->light[l], sf->hit.p, &dist);
    double ndl = px_v3_dot(sf->nf, L);
    if (!(ndl > 0.0))
      continue;
    rt_rgb_t through = shadow(s, plan, sf, ray, l, s->light[l].v, L, dist, cm != NULL, tr);
    if (!(rt_rgb_max(through) > 0.0))
      continue;
    for (int i = 0; i < 2; i++)
      if (lit[i])
        out[i] =
            rt_rgb_add(out[i], rt_rgb_mul(rt_rgb_mul(through, intensity_at(&s->light[l], dist)),
                                          light_term(m[i], spec[i], sf, ray, L, ndl)));
  }
}

/* The mirror child (px_interface_outgoing with PX_EVENT_REFLECT: s' = s - 2 (nu.s) nu). */
static inline __attribute__((always_inline)) int reflect_child(const rt_scene_t *s,
                                                               const rt_surface_t *sf,
                                                               const rt_ray_t *ray, rt_rgb_t w,
                                                               int tir, rt_child_t *out) {
  px_interface_t ifc = {.s = ray->d, .nu = px_v3_scale(sf->nf, -1.0), .n1 = sf->n1, .n2 = sf->n1};
  px_vec3_t dir;
  double co;
  if (!(rt_rgb_max(w) > 0.0) || px_interface_outgoing(&ifc, PX_EVENT_REFLECT, &dir, &co) != PX_OK)
    return 0;
  int skip = planar_prim(s, sf->hit.prim) ? sf->hit.prim : -1;
  out->ray =
      (rt_ray_t){rt__offset_origin(sf, 1.0), dir, 0.0, INFINITY, ray->ior, skip, ray->lambda};
  out->weight = w;
  out->kind = RT_RAY_REFLECT;
  out->tir = tir;
  return 1;
}

/* The split of the hit's coherent light: the mirror child's weight *wr (kr, plus what the
 * refraction passes on to it: its Fresnel share, or all of kt T after total internal reflection,
 * *tir set) and whether the refracted child exists, built into *refr unless refr is NULL. */
static int split(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                 const rt_ray_t *ray, rt_child_t *refr, rt_rgb_t *wr, int *tir) {
  const rt_material_t *m = sf->mat;
  *wr = rt_rgb(0, 0, 0);
  if (rt_plan_has(plan, RT_EFFECT_REFLECTION))
    *wr = rt_rgb(m->kr, m->kr, m->kr);
  *tir = 0;
  if (rt_plan_has(plan, RT_EFFECT_REFRACTION) && m->kt > 0.0)
    return rt__shade_refract(s, sf, ray, refr, wr, tir);
  return 0;
}

/* rt_shade_children(), always inlined into rt_shade_hit() (the exact renderer's hot path: with
 * the spectral fan beside it, the compiler stopped inlining it and the renderer ran 2% more
 * instructions; docs/journal/2026-12-03-spectral-fan.md). */
static inline __attribute__((always_inline)) int
children(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf, const rt_ray_t *ray,
         int depth, rt_child_t out[2]) {
  if (depth >= plan->max_depth)
    return 0;
  rt_rgb_t wr;
  int tir;
  int has_t = split(s, plan, sf, ray, &out[1], &wr, &tir); /* built in place: no copy */
  int n = reflect_child(s, sf, ray, wr, tir, &out[0]);
  if (has_t && !n)
    out[0] = out[1];
  return n + has_t;
}

int rt_shade_children(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                      const rt_ray_t *ray, int depth, rt_child_t out[2]) {
  return children(s, plan, sf, ray, depth, out);
}

int rt_shade_child(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                   const rt_ray_t *ray, int depth, rt_ray_kind_t kind, rt_child_t *out) {
  if (depth >= plan->max_depth)
    return 0;
  rt_rgb_t wr;
  int tir;
  if (kind == RT_RAY_REFRACT)
    return split(s, plan, sf, ray, out, &wr, &tir);
  if (kind != RT_RAY_REFLECT)
    return 0;
  split(s, plan, sf, ray, NULL, &wr, &tir);
  return reflect_child(s, sf, ray, wr, tir, out);
}

int rt_shade_child_ray(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                       const rt_ray_t *ray, int depth, rt_ray_kind_t kind, rt_ray_t *out) {
  if (depth >= plan->max_depth)
    return 0;
  const rt_material_t *m = sf->mat;
  if (kind == RT_RAY_REFRACT) /* split(): exists unless total internal reflection */
    return rt_plan_has(plan, RT_EFFECT_REFRACTION) && m->kt > 0.0 &&
           rt__refract_ray(s, sf, ray, out);
  if (kind != RT_RAY_REFLECT)
    return 0;
  rt_child_t ch;
  if (!(rt_plan_has(plan, RT_EFFECT_REFLECTION) && m->kr > 0.0 && m->kt >= 0.0 &&
        m->transmittance.r >= 0.0 && m->transmittance.g >= 0.0 && m->transmittance.b >= 0.0)) {
    /* the mirror child's weight is what the refraction passes on (or, for a material made
     * through the C API with a negative share, could take away): it decides */
    if (!rt_shade_child(s, plan, sf, ray, depth, kind, &ch))
      return 0;
    *out = ch.ray;
    return 1;
  }
  /* kr > 0 and the refraction's shares (kt T, kt F with 0 <= F <= 1) are not negative: the
   * weight is positive */
  if (!reflect_child(s, sf, ray, rt_rgb(m->kr, m->kr, m->kr), 0, &ch))
    return 0;
  *out = ch.ray;
  return 1;
}

/* The spectral fan (docs/spectral.md, section 3): a white ray refracting at a dispersive material
 * becomes one monochromatic refracted child per bin i of the plan, each with its own direction
 * (Snell's law with the indices at the bin's centre), Fresnel split and total internal reflection,
 * weighted by the bin's RGB weight w_i; the mirror child stays white, its weight kr plus the sum
 * over bins of w_i times the share each bin reflects. With w_i summing to 1 per channel, a glass
 * whose index does not vary gives back the white ray's children. Out of line: only scenes with
 * dispersive glass call it. */
static __attribute__((noinline)) rt_rgb_t fan(const rt_scene_t *s, const rt_plan_t *plan,
                                              const rt_surface_t *sf, const rt_ray_t *ray,
                                              int depth, const rt_tracer_t *tr) {
  const rt_material_t *m = sf->mat;
  rt_rgb_t c = rt_rgb(0, 0, 0), wr = rt_rgb(0, 0, 0);
  if (rt_plan_has(plan, RT_EFFECT_REFLECTION))
    wr = rt_rgb(m->kr, m->kr, m->kr);
  int all_tir = 1;
  for (int i = 0; i < plan->bins; i++) {
    double n = rt__index_at(m, plan->bin_lambda[i]);
    rt_surface_t si = *sf;
    rt_ray_t ri = *ray;
    si.n1 = sf->entering ? sf->n1 : n;
    si.n2 = sf->entering ? n : sf->n2;
    ri.ior = si.n1;
    ri.lambda = (float)plan->bin_lambda[i];
    rt_child_t ch;
    rt_rgb_t extra = rt_rgb(0, 0, 0);
    int tir = 0;
    int has = rt__shade_refract(s, &si, &ri, &ch, &extra, &tir);
    wr = rt_rgb_add(wr, rt_rgb_mul(plan->bin_weight[i], extra));
    all_tir &= tir;
    if (!has)
      continue;
    ch.weight = rt_rgb_mul(plan->bin_weight[i], ch.weight);
    c = rt_rgb_add(c, rt_rgb_mul(ch.weight, tr->child(tr->ctx, &ch, depth + 1)));
  }
  rt_child_t rc;
  if (reflect_child(s, sf, ray, wr, all_tir, &rc))
    c = rt_rgb_add(c, rt_rgb_mul(rc.weight, tr->child(tr->ctx, &rc, depth + 1)));
  return c;
}

int rt_shade_spectral_at(const rt_plan_t *plan, const rt_material_t *m, int depth) {
  return plan->bins > 0 && plan->spectral == RT_SPECTRAL_PENCIL && m->kt > 0.0 &&
         depth < plan->max_depth && rt_plan_has(plan, RT_EFFECT_REFRACTION) &&
         px_index_disperses(&m->index);
}

rt_rgb_t rt_shade_spectral_rec(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                               const rt_ray_t *ray, int depth, const rt_tracer_t *tr,
                               rt_child_t *mirror, int *nmirror, rt_spectral_rec_t *rec) {
  const rt_material_t *m = sf->mat;
  rt_rgb_t wr = rt_rgb(0, 0, 0);
  if (rt_plan_has(plan, RT_EFFECT_REFLECTION))
    wr = rt_rgb(m->kr, m->kr, m->kr);
  int all_tir;
  rt_rgb_t c = rt__wp_refract(s, plan, sf, ray, depth, tr, &wr, &all_tir, rec);
  *nmirror = reflect_child(s, sf, ray, wr, all_tir, mirror);
  return c;
}

rt_rgb_t rt_shade_spectral(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                           const rt_ray_t *ray, int depth, const rt_tracer_t *tr,
                           rt_child_t *mirror, int *nmirror) {
  return rt_shade_spectral_rec(s, plan, sf, ray, depth, tr, mirror, nmirror, NULL);
}

int rt_shade_spectral_mirror(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                             const rt_ray_t *ray, int depth, rt_child_t *mirror) {
  const rt_material_t *m = sf->mat;
  rt_rgb_t wr = rt_rgb(0, 0, 0);
  if (rt_plan_has(plan, RT_EFFECT_REFLECTION))
    wr = rt_rgb(m->kr, m->kr, m->kr);
  int all_tir;
  rt__wp_refract(s, plan, sf, ray, depth, NULL, &wr, &all_tir, NULL);
  return reflect_child(s, sf, ray, wr, all_tir, mirror);
}

/* The fan's place under RT_SPECTRAL_PENCIL: spectral pencils for the refracted light (wpencil.c),
 * the mirror child white as in fan(). */
static __attribute__((noinline)) rt_rgb_t pencils(const rt_scene_t *s, const rt_plan_t *plan,
                                                  const rt_surface_t *sf, const rt_ray_t *ray,
                                                  int depth, const rt_tracer_t *tr) {
  rt_child_t rc;
  int n;
  rt_rgb_t c = rt_rgb(0, 0, 0);
  if (tr->shape) /* the tree's shape: the white mirror child alone */
    n = rt_shade_spectral_mirror(s, plan, sf, ray, depth, &rc);
  else
    c = rt_shade_spectral(s, plan, sf, ray, depth, tr, &rc, &n);
  if (n)
    c = rt_rgb_add(c, rt_rgb_mul(rc.weight, tr->child(tr->ctx, &rc, depth + 1)));
  return c;
}

/* Shading under a plan with wavelength bins (out of line: other plans never enter it). A white
 * ray refracting at a dispersive material fans out; a monochromatic ray entering a material takes
 * its index at the ray's wavelength (the surface's n2 is the scalar at the d-line); else as
 * rt_shade_hit(). */
static __attribute__((noinline)) rt_rgb_t spectral(const rt_scene_t *s, const rt_plan_t *plan,
                                                   const rt_surface_t *sf, const rt_ray_t *ray,
                                                   int depth, const rt_tracer_t *tr) {
  const rt_material_t *m = sf->mat;
  if (ray->lambda == 0.0f && m->kt > 0.0 && depth < plan->max_depth &&
      px_index_disperses(&m->index))
    return plan->spectral == RT_SPECTRAL_PENCIL ? pencils(s, plan, sf, ray, depth, tr)
                                                : fan(s, plan, sf, ray, depth, tr);
  rt_surface_t mono = *sf;
  if (ray->lambda > 0.0f && sf->entering && m->kt > 0.0)
    mono.n2 = rt__index_at(m, ray->lambda);
  rt_child_t ch[2];
  int n = children(s, plan, &mono, ray, depth, ch);
  rt_rgb_t c = rt_rgb(0, 0, 0);
  for (int k = 0; k < n; k++)
    c = rt_rgb_add(c, rt_rgb_mul(ch[k].weight, tr->child(tr->ctx, &ch[k], depth + 1)));
  return c;
}

rt_rgb_t rt_shade_hit(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                      const rt_ray_t *ray, int depth, const rt_tracer_t *tr) {
  rt_rgb_t c = rt_shade_direct(s, plan, sf, ray, tr);
  if (__builtin_expect(plan->bins > 0, 0))
    return rt_rgb_add(c, spectral(s, plan, sf, ray, depth, tr));
  rt_child_t ch[2];
  int n = children(s, plan, sf, ray, depth, ch);
  for (int k = 0; k < n; k++)
    c = rt_rgb_add(c, rt_rgb_mul(ch[k].weight, tr->child(tr->ctx, &ch[k], depth + 1)));
  return c;
}
