/* cmd_bounds.c -- `pencil bounds`: the error coefficients a-f of Appendix A-1 for one refraction
 * or reflection at a sphere or plane (section 3.2, Eq. 4). Its stdout is a contract:
 * {"a": .., "b": .., "c": .., "d": .., "e": .., "f": ..}; on any error nothing is printed on
 * stdout. Conventions are those of `pencil matrix` (cmd_matrix.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "io/output.h"
#include "paraxial/paraxial.h"

static void help(FILE *f) {
  fprintf(
      f,
      "usage: pencil bounds refract --theta-deg T --n1 N1 --n2 N2 [--radius R] [--d3m D]\n"
      "                             [--variant V]\n"
      "       pencil bounds reflect --theta-deg T [--radius R] [--d3m D] [--variant V]\n\n"
      "Prints the coefficients of the element's error estimation functions (Appendix A-1)\n"
      "  e_x  = a x^2 + b x xi + c xi^2  >= |Delta x|\n"
      "  e_xi = d x^2 + e x xi + f xi^2  >= |Delta xi|\n"
      "as JSON {\"a\": .., \"b\": .., \"c\": .., \"d\": .., \"e\": .., \"f\": ..}, where x = |x|\n"
      "and xi = |xi| are the sizes of a ray vector's position and direction parts in the\n"
      "element's frames and Delta the second-order error of the linear map (Eq. 2). Units with\n"
      "a length L: a 1/L, b 1, c L, d 1/L^2, e 1/L, f 1.\n\n"
      "options:\n"
      "  --theta-deg T   angle of incidence in degrees, 0 <= T <= 90 (90: grazing, exit 1)\n"
      "  --n1 N1         index of the incident medium, 0.001..100 (as a scene's\n"
      "                  ior); optional for reflect\n"
      "  --n2 N2         index of the far medium, 0.001..100\n"
      "  --radius R      radius of a spherical surface (non-zero; its sign, as in\n"
      "                  `pencil matrix`, does not change the coefficients). Without\n"
      "                  --radius the surface is a plane. A sphere has d_3m = 0.\n"
      "  --d3m D         largest |third derivative| of a general surface's height (>= 0,\n"
      "                  units 1/L^2; default 0), the d_3m of A-1\n"
      "  --variant V     corrected (default: derived by the project and confirmed by exact\n"
      "                  tracing) or printed (A-1 verbatim, R read as the smallest radius of\n"
      "                  curvature; may be negative for mirrors; see docs/errata.md)\n\n"
      "Exit codes: 0 coefficients printed; 1 no system matrix exists (total internal\n"
      "reflection, grazing incidence or exit, ill-conditioned, overflow: exactly where\n"
      "`pencil matrix` prints none; reason on stderr); 2 usage error.\n");
}

int cmd_bounds(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  const char *kind = argv[1];
  int is_reflect = strcmp(kind, "reflect") == 0;
  if (!is_reflect && strcmp(kind, "refract") != 0) {
    fprintf(stderr, "pencil bounds: unknown element '%s' (refract or reflect)\n", kind);
    return CLI_USAGE;
  }
  cli_element_t el = {is_reflect, NAN, NAN, NAN, INFINITY, PX_VARIANT_CORRECTED};
  double d3m = 0.0;
  cli_spec_t specs[6];
  int ns = cli_element_specs(&el, specs);
  specs[ns++] = (cli_spec_t){"--d3m", 0, 1, 1};
  char cmd[32];
  snprintf(cmd, sizeof cmd, "bounds %s", kind);
  int n, rc;
  cli_arg_t *args = cli_args(cmd, argc - 1, argv + 1, specs, ns, help, &n, &rc);
  if (!args)
    return rc;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    int r = cli_element_apply(cmd, &args[k], &el);
    if (r == 0 && !args[k].spec) {
      fprintf(stderr, "pencil bounds %s: unexpected argument '%s'\n", kind, args[k].value);
    } else if (r == 0 && cli_parse_double("--d3m", args[k].value, &d3m)) { /* --d3m */
      r = d3m >= 0.0 ? 1 : 0;
      if (!r)
        fprintf(stderr, "pencil bounds %s: --d3m must be >= 0, got %s\n", kind, args[k].value);
    }
    rc = r > 0 ? CLI_OK : CLI_USAGE;
  }
  free(args);
  if (rc != CLI_OK)
    return rc;
  if (!cli_element_check("bounds", &el))
    return CLI_USAGE;
  double theta = el.theta_deg, n1 = el.n1, n2 = el.n2, radius = el.radius;
  px_variant_t variant = el.variant;
  px_element_geom_t g = {is_reflect ? PX_EVENT_REFLECT : PX_EVENT_REFRACT,
                         theta * M_PI / 180.0,
                         n1,
                         n2,
                         fabs(radius),
                         d3m};
  px_coeffs_t k;
  double c, s; /* as `pencil matrix`: the same cosines, so both refuse alike */
  px_cos_sin_deg(theta, &c, &s);
  px_status_t st = px_error_coeffs_cs(&g, c, s, variant, &k);
  if (st != PX_OK) {
    char th[IO_SHORTEST_MAX], s1[IO_SHORTEST_MAX], s2[IO_SHORTEST_MAX];
    fprintf(
        stderr, "pencil bounds %s: no error coefficients at theta = %s deg, n1 = %s, n2 = %s: %s\n",
        kind, io_shortest(theta, th), io_shortest(n1, s1), io_shortest(n2, s2), px_strerror(st));
    return st == PX_EINVAL ? CLI_USAGE : CLI_FAIL;
  }
  const double v[6] = {k.a, k.b, k.c, k.d, k.e, k.f};
  const char *names = "abcdef";
  printf("{");
  for (int i = 0; i < 6; i++)
    printf("%s\"%c\": %.17g", i ? ", " : "", names[i], v[i] == 0.0 ? 0.0 : v[i]);
  printf("}\n");
  return CLI_OK;
}
