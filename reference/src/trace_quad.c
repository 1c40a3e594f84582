/* trace_quad.c -- the exact map and its Jacobian in __float128 (libquadmath), for verification:
 * 113-bit significands leave ~1e-22 of rounding in a 1e-12 central difference. */
#include "exact/trace.h"

#include <math.h>
#include <quadmath.h>

#define REAL __float128
#define R_SQRT sqrtq
#define FN(name) name##_q
#define JAC_STEP 1e-12
#include "trace_impl.h"
