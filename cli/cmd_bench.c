/* cmd_bench.c -- `pencil bench render`: exact-tracing rays per second for the Fig. 8 scene and a
 * 1,000-polygon scene, median of several runs, 1 and 2 threads (issue 4; textbook 9.2: with an
 * acceleration structure the cost per ray should hardly grow with the number of objects).
 * `pencil bench pencil` (the pencil tracer's speed targets, section 5) is in cmd_bench_pencil.c.
 * Speed is measured here, never in a timed unit test (docs/DEVELOPING.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "core/builtin.h"
#include "io/json.h"
#include "io/output.h"
#include "light/illuminance.h"
#include "post/star.h"
#include "render/render.h"
#include "renderers/renderer.h"
#include "validation/area_bench.h"
#include "validation/beam_bench.h"
#include "validation/caustic_bench.h"
#include "validation/dispersion_bench.h"
#include "validation/illum_bench.h"
#include "validation/timing.h"

#define MAX_RUNS 101

static void help(FILE *f) {
  fprintf(f, "usage: pencil bench render [--runs N] [--size WxH] [--spp N] [--json FILE]\n\n"
             "Renders the built-in Fig. 8 scene (glass sphere over a checkerboard) and a\n"
             "1,000-polygon scene (a faceted glass sphere of 25 x 40 faces over the same board)\n"
             "with the exact tracer, N times each with 1 and with 2 threads, and reports the\n"
             "median rays per second (all rays: primary, reflected, refracted, shadow). Plain\n"
             "rendering: no ray trees, no auxiliary channels. Other processes on the machine\n"
             "share the cores, so compare runs made under the same load.\n\n"
             "options:\n"
             "  --runs N      runs per configuration, 1..101 (default 5)\n"
             "  --size WxH    image size (default 256x256)\n"
             "  --spp N       samples per pixel, 1, 4, ..., 1024 (default 4)\n"
             "  --json FILE   also write the results as JSON\n");
}

typedef struct {
  const char *scene;
  int primitives, threads;
  uint64_t rays;
  double median_s, median_rps;
} result_t;

/* N renders of scene s with `threads`; median time and rays per second in *r. */
static int measure(const rt_scene_t *s, int side, int threads, int runs, result_t *r) {
  const rn_renderer_t *x = rn_exact(); /* the table's exact entry: its rays are rt_stats_t */
  rt_plan_t plan = rn_plan_make(x, s, side * side, NULL);
  unsigned char xopt[64];
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = side;
  c.threads = threads;
  c.aux = 0;
  rt_image_t img;
  double t[MAX_RUNS];
  rt_stats_t st;
  rn_output_t out = {.image = &img, .stats = &st};
  if (x->options_size > sizeof xopt ||
      rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK)
    return 0;
  rn_defaults(x, xopt);
  for (int k = 0; k < runs; k++) {
    double t0 = val_wall_seconds();
    if (x->render(s, &plan, &c, xopt, &out) != RT_OK) {
      rt_image_free(&img);
      return 0;
    }
    t[k] = val_wall_seconds() - t0;
  }
  rt_image_free(&img);
  r->threads = threads;
  r->rays = rt_stats_total(&st);
  r->median_s = val_median(t, runs);
  r->median_rps = r->rays / r->median_s;
  return 1;
}

static void print_table(const result_t *r, int n, int w, int h, int spp, int runs) {
  printf("exact tracing, %dx%d, %d spp, median of %d runs\n", w, h, spp, runs);
  printf("%-10s %10s %8s %12s %10s %14s\n", "scene", "primitives", "threads", "rays/run",
         "median s", "rays/s");
  for (int k = 0; k < n; k++)
    printf("%-10s %10d %8d %12llu %10.4f %14.4g\n", r[k].scene, r[k].primitives, r[k].threads,
           (unsigned long long)r[k].rays, r[k].median_s, r[k].median_rps);
}

static int write_json(const char *path, const result_t *r, int n, int w, int h, int spp, int runs) {
  json_t *results = json_array();
  for (int k = 0; k < n; k++)
    json_array_append_new(results, json_pack("{s:s, s:i, s:i, s:I, s:o, s:o}", "scene", r[k].scene,
                                             "primitives", r[k].primitives, "threads", r[k].threads,
                                             "rays", (json_int_t)r[k].rays, "median_seconds",
                                             io_json_number(r[k].median_s), "rays_per_second",
                                             io_json_number(r[k].median_rps)));
  json_t *root =
      json_pack("{s:s, s:s, s:i, s:i, s:i, s:i, s:o}", "benchmark", "render", "method", "exact",
                "width", w, "height", h, "spp", spp, "runs", runs, "results", results);
  char err[1024];
  int rc = root ? io_json_write(path, root, err, sizeof err) : -1;
  if (rc != 0)
    fprintf(stderr, "pencil bench render: %s\n", root ? err : "out of memory");
  json_decref(root);
  return rc == 0;
}

static int run(int runs, long w, long h, int side, const char *json) {
  const char *names[2] = {"fig8", "mesh1000"};
  result_t res[4];
  int n = 0;
  for (int k = 0; k < 2; k++) {
    rt_scene_t s;
    rt_scene_init(&s);
    if (rt_builtin(names[k], &s) != RT_OK) {
      fprintf(stderr, "pencil bench render: cannot build scene %s\n", names[k]);
      rt_scene_free(&s);
      return CLI_FAIL;
    }
    s.camera.width = (int)w;
    s.camera.height = (int)h;
    for (int threads = 1; threads <= 2; threads++, n++) {
      res[n].scene = names[k];
      res[n].primitives = s.nprim;
      if (!measure(&s, side, threads, runs, &res[n])) {
        rt_scene_free(&s);
        return CLI_FAIL;
      }
    }
    rt_scene_free(&s);
  }
  print_table(res, n, (int)w, (int)h, side * side, runs);
  return json && !write_json(json, res, n, (int)w, (int)h, side * side, runs) ? CLI_FAIL : CLI_OK;
}

/* The options the benchmark drivers of validation/ share (bench illuminance, caustics, area,
 * beam, dispersion), by the ids their specs give them; a driver's own options take ids from
 * B_OWN on. */
enum { B_JSON = 1, B_OUT, B_RUNS, B_THREADS, B_QUICK, B_SCENES, B_OWN };
typedef struct {
  const char *json, *out, *scenes;
  long runs, threads; /* runs: the driver's default until given */
  int quick, runs_given;
} bench_common_t;

/* Apply parsed argument g when it is a shared option (or no option at all: a usage error naming
 * `cmd`, "bench beam"); 1 when it was, with *rc the result, 0 when it is the driver's own. */
static int common_arg(const char *cmd, const cli_arg_t *g, bench_common_t *c, int *rc) {
  if (!g->spec) {
    fprintf(stderr, "pencil %s: unexpected argument '%s'\n", cmd, g->value);
    *rc = CLI_USAGE;
    return 1;
  }
  switch (g->spec->id) {
  case B_JSON:
    c->json = g->value;
    return 1;
  case B_OUT:
    c->out = g->value;
    return 1;
  case B_RUNS:
    *rc = cli_parse_long("--runs", g->value, 1, 15, &c->runs) ? CLI_OK : CLI_USAGE;
    c->runs_given = 1;
    return 1;
  case B_THREADS:
    *rc = cli_parse_long("--threads", g->value, 1, 1024, &c->threads) ? CLI_OK : CLI_USAGE;
    return 1;
  case B_QUICK:
    c->quick = 1;
    return 1;
  case B_SCENES:
    c->scenes = g->value;
    return 1;
  default:
    return 0;
  }
}

/* --case LIST of `cmd`: comma-separated names that ok() accepts (names: the list for the
 * message); CLI_OK or CLI_USAGE after a message. */
static int case_list(const char *cmd, const char *value, int (*ok)(const char *, char *, size_t),
                     const char *names) {
  char bad[256], buf[256];
  const char *item[16];
  int nc;
  if (!cli_split_list("--case", value, buf, sizeof buf, item, 16, &nc))
    return CLI_USAGE;
  if (!ok(value, bad, sizeof bad)) {
    fprintf(stderr, "pencil %s: --case: no case '%s' (%s)\n", cmd, bad, names);
    return CLI_USAGE;
  }
  return CLI_OK;
}

/* The outputs of `cmd` checked before minutes of work: --out (or another directory option,
 * `dir`) made, --json writable; CLI_OK or CLI_USAGE after a message. */
static int common_outputs(const char *cmd, const char *dir, const char *json) {
  char err[1024];
  if (dir && io_make_dirs(dir) != 0)
    return CLI_USAGE;
  if (json && io_output_check(json, err, sizeof err) != 0) {
    fprintf(stderr, "pencil %s: --json: %s\n", cmd, err);
    return CLI_USAGE;
  }
  return CLI_OK;
}

static void help_illum(FILE *f) {
  fprintf(f,
          "usage: pencil bench illuminance [--json FILE] [--maps DIR] [--threads N] [--quick]\n"
          "                                [--fig11 SCENE.json]\n"
          "                                [--max-split S] [--linear-tol C] [--uniform-tol R]\n\n"
          "Illuminance maps (pencil illuminance) against exact references: a glass ball over a\n"
          "floor lit along its axis by a parallel and by a point light, whose exact map is a\n"
          "one-dimensional integral over meridional rays. Reports, per method, the rays, the\n"
          "time, the largest relative error over the cells where the exact field is smooth\n"
          "(varies by less than 10%% and has no edge), the RMS error over the map relative to\n"
          "its mean, and the total flux's error. Targets (issue 21): grid-pencil within 1%% on\n"
          "smooth cells, flux within 0.5%%; photon counting is given the same number of rays.\n\n"
          "options:\n"
          "  --json FILE   also write the results as JSON\n"
          "  --maps DIR    also write the ball cases' maps (exact, grid-pencil, photons) there as\n"
          "                CASE-METHOD.exr/.json: notebooks/illuminance.ipynb plots them\n"
          "  --threads N   OpenMP threads (default: all cores)\n"
          "  --quick       small maps and grids (tests; no Fig. 11)\n"
          "  --fig11 SCENE.json\n"
          "                the Fig. 11 scene (default: scenes/fig11.json of the source tree the\n"
          "                command was built from)\n"
          "  --max-split S, --linear-tol C, --uniform-tol R\n"
          "                the grid-pencil runs' settings (pencil illuminance; defaults its own)\n"
          "Exit codes: 0 targets met; 1 not met, or the work failed; 2 usage, a Fig. 11\n"
          "scene that cannot be read, an output that cannot be written.\n");
}

static int bench_illuminance(int argc, char **argv) {
  static const cli_spec_t specs[] = {
      {"--json", 0, 1, B_JSON},          {"--threads", 0, 1, B_THREADS},
      {"--quick", 0, 0, B_QUICK},        {"--max-split", 0, 1, B_OWN},
      {"--linear-tol", 0, 1, B_OWN + 1}, {"--uniform-tol", 0, 1, B_OWN + 2},
      {"--maps", 0, 1, B_OWN + 3},       {"--fig11", 0, 1, B_OWN + 4}};
  const char *cmd = "bench illuminance";
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc, argv, specs, 8, help_illum, &n, &rc);
  if (!args)
    return rc;
  lt_options_t d = LT_OPTIONS_DEFAULT;
  val_illum_bench_opts_t o;
  memset(&o, 0, sizeof o);
  o.max_split = d.max_split;
  o.linear_tol = d.linear_tol;
  o.uniform_tol = d.uniform_tol;
  o.report = stdout;
  bench_common_t c = {0};
  long split = d.max_split;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (common_arg(cmd, g, &c, &rc))
      continue;
    if (g->spec->id == B_OWN + 3) {
      o.maps = g->value;
    } else if (g->spec->id == B_OWN + 4) {
      o.fig11 = g->value;
    } else if (g->spec->id == B_OWN) {
      rc = cli_parse_long("--max-split", g->value, 0, 12, &split) ? CLI_OK : CLI_USAGE;
    } else {
      double *t = g->spec->id == B_OWN + 1 ? &o.linear_tol : &o.uniform_tol;
      rc = cli_parse_double_in(g->spec->name, g->value, 0, 1e6, t) ? CLI_OK : CLI_USAGE;
    }
  }
  free(args);
  if (rc != CLI_OK)
    return rc;
  if (c.quick && o.fig11) {
    fprintf(stderr,
            "pencil bench illuminance: --fig11 has no effect with --quick (which leaves out "
            "Fig. 11)\n");
    return CLI_USAGE;
  }
  o.json = c.json;
  o.quick = c.quick;
  o.threads = (int)c.threads;
  o.max_split = (int)split;
  if ((rc = common_outputs(cmd, o.maps, o.json)) != CLI_OK) /* before minutes of tracing */
    return rc;
  return cli_exit_of(val_bench_illuminance(&o));
}

static void help_caustics(FILE *f) {
  fprintf(f, "usage: pencil bench caustics [--json FILE] [--out DIR] [--runs N] [--threads N]\n"
             "                             [--quick] [--scenes DIR] [--reference-rays N]\n"
             "                             [--case NAME[,NAME...]]\n\n"
             "Renders with caustics (issue 25) against the exact renderer with a converged\n"
             "backward-ray-traced map (photons, 8193 or 16384 rays a side of a grid face), on\n"
             "Fig. 8 with caustics (case fig8, scenes/fig8-caustics.json), the 1987 Fig. 11\n"
             "(fig11, fig11-caustics.json), the 1989 Fig. 8 pool (pool, pool.json) and the\n"
             "1989 Fig. 10 glass of water under an area light (glass, glass.json, at 256 x 171,\n"
             "9 spp), each at its own size and samples: the exact\n"
             "renderer with its default map (photons), the pencil renderer with its own\n"
             "(grid-pencils) and, for polyhedral scenes, with illuminance polygons, and the\n"
             "textbook's image (caustics off). Per pixel (the largest of R, G, B) the RMS, 99th\n"
             "percentile and largest difference from the reference; each render's time (median\n"
             "of the runs, maps included) and the time ratios; the reference's own RMS error,\n"
             "estimated from a second reference with half the rays. The exact renderer with the\n"
             "pencil renderer's grid-pencil map compares the maps alone (and how many photons\n"
             "would match it, by 1/sqrt(N)); the pencil renderer with caustics off, against the\n"
             "exact textbook image, gives its own error apart from the maps'.\n\n"
             "options:\n"
             "  --json FILE   also write the results as JSON\n"
             "  --out DIR     also write every image as DIR/CASE-VARIANT.exr and .png\n"
             "  --runs N      timed runs per render, the median reported (default 3)\n"
             "  --threads N   OpenMP threads (default: all cores)\n"
             "  --quick       48 x 48 images, 1 spp, small maps (tests)\n"
             "  --scenes DIR  the directory holding the scenes (default: scenes/ of the\n"
             "                source tree the command was built from)\n"
             "  --reference-rays N\n"
             "                rays a side of the reference's photon grids, 3..16384 (default 8193\n"
             "                for Fig. 8, 16384 for the others; --quick 513); the half reference\n"
             "                takes N / sqrt(2); an area light's N x N points share them\n"
             "  --case LIST   only these cases, comma-separated (default: all four)\n"
             "Exit codes: 0 done; 1 the work failed (out of memory, a render, a write);\n"
             "2 usage, a scene that cannot be read, an output that cannot be written.\n");
}

static int bench_caustics(int argc, char **argv) {
  static const cli_spec_t specs[] = {
      {"--json", 0, 1, B_JSON},          {"--out", 0, 1, B_OUT},     {"--runs", 0, 1, B_RUNS},
      {"--threads", 0, 1, B_THREADS},    {"--quick", 0, 0, B_QUICK}, {"--scenes", 0, 1, B_SCENES},
      {"--reference-rays", 0, 1, B_OWN}, {"--case", 0, 1, B_OWN + 1}};
  const char *cmd = "bench caustics";
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc, argv, specs, 8, help_caustics, &n, &rc);
  if (!args)
    return rc;
  val_caustic_bench_opts_t o;
  memset(&o, 0, sizeof o);
  o.report = stdout;
  bench_common_t c = {.runs = 3};
  long ref_rays = 0;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (common_arg(cmd, g, &c, &rc))
      continue;
    if (g->spec->id == B_OWN) {
      rc = cli_parse_long("--reference-rays", g->value, 3, LT_MAX_GRID, &ref_rays) ? CLI_OK
                                                                                   : CLI_USAGE;
    } else {
      o.cases = g->value;
      rc = case_list(cmd, g->value, val_bench_caustics_cases_ok, "fig8, fig11, pool or glass");
    }
  }
  free(args);
  if (rc != CLI_OK || (rc = common_outputs(cmd, c.out, c.json)) != CLI_OK)
    return rc;
  o.json = c.json;
  o.out = c.out;
  o.scenes = c.scenes;
  o.quick = c.quick;
  o.runs = (int)c.runs;
  o.threads = (int)c.threads;
  o.ref_rays = (int)ref_rays;
  return cli_exit_of(val_bench_caustics(&o));
}

static void help_area(FILE *f) {
  fprintf(f, "usage: pencil bench area [--json FILE] [--out DIR] [--runs N] [--threads N]\n"
             "                         [--quick] [--reference-mesh M]\n\n"
             "Area lights (the 1989 paper's section 2.3) traced as M x M meshes of Lambertian\n"
             "point sources: M = 1, 2, 4, 8 as the plain sum of the points' grid-pencil maps,\n"
             "and M = 1, 2, 4 with the space-variant filter of the 1989 Eqs. (9)-(12), its\n"
             "displacement quadratic over the mesh cell and linear as the printed Eq. (10) has\n"
             "it; against the brute-force sum of M_ref x M_ref point sources (64 x 64; its own\n"
             "error estimated from 32 x 32): the RMS and 99th percentile of the difference over\n"
             "the reference's mean, the largest over its peak, the flux, the rays and the time,\n"
             "for\n"
             "  floor   a bare floor under a rectangle (also against the exact illuminance, known\n"
             "          in closed form; Eq. 9 holds exactly there),\n"
             "  ball    a glass ball over a floor past its focus (light through it only);\n"
             "and the ball with its light scaled by 1/4 .. 2 at M = 2 against 24 x 24 points:\n"
             "the filter's error as the mesh cells outgrow Eq. (9)'s small-source assumption.\n\n"
             "options:\n"
             "  --json FILE   also write the results as JSON\n"
             "  --out DIR     also write every map as DIR/CASE-VARIANT.exr (channel E), .png and\n"
             "                .json, and the tables as DIR/area-curve.csv and DIR/area-size.csv\n"
             "  --runs N      timed runs of each map, the median reported (default 1)\n"
             "  --threads N   OpenMP threads (default: all cores)\n"
             "  --quick       32 x 32 maps, M = 1, 2 against 16 x 16 points (tests)\n"
             "  --reference-mesh M\n"
             "                the reference's points a side, 2..256 (default 64; --quick 16)\n"
             "Exit codes: 0 done; 1 the work failed (out of memory, a render, a write);\n"
             "2 usage, a scene that cannot be read, an output that cannot be written.\n");
}

static int bench_area(int argc, char **argv) {
  static const cli_spec_t specs[] = {{"--json", 0, 1, B_JSON},   {"--out", 0, 1, B_OUT},
                                     {"--runs", 0, 1, B_RUNS},   {"--threads", 0, 1, B_THREADS},
                                     {"--quick", 0, 0, B_QUICK}, {"--reference-mesh", 0, 1, B_OWN}};
  const char *cmd = "bench area";
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc, argv, specs, 6, help_area, &n, &rc);
  if (!args)
    return rc;
  val_area_bench_opts_t o;
  memset(&o, 0, sizeof o);
  o.report = stdout;
  bench_common_t c = {.runs = 1};
  long ref_mesh = 0;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (!common_arg(cmd, g, &c, &rc))
      rc = cli_parse_long("--reference-mesh", g->value, 2, LT_MAX_AREA_MESH, &ref_mesh) ? CLI_OK
                                                                                        : CLI_USAGE;
  }
  free(args);
  if (rc != CLI_OK || (rc = common_outputs(cmd, c.out, c.json)) != CLI_OK)
    return rc;
  o.json = c.json;
  o.out = c.out;
  o.quick = c.quick;
  o.runs = (int)c.runs;
  o.threads = (int)c.threads;
  o.ref_mesh = (int)ref_mesh;
  return cli_exit_of(val_bench_area(&o));
}

static void help_beam(FILE *f) {
  fprintf(f,
          "usage: pencil bench beam [--json FILE] [--out DIR] [--runs N] [--threads N]\n"
          "                         [--quick] [--size N] [--rho R] [--scenes DIR]\n"
          "                         [--case NAME[,NAME...]]\n\n"
          "Beam tracing of polyhedra (issue 24; 1987 section 4.1 (3), Fig. 11) against the\n"
          "exact and the pencil renderers. Each case is the Fig. 11 set-up (scenes/fig11.json:\n"
          "three coloured rectangles, a point light, its camera) with a glass polyhedron: the\n"
          "paper's torus of 100 faces (fig11), a triangular prism (prism), or UV spheres of\n"
          "100 to 10,000 faces (sphere100 ... sphere10000). The reference is the exact renderer\n"
          "at 256 spp. Against it, per pixel the largest of R, G, B: mean, 99th percentile and\n"
          "largest difference, with the median time of the runs, of the beam renderer (Eq. (4)\n"
          "bounds, and probes only), the exact renderer at 1, 4, 16 and 64 spp, and the pencil\n"
          "renderer at 16 spp. The exact renderer's time at the beams' mean error is\n"
          "interpolated on its ladder (log-log); the ratio exact / beam at equal error is the\n"
          "cost curve against facet count.\n\n"
          "options:\n"
          "  --json FILE   also write the results as JSON\n"
          "  --out DIR     also write every image as DIR/CASE-VARIANT.exr and .png\n"
          "  --runs N      timed runs per render, the median reported, 1..15 (default 3)\n"
          "  --threads N   OpenMP threads (default: all cores)\n"
          "  --quick       32 x 32 images, the reference at 144 spp, cases fig11, prism and\n"
          "                sphere100 (tests)\n"
          "  --size N      image side in pixels, 8..4096 (default 256)\n"
          "  --rho R       the beam renderer's tolerance, > 0 (default 0.5)\n"
          "  --scenes DIR  the directory holding fig11.json (default: scenes/ of the source\n"
          "                tree the command was built from)\n"
          "  --case LIST   only these cases, comma-separated (%s)\n"
          "Exit codes: 0 done; 1 the work failed (out of memory, a render, a write);\n"
          "2 usage, a scene that cannot be read, an output that cannot be written.\n",
          val_bench_beam_case_names());
}

static int bench_beam(int argc, char **argv) {
  static const cli_spec_t specs[] = {
      {"--json", 0, 1, B_JSON},       {"--out", 0, 1, B_OUT},      {"--runs", 0, 1, B_RUNS},
      {"--threads", 0, 1, B_THREADS}, {"--quick", 0, 0, B_QUICK},  {"--scenes", 0, 1, B_SCENES},
      {"--size", 0, 1, B_OWN},        {"--case", 0, 1, B_OWN + 1}, {"--rho", 0, 1, B_OWN + 2}};
  const char *cmd = "bench beam";
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc, argv, specs, 9, help_beam, &n, &rc);
  if (!args)
    return rc;
  val_beam_bench_opts_t o;
  memset(&o, 0, sizeof o);
  o.report = stdout;
  o.rho = 0.5;
  bench_common_t c = {.runs = 3};
  long size = 0;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (common_arg(cmd, g, &c, &rc))
      continue;
    if (g->spec->id == B_OWN) {
      rc = cli_parse_long("--size", g->value, 8, 4096, &size) ? CLI_OK : CLI_USAGE;
    } else if (g->spec->id == B_OWN + 2) {
      rc = cli_parse_double_in("--rho", g->value, 1e-6, 1e6, &o.rho) ? CLI_OK : CLI_USAGE;
    } else {
      o.cases = g->value;
      rc = case_list(cmd, g->value, val_bench_beam_cases_ok, val_bench_beam_case_names());
    }
  }
  free(args);
  if (rc != CLI_OK || (rc = common_outputs(cmd, c.out, c.json)) != CLI_OK)
    return rc;
  o.json = c.json;
  o.out = c.out;
  o.scenes = c.scenes;
  o.quick = c.quick;
  o.runs = (int)c.runs;
  o.threads = (int)c.threads;
  o.size = (int)size;
  return cli_exit_of(val_bench_beam(&o));
}

static void help_dispersion(FILE *f) {
  fprintf(f, "usage: pencil bench dispersion [--json FILE] [--out DIR] [--runs N] [--threads N]\n"
             "                               [--quick] [--size N] [--reference-bins N]\n"
             "                               [--spp N] [--reference-spp N] [--scenes DIR]\n\n"
             "The 1989 paper's Fig. 14 table (section 3.3; issue 22): scenes/fig14.json, a\n"
             "polyhedron of 120 polygons of SF11 glass, rendered by each method, with its median\n"
             "time and its colour error against a converged spectral reference (the exact\n"
             "renderer's spectral fan with R bins): CIEDE2000 per pixel, mean, 99th percentile\n"
             "and largest. Methods: pencil (the glass at n_d), pencil-spectral (the pencil\n"
             "renderer with spectral pencils), exact-nd (the exact renderer with\n"
             "--wavelengths off: the conventional non-dispersive tracer), exact-takagi9 (every\n"
             "primary ray at 9 wavelengths: the paper's conventional dispersive method),\n"
             "exact-fan9 and exact-fan40 (the spectral fan), exact-spectral-pencil (one spectral\n"
             "pencil per white refraction: an axial ray and its wavelength column, the 1989\n"
             "paper's Eq. 13), the fan with R/2 bins (how far the reference has converged),\n"
             "and the beam renderer (polyhedra): beam (the glass at n_d), beam-solids\n"
             "(dispersion image solids, the 1989 paper's method) and beam-pencils (spectral\n"
             "pencils from each cell share; JSON: beams). The pencil renderer's paths do not\n"
             "carry the wavelength column yet. The last\n"
             "line gives the issue's targets with their verdicts (pencil-spectral at most 1.3\n"
             "times pencil's time, its mean dE2000 at most 1) and the paper's claim that the\n"
             "dispersive pencil is faster than exact-nd; a missed target is reported, not an\n"
             "exit code (JSON: targets).\n\n"
             "options:\n"
             "  --json FILE          also write the results as JSON\n"
             "  --out DIR            also write every image as DIR/fig14-METHOD.exr and .png\n"
             "  --runs N             timed runs per method, the median reported, 1..15\n"
             "                       (default 3; the reference runs once)\n"
             "  --threads N          OpenMP threads (default: all cores)\n"
             "  --quick              48 x 48, the reference at 100 bins, 1 run (tests)\n"
             "  --size N             image side in pixels, 8..4096 (default 256)\n"
             "  --reference-bins N   the reference's bins, 8..400 (default 400)\n"
             "  --spp N              every method's samples per pixel, a square (default: the\n"
             "                       scene's, 1)\n"
             "  --reference-spp N    the reference's samples per pixel, a square (default: as\n"
             "                       --spp); above the methods' its pixels approach area\n"
             "                       averages, as beams compute, so that point-sampling\n"
             "                       methods at higher --spp are compared at equal error\n"
             "  --scenes DIR         the directory holding fig14.json (default: scenes/ of the\n"
             "                       source tree the command was built from)\n"
             "Exit codes: 0 done; 1 the work failed (out of memory, a render, a write);\n"
             "2 usage, a scene that cannot be read, an output that cannot be written.\n");
}

static int bench_dispersion(int argc, char **argv) {
  static const cli_spec_t specs[] = {
      {"--json", 0, 1, B_JSON},   {"--out", 0, 1, B_OUT},
      {"--runs", 0, 1, B_RUNS},   {"--threads", 0, 1, B_THREADS},
      {"--quick", 0, 0, B_QUICK}, {"--scenes", 0, 1, B_SCENES},
      {"--size", 0, 1, B_OWN},    {"--reference-bins", 0, 1, B_OWN + 1},
      {"--spp", 0, 1, B_OWN + 2}, {"--reference-spp", 0, 1, B_OWN + 3}};
  const char *cmd = "bench dispersion";
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc, argv, specs, 10, help_dispersion, &n, &rc);
  if (!args)
    return rc;
  val_dispersion_bench_opts_t o;
  memset(&o, 0, sizeof o);
  o.report = stdout;
  bench_common_t c = {.runs = 3};
  long size = 0, bins = 0, spp = 0, ref_spp = 0;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (common_arg(cmd, g, &c, &rc))
      continue;
    if (g->spec->id == B_OWN) {
      rc = cli_parse_long("--size", g->value, 8, 4096, &size) ? CLI_OK : CLI_USAGE;
    } else if (g->spec->id == B_OWN + 1) {
      rc = cli_parse_long("--reference-bins", g->value, 8, 400, &bins) ? CLI_OK : CLI_USAGE;
    } else {
      long *v = g->spec->id == B_OWN + 2 ? &spp : &ref_spp;
      rc = cli_parse_spp(cmd, g->spec->name, g->value, v) ? CLI_OK : CLI_USAGE;
    }
  }
  free(args);
  if (rc != CLI_OK || (rc = common_outputs(cmd, c.out, c.json)) != CLI_OK)
    return rc;
  o.json = c.json;
  o.out = c.out;
  o.scenes = c.scenes;
  o.quick = c.quick;
  o.runs = c.quick && !c.runs_given ? 1 : (int)c.runs;
  o.threads = (int)c.threads;
  o.size = (int)size;
  o.ref_bins = (int)bins;
  o.spp = (int)spp;
  o.ref_spp = (int)ref_spp;
  return cli_exit_of(val_bench_dispersion(&o));
}

static void help_star(FILE *f) {
  fprintf(f, "usage: pencil bench star [--runs N] [--sizes N[,N...]] [--threads N] [--json FILE]\n"
             "                         [--same-pixels]\n\n"
             "The cross-screen filter (pencil post star, 1989 section 4) on synthetic HDR images:\n"
             "a dim random background with sun-like spots 3,200 times brighter, three channels,\n"
             "the default plate (its kernel scales with the image: the same star on the sensor).\n"
             "For each size, with 1 thread and with N: the median wall-clock time of the runs of\n"
             "the filter (kernel, FFTs, products; not reading or writing files), the kernel's\n"
             "share, and the FFT grid. Targets (issue 23): 512 x 512 under 50 ms on one core,\n"
             "4096 x 4096 under 2 s.\n\n"
             "options:\n"
             "  --runs N        runs per configuration, 1..101 (default 5)\n"
             "  --sizes LIST    image sides, 16..8192 (default 512,4096)\n"
             "  --threads N     the second configuration's threads (default: all cores)\n"
             "  --json FILE     also write the results as JSON\n"
             "  --same-pixels   the 512 x 512 image's kernel in pixels at every size (the sensor\n"
             "                  grows with the image) instead of the same star on the sensor\n"
             "Exit codes: 0 done; 1 the work failed (out of memory, a render, a write);\n"
             "2 usage, a scene that cannot be read, an output that cannot be written.\n");
}

/* A synthetic HDR plane: background in [0, 0.2), a few spots 3,200 times the background's mean. */
static void star_plane(float *p, int side, unsigned seed) {
  for (size_t k = 0; k < (size_t)side * side; k++) {
    seed = seed * 1664525u + 1013904223u;
    p[k] = 0.2f * (float)(seed >> 8) / 16777216.0f;
  }
  for (int s = 0; s < 12; s++) {
    seed = seed * 1664525u + 1013904223u;
    size_t k = (size_t)(seed >> 4) % ((size_t)side * side);
    p[k] = 320.0f;
  }
}

static int bench_star(int argc, char **argv) {
  static const cli_spec_t specs[] = {{"--runs", 0, 1, 1},
                                     {"--sizes", 0, 1, 2},
                                     {"--threads", 0, 1, 3},
                                     {"--json", 0, 1, 4},
                                     {"--same-pixels", 0, 0, 5}};
  int n, rc, same = 0;
  cli_arg_t *args = cli_args("bench star", argc, argv, specs, 5, help_star, &n, &rc);
  if (!args)
    return rc;
  long runs = 5, threads = 0;
  int sizes[8] = {512, 4096}, nsizes = 2;
  const char *json = NULL;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (!g->spec) {
      fprintf(stderr, "pencil bench star: unexpected argument '%s'\n", g->value);
      rc = CLI_USAGE;
    } else if (g->spec->id == 1) {
      rc = cli_parse_long("--runs", g->value, 1, MAX_RUNS, &runs) ? CLI_OK : CLI_USAGE;
    } else if (g->spec->id == 2) {
      char buf[256];
      const char *item[8];
      if (!cli_split_list("--sizes", g->value, buf, sizeof buf, item, 8, &nsizes))
        rc = CLI_USAGE;
      for (int q = 0; q < nsizes && rc == CLI_OK; q++) {
        long v;
        rc = cli_parse_long("--sizes", item[q], 16, 8192, &v) ? CLI_OK : CLI_USAGE;
        sizes[q] = (int)v;
      }
    } else if (g->spec->id == 3) {
      rc = cli_parse_long("--threads", g->value, 1, 1024, &threads) ? CLI_OK : CLI_USAGE;
    } else if (g->spec->id == 5) {
      same = 1;
    } else {
      json = g->value;
    }
  }
  free(args);
  if (rc != CLI_OK)
    return rc;
  char err[1024], why[512] = "";
  if (json && io_output_check(json, err, sizeof err) != 0) {
    fprintf(stderr, "pencil bench star: --json: %s\n", err);
    return CLI_USAGE;
  }
  int nt = threads > 0 ? (int)threads : rt_thread_count(0);
  pp_star_t p = PP_STAR_DEFAULT;
  json_t *rows = json_array();
  printf("pencil bench star: the cross-screen filter, default plate, 3 channels, median of %ld "
         "run(s)\n%6s %7s %10s %10s %12s\n",
         runs, "size", "threads", "seconds", "kernel s", "kernel side");
  for (int q = 0; q < nsizes && rc == CLI_OK; q++) {
    int side = sizes[q];
    size_t np = (size_t)side * side;
    p.frame_mm = same ? 36.0 * side / 512.0 : 36.0;
    float *in[3], *out[3];
    int ok = 1;
    for (int c = 0; c < 3; c++) {
      in[c] = malloc(np * sizeof(float));
      out[c] = malloc(np * sizeof(float));
      ok = ok && in[c] && out[c];
      if (in[c])
        star_plane(in[c], side, 17u + (unsigned)c);
    }
    for (int th = 0; th < 2 && ok; th++) {
      int t = th ? nt : 1;
      double tk[MAX_RUNS], ta[MAX_RUNS];
      int kside = 0;
      for (int r = 0; r < runs && ok; r++) {
        pp_kernel_t k;
        double t0 = val_wall_seconds();
        ok = pp_star_kernel(&p, side, side, &k, why, sizeof why) == 0;
        double t1 = val_wall_seconds();
        ok = ok && pp_star_apply(&k, side, side, 3, (const float *const *)in, out, t, NULL, why,
                                 sizeof why) == 0;
        ta[r] = val_wall_seconds() - t0;
        tk[r] = t1 - t0;
        kside = k.side;
        pp_kernel_free(&k);
      }
      if (!ok)
        break;
      double med = val_median(ta, (int)runs), medk = val_median(tk, (int)runs);
      printf("%6d %7d %10.4f %10.4f %12d\n", side, t, med, medk, kside);
      json_array_append_new(rows, json_pack("{s:i, s:i, s:f, s:f, s:i, s:b}", "size", side,
                                            "threads", t, "seconds", med, "kernel_seconds", medk,
                                            "kernel_side", kside, "same_pixels", same));
      if (nt == 1)
        break;
    }
    if (!ok) {
      fprintf(stderr, "pencil bench star: %s\n", why[0] ? why : "out of memory");
      rc = CLI_FAIL;
    }
    for (int c = 0; c < 3; c++) {
      free(in[c]);
      free(out[c]);
    }
  }
  if (rc == CLI_OK && json) {
    json_t *root =
        json_pack("{s:s, s:i, s:o}", "benchmark", "star", "runs", (int)runs, "rows", rows);
    if (io_json_write(json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil bench star: %s\n", err);
      rc = CLI_FAIL;
    }
    json_decref(root);
  } else {
    json_decref(rows);
  }
  return rc;
}

/* `pencil bench render [--runs N] [--size WxH] [--spp N] [--json FILE]`; argv[0] is "render". */
static int bench_render(int argc, char **argv) {
  long runs = 5, w = 256, h = 256, spp = 4;
  const char *json = NULL;
  static const cli_spec_t specs[] = {
      {"--runs", 0, 1, 1}, {"--size", 0, 1, 2}, {"--spp", 0, 1, 3}, {"--json", 0, 1, 4}};
  int n, rc;
  cli_arg_t *args = cli_args("bench render", argc, argv, specs, 4, help, &n, &rc);
  if (!args)
    return rc;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const char *v = args[k].value; /* points into argv, not into args */
    char err[1024];
    int id = args[k].spec ? args[k].spec->id : 0;
    if (id == 0) {
      fprintf(stderr, "pencil bench render: unexpected argument '%s' (see --help)\n", v);
      rc = CLI_USAGE;
    } else if (id == 1 && !cli_parse_long("--runs", v, 1, MAX_RUNS, &runs)) {
      rc = CLI_USAGE;
    } else if (id == 2 && !cli_parse_wxh("bench render", "--size", v, 4096, &w, &h)) {
      rc = CLI_USAGE;
    } else if (id == 3 && !cli_parse_spp("bench render", "--spp", v, &spp)) {
      rc = CLI_USAGE;
    } else if (id == 4) {
      json = v;
      if (io_output_check(json, err, sizeof err) != 0) { /* before minutes of rendering */
        fprintf(stderr, "pencil bench render: --json: %s\n", err);
        rc = CLI_USAGE;
      }
    }
  }
  free(args);
  if (rc != CLI_OK)
    return rc;
  return run((int)runs, w, h, (int)lrint(sqrt((double)spp)), json);
}

/* The benchmarks: `pencil bench --help`, the dispatch and the list an unknown name is given all
 * come from this table. */
static const struct {
  const char *name;
  int (*run)(int argc, char **argv); /**< argv[0] is the benchmark's name */
  const char *summary;
} benches[] = {
    {"render", bench_render, "exact-tracing rays per second (Fig. 8 scene, 1,000-polygon scene)"},
    {"pencil", cmd_bench_pencil, "pencil / exact CPU-time ratio and accuracy at 49 spp (issue 5)"},
    {"illuminance", bench_illuminance, "illuminance maps against exact references (issue 21)"},
    {"caustics", bench_caustics, "renders with caustics against a converged reference (issue 25)"},
    {"area", bench_area, "area lights: meshes, plain and filtered, against the brute force"},
    {"beam", bench_beam, "beam tracing of polyhedra against exact and pencil at equal error"},
    {"star", bench_star, "the cross-screen filter: 512 x 512 and 4096 x 4096 HDR images"},
    {"dispersion", bench_dispersion,
     "1989 Fig. 14: dispersive glass, each method's time, CIEDE2000"},
};
#define NBENCHES (sizeof benches / sizeof benches[0])

/* "render, pencil, ... or dispersion" (sep ", ", last " or ") or "render|pencil|..." (sep "|"). */
static void bench_names(FILE *f, const char *sep, const char *last) {
  for (size_t k = 0; k < NBENCHES; k++)
    fprintf(f, "%s%s", k == 0 ? "" : k + 1 < NBENCHES ? sep : last, benches[k].name);
}

static void help_bench(FILE *f) {
  fprintf(f, "usage: pencil bench ");
  bench_names(f, "|", "|");
  fprintf(f, "\n                    [OPTIONS]\n\nbenchmarks:\n");
  for (size_t k = 0; k < NBENCHES; k++)
    fprintf(f, "  %-12s %s\n", benches[k].name, benches[k].summary);
  fprintf(f, "'pencil bench NAME --help' describes each.\n");
}

int cmd_bench(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help_bench(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  for (size_t k = 0; k < NBENCHES; k++)
    if (strcmp(argv[1], benches[k].name) == 0)
      return benches[k].run(argc - 1, argv + 1);
  fprintf(stderr, "pencil bench: unknown benchmark '%s' (available: ", argv[1]);
  bench_names(stderr, ", ", " and ");
  fprintf(stderr, ")\n");
  return CLI_USAGE;
}
