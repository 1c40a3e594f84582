/* cmd_verify.c -- `pencil verify WHAT`: the verification runs of the validation suite. */
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "io/output.h"
#include "validation/bounds.h"
#include "validation/dispersion.h"
#include "validation/illuminance.h"
#include "validation/stability.h"
#include "validation/star.h"
#include "validation/verify.h"

static void help(FILE *f) {
  fprintf(
      f,
      "usage: pencil verify matrices [--json FILE] [--csv FILE] [--quick]\n"
      "       pencil verify bounds [--json FILE] [--csv DIR] [--quick] [--no-fit] [--threads N]\n"
      "       pencil verify stability [--samples N] [--seed S] [--json FILE] [--threads N]\n"
      "                               [--quick]\n"
      "       pencil verify illuminance [--json FILE] [--csv FILE] [--quick]\n"
      "       pencil verify star [--json FILE] [--csv FILE] [--quick]\n"
      "       pencil verify dispersion [--json FILE] [--csv FILE] [--quick]\n\n"
      "matrices  compare every system matrix (transfer Eq. 1, refraction Eq. 2, reflection,\n"
      "          cascades) of a sweep of > 2,000 systems with the Jacobian of exact\n"
      "          Snell-law tracing in __float128; prints a summary table per family and\n"
      "          for the printed form of Eq. (2).\n"
      "bounds    the error coefficients a-f of Appendix A-1 (printed and corrected) and the\n"
      "          pencil constants A-F of Eq. (4) against the true worst-case second-order\n"
      "          error of exact tracing (jets, checked by __float128 differences), over\n"
      "          > 3,000 systems: min/max ratio bound / true per coefficient; the third-order\n"
      "          onset of pinhole pencils; a Ceres fit of empirical A-F (docs/bounds.md).\n"
      "          --csv DIR writes bounds_{systems,summary,families,onset,fit}.csv there;\n"
      "          --no-fit skips the Ceres fit; --threads N verifies N systems at a time\n"
      "          (default: all cores; the results are the same for any N).\n"
      "stability N randomized hard configurations (default 10^7; --quick 20,000): grazing,\n"
      "          the critical angle from both sides, total internal reflection, normal\n"
      "          incidence, n1 = n2 and nearly so, mirrors, radii 1e-12 .. 1e12 and planes,\n"
      "          rotated frames, cylinders, cascades through a caustic. Each is refused with a\n"
      "          status (counted by reason) or checked against its stated accuracy: the\n"
      "          invariants S^t J S = (n/n') J and det S = (n/n')^2, Eq. (2) in __float128 from\n"
      "          the same inputs, and on 1 in 1000 the __float128 Jacobian of exact tracing.\n"
      "          Fails on any result beyond its bound and on any silent NaN/Inf. --seed S\n"
      "          (default 1) picks the configurations; --threads N as for bounds.\n"
      "illuminance  Eqs. (8)-(9), E = t_r I cos(alpha) / |det B| (point source) and\n"
      "          / |det A| (parallel), against the exact flux Jacobian (the area exactly\n"
      "          traced rays cover on the receiver, __float128 differences) for every system\n"
      "          of the matrix sweep with both sources and receivers at 0 to 89.9 degrees,\n"
      "          and receivers approaching caustics; the 1989 Eq. (1)'s factor n1/n2 as\n"
      "          printed, and the flux it puts on a pool's floor (docs/errata.md, E4).\n"
      "star      the cross-screen filter's linearisation (1989 Eq. 16: a normal N lands at\n"
      "          (n - 1) d N) against a plate simulated by exact refraction at both faces:\n"
      "          first-order agreement, the slopes where it errs by 1%% and 10%%, total\n"
      "          internal reflection, and the star's profile for plates of fine to coarse\n"
      "          scratches (docs/star.md).\n"
      "dispersion  the wavelength column of the 5 x 5 extended matrix (1989 Eq. 13) of every\n"
      "          system of the matrix sweep, its media given glasses of low and high\n"
      "          dispersion, against exact tracing differentiated in wavelength (__float128);\n"
      "          the printed Eq. (14); how far in wavelength the linear model holds\n"
      "          (docs/spectral.md, docs/errata.md E7).\n\n"
      "options:\n"
      "  --json FILE   write the summary {\"systems\", \"worst_relative_error\", \"failures\", "
      "...}\n"
      "  --csv FILE    write one row per system\n"
      "  --quick       a small sweep (for tests)\n\n"
      "Exit codes: 0 all systems pass, 1 some fail or a write failed, 2 usage or an\n"
      "output that cannot be written.\n");
}

/* The options both verifications take. */
typedef struct {
  const char *json, *csv;
  int quick, no_fit;
  long threads; /**< bounds: 0 = all cores */
} verify_args_t;

enum { OPT_JSON = 1, OPT_CSV, OPT_QUICK, OPT_NO_FIT, OPT_THREADS };

/* Parse argv[2..] for `pencil verify WHAT`; --no-fit and --threads only when `what` is bounds.
 * Returns -1 to go on, else the exit code (after --help or a usage error). */
static int parse(int argc, char **argv, verify_args_t *a) {
  static const cli_spec_t specs[] = {{"--json", 0, 1, OPT_JSON},
                                     {"--csv", 0, 1, OPT_CSV},
                                     {"--quick", 0, 0, OPT_QUICK},
                                     {"--no-fit", 0, 0, OPT_NO_FIT},
                                     {"--threads", 0, 1, OPT_THREADS}};
  int bounds = strcmp(argv[1], "bounds") == 0;
  char cmd[32];
  snprintf(cmd, sizeof cmd, "verify %s", argv[1]);
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc - 1, argv + 1, specs, bounds ? 5 : 3, help, &n, &rc);
  if (!args)
    return rc;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k]; /* values point into argv, not into args */
    if (!g->spec) {
      fprintf(stderr, "pencil %s: unexpected argument '%s'\n", cmd, g->value);
      rc = CLI_USAGE;
      continue;
    }
    switch (g->spec->id) {
    case OPT_JSON:
      a->json = g->value;
      break;
    case OPT_CSV:
      a->csv = g->value;
      break;
    case OPT_QUICK:
      a->quick = 1;
      break;
    case OPT_NO_FIT:
      a->no_fit = 1;
      break;
    default:
      if (!cli_parse_long("--threads", g->value, 1, 1024, &a->threads))
        rc = CLI_USAGE;
    }
  }
  free(args);
  return rc == CLI_OK ? -1 : rc;
}

/* The outputs checked before the verification runs (some run for minutes): JSON and CSV files
 * writable, a CSV directory there and writable. CLI_OK, or CLI_USAGE with the reason on stderr. */
static int outputs_ok(const char *cmd, const char *json, const char *csv, int csv_dir) {
  char err[1024];
  if (json && io_output_check(json, err, sizeof err) != 0)
    return fprintf(stderr, "pencil %s: --json: %s\n", cmd, err), CLI_USAGE;
  struct stat st;
  if (csv && csv_dir && (stat(csv, &st) != 0 || !S_ISDIR(st.st_mode) || access(csv, W_OK) != 0))
    return fprintf(stderr, "pencil %s: --csv: %s is not a writable directory\n", cmd, csv),
           CLI_USAGE;
  if (csv && !csv_dir && io_output_check(csv, err, sizeof err) != 0)
    return fprintf(stderr, "pencil %s: --csv: %s\n", cmd, err), CLI_USAGE;
  return CLI_OK;
}

/* `pencil verify stability [--samples N] [--seed S] [--json FILE] [--threads N] [--quick]` */
static int run_stability(int argc, char **argv) {
  static const cli_spec_t specs[] = {{"--samples", 0, 1, 1},
                                     {"--seed", 0, 1, 2},
                                     {"--json", 0, 1, 3},
                                     {"--threads", 0, 1, 4},
                                     {"--quick", 0, 0, 5}};
  cli_arg_t args[64];
  if (argc - 1 > 64)
    return fprintf(stderr, "pencil verify stability: too many arguments\n"), CLI_USAGE;
  int n = cli_parse("verify stability", argc - 1, argv + 1, specs, 5, args);
  if (n == CLI_ARGS_HELP) {
    help(stdout);
    return CLI_OK;
  }
  if (n < 0)
    return CLI_USAGE;
  val_stability_opts_t o = {10000000, 1, 1000, 0, NULL, stdout, NULL, NULL};
  long samples = -1, v;
  int quick = 0;
  for (int k = 0; k < n; k++) {
    const cli_arg_t *g = &args[k];
    if (!g->spec)
      return fprintf(stderr, "pencil verify stability: unexpected argument '%s'\n", g->value),
             CLI_USAGE;
    switch (g->spec->id) {
    case 1:
      if (!cli_parse_long("--samples", g->value, 1, 4000000000L, &samples))
        return CLI_USAGE;
      break;
    case 2:
      if (!cli_parse_long("--seed", g->value, 0, 2147483647L, &v))
        return CLI_USAGE;
      o.seed = (uint64_t)v;
      break;
    case 3:
      o.json = g->value;
      break;
    case 4:
      if (!cli_parse_long("--threads", g->value, 1, 1024, &v))
        return CLI_USAGE;
      o.threads = (int)v;
      break;
    default:
      o.samples = 20000;
      quick = 1;
    }
  }
  if (samples > 0 && quick) /* --quick sets only the count --samples sets */
    return fprintf(stderr, "pencil verify stability: --quick has no effect with --samples (it "
                           "only sets 20,000 samples)\n"),
           CLI_USAGE;
  if (samples > 0)
    o.samples = (uint64_t)samples;
  if (outputs_ok("verify stability", o.json, NULL, 0) != CLI_OK)
    return CLI_USAGE;
  if (isatty(2)) {
    o.progress = cli_progress;
    o.progress_ctx = (void *)"verifying stability";
  }
  int r = val_verify_stability(&o);
  return r != 0 ? CLI_FAIL : CLI_OK; /* r < 0: a write after the work failed */
}

int cmd_verify(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  if (strcmp(argv[1], "stability") == 0)
    return run_stability(argc, argv);
  int bounds = strcmp(argv[1], "bounds") == 0, illum = strcmp(argv[1], "illuminance") == 0;
  int star = strcmp(argv[1], "star") == 0, disp = strcmp(argv[1], "dispersion") == 0;
  if (!bounds && !illum && !star && !disp && strcmp(argv[1], "matrices") != 0) {
    fprintf(stderr,
            "pencil verify: unknown verification '%s' (try: matrices, bounds, stability, "
            "illuminance, star, dispersion)\n",
            argv[1]);
    return CLI_USAGE;
  }
  verify_args_t a = {NULL, NULL, 0, 0, 0};
  int rc = parse(argc, argv, &a);
  if (rc >= 0)
    return rc;
  char cmd[64];
  snprintf(cmd, sizeof cmd, "verify %s", argv[1]);
  if (outputs_ok(cmd, a.json, a.csv, bounds) != CLI_OK)
    return CLI_USAGE;
  int r;
  if (bounds) { /* issue 3: validation/src/verify_bounds.c */
    val_bounds_opts_t o = {a.quick, a.no_fit, a.json, a.csv, stdout, NULL, NULL, (int)a.threads};
    if (isatty(2)) {
      o.progress = cli_progress;
      o.progress_ctx = (void *)"verifying bounds";
    }
    r = val_verify_bounds(&o);
  } else if (disp) { /* issue 22: validation/src/verify_dispersion.c */
    val_disp_opts_t o = {a.quick, a.json, a.csv, stdout};
    r = val_verify_dispersion(&o);
  } else if (star) { /* issue 23: validation/src/verify_star.c */
    val_star_opts_t o = {a.quick, a.json, a.csv, stdout};
    r = val_verify_star(&o);
  } else if (illum) {
    val_illum_opts_t o = {a.quick, a.json, a.csv, stdout};
    r = val_verify_illuminance(&o);
  } else {
    val_matrices_opts_t o = {a.quick, a.json, a.csv, stdout};
    r = val_verify_matrices(&o);
  }
  return r != 0 ? CLI_FAIL : CLI_OK; /* r < 0: a write after the work failed */
}
