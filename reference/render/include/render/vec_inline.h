/* vec_inline.h -- internal to the renderers (reference/render, pencil/): inline 3-vector
 * arithmetic for the per-ray code. libparaxial's px_vec3_*
 * functions live in another translation unit and are not inlined without LTO; these are the
 * same operations on the same px_vec3_t, visible to the optimiser. */
#ifndef RENDER_VEC_INLINE_H
#define RENDER_VEC_INLINE_H

#include <math.h>

#include "paraxial/linalg.h"

static inline px_vec3_t v3(double x, double y, double z) {
  return (px_vec3_t){x, y, z};
}
static inline px_vec3_t v3_add(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){a.x + b.x, a.y + b.y, a.z + b.z};
}
static inline px_vec3_t v3_sub(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){a.x - b.x, a.y - b.y, a.z - b.z};
}
static inline px_vec3_t v3_scale(px_vec3_t a, double s) {
  return (px_vec3_t){a.x * s, a.y * s, a.z * s};
}
/** s * x + y */
static inline px_vec3_t v3_axpy(double s, px_vec3_t x, px_vec3_t y) {
  return (px_vec3_t){s * x.x + y.x, s * x.y + y.y, s * x.z + y.z};
}
static inline double v3_dot(px_vec3_t a, px_vec3_t b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline double v3_norm(px_vec3_t a) {
  return sqrt(v3_dot(a, a));
}
/** Unit vector along a (a must be non-zero: callers pass directions). */
static inline px_vec3_t v3_unit(px_vec3_t a) {
  return v3_scale(a, 1.0 / v3_norm(a));
}
/** Component `axis` (0, 1, 2). */
static inline double v3_at(px_vec3_t v, int axis) {
  return axis == 0 ? v.x : (axis == 1 ? v.y : v.z);
}
/** Branch-free min and max without libm calls. Unlike fmin/fmax they return the second operand
 *  when either is NaN; the slab test in query.c relies on that. */
static inline double mind(double a, double b) {
  return a < b ? a : b;
}
static inline double maxd(double a, double b) {
  return a > b ? a : b;
}

#endif
