/* cli.h -- the pencil command: shared argument helpers and the subcommand table.
 *
 * Each subcommand lives in its own cmd_*.c with an entry `int cmd_NAME(int argc, char **argv)`
 * (argv[0] is the subcommand's own name) and returns a process exit code:
 * 0 success, 1 the computation reported a failure (e.g. TIR, failed verification, a write after
 * the work), 2 usage or input error (bad option or parameter, a bad scene, an output path that
 * cannot be written found before any work; message on stderr).
 */
#ifndef PENCIL_CLI_H
#define PENCIL_CLI_H

#include <stdio.h>

#include "args.h"
#include "core/scene.h"
#include "paraxial/system.h"
#include "post/star.h"

enum { CLI_OK = 0, CLI_FAIL = 1, CLI_USAGE = 2 };

/** The exit code of a validation driver's result (validation/status.h): 0 CLI_OK; VAL_ESCENE and
 *  VAL_EOUTPUT CLI_USAGE (the input was wrong); any other failure CLI_FAIL (the work failed). */
int cli_exit_of(int val_rc);

/** Numbers on the command line follow one rule, rn_parse_double() and rn_parse_long()
 *  (renderers/renderer.h): an optional '-', digits, for a double an optional point and exponent;
 *  no spaces, no '+', no hexadecimal. */

/** Parse a finite double for option `opt`; on failure print "pencil CMD: OPT: ..." (io_command())
 *  and return 0. */
int cli_parse_double(const char *opt, const char *text, double *out);
/** cli_parse_double() of a number in [lo, hi]; on failure print an error and return 0. */
int cli_parse_double_in(const char *opt, const char *text, double lo, double hi, double *out);
/** Parse an integer in [lo, hi] for option `opt`; on failure print an error and return 0. */
int cli_parse_long(const char *opt, const char *text, long lo, long hi, long *out);
/** Parse a number of samples per pixel for option `opt` of command `cmd`: a square s x s with
 *  1 <= s <= RT_MAX_SPP_SIDE (1, 4, 9, ..., 1024); on failure print an error and return 0. */
int cli_parse_spp(const char *cmd, const char *opt, const char *text, long *out);
/** Parse "WxH" for option `opt` of command `cmd`, both in 1..max; on failure print an error
 *  naming the option and return 0. */
int cli_parse_wxh(const char *cmd, const char *opt, const char *text, long max, long *w, long *h);
/** Split `text`, a comma-separated list for option `opt`, the one list rule of every command: 1
 *  to `max` items, none empty (no leading, trailing or double comma), nothing trimmed (each item
 *  is then parsed by the number rule, rn_parse_double()/rn_parse_long()). The items are copied
 *  into buf (cap bytes) and item[0 .. *n - 1] point into it. On failure prints "pencil CMD: OPT:
 *  ..." and returns 0. */
int cli_split_list(const char *opt, const char *text, char *buf, size_t cap, const char **item,
                   int max, int *n);
/** A comma-separated list (cli_split_list()) of such numbers, at most `max`, into
 *  out[0 .. *n - 1]. */
int cli_parse_spp_list(const char *cmd, const char *opt, const char *text, int *out, int max,
                       int *n);
/** cli_parse() of argv[1 .. argc-1] for `pencil CMD` (argv[0] the subcommand's word) into a
 *  new array (free() it): returns it with the count in *n, or NULL when the command is done,
 *  with *rc = CLI_OK after help(stdout) for -h/--help, CLI_USAGE after a message. */
cli_arg_t *cli_args(const char *cmd, int argc, char **argv, const cli_spec_t *specs, int nspecs,
                    void (*help)(FILE *), int *n, int *rc);
/** 1 when argv[i] is -h or --help. */
int cli_is_help(const char *arg);

/** Load SCENE.json (path) or, when path is NULL, the built-in Fig. 8 scene into s, and override
 *  its image size when width > 0. Returns CLI_OK; on failure prints "pencil CMD: why" on stderr
 *  (the file and line for a bad scene) and returns CLI_USAGE for a bad scene, CLI_FAIL when
 *  memory ran out. */
int cli_load_scene(const char *cmd, const char *path, long width, long height, rt_scene_t *s);
/** A progress bar on stderr for long work: "\rLABEL [####    ]  42%", a newline when done.
 *  The signature is the renderers' and drivers' progress callback, with ctx = the label (a
 *  const char *). Callers install it only when isatty(2). */
void cli_progress(void *label, int done, int total);

/** The star filter's parameters as the pencil:star attribute holds them ("directions 4, angle 20
 *  deg, ratio 0.01, ..."), every number in its shortest round-trip form (io_shortest()). */
void cli_star_describe(const pp_star_t *p, char *buf, size_t cap);

/** Print a JSON array of a 4x4 matrix as {"T": [[...], ...]} with 17 significant digits. */
void cli_print_matrix_json(FILE *f, const char *key, const double m[4][4]);

/** One refraction or reflection as `pencil matrix` and `pencil bounds` take it (the paper's
 *  frames; radius sign convention of docs/conventions.md). */
typedef struct {
  int reflect;          /**< 1: reflect, 0: refract */
  double theta_deg;     /**< incidence angle in degrees; NAN until given */
  double n1, n2;        /**< indices; NAN until given (a reflection defaults to 1) */
  double radius;        /**< sphere radius, INFINITY (plane) until given */
  px_variant_t variant; /**< corrected unless --variant printed */
} cli_element_t;

/** The options of an element (args.h ids CLI_EL_*): --theta-deg, --n1, --n2 (refraction only),
 *  --radius, --variant. */
enum { CLI_EL_THETA = 100, CLI_EL_N1, CLI_EL_N2, CLI_EL_RADIUS, CLI_EL_VARIANT };
/** The specs of those options into specs[] (room for 5); returns how many (4 for a reflection,
 *  which has no --n2). */
int cli_element_specs(const cli_element_t *e, cli_spec_t *specs);
/** Apply a parsed argument: 1 when it was an element option and valid, 0 when it is another
 *  argument, -1 after printing a usage error that names `cmd` ("matrix refract") and the option.
 *  An index outside RT_IOR_MIN..RT_IOR_MAX (core/scene.h: what a scene's ior may be) is refused. */
int cli_element_apply(const char *cmd, const cli_arg_t *g, cli_element_t *e);

/** After parsing: check that the angle (in [0, 90]) and the indices are given (cli_element_apply()
 *  took them only from RT_IOR_MIN to RT_IOR_MAX); fills in n1 = n2 for a reflection. Returns 1,
 *  or 0 after printing a usage error. */
int cli_element_check(const char *cmd, cli_element_t *e);

int cmd_matrix(int argc, char **argv);
int cmd_verify(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_bench(int argc, char **argv);
/** `pencil bench pencil` (cmd_bench_pencil.c); argv[0] is "pencil". */
int cmd_bench_pencil(int argc, char **argv);
int cmd_bounds(int argc, char **argv);
/** `pencil illuminance` (cmd_illuminance.c). */
int cmd_illuminance(int argc, char **argv);
/** `pencil figures` and `pencil sweep` (cmd_figures.c). */
int cmd_figures(int argc, char **argv);
int cmd_sweep(int argc, char **argv);
/** `pencil post` (cmd_post.c): post-processing filters, `post star`. */
int cmd_post(int argc, char **argv);
/** `pencil export` (cmd_export.c): a scene for another renderer, `export pov`. */
int cmd_export(int argc, char **argv);

#endif
