/* cli.c -- argument helpers shared by the pencil subcommands. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/builtin.h"
#include "io/output.h"
#include "io/scene_json.h"
#include "renderers/renderer.h"
#include "validation/status.h"

int cli_exit_of(int val_rc) {
  return val_rc == 0                                     ? CLI_OK
         : val_rc == VAL_ESCENE || val_rc == VAL_EOUTPUT ? CLI_USAGE
                                                         : CLI_FAIL;
}

int cli_parse_double(const char *opt, const char *text, double *out) {
  int r = rn_parse_double(text, out);
  if (r < 0)
    fprintf(stderr, "%s: %s: '%s' is beyond the range of a double (about 1.8e308)\n", io_command(),
            opt, text);
  else if (r == 0)
    fprintf(stderr, "%s: %s: expected a decimal number such as 1.5 or -2e-3, got '%s'\n",
            io_command(), opt, text);
  return r == 1;
}

int cli_parse_double_in(const char *opt, const char *text, double lo, double hi, double *out) {
  double v;
  if (!cli_parse_double(opt, text, &v))
    return 0;
  if (!(v >= lo && v <= hi)) {
    fprintf(stderr, "%s: %s: expected a number from %g to %g, got '%s'\n", io_command(), opt, lo,
            hi, text);
    return 0;
  }
  *out = v;
  return 1;
}

int cli_parse_long(const char *opt, const char *text, long lo, long hi, long *out) {
  long v;
  if (rn_parse_long(text, &v) != 1 || v < lo || v > hi) {
    fprintf(stderr, "%s: %s: expected an integer from %ld to %ld, got '%s'\n", io_command(), opt,
            lo, hi, text);
    return 0;
  }
  *out = v;
  return 1;
}

int cli_parse_spp(const char *cmd, const char *opt, const char *text, long *out) {
  long v = 0, s = 1;
  int ok = rn_parse_long(text, &v) == 1 && v >= 1 && v <= RT_MAX_SPP;
  while (ok && s * s < v)
    s++;
  if (!ok || s * s != v) {
    fprintf(stderr,
            "pencil %s: %s: expected a square number of samples per pixel (1, 4, 9, ..., %d), got "
            "'%s'\n",
            cmd, opt, RT_MAX_SPP, text);
    return 0;
  }
  *out = v;
  return 1;
}

int cli_parse_wxh(const char *cmd, const char *opt, const char *text, long max, long *w, long *h) {
  const char *x = strchr(text, 'x');
  char wtext[32];
  int ok = x && (size_t)(x - text) < sizeof wtext;
  if (ok) {
    memcpy(wtext, text, (size_t)(x - text));
    wtext[x - text] = '\0';
    ok = rn_parse_long(wtext, w) == 1 && rn_parse_long(x + 1, h) == 1;
  }
  if (!ok || *w < 1 || *h < 1 || *w > max || *h > max) {
    fprintf(stderr, "pencil %s: %s: expected WxH with 1 <= W, H <= %ld, got '%s'\n", cmd, opt, max,
            text);
    return 0;
  }
  return 1;
}

int cli_split_list(const char *opt, const char *text, char *buf, size_t cap, const char **item,
                   int max, int *n) {
  size_t len = strlen(text);
  *n = 0;
  int ok = len < cap;
  if (ok) {
    memcpy(buf, text, len + 1);
    for (char *t = buf; ok; t++) {
      char *end = strchr(t, ',');
      if (end)
        *end = '\0';
      ok = *t != '\0' && *n < max; /* no empty item: no leading, trailing or double comma */
      if (ok)
        item[(*n)++] = t;
      if (!end)
        break;
      t = end;
    }
  }
  if (!ok)
    fprintf(stderr,
            "%s: %s: expected a comma-separated list of 1 to %d values, none empty (no leading, "
            "trailing or double comma), got '%s'\n",
            io_command(), opt, max, text);
  return ok;
}

int cli_parse_spp_list(const char *cmd, const char *opt, const char *text, int *out, int max,
                       int *n) {
  char buf[512];
  const char *item[64];
  if (!cli_split_list(opt, text, buf, sizeof buf, item, max < 64 ? max : 64, n))
    return 0;
  for (int k = 0; k < *n; k++) {
    long v;
    if (!cli_parse_spp(cmd, opt, item[k], &v))
      return 0;
    out[k] = (int)v;
  }
  return 1;
}

cli_arg_t *cli_args(const char *cmd, int argc, char **argv, const cli_spec_t *specs, int nspecs,
                    void (*help)(FILE *), int *n, int *rc) {
  cli_arg_t *args = malloc((size_t)(argc > 0 ? argc : 1) * sizeof *args);
  *n = args ? cli_parse(cmd, argc, argv, specs, nspecs, args) : -1;
  *rc = CLI_OK;
  if (*n >= 0)
    return args;
  free(args);
  if (*n == CLI_ARGS_HELP)
    help(stdout);
  else if (!args)
    fprintf(stderr, "pencil %s: out of memory\n", cmd);
  *rc = *n == CLI_ARGS_HELP ? CLI_OK : CLI_USAGE;
  return NULL;
}

int cli_is_help(const char *arg) {
  return strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0;
}

void cli_star_describe(const pp_star_t *p, char *buf, size_t cap) {
  char v[8][IO_SHORTEST_MAX];
  snprintf(buf, cap,
           "directions %d, angle %s deg, ratio %s, sigma %s,%s rad, weight2 %s, ior %s, focal %s "
           "mm, frame %s mm",
           p->directions, io_shortest(p->angle_deg, v[0]), io_shortest(p->ratio, v[1]),
           io_shortest(p->sigma1, v[2]), io_shortest(p->sigma2, v[3]),
           io_shortest(p->weight2, v[4]), io_shortest(p->ior, v[5]), io_shortest(p->focal_mm, v[6]),
           io_shortest(p->frame_mm, v[7]));
}

void cli_print_matrix_json(FILE *f, const char *key, const double m[4][4]) {
  fprintf(f, "{\"%s\": [", key);
  for (int i = 0; i < 4; i++) {
    fprintf(f, "%s[", i ? ", " : "");
    for (int j = 0; j < 4; j++)
      fprintf(f, "%s%.17g", j ? ", " : "", m[i][j] == 0.0 ? 0.0 : m[i][j]);
    fprintf(f, "]");
  }
  fprintf(f, "]}\n");
}

int cli_element_specs(const cli_element_t *e, cli_spec_t *specs) {
  int n = 0;
  specs[n++] = (cli_spec_t){"--theta-deg", 0, 1, CLI_EL_THETA};
  specs[n++] = (cli_spec_t){"--n1", 0, 1, CLI_EL_N1};
  if (!e->reflect)
    specs[n++] = (cli_spec_t){"--n2", 0, 1, CLI_EL_N2};
  specs[n++] = (cli_spec_t){"--radius", 0, 1, CLI_EL_RADIUS};
  specs[n++] = (cli_spec_t){"--variant", 0, 1, CLI_EL_VARIANT};
  return n;
}

int cli_element_apply(const char *cmd, const cli_arg_t *g, cli_element_t *e) {
  double *target = NULL;
  if (!g->spec)
    return 0;
  switch (g->spec->id) {
  case CLI_EL_THETA:
    target = &e->theta_deg;
    break;
  case CLI_EL_N1:
    target = &e->n1;
    break;
  case CLI_EL_N2:
    target = &e->n2;
    break;
  case CLI_EL_RADIUS:
    target = &e->radius;
    break;
  case CLI_EL_VARIANT:
    if (px_variant_parse(g->value, &e->variant) == PX_OK)
      return 1;
    fprintf(stderr, "pencil %s: --variant: expected corrected or printed, got '%s'\n", cmd,
            g->value);
    return -1;
  default:
    return 0;
  }
  if (!cli_parse_double(g->name, g->value, target))
    return -1;
  if ((target == &e->n1 || target == &e->n2) && !(*target >= RT_IOR_MIN && *target <= RT_IOR_MAX)) {
    fprintf(stderr,
            "pencil %s: %s: expected a refractive index from %g to %g (as a scene's ior), got "
            "'%s'\n",
            cmd, g->name, RT_IOR_MIN, RT_IOR_MAX, g->value);
    return -1;
  }
  if (target == &e->radius && e->radius == 0.0) {
    fprintf(stderr, "pencil %s: --radius must be non-zero (omit it for a plane)\n", cmd);
    return -1;
  }
  return 1;
}

int cli_element_check(const char *cmd, cli_element_t *e) {
  const char *kind = e->reflect ? "reflect" : "refract";
  if (isnan(e->theta_deg)) {
    fprintf(stderr, "pencil %s %s: --theta-deg is required\n", cmd, kind);
    return 0;
  }
  if (e->theta_deg < 0.0 || e->theta_deg > 90.0) {
    char got[IO_SHORTEST_MAX];
    fprintf(stderr, "pencil %s %s: --theta-deg must be in [0, 90], got %s\n", cmd, kind,
            io_shortest(e->theta_deg, got));
    return 0;
  }
  if (e->reflect) {
    if (isnan(e->n1))
      e->n1 = 1.0; /* a reflection does not depend on the index */
    e->n2 = e->n1;
  }
  if (isnan(e->n1) || isnan(e->n2)) {
    fprintf(stderr, "pencil %s refract: --n1 and --n2 are required\n", cmd);
    return 0;
  }
  return 1;
}

void cli_progress(void *label, int done, int total) {
  int w = 40, k = total > 0 ? (int)((long)w * done / total) : w;
  fprintf(stderr, "\r%s [%.*s%*s] %3d%%", (const char *)label, k,
          "########################################", w - k, "",
          total > 0 ? (int)(100L * done / total) : 100);
  if (done >= total)
    fputc('\n', stderr);
}

int cli_load_scene(const char *cmd, const char *path, long width, long height, rt_scene_t *s) {
  char err[1024];
  rt_scene_init(s);
  int rc = path ? io_scene_load(path, s, err, sizeof err) : 0;
  if (rc != 0) /* -2: out of memory, the work failed; else the input was wrong */
    return fprintf(stderr, "pencil %s: %s\n", cmd, err), rc == -2 ? CLI_FAIL : CLI_USAGE;
  rt_status_t st = path ? RT_OK : rt_builtin_fig8(s);
  if (st != RT_OK)
    return fprintf(stderr, "pencil %s: cannot build the built-in Fig. 8 scene: %s\n", cmd,
                   rt_strerror(st)),
           CLI_FAIL;
  if (width > 0) {
    s->camera.width = (int)width;
    s->camera.height = (int)height;
  }
  return CLI_OK;
}
