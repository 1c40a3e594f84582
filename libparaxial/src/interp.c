/* interp.c -- ray interpolation and its error e_int (section 4.1 (2)). */
#include "paraxial/interp.h"

#include <math.h>

void px_interp_linear(size_t n, const double *x0, const double *x1, double a, double *out) {
  for (size_t i = 0; i < n; i++)
    out[i] = fma(a, x1[i] - x0[i], x0[i]);
}

void px_interp_quadratic(size_t n, const double *xm1, const double *x0, const double *x1, double a,
                         double *out) {
  double wm = 0.5 * a * (a - 1.0), w0 = (1.0 - a) * (1.0 + a), w1 = 0.5 * a * (1.0 + a);
  for (size_t i = 0; i < n; i++)
    out[i] = wm * xm1[i] + w0 * x0[i] + w1 * x1[i];
}

/* |quadratic - linear| = |a (a - 1) / 2| |xm1 - 2 x0 + x1| */
static double second_difference(size_t n, const double *xm1, const double *x0, const double *x1) {
  double s = 0.0;
  for (size_t i = 0; i < n; i++) {
    double d = xm1[i] - 2.0 * x0[i] + x1[i];
    s += d * d;
  }
  return sqrt(s);
}

double px_interp_error(size_t n, const double *xm1, const double *x0, const double *x1, double a) {
  return fabs(0.5 * a * (a - 1.0)) * second_difference(n, xm1, x0, x1);
}

double px_interp_error_max(size_t n, const double *xm1, const double *x0, const double *x1) {
  return 0.125 * second_difference(n, xm1, x0, x1);
}

void px_interp_bilinear(size_t n, const double *c00, const double *c10, const double *c01,
                        const double *c11, double u, double v, double *out) {
  for (size_t i = 0; i < n; i++) {
    double b = fma(u, c10[i] - c00[i], c00[i]);
    double t = fma(u, c11[i] - c01[i], c01[i]);
    out[i] = fma(v, t - b, b);
  }
}
