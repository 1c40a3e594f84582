/* wpencil_math.h -- private to core/ (and tests/test_wpencil.c): Snell's law and the mirror law
 * in vector form with their derivatives along a one-parameter family (the wavelength axis u of
 * spectral pencils, core/src/wpencil.c). d and m are unit vectors (the ray and the normal facing
 * it), dd and dm their derivatives (perpendicular to them), eta = n1 / n2 and deta its
 * derivative. */
#ifndef CORE_WPENCIL_MATH_H
#define CORE_WPENCIL_MATH_H

#include <math.h>

#include "paraxial/vec3.h"

static inline px_vec3_t wp_unit(px_vec3_t v) {
  return px_v3_scale(v, 1.0 / px_v3_norm(v));
}

/* d' = eta d + (eta c1 - c2) m, c1 = -d.m, c2 = sqrt(1 - eta^2 (1 - c1^2)) = *cos_t, and its
 * derivative *dout; 0 on total internal reflection. */
static inline int wp_refract_du(px_vec3_t d, px_vec3_t dd, px_vec3_t m, px_vec3_t dm, double eta,
                                double deta, px_vec3_t *out, px_vec3_t *dout, double *cos_t) {
  double c1 = -px_v3_dot(d, m);
  double k = 1.0 - eta * eta * (1.0 - c1 * c1);
  if (!(k > 0.0))
    return 0;
  double c2 = sqrt(k);
  double dc1 = -(px_v3_dot(dd, m) + px_v3_dot(d, dm));
  double dk = -2.0 * eta * deta * (1.0 - c1 * c1) + 2.0 * eta * eta * c1 * dc1;
  double dc2 = dk / (2.0 * c2);
  *out = px_v3_axpy(eta * c1 - c2, m, px_v3_scale(d, eta));
  px_vec3_t g = px_v3_axpy(eta, dd, px_v3_scale(d, deta));
  g = px_v3_axpy(deta * c1 + eta * dc1 - dc2, m, g);
  *dout = px_v3_axpy(eta * c1 - c2, dm, g);
  *cos_t = c2;
  return 1;
}

/* d' = d - 2 (d.m) m and its derivative *dout. */
static inline void wp_reflect_du(px_vec3_t d, px_vec3_t dd, px_vec3_t m, px_vec3_t dm,
                                 px_vec3_t *out, px_vec3_t *dout) {
  double c = px_v3_dot(d, m), dc = px_v3_dot(dd, m) + px_v3_dot(d, dm);
  *out = px_v3_axpy(-2.0 * c, m, d);
  *dout = px_v3_axpy(-2.0 * c, dm, px_v3_axpy(-2.0 * dc, m, dd));
}

#endif
