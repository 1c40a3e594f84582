/* trace_double.c -- the exact map and its Jacobian in double precision (the fast path). */
#include "exact/trace.h"

#include <math.h>

#define REAL double
#define R_SQRT sqrt
#define FN(name) name##_d
#define JAC_STEP 1e-4
/* the double-precision instances of trace_impl.h, private to this file */
static px_status_t ex_map_d(const ex_system_t *sys, const ex_axial_t *ax, const double psi[4],
                            double out[4]);
static px_status_t ex_jacobian_d(const ex_system_t *sys, const ex_axial_t *ax, double length,
                                 px_mat4_t *j);
static px_status_t ex_flux_d(const ex_system_t *sys, const ex_axial_t *ax,
                             px_vec3_t receiver_normal, int parallel, double length, double *area);
#include "trace_impl.h"

px_status_t ex_flux(const ex_system_t *sys, const ex_axial_t *ax, px_vec3_t receiver_normal,
                    int parallel, double length, double *area) {
  return ex_flux_d(sys, ax, receiver_normal, parallel, length, area);
}

px_status_t ex_map(const ex_system_t *sys, const ex_axial_t *ax, const double psi[4],
                   double out[4]) {
  return ex_map_d(sys, ax, psi, out);
}
px_status_t ex_jacobian(const ex_system_t *sys, const ex_axial_t *ax, double length, px_mat4_t *j) {
  return ex_jacobian_d(sys, ax, length, j);
}
