/* cmd_matrix.c -- `pencil matrix`: the system matrix calculator (Eqs. 1 and 2).
 * Its stdout is a contract: {"T": [[...], [...], [...], [...]]}, rows and columns ordered
 * x1, x2, xi1, xi2; on any error nothing is printed on stdout. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "io/output.h"
#include "paraxial/paraxial.h"

static void help(FILE *f) {
  fprintf(f,
          "usage: pencil matrix refract --theta-deg T --n1 N1 --n2 N2 [--radius R] [--variant V]\n"
          "                            [--error-bound] [--dispersion D]\n"
          "       pencil matrix reflect --theta-deg T [--radius R] [--variant V] [--error-bound]\n"
          "                            [--dispersion D]\n"
          "       pencil matrix transfer --distance D [--dispersion D]\n\n"
          "Prints the 4x4 system matrix as JSON {\"T\": [[...], ...]}; rows and columns are\n"
          "ordered x1, x2, xi1, xi2 (position, then direction; Eq. 1 and Eq. 2).\n\n"
          "Frames (paper, Fig. 3): x2 = x2' = the unit normal of the plane of incidence,\n"
          "x1 = x2 x z and x1' = x2' x z' (right-handed, also after a reflection), so that\n"
          "Theta = diag(cos theta, 1) and Theta' = diag(cos theta', 1).\n\n"
          "options:\n"
          "  --theta-deg T   angle of incidence in degrees, 0 <= T <= 90 (90: grazing, exit 1)\n"
          "  --n1 N1         index of the incident medium, 0.001..100 (as a scene's\n"
          "                  ior); optional for reflect\n"
          "  --n2 N2         index of the far medium, 0.001..100\n"
          "  --radius R      radius of curvature of a spherical surface (non-zero). R > 0 when\n"
          "                  the centre of curvature is on the far side of the surface from the\n"
          "                  incoming light (a glass ball entered from outside, a convex mirror);\n"
          "                  R < 0 otherwise (a ball left from inside, a concave mirror).\n"
          "                  Without --radius the surface is a plane.\n"
          "  --distance D    transfer length along the axial ray\n"
          "  --variant V     corrected (default: confirmed by exact tracing) or printed\n"
          "                  (Eq. 2 verbatim from the paper; see docs/errata.md)\n"
          "  --dispersion D  print the 5 x 5 extended matrix of the 1989 Eq. (13) instead, rows\n"
          "                  and columns x1, x2, xi1, xi2, delta-lambda (nm): D = dn2/dlambda\n"
          "                  (1/nm) of the far medium at the axial ray's wavelength (the near\n"
          "                  one taken as not dispersing); the upper-left 4 x 4 is the matrix\n"
          "                  printed without it. A reflection's and a transfer's wavelength\n"
          "                  column is zero. --variant printed evaluates Eq. (14) as printed\n"
          "                  (docs/errata.md, E7).\n"
          "  --error-bound   also print \"error_bound\": the bound on the matrix's scaled\n"
          "                  relative error (<= 1e-8; docs/verification.md, \"Stability\")\n\n"
          "Every matrix printed is within 1e-8 of the exact one (relative to its largest entry,\n"
          "C scaled by |R|); where double precision cannot promise that (within ~1e-5 deg of\n"
          "the critical angle, a radius below 1e-120) none is printed.\n\n"
          "Exit codes: 0 matrix printed; 1 no matrix exists or it cannot be given to that\n"
          "accuracy (total internal reflection, grazing incidence or exit, ill-conditioned,\n"
          "overflow; reason on stderr); 2 usage error.\n");
}

int cmd_matrix(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  const char *kind = argv[1];
  int is_transfer = strcmp(kind, "transfer") == 0;
  cli_element_t e = {strcmp(kind, "reflect") == 0, NAN, NAN, NAN, INFINITY, PX_VARIANT_CORRECTED};
  if (!is_transfer && !e.reflect && strcmp(kind, "refract") != 0) {
    fprintf(stderr, "pencil matrix: unknown element '%s' (refract, reflect or transfer)\n", kind);
    return CLI_USAGE;
  }
  double distance = NAN;
  enum { OPT_ERROR_BOUND = 1, OPT_DISPERSION = 2 };
  cli_spec_t specs[8];
  int ns = is_transfer ? 1 : cli_element_specs(&e, specs), error_bound = 0, five = 0;
  double disp = 0.0;
  if (is_transfer)
    specs[0] = (cli_spec_t){"--distance", 0, 1, 1};
  else
    specs[ns++] = (cli_spec_t){"--error-bound", 0, 0, OPT_ERROR_BOUND};
  specs[ns++] = (cli_spec_t){"--dispersion", 0, 1, OPT_DISPERSION};
  char cmd[32];
  snprintf(cmd, sizeof cmd, "matrix %s", kind);
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc - 1, argv + 1, specs, ns, help, &n, &rc);
  if (!args)
    return rc;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    if (!is_transfer && args[k].spec && args[k].spec->id == OPT_ERROR_BOUND) {
      error_bound = 1;
      continue;
    }
    if (args[k].spec && args[k].spec->id == OPT_DISPERSION) {
      five = 1;
      rc =
          cli_parse_double_in("--dispersion", args[k].value, -1.0, 1.0, &disp) ? CLI_OK : CLI_USAGE;
      continue;
    }
    int r =
        is_transfer
            ? (args[k].spec ? cli_parse_double("--distance", args[k].value, &distance) ? 1 : -1 : 0)
            : cli_element_apply(cmd, &args[k], &e);
    if (r == 0)
      fprintf(stderr, "pencil matrix %s: unexpected argument '%s'\n", kind, args[k].value);
    rc = r > 0 ? CLI_OK : CLI_USAGE;
  }
  free(args);
  if (rc != CLI_OK)
    return rc;

  px_mat4_t t;
  px_ray4_t w = {{0, 0, 0, 0}}; /* the wavelength column (with --dispersion) */
  double bound = 0.0;           /* a transfer is exact: its entries are the inputs */
  if (is_transfer) {
    if (isnan(distance)) {
      fprintf(stderr, "pencil matrix transfer: --distance is required\n");
      return CLI_USAGE;
    }
    t = px_transfer_matrix(distance);
  } else {
    if (!cli_element_check("matrix", &e))
      return CLI_USAGE;
    px_event_t ev = e.reflect ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
    double c, s; /* from degrees without rounding the radian value (accurate near grazing) */
    px_cos_sin_deg(e.theta_deg, &c, &s);
    px_status_t st = px_element_matrix_cs(ev, c, s, e.n1, e.n2, e.radius, e.variant, &t, &bound);
    px_mat5_t t5;
    if (st == PX_OK && five) {
      st = px_element_matrix5_cs(ev, c, s, e.n1, e.n2, 0.0, disp, e.radius, e.variant, &t5, NULL);
      w = t5.w;
    }
    if (st != PX_OK) {
      char th[IO_SHORTEST_MAX], n1[IO_SHORTEST_MAX], n2[IO_SHORTEST_MAX];
      fprintf(stderr,
              "pencil matrix %s: no system matrix at theta = %s deg, n1 = %s, n2 = %s: %s\n", kind,
              io_shortest(e.theta_deg, th), io_shortest(e.n1, n1), io_shortest(e.n2, n2),
              px_strerror(st));
      return st == PX_EINVAL ? CLI_USAGE : CLI_FAIL;
    }
  }
  if (five) { /* the 5 x 5 of Eq. (13): the 4 x 4's rows with the column, then (0 0 0 0 1) */
    printf("{\"T\": [");
    for (int i = 0; i < 5; i++) {
      printf("%s[", i ? ", " : "");
      for (int j = 0; j < 5; j++) {
        double v = i < 4 ? (j < 4 ? t.m[i][j] : w.v[i]) : (j == 4 ? 1.0 : 0.0);
        printf("%s%.17g", j ? ", " : "", v == 0.0 ? 0.0 : v);
      }
      printf("]");
    }
    if (error_bound)
      printf("], \"error_bound\": %.3g}\n", bound);
    else
      printf("]}\n");
    return CLI_OK;
  }
  if (!error_bound) {
    cli_print_matrix_json(stdout, "T", t.m);
    return CLI_OK;
  }
  printf("{\"T\": ["); /* the format of cli_print_matrix_json, then the bound */
  for (int i = 0; i < 4; i++) {
    printf("%s[", i ? ", " : "");
    for (int j = 0; j < 4; j++)
      printf("%s%.17g", j ? ", " : "", t.m[i][j] == 0.0 ? 0.0 : t.m[i][j]);
    printf("]");
  }
  printf("], \"error_bound\": %.3g}\n", bound);
  return CLI_OK;
}
