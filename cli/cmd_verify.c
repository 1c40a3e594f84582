/* cmd_verify.c -- `pencil verify WHAT`: the verification runs of the validation suite. */
#include <string.h>

#include "cli.h"
#include "validation/verify.h"

static void help(FILE *f) {
  fprintf(f, "usage: pencil verify matrices [--json FILE] [--csv FILE] [--quick]\n\n"
             "matrices  compare every system matrix (transfer Eq. 1, refraction Eq. 2, reflection,\n"
             "          cascades) of a sweep of > 2,000 systems with the Jacobian of exact\n"
             "          Snell-law tracing in __float128; prints a summary table per family and\n"
             "          for the printed form of Eq. (2).\n\n"
             "options:\n"
             "  --json FILE   write the summary {\"systems\", \"worst_relative_error\", \"failures\", ...}\n"
             "  --csv FILE    write one row per system\n"
             "  --quick       a small sweep (for tests)\n\n"
             "Exit codes: 0 all systems pass, 1 some fail, 2 usage or I/O error.\n");
}

int cmd_verify(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  if (strcmp(argv[1], "matrices") != 0) {
    fprintf(stderr, "pencil verify: unknown verification '%s' (try: matrices)\n", argv[1]);
    return CLI_USAGE;
  }
  val_matrices_opts_t o = {0, NULL, NULL, stdout};
  for (int i = 2; i < argc; i++) {
    int err = 0;
    const char *v, *opt = argv[i];
    if (cli_is_help(opt)) {
      help(stdout);
      return CLI_OK;
    } else if ((v = cli_option(argc, argv, &i, "--json", &err))) {
      o.json = v;
    } else if ((v = cli_option(argc, argv, &i, "--csv", &err))) {
      o.csv = v;
    } else if (strcmp(opt, "--quick") == 0) {
      o.quick = 1;
    } else {
      if (!err)
        fprintf(stderr, "pencil verify matrices: unknown option '%s'\n", opt);
      return CLI_USAGE;
    }
    if (err)
      return CLI_USAGE;
  }
  int r = val_verify_matrices(&o);
  return r < 0 ? CLI_USAGE : r ? CLI_FAIL : CLI_OK;
}
