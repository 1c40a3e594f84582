/* scene_fuzz.c -- the fuzzer's harness: any bytes are a scene file (docs/scene-format.md) for
 * the loader, and a scene that loads is rendered small by every renderer of the table (the
 * exact Whitted renderer and the pencil renderer of the 1987 paper, section 4.1, measured
 * against exact tracing as in its Fig. 10). What must hold, whatever the bytes:
 *   - the loader returns 0 or -1 with a message, and leaves the scene empty on -1;
 *   - a render returns RT_OK or RT_ENOMEM (the one status a valid image, valid options and a
 *     prepared scene leave it: renderers/renderer.h);
 *   - every R, G, B value of the image is finite (rn_image_nonfinite), and the `spectral`
 *     channel, where the plan draws dispersion, is 0 or 1;
 *   - nothing crashes, leaks, or trips AddressSanitizer or UndefinedBehaviorSanitizer, and each
 *     input finishes in bounded time (libFuzzer's -timeout).
 * A broken rule is reported on stderr and ends the process with abort(), which libFuzzer records
 * as a crash with its input.
 *
 * Built by libFuzzer (fuzz/CMakeLists.txt, PENCIL_FUZZ=ON with clang), or with any compiler as
 * scene_fuzz_replay (replay.c), which runs the same function over files: docs/DEVELOPING.md,
 * "Fuzzing". */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "io/scene_json.h"
#include "renderers/renderer.h"

/** Largest image side rendered: enough for the pencil renderer's domains (5 pixels by default)
 *  to meet and split, small enough for thousands of inputs a second. */
#define FUZZ_MAX_SIDE 16
/** Largest sub-pixel grid side: 2 x 2 exercises supersampling and sample lattices. */
#define FUZZ_MAX_SPP_SIDE 2
/** Largest ray-tree depth rendered. A scene may ask for 32 generations, and ray trees with both
 *  reflection and refraction grow as 2^depth up to the plan's bound of 2^17 nodes per sample:
 *  legal, but seconds per pixel. Eight generations reach every kind of node and every path
 *  length the renderers treat differently, at 511 nodes per sample at most. */
#define FUZZ_MAX_DEPTH 8

/** An area light's mesh side (rt_light_t.samples, up to 64 in a scene: 4096 shadow rays per
 *  shading point, and as many grid-pencil maps, each with the space-variant filter) is cut to
 *  this: a 1 x 1 mesh runs every code path (the mesh loop, the filter over the whole light). At
 *  3 x 3 the glass of water (scenes/glass.json) took 5 s in the release build and over the
 *  replay's 120 s with the sanitizers. */
#define FUZZ_MAX_AREA_SAMPLES 1

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void broken(const char *what, const char *renderer) {
  fprintf(stderr, "scene_fuzz: %s (%s renderer)\n", what, renderer);
  abort();
}

static int min_int(int a, int b) {
  return a < b ? a : b;
}

/* Render s with entry r at its camera's size and spp_side x spp_side samples, with the Fig. 10
 * measurement when r has one, and check the rules above. */
static void render_with(const rn_renderer_t *r, const rt_scene_t *s, int spp_side) {
  rt_plan_t plan = rn_plan_make(r, s, spp_side * spp_side, NULL);
  rt_image_t img;
  rn_output_t out = {.image = &img};
  void *options = malloc(r->options_size);
  void *stats = calloc(1, r->stats_size ? r->stats_size : 1);
  if (!options || !stats || rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK) {
    free(options);
    free(stats);
    return; /* out of memory: not what the fuzzer looks for */
  }
  if (rt_plan_has(&plan, RT_EFFECT_DISPERSION))
    (void)rt_image_want_spectral(&img); /* `pencil render`'s plane; without it on ENOMEM */
  if (rn_channels_alloc(r, s->camera.width, s->camera.height, &out) == RT_OK) {
    rn_defaults(r, options);
    out.stats = stats;
    rn_common_t c = RN_COMMON_DEFAULT;
    c.spp_side = spp_side;
    c.threads = 1; /* one fuzzer process per core; no OpenMP pool per input */
    c.measure = r->errors != NULL;
    c.caustic_rays = 9; /* small caustic maps: the fuzzer looks for failures, not accuracy */
    c.caustic_cells = 8;
    rt_status_t st = r->render(s, &plan, &c, options, &out);
    int x, y, ch;
    /* a renderer may refuse a scene it is not made for, saying why (beams and spheres) */
    if (st != RT_OK && st != RT_ENOMEM && !(st == RT_EINVAL && out.why[0]))
      broken(rt_strerror(st), r->name);
    if (st == RT_OK && rn_image_nonfinite(&img, &x, &y, &ch))
      broken("a non-finite R, G or B", r->name);
    for (size_t k = 0; st == RT_OK && img.spectral && k < (size_t)img.width * img.height; k++)
      if (img.spectral[k] != 0.0f && img.spectral[k] != 1.0f)
        broken("a spectral channel value other than 0 or 1", r->name);
    rn_errors_t e;
    if (st == RT_OK && r->errors && (r->errors(stats, &e), e.within > e.measured))
      broken("more samples within rho than measured", r->name);
  }
  rn_channels_free(&out);
  rt_image_free(&img);
  free(options);
  free(stats);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  rt_scene_t s;
  char err[1024];
  rt_scene_init(&s);
  if (io_scene_load_buffer("fuzz.json", (const char *)data, size, &s, err, sizeof err) != 0) {
    if (s.nobject != 0 || s.nmaterial != 0 || s.bvh != NULL)
      broken("a scene that failed to load was not left empty", "no");
    return 0;
  }
  s.camera.width = min_int(s.camera.width, FUZZ_MAX_SIDE);
  s.camera.height = min_int(s.camera.height, FUZZ_MAX_SIDE);
  s.max_depth = min_int(s.max_depth, FUZZ_MAX_DEPTH);
  for (int l = 0; l < s.nlight; l++) /* an area light's N^2 shadow rays per shading point */
    if (s.light[l].kind == RT_LIGHT_AREA)
      s.light[l].samples = min_int(s.light[l].samples, FUZZ_MAX_AREA_SAMPLES);
  int spp_side = 1;
  while ((spp_side + 1) * (spp_side + 1) <= s.spp && spp_side < FUZZ_MAX_SPP_SIDE)
    spp_side++;
  for (int k = 0; k < rn_count(); k++)
    render_with(rn_entry(k), &s, spp_side);
  rt_scene_free(&s);
  return 0;
}
