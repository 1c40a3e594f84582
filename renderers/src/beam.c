/* beam.c -- the renderer table's entry for beam tracing of polyhedra (beam/render.h): the 1987
 * paper's section 4.1 (3), pencils bounded by polygon edges mapped to the screen by the
 * generalised perspective transformation of Eq. (7), with error control against exact tracing
 * (tolerance rho of Eq. 3). Its caustic maps are grid-pencil maps, as the pencil renderer's. */
#include <assert.h>
#include <stddef.h>
#include <string.h>

#include "beam/render.h"
#include "entries.h"

static_assert(RN_HIST_BINS == BT_HIST_BINS, "one histogram for every renderer");

static const bt_options_t defaults = BT_OPTIONS_DEFAULT;

/* bt_bound_t's values in order (the pencil renderer's names) */
static const char *const bound_names[] = {"corrected", "printed", "probe", NULL};

static const char *const channels[] = {"beam.error"};

/* bt_options_t.wavelengths */
static const char *const wavelength_names[] = {"solids", "off", "pencils", NULL};

static const rn_option_t beam_options[] = {
    {"--rho", RN_OPT_DOUBLE, offsetof(bt_options_t, rho), 0, 0, INFINITY, 1, NULL, "R",
     "tolerance ratio of Eq. (3), > 0 (default 0.5): a piece's model\n"
     "within R pixel intervals of exact tracing"},
    {"--max-split", RN_OPT_INT, offsetof(bt_options_t, max_split), 0, 0, 30, 0, NULL, "N",
     "divide a beam at most 2 N times along its path before tracing\n"
     "it exactly, 0..30 (default 8)"},
    {"--bounds", RN_OPT_CHOICE, offsetof(bt_options_t, bound), 0, 0, 0, 0, bound_names, "B",
     "what limits a piece's model error: the bound of Eq. (4),\n"
     "corrected (default) or printed, or probe (exact rays at its\n"
     "vertices and edge midpoints; not a bound)"},
    {"--certified", RN_OPT_FLAG, offsetof(bt_options_t, certified), 1, 0, 0, 0, NULL, NULL,
     "also check every sample cell's centre of a piece exactly"},
    {"--tile", RN_OPT_INT, offsetof(bt_options_t, tile), 0, 1, 256, 0, NULL, "N",
     "pixels per side of a beam from the eye, 1..256 (default 16)"},
    {"--exact-spp", RN_OPT_INT, offsetof(bt_options_t, exact_side), 0, 1, 16, 0, NULL, "E",
     "what is traced exactly is sampled on an E x E grid a sample\n"
     "cell, 1..16 (default 4)"},
    {"--wavelengths", RN_OPT_CHOICE, offsetof(bt_options_t, wavelengths), 0, 0, 0, 0,
     wavelength_names, "W",
     "dispersion (a scene whose glass disperses): solids (default) draws the\n"
     "light refracted into such glass as dispersion image solids (1989\n"
     "section 3.2: pieces swept along the wavelength axis, scan-converted\n"
     "per cell with the colour weights' integrals); pencils traces that light\n"
     "from each cell share's point by spectral pencils instead (the solids'\n"
     "reference at the same points); off draws the glass at n_d"},
};

static void adapt_plan(rt_plan_t *p, const rt_scene_t *s, const void *options) {
  const bt_options_t *o = options;
  if (!rt_plan_has(p, RT_EFFECT_DISPERSION))
    return;
  if (o->wavelengths == 1)
    rt_plan_no_dispersion(p, s, "the beam renderer was asked for --wavelengths off");
  else if (rt_plan_spectral_pencils(p, s, RT_SPECTRAL_TOL) != 0)
    rt_plan_no_dispersion(p, s, "its wavelength axis could not be built");
  else if (o->wavelengths == 0 && !p->wave.scaled)
    rt_plan_no_dispersion(p, s,
                          "dispersion image solids need one glass (its Lambda scale): the scene's "
                          "dispersive materials differ (--wavelengths pencils draws them)");
  else if (o->wavelengths == 0)
    snprintf(p->why[RT_EFFECT_DISPERSION], RT_PLAN_WHY_MAX,
             "on: white rays refracting into dispersive glass become dispersion image solids "
             "(Lambda of the scene's one glass; points they cannot draw by spectral pencils)");
  else
    snprintf(p->why[RT_EFFECT_DISPERSION], RT_PLAN_WHY_MAX,
             "on: the light of white rays refracting into dispersive glass is traced from each "
             "cell share's point by spectral pencils");
}

static rt_status_t render(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *c,
                          const void *options, rn_output_t *out) {
  bt_options_t o = *(const bt_options_t *)options;
  o.spp_side = c->spp_side;
  o.threads = c->threads;
  o.aux = c->aux;
  o.measure = c->measure;
  o.progress = c->progress;
  o.progress_ctx = c->progress_ctx;
  o.memory_budget = c->memory_budget;
  rt_plan_t run;
  rt_caustic_maps_t maps;
  rn_caustic_stats_t own;
  memset(&own, 0, sizeof own);
  rn_caustic_stats_t *cs = out->caustics ? out->caustics : &own;
  rt_status_t r = rn__caustics_make(s, plan, c, LT_METHOD_GRID_PENCIL, &run, &maps, cs);
  if (r != RT_OK) /* illuminance polygons refuse what beams refuse: say why here too */
    snprintf(out->why, sizeof out->why, "%s", cs->why);
  if (r == RT_OK) {
    bt_extra_t x = {out->sample_error, out->channels[0]};
    r = bt_render(s, &run, &o, out->image, &x, out->stats, out->why, sizeof out->why);
    if (r == RT_ENOMEM && out->stats && ((const bt_stats_t *)out->stats)->solid_over_budget) {
      snprintf(out->why, sizeof out->why,
               "the dispersion image solids need more than the %.0f MiB that the memory allowed "
               "leaves them; use a smaller --size, fewer --spp, --wavelengths pencils, or "
               "--max-memory to allow more",
               (double)o.memory_budget / 1048576.0);
    }
  }
  rt_caustic_maps_free(&maps);
  return r;
}

static int describe(const void *options, rn_attr_t *attrs) {
  const bt_options_t *o = options;
  attrs[0].key = "beam:rho";
  snprintf(attrs[0].value, sizeof attrs[0].value, "%g", o->rho);
  attrs[1].key = "beam:max_split";
  snprintf(attrs[1].value, sizeof attrs[1].value, "%d", o->max_split);
  attrs[2].key = "beam:certified";
  snprintf(attrs[2].value, sizeof attrs[2].value, "%s", o->certified ? "yes" : "no");
  attrs[3].key = "beam:bounds";
  snprintf(attrs[3].value, sizeof attrs[3].value, "%s", bound_names[o->bound]);
  attrs[4].key = "beam:wavelengths";
  snprintf(attrs[4].value, sizeof attrs[4].value, "%s", wavelength_names[o->wavelengths]);
  return 5;
}

static void report(FILE *f, const rn_report_t *r) {
  const bt_stats_t *st = r->stats;
  const bt_options_t *o = r->options;
  const rt_scene_t *s = r->scene;
  uint64_t cells = st->fragments + st->exact_cells;
  fprintf(
      f,
      "beam-traced %dx%d at %d spp in %.3f s (rho %g, bounds %s%s): %llu beams, %llu pieces by "
      "their "
      "model (%llu divided, %llu traced exactly, %llu slivers, %llu crowded beams divided, %llu "
      "dense beams traced exactly); "
      "%llu cell shares, %.2f%% "
      "traced exactly; largest checked error %.3g pixel intervals (%llu check rays); %llu "
      "exact rays (%llu shadow) -> %s\n",
      s->camera.width, s->camera.height, r->spp, r->seconds, o->rho, bound_names[o->bound],
      o->certified ? ", certified" : "", (unsigned long long)st->beams,
      (unsigned long long)st->pieces, (unsigned long long)st->divided,
      (unsigned long long)st->exact, (unsigned long long)st->slivers,
      (unsigned long long)st->crowded, (unsigned long long)st->dense, (unsigned long long)cells,
      cells ? 100.0 * st->exact_cells / cells : 0.0, st->max_error, (unsigned long long)st->checks,
      (unsigned long long)rt_stats_total(&st->rays), (unsigned long long)st->rays.shadow, r->out);
  if (o->bound != BT_BOUND_PROBE)
    fprintf(f,
            "Eq. (4) bounds: %llu pieces bounded, largest accepted bound %.3g pixel intervals; "
            "%llu unbounded (traced exactly); checked error over bound at most %.3g, %llu "
            "violations\n",
            (unsigned long long)st->bounded, st->max_bound, (unsigned long long)st->unbounded,
            st->max_ratio, (unsigned long long)st->violations);
  if (st->solids)
    fprintf(f,
            "dispersion image solids: %llu white refractions into glass (%llu traced: their "
            "path and face's subtrees too fine to record; %llu of them recorded nothing), %llu "
            "pieces and exact "
            "regions below them (%llu failed at the range's ends, %llu with weights traced per "
            "point, %llu children dark over their boxes); %llu cell shares scan-converted along "
            "wavelength (%llu spectral pencils for "
            "what their solids leave), %llu traced "
            "exactly by spectral pencils\n",
            (unsigned long long)st->solids, (unsigned long long)st->solid_fine,
            (unsigned long long)st->solid_skipped, (unsigned long long)st->solid_records,
            (unsigned long long)st->solid_failed, (unsigned long long)st->solid_wexact,
            (unsigned long long)st->solid_dark, (unsigned long long)st->solid_points,
            (unsigned long long)st->solid_traced, (unsigned long long)st->solid_exact);
  if (r->common->measure)
    fprintf(f,
            "Fig. 10 error: %llu samples (%llu with measured points, %llu traced exactly from the "
            "eye), %.4f%% within rho = %g, max %.4g (transmission path: %.4f%% within, max %.4g; "
            "strict: %.4f%% within, max %.4g), %llu path mismatches\n",
            (unsigned long long)st->measured, (unsigned long long)st->with_points,
            (unsigned long long)st->samples_exact, 100.0 * st->within / st->measured, o->rho,
            st->fig10_max, 100.0 * st->within_t / st->measured, st->fig10_max_t,
            100.0 * st->within_strict / st->measured, st->fig10_max_strict,
            (unsigned long long)st->mismatches);
}

static void errors(const void *stats, rn_errors_t *e) {
  const bt_stats_t *st = stats;
  memset(e, 0, sizeof *e);
  e->measured = st->measured;
  e->with_points = st->with_points;
  e->within = st->within;
  e->mismatches = st->mismatches;
  e->max_error = st->fig10_max;
  e->within_t = st->within_t;
  e->max_error_t = st->fig10_max_t;
  e->within_strict = st->within_strict;
  e->within_axial = st->within; /* one footprint: the beam's own (beam/src/render.c) */
  e->max_error_axial = st->fig10_max;
  e->max_error_strict = st->fig10_max_strict;
  memcpy(e->hist, st->hist, sizeof e->hist);
  e->samples_exact = st->samples_exact;
  e->samples_matrix = st->measured - st->samples_exact; /* drawn by the beams' models */
}

static double rho(const void *options) {
  return ((const bt_options_t *)options)->rho;
}

/* the dispersion image solids, estimated (BT_SOLID_SAMPLE_BYTES a sample; their points alone under
 * --wavelengths pencils) */
static size_t image_bytes(const rt_plan_t *plan, const rn_common_t *c, const void *options,
                          int width, int height) {
  const bt_options_t *o = options;
  if (!rt_plan_has(plan, RT_EFFECT_DISPERSION) || o->wavelengths == 1)
    return 0;
  return (size_t)width * (size_t)height * (size_t)c->spp_side * (size_t)c->spp_side *
         (o->wavelengths == 2 ? BT_SOLID_POINT_BYTES : BT_SOLID_SAMPLE_BYTES);
}

/* a tile's cells and, with auxiliary channels, a centre-ray tree */
static size_t thread_bytes(const rt_plan_t *plan, const rn_common_t *c, const void *options) {
  const bt_options_t *o = options;
  size_t cells = (size_t)o->tile * o->tile * c->spp_side * c->spp_side;
  size_t measure = c->measure ? cells * (3 * sizeof(double) + 1 + (size_t)plan->tree_nodes) +
                                    (size_t)plan->tree_nodes * sizeof(rt_tree_node_t)
                              : 0;
  return cells * 3 * sizeof(double) +
         (c->aux ? (size_t)plan->tree_nodes * sizeof(rt_tree_node_t) : 0) + measure;
}

const rn_renderer_t rn_beam_entry = {
    .name = "beam",
    .summary = "beam tracing of polyhedra with error control (1987, section 4.1 (3))",
    .description =
        "Beam tracing (1987 paper, section 4.1 (3)): each tile of N x N pixels is a beam from\n"
        "the eye, cut at the edges of the faces it meets (hidden surfaces removed in screen\n"
        "space, faces mapped by the generalised perspective transformation of Eq. (7) after\n"
        "the first face) and followed through reflections and refractions. Pieces are drawn\n"
        "by their exact coverage of s x s cells a pixel, each share shaded once by the exact\n"
        "renderer's shading. A piece whose model error, bounded by Eq. (4) over the whole\n"
        "piece, exceeds rho pixel intervals, or whose exact rays at its vertices and edge\n"
        "midpoints meet another face or change children, is divided, and past --max-split\n"
        "traced exactly; so is a piece whose error cannot be bounded (grazing, a focus).\n"
        "Polygons and planes only: a scene with a sphere is refused.\n"
        "Auxiliary channels come from exact centre-ray trees. With --measure, every sample\n"
        "cell's centre is measured as Fig. 10 (the model's points on surfaces with a diffuse\n"
        "term against the exact tracer's, in pixel intervals); channel beam.error holds each\n"
        "pixel's largest (0 without --measure). A dispersive glass is drawn by the 1989\n"
        "paper's dispersion image solids (--wavelengths).",
    .options_size = sizeof(bt_options_t),
    .defaults = &defaults,
    .options = beam_options,
    .noptions = (int)(sizeof beam_options / sizeof beam_options[0]),
    .channels = channels,
    .nchannels = 1,
    .error_channel = 0,
    .method_channel = -1,
    .stats_size = sizeof(bt_stats_t),
    .render = render,
    .describe = describe,
    .report = report,
    .errors = errors,
    .rho = rho,
    .thread_bytes = thread_bytes,
    .image_bytes = image_bytes,
    .dispersion = 1,
    .adapt_plan = adapt_plan,
};
