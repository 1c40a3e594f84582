/* pvec.h -- private: inline 3-vector arithmetic for the pencil renderer's per-sample code
 * (libparaxial's px_vec3_* live in another translation unit and are not inlined without LTO). */
#ifndef PENCIL_PVEC_H
#define PENCIL_PVEC_H

#include <math.h>

#include "paraxial/linalg.h"

static inline px_vec3_t pv(double x, double y, double z) {
  return (px_vec3_t){x, y, z};
}
static inline px_vec3_t pv_add(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){a.x + b.x, a.y + b.y, a.z + b.z};
}
static inline px_vec3_t pv_sub(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){a.x - b.x, a.y - b.y, a.z - b.z};
}
static inline px_vec3_t pv_scale(px_vec3_t a, double s) {
  return (px_vec3_t){a.x * s, a.y * s, a.z * s};
}
/** s x + y */
static inline px_vec3_t pv_axpy(double s, px_vec3_t x, px_vec3_t y) {
  return (px_vec3_t){s * x.x + y.x, s * x.y + y.y, s * x.z + y.z};
}
static inline double pv_dot(px_vec3_t a, px_vec3_t b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline double pv_norm(px_vec3_t a) {
  return sqrt(pv_dot(a, a));
}
static inline px_vec3_t pv_unit(px_vec3_t a) {
  return pv_scale(a, 1.0 / pv_norm(a));
}

#endif
