/* cmd_render.c -- `pencil render`: the conventional (exact, Whitted) renderer of issue 4 on a
 * scene file or the built-in Fig. 8 scene (paper section 5), writing OpenEXR with auxiliary
 * accuracy channels and a PNG preview. The method switch is where the pencil tracer plugs in. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "io/image_io.h"
#include "render/render.h"
#include "validation/timing.h"

static void help(FILE *f) {
  fprintf(
      f, "usage: pencil render [SCENE.json] -o OUT.exr [--method exact] [--spp N] [--threads N]\n"
         "                     [--size WxH] [--no-aux] [--explain]\n\n"
         "Renders SCENE.json (docs/scene-format.md) or, without it, the built-in Fig. 8 scene\n"
         "(a glass sphere over a checkerboard; scenes/README.md) by exact recursive ray tracing.\n"
         "Writes OUT.exr (float R, G, B and, for each pixel's centre ray, Z, id and the points\n"
         "where its paths meet the checkerboard: pathT.*, pathR.*) and a PNG preview beside it.\n\n"
         "options:\n"
         "  -o, --output OUT.exr  output image (required unless --explain is given alone)\n"
         "  --method M            exact (default) or pencil ('pencil render --method pencil\n"
         "                        --help' lists the pencil tracer's options)\n"
         "  --spp N               samples per pixel on an s x s grid: 1, 4, 9, ..., 256\n"
         "                        (default: the scene's, 9 for the built-in scene)\n"
         "  --threads N           OpenMP threads (default: all cores)\n"
         "  --size WxH            override the scene's image size\n"
         "  --no-aux              leave the auxiliary channels empty (no centre-ray trees), as\n"
         "                        the benchmarks render\n"
         "  --explain             print the effects plan (which effects run and why)\n\n"
         "A progress bar is drawn on stderr when it is a terminal; the closing line gives the\n"
         "time, rays traced and rays per second.\n"
         "Exit codes: 0 image written; 1 rendering or writing failed; 2 usage or scene error.\n");
}

typedef struct {
  const char *scene, *out;
  long spp, threads, width, height;
  int explain, no_aux;
} args_t;

static int parse_size(const char *v, long *w, long *h) {
  char tail;
  if (sscanf(v, "%ldx%ld%c", w, h, &tail) != 2 || *w < 1 || *h < 1 || *w > 16384 || *h > 16384) {
    fprintf(stderr, "pencil render: --size: expected WxH with 1 <= W, H <= 16384, got '%s'\n", v);
    return 0;
  }
  return 1;
}

static int parse_method(const char *v) {
  if (strcmp(v, "exact") == 0)
    return 1;
  fprintf(stderr, "pencil render: --method: expected exact or pencil, got '%s'\n", v);
  return 0;
}

/* 1 ok, 0 usage error, -1 help printed. */
static int parse_args(int argc, char **argv, args_t *a) {
  for (int i = 1; i < argc; i++) {
    int err = 0;
    const char *v;
    if (cli_is_help(argv[i])) {
      help(stdout);
      return -1;
    } else if (strcmp(argv[i], "-o") == 0) {
      if (i + 1 >= argc) {
        fprintf(stderr, "pencil: -o needs a value\n");
        return 0;
      }
      a->out = argv[++i];
    } else if ((v = cli_option(argc, argv, &i, "--output", &err))) {
      a->out = v;
    } else if ((v = cli_option(argc, argv, &i, "--method", &err))) {
      if (!parse_method(v))
        return 0;
    } else if ((v = cli_option(argc, argv, &i, "--spp", &err))) {
      if (!cli_parse_spp("render", "--spp", v, &a->spp))
        return 0;
    } else if ((v = cli_option(argc, argv, &i, "--threads", &err))) {
      if (!cli_parse_long("--threads", v, 1, 1024, &a->threads))
        return 0;
    } else if ((v = cli_option(argc, argv, &i, "--size", &err))) {
      if (!parse_size(v, &a->width, &a->height))
        return 0;
    } else if (strcmp(argv[i], "--explain") == 0) {
      a->explain = 1;
    } else if (strcmp(argv[i], "--no-aux") == 0) {
      a->no_aux = 1;
    } else if (!err && argv[i][0] != '-' && !a->scene) {
      a->scene = argv[i];
    } else {
      if (!err)
        fprintf(stderr, "pencil render: unexpected argument '%s' (see --help)\n", argv[i]);
      return 0;
    }
  }
  if (!a->out && !a->explain) {
    fprintf(stderr, "pencil render: -o OUT.exr is required (see --help)\n");
    return 0;
  }
  return 1;
}

static void explain(FILE *f, const rt_plan_t *p, const char *scene) {
  fprintf(f, "effects plan for %s:\n", scene);
  for (int e = 0; e < RT_EFFECT_COUNT; e++)
    fprintf(f, "  %-14s %s\n", rt_effect_name((rt_effect_t)e), p->why[e]);
  fprintf(f, "  ray depth %d, ray-tree buffer %d node(s) per thread\n", p->max_depth,
          p->tree_nodes);
}

static int load(const args_t *a, rt_scene_t *s) {
  return cli_load_scene("render", a->scene, a->width, a->height, s);
}

static int write_outputs(const args_t *a, const rt_image_t *img, int spp) {
  char err[1024], png[4096], sppbuf[16];
  snprintf(sppbuf, sizeof sppbuf, "%d", spp);
  const char *meta[][2] = {{"pencil:scene", a->scene ? a->scene : "built-in fig8"},
                           {"pencil:method", "exact"},
                           {"pencil:spp", sppbuf}};
  if (io_exr_write(a->out, img, meta, 3, err, sizeof err) != 0 ||
      (io_png_path_for(a->out, png, sizeof png) && io_png_write(png, img, err, sizeof err) != 0)) {
    fprintf(stderr, "pencil render: %s\n", err);
    return 0;
  }
  return 1;
}

static int render(const args_t *a, rt_scene_t *s) {
  int spp = a->spp > 0 ? (int)a->spp : s->spp, side = (int)lrint(sqrt(spp));
  rt_plan_t plan = rt_plan_make(s, spp);
  if (a->explain)
    explain(stdout, &plan, a->scene ? a->scene : "the built-in Fig. 8 scene");
  if (!a->out)
    return CLI_OK;
  rt_image_t img;
  if (rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK) {
    fprintf(stderr, "pencil render: cannot allocate a %dx%d image\n", s->camera.width,
            s->camera.height);
    return CLI_FAIL;
  }
  rt_render_options_t opt = RT_RENDER_OPTIONS_DEFAULT;
  opt.spp_side = side;
  opt.threads = (int)a->threads;
  opt.aux = !a->no_aux;
  opt.progress = isatty(2) ? cli_progress : NULL;
  opt.progress_ctx = (void *)"rendering";
  rt_stats_t st;
  double t0 = val_wall_seconds();
  rt_status_t rs = rt_render(s, &plan, &opt, &img, &st);
  double dt = val_wall_seconds() - t0;
  int ok = rs == RT_OK && write_outputs(a, &img, spp);
  if (rs != RT_OK)
    fprintf(stderr, "pencil render: %s\n", rt_strerror(rs));
  rt_image_free(&img);
  if (!ok)
    return CLI_FAIL;
  uint64_t total = rt_stats_total(&st);
  printf("rendered %dx%d at %d spp in %.3f s: %llu rays (%llu primary, %llu reflected, %llu "
         "refracted, %llu shadow), %.3g rays/s -> %s\n",
         s->camera.width, s->camera.height, spp, dt, (unsigned long long)total,
         (unsigned long long)st.primary, (unsigned long long)st.reflect,
         (unsigned long long)st.refract, (unsigned long long)st.shadow, total / dt, a->out);
  return CLI_OK;
}

int cmd_render(int argc, char **argv) {
  for (int i = 1; i < argc; i++) /* the pencil tracer has its own options (cmd_render_pencil.c) */
    if (strcmp(argv[i], "--method=pencil") == 0 ||
        (strcmp(argv[i], "--method") == 0 && i + 1 < argc && strcmp(argv[i + 1], "pencil") == 0))
      return cmd_render_pencil(argc, argv);
  args_t a = {NULL, NULL, 0, 0, 0, 0, 0, 0};
  int p = parse_args(argc, argv, &a);
  if (p <= 0)
    return p < 0 ? CLI_OK : CLI_USAGE;
  rt_scene_t s;
  if (!load(&a, &s)) {
    rt_scene_free(&s);
    return CLI_USAGE;
  }
  int rc = render(&a, &s);
  rt_scene_free(&s);
  return rc;
}
