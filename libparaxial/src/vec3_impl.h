/* vec3_impl.h -- private to libparaxial: the 3-vector arithmetic of linalg.c as inline
 * functions, so that per-ray code in other files of the library (px_interface_outgoing, the
 * vector form of Snell's law, section 2.2) inlines it instead of calling out. The exported
 * px_vec3_* functions in linalg.c are these, so results are the same bit for bit.
 *
 * PX_FMA_CLONES marks a per-ray function to be compiled twice, for any x86-64 and for CPUs with
 * FMA instructions, the loader picking one (GCC/Clang target_clones, a glibc ifunc). fma() is
 * correctly rounded either way and the library is built with -ffp-contract=off, so the clones
 * compute identical results; the FMA clone only replaces each libm fma() call by an instruction.
 * The binary still runs on any x86-64. */
#ifndef PARAXIAL_VEC3_IMPL_H
#define PARAXIAL_VEC3_IMPL_H

#include <math.h>

#include "paraxial/linalg.h"

#ifndef PX_FMA_CLONES /* -DPX_FMA_CLONES= builds without clones, e.g. to compare results */
#if defined(__x86_64__) && defined(__linux__) && defined(__has_attribute)
#if __has_attribute(target_clones)
#define PX_FMA_CLONES __attribute__((target_clones("fma", "default")))
#endif
#endif
#endif
#ifndef PX_FMA_CLONES
#define PX_FMA_CLONES
#endif

static inline px_vec3_t vec3_add(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){a.x + b.x, a.y + b.y, a.z + b.z};
}
static inline px_vec3_t vec3_sub(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){a.x - b.x, a.y - b.y, a.z - b.z};
}
static inline px_vec3_t vec3_scale(px_vec3_t a, double s) {
  return (px_vec3_t){a.x * s, a.y * s, a.z * s};
}
static inline px_vec3_t vec3_axpy(double s, px_vec3_t x, px_vec3_t y) {
  return (px_vec3_t){fma(s, x.x, y.x), fma(s, x.y, y.y), fma(s, x.z, y.z)};
}
static inline double vec3_dot(px_vec3_t a, px_vec3_t b) {
  return fma(a.x, b.x, fma(a.y, b.y, a.z * b.z));
}

/* a*b - c*d with one rounding error less (Kahan's FMA trick, as in pbrt's DifferenceOfProducts) */
static inline double diff_products(double a, double b, double c, double d) {
  double cd = c * d;
  double err = fma(-c, d, cd);
  return fma(a, b, -cd) + err;
}

static inline px_vec3_t vec3_cross(px_vec3_t a, px_vec3_t b) {
  return (px_vec3_t){diff_products(a.y, b.z, a.z, b.y), diff_products(a.z, b.x, a.x, b.z),
                     diff_products(a.x, b.y, a.y, b.x)};
}
static inline double vec3_norm(px_vec3_t a) {
  return sqrt(vec3_dot(a, a));
}

static inline px_status_t vec3_normalize(px_vec3_t a, px_vec3_t *out) {
  double n = vec3_norm(a);
  if (!(n > 0.0) || !isfinite(n))
    return PX_ESINGULAR;
  *out = vec3_scale(a, 1.0 / n);
  return PX_OK;
}

#endif
