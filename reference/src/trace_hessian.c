/* trace_hessian.c -- the second-order tensor t(2)_ijk = d2 psi'_i / d psi_j d psi_k of the exact
 * map (section 3.2) at psi = 0 from __float128 second differences of ex_map_q(), Richardson-
 * extrapolated. Independent of the jets of trace_jet.c, which it is cross-checked against. */
#include "exact/trace.h"

/* Step, relative to the length scale for positions: truncation (h/rho)^4 after extrapolation
 * (rho = the map's radius of convergence, >= ~1e-5 rad even 0.001 deg from the critical angle
 * in the sweep: <= 1e-13), rounding ~1e-34 / h^2 = 1e-18. */
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
    if ((s = eval(sys, ax, j, hj, k, 0, a)) != PX_OK || (s = eval(sys, ax, j, -hj, k, 0, b)) != PX_OK)
      return s;
    for (int i = 0; i < 4; i++)
      d[i] = (a[i] - 2 * f0[i] + b[i]) / (hj * hj);
    return PX_OK;
  }
  if ((s = eval(sys, ax, j, hj, k, hk, a)) != PX_OK || (s = eval(sys, ax, j, hj, k, -hk, b)) != PX_OK ||
      (s = eval(sys, ax, j, -hj, k, hk, c)) != PX_OK || (s = eval(sys, ax, j, -hj, k, -hk, e)) != PX_OK)
    return s;
  for (int i = 0; i < 4; i++)
    d[i] = (a[i] - b[i] - c[i] + e[i]) / (4 * hj * hk);
  return PX_OK;
}

px_status_t ex_hessian_q(const ex_system_t *sys, const ex_axial_t *ax, double length,
                         double hess[4][4][4]) {
  __float128 f0[4], zero[4] = {0, 0, 0, 0};
  px_status_t s = ex_map_q(sys, ax, zero, f0);
  if (s != PX_OK)
    return s;
  double r[4][4][4];
  for (int j = 0; j < 4; j++)
    for (int k = j; k < 4; k++) {
      __float128 hj = (__float128)HESS_STEP * (j < 2 ? (__float128)length : 1);
      __float128 hk = (__float128)HESS_STEP * (k < 2 ? (__float128)length : 1);
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
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      for (int k = 0; k < 4; k++)
        hess[i][j][k] = r[i][j][k];
  return PX_OK;
}
