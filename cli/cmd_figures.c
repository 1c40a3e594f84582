/* cmd_figures.c -- `pencil figures` and `pencil sweep`: the paper's section 5 experiments with
 * the pencil renderer (Fig. 8 image, Fig. 9 time ratio against samples per pixel, Fig. 10 error
 * distribution) and the rho sweep, written under one directory with a comparison table. */
#define _GNU_SOURCE /* fopencookie(): the log that clears the progress bar */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

#include "args.h"
#include "cli.h"
#include "renderers/renderer.h"
#include "validation/figures.h"

#ifndef PENCIL_PLOT_SCRIPT
#define PENCIL_PLOT_SCRIPT NULL
#endif

static void help_figures(FILE *f) {
  fprintf(
      f,
      "usage: pencil figures [SCENE.json] [--out DIR] [--quick] [--threads N] [--runs N]\n"
      "                      [--size WxH] [--no-sweep] [--fig9-spp LIST] [--method NAME]\n"
      "                      [--only LIST] [--shard K/N] [--peer povray]\n"
      "       pencil figures --merge --out DIR\n\n"
      "The paper's section 5 with the pencil renderer, on SCENE.json or the built-in Fig. 8\n"
      "scene (a glass sphere over a checkerboard, 256x256):\n"
      "  Fig. 8   DIR/fig8.exr, fig8.png: the pencil-traced image at 9 samples per pixel\n"
      "           (fig8_exact.* by exact tracing beside it)\n"
      "  Fig. 9   DIR/fig9.csv: CPU time of pencil and exact tracing at 1, 4, ..., 49 spp,\n"
      "           rho = 1/2, each the median of N runs interleaved in this process\n"
      "  Fig. 10  DIR/fig10_hist.csv, fig10_error_map.png: the error of every sample (distance\n"
      "           between the points found by pencil and exact tracing on surfaces with a\n"
      "           diffuse term - the checkerboard in Fig. 8 - in pixel intervals there),\n"
      "           fraction within rho, maximum\n"
      "  sweep    DIR/sweep.csv: time ratio and errors for rho 0.05 ... 2, both bound variants\n"
      "           and the certified mode (as 'pencil sweep')\n"
      "and DIR/summary.json, PNG plots (notebooks/pencil_plots.py with /usr/bin/python3), and a\n"
      "table comparing each figure with the paper's numbers.\n\n"
      "options:\n"
      "  --out DIR      output directory (default figures)\n"
      "  --quick        64x64 image, spp 1, 9, 49, rho 0.5, 1 (tests)\n"
      "  --threads N    threads of every render (default 1, as the paper's single CPU)\n"
      "  --runs N       timed renders per configuration, 3..101 (default 3)\n"
      "  --size WxH     override the image size\n"
      "  --no-sweep     skip the rho sweep\n"
      "  --method NAME  the renderer compared with exact tracing (default pencil)\n"
      "  --shard K/N    run only the K-th of N shares of the work (for running on N machines:\n"
      "                 scripts/slurm-shards.sh, scripts/mpi-shards); the results go to\n"
      "                 DIR/shards/, the images of Fig. 8 to DIR/ from the shard that makes\n"
      "                 them\n"
      "  --only LIST    run these figures alone: fig8 (with fig10: one measured render),\n"
      "                 fig9, targets, sweep; summary.json holds only their sections\n"
      "  --merge        run nothing: merge DIR/shards/ (all N shards of one run) into the\n"
      "                 outputs a single run writes; takes only --out DIR\n"
      "  --fig9-spp LIST\n"
      "                 Fig. 9's samples per pixel, increasing squares up to 1024 (default the\n"
      "                 paper's 1,4,9,16,25,36,49; 1,...,49,100,144,256 extends it to where\n"
      "                 the ratio falls below 0.10 here); the targets are read at 49 spp, or\n"
      "                 at the largest when 49 is not listed\n"
      "  --peer povray  also time POV-Ray 3.7 at each Fig. 9 spp, after the exact and pencil\n"
      "                 renders of each run, as 'pencil bench pencil --peer povray' does\n"
      "                 (the scene exported, sqrt(spp) times the size, no anti-aliasing; its\n"
      "                 Trace Time CPU seconds): fig9.csv and summary.json get povray_s,\n"
      "                 povray_rays, pencil_over_povray and exact_over_povray; left out with a\n"
      "                 note when povray is not installed or the scene cannot be exported\n"
      "A progress bar of work items is drawn on stderr when it is a terminal.\n"
      "Exit codes: 0 done (the table says whether the paper's numbers and the targets were\n"
      "met); 1 a render or a file failed; 2 usage or scene error, or an output that cannot be\n"
      "written (every one is checked before the first render).\n");
}

static void help_sweep(FILE *f) {
  fprintf(
      f, "usage: pencil sweep [SCENE.json] [--rho R1,R2,...] [--spp N] [--out DIR] [--quick]\n"
         "                    [--threads N] [--runs N] [--size WxH] [--method NAME] [--shard K/N]\n"
         "       pencil sweep --merge --out DIR\n\n"
         "What accuracy costs in time: for each rho, the CPU-time ratio pencil / exact (median\n"
         "of N interleaved runs) and the Fig. 10 error statistics (fraction of samples within\n"
         "rho, 99th percentile, maximum) for the corrected and printed bounds and the certified\n"
         "mode. Writes DIR/sweep.csv, DIR/sweep.json and DIR/sweep.png (plot).\n\n"
         "options:\n"
         "  --rho LIST     comma-separated rho values > 0 (default 0.05,0.1,0.25,0.5,1,2)\n"
         "  --spp N        samples per pixel, a square 1..1024 (default 9)\n"
         "  --out DIR      output directory (default figures)\n"
         "  --quick        64x64 image, rho 0.5,1 (tests)\n"
         "  --method NAME  the renderer compared with exact tracing (default pencil); its\n"
         "                 --rho, --bounds and --certified options are swept\n"
         "  --shard K/N    run only the K-th of N shares of the rows (results in DIR/shards/)\n"
         "  --merge        merge DIR/shards/ into sweep.csv, sweep.json and the plot\n"
         "  --threads N    threads (default 1); --runs N timed runs (default 3); --size WxH\n"
         "A progress bar of work items is drawn on stderr when it is a terminal.\n"
         "Exit codes: 0 done; 1 a render or a file failed; 2 usage or scene error, or an output\n"
         "that cannot be written (every one is checked before the first render).\n");
}

static int parse_rho(const char *v, val_figures_opts_t *o) {
  char buf[1024];
  const char *item[VAL_MAX_RHO];
  if (!cli_split_list("--rho", v, buf, sizeof buf, item, VAL_MAX_RHO, &o->nrho))
    return 0;
  for (int k = 0; k < o->nrho; k++) {
    if (!cli_parse_double("--rho", item[k], &o->rho[k]))
      return 0;
    if (!(o->rho[k] > 0.0))
      return fprintf(stderr, "pencil sweep: --rho: expected values > 0, got '%s'\n", item[k]), 0;
  }
  return 1;
}

enum {
  OPT_OUT = 1,
  OPT_THREADS,
  OPT_RUNS,
  OPT_SIZE,
  OPT_RHO,
  OPT_SPP,
  OPT_FIG9,
  OPT_QUICK,
  OPT_NO_SWEEP,
  OPT_METHOD,
  OPT_SHARD,
  OPT_MERGE,
  OPT_ONLY,
  OPT_PEER
};

static const cli_spec_t figures_specs[] = {
    {"--out", 0, 1, OPT_OUT},           {"--threads", 0, 1, OPT_THREADS},
    {"--runs", 0, 1, OPT_RUNS},         {"--size", 0, 1, OPT_SIZE},
    {"--fig9-spp", 0, 1, OPT_FIG9},     {"--quick", 0, 0, OPT_QUICK},
    {"--no-sweep", 0, 0, OPT_NO_SWEEP}, {"--method", 0, 1, OPT_METHOD},
    {"--shard", 0, 1, OPT_SHARD},       {"--merge", 0, 0, OPT_MERGE},
    {"--only", 0, 1, OPT_ONLY},         {"--peer", 0, 1, OPT_PEER}};
static const cli_spec_t sweep_specs[] = {
    {"--out", 0, 1, OPT_OUT},     {"--threads", 0, 1, OPT_THREADS}, {"--runs", 0, 1, OPT_RUNS},
    {"--size", 0, 1, OPT_SIZE},   {"--rho", 0, 1, OPT_RHO},         {"--spp", 0, 1, OPT_SPP},
    {"--quick", 0, 0, OPT_QUICK}, {"--method", 0, 1, OPT_METHOD},   {"--shard", 0, 1, OPT_SHARD},
    {"--merge", 0, 0, OPT_MERGE}};

static int parse_fig9(const char *v, val_figures_opts_t *o) {
  if (!cli_parse_spp_list("figures", "--fig9-spp", v, o->spp, VAL_MAX_SPP, &o->nspp))
    return 0;
  for (int k = 1; k < o->nspp; k++)
    if (o->spp[k] <= o->spp[k - 1])
      return fprintf(stderr, "pencil figures: --fig9-spp: expected increasing values, got '%s'\n",
                     v),
             0;
  return 1;
}

static int parse_method(const char *cmd, const char *v, val_figures_opts_t *o) {
  const rn_renderer_t *r = rn_find(v);
  /* the drivers set these options of the method (their variants and baselines) */
  static const char *const needs[] = {"--rho", "--bounds", "--certified", "--brightness-tol"};
  int ok = r && r->errors;
  for (size_t k = 0; ok && k < sizeof needs / sizeof needs[0]; k++)
    ok = rn_option_find(r, needs[k]) != NULL;
  if (!ok)
    return fprintf(stderr,
                   "pencil %s: --method: expected a renderer that approximates exact "
                   "tracing with --rho, --bounds, --certified and --brightness-tol (pencil), "
                   "got '%s'\n",
                   cmd, v),
           0;
  o->method = r;
  return 1;
}

/* "K/N" with 1 <= K <= N <= 10000, each an integer by the number rule (rn_parse_long()). */
static int parse_shard(const char *cmd, const char *v, val_figures_opts_t *o) {
  const char *slash = strchr(v, '/');
  char k[16];
  long ks = 0, ns = 0;
  int ok = slash && (size_t)(slash - v) < sizeof k;
  if (ok) {
    memcpy(k, v, (size_t)(slash - v));
    k[slash - v] = '\0';
    ok = rn_parse_long(k, &ks) == 1 && rn_parse_long(slash + 1, &ns) == 1;
  }
  o->shard = ok && ks >= 1 && ks <= 10000 ? (int)ks : 0;
  o->nshards = ok && ns >= 1 && ns <= 10000 ? (int)ns : 0;
  if (!ok || o->nshards < 1 || o->shard < 1 || o->shard > o->nshards)
    return fprintf(stderr, "pencil %s: --shard: expected K/N with 1 <= K <= N <= 10000, got '%s'\n",
                   cmd, v),
           0;
  return 1;
}

/* A comma-separated list of fig8, fig9, fig10 (= fig8), targets, sweep. */
static int parse_only(const char *v, val_figures_opts_t *o) {
  static const struct {
    const char *name;
    unsigned bit;
  } names[] = {{"fig8", VAL_ONLY_FIG8},
               {"fig10", VAL_ONLY_FIG8},
               {"fig9", VAL_ONLY_FIG9},
               {"targets", VAL_ONLY_TARGETS},
               {"sweep", VAL_ONLY_SWEEP}};
  char buf[256];
  const char *item[8];
  int n;
  o->only = 0;
  if (!cli_split_list("--only", v, buf, sizeof buf, item, 8, &n))
    return 0;
  for (int j = 0; j < n; j++) {
    unsigned bit = 0;
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
      if (strcmp(names[k].name, item[j]) == 0)
        bit = names[k].bit;
    if (!bit)
      return fprintf(stderr,
                     "pencil figures: --only: expected a comma-separated list of fig8, "
                     "fig9, fig10, targets and sweep, got '%s'\n",
                     v),
             0;
    o->only |= bit;
  }
  return 1;
}

/* One argument; 1 ok, 0 usage error (printed). */
static int apply(const char *cmd, const cli_arg_t *g, val_figures_opts_t *o, int *given) {
  const char *v = g->value;
  long l;
  if (!g->spec) {
    if (o->scene)
      return fprintf(stderr, "pencil %s: unexpected argument '%s' (see --help)\n", cmd, v), 0;
    o->scene = v;
    return 1;
  }
  *given |= 1 << g->spec->id;
  switch (g->spec->id) {
  case OPT_OUT:
    o->out_dir = v;
    return 1;
  case OPT_THREADS:
    return cli_parse_long("--threads", v, 1, 1024, &l) && (o->threads = (int)l);
  case OPT_RUNS:
    return cli_parse_long("--runs", v, 3, 101, &l) && (o->runs = (int)l);
  case OPT_SIZE: {
    long w, h;
    if (!cli_parse_wxh(cmd, "--size", v, 4096, &w, &h))
      return 0;
    if (w < 8 || h < 8)
      return fprintf(stderr, "pencil %s: --size: expected WxH with 8 <= W, H <= 4096, got '%s'\n",
                     cmd, v),
             0;
    o->width = (int)w;
    o->height = (int)h;
    return 1;
  }
  case OPT_RHO:
    return parse_rho(v, o);
  case OPT_SPP:
    return cli_parse_spp("sweep", "--spp", v, &l) && (o->sweep_spp = (int)l);
  case OPT_FIG9:
    return parse_fig9(v, o);
  case OPT_QUICK:
    return o->quick = 1;
  case OPT_NO_SWEEP:
    o->sweep = 0;
    return 1;
  case OPT_SHARD:
    return parse_shard(cmd, v, o);
  case OPT_MERGE:
    return o->merge = 1;
  case OPT_ONLY:
    return parse_only(v, o);
  case OPT_PEER:
    if (strcmp(v, "povray") != 0)
      return fprintf(stderr, "pencil %s: --peer: expected povray, got '%s'\n", cmd, v), 0;
    return o->peer = 1;
  default:
    return parse_method(cmd, v, o);
  }
}

/* Options of either command; 1 ok, 0 usage error, -1 help printed. */
static int parse(int argc, char **argv, val_figures_opts_t *o, int sweep) {
  const char *cmd = sweep ? "sweep" : "figures";
  const cli_spec_t *specs = sweep ? sweep_specs : figures_specs;
  int nspecs = (int)(sweep ? sizeof sweep_specs / sizeof sweep_specs[0]
                           : sizeof figures_specs / sizeof figures_specs[0]);
  int n, rc, given = 0;
  cli_arg_t *args =
      cli_args(cmd, argc, argv, specs, nspecs, sweep ? help_sweep : help_figures, &n, &rc);
  if (!args)
    return rc == CLI_OK ? -1 : 0;
  int ok = 1;
  for (int k = 0; ok && k < n; k++)
    ok = apply(cmd, &args[k], o, &given);
  free(args);
  if (ok && o->merge && given & ~((1 << OPT_MERGE) | (1 << OPT_OUT)))
    ok = (fprintf(stderr,
                  "pencil %s: --merge takes only --out DIR: the run's options come from "
                  "its shard files\n",
                  cmd),
          0);
  /* options that --only leaves without an effect */
  if (ok && o->only && (given & (1 << OPT_NO_SWEEP)))
    ok = (fprintf(stderr,
                  "pencil %s: --no-sweep has no effect with --only (which names the "
                  "figures run)\n",
                  cmd),
          0);
  if (ok && o->only && !(o->only & (VAL_ONLY_FIG9 | VAL_ONLY_TARGETS)) && (given & (1 << OPT_FIG9)))
    ok = (fprintf(stderr,
                  "pencil %s: --fig9-spp has no effect with --only without fig9 or targets\n", cmd),
          0);
  if (ok && o->only && !(o->only & VAL_ONLY_FIG9) && (given & (1 << OPT_PEER)))
    ok = (fprintf(stderr, "pencil %s: --peer has no effect with --only without fig9\n", cmd), 0);
  if (ok && o->merge && o->scene)
    ok =
        (fprintf(stderr, "pencil %s: --merge takes no scene: it comes from the shard files\n", cmd),
         0);
  if (ok && o->quick) {
    static const int spp[] = {1, 9, 49};
    static const double rho[] = {0.5, 1.0};
    if (!(given & (1 << OPT_FIG9))) {
      o->nspp = 3;
      memcpy(o->spp, spp, sizeof spp);
    }
    if (!(given & (1 << OPT_RHO))) {
      o->nrho = 2;
      memcpy(o->rho, rho, sizeof rho);
    }
  }
  return ok;
}

/* The progress bar, on stderr when it is a terminal: work items done of the run's, drawn before
 * each item and erased at the end. Meanwhile the process's messages reach the terminal through
 * err_write() (stderr is a stream of it, glibc's stderr being an ordinary variable) and, when
 * stdout is that terminal too, the log through log_write(): each erases the bar first, so that no
 * line starts after it. A child process's own messages (POV-Ray's) still can. */
static FILE *bar_out; /* the terminal's stderr */
static int bar_drawn;

static void bar_erase(void) {
  if (bar_drawn)
    fputs("\r\033[K", bar_out);
  bar_drawn = 0;
}

static void bar_progress(void *label, int done, int total) {
  bar_erase();
  if (done < total) {
    int w = 40, k = total > 0 ? (int)((long)w * done / total) : w;
    fprintf(bar_out, "%s [%.*s%*s] %d/%d work items", (const char *)label, k,
            "########################################", w - k, "", done, total);
    bar_drawn = 1;
  }
  fflush(bar_out);
}

/* A cookie stream's write: the bar erased, then buf to `to` (stdout or the terminal's stderr);
 * the bytes written, 0 on an error (fopencookie(3)). */
static ssize_t bar_then(FILE *to, const char *buf, size_t n) {
  bar_erase();
  fflush(bar_out);
  size_t w = fwrite(buf, 1, n, to);
  fflush(to);
  return w == n ? (ssize_t)n : 0;
}

static ssize_t log_write(void *cookie, const char *buf, size_t n) {
  (void)cookie;
  return bar_then(stdout, buf, n);
}

static ssize_t err_write(void *cookie, const char *buf, size_t n) {
  (void)cookie;
  return bar_then(bar_out, buf, n);
}

static int run(int argc, char **argv, int sweep) {
  val_figures_opts_t o;
  val_figures_defaults(&o);
  o.plot = PENCIL_PLOT_SCRIPT;
  int p = parse(argc, argv, &o, sweep);
  if (p <= 0)
    return p < 0 ? CLI_OK : CLI_USAGE;
  FILE *log = NULL, *err = NULL;
  bar_out = stderr;
  if (isatty(2) && (err = fopencookie(NULL, "w", (cookie_io_functions_t){.write = err_write}))) {
    setvbuf(err, NULL, _IONBF, 0);
    stderr = err;
    o.progress = bar_progress;
    o.progress_ctx = (void *)(sweep ? "pencil sweep" : "pencil figures");
    if (isatty(1) && (log = fopencookie(NULL, "w", (cookie_io_functions_t){.write = log_write}))) {
      setvbuf(log, NULL, _IOLBF, 0);
      o.log = log;
    }
  }
  int rc = sweep ? val_sweep(&o) : val_figures(&o);
  if (log)
    fclose(log);
  bar_erase(); /* a run that failed part way */
  if (err) {
    stderr = bar_out;
    fclose(err);
  }
  return cli_exit_of(rc);
}

int cmd_figures(int argc, char **argv) {
  return run(argc, argv, 0);
}

int cmd_sweep(int argc, char **argv) {
  return run(argc, argv, 1);
}
