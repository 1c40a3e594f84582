/* cmd_illuminance.c -- `pencil illuminance`: the illuminance map of a receiver (light/), as
 * OpenEXR (one float channel E), a PNG preview and a JSON summary. The options, the EXR channel
 * and the JSON keys are a contract (issue 21): scripts read them. */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "io/image_io.h"
#include "io/json.h"
#include "io/output.h"
#include "light/illuminance.h"
#include "renderers/renderer.h"
#include "validation/timing.h"

static void help(FILE *f) {
  fprintf(
      f,
      "usage: pencil illuminance SCENE.json --receiver NAME -o MAP.exr [--grid WxH]\n"
      "                          [--extent U0,U1,V0,V1] [--method grid-pencil|photons|polygons]\n"
      "                          [--rays N] [--light K] [--max-split S] [--linear-tol C]\n"
      "                          [--uniform-tol R] [--area-mesh M] [--area-filter F] [--threads "
      "N]\n\n"
      "The illuminance E that the scene's point, parallel and area lights deliver to the\n"
      "object NAME (a plane or a polygon), directly and through chains of specular\n"
      "reflections and refractions up to the scene's max_depth (weighted by kr, kt,\n"
      "transmittance and Fresnel as in rendering; opaque objects block), in the scene's units:\n"
      "a parallel light of intensity I gives I cos(alpha) on an unobstructed receiver, a point\n"
      "light I cos(alpha) / r^2, an area light (a Lambertian rectangle of intensity I0 along\n"
      "its normal) the sum over its mesh points of their share of I0 cos(theta) cos(alpha) /\n"
      "r^2 (mean of R, G and B). Cell\n"
      "(i, j) of a W x H grid covers [U0 + i dU, U0 + (i+1) dU] x [V0 + j dV, V0 + (j+1) dV] of\n"
      "the receiver's coordinates: a plane's texture coordinates (origin its point, u its u\n"
      "axis, v = normal x u: docs/scene-format.md); a polygon's origin is its first vertex and\n"
      "u runs along its first edge. Writes MAP.exr (one float channel E; image row y is j = y: "
      "the\n"
      "first row holds V0, as the header's pencil:rows says), MAP.png (E / the largest E, grey)\n"
      "and MAP.json (extent, grid, method, lights, rays, flux, wall-clock and CPU time,\n"
      "provenance).\n\n"
      "options:\n"
      "  --receiver NAME   the receiver: the plane or polygon object with that \"name\"\n"
      "                    (required); given again, objects in the same plane join it (the\n"
      "                    first sets the coordinates)\n"
      "  -o, --output MAP.exr\n"
      "  --grid WxH        cells of the map (default 256x256; 1 .. 16384 each)\n"
      "  --extent U0,U1,V0,V1\n"
      "                    the map's rectangle (default: the polygons' bounds; with a plane, a\n"
      "                    square around the projection of the scene's bounded objects, twice\n"
      "                    their larger extent)\n"
      "  --method M        grid-pencil (default): the 1989 paper's grid-pencil tracing, pencils\n"
      "                    between neighbouring rays spread over their triangles on the\n"
      "                    receiver and divided at edges; photons: backward ray tracing, each\n"
      "                    ray's flux counted in the cell it lands in; polygons: pencil tracing\n"
      "                    of polyhedra, beams cut at the edges of the faces they meet, each\n"
      "                    piece on the receiver an illuminance polygon (planar faces only)\n"
      "  --rays N          source rays per grid face of each light, a square grid of\n"
      "                    round(sqrt(N)) a side (default: 129 x 129 for grid-pencil, 128 x 128\n"
      "                    pencils; 1024 x 1024 for photons; not for polygons)\n"
      "  --light K         trace light K only (0-based; default: all)\n"
      "  --max-split S     grid-pencil: divisions of a pencil into four (default 6, at most\n"
      "                    12); polygons: a beam is halved up to 2S times along its path\n"
      "  --linear-tol C    grid-pencil: a pencil landing on the map is divided when an edge's\n"
      "                    midpoint ray lands more than C cells off the midpoint of its corners'\n"
      "                    landings (default 0.05; 0: no test, the 1989 paper's plain method);\n"
      "                    polygons: when a vertex's exact ray lands more than C cells from\n"
      "                    where the system matrix puts it\n"
      "  --uniform-tol R   grid-pencil: ... or when the flux density over a quarter of it (the\n"
      "                    triangles its midpoints make) differs from the whole's by more than\n"
      "                    the share R, or a quarter is turned over (default 0.02; 0: no test);\n"
      "                    polygons: when the light its vertices' errors could send the wrong way\n"
      "                    at a face exceeds the share R, or E is not near linear over it\n"
      "  --area-mesh M     an area light is traced as M x M Lambertian point sources at its\n"
      "                    mesh cells' centres (default 8; 1..256; 1989 section 2.3)\n"
      "  --area-filter F   grid-pencil: spread each mesh point's light over its mesh cell by the\n"
      "                    space-variant filter of the 1989 Eqs. (9)-(12), against the\n"
      "                    \"discrete focuses\" of a coarse mesh, each pencil moved by its centre\n"
      "                    ray's displacement as the source moves over the cell: quadratic, the\n"
      "                    displacement interpolated from 3 x 3 points of the cell; linear, the\n"
      "                    printed Eq. (10), from its corners (drifts light outwards where the\n"
      "                    landing is curved: docs/illuminance.md); none (the default)\n"
      "  --indirect        only light that met another surface first (a caustic map, as the\n"
      "                    renderers make them: their shadow rays give the direct light)\n"
      "  --threads N       OpenMP threads (default: all cores)\n\n"
      "A light's grid covers the directions (or, for a parallel light, the beam) towards the\n"
      "map's rectangle and every object that reflects or transmits (docs/illuminance.md).\n"
      "Exit codes: 0 map written; 1 computing or writing failed; 2 usage or scene error (then\n"
      "nothing is written).\n");
}

enum {
  OPT_OUT = 1,
  OPT_RECEIVER,
  OPT_GRID,
  OPT_EXTENT,
  OPT_METHOD,
  OPT_RAYS,
  OPT_LIGHT,
  OPT_SPLIT,
  OPT_THREADS,
  OPT_AREA_MESH,
  OPT_AREA_FILTER,
  OPT_INDIRECT,
  OPT_LINEAR,
  OPT_UNIFORM
};

typedef struct {
  const char *scene, *out, *method;
  const char *receiver[LT_MAX_RECEIVERS]; /**< the names given, in order */
  int nreceiver;
  long gw, gh, rays, light, split, threads, area_mesh;
  int area_filter, indirect;
  double linear_tol, uniform_tol;
  int have_extent;
  double ext[4];
  const char *tuning; /**< the first of --max-split, --linear-tol, --uniform-tol given, or NULL */
} args_t;

static int parse_extent(const char *v, double ext[4]) {
  char buf[256];
  const char *item[4];
  int n = 0;
  if (!cli_split_list("--extent", v, buf, sizeof buf, item, 4, &n))
    return 0;
  int ok = n == 4;
  for (int k = 0; ok && k < 4; k++) /* the number rule of every option (rn_parse_double) */
    ok = rn_parse_double(item[k], &ext[k]) == 1 && fabs(ext[k]) <= 1e12;
  if (!ok) {
    fprintf(stderr,
            "pencil illuminance: --extent: expected U0,U1,V0,V1 (four numbers within 1e12), got "
            "'%s'\n",
            v);
    return 0;
  }
  if (!(ext[1] > ext[0]) || !(ext[3] > ext[2])) {
    fprintf(stderr,
            "pencil illuminance: --extent: the rectangle has zero area (need U0 < U1 and V0 < "
            "V1), got '%s'\n",
            v);
    return 0;
  }
  return 1;
}

static int parse_grid(const char *v, long *w, long *h) {
  return cli_parse_wxh("illuminance", "--grid", v, LT_MAX_GRID, w, h);
}

static int parse(int argc, char **argv, args_t *a) {
  static const cli_spec_t specs[] = {{"--output", 'o', 1, OPT_OUT},
                                     {"--receiver", 0, CLI_REPEATED, OPT_RECEIVER},
                                     {"--grid", 0, 1, OPT_GRID},
                                     {"--extent", 0, 1, OPT_EXTENT},
                                     {"--method", 0, 1, OPT_METHOD},
                                     {"--rays", 0, 1, OPT_RAYS},
                                     {"--light", 0, 1, OPT_LIGHT},
                                     {"--max-split", 0, 1, OPT_SPLIT},
                                     {"--linear-tol", 0, 1, OPT_LINEAR},
                                     {"--uniform-tol", 0, 1, OPT_UNIFORM},
                                     {"--threads", 0, 1, OPT_THREADS},
                                     {"--area-mesh", 0, 1, OPT_AREA_MESH},
                                     {"--area-filter", 0, 1, OPT_AREA_FILTER},
                                     {"--indirect", 0, 0, OPT_INDIRECT}};
  int n, rc;
  cli_arg_t *args = cli_args("illuminance", argc, argv, specs,
                             (int)(sizeof specs / sizeof specs[0]), help, &n, &rc);
  if (!args)
    return rc;
  for (int k = 0; k < n && rc == CLI_OK; k++) {
    const cli_arg_t *g = &args[k];
    if (!g->spec) {
      if (a->scene) {
        fprintf(stderr, "pencil illuminance: unexpected argument '%s' (one scene only)\n",
                g->value);
        rc = CLI_USAGE;
      }
      a->scene = g->value;
      continue;
    }
    if (!a->tuning &&
        (g->spec->id == OPT_SPLIT || g->spec->id == OPT_LINEAR || g->spec->id == OPT_UNIFORM))
      a->tuning = g->spec->name;
    switch (g->spec->id) {
    case OPT_OUT:
      a->out = g->value;
      break;
    case OPT_RECEIVER:
      if (a->nreceiver == LT_MAX_RECEIVERS) {
        fprintf(stderr, "pencil illuminance: --receiver: at most %d objects\n", LT_MAX_RECEIVERS);
        rc = CLI_USAGE;
      } else {
        a->receiver[a->nreceiver++] = g->value;
      }
      break;
    case OPT_GRID:
      rc = parse_grid(g->value, &a->gw, &a->gh) ? CLI_OK : CLI_USAGE;
      break;
    case OPT_EXTENT:
      a->have_extent = 1;
      rc = parse_extent(g->value, a->ext) ? CLI_OK : CLI_USAGE;
      break;
    case OPT_METHOD:
      a->method = g->value;
      break;
    case OPT_RAYS:
      rc = cli_parse_long("--rays", g->value, 4, (long)LT_MAX_GRID * LT_MAX_GRID, &a->rays)
               ? CLI_OK
               : CLI_USAGE;
      break;
    case OPT_LIGHT:
      rc = cli_parse_long("--light", g->value, 0, 1 << 20, &a->light) ? CLI_OK : CLI_USAGE;
      break;
    case OPT_SPLIT:
      rc = cli_parse_long("--max-split", g->value, 0, 12, &a->split) ? CLI_OK : CLI_USAGE;
      break;
    case OPT_AREA_FILTER:
      a->area_filter = lt_area_filter_parse(g->value);
      if (a->area_filter < 0) {
        fprintf(stderr,
                "pencil illuminance: --area-filter: '%s' is not a filter (quadratic, linear, "
                "none)\n",
                g->value);
        rc = CLI_USAGE;
      }
      break;
    case OPT_INDIRECT:
      a->indirect = 1;
      break;
    case OPT_AREA_MESH:
      rc = cli_parse_long("--area-mesh", g->value, 1, LT_MAX_AREA_MESH, &a->area_mesh) ? CLI_OK
                                                                                       : CLI_USAGE;
      break;
    case OPT_UNIFORM: /* a share */
      rc = cli_parse_double_in("--uniform-tol", g->value, 0, 1e6, &a->uniform_tol) ? CLI_OK
                                                                                   : CLI_USAGE;
      break;
    case OPT_LINEAR: /* cells */
      rc = cli_parse_double_in("--linear-tol", g->value, 0, 1e6, &a->linear_tol) ? CLI_OK
                                                                                 : CLI_USAGE;
      break;
    default:
      rc = cli_parse_long("--threads", g->value, 1, 1024, &a->threads) ? CLI_OK : CLI_USAGE;
    }
  }
  free(args);
  if (rc != CLI_OK)
    return rc;
  const char *missing = !a->scene       ? "a scene file SCENE.json"
                        : !a->nreceiver ? "--receiver NAME"
                        : !a->out       ? "-o MAP.exr"
                                        : NULL;
  if (missing) {
    fprintf(stderr, "pencil illuminance: missing %s (see --help)\n", missing);
    return CLI_USAGE;
  }
  return -1;
}

int cmd_illuminance(int argc, char **argv) {
  args_t a;
  memset(&a, 0, sizeof a);
  const lt_options_t d = LT_OPTIONS_DEFAULT; /* one source of the defaults */
  a.method = "grid-pencil";
  a.gw = a.gh = 256;
  a.light = -1;
  a.split = d.max_split;
  a.area_mesh = d.area_mesh;
  a.linear_tol = d.linear_tol;
  a.uniform_tol = d.uniform_tol;
  int rc = parse(argc, argv, &a);
  if (rc >= 0)
    return rc;
  int method = lt_method_parse(a.method);
  if (method < 0) {
    fprintf(stderr,
            "pencil illuminance: --method: expected grid-pencil, photons or polygons, got '%s'\n",
            a.method);
    return CLI_USAGE;
  }
  if (method == LT_METHOD_PHOTONS && a.tuning) {
    fprintf(stderr,
            "pencil illuminance: %s has no effect with --method photons (only with grid-pencil "
            "and polygons)\n",
            a.tuning);
    return CLI_USAGE;
  }
  if (method == LT_METHOD_POLYGONS && a.rays > 0) {
    fprintf(stderr, "pencil illuminance: --rays: the polygons method traces the rays its beams "
                    "need and takes no --rays\n");
    return CLI_USAGE;
  }
  char err[1024], json_path[4096];
  size_t len = strlen(a.out);
  if (len < 5 || strcmp(a.out + len - 4, ".exr") != 0 || len + 2 > sizeof json_path) {
    fprintf(stderr, "pencil illuminance: -o: expected a file name ending in .exr, got '%s'\n",
            a.out);
    return CLI_USAGE;
  }
  memcpy(json_path, a.out, len - 4);
  strcpy(json_path + len - 4, ".json");
  char png_path[4096];
  if (io_render_check(a.out, err, sizeof err) != 0 || io_output_check(json_path, err, sizeof err) ||
      !io_png_path_for(a.out, png_path, sizeof png_path) ||
      io_output_not_input(a.out, a.scene, err, sizeof err) ||
      io_output_not_input(png_path, a.scene, err, sizeof err) ||
      io_output_not_input(json_path, a.scene, err, sizeof err)) {
    fprintf(stderr, "pencil illuminance: %s\n", err);
    return CLI_USAGE;
  }
  rt_scene_t s;
  rc = cli_load_scene("illuminance", a.scene, 0, 0, &s);
  if (rc != CLI_OK)
    return rc;
  int objs[LT_MAX_RECEIVERS];
  lt_receiver_t rcv;
  rc = CLI_USAGE;
  if (lt_method_check(&s, (lt_method_t)method, err, sizeof err) != RT_OK) {
    fprintf(stderr, "pencil illuminance: --method %s: %s: %s\n", a.method, a.scene, err);
    goto done;
  }
  if (a.area_filter && method != LT_METHOD_GRID_PENCIL) {
    fprintf(stderr, "pencil illuminance: --area-filter: the filter is grid-pencil tracing's "
                    "(--method grid-pencil)\n");
    goto done;
  }
  for (int k = 0; k < a.nreceiver; k++) {
    objs[k] = -1;
    for (int o = 0; o < s.nobject && objs[k] < 0; o++)
      if (strcmp(s.object[o].name, a.receiver[k]) == 0)
        objs[k] = o;
    if (objs[k] < 0) {
      fprintf(stderr, "pencil illuminance: --receiver: %s has no object named '%s'\n", a.scene,
              a.receiver[k]);
      goto done;
    }
  }
  if (lt_receiver_make(&s, objs, a.nreceiver, &rcv, err, sizeof err) != RT_OK) {
    fprintf(stderr, "pencil illuminance: --receiver: %s\n", err);
    goto done;
  }
  if (s.nlight == 0 || a.light >= s.nlight) {
    fprintf(stderr, "pencil illuminance: --light: %s has %d light%s, no light %ld\n", a.scene,
            s.nlight, s.nlight == 1 ? "" : "s", a.light < 0 ? 0 : a.light);
    goto done;
  }
  if (!a.have_extent && !lt_default_extent(&s, &rcv, a.ext)) {
    fprintf(stderr,
            "pencil illuminance: --extent: %s has no bounded object to place a default "
            "map around; give the rectangle\n",
            a.scene);
    goto done;
  }
  long side = a.rays > 0                    ? lrint(sqrt((double)a.rays))
              : method == LT_METHOD_PHOTONS ? 1024
                                            : d.side;
  double cells = (double)a.gw * (double)a.gh;
  size_t need = (size_t)(cells * (24.0 * (rt_thread_count((int)a.threads) + 1) + 4 + 3 * 11 * 4));
  size_t have = io_memory_available();
  if (have && need > have) {
    char n1[32], h1[32];
    io_format_size(need, n1, sizeof n1);
    io_format_size(have, h1, sizeof h1);
    fprintf(stderr, "pencil illuminance: --grid %ldx%ld needs %s, more than the %s available\n",
            a.gw, a.gh, n1, h1);
    goto done;
  }
  lt_map_t m;
  if (lt_map_alloc(&m, (int)a.gw, (int)a.gh, a.ext[0], a.ext[1], a.ext[2], a.ext[3]) != RT_OK) {
    fprintf(stderr, "pencil illuminance: cannot allocate a %ldx%ld map\n", a.gw, a.gh);
    rc = CLI_FAIL;
    goto done;
  }
  lt_options_t o = LT_OPTIONS_DEFAULT;
  o.method = (lt_method_t)method;
  o.light = (int)a.light;
  o.side = (int)(side < 2 ? 2 : side);
  o.max_split = (int)a.split;
  o.area_mesh = (int)a.area_mesh;
  o.area_filter = a.area_filter;
  o.indirect = a.indirect;
  o.linear_tol = a.linear_tol;
  o.uniform_tol = a.uniform_tol;
  o.threads = (int)a.threads;
  if (isatty(2)) {
    o.progress = cli_progress;
    o.progress_ctx = (void *)"illuminance";
  }
  lt_stats_t st;
  double cpu = val_cpu_seconds();
  rt_status_t r = lt_illuminance(&s, &rcv, &o, &m, &st);
  cpu = val_cpu_seconds() - cpu; /* of the process: every thread's */
  if (r != RT_OK) {
    fprintf(stderr, "pencil illuminance: %s\n", rt_strerror(r));
    rc = CLI_FAIL;
    lt_map_free(&m);
    goto done;
  }
  if (st.arrivals == 0) {
    fprintf(stderr,
            "pencil illuminance: no light reaches the receiver '%s' (every path from %s is "
            "blocked or misses it); nothing was written\n",
            a.receiver[0], a.light < 0 ? "every light" : "the light");
    lt_map_free(&m);
    goto done;
  }
  size_t n = (size_t)m.width * (size_t)m.height;
  float *e = malloc(n * sizeof *e);
  rt_image_t prev;
  int ok = e != NULL;
  for (size_t k = 0; ok && k < n; k++) {
    double v = (m.e[3 * k] + m.e[3 * k + 1] + m.e[3 * k + 2]) / 3.0;
    ok = isfinite(v) && fabs(v) < 3e38;
    e[k] = (float)v;
  }
  if (!ok) {
    fprintf(stderr, "pencil illuminance: %s\n",
            e ? "the map holds a value beyond float range; nothing was written" : "out of memory");
    free(e);
    lt_map_free(&m);
    rc = CLI_FAIL;
    goto done;
  }
  ok = io_map_preview(m.width, m.height, e, &prev);
  char ext[160];
  snprintf(ext, sizeof ext, "%.17g,%.17g,%.17g,%.17g", m.u0, m.u1, m.v0, m.v1);
  io_exr_channel_t ch = {"E", e};
  char names[1024] = "";
  for (int k = 0; k < a.nreceiver; k++)
    snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? "," : "",
             a.receiver[k]);
  io_attr_t attrs[] = {
      {"pencil:receiver", names},
      {"pencil:method", lt_method_name(o.method)},
      {"pencil:extent", ext},
      {"pencil:rows", "row y holds cells j = y: the first row is V0, the last V1"}};
  json_t *lights = json_array();
  for (int l = 0; l < s.nlight; l++)
    if (a.light < 0 || l == a.light)
      json_array_append_new(lights, json_integer(l));
  json_t *root = json_pack(
      "{s:s, s:s, s:s, s:[f, f, f, f], s:[i, i], s:s, s:o, s:o, s:i, s:f, s:f, s:{s:I, s:I, s:I, "
      "s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:I}, s:{s:f, s:f, s:f, s:f, s:f}, s:f, s:f, s:s, s:i, "
      "s:s, s:b}",
      "scene", a.scene, "receiver", names, "method", lt_method_name(o.method), "extent", m.u0, m.u1,
      m.v0, m.v1, "grid", m.width, m.height, "rows", "j = 0 is the first EXR row (V0)", "lights",
      lights, "rays_per_side", o.method == LT_METHOD_POLYGONS ? json_null() : json_integer(o.side),
      "max_split", o.max_split, "linear_tol", o.linear_tol, "uniform_tol", o.uniform_tol, "counts",
      "rays", (json_int_t)st.rays, "segments", (json_int_t)st.segments, "arrivals",
      (json_int_t)st.arrivals, "pencils", (json_int_t)st.pencils, "divided", (json_int_t)st.divided,
      "nonlinear", (json_int_t)st.nonlinear, "photons", (json_int_t)st.photons, "lost",
      (json_int_t)st.lost, "filtered", (json_int_t)st.filtered, "unshifted",
      (json_int_t)st.unshifted, "resampled", (json_int_t)st.resampled, "flux", "emitted_by_grid",
      st.flux_emitted, "on_map", st.flux_map, "on_receiver_outside", st.flux_outside, "escaped",
      st.flux_escaped, "absorbed", st.flux_absorbed, "seconds", st.seconds, "cpu_seconds", cpu,
      "units", "E in the scene's units (mean of R, G, B): intensity over length squared",
      "area_mesh", o.area_mesh, "area_filter", lt_area_filter_name((lt_area_filter_t)o.area_filter),
      "indirect", o.indirect);
  if (!ok || !root ||
      io_map_write(a.out, m.width, m.height, &ch, 1, &prev, attrs, 4, json_path, root, err,
                   sizeof err) != 0) {
    fprintf(stderr, "pencil illuminance: %s\n", ok && root ? err : "out of memory");
    rc = CLI_FAIL;
  } else {
    printf("illuminance of '%s' by %s: %dx%d cells over u [%g, %g] v [%g, %g]; %llu rays, %llu "
           "arrivals (%llu pencils, %llu divisions, %llu photons), flux on the map %.6g of %.6g "
           "the grid covers, in %.3f s -> %s\n",
           names, lt_method_name(o.method), m.width, m.height, m.u0, m.u1, m.v0, m.v1,
           (unsigned long long)st.rays, (unsigned long long)st.arrivals,
           (unsigned long long)st.pencils, (unsigned long long)st.divided,
           (unsigned long long)st.photons, st.flux_map, st.flux_emitted, st.seconds, a.out);
    rc = CLI_OK;
  }
  if (ok)
    rt_image_free(&prev);
  json_decref(root);
  free(e);
  lt_map_free(&m);
done:
  rt_scene_free(&s);
  return rc;
}
