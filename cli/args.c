/* args.c -- the one command-line parser of the pencil command (args.h). */
#include "args.h"

#include <stdio.h>
#include <string.h>

static const cli_spec_t *find_long(const char *arg, size_t len, const cli_spec_t *specs, int n) {
  for (int k = 0; k < n; k++)
    if (specs[k].name && strlen(specs[k].name) == len && strncmp(specs[k].name, arg, len) == 0)
      return &specs[k];
  return NULL;
}

static const cli_spec_t *find_short(char c, const cli_spec_t *specs, int n) {
  for (int k = 0; k < n; k++)
    if (c && specs[k].short_name == c)
      return &specs[k];
  return NULL;
}

static int fail(const char *cmd, const char *what, const char *arg) {
  fprintf(stderr, "pencil %s: %s '%s' (see --help)\n", cmd, what, arg);
  return -1;
}

/* Parse the option at argv[*i] into *a; 0 ok, -1 error (printed). */
static int option(const char *cmd, int argc, char **argv, int *i, const cli_spec_t *specs, int n,
                  cli_arg_t *a) {
  const char *arg = argv[*i], *value = NULL;
  const cli_spec_t *s;
  int attached = 0;
  if (arg[1] == '-') { /* --name or --name=value */
    const char *eq = strchr(arg, '=');
    s = find_long(arg, eq ? (size_t)(eq - arg) : strlen(arg), specs, n);
    if (!s)
      return fail(cmd, "unknown option", arg);
    if (eq)
      value = eq + 1, attached = 1;
  } else { /* -x or -xVALUE */
    s = find_short(arg[1], specs, n);
    if (!s || (!s->has_value && arg[2] != '\0'))
      return fail(cmd, "unknown option", arg);
    if (arg[2] != '\0')
      value = arg + 2, attached = 1;
  }
  if (!s->has_value && attached)
    return fail(cmd, "this option takes no value:", arg);
  if (s->has_value && !attached) {
    if (*i + 1 >= argc)
      return fail(cmd, "this option needs a value:", arg);
    value = argv[++*i];
  }
  *a = (cli_arg_t){s, s->name, value};
  return 0;
}

int cli_parse(const char *cmd, int argc, char **argv, const cli_spec_t *specs, int nspecs,
              cli_arg_t *out) {
  int n = 0, positional_only = 0;
  for (int i = 1; i < argc; i++) {
    const char *arg = argv[i];
    if (!positional_only && strcmp(arg, "--") == 0) {
      positional_only = 1;
    } else if (!positional_only && (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0)) {
      return CLI_ARGS_HELP;
    } else if (!positional_only && arg[0] == '-' && arg[1] != '\0') {
      if (option(cmd, argc, argv, &i, specs, nspecs, &out[n]) != 0)
        return -1;
      const cli_spec_t *s = out[n].spec;
      for (int j = 0; j < n && s->has_value != CLI_REPEATED; j++)
        if (out[j].spec == s) { /* the last would win silently */
          char alias[8] = "";
          if (s->short_name)
            snprintf(alias, sizeof alias, " (-%c)", s->short_name);
          fprintf(stderr, "pencil %s: %s%s is given twice; give it once (see --help)\n", cmd,
                  s->name, alias);
          return -1;
        }
      n++;
    } else {
      out[n++] = (cli_arg_t){NULL, NULL, arg};
    }
  }
  return n;
}
