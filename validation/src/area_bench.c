/* area_bench.c -- `pencil bench area` (area_bench.h). */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"
#include "io/json.h"
#include "io/output.h"
#include "io/scene_json.h"
#include "light/illuminance.h"
#include "validation/area_bench.h"
#include "validation/timing.h"

#ifndef PENCIL_SOURCE_DIR
#define PENCIL_SOURCE_DIR "."
#endif

#define PROG "pencil bench area"

/* The floor case's light: a rectangle 1.2 x 0.8 facing down at height 2 over (0.2, -0.1), I0 3. */
#define FLOOR_CX 0.2
#define FLOOR_CZ (-0.1)
#define FLOOR_H 2.0
#define FLOOR_W 1.2
#define FLOOR_D 0.8
#define FLOOR_I0 3.0

/* The ball case: a glass ball (radius 1, index 1.5) with its centre 2.5 above the floor under a
 * light 0.4 x 0.3 at height 8 (the light's cells 5.5 from the ball's centre; the paraxial image
 * 2.06 below the centre, so that the floor sees the pattern past its focus). */
#define BALL_LIGHT_H 8.0
#define BALL_H 2.5
#define BALL_W 0.4
#define BALL_D 0.3

typedef struct {
  const char *name;
  rt_scene_t s;
  lt_receiver_t rc;
  double ext[4];
  int grid;        /* cells a side of the map */
  int indirect;    /* only light that met another surface first (the renderers' caustic maps) */
  double size;     /* the light's larger edge */
  double distance; /* from the light to the object it shines through (or the floor) */
} case_t;

static int load_json(const char *name, const char *json, rt_scene_t *s) {
  char err[1024];
  rt_scene_init(s);
  if (io_scene_load_buffer(name, json, strlen(json), s, err, sizeof err) != 0) {
    fprintf(stderr, PROG ": %s\n", err);
    return 0;
  }
  return 1;
}

/* c zeroed, with its name, map extent and grid, and what its light is. */
static void case_init(case_t *c, const char *name, const double ext[4], int grid, int indirect,
                      double size, double distance) {
  memset(c, 0, sizeof *c);
  c->name = name;
  memcpy(c->ext, ext, sizeof c->ext);
  c->grid = grid;
  c->indirect = indirect;
  c->size = size;
  c->distance = distance;
}

static int receiver_of(case_t *c, const char *const *names, int n) {
  int obj[4];
  char why[512];
  for (int k = 0; k < n; k++) {
    obj[k] = -1;
    for (int i = 0; i < c->s.nobject; i++)
      if (strcmp(c->s.object[i].name, names[k]) == 0)
        obj[k] = i;
    if (obj[k] < 0) {
      fprintf(stderr, PROG ": %s: no object named '%s'\n", c->name, names[k]);
      return 0;
    }
  }
  if (lt_receiver_make(&c->s, obj, n, &c->rc, why, sizeof why) != RT_OK) {
    fprintf(stderr, PROG ": %s: %s\n", c->name, why);
    return 0;
  }
  return 1;
}

static int floor_case(case_t *c, int grid) {
  char json[1024];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
           " \"materials\": {\"white\": {\"kd\": 0.8}},"
           " \"lights\": [{\"type\": \"area\", \"center\": [%.17g, %.17g, %.17g], \"edge_u\": "
           "[%.17g, 0, 0], \"edge_v\": [0, 0, %.17g], \"intensity\": %.17g}],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           " \"normal\": [0, 1, 0], \"material\": \"white\"}]}",
           FLOOR_CX, FLOOR_H, FLOOR_CZ, FLOOR_W, FLOOR_D, FLOOR_I0);
  static const char *const names[] = {"floor"};
  static const double ext[4] = {-2, 2, -2, 2};
  case_init(c, "floor", ext, grid, 0, FLOOR_W, FLOOR_H);
  return load_json("floor", json, &c->s) && receiver_of(c, names, 1);
}

/* The ball case with its light's edges scaled by `scale`, the same I0. */
static int ball_case(case_t *c, int grid, double scale) {
  char json[2048];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
           " \"settings\": {\"max_depth\": 4},"
           " \"materials\": {\"white\": {\"kd\": 0.8},"
           "  \"glass\": {\"kd\": 0, \"ka\": 0, \"kr\": 0, \"kt\": 1, \"ior\": 1.5}},"
           " \"lights\": [{\"type\": \"area\", \"center\": [0, %.17g, 0], \"edge_u\": [%.17g, 0, "
           "0], \"edge_v\": [0, 0, %.17g], \"intensity\": 64}],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           "  \"normal\": [0, 1, 0], \"material\": \"white\"},"
           "  {\"type\": \"sphere\", \"name\": \"ball\", \"center\": [0, %.17g, 0], \"radius\": 1,"
           "  \"material\": \"glass\"}]}",
           BALL_LIGHT_H, BALL_W * scale, BALL_D * scale, BALL_H);
  static const char *const names[] = {"floor"};
  static const double ext[4] = {-0.6, 0.6, -0.6, 0.6};
  case_init(c, "ball", ext, grid, 1, BALL_W * scale, BALL_LIGHT_H - BALL_H);
  return load_json("ball", json, &c->s) && receiver_of(c, names, 1);
}

static double cell(const lt_map_t *m, size_t k) {
  return (m->e[3 * k] + m->e[3 * k + 1] + m->e[3 * k + 2]) / 3.0;
}

/* The floor case's exact illuminance at (x, 0, z): the radiance I0 / area times the integral of
 * cos(theta) cos(alpha) / r^2 over the rectangle, by the configuration factor of a parallel
 * rectangle with a corner above the point, G(a, b) = (1/2)[a/sqrt(a^2+h^2) atan(b/sqrt(a^2+h^2))
 * + b/sqrt(b^2+h^2) atan(a/sqrt(b^2+h^2))] for the corner at (a, b), odd in a and b. */
static double rect_g(double a, double b, double h) {
  double ra = sqrt(a * a + h * h), rb = sqrt(b * b + h * h);
  return 0.5 * (a / ra * atan(b / ra) + b / rb * atan(a / rb));
}

static double floor_exact(double x, double z) {
  double x1 = FLOOR_CX - FLOOR_W / 2 - x, x2 = FLOOR_CX + FLOOR_W / 2 - x;
  double z1 = FLOOR_CZ - FLOOR_D / 2 - z, z2 = FLOOR_CZ + FLOOR_D / 2 - z;
  return FLOOR_I0 / (FLOOR_W * FLOOR_D) *
         (rect_g(x2, z2, FLOOR_H) - rect_g(x1, z2, FLOOR_H) - rect_g(x2, z1, FLOOR_H) +
          rect_g(x1, z1, FLOOR_H));
}

/* Cell averages of floor_exact() over m (u = x, v = -z: the plane's texture axes), by 4-point
 * Gauss-Legendre rules over 2 x 2 parts of each cell (error far below 1e-8 here). */
static void floor_exact_map(lt_map_t *m) {
  static const double gx[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                               0.8611363115940526};
  static const double gw[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                               0.3478548451374538};
  double du = (m->u1 - m->u0) / m->width, dv = (m->v1 - m->v0) / m->height;
  for (int j = 0; j < m->height; j++)
    for (int i = 0; i < m->width; i++) {
      double sum = 0.0;
      for (int pa = 0; pa < 2; pa++)
        for (int pb = 0; pb < 2; pb++)
          for (int a = 0; a < 4; a++)
            for (int b = 0; b < 4; b++) {
              double u = m->u0 + (i + 0.25 + 0.5 * pa + 0.25 * gx[a]) * du;
              double v = m->v0 + (j + 0.25 + 0.5 * pb + 0.25 * gx[b]) * dv;
              sum += gw[a] * gw[b] * floor_exact(u, -v);
            }
      double e = sum / 16.0; /* weights sum to 2 per axis, over 2 x 2 parts */
      double *c = m->e + 3 * ((size_t)j * m->width + i);
      c[0] = c[1] = c[2] = e;
    }
}

/* A map against a reference: RMS and 99th percentile of the difference over the reference's mean,
 * the largest over its peak, and the relative difference of the flux on the map. */
typedef struct {
  double rms, p99, max, flux;
} diff_t;

static diff_t compare(const lt_map_t *a, const lt_map_t *ref) {
  size_t n = (size_t)a->width * a->height;
  double mean = 0.0, peak = 0.0, sq = 0.0, fa = 0.0, mx = 0.0;
  double *d = malloc(n * sizeof *d);
  for (size_t k = 0; k < n; k++) {
    double x = cell(a, k), y = cell(ref, k);
    mean += y / (double)n;
    peak = fmax(peak, y);
    fa += x / (double)n;
    sq += (x - y) * (x - y);
    mx = fmax(mx, fabs(x - y));
    if (d)
      d[k] = fabs(x - y);
  }
  diff_t r = {sqrt(sq / (double)n) / mean, NAN, mx / peak, fa / mean - 1.0};
  if (d) {
    val_sort(d, n);
    r.p99 = val_quantile(d, n, 0.99) / mean;
    free(d);
  }
  return r;
}

/* Write map m as DIR/CASE-VARIANT.exr (channel E), its grey PNG and a JSON summary; 1 when dir is
 * NULL or all were written, 0 after a message on stderr. */
static int save(const char *dir, const char *name, const char *variant, const lt_map_t *m,
                const char *what) {
  if (!dir)
    return 1;
  char exr[4096], js[4096], err[1024], ext[160];
  snprintf(exr, sizeof exr, "%s/%s-%s.exr", dir, name, variant);
  snprintf(js, sizeof js, "%s/%s-%s.json", dir, name, variant);
  size_t n = (size_t)m->width * m->height;
  float *e = malloc(n * sizeof *e);
  rt_image_t prev;
  if (!e) {
    fprintf(stderr, PROG ": out of memory\n");
    return 0;
  }
  for (size_t k = 0; k < n; k++)
    e[k] = (float)cell(m, k);
  int have_prev = io_map_preview(m->width, m->height, e, &prev), ok = have_prev;
  snprintf(err, sizeof err, "out of memory");
  snprintf(ext, sizeof ext, "%.17g,%.17g,%.17g,%.17g", m->u0, m->u1, m->v0, m->v1);
  io_exr_channel_t ch = {"E", e};
  io_attr_t attrs[] = {{"pencil:variant", variant}, {"pencil:extent", ext}};
  json_t *root =
      json_pack("{s:s, s:s, s:s, s:[f, f, f, f], s:[i, i]}", "case", name, "variant", variant,
                "map", what, "extent", m->u0, m->u1, m->v0, m->v1, "grid", m->width, m->height);
  ok = ok && io_map_write(exr, m->width, m->height, &ch, 1, &prev, attrs, 2, js, root, err,
                          sizeof err) == 0;
  if (!ok)
    fprintf(stderr, PROG ": %s\n", err);
  if (have_prev)
    rt_image_free(&prev);
  json_decref(root);
  free(e);
  return ok;
}

/* Case c's map as mesh x mesh points (filtered or not) at `side` rays a side (0: the default)
 * and at most `split` divisions (-1: the default), the median time of `runs` runs. */
static int make(const case_t *c, int mesh, int filter, int side, int split, int threads, int runs,
                lt_map_t *m, lt_stats_t *st, double *seconds) {
  if (lt_map_alloc(m, c->grid, c->grid, c->ext[0], c->ext[1], c->ext[2], c->ext[3]) != RT_OK) {
    fprintf(stderr, PROG ": out of memory\n");
    return 0;
  }
  lt_options_t o = LT_OPTIONS_DEFAULT;
  if (side > 0)
    o.side = side;
  if (split >= 0)
    o.max_split = split;
  o.indirect = c->indirect;
  o.area_mesh = mesh;
  o.area_filter = filter;
  o.threads = threads;
  double t[16];
  for (int r = 0; r < runs; r++) {
    if (lt_illuminance(&c->s, &c->rc, &o, m, st) != RT_OK) {
      fprintf(stderr, PROG ": %s: the map of %d x %d points failed\n", c->name, mesh, mesh);
      lt_map_free(m);
      return 0;
    }
    t[r] = st->seconds;
  }
  *seconds = val_median(t, runs);
  return 1;
}

typedef struct {
  const char *name;
  int mesh, filter; /* filter: an lt_area_filter_t */
  uint64_t rays, filtered, resampled;
  double seconds;
  diff_t d;
} row_t;

/* The filters compared, in the order of the rows: none (the plain sum), this project's quadratic
 * displacement, the printed linear one (Eq. 10). */
static const int filters[3] = {LT_AREA_FILTER_NONE, LT_AREA_FILTER_QUADRATIC,
                               LT_AREA_FILTER_LINEAR};

static json_t *row_json(const row_t *r) {
  return json_pack("{s:s, s:i, s:s, s:I, s:f, s:f, s:f, s:f, s:f, s:I, s:I}", "case", r->name,
                   "mesh", r->mesh, "filter", lt_area_filter_name((lt_area_filter_t)r->filter),
                   "rays", (json_int_t)r->rays, "seconds", r->seconds, "rms", r->d.rms, "p99",
                   r->d.p99, "max", r->d.max, "flux_relative_error", r->d.flux, "filtered",
                   (json_int_t)r->filtered, "resampled", (json_int_t)r->resampled);
}

static void print_row(FILE *f, const row_t *r) {
  if (f)
    fprintf(f, "%-7s %5d %-10s %12llu %9.3f %10.3e %10.3e %10.3e %+10.2e %9llu %9llu\n", r->name,
            r->mesh, lt_area_filter_name((lt_area_filter_t)r->filter), (unsigned long long)r->rays,
            r->seconds, r->d.rms, r->d.p99, r->d.max, r->d.flux, (unsigned long long)r->filtered,
            (unsigned long long)r->resampled);
}

/* Rays a side and divisions of the brute-force references: each point's map coarse, its errors
 * averaged over thousands of points (the journal of 2026-12-02 measures the choice). */
#define REF_SIDE 65
#define REF_SPLIT 2

/* The brute-force reference of case c: the plain sum of mesh x mesh point sources. */
static int reference(const case_t *c, int mesh, int side, int threads, lt_map_t *m,
                     lt_stats_t *st) {
  double sec;
  return make(c, mesh, 0, side, REF_SPLIT, threads, 1, m, st, &sec);
}

/* One case: the reference (exact for the floor, else the brute-force sum), its own error, and the
 * mesh sizes plain (meshes[0 .. nmesh-1]) and filtered (the first nfilt of them). Rows go to the
 * JSON and to csv (may be NULL). */
static json_t *run_case(case_t *c, const val_area_bench_opts_t *o, int ref_mesh, int ref_side,
                        const int *meshes, int nmesh, int nfilt, FILE *csv) {
  FILE *f = o->report;
  lt_map_t ref, brute, half;
  lt_stats_t st_b, st_h;
  int exact = strcmp(c->name, "floor") == 0;
  int half_mesh = ref_mesh / 2;
  if (!reference(c, ref_mesh, ref_side, o->threads, &brute, &st_b))
    return NULL;
  if (!reference(c, half_mesh, ref_side, o->threads, &half, &st_h)) {
    lt_map_free(&brute);
    return NULL;
  }
  if (exact) {
    if (lt_map_alloc(&ref, c->grid, c->grid, c->ext[0], c->ext[1], c->ext[2], c->ext[3]) != RT_OK) {
      fprintf(stderr, PROG ": out of memory\n");
      lt_map_free(&brute);
      lt_map_free(&half);
      return NULL;
    }
    floor_exact_map(&ref);
  } else {
    ref = brute;
  }
  /* the mesh's error is second order: the half mesh's is about 4 times the reference's, and
   * their difference about 3 times */
  diff_t own = compare(&half, &brute), bx = {NAN, NAN, NAN, NAN};
  own.rms /= 3.0;
  if (exact)
    bx = compare(&brute, &ref);
  int ok = save(o->out, c->name, "reference", &brute, "brute-force sum of point sources") &&
           (!exact || save(o->out, c->name, "exact", &ref, "exact"));
  if (f) {
    fprintf(f,
            "\n%s: %d x %d cells; reference: %d x %d point sources (%d rays a side, %llu rays, "
            "%.1f s); its own RMS error about %.2e (from %d x %d points)\n",
            c->name, c->grid, c->grid, ref_mesh, ref_mesh, ref_side, (unsigned long long)st_b.rays,
            st_b.seconds, own.rms, half_mesh, half_mesh);
    if (exact)
      fprintf(f,
              "  compared with the exact rectangle instead: the brute-force sum is off by RMS "
              "%.2e, max %.2e\n",
              bx.rms, bx.max);
    fprintf(f, "%-7s %5s %-10s %12s %9s %10s %10s %10s %10s %9s %9s\n", "case", "mesh", "filter",
            "rays", "seconds", "rms", "p99", "max", "flux", "filtered", "resampled");
  }
  json_t *rows = json_array();
  for (int k = 0; k < nmesh && ok; k++)
    for (int fi = 0; fi < (k < nfilt ? 3 : 1) && ok; fi++) {
      lt_map_t m;
      lt_stats_t st;
      row_t r;
      memset(&r, 0, sizeof r);
      r.name = c->name;
      r.mesh = meshes[k];
      r.filter = filters[fi];
      ok = make(c, meshes[k], r.filter, o->quick ? 65 : 0, -1, o->threads, o->runs, &m, &st,
                &r.seconds);
      if (!ok)
        break;
      r.rays = st.rays;
      r.filtered = st.filtered;
      r.resampled = st.resampled;
      r.d = compare(&m, &ref);
      char variant[64];
      snprintf(variant, sizeof variant, "m%d-%s", meshes[k],
               lt_area_filter_name((lt_area_filter_t)r.filter));
      ok = save(o->out, c->name, variant, &m, variant);
      lt_map_free(&m);
      print_row(f, &r);
      json_array_append_new(rows, row_json(&r));
      if (csv)
        fprintf(csv, "%s,%d,%s,%llu,%.6g,%.6g,%.6g,%.6g,%.6g,%llu,%llu\n", r.name, r.mesh,
                lt_area_filter_name((lt_area_filter_t)r.filter), (unsigned long long)r.rays,
                r.seconds, r.d.rms, r.d.p99, r.d.max, r.d.flux, (unsigned long long)r.filtered,
                (unsigned long long)r.resampled);
    }
  json_t *j = NULL;
  if (ok)
    j = json_pack("{s:s, s:i, s:{s:i, s:i, s:I, s:f, s:f, s:i, s:o, s:o}, s:o}", "case", c->name,
                  "grid", c->grid, "reference", "mesh", ref_mesh, "rays_per_side", ref_side, "rays",
                  (json_int_t)st_b.rays, "seconds", st_b.seconds, "own_rms", own.rms, "half_mesh",
                  half_mesh, "exact_rms", io_json_number(bx.rms), "exact_max",
                  io_json_number(bx.max), "rows", rows);
  else
    json_decref(rows);
  if (exact)
    lt_map_free(&ref);
  lt_map_free(&brute);
  lt_map_free(&half);
  return j;
}

/* The ball with its light scaled: plain and filtered (both forms) at one mesh against a
 * brute-force sum, as the light's cells grow past the small-source assumption of Eq. (9). */
static json_t *size_sweep(const val_area_bench_opts_t *o, int grid, int mesh, int ref_mesh,
                          int ref_side, FILE *csv) {
  static const double full[] = {0.25, 0.5, 1.0, 2.0}, quick[] = {0.5, 2.0};
  const double *scale = o->quick ? quick : full;
  int n = o->quick ? 2 : 4;
  FILE *f = o->report;
  if (f)
    fprintf(f,
            "\nball, the light scaled (%d x %d points against %d x %d): where Eq. (9)'s small "
            "source stops holding\n%6s %11s %10s %10s %10s %9s %9s %9s\n",
            mesh, mesh, ref_mesh, ref_mesh, "scale", "cell (rad)", "plain", "quadratic", "linear",
            "plain s", "quad. s", "linear s");
  json_t *rows = json_array();
  for (int k = 0; k < n; k++) {
    case_t c;
    if (!ball_case(&c, grid, scale[k])) {
      json_decref(rows);
      return NULL;
    }
    lt_map_t ref, m;
    lt_stats_t st;
    double t[3];
    diff_t d[3];
    int ok = reference(&c, ref_mesh, ref_side, o->threads, &ref, &st);
    for (int fi = 0; fi < 3 && ok; fi++) {
      ok = make(&c, mesh, filters[fi], o->quick ? 65 : 0, -1, o->threads, o->runs, &m, &st, &t[fi]);
      if (ok) {
        d[fi] = compare(&m, &ref);
        lt_map_free(&m);
      }
    }
    if (ok)
      lt_map_free(&ref);
    rt_scene_free(&c.s);
    if (!ok) {
      json_decref(rows);
      return NULL;
    }
    double angle = c.size / mesh / c.distance; /* a mesh cell seen from the ball's centre */
    if (f)
      fprintf(f, "%6.2f %11.3e %10.3e %10.3e %10.3e %9.3f %9.3f %9.3f\n", scale[k], angle, d[0].rms,
              d[1].rms, d[2].rms, t[0], t[1], t[2]);
    json_t *row = json_pack("{s:f, s:f, s:i}", "scale", scale[k], "cell_rad", angle, "mesh", mesh);
    for (int fi = 0; fi < 3; fi++) {
      const char *name = fi ? lt_area_filter_name((lt_area_filter_t)filters[fi]) : "plain";
      json_object_set_new(
          row, name,
          json_pack("{s:f, s:f, s:f}", "rms", d[fi].rms, "max", d[fi].max, "seconds", t[fi]));
      if (csv)
        fprintf(csv, "%.6g,%.6g,%d,%s,%.6g,%.6g,%.6g\n", scale[k], angle, mesh,
                lt_area_filter_name((lt_area_filter_t)filters[fi]), d[fi].rms, d[fi].max, t[fi]);
    }
    json_array_append_new(rows, row);
  }
  return rows;
}

static FILE *csv_open(const char *dir, const char *name, const char *header, io_atomic_t *at) {
  if (!dir)
    return NULL;
  char path[4096], err[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (io_csv_open(at, path, err, sizeof err) != 0) {
    fprintf(stderr, PROG ": %s\n", err);
    return NULL;
  }
  fputs(header, at->f);
  return at->f;
}

int val_bench_area(const val_area_bench_opts_t *o) {
  int quick = o->quick, grid = quick ? 32 : 64;
  int ref_mesh = o->ref_mesh > 0 ? o->ref_mesh : quick ? 16 : 64;
  int ref_side = quick ? 17 : REF_SIDE;
  static const int meshes[] = {1, 2, 4, 8};
  int nmesh = quick ? 2 : 4, nfilt = quick ? 2 : 3; /* the filters cost more: up to M = 4 */
  io_atomic_t ac, as;
  FILE *curve = csv_open(o->out, "area-curve.csv",
                         "case,mesh,filter,rays,seconds,rms,p99,max,flux_rel_err,filtered,"
                         "resampled\n",
                         &ac);
  if (o->out && !curve)
    return VAL_EOUTPUT;
  FILE *sizes =
      csv_open(o->out, "area-size.csv", "scale,cell_rad,mesh,filter,rms,max,seconds\n", &as);
  if (o->out && !sizes) {
    io_atomic_abort(&ac);
    return VAL_EOUTPUT;
  }
  if (o->report)
    fprintf(o->report,
            "pencil bench area: area lights as meshes of point sources, plain and filtered (1989 "
            "Eqs. 9-12; the displacement quadratic, or linear as Eq. 10 prints it), against the "
            "brute-force sum\n(rms and p99 over the reference's mean, "
            "max over its peak; flux: the map's relative to the reference's)\n");
  json_t *cases = json_array();
  int ok = 1;
  for (int k = 0; k < 2 && ok; k++) {
    case_t c;
    ok = k == 0 ? floor_case(&c, grid) : ball_case(&c, grid, 1.0);
    if (!ok)
      break;
    json_t *j = run_case(&c, o, ref_mesh, ref_side, meshes, nmesh, nfilt, curve);
    rt_scene_free(&c.s);
    ok = j != NULL;
    if (ok)
      json_array_append_new(cases, j);
  }
  json_t *sweep = NULL;
  if (ok) {
    sweep = size_sweep(o, grid, quick ? 1 : 2, quick ? 8 : 24, ref_side, sizes);
    ok = sweep != NULL;
  }
  char err[1024];
  io_atomic_t *files[2] = {curve ? &ac : NULL, sizes ? &as : NULL};
  for (int k = 0; k < 2; k++) {
    if (!files[k])
      continue;
    if (!ok) {
      io_atomic_abort(files[k]);
    } else if (io_atomic_commit(files[k], err, sizeof err) != 0) {
      fprintf(stderr, PROG ": %s\n", err);
      ok = 0;
    }
  }
  if (ok && o->json) {
    json_t *root =
        json_pack("{s:O, s:O, s:i, s:i, s:b}", "cases", cases, "size_sweep", sweep,
                  "reference_mesh", ref_mesh, "reference_rays_per_side", ref_side, "quick", quick);
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, PROG ": %s\n", err);
      ok = 0;
    }
    json_decref(root);
  }
  json_decref(cases);
  json_decref(sweep);
  return ok ? 0 : VAL_EFAIL;
}
