/* beam_bench.c -- `pencil bench beam` (beam_bench.h). */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "beam/render.h"
#include "core/builtin.h"
#include "io/image_io.h"
#include "io/json.h"
#include "io/scene_json.h"
#include "renderers/renderer.h"
#include "validation/beam_bench.h"
#include "validation/compare.h"
#include "validation/timing.h"

#ifndef PENCIL_SOURCE_DIR
#define PENCIL_SOURCE_DIR "."
#endif

#define SIZE 256
#define QUICK_SIZE 32
#define REF_SIDE 16 /* the reference: 16 x 16 samples a pixel */
#define QUICK_REF_SIDE 12

/* The polyhedron of a case: 0 the scene's own (Fig. 11's torus), -1 the prism, else a UV sphere
 * of stacks x slices faces. */
typedef struct {
  const char *name, *what;
  int stacks, slices, quick;
} bench_case_t;

static const bench_case_t cases[] = {
    {"fig11", "1987 Fig. 11: the glass torus of 100 faces", 0, 0, 1},
    {"prism", "a glass triangular prism (5 faces)", -1, 0, 1},
    {"sphere100", "a glass UV sphere of 10 x 10 faces", 10, 10, 1},
    {"sphere500", "a glass UV sphere of 20 x 25 faces", 20, 25, 0},
    {"sphere990", "a glass UV sphere of 30 x 33 faces", 30, 33, 0},
    {"sphere2500", "a glass UV sphere of 50 x 50 faces", 50, 50, 0},
    {"sphere5040", "a glass UV sphere of 70 x 72 faces", 70, 72, 0},
    {"sphere10000", "a glass UV sphere of 100 x 100 faces", 100, 100, 0},
};
#define NCASES ((int)(sizeof cases / sizeof cases[0]))

/* The renders of a case. */
enum {
  V_REF = 0,  /* exact, REF_SIDE^2 spp */
  V_BEAM,     /* beams, Eq. (4) bounds */
  V_PROBE,    /* beams, probes only */
  V_EXACT1,   /* the ladder: exact at 1, 4, 16, 64 spp */
  V_EXACT4,   /* ... */
  V_EXACT16,  /* ... */
  V_EXACT64,  /* ... */
  V_PENCIL16, /* pencil, 16 spp */
  NVARIANTS
};
#define LADDER 4

typedef struct {
  const char *name, *renderer;
  int side;  /* samples a pixel side */
  int bound; /* the beams' bt_bound_t */
} variant_t;

typedef struct {
  double seconds, mean, p99, max;
  int done;
} result_t;

/* Per-pixel differences (largest channel) of a against b: mean, 99th percentile, largest. */
static int compare(const rt_image_t *a, const rt_image_t *b, result_t *r) {
  val_diff_t d;
  if (val_image_diff(a, b, &d) != 0)
    return fprintf(stderr, "pencil bench beam: out of memory\n"), VAL_EFAIL;
  r->mean = d.mean;
  r->p99 = d.p99;
  r->max = d.max;
  return 0;
}

/* The case's scene, prepared at side x side: fig11.json, its polyhedron replaced where the case
 * says. 0, or VAL_ESCENE (the file) or VAL_EFAIL with the reason on stderr. */
static int make_scene(const bench_case_t *bc, const val_beam_bench_opts_t *o, int side,
                      rt_scene_t *s) {
  char path[4096], err[1024];
  snprintf(path, sizeof path, "%s/fig11.json", o->scenes ? o->scenes : PENCIL_SOURCE_DIR "/scenes");
  rt_scene_init(s);
  json_error_t je;
  json_t *root = json_load_file(path, 0, &je);
  json_t *objs = root ? json_object_get(root, "objects") : NULL;
  if (!json_is_array(objs)) {
    if (root || je.line < 1)
      fprintf(stderr, "pencil bench beam: %s: %s\n", path, root ? "no \"objects\" array" : je.text);
    else
      fprintf(stderr, "pencil bench beam: %s:%d: %s\n", path, je.line, je.text);
    json_decref(root);
    return VAL_ESCENE;
  }
  if (bc->stacks != 0) /* the polyhedron goes; another comes below */
    for (size_t k = json_array_size(objs); k-- > 0;) {
      const char *type = json_string_value(json_object_get(json_array_get(objs, k), "type"));
      if (type && strcmp(type, "polyhedron") == 0)
        json_array_remove(objs, k);
    }
  char *text = json_dumps(root, JSON_COMPACT);
  json_decref(root);
  int bad = text ? io_scene_load_buffer(path, text, strlen(text), s, err, sizeof err) : -2;
  if (bad) {
    fprintf(stderr, "pencil bench beam: %s\n", text ? err : "out of memory");
    free(text);
    return bad == -2 ? VAL_EFAIL : VAL_ESCENE;
  }
  free(text);
  int glass = rt_scene_find_material(s, "glass"), obj = -1;
  rt_status_t st = RT_OK;
  if (bc->stacks != 0 && glass < 0) {
    fprintf(stderr, "pencil bench beam: %s: no material \"glass\"\n", path);
    return VAL_ESCENE;
  }
  if (bc->stacks > 0) {
    st = rt_scene_add_faceted_sphere(s, px_vec3(0.0, 1.5, 0.0), 1.0, bc->stacks, bc->slices, glass,
                                     &obj);
  } else if (bc->stacks < 0) { /* a triangular prism standing on the rectangles' plane */
    const double h = 1.2;
    const px_vec3_t v[6] = {px_vec3(-0.9, 0.9, -0.6),    px_vec3(0.9, 0.9, -0.6),
                            px_vec3(0.0, 0.9, 0.9),      px_vec3(-0.9, 0.9 + h, -0.6),
                            px_vec3(0.9, 0.9 + h, -0.6), px_vec3(0.0, 0.9 + h, 0.9)};
    const int idx[18] = {0, 2, 1, 3, 4, 5, 0, 1, 4, 3, 1, 2, 5, 4, 2, 0, 3, 5};
    const int len[5] = {3, 3, 4, 4, 4};
    st = rt_scene_add_polyhedron(s, v, 6, idx, len, 5, glass, &obj, err, sizeof err);
  }
  if (st == RT_OK && obj >= 0)
    rt_scene_name_object(s, obj, "glass polyhedron");
  s->camera.width = s->camera.height = side;
  if (st == RT_OK)
    st = rt_scene_prepare(s);
  if (st != RT_OK) {
    fprintf(stderr, "pencil bench beam: case %s: cannot build the scene: %s\n", bc->name,
            rt_strerror(st));
    return st == RT_ENOMEM ? VAL_EFAIL : VAL_ESCENE;
  }
  return 0;
}

/* Render s with variant v into img (allocated here); the median time of `runs` runs. */
static int render(const rt_scene_t *s, const variant_t *v, const val_beam_bench_opts_t *o, int runs,
                  rt_image_t *img, result_t *r) {
  const rn_renderer_t *rn = rn_find(v->renderer);
  rt_plan_t plan = rn_plan_make(rn, s, v->side * v->side, NULL);
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = v->side;
  c.threads = o->threads;
  c.aux = 0;
  void *opt = malloc(rn->options_size), *stats = calloc(1, rn->stats_size);
  double t[128];
  int ok = opt && stats && rt_image_alloc(img, s->camera.width, s->camera.height) == RT_OK;
  if (!ok)
    fprintf(stderr, "pencil bench beam: the %s render: cannot allocate a %dx%d image\n", v->name,
            s->camera.width, s->camera.height);
  if (ok) {
    rn_defaults(rn, opt);
    if (strcmp(v->renderer, "beam") == 0) {
      ((bt_options_t *)opt)->rho = o->rho;
      ((bt_options_t *)opt)->bound = v->bound;
    }
  }
  for (int k = 0; k < runs && ok; k++) {
    rn_output_t out = {.image = img, .stats = stats};
    double t0 = val_wall_seconds();
    rt_status_t st = rn->render(s, &plan, &c, opt, &out);
    t[k] = val_wall_seconds() - t0;
    if (st != RT_OK) {
      fprintf(stderr, "pencil bench beam: the %s render failed: %s%s%s\n", v->name, rt_strerror(st),
              out.why[0] ? ": " : "", out.why);
      ok = 0;
    }
  }
  free(opt);
  free(stats);
  if (!ok)
    return -1;
  r->seconds = val_median(t, runs);
  r->done = 1;
  return 0;
}

/* The exact renderer's time at mean error e, by log-log interpolation between the rungs of the
 * ladder (errors falling with the samples); *where is "inside", or "below" when e is below the
 * finest rung's error (the finest rung's time is returned: the exact renderer needs more) or
 * "above" when above the coarsest's (its time: the exact renderer needs less). */
static double exact_at(const result_t *ladder, double e, const char **where) {
  if (e <= ladder[LADDER - 1].mean) {
    *where = "below";
    return ladder[LADDER - 1].seconds;
  }
  if (e >= ladder[0].mean) {
    *where = "above";
    return ladder[0].seconds;
  }
  *where = "inside";
  for (int k = 0; k + 1 < LADDER; k++) {
    const result_t *a = &ladder[k], *b = &ladder[k + 1];
    if (e <= a->mean && e >= b->mean) {
      double u = (log(e) - log(a->mean)) / (log(b->mean) - log(a->mean));
      if (!isfinite(u))
        return a->seconds;
      return exp(log(a->seconds) + u * (log(b->seconds) - log(a->seconds)));
    }
  }
  *where = "not monotone";
  return NAN;
}

/* The per-pixel difference |a - b| of every channel into a new image, saved as CASE-VARIANT-diff
 * (the map of the beams' error). */
static int save_diff(const char *dir, const char *name, const char *variant, const rt_image_t *a,
                     const rt_image_t *b) {
  rt_image_t d;
  if (rt_image_alloc(&d, a->width, a->height) != RT_OK) {
    fprintf(stderr, "pencil bench beam: out of memory\n");
    return -1;
  }
  size_t n = (size_t)a->width * a->height;
  for (int c = RT_CH_R; c <= RT_CH_B; c++)
    for (size_t k = 0; k < n; k++)
      d.ch[c][k] = fabsf(a->ch[c][k] - b->ch[c][k]);
  char v[64];
  snprintf(v, sizeof v, "%s-diff", variant);
  int r = val_save_case("bench beam", dir, name, v, &d);
  rt_image_free(&d);
  return r;
}

/* The Fig. 10 measure of a beam render (one sample a pixel): the share of samples within rho, the
 * largest finite error, path mismatches. */
typedef struct {
  double within, max, seconds;
  unsigned long long measured, mismatches;
} fig10_t;

static int measure(const rt_scene_t *s, const val_beam_bench_opts_t *o, int certified, fig10_t *m) {
  rt_plan_t plan = rn_plan_make(rn_find("beam"), s, 1, NULL);
  bt_options_t bo = BT_OPTIONS_DEFAULT;
  bo.rho = o->rho;
  bo.certified = certified;
  bo.threads = o->threads;
  bo.aux = 0;
  bo.measure = 1;
  rt_image_t img;
  bt_stats_t st;
  char why[256];
  if (rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK)
    return fprintf(stderr,
                   "pencil bench beam: the measured beam render: cannot allocate a %dx%d "
                   "image\n",
                   s->camera.width, s->camera.height),
           VAL_EFAIL;
  double t0 = val_wall_seconds();
  rt_status_t r = bt_render(s, &plan, &bo, &img, NULL, &st, why, sizeof why);
  m->seconds = val_wall_seconds() - t0;
  rt_image_free(&img);
  if (r != RT_OK || st.measured == 0) {
    fprintf(stderr, "pencil bench beam: the measured beam render failed: %s%s%s\n", rt_strerror(r),
            why[0] ? ": " : "", why);
    return -1;
  }
  m->within = (double)st.within / (double)st.measured;
  m->max = st.fig10_max;
  m->measured = (unsigned long long)st.measured;
  m->mismatches = (unsigned long long)st.mismatches;
  return 0;
}

static json_t *fig10_json(const fig10_t *m) {
  return json_pack("{s:I, s:f, s:f, s:I, s:f}", "samples", (json_int_t)m->measured, "within",
                   m->within, "max", m->max, "mismatches", (json_int_t)m->mismatches,
                   "seconds_measured", m->seconds);
}

static int faces_of(const bench_case_t *bc) {
  return bc->stacks > 0 ? bc->stacks * bc->slices : bc->stacks < 0 ? 5 : 100;
}

/* One case: every variant against the reference. NULL on an error, its kind in *rc
 * (validation/status.h), after a message. */
static json_t *run_case(const bench_case_t *bc, const val_beam_bench_opts_t *o, int side,
                        int ref_side, FILE *f, int *rc) {
  rt_scene_t s;
  *rc = make_scene(bc, o, side, &s);
  if (*rc != 0) {
    rt_scene_free(&s);
    return NULL;
  }
  *rc = VAL_EFAIL;
  const variant_t vs[NVARIANTS] = {
      {"reference", "exact", ref_side, 0},
      {"beam", "beam", 1, BT_BOUND_CORRECTED},
      {"beam-probe", "beam", 1, BT_BOUND_PROBE},
      {"exact-1", "exact", 1, 0},
      {"exact-4", "exact", 2, 0},
      {"exact-16", "exact", 4, 0},
      {"exact-64", "exact", 8, 0},
      {"pencil-16", "pencil", 4, 0},
  };
  rt_image_t img[NVARIANTS];
  result_t res[NVARIANTS];
  memset(img, 0, sizeof img);
  memset(res, 0, sizeof res);
  int bad = 0;
  for (int v = 0; v < NVARIANTS && !bad; v++) {
    bad = render(&s, &vs[v], o, v == V_REF ? 1 : o->runs, &img[v], &res[v]) != 0;
    if (!bad && v != V_REF)
      bad = compare(&img[v], &img[V_REF], &res[v]) != 0;
    if (!bad && o->out)
      bad = val_save_case("bench beam", o->out, bc->name, vs[v].name, &img[v]) != 0;
    if (!bad && o->out && v == V_BEAM)
      bad = save_diff(o->out, bc->name, vs[v].name, &img[v], &img[V_REF]) != 0;
  }
  /* the paper's own case: the Fig. 10 measure, without and with certification */
  fig10_t m10[2];
  int with10 = bc->stacks == 0;
  for (int k = 0; k < 2 && with10 && !bad; k++)
    bad = measure(&s, o, k, &m10[k]) != 0;
  json_t *j = NULL;
  if (!bad) {
    const char *where = "", *where_p = "";
    double te = exact_at(&res[V_EXACT1], res[V_BEAM].mean, &where);
    double tp = exact_at(&res[V_EXACT1], res[V_PROBE].mean, &where_p);
    double ratio = te / res[V_BEAM].seconds;
    if (f) {
      fprintf(f, "\n%s (%s, %d faces), %dx%d; reference: exact at %d spp, %.2f s\n", bc->name,
              bc->what, faces_of(bc), side, side, ref_side * ref_side, res[V_REF].seconds);
      fprintf(f, "%-11s %-7s %4s %9s  %10s %10s %10s\n", "variant", "render", "spp", "s", "mean",
              "p99", "max");
      for (int v = V_BEAM; v < NVARIANTS; v++)
        fprintf(f, "%-11s %-7s %4d %9.3f  %10.3e %10.3e %10.3e\n", vs[v].name, vs[v].renderer,
                vs[v].side * vs[v].side, res[v].seconds, res[v].mean, res[v].p99, res[v].max);
      fprintf(f,
              "exact at the beams' mean error: %.3f s (%s the ladder); exact / beam %.2f; "
              "beam / exact-16 %.3f; beam / pencil-16 %.3f; bounds / probes %.3f\n",
              te, where, ratio, res[V_BEAM].seconds / res[V_EXACT16].seconds,
              res[V_BEAM].seconds / res[V_PENCIL16].seconds,
              res[V_BEAM].seconds / res[V_PROBE].seconds);
      for (int k = 0; k < 2 && with10; k++)
        fprintf(f,
                "Fig. 10 measure%s: %.4f%% of %llu samples within rho = %g, max %.4g pixel "
                "intervals, %llu path mismatches\n",
                k ? " (certified)" : "", 100.0 * m10[k].within, m10[k].measured, o->rho, m10[k].max,
                m10[k].mismatches);
      fflush(f);
    }
    json_t *rows = json_array();
    for (int v = 0; v < NVARIANTS; v++)
      json_array_append_new(
          rows, json_pack("{s:s, s:s, s:i, s:f, s:o, s:o, s:o}", "variant", vs[v].name, "renderer",
                          vs[v].renderer, "spp", vs[v].side * vs[v].side, "seconds", res[v].seconds,
                          "mean", v == V_REF ? json_null() : json_real(res[v].mean), "p99",
                          v == V_REF ? json_null() : json_real(res[v].p99), "max",
                          v == V_REF ? json_null() : json_real(res[v].max)));
    j = json_pack("{s:s, s:s, s:i, s:i, s:i, s:o, s:{s:o, s:s, s:o, s:o, s:s, s:o}, s:f, s:f}",
                  "case", bc->name, "what", bc->what, "faces", faces_of(bc), "width", side,
                  "height", side, "variants", rows, "equal_error", "exact_seconds",
                  io_json_number(te), "bracket", where, "exact_over_beam", io_json_number(ratio),
                  "exact_seconds_probe", io_json_number(tp), "bracket_probe", where_p,
                  "exact_over_beam_probe", io_json_number(tp / res[V_PROBE].seconds),
                  "beam_over_exact16", res[V_BEAM].seconds / res[V_EXACT16].seconds,
                  "beam_over_pencil16", res[V_BEAM].seconds / res[V_PENCIL16].seconds);
    if (!j)
      fprintf(stderr, "pencil bench beam: out of memory\n");
    if (j && with10)
      json_object_set_new(j, "fig10",
                          json_pack("{s:o, s:o}", "default", fig10_json(&m10[0]), "certified",
                                    fig10_json(&m10[1])));
  }
  for (int v = 0; v < NVARIANTS; v++)
    rt_image_free(&img[v]);
  rt_scene_free(&s);
  return j;
}

const char *val_bench_beam_case_names(void) {
  return "fig11, prism, sphere100, sphere500, sphere990, sphere2500, sphere5040, sphere10000";
}

int val_bench_beam_cases_ok(const char *list, char *bad, size_t cap) {
  const char *names[NCASES];
  for (int c = 0; c < NCASES; c++)
    names[c] = cases[c].name;
  return val_case_list_ok(list, names, NCASES, bad, cap);
}

int val_bench_beam(const val_beam_bench_opts_t *o) {
  FILE *f = o->report;
  int side = o->size > 0 ? o->size : o->quick ? QUICK_SIZE : SIZE;
  int ref_side = o->quick ? QUICK_REF_SIDE : REF_SIDE;
  if (f)
    fprintf(f,
            "pencil bench beam: beam tracing against exact and pencil renderers, Fig. 11's set-up "
            "at %dx%d, rho %g\n(per pixel the largest of R, G, B against the exact renderer at %d "
            "spp; times are medians of %d run(s))\n",
            side, side, o->rho, ref_side * ref_side, o->runs);
  json_t *all = json_array();
  for (int k = 0; k < NCASES; k++) {
    if (o->cases ? !val_case_listed(o->cases, cases[k].name) : o->quick && !cases[k].quick)
      continue;
    int rc;
    json_t *j = run_case(&cases[k], o, side, ref_side, f, &rc);
    if (!j) {
      json_decref(all);
      return rc;
    }
    json_array_append_new(all, j);
  }
  int rc = 0;
  if (o->json) {
    char err[1024];
    json_t *root = json_pack("{s:s, s:o, s:i, s:i, s:f, s:i, s:b}", "benchmark", "beam", "cases",
                             all, "size", side, "reference_spp", ref_side * ref_side, "rho", o->rho,
                             "runs", o->runs, "quick", o->quick);
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil bench beam: %s\n", err);
      rc = VAL_EFAIL;
    }
    json_decref(root);
  } else {
    json_decref(all);
  }
  return rc;
}
