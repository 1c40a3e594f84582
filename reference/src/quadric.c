/* quadric.c -- quadric surfaces and their local geometry for Eq. (2). */
#include "exact/quadric.h"

#include <math.h>
#include <string.h>

static ex_quadric_t zero_quadric(void) {
  ex_quadric_t q;
  memset(&q, 0, sizeof q);
  return q;
}

ex_quadric_t ex_quadric_plane(px_vec3_t point, px_vec3_t normal) {
  ex_quadric_t q = zero_quadric(); /* F = 2 n.(p - point) */
  px_vec3_t n;
  if (px_vec3_normalize(normal, &n) != PX_OK)
    n = px_vec3(0, 0, 1);
  q.b[0] = n.x;
  q.b[1] = n.y;
  q.b[2] = n.z;
  q.c = -2.0 * px_vec3_dot(n, point);
  return q;
}

/* F = (p-c)^t M (p-c) - k for a given M: b = -M c, c = c^t M c - k */
static ex_quadric_t centred(const double m[9], px_vec3_t c, double k) {
  ex_quadric_t q = zero_quadric();
  memcpy(q.m, m, sizeof q.m);
  double cv[3] = {c.x, c.y, c.z};
  double ctmc = 0.0;
  for (int i = 0; i < 3; i++) {
    double mc = 0.0;
    for (int j = 0; j < 3; j++)
      mc += m[3 * i + j] * cv[j];
    q.b[i] = -mc;
    ctmc += cv[i] * mc;
  }
  q.c = ctmc - k;
  return q;
}

ex_quadric_t ex_quadric_sphere(px_vec3_t centre, double r) {
  const double m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  return centred(m, centre, r * r);
}

ex_quadric_t ex_quadric_cylinder(px_vec3_t point, px_vec3_t axis, double r) {
  px_vec3_t a;
  if (px_vec3_normalize(axis, &a) != PX_OK)
    a = px_vec3(0, 0, 1);
  const double av[3] = {a.x, a.y, a.z};
  double m[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      m[3 * i + j] = (i == j ? 1.0 : 0.0) - av[i] * av[j];
  return centred(m, point, r * r);
}

ex_quadric_t ex_quadric_ellipsoid(px_vec3_t centre, const px_vec3_t axes[3], double a, double b,
                                  double c) {
  const double inv2[3] = {1.0 / (a * a), 1.0 / (b * b), 1.0 / (c * c)};
  double m[9] = {0};
  for (int k = 0; k < 3; k++) {
    const double e[3] = {axes[k].x, axes[k].y, axes[k].z};
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++)
        m[3 * i + j] += inv2[k] * e[i] * e[j];
  }
  return centred(m, centre, 1.0);
}

px_vec3_t ex_quadric_half_gradient(const ex_quadric_t *q, px_vec3_t p) {
  const double *m = q->m;
  return px_vec3(m[0] * p.x + m[1] * p.y + m[2] * p.z + q->b[0],
                 m[3] * p.x + m[4] * p.y + m[5] * p.z + q->b[1],
                 m[6] * p.x + m[7] * p.y + m[8] * p.z + q->b[2]);
}

double ex_quadric_eval(const ex_quadric_t *q, px_vec3_t p) {
  px_vec3_t g = ex_quadric_half_gradient(q, p); /* p^t M p + 2 b.p + c = p.(Mp + b) + b.p + c */
  return px_vec3_dot(p, g) + q->b[0] * p.x + q->b[1] * p.y + q->b[2] * p.z + q->c;
}

px_status_t ex_quadric_interface(const ex_quadric_t *q, px_vec3_t p, px_vec3_t s, px_vec3_t hint,
                                 double n1, double n2, px_interface_t *out) {
  px_vec3_t g = ex_quadric_half_gradient(q, p);
  double gn = px_vec3_norm(g);
  if (!(gn > 0.0) || !isfinite(gn))
    return PX_ESINGULAR;
  /* Along nu_F = g/|g| the surface height is w = -(u^t M u)/|g| + O(u^3), i.e. Q = -M/|g|
   * (F = 0 with Hessian 2M and gradient 2g); px_interface_make flips both when nu_F.s < 0. */
  double qw[9];
  for (int i = 0; i < 9; i++)
    qw[i] = -q->m[i] / gn;
  return px_interface_make(s, px_vec3_scale(g, 1.0 / gn), hint, px_mat2_zero(), qw, n1, n2, out);
}

px_status_t ex_quadric_cubic(const ex_quadric_t *q, px_vec3_t p, const px_interface_t *ifc,
                             double cubic[4]) {
  /* With g = M p + b = sigma |g| nu, the points p + t + w nu on F = 0 satisfy
   * 2 sigma |g| w + t^t M t + 2 w t^t M nu + O(w^2) = 0, so w = 1/2 t^t Q t + 1/2 (t^t Q t)(m . t)
   * + O(t^4) with m_k = -sigma (u_k . M nu) / |g|: c_ijk = Q_ij m_k + Q_ik m_j + Q_jk m_i. */
  px_vec3_t g = ex_quadric_half_gradient(q, p);
  double gn = px_vec3_norm(g);
  if (!(gn > 0.0) || !isfinite(gn))
    return PX_ESINGULAR;
  double sigma = px_vec3_dot(g, ifc->nu) >= 0.0 ? 1.0 : -1.0;
  const double *m = q->m;
  px_vec3_t n = ifc->nu;
  px_vec3_t mn = px_vec3(m[0] * n.x + m[1] * n.y + m[2] * n.z, m[3] * n.x + m[4] * n.y + m[5] * n.z,
                         m[6] * n.x + m[7] * n.y + m[8] * n.z);
  double mt[2] = {-sigma * px_vec3_dot(ifc->u1, mn) / gn, -sigma * px_vec3_dot(ifc->u2, mn) / gn};
  const px_mat2_t Q = ifc->q;
  /* entries by the number of indices equal to 2: (111), (112), (122), (222) */
  cubic[0] = 3.0 * Q.m[0][0] * mt[0];
  cubic[1] = Q.m[0][0] * mt[1] + 2.0 * Q.m[0][1] * mt[0];
  cubic[2] = 2.0 * Q.m[0][1] * mt[1] + Q.m[1][1] * mt[0];
  cubic[3] = 3.0 * Q.m[1][1] * mt[1];
  for (int i = 0; i < 4; i++)
    if (!isfinite(cubic[i]))
      return PX_ENONFINITE;
  return PX_OK;
}
