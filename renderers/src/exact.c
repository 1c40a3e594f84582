/* exact.c -- the renderer table's entry for the exact renderer: recursive (Whitted) ray tracing
 * with the exact Snell-law tracer (render/render.h; textbook "Recursive Ray Tracing",
 * course notes "Ray Tracing"). Its options say how it draws dispersion; it adds no channels:
 * every other renderer is timed and measured against it. */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "colour/colour.h"
#include "entries.h"
#include "render/render.h"

/** How the exact renderer draws dispersion (docs/spectral.md). */
typedef enum {
  WL_FAN = 0, /**< white rays fan out into the bins where they refract at a dispersive glass */
  WL_PRIMARY, /**< Takagi et al.'s wavelength supersampling: each primary ray once per bin */
  WL_OFF,     /**< dispersive glass at its index at the d-line (as the other renderers) */
  WL_PENCIL   /**< spectral pencils: one axial ray and its wavelength column (core/src/wpencil.c) */
} wavelengths_t;

typedef struct {
  int wavelengths; /**< wavelengths_t */
  int bins;        /**< 0: the scene's settings.spectral_bins; else RT_MIN_BINS..RT_MAX_BINS */
  double tol;      /**< WL_PENCIL: rt_plan_t.spectral_tol */
  int axis;        /**< WL_PENCIL: 0 Lambda where the glasses are one ([P89] 3.3), 1 lambda */
} exact_options_t;

static const exact_options_t defaults = {WL_FAN, 0, RT_SPECTRAL_TOL, 0};

static const char *const wavelength_names[] = {"fan", "primary", "off", "pencil", NULL};
static const char *const axis_names[] = {"Lambda", "lambda", NULL};

static const rn_option_t options_[] = {
    {"--wavelengths", RN_OPT_CHOICE, offsetof(exact_options_t, wavelengths), 0, 0, 0, 0,
     wavelength_names, "W",
     "dispersion (a scene whose glass disperses): fan (default) splits a\n"
     "white ray into the bins where it refracts at such glass; primary traces\n"
     "every primary ray once per bin (Takagi et al.'s wavelength supersampling,\n"
     "the 1989 paper's conventional method); off draws the glass at n_d; pencil\n"
     "traces one spectral pencil instead of the fan: an axial ray and its\n"
     "wavelength column (1989 Eq. 13), split where the spectrum parts"},
    {"--bins", RN_OPT_INT, offsetof(exact_options_t, bins), 0, RT_MIN_BINS, RT_MAX_BINS, 0, NULL,
     "N",
     "wavelength bins over 380-780 nm for fan and primary (default: the scene's\n"
     "spectral_bins, 40)"},
    {"--spectral-tol", RN_OPT_DOUBLE, offsetof(exact_options_t, tol), 0, 0, 0.5, 1, NULL, "T",
     "--wavelengths pencil: the linear model's largest error at a pencil's ends,\n"
     "relative to the dispersive shift it predicts there (default 0.1)"},
    {"--wavelength-axis", RN_OPT_CHOICE, offsetof(exact_options_t, axis), 0, 0, 0, 0, axis_names,
     "A",
     "--wavelengths pencil: the axis along which a pencil's column is linear:\n"
     "Lambda (default), the 1989 paper's scale of the scene's one dispersive\n"
     "glass, on which its index is linear (section 3.3); lambda, wavelength\n"
     "itself (as where glasses differ), to measure what the scale removes"},
};

/* options that act only with some --wavelengths (rn_option_idle()) */
static const rn_needs_t needs[] = {
    {"--bins", "--wavelengths", 1u << WL_FAN | 1u << WL_PRIMARY, "--wavelengths fan or primary"},
    {"--spectral-tol", "--wavelengths", 1u << WL_PENCIL, "--wavelengths pencil"},
    {"--wavelength-axis", "--wavelengths", 1u << WL_PENCIL, "--wavelengths pencil"},
};

static void adapt_plan(rt_plan_t *p, const rt_scene_t *s, const void *options) {
  const exact_options_t *o = options;
  if (!rt_plan_has(p, RT_EFFECT_DISPERSION))
    return;
  if (o->wavelengths == WL_OFF) {
    rt_plan_no_dispersion(p, s, "the exact renderer was asked for --wavelengths off");
    return;
  }
  if (o->wavelengths == WL_PENCIL) {
    if (rt_plan_spectral_pencils_axis(p, s, o->tol, o->axis) != 0)
      rt_plan_no_dispersion(p, s, "its wavelength axis could not be built");
    return;
  }
  if (o->bins > 0)
    rt_plan_set_bins(p, s, o->bins);
  if (o->wavelengths == WL_PRIMARY) {
    const rt_material_t *m = rt_plan_dispersive_material(s);
    snprintf(p->why[RT_EFFECT_DISPERSION], RT_PLAN_WHY_MAX,
             "on: material '%.40s' disperses: every primary ray traced at %d wavelengths over "
             "%g-%g nm (Takagi et al.)",
             m ? m->name : "?", p->bins, CS_LAMBDA_LO, CS_LAMBDA_HI);
  }
}

static rt_status_t render(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *c,
                          const void *options, rn_output_t *out) {
  const exact_options_t *eo = options;
  xr_options_t o = XR_OPTIONS_DEFAULT;
  o.spp_side = c->spp_side;
  o.threads = c->threads;
  o.aux = c->aux;
  o.progress = c->progress;
  o.progress_ctx = c->progress_ctx;
  o.per_wavelength = eo->wavelengths == WL_PRIMARY;
  rt_plan_t mine; /* a plan not made by rn_plan_make(): --wavelengths off and pencil still hold */
  if (rt_plan_has(plan, RT_EFFECT_DISPERSION) &&
      (eo->wavelengths == WL_OFF ||
       (eo->wavelengths == WL_PENCIL && plan->spectral != RT_SPECTRAL_PENCIL))) {
    mine = *plan;
    adapt_plan(&mine, s, options);
    plan = &mine;
  }
  rt_plan_t run;
  rt_caustic_maps_t maps;
  rt_status_t r = rn__caustics_make(s, plan, c, LT_METHOD_PHOTONS, &run, &maps, out->caustics);
  if (r == RT_OK)
    r = xr_render(s, &run, &o, out->image, out->stats);
  rt_caustic_maps_free(&maps);
  return r;
}

/* xr_render()'s tree buffer, which it allocates when it records trees (auxiliary channels). */
static size_t thread_bytes(const rt_plan_t *plan, const rn_common_t *c, const void *options) {
  (void)options;
  return c->aux ? (size_t)plan->tree_nodes * sizeof(rt_tree_node_t) : 0;
}

static int describe(const void *options, rn_attr_t *attrs) {
  const exact_options_t *o = options;
  attrs[0].key = "exact:wavelengths";
  snprintf(attrs[0].value, sizeof attrs[0].value, "%s", wavelength_names[o->wavelengths]);
  attrs[1].key = "exact:bins";
  if (o->bins > 0)
    snprintf(attrs[1].value, sizeof attrs[1].value, "%d", o->bins);
  else
    snprintf(attrs[1].value, sizeof attrs[1].value, "the scene's spectral_bins");
  if (o->wavelengths != WL_PENCIL)
    return 2;
  attrs[2].key = "exact:spectral_tol";
  snprintf(attrs[2].value, sizeof attrs[2].value, "%.17g", o->tol);
  attrs[3].key = "exact:wavelength_axis";
  snprintf(attrs[3].value, sizeof attrs[3].value, "%s", axis_names[o->axis]);
  return 4;
}

static void report(FILE *f, const rn_report_t *r) {
  const rt_stats_t *st = r->stats;
  uint64_t total = rt_stats_total(st);
  fprintf(f,
          "rendered %dx%d at %d spp in %.3f s: %llu rays (%llu primary, %llu reflected, %llu "
          "refracted, %llu shadow), %.3g rays/s -> %s\n",
          r->scene->camera.width, r->scene->camera.height, r->spp, r->seconds,
          (unsigned long long)total, (unsigned long long)st->primary,
          (unsigned long long)st->reflect, (unsigned long long)st->refract,
          (unsigned long long)st->shadow, (double)total / r->seconds, r->out);
  char line[256];
  rt_stats_spectral_line(st, line, sizeof line);
  fputs(line, f);
}

const rn_renderer_t rn_exact_entry = {
    .name = "exact",
    .summary = "exact recursive (Whitted) ray tracing, Snell's law at every surface",
    .description =
        "Exact recursive ray tracing: every sample's ray tree is traced through the BVH with\n"
        "Snell's law at every refraction, shadow rays towards each light, to the scene's\n"
        "depth limit. The reference every other renderer is timed and measured against.",
    .options_size = sizeof(exact_options_t),
    .defaults = &defaults,
    .options = options_,
    .noptions = (int)(sizeof options_ / sizeof options_[0]),
    .channels = NULL,
    .nchannels = 0,
    .error_channel = -1,
    .method_channel = -1,
    .stats_size = sizeof(rt_stats_t),
    .render = render,
    .describe = describe,
    .report = report,
    .errors = NULL,
    .rho = NULL,
    .thread_bytes = thread_bytes,
    .dispersion = 1,
    .adapt_plan = adapt_plan,
    .needs = needs,
    .nneeds = (int)(sizeof needs / sizeof needs[0]),
};
