/* cmd_post.c -- `pencil post star`: the cross-screen (star) filter of the 1989 paper's section 4
 * (post/star.h) on a rendered HDR image. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "io/image_io.h"
#include "io/output.h"
#include "post/star.h"
#include "renderers/renderer.h"
#include "validation/timing.h"

static void help_post(FILE *f) {
  fprintf(f, "usage: pencil post star IN.exr -o OUT.exr [OPTIONS]\n\n"
             "post-processing filters on rendered HDR images:\n"
             "  star   the cross-screen (star) filter of the 1989 paper, section 4\n"
             "'pencil post star --help' describes it.\n");
}

static void help_star(FILE *f) {
  pp_star_t d = PP_STAR_DEFAULT;
  fprintf(f,
          "usage: pencil post star IN.exr -o OUT.exr [--directions K] [--angle DEG]\n"
          "                        [--ratio B] [--sigma S1,S2] [--weight2 W] [--ior N]\n"
          "                        [--focal MM] [--frame MM] [--exposure E] [--white L]\n"
          "                        [--threads N]\n\n"
          "The cross-screen filter (1989 paper, section 4; docs/star.md): a camera filter of a\n"
          "glass plate with scratches in K directions turns every bright point into a star.\n"
          "The plate's normals are flat on a share 1 - B of it and tilted across each scratch\n"
          "on B, with slopes in two Gaussians of standard deviations S1 and S2 (W of the light\n"
          "in the wider); a lens of focal length d images a normal N at (n - 1) d N (Eq. 16),\n"
          "so the image (channels R, G, B of IN.exr, linear HDR) is convolved with that star\n"
          "(by FFT, linear, energy-preserving: light carried beyond the frame is reported).\n"
          "Star rays run perpendicular to their scratches. Writes OUT.exr (R, G, B filtered,\n"
          "linear), OUT.png through the display curve phi (extended Reinhard: E L scaled so\n"
          "that L = white maps to 1), and OUT.json (parameters, kernel, flux per channel).\n\n"
          "options:\n"
          "  -o, --out OUT.exr  the filtered image (required)\n"
          "  --directions K     scratch directions over 180 degrees, 1..16 (default %d)\n"
          "  --angle DEG        the first scratches' angle to the x axis, counter-clockwise\n"
          "                     (default %g)\n"
          "  --ratio B          scratched share of the plate, [0, 1) (default %g, the paper's)\n"
          "  --sigma S1,S2      the Gaussians' standard deviations of slope, radians, > 0\n"
          "                     (default %g,%g)\n"
          "  --weight2 W        the wider Gaussian's share, [0, 1] (default %g)\n"
          "  --ior N            the plate's index, > 1 (default %g)\n"
          "  --focal MM         focal length, mm, > 0 (default %g)\n"
          "  --frame MM         the image's width on the sensor, mm, > 0 (default %g)\n"
          "  --exposure E       the preview's exposure, > 0 (default 1)\n"
          "  --white L          the preview's white point, > 0 (default 4)\n"
          "  --threads N        FFT threads (default 1)\n"
          "Exit codes: 0 done; 2 usage error or bad input (nothing written).\n",
          d.directions, d.angle_deg, d.ratio, d.sigma1, d.sigma2, d.weight2, d.ior, d.focal_mm,
          d.frame_mm);
}

enum {
  O_OUT = 1,
  O_DIR,
  O_ANGLE,
  O_RATIO,
  O_SIGMA,
  O_W2,
  O_IOR,
  O_FOCAL,
  O_FRAME,
  O_EXP,
  O_WHITE,
  O_THREADS
};

/* Parse "S1,S2" into two positive numbers (the list and number rules of every option:
 * cli_split_list(), rn_parse_double()); 0 after a message. */
static int parse_sigma(const char *text, double *s1, double *s2) {
  char buf[128];
  const char *item[2];
  int n;
  if (!cli_split_list("--sigma", text, buf, sizeof buf, item, 2, &n))
    return 0;
  if (n == 2 && rn_parse_double(item[0], s1) == 1 && rn_parse_double(item[1], s2) == 1 && *s1 > 0 &&
      *s2 > 0)
    return 1;
  fprintf(stderr, "pencil post star: --sigma: expected two numbers > 0 as S1,S2, got '%s'\n", text);
  return 0;
}

/* The R, G, B planes of path (w x h each, malloc'd) after checking them: every value finite and
 * >= 0. 0 after a message naming the file, the channel and a bad pixel. */
static int read_rgb(const char *path, float *rgb[3], int *w, int *h) {
  char err[1024];
  struct stat st;
  if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) {
    fprintf(stderr, "pencil post star: %s: %s\n", path,
            stat(path, &st) != 0 ? "no such file" : "not a regular file");
    return 0;
  }
  if (io_exr_read_channel(path, "R", NULL, w, h, err, sizeof err) != 0) {
    fprintf(stderr, "pencil post star: %s (not a readable OpenEXR file)\n", err);
    return 0;
  }
  static const char *const names[3] = {"R", "G", "B"};
  size_t n = (size_t)*w * (size_t)*h;
  for (int c = 0; c < 3; c++) {
    rgb[c] = malloc(n * sizeof(float));
    if (!rgb[c]) {
      fprintf(stderr, "pencil post star: out of memory for a %d x %d image\n", *w, *h);
      return 0;
    }
    int w2, h2;
    if (io_exr_read_channel(path, names[c], rgb[c], &w2, &h2, err, sizeof err) != 0) {
      fprintf(stderr, "pencil post star: %s\n", err);
      return 0;
    }
    for (size_t k = 0; k < n; k++)
      if (!isfinite(rgb[c][k]) || rgb[c][k] < 0.0f) {
        char got[IO_SHORTEST_MAX];
        fprintf(stderr,
                "pencil post star: %s: channel %s, pixel (%zu, %zu): %s; the filter needs "
                "finite radiance >= 0\n",
                path, names[c], k % (size_t)*w, k / (size_t)*w, io_shortest(rgb[c][k], got));
        return 0;
      }
  }
  return 1;
}

static int post_star(int argc, char **argv) {
  static const cli_spec_t specs[] = {
      {"--out", 'o', 1, O_OUT},    {"--directions", 0, 1, O_DIR}, {"--angle", 0, 1, O_ANGLE},
      {"--ratio", 0, 1, O_RATIO},  {"--sigma", 0, 1, O_SIGMA},    {"--weight2", 0, 1, O_W2},
      {"--ior", 0, 1, O_IOR},      {"--focal", 0, 1, O_FOCAL},    {"--frame", 0, 1, O_FRAME},
      {"--exposure", 0, 1, O_EXP}, {"--white", 0, 1, O_WHITE},    {"--threads", 0, 1, O_THREADS},
  };
  int n, rc;
  cli_arg_t *args = cli_args("post star", argc, argv, specs, (int)(sizeof specs / sizeof *specs),
                             help_star, &n, &rc);
  if (!args)
    return rc;
  pp_star_t p = PP_STAR_DEFAULT;
  const char *in = NULL, *out = NULL;
  double exposure = 1.0, white = 4.0;
  long dirs = p.directions, threads = 1;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    int ok = 1;
    if (!g->spec) {
      if (in) {
        fprintf(stderr, "pencil post star: one input image, got '%s' and '%s'\n", in, g->value);
        ok = 0;
      }
      in = g->value;
    } else {
      switch (g->spec->id) {
      case O_OUT:
        out = g->value;
        break;
      case O_DIR:
        ok = cli_parse_long("--directions", g->value, 1, 16, &dirs);
        break;
      case O_ANGLE:
        ok = cli_parse_double_in("--angle", g->value, -360.0, 360.0, &p.angle_deg);
        break;
      case O_RATIO:
        ok = cli_parse_double_in("--ratio", g->value, 0.0, 0.999999, &p.ratio);
        break;
      case O_SIGMA:
        ok = parse_sigma(g->value, &p.sigma1, &p.sigma2);
        break;
      case O_W2:
        ok = cli_parse_double_in("--weight2", g->value, 0.0, 1.0, &p.weight2);
        break;
      case O_IOR:
        ok = cli_parse_double_in("--ior", g->value, 0.0, 10.0, &p.ior);
        if (ok && !(p.ior > 1.0)) {
          fprintf(stderr, "pencil post star: --ior: the plate's index must be > 1, got %s\n",
                  g->value);
          ok = 0;
        }
        break;
      case O_FOCAL:
        ok = cli_parse_double_in("--focal", g->value, 1e-3, 1e5, &p.focal_mm);
        break;
      case O_FRAME:
        ok = cli_parse_double_in("--frame", g->value, 1e-3, 1e5, &p.frame_mm);
        break;
      case O_EXP:
        ok = cli_parse_double_in("--exposure", g->value, 1e-12, 1e12, &exposure);
        break;
      case O_WHITE:
        ok = cli_parse_double_in("--white", g->value, 1e-12, 1e12, &white);
        break;
      default:
        ok = cli_parse_long("--threads", g->value, 1, 1024, &threads);
      }
    }
    rc = ok ? CLI_OK : CLI_USAGE;
  }
  free(args);
  if (rc != CLI_OK)
    return rc;
  p.directions = (int)dirs;
  if (!in || !out) {
    fprintf(stderr, "pencil post star: %s (see --help)\n",
            !in ? "an input image IN.exr is required" : "-o OUT.exr is required");
    return CLI_USAGE;
  }
  char err[1024], why[512], json_path[4096];
  size_t len = strlen(out);
  if (len < 5 || strcmp(out + len - 4, ".exr") != 0 || len + 2 > sizeof json_path) {
    fprintf(stderr, "pencil post star: -o: '%s' must name an .exr file\n", out);
    return CLI_USAGE;
  }
  memcpy(json_path, out, len - 4);
  strcpy(json_path + len - 4, ".json");
  if (io_render_check(out, err, sizeof err) != 0 || io_output_check(json_path, err, sizeof err) ||
      io_output_not_input(out, in, err, sizeof err) ||
      io_output_not_input(json_path, in, err, sizeof err)) {
    fprintf(stderr, "pencil post star: %s\n", err);
    return CLI_USAGE;
  }
  float *rgb[3] = {NULL, NULL, NULL}, *flt[3] = {NULL, NULL, NULL};
  int w = 0, h = 0, result = CLI_USAGE;
  pp_kernel_t k;
  memset(&k, 0, sizeof k);
  rt_image_t prev;
  memset(&prev, 0, sizeof prev);
  if (!read_rgb(in, rgb, &w, &h))
    goto done;
  if (pp_star_kernel(&p, w, w < h ? w : h, &k, why, sizeof why) != 0) {
    fprintf(stderr, "pencil post star: %s\n", why);
    goto done;
  }
  size_t np = (size_t)w * (size_t)h;
  for (int c = 0; c < 3; c++)
    if (!(flt[c] = malloc(np * sizeof(float)))) {
      fprintf(stderr, "pencil post star: out of memory\n");
      goto done;
    }
  pp_star_flux_t flux[3];
  double t0 = val_wall_seconds();
  if (pp_star_apply(&k, w, h, 3, (const float *const *)rgb, flt, (int)threads, flux, why,
                    sizeof why) != 0) {
    fprintf(stderr, "pencil post star: %s\n", why);
    goto done;
  }
  double seconds = val_wall_seconds() - t0;
  if (rt_image_alloc(&prev, w, h) != RT_OK) {
    fprintf(stderr, "pencil post star: out of memory\n");
    goto done;
  }
  for (int c = 0; c < 3; c++)
    for (size_t q = 0; q < np; q++)
      prev.ch[RT_CH_R + c][q] = pp_tone(flt[c][q], exposure, white);
  io_exr_channel_t ch[3] = {{"R", flt[0]}, {"G", flt[1]}, {"B", flt[2]}};
  char params[512];
  cli_star_describe(&p, params, sizeof params);
  io_attr_t attrs[3] = {{"pencil:filter", "star (1989 section 4, Eq. 16)"},
                        {"pencil:star", params},
                        {"pencil:input", in}};
  static const char *const names[3] = {"R", "G", "B"};
  json_t *fl = json_object();
  for (int c = 0; c < 3; c++)
    json_object_set_new(fl, names[c],
                        json_pack("{s:f, s:f, s:f, s:f}", "in", flux[c].in, "full", flux[c].full,
                                  "frame", flux[c].frame, "clamped", flux[c].clamped));
  json_t *root = json_pack(
      "{s:s, s:s, s:i, s:i, s:{s:i, s:f, s:f, s:i, s:f, s:f, s:f, s:f, s:f}, s:{s:i, s:i, s:f, "
      "s:f}, s:o, s:{s:f, s:f}, s:f}",
      "filter", "star", "input", in, "width", w, "height", h, "parameters", "directions",
      p.directions, "angle_deg", p.angle_deg, "ratio", p.ratio, "gaussians", 2, "sigma1", p.sigma1,
      "sigma2", p.sigma2, "weight2", p.weight2, "ior", p.ior, "focal_mm", p.focal_mm, "kernel",
      "radius", k.radius, "side", k.side, "pixels_per_slope", k.scale, "tail", k.tail, "flux", fl,
      "tone", "exposure", exposure, "white", white, "seconds", seconds);
  json_object_set_new(json_object_get(root, "parameters"), "frame_mm", json_real(p.frame_mm));
  if (io_map_write(out, w, h, ch, 3, &prev, attrs, 3, json_path, root, err, sizeof err) != 0) {
    fprintf(stderr, "pencil post star: %s\n", err);
    json_decref(root);
    goto done;
  }
  json_decref(root);
  fprintf(stderr,
          "star filter: %d x %d, kernel %d x %d (%.4g pixels a unit of slope), %.3f s; flux in "
          "the frame %.6f of the input's (R), the rest carried beyond it -> %s\n",
          w, h, k.side, k.side, k.scale, seconds, flux[0].in > 0 ? flux[0].frame / flux[0].in : 1.0,
          out);
  result = CLI_OK;
done:
  for (int c = 0; c < 3; c++) {
    free(rgb[c]);
    free(flt[c]);
  }
  pp_kernel_free(&k);
  rt_image_free(&prev);
  return result;
}

int cmd_post(int argc, char **argv) {
  if (argc < 2 || cli_is_help(argv[1])) {
    help_post(argc < 2 ? stderr : stdout);
    return argc < 2 ? CLI_USAGE : CLI_OK;
  }
  if (strcmp(argv[1], "star") == 0)
    return post_star(argc - 1, argv + 1);
  fprintf(stderr, "pencil post: unknown filter '%s' (available: star)\n", argv[1]);
  return CLI_USAGE;
}
