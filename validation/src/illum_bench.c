/* illum_bench.c -- `pencil bench illuminance` (illum_bench.h). */
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"
#include "io/json.h"
#include "io/output.h"
#include "io/scene_json.h"
#include "validation/illum_bench.h"
#include "validation/timing.h"

#ifndef PENCIL_SOURCE_DIR
#define PENCIL_SOURCE_DIR "."
#endif

/* The ball scenes of val_ring_map(): ball radius 1, index 1.5, centre 2.5 above the floor (the
 * parallel beam's paraxial focus 1.5 below the centre, so that the floor sees the beam past its
 * focus, with the caustic of spherical aberration), light from above. */
#define BALL_R 1.0
#define BALL_N 1.5
#define BALL_H 2.5
#define POINT_H 8.0

static int ball_scene(int point, rt_scene_t *s) {
  char json[2048], err[512];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
           " \"settings\": {\"max_depth\": 8},"
           " \"materials\": {\"white\": {\"kd\": 0.8},"
           "  \"glass\": {\"ka\": 0, \"kd\": 0, \"kr\": 0, \"kt\": 1, \"ior\": %.17g}},"
           " \"lights\": [%s],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           "  \"normal\": [0, 1, 0], \"material\": \"white\"},"
           "  {\"type\": \"sphere\", \"name\": \"ball\", \"center\": [0, %.17g, 0], \"radius\": "
           "%.17g, \"material\": \"glass\"}]}",
           BALL_N,
           point ? "{\"type\": \"point\", \"position\": [0, 8, 0], \"intensity\": 1}"
                 : "{\"type\": \"parallel\", \"direction\": [0, -1, 0], \"intensity\": 1}",
           BALL_H, BALL_R);
  rt_scene_init(s);
  if (io_scene_load_buffer(point ? "ball-point" : "ball-parallel", json, strlen(json), s, err,
                           sizeof err) != 0) {
    fprintf(stderr, "pencil bench illuminance: %s\n", err);
    return 0;
  }
  return 1;
}

static double cell(const lt_map_t *m, size_t k) {
  return (m->e[3 * k] + m->e[3 * k + 1] + m->e[3 * k + 2]) / 3.0;
}

/* A map against a reference: the largest relative error over the cells marked (all when mask is
 * NULL), the RMS error over the cells relative to the reference's mean, and the total flux. */
typedef struct {
  double worst, rms, flux, ref_flux;
  size_t compared;
  double worst_u, worst_v, worst_value, worst_ref; /**< where the worst cell is, its values */
} cmp_t;

static cmp_t compare(const lt_map_t *a, const lt_map_t *ref, const unsigned char *mask) {
  cmp_t c = {0, 0, 0, 0, 0, NAN, NAN, NAN, NAN};
  size_t n = (size_t)a->width * a->height;
  double da = (a->u1 - a->u0) / a->width * (a->v1 - a->v0) / a->height, mean = 0.0, sq = 0.0;
  for (size_t k = 0; k < n; k++)
    mean += cell(ref, k) / (double)n;
  for (size_t k = 0; k < n; k++) {
    double x = cell(a, k), y = cell(ref, k);
    c.flux += x * da;
    c.ref_flux += y * da;
    sq += (x - y) * (x - y);
    if (mask && !mask[k])
      continue;
    c.compared++;
    if (y > 0 && fabs(x - y) / y > c.worst) {
      c.worst = fabs(x - y) / y;
      c.worst_u = a->u0 + ((double)(k % (size_t)a->width) + 0.5) * (a->u1 - a->u0) / a->width;
      c.worst_v = a->v0 + ((double)(k / (size_t)a->width) + 0.5) * (a->v1 - a->v0) / a->height;
      c.worst_value = x;
      c.worst_ref = y;
    }
  }
  c.rms = sqrt(sq / (double)n) / mean;
  return c;
}

typedef struct {
  const char *name, *method;
  const char *file; /**< the case's file name stem ("ball-parallel") */
  int side;
  uint64_t rays;
  double seconds, worst_smooth, rms, flux_rel;
  size_t smooth, cells;
  double worst_u, worst_v, worst_value, worst_ref;
} row_t;

static json_t *row_json(const row_t *r) {
  return json_pack("{s:s, s:s, s:i, s:I, s:f, s:o, s:f, s:f, s:I, s:I}", "case", r->name, "method",
                   r->method, "rays_per_side", r->side, "rays", (json_int_t)r->rays, "seconds",
                   r->seconds, "worst_relative_error_smooth", io_json_number(r->worst_smooth),
                   "rms_error", r->rms, "flux_relative_error", r->flux_rel, "smooth_cells",
                   (json_int_t)r->smooth, "cells", (json_int_t)r->cells);
}

/* Write map m as DIR/NAME.exr (channel E), .png and .json (extent, grid, method); 0 after a
 * message on stderr. */
static int save_map(const char *dir, const char *name, const char *method, const lt_map_t *m) {
  if (!dir)
    return 1;
  char exr[4096], json[4096], err[1024], ext[160];
  snprintf(exr, sizeof exr, "%s/%s-%s.exr", dir, name, method);
  snprintf(json, sizeof json, "%s/%s-%s.json", dir, name, method);
  size_t n = (size_t)m->width * m->height;
  float *e = malloc(n * sizeof *e);
  if (!e)
    return 0;
  for (size_t k = 0; k < n; k++)
    e[k] = (float)cell(m, k);
  snprintf(ext, sizeof ext, "%.17g,%.17g,%.17g,%.17g", m->u0, m->u1, m->v0, m->v1);
  io_exr_channel_t ch = {"E", e};
  io_attr_t attrs[] = {{"pencil:method", method}, {"pencil:extent", ext}};
  json_t *root = json_pack("{s:s, s:s, s:[f, f, f, f], s:[i, i]}", "case", name, "method", method,
                           "extent", m->u0, m->u1, m->v0, m->v1, "grid", m->width, m->height);
  int ok = io_map_write(exr, m->width, m->height, &ch, 1, NULL, attrs, 2, json, root, err,
                        sizeof err) == 0;
  if (!ok)
    fprintf(stderr, "pencil bench illuminance: %s\n", err);
  json_decref(root);
  free(e);
  return ok;
}

/* One map of scene s by method at `side`; the comparison with ref. */
static int run(const rt_scene_t *s, const lt_receiver_t *rc, lt_method_t method, int side,
               const val_illum_bench_opts_t *bo, const lt_map_t *ref, const unsigned char *mask,
               row_t *row, lt_map_t *keep) {
  lt_map_t m;
  if (lt_map_alloc(&m, ref->width, ref->height, ref->u0, ref->u1, ref->v0, ref->v1) != RT_OK)
    return 0;
  lt_options_t o = LT_OPTIONS_DEFAULT;
  o.method = method;
  o.side = side;
  o.threads = bo->threads;
  o.max_split = bo->max_split;
  o.linear_tol = bo->linear_tol;
  o.uniform_tol = bo->uniform_tol;
  lt_stats_t st;
  if (lt_illuminance(s, rc, &o, &m, &st) != RT_OK) {
    lt_map_free(&m);
    return 0;
  }
  cmp_t c = compare(&m, ref, mask);
  row->method = lt_method_name(method);
  row->side = side;
  row->rays = st.rays;
  row->seconds = st.seconds;
  row->worst_smooth = mask ? c.worst : NAN;
  row->worst_u = c.worst_u;
  row->worst_v = c.worst_v;
  row->worst_value = c.worst_value;
  row->worst_ref = c.worst_ref;
  row->rms = c.rms;
  row->flux_rel = fabs(c.flux - c.ref_flux) / c.ref_flux;
  row->smooth = c.compared;
  row->cells = (size_t)m.width * m.height;
  int saved = save_map(bo->maps, row->file, row->method, &m);
  if (keep)
    *keep = m;
  else
    lt_map_free(&m);
  return saved;
}

static void print_row(FILE *f, const row_t *r) {
  fprintf(f,
          "%-14s %-12s %6d %10llu %9.3f  %10.3e %8zu/%-8zu %10.3e %10.3e  at (%.3f, %.3f): %.4g "
          "vs %.4g\n",
          r->name, r->method, r->side, (unsigned long long)r->rays, r->seconds, r->worst_smooth,
          r->smooth, r->cells, r->rms, r->flux_rel, r->worst_u, r->worst_v, r->worst_value,
          r->worst_ref);
}

/* The RMS difference of a map from the reference over the cells whose reference is below half
 * the mean (the dim areas, where photon counting shows its moire), relative to their mean. */
static double dim_rms(const lt_map_t *a, const lt_map_t *ref) {
  size_t n = (size_t)a->width * a->height, nd = 0;
  double mean = 0.0, sq = 0.0, dmean = 0.0;
  for (size_t k = 0; k < n; k++)
    mean += cell(ref, k) / (double)n;
  for (size_t k = 0; k < n; k++) {
    double y = cell(ref, k);
    if (y > 0 && y < 0.5 * mean) {
      double d = cell(a, k) - y;
      sq += d * d;
      dmean += y;
      nd++;
    }
  }
  return nd ? sqrt(sq / (double)nd) / (dmean / (double)nd) : NAN;
}

/* One point of Fig. 11's cost-of-accuracy curve: a method's map at a grid (rays a side; 0 for
 * polygons), its rays, time and errors against the reference. */
typedef struct {
  const char *method;
  int side;
  uint64_t rays;
  double seconds, rms, dim_rms;
} curve_row_t;

#define CURVE_MAX 16

/* The curve as JSON rows, and as DIR/fig11-curve.csv when dir is not NULL (0 on a write error,
 * message on stderr). */
static json_t *curve_out(const curve_row_t *r, int n, const char *dir, int *ok) {
  json_t *a = json_array();
  for (int k = 0; k < n; k++)
    json_array_append_new(a, json_pack("{s:s, s:i, s:I, s:f, s:f, s:o}", "method", r[k].method,
                                       "rays_per_side", r[k].side, "rays", (json_int_t)r[k].rays,
                                       "seconds", r[k].seconds, "rms", r[k].rms, "dim_rms",
                                       io_json_number(r[k].dim_rms)));
  *ok = 1;
  if (!dir)
    return a;
  char path[4096], err[1024];
  snprintf(path, sizeof path, "%s/fig11-curve.csv", dir);
  io_atomic_t at;
  if (io_csv_open(&at, path, err, sizeof err) != 0) {
    fprintf(stderr, "pencil bench illuminance: %s\n", err);
    *ok = 0;
    return a;
  }
  fprintf(at.f, "method,rays_per_side,rays,seconds,rms,dim_rms\n");
  for (int k = 0; k < n; k++)
    fprintf(at.f, "%s,%d,%llu,%.6g,%.6g,%.6g\n", r[k].method, r[k].side,
            (unsigned long long)r[k].rays, r[k].seconds, r[k].rms, r[k].dim_rms);
  if (io_atomic_commit(&at, err, sizeof err) != 0) {
    fprintf(stderr, "pencil bench illuminance: %s\n", err);
    *ok = 0;
  }
  return a;
}

/* 1987 Fig. 11 (scenes/fig11.json): the torus's light on its three-coloured rectangle, 256 x 256
 * cells. The reference is grid-pencil tracing at 4 times the resolution (513 rays a side, a
 * tenth of the default tolerances); grid-pencil tracing at 33, 65, 129 and 257 rays a side (the
 * cost of accuracy: "curve", and fig11-curve.csv with --maps), illuminance polygons, and photon
 * counting with 100 times the 129 grid's rays are compared with it, and photon counting is run with
 * twice the rays until its error is as low as grid-pencil's (or 100 M rays, beyond which the
 * 1/sqrt(N) law of its noise, fitted to the last run, gives the rays and time it would need). */
static json_t *bench_fig11(const val_illum_bench_opts_t *o, FILE *f, int *met) {
  rt_scene_t s;
  char err[1024];
  rt_scene_init(&s);
  const char *path = o->fig11 ? o->fig11 : PENCIL_SOURCE_DIR "/scenes/fig11.json";
  if (io_scene_load(path, &s, err, sizeof err) != 0) {
    fprintf(stderr, "pencil bench illuminance: %s\n", err);
    return NULL;
  }
  const char *names[3] = {"rectangle red", "rectangle green", "rectangle blue"};
  int obj[3] = {-1, -1, -1};
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < s.nobject; i++)
      if (strcmp(s.object[i].name, names[k]) == 0)
        obj[k] = i;
  lt_receiver_t rc;
  double ext[4];
  lt_map_t ref, gp, ph;
  if (lt_receiver_make(&s, obj, 3, &rc, err, sizeof err) != RT_OK ||
      !lt_default_extent(&s, &rc, ext) ||
      lt_map_alloc(&ref, 256, 256, ext[0], ext[1], ext[2], ext[3]) != RT_OK) {
    fprintf(stderr, "pencil bench illuminance: %s: %s\n", path, err);
    rt_scene_free(&s);
    return NULL;
  }
  lt_options_t lo = LT_OPTIONS_DEFAULT;
  lo.threads = o->threads;
  lo.side = 513;
  lo.linear_tol = 0.005;
  lo.uniform_tol = 0.002;
  lo.max_split = 6;
  lt_stats_t sr, sg, sp;
  int ok = lt_illuminance(&s, &rc, &lo, &ref, &sr) == RT_OK;
  ok = ok && lt_map_alloc(&gp, 256, 256, ext[0], ext[1], ext[2], ext[3]) == RT_OK;
  lo = (lt_options_t)LT_OPTIONS_DEFAULT;
  lo.threads = o->threads;
  lo.max_split = o->max_split;
  lo.linear_tol = o->linear_tol;
  lo.uniform_tol = o->uniform_tol;
  ok = ok && lt_illuminance(&s, &rc, &lo, &gp, &sg) == RT_OK;
  ok = ok && lt_map_alloc(&ph, 256, 256, ext[0], ext[1], ext[2], ext[3]) == RT_OK;
  if (!ok) {
    fprintf(stderr, "pencil bench illuminance: the Fig. 11 maps failed\n");
    rt_scene_free(&s);
    return NULL;
  }
  cmp_t cg = compare(&gp, &ref, NULL);
  double dim_g = dim_rms(&gp, &ref);
  /* illuminance polygons, the pencil tracing of polyhedra, with the same tolerances */
  lo.method = LT_METHOD_POLYGONS;
  lt_stats_t sq;
  lt_map_t pq;
  ok = lt_map_alloc(&pq, 256, 256, ext[0], ext[1], ext[2], ext[3]) == RT_OK &&
       lt_illuminance(&s, &rc, &lo, &pq, &sq) == RT_OK;
  if (!ok) {
    fprintf(stderr, "pencil bench illuminance: the Fig. 11 polygons map failed\n");
    lt_map_free(&ref);
    lt_map_free(&gp);
    lt_map_free(&ph);
    rt_scene_free(&s);
    return NULL;
  }
  cmp_t cq = compare(&pq, &ref, NULL);
  double dim_q = dim_rms(&pq, &ref);
  /* the cost of accuracy: grid-pencil tracing at other grids (the 129 one is sg above) */
  static const int sides[] = {33, 65, 257};
  curve_row_t rows[CURVE_MAX];
  int nrows = 0;
  lt_options_t co = lo;
  co.method = LT_METHOD_GRID_PENCIL;
  for (int k = 0; k < 3 && ok; k++) {
    lt_stats_t sc;
    co.side = sides[k];
    ok = lt_illuminance(&s, &rc, &co, &pq, &sc) == RT_OK;
    if (ok)
      rows[nrows++] = (curve_row_t){
          "grid-pencil",     sides[k], sc.rays, sc.seconds, compare(&pq, &ref, NULL).rms,
          dim_rms(&pq, &ref)};
  }
  rows[nrows++] = (curve_row_t){"grid-pencil", 129, sg.rays, sg.seconds, cg.rms, dim_g};
  rows[nrows++] = (curve_row_t){"polygons", 0, sq.rays, sq.seconds, cq.rms, dim_q};
  lt_map_free(&pq);
  if (!ok) {
    fprintf(stderr, "pencil bench illuminance: the Fig. 11 grid-pencil curve failed\n");
    lt_map_free(&ref);
    lt_map_free(&gp);
    lt_map_free(&ph);
    rt_scene_free(&s);
    return NULL;
  }
  json_t *runs = json_array();
  double rms100 = NAN, dim100 = NAN, t_equal = NAN, n_equal = NAN;
  int equal_measured = 0;
  lt_options_t po = LT_OPTIONS_DEFAULT;
  po.method = LT_METHOD_PHOTONS;
  po.threads = o->threads;
  double base = 129.0 * 129.0; /* the grid-pencil grid's rays */
  if (f)
    fprintf(f,
            "\nFig. 11 (scenes/fig11.json), 256 x 256 cells; reference: grid-pencil, 513 rays a "
            "side, %llu rays in %.1f s\n%-12s %10s %9s %10s %10s\n",
            (unsigned long long)sr.rays, sr.seconds, "method", "rays", "seconds", "rms", "dim rms");
  if (f) {
    for (int k = 0; k < 3; k++)
      fprintf(f, "%-12s %10llu %9.3f %10.3e %10.3e  (%d rays a side)\n", "grid-pencil",
              (unsigned long long)rows[k].rays, rows[k].seconds, rows[k].rms, rows[k].dim_rms,
              rows[k].side);
    fprintf(f, "%-12s %10llu %9.3f %10.3e %10.3e\n", "grid-pencil", (unsigned long long)sg.rays,
            sg.seconds, cg.rms, dim_g);
    fprintf(f, "%-12s %10llu %9.3f %10.3e %10.3e\n", "polygons", (unsigned long long)sq.rays,
            sq.seconds, cq.rms, dim_q);
  }
  for (double n = base * 100; ok; n *= 2) {
    po.side = (int)lrint(sqrt(n));
    ok = lt_illuminance(&s, &rc, &po, &ph, &sp) == RT_OK;
    cmp_t cp = compare(&ph, &ref, NULL);
    double dim_p = dim_rms(&ph, &ref);
    if (isnan(rms100)) {
      rms100 = cp.rms;
      dim100 = dim_p;
    }
    json_array_append_new(runs,
                          json_pack("{s:I, s:f, s:f, s:o}", "rays", (json_int_t)sp.rays, "seconds",
                                    sp.seconds, "rms", cp.rms, "dim_rms", io_json_number(dim_p)));
    if (nrows < CURVE_MAX)
      rows[nrows++] = (curve_row_t){"photons", po.side, sp.rays, sp.seconds, cp.rms, dim_p};
    if (f)
      fprintf(f, "%-12s %10llu %9.3f %10.3e %10.3e\n", "photons", (unsigned long long)sp.rays,
              sp.seconds, cp.rms, dim_p);
    if (cp.rms <= cg.rms) {
      t_equal = sp.seconds;
      n_equal = (double)sp.rays;
      equal_measured = 1;
      break;
    }
    if (sp.rays >= 100000000ull) { /* extrapolate: rms ~ N^-1/2 */
      double k = (cp.rms / cg.rms) * (cp.rms / cg.rms);
      n_equal = (double)sp.rays * k;
      t_equal = sp.seconds * k;
      break;
    }
  }
  double speedup = t_equal / sg.seconds;
  int beat = cg.rms < rms100 && dim_g < dim100;
  *met &= beat;
  if (f)
    fprintf(f,
            "grid-pencil (128 x 128 pencils) against photons with 100 x its grid's rays: rms "
            "%.3e vs %.3e, in dim areas %.3e vs %.3e: %s\nphotons reach grid-pencil's error "
            "with %.3g rays in %.3g s (%s): %.0f times grid-pencil's %.3f s (the paper: about "
            "120)\n",
            cg.rms, rms100, dim_g, dim100, beat ? "lower" : "NOT lower", n_equal, t_equal,
            equal_measured ? "measured" : "extrapolated by 1/sqrt(N)", speedup, sg.seconds);
  int csv_ok;
  json_t *curve = curve_out(rows, nrows, o->maps, &csv_ok);
  json_t *j = json_pack(
      "{s:{s:I, s:f}, s:{s:I, s:f, s:f, s:f}, s:{s:I, s:f, s:f, s:f}, s:o, s:{s:f, s:f, s:b, "
      "s:f}, s:b, s:o}",
      "reference", "rays", (json_int_t)sr.rays, "seconds", sr.seconds, "grid_pencil", "rays",
      (json_int_t)sg.rays, "seconds", sg.seconds, "rms", cg.rms, "dim_rms", dim_g, "polygons",
      "rays", (json_int_t)sq.rays, "seconds", sq.seconds, "rms", cq.rms, "dim_rms", dim_q,
      "photons", runs, "equal_error", "rays", n_equal, "seconds", t_equal, "measured",
      equal_measured, "speedup", speedup, "grid_pencil_lower_than_photons_100x", beat, "curve",
      curve);
  lt_map_free(&ref);
  lt_map_free(&gp);
  lt_map_free(&ph);
  rt_scene_free(&s);
  if (!csv_ok) { /* the CSV could not be written: an I/O error, as a map's would be */
    json_decref(j);
    return NULL;
  }
  return j;
}

int val_bench_illuminance(const val_illum_bench_opts_t *o) {
  if (!o->quick) { /* a bad Fig. 11 scene is an error before minutes of work, not after */
    const char *path = o->fig11 ? o->fig11 : PENCIL_SOURCE_DIR "/scenes/fig11.json";
    char err[1024];
    rt_scene_t t;
    rt_scene_init(&t);
    int bad = io_scene_load(path, &t, err, sizeof err);
    rt_scene_free(&t);
    if (bad) {
      fprintf(stderr, "pencil bench illuminance: cannot read the Fig. 11 scene: %s\n", err);
      return bad == -2 ? VAL_EFAIL : VAL_ESCENE;
    }
  }
  int grid = o->quick ? 32 : 128;
  long rings = o->quick ? 100000 : 1000000;
  json_t *rows = json_array();
  int met = 1;
  FILE *f = o->report;
  if (f)
    fprintf(f,
            "pencil bench illuminance: maps against exact references\n\n"
            "%-14s %-12s %6s %10s %9s  %10s %17s %10s %10s\n",
            "case", "method", "side", "rays", "seconds", "worst smooth", "smooth/cells", "rms",
            "flux err");
  for (int point = 0; point < 2; point++) {
    rt_scene_t s;
    if (!ball_scene(point, &s)) {
      json_decref(rows);
      return -1;
    }
    lt_map_t ref;
    unsigned char *mask = malloc((size_t)grid * grid);
    if (!mask || lt_map_alloc(&ref, grid, grid, -2, 2, -2, 2) != RT_OK) {
      free(mask);
      rt_scene_free(&s);
      json_decref(rows);
      return -1;
    }
    double t0 = val_wall_seconds();
    val_ring_map(BALL_R, BALL_N, BALL_H, point ? POINT_H : 0.0, rings, &ref, mask);
    double tref = val_wall_seconds() - t0;
    if (!save_map(o->maps, point ? "ball-point" : "ball-parallel", "exact", &ref)) {
      free(mask);
      lt_map_free(&ref);
      rt_scene_free(&s);
      json_decref(rows);
      return -1;
    }
    const int floor_obj = 0;
    lt_receiver_t rc;
    char why[200];
    lt_receiver_make(&s, &floor_obj, 1, &rc, why, sizeof why);
    const char *name = point ? "ball, point" : "ball, parallel";
    const char *stem = point ? "ball-point" : "ball-parallel";
    row_t gp = {name, "", stem, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, ph = gp;
    int side = o->quick ? 65 : 129;
    int ok = run(&s, &rc, LT_METHOD_GRID_PENCIL, side, o, &ref, mask, &gp, NULL) &&
             run(&s, &rc, LT_METHOD_PHOTONS, (int)lrint(sqrt((double)gp.rays)), o, &ref, mask, &ph,
                 NULL);
    if (ok && f) {
      print_row(f, &gp);
      print_row(f, &ph);
      fprintf(f, "%-14s %-12s %6s %10ld %9.3f  (exact: meridional rays, annuli)\n", name,
              "reference", "", rings, tref);
    }
    met &= ok && gp.worst_smooth <= 0.01 && gp.flux_rel <= 0.005;
    json_array_append_new(rows, row_json(&gp));
    json_array_append_new(rows, row_json(&ph));
    free(mask);
    lt_map_free(&ref);
    rt_scene_free(&s);
    if (!ok) {
      json_decref(rows);
      return -1;
    }
  }
  if (f)
    fprintf(f,
            "\ntargets: grid-pencil within 1%% of the exact map on smooth cells and its flux "
            "within 0.5%%: %s\n",
            met ? "met" : "NOT met");
  json_t *fig11 = o->quick ? json_null() : bench_fig11(o, f, &met);
  if (!fig11) {
    json_decref(rows);
    return -1;
  }
  int io_err = 0;
  if (o->json) {
    char err[1024];
    json_t *root = json_pack("{s:o, s:o, s:b, s:i, s:I}", "cases", rows, "fig11", fig11,
                             "targets_met", met, "grid", grid, "reference_rays", (json_int_t)rings);
    rows = NULL;
    fig11 = NULL;
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil bench illuminance: %s\n", err);
      io_err = 1;
    }
    json_decref(root);
  }
  json_decref(rows);
  json_decref(fig11);
  return io_err ? -1 : met ? 0 : 1;
}
