/* vec3.h -- the project's one 3-vector library: inline arithmetic on px_vec3_t for per-ray code
 * in every layer (libparaxial, the core, the renderers), and the one min and max.
 *
 * Rounding policy. Every function rounds exactly as its expression is written, in the order
 * written: the project compiles C with contraction off (ISO C mode, and -ffp-contract=off for
 * libparaxial), so no compiler fuses a product into a sum behind the code's back and results
 * are the same in every build. Two families:
 *   - plain (px_v3_dot, px_v3_axpy, px_v3_norm, px_v3_unit): each product and each sum rounded;
 *     the renderers' geometry (intersections, shading) is defined by these;
 *   - fused (px_v3_dot_fma, px_v3_axpy_fma, px_v3_norm_fma, px_v3_cross, px_v3_normalize):
 *     multiply-adds through fma(), one rounding less, correctly rounded whether libm or an FMA
 *     instruction computes it (so bit-identical either way); libparaxial's frames, interfaces
 *     and Snell's law (px_interface_outgoing, section 2.2) use these, and the exported
 *     px_vec3_* functions of linalg.h are these. px_v3_cross subtracts products with Kahan's
 *     compensated difference (px_diff_products), which keeps it accurate where the two
 *     products nearly cancel (nearly parallel vectors).
 * add, sub and scale round once per component and belong to both families.
 *
 * px_min and px_max propagate NaN: a NaN in either operand gives NaN, so that an error bound
 * that failed is never mistaken for a small one. (The BVH slab test, which needs the opposite,
 * has its own ordered min and max, private to core/src/prim.h.) No libm call is made. */
#ifndef PARAXIAL_VEC3_H
#define PARAXIAL_VEC3_H

#include <math.h>

#include "paraxial/linalg.h"
#include "paraxial/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** max(a, b), NaN when either is NaN. */
static inline double px_max(double a, double b) {
  return a > b || a != a ? a : b;
}
/** min(a, b), NaN when either is NaN. */
static inline double px_min(double a, double b) {
  return a < b || a != a ? a : b;
}

/** The vector (x, y, z); an initialised local rather than a compound literal, so that the header
 *  is also valid C++. */
static inline px_vec3_t px_v3(double x, double y, double z) {
  px_vec3_t v = {x, y, z};
  return v;
}
static inline px_vec3_t px_v3_add(px_vec3_t a, px_vec3_t b) {
  return px_v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline px_vec3_t px_v3_sub(px_vec3_t a, px_vec3_t b) {
  return px_v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline px_vec3_t px_v3_scale(px_vec3_t a, double s) {
  return px_v3(a.x * s, a.y * s, a.z * s);
}
/** Component `axis` (0, 1, 2). */
static inline double px_v3_at(px_vec3_t v, int axis) {
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}

/* ---- plain: every product and sum rounded ------------------------------------------------- */

/** s * x + y */
static inline px_vec3_t px_v3_axpy(double s, px_vec3_t x, px_vec3_t y) {
  return px_v3(s * x.x + y.x, s * x.y + y.y, s * x.z + y.z);
}
static inline double px_v3_dot(px_vec3_t a, px_vec3_t b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline double px_v3_norm(px_vec3_t a) {
  return sqrt(px_v3_dot(a, a));
}
/** Unit vector along a (a must be non-zero and finite: callers pass directions). */
static inline px_vec3_t px_v3_unit(px_vec3_t a) {
  return px_v3_scale(a, 1.0 / px_v3_norm(a));
}

/* ---- fused: multiply-adds through fma() --------------------------------------------------- */

/** s * x + y, each component one fma() */
static inline px_vec3_t px_v3_axpy_fma(double s, px_vec3_t x, px_vec3_t y) {
  return px_v3(fma(s, x.x, y.x), fma(s, x.y, y.y), fma(s, x.z, y.z));
}
static inline double px_v3_dot_fma(px_vec3_t a, px_vec3_t b) {
  return fma(a.x, b.x, fma(a.y, b.y, a.z * b.z));
}
static inline double px_v3_norm_fma(px_vec3_t a) {
  return sqrt(px_v3_dot_fma(a, a));
}
/** a*b - c*d with one rounding error less (Kahan's compensated difference of products). */
static inline double px_diff_products(double a, double b, double c, double d) {
  double cd = c * d;
  double err = fma(-c, d, cd);
  return fma(a, b, -cd) + err;
}
static inline px_vec3_t px_v3_cross(px_vec3_t a, px_vec3_t b) {
  return px_v3(px_diff_products(a.y, b.z, a.z, b.y), px_diff_products(a.z, b.x, a.x, b.z),
               px_diff_products(a.x, b.y, a.y, b.x));
}
/** a / |a| (fused norm); PX_ESINGULAR for a zero, infinite or NaN vector. */
static inline px_status_t px_v3_normalize(px_vec3_t a, px_vec3_t *out) {
  double n = px_v3_norm_fma(a);
  if (!(n > 0.0) || !isfinite(n))
    return PX_ESINGULAR;
  *out = px_v3_scale(a, 1.0 / n);
  return PX_OK;
}

#ifdef __cplusplus
}
#endif

#endif
