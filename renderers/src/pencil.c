/* pencil.c -- the renderer table's entry for the pencil renderer (pencil/pencil.h): ray tracing
 * with a system matrix and ray interpolation, 1987 paper section 4.1 (1) and (2), with the
 * tolerance of Eq. (3) and the spread limit of Eqs. (4)-(6). Its options are pt_options_t's;
 * the common ones (samples, threads, auxiliary channels, measurement, progress) come from
 * rn_common_t. */
#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "entries.h"
#include "paraxial/system.h"
#include "pencil/pencil.h"

static_assert(RN_HIST_BINS == PT_HIST_BINS, "one histogram for every renderer");
static_assert(sizeof(pt_bound_t) == sizeof(int), "--bounds is stored as an int");
static_assert(sizeof(pt_tolerance_t) == sizeof(int), "--tolerance is stored as an int");

static const pt_options_t defaults = PT_OPTIONS_DEFAULT;

/* pt_bound_t's values in order */
static const char *const bound_names[] = {"corrected", "printed", "probe", NULL};

/* pt_tolerance_t's values in order */
static const char *const tolerance_names[] = {"geometric", "image", NULL};

/* pt_options_t.wavelengths */
static const char *const wavelength_names[] = {"pencil", "off", NULL};
static const char *const axis_names[] = {"Lambda", "lambda", NULL};

static const rn_option_t pencil_options[] = {
    {"--domain", RN_OPT_INT, offsetof(pt_options_t, domain), 0, 1, 32, 0, NULL, "N",
     "initial domain size in pixels, 1..32 (default 5, as the paper)"},
    {"--rho", RN_OPT_DOUBLE, offsetof(pt_options_t, rho), 0, 0, INFINITY, 1, NULL, "R",
     "tolerance ratio of Eq. (3), > 0 (default 0.5)"},
    {"--bounds", RN_OPT_CHOICE, offsetof(pt_options_t, bound), 0, 0, 0, 0, bound_names, "B",
     "C of Eq. (4): corrected (default), printed, or probe (exact\n"
     "errors on the spread circle; not a bound)"},
    {"--tolerance", RN_OPT_CHOICE, offsetof(pt_options_t, tolerance), 0, 0, 0, 0, tolerance_names,
     "T",
     "what rho bounds on each surface of a sample's tree: geometric (default,\n"
     "the paper's: rho pixel intervals everywhere) or image (rho / W where the\n"
     "surface's light reaches the pixel with weight W, the product of the\n"
     "reflection and transmission coefficients from the eye; the measure then\n"
     "counts each point's error in its own tolerance)"},
    {"--weight-floor", RN_OPT_DOUBLE, offsetof(pt_options_t, weight_floor), 0, 0, 1, 1, NULL, "W",
     "--tolerance image: weights below W count as W, so that no tolerance grows\n"
     "past rho / W; 0 < W <= 1 (default 1/64)"},
    {"--certified", RN_OPT_FLAG, offsetof(pt_options_t, certified), 1, 0, 0, 0, NULL, NULL,
     "also check every path exactly on each domain's boundary"},
    {"--no-interp", RN_OPT_FLAG, offsetof(pt_options_t, interp), 0, 0, 0, 0, NULL, NULL,
     "trace every sample with matrices (no ray interpolation)"},
    {"--no-memo", RN_OPT_FLAG, offsetof(pt_options_t, memo), 0, 0, 0, 0, NULL, NULL,
     "trace a lattice point again for each lattice cell that shares\n"
     "it (slower; the image is the same)"},
    {"--no-simd", RN_OPT_FLAG, offsetof(pt_options_t, simd), 0, 0, 0, 0, NULL, NULL,
     "carry interpolated samples along their exact walks one at a time, not\n"
     "four at once (AVX2 where the CPU has it; the image is the same)"},
    {"--brightness-tol", RN_OPT_DOUBLE, offsetof(pt_options_t, brightness_tol), 0, 0, INFINITY, 0,
     NULL, "L",
     "ray interpolation: largest deviation of interpolated from\n"
     "traced brightness on a lattice cell, >= 0 (default 1/1024)"},
    {"--wavelengths", RN_OPT_CHOICE, offsetof(pt_options_t, wavelengths), 0, 0, 0, 0,
     wavelength_names, "W",
     "dispersion (a scene whose glass disperses): pencil (default) traces the\n"
     "light refracted at such glass by spectral pencils from each sample's hit\n"
     "(an axial ray and its wavelength column, 1989 Eq. 13); off draws the\n"
     "glass at n_d"},
    {"--spectral-tol", RN_OPT_DOUBLE, offsetof(pt_options_t, spectral_tol), 0, 0, 0.5, 1, NULL, "T",
     "spectral pencils: the linear model's largest error at a pencil's ends,\n"
     "relative to the dispersive shift it predicts there (default 0.1)"},
    {"--wavelength-axis", RN_OPT_CHOICE, offsetof(pt_options_t, wavelength_axis), 0, 0, 0, 0,
     axis_names, "A",
     "spectral pencils: the axis along which a pencil's column is linear:\n"
     "Lambda (default), the 1989 paper's scale of the scene's one dispersive\n"
     "glass, on which its index is linear (section 3.3); lambda, wavelength\n"
     "itself (as where glasses differ), to measure what the scale removes"},
    {"--no-spectral-lattice", RN_OPT_FLAG, offsetof(pt_options_t, spectral_lattice), 0, 0, 0, 0,
     NULL, NULL,
     "spectral pencils: every interpolated sample traces its own from its\n"
     "hit; by default a lattice cell whose points' pencils met the same\n"
     "surfaces, with nothing else between them and no light shading them,\n"
     "interpolates their light (not with --certified)"},
};

/* options that act only with others' values (rn_option_idle()): --no-interp stores interp = 0,
 * and without ray interpolation its brightness tolerance, its lattice memo and its four-at-once
 * walks do nothing */
static const rn_needs_t needs[] = {
    {"--weight-floor", "--tolerance", 1u << PT_TOL_IMAGE, "--tolerance image"},
    {"--spectral-tol", "--wavelengths", 1u << 0, "--wavelengths pencil"},
    {"--wavelength-axis", "--wavelengths", 1u << 0, "--wavelengths pencil"},
    {"--no-spectral-lattice", "--wavelengths", 1u << 0, "--wavelengths pencil"},
    {"--no-spectral-lattice", "--no-interp", 1u << 1, "ray interpolation, without --no-interp"},
    {"--no-spectral-lattice", "--certified", 1u << 0, "the default checks, without --certified"},
    {"--brightness-tol", "--no-interp", 1u << 1, "ray interpolation, without --no-interp"},
    {"--no-memo", "--no-interp", 1u << 1, "ray interpolation, without --no-interp"},
    {"--no-simd", "--no-interp", 1u << 1, "ray interpolation, without --no-interp"},
};

static void adapt_plan(rt_plan_t *p, const rt_scene_t *s, const void *options) {
  const pt_options_t *o = options;
  if (!rt_plan_has(p, RT_EFFECT_DISPERSION))
    return;
  if (o->wavelengths == 1)
    rt_plan_no_dispersion(p, s, "the pencil renderer was asked for --wavelengths off");
  else if (rt_plan_spectral_pencils_axis(p, s, o->spectral_tol, o->wavelength_axis) != 0)
    rt_plan_no_dispersion(p, s, "its wavelength axis could not be built");
}

static const char *const channels[] = {"pencil.error", "pencil.method", "pencil.rays"};

static rt_status_t render(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *c,
                          const void *options, rn_output_t *out) {
  if (rt_plan_has(plan, RT_EFFECT_DISPERSION) && plan->spectral != RT_SPECTRAL_PENCIL) {
    snprintf(out->why, sizeof out->why,
             "the plan asks for dispersion by the spectral fan, which the pencil renderer does "
             "not draw (rn_plan_make() gives it spectral pencils)");
    return RT_EINVAL;
  }
  pt_options_t o = *(const pt_options_t *)options;
  o.spp_side = c->spp_side;
  o.threads = c->threads;
  o.aux = c->aux;
  o.measure = c->measure;
  o.progress = c->progress;
  o.progress_ctx = c->progress_ctx;
  pt_extra_t x = {out->channels[0], out->channels[1], out->channels[2]};
  rt_plan_t run;
  rt_caustic_maps_t maps;
  rt_status_t r = rn__caustics_make(s, plan, c, LT_METHOD_GRID_PENCIL, &run, &maps, out->caustics);
  if (r == RT_OK)
    r = pt_render(s, &run, &o, out->image, &x, out->sample_error, out->stats);
  rt_caustic_maps_free(&maps);
  return r;
}

static int describe(const void *options, rn_attr_t *attrs) {
  const pt_options_t *o = options;
  attrs[0].key = "pencil:rho";
  snprintf(attrs[0].value, sizeof attrs[0].value, "%g", o->rho);
  attrs[1].key = "pencil:bounds";
  snprintf(attrs[1].value, sizeof attrs[1].value, "%s", pt_bound_name(o->bound));
  attrs[2].key = "pencil:certified";
  snprintf(attrs[2].value, sizeof attrs[2].value, "%s", o->certified ? "yes" : "no");
  attrs[3].key = "pencil:wavelengths";
  snprintf(attrs[3].value, sizeof attrs[3].value, "%s", wavelength_names[o->wavelengths]);
  attrs[4].key = "pencil:spectral_tol";
  snprintf(attrs[4].value, sizeof attrs[4].value, "%.17g", o->spectral_tol);
  attrs[5].key = "pencil:tolerance";
  snprintf(attrs[5].value, sizeof attrs[5].value, "%s", tolerance_names[o->tolerance]);
  attrs[6].key = "pencil:weight_floor";
  snprintf(attrs[6].value, sizeof attrs[6].value, "%.17g", o->weight_floor);
  attrs[7].key = "pencil:wavelength_axis";
  snprintf(attrs[7].value, sizeof attrs[7].value, "%s", axis_names[o->wavelength_axis]);
  attrs[8].key = "pencil:spectral_lattice";
  snprintf(attrs[8].value, sizeof attrs[8].value, "%s", o->spectral_lattice ? "yes" : "no");
  return 9;
}

static void report(FILE *f, const rn_report_t *r) {
  const pt_stats_t *st = r->stats;
  const pt_options_t *o = r->options;
  const rt_scene_t *s = r->scene;
  uint64_t n = st->samples[0] + st->samples[1] + st->samples[2];
  fprintf(f,
          "pencil-traced %dx%d at %d spp in %.3f s (rho %g%s, bounds %s%s): samples %.1f%% matrix, "
          "%.1f%% interpolated, %.1f%% exact; %llu domains (%llu accepted, %llu partly exact, %llu "
          "edge, "
          "%llu split, %llu deep, %llu small), %llu paths exact, %llu guarded (and %llu shadows); "
          "%llu exact rays -> %s\n",
          s->camera.width, s->camera.height, r->spp, r->seconds, o->rho,
          o->tolerance == PT_TOL_IMAGE ? " / W, image tolerance" : "", pt_bound_name(o->bound),
          o->certified ? ", certified" : "", 100.0 * st->samples[1] / n, 100.0 * st->samples[2] / n,
          100.0 * st->samples[0] / n, (unsigned long long)st->domains,
          (unsigned long long)st->domains_accepted, (unsigned long long)st->domains_partial,
          (unsigned long long)st->domains_edge, (unsigned long long)st->domains_split,
          (unsigned long long)st->domains_deep, (unsigned long long)st->domains_small,
          (unsigned long long)st->paths_exact, (unsigned long long)st->paths_guard,
          (unsigned long long)st->lights_guard, (unsigned long long)rt_stats_total(&st->rays),
          r->out);
  fprintf(
      f,
      "ray interpolation: %llu lattice points (%llu more reused), %llu biquadratic lattice "
      "cells, %llu with faint shadow edges, %llu with narrow highlights, %llu halves; samples by "
      "matrices: %llu small cell, %llu "
      "left the paths, %llu reach, %llu error; "
      "%llu fallback samples, %llu partial samples, %llu brightness-interpolated samples\n",
      (unsigned long long)st->lattice_points, (unsigned long long)st->lattice_reused,
      (unsigned long long)st->biquad_lattice_cells, (unsigned long long)st->faint_lattice_cells,
      (unsigned long long)st->highlight_lattice_cells, (unsigned long long)st->halved_lattice_cells,
      (unsigned long long)st->matrix_samples[0], (unsigned long long)st->matrix_samples[1],
      (unsigned long long)st->matrix_samples[2], (unsigned long long)st->matrix_samples[3],
      (unsigned long long)st->fallbacks, (unsigned long long)st->partial,
      (unsigned long long)st->lerp_samples);
  if (st->walk_steps)
    fprintf(f,
            "exact walks in groups of samples: %llu steps, %.2f samples a step (%s), %llu "
            "times a sample left the path\n",
            (unsigned long long)st->walk_steps, (double)st->walk_lanes / (double)st->walk_steps,
            px_simd4_available() ? "four at a time, AVX2" : "one at a time: no AVX2 and FMA",
            (unsigned long long)st->walk_left);
  char line[256];
  rt_stats_spectral_line(&st->rays, line, sizeof line);
  fputs(line, f);
  if (st->spectral_points)
    fprintf(f,
            "spectral light at lattice points: %llu points traced spectral pencils, %llu "
            "samples took their interpolated light%s\n",
            (unsigned long long)st->spectral_points, (unsigned long long)st->spectral_samples,
            st->spectral_full ? "; some domains' records overflowed (PT_SPEC_EVENTS): traced "
                                "per sample there"
                              : "");
  if (r->common->measure)
    fprintf(f,
            "Fig. 10 error: %llu samples (%llu with measured points), %.4f%% within rho = %g, max "
            "%.4g (transmission path: %.4f%% within, max %.4g; strict: %.4f%% within, max %.4g; "
            "axial footprint alone: %.4f%% within, max %.4g), %llu path mismatches, %llu points "
            "without a local footprint\n",
            (unsigned long long)st->measured, (unsigned long long)st->with_points,
            100.0 * st->within / st->measured, o->rho, st->max_error,
            100.0 * st->within_t / st->measured, st->max_error_t,
            100.0 * st->within_strict / st->measured, st->max_error_strict,
            100.0 * st->within_axial / st->measured, st->max_error_axial,
            (unsigned long long)st->mismatches, (unsigned long long)st->local_unknown);
}

static void errors(const void *stats, rn_errors_t *e) {
  const pt_stats_t *st = stats;
  e->measured = st->measured;
  e->with_points = st->with_points;
  e->within = st->within;
  e->mismatches = st->mismatches;
  e->max_error = st->max_error;
  e->within_t = st->within_t;
  e->max_error_t = st->max_error_t;
  e->within_strict = st->within_strict;
  e->within_axial = st->within_axial;
  e->max_error_axial = st->max_error_axial;
  e->local_unknown = st->local_unknown;
  e->max_error_strict = st->max_error_strict;
  memcpy(e->hist, st->hist, sizeof e->hist);
  e->samples_exact = st->samples[PT_METHOD_EXACT];
  e->samples_matrix = st->samples[PT_METHOD_MATRIX];
  e->samples_interpolated = st->samples[PT_METHOD_INTERP];
}

static size_t thread_bytes(const rt_plan_t *plan, const rn_common_t *c, const void *options) {
  (void)c;
  return pt_thread_bytes(plan->tree_nodes, ((const pt_options_t *)options)->domain);
}

static double rho(const void *options) {
  return ((const pt_options_t *)options)->rho;
}

const rn_renderer_t rn_pencil_entry = {
    .name = "pencil",
    .summary = "pencil tracing: system matrices and ray interpolation (1987, section 4.1)",
    .description =
        "Pencil tracing (1987 paper, section 4.1): initial domains of N x N pixels, the axial\n"
        "ray of each traced exactly with its ray tree, a system matrix per path, edges found\n"
        "by comparing ray trees, the tolerance of Eq. (3) and the spread limit of Eq. (6)\n"
        "deciding between matrices, exact tracing and subdivision; samples by ray\n"
        "interpolation where e_int allows. Shading is the exact renderer's; light\n"
        "refracted at dispersive glass is traced per sample by spectral pencils.\n"
        "Adds the channels pencil.error (largest Fig. 10 error of the pixel's samples with\n"
        "--measure), pencil.method (0 exact, 1 matrix, 2 interpolated) and pencil.rays (exact\n"
        "rays traced for the pixel's samples).",
    .options_size = sizeof(pt_options_t),
    .defaults = &defaults,
    .options = pencil_options,
    .noptions = (int)(sizeof pencil_options / sizeof pencil_options[0]),
    .channels = channels,
    .nchannels = 3,
    .error_channel = 0,
    .method_channel = 1,
    .stats_size = sizeof(pt_stats_t),
    .render = render,
    .describe = describe,
    .report = report,
    .errors = errors,
    .rho = rho,
    .thread_bytes = thread_bytes,
    .dispersion = 1,
    .adapt_plan = adapt_plan,
    .needs = needs,
    .nneeds = (int)(sizeof needs / sizeof needs[0]),
};
