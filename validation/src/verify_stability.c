/* verify_stability.c -- `pencil verify stability`: the counts over N randomized hard
 * configurations (stability_cases.c draws and checks each one): refused by reason, checked,
 * failures of the invariants, of the __float128 reference and of the exact-tracing Jacobian on
 * a sample, and silent NaN/Inf (docs/verification.md, "Stability"). */
#include <jansson.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "io/json.h"
#include "validation/stability.h"
#include "validation/timing.h"

#define NSTATUS (PX_ECAUSTIC + 1)
#define MAX_LISTED 10

typedef struct {
  uint64_t total, checked, refused[NSTATUS];
  uint64_t invariant_fail, reference_fail, accuracy_fail, refusal_wrong, returned_tir, nonfinite;
  uint64_t bounds_disagree;
  uint64_t sampled, sample_fail, sample_unresolved, sample_invariant_fail;
  double worst_err, worst_ratio, worst_bound, worst_sample_err;
} counts_t;

static void add_case(counts_t *c, const val_stab_case_t *k) {
  c->total++;
  if (k->status == PX_OK && !k->nonfinite)
    c->checked++;
  else if (k->status != PX_OK)
    c->refused[k->status]++;
  c->invariant_fail += (uint64_t)k->invariant_fail;
  c->reference_fail += (uint64_t)k->reference_fail;
  c->accuracy_fail += (uint64_t)k->accuracy_fail;
  c->refusal_wrong += (uint64_t)k->refusal_wrong;
  c->returned_tir += (uint64_t)k->returned_tir;
  c->bounds_disagree += (uint64_t)k->bounds_disagree;
  c->nonfinite += (uint64_t)k->nonfinite;
  c->sampled += (uint64_t)k->sampled;
  c->sample_fail += (uint64_t)k->sample_fail;
  c->sample_unresolved += (uint64_t)k->sample_unresolved;
  c->sample_invariant_fail += (uint64_t)k->sample_invariant_fail;
  if (k->status == PX_OK && !k->nonfinite && !k->returned_tir) {
    c->worst_err = fmax(c->worst_err, k->err);
    if (k->regime != VAL_STAB_CASCADE) /* a cascade's bound is propagated, not PX_ACCURACY */
      c->worst_bound = fmax(c->worst_bound, k->err_bound);
    if (k->err_bound > 0)
      c->worst_ratio = fmax(c->worst_ratio, k->err / k->err_bound);
  }
  if (k->sampled && !k->sample_unresolved && k->status == PX_OK)
    c->worst_sample_err = fmax(c->worst_sample_err, k->sample_err);
}

static void merge(counts_t *a, const counts_t *b) {
  a->total += b->total;
  a->checked += b->checked;
  for (int s = 0; s < NSTATUS; s++)
    a->refused[s] += b->refused[s];
  a->invariant_fail += b->invariant_fail;
  a->reference_fail += b->reference_fail;
  a->accuracy_fail += b->accuracy_fail;
  a->refusal_wrong += b->refusal_wrong;
  a->returned_tir += b->returned_tir;
  a->bounds_disagree += b->bounds_disagree;
  a->nonfinite += b->nonfinite;
  a->sampled += b->sampled;
  a->sample_fail += b->sample_fail;
  a->sample_unresolved += b->sample_unresolved;
  a->sample_invariant_fail += b->sample_invariant_fail;
  a->worst_err = fmax(a->worst_err, b->worst_err);
  a->worst_ratio = fmax(a->worst_ratio, b->worst_ratio);
  a->worst_bound = fmax(a->worst_bound, b->worst_bound);
  a->worst_sample_err = fmax(a->worst_sample_err, b->worst_sample_err);
}

static uint64_t failures(const counts_t *c) {
  return c->invariant_fail + c->reference_fail + c->accuracy_fail + c->refusal_wrong +
         c->returned_tir + c->nonfinite + c->sample_fail + c->sample_invariant_fail +
         c->bounds_disagree;
}

static int is_failure(const val_stab_case_t *k) {
  return k->invariant_fail || k->reference_fail || k->accuracy_fail || k->refusal_wrong ||
         k->returned_tir || k->nonfinite || k->sample_fail || k->sample_invariant_fail ||
         k->bounds_disagree;
}

static const px_status_t refusal_order[] = {PX_ETIR,       PX_EGRAZING, PX_EILLCOND,
                                            PX_ENONFINITE, PX_EINVAL,   PX_ESINGULAR};
static const char *const refusal_names[] = {"tir",      "grazing", "illcond",
                                            "overflow", "invalid", "singular"};
#define NREFUSAL 6

static void report(FILE *f, const counts_t *reg, const counts_t *all, double secs, uint64_t seed,
                   uint64_t every) {
  fprintf(f,
          "pencil verify stability: %llu randomized hard configurations (seed %llu), each refused\n"
          "with a status or checked against its stated accuracy (bound <= %.0e): invariants and\n"
          "Eq. (2) in __float128 on all, the exact-tracing Jacobian (__float128) on 1 in %llu\n\n",
          (unsigned long long)all->total, (unsigned long long)seed, PX_ACCURACY,
          (unsigned long long)every);
  fprintf(f, "%-10s %9s %9s %8s %8s %8s %8s %6s | %5s %5s %5s %5s %5s | %7s %5s %10s\n", "regime",
          "cases", "checked", "tir", "grazing", "illcond", "overflw", "other", "invar", "ref",
          "acc", "refus", "NaN", "sampled", "sfail", "worst err");
  for (int i = 0; i <= VAL_STAB_REGIMES; i++) {
    const counts_t *c = i < VAL_STAB_REGIMES ? &reg[i] : all;
    if (i == VAL_STAB_REGIMES)
      fprintf(f, "%.*s\n", 132,
              "------------------------------------------------------------------------------"
              "------------------------------------------------------------------------");
    uint64_t other = c->refused[PX_EINVAL] + c->refused[PX_ESINGULAR] + c->refused[PX_EMISS];
    fprintf(
        f,
        "%-10s %9llu %9llu %8llu %8llu %8llu %8llu %6llu | %5llu %5llu %5llu %5llu %5llu | "
        "%7llu %5llu %10.2e\n",
        i < VAL_STAB_REGIMES ? val_stab_regime_name((val_stab_regime_t)i) : "all",
        (unsigned long long)c->total, (unsigned long long)c->checked,
        (unsigned long long)c->refused[PX_ETIR], (unsigned long long)c->refused[PX_EGRAZING],
        (unsigned long long)c->refused[PX_EILLCOND], (unsigned long long)c->refused[PX_ENONFINITE],
        (unsigned long long)other, (unsigned long long)c->invariant_fail,
        (unsigned long long)c->reference_fail, (unsigned long long)c->accuracy_fail,
        (unsigned long long)(c->refusal_wrong + c->returned_tir), (unsigned long long)c->nonfinite,
        (unsigned long long)c->sampled, (unsigned long long)c->sample_fail, c->worst_err);
  }
  fprintf(f,
          "\nfailures: %llu (invariants %llu, beyond own bound %llu, beyond %.0e %llu, wrong "
          "refusals %llu, matrices at TIR %llu, silent NaN/Inf %llu, sample %llu, matrix and "
          "coefficients refusing differently %llu)\n"
          "worst error / own bound %.3g; largest element bound returned %.3g; sampled: %llu, "
          "%llu unresolved by the reference (its step sizes disagree), worst error %.3g;\n"
          "invariants on the exact Jacobian: %llu failures\n"
          "(worst err of all: single elements, within 1e-8; a cascade's is judged against its "
          "propagated bound)\ntime %.1f s\n",
          (unsigned long long)failures(all), (unsigned long long)all->invariant_fail,
          (unsigned long long)all->reference_fail, PX_ACCURACY,
          (unsigned long long)all->accuracy_fail, (unsigned long long)all->refusal_wrong,
          (unsigned long long)all->returned_tir, (unsigned long long)all->nonfinite,
          (unsigned long long)all->sample_fail, (unsigned long long)all->bounds_disagree,
          all->worst_ratio, all->worst_bound, (unsigned long long)all->sampled,
          (unsigned long long)all->sample_unresolved, all->worst_sample_err,
          (unsigned long long)all->sample_invariant_fail, secs);
}

static json_t *counts_json(const counts_t *c) {
  json_t *ref = json_object();
  for (int i = 0; i < NREFUSAL; i++)
    json_object_set_new(ref, refusal_names[i],
                        json_integer((json_int_t)c->refused[refusal_order[i]]));
  json_t *o = json_object();
  json_object_set_new(o, "total", json_integer((json_int_t)c->total));
  json_object_set_new(o, "checked", json_integer((json_int_t)c->checked));
  json_object_set_new(o, "refused", ref);
  json_object_set_new(o, "invariant_failures", json_integer((json_int_t)c->invariant_fail));
  json_object_set_new(o, "beyond_own_bound", json_integer((json_int_t)c->reference_fail));
  json_object_set_new(o, "beyond_accuracy", json_integer((json_int_t)c->accuracy_fail));
  json_object_set_new(o, "wrong_refusals", json_integer((json_int_t)c->refusal_wrong));
  json_object_set_new(o, "matrices_at_tir", json_integer((json_int_t)c->returned_tir));
  json_object_set_new(o, "silent_nonfinite", json_integer((json_int_t)c->nonfinite));
  json_object_set_new(o, "matrix_coefficients_disagree",
                      json_integer((json_int_t)c->bounds_disagree));
  json_object_set_new(o, "sampled", json_integer((json_int_t)c->sampled));
  json_object_set_new(o, "sampled_failures", json_integer((json_int_t)c->sample_fail));
  json_object_set_new(o, "sampled_unresolved", json_integer((json_int_t)c->sample_unresolved));
  json_object_set_new(o, "exact_jacobian_invariant_failures",
                      json_integer((json_int_t)c->sample_invariant_fail));
  json_object_set_new(o, "worst_error", io_json_number(c->worst_err));
  json_object_set_new(o, "worst_error_over_bound", io_json_number(c->worst_ratio));
  json_object_set_new(o, "largest_bound", io_json_number(c->worst_bound));
  json_object_set_new(o, "worst_sampled_error", io_json_number(c->worst_sample_err));
  return o;
}

int val_verify_stability(const val_stability_opts_t *o) {
  counts_t reg[VAL_STAB_REGIMES], all;
  memset(reg, 0, sizeof reg);
  memset(&all, 0, sizeof all);
  val_stab_case_t listed[MAX_LISTED];
  int nlisted = 0;
  uint64_t n = o->samples, every = o->sample_every ? o->sample_every : 1000;
  int nt = o->threads > 0 ? o->threads : omp_get_max_threads();
  uint64_t block = 10000, nblocks = (n + block - 1) / block, done = 0;
  double t0 = val_wall_seconds();
#pragma omp parallel num_threads(nt)
  {
    counts_t mine[VAL_STAB_REGIMES];
    memset(mine, 0, sizeof mine);
#pragma omp for schedule(dynamic, 1)
    for (uint64_t b = 0; b < nblocks; b++) {
      for (uint64_t i = b * block; i < n && i < (b + 1) * block; i++) {
        val_stab_case_t k;
        /* one in `every`, spread over the regimes (i mod VAL_STAB_REGIMES picks the regime) */
        val_stability_case(o->seed, i, (i / VAL_STAB_REGIMES) % every == 0, &k);
        add_case(&mine[k.regime], &k);
        if (is_failure(&k)) {
#pragma omp critical(val_stab_list)
          if (nlisted < MAX_LISTED)
            listed[nlisted++] = k;
        }
      }
      if (o->progress) {
#pragma omp critical(val_stab_progress)
        {
          done++;
          o->progress(o->progress_ctx, (int)done, (int)nblocks);
        }
      }
    }
#pragma omp critical(val_stab_merge)
    for (int r = 0; r < VAL_STAB_REGIMES; r++)
      merge(&reg[r], &mine[r]);
  }
  double secs = val_wall_seconds() - t0;
  for (int r = 0; r < VAL_STAB_REGIMES; r++) {
    double w = all.worst_err; /* the worst error of all: elements (a cascade has its own row) */
    merge(&all, &reg[r]);
    if (r == VAL_STAB_CASCADE)
      all.worst_err = w;
  }
  if (o->report) {
    report(o->report, reg, &all, secs, o->seed, every);
    for (int i = 0; i < nlisted; i++)
      fprintf(o->report, "FAIL %s: %s, error %.3g, bound %.3g%s%s%s%s%s%s\n", listed[i].label,
              px_strerror(listed[i].status), listed[i].err, listed[i].err_bound,
              listed[i].invariant_fail ? " [invariant]" : "",
              listed[i].reference_fail ? " [beyond bound]" : "",
              listed[i].refusal_wrong ? " [wrong refusal]" : "",
              listed[i].returned_tir ? " [matrix at TIR]" : "",
              listed[i].nonfinite         ? " [NaN/Inf]"
              : listed[i].bounds_disagree ? " [coefficients refuse differently]"
                                          : "",
              listed[i].sample_fail || listed[i].sample_invariant_fail ? " [sample]" : "");
  }
  int io_err = 0;
  if (o->json) {
    json_t *root = json_object();
    json_object_set_new(root, "samples", json_integer((json_int_t)n));
    json_object_set_new(root, "seed", json_integer((json_int_t)o->seed));
    json_object_set_new(root, "sample_every", json_integer((json_int_t)every));
    json_object_set_new(root, "accuracy", json_real(PX_ACCURACY));
    json_object_set_new(root, "seconds", json_real(secs));
    json_object_set_new(root, "threads", json_integer(nt));
    json_object_set_new(root, "failures", json_integer((json_int_t)failures(&all)));
    json_object_set_new(root, "all", counts_json(&all));
    json_t *rj = json_object();
    for (int r = 0; r < VAL_STAB_REGIMES; r++)
      json_object_set_new(rj, val_stab_regime_name((val_stab_regime_t)r), counts_json(&reg[r]));
    json_object_set_new(root, "regimes", rj);
    json_t *fl = json_array();
    for (int i = 0; i < nlisted; i++)
      json_array_append_new(fl, json_string(listed[i].label));
    json_object_set_new(root, "first_failures", fl);
    char err[1024];
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil verify stability: %s\n", err);
      io_err = 1;
    }
    json_decref(root);
  }
  if (io_err)
    return -1;
  return failures(&all) ? 1 : 0;
}
