/* plan.c -- deciding the effects plan from the scene (issue 4, "effects plan"): an effect runs
 * only when some object's material or the scene's settings call for it (textbook 9.1: the
 * reflective and refractive children exist only "if object(q) is reflective/refractive"). */
#include "core/plan.h"

#include "colour/colour.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static const char *const names[RT_EFFECT_COUNT] = {"shadows",    "specular",   "reflection",
                                                   "refraction", "fresnel",    "supersampling",
                                                   "caustics",   "dispersion", "star-filter"};

const char *rt_effect_name(rt_effect_t e) {
  return (unsigned)e < RT_EFFECT_COUNT ? names[e] : "unknown";
}

/* The first material used by an object that satisfies `pred`, or NULL. */
static const rt_material_t *used(const rt_scene_t *s, int (*pred)(const rt_material_t *)) {
  for (int i = 0; i < s->nobject; i++) {
    const rt_object_t *o = &s->object[i];
    if (pred(&s->material[o->material]))
      return &s->material[o->material];
    if (o->material2 >= 0 && pred(&s->material[o->material2]))
      return &s->material[o->material2];
  }
  return NULL;
}

static int is_specular(const rt_material_t *m) {
  return m->ks > 0.0;
}
static int is_mirror(const rt_material_t *m) {
  return m->kr > 0.0;
}
static int is_transparent(const rt_material_t *m) {
  return m->kt > 0.0;
}
static int is_fresnel(const rt_material_t *m) {
  return m->kt > 0.0 && m->fresnel;
}

__attribute__((format(printf, 4, 5))) static void set(rt_plan_t *p, rt_effect_t e, int on,
                                                      const char *fmt, ...) {
  if (on)
    p->on |= 1u << e;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(p->why[e], RT_PLAN_WHY_MAX, fmt, ap);
  va_end(ap);
}

static void plan_lighting(rt_plan_t *p, const rt_scene_t *s) {
  if (s->nlight == 0)
    set(p, RT_EFFECT_SHADOWS, 0, "off: the scene has no lights");
  else if (!s->shadows)
    set(p, RT_EFFECT_SHADOWS, 0, "off: the scene disables them (\"shadows\": false)");
  else
    set(p, RT_EFFECT_SHADOWS, 1, "on: %d light(s) may be occluded", s->nlight);
  const rt_material_t *m = used(s, is_specular);
  if (m && s->nlight > 0)
    set(p, RT_EFFECT_SPECULAR, 1, "on: material '%s' has ks = %g", m->name, m->ks);
  else
    set(p, RT_EFFECT_SPECULAR, 0, "off: no lit material has ks > 0");
}

static void plan_secondary(rt_plan_t *p, const rt_scene_t *s) {
  const rt_material_t *mr = used(s, is_mirror), *mt = used(s, is_transparent);
  const rt_material_t *mf = used(s, is_fresnel);
  int depth_ok = s->max_depth > 0;
  if (!depth_ok)
    set(p, RT_EFFECT_REFLECTION, 0, "off: max_depth is 0");
  else if (mr)
    set(p, RT_EFFECT_REFLECTION, 1, "on: material '%s' has kr = %g", mr->name, mr->kr);
  else if (mt)
    set(p, RT_EFFECT_REFLECTION, 1, "on: material '%s' is transparent (total internal reflection)",
        mt->name);
  else
    set(p, RT_EFFECT_REFLECTION, 0, "off: no material has kr > 0 or kt > 0");
  if (!depth_ok)
    set(p, RT_EFFECT_REFRACTION, 0, "off: max_depth is 0");
  else if (mt)
    set(p, RT_EFFECT_REFRACTION, 1, "on: material '%s' has kt = %g", mt->name, mt->kt);
  else
    set(p, RT_EFFECT_REFRACTION, 0, "off: no transparent material (every kt is 0)");
  if (mf && depth_ok)
    set(p, RT_EFFECT_FRESNEL, 1, "on: material '%s' weights kt by Fresnel's formula", mf->name);
  else
    set(p, RT_EFFECT_FRESNEL, 0, "off: no transparent material asks for it");
}

/* The object's name for a message: its own, or its index. */
static const char *object_label(const rt_scene_t *s, int o, char *buf, size_t cap) {
  if (s->object[o].name[0])
    return s->object[o].name;
  snprintf(buf, cap, "object %d", o);
  return buf;
}

/* Caustics: light that reaches a diffuse surface through a reflecting or transparent object (by
 * materials: any light, any such object, any other diffuse object; geometry is the illuminance
 * maps' business), for the receivers and lights rt_caustic_plan() finds mappable. The why names
 * a light, the object, the receivers, and what keeps the textbook's shadow. */
static void plan_caustics(rt_plan_t *p, const rt_scene_t *s) {
  rt_caustic_plan_t *cp = &p->caustic;
  int nmaps = rt_caustic_plan(s, cp);
  if (s->caustics == RT_CAUSTICS_OFF) {
    cp->nplane = 0;
    cp->lights = 0;
    set(p, RT_EFFECT_CAUSTICS, 0, "off: the scene refuses them (\"caustics\": \"off\")");
    return;
  }
  char a[32], b[32], c[32];
  if (!s->shadows && cp->via >= 0 && nmaps > 0) {
    /* every light reaches every point unblocked: the light a map carries through the objects
     * would be counted twice, and the objects' shadows it replaces are not drawn */
    cp->nplane = 0;
    cp->lights = 0;
    set(p, RT_EFFECT_CAUSTICS, 0,
        "off: shadows are off (\"shadows\": false), so every light reaches every point "
        "directly; light through '%s' would be counted twice",
        object_label(s, cp->via, a, sizeof a));
    return;
  }
  if (cp->via < 0 || (cp->nplane == 0 && cp->unmapped < 0)) {
    set(p, RT_EFFECT_CAUSTICS, 0,
        "off: no light reaches a diffuse surface through a reflecting or transparent object");
    return;
  }
  if (nmaps == 0) {
    if (cp->lights == 0)
      set(p, RT_EFFECT_CAUSTICS, 0,
          "off: light may pass '%s', but no light is physical (a point light needs \"falloff\": "
          "\"inverse-square\")",
          object_label(s, cp->via, a, sizeof a));
    else
      set(p, RT_EFFECT_CAUSTICS, 0,
          "off: light may pass '%s', but '%s' cannot take a map (not a plane or polygon)",
          object_label(s, cp->via, a, sizeof a), object_label(s, cp->unmapped, b, sizeof b));
    cp->nplane = 0;
    cp->lights = 0;
    return;
  }
  int nl = __builtin_popcount(cp->lights), n = 0;
  for (int g = 0; g < cp->nplane; g++)
    n += cp->nobject[g];
  char rest[96] = "";
  if (cp->unmapped >= 0)
    snprintf(rest, sizeof rest, "; '%s'%s keeps the textbook shadow",
             object_label(s, cp->unmapped, c, sizeof c), cp->nunmapped > 1 ? " and others" : "");
  else if (cp->unphysical >= 0)
    snprintf(rest, sizeof rest, "; light %d (no fall-off) keeps the textbook shadow",
             cp->unphysical);
  set(p, RT_EFFECT_CAUSTICS, 1, "on: %d light(s) through '%s' onto '%s'%s, %d map(s)%s", nl,
      object_label(s, cp->via, a, sizeof a), object_label(s, cp->object[0][0], b, sizeof b),
      n > 1 ? " and others" : "", nmaps, rest);
}

/* Ray-tree nodes a sample can make: a binary tree (or a chain) to the depth limit; below a spectral
 * fan, p->bins monochromatic subtrees where a white ray refracts (each binary again, with no fan of
 * its own). Capped: a renderer's buffer that overflows flags the tree (core/raytree.h). */
static int tree_bound(const rt_plan_t *p) {
  int r = rt_plan_has(p, RT_EFFECT_REFLECTION), t = rt_plan_has(p, RT_EFFECT_REFRACTION);
  double white = 1.0, mono = 1.0, cap = p->bins > 0 ? (1 << 18) - 1 : (1 << 17) - 1;
  /* spectral pencils record no tree below the glass (core/src/wpencil.c) */
  for (int d = 1; d <= p->max_depth && (r || t); d++) {
    double fan = p->bins > 0 && p->spectral == RT_SPECTRAL_FAN ? p->bins * mono : white;
    white = fmin(cap, 1.0 + r * white + t * fan);
    mono = fmin(cap, 1.0 + (r + t) * mono);
  }
  return (int)white;
}

static int is_dispersive(const rt_material_t *m) {
  return m->kt > 0.0 && px_index_disperses(&m->index);
}

/* Dispersion: on where refraction runs and a transparent material's index varies with wavelength
 * (the scene's own index, settings.ior, is a number). White rays that refract into or out of such
 * a material fan out into the scene's bins (docs/spectral.md, section 3). */
const rt_material_t *rt_plan_dispersive_material(const rt_scene_t *s) {
  return used(s, is_dispersive);
}

static void plan_dispersion(rt_plan_t *p, const rt_scene_t *s, int n) {
  const rt_material_t *m = used(s, is_dispersive);
  p->bins = 0;
  p->spectral = RT_SPECTRAL_FAN;
  double dn = 0.0;
  if (!m) {
    set(p, RT_EFFECT_DISPERSION, 0, "off: no transparent material's index varies with wavelength");
    return;
  }
  if (px_index_eval(&m->index, PX_LAMBDA_D, NULL, &dn) != PX_OK)
    dn = NAN; /* the loader checked the model over 380-780 nm: not reached */
  if (!rt_plan_has(p, RT_EFFECT_REFRACTION)) {
    set(p, RT_EFFECT_DISPERSION, 0,
        "off: material '%s' disperses (dn/dlambda %.3g /nm at the d-line), but refraction is "
        "off",
        m->name, dn);
    return;
  }
  if (n < RT_MIN_BINS || n > RT_MAX_BINS)
    n = RT_DEFAULT_BINS;
  double w[RT_MAX_BINS][3];
  if (cs_bins(n, CS_LAMBDA_LO, CS_LAMBDA_HI, p->bin_lambda, w) != 0) {
    set(p, RT_EFFECT_DISPERSION, 0, "off: the colour-matching functions do not cover %g-%g nm",
        CS_LAMBDA_LO, CS_LAMBDA_HI);
    return;
  }
  for (int i = 0; i < n; i++)
    p->bin_weight[i] = rt_rgb(w[i][0], w[i][1], w[i][2]);
  p->bins = n;
  set(p, RT_EFFECT_DISPERSION, 1,
      "on: material '%s' disperses (dn/dlambda %.3g /nm at the d-line): white rays refracting "
      "at it fan out into %d wavelength bins over %g-%g nm",
      m->name, dn, n, CS_LAMBDA_LO, CS_LAMBDA_HI);
}

void rt_plan_no_dispersion(rt_plan_t *p, const rt_scene_t *s, const char *why) {
  if (!rt_plan_has(p, RT_EFFECT_DISPERSION))
    return;
  const rt_material_t *m = used(s, is_dispersive);
  p->on &= ~(1u << RT_EFFECT_DISPERSION);
  p->bins = 0;
  set(p, RT_EFFECT_DISPERSION, 0,
      "off: material '%s' disperses, but %s: it is rendered at n_d = %.5g", m ? m->name : "?", why,
      m ? m->ior : 0.0);
  p->tree_nodes = tree_bound(p);
}

void rt_plan_set_bins(rt_plan_t *p, const rt_scene_t *s, int n) {
  if (!rt_plan_has(p, RT_EFFECT_DISPERSION))
    return;
  p->on &= ~(1u << RT_EFFECT_DISPERSION);
  plan_dispersion(p, s, n);
  p->tree_nodes = tree_bound(p);
}

/* 1 when every transparent dispersive material of s has the index model of m. */
static int one_glass(const rt_scene_t *s, const rt_material_t *m) {
  for (int i = 0; i < s->nobject; i++) {
    const rt_object_t *o = &s->object[i];
    for (int k = 0; k < 2; k++) {
      int mi = k ? o->material2 : o->material;
      if (mi < 0)
        continue;
      const rt_material_t *q = &s->material[mi];
      if (is_dispersive(q) && memcmp(&q->index, &m->index, sizeof m->index) != 0)
        return 0;
    }
  }
  return 1;
}

int rt_plan_spectral_pencils(rt_plan_t *p, const rt_scene_t *s, double tol) {
  return rt_plan_spectral_pencils_axis(p, s, tol, 0);
}

int rt_plan_spectral_pencils_axis(rt_plan_t *p, const rt_scene_t *s, double tol, int lambda_axis) {
  if (!rt_plan_has(p, RT_EFFECT_DISPERSION))
    return 0;
  const rt_material_t *m = used(s, is_dispersive);
  if (!m || !(tol > 0.0 && tol < 1.0))
    return -1;
  rt_wavescale_t wave, *w = &wave; /* into the plan once complete: unchanged on failure */
  memset(w, 0, sizeof *w);
  int one = one_glass(s, m);
  w->scaled =
      !lambda_axis && one && px_wavescale_make(&m->index, PX_LAMBDA_D, &w->scale) == PX_OK ? 1 : 0;
  int n = RT_MAX_BINS;
  double wt[RT_MAX_BINS][3], centre[RT_MAX_BINS];
  if (cs_bins(n, CS_LAMBDA_LO, CS_LAMBDA_HI, centre, wt) != 0)
    return -1;
  double step = (CS_LAMBDA_HI - CS_LAMBDA_LO) / n;
  for (int i = 0; i <= n; i++) {
    double l = CS_LAMBDA_LO + i * step, u = l;
    if (w->scaled && px_wavescale_to(&w->scale, l, &u) != PX_OK)
      return -1;
    w->u_edge[i] = u;
    if (i > 0 && !(u > w->u_edge[i - 1]))
      return -1; /* not monotone: anomalous dispersion, not in the catalogue */
    w->cum[i] = i ? rt_rgb_add(w->cum[i - 1], rt_rgb(wt[i - 1][0], wt[i - 1][1], wt[i - 1][2]))
                  : rt_rgb(0, 0, 0);
  }
  p->wave = wave;
  for (int i = 0; i < n; i++) {
    p->bin_lambda[i] = centre[i];
    p->bin_weight[i] = rt_rgb(wt[i][0], wt[i][1], wt[i][2]);
  }
  p->bins = n;
  p->spectral = RT_SPECTRAL_PENCIL;
  p->spectral_tol = tol;
  p->pixel_angle = 2.0 * tan(0.5 * s->camera.fov_deg * (M_PI / 180.0)) /
                   (s->camera.height > 0 ? s->camera.height : 1);
  double dn = 0.0;
  if (px_index_eval(&m->index, PX_LAMBDA_D, NULL, &dn) != PX_OK)
    dn = NAN;
  set(p, RT_EFFECT_DISPERSION, 1,
      "on: material '%s' disperses (dn/dlambda %.3g /nm at the d-line): white rays refracting "
      "at it become spectral pencils over %g-%g nm (%s, tolerance %g)",
      m->name, dn, CS_LAMBDA_LO, CS_LAMBDA_HI,
      w->scaled ? "wavelength axis Lambda of its glass"
      : one     ? "wavelength axis lambda, as asked"
                : "wavelength axis lambda: glasses differ",
      tol);
  p->tree_nodes = tree_bound(p);
  return 0;
}

rt_plan_t rt_plan_make(const rt_scene_t *s, int spp) {
  rt_plan_t p;
  memset(&p, 0, sizeof p);
  plan_lighting(&p, s);
  plan_secondary(&p, s);
  if (spp > 1)
    set(&p, RT_EFFECT_SUPERSAMPLING, 1, "on: %d samples per pixel, box filter", spp);
  else
    set(&p, RT_EFFECT_SUPERSAMPLING, 0, "off: 1 sample per pixel");
  plan_caustics(&p, s);
  for (int l = 0; l < s->nlight; l++)
    p.area_lights |= s->light[l].kind == RT_LIGHT_AREA;
  plan_dispersion(&p, s, s->spectral_bins);
  if (s->star.on)
    set(&p, RT_EFFECT_STAR_FILTER, 1,
        "on: a cross-screen filter of %d scratch direction(s), B = %g, slopes %g and %g, after "
        "rendering (1989 section 4)",
        s->star.directions, s->star.ratio, s->star.sigma1, s->star.sigma2);
  else
    set(&p, RT_EFFECT_STAR_FILTER, 0,
        "off: the scene does not ask for it (\"post\": {\"star\": {...}} or --star)");
  int secondary = rt_plan_has(&p, RT_EFFECT_REFLECTION) || rt_plan_has(&p, RT_EFFECT_REFRACTION);
  p.max_depth = secondary ? s->max_depth : 0;
  p.tree_nodes = tree_bound(&p);
  return p;
}
