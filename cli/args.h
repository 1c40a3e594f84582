/* args.h -- the one command-line parser of the pencil command.
 *
 * Every subcommand describes its options as cli_spec_t records and gets its arguments back as a
 * list of cli_arg_t, in order. Conventions, the GNU ones users expect:
 *   --name VALUE and --name=VALUE; -x VALUE and -xVALUE for an option with a short name;
 *   -h and --help anywhere before "--"; "--" ends the options (what follows is positional, even
 *   when it starts with '-'); a lone "-" is positional. Option names match exactly (no
 *   abbreviations, so that adding an option never breaks a script). */
#ifndef PENCIL_CLI_ARGS_H
#define PENCIL_CLI_ARGS_H

/** cli_spec_t.has_value of an option that takes a value each time it is given, and may be given
 *  more than once (illuminance --receiver). Every other option given twice is an error: the last
 *  would win silently. */
#define CLI_REPEATED 2

/** One option a command accepts. */
typedef struct {
  const char *name; /**< the long option, "--output" */
  char short_name;  /**< 'o' for -o, or 0 */
  int has_value;    /**< 0: a flag; 1: takes a value; CLI_REPEATED: a value, and may repeat */
  int id;           /**< the caller's code for it */
} cli_spec_t;

/** One parsed argument. */
typedef struct {
  const cli_spec_t *spec; /**< the option, or NULL for a positional argument */
  const char *name;       /**< the option's long name (spec->name), NULL when positional */
  const char *value;      /**< the option's value (NULL for a flag), or the positional text */
} cli_arg_t;

/** cli_parse(): help was asked for. */
#define CLI_ARGS_HELP (-2)

/** Parse argv[1 .. argc-1] (argv[0] is the subcommand) against specs[0 .. nspecs-1] into
 *  out[] (room for argc entries). Returns the number of arguments, CLI_ARGS_HELP when -h or
 *  --help was given, or -1 after printing "pencil CMD: what is wrong (see --help)" on stderr
 *  (an unknown option, a missing value, a value given to a flag, an option given twice that is
 *  not cli_spec_t.repeat). */
int cli_parse(const char *cmd, int argc, char **argv, const cli_spec_t *specs, int nspecs,
              cli_arg_t *out);

#endif
