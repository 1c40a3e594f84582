/* stability_cases.c -- the configurations of `pencil verify stability` and their checks: one
 * randomized hard configuration (grazing, the critical angle from both sides, total internal
 * reflection, normal incidence, n1 = n2 and nearly so, mirrors, radii 1e-12 .. 1e12 and planes,
 * an overflowing curvature now and then, rotated frames and cylinders; cascades through a
 * caustic) built through libparaxial's public calls as a user would, and checked against
 *  - the invariants of a system matrix of the paper's ray vectors (docs/verification.md):
 *    S^t J S = (n/n') J and det S = (n/n')^2;
 *  - Eq. (2) (corrected) evaluated in __float128 from the same double inputs, every case;
 *  - the __float128 Jacobian of exact Snell-law tracing (ex_jacobian_q), on a sample.
 * The error measure is the one of `pencil verify matrices`: max|S - S*| / max|S*| on the
 * scaled matrix S = diag(1/L, 1/L, 1, 1) T diag(L, L, 1, 1). */
#include <float.h>
#include <math.h>
#include <quadmath.h>
#include <stdio.h>
#include <string.h>

#include "exact/trace.h"
#include "validation/stability.h"
#include "validation/verify.h"

#define U (DBL_EPSILON / 2)

typedef __float128 q_t;
typedef struct {
  q_t x, y, z;
} qv_t;

static const char *const regime_names[VAL_STAB_REGIMES] = {
    "grazing", "crit_below", "crit_above", "tir",     "normal",
    "n1=n2",   "n1~n2",      "mirror",     "general", "cascade"};

const char *val_stab_regime_name(val_stab_regime_t r) {
  return r < VAL_STAB_REGIMES ? regime_names[r] : "?";
}

/* ---- the generator: splitmix64 on (seed, index), so a case does not depend on threads ---- */

typedef struct {
  uint64_t s;
} rng_t;

static uint64_t next64(rng_t *r) {
  uint64_t z = (r->s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static double uni(rng_t *r, double a, double b) {
  return a + (b - a) * ((double)(next64(r) >> 11) * 0x1.0p-53);
}
static double log_uni(rng_t *r, double lo_exp, double hi_exp) {
  return pow(10.0, uni(r, lo_exp, hi_exp));
}
static int coin(rng_t *r, double p) {
  return uni(r, 0, 1) < p;
}

/* One element as drawn: incidence in degrees, indices, curvature matrix, frame rotations. */
typedef struct {
  px_event_t ev;
  double theta_deg, n1, n2;
  double k1, k2, axis; /* principal curvatures and the angle of the first in (u1, u2) */
  double phi_in, phi_out;
} elem_cfg_t;

static double index_draw(rng_t *r) {
  static const double common[] = {1.0, 1.33, 1.4, 1.5, 1.7, 2.42};
  return coin(r, 0.5) ? common[next64(r) % 6] : uni(r, 1.0, 2.5);
}

static double curvature_draw(rng_t *r) {
  double u = uni(r, 0, 1);
  if (u < 0.1)
    return 0.0; /* a plane */
  if (u < 0.11) /* beyond what double can carry with its squares: must be refused */
    return (coin(r, 0.5) ? 1 : -1) * log_uni(r, 100, 300);
  return (coin(r, 0.5) ? 1 : -1) * log_uni(r, -12, 12); /* radii 1e-12 .. 1e12 */
}

static void draw_surface(rng_t *r, elem_cfg_t *e) {
  e->k1 = curvature_draw(r);
  e->k2 = e->k1;
  e->axis = 0.0;
  if (coin(r, 0.25)) { /* a cylinder or a saddle at a random orientation */
    e->k2 = coin(r, 0.5) ? 0.0 : e->k1 * uni(r, -2, 2);
    e->axis = uni(r, 0, M_PI);
  }
  int rot = coin(r, 0.5);
  e->phi_in = rot ? uni(r, 0, 2 * M_PI) : 0.0;
  e->phi_out = rot ? uni(r, 0, 2 * M_PI) : 0.0;
}

static double crit_deg(double n1, double n2) {
  return asin(n2 / n1) * 180.0 / M_PI;
}

/* pair with n1 > n2 (for the critical angle) */
static void dense_to_thin(rng_t *r, elem_cfg_t *e) {
  do {
    e->n1 = index_draw(r);
    e->n2 = index_draw(r);
  } while (e->n1 == e->n2);
  if (e->n1 < e->n2) {
    double t = e->n1;
    e->n1 = e->n2;
    e->n2 = t;
  }
}

static void draw_element(rng_t *r, val_stab_regime_t g, elem_cfg_t *e) {
  e->ev = PX_EVENT_REFRACT;
  e->n1 = index_draw(r);
  e->n2 = index_draw(r);
  switch (g) {
  case VAL_STAB_GRAZING:
    e->theta_deg = 90.0 - log_uni(r, -9, -1);
    break;
  case VAL_STAB_CRIT_BELOW:
    dense_to_thin(r, e);
    e->theta_deg = crit_deg(e->n1, e->n2) - log_uni(r, -13, -1);
    break;
  case VAL_STAB_CRIT_ABOVE:
    dense_to_thin(r, e);
    e->theta_deg = crit_deg(e->n1, e->n2) + log_uni(r, -13, -1);
    break;
  case VAL_STAB_TIR:
    dense_to_thin(r, e);
    e->theta_deg = uni(r, crit_deg(e->n1, e->n2), 90.0);
    break;
  case VAL_STAB_NORMAL:
    e->theta_deg = coin(r, 0.2) ? 0.0 : log_uni(r, -12, -1);
    break;
  case VAL_STAB_EQUAL:
    e->n2 = e->n1;
    e->theta_deg = coin(r, 0.5) ? 90.0 - log_uni(r, -12, -1) : uni(r, 0, 90);
    break;
  case VAL_STAB_CLOSE:
    e->n2 = e->n1 * (1.0 + (coin(r, 0.5) ? 1 : -1) * log_uni(r, -15, -3));
    e->theta_deg = coin(r, 0.5) ? 90.0 - log_uni(r, -12, -1) : uni(r, 0, 90);
    break;
  case VAL_STAB_REFLECT:
    e->ev = PX_EVENT_REFLECT;
    e->n2 = e->n1;
    e->theta_deg = coin(r, 0.5) ? 90.0 - log_uni(r, -12, -1) : uni(r, 0, 90);
    break;
  default:
    e->theta_deg = uni(r, 0, 90);
  }
  if (e->theta_deg < 0.0)
    e->theta_deg = 0.0;
  if (e->theta_deg > 90.0)
    e->theta_deg = 90.0;
  draw_surface(r, e);
}

static px_mat2_t curvature_matrix(const elem_cfg_t *e) {
  double c = cos(e->axis), s = sin(e->axis);
  return px_mat2(e->k1 * c * c + e->k2 * s * s, (e->k1 - e->k2) * c * s, (e->k1 - e->k2) * c * s,
                 e->k1 * s * s + e->k2 * c * c);
}

/* ---- the reference: Eq. (2) in __float128 from the double inputs as given ---- */

static qv_t qv(px_vec3_t v) {
  qv_t r = {v.x, v.y, v.z};
  return r;
}
static q_t qdot(qv_t a, qv_t b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static qv_t qcross(qv_t a, qv_t b) {
  qv_t r = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  return r;
}
static qv_t qunit(qv_t a) {
  q_t n = sqrtq(qdot(a, a));
  qv_t r = {a.x / n, a.y / n, a.z / n};
  return r;
}
static qv_t qaxpy(q_t a, qv_t x, qv_t y) {
  qv_t r = {a * x.x + y.x, a * x.y + y.y, a * x.z + y.z};
  return r;
}

typedef struct {
  q_t m[4][4];
} qmat_t;

static qmat_t qmul(const qmat_t *a, const qmat_t *b) {
  qmat_t r;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      q_t s = 0;
      for (int k = 0; k < 4; k++)
        s += a->m[i][k] * b->m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

static qmat_t qtransfer(double z) {
  qmat_t r;
  memset(&r, 0, sizeof r);
  for (int i = 0; i < 4; i++)
    r.m[i][i] = 1;
  r.m[0][2] = r.m[1][3] = z;
  return r;
}

/* The exact quantities of one element: cos^2 theta' (< 0: TIR), the cosines, the matrix. */
typedef struct {
  q_t c, k, cp;
  int tir;
  qmat_t t;
} qelem_t;

static void ref_element(const px_interface_t *f, px_event_t ev, const px_frame_t *in,
                        const px_frame_t *out, qelem_t *r) {
  qv_t s = qunit(qv(f->s)), nu = qunit(qv(f->nu)), u2 = qunit(qv(f->u2));
  q_t c = qdot(nu, s), eta, h, cp;
  qv_t sp;
  r->c = c;
  r->tir = 0;
  if (ev == PX_EVENT_REFLECT) {
    eta = 1;
    cp = -c;
    h = -2 * c;
    r->k = c * c;
  } else {
    q_t n1 = f->n1, n2 = f->n2;
    q_t one_m = (n2 - n1) * (n2 + n1) / (n2 * n2);
    eta = n1 / n2;
    r->k = one_m + eta * eta * c * c;
    if (r->k <= 0) {
      r->tir = 1;
      return;
    }
    cp = sqrtq(r->k);
    h = one_m / (cp + eta * c);
  }
  r->cp = cp;
  if (!in)
    return;
  sp = qaxpy(h, nu, (qv_t){eta * s.x, eta * s.y, eta * s.z}); /* eta s + h nu, unit */
  qv_t p1 = qcross(u2, s), pp1 = qcross(u2, sp);
  qv_t x1 = qv(in->x1), x2 = qv(in->x2), y1 = qv(out->x1), y2 = qv(out->x2);
  q_t p[2][2] = {{qdot(x1, p1), qdot(x1, u2)}, {qdot(x2, p1), qdot(x2, u2)}};
  q_t pp[2][2] = {{qdot(y1, pp1), qdot(y1, u2)}, {qdot(y2, pp1), qdot(y2, u2)}};
  q_t da[2] = {cp / c, 1}, dd[2] = {eta * c / cp, eta};
  q_t cq[2][2] = {{-h * (q_t)f->q.m[0][0] / (cp * c), -h * (q_t)f->q.m[0][1] / cp},
                  {-h * (q_t)f->q.m[1][0] / c, -h * (q_t)f->q.m[1][1]}};
  memset(&r->t, 0, sizeof r->t);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++) {
      q_t a = 0, cc = 0, d = 0;
      for (int k = 0; k < 2; k++) {
        a += pp[i][k] * da[k] * p[j][k];
        d += pp[i][k] * dd[k] * p[j][k];
        for (int l = 0; l < 2; l++)
          cc += pp[i][k] * cq[k][l] * p[j][l];
      }
      r->t.m[i][j] = a;
      r->t.m[2 + i][j] = cc;
      r->t.m[2 + i][2 + j] = d;
    }
}

/* ---- checks on a double matrix ---- */

static double rel_error_q(px_mat4_t t, const qmat_t *ex, double L) {
  q_t emax = 0, dmax = 0, ql = L;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      q_t sc = (i >= 2 && j < 2) ? ql : ((i < 2 && j >= 2) ? 1 / ql : 1);
      emax = fmaxq(emax, fabsq(ex->m[i][j] * sc));
      dmax = fmaxq(dmax, fabsq(((q_t)t.m[i][j] - ex->m[i][j]) * sc));
    }
  return (double)(dmax / emax);
}

static long double det4(px_mat4_t s) {
  long double a[4][4], det = 1;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      a[i][j] = s.m[i][j];
  for (int k = 0; k < 4; k++) {
    int p = k;
    for (int i = k + 1; i < 4; i++)
      if (fabsl(a[i][k]) > fabsl(a[p][k]))
        p = i;
    if (a[p][k] == 0)
      return 0;
    if (p != k) {
      for (int j = 0; j < 4; j++) {
        long double t = a[k][j];
        a[k][j] = a[p][j];
        a[p][j] = t;
      }
      det = -det;
    }
    det *= a[k][k];
    for (int i = k + 1; i < 4; i++) {
      long double f = a[i][k] / a[k][k];
      for (int j = k; j < 4; j++)
        a[i][j] -= f * a[k][j];
    }
  }
  return det;
}

/* The invariants of a matrix of the ray vectors (x, xi) with xi the unit direction's projection
 * (docs/verification.md): S^t J S = eta J with J = [[0, I], [-I, 0]], and det S = eta^2. With a
 * normwise relative error e of S (max norm), the computed S^t J S is off by at most
 * 2 * 2 e |S|^2 (two factors, sums of two products) and det S by 4! * 4 e |S|^4; both with
 * the rounding of this evaluation (long double) added. Returns 1 when both hold. */
static int invariants_hold(px_mat4_t s, double eta, double e) {
  double nrm = px_mat4_maxabs(s);
  double tol = 4.0 * (e + 4 * U) * nrm * nrm;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      long double v = 0;
      for (int k = 0; k < 2; k++) /* (S^t J S)_ij = sum_k S_ki S_(k+2)j - S_(k+2)i S_kj */
        v += (long double)s.m[k][i] * s.m[k + 2][j] - (long double)s.m[k + 2][i] * s.m[k][j];
      double want = (i < 2 && j == i + 2) ? eta : ((i >= 2 && j == i - 2) ? -eta : 0.0);
      if (!(fabsl(v - want) <= tol))
        return 0;
    }
  long double d = det4(s);
  double dtol = 96.0 * (e + 4 * U) * nrm * nrm * nrm * nrm;
  return fabsl(d - (long double)eta * eta) <= dtol;
}

/* ---- one element through the public calls ---- */

typedef struct {
  px_interface_t ifc;
  px_frame_t in, out;
  int built; /* 0: px_interface_make refused, 1: the interface, 2: and the frames */
  px_status_t st;
  px_mat4_t t;
  double err;
  double kmax; /* largest |Q| entry */
} elem_run_t;

/* Build the interface and frames as a user would, then the matrix. Without `in_given` the
 * surface is canonical (normal +z, incidence in the x-z plane) and the frames are the paper's
 * rotated by phi_in, phi_out; with it, the normal is at theta from s_dir in the azimuth e->axis
 * of in_given, and in_given is the input frame (a cascade's previous output frame). */
static void run_element(const elem_cfg_t *e, px_vec3_t s_dir, const px_frame_t *in_given,
                        elem_run_t *r) {
  double c, s;
  px_cos_sin_deg(e->theta_deg, &c, &s);
  px_mat2_t q = curvature_matrix(e);
  r->kmax = fmax(fmax(fabs(q.m[0][0]), fabs(q.m[0][1])), fabs(q.m[1][1]));
  r->err = NAN;
  r->built = 0;
  if (in_given) {
    px_vec3_t az = px_vec3_add(px_vec3_scale(in_given->x1, cos(e->axis)),
                               px_vec3_scale(in_given->x2, sin(e->axis)));
    px_vec3_t nu = px_vec3_add(px_vec3_scale(s_dir, c), px_vec3_scale(az, s));
    r->st = px_interface_make(s_dir, nu, in_given->x2, q, NULL, e->n1, e->n2, &r->ifc);
  } else {
    r->st = px_interface_make(px_vec3(s, 0.0, c), px_vec3(0, 0, 1), px_vec3(0, 1, 0), q, NULL,
                              e->n1, e->n2, &r->ifc);
  }
  if (r->st != PX_OK)
    return;
  r->built = 1;
  r->st = px_interface_frames(&r->ifc, e->ev, &r->in, &r->out);
  if (r->st != PX_OK)
    return;
  r->built = 2;
  r->in = in_given ? *in_given : px_frame_rotate(r->in, e->phi_in);
  r->out = px_frame_rotate(r->out, e->phi_out);
  r->st =
      px_interface_matrix_err(&r->ifc, e->ev, r->in, r->out, PX_VARIANT_CORRECTED, &r->t, &r->err);
}

/* Is the refusal `st` contradicted by the exact values? */
static int refusal_wrong(px_status_t st, const qelem_t *x, double kmax) {
  switch (st) {
  case PX_ETIR:
    return !x->tir && x->k > 1e-12Q;
  case PX_EGRAZING:
    return !x->tir && x->c > 2e-10Q && fabsq(x->cp) > 2e-10Q;
  case PX_ENONFINITE:
    return kmax <= PX_CURVATURE_MAX / 10;
  case PX_EILLCOND:
    return 0; /* the bound said so; the counts show how often */
  default:
    return 1; /* EINVAL, ESINGULAR, ...: the configurations are all valid */
  }
}

static int mat_finite(px_mat4_t t) {
  return px_mat4_isfinite(t);
}

/* ---- the exact-tracing Jacobian of a single element (spheres and planes) ---- */

static void sample_jacobian(const elem_cfg_t *e, const elem_run_t *r, double L,
                            val_stab_case_t *o) {
  if (e->k1 != e->k2 || fabs(e->k1) > 1e12) /* ex_ spheres and planes only */
    return;
  double c, s;
  px_cos_sin_deg(e->theta_deg, &c, &s);
  px_vec3_t sd = px_vec3(s, 0, c);
  double radius = e->k1 == 0 ? INFINITY : 1.0 / e->k1;
  ex_stage_t st = {isinf(radius) ? ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 0, 1))
                                 : ex_quadric_sphere(px_vec3(0, 0, radius), fabs(radius)),
                   e->ev, e->n2, 1};
  px_frame_t f;
  if (px_frame_from_z(sd, px_vec3(0, 1, 0), &f) != PX_OK)
    return;
  ex_system_t sys = {px_vec3(0, 0, 0), px_frame_rotate(f, e->phi_in), e->n1, &st, 1, 0.0,
                     e->phi_out};
  ex_axial_t ax;
  px_mat4_t j1, j2;
  px_status_t ts = ex_trace_axial(&sys, &ax);
  o->sampled = 1;
  if (ts != PX_OK) { /* the exact tracer refuses (TIR, grazing): a matrix would be a lie */
    o->sample_fail = r->st == PX_OK && ts == PX_ETIR;
    return;
  }
  if (r->st != PX_OK)
    return;
  if (ex_jacobian_q(&sys, &ax, L, &j1) != PX_OK ||
      ex_jacobian_q(&sys, &ax, 0.125 * L, &j2) != PX_OK) {
    o->sample_unresolved = 1;
    return;
  }
  /* the library's matrix in the exact tracer's own frames: at normal incidence the two take
   * the tangent basis from different hints, and the matrix between given frames does not
   * depend on that choice */
  px_mat4_t t;
  double err;
  if (px_interface_matrix_err(&r->ifc, e->ev, sys.frame, ax.out_frame, PX_VARIANT_CORRECTED, &t,
                              &err) != PX_OK) {
    o->sample_unresolved = 1;
    return;
  }
  px_mat4_t s1 = val_mat4_scaled(j1, L), s2 = val_mat4_scaled(j2, L), sl = val_mat4_scaled(t, L);
  double nrm = px_mat4_maxabs(s1), ref_err = 0, dev = 0;
  for (int i = 0; i < 4; i++)
    for (int k = 0; k < 4; k++) {
      ref_err = fmax(ref_err, fabs(s1.m[i][k] - s2.m[i][k]) / nrm);
      dev = fmax(dev, fabs(sl.m[i][k] - s1.m[i][k]) / nrm);
    }
  o->sample_err = dev;
  if (!(ref_err <= 1e-9)) {
    o->sample_unresolved = 1;
    return;
  }
  o->sample_fail = !(dev <= err + 10 * ref_err + 1e-12);
  /* the invariants are checked on the exact Jacobian too, before they serve as oracles */
  double eta = e->ev == PX_EVENT_REFLECT ? 1.0 : e->n1 / e->n2;
  o->sample_invariant_fail = !invariants_hold(s1, eta, 10 * ref_err + 1e-12);
}

/* ---- one case ---- */

static void check_element(rng_t *rng, val_stab_regime_t g, int sample, val_stab_case_t *o) {
  elem_cfg_t e;
  draw_element(rng, g, &e);
  snprintf(o->label, sizeof o->label,
           "%s theta %.17g deg n %.17g -> %.17g k %.3g/%.3g axis %.3f phi %.3f/%.3f",
           e.ev == PX_EVENT_REFLECT ? "reflect" : "refract", e.theta_deg, e.n1, e.n2, e.k1, e.k2,
           e.axis, e.phi_in, e.phi_out);
  elem_run_t r;
  run_element(&e, px_vec3(0, 0, 0), NULL, &r);
  o->status = r.st;
  o->err_bound = r.err;
  double L = r.kmax > 0 ? 1.0 / r.kmax : 1.0;
  if (r.built == 0) { /* px_interface_make: only grazing incidence is a valid reason */
    double c, s;
    px_cos_sin_deg(e.theta_deg, &c, &s);
    o->refusal_wrong = !(r.st == PX_EGRAZING && c <= 2 * PX_COS_MIN);
    return;
  }
  qelem_t x;
  ref_element(&r.ifc, e.ev, r.built == 2 ? &r.in : NULL, r.built == 2 ? &r.out : NULL, &x);
  if (r.built == 2) { /* the error coefficients exist exactly where the matrix does */
    px_element_t el = {e.ev == PX_EVENT_REFLECT ? PX_ELEMENT_REFLECT : PX_ELEMENT_REFRACT,
                       r.t,
                       0.0,
                       r.ifc,
                       r.in,
                       r.out};
    px_coeffs_t k;
    o->bounds_disagree = px_element_coeffs(&el, 0.0, PX_VARIANT_CORRECTED, &k) != r.st;
  }
  if (r.st != PX_OK) {
    o->refusal_wrong = refusal_wrong(r.st, &x, r.kmax);
    if (sample)
      sample_jacobian(&e, &r, L, o);
    return;
  }
  if (!mat_finite(r.t) || !isfinite(r.err)) {
    o->nonfinite = 1;
    return;
  }
  if (x.tir) {
    o->returned_tir = 1;
    return;
  }
  o->err = rel_error_q(r.t, &x.t, L);
  o->reference_fail = !(o->err <= r.err);
  o->accuracy_fail = !(o->err <= PX_ACCURACY);
  double eta = e.ev == PX_EVENT_REFLECT ? 1.0 : e.n1 / e.n2;
  o->invariant_fail = !invariants_hold(val_mat4_scaled(r.t, L), eta, r.err);
  if (sample)
    sample_jacobian(&e, &r, L, o);
}

/* transfer z1, element 1 (paper frames of a canonical surface), transfer z2 chosen 1 +- delta
 * times the distance where B_11 of the partial product vanishes (the tangential caustic of the
 * point at -z1), element 2 (a surface met by the outgoing ray at a random angle and azimuth,
 * entered in element 1's output frame), transfer z3. The stated accuracy of the product is the
 * elements' bounds propagated: (sum e_i + 8 U n) prod(4 |S_i|) / 4 / |S| (max norms). */
static void check_cascade(rng_t *rng, val_stab_case_t *o) {
  elem_cfg_t e1, e2;
  val_stab_regime_t g1 = coin(rng, 0.5) ? VAL_STAB_GENERAL : (val_stab_regime_t)(next64(rng) % 8);
  draw_element(rng, g1, &e1);
  if (e1.k1 == 0 || fabs(e1.k1) > 1e12) { /* a curved first surface sets the length scale */
    e1.k1 = e1.k2 = (coin(rng, 0.5) ? 1 : -1) * log_uni(rng, -3, 3);
    e1.axis = 0;
  }
  e1.phi_in = e1.phi_out = 0.0;
  draw_element(rng, coin(rng, 0.5) ? VAL_STAB_GENERAL : (val_stab_regime_t)(next64(rng) % 8), &e2);
  e2.n1 = e1.ev == PX_EVENT_REFLECT ? e1.n1 : e1.n2;
  if (e2.ev == PX_EVENT_REFLECT)
    e2.n2 = e2.n1;
  e2.axis = uni(rng, 0, 2 * M_PI); /* azimuth of the second normal */
  double L = 1.0 / fabs(e1.k1);
  double z1 = L * log_uni(rng, -1, 1), z3 = L * uni(rng, -2, 2);
  snprintf(o->label, sizeof o->label, "cascade: z1 %.3g, %s theta %.12g n %.6g -> %.6g k %.3g; ",
           z1, e1.ev == PX_EVENT_REFLECT ? "reflect" : "refract", e1.theta_deg, e1.n1, e1.n2,
           e1.k1);
  elem_run_t r1, r2;
  run_element(&e1, px_vec3(0, 0, 0), NULL, &r1);
  o->status = r1.st;
  if (r1.st != PX_OK) {
    o->nonfinite = 0;
    return; /* the element checks judge single refusals; here only products are of interest */
  }
  /* B_11 of T(z2) T1 T(z1) = z1 A_11 + z2 (z1 C_11 + D_11) = 0 at the caustic */
  double den = z1 * r1.t.m[2][0] + r1.t.m[2][2];
  double z2 = den != 0 ? -z1 * r1.t.m[0][0] / den : L;
  if (!isfinite(z2) || fabs(z2) > 1e6 * L)
    z2 = L;
  z2 *= 1.0 + (coin(rng, 0.5) ? 1 : -1) * log_uni(rng, -12, -1);
  run_element(&e2, r1.out.z, &r1.out, &r2);
  size_t len = strlen(o->label);
  snprintf(o->label + len, sizeof o->label - len, "z2 %.6g; %s theta %.12g n -> %.6g k %.3g", z2,
           e2.ev == PX_EVENT_REFLECT ? "reflect" : "refract", e2.theta_deg, e2.n2, e2.k1);
  o->status = r2.st;
  if (r2.st != PX_OK)
    return;
  px_mat4_t f[5] = {px_transfer_matrix(z1), r1.t, px_transfer_matrix(z2), r2.t,
                    px_transfer_matrix(z3)};
  double ei[5] = {0, r1.err, 0, r2.err, 0};
  px_mat4_t t = f[0];
  double prod = 1.0, esum = 0.0;
  for (int i = 0; i < 5; i++) {
    if (i)
      t = px_mat4_mul(f[i], t);
    prod *= 4.0 * px_mat4_maxabs(val_mat4_scaled(f[i], L));
    esum += ei[i] + 8 * U;
  }
  double bound = esum * prod / 4.0 / px_mat4_maxabs(val_mat4_scaled(t, L));
  o->err_bound = bound;
  if (!mat_finite(t) || !isfinite(bound)) {
    o->nonfinite = 1;
    return;
  }
  qelem_t x1, x2;
  ref_element(&r1.ifc, e1.ev, &r1.in, &r1.out, &x1);
  ref_element(&r2.ifc, e2.ev, &r2.in, &r2.out, &x2);
  if (x1.tir || x2.tir) {
    o->returned_tir = 1;
    return;
  }
  qmat_t q = qtransfer(z1), tq;
  tq = qmul(&x1.t, &q);
  q = qtransfer(z2);
  tq = qmul(&q, &tq);
  tq = qmul(&x2.t, &tq);
  q = qtransfer(z3);
  tq = qmul(&q, &tq);
  o->err = rel_error_q(t, &tq, L);
  o->reference_fail = !(o->err <= bound);
  o->accuracy_fail = 0; /* a product has the propagated bound, not PX_ACCURACY */
  double eta1 = e1.ev == PX_EVENT_REFLECT ? 1.0 : e1.n1 / e1.n2;
  double eta2 = e2.ev == PX_EVENT_REFLECT ? 1.0 : e2.n1 / e2.n2;
  o->invariant_fail = !invariants_hold(val_mat4_scaled(t, L), eta1 * eta2, bound);
}

void val_stability_case(uint64_t seed, uint64_t index, int sample, val_stab_case_t *out) {
  memset(out, 0, sizeof *out);
  rng_t r = {seed * 0x2545f4914f6cdd1dULL + index * 0x9e3779b97f4a7c15ULL};
  next64(&r);
  val_stab_regime_t g = (val_stab_regime_t)(index % VAL_STAB_REGIMES);
  out->regime = g;
  if (g == VAL_STAB_CASCADE)
    check_cascade(&r, out);
  else
    check_element(&r, g, sample, out);
}
