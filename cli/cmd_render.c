/* cmd_render.c -- `pencil render`: any renderer of the renderer table (renderers/renderer.h) on a
 * scene file or the built-in Fig. 8 scene (1987 paper, section 5), writing OpenEXR (the image,
 * its auxiliary channels and the renderer's own) with a PNG preview beside it. The exact
 * renderer is the default; `--method NAME` picks another entry, whose options are accepted
 * after it has been named anywhere on the line. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "args.h"
#include "cli.h"
#include "io/image_io.h"
#include "io/output.h"
#include "light/illuminance.h"
#include "post/star.h"
#include "renderers/renderer.h"
#include "validation/timing.h"

enum {
  OPT_OUTPUT = 1,
  OPT_METHOD,
  OPT_SPP,
  OPT_THREADS,
  OPT_SIZE,
  OPT_NO_AUX,
  OPT_EXPLAIN,
  OPT_MEASURE,
  OPT_STAR,
  OPT_MAX_MEMORY,
  OPT_CAUSTIC_METHOD,
  OPT_CAUSTIC_RAYS,
  OPT_CAUSTIC_CELLS,
  OPT_RENDERER
};

static const cli_spec_t common[] = {{"--output", 'o', 1, OPT_OUTPUT},
                                    {"--method", 0, 1, OPT_METHOD},
                                    {"--spp", 0, 1, OPT_SPP},
                                    {"--threads", 0, 1, OPT_THREADS},
                                    {"--size", 0, 1, OPT_SIZE},
                                    {"--no-aux", 0, 0, OPT_NO_AUX},
                                    {"--explain", 0, 0, OPT_EXPLAIN},
                                    {"--measure", 0, 0, OPT_MEASURE},
                                    {"--star", 0, 0, OPT_STAR},
                                    {"--max-memory", 0, 1, OPT_MAX_MEMORY},
                                    {"--caustic-method", 0, 1, OPT_CAUSTIC_METHOD},
                                    {"--caustic-rays", 0, 1, OPT_CAUSTIC_RAYS},
                                    {"--caustic-cells", 0, 1, OPT_CAUSTIC_CELLS}};
#define NCOMMON ((int)(sizeof common / sizeof common[0]))
#define MAX_SPECS 64

static void help(FILE *f, const rn_renderer_t *r) {
  fprintf(
      f, "usage: pencil render [SCENE.json] -o OUT.exr [--method NAME] [--spp N] [--threads N]\n"
         "                     [--size WxH] [--no-aux] [--measure] [--explain] [METHOD OPTIONS]\n\n"
         "Renders SCENE.json (docs/scene-format.md) or, without it, the built-in Fig. 8 scene\n"
         "(a glass sphere over a checkerboard; scenes/README.md). Writes OUT.exr (float R, G, B\n"
         "and, for each pixel's centre ray, Z, id and the points where its paths meet the\n"
         "checkerboard: pathT.*, pathR.*; where dispersion is drawn, spectral: 1 where that\n"
         "ray's tree refracts at dispersive glass; the method's own channels; the version and\n"
         "command line as header attributes) and a PNG preview beside it (OUT.png).\n\n"
         "methods:\n");
  for (int k = 0; k < rn_count(); k++)
    fprintf(f, "  %-10s %s%s\n", rn_entry(k)->name, rn_entry(k)->summary,
            k == 0 ? " (default)" : "");
  fprintf(
      f,
      "\noptions:\n"
      "  -o, --output OUT.exr  output image, an .exr file (required unless --explain is\n"
      "                        given alone)\n"
      "  --method NAME         the renderer (default exact); 'pencil render --method NAME\n"
      "                        --help' lists its own options\n"
      "  --spp N               samples per pixel on an s x s grid: 1, 4, 9, ..., 1024\n"
      "                        (default: the scene's, 9 for the built-in scene)\n"
      "  --threads N           OpenMP threads (default: all cores)\n"
      "  --size WxH            override the scene's image size (1 <= W, H <= 16384)\n"
      "  --no-aux              leave the auxiliary channels empty (no centre-ray trees), as\n"
      "                        the benchmarks render\n"
      "  --measure             methods that approximate: trace every sample exactly too and\n"
      "                        print the Fig. 10 error statistics (points on surfaces with a\n"
      "                        diffuse term: Fig. 8's board)\n"
      "  --explain             print the effects plan (which effects run and why)\n"
      "  --star                apply the cross-screen (star) filter after rendering, with\n"
      "                        the scene's \"post\": {\"star\"} parameters or the defaults\n"
      "                        (1989 section 4, docs/star.md): R, G, B filtered, the\n"
      "                        unfiltered image kept as channels unfiltered.R, .G, .B, the\n"
      "                        PNG through the display curve phi\n"
      "  --max-memory SIZE     refuse a render whose image, working buffers and caustic\n"
      "                        maps need more than SIZE (512M, 8G; default: the memory\n"
      "                        available now)\n"
      "\ncaustics (when the effects plan has them: light through reflecting or transparent\n"
      "objects onto diffuse planes and polygons, from illuminance maps made before tracing):\n"
      "  --caustic-method M    photons, grid-pencil or polygons (default: photons for the\n"
      "                        exact renderer, grid-pencil for the others)\n"
      "  --caustic-rays N      rays per side of each light's grid, 2..16384 (default %d for\n"
      "                        photons, %d for grid-pencil; polygons take none)\n"
      "  --caustic-cells N     cells along the longer side of each map, 1..16384 (default %d)\n",
      RN_CAUSTIC_PHOTON_RAYS, RN_CAUSTIC_PENCIL_RAYS, RN_CAUSTIC_CELLS);
  if (r && r->noptions > 0) {
    fprintf(f, "\n%s\n\noptions of --method %s:\n", r->description, r->name);
    rn_print_options(f, r, 2);
  } else if (r) {
    fprintf(f, "\n%s\n", r->description);
  }
  fprintf(
      f,
      "\nA progress bar is drawn on stderr when it is a terminal; the closing lines give the\n"
      "time and what was traced.\n"
      "Exit codes: 0 image written; 1 rendering or writing failed; 2 usage or scene error, or an\n"
      "output that cannot be written (found before rendering).\n");
}

typedef struct {
  const char *scene, *out;
  long spp, threads, width, height;
  int explain, no_aux, measure, star;
  long caustic_method, caustic_rays, caustic_cells; /**< 0: the renderer's default */
  size_t max_memory; /**< refuse a render needing more (bytes); 0: the memory available */
  const rn_renderer_t *r;
  void *opt; /**< the renderer's options (r->options_size bytes) */
} args_t;

static int parse_size(const char *v, long *w, long *h) {
  return cli_parse_wxh("render", "--size", v, 16384, w, h);
}

/* The specs of the common options and of every renderer's (one spec per name). */
static int all_specs(cli_spec_t *specs) {
  int n = NCOMMON;
  memcpy(specs, common, sizeof common);
  for (int k = 0; k < rn_count(); k++)
    for (int j = 0; j < rn_entry(k)->noptions; j++) {
      const rn_option_t *o = &rn_entry(k)->options[j];
      int seen = 0;
      for (int i = 0; i < n && !seen; i++)
        seen = strcmp(specs[i].name, o->name) == 0;
      if (!seen && n < MAX_SPECS)
        specs[n++] = (cli_spec_t){o->name, 0, o->kind != RN_OPT_FLAG, OPT_RENDERER};
    }
  return n;
}

/* The entry named by --method (given once: the parser refuses a second), or the exact renderer;
 * NULL after an error. */
static const rn_renderer_t *method_of(const cli_arg_t *args, int n) {
  const char *name = "exact";
  for (int k = 0; k < n; k++)
    if (args[k].spec && args[k].spec->id == OPT_METHOD)
      name = args[k].value;
  const rn_renderer_t *r = rn_find(name);
  if (!r) {
    fprintf(stderr, "pencil render: --method: expected ");
    for (int k = 0; k < rn_count(); k++)
      fprintf(stderr, "%s%s", k == 0 ? "" : k + 1 < rn_count() ? ", " : " or ", rn_entry(k)->name);
    fprintf(stderr, ", got '%s'\n", name);
  }
  return r;
}

/* One argument; 1 ok, 0 usage error (printed). */
static int apply(args_t *a, const cli_arg_t *g) {
  char err[256];
  if (!g->spec) {
    if (a->scene)
      return fprintf(stderr, "pencil render: unexpected argument '%s' (see --help)\n", g->value), 0;
    a->scene = g->value;
    return 1;
  }
  switch (g->spec->id) {
  case OPT_OUTPUT:
    a->out = g->value;
    return 1;
  case OPT_METHOD:
    return 1;
  case OPT_SPP:
    return cli_parse_spp("render", "--spp", g->value, &a->spp);
  case OPT_THREADS:
    return cli_parse_long("--threads", g->value, 1, 1024, &a->threads);
  case OPT_SIZE:
    return parse_size(g->value, &a->width, &a->height);
  case OPT_NO_AUX:
    return a->no_aux = 1;
  case OPT_EXPLAIN:
    return a->explain = 1;
  case OPT_STAR:
    return a->star = 1;
  case OPT_MAX_MEMORY:
    if (!io_parse_size(g->value, &a->max_memory))
      return fprintf(stderr,
                     "pencil render: --max-memory: expected a size such as 512M or 8G, got "
                     "'%s'\n",
                     g->value),
             0;
    return 1;
  case OPT_CAUSTIC_METHOD: {
    int m = lt_method_parse(g->value);
    if (m < 0)
      return fprintf(stderr,
                     "pencil render: --caustic-method: expected photons, grid-pencil or polygons, "
                     "got '%s'\n",
                     g->value),
             0;
    a->caustic_method = m + 1;
    return 1;
  }
  case OPT_CAUSTIC_RAYS:
    return cli_parse_long("--caustic-rays", g->value, 2, LT_MAX_GRID, &a->caustic_rays);
  case OPT_CAUSTIC_CELLS:
    return cli_parse_long("--caustic-cells", g->value, 1, LT_MAX_GRID, &a->caustic_cells);
  case OPT_MEASURE:
    if (!a->r->errors)
      return fprintf(stderr,
                     "pencil render: --measure: the %s renderer has nothing to measure "
                     "(its samples are exact)\n",
                     a->r->name),
             0;
    return a->measure = 1;
  default: {
    const rn_option_t *o = rn_option_find(a->r, g->name);
    if (!o) {
      fprintf(stderr,
              "pencil render: %s is not an option of --method %s (see 'pencil render "
              "--method NAME --help')\n",
              g->name, a->r->name);
      return 0;
    }
    if (!rn_option_set(o, a->opt, g->value, err, sizeof err))
      return fprintf(stderr, "pencil render: %s\n", err), 0;
    return 1;
  }
  }
}

/* 1 ok, 0 usage error, -1 help printed. */
static int parse_args(int argc, char **argv, args_t *a) {
  cli_spec_t specs[MAX_SPECS];
  cli_arg_t *args = malloc((size_t)argc * sizeof *args);
  if (!args)
    return fprintf(stderr, "pencil render: out of memory\n"), 0;
  int n = cli_parse("render", argc, argv, specs, all_specs(specs), args), ok = n >= 0;
  a->r = ok ? method_of(args, n) : n == CLI_ARGS_HELP ? method_of(NULL, 0) : NULL;
  if (n == CLI_ARGS_HELP) { /* --help after --method NAME lists NAME's options */
    for (int i = 1; i + 1 < argc; i++)
      if (strcmp(argv[i], "--method") == 0 && rn_find(argv[i + 1]))
        a->r = rn_find(argv[i + 1]);
      else if (strncmp(argv[i], "--method=", 9) == 0 && rn_find(argv[i] + 9))
        a->r = rn_find(argv[i] + 9);
    help(stdout, a->r);
    free(args);
    return -1;
  }
  ok = ok && a->r && (a->opt = malloc(a->r->options_size));
  if (ok)
    rn_defaults(a->r, a->opt);
  for (int k = 0; ok && k < n; k++)
    ok = apply(a, &args[k]);
  /* an option given where it does nothing is refused, naming what it needs */
  char err[256];
  for (int k = 0; ok && k < n; k++)
    if (args[k].spec && args[k].spec->id == OPT_RENDERER &&
        rn_option_idle(a->r, a->opt, args[k].name, err, sizeof err))
      ok = (fprintf(stderr, "pencil render: %s\n", err), 0);
  if (ok && a->caustic_rays && a->caustic_method == LT_METHOD_POLYGONS + 1)
    ok = (fprintf(stderr, "pencil render: --caustic-rays has no effect with --caustic-method "
                          "polygons (its beams trace the rays they need)\n"),
          0);
  free(args);
  if (ok && !a->out && !a->explain)
    ok = (fprintf(stderr, "pencil render: -o OUT.exr is required (see --help)\n"), 0);
  return ok;
}

static void explain(FILE *f, const rt_plan_t *p, const char *scene) {
  fprintf(f, "effects plan for %s:\n", scene);
  for (int e = 0; e < RT_EFFECT_COUNT; e++)
    fprintf(f, "  %-14s %s\n", rt_effect_name((rt_effect_t)e), p->why[e]);
  fprintf(f, "  ray depth %d, ray-tree buffer %d node(s) per thread\n", p->max_depth,
          p->tree_nodes);
}

/* The star filter's parameters of the scene (post/star.h). */
static pp_star_t star_params(const rt_star_t *st) {
  return (pp_star_t){st->directions, st->angle_deg, st->ratio,    st->sigma1,  st->sigma2,
                     st->weight2,    st->ior,       st->focal_mm, st->frame_mm};
}

/* After rendering: the star filter on img's R, G, B in place (kernel k), the unfiltered planes
 * into unf[3] and the preview through the display curve into prev. 0 after a message. */
static int apply_star(const rt_scene_t *s, const pp_kernel_t *k, int threads, rt_image_t *img,
                      float *unf[3], rt_image_t *prev, char *line, size_t cap) {
  int w = img->width, h = img->height;
  size_t n = (size_t)w * (size_t)h;
  char why[512];
  if (rt_image_alloc(prev, w, h) != RT_OK) {
    fprintf(stderr, "pencil render: out of memory for the star filter\n");
    return 0;
  }
  for (int c = 0; c < 3; c++) {
    if (!(unf[c] = malloc(n * sizeof(float)))) {
      fprintf(stderr, "pencil render: out of memory for the star filter\n");
      return 0;
    }
    memcpy(unf[c], img->ch[RT_CH_R + c], n * sizeof(float));
  }
  float *planes[3] = {img->ch[RT_CH_R], img->ch[RT_CH_G], img->ch[RT_CH_B]};
  pp_star_flux_t fl[3];
  double t0 = val_wall_seconds();
  if (pp_star_apply(k, w, h, 3, (const float *const *)unf, planes, threads, fl, why, sizeof why) !=
      0) {
    fprintf(stderr, "pencil render: star filter: %s\n", why);
    return 0;
  }
  for (int c = 0; c < 3; c++)
    for (size_t q = 0; q < n; q++)
      prev->ch[RT_CH_R + c][q] = pp_tone(planes[c][q], s->star.exposure, s->star.white);
  snprintf(line, cap,
           "star filter: kernel %d x %d (%.4g pixels a unit of slope), %.3f s; %.6f of the light "
           "stayed in the frame (R), the rest was carried beyond it\n",
           k->side, k->side, k->scale, val_wall_seconds() - t0,
           fl[0].in > 0.0 ? fl[0].frame / fl[0].in : 1.0);
  return 1;
}

/* The image and its preview; `more` channels after the renderer's (the star filter's
 * unfiltered planes), the preview from `prev` when not NULL. */
static int write_outputs(const args_t *a, const rn_output_t *o, int spp,
                         const io_exr_channel_t *more, int nmore, const rt_image_t *prev,
                         const char *star) {
  char err[1024];
  rn_attr_t ra[RN_MAX_ATTRS];
  io_attr_t attrs[5 + RN_MAX_ATTRS];
  char cbuf[160];
  io_exr_channel_t ch[RN_MAX_CHANNELS + 4];
  char sppbuf[16];
  snprintf(sppbuf, sizeof sppbuf, "%d", spp);
  int na = 0, nr = a->r->describe(a->opt, ra);
  attrs[na++] = (io_attr_t){"pencil:scene", a->scene ? a->scene : "built-in fig8"};
  attrs[na++] = (io_attr_t){"pencil:method", a->r->name};
  attrs[na++] = (io_attr_t){"pencil:spp", sppbuf};
  for (int k = 0; k < nr; k++)
    attrs[na++] = (io_attr_t){ra[k].key, ra[k].value};
  if (o->caustics && o->caustics->maps > 0) { /* how the image's caustic light was mapped */
    const rn_caustic_stats_t *c = o->caustics;
    snprintf(cbuf, sizeof cbuf, "%d map(s) by %s, %d rays a side, %d cells, %.4g%% beside", c->maps,
             c->method, c->rays, c->cells, 100.0 * c->outside);
    attrs[na++] = (io_attr_t){"pencil:caustics", cbuf};
  }
  if (star)
    attrs[na++] = (io_attr_t){"pencil:star", star};
  int nch = 0;
  for (int k = 0; k < a->r->nchannels; k++)
    ch[nch++] = (io_exr_channel_t){a->r->channels[k], o->channels[k]};
  if (o->image->spectral)
    ch[nch++] = (io_exr_channel_t){"spectral", o->image->spectral};
  for (int k = 0; k < nmore && nch < RN_MAX_CHANNELS + 4; k++)
    ch[nch++] = more[k];
  if (io_render_write_preview(a->out, o->image, ch, nch, attrs, na, prev ? prev : o->image, err,
                              sizeof err) != 0)
    return fprintf(stderr, "pencil render: %s\n", err), 0;
  return 1;
}

/* 1 when the render fits in the memory allowed, c->memory_budget set to what that leaves the
 * renderer for what it builds as it goes; else a message and 0. */
static int memory_fits(const args_t *a, const rt_scene_t *s, const rt_plan_t *plan, rn_common_t *c,
                       size_t star) {
  size_t need = rn_memory_estimate(a->r, plan, c, a->opt, s->camera.width, s->camera.height, 0);
  size_t maps = rn_caustic_bytes(a->r, s, plan, c);
  need = need > SIZE_MAX - star ? SIZE_MAX : need + star; /* the star filter after rendering */
  size_t have = a->max_memory ? a->max_memory : io_memory_available();
  need = need > SIZE_MAX - maps ? SIZE_MAX : need + maps;
  size_t grows =
      a->r->image_bytes ? a->r->image_bytes(plan, c, a->opt, s->camera.width, s->camera.height) : 0;
  if (have == 0 || need <= have) { /* what it builds may take its estimate and what is left */
    c->memory_budget = have == 0 ? 0 : have - need + grows + 1; /* 0 would mean no limit */
    return 1;
  }
  int nt = rt_thread_count(c->threads);
  char n[32], h[32], m[32];
  io_format_size(need, n, sizeof n);
  io_format_size(have, h, sizeof h);
  io_format_size(maps, m, sizeof m);
  if (maps > need / 2) { /* the maps are the larger part: say which options shrink them */
    fprintf(stderr,
            "pencil render: the caustic maps of %s need %s (of %s in all), more than the %s %s; "
            "use fewer --caustic-rays or --caustic-cells, or --max-memory to allow more\n",
            a->scene ? a->scene : "the built-in scene", m, n, h,
            a->max_memory ? "--max-memory allows" : "available");
    return 0;
  }
  fprintf(stderr,
          "pencil render: a %dx%d image by --method %s on %d thread%s allocates %s (%d float "
          "channels, the preview, each thread's buffers%s%s%s%s%s), more than the "
          "%s %s; use a smaller --size or fewer --threads%s, or --max-memory to allow more\n",
          s->camera.width, s->camera.height, a->r->name, nt, nt == 1 ? "" : "s", n,
          RT_CH_COUNT + a->r->nchannels, maps ? ", " : "", maps ? m : "",
          maps ? " of caustic maps" : "", star ? ", the star filter's FFT grid" : "",
          grows ? ", the dispersion image solids, estimated" : "", h,
          a->max_memory ? "--max-memory allows" : "available",
          grows ? ", fewer --spp or --wavelengths pencils" : "");
  return 0;
}

static int render(const args_t *a, rt_scene_t *s) {
  int spp = a->spp > 0 ? (int)a->spp : s->spp;
  if (a->star && !s->star.on) { /* --star: the defaults */
    pp_star_t d = PP_STAR_DEFAULT;
    s->star = (rt_star_t){1,         d.directions, d.angle_deg, d.ratio,    d.sigma1, d.sigma2,
                          d.weight2, d.ior,        d.focal_mm,  d.frame_mm, 1.0,      4.0};
  }
  rt_plan_t plan = rn_plan_make(a->r, s, spp, a->opt);
  /* the star filter's kernel before a long render: a plate too coarse for the image is a scene
   * error found now */
  pp_kernel_t kernel;
  memset(&kernel, 0, sizeof kernel);
  char kwhy[512], star_attr[256] = "";
  if (rt_plan_has(&plan, RT_EFFECT_STAR_FILTER)) {
    pp_star_t sp = star_params(&s->star);
    int w = s->camera.width, h = s->camera.height;
    if (pp_star_kernel(&sp, w, w < h ? w : h, &kernel, kwhy, sizeof kwhy) != 0) {
      fprintf(stderr, "pencil render: %s: \"post\": \"star\": %s\n",
              a->scene ? a->scene : "the built-in scene", kwhy);
      return CLI_USAGE;
    }
    cli_star_describe(&sp, star_attr, sizeof star_attr);
  }
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = (int)lrint(sqrt(spp));
  c.threads = (int)a->threads;
  c.aux = !a->no_aux;
  c.measure = a->measure;
  c.progress = isatty(2) ? cli_progress : NULL;
  c.progress_ctx = (void *)"rendering";
  c.caustic_method = (int)a->caustic_method;
  c.caustic_rays = (int)a->caustic_rays;
  c.caustic_cells = (int)a->caustic_cells;
  /* the star filter's FFT grid, the unfiltered planes and the preview */
  size_t star_bytes =
      kernel.k ? pp_star_bytes(&kernel, s->camera.width, s->camera.height,
                               c.threads > 0 ? c.threads : rt_thread_count(0)) +
                     (size_t)s->camera.width * s->camera.height * 3 * sizeof(float) +
                     (size_t)s->camera.width * s->camera.height * RT_CH_COUNT * sizeof(float)
               : 0;
  if (a->out && !memory_fits(a, s, &plan, &c, star_bytes)) {
    pp_kernel_free(&kernel);
    return CLI_USAGE;
  }
  if (rt_plan_has(&plan, RT_EFFECT_CAUSTICS) && a->caustic_method) {
    char why[256];
    if (lt_method_check(s, (lt_method_t)(a->caustic_method - 1), why, sizeof why) != RT_OK) {
      fprintf(stderr, "pencil render: --caustic-method: %s\n", why);
      pp_kernel_free(&kernel);
      return CLI_USAGE;
    }
  }
  if (a->explain)
    explain(stdout, &plan, a->scene ? a->scene : "the built-in Fig. 8 scene");
  if (!a->out) {
    pp_kernel_free(&kernel);
    return CLI_OK;
  }
  rt_image_t img;
  rn_caustic_stats_t caustics;
  rn_output_t out = {.image = &img, .caustics = &caustics};
  void *stats = calloc(1, a->r->stats_size);
  if (!stats || rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK) {
    free(stats);
    fprintf(stderr, "pencil render: cannot allocate a %dx%d image\n", s->camera.width,
            s->camera.height);
    pp_kernel_free(&kernel);
    return CLI_FAIL;
  }
  if (rn_channels_alloc(a->r, s->camera.width, s->camera.height, &out) != RT_OK ||
      (c.aux && rt_plan_has(&plan, RT_EFFECT_DISPERSION) &&
       rt_image_want_spectral(&img) != RT_OK)) {
    rn_channels_free(&out);
    free(stats);
    rt_image_free(&img);
    fprintf(stderr, "pencil render: out of memory\n");
    pp_kernel_free(&kernel);
    return CLI_FAIL;
  }
  out.stats = stats;
  double t0 = val_wall_seconds();
  rt_status_t rs = a->r->render(s, &plan, &c, a->opt, &out);
  double dt = val_wall_seconds() - t0;
  int px, py, pc, ok = rs == RT_OK;
  if (ok && rn_image_nonfinite(&img, &px, &py, &pc)) {
    fprintf(stderr,
            "pencil render: the %s renderer produced a non-finite %c at pixel (%d, %d) (column, "
            "row from the top); nothing was written\n",
            a->r->name, "RGB"[pc], px, py);
    ok = 0;
  }
  float *unf[3] = {NULL, NULL, NULL};
  rt_image_t prev;
  memset(&prev, 0, sizeof prev);
  int star = ok && rt_plan_has(&plan, RT_EFFECT_STAR_FILTER);
  char star_line[256] = ""; /* printed after the renderer's closing line */
  if (star)
    ok = apply_star(s, &kernel, c.threads > 0 ? c.threads : rt_thread_count(0), &img, unf, &prev,
                    star_line, sizeof star_line);
  io_exr_channel_t more[3] = {
      {"unfiltered.R", unf[0]}, {"unfiltered.G", unf[1]}, {"unfiltered.B", unf[2]}};
  ok = ok && write_outputs(a, &out, spp, more, star ? 3 : 0, star ? &prev : NULL,
                           star ? star_attr : NULL);
  for (int k = 0; k < 3; k++)
    free(unf[k]);
  rt_image_free(&prev);
  pp_kernel_free(&kernel);
  /* a renderer that refuses the scene with a reason (beams and a sphere) is a scene error */
  int refused = rs == RT_EINVAL && out.why[0];
  if (refused)
    fprintf(stderr, "pencil render: --method %s: %s\n", a->r->name, out.why);
  else if (rs != RT_OK) {
    const char *why = out.why[0] ? out.why : caustics.why;
    fprintf(stderr, "pencil render: %s%s%s\n", rt_strerror(rs), why[0] ? ": " : "", why);
  }
  if (ok) {
    rn_report_t rep = {s, spp, dt, a->out, &c, a->opt, stats};
    a->r->report(stdout, &rep);
    fputs(star_line, stdout);
    if (caustics.maps > 0) {
      char grid[48] = "";
      if (caustics.rays)
        snprintf(grid, sizeof grid, " (grids of %d x %d rays)", caustics.rays, caustics.rays);
      printf("caustics: %d map(s) of %d cells along the longer side by %s%s, %d empty; %llu "
             "light rays in %.3f s (part of the render time); %.3g%% of the mapped light fell "
             "beside the maps\n",
             caustics.maps, caustics.cells, caustics.method, grid, caustics.empty,
             (unsigned long long)caustics.traced, caustics.seconds, 100.0 * caustics.outside);
    }
    if (a->measure) {
      rn_errors_t e;
      a->r->errors(stats, &e);
      if (e.with_points == 0)
        fprintf(stderr, "pencil render: warning: no sample had a traced point on a surface with a "
                        "diffuse term, so the Fig. 10 error compared nothing\n");
    }
  }
  rn_channels_free(&out);
  rt_image_free(&img);
  free(stats);
  return ok ? CLI_OK : refused ? CLI_USAGE : CLI_FAIL;
}

int cmd_render(int argc, char **argv) {
  args_t a = {0};
  int p = parse_args(argc, argv, &a);
  if (p <= 0) {
    free(a.opt);
    return p < 0 ? CLI_OK : CLI_USAGE;
  }
  char err[1024];
  if (a.out && io_render_check(a.out, err, sizeof err) != 0) { /* before a long render */
    fprintf(stderr, "pencil render: %s\n", err);
    free(a.opt);
    return CLI_USAGE; /* an input error, found before rendering */
  }
  rt_scene_t s;
  int rc = cli_load_scene("render", a.scene, a.width, a.height, &s);
  if (rc == CLI_OK)
    rc = render(&a, &s);
  rt_scene_free(&s);
  free(a.opt);
  return rc;
}
