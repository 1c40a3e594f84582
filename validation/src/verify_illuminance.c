/* verify_illuminance.c -- `pencil verify illuminance`: Eqs. (8)-(9) of the 1987 paper
 * (px_spread_ratio) against the exact flux Jacobian of light paths (ex_flux_q: the area that
 * exactly traced rays cover on the receiver per unit of the source's measure), over
 *  - every system of the matrix sweep (transfers, planes, spheres of both signs, mirrors,
 *    cylinders, ellipsoids, cascades; several media), each with a point and a parallel source and
 *    a receiver at an angle from 0 to 89.9 degrees to the arriving ray;
 *  - receivers approaching the caustics of focusing systems (distance t* (1 + delta) from the
 *    last surface, t* where det B or det A vanishes), where the determinant's condition grows;
 * and the energy check of the 1989 Eq. (1)'s index factor on a pool (val_pool_flux_ratio). */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/json.h"
#include "io/output.h"
#include "io/scene_json.h"
#include "light/illuminance.h"
#include "validation/illuminance.h"
#include "validation/verify.h"

static const double alphas[] = {0.0, 25.0, 50.0, 70.0, 85.0, 89.9};
#define NALPHA (sizeof alphas / sizeof alphas[0])
static const double deltas[] = {1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8};
#define NDELTA (sizeof deltas / sizeof deltas[0])

/* The receiver normal at alpha to the output frame's z, turned by phi about it. */
static px_vec3_t receiver_normal(const px_frame_t *g, double alpha_deg, double phi_deg) {
  double a = alpha_deg * M_PI / 180, p = phi_deg * M_PI / 180;
  px_vec3_t n = px_vec3_scale(g->z, cos(a));
  n = px_vec3_add(n, px_vec3_scale(g->x1, sin(a) * cos(p)));
  return px_vec3_add(n, px_vec3_scale(g->x2, sin(a) * sin(p)));
}

/* The index after the last refraction of the system (the receiver's medium). */
static double final_index(const ex_system_t *s) {
  double n = s->n0;
  for (size_t k = 0; k < s->nstage; k++)
    if (s->stage[k].event == PX_EVENT_REFRACT)
      n = s->stage[k].n_after;
  return n;
}

void val_verify_illum_case(const val_system_t *v, px_source_t src, double tail, double alpha_deg,
                           double phi_deg, val_illum_result_t *r) {
  memset(r, 0, sizeof *r);
  ex_system_t sys = val_system_bind(v);
  if (tail > 0)
    sys.tail = tail;
  r->tail = sys.tail;
  r->n_source = sys.n0;
  r->n_receiver = final_index(&sys);
  ex_axial_t ax;
  px_element_t buf[2 * EX_MAX_STAGES + 2];
  px_cascade_t c;
  px_status_t st = ex_trace_axial(&sys, &ax);
  if (st == PX_OK)
    st = ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 2 * EX_MAX_STAGES + 2, &c);
  if (st != PX_OK) {
    r->status = r->exact_status = st;
    r->pass = 1; /* no axial path: nothing to compare (TIR and misses are verify matrices') */
    return;
  }
  px_vec3_t nrm = receiver_normal(&ax.out_frame, alpha_deg, phi_deg);
  r->cos_alpha = px_vec3_dot(nrm, ax.out_frame.z);
  px_mat4_t t = px_cascade_product(&c), ta = px_cascade_product_abs(&c);
  r->status = px_spread_ratio(&t, &ta, src, r->cos_alpha, &r->ratio, &r->cond);
  double area = 0.0;
  r->exact_status = ex_flux_q(&sys, &ax, nrm, src == PX_SOURCE_PARALLEL, v->length, &area);
  if (r->exact_status == PX_OK)
    r->exact = area > 0 ? 1.0 / area : INFINITY;
  px_mat4_t jac;
  int have_jac = r->exact_status == PX_OK && isfinite(r->exact) &&
                 ex_jacobian_q(&sys, &ax, v->length, &jac) == PX_OK;
  double jratio = 0.0;
  if (have_jac) { /* Eq. (8)/(9) from the exact block: the formula itself */
    int col = src == PX_SOURCE_POINT ? 2 : 0;
    double det = jac.m[0][col] * jac.m[1][col + 1] - jac.m[0][col + 1] * jac.m[1][col];
    jratio = fabs(r->cos_alpha) / fabs(det);
    r->formula_err = fabs(jratio - r->exact) / r->exact;
    px_mat4_t js = val_mat4_scaled(jac, v->length);
    px_mat4_t ds = val_mat4_scaled(t, v->length);
    double e = 0.0;
    for (int i = 0; i < 4; i++)
      for (int k = 0; k < 4; k++)
        e = fmax(e, fabs(ds.m[i][k] - js.m[i][k]));
    r->matrix_err = e / px_mat4_maxabs(js);
  }
  int formula_ok = have_jac && r->formula_err <= VAL_ILLUM_TOL;
  if (r->status == PX_OK && have_jac) {
    r->rel_err = fabs(r->ratio - r->exact) / r->exact;
    r->printed_err = fabs(r->ratio * r->n_source / r->n_receiver - r->exact) / r->exact;
    double tol = r->cond <= VAL_ILLUM_COND_AWAY
                     ? VAL_ILLUM_TOL
                     : fmax(VAL_ILLUM_TOL,
                            VAL_ILLUM_COND_FACTOR * r->cond * fmax(r->matrix_err, PX_ENTRY_EPS));
    r->pass = formula_ok && r->rel_err <= tol;
  } else if (r->status == PX_ECAUSTIC) {
    r->pass = r->cond * PX_ENTRY_EPS > PX_ACCURACY; /* refused where it cannot be accurate */
  } else {
    r->pass = r->status != PX_OK; /* both refused, or the formula refused (grazing) */
  }
}

/* The smallest positive distance t after the last surface where det(M0 + t N0) = 0 (M = B, N = D
 * for a point source; M = A, N = C for a parallel one), or 0 when there is none. */
static double caustic_distance(px_mat4_t t0, px_source_t src) {
  int col = src == PX_SOURCE_POINT ? 2 : 0;
  double m00 = t0.m[0][col], m01 = t0.m[0][col + 1], m10 = t0.m[1][col], m11 = t0.m[1][col + 1];
  double n00 = t0.m[2][col], n01 = t0.m[2][col + 1], n10 = t0.m[3][col], n11 = t0.m[3][col + 1];
  double a = n00 * n11 - n01 * n10, b = m00 * n11 + n00 * m11 - m01 * n10 - n01 * m10,
         c = m00 * m11 - m01 * m10, best = 0.0;
  double roots[2];
  int nr = 0;
  if (fabs(a) < 1e-14 * (fabs(b) + fabs(c))) {
    if (b != 0)
      roots[nr++] = -c / b;
  } else {
    double disc = b * b - 4 * a * c;
    if (disc >= 0) {
      double q = -0.5 * (b + copysign(sqrt(disc), b));
      roots[nr++] = q / a;
      if (q != 0)
        roots[nr++] = c / q;
    }
  }
  for (int i = 0; i < nr; i++)
    if (roots[i] > 1e-9 && (best == 0.0 || roots[i] < best))
      best = roots[i];
  return best;
}

double val_pool_flux_ratio(double h1, double h2, double n2, double theta0_deg, px_variant_t v) {
  enum { N = 4000 }; /* Simpson intervals */
  double th0 = theta0_deg * M_PI / 180, sum = 0.0;
  ex_stage_t water = {ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 1, 0)), PX_EVENT_REFRACT, n2,
                      0};
  for (int k = 0; k <= N; k++) {
    double th = th0 * k / N;
    double st = sin(th) / n2, ct = sqrt(1 - st * st);
    double r = h1 * tan(th) + h2 * st / ct;
    double dr = h1 / (cos(th) * cos(th)) + h2 / (ct * ct * ct) * cos(th) / n2;
    double f = 0.0;
    if (k > 0) {
      px_frame_t fr;
      px_frame_from_z(px_vec3(sin(th), -cos(th), 0), px_vec3(0, 0, 1), &fr);
      ex_system_t sys = {px_vec3(0, h1, 0), fr, 1.0, &water, 1, h2 / ct, 0.0};
      ex_axial_t ax;
      px_element_t buf[4];
      px_cascade_t c;
      px_mat4_t t;
      double e = 0.0;
      if (ex_trace_axial(&sys, &ax) != PX_OK ||
          ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 4, &c) != PX_OK)
        return NAN;
      t = px_cascade_product(&c);
      px_mat4_t ta = px_cascade_product_abs(&c);
      if (px_illuminance(&t, &ta, PX_SOURCE_POINT, ct, 1.0, 1.0, 1.0, n2, v, &e) != PX_OK)
        return NAN;
      f = e * 2 * M_PI * r * dr;
    }
    sum += f * (k == 0 || k == N ? 1 : k % 2 ? 4 : 2);
  }
  double flux = sum * th0 / (3 * N);
  return flux / (2 * M_PI * (1 - cos(th0)));
}

int val_pool_counted(double h1, double h2, double n2, double cell, double out[4]) {
  /* the water's surface a square of side 2 (a polygon, so that the light's grid covers only
   * it), the floor under it; kt 1 at the surface, no reflection */
  char json[2048], err[512];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
           " \"settings\": {\"max_depth\": 4},"
           " \"materials\": {\"floor\": {\"kd\": 0.8},"
           "  \"water\": {\"ka\": 0, \"kd\": 0, \"kr\": 0, \"kt\": 1, \"ior\": %.17g}},"
           " \"lights\": [{\"type\": \"point\", \"position\": [0, %.17g, 0]}],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           "  \"normal\": [0, 1, 0], \"material\": \"floor\"},"
           "  {\"type\": \"polygon\", \"name\": \"surface\", \"material\": \"water\","
           "   \"vertices\": [[-1, %.17g, -1], [-1, %.17g, 1], [1, %.17g, 1], [1, %.17g, -1]]}]}",
           n2, h1 + h2, h2, h2, h2, h2);
  rt_scene_t s;
  rt_scene_init(&s);
  if (io_scene_load_buffer("pool", json, strlen(json), &s, err, sizeof err) != 0) {
    fprintf(stderr, "pencil verify illuminance: %s\n", err);
    return 0;
  }
  const int floor_obj = 0;
  lt_receiver_t rc;
  lt_map_t m;
  int ok = lt_receiver_make(&s, &floor_obj, 1, &rc, err, sizeof err) == RT_OK &&
           lt_map_alloc(&m, 1, 1, -cell / 2, cell / 2, -cell / 2, cell / 2) == RT_OK;
  for (int method = 0; method < 2 && ok; method++) {
    lt_options_t o = LT_OPTIONS_DEFAULT;
    o.method = (lt_method_t)method;
    o.side = method == LT_METHOD_PHOTONS ? 1500 : 129;
    ok = lt_illuminance(&s, &rc, &o, &m, NULL) == RT_OK;
    out[method] = m.e[0];
  }
  if (ok)
    lt_map_free(&m);
  rt_scene_free(&s);
  /* Eq. (8) on the axis: B = (h1 + h2 / n2) I for a flat surface at normal incidence */
  double b = h1 + h2 / n2;
  out[2] = 1.0 / (b * b);
  out[3] = out[2] / n2;
  return ok;
}

/* Counters of a group of cases. */
typedef struct {
  size_t cases, failures, caustic, refused, compared, away, printed_off;
  double worst_away, worst_near, worst_printed, worst_formula;
  double worst_cond_ok; /* largest condition among the cases answered */
} stats_t;

static void accumulate(stats_t *s, const val_illum_result_t *r) {
  s->cases++;
  s->failures += !r->pass;
  if (r->status == PX_ECAUSTIC)
    s->caustic++;
  else if (r->status != PX_OK)
    s->refused++;
  if (r->status != PX_OK || r->exact_status != PX_OK)
    return;
  s->compared++;
  s->worst_cond_ok = fmax(s->worst_cond_ok, r->cond);
  s->worst_formula = fmax(s->worst_formula, r->formula_err);
  if (r->cond <= VAL_ILLUM_COND_AWAY) {
    s->away++;
    s->worst_away = fmax(s->worst_away, r->rel_err);
  } else {
    s->worst_near = fmax(s->worst_near, r->rel_err / (r->cond * fmax(r->matrix_err, PX_ENTRY_EPS)));
  }
  if (r->printed_err > VAL_ILLUM_TOL) {
    s->printed_off++;
    s->worst_printed = fmax(s->worst_printed, r->printed_err);
  }
}

static json_t *stats_json(const stats_t *s) {
  return json_pack(
      "{s:I, s:I, s:I, s:I, s:I, s:I, s:f, s:f, s:f, s:f, s:I, s:f}", "cases", (json_int_t)s->cases,
      "failures", (json_int_t)s->failures, "compared", (json_int_t)s->compared,
      "away_from_caustics", (json_int_t)s->away, "refused_caustic", (json_int_t)s->caustic,
      "refused_other", (json_int_t)s->refused, "worst_formula_error", s->worst_formula,
      "worst_relative_error_away", s->worst_away, "worst_error_over_condition_bound_near",
      s->worst_near, "largest_condition_answered", s->worst_cond_ok, "printed_eq1_off",
      (json_int_t)s->printed_off, "printed_eq1_worst", s->worst_printed);
}

static void csv_row(FILE *f, size_t id, const char *group, const val_system_t *v, px_source_t src,
                    double alpha, double delta, const val_illum_result_t *r) {
  fprintf(f,
          "%zu,%s,%s,\"%s\",%s,%.17g,%.17g,%.17g,%.17g,%.17g,%s,%s,%.17g,%.17g,%.6e,%.6e,%.6e,"
          "%.6e,%.6e,%d\n",
          id, group, val_family_name(v->family), v->label, px_source_name(src), alpha, r->cos_alpha,
          r->tail, delta, r->n_receiver / r->n_source,
          r->status == PX_OK ? "ok" : px_status_name(r->status),
          r->exact_status == PX_OK ? "ok" : px_status_name(r->exact_status), r->ratio, r->exact,
          r->cond, r->rel_err, r->formula_err, r->matrix_err, r->printed_err, r->pass);
}

static void report_line(FILE *f, const char *name, const stats_t *s) {
  fprintf(f, "%-9s %7zu %8zu %8zu %7zu %8zu %11.3e %11.3e %10.3e %9.2e\n", name, s->cases,
          s->failures, s->compared, s->away, s->caustic, s->worst_formula, s->worst_away,
          s->worst_near, s->worst_cond_ok);
}

int val_verify_illuminance(const val_illum_opts_t *o) {
  size_t n = 0;
  val_system_t *sw = val_sweep_build(1, o->quick, &n);
  if (!sw) {
    fprintf(stderr, "pencil verify illuminance: out of memory building the sweep\n");
    return -1;
  }
  io_atomic_t ca;
  char err[1024];
  FILE *csv = NULL;
  if (o->csv) {
    if (io_csv_open(&ca, o->csv, err, sizeof err) != 0) {
      fprintf(stderr, "pencil verify illuminance: %s\n", err);
      free(sw);
      return -1;
    }
    csv = ca.f;
    fprintf(csv, "id,group,family,label,source,alpha_deg,cos_alpha,tail,caustic_delta,"
                 "n_receiver_over_n_source,status,exact_status,ratio,exact,cond,rel_err,"
                 "formula_err,matrix_err,printed_rel_err,pass\n");
  }
  stats_t sweep[2], near[2], all;
  memset(sweep, 0, sizeof sweep);
  memset(near, 0, sizeof near);
  memset(&all, 0, sizeof all);
  size_t id = 0, caustic_per_family[VAL_FAMILY_COUNT] = {0};
  for (size_t i = 0; i < n; i++) {
    const val_system_t *v = &sw[i];
    if (v->expect_tir)
      continue;
    double tail = v->sys.tail > 1e-9 * v->length ? 0.0 : v->length; /* a receiver beyond O */
    for (int s = 0; s < 2; s++) {
      val_illum_result_t r;
      double alpha = alphas[(i + (size_t)s) % NALPHA], phi = fmod(37.0 * (double)i, 360.0);
      val_verify_illum_case(v, (px_source_t)s, tail, alpha, phi, &r);
      accumulate(&sweep[s], &r);
      accumulate(&all, &r);
      if (csv)
        csv_row(csv, id, "sweep", v, (px_source_t)s, alpha, 0.0, &r);
      if (!r.pass && o->report)
        fprintf(o->report,
                "FAIL #%zu %s (%s source, alpha %g): %s / exact %s, rel err %.3e, formula %.3e, "
                "cond %.3g\n",
                id, v->label, px_source_name((px_source_t)s), alpha, px_strerror(r.status),
                px_strerror(r.exact_status), r.rel_err, r.formula_err, r.cond);
      id++;
    }
    /* receivers approaching a caustic of this system, when it has one beyond its last surface */
    if (v->family == VAL_FAMILY_TRANSFER || caustic_per_family[v->family] >= (o->quick ? 3u : 80u))
      continue;
    ex_system_t sys = val_system_bind(v);
    sys.tail = 0.0;
    ex_axial_t ax;
    px_element_t buf[2 * EX_MAX_STAGES + 2];
    px_cascade_t c;
    if (ex_trace_axial(&sys, &ax) != PX_OK ||
        ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 2 * EX_MAX_STAGES + 2, &c) != PX_OK)
      continue;
    px_mat4_t t0 = px_cascade_product(&c);
    int any = 0;
    for (int s = 0; s < 2; s++) {
      /* a point source on the first surface (an at-origin system) has no caustic beyond it:
       * move it back by the system's length */
      val_system_t moved = *v;
      const val_system_t *u = v;
      if (s == PX_SOURCE_POINT && v->stage[0].at_origin) {
        moved.stage[0].at_origin = 0;
        moved.sys.origin = px_vec3_sub(v->sys.origin, px_vec3_scale(v->sys.frame.z, v->length));
        u = &moved;
        ex_system_t ms = val_system_bind(u);
        ms.tail = 0.0;
        px_cascade_t mc;
        if (ex_trace_axial(&ms, &ax) != PX_OK ||
            ex_axial_cascade(&ms, &ax, PX_VARIANT_CORRECTED, buf, 2 * EX_MAX_STAGES + 2, &mc) !=
                PX_OK)
          continue;
        t0 = px_cascade_product(&mc);
      }
      double ts = caustic_distance(t0, (px_source_t)s);
      if (!(ts > 0) || ts > 1e6 * v->length)
        continue;
      any = 1;
      for (size_t k = 0; k < NDELTA; k++) {
        val_illum_result_t r;
        val_verify_illum_case(u, (px_source_t)s, ts * (1 + deltas[k]), 0.0, 0.0, &r);
        accumulate(&near[s], &r);
        accumulate(&all, &r);
        if (csv)
          csv_row(csv, id, "caustic", u, (px_source_t)s, 0.0, deltas[k], &r);
        if (!r.pass && o->report)
          fprintf(o->report,
                  "FAIL #%zu %s (%s source, delta %g): %s / exact %s, rel err %.3e, "
                  "cond %.3g\n",
                  id, v->label, px_source_name((px_source_t)s), deltas[k], px_strerror(r.status),
                  px_strerror(r.exact_status), r.rel_err, r.cond);
        id++;
      }
    }
    caustic_per_family[v->family] += (size_t)any;
  }
  int io_err = csv && io_atomic_commit(&ca, err, sizeof err) != 0;
  if (io_err)
    fprintf(stderr, "pencil verify illuminance: %s\n", err);
  /* the pool: a light 2 above water (n 1.333), the floor 1 below the surface, cone of 40 deg */
  double pool_c = val_pool_flux_ratio(2.0, 1.0, 1.333, 40.0, PX_VARIANT_CORRECTED);
  double pool_p = val_pool_flux_ratio(2.0, 1.0, 1.333, 40.0, PX_VARIANT_PRINTED);
  double counted[4] = {NAN, NAN, NAN, NAN}; /* grid-pencil, photons, Eq. (8), printed Eq. (1) */
  if (!val_pool_counted(2.0, 1.0, 1.333, 0.2, counted)) {
    free(sw);
    return -1;
  }
  if (o->report) {
    fprintf(o->report,
            "pencil verify illuminance: Eqs. (8)-(9) (dOmega/dS = cos(alpha)/|det B|, dS0/dS = "
            "cos(alpha)/|det A|)\nvs. the exact flux Jacobian (__float128 differences of exactly "
            "traced rays' receiver hits).\nformula: the block of the exact Jacobian, tolerance "
            "%.0e everywhere; away: the system matrix's block where\nthe determinant's condition "
            "kappa <= %.0e, tolerance %.0e; near: error / (kappa x matrix error), at most %g;\n"
            "caustic: refused (PX_ECAUSTIC, kappa x %.1e > %.0e)\n\n",
            VAL_ILLUM_TOL, VAL_ILLUM_COND_AWAY, VAL_ILLUM_TOL, VAL_ILLUM_COND_FACTOR, PX_ENTRY_EPS,
            PX_ACCURACY);
    fprintf(o->report, "%-9s %7s %8s %8s %7s %8s %11s %11s %10s %9s\n", "group", "cases",
            "failures", "compared", "away", "caustic", "formula", "away", "near", "max kappa");
    report_line(o->report, "point", &sweep[0]);
    report_line(o->report, "parallel", &sweep[1]);
    report_line(o->report, "near pt", &near[0]);
    report_line(o->report, "near par", &near[1]);
    report_line(o->report, "all", &all);
    fprintf(o->report,
            "\n1989 Eq. (1) as printed (factor n1/n2): off by more than %.0e in %zu cases, worst "
            "%.3g\npool (light 2 above water of index 1.333, floor 1 below, 40 deg cone): flux on "
            "the floor / flux emitted = %.12f (Eq. 8), %.6f (printed Eq. 1)\n",
            VAL_ILLUM_TOL, all.printed_off, all.worst_printed, pool_c, pool_p);
    fprintf(o->report,
            "counted flux under the light (pencil illuminance, the pool's floor, a 0.2 x 0.2 cell "
            "on the axis): grid-pencil %.5f, photons %.5f; Eq. (8) %.5f, printed Eq. (1) %.5f\n",
            counted[0], counted[1], counted[2], counted[3]);
  }
  if (o->json) {
    json_t *root = json_pack(
        "{s:I, s:I, s:f, s:f, s:f, s:o, s:o, s:o, s:o, s:o, s:{s:f, s:f, s:f, s:f, s:f, s:f}}",
        "cases", (json_int_t)all.cases, "failures", (json_int_t)all.failures, "tolerance",
        VAL_ILLUM_TOL, "condition_away", VAL_ILLUM_COND_AWAY, "worst_relative_error_away",
        all.worst_away, "point", stats_json(&sweep[0]), "parallel", stats_json(&sweep[1]),
        "near_caustic_point", stats_json(&near[0]), "near_caustic_parallel", stats_json(&near[1]),
        "all", stats_json(&all), "pool", "h_air", 2.0, "h_water", 1.0, "n_water", 1.333, "cone_deg",
        40.0, "flux_ratio_eq8", pool_c, "flux_ratio_printed_eq1", pool_p);
    json_object_set_new(json_object_get(root, "pool"), "counted_axis",
                        json_pack("{s:f, s:f, s:f, s:f, s:f}", "cell", 0.2, "grid_pencil",
                                  counted[0], "photons", counted[1], "eq8", counted[2],
                                  "printed_eq1", counted[3]));
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil verify illuminance: %s\n", err);
      io_err = 1;
    }
    json_decref(root);
  }
  free(sw);
  if (io_err)
    return -1;
  return all.failures ? 1 : 0;
}
