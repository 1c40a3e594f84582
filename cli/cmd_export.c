/* cmd_export.c -- `pencil export`: a scene written for another renderer. `export pov` writes a
 * POV-Ray 3.7 scene file (io/pov.h), the peer that issue 26 times beside the exact renderer
 * (`pencil bench pencil --peer povray`) and checks pixel by pixel (tests/cli_export_pov.sh). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli.h"
#include "io/output.h"
#include "io/pov.h"

static void help_export(FILE *f) {
  fprintf(f, "usage: pencil export pov [OPTIONS]\n\n"
             "formats:\n"
             "  pov   a POV-Ray 3.7 scene file: the same camera, objects, materials, lights\n"
             "        and depth, for timing POV-Ray beside the exact renderer\n"
             "'pencil export FORMAT --help' describes each.\n");
}

static void help_pov(FILE *f) {
  fprintf(
      f,
      "usage: pencil export pov [SCENE.json] -o OUT.pov [--flat] [--size WxH] [--spp N]\n\n"
      "Writes SCENE.json (docs/scene-format.md) or, without it, the built-in Fig. 8 scene as\n"
      "a POV-Ray 3.7 scene: a camera whose rays through the pixel centres are the exact\n"
      "renderer's, spheres, planes (a checkerboard as a checker texture of its two\n"
      "materials), polygons, polyhedra (mesh2), point and parallel lights, the materials'\n"
      "ambient, diffuse, Phong, mirror and transparent terms, the background and the ray\n"
      "depth (max_trace_level = max_depth + 1, adc_bailout 0). What POV-Ray cannot be told\n"
      "(area lights, dispersive or Fresnel glass, caustics, ...) is refused naming it; what\n"
      "it will still shade differently is printed as notes and kept as comments in the file.\n"
      "The header comments give the pencil version, this command line and the POV-Ray\n"
      "command that renders the file.\n\n"
      "options:\n"
      "  -o, --output OUT.pov  the file to write (required)\n"
      "  --flat                the export check's file: every object a flat colour that\n"
      "                        encodes its index (code = index + 1, plus 2^23 on a\n"
      "                        checkerboard's odd squares; R + 256 G + 65536 B of an 8-bit\n"
      "                        PNG rendered with File_Gamma=1.0), no lights, no secondary\n"
      "                        rays, black background (code 0)\n"
      "  --size WxH            override the scene's image size (1 <= W, H <= 16384); the file\n"
      "                        holds only its aspect ratio, the header the size to render\n"
      "  --spp N               samples per pixel the file is for (1, 4, 9, ..., 1024): POV-Ray\n"
      "                        renders it at sqrt(N) times the width and height without\n"
      "                        anti-aliasing, and each sqrt(N) x sqrt(N) block averaged is\n"
      "                        one pixel of the exact renderer's N-sample grid (default: the\n"
      "                        scene's, as pencil render; 9 for the built-in scene)\n"
      "Exit codes: 0 written; 1 the file could not be written; 2 usage or scene error, a scene\n"
      "the exporter refuses, or an output path that cannot be written (found before the work).\n");
}

enum { OPT_OUTPUT = 1, OPT_FLAT, OPT_SIZE, OPT_SPP };

static const cli_spec_t specs[] = {{"--output", 'o', 1, OPT_OUTPUT},
                                   {"--flat", 0, 0, OPT_FLAT},
                                   {"--size", 0, 1, OPT_SIZE},
                                   {"--spp", 0, 1, OPT_SPP}};

typedef struct {
  const char *scene, *out; /**< scene file (NULL: built-in Fig. 8) and the .pov to write */
  int flat;                /**< --flat */
  long width, height;      /**< --size, 0: the scene's */
  long spp;                /**< --spp */
} args_t;

/* One argument; 1 ok, 0 usage error (printed). */
static int apply(args_t *a, const cli_arg_t *g) {
  if (!g->spec) {
    if (a->scene)
      return fprintf(stderr, "pencil export pov: unexpected argument '%s' (see --help)\n",
                     g->value),
             0;
    a->scene = g->value;
    return 1;
  }
  switch (g->spec->id) {
  case OPT_OUTPUT:
    a->out = g->value;
    return 1;
  case OPT_FLAT:
    return a->flat = 1;
  case OPT_SIZE:
    return cli_parse_wxh("export pov", "--size", g->value, 16384, &a->width, &a->height);
  default:
    return cli_parse_spp("export pov", "--spp", g->value, &a->spp);
  }
}

static int export_pov(int argc, char **argv) {
  int n, rc;
  cli_arg_t *args = cli_args("export pov", argc, argv, specs, (int)(sizeof specs / sizeof specs[0]),
                             help_pov, &n, &rc);
  if (!args)
    return rc;
  args_t a = {.spp = 0}; /* 0: the scene's */
  int ok = 1;
  for (int k = 0; ok && k < n; k++)
    ok = apply(&a, &args[k]);
  free(args);
  if (ok && !a.out)
    ok = (fprintf(stderr, "pencil export pov: -o OUT.pov is required (see --help)\n"), 0);
  if (!ok)
    return CLI_USAGE;
  char err[1024], notes[2048];
  if (io_output_check(a.out, err, sizeof err) != 0 ||
      (a.scene && io_output_not_input(a.out, a.scene, err, sizeof err) != 0)) {
    fprintf(stderr, "pencil export pov: %s\n", err);
    return CLI_USAGE;
  }
  rt_scene_t s;
  rc = cli_load_scene("export pov", a.scene, a.width, a.height, &s);
  if (rc != CLI_OK) {
    rt_scene_free(&s);
    return rc;
  }
  io_pov_options_t o = IO_POV_OPTIONS_DEFAULT;
  o.flat = a.flat;
  o.spp = a.spp > 0 ? (int)a.spp : s.spp;
  o.source = a.scene ? a.scene : "built-in Fig. 8 scene";
  rc = CLI_OK;
  if (io_pov_check(&s, &o, notes, sizeof notes, err, sizeof err) != 0) {
    fprintf(stderr, "pencil export pov: %s: %s\n", o.source, err);
    rc = CLI_USAGE;
  } else if (io_pov_export(a.out, &s, &o, NULL, 0, err, sizeof err) != 0) {
    fprintf(stderr, "pencil export pov: %s\n", err);
    rc = CLI_FAIL;
  } else {
    for (char *p = strtok(notes, "\n"); p; p = strtok(NULL, "\n"))
      fprintf(stderr, "pencil export pov: note: %s\n", p);
    printf("wrote %s: %s, %d object%s, %dx%d at %d spp\n", a.out,
           a.flat ? "flat (the export check's)" : "shaded", s.nobject, s.nobject == 1 ? "" : "s",
           s.camera.width, s.camera.height, o.spp);
  }
  rt_scene_free(&s);
  return rc;
}

int cmd_export(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help_export(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  if (strcmp(argv[1], "pov") == 0)
    return export_pov(argc - 1, argv + 1);
  fprintf(stderr, "pencil export: unknown format '%s' (available: pov)\n", argv[1]);
  return CLI_USAGE;
}
