/* shards.c -- a figures or sweep run split into independent work items, so that a researcher's
 * sweep can run on many machines (Slurm job arrays, mpirun: scripts/) and be merged into the
 * outputs one run gives. Shard files record every measured number exactly (17 significant
 * digits, infinities and NaN as strings), so that a merge is the single run's computation with
 * only the timings differing. */
#include "figures_impl.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/json.h"
#include "io/output.h"

/* ---- the work items ------------------------------------------------------------------------ */

unsigned val__selected(const val_figures_opts_t *o, int sweep_only) {
  unsigned all = VAL_ONLY_FIG8 | VAL_ONLY_FIG9 | VAL_ONLY_TARGETS | (o->sweep ? VAL_ONLY_SWEEP : 0);
  return sweep_only ? VAL_ONLY_SWEEP : o->only ? o->only : all;
}

int val__items(const val_figures_opts_t *o, int sweep_only, val_item_t *items) {
  unsigned sel = val__selected(o, sweep_only);
  int n = 0;
  if (sel & VAL_ONLY_FIG9)
    for (int k = 0; k < o->nspp; k++)
      items[n++] = (val_item_t){VAL_ITEM_FIG9, k};
  if (sel & VAL_ONLY_FIG8)
    items[n++] = (val_item_t){VAL_ITEM_FIG8, 0};
  if (sel & VAL_ONLY_TARGETS)
    for (int kind = VAL_ITEM_TARGET; kind <= VAL_ITEM_NOACC_CERT; kind++)
      items[n++] = (val_item_t){(val_item_kind_t)kind, 0};
  if (sel & VAL_ONLY_SWEEP)
    for (int k = 0; k < 3 * o->nrho; k++)
      items[n++] = (val_item_t){VAL_ITEM_SWEEP, k};
  return n;
}

void val__item_name(val_item_t it, const val_figures_opts_t *o, char *buf, size_t cap) {
  static const char *const names[] = {"fig9",
                                      "fig8",
                                      "target",
                                      "target_certified",
                                      "time_certified",
                                      "no_accuracy",
                                      "no_accuracy_certified",
                                      "sweep"};
  if (it.kind == VAL_ITEM_FIG9)
    snprintf(buf, cap, "fig9:%d", o->spp[it.index]);
  else if (it.kind == VAL_ITEM_SWEEP)
    snprintf(buf, cap, "sweep:%d", it.index);
  else
    snprintf(buf, cap, "%s", names[it.kind]);
}

void val__results_init(const val_figures_opts_t *o, val_results_t *r) {
  /* no peer timed until one is (val_time_peer() sets them) */
  for (int k = 0; k < VAL_MAX_SPP; k++)
    r->fig9[k].peer_s = r->fig9[k].peer_wall = NAN;
  r->tc49.peer_s = r->tc49.peer_wall = r->floor.peer_s = r->floor.peer_wall = NAN;
  r->cfloor.peer_s = r->cfloor.peer_wall = NAN;
  for (int k = 0; k < 3 * VAL_MAX_RHO; k++)
    r->sweep[k].t.peer_s = r->sweep[k].t.peer_wall = NAN;
  r->fig8_spp = 9;
  r->target_spp = o->nspp > 0 ? o->spp[o->nspp - 1] : 0;
  for (int k = 0; k < o->nspp; k++)
    if (o->spp[k] == 49) /* the paper's Fig. 9 falls below 0.1 at 49 spp */
      r->target_spp = 49;
  r->nsweep = 3 * o->nrho;
  for (int k = 0; k < r->nsweep; k++) {
    r->sweep[k].rho = o->rho[k / 3];
    r->sweep[k].variant = k % 3;
  }
}

/* ---- exact numbers ------------------------------------------------------------------------- */

/* A double that reads back bit for bit: a JSON real (17 digits), or a string for the
 * non-finite values JSON has no number for. */
static json_t *num(double x) {
  if (isfinite(x))
    return json_real(x);
  return json_string(isnan(x) ? "nan" : x > 0 ? "inf" : "-inf");
}

static int num_in(json_t *j, double *x) {
  const char *s = json_string_value(j);
  if (json_is_number(j))
    *x = json_number_value(j);
  else if (s && strcmp(s, "nan") == 0)
    *x = NAN;
  else if (s && strcmp(s, "inf") == 0)
    *x = INFINITY;
  else if (s && strcmp(s, "-inf") == 0)
    *x = -INFINITY;
  else
    return 0;
  return 1;
}

static int count_in(json_t *j, uint64_t *x) {
  if (!json_is_integer(j) || json_integer_value(j) < 0)
    return 0;
  *x = (uint64_t)json_integer_value(j);
  return 1;
}

static json_t *timing_json(const val_timing_t *t) {
  json_t *j = json_pack("{s:i, s:o, s:o, s:o, s:o, s:o}", "spp", t->spp, "exact_s", num(t->exact_s),
                        "pencil_s", num(t->pencil_s), "exact_wall", num(t->exact_wall),
                        "pencil_wall", num(t->pencil_wall), "ratio", num(t->ratio));
  if (j && !isnan(t->peer_s)) /* POV-Ray beside Fig. 9 (--peer povray) */
    json_object_update_new(j, json_pack("{s:o, s:o, s:I}", "peer_s", num(t->peer_s), "peer_wall",
                                        num(t->peer_wall), "peer_rays", (json_int_t)t->peer_rays));
  return j;
}

static int timing_in(json_t *j, val_timing_t *t) {
  json_t *spp = json_object_get(j, "spp");
  t->spp = json_is_integer(spp) ? (int)json_integer_value(spp) : -1;
  t->peer_s = t->peer_wall = NAN;
  t->peer_rays = 0;
  json_t *peer = json_object_get(j, "peer_s");
  if (peer &&
      !(num_in(peer, &t->peer_s) && num_in(json_object_get(j, "peer_wall"), &t->peer_wall) &&
        count_in(json_object_get(j, "peer_rays"), &t->peer_rays)))
    return 0;
  return t->spp >= 0 && num_in(json_object_get(j, "exact_s"), &t->exact_s) &&
         num_in(json_object_get(j, "pencil_s"), &t->pencil_s) &&
         num_in(json_object_get(j, "exact_wall"), &t->exact_wall) &&
         num_in(json_object_get(j, "pencil_wall"), &t->pencil_wall) &&
         num_in(json_object_get(j, "ratio"), &t->ratio);
}

/* The fields of val_errors_t and rn_errors_t, by name, for both directions. (Not formatted:
 * clang-format 14 does not settle on one layout for these lists.) */
// clang-format off
#define ERR_DOUBLES(X) \
  X(rho) X(fraction_within) X(p99) X(max_error) X(fraction_within_strict) X(max_error_strict) \
  X(fraction_within_t) X(max_error_t) X(fraction_within_axial) X(max_error_axial) X(image_rms) X(image_max) X(image_bias)
#define ERR_COUNTS(X) X(samples) X(samples_with_points) X(mismatches)
#define CNT_DOUBLES(X) X(max_error) X(max_error_t) X(max_error_strict) X(max_error_axial)
#define CNT_COUNTS(X) \
  X(measured) X(with_points) X(within) X(mismatches) X(within_t) X(within_strict) \
  X(within_axial) X(local_unknown) X(samples_exact) X(samples_matrix) X(samples_interpolated)
// clang-format on

static json_t *errors_json(const val_errors_t *e) {
  json_t *j = json_object(), *c = json_object(), *h = json_array();
#define OUT_D(f) json_object_set_new(j, #f, num(e->f));
#define OUT_C(f) json_object_set_new(j, #f, json_integer((json_int_t)e->f));
#define OUT_CD(f) json_object_set_new(c, #f, num(e->counts.f));
#define OUT_CC(f) json_object_set_new(c, #f, json_integer((json_int_t)e->counts.f));
  ERR_DOUBLES(OUT_D)
  ERR_COUNTS(OUT_C)
  CNT_DOUBLES(OUT_CD)
  CNT_COUNTS(OUT_CC)
  json_object_set_new(j, "image_bias_object", json_integer(e->image_bias_object));
  for (int k = 0; k < RN_HIST_BINS; k++)
    json_array_append_new(h, json_integer((json_int_t)e->counts.hist[k]));
  json_object_set_new(c, "hist", h);
  json_object_set_new(j, "counts", c);
  return j;
}

static int errors_in(json_t *j, val_errors_t *e) {
  json_t *c = json_object_get(j, "counts"), *h = json_object_get(c, "hist"),
         *obj = json_object_get(j, "image_bias_object");
  int ok = json_is_object(c) && json_is_array(h) && json_array_size(h) == RN_HIST_BINS &&
           json_is_integer(obj);
#define IN_D(f) ok = ok && num_in(json_object_get(j, #f), &e->f);
#define IN_C(f) ok = ok && count_in(json_object_get(j, #f), &e->f);
#define IN_CD(f) ok = ok && num_in(json_object_get(c, #f), &e->counts.f);
#define IN_CC(f) ok = ok && count_in(json_object_get(c, #f), &e->counts.f);
  ERR_DOUBLES(IN_D)
  ERR_COUNTS(IN_C)
  CNT_DOUBLES(IN_CD)
  CNT_COUNTS(IN_CC)
  for (int k = 0; ok && k < RN_HIST_BINS; k++)
    ok = count_in(json_array_get(h, (size_t)k), &e->counts.hist[k]);
  if (ok)
    e->image_bias_object = (int)json_integer_value(obj);
  return ok;
}

/* ---- the configuration --------------------------------------------------------------------- */

json_t *val__config_json(const val_figures_opts_t *o, const char *command, int width, int height) {
  json_t *spp = json_array(), *rho = json_array();
  for (int k = 0; k < o->nspp; k++)
    json_array_append_new(spp, json_integer(o->spp[k]));
  for (int k = 0; k < o->nrho; k++)
    json_array_append_new(rho, num(o->rho[k]));
  return json_pack("{s:s, s:o, s:s, s:i, s:i, s:i, s:i, s:b, s:o, s:o, s:i, s:b, s:b, s:I}",
                   "command", command, "scene", o->scene ? json_string(o->scene) : json_null(),
                   "method", o->method->name, "width", width, "height", height, "threads",
                   o->threads, "runs", o->runs, "quick", o->quick, "spp", spp, "rho", rho,
                   "sweep_spp", o->sweep_spp, "sweep", o->sweep, "peer", o->peer, "only",
                   (json_int_t)o->only);
}

/* Options of the run from its configuration (o->scene points into c). */
static int config_in(json_t *c, val_figures_opts_t *o, int *width, int *height) {
  json_t *spp = json_object_get(c, "spp"), *rho = json_object_get(c, "rho"),
         *scene = json_object_get(c, "scene");
  const char *method = json_string_value(json_object_get(c, "method"));
  int ok = json_is_array(spp) && json_is_array(rho) && json_array_size(spp) <= VAL_MAX_SPP &&
           json_array_size(rho) <= VAL_MAX_RHO && method && rn_find(method) &&
           (json_is_null(scene) || json_is_string(scene));
  if (!ok)
    return 0;
  o->method = rn_find(method);
  o->scene = json_is_string(scene) ? json_string_value(scene) : NULL;
  *width = (int)json_integer_value(json_object_get(c, "width"));
  *height = (int)json_integer_value(json_object_get(c, "height"));
  o->threads = (int)json_integer_value(json_object_get(c, "threads"));
  o->runs = (int)json_integer_value(json_object_get(c, "runs"));
  o->quick = json_is_true(json_object_get(c, "quick"));
  o->sweep_spp = (int)json_integer_value(json_object_get(c, "sweep_spp"));
  o->sweep = json_is_true(json_object_get(c, "sweep"));
  o->peer = json_is_true(json_object_get(c, "peer"));
  o->only = (unsigned)json_integer_value(json_object_get(c, "only"));
  o->nspp = (int)json_array_size(spp);
  for (int k = 0; k < o->nspp; k++)
    o->spp[k] = (int)json_integer_value(json_array_get(spp, (size_t)k));
  o->nrho = (int)json_array_size(rho);
  for (int k = 0; ok && k < o->nrho; k++)
    ok = num_in(json_array_get(rho, (size_t)k), &o->rho[k]);
  return ok && *width > 0 && *height > 0;
}

/* ---- shard files --------------------------------------------------------------------------- */

static json_t *item_json(val_item_t it, const val_results_t *r) {
  switch (it.kind) {
  case VAL_ITEM_FIG9:
    return json_pack("{s:o}", "timing", timing_json(&r->fig9[it.index]));
  case VAL_ITEM_FIG8:
    return json_pack("{s:o}", "errors", errors_json(&r->fig10));
  case VAL_ITEM_TARGET:
    return json_pack("{s:o}", "errors", errors_json(&r->t49));
  case VAL_ITEM_TARGET_CERT:
    return json_pack("{s:o}", "errors", errors_json(&r->c49));
  case VAL_ITEM_TIME_CERT:
    return json_pack("{s:o}", "timing", timing_json(&r->tc49));
  case VAL_ITEM_NOACC:
    return json_pack("{s:o}", "timing", timing_json(&r->floor));
  case VAL_ITEM_NOACC_CERT:
    return json_pack("{s:o}", "timing", timing_json(&r->cfloor));
  default:
    return json_pack("{s:o, s:o}", "timing", timing_json(&r->sweep[it.index].t), "errors",
                     errors_json(&r->sweep[it.index].e));
  }
}

static int item_in(val_item_t it, json_t *j, val_results_t *r) {
  json_t *t = json_object_get(j, "timing"), *e = json_object_get(j, "errors");
  switch (it.kind) {
  case VAL_ITEM_FIG9:
    return timing_in(t, &r->fig9[it.index]);
  case VAL_ITEM_FIG8:
    return errors_in(e, &r->fig10);
  case VAL_ITEM_TARGET:
    return errors_in(e, &r->t49);
  case VAL_ITEM_TARGET_CERT:
    return errors_in(e, &r->c49);
  case VAL_ITEM_TIME_CERT:
    return timing_in(t, &r->tc49);
  case VAL_ITEM_NOACC:
    return timing_in(t, &r->floor);
  case VAL_ITEM_NOACC_CERT:
    return timing_in(t, &r->cfloor);
  default:
    return timing_in(t, &r->sweep[it.index].t) && errors_in(e, &r->sweep[it.index].e);
  }
}

int val__shard_write(const val_figures_opts_t *o, const char *command, json_t *config,
                     const val_item_t *items, int nitems, const val_results_t *r) {
  char dir[4096], path[4200], err[1024];
  snprintf(dir, sizeof dir, "%s/shards", o->out_dir);
  if (mkdir(dir, 0777) != 0 && errno != EEXIST)
    return fprintf(stderr, "%s: cannot create directory %s\n", io_command(), dir), -1;
  snprintf(path, sizeof path, "%s/%s-%d-of-%d.json", dir, command, o->shard, o->nshards);
  json_t *done = json_object();
  for (int j = 0; j < nitems; j++)
    if (j % o->nshards == o->shard - 1) {
      char name[64];
      val__item_name(items[j], o, name, sizeof name);
      json_object_set_new(done, name, item_json(items[j], r));
    }
  json_t *root = json_pack("{s:i, s:i, s:O, s:o}", "shard", o->shard, "of", o->nshards, "config",
                           config, "items", done);
  int rc = root ? io_json_write(path, root, err, sizeof err) : -1;
  if (rc != 0)
    fprintf(stderr, "%s: %s\n", io_command(), root ? err : "out of memory");
  json_decref(root);
  return rc;
}

/* 1 when name is COMMAND-K-of-N.json, with K and N. */
static int shard_name(const char *name, const char *command, int *k, int *n) {
  size_t len = strlen(command);
  char tail;
  return strncmp(name, command, len) == 0 && name[len] == '-' &&
         sscanf(name + len + 1, "%d-of-%d.jso%c", k, n, &tail) == 3 && tail == 'n' &&
         strcmp(name + strlen(name) - 5, ".json") == 0;
}

int val__shard_merge(val_figures_opts_t *o, const char *command, int *width, int *height,
                     val_results_t *r, json_t **keep) {
  char dir[4096];
  snprintf(dir, sizeof dir, "%s/shards", o->out_dir);
  DIR *d = opendir(dir);
  if (!d)
    return fprintf(stderr, "pencil %s --merge: no shard files in %s\n", command, dir), -1;
  json_t *config = NULL, *files[VAL_MAX_ITEMS + 1] = {0};
  int nshards = 0, rc = 0;
  for (struct dirent *e; rc == 0 && (e = readdir(d));) {
    int k, n;
    if (!shard_name(e->d_name, command, &k, &n))
      continue;
    char path[4400];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    json_error_t je;
    json_t *f = json_load_file(path, 0, &je);
    if (nshards == 0)
      nshards = n;
    if (!f || n != nshards || k < 1 || k > n || n > VAL_MAX_ITEMS || files[k]) {
      fprintf(stderr, "pencil %s --merge: %s: %s\n", command, path,
              !f             ? je.text
              : n != nshards ? "its shard count differs from the others'"
                             : "a shard number out of range or seen twice");
      json_decref(f);
      rc = -1;
      break;
    }
    files[k] = f;
    json_t *c = json_object_get(f, "config");
    if (!config)
      config = c;
    else if (!json_equal(config, c)) {
      fprintf(stderr,
              "pencil %s --merge: %s is a shard of another run (its configuration "
              "differs)\n",
              command, path);
      rc = -1;
    }
  }
  closedir(d);
  for (int k = 1; rc == 0 && k <= nshards; k++)
    if (!files[k]) {
      fprintf(stderr, "pencil %s --merge: shard %d of %d is missing (%s/%s-%d-of-%d.json)\n",
              command, k, nshards, dir, command, k, nshards);
      rc = -1;
    }
  if (rc == 0 && (!config || !config_in(config, o, width, height))) {
    fprintf(stderr, "pencil %s --merge: %s\n", command,
            config ? "a shard's configuration is not readable" : "no shard files found");
    rc = -1;
  }
  val_item_t items[VAL_MAX_ITEMS];
  int nitems = rc == 0 ? val__items(o, strcmp(command, "sweep") == 0, items) : 0;
  if (rc == 0)
    val__results_init(o, r);
  for (int j = 0; rc == 0 && j < nitems; j++) { /* every item once, from the shard that ran it */
    char name[64];
    val__item_name(items[j], o, name, sizeof name);
    json_t *it = json_object_get(json_object_get(files[j % nshards + 1], "items"), name);
    if (!it || !item_in(items[j], it, r)) {
      fprintf(stderr, "pencil %s --merge: shard %d of %d lacks a readable '%s'\n", command,
              j % nshards + 1, nshards, name);
      rc = -1;
    }
  }
  *keep = rc == 0 ? json_incref(config) : NULL;
  for (int k = 1; k <= VAL_MAX_ITEMS; k++)
    json_decref(files[k]);
  return rc;
}
