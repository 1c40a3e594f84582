/* cmd_bench_pencil.c -- `pencil bench pencil`: the speed targets of issue 5 on the paper's Fig. 8
 * scene (section 5, Figs. 9 and 10): at 49 samples per pixel the pencil tracer's CPU time is at
 * most 1/10 of exact tracing's with >= 99.8% of the image area within rho = 1/2 (default mode),
 * and 100% within rho at the same time ratio (certified mode).
 *
 * Times are the validation drivers' (val_time_pair: process CPU seconds, median of N runs, exact
 * and pencil renders interleaved in this process, no auxiliary channels); the ratio is taken
 * within one invocation, never across runs of the command. Accuracy comes from one separate
 * measured render per mode (val_measure: Fig. 10 error of every sample). Speed is measured here,
 * never in a timed test (docs/DEVELOPING.md). A missed target is a result, not a failure.
 *
 * --peer povray times POV-Ray 3.7 on the same scene beside them (issue 26, "a peer beside the
 * exact renderer"; validation/povray.h): the scene exported for each spp, POV-Ray run after the
 * exact and pencil renders of each default-mode run, its "Trace Time" CPU seconds taken. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "args.h"
#include "cli.h"
#include "io/json.h"
#include "io/output.h"
#include "pencil/pencil.h"
#include "validation/figures.h"
#include "validation/povray.h"
#include "validation/timing.h"

/* The targets of issue 5 (the paper's Fig. 9 falls below 0.1 at 49 spp; Fig. 10: 99.8%). */
#define TARGET_SPP 49
#define TARGET_RHO 0.5
#define TARGET_RATIO 0.1
#define TARGET_WITHIN 0.998 /* default mode; the certified mode needs every sample */

#define MAX_SPP 8 /* values in --spp */

static void help(FILE *f) {
  fprintf(
      f, "usage: pencil bench pencil [SCENE.json] [--spp 49[,N...]] [--runs N] [--threads N]\n"
         "                           [--rho R] [--brightness-tol L] [--size WxH] [--json FILE]\n"
         "                           [--no-measure] [--method NAME] [--peer povray]\n"
         "                           [--tolerance geometric|image]\n\n"
         "The speed targets of issue 5 on SCENE.json or the built-in Fig. 8 scene (a glass sphere\n"
         "over a checkerboard, 256x256): at 49 samples per pixel, pencil time <= 1/10 of exact\n"
         "time with >= 99.8%% of the samples (the image area) within rho = 1/2, and the certified\n"
         "mode with 100%% of the samples within rho at <= 1/10 of exact time.\n\n"
         "For each spp and each mode (default, certified), N exact and N pencil renders are\n"
         "timed interleaved in this process (process CPU seconds, no auxiliary channels) and the\n"
         "ratio of the medians is reported; then one measured pencil render per mode gives the\n"
         "Fig. 10 error of every sample (distance between the points of pencil and exact\n"
         "tracing on surfaces with a diffuse term - the checkerboard in Fig. 8 - in pixel\n"
         "intervals): fraction within rho, samples over rho, largest error, 99th percentile;\n"
         "and its image against an exact render: RMS and largest pixel difference, and the\n"
         "largest mean difference over the pixels of one object (by the exact image's centre\n"
         "rays; objects of at least 100 pixels), which a systematic error shows and the\n"
         "checkerboard's flips at rho = 1/2 (both ways) do not.\n"
         "The target column is filled at 49 spp with rho = 0.5 and the default brightness\n"
         "tolerance or a tighter one; a missed target is reported in\n"
         "the table and the JSON, not by the exit code. A scene without such a surface has\n"
         "nothing to measure: a warning says so and no target counts as met.\n\n"
         "options:\n"
         "  --spp LIST     comma-separated squares 1, 4, ..., 1024 (default 49)\n"
         "  --runs N       timed renders per method and mode, 3..101 (default 5)\n"
         "  --threads N    threads of every render, 1..1024 (default 1, the paper's single CPU)\n"
         "  --rho R        tolerance ratio of Eq. (3), > 0 (default 0.5)\n"
         "  --brightness-tol L\n"
         "                 ray interpolation's brightness tolerance, >= 0 (default 1/1024);\n"
         "                 with --rho 100 --brightness-tol 100 the ratio is what the pencil\n"
         "                 costs when no accuracy is asked of it\n"
         "  --tolerance T  what rho bounds per surface in the pencil renders: geometric (the\n"
         "                 paper's, default) or image (rho / W on a surface whose light reaches\n"
         "                 the pixel with weight W: pencil render --method pencil --help); with\n"
         "                 image the error columns count each point in its own tolerance, the\n"
         "                 image against exact is the measure that matters, and no target is\n"
         "                 judged (the targets are the paper's tolerance's)\n"
         "  --size WxH     override the image size (1 <= W, H <= 4096)\n"
         "  --json FILE    also write the results as JSON\n"
         "  --no-measure   skip the measured renders (times only; no accuracy, no verdict)\n"
         "  --method NAME  the renderer timed and measured against exact tracing (default\n"
         "                 pencil; it must take --rho, --brightness-tol and --certified)\n"
         "  --peer povray  also time POV-Ray 3.7 on the same scene (pencil export pov): for\n"
         "                 each spp = s^2 it renders the exported scene at s times the size\n"
         "                 without anti-aliasing (its pixel centres are the s x s grid), with\n"
         "                 --threads render threads and no output file, after the exact and\n"
         "                 pencil renders of each default-mode run; its time is the CPU time\n"
         "                 of its statistics' Trace Time (parsing and start-up excluded).\n"
         "                 Skipped with a note when povray is not installed or the scene\n"
         "                 cannot be exported (default: no peer)\n"
         "A second table gives rays per second: the exact renderer's rays (primary,\n"
         "reflected, refracted, shadow) over its time, the same count over the pencil's time\n"
         "(the rate at which it delivers the exact renderer's image), and POV-Ray's own count\n"
         "(its Rays and Shadow Ray Tests) over its time; and the time ratios side by side.\n"
         "Exit codes: 0 done (whether or not the targets were met); 1 a render or the JSON file\n"
         "failed; 2 usage or scene error, or a JSON path that cannot be written (found before\n"
         "rendering).\n");
}

typedef struct {
  const char *scene;           /**< scene file, NULL: the built-in Fig. 8 scene */
  const char *json;            /**< JSON output path or NULL */
  const rn_renderer_t *method; /**< the renderer timed against exact tracing (default pencil) */
  int spp[MAX_SPP];            /**< samples per pixel to benchmark */
  int nspp;
  long runs, threads, width, height; /**< width = 0: the scene's size */
  double rho;
  double btol;           /**< brightness tolerance of the pencil renders */
  const char *tolerance; /**< --tolerance of the pencil renders: "geometric" or "image" */
  int measure;           /**< 1: one measured render per mode for the accuracy figures */
  int peer;              /**< 1: --peer povray */
} args_t;

/** One row of the table: a sample count and a mode. */
typedef struct {
  int spp, certified;
  val_timing_t t;  /**< medians of the interleaved timed renders */
  val_errors_t e;  /**< the measured render (valid when measured) */
  int measured;    /**< 1: e holds a measurement */
  int target;      /**< -1 not applicable, 0 missed, 1 met */
  const char *why; /**< which part of the target was missed (static) or NULL */
  int pov;         /**< 1: pov and t.peer_s hold POV-Ray's figures at this spp (timed with the
                        default mode's runs; the certified row shares them) */
  val_povray_run_t pov_run; /**< POV-Ray's counts (every run the same) and, in process_s, the
                                 median of its process CPU seconds */
} row_t;

/** The peer of a bench run: asked for, found, and still timed. */
typedef struct {
  int asked;        /**< --peer povray */
  int timed;        /**< 1 while POV-Ray is timed (installed, the scene exported) */
  val_povray_t *pv; /**< the installation and its private directory */
  char why[1024];   /**< why it is not timed, when asked and not timed */
} peer_t;

static int usage_err(const char *opt, const char *v, const char *want) {
  fprintf(stderr, "pencil bench pencil: %s: expected %s, got '%s'\n", opt, want, v);
  return 0;
}

enum {
  OPT_SPP = 1,
  OPT_RUNS,
  OPT_THREADS,
  OPT_RHO,
  OPT_BTOL,
  OPT_SIZE,
  OPT_JSON,
  OPT_NO_MEASURE,
  OPT_METHOD,
  OPT_PEER,
  OPT_TOL
};

static const cli_spec_t specs[] = {{"--spp", 0, 1, OPT_SPP},
                                   {"--runs", 0, 1, OPT_RUNS},
                                   {"--threads", 0, 1, OPT_THREADS},
                                   {"--rho", 0, 1, OPT_RHO},
                                   {"--brightness-tol", 0, 1, OPT_BTOL},
                                   {"--size", 0, 1, OPT_SIZE},
                                   {"--json", 0, 1, OPT_JSON},
                                   {"--no-measure", 0, 0, OPT_NO_MEASURE},
                                   {"--method", 0, 1, OPT_METHOD},
                                   {"--peer", 0, 1, OPT_PEER},
                                   {"--tolerance", 0, 1, OPT_TOL}};

/* One argument; 1 ok, 0 usage error (printed). */
static int apply(args_t *a, const cli_arg_t *g) {
  const char *v = g->value;
  if (!g->spec) {
    if (a->scene)
      return fprintf(stderr, "pencil bench pencil: unexpected argument '%s' (see --help)\n", v), 0;
    a->scene = v;
    return 1;
  }
  switch (g->spec->id) {
  case OPT_SPP:
    return cli_parse_spp_list("bench pencil", "--spp", v, a->spp, MAX_SPP, &a->nspp);
  case OPT_RUNS:
    return cli_parse_long("--runs", v, 3, 101, &a->runs);
  case OPT_THREADS:
    return cli_parse_long("--threads", v, 1, 1024, &a->threads);
  case OPT_RHO:
    return cli_parse_double("--rho", v, &a->rho) &&
           (a->rho > 0.0 || usage_err("--rho", v, "a number > 0"));
  case OPT_BTOL:
    return cli_parse_double("--brightness-tol", v, &a->btol) &&
           (a->btol >= 0.0 || usage_err("--brightness-tol", v, "a number >= 0"));
  case OPT_SIZE:
    return cli_parse_wxh("bench pencil", "--size", v, 4096, &a->width, &a->height);
  case OPT_JSON:
    a->json = v;
    return 1;
  case OPT_METHOD:
    a->method = rn_find(v);
    if (!a->method || !a->method->errors || !rn_option_find(a->method, "--rho") ||
        !rn_option_find(a->method, "--brightness-tol") || !rn_option_find(a->method, "--certified"))
      return usage_err("--method", v,
                       "a renderer that approximates exact tracing with --rho, "
                       "--brightness-tol and --certified (pencil)");
    return 1;
  case OPT_TOL:
    if (strcmp(v, "geometric") != 0 && strcmp(v, "image") != 0)
      return usage_err("--tolerance", v, "geometric or image");
    a->tolerance = v;
    return 1;
  case OPT_PEER:
    if (strcmp(v, "povray") != 0)
      return usage_err("--peer", v, "povray (the one peer renderer)");
    a->peer = 1;
    return 1;
  default:
    a->measure = 0;
    return 1;
  }
}

/* Options; argv[0] is "pencil". 1 ok, 0 usage error (message printed), -1 help printed. */
static int parse(int argc, char **argv, args_t *a) {
  int n, rc;
  cli_arg_t *args = cli_args("bench pencil", argc, argv, specs,
                             (int)(sizeof specs / sizeof specs[0]), help, &n, &rc);
  if (!args)
    return rc == CLI_OK ? -1 : 0;
  int ok = 1;
  for (int k = 0; ok && k < n; k++)
    ok = apply(a, &args[k]);
  free(args);
  return ok;
}

static int load(const args_t *a, rt_scene_t *s) {
  return cli_load_scene("bench pencil", a->scene, a->width, a->height, s);
}

static uint64_t over_rho(const row_t *r) {
  return r->e.counts.measured - r->e.counts.within;
}

/* The verdict for one row: only at 49 spp, rho = 1/2, a brightness tolerance no looser
 * than the default (a looser one changes the image, which Fig. 10's measure does not see), and
 * when measured. */
static void judge(row_t *r, const args_t *a) {
  r->target = -1;
  r->why = NULL;
  if (r->spp != TARGET_SPP || a->rho != TARGET_RHO || a->btol > PT_BRIGHTNESS_TOL || !r->measured ||
      strcmp(a->tolerance, "geometric") != 0)
    return;
  int fast = r->t.ratio <= TARGET_RATIO;
  int accurate = r->certified ? over_rho(r) == 0 : r->e.fraction_within >= TARGET_WITHIN;
  accurate = accurate && r->e.samples_with_points > 0; /* a measure that compared nothing */
  r->target = fast && accurate;
  r->why = fast && accurate     ? NULL
           : !fast && !accurate ? "ratio and accuracy"
           : !fast              ? "ratio"
                                : "accuracy";
}

/* Time and measure one row, with POV-Ray beside it when pv is not NULL; 0 ok, -1 a render failed
 * (message printed). */
static int bench_row(const rt_scene_t *s, const args_t *a, row_t *r, val_povray_t *pv) {
  const rn_renderer_t *p = a->method;
  pt_options_t po;
  char rho[32], btol[32], err[256];
  snprintf(rho, sizeof rho, "%.17g", a->rho);
  snprintf(btol, sizeof btol, "%.17g", a->btol);
  rn_defaults(p, &po);
  if (!rn_set(p, &po, "--rho", rho, err, sizeof err) ||
      !rn_set(p, &po, "--brightness-tol", btol, err, sizeof err) ||
      (r->certified && !rn_set(p, &po, "--certified", NULL, err, sizeof err)) ||
      (strcmp(a->tolerance, "geometric") != 0 &&
       !rn_set(p, &po, "--tolerance", a->tolerance, err, sizeof err)))
    return fprintf(stderr, "pencil bench pencil: %s\n", err), -1;
  val_method_t m = {p, &po};
  val_povray_peer_t pc = {
      .pv = pv, .s = s, .threads = (int)a->threads, .who = "pencil bench pencil"};
  val_peer_t peer = {val_povray_peer_run, &pc};
  int tr = val_time_peer(s, m, r->spp, (int)a->threads, (int)a->runs, pv ? &peer : NULL, &r->t);
  if (tr < 0)
    return -1;
  r->pov = pv != NULL && tr == 0; /* 1: POV-Ray failed (it said why), the pair was timed */
  if (pv) {
    r->pov_run = pc.last;
    r->pov_run.process_s = val_median(pc.process, pc.n);
  }
  r->measured = 0;
  if (a->measure) {
    if (val_measure(s, m, r->spp, (int)a->threads, &r->e, NULL, NULL, NULL, NULL) != 0)
      return -1;
    r->measured = 1;
  }
  judge(r, a);
  return 0;
}

static const char *mode_name(const row_t *r) {
  return r->certified ? "certified" : "default";
}

/* Rays per second and the time ratios side by side (issue 26): the exact renderer's rays over
 * each of our renderers' time, POV-Ray's own count over its time. */
static void print_rates(const row_t *rows, int n, const peer_t *peer) {
  printf("rays per second: exact = its rays / its time; pencil = the exact renderer's rays of the "
         "same image / pencil time; POV-Ray = its Rays + Shadow Ray Tests / its Trace Time CPU\n");
  printf("%4s %-10s %12s %12s %12s %9s %12s %12s %8s %8s %8s\n", "spp", "mode", "exact_rays",
         "exact_rps", "pencil_rps", "povray_s", "povray_rays", "povray_rps", "p/exact", "p/povray",
         "x/povray");
  for (int k = 0; k < n; k++) {
    const row_t *r = &rows[k];
    double x = (double)r->t.exact_rays;
    printf("%4d %-10s %12.0f %12.4g %12.4g ", r->spp, mode_name(r), x, x / r->t.exact_s,
           x / r->t.pencil_s);
    if (r->pov && r->t.peer_s > 0.0) {
      double pr = (double)(r->pov_run.rays + r->pov_run.shadow_tests);
      printf("%9.4f %12.0f %12.4g %8.3f %8.3f %8.3f\n", r->t.peer_s, pr, pr / r->t.peer_s,
             r->t.ratio, r->t.pencil_s / r->t.peer_s, r->t.exact_s / r->t.peer_s);
    } else if (r->pov) { /* under POV-Ray's millisecond: no rate, no ratio */
      printf("%9.4f %12.0f %12s %8.3f %8s %8s\n", r->t.peer_s,
             (double)(r->pov_run.rays + r->pov_run.shadow_tests), "-", r->t.ratio, "-", "-");
    } else {
      printf("%9s %12s %12s %8.3f %8s %8s\n", "-", "-", "-", r->t.ratio, "-", "-");
    }
  }
  if (peer->asked && !peer->timed)
    printf("POV-Ray not timed: %s\n", peer->why);
  else if (peer->timed)
    printf("POV-Ray %s (%s): the exported scene (pencil export pov) at sqrt(spp) times the size, "
           "no anti-aliasing, no file, %s; median of the runs, timed after the exact and pencil "
           "renders of each default-mode run (the certified rows share them)\n",
           peer->pv->version[0] ? peer->pv->version : "3.7", peer->pv->exe,
           "its render threads = --threads");
}

static void print_table(const rt_scene_t *s, const args_t *a, const row_t *rows, int n,
                        const peer_t *peer) {
  char rho[IO_SHORTEST_MAX], btol[IO_SHORTEST_MAX];
  printf("pencil bench: %s, %dx%d, rho %s (%s tolerance), brightness tolerance %s, %ld thread%s; "
         "process CPU seconds, median of %ld interleaved runs\n",
         a->scene ? a->scene : "built-in Fig. 8 scene", s->camera.width, s->camera.height,
         io_shortest(a->rho, rho), a->tolerance, io_shortest(a->btol, btol), a->threads,
         a->threads == 1 ? "" : "s", a->runs);
  printf("%4s %-10s %9s %9s %7s %11s %9s %10s %7s  %s\n", "spp", "mode", "exact_s", "pencil_s",
         "ratio", "within rho", "over rho", "max error", "p99", "target met");
  for (int k = 0; k < n; k++) {
    const row_t *r = &rows[k];
    printf("%4d %-10s %9.4f %9.4f %7.3f ", r->spp, mode_name(r), r->t.exact_s, r->t.pencil_s,
           r->t.ratio);
    if (r->measured && r->e.samples_with_points > 0)
      printf("%10.4f%% %9llu %10.4f %7.4f  ", 100.0 * r->e.fraction_within,
             (unsigned long long)over_rho(r), r->e.max_error, r->e.p99);
    else
      printf("%11s %9s %10s %7s  ", "-", "-", "-", "-");
    if (r->target < 0)
      printf("-\n");
    else
      printf(r->target ? "yes\n" : "no (%s)\n", r->why);
  }
  for (int k = 0; k < n; k++)
    if (rows[k].measured)
      printf("%4d %-10s image against exact: RMS %.4f, largest pixel difference %.4f, largest "
             "mean difference on one object %.5f (object %d)\n",
             rows[k].spp, mode_name(&rows[k]), rows[k].e.image_rms, rows[k].e.image_max,
             rows[k].e.image_bias, rows[k].e.image_bias_object);
  for (int k = 0; k < n; k++)
    if (rows[k].measured && rows[k].e.samples_with_points == 0) {
      printf("warning: no sample had a pencil-traced point on a surface with a diffuse term; the "
             "error columns compared nothing on this scene\n");
      break;
    }
  print_rates(rows, n, peer);
  printf(
      "targets at %d spp, rho = %g: ratio <= %.2f; within rho >= %.1f%% (default), 100%% "
      "(certified)%s\n",
      TARGET_SPP, TARGET_RHO, TARGET_RATIO, 100.0 * TARGET_WITHIN,
      !a->measure                   ? "; not judged without measurement"
      : a->btol > PT_BRIGHTNESS_TOL ? "; not judged above the default brightness tolerance"
      : strcmp(a->tolerance, "geometric") != 0
          ? "; not judged with the image-space tolerance (its measure is the image against exact)"
          : "");
}

/* POV-Ray's figures of a row (issue 26's peer). */
static json_t *json_povray(const row_t *r) {
  const val_povray_run_t *p = &r->pov_run;
  double rays = (double)(p->rays + p->shadow_tests);
  return json_pack("{s:o, s:o, s:o, s:I, s:I, s:I, s:o, s:o, s:o, s:s}", "seconds",
                   io_json_number(r->t.peer_s), "wall_seconds", io_json_number(r->t.peer_wall),
                   "process_seconds", io_json_number(p->process_s), "rays",
                   (json_int_t)(p->rays + p->shadow_tests), "traced_rays", (json_int_t)p->rays,
                   "shadow_tests", (json_int_t)p->shadow_tests, "rays_per_second",
                   io_json_number(rays / r->t.peer_s), "pencil_over_povray",
                   io_json_number(r->t.pencil_s / r->t.peer_s), "exact_over_povray",
                   io_json_number(r->t.exact_s / r->t.peer_s), "timed_with",
                   r->certified ? "the default mode's runs" : "this row's runs");
}

static json_t *json_row(const row_t *r) {
  json_t *j =
      json_pack("{s:i, s:s, s:o, s:o, s:o, s:o, s:o}", "spp", r->spp, "mode", mode_name(r),
                "exact_s", io_json_number(r->t.exact_s), "pencil_s", io_json_number(r->t.pencil_s),
                "ratio", io_json_number(r->t.ratio), "exact_wall_s",
                io_json_number(r->t.exact_wall), "pencil_wall_s", io_json_number(r->t.pencil_wall));
  int compared = r->measured && r->e.samples_with_points > 0;
  /* measured but nothing compared, or not measured: the error fields say nothing */
  json_object_set_new(j, "samples",
                      r->measured ? json_integer((json_int_t)r->e.samples) : json_null());
  json_object_set_new(j, "samples_with_points",
                      r->measured ? json_integer((json_int_t)r->e.samples_with_points)
                                  : json_null());
  json_object_set_new(j, "fraction_within",
                      compared ? io_json_number(r->e.fraction_within) : json_null());
  json_object_set_new(j, "samples_over_rho",
                      compared ? json_integer((json_int_t)over_rho(r)) : json_null());
  json_object_set_new(j, "max_error", compared ? io_json_number(r->e.max_error) : json_null());
  json_object_set_new(j, "p99", compared ? io_json_number(r->e.p99) : json_null());
  if (compared) {
    const rn_errors_t *c = &r->e.counts;
    json_object_set_new(j, "mismatches", json_integer((json_int_t)r->e.mismatches));
    json_object_set_new(j, "samples_exact", json_integer((json_int_t)c->samples_exact));
    json_object_set_new(j, "samples_matrix", json_integer((json_int_t)c->samples_matrix));
    json_object_set_new(j, "samples_interpolated",
                        json_integer((json_int_t)c->samples_interpolated));
    json_object_set_new(j, "image_rms", io_json_number(r->e.image_rms));
    json_object_set_new(j, "image_max", io_json_number(r->e.image_max));
    json_object_set_new(j, "image_bias", io_json_number(r->e.image_bias));
    json_object_set_new(j, "image_bias_object", json_integer(r->e.image_bias_object));
  }
  json_object_set_new(j, "target_met", r->target < 0 ? json_null() : json_boolean(r->target));
  double x = (double)r->t.exact_rays;
  json_object_set_new(j, "exact_rays", json_integer((json_int_t)r->t.exact_rays));
  json_object_set_new(j, "exact_rays_per_second", io_json_number(x / r->t.exact_s));
  json_object_set_new(j, "pencil_rays_per_second", io_json_number(x / r->t.pencil_s));
  json_object_set_new(j, "povray", r->pov ? json_povray(r) : json_null());
  return j;
}

/* Write the results to a->json; 0, or -1 when writing failed (message printed). */
static int write_json(const rt_scene_t *s, const args_t *a, const row_t *rows, int n,
                      const peer_t *peer) {
  int judged = 0, met = 1;
  for (int k = 0; k < n; k++)
    if (rows[k].target >= 0)
      judged = 1, met &= rows[k].target;
  json_t *results = json_array();
  for (int k = 0; k < n; k++)
    json_array_append_new(results, json_row(&rows[k]));
  json_t *root = json_pack(
      "{s:s, s:s, s:s, s:i, s:i, s:o, s:o, s:i, s:i, s:s, s:s, s:b, s:{s:i, s:o, s:o, s:o, s:i}, "
      "s:o, s:o}",
      "benchmark", "pencil", "method", a->method->name, "scene",
      a->scene ? a->scene : "built-in fig8", "width", s->camera.width, "height", s->camera.height,
      "rho", io_json_number(a->rho), "brightness_tol", io_json_number(a->btol), "threads",
      (int)a->threads, "runs", (int)a->runs, "clock", "process_cpu", "statistic", "median",
      "measured", a->measure, "targets", "spp", TARGET_SPP, "rho", io_json_number(TARGET_RHO),
      "ratio_max", io_json_number(TARGET_RATIO), "fraction_within_default_min",
      io_json_number(TARGET_WITHIN), "fraction_within_certified_min", 1, "results", results,
      "targets_met", judged ? json_boolean(met) : json_null());
  if (root)
    json_object_set_new(root, "tolerance", json_string(a->tolerance));
  json_t *pj = json_null();
  if (root && peer->asked) {
    int timed = n > 0 && rows[0].pov;
    pj = json_pack("{s:s, s:s?, s:s?, s:b, s:s?, s:s, s:s}", "name", "povray", "program",
                   peer->pv->exe[0] ? peer->pv->exe : NULL, "version",
                   peer->pv->version[0] ? peer->pv->version : NULL, "timed", timed, "why",
                   peer->timed ? NULL : peer->why, "clock",
                   "Trace Time CPU-seconds of POV-Ray's statistics (its render threads)", "image",
                   "sqrt(spp) times the size, no anti-aliasing, no output file");
  }
  if (root)
    json_object_set_new(root, "peer", pj ? pj : json_null());
  char err[1024];
  int rc = root ? io_json_write(a->json, root, err, sizeof err) : -1;
  if (rc != 0)
    fprintf(stderr, "pencil bench pencil: %s\n", root ? err : "out of memory");
  json_decref(root);
  return rc;
}

/* Find POV-Ray; 0 (timed, or not with a note when it is not installed), -1 when its private
 * directory cannot be made (message printed). */
static int peer_open(peer_t *p, const rt_scene_t *s, const args_t *a) {
  (void)s, (void)a;
  int r = val_povray_open(p->pv, p->why, sizeof p->why);
  if (r < 0)
    return fprintf(stderr, "pencil bench pencil: --peer povray: %s\n", p->why), -1;
  p->timed = r == 0;
  if (!p->timed)
    fprintf(stderr, "pencil bench pencil: note: --peer povray: %s; POV-Ray is not timed\n", p->why);
  return 0;
}

/* Export the scene for spp; a refusal turns the peer off with a note (the same scene is refused
 * at every spp). */
static void peer_export(peer_t *p, const rt_scene_t *s, const args_t *a, int spp) {
  char err[900];
  const char *src = a->scene ? a->scene : "built-in Fig. 8 scene";
  if (val_povray_export(p->pv, s, spp, src, err, sizeof err) == 0)
    return;
  p->timed = 0;
  snprintf(p->why, sizeof p->why, "the scene cannot be exported: %s", err);
  fprintf(stderr, "pencil bench pencil: note: --peer povray: %s; POV-Ray is not timed\n", p->why);
}

static int run(const args_t *a) {
  rt_scene_t s;
  int loaded = load(a, &s);
  if (loaded != CLI_OK) {
    rt_scene_free(&s);
    return loaded;
  }
  /* check the JSON path first, so that an unwritable path fails before minutes of rendering */
  char err[1024];
  if (a->json && (io_output_check(a->json, err, sizeof err) != 0 ||
                  (a->scene && io_output_not_input(a->json, a->scene, err, sizeof err) != 0))) {
    fprintf(stderr, "pencil bench pencil: %s\n", err);
    rt_scene_free(&s);
    return CLI_USAGE;
  }
  static val_povray_t pv; /* kilobytes of paths: not on the stack */
  peer_t peer = {.asked = a->peer, .pv = &pv};
  if (a->peer && peer_open(&peer, &s, a) != 0) {
    rt_scene_free(&s);
    return CLI_FAIL;
  }
  row_t rows[2 * MAX_SPP];
  int n = 0, rc = 0, total = 2 * a->nspp;
  void (*progress)(void *, int, int) = isatty(2) ? cli_progress : NULL;
  if (progress)
    progress((void *)"pencil bench", 0, total);
  for (int k = 0; k < a->nspp && rc == 0; k++)
    for (int c = 0; c < 2 && rc == 0; c++, n++) {
      rows[n] = (row_t){.spp = a->spp[k], .certified = c};
      if (c == 0 && peer.timed)
        peer_export(&peer, &s, a, a->spp[k]);
      rc = bench_row(&s, a, &rows[n], c == 0 && peer.timed ? &pv : NULL);
      if (rc == 0 && c == 0 && peer.timed && !rows[n].pov) { /* it failed: not timed any more */
        peer.timed = 0;
        snprintf(peer.why, sizeof peer.why,
                 "POV-Ray failed at %d spp (its message is on stderr); not timed from there on",
                 a->spp[k]);
        fprintf(stderr, "pencil bench pencil: note: --peer povray: %s\n", peer.why);
      }
      if (c == 1 && rows[n - 1].pov) { /* POV-Ray's figures at this spp, timed with the default */
        rows[n].pov = 1;
        rows[n].pov_run = rows[n - 1].pov_run;
        rows[n].t.peer_s = rows[n - 1].t.peer_s;
        rows[n].t.peer_wall = rows[n - 1].t.peer_wall;
      }
      if (progress && rc == 0)
        progress((void *)"pencil bench", n + 1, total);
    }
  val_povray_close(&pv);
  if (rc != 0) {
    if (progress)
      fputc('\n', stderr);
    rt_scene_free(&s);
    return CLI_FAIL;
  }
  print_table(&s, a, rows, n, &peer);
  int wrc = a->json ? write_json(&s, a, rows, n, &peer) : 0;
  rt_scene_free(&s);
  return wrc == 0 ? CLI_OK : CLI_FAIL;
}

int cmd_bench_pencil(int argc, char **argv) {
  args_t a = {.spp = {TARGET_SPP},
              .nspp = 1,
              .runs = 5,
              .threads = 1,
              .rho = TARGET_RHO,
              .btol = PT_BRIGHTNESS_TOL,
              .tolerance = "geometric",
              .measure = 1,
              .method = rn_find("pencil")};
  int p = parse(argc, argv, &a);
  if (p <= 0)
    return p < 0 ? CLI_OK : CLI_USAGE;
  if (strcmp(a.tolerance, "geometric") != 0 && !rn_option_find(a.method, "--tolerance")) {
    fprintf(stderr, "pencil bench pencil: --tolerance %s: the method '%s' has no such option\n",
            a.tolerance, a.method->name);
    return CLI_USAGE;
  }
  return run(&a);
}
