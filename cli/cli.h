/* cli.h -- the pencil command: shared argument helpers and the subcommand table.
 *
 * Each subcommand lives in its own cmd_*.c with an entry `int cmd_NAME(int argc, char **argv)`
 * (argv[0] is the subcommand's own name) and returns a process exit code:
 * 0 success, 1 the computation reported a failure (e.g. TIR, failed verification),
 * 2 usage error (bad option or parameter; message on stderr).
 */
#ifndef PENCIL_CLI_H
#define PENCIL_CLI_H

#include <stdio.h>

enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2 };

/** Parse a finite double for option `opt`; on failure print "pencil: OPT: ..." and return 0. */
int cli_parse_double(const char *opt, const char *text, double *out);
/** Parse an integer in [lo, hi] for option `opt`; on failure print an error and return 0. */
int cli_parse_long(const char *opt, const char *text, long lo, long hi, long *out);
/** "--name=value" or "--name value": return the value for `name` at argv[*i] or NULL. Advances
 *  *i past a separate value. Prints an error and sets *err when the value is missing. */
const char *cli_option(int argc, char **argv, int *i, const char *name, int *err);
/** 1 when argv[i] is -h or --help. */
int cli_is_help(const char *arg);
/** Print a JSON array of a 4x4 matrix as {"T": [[...], ...]} with 17 significant digits. */
void cli_print_matrix_json(FILE *f, const char *key, const double m[4][4]);

int cmd_matrix(int argc, char **argv);
int cmd_verify(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_bounds(int argc, char **argv);

#endif
