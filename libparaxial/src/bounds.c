/* bounds.c -- error estimation (paper section 3, Eqs. 3-6, and the Appendix: A-1 and the general
 * system (3)). The corrected coefficients and the element's exact second-order term are derived
 * in docs/bounds.md (checked symbolically by scripts/derive/a1_series.py and numerically
 * against exact tracing by `pencil verify bounds`); the printed ones are A-1 verbatim. */
#include "paraxial/bounds.h"

#include <math.h>

#include "curvature.h"

/* Angles of one element in the paper's frames (section 2.2 (2), (3)): the cosines of
 * px_element_cosines(), so that the coefficients refuse exactly where the matrices do. */
typedef px_cosines_t angles_t;

static px_status_t element_angles(px_event_t ev, double c, double s, double n1, double n2,
                                  double curvature, angles_t *a) {
  return px_element_cosines(ev, c, s, n1, n2, curvature, a);
}

static px_status_t theta_ok(double theta) {
  return isfinite(theta) && theta >= 0.0 && theta <= M_PI / 2 ? PX_OK : PX_EINVAL;
}

/* A-1 verbatim. R is read as the smallest radius of curvature (1/R = 0 for a plane): a and e
 * need 1/length, which only a radius gives (docs/errata.md). A reflection substitutes
 * theta' = pi - theta and n' = n (section 2.2 (3)), so cos theta' < 0 and tan theta' < 0. */
static void coeffs_printed(const angles_t *g, double inv_r, double d3m, px_coeffs_t *k) {
  double t = g->s / g->c, tp = g->sp / g->cp;
  double gamma = g->eta * g->c / g->cp; /* n cos theta / n' cos theta' */
  double alpha = t - gamma * tp, beta = 1.0 - gamma;
  k->a = g->cp / (2.0 * g->c * g->c) * inv_r * fabs(alpha + beta * tp);
  k->b = fabs(alpha) / gamma * g->eta;
  k->c = 0.0;
  k->d = fabs(beta) / (g->c * g->c) *
         (0.25 * inv_r * inv_r * inv_r * (t + (2.0 + fabs(beta)) * tp) + M_SQRT2 * d3m);
  k->e = fabs(gamma * tp - t / gamma) * inv_r / g->c * g->eta;
  k->f = 0.5 * gamma * fabs(alpha) * g->eta;
}

/* Corrected: norm bounds of the exact second-order terms (docs/bounds.md, "corrected A-1"),
 * valid for any surface with |Q|_2 <= k = 1/R and third derivatives <= d3m, any directions.
 * With u = Theta^-1 x (|u| <= x0/c), g = Q u (|g| <= k x0 / c):
 *   Delta x  = (sin(theta-theta')/c) w e1 + u1 (s Theta' Theta^-1 xi - s' xi'_lin)
 *   Delta xi = -h Theta'^-1 g2 + (terms quadratic in g, xi)     (g2 = Q u2 + 1/2 c[u,u]). */
static void coeffs_corrected(const angles_t *g, double k, double d3m, px_coeffs_t *r) {
  double c = g->c, s = g->s, cp = fabs(g->cp), sp = g->sp, eta = g->eta, h = g->h;
  double one_m = (1.0 - eta) * (1.0 + eta); /* 1 - eta^2 */
  double cp3 = cp * cp * cp;
  /* a: Delta x_xx = al u^T Q u e1 + s' h u1 Theta'^-1 Q u with al = sin(theta-theta')/(2c),
   * be = s' h / c'. Two bounds, the smaller taken (|u| <= x0/c, |u1| <= x0/c):
   *  - the triangle inequality: k (|al| + |be|) |u|^2 (tight for refraction on a sphere);
   *  - by components: Delta x1 = u^T M u with M = (al + be/2) Q + (be/2) diag(q11, -q22), so
   *    |Delta x1| <= (|al + be/2| + |be|/2) k |u|^2, and |Delta x2| <= |s' h| k |u1| |u|. For a
   *    mirror al + be/2 = 0: the two terms of the triangle form cancel (3x tighter at most). */
  /* sin(theta - theta') = s cp - c sp = s h (sp = eta s, or theta' = pi - theta), the product
   * form where the difference cancels (h factored, e.g. n1 ~ n2) */
  double sin_d = fabs(h) < 0.0625 * cp ? s * h : s * g->cp - c * sp;
  double al = sin_d / (2.0 * c), be = sp * h / g->cp;
  double tri = fabs(al) + fabs(be);
  double comp = hypot(fabs(al + 0.5 * be) + 0.5 * fabs(be), sp * h);
  r->a = k / (c * c) * fmin(tri, comp);
  /* b: u1 s (1 - eta^2) diag(1/(c c'), 1) xi, attained for x, xi along x1 (= printed b) */
  r->b = fabs(s * one_m) / (c * c * cp);
  r->c = 0.0; /* rays through O stay at x' = 0 */
  /* d: -h Theta'^-1 Q Theta^-1 s w e1, the cubic term, and (alpha1 |g|^2 + alpha2 g1^2, m3 g1 g2)
   */
  double alpha1 = 0.5 * eta * h * h * s / g->cp;
  double alpha2 =
      -eta * h * s - 0.5 * eta * eta * eta * s * s * s * one_m / (g->cp * g->cp * g->cp);
  double m3 = -eta * h * s / g->cp;
  double amax = fmax(fabs(alpha1), fabs(alpha1 + alpha2));
  r->d = k * k * (fabs(h) * s / (2.0 * cp * c * c * c) + hypot(amax, 0.5 * m3) / (c * c)) +
         M_SQRT2 * fabs(h) * d3m / (cp * c * c);
  /* e: -h s u1 Theta'^-1 Q Theta^-1 xi and (m11 xi1 g1 + m22 xi2 g2, m3 xi1 g2) */
  double m11 = -eta * h * s - eta * eta * h * s * c / g->cp -
               eta * eta * eta * s * s * s * one_m / (g->cp * g->cp * g->cp);
  double m22 = -eta * eta * h * s / g->cp;
  r->e = k * (fabs(h) * s / (c * c * cp) + hypot(fmax(fabs(m11), fabs(m22)), m3) / c);
  /* f: -(1/2) eta s (1 - eta^2) (xi1^2 / c'^3 + xi2^2 / c'), largest along xi1 */
  r->f = 0.5 * fabs(eta * s * one_m) / cp3;
}

static int coeffs_finite(const px_coeffs_t *k) {
  return isfinite(k->a) && isfinite(k->b) && isfinite(k->c) && isfinite(k->d) && isfinite(k->e) &&
         isfinite(k->f);
}

px_status_t px_error_coeffs(const px_element_geom_t *geo, px_variant_t variant, px_coeffs_t *out) {
  if (theta_ok(geo->theta) != PX_OK)
    return PX_EINVAL;
  return px_error_coeffs_cs(geo, cos(geo->theta), sin(geo->theta), variant, out);
}

px_status_t px_error_coeffs_cs(const px_element_geom_t *geo, double cos_theta, double sin_theta,
                               px_variant_t variant, px_coeffs_t *out) {
  if (isnan(geo->radius) || !(geo->radius > 0.0) || !(geo->d3m >= 0.0) || !isfinite(geo->d3m))
    return PX_EINVAL;
  double k = isinf(geo->radius) ? 0.0 : 1.0 / geo->radius;
  angles_t g;
  px_status_t st = element_angles(geo->event, cos_theta, sin_theta, geo->n1,
                                  geo->event == PX_EVENT_REFLECT ? geo->n1 : geo->n2, k, &g);
  if (st != PX_OK)
    return st;
  px_coeffs_t r;
  if (variant == PX_VARIANT_PRINTED)
    coeffs_printed(&g, k, geo->d3m, &r);
  else
    coeffs_corrected(&g, k, geo->d3m, &r);
  if (!coeffs_finite(&r))
    return PX_ENONFINITE;
  *out = r;
  return PX_OK;
}

px_status_t px_element_coeffs(const px_element_t *e, double d3m, px_variant_t variant,
                              px_coeffs_t *out) {
  if (e->kind == PX_ELEMENT_TRANSFER)
    return PX_EINVAL;
  const px_interface_t *f = &e->ifc;
  double c, s, qn = px__curvature(f->q);
  px_interface_cos_sin(f, &c, &s);
  px_element_geom_t geo = {e->kind == PX_ELEMENT_REFLECT ? PX_EVENT_REFLECT : PX_EVENT_REFRACT,
                           NAN, /* the angle itself: unused, the cosines are given */
                           f->n1,
                           f->n2,
                           qn > 0.0 ? 1.0 / qn : INFINITY,
                           d3m};
  return px_error_coeffs_cs(&geo, c, s, variant, out);
}

px_status_t px_element_geom(const px_element_t *e, double d3m, px_element_geom_t *out) {
  if (e->kind == PX_ELEMENT_TRANSFER)
    return PX_EINVAL;
  const px_interface_t *f = &e->ifc;
  double ci = px_vec3_dot(f->nu, f->s);
  double si = px_vec3_norm(px_vec3_cross(f->nu, f->s));
  double qn = px_mat2_norm2(f->q); /* Q symmetric: the largest |principal curvature| */
  out->event = e->kind == PX_ELEMENT_REFLECT ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
  out->theta = atan2(si, ci);
  out->n1 = f->n1;
  out->n2 = f->n2;
  out->radius = qn > 0.0 ? 1.0 / qn : INFINITY;
  out->d3m = d3m;
  return isfinite(out->theta) ? PX_OK : PX_EINVAL;
}

double px_d3m(const double cubic[4]) {
  double m = 0.0;
  for (int i = 0; i < 4; i++)
    m = fmax(m, fabs(cubic[i]));
  return m;
}

/* c_ijk of the symmetric tensor from (c111, c112, c122, c222): the entry depends only on how
 * many indices are 2. */
static double cubic_entry(const double c[4], int i, int j, int k) {
  return c[i + j + k];
}

px_status_t px_element_second_order(const px_element_t *e, const double cubic[4], px_ray4_t psi,
                                    px_ray4_t *out) {
  if (e->kind == PX_ELEMENT_TRANSFER) { /* A-1 (1): straight rays, no second-order term */
    *out = (px_ray4_t){{0, 0, 0, 0}};
    return PX_OK;
  }
  const px_interface_t *f = &e->ifc;
  px_event_t ev = e->kind == PX_ELEMENT_REFLECT ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
  double ci = px_vec3_dot(f->nu, f->s);
  double si = px_vec3_norm(px_vec3_cross(f->nu, f->s));
  angles_t g;
  double th = atan2(si, ci);
  px_status_t st =
      element_angles(ev, cos(th), sin(th), f->n1, ev == PX_EVENT_REFLECT ? f->n1 : f->n2, 0.0, &g);
  if (st != PX_OK)
    return st;
  px_vec3_t so;
  double co;
  if ((st = px_interface_outgoing(f, ev, &so, &co)) != PX_OK)
    return st;
  /* paper frames: x2 = x2' = u2, x1 = u2 x s, x1' = u2 x s' (system.h) */
  px_vec3_t p1 = px_vec3_cross(f->u2, f->s), q1 = px_vec3_cross(f->u2, so);
  double r_in[2][2] = {{px_vec3_dot(p1, e->in.x1), px_vec3_dot(p1, e->in.x2)},
                       {px_vec3_dot(f->u2, e->in.x1), px_vec3_dot(f->u2, e->in.x2)}};
  double x[2], xi[2];
  for (int b = 0; b < 2; b++) {
    x[b] = r_in[b][0] * psi.v[0] + r_in[b][1] * psi.v[1];
    xi[b] = r_in[b][0] * psi.v[2] + r_in[b][1] * psi.v[3];
  }
  const double c = g.c, s = g.s, cp = g.cp, sp = g.sp, eta = g.eta, h = g.h;
  const double one_m = (1.0 - eta) * (1.0 + eta);
  const px_mat2_t q = f->q;
  double u[2] = {x[0] / c, x[1]};
  double qu[2] = {q.m[0][0] * u[0] + q.m[0][1] * u[1], q.m[1][0] * u[0] + q.m[1][1] * u[1]};
  double w = 0.5 * (u[0] * qu[0] + u[1] * qu[1]);
  /* first-order output direction xi' = -h Theta'^-1 Q u + eta Theta'^-1 Theta xi (Eq. 2) */
  double xl[2] = {(-h * qu[0] + eta * c * xi[0]) / cp, -h * qu[1] + eta * xi[1]};
  double dx[2] = {(s * cp - c * sp) / c * w + u[0] * (s * cp / c * xi[0] - sp * xl[0]),
                  u[0] * (s * xi[1] - sp * xl[1])};
  /* second-order hit point and normal tilt g2 = Q u2 + 1/2 c[u, u, .] */
  double u2v[2] = {s * (w + u[0] * xi[0]) / c, s * u[0] * xi[1]};
  double g2[2];
  for (int k = 0; k < 2; k++) {
    double cub = 0.0;
    if (cubic)
      for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
          cub += cubic_entry(cubic, i, j, k) * u[i] * u[j];
    g2[k] = q.m[k][0] * u2v[0] + q.m[k][1] * u2v[1] + 0.5 * cub;
  }
  double xx = xi[0] * xi[0] + xi[1] * xi[1], gg = qu[0] * qu[0] + qu[1] * qu[1];
  double dc1 = -s * (qu[0] + xi[0]);
  double dxi[2];
  dxi[0] = -h / cp * g2[0] - 0.5 * eta * s * one_m * xx / cp + 0.5 * h * h * sp * gg / cp -
           eta * h * s * (qu[0] + xi[0]) * qu[0] -
           eta * h * sp / cp * (c * xi[0] * qu[0] + xi[1] * qu[1]) -
           0.5 * sp * eta * eta * one_m * dc1 * dc1 / (cp * cp * cp);
  dxi[1] = -h * g2[1] - eta * h * s / cp * (qu[0] + xi[0]) * qu[1];
  /* back to the element's output frame */
  double r_out[2][2] = {{px_vec3_dot(e->out.x1, q1), px_vec3_dot(e->out.x1, f->u2)},
                        {px_vec3_dot(e->out.x2, q1), px_vec3_dot(e->out.x2, f->u2)}};
  px_ray4_t r;
  for (int a = 0; a < 2; a++) {
    r.v[a] = r_out[a][0] * dx[0] + r_out[a][1] * dx[1];
    r.v[2 + a] = r_out[a][0] * dxi[0] + r_out[a][1] * dxi[1];
  }
  for (int i = 0; i < 4; i++)
    if (!isfinite(r.v[i]))
      return PX_ENONFINITE;
  *out = r;
  return PX_OK;
}

px_status_t px_cascade_weights(const px_cascade_t *c, size_t i, double lambda[4], double mu[4]) {
  if (i == 0 || i > c->n)
    return PX_EINVAL;
  px_mat4_t ta = px_cascade_after(c, i), tb = px_cascade_before(c, i);
  for (int k = 0; k < 4; k++) {
    lambda[k] = px_mat2_norm2(px_mat4_block(ta, k / 2, k % 2));
    mu[k] = px_mat2_norm2(px_mat4_block(tb, k / 2, k % 2));
  }
  return PX_OK;
}

/* M^t S M for symmetric S = [[s11, s12], [s12, s22]] and M = [[m0, m1], [m2, m3]] */
static void congruence(const double m[4], double s11, double s12, double s22, double r[3]) {
  double a0 = s11 * m[0] + s12 * m[2], a1 = s11 * m[1] + s12 * m[3]; /* row 1 of S M */
  double b0 = s12 * m[0] + s22 * m[2], b1 = s12 * m[1] + s22 * m[3]; /* row 2 of S M */
  r[0] = m[0] * a0 + m[2] * b0;
  r[1] = m[0] * a1 + m[2] * b1;
  r[2] = m[1] * a1 + m[3] * b1;
}

px_status_t px_pencil_constants(const px_cascade_t *c, const double *d3m, px_variant_t variant,
                                px_pencil_t *out) {
  px_pencil_t sum = {0, 0, 0, 0, 0, 0};
  for (size_t i = 1; i <= c->n; i++) {
    const px_element_t *e = &c->elem[i - 1];
    if (e->kind == PX_ELEMENT_TRANSFER)
      continue;
    px_coeffs_t k;
    px_status_t st = px_element_coeffs(e, d3m ? d3m[i - 1] : 0.0, variant, &k);
    double lam[4], mu[4];
    if (st == PX_OK)
      st = px_cascade_weights(c, i, lam, mu);
    if (st != PX_OK)
      return st;
    double rx[3], rxi[3];
    /* e_x: lambda_1 P + lambda_2 Q; e_xi: lambda_3 P + lambda_4 Q (Appendix (3)) */
    congruence(mu, lam[0] * k.a + lam[1] * k.d, 0.5 * (lam[0] * k.b + lam[1] * k.e),
               lam[0] * k.c + lam[1] * k.f, rx);
    congruence(mu, lam[2] * k.a + lam[3] * k.d, 0.5 * (lam[2] * k.b + lam[3] * k.e),
               lam[2] * k.c + lam[3] * k.f, rxi);
    sum.a += rx[0];
    sum.b += 2.0 * rx[1];
    sum.c += rx[2];
    sum.d += rxi[0];
    sum.e += 2.0 * rxi[1];
    sum.f += rxi[2];
  }
  if (!coeffs_finite(&sum))
    return PX_ENONFINITE;
  *out = sum;
  return PX_OK;
}

double px_pencil_ex(const px_pencil_t *k, double x0, double xi0) {
  return k->a * x0 * x0 + k->b * x0 * xi0 + k->c * xi0 * xi0;
}

double px_pencil_exi(const px_pencil_t *k, double x0, double xi0) {
  return k->d * x0 * x0 + k->e * x0 * xi0 + k->f * xi0 * xi0;
}

px_status_t px_tolerance(px_mat4_t t, px_ray4_t delta, double rho, double *tau) {
  if (!(rho > 0.0) || !isfinite(rho) || !px_mat4_isfinite(t))
    return PX_EINVAL;
  double p[2] = {0.0, 0.0};
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 4; j++) {
      if (!isfinite(delta.v[j]))
        return PX_EINVAL;
      p[i] = fma(t.m[i][j], delta.v[j], p[i]);
    }
  double r = rho * hypot(p[0], p[1]); /* Eq. (3) */
  if (!isfinite(r))
    return PX_ENONFINITE;
  *tau = r;
  return PX_OK;
}

int px_pencil_accept(const px_pencil_t *k, double x0, double xi0, double tau) {
  return px_pencil_ex(k, x0, xi0) <= tau; /* Eq. (5) */
}

px_status_t px_spread_limit(double c, double k3, double tau, double cap, double *xi_max,
                            px_spread_regime_t *regime) {
  if (!(tau > 0.0) || !isfinite(tau) || !(c >= 0.0) || !isfinite(c) || !(k3 >= 0.0) ||
      !isfinite(k3) || !(cap > 0.0) || !isfinite(cap))
    return PX_EINVAL;
  /* p(xi) = c xi^2 + k3 xi^3 - tau is increasing on xi >= 0; p(0) < 0 */
  double p_cap = (c + k3 * cap) * cap * cap - tau;
  px_spread_regime_t why;
  double x;
  if (!(p_cap > 0.0)) {
    x = cap;
    why = PX_SPREAD_CAP;
  } else {
    /* bracket [0, min(cap, sqrt(tau/c), cbrt(tau/k3))], then safeguarded Newton */
    double hi = cap;
    if (c > 0.0)
      hi = fmin(hi, sqrt(tau / c));
    if (k3 > 0.0)
      hi = fmin(hi, cbrt(tau / k3));
    double lo = 0.0;
    x = hi;
    for (int it = 0; it < 200; it++) {
      double p = (c + k3 * x) * x * x - tau, dp = (2.0 * c + 3.0 * k3 * x) * x;
      if (p > 0.0)
        hi = x;
      else
        lo = x;
      double nx = dp > 0.0 ? x - p / dp : 0.5 * (lo + hi);
      if (!(nx > lo && nx < hi))
        nx = 0.5 * (lo + hi);
      if (fabs(nx - x) <= 1e-15 * x || hi - lo <= 1e-15 * hi) {
        x = nx;
        break;
      }
      x = nx;
    }
    why = c * x * x >= k3 * x * x * x ? PX_SPREAD_SECOND_ORDER : PX_SPREAD_THIRD_ORDER;
  }
  if (!isfinite(x))
    return PX_ENONFINITE;
  *xi_max = x;
  if (regime)
    *regime = why;
  return PX_OK;
}
