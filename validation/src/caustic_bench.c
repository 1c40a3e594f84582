/* caustic_bench.c -- `pencil bench caustics` (caustic_bench.h). */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/image_io.h"
#include "io/json.h"
#include "io/scene_json.h"
#include "light/illuminance.h"
#include "renderers/renderer.h"
#include "validation/caustic_bench.h"
#include "validation/compare.h"
#include "validation/timing.h"

#ifndef PENCIL_SOURCE_DIR
#define PENCIL_SOURCE_DIR "."
#endif

/* Reference maps: photons on grids of this many rays a side (about 67 million a grid face), and
 * half as many rays for the estimate of the reference's own error. */
#define REF_RAYS 8193
#define HALF_RAYS 5793
#define QUICK_REF_RAYS 513
#define QUICK_HALF_RAYS 363
#define QUICK_SIZE 48

typedef struct {
  const char *name, *file, *what;
  int ref_rays;           /* the reference's rays a side (0: REF_RAYS) */
  int width, height, spp; /* the image (0: the scene's) */
  int no_polygons;        /* no illuminance-polygons variant even where the scene is polyhedral */
} bench_case_t;

/* Fig. 11 and the pool take 16384 rays a side (268 million a face): with 8193 the reference's own
 * error was as large as the grid-pencil map's (docs/journal/2026-12-02-caustic-renders.md). */
static const bench_case_t cases[] = {
    {"fig8", "fig8-caustics.json", "Fig. 8 with caustics: a glass ball over a checkerboard", 0, 0,
     0, 0, 0},
    {"fig11", "fig11-caustics.json", "1987 Fig. 11: a glass torus of 100 faces, its caustic", 16384,
     0, 0, 0, 0},
    {"pool", "pool.json", "1989 Fig. 8: a pool under a parallel light", 16384, 0, 0, 0, 0},
    /* a quarter of the paper's 1024 x 682 (its 3 x 3 samples kept); no polygons: they would
     * trace the glass's and the water's 196 faces once for each of the light's
     * 49 points */
    {"glass", "glass.json", "1989 Fig. 10: a glass of water under an area light", 16384, 256, 171,
     9, 1},
};
#define NCASES ((int)(sizeof cases / sizeof cases[0]))

/* A render variant: the renderer, whether caustics are drawn, the map's method (1 + lt_method_t,
 * 0 the renderer's), rays a side (0 the default), whether it is timed, and the variant it is
 * compared with. */
typedef struct {
  const char *name, *renderer;
  int caustics, method, rays, timed, against;
} variant_t;

enum {
  V_REF = 0,   /* the reference: exact, converged photon map */
  V_HALF,      /* the same with half the rays: the reference's own error */
  V_EXACT,     /* exact, its default photon map */
  V_EXACT_GP,  /* exact with the pencil renderer's grid-pencil map: the maps compared alone */
  V_PENCIL,    /* pencil, its default grid-pencil map */
  V_POLYGONS,  /* pencil with illuminance polygons (polyhedral scenes) */
  V_TEXTBOOK,  /* exact, caustics off */
  V_PENCIL_TB, /* pencil, caustics off: compared with V_TEXTBOOK, the pencil's own error */
  NVARIANTS
};

typedef struct {
  double seconds;       /* median wall-clock time of the runs */
  double map_seconds;   /* the maps' share of the last run */
  long long map_rays;   /* light rays of the maps */
  const char *method;   /* the maps' method, or "none" */
  int rays;             /* rays a side of the maps' grids (0: polygons, none) */
  double rms, p99, max; /* against the reference, per pixel the largest of R, G, B */
  int done;
} result_t;

/* Per-pixel differences (largest channel) of a against b: RMS, 99th percentile, largest. */
static int compare(const rt_image_t *a, const rt_image_t *b, double *rms, double *p99,
                   double *max) {
  val_diff_t d;
  if (val_image_diff(a, b, &d) != 0)
    return fprintf(stderr, "pencil bench caustics: out of memory\n"), VAL_EFAIL;
  *rms = d.rms;
  *p99 = d.p99;
  *max = d.max;
  return 0;
}

/* Render s with variant v into img (allocated here); the median time of `runs` runs. */
static int render(const rt_scene_t *s0, const variant_t *v, const val_caustic_bench_opts_t *o,
                  int runs, rt_image_t *img, result_t *r) {
  const rn_renderer_t *rn = rn_find(v->renderer);
  rt_scene_t s = *s0; /* a shallow copy: only the setting below differs */
  if (!v->caustics)
    s.caustics = RT_CAUSTICS_OFF;
  int spp = s.spp;
  rt_plan_t plan = rn_plan_make(rn, &s, spp, NULL);
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = (int)lrint(sqrt(spp));
  c.threads = o->threads;
  c.aux = 0;
  c.caustic_method = v->method;
  c.caustic_rays = v->rays;
  if (o->quick) { /* small maps: photons on 129 rays a side, grid-pencils on 33 */
    int method = v->method                           ? v->method - 1
                 : strcmp(v->renderer, "exact") == 0 ? LT_METHOD_PHOTONS
                                                     : LT_METHOD_GRID_PENCIL;
    c.caustic_cells = 64;
    if (!v->rays && method != LT_METHOD_POLYGONS)
      c.caustic_rays = method == LT_METHOD_PHOTONS ? 129 : 33;
  }
  void *opt = malloc(rn->options_size), *stats = calloc(1, rn->stats_size);
  double t[16];
  int ok = opt && stats && rt_image_alloc(img, s.camera.width, s.camera.height) == RT_OK;
  if (!ok)
    fprintf(stderr, "pencil bench caustics: the %s render: cannot allocate a %dx%d image\n",
            v->name, s.camera.width, s.camera.height);
  if (ok)
    rn_defaults(rn, opt);
  rn_caustic_stats_t cs;
  memset(&cs, 0, sizeof cs);
  for (int k = 0; k < runs && ok; k++) {
    rn_output_t out = {.image = img, .stats = stats, .caustics = &cs};
    double t0 = val_wall_seconds();
    rt_status_t st = rn->render(&s, &plan, &c, opt, &out);
    t[k] = val_wall_seconds() - t0;
    if (st != RT_OK) {
      fprintf(stderr, "pencil bench caustics: the %s render failed: %s%s%s\n", v->name,
              rt_strerror(st), cs.why[0] ? ": " : "", cs.why);
      ok = 0;
    }
  }
  free(opt);
  free(stats);
  if (!ok)
    return -1;
  r->seconds = val_median(t, runs);
  r->map_seconds = cs.seconds;
  r->map_rays = (long long)cs.traced;
  r->method = cs.maps ? cs.method : "none";
  r->rays = cs.maps ? cs.rays : 0;
  r->done = 1;
  return 0;
}

static json_t *result_json(const variant_t *v, const variant_t *against, const result_t *r,
                           int reference) {
  return json_pack("{s:s, s:s, s:b, s:s, s:i, s:f, s:f, s:I, s:o, s:o, s:o, s:o}", "variant",
                   v->name, "renderer", v->renderer, "caustics", v->caustics, "caustic_method",
                   r->method, "caustic_rays", r->rays, "seconds", r->seconds, "map_seconds",
                   r->map_seconds, "map_rays", (json_int_t)r->map_rays, "against",
                   reference ? json_null() : json_string(against->name), "rms",
                   reference ? json_null() : io_json_number(r->rms), "p99",
                   reference ? json_null() : io_json_number(r->p99), "max",
                   reference ? json_null() : io_json_number(r->max));
}

/* One scene: every variant, compared with the reference. NULL on an error, its kind in *rc
 * (validation/status.h), after a message. */
static json_t *run_case(const bench_case_t *bc, const val_caustic_bench_opts_t *o, FILE *f,
                        int *rc) {
  char path[4096], err[1024];
  snprintf(path, sizeof path, "%s/%s", o->scenes ? o->scenes : PENCIL_SOURCE_DIR "/scenes",
           bc->file);
  rt_scene_t s;
  rt_scene_init(&s);
  *rc = VAL_ESCENE;
  int lr = io_scene_load(path, &s, err, sizeof err);
  if (lr) {
    *rc = lr == -2 ? VAL_EFAIL : VAL_ESCENE;
    fprintf(stderr, "pencil bench caustics: %s\n", err);
    rt_scene_free(&s);
    return NULL;
  }
  if (bc->width > 0) {
    s.camera.width = bc->width;
    s.camera.height = bc->height;
    s.spp = bc->spp;
  }
  if (o->quick) {
    s.camera.width = s.camera.height = QUICK_SIZE;
    s.spp = 1;
  }
  rt_status_t ps = rt_scene_prepare(&s);
  if (ps != RT_OK) {
    fprintf(stderr, "pencil bench caustics: %s: cannot prepare the scene: %s\n", path,
            rt_strerror(ps));
    rt_scene_free(&s);
    *rc = ps == RT_ENOMEM ? VAL_EFAIL : VAL_ESCENE;
    return NULL;
  }
  *rc = VAL_EFAIL;
  /* illuminance polygons where the scene is polyhedral; not in the quick run (their cost does
   * not shrink with the map: Fig. 11's torus takes half a minute whatever the cells) */
  int polyhedral = !o->quick && !bc->no_polygons &&
                   lt_method_check(&s, LT_METHOD_POLYGONS, err, sizeof err) == RT_OK;
  const int ref_rays = o->ref_rays    ? o->ref_rays
                       : o->quick     ? QUICK_REF_RAYS
                       : bc->ref_rays ? bc->ref_rays
                                      : REF_RAYS;
  const int half_rays = (int)lrint(ref_rays / sqrt(2.0));
  const variant_t vs[NVARIANTS] = {
      {"reference", "exact", 1, 1 + LT_METHOD_PHOTONS, ref_rays, 0, V_REF},
      {"reference-half", "exact", 1, 1 + LT_METHOD_PHOTONS, half_rays, 0, V_REF},
      {"exact", "exact", 1, 0, 0, 1, V_REF},
      {"exact-grid-pencil", "exact", 1, 1 + LT_METHOD_GRID_PENCIL, 0, 1, V_REF},
      {"pencil", "pencil", 1, 0, 0, 1, V_REF},
      {"pencil-polygons", "pencil", 1, 1 + LT_METHOD_POLYGONS, 0, 1, V_REF},
      {"textbook", "exact", 0, 0, 0, 1, V_REF},
      {"pencil-textbook", "pencil", 0, 0, 0, 1, V_TEXTBOOK},
  };
  rt_image_t img[NVARIANTS];
  result_t res[NVARIANTS];
  memset(img, 0, sizeof img);
  memset(res, 0, sizeof res);
  int bad = 0;
  for (int v = 0; v < NVARIANTS && !bad; v++) {
    if (v == V_POLYGONS && !polyhedral)
      continue;
    bad = render(&s, &vs[v], o, vs[v].timed ? o->runs : 1, &img[v], &res[v]) != 0;
    if (!bad && v != V_REF &&
        compare(&img[v], &img[vs[v].against], &res[v].rms, &res[v].p99, &res[v].max) != 0)
      bad = 1;
    if (!bad && o->out)
      bad = val_save_case("bench caustics", o->out, bc->name, vs[v].name, &img[v]) != 0;
  }
  json_t *j = NULL;
  if (!bad) {
    double mean = 0.0;
    size_t n = (size_t)s.camera.width * s.camera.height;
    for (size_t k = 0; k < n; k++)
      mean +=
          (img[V_REF].ch[RT_CH_R][k] + img[V_REF].ch[RT_CH_G][k] + img[V_REF].ch[RT_CH_B][k]) / 3.0;
    mean /= n;
    /* the two references' errors, if independent and the half's sqrt(2) times the whole's,
     * differ by sqrt(3) times the whole's */
    double ref_rms = res[V_HALF].rms / sqrt(3.0);
    /* the maps alone, in the exact renderer: photons against grid-pencils, each error less the
     * reference's (in quadrature); photons' error falls as 1 / sqrt(rays), which gives the rays
     * (and the map time) photons need for the grid-pencil map's error. Unknown (NaN) when the
     * grid-pencil map's error is within the reference's own. */
    double e_ph = sqrt(fmax(0.0, res[V_EXACT].rms * res[V_EXACT].rms - ref_rms * ref_rms));
    double e_gp = sqrt(fmax(0.0, res[V_EXACT_GP].rms * res[V_EXACT_GP].rms - ref_rms * ref_rms));
    double resolved = res[V_EXACT_GP].rms > 2.0 * ref_rms;
    double eq_rays = resolved ? res[V_EXACT].map_rays * (e_ph / e_gp) * (e_ph / e_gp) : NAN;
    double eq_seconds = resolved ? res[V_EXACT].map_seconds * eq_rays / res[V_EXACT].map_rays : NAN;
    double gp_map = res[V_EXACT_GP].map_seconds;
    if (f) {
      fprintf(f,
              "\n%s (%s), %dx%d at %d spp; mean radiance %.4g; reference: exact with %s on "
              "%d x %d rays a grid face (%lld rays, %.1f s), its RMS error about %.2e\n",
              bc->name, bc->what, s.camera.width, s.camera.height, s.spp, mean, res[V_REF].method,
              res[V_REF].rays, res[V_REF].rays, res[V_REF].map_rays, res[V_REF].seconds, ref_rms);
      fprintf(f, "%-18s %-7s %-12s %6s %11s %8s %8s  %10s %10s %10s  %s\n", "variant", "render",
              "map", "rays", "map rays", "map s", "s", "rms", "p99", "max", "against");
      for (int v = V_HALF; v < NVARIANTS; v++)
        if (res[v].done)
          fprintf(f, "%-18s %-7s %-12s %6d %11lld %8.3f %8.3f  %10.3e %10.3e %10.3e  %s\n",
                  vs[v].name, vs[v].renderer, res[v].method, res[v].rays, res[v].map_rays,
                  res[v].map_seconds, res[v].seconds, res[v].rms, res[v].p99, res[v].max,
                  vs[vs[v].against].name);
      fprintf(f, "pencil / exact time %.3f; pencil / reference time %.3f; textbook / exact %.3f\n",
              res[V_PENCIL].seconds / res[V_EXACT].seconds,
              res[V_PENCIL].seconds / res[V_REF].seconds,
              res[V_TEXTBOOK].seconds / res[V_EXACT].seconds);
      if (resolved)
        fprintf(f,
                "maps alone (exact renderer): photons reach the grid-pencil map's error (%.2e "
                "less the reference's) with about %.3g rays in %.3g s (by 1/sqrt(N)), %.3g times "
                "the grid-pencil map's %.3g s\n",
                e_gp, eq_rays, eq_seconds, eq_seconds / gp_map, gp_map);
      else
        fprintf(f,
                "maps alone (exact renderer): the grid-pencil map's error is within twice the "
                "reference's own (%.2e against %.2e): the reference cannot say how many photons "
                "would match it\n",
                res[V_EXACT_GP].rms, ref_rms);
    }
    json_t *rows = json_array();
    for (int v = 0; v < NVARIANTS; v++)
      if (res[v].done)
        json_array_append_new(rows, result_json(&vs[v], &vs[vs[v].against], &res[v], v == V_REF));
    j = json_pack(
        "{s:s, s:s, s:i, s:i, s:i, s:f, s:f, s:o, s:f, s:f, s:{s:o, s:o, s:o, s:f}}", "case",
        bc->name, "scene", bc->file, "width", s.camera.width, "height", s.camera.height, "spp",
        s.spp, "mean_radiance", mean, "reference_rms_estimate", ref_rms, "variants", rows,
        "pencil_over_exact", res[V_PENCIL].seconds / res[V_EXACT].seconds, "pencil_over_reference",
        res[V_PENCIL].seconds / res[V_REF].seconds, "equal_error", "photon_rays",
        io_json_number(eq_rays), "photon_seconds", io_json_number(eq_seconds), "over_grid_pencil",
        io_json_number(eq_seconds / gp_map), "grid_pencil_seconds", gp_map);
    if (!j)
      fprintf(stderr, "pencil bench caustics: out of memory\n");
  }
  for (int v = 0; v < NVARIANTS; v++)
    rt_image_free(&img[v]);
  rt_scene_free(&s);
  return j;
}

int val_bench_caustics_cases_ok(const char *list, char *bad, size_t cap) {
  const char *names[NCASES];
  for (int c = 0; c < NCASES; c++)
    names[c] = cases[c].name;
  return val_case_list_ok(list, names, NCASES, bad, cap);
}

int val_bench_caustics(const val_caustic_bench_opts_t *o) {
  FILE *f = o->report;
  if (f)
    fprintf(f,
            "pencil bench caustics: renders with caustics against the exact renderer with a "
            "converged photon map\n(per pixel the largest of R, G, B; times are medians of %d "
            "run(s) and include the maps)\n",
            o->runs);
  json_t *all = json_array();
  for (int k = 0; k < NCASES; k++) {
    if (!val_case_listed(o->cases, cases[k].name))
      continue;
    int rc;
    json_t *j = run_case(&cases[k], o, f, &rc);
    if (!j) {
      json_decref(all);
      return rc;
    }
    json_array_append_new(all, j);
  }
  int rc = 0;
  if (o->json) {
    char err[1024];
    json_t *root = json_pack("{s:o, s:i, s:b}", "cases", all, "runs", o->runs, "quick", o->quick);
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil bench caustics: %s\n", err);
      rc = VAL_EFAIL;
    }
    json_decref(root);
  } else {
    json_decref(all);
  }
  return rc;
}
