/* system.c -- element system matrices: transfer (Eq. 1), refraction (Eq. 2) and reflection
 * (section 2.2 (3)). The corrected form is derived in docs/conventions.md from the vector form
 * of Snell's law, n1 (d x N) = n2 (d' x N), linearised about the axial ray; the printed form is
 * Eq. (2) verbatim (docs/errata.md). */
#include "paraxial/system.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "curvature.h"
#include "fma_clones.h"

/* Four lanes at a time (px_interface_outgoing4()) where the compiler can target AVX2 and FMA for
 * one function; the CPU is asked at run time. -DPX_NO_SIMD4 builds without. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(PX_NO_SIMD4)
#define PX_SIMD4 1
#include <immintrin.h>
#endif

/* Rays and frames are accepted when they agree to this many units of the last place of a unit
 * vector times 1e6: loose enough for frames carried through a long cascade, tight enough to
 * catch a frame passed for the wrong ray. */
#define DIRECTION_MATCH 1e-9
/* Below this sin(theta) the plane of incidence is taken as undefined (normal incidence). */
#define SIN_NORMAL 1e-12

/* Numerical limits (docs/conventions.md). U is the unit roundoff. cos and sin of the incidence
 * from unit vectors (normalised, a dot product, a cross product) or from an angle carry a
 * relative error of a few U; EPS_IN bounds it. cos^2 theta' = (1 - eta s)(1 + eta s) loses
 * eta s / (1 - eta s) units of U: at most 16 while eta s < ES_HARD, and the form is kept in
 * this ordinary regime (and for c >= C_HARD, near the critical angle, where any form cancels
 * alike and the error bound says how much) so that the renderers' rays stay what they were;
 * near grazing with eta ~ 1 (eta s > ES_HARD, c < C_HARD: s no longer carries c) the form
 * (1 - eta^2) + (eta c)^2 has no cancellation. h = cp - eta c is factored as
 * (1 - eta^2) / (cp + eta c) when it loses more than 4 bits (|h| < |cp| H_HARD). The matrix
 * takes its cosines from the frames (Theta = frame . tangent basis) only when both are >=
 * C_FRAMES, where that costs at most 2 U / C_FRAMES; otherwise from the rotations of the frames
 * about the rays and the cosines here. */
#define U (DBL_EPSILON / 2)
#define EPS_IN (4 * U)
#define ES_HARD (15.0 / 16.0)
#define K_HARD (1.0 - ES_HARD * ES_HARD)
#define C_HARD 0.25
#define H_HARD (1.0 / 16.0)
#define C_FRAMES (1.0 / 16.0)

px_status_t px_variant_parse(const char *name, px_variant_t *out) {
  if (name && strcmp(name, "corrected") == 0) {
    *out = PX_VARIANT_CORRECTED;
    return PX_OK;
  }
  if (name && strcmp(name, "printed") == 0) {
    *out = PX_VARIANT_PRINTED;
    return PX_OK;
  }
  return PX_EINVAL;
}

const char *px_variant_name(px_variant_t v) {
  return v == PX_VARIANT_PRINTED ? "printed" : "corrected";
}

static int vec3_isfinite(px_vec3_t v) {
  return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

static int index_ok(double n) {
  return isfinite(n) && n > 0.0;
}

px_status_t px_interface_make(px_vec3_t s, px_vec3_t nu, px_vec3_t hint, px_mat2_t q_in_u,
                              const double *q_world, double n1, double n2, px_interface_t *out) {
  px_interface_t r;
  if (!index_ok(n1) || !index_ok(n2) || !vec3_isfinite(hint))
    return PX_EINVAL;
  if (px_vec3_normalize(s, &r.s) != PX_OK || px_vec3_normalize(nu, &r.nu) != PX_OK)
    return PX_EINVAL;
  double sign = 1.0;
  double c = px_vec3_dot(r.nu, r.s);
  if (c < 0.0) { /* orient nu along the incident ray; the height w = (1/2) t^t Q t flips sign */
    r.nu = px_vec3_scale(r.nu, -1.0);
    sign = -1.0;
    c = -c;
  }
  if (!(c > PX_COS_MIN))
    return PX_EGRAZING;
  px_vec3_t p = px_vec3_cross(r.nu, r.s);
  if (px_vec3_norm(p) > SIN_NORMAL) {
    px_vec3_normalize(p, &r.u2);
  } else { /* normal incidence: the plane of incidence is undefined, take u2 from the hint */
    px_frame_t f;
    if (px_frame_from_z(r.nu, hint, &f) != PX_OK)
      return PX_EINVAL;
    r.u2 = f.x2;
  }
  r.u1 = px_vec3_cross(r.u2, r.nu);
  if (q_world) {
    const px_vec3_t u[2] = {r.u1, r.u2};
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) {
        const double *m = q_world;
        px_vec3_t su = px_vec3(m[0] * u[j].x + m[1] * u[j].y + m[2] * u[j].z,
                               m[3] * u[j].x + m[4] * u[j].y + m[5] * u[j].z,
                               m[6] * u[j].x + m[7] * u[j].y + m[8] * u[j].z);
        r.q.m[i][j] = sign * px_vec3_dot(u[i], su);
      }
  } else {
    r.q = px_mat2_scale(q_in_u, sign);
  }
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      if (!isfinite(r.q.m[i][j]))
        return PX_EINVAL;
  r.n1 = n1;
  r.n2 = n2;
  *out = r;
  return PX_OK;
}

px_status_t px_interface_canonical(double theta, double radius, double n1, double n2,
                                   px_interface_t *out) {
  if (!isfinite(theta) || theta < 0.0 || theta > M_PI / 2 || isnan(radius) || radius == 0.0)
    return PX_EINVAL;
  double k = isinf(radius) ? 0.0 : 1.0 / radius;
  px_vec3_t s = px_vec3(sin(theta), 0.0, cos(theta));
  return px_interface_make(s, px_vec3(0, 0, 1), px_vec3(0, 1, 0), px_mat2_diag(k, k), NULL, n1, n2,
                           out);
}

/* a . b with the rounding error of each product and sum compensated (Ogita, Rump and Oishi's
 * Dot2): accurate to a few U relative even where the terms cancel (near grazing, nu . s small).
 * Used only outside the ordinary regime. */
static double dot_compensated(px_vec3_t a, px_vec3_t b) {
  const double x[3] = {a.x, a.y, a.z}, y[3] = {b.x, b.y, b.z};
  double p = x[0] * y[0], err = fma(x[0], y[0], -p);
  for (int i = 1; i < 3; i++) {
    double q = x[i] * y[i], eq = fma(x[i], y[i], -q);
    double sum = p + q, z = sum - p;
    err += ((p - (sum - z)) + (q - z)) + eq;
    p = sum;
  }
  return p + err;
}

/* 1 - (n1/n2)^2 to a few U: n2 - n1 is exact when the indices are within a factor 2. */
static double one_minus_eta2(double n1, double n2) {
  return (n2 - n1) * (n2 + n1) / (n2 * n2);
}

/* Outside the ordinary regime of k = cos^2 theta' = (1 - eta s)(1 + eta s) (see ES_HARD):
 * k < 1 - ES_HARD^2 is eta s > ES_HARD, tested on k so that the ordinary path pays one
 * comparison. */
static int snell_hard(double k, double c) {
  return k < K_HARD && c < C_HARD;
}

/* px_interface_outgoing() for a refraction near grazing with eta ~ 1 (snell_hard): cos theta
 * by a compensated dot product, cos^2 theta' = (1 - eta^2) + (eta c)^2, h factored (exactly 0
 * when n1 = n2, so that s' = s). Kept out of line: the ordinary path stays as it was. */
static px_status_t __attribute__((noinline))
outgoing_hard(const px_interface_t *ifc, double eta, px_vec3_t *s_out, double *cos_out) {
  double ci = dot_compensated(ifc->nu, ifc->s), ec = eta * ci;
  double one_m = one_minus_eta2(ifc->n1, ifc->n2), k = one_m + ec * ec;
  if (k < 0.0)
    return PX_ETIR;
  double co = sqrt(k);
  px_vec3_t d = px_v3_add(px_v3_scale(ifc->s, eta), px_v3_scale(ifc->nu, one_m / (co + ec)));
  if (px_v3_normalize(d, s_out) != PX_OK)
    return PX_ENONFINITE;
  *cos_out = co;
  return PX_OK;
}

PX_FMA_CLONES /* per ray in the renderers: see fma_clones.h */
    px_status_t
    px_interface_outgoing(const px_interface_t *ifc, px_event_t ev, px_vec3_t *s_out,
                          double *cos_out) {
  double ci = px_v3_dot_fma(ifc->nu, ifc->s);
  px_vec3_t d;
  double co;
  if (ev == PX_EVENT_REFLECT) {
    d = px_v3_axpy_fma(-2.0 * ci, ifc->nu, ifc->s);
    co = -ci;
  } else {
    double eta = ifc->n1 / ifc->n2;
    double sin_i = px_v3_norm_fma(px_v3_cross(ifc->nu, ifc->s));
    double k = (1.0 - eta * sin_i) * (1.0 + eta * sin_i); /* cos^2(theta'), ordinary regime */
    if (k < K_HARD && snell_hard(k, ci)) /* a tail call: the ordinary path spills nothing */
      return outgoing_hard(ifc, eta, s_out, cos_out);
    if (k < 0.0)
      return PX_ETIR;
    co = sqrt(k);
    d = px_v3_add(px_v3_scale(ifc->s, eta), px_v3_scale(ifc->nu, co - eta * ci));
  }
  if (px_v3_normalize(d, s_out) != PX_OK)
    return PX_ENONFINITE;
  *cos_out = co;
  return PX_OK;
}

/* Lane i of px_interface_outgoing4() by px_interface_outgoing(). */
static px_status_t outgoing_lane(px_event_t ev, const px_vec3x4_t *s, const px_vec3x4_t *nu,
                                 const double n1[4], const double n2[4], int i, px_vec3x4_t *out) {
  px_interface_t f = {.s = {s->x[i], s->y[i], s->z[i]},
                      .nu = {nu->x[i], nu->y[i], nu->z[i]},
                      .n1 = n1[i],
                      .n2 = n2[i]};
  px_vec3_t o;
  double co;
  px_status_t st = px_interface_outgoing(&f, ev, &o, &co);
  if (st == PX_OK)
    out->x[i] = o.x, out->y[i] = o.y, out->z[i] = o.z;
  return st;
}

/* Four lanes of px_interface_outgoing() with AVX2 and FMA: the same operations in the same order
 * (products and sums rounded apart, fma() where it has fma()), so each lane rounds as the scalar
 * function does. Lanes near grazing, which take outgoing_hard() there, are left to it. */
#ifdef PX_SIMD4
__attribute__((target("avx2,fma"))) static void
outgoing4_avx2(px_event_t ev, const px_vec3x4_t *s, const px_vec3x4_t *nu, const double n1[4],
               const double n2[4], unsigned lanes, px_vec3x4_t *out, px_status_t st[4]) {
  __m256d sx = _mm256_loadu_pd(s->x), sy = _mm256_loadu_pd(s->y), sz = _mm256_loadu_pd(s->z);
  __m256d nx = _mm256_loadu_pd(nu->x), ny = _mm256_loadu_pd(nu->y), nz = _mm256_loadu_pd(nu->z);
  __m256d ci = _mm256_fmadd_pd(nx, sx, _mm256_fmadd_pd(ny, sy, _mm256_mul_pd(nz, sz)));
  __m256d dx, dy, dz;
  unsigned hard = 0, tir = 0;
  if (ev == PX_EVENT_REFLECT) {
    __m256d m = _mm256_mul_pd(_mm256_set1_pd(-2.0), ci);
    dx = _mm256_fmadd_pd(m, nx, sx);
    dy = _mm256_fmadd_pd(m, ny, sy);
    dz = _mm256_fmadd_pd(m, nz, sz);
  } else {
    __m256d eta = _mm256_div_pd(_mm256_loadu_pd(n1), _mm256_loadu_pd(n2));
    /* px_v3_cross(nu, s), each component px_diff_products(a, b, c, d) = a b - c d */
    __m256d sign = _mm256_set1_pd(-0.0); /* negation flips the sign bit, as unary minus */
#define DIFF_PRODUCTS(a, b, c, d)                                                                  \
  _mm256_add_pd(_mm256_fmadd_pd(a, b, _mm256_xor_pd(_mm256_mul_pd(c, d), sign)),                   \
                _mm256_fmadd_pd(_mm256_xor_pd(c, sign), d, _mm256_mul_pd(c, d)))
    __m256d cx = DIFF_PRODUCTS(ny, sz, nz, sy), cy = DIFF_PRODUCTS(nz, sx, nx, sz),
            cz = DIFF_PRODUCTS(nx, sy, ny, sx);
#undef DIFF_PRODUCTS
    __m256d sin_i =
        _mm256_sqrt_pd(_mm256_fmadd_pd(cx, cx, _mm256_fmadd_pd(cy, cy, _mm256_mul_pd(cz, cz))));
    __m256d one = _mm256_set1_pd(1.0), es = _mm256_mul_pd(eta, sin_i);
    __m256d k = _mm256_mul_pd(_mm256_sub_pd(one, es), _mm256_add_pd(one, es));
    hard = (unsigned)_mm256_movemask_pd(
        _mm256_and_pd(_mm256_cmp_pd(k, _mm256_set1_pd(K_HARD), _CMP_LT_OQ),
                      _mm256_cmp_pd(ci, _mm256_set1_pd(C_HARD), _CMP_LT_OQ)));
    tir = (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(k, _mm256_setzero_pd(), _CMP_LT_OQ)) & ~hard;
    __m256d h = _mm256_sub_pd(_mm256_sqrt_pd(k), _mm256_mul_pd(eta, ci));
    dx = _mm256_add_pd(_mm256_mul_pd(sx, eta), _mm256_mul_pd(nx, h));
    dy = _mm256_add_pd(_mm256_mul_pd(sy, eta), _mm256_mul_pd(ny, h));
    dz = _mm256_add_pd(_mm256_mul_pd(sz, eta), _mm256_mul_pd(nz, h));
  }
  /* px_v3_normalize(): a zero, infinite or NaN norm is PX_ENONFINITE */
  __m256d n =
      _mm256_sqrt_pd(_mm256_fmadd_pd(dx, dx, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dz, dz))));
  unsigned good = (unsigned)_mm256_movemask_pd(
      _mm256_and_pd(_mm256_cmp_pd(n, _mm256_setzero_pd(), _CMP_GT_OQ),
                    _mm256_cmp_pd(n, _mm256_set1_pd(INFINITY), _CMP_LT_OQ)));
  __m256d inv = _mm256_div_pd(_mm256_set1_pd(1.0), n);
  double ox[4], oy[4], oz[4];
  _mm256_storeu_pd(ox, _mm256_mul_pd(dx, inv));
  _mm256_storeu_pd(oy, _mm256_mul_pd(dy, inv));
  _mm256_storeu_pd(oz, _mm256_mul_pd(dz, inv));
  for (int i = 0; i < 4; i++) {
    unsigned b = 1u << i;
    if (!(lanes & b)) {
      st[i] = PX_EINVAL;
    } else if (hard & b) {
      st[i] = outgoing_lane(ev, s, nu, n1, n2, i, out);
    } else if (tir & b) {
      st[i] = PX_ETIR;
    } else if (!(good & b)) {
      st[i] = PX_ENONFINITE;
    } else {
      st[i] = PX_OK;
      out->x[i] = ox[i], out->y[i] = oy[i], out->z[i] = oz[i];
    }
  }
}
#endif

int px_simd4_available(void) {
#ifdef PX_SIMD4
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return 0;
#endif
}

void px_interface_outgoing4(px_event_t ev, const px_vec3x4_t *s, const px_vec3x4_t *nu,
                            const double n1[4], const double n2[4], unsigned lanes,
                            px_vec3x4_t *out, px_status_t st[4]) {
#ifdef PX_SIMD4
  if (px_simd4_available()) {
    outgoing4_avx2(ev, s, nu, n1, n2, lanes, out, st);
    return;
  }
#endif
  for (int i = 0; i < 4; i++) {
    if (!(lanes & (1u << i))) {
      st[i] = PX_EINVAL;
      continue;
    }
    st[i] = outgoing_lane(ev, s, nu, n1, n2, i, out);
  }
}

px_status_t px_interface_frames(const px_interface_t *ifc, px_event_t ev, px_frame_t *in,
                                px_frame_t *out) {
  px_vec3_t so;
  double co;
  px_status_t st = px_interface_outgoing(ifc, ev, &so, &co);
  if (st != PX_OK)
    return st;
  in->z = ifc->s;
  in->x2 = ifc->u2;
  in->x1 = px_vec3_cross(ifc->u2, ifc->s);
  out->z = so;
  out->x2 = ifc->u2;
  out->x1 = px_vec3_cross(ifc->u2, so);
  return PX_OK;
}

void px_interface_cos_sin(const px_interface_t *ifc, double *c, double *s) {
  double ci = px_vec3_dot(ifc->nu, ifc->s);
  if (ci < C_HARD) /* near grazing the fused dot product is only good to U absolute */
    ci = dot_compensated(ifc->nu, ifc->s);
  *c = fmin(ci, 1.0);
  *s = fmin(px_vec3_norm(px_vec3_cross(ifc->nu, ifc->s)), 1.0);
}

px_status_t px_element_cosines(px_event_t ev, double c, double s, double n1, double n2,
                               double curvature, px_cosines_t *out) {
  if (!index_ok(n1) || (ev == PX_EVENT_REFRACT && !index_ok(n2)) || !(c >= 0.0 && c <= 1.0) ||
      !(s >= 0.0 && s <= 1.0) || !(curvature >= 0.0))
    return PX_EINVAL;
  if (!(c > PX_COS_MIN))
    return PX_EGRAZING;
  px_cosines_t g;
  g.c = c;
  g.s = s;
  double eps_c = EPS_IN, eps_cp, eps_h;
  if (ev == PX_EVENT_REFLECT) { /* theta' = pi - theta: exact */
    g.eta = 1.0;
    g.cp = -c;
    g.sp = s;
    g.h = -2.0 * c;
    eps_cp = eps_h = eps_c;
  } else {
    double eta = n1 / n2, es = eta * s, k, eps_k, one_m = one_minus_eta2(n1, n2);
    k = (1.0 - es) * (1.0 + es);
    if (!snell_hard(k, c)) { /* (1 - eta s)(1 + eta s): loses eta s / (1 - eta s) U */
      eps_k = 2.0 * es * es * (EPS_IN + 2 * U) / fabs(k) + 3 * U;
    } else { /* (1 - eta^2) + (eta c)^2: cancels only beyond the critical angle's edge */
      double ec = eta * c;
      k = one_m + ec * ec;
      eps_k = (fabs(one_m) * 4 * U + ec * ec * (2.0 * eps_c + 5 * U)) / fabs(k) + U;
    }
    if (k < 0.0)
      return PX_ETIR;
    g.eta = eta;
    g.sp = es;
    g.cp = sqrt(k);
    eps_cp = 0.5 * eps_k + U;
    if (!(g.cp > PX_COS_MIN))
      return PX_EGRAZING;
    double h = g.cp - eta * c;
    if (fabs(h) < H_HARD * g.cp) { /* cancels: (cp^2 - eta^2 c^2) / (cp + eta c) */
      h = one_m / (g.cp + eta * c);
      eps_h = fmax(eps_cp, eps_c + 2 * U) + 7 * U;
    } else {
      eps_h = (g.cp * eps_cp + eta * c * (eps_c + 2 * U)) / fabs(h) + U;
    }
    g.h = h;
  }
  if (curvature > PX_CURVATURE_MAX)
    return PX_ENONFINITE;
  /* entries are c'/c, eta c/c', h q/(c c'), h q, rotated by the frames: their relative errors
   * add; the factor 2 covers the second-order terms and the rotations' few U */
  g.err = 2.0 * (eps_c + eps_cp + eps_h) + 32 * U;
  if (!(g.err <= PX_ACCURACY))
    return PX_EILLCOND;
  *out = g;
  return PX_OK;
}

void px_cos_sin_deg(double deg, double *c, double *s) {
  if (deg <= 45.0) {
    double r = deg * (M_PI / 180.0);
    *c = cos(r);
    *s = sin(r);
  } else { /* 90 - deg is exact (Sterbenz) and small angles keep their relative accuracy */
    double r = (90.0 - deg) * (M_PI / 180.0);
    *c = sin(r);
    *s = cos(r);
  }
}

px_mat4_t px_transfer_matrix(double z0) {
  px_mat4_t t = px_mat4_identity(); /* Eq. (1) */
  t.m[0][2] = z0;
  t.m[1][3] = z0;
  return t;
}

static int same_direction(px_vec3_t a, px_vec3_t b) {
  return px_vec3_norm(px_vec3_sub(a, b)) <= DIRECTION_MATCH;
}

/* The rotation of frame f about its ray z from the paper's frame (p1 = u2 x z, u2):
 * P = [[x1 . p1, x1 . u2], [x2 . p1, x2 . u2]], orthogonal, so that Theta = P diag(cos, 1)
 * with the cosine taken from px_element_cosines() rather than from x1 . u1, which near grazing
 * is a small difference of O(1) products. */
static px_mat2_t frame_rotation(px_frame_t f, px_vec3_t u2) {
  px_vec3_t p1 = px_vec3_cross(u2, f.z);
  return px_mat2(px_vec3_dot(f.x1, p1), px_vec3_dot(f.x1, u2), px_vec3_dot(f.x2, p1),
                 px_vec3_dot(f.x2, u2));
}

/* Corrected Eq. (2) from the rotations and the cosines: with Theta = P diag(c, 1) and
 * Theta' = P' diag(c', 1),
 *   A = P' diag(c'/c, 1) P^t,  C = -h P' diag(1/c', 1) Q diag(1/c, 1) P^t,
 *   D = eta P' diag(c/c', 1) P^t. */
static px_mat4_t matrix_from_cosines(const px_interface_t *ifc, const px_cosines_t *g,
                                     px_frame_t in, px_frame_t out) {
  px_mat2_t p = frame_rotation(in, ifc->u2), pp = frame_rotation(out, ifc->u2);
  px_mat2_t pt = px_mat2_transpose(p);
  px_mat2_t q = ifc->q;
  px_mat2_t cq = px_mat2(-g->h * q.m[0][0] / (g->cp * g->c), -g->h * q.m[0][1] / g->cp,
                         -g->h * q.m[1][0] / g->c, -g->h * q.m[1][1]);
  px_mat2_t a = px_mat2_mul(px_mat2_mul(pp, px_mat2_diag(g->cp / g->c, 1.0)), pt);
  px_mat2_t c = px_mat2_mul(px_mat2_mul(pp, cq), pt);
  px_mat2_t d = px_mat2_mul(px_mat2_mul(pp, px_mat2_diag(g->eta * g->c / g->cp, g->eta)), pt);
  return px_mat4_blocks(a, px_mat2_zero(), c, d);
}

px_status_t px_interface_matrix_err(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                    px_frame_t out, px_variant_t variant, px_mat4_t *t,
                                    double *err) {
  if (!index_ok(ifc->n1) || (ev == PX_EVENT_REFRACT && !index_ok(ifc->n2)))
    return PX_EINVAL;
  double ci, si;
  px_interface_cos_sin(ifc, &ci, &si);
  if (!(ci > PX_COS_MIN))
    return PX_EGRAZING;
  px_cosines_t g;
  px_status_t st = px_element_cosines(ev, ci, si, ifc->n1, ifc->n2, px__curvature(ifc->q), &g);
  if (st != PX_OK)
    return st;
  /* the outgoing axial ray, only to check the output frame against it (to 1e-9): eta s + h nu
   * (s - 2 c nu for a mirror) as in px_interface_outgoing(), which agrees to rounding */
  px_vec3_t so;
  double co = g.cp;
  if (px_vec3_normalize(px_vec3_add(px_vec3_scale(ifc->s, g.eta), px_vec3_scale(ifc->nu, g.h)),
                        &so) != PX_OK)
    return PX_ENONFINITE;
  if (!same_direction(in.z, ifc->s) || !same_direction(out.z, so) || px_frame_defect(in) > 1e-9 ||
      px_frame_defect(out) > 1e-9)
    return PX_EINVAL;

  px_mat4_t r;
  double e = g.err;
  double h = g.h, eta = g.eta; /* h of Eq. (2); -2 cos(theta) for a reflection */
  int from_frames = variant == PX_VARIANT_PRINTED ||
                    (ci >= C_FRAMES && fabs(co) >= C_FRAMES && fabs(h) >= H_HARD * fabs(co));
  if (!from_frames) {
    r = matrix_from_cosines(ifc, &g, in, out);
  } else { /* the ordinary regime: Theta and Theta' from the frames, 2 U / C_FRAMES at most */
    e += 8 * U / fmin(ci, fabs(co));
    px_mat2_t th = px_frame_theta(in, ifc->u1, ifc->u2);   /* Theta,  det = cos(theta)  */
    px_mat2_t thp = px_frame_theta(out, ifc->u1, ifc->u2); /* Theta', det = cos(theta') */
    px_mat2_t th_inv, thp_inv;
    if (px_mat2_inverse(th, &th_inv) != PX_OK || px_mat2_inverse(thp, &thp_inv) != PX_OK)
      return PX_ESINGULAR;
    px_mat2_t a = px_mat2_mul(thp, th_inv), b, c, d;
    if (variant == PX_VARIANT_PRINTED) { /* Eq. (2) verbatim */
      b = px_mat2_identity();
      c = px_mat2_scale(px_mat2_mul(px_mat2_mul(thp_inv, ifc->q), th_inv), h);
      d = px_mat2_scale(px_mat2_mul(thp_inv, px_mat2_transpose(th)), eta);
    } else { /* corrected: docs/errata.md E1-E3 */
      px_mat2_t thp_invt = px_mat2_transpose(thp_inv);
      b = px_mat2_zero();
      c = px_mat2_scale(px_mat2_mul(px_mat2_mul(thp_invt, ifc->q), th_inv), -h);
      d = px_mat2_scale(px_mat2_mul(thp_invt, px_mat2_transpose(th)), eta);
    }
    r = px_mat4_blocks(a, b, c, d);
  }
  if (!(e <= PX_ACCURACY))
    return PX_EILLCOND;
  if (!px_mat4_isfinite(r))
    return PX_ENONFINITE;
  *t = r;
  if (err)
    *err = e;
  return PX_OK;
}

px_status_t px_interface_matrix(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                px_frame_t out, px_variant_t variant, px_mat4_t *t) {
  return px_interface_matrix_err(ifc, ev, in, out, variant, t, NULL);
}

px_status_t px_element_matrix_cs(px_event_t ev, double c, double s, double n1, double n2,
                                 double radius, px_variant_t variant, px_mat4_t *t, double *err) {
  if (!(c >= 0.0 && c <= 1.0) || !(s >= 0.0 && s <= 1.0) || isnan(radius) || radius == 0.0)
    return PX_EINVAL;
  if (ev == PX_EVENT_REFLECT)
    n2 = n1;
  double k = isinf(radius) ? 0.0 : 1.0 / radius;
  px_interface_t ifc;
  px_frame_t in, out;
  px_status_t st = px_interface_make(px_vec3(s, 0.0, c), px_vec3(0, 0, 1), px_vec3(0, 1, 0),
                                     px_mat2_diag(k, k), NULL, n1, n2, &ifc);
  if (st == PX_OK)
    st = px_interface_frames(&ifc, ev, &in, &out);
  if (st == PX_OK)
    st = px_interface_matrix_err(&ifc, ev, in, out, variant, t, err);
  return st;
}

px_status_t px_element_matrix(px_event_t ev, double theta, double n1, double n2, double radius,
                              px_variant_t variant, px_mat4_t *t) {
  if (!isfinite(theta) || theta < 0.0 || theta > M_PI / 2)
    return PX_EINVAL;
  return px_element_matrix_cs(ev, cos(theta), sin(theta), n1, n2, radius, variant, t, NULL);
}
