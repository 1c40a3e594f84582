/* main.c -- the pencil command: dispatch to subcommands. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "commit.h"
#include "io/output.h"

typedef struct {
  const char *name;
  int (*run)(int argc, char **argv);
  const char *summary;
  int kinds; /**< 1: the next word names what (`bench star`, `verify bounds`, `matrix refract`) */
} command_t;

static const command_t commands[] = {
    {"matrix", cmd_matrix, "system matrix calculator (transfer, refraction, reflection)", 1},
    {"verify", cmd_verify, "verify the paper's formulas against exact tracing", 1},
    {"render", cmd_render, "render a scene (exact Whitted or pencil tracing) to OpenEXR + PNG", 0},
    {"bench", cmd_bench,
     "benchmarks: 'bench render' rays per second, 'bench pencil' the 49-spp targets", 1},
    {"bounds", cmd_bounds, "error coefficients a-f of Appendix A-1 (refraction, reflection)", 1},
    {"illuminance", cmd_illuminance,
     "illuminance map of a receiver: grid-pencil tracing or photon counting (1989 section 2)", 0},
    {"figures", cmd_figures, "the paper's Figs. 8-10 with the pencil renderer, and the rho sweep",
     0},
    {"sweep", cmd_sweep, "time ratio and errors of the pencil renderer against rho", 0},
    {"post", cmd_post, "post-processing of HDR images: the cross-screen (star) filter (1989)", 1},
    {"export", cmd_export, "a scene for another renderer: 'export pov', POV-Ray 3.7", 1},
};

static void usage(FILE *f) {
  fprintf(f, "usage: pencil COMMAND [OPTIONS]\n\n"
             "Pencil tracing (Shinya, Takahashi, Naito, SIGGRAPH 1987): system matrices,\n"
             "error bounds, and their verification against exact Snell-law tracing.\n\n"
             "commands:\n");
  for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
    fprintf(f, "  %-10s %s\n", commands[i].name, commands[i].summary);
  fprintf(f, "\n'pencil COMMAND --help' describes each command.\n"
             "Exit codes: 0 success, 1 computation or verification failure, 2 usage or input\n"
             "error (an option, the scene, an output path that cannot be written).\n");
}

/* Whether s is valid UTF-8 (RFC 3629: no overlong forms, surrogates or code points past
 * U+10FFFF). */
static int utf8_valid(const char *s) {
  const unsigned char *p = (const unsigned char *)s;
  while (*p) {
    unsigned c = *p++;
    int more = c < 0x80             ? 0
               : (c & 0xE0) == 0xC0 ? 1
               : (c & 0xF0) == 0xE0 ? 2
               : (c & 0xF8) == 0xF0 ? 3
                                    : -1;
    if (more < 0 || c == 0xC0 || c == 0xC1 || c > 0xF4)
      return 0;
    unsigned cp = more == 0 ? c : c & (0x3Fu >> more);
    for (int k = 0; k < more; k++, p++) {
      if ((*p & 0xC0) != 0x80)
        return 0;
      cp = (cp << 6) | (*p & 0x3Fu);
    }
    if ((more == 2 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
        (more == 3 && (cp < 0x10000 || cp > 0x10FFFF)))
      return 0;
  }
  return 1;
}

int main(int argc, char **argv) {
  /* every argument is recorded in JSON outputs (the command line, paths), which hold UTF-8 only:
   * refused at once rather than failing after the work as "out of memory" */
  for (int i = 1; i < argc; i++)
    if (!utf8_valid(argv[i])) {
      fprintf(stderr, "pencil: argument %d ('", i);
      for (const unsigned char *p = (const unsigned char *)argv[i]; *p; p++)
        fprintf(stderr, *p >= 0x20 && *p < 0x7F ? "%c" : "\\x%02X", *p);
      fprintf(stderr, "') is not valid UTF-8; paths and options must be (outputs record them in "
                      "JSON)\n");
      return CLI_USAGE;
    }
  io_provenance_set(PENCIL_VERSION, PENCIL_COMMIT, argc, argv);
  io_cleanup_on_signals(); /* no temporary file outlives an interrupted write */
  if (argc < 2) {
    usage(stderr);
    return CLI_USAGE;
  }
  if (cli_is_help(argv[1])) {
    usage(stdout);
    return CLI_OK;
  }
  if (strcmp(argv[1], "--version") == 0) {
    printf("pencil %s (%s)\n", PENCIL_VERSION, PENCIL_COMMIT);
    return CLI_OK;
  }
  for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
    if (strcmp(argv[1], commands[i].name) == 0) {
      char name[128]; /* what messages start with: "pencil sweep", "pencil bench star" */
      int kind = commands[i].kinds && argc > 2 && argv[2][0] != '-';
      snprintf(name, sizeof name, "pencil %s%s%.64s", argv[1], kind ? " " : "",
               kind ? argv[2] : "");
      io_command_set(name);
      return commands[i].run(argc - 1, argv + 1);
    }
  fprintf(stderr, "pencil: unknown command '%s' (try 'pencil --help')\n", argv[1]);
  return CLI_USAGE;
}
