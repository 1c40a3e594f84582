/* cmd_render_pencil.c -- `pencil render --method pencil`: the pencil renderer (paper section 4.1
 * (1) ray tracing with a system matrix, (2) ray interpolation) on a scene file or the built-in
 * Fig. 8 scene, writing OpenEXR (the reference renderer's channels plus pencil.error and
 * pencil.method) and a PNG preview; --measure also traces every sample exactly and prints the
 * Fig. 10 error statistics. cmd_render.c hands over here when --method pencil is given. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "io/image_io.h"
#include "pencil/pencil.h"
#include "validation/timing.h"

static void help(FILE *f) {
  fprintf(
      f, "usage: pencil render [SCENE.json] -o OUT.exr --method pencil [--spp N] [--threads N]\n"
         "                     [--size WxH] [--domain N] [--rho R] [--bounds B] [--certified]\n"
         "                     [--no-interp] [--no-memo] [--brightness-tol L] [--measure]\n"
         "                     [--no-aux] [--explain]\n\n"
         "Renders SCENE.json or the built-in Fig. 8 scene by pencil tracing (paper section 4.1):\n"
         "initial domains of N x N pixels, the axial ray of each traced exactly with its ray\n"
         "tree, a system matrix per path, edges found by comparing ray trees, the tolerance of\n"
         "Eq. (3) and the spread limit of Eq. (6) deciding between matrices, exact tracing and\n"
         "subdivision; samples by ray interpolation where e_int allows.\n"
         "Writes OUT.exr (the exact renderer's channels, plus pencil.error: largest Fig. 10 error\n"
         "of the pixel's samples when --measure is given, and pencil.method: 0 exact, 1 matrix,\n"
         "2 interpolated; pencil.rays: exact rays traced for the pixel's samples) and a PNG\n"
         "preview beside it.\n\n"
         "options:\n"
         "  -o, --output OUT.exr  output image\n"
         "  --spp N               samples per pixel on an s x s grid: 1, 4, 9, ..., 256\n"
         "  --threads N           OpenMP threads (default: all cores)\n"
         "  --size WxH            override the scene's image size\n"
         "  --domain N            initial domain size in pixels, 1..32 (default 5, as the paper)\n"
         "  --rho R               tolerance ratio of Eq. (3), > 0 (default 0.5)\n"
         "  --bounds B            C of Eq. (4): corrected (default), printed, or probe (exact\n"
         "                        errors on the spread circle; not a bound)\n"
         "  --certified           also check every path exactly on each domain's boundary\n"
         "  --no-interp           trace every sample with matrices (no ray interpolation)\n"
         "  --no-memo             trace a lattice point again for each lattice cell that shares\n"
         "                        it (slower; the image is the same)\n"
         "  --brightness-tol L    ray interpolation: largest deviation of interpolated from\n"
         "                        traced brightness on a lattice cell, >= 0 (default 1/1024)\n"
         "  --measure             trace every sample exactly too; Fig. 10 error statistics\n"
         "                        (points on surfaces with a diffuse term: Fig. 8's board)\n"
         "  --no-aux              leave the auxiliary channels (Z, id, pathT.*, pathR.*) empty,\n"
         "                        as the benchmarks render\n"
         "  --explain             print the effects plan\n"
         "Exit codes: 0 image written; 1 rendering or writing failed; 2 usage or scene error.\n");
}

typedef struct {
  const char *scene, *out;
  long spp, threads, width, height;
  int explain;
  pt_options_t opt;
} args_t;

static int bad(const char *opt, const char *v, const char *want) {
  fprintf(stderr, "pencil render: %s: expected %s, got '%s'\n", opt, want, v);
  return 0;
}

static int parse_value(args_t *a, const char *name, const char *v) {
  long l;
  if (strcmp(name, "--method") == 0)
    return strcmp(v, "pencil") == 0 || bad(name, v, "pencil");
  if (strcmp(name, "--spp") == 0) {
    return cli_parse_spp("render", name, v, &a->spp);
  }
  if (strcmp(name, "--threads") == 0)
    return cli_parse_long(name, v, 1, 1024, &a->threads);
  if (strcmp(name, "--size") == 0) {
    char tail;
    if (sscanf(v, "%ldx%ld%c", &a->width, &a->height, &tail) != 2 || a->width < 1 ||
        a->height < 1 || a->width > 16384 || a->height > 16384)
      return bad(name, v, "WxH with 1 <= W, H <= 16384");
    return 1;
  }
  if (strcmp(name, "--domain") == 0) {
    if (!cli_parse_long(name, v, 1, 32, &l))
      return 0;
    a->opt.domain = (int)l;
    return 1;
  }
  if (strcmp(name, "--rho") == 0) {
    if (!cli_parse_double(name, v, &a->opt.rho))
      return 0;
    return a->opt.rho > 0.0 || bad(name, v, "a number > 0");
  }
  if (strcmp(name, "--brightness-tol") == 0) {
    if (!cli_parse_double(name, v, &a->opt.brightness_tol))
      return 0;
    return a->opt.brightness_tol >= 0.0 || bad(name, v, "a number >= 0");
  }
  if (strcmp(name, "--bounds") == 0)
    return pt_bound_parse(v, &a->opt.bound) || bad(name, v, "corrected, printed or probe");
  a->out = v; /* -o / --output */
  return 1;
}

/* 1 ok, 0 usage error, -1 help printed. */
static int parse_args(int argc, char **argv, args_t *a) {
  static const char *const valued[] = {"--method", "--spp",    "--threads",
                                       "--size",   "--domain", "--rho",
                                       "--bounds", "--output", "--brightness-tol"};
  for (int i = 1; i < argc; i++) {
    int err = 0, done = 0;
    if (cli_is_help(argv[i])) {
      help(stdout);
      return -1;
    }
    if (strcmp(argv[i], "-o") == 0) {
      if (i + 1 >= argc)
        return fprintf(stderr, "pencil: -o needs a value\n"), 0;
      a->out = argv[++i];
      continue;
    }
    for (size_t k = 0; k < sizeof valued / sizeof valued[0] && !done && !err; k++) {
      const char *v = cli_option(argc, argv, &i, valued[k], &err);
      if (v) {
        if (!parse_value(a, valued[k], v))
          return 0;
        done = 1;
      }
    }
    if (err)
      return 0;
    if (done)
      continue;
    if (strcmp(argv[i], "--certified") == 0)
      a->opt.certified = 1;
    else if (strcmp(argv[i], "--no-interp") == 0)
      a->opt.interp = 0;
    else if (strcmp(argv[i], "--no-memo") == 0)
      a->opt.memo = 0;
    else if (strcmp(argv[i], "--measure") == 0)
      a->opt.measure = 1;
    else if (strcmp(argv[i], "--no-aux") == 0)
      a->opt.aux = 0;
    else if (strcmp(argv[i], "--explain") == 0)
      a->explain = 1;
    else if (argv[i][0] != '-' && !a->scene)
      a->scene = argv[i];
    else
      return fprintf(stderr, "pencil render: unexpected argument '%s' (see --help)\n", argv[i]), 0;
  }
  if (!a->out && !a->explain) {
    fprintf(stderr, "pencil render: -o OUT.exr is required (see --help)\n");
    return 0;
  }
  return 1;
}

static int load(const args_t *a, rt_scene_t *s) {
  return cli_load_scene("render", a->scene, a->width, a->height, s);
}

static int write_outputs(const args_t *a, const rt_image_t *img, const pt_extra_t *x, int spp) {
  char err[1024], png[4096], sppbuf[16], rho[32];
  snprintf(sppbuf, sizeof sppbuf, "%d", spp);
  snprintf(rho, sizeof rho, "%g", a->opt.rho);
  const char *meta[][2] = {{"pencil:scene", a->scene ? a->scene : "built-in fig8"},
                           {"pencil:method", "pencil"},
                           {"pencil:spp", sppbuf},
                           {"pencil:rho", rho},
                           {"pencil:bounds", pt_bound_name(a->opt.bound)},
                           {"pencil:certified", a->opt.certified ? "yes" : "no"}};
  io_exr_channel_t ch[3] = {
      {"pencil.error", x->error}, {"pencil.method", x->method}, {"pencil.rays", x->rays}};
  if (io_exr_write_extra(a->out, img, ch, 3, meta, 6, err, sizeof err) != 0 ||
      (io_png_path_for(a->out, png, sizeof png) && io_png_write(png, img, err, sizeof err) != 0))
    return fprintf(stderr, "pencil render: %s\n", err), 0;
  return 1;
}

static void report(const rt_scene_t *s, int spp, double dt, const pt_stats_t *st, const args_t *a) {
  uint64_t n = st->samples[0] + st->samples[1] + st->samples[2];
  printf(
      "pencil-traced %dx%d at %d spp in %.3f s (rho %g, bounds %s%s): samples %.1f%% matrix, "
      "%.1f%% interpolated, %.1f%% exact; %llu cells (%llu accepted, %llu partly exact, %llu edge, "
      "%llu split), %llu paths exact, %llu guarded (and %llu shadows); %llu exact rays -> %s\n",
      s->camera.width, s->camera.height, spp, dt, a->opt.rho, pt_bound_name(a->opt.bound),
      a->opt.certified ? ", certified" : "", 100.0 * st->samples[1] / n, 100.0 * st->samples[2] / n,
      100.0 * st->samples[0] / n, (unsigned long long)st->cells,
      (unsigned long long)st->cells_accepted, (unsigned long long)st->cells_partial,
      (unsigned long long)st->cells_edge, (unsigned long long)st->cells_split,
      (unsigned long long)st->paths_exact, (unsigned long long)st->paths_guard,
      (unsigned long long)st->lights_guard, (unsigned long long)rt_stats_total(&st->rays), a->out);
  printf("ray interpolation: %llu lattice points (%llu more reused), %llu biquadratic lattice "
         "cells, %llu with faint shadow edges, %llu halves; samples by "
         "matrices: %llu small cell, %llu "
         "left the paths, %llu reach, %llu error; "
         "%llu fallback samples, %llu partial samples, %llu brightness-interpolated samples\n",
         (unsigned long long)st->lattice_points, (unsigned long long)st->lattice_reused,
         (unsigned long long)st->biquad_cells, (unsigned long long)st->faint_cells,
         (unsigned long long)st->halved_cells, (unsigned long long)st->matrix_samples[0],
         (unsigned long long)st->matrix_samples[1], (unsigned long long)st->matrix_samples[2],
         (unsigned long long)st->matrix_samples[3], (unsigned long long)st->fallbacks,
         (unsigned long long)st->partial, (unsigned long long)st->lerp_samples);
  if (a->opt.measure) {
    printf("Fig. 10 error: %llu samples (%llu with measured points), %.4f%% within rho = %g, max "
           "%.4g (transmission path: %.4f%% within, max %.4g; strict: %.4f%% within, max %.4g), "
           "%llu path mismatches\n",
           (unsigned long long)st->measured, (unsigned long long)st->with_points,
           100.0 * st->within / st->measured, a->opt.rho, st->max_error,
           100.0 * st->within_t / st->measured, st->max_error_t,
           100.0 * st->within_strict / st->measured, st->max_error_strict,
           (unsigned long long)st->mismatches);
    if (st->with_points == 0)
      fprintf(stderr, "pencil: warning: no sample had a pencil-traced point on a surface with a "
                      "diffuse term, so the Fig. 10 error compared nothing\n");
  }
}

static int render(args_t *a, rt_scene_t *s) {
  int spp = a->spp > 0 ? (int)a->spp : s->spp, side = (int)lrint(sqrt(spp));
  rt_plan_t plan = rt_plan_make(s, spp);
  if (a->explain) {
    printf("effects plan for %s:\n", a->scene ? a->scene : "the built-in Fig. 8 scene");
    for (int e = 0; e < RT_EFFECT_COUNT; e++)
      printf("  %-14s %s\n", rt_effect_name((rt_effect_t)e), plan.why[e]);
  }
  if (!a->out)
    return CLI_OK;
  rt_image_t img;
  size_t np = (size_t)s->camera.width * (size_t)s->camera.height;
  float *err = malloc(np * sizeof *err), *meth = malloc(np * sizeof *meth);
  float *rays = malloc(np * sizeof *rays);
  if (!err || !meth || !rays || rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK) {
    free(err);
    free(meth);
    free(rays);
    fprintf(stderr, "pencil render: cannot allocate a %dx%d image\n", s->camera.width,
            s->camera.height);
    return CLI_FAIL;
  }
  pt_extra_t x = {err, meth, rays};
  a->opt.spp_side = side;
  a->opt.threads = (int)a->threads;
  a->opt.progress = isatty(2) ? cli_progress : NULL;
  a->opt.progress_ctx = (void *)"pencil tracing";
  pt_stats_t st;
  double t0 = val_wall_seconds();
  rt_status_t rs = pt_render(s, &plan, &a->opt, &img, &x, NULL, &st);
  double dt = val_wall_seconds() - t0;
  int ok = rs == RT_OK && write_outputs(a, &img, &x, spp);
  if (rs != RT_OK)
    fprintf(stderr, "pencil render: %s\n", rt_strerror(rs));
  if (ok)
    report(s, spp, dt, &st, a);
  if (ok && getenv("PT_DUMP")) {
    FILE *f = fopen(getenv("PT_DUMP"), "wb");
    if (f) {
      fwrite(rays, sizeof *rays, np, f);
      fwrite(meth, sizeof *meth, np, f);
      fwrite(err, sizeof *err, np, f);
      fclose(f);
    }
  }
  rt_image_free(&img);
  free(err);
  free(meth);
  free(rays);
  return ok ? CLI_OK : CLI_FAIL;
}

int cmd_render_pencil(int argc, char **argv) {
  args_t a = {.opt = PT_OPTIONS_DEFAULT};
  int p = parse_args(argc, argv, &a);
  if (p <= 0)
    return p < 0 ? CLI_OK : CLI_USAGE;
  rt_scene_t s;
  int rc = load(&a, &s) ? render(&a, &s) : CLI_USAGE;
  rt_scene_free(&s);
  return rc;
}
