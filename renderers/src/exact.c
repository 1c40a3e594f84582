/* exact.c -- the renderer table's entry for the exact renderer: recursive (Whitted) ray tracing
 * with the exact Snell-law tracer (render/render.h; textbook "Recursive Ray Tracing",
 * course notes "Ray Tracing"). It has no options of its own and adds no channels: every other
 * renderer is timed and measured against it. */
#include "entries.h"
#include "render/render.h"

/** The exact renderer has no options; the struct keeps the table's generic code uniform. */
typedef struct {
  int unused; /**< always 0 */
} exact_options_t;

static const exact_options_t defaults = {0};

static rt_status_t render(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *c,
                          const void *options, rn_output_t *out) {
  (void)options;
  xr_options_t o = XR_OPTIONS_DEFAULT;
  o.spp_side = c->spp_side;
  o.threads = c->threads;
  o.aux = c->aux;
  o.progress = c->progress;
  o.progress_ctx = c->progress_ctx;
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
  (void)options;
  (void)attrs;
  return 0;
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
    .options = NULL,
    .noptions = 0,
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
};
