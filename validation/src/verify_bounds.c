/* verify_bounds.c -- `pencil verify bounds`: the error estimation functions of section 3.2 and
 * the Appendix (A-1 coefficients, general system (3), Eq. 4), the tolerance and spread limit
 * (Eqs. 3, 6) against exact tracing, for both variants of A-1, plus the Ceres-fitted empirical
 * constants and the third-order onset (docs/bounds.md describes the method). */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "io/json.h"
#include "io/output.h"
#include "validation/bounds.h"

/* Jets and __float128 differences must agree to this fraction of the tensor's scale. */
#define TENSOR_TOL 1e-7
/* Starting amplitude of the sampled exact errors for the fit (scaled; lowered where third-order
 * terms still show, val_sampled_error), __float128 rounding ~1e-20 of the sample. */
#define SAMPLE_EPS 1e-7
/* Spreads probed for the onset: NONSET points, log-spaced from ONSET_MIN to VAL_ONSET_MAX. */
#define ONSET_MIN 1e-4
#define NONSET 48

static const char *coef_names[VAL_NCOEF] = {"A", "B", "C", "D", "E", "F"};

/* ---- the sweep: val_sweep_build() plus pinhole -> glass sphere -> plane at several aims ---- */

/* Coefficient q (0..5: a..f) of k, without indexing past the struct's first member. */
static double coef_at(const px_coeffs_t *k, int q) {
  const double v[VAL_NCOEF] = {k->a, k->b, k->c, k->d, k->e, k->f};
  return v[q];
}

static void add_aimed(val_system_t *v, double n, double aim, int internal) {
  memset(v, 0, sizeof *v);
  double r = 1.0, dist = 4.0, floor_dist = 3.0;
  px_vec3_t pin = px_vec3(0, 0, -dist), dir;
  px_vec3_normalize(px_vec3_sub(px_vec3(aim * r, 0, 0), pin), &dir);
  ex_quadric_t sph = ex_quadric_sphere(px_vec3(0, 0, 0), r);
  size_t k = 0;
  v->stage[k++] = (ex_stage_t){sph, PX_EVENT_REFRACT, n, 0};
  if (internal)
    v->stage[k++] = (ex_stage_t){sph, PX_EVENT_REFLECT, n, 0};
  v->stage[k++] = (ex_stage_t){sph, PX_EVENT_REFRACT, 1.0, 0};
  px_frame_t f;
  px_frame_from_z(dir, px_vec3(0, 1, 0), &f);
  v->family = VAL_FAMILY_CASCADE;
  v->sys = (ex_system_t){pin, f, 1.0, NULL, k, floor_dist, 0.0};
  v->length = r;
  v->n1 = 1.0;
  v->n2 = n;
  v->radius = r;
  snprintf(v->label, sizeof v->label, "aim: pinhole -> sphere n %.3g R 1 aim %.2f%s -> plane at 3",
           n, aim, internal ? " (internal reflection)" : "");
}

val_system_t *val_bounds_sweep(int quick, size_t *count) {
  size_t n = 0;
  val_system_t *sw = val_sweep_build(1, quick, &n);
  if (!sw)
    return NULL;
  static const double aims[] = {0.0, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9};
  static const double idx[] = {1.33, 1.5, 2.42};
  size_t extra = quick ? 6 : 2 * 3 * 8;
  val_system_t *p = realloc(sw, (n + extra) * sizeof *p);
  if (!p) {
    free(sw);
    return NULL;
  }
  sw = p;
  for (int internal = 0; internal < 2; internal++)
    for (int i = 0; i < 3; i++)
      for (int a = 0; a < 8; a++) {
        if (quick && (i != 1 || (a != 0 && a != 4 && a != 6)))
          continue;
        add_aimed(&sw[n++], idx[i], aims[a], internal);
      }
  *count = n;
  return sw;
}

/* ---- one system ---- */

/* d_3m of A-1 for every element of the cascade built by ex_axial_cascade() (stage k gives an
 * optional transfer, then its interface). */
static px_status_t element_d3m(const val_system_t *v, const ex_axial_t *ax, const px_cascade_t *c,
                               double *d3m) {
  size_t k = 0;
  for (size_t i = 0; i < c->n; i++) {
    d3m[i] = 0.0;
    if (c->elem[i].kind == PX_ELEMENT_TRANSFER)
      continue;
    double cubic[4];
    px_status_t st = ex_quadric_cubic(&v->stage[k].surface, ax->hit[k], &ax->ifc[k], cubic);
    if (st != PX_OK)
      return st;
    d3m[i] = px_d3m(cubic);
    k++;
  }
  return PX_OK;
}

static double ratio_of(double bound, double truth, double zero) {
  if (truth <= zero) {
    if (bound < -zero)
      return -INFINITY; /* a negative "bound" of a zero error */
    return fabs(bound) <= zero ? NAN : INFINITY;
  }
  return bound / truth;
}

static void pinhole_analysis(const ex_system_t *sys, const ex_axial_t *ax, px_mat4_t t,
                             const val_system_t *v, val_bounds_result_t *r) {
  double L = v->length, zero = VAL_ZERO_TOL * r->truth.scale, ctrue = r->truth.coef[2];
  double e;
  r->err_at_probe = val_pinhole_error(sys, ax, t, L, 1e-2, &e) == PX_OK ? e : NAN;
  r->second_order_vanishes = ctrue <= zero && r->err_at_probe > 1e-12;
  /* empirical third-order coefficient: the full error beyond the true second-order term */
  r->k3 = 0.0;
  for (double x = 1e-3; x < 5e-3; x *= 2)
    if (val_pinhole_error(sys, ax, t, L, x, &e) == PX_OK)
      r->k3 = fmax(r->k3, (e - ctrue * x * x) / (x * x * x));
  for (int var = 0; var < 2; var++) {
    double cb = r->bound[var].c, prev = 0.0;
    r->onset[var] = INFINITY;
    for (int i = 0; i < NONSET; i++) {
      double x = ONSET_MIN * pow(VAL_ONSET_MAX / ONSET_MIN, (double)i / (NONSET - 1));
      if (val_pinhole_error(sys, ax, t, L, x, &e) != PX_OK)
        break; /* the pencil leaves the surfaces (miss, TIR) before the bound fails */
      if (e > cb * x * x * (1 + VAL_BOUND_SLACK)) {
        if (i == 0) { /* fails from the smallest spread on: a second-order failure */
          r->onset[var] = 0.0;
          break;
        }
        double lo = prev, hi = x;
        for (int it = 0; it < 30; it++) {
          double mid = sqrt(lo * hi);
          if (val_pinhole_error(sys, ax, t, L, mid, &e) == PX_OK &&
              e > cb * mid * mid * (1 + VAL_BOUND_SLACK))
            hi = mid;
          else
            lo = mid;
        }
        r->onset[var] = hi;
        break;
      }
      prev = x;
    }
  }
  /* Eq. (3) for rho = 1/2 and a direction interval of 1e-3 rad, then Eq. (6) with and without
   * the third-order term (cap VAL_ONSET_MAX) */
  double tau;
  if (px_tolerance(t, (px_ray4_t){{0, 0, 1e-3, 0}}, 0.5, &tau) == PX_OK && tau > 0) {
    r->tau = tau / L;
    double cc = r->bound[PX_VARIANT_CORRECTED].c;
    px_spread_limit(cc, 0.0, r->tau, VAL_ONSET_MAX, &r->spread[0], &r->regime[0]);
    px_spread_limit(cc, r->k3, r->tau, VAL_ONSET_MAX, &r->spread[1], &r->regime[1]);
    /* does the pencil at that spread meet the tolerance in exact tracing? */
    for (int m = 0; m < 2; m++)
      r->err_over_tau[m] = val_pinhole_error(sys, ax, t, L, r->spread[m], &e) == PX_OK
                               ? e / r->tau
                               : NAN; /* the pencil leaves a surface: no pencil that wide */
  }
}

static void fit_envelope_of(const ex_system_t *sys, const ex_axial_t *ax, const val_system_t *v,
                            val_bounds_result_t *r) {
  double samples[2][VAL_NPHI];
  r->sampled_vs_tensor = 0.0;
  double zero = VAL_ZERO_TOL * r->truth.scale, tens_max[2] = {0, 0};
  for (int k = 0; k < VAL_NPHI; k++) {
    tens_max[0] = fmax(tens_max[0], r->truth.ex[k]);
    tens_max[1] = fmax(tens_max[1], r->truth.exi[k]);
  }
  for (int part = 0; part < 2; part++)
    for (int k = 0; k < VAL_NPHI; k++) {
      const double *dir = part ? r->truth.dir_xi[k] : r->truth.dir_x[k];
      if (val_sampled_error(sys, ax, v->length, SAMPLE_EPS, val_phi(k), part, dir,
                            &samples[part][k], NULL) != PX_OK)
        return;
      double tens = part ? r->truth.exi[k] : r->truth.ex[k];
      /* compared where the worst case is not a near-zero of this system (1e-6 of its peak):
       * there the O(eps) third-order share is no longer small relative to it */
      if (tens > zero && tens > 1e-6 * tens_max[part])
        r->sampled_vs_tensor = fmax(r->sampled_vs_tensor, fabs(samples[part][k] / tens - 1.0));
    }
  double cx[3] = {samples[0][0], 0.0, samples[0][VAL_NPHI - 1]};
  double cxi[3] = {samples[1][0], 0.0, samples[1][VAL_NPHI - 1]};
  int okx = 1, okxi = 1;
  double tmax[2] = {0, 0};
  for (int k = 0; k < VAL_NPHI; k++)
    for (int p = 0; p < 2; p++)
      tmax[p] = fmax(tmax[p], samples[p][k]);
  /* A part whose true second-order worst case is zero in every shape (e.g. a sphere at normal
   * incidence) has no quadratic envelope to fit: its samples are third-order remnants. */
  if (tens_max[0] > zero && tmax[0] > zero)
    okx = val_fit_envelope(samples[0], cx, &r->fit_excess[0], &r->fit_dev[0]) == 0;
  else
    cx[0] = cx[1] = cx[2] = 0.0;
  if (tens_max[1] > zero && tmax[1] > zero)
    okxi = val_fit_envelope(samples[1], cxi, &r->fit_excess[1], &r->fit_dev[1]) == 0;
  else
    cxi[0] = cxi[1] = cxi[2] = 0.0;
  r->fit = (px_pencil_t){cx[0], cx[1], cx[2], cxi[0], cxi[1], cxi[2]};
  r->fitted = okx && okxi ? 1 : -1;
}

void val_verify_bounds_one(const val_system_t *v, int with_fit, val_bounds_result_t *r) {
  memset(r, 0, sizeof *r);
  for (int var = 0; var < 2; var++)
    r->onset[var] = INFINITY;
  if (v->expect_tir) {
    r->status = PX_ETIR;
    return;
  }
  ex_system_t sys = val_system_bind(v);
  ex_axial_t ax;
  px_element_t buf[2 * EX_MAX_STAGES + 2];
  double d3m[2 * EX_MAX_STAGES + 2];
  px_cascade_t c;
  px_status_t st = ex_trace_axial(&sys, &ax);
  if (st == PX_OK)
    st = ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 2 * EX_MAX_STAGES + 2, &c);
  if (st == PX_OK)
    st = element_d3m(v, &ax, &c, d3m);
  px_pencil_t k[2];
  /* Both variants of A-1 with the same (corrected, exact) system matrices in the weights, so
   * that the comparison isolates the coefficients. */
  for (int var = 0; var < 2 && st == PX_OK; var++)
    st = px_pencil_constants(&c, d3m, (px_variant_t)var, &k[var]);
  double hj[4][4][4], hq[4][4][4], zero4[4] = {0, 0, 0, 0};
  if (st == PX_OK)
    st = ex_map_jet(&sys, &ax, zero4, NULL, NULL, hj);
  if (st == PX_OK)
    st = ex_hessian_q(&sys, &ax, v->length, hq);
  r->status = st;
  if (st != PX_OK)
    return;
  r->theta_deg = ax.n ? atan2(px_vec3_norm(px_vec3_cross(ax.ifc[0].nu, ax.ifc[0].s)),
                              px_vec3_dot(ax.ifc[0].nu, ax.ifc[0].s)) *
                            180.0 / M_PI
                      : 0.0;
  val_truth_from_tensor(hj, v->length, &r->truth);
  double L = v->length, diff = 0.0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      for (int m = 0; m < 4; m++) {
        double w = (i < 2 ? 1.0 / L : 1.0) * (j < 2 ? L : 1.0) * (m < 2 ? L : 1.0);
        diff = fmax(diff, fabs(hj[i][j][m] - hq[i][j][m]) * w);
      }
  r->tensor_diff = diff / r->truth.scale;
  double zero = VAL_ZERO_TOL * r->truth.scale;
  for (int var = 0; var < 2; var++) {
    r->bound[var] = val_scale_pencil(&k[var], L);
    for (int q = 0; q < VAL_NCOEF; q++)
      r->ratio[var][q] = ratio_of(coef_at(&r->bound[var], q), r->truth.coef[q], zero);
    r->ratio_ex[var] = r->ratio_exi[var] = INFINITY;
    int any_x = 0, any_xi = 0; /* a shape where the true error or the bound is non-zero */
    for (int p = 0; p < VAL_NPHI; p++) {
      double rx = ratio_of(val_ex_scaled(&r->bound[var], val_phi(p)), r->truth.ex[p], zero);
      double rxi = ratio_of(val_exi_scaled(&r->bound[var], val_phi(p)), r->truth.exi[p], zero);
      any_x |= !isnan(rx);
      any_xi |= !isnan(rxi);
      if (!isnan(rx) && rx < r->ratio_ex[var]) {
        r->ratio_ex[var] = rx;
        r->phi_ex[var] = val_phi(p);
      }
      if (!isnan(rxi) && rxi < r->ratio_exi[var]) {
        r->ratio_exi[var] = rxi;
        r->phi_exi[var] = val_phi(p);
      }
    }
    if (!any_x) /* the system makes no position error and the bound says so */
      r->ratio_ex[var] = NAN;
    if (!any_xi)
      r->ratio_exi[var] = NAN;
  }
  px_mat4_t t = px_cascade_product(&c);
  r->pinhole = v->family == VAL_FAMILY_CASCADE;
  if (r->pinhole)
    pinhole_analysis(&sys, &ax, t, v, r);
  if (with_fit)
    fit_envelope_of(&sys, &ax, v, r);
}

/* ---- statistics and output ---- */

typedef struct {
  size_t finite, fail, vacuous, zero;
  double min, max, sum_log;
  size_t argmin;
} ratio_stats_t;

static void stats_init(ratio_stats_t *s) {
  memset(s, 0, sizeof *s);
  s->min = INFINITY;
  s->max = -INFINITY;
}

static void stats_add(ratio_stats_t *s, double r, size_t id) {
  if (isnan(r)) {
    s->zero++;
    return;
  }
  if (r < 1.0 - VAL_BOUND_SLACK)
    s->fail++;
  if (isinf(r) && r > 0) {
    s->vacuous++;
    return;
  }
  if (r < s->min) {
    s->min = r;
    s->argmin = id;
  }
  if (isfinite(r)) {
    s->finite++;
    s->max = fmax(s->max, r);
    if (r > 0)
      s->sum_log += log(r);
  }
}

static double stats_geomean(const ratio_stats_t *s) {
  return s->finite ? exp(s->sum_log / (double)s->finite) : NAN;
}

/* JSON cannot hold Inf/NaN: null */
static json_t *jnum(double x) {
  return isfinite(x) ? json_real(x) : json_null();
}

static json_t *stats_json(const ratio_stats_t *s, const val_system_t *sw) {
  json_t *o = json_object();
  json_object_set_new(o, "min", jnum(s->min));
  json_object_set_new(o, "max", jnum(s->max));
  json_object_set_new(o, "geometric_mean", jnum(stats_geomean(s)));
  json_object_set_new(o, "failures", json_integer((json_int_t)s->fail));
  json_object_set_new(o, "finite", json_integer((json_int_t)s->finite));
  json_object_set_new(o, "true_zero_bound_positive", json_integer((json_int_t)s->vacuous));
  json_object_set_new(o, "both_zero", json_integer((json_int_t)s->zero));
  json_object_set_new(o, "min_system", json_string(isfinite(s->min) ? sw[s->argmin].label : ""));
  return o;
}

/* DIR/NAME written to a temporary file and renamed when complete (io/output.h). */
static FILE *open_csv(const char *dir, const char *name, io_atomic_t *a, int *io_err) {
  char path[4096], err[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  if (io_csv_open(a, path, err, sizeof err) != 0) {
    fprintf(stderr, "pencil verify bounds: %s\n", err);
    *io_err = 1;
    return NULL;
  }
  return a->f;
}

static void close_csv(io_atomic_t *a, int *io_err) {
  char err[1024];
  if (io_atomic_commit(a, err, sizeof err) != 0) {
    fprintf(stderr, "pencil verify bounds: %s\n", err);
    *io_err = 1;
  }
}

static const char *event_name(const val_system_t *v) {
  return v->family == VAL_FAMILY_CASCADE || v->family == VAL_FAMILY_TRANSFER
             ? "system"
             : (v->event == PX_EVENT_REFLECT ? "reflect" : "refract");
}

static void systems_csv_row(FILE *f, size_t id, const val_system_t *v,
                            const val_bounds_result_t *r) {
  fprintf(f, "%zu,%s,%s,\"%s\",%.10g,%.10g,%.10g,%.10g,%d,%.10g,%s", id, val_family_name(v->family),
          event_name(v), v->label, r->theta_deg, v->n1, v->n2, v->radius, v->rotated, v->length,
          r->status == PX_OK ? "ok" : px_strerror(r->status));
  for (int q = 0; q < VAL_NCOEF; q++)
    fprintf(f, ",%.10g", r->truth.coef[q]);
  for (int var = 0; var < 2; var++) {
    for (int q = 0; q < VAL_NCOEF; q++)
      fprintf(f, ",%.10g", coef_at(&r->bound[var], q));
    for (int q = 0; q < VAL_NCOEF; q++)
      fprintf(f, ",%.10g", r->ratio[var][q]);
    fprintf(f, ",%.10g,%.10g", r->ratio_ex[var], r->ratio_exi[var]);
  }
  fprintf(f, ",%.3e\n", r->tensor_diff);
}

static void report_summary(FILE *f, ratio_stats_t st[2][VAL_NCOEF + 2], const val_system_t *sw,
                           size_t verified, size_t skipped) {
  fprintf(f,
          "pencil verify bounds: A-1 error coefficients and Eq. (4) vs. exact tracing\n"
          "(%zu systems verified, %zu skipped with a status; ratio = bound / true worst case\n"
          "over all directions, dimensionless with the system length; >= 1 means it holds)\n\n",
          verified, skipped);
  fprintf(f, "%-9s %-5s %11s %11s %11s %8s %8s %8s  %s\n", "variant", "coef", "min ratio",
          "max ratio", "geo mean", "failures", "true=0", "both=0", "worst system");
  for (int var = 0; var < 2; var++)
    for (int q = 0; q < VAL_NCOEF + 2; q++) {
      const ratio_stats_t *s = &st[var][q];
      const char *name = q < VAL_NCOEF ? coef_names[q] : (q == VAL_NCOEF ? "e_x" : "e_xi");
      fprintf(f, "%-9s %-5s %11.4g %11.4g %11.4g %8zu %8zu %8zu  %.60s\n",
              px_variant_name((px_variant_t)var), name, s->min, s->max, stats_geomean(s), s->fail,
              s->vacuous, s->zero, isfinite(s->min) ? sw[s->argmin].label : "-");
    }
  fprintf(f, "(true=0: the true term vanishes and the bound does not; both=0: exact zero)\n");
}

int val_verify_bounds(const val_bounds_opts_t *o) {
  size_t n = 0;
  val_system_t *sw = val_bounds_sweep(o->quick, &n);
  val_bounds_result_t *res = sw ? calloc(n, sizeof *res) : NULL;
  if (!res) {
    fprintf(stderr, "pencil verify bounds: out of memory building the sweep\n");
    free(sw);
    return -1;
  }
  /* the systems are independent (each result in its own slot), so the run is the same for any
   * number of threads */
  int done = 0, nt = o->threads > 0 ? o->threads : 1;
#ifdef _OPENMP
  if (o->threads <= 0)
    nt = omp_get_max_threads();
#endif
#pragma omp parallel for schedule(dynamic, 4) num_threads(nt)
  for (size_t i = 0; i < n; i++) {
    val_verify_bounds_one(&sw[i], !o->no_fit, &res[i]);
    if (o->progress) {
#pragma omp critical(val_bounds_progress)
      {
        done++;
        if (done == (int)n || done % 16 == 0)
          o->progress(o->progress_ctx, done, (int)n);
      }
    }
  }

  /* statistics: per variant x (A..F, e_x, e_xi); per family (corrected e_x, e_xi) */
  ratio_stats_t st[2][VAL_NCOEF + 2], fam[VAL_FAMILY_COUNT][2][2];
  for (int var = 0; var < 2; var++) {
    for (int q = 0; q < VAL_NCOEF + 2; q++)
      stats_init(&st[var][q]);
    for (int fa = 0; fa < VAL_FAMILY_COUNT; fa++)
      for (int p = 0; p < 2; p++)
        stats_init(&fam[fa][var][p]);
  }
  size_t verified = 0, skipped = 0, tensor_bad = 0, fits = 0, fit_bad = 0, fit_failed = 0;
  size_t pinholes = 0, vanish = 0, onset_found[2] = {0, 0}, onset_zero[2] = {0, 0};
  double tensor_worst = 0, fit_excess_worst = -INFINITY, fit_dev_worst = 0, sampled_worst = 0;
  double onset_min[2] = {INFINITY, INFINITY};
  for (size_t i = 0; i < n; i++) {
    const val_bounds_result_t *r = &res[i];
    if (r->status != PX_OK) {
      skipped++;
      continue;
    }
    verified++;
    tensor_worst = fmax(tensor_worst, r->tensor_diff);
    tensor_bad += r->tensor_diff > TENSOR_TOL;
    for (int var = 0; var < 2; var++) {
      for (int q = 0; q < VAL_NCOEF; q++)
        stats_add(&st[var][q], r->ratio[var][q], i);
      stats_add(&st[var][VAL_NCOEF], r->ratio_ex[var], i);
      stats_add(&st[var][VAL_NCOEF + 1], r->ratio_exi[var], i);
      stats_add(&fam[sw[i].family][var][0], r->ratio_ex[var], i);
      stats_add(&fam[sw[i].family][var][1], r->ratio_exi[var], i);
    }
    if (r->pinhole) {
      pinholes++;
      vanish += r->second_order_vanishes;
      for (int var = 0; var < 2; var++)
        if (isfinite(r->onset[var]) && !r->second_order_vanishes) {
          onset_found[var]++;
          if (r->onset[var] > 0)
            onset_min[var] = fmin(onset_min[var], r->onset[var]);
          else
            onset_zero[var]++;
        }
    }
    if (r->fitted) {
      fits++;
      if (r->fitted < 0) {
        fit_failed++;
        continue;
      }
      double ex = fmax(r->fit_excess[0], r->fit_excess[1]);
      double dv = fmax(r->fit_dev[0], r->fit_dev[1]);
      fit_excess_worst = fmax(fit_excess_worst, ex);
      fit_dev_worst = fmax(fit_dev_worst, dv);
      sampled_worst = fmax(sampled_worst, r->sampled_vs_tensor);
      fit_bad += ex > VAL_FIT_TOL || dv > VAL_FIT_TOL;
    }
  }
  size_t corrected_fail =
      st[PX_VARIANT_CORRECTED][VAL_NCOEF].fail + st[PX_VARIANT_CORRECTED][VAL_NCOEF + 1].fail;
  for (int q = 0; q < VAL_NCOEF; q++)
    corrected_fail += st[PX_VARIANT_CORRECTED][q].fail;

  FILE *f = o->report;
  if (f) {
    report_summary(f, st, sw, verified, skipped);
    fprintf(f, "\nper family (e_x, e_xi as wholes, min ratio over the pencil shapes):\n");
    fprintf(f, "%-10s %22s %22s %10s\n", "family", "corrected e_x / e_xi", "printed e_x / e_xi",
            "failures");
    for (int fa = 0; fa < VAL_FAMILY_COUNT; fa++)
      fprintf(f, "%-10s %10.4g / %-10.4g %10.4g / %-10.4g %4zu/%zu\n",
              val_family_name((val_family_t)fa), fam[fa][0][0].min, fam[fa][0][1].min,
              fam[fa][1][0].min, fam[fa][1][1].min, fam[fa][0][0].fail + fam[fa][0][1].fail,
              fam[fa][1][0].fail + fam[fa][1][1].fail);
    fprintf(f,
            "\nsecond-order tensor: jets vs __float128 differences, worst %.3g of the tensor "
            "scale (%zu above %.0e)\n",
            tensor_worst, tensor_bad, TENSOR_TOL);
    fprintf(f,
            "\nthird-order onset (pinhole pencils, %zu systems): spread xi0 where the full "
            "exact error first exceeds C xi0^2\n",
            pinholes);
    fprintf(f,
            "  corrected C: onset below %.2g rad in %zu systems, smallest %.4g rad, %zu failing "
            "from the smallest spread\n",
            VAL_ONSET_MAX, onset_found[0], onset_min[0], onset_zero[0]);
    fprintf(f,
            "  printed C:   onset below %.2g rad in %zu systems, smallest %.4g rad, %zu failing "
            "from the smallest spread\n",
            VAL_ONSET_MAX, onset_found[1], onset_min[1], onset_zero[1]);
    fprintf(f,
            "  second-order terms vanish but the error does not (C = 0, the bound fails at any "
            "spread): %zu systems\n",
            vanish);
    fprintf(f, "  %-56s %8s %8s %9s %8s %8s %7s %8s %7s\n", "system", "C", "onset", "err(1e-2)",
            "k3", "Eq.6", "err/tau", "with k3", "err/tau");
    for (size_t i = 0; i < n; i++) {
      const val_bounds_result_t *r = &res[i];
      if (r->status != PX_OK || !r->pinhole ||
          !(r->second_order_vanishes || strncmp(sw[i].label, "aim:", 4) == 0))
        continue;
      char ratio[2][16];
      for (int m = 0; m < 2; m++) /* NaN: at that spread the pencil leaves a surface */
        if (isnan(r->err_over_tau[m]))
          snprintf(ratio[m], sizeof ratio[m], "leaves");
        else
          snprintf(ratio[m], sizeof ratio[m], "%.3g", r->err_over_tau[m]);
      fprintf(f, "  %-56.56s %8.3g %8.3g %9.3g %8.3g %7.3g%s %7s %7.3g%s %7s\n",
              strncmp(sw[i].label, "aim: ", 5) == 0 ? sw[i].label + 5 : sw[i].label, r->bound[0].c,
              r->onset[0], r->err_at_probe, r->k3, r->spread[0],
              r->regime[0] == PX_SPREAD_CAP ? "*" : " ", ratio[0], r->spread[1],
              r->regime[1] == PX_SPREAD_THIRD_ORDER ? "3"
                                                    : (r->regime[1] == PX_SPREAD_CAP ? "*" : " "),
              ratio[1]);
    }
    fprintf(f,
            "  (corrected C, scaled by L; onset 0 = the bound fails from the smallest spread, inf "
            "= it holds\n   up to the cap;"
            " Eq.6 = spread limit\n   from C alone, * = only the cap %.2g rad limits it; with "
            "k3 = Eq. (6) plus the third-order term,\n   3 = third order decides; err/tau = "
            "full exact error at that spread over tau (> 1: too wide;\n   leaves: a pencil that "
            "wide misses a surface); tau of Eq. (3) for"
            " rho 1/2 and a direction interval of 1e-3 rad)\n",
            VAL_ONSET_MAX);
    size_t over[2] = {0, 0}, counted = 0;
    for (size_t i = 0; i < n; i++)
      if (res[i].status == PX_OK && res[i].pinhole && res[i].tau > 0) {
        counted++;
        for (int m = 0; m < 2; m++)
          over[m] += res[i].err_over_tau[m] > 1.0;
      }
    fprintf(f,
            "  spread limits too wide in exact tracing (err/tau > 1): Eq. (6) alone %zu, with the "
            "third-order term %zu, of %zu pinhole systems\n",
            over[0], over[1], counted);
    if (!o->no_fit)
      fprintf(f,
              "\nCeres fit (tightest non-negative quadratic envelope of sampled exact errors):"
              " %zu systems, %zu unusable,\n  worst excess of the samples over the envelope "
              "%.3g, worst deviation where attained %.3g (tolerance %.2g): %zu outside;\n  "
              "sampled exact vs tensor worst case: %.3g\n",
              fits, fit_failed, fit_excess_worst, fit_dev_worst, VAL_FIT_TOL, fit_bad,
              sampled_worst);
  }

  int io_err = 0;
  if (o->csv) {
    io_atomic_t ca;
    FILE *c = open_csv(o->csv, "bounds_systems.csv", &ca, &io_err);
    if (c) {
      fprintf(c, "id,family,event,label,theta_deg,n1,n2,radius,rotated,length,status");
      for (int q = 0; q < VAL_NCOEF; q++)
        fprintf(c, ",true_%s", coef_names[q]);
      for (int var = 0; var < 2; var++) {
        const char *vn = px_variant_name((px_variant_t)var);
        for (int q = 0; q < VAL_NCOEF; q++)
          fprintf(c, ",%s_%s", vn, coef_names[q]);
        for (int q = 0; q < VAL_NCOEF; q++)
          fprintf(c, ",%s_ratio_%s", vn, coef_names[q]);
        fprintf(c, ",%s_ratio_ex,%s_ratio_exi", vn, vn);
      }
      fprintf(c, ",tensor_diff\n");
      for (size_t i = 0; i < n; i++)
        systems_csv_row(c, i, &sw[i], &res[i]);
      close_csv(&ca, &io_err);
    }
    c = open_csv(o->csv, "bounds_summary.csv", &ca, &io_err);
    if (c) {
      fprintf(c, "variant,coefficient,min_ratio,max_ratio,geometric_mean,failures,finite,"
                 "true_zero_bound_positive,both_zero,min_system\n");
      for (int var = 0; var < 2; var++)
        for (int q = 0; q < VAL_NCOEF + 2; q++) {
          const ratio_stats_t *s = &st[var][q];
          fprintf(c, "%s,%s,%.10g,%.10g,%.10g,%zu,%zu,%zu,%zu,\"%s\"\n",
                  px_variant_name((px_variant_t)var),
                  q < VAL_NCOEF ? coef_names[q] : (q == VAL_NCOEF ? "e_x" : "e_xi"), s->min, s->max,
                  stats_geomean(s), s->fail, s->finite, s->vacuous, s->zero,
                  isfinite(s->min) ? sw[s->argmin].label : "");
        }
      close_csv(&ca, &io_err);
    }
    c = open_csv(o->csv, "bounds_families.csv", &ca, &io_err);
    if (c) {
      fprintf(c, "family,variant,min_ratio_ex,min_ratio_exi,failures\n");
      for (int fa = 0; fa < VAL_FAMILY_COUNT; fa++)
        for (int var = 0; var < 2; var++)
          fprintf(c, "%s,%s,%.10g,%.10g,%zu\n", val_family_name((val_family_t)fa),
                  px_variant_name((px_variant_t)var), fam[fa][var][0].min, fam[fa][var][1].min,
                  fam[fa][var][0].fail + fam[fa][var][1].fail);
      close_csv(&ca, &io_err);
    }
    c = open_csv(o->csv, "bounds_onset.csv", &ca, &io_err);
    if (c) {
      fprintf(c,
              "id,label,C_corrected,C_printed,C_true,second_order_vanishes,onset_corrected,"
              "onset_printed,err_at_1e-2,k3,tau,spread_eq6,regime_eq6,err_over_tau_eq6,spread_k3,"
              "regime_k3,err_over_tau_k3\n");
      static const char *reg[3] = {"second_order", "third_order", "cap"};
      for (size_t i = 0; i < n; i++) {
        const val_bounds_result_t *r = &res[i];
        if (r->status != PX_OK || !r->pinhole)
          continue;
        fprintf(c,
                "%zu,\"%s\",%.10g,%.10g,%.10g,%d,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%s,%.10g,"
                "%.10g,%s,%.10g\n",
                i, sw[i].label, r->bound[0].c, r->bound[1].c, r->truth.coef[2],
                r->second_order_vanishes, r->onset[0], r->onset[1], r->err_at_probe, r->k3, r->tau,
                r->spread[0], reg[r->regime[0]], r->err_over_tau[0], r->spread[1],
                reg[r->regime[1]], r->err_over_tau[1]);
      }
      close_csv(&ca, &io_err);
    }
    if (!o->no_fit) {
      c = open_csv(o->csv, "bounds_fit.csv", &ca, &io_err);
      if (c) {
        fprintf(c, "id,family,event,theta_deg,label");
        for (int q = 0; q < VAL_NCOEF; q++)
          fprintf(c, ",fit_%s,corrected_%s,printed_%s,true_%s", coef_names[q], coef_names[q],
                  coef_names[q], coef_names[q]);
        fprintf(c, ",fit_excess_x,fit_dev_x,fit_excess_xi,fit_dev_xi,sampled_vs_tensor,usable\n");
        for (size_t i = 0; i < n; i++) {
          const val_bounds_result_t *r = &res[i];
          if (r->status != PX_OK || !r->fitted)
            continue;
          fprintf(c, "%zu,%s,%s,%.10g,\"%s\"", i, val_family_name(sw[i].family), event_name(&sw[i]),
                  r->theta_deg, sw[i].label);
          for (int q = 0; q < VAL_NCOEF; q++)
            fprintf(c, ",%.10g,%.10g,%.10g,%.10g", coef_at(&r->fit, q), coef_at(&r->bound[0], q),
                    coef_at(&r->bound[1], q), r->truth.coef[q]);
          fprintf(c, ",%.4g,%.4g,%.4g,%.4g,%.4g,%d\n", r->fit_excess[0], r->fit_dev[0],
                  r->fit_excess[1], r->fit_dev[1], r->sampled_vs_tensor, r->fitted > 0);
        }
        close_csv(&ca, &io_err);
      }
    }
  }
  int pass =
      corrected_fail == 0 && tensor_bad == 0 && (o->no_fit || (fit_bad == 0 && fit_failed == 0));
  if (f)
    fprintf(f, "\nresult: corrected variant %s (%zu failures); %s\n",
            corrected_fail ? "FAILS" : "holds everywhere", corrected_fail, pass ? "PASS" : "FAIL");
  if (o->json) {
    json_t *root = json_object();
    json_object_set_new(root, "systems", json_integer((json_int_t)verified));
    json_object_set_new(root, "skipped", json_integer((json_int_t)skipped));
    json_object_set_new(root, "pass", json_boolean(pass));
    json_object_set_new(root, "corrected_failures", json_integer((json_int_t)corrected_fail));
    for (int var = 0; var < 2; var++) {
      json_t *vj = json_object();
      for (int q = 0; q < VAL_NCOEF + 2; q++)
        json_object_set_new(vj, q < VAL_NCOEF ? coef_names[q] : (q == VAL_NCOEF ? "e_x" : "e_xi"),
                            stats_json(&st[var][q], sw));
      json_object_set_new(root, px_variant_name((px_variant_t)var), vj);
    }
    json_object_set_new(root, "tensor_crosscheck",
                        json_pack("{s:o, s:I, s:f}", "worst", jnum(tensor_worst), "above_tolerance",
                                  (json_int_t)tensor_bad, "tolerance", TENSOR_TOL));
    json_object_set_new(root, "onset",
                        json_pack("{s:I, s:I, s:I, s:I, s:o, s:o, s:I, s:I}", "pinhole_systems",
                                  (json_int_t)pinholes, "second_order_vanishes", (json_int_t)vanish,
                                  "found_corrected", (json_int_t)onset_found[0], "found_printed",
                                  (json_int_t)onset_found[1], "smallest_corrected",
                                  jnum(onset_min[0]), "smallest_printed", jnum(onset_min[1]),
                                  "fails_from_start_corrected", (json_int_t)onset_zero[0],
                                  "fails_from_start_printed", (json_int_t)onset_zero[1]));
    if (!o->no_fit)
      json_object_set_new(root, "fit",
                          json_pack("{s:I, s:I, s:o, s:o, s:I, s:f, s:o}", "systems",
                                    (json_int_t)fits, "unusable", (json_int_t)fit_failed,
                                    "worst_excess", jnum(fit_excess_worst),
                                    "worst_attained_deviation", jnum(fit_dev_worst),
                                    "outside_tolerance", (json_int_t)fit_bad, "tolerance",
                                    VAL_FIT_TOL, "sampled_vs_tensor", jnum(sampled_worst)));
    char err[1024];
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil verify bounds: %s\n", err);
      io_err = 1;
    }
    json_decref(root);
  }
  free(res);
  free(sw);
  if (io_err)
    return -1;
  return pass ? 0 : 1;
}
