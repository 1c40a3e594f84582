/* cli.c -- argument helpers shared by the pencil subcommands. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int cli_parse_double(const char *opt, const char *text, double *out) {
  char *end = NULL;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !isfinite(v)) {
    fprintf(stderr, "pencil: %s: expected a finite number, got '%s'\n", opt, text);
    return 0;
  }
  *out = v;
  return 1;
}

int cli_parse_long(const char *opt, const char *text, long lo, long hi, long *out) {
  char *end = NULL;
  errno = 0;
  long v = strtol(text, &end, 10);
  if (end == text || *end != '\0' || errno == ERANGE || v < lo || v > hi) {
    fprintf(stderr, "pencil: %s: expected an integer from %ld to %ld, got '%s'\n", opt, lo, hi,
            text);
    return 0;
  }
  *out = v;
  return 1;
}

const char *cli_option(int argc, char **argv, int *i, const char *name, int *err) {
  const char *a = argv[*i];
  size_t n = strlen(name);
  if (strncmp(a, name, n) != 0)
    return NULL;
  if (a[n] == '=')
    return a + n + 1;
  if (a[n] != '\0')
    return NULL;
  if (*i + 1 >= argc) {
    fprintf(stderr, "pencil: %s needs a value\n", name);
    *err = 1;
    return NULL;
  }
  return argv[++*i];
}

int cli_is_help(const char *arg) { return strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0; }

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
