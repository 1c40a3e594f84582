/* cmd_verify.c -- `pencil verify WHAT`: the verification runs of the validation suite. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "validation/bounds.h"
#include "validation/verify.h"

static void help(FILE *f) {
  fprintf(
      f,
      "usage: pencil verify matrices [--json FILE] [--csv FILE] [--quick]\n"
      "       pencil verify bounds [--json FILE] [--csv DIR] [--quick] [--no-fit] [--threads N]\n\n"
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
      "          (default: all cores; the results are the same for any N).\n\n"
      "options:\n"
      "  --json FILE   write the summary {\"systems\", \"worst_relative_error\", \"failures\", "
      "...}\n"
      "  --csv FILE    write one row per system\n"
      "  --quick       a small sweep (for tests)\n\n"
      "Exit codes: 0 all systems pass, 1 some fail, 2 usage or I/O error.\n");
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

int cmd_verify(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  int bounds = strcmp(argv[1], "bounds") == 0;
  if (!bounds && strcmp(argv[1], "matrices") != 0) {
    fprintf(stderr, "pencil verify: unknown verification '%s' (try: matrices, bounds)\n", argv[1]);
    return CLI_USAGE;
  }
  verify_args_t a = {NULL, NULL, 0, 0, 0};
  int rc = parse(argc, argv, &a);
  if (rc >= 0)
    return rc;
  int r;
  if (bounds) { /* issue 3: validation/src/verify_bounds.c */
    val_bounds_opts_t o = {a.quick, a.no_fit, a.json, a.csv, stdout, NULL, NULL, (int)a.threads};
    if (isatty(2)) {
      o.progress = cli_progress;
      o.progress_ctx = (void *)"verifying bounds";
    }
    r = val_verify_bounds(&o);
  } else {
    val_matrices_opts_t o = {a.quick, a.json, a.csv, stdout};
    r = val_verify_matrices(&o);
  }
  return r < 0 ? CLI_USAGE : r ? CLI_FAIL : CLI_OK;
}
