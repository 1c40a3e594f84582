/* plan.h -- the effects plan: which effects a render runs, decided from the scene before any
 * ray is traced, with the reason for each decision (issue 4, "effects plan").
 *
 * An effect the scene does not call for executes no code and allocates nothing: the shading
 * module consults the plan before spawning shadow, reflected or refracted rays, and the
 * renderer sizes its per-thread ray-tree buffers from the plan. Later effects (caustics through
 * the illuminance formula, dispersion, a star filter) add an entry to rt_effect_t and a rule
 * to rt_plan_make(); renderers that do not implement an effect list it as "not implemented".
 */
#ifndef RENDER_PLAN_H
#define RENDER_PLAN_H

#include "core/caustics.h"
#include "core/scene.h"
#include "paraxial/dispersion.h"

typedef enum {
  RT_EFFECT_SHADOWS = 0,   /**< shadow rays towards the lights (textbook 9.1) */
  RT_EFFECT_SPECULAR,      /**< Phong highlights */
  RT_EFFECT_REFLECTION,    /**< coherent reflection rays */
  RT_EFFECT_REFRACTION,    /**< coherent refraction rays */
  RT_EFFECT_FRESNEL,       /**< Fresnel-weighted reflection/refraction split */
  RT_EFFECT_SUPERSAMPLING, /**< s x s sub-pixel grid with a box filter */
  RT_EFFECT_CAUSTICS,      /**< light through specular and transparent objects from illuminance
                                maps (1987 Eq. 8; core/caustics.h) */
  RT_EFFECT_DISPERSION,    /**< wavelength-dependent index: white rays refracting into a
                                dispersive material fan out into wavelength bins (core/src/shade.c,
                              docs/spectral.md) */
  RT_EFFECT_STAR_FILTER,   /**< the cross-screen filter after rendering (post/star.h) */
  RT_EFFECT_COUNT
} rt_effect_t;

#define RT_PLAN_WHY_MAX 200

/** How white rays meet dispersive glass under RT_EFFECT_DISPERSION (docs/spectral.md). */
typedef enum {
  /** One monochromatic ray per bin where a white ray refracts (the exact reference). */
  RT_SPECTRAL_FAN = 0,
  /** One spectral pencil ([P89] section 3.2): an axial ray whose wavelength column (Eq. 13)
   *  carries the whole spectrum, split only where the spectrum meets different surfaces, squares
   *  or total internal reflection, or where the linear model errs (core/src/wpencil.c). */
  RT_SPECTRAL_PENCIL = 1
} rt_spectral_t;

/** The wavelength axis of spectral pencils: u = Lambda(lambda) of the scene's one dispersive glass
 *  ([P89] section 3.3, px_wavescale_t), or u = lambda when the glasses differ; and the colour
 *  weights' integral over u, tabulated at 1 nm. */
typedef struct {
  int scaled;                     /**< 1: u = Lambda(lambda) of `scale`; 0: u = lambda */
  px_wavescale_t scale;           /**< the scale when `scaled` */
  double u_edge[RT_MAX_BINS + 1]; /**< u at 380, 381, ..., 780 nm (increasing) */
  rt_rgb_t cum[RT_MAX_BINS + 1];  /**< integral of the RGB weights from 380 nm to u_edge[i]
                                       (each channel 1 at 780 nm) */
} rt_wavescale_t;

typedef struct {
  unsigned on;                                /**< bit (1u << e) set when effect e runs */
  char why[RT_EFFECT_COUNT][RT_PLAN_WHY_MAX]; /**< reason for each decision, one line */
  int max_depth;  /**< generations of secondary rays actually possible (0 without reflection
                       and refraction, else the scene's max_depth) */
  int tree_nodes; /**< upper bound on ray-tree nodes per sample (1 + max secondary rays) */
  rt_caustic_plan_t caustic; /**< with RT_EFFECT_CAUSTICS: the receiver planes and lights to map */
  /** The maps shading reads when RT_EFFECT_CAUSTICS is on: NULL from rt_plan_make(); a renderer
   *  makes them (lt_caustic_maps()) and points its own copy of the plan at them. Shading with
   *  the effect on and no maps is the textbook's (as with the effect off). */
  const rt_caustic_maps_t *maps;
  /** 1 when the scene has an area light (its mesh points shade with their own shadow rays,
   *  core/shade.c): shading takes that branch only then, so that other scenes pay nothing. */
  int area_lights;
  /** With RT_EFFECT_DISPERSION: the bins of the spectral fan, their centres (nm) and RGB weights
   *  (colour/colour.h, cs_bins(): each channel's weights sum to 1). 0 bins otherwise. */
  int bins;
  double bin_lambda[RT_MAX_BINS];
  rt_rgb_t bin_weight[RT_MAX_BINS];
  /** With RT_EFFECT_DISPERSION: rt_spectral_t; RT_SPECTRAL_FAN from rt_plan_make(). */
  int spectral;
  /** RT_SPECTRAL_PENCIL: the largest error of the linear model in wavelength at a pencil's ends,
   *  relative to the dispersive shift it predicts there, before the pencil is split. */
  double spectral_tol;
  /** RT_SPECTRAL_PENCIL: the camera's angle per pixel (radians, at the image centre). An error
   *  of the model under WP_PIXELS of it, seen from the eye, passes whatever spectral_tol says. */
  double pixel_angle;
  rt_wavescale_t wave; /**< RT_SPECTRAL_PENCIL: the wavelength axis */
} rt_plan_t;

/** Default of rt_plan_t.spectral_tol (docs/spectral.md; docs/journal/2026-12-03-spectral-pencils.md
 *  measures it). */
#define RT_SPECTRAL_TOL 0.1

/** Decide the plan for scene `s` rendered with `spp` samples per pixel. Pure function of its
 *  inputs; the scene need not be prepared. */
rt_plan_t rt_plan_make(const rt_scene_t *s, int spp);

/** Turn dispersion off, `why` saying in the reason who does not draw it ("the pencil renderer does
 *  not draw dispersion yet"): the dispersive material is then rendered at its index at the d-line.
 *  No-op when it is off. */
void rt_plan_no_dispersion(rt_plan_t *p, const rt_scene_t *s, const char *why);

/** The first material of an object of s that is transparent and disperses (the one the plan's
 *  dispersion entry names), or NULL. */
const rt_material_t *rt_plan_dispersive_material(const rt_scene_t *s);

/** Re-make the bins with n of them (RT_MIN_BINS..RT_MAX_BINS) when dispersion is on. */
void rt_plan_set_bins(rt_plan_t *p, const rt_scene_t *s, int n);

/** Draw dispersion by spectral pencils (RT_SPECTRAL_PENCIL) with tolerance tol (> 0, < 1) instead
 *  of the fan, when dispersion is on: the bins become the 400 1-nm bins of the weights' table.
 *  Returns 0, or -1 when the wavelength axis cannot be built (the plan is then unchanged). */
int rt_plan_spectral_pencils(rt_plan_t *p, const rt_scene_t *s, double tol);

/** rt_plan_spectral_pencils() with the wavelength axis chosen: lambda_axis 0 as there (Lambda of
 *  the scene's one dispersive glass, [P89] 3.3, where its glasses are one); 1 wavelength itself
 *  even then, for the comparison that shows what the paper's scale removes. */
int rt_plan_spectral_pencils_axis(rt_plan_t *p, const rt_scene_t *s, double tol, int lambda_axis);

/** The colour weights' integral over [ua, ub] of wavelength axis w (u as w says; each channel
 *  integrates to 1 over the visible range): the integral table of [P89] 3.2.3, linear within
 *  each 1-nm step (core/src/wpencil.c). */
rt_rgb_t rt_wave_weight(const rt_wavescale_t *w, double ua, double ub);

/** 1 when effect e runs. */
static inline int rt_plan_has(const rt_plan_t *p, rt_effect_t e) {
  return (p->on >> e) & 1u;
}

/** Short lower-case name of an effect ("shadows", "refraction", ...). */
const char *rt_effect_name(rt_effect_t e);

#endif
