/* verify_matrices.c -- `pencil verify matrices`: each system matrix (Eqs. 1-2 and cascades)
 * against the Jacobian of the exact Snell-law map, in both variants (corrected, printed).
 *
 * The comparison is made on the scaled matrix S = diag(1/L, 1/L, 1, 1) T diag(L, L, 1, 1),
 * which is dimensionless (A, D unchanged, B/L, C L) and invariant when the whole system is
 * scaled together with L; the error of a block is max |S - S_exact| over the block divided by
 * max |S_exact| over the matrix (docs/verification.md). */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/json.h"
#include "io/output.h"
#include "validation/verify.h"

px_mat4_t val_mat4_scaled(px_mat4_t t, double L) {
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      if (i < 2 && j >= 2)
        t.m[i][j] /= L;
      else if (i >= 2 && j < 2)
        t.m[i][j] *= L;
    }
  return t;
}

static void block_errors(px_mat4_t t, px_mat4_t j, double norm, double out[4], double *worst) {
  *worst = 0.0;
  for (int b = 0; b < 4; b++) {
    double e = 0.0;
    for (int r = 0; r < 2; r++)
      for (int c = 0; c < 2; c++) {
        int i = 2 * (b / 2) + r, k = 2 * (b % 2) + c;
        e = fmax(e, fabs(t.m[i][k] - j.m[i][k]));
      }
    out[b] = e / norm;
    *worst = fmax(*worst, out[b]);
  }
}

void val_verify_matrix(const val_system_t *v, val_matrix_result_t *r) {
  memset(r, 0, sizeof *r);
  ex_system_t sys = val_system_bind(v);
  ex_axial_t ax;
  px_status_t st = ex_trace_axial(&sys, &ax);
  if (v->expect_tir) { /* both the paraxial library and the exact tracer must refuse */
    px_mat4_t t;
    px_status_t sm = px_element_matrix(v->event, v->theta_deg * M_PI / 180, v->n1, v->n2, v->radius,
                                       PX_VARIANT_CORRECTED, &t);
    r->status = st;
    r->pass = st == PX_ETIR && sm == PX_ETIR;
    return;
  }
  px_element_t buf[2 * EX_MAX_STAGES + 2];
  px_cascade_t c, cp;
  px_mat4_t jac;
  if (st == PX_OK)
    st = ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 2 * EX_MAX_STAGES + 2, &c);
  if (st == PX_OK)
    st = ex_jacobian_q(&sys, &ax, v->length, &jac);
  r->status = st;
  if (st != PX_OK)
    return;
  px_mat4_t js = val_mat4_scaled(jac, v->length);
  r->jac_norm = px_mat4_maxabs(js);
  block_errors(val_mat4_scaled(px_cascade_product(&c), v->length), js, r->jac_norm, r->block_err,
               &r->rel_err);
  if (ex_axial_cascade(&sys, &ax, PX_VARIANT_PRINTED, buf, 2 * EX_MAX_STAGES + 2, &cp) == PX_OK)
    block_errors(val_mat4_scaled(px_cascade_product(&cp), v->length), js, r->jac_norm,
                 r->printed_block, &r->printed_err);
  r->pass = r->rel_err <= VAL_MATRIX_TOL;
}

typedef struct {
  size_t count, failures, tir;
  double worst;
  size_t printed_fail;
  double printed_worst[4];
  size_t printed_block_fail[4];
} family_stats_t;

static json_t *stats_json(const family_stats_t *s) {
  json_t *pb = json_object();
  static const char *blk[4] = {"A", "B", "C", "D"};
  for (int b = 0; b < 4; b++)
    json_object_set_new(pb, blk[b],
                        json_pack("{s:f, s:I}", "worst", s->printed_worst[b], "failures",
                                  (json_int_t)s->printed_block_fail[b]));
  return json_pack("{s:I, s:f, s:I, s:I, s:{s:I, s:o}}", "systems", (json_int_t)s->count,
                   "worst_relative_error", s->worst, "failures", (json_int_t)s->failures,
                   "tir_checked", (json_int_t)s->tir, "printed", "failures",
                   (json_int_t)s->printed_fail, "blocks", pb);
}

static void accumulate(family_stats_t *s, const val_system_t *v, const val_matrix_result_t *r) {
  s->count++;
  if (!r->pass)
    s->failures++;
  if (v->expect_tir) {
    s->tir++;
    return;
  }
  if (r->status != PX_OK)
    return;
  s->worst = fmax(s->worst, r->rel_err);
  if (r->printed_err > VAL_MATRIX_TOL)
    s->printed_fail++;
  for (int b = 0; b < 4; b++) {
    s->printed_worst[b] = fmax(s->printed_worst[b], r->printed_block[b]);
    if (r->printed_block[b] > VAL_MATRIX_TOL)
      s->printed_block_fail[b]++;
  }
}

static void csv_row(FILE *f, size_t id, const val_system_t *v, const val_matrix_result_t *r) {
  fprintf(f, "%zu,%s,%s,\"%s\",%.17g,%.17g,%.17g,%.17g,%d,%.17g,%s,%d", id,
          val_family_name(v->family), v->event == PX_EVENT_REFLECT ? "reflect" : "refract",
          v->label, v->theta_deg, v->n1, v->n2, v->radius, v->rotated, v->length,
          r->status == PX_OK ? "ok" : px_strerror(r->status), r->pass);
  fprintf(f, ",%.6e", r->rel_err);
  for (int b = 0; b < 4; b++)
    fprintf(f, ",%.6e", r->block_err[b]);
  fprintf(f, ",%.6e", r->printed_err);
  for (int b = 0; b < 4; b++)
    fprintf(f, ",%.6e", r->printed_block[b]);
  fprintf(f, "\n");
}

static void report(FILE *f, const family_stats_t *fam, const family_stats_t *all) {
  fprintf(f,
          "pencil verify matrices: system matrices vs. the Jacobian of exact Snell-law tracing\n"
          "(__float128 Richardson differences; tolerance %.0e on the scaled relative error)\n\n",
          VAL_MATRIX_TOL);
  fprintf(f, "%-10s %8s %8s %6s %14s | %-28s\n", "family", "systems", "failures", "TIR",
          "worst rel err", "printed Eq.(2): failing A/B/C/D");
  for (int i = 0; i <= VAL_FAMILY_COUNT; i++) {
    const family_stats_t *s = i < VAL_FAMILY_COUNT ? &fam[i] : all;
    if (i == VAL_FAMILY_COUNT)
      fprintf(f, "%.*s\n", 82,
              "----------------------------------------------------------------"
              "------------------------------------");
    fprintf(f, "%-10s %8zu %8zu %6zu %14.3e | %6zu/%zu/%zu/%zu\n",
            i < VAL_FAMILY_COUNT ? val_family_name((val_family_t)i) : "all", s->count, s->failures,
            s->tir, s->worst, s->printed_block_fail[0], s->printed_block_fail[1],
            s->printed_block_fail[2], s->printed_block_fail[3]);
  }
  fprintf(f,
          "\nprinted Eq. (2), worst block errors: A %.3g  B %.3g  C %.3g  D %.3g "
          "(docs/errata.md)\n",
          all->printed_worst[0], all->printed_worst[1], all->printed_worst[2],
          all->printed_worst[3]);
}

/* Evidence for docs/errata.md: three systems with the exact Jacobian beside both variants. */
typedef struct {
  const char *name;
  px_event_t ev;
  double theta_deg, n1, n2, radius, phi_in, phi_out;
} evidence_t;

static const evidence_t evidence[] = {
    {"E1/E2: glass ball entered from outside, theta 30, n 1->1.5, R 2, paper frames",
     PX_EVENT_REFRACT, 30, 1.0, 1.5, 2.0, 0.0, 0.0},
    {"E3: the same surface, frames rotated about the rays by 0.7 and -0.4 rad", PX_EVENT_REFRACT,
     30, 1.0, 1.5, 2.0, 0.7, -0.4},
    {"E2 (reflection): concave mirror, theta 20, R -3, paper frames", PX_EVENT_REFLECT, 20, 1.0,
     1.0, -3.0, 0.0, 0.0},
};

static void print_matrix(FILE *f, const char *name, px_mat4_t t) {
  for (int i = 0; i < 4; i++)
    fprintf(f, "  %-10s [% .10f % .10f % .10f % .10f]\n", i ? "" : name, t.m[i][0], t.m[i][1],
            t.m[i][2], t.m[i][3]);
}

static json_t *matrix_json(px_mat4_t t) {
  json_t *a = json_array();
  for (int i = 0; i < 4; i++)
    json_array_append_new(a, json_pack("[f, f, f, f]", t.m[i][0], t.m[i][1], t.m[i][2], t.m[i][3]));
  return a;
}

/* One evidence system: exact Jacobian, corrected and printed matrices; NULL on failure. */
static json_t *run_evidence(const evidence_t *e, FILE *report) {
  double th = e->theta_deg * M_PI / 180;
  px_vec3_t s = px_vec3(sin(th), 0, cos(th));
  ex_stage_t st = {ex_quadric_sphere(px_vec3(0, 0, e->radius), fabs(e->radius)), e->ev, e->n2, 1};
  px_frame_t f;
  px_frame_from_z(s, px_vec3(0, 1, 0), &f);
  ex_system_t sys = {px_vec3(0, 0, 0), px_frame_rotate(f, e->phi_in), e->n1, &st, 1, 0.0,
                     e->phi_out};
  ex_axial_t ax;
  px_element_t buf[4];
  px_cascade_t c, p;
  px_mat4_t j;
  if (ex_trace_axial(&sys, &ax) != PX_OK ||
      ex_jacobian_q(&sys, &ax, fabs(e->radius), &j) != PX_OK ||
      ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 2, &c) != PX_OK ||
      ex_axial_cascade(&sys, &ax, PX_VARIANT_PRINTED, buf + 2, 2, &p) != PX_OK)
    return NULL;
  px_mat4_t tc = px_cascade_product(&c), tp = px_cascade_product(&p);
  if (report) {
    fprintf(report, "\n%s\n", e->name);
    print_matrix(report, "exact", j);
    print_matrix(report, "corrected", tc);
    print_matrix(report, "printed", tp);
  }
  return json_pack("{s:s, s:o, s:o, s:o}", "system", e->name, "exact", matrix_json(j), "corrected",
                   matrix_json(tc), "printed", matrix_json(tp));
}

int val_verify_matrices(const val_matrices_opts_t *o) {
  size_t n = 0;
  val_system_t *sw = val_sweep_build(1, o->quick, &n);
  if (!sw) {
    fprintf(stderr, "pencil verify matrices: out of memory building the sweep\n");
    return -1;
  }
  FILE *csv = NULL;
  io_atomic_t ca; /* the CSV is written to a temporary file and renamed when complete */
  char err[1024];
  if (o->csv && io_csv_open(&ca, o->csv, err, sizeof err) != 0) {
    fprintf(stderr, "pencil verify matrices: %s\n", err);
    free(sw);
    return -1;
  }
  if (o->csv)
    csv = ca.f;
  if (csv)
    fprintf(csv, "id,family,event,label,theta_deg,n1,n2,radius,rotated,length,status,pass,"
                 "rel_err,err_A,err_B,err_C,err_D,printed_rel_err,printed_A,printed_B,"
                 "printed_C,printed_D\n");
  family_stats_t fam[VAL_FAMILY_COUNT], all;
  memset(fam, 0, sizeof fam);
  memset(&all, 0, sizeof all);
  size_t worst_id = 0;
  for (size_t i = 0; i < n; i++) {
    val_matrix_result_t r;
    val_verify_matrix(&sw[i], &r);
    accumulate(&fam[sw[i].family], &sw[i], &r);
    if (r.rel_err > all.worst)
      worst_id = i;
    accumulate(&all, &sw[i], &r);
    if (csv)
      csv_row(csv, i, &sw[i], &r);
    if (!r.pass && o->report)
      fprintf(o->report, "FAIL #%zu %s: %s, rel err %.3e\n", i, sw[i].label, px_strerror(r.status),
              r.rel_err);
  }
  int io_err = csv && io_atomic_commit(&ca, err, sizeof err) != 0;
  if (io_err)
    fprintf(stderr, "pencil verify matrices: %s\n", err);
  if (o->report) {
    report(o->report, fam, &all);
    fprintf(o->report, "worst system: #%zu %s\n", worst_id, sw[worst_id].label);
    fprintf(o->report, "\nErrata evidence (rows x1 x2 xi1 xi2; docs/errata.md):");
    for (size_t i = 0; i < sizeof evidence / sizeof evidence[0]; i++)
      if (!run_evidence(&evidence[i], o->report))
        fprintf(o->report, "\n(evidence system %zu could not be traced)\n", i);
    fprintf(o->report, "\n");
  }
  if (o->json) {
    json_t *root =
        json_pack("{s:I, s:f, s:I, s:f, s:s}", "systems", (json_int_t)all.count,
                  "worst_relative_error", all.worst, "failures", (json_int_t)all.failures,
                  "tolerance", VAL_MATRIX_TOL, "worst_system", sw[worst_id].label);
    json_t *fj = json_object();
    for (int i = 0; i < VAL_FAMILY_COUNT; i++)
      json_object_set_new(fj, val_family_name((val_family_t)i), stats_json(&fam[i]));
    json_object_set_new(root, "families", fj);
    json_object_set_new(root, "all", stats_json(&all));
    json_t *ev = json_array();
    for (size_t i = 0; i < sizeof evidence / sizeof evidence[0]; i++) {
      json_t *e = run_evidence(&evidence[i], NULL);
      if (e)
        json_array_append_new(ev, e);
    }
    json_object_set_new(root, "errata_evidence", ev);
    if (io_json_write(o->json, root, err, sizeof err) != 0) {
      fprintf(stderr, "pencil verify matrices: %s\n", err);
      io_err = 1;
    }
    json_decref(root);
  }
  size_t failures = all.failures;
  free(sw);
  if (io_err)
    return -1;
  return failures ? 1 : 0;
}
