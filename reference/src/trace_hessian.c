/* trace_hessian.c -- the second-order tensor t(2)_ijk = d2 psi'_i / d psi_j d psi_k of the exact
 * map (section 3.2) at psi = 0 from __float128 second differences of ex_map_q(), Richardson-
 * extrapolated. Independent of the jets of trace_jet.c, which it is cross-checked against. */
#include <math.h>
#include <string.h>

#include "exact/trace.h"

/* Base step, relative to the length scale for positions: truncation (h/rho)^4 after
 * extrapolation (rho = the map's radius of convergence), rounding ~1e-34 / h^2 = 1e-18; reduced
 * where rho is small (ex_hessian_q). */
#define HESS_STEP 1e-8

static px_status_t eval(const ex_system_t *sys, const ex_axial_t *ax, int j, __float128 hj, int k,
                        __float128 hk, __float128 out[4]) {
  __float128 p[4] = {0, 0, 0, 0};
  p[j] += hj;
  p[k] += hk;
  return ex_map_q(sys, ax, p, out);
}

/* second difference of component set at steps (hj, hk) */
static px_status_t diff2(const ex_system_t *sys, const ex_axial_t *ax, int j, int k, __float128 hj,
                         __float128 hk, const __float128 f0[4], __float128 d[4]) {
  __float128 a[4], b[4], c[4], e[4];
  px_status_t s;
  if (j == k) {
    if ((s = eval(sys, ax, j, hj, k, 0, a)) != PX_OK ||
        (s = eval(sys, ax, j, -hj, k, 0, b)) != PX_OK)
      return s;
    for (int i = 0; i < 4; i++)
      d[i] = (a[i] - 2 * f0[i] + b[i]) / (hj * hj);
    return PX_OK;
  }
  if ((s = eval(sys, ax, j, hj, k, hk, a)) != PX_OK ||
      (s = eval(sys, ax, j, hj, k, -hk, b)) != PX_OK ||
      (s = eval(sys, ax, j, -hj, k, hk, c)) != PX_OK ||
      (s = eval(sys, ax, j, -hj, k, -hk, e)) != PX_OK)
    return s;
  for (int i = 0; i < 4; i++)
    d[i] = (a[i] - b[i] - c[i] + e[i]) / (4 * hj * hk);
  return PX_OK;
}

/* the tensor from second differences with base step `step` (relative; positions times length) */
static px_status_t hessian_at(const ex_system_t *sys, const ex_axial_t *ax, double length,
                              double step, double r[4][4][4]) {
  __float128 f0[4], zero[4] = {0, 0, 0, 0};
  px_status_t s = ex_map_q(sys, ax, zero, f0);
  if (s != PX_OK)
    return s;
  for (int j = 0; j < 4; j++)
    for (int k = j; k < 4; k++) {
      __float128 hj = (__float128)step * (j < 2 ? (__float128)length : 1);
      __float128 hk = (__float128)step * (k < 2 ? (__float128)length : 1);
      __float128 d1[4], d2[4];
      if ((s = diff2(sys, ax, j, k, hj, hk, f0, d1)) != PX_OK ||
          (s = diff2(sys, ax, j, k, hj / 2, hk / 2, f0, d2)) != PX_OK)
        return s;
      for (int i = 0; i < 4; i++) {
        double v = (double)((4 * d2[i] - d1[i]) / 3);
        if (!(v == v) || v - v != 0) /* NaN or Inf */
          return PX_ENONFINITE;
        r[i][j][k] = r[i][k][j] = v;
      }
    }
  return PX_OK;
}

px_status_t ex_hessian_q(const ex_system_t *sys, const ex_axial_t *ax, double length,
                         double hess[4][4][4]) {
  /* The step must stay well inside the map's radius of convergence rho, which near grazing
   * incidence shrinks like L cos^2(theta) (3e-8 L at 89.99 deg). rho is estimated as
   * |J| / |t(2)| (scaled by L) from a first pass and the step reduced to 1e-3 rho: the
   * extrapolated truncation error is then ~(1e-3)^4, the rounding ~1e-34 |J| / step. */
  double r[4][4][4], step = HESS_STEP;
  px_mat4_t jac;
  px_status_t s = ex_jacobian_q(sys, ax, length, &jac);
  for (int pass = 0; pass < 3 && s == PX_OK; pass++) {
    if ((s = hessian_at(sys, ax, length, step, r)) != PX_OK)
      break;
    double jn = 0.0, hn = 0.0;
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++) {
        jn = fmax(jn, fabs(jac.m[i][j] * (i < 2 ? 1.0 / length : 1.0) * (j < 2 ? length : 1.0)));
        for (int k = 0; k < 4; k++)
          hn = fmax(hn, fabs(r[i][j][k] * (i < 2 ? 1.0 / length : 1.0) * (j < 2 ? length : 1.0) *
                             (k < 2 ? length : 1.0)));
      }
    double rho = hn > 0.0 ? jn / hn : INFINITY;
    if (!(step > 1e-3 * rho))
      break;
    step = 1e-3 * rho;
  }
  if (s != PX_OK)
    return s;
  memcpy(hess, r, sizeof r);
  return PX_OK;
}
