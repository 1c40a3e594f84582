/* trace.h -- exact Snell-law tracing of a ray vector through a sequence of real surfaces, and
 * the Jacobian of that exact map, the reference against which every system matrix is checked.
 *
 * An ex_system_t is an optical system as the paper sees it: an input ray frame at a point O on
 * the axial ray, a list of stages (a refraction or a reflection at a quadric), and a final
 * transfer of `tail` along the outgoing axial ray. ex_trace_axial() traces the axial ray once
 * and records, per stage, the hit, the surface geometry and the ray frames; from that record
 * ex_axial_cascade() builds the paraxial cascade and ex_map() carries any ray vector through
 * the same surfaces exactly. Double precision is the fast path; the _q functions use
 * __float128 (libquadmath) for verification. Nothing allocates.
 */
#ifndef EXACT_TRACE_H
#define EXACT_TRACE_H

#include <stddef.h>

#include "exact/quadric.h"
#include "paraxial/paraxial.h"

#define EX_MAX_STAGES 16

typedef struct {
  ex_quadric_t surface; /**< the real surface */
  px_event_t event;     /**< refraction or reflection */
  double n_after;       /**< index after the event (ignored for a reflection) */
  int at_origin;        /**< the axial ray meets this surface at its current point (t = 0):
                             used for single elements whose reference point O is on the surface */
} ex_stage_t;

typedef struct {
  px_vec3_t origin;        /**< O: start of the axial ray, the input reference plane's point */
  px_frame_t frame;        /**< input ray frame; frame.z is the axial direction */
  double n0;               /**< index of the starting medium */
  const ex_stage_t *stage; /**< caller-owned stages, stage[0] acts first */
  size_t nstage;           /**< number of stages, <= EX_MAX_STAGES */
  double tail;             /**< transfer after the last stage, along the outgoing axial ray */
  double out_phi;          /**< output frame: the last interface's frame rotated by out_phi
                                (ignored when there is no stage) */
} ex_system_t;

/** The axial ray's path, recorded once per system. */
typedef struct {
  size_t n;                          /**< stages traced */
  double t[EX_MAX_STAGES];           /**< ray parameter (distance) from the previous point */
  px_vec3_t hit[EX_MAX_STAGES];      /**< hit points */
  px_interface_t ifc[EX_MAX_STAGES]; /**< local geometry at each hit */
  px_frame_t in[EX_MAX_STAGES];      /**< ray frame arriving at stage k */
  px_frame_t out[EX_MAX_STAGES];     /**< ray frame leaving stage k */
  px_vec3_t out_origin;              /**< O': end of the axial ray */
  px_frame_t out_frame;              /**< output ray frame at O' */
  double length;                     /**< total geometric length of the axial path */
} ex_axial_t;

/** Trace the axial ray. Errors: PX_EMISS (a stage's surface is not met), PX_ETIR,
 *  PX_EGRAZING, PX_EINVAL (too many stages, bad index). */
px_status_t ex_trace_axial(const ex_system_t *sys, ex_axial_t *ax);

/** The paraxial cascade of the traced system: transfer, element, transfer, ... , tail.
 *  `storage` needs 2 * nstage + 2 elements. */
px_status_t ex_axial_cascade(const ex_system_t *sys, const ex_axial_t *ax, px_variant_t variant,
                             px_element_t *storage, size_t cap, px_cascade_t *out);

/** Exact map psi -> psi' in double precision. |xi| must be < 1. */
px_status_t ex_map(const ex_system_t *sys, const ex_axial_t *ax, const double psi[4],
                   double out[4]);

/** The Jacobian of the exact map at psi = 0 in double precision (Richardson-extrapolated
 *  central differences; relative accuracy ~1e-8). `length` scales the position steps. */
px_status_t ex_jacobian(const ex_system_t *sys, const ex_axial_t *ax, double length, px_mat4_t *j);

/** The exact map at psi0 with its Jacobian jac[i][j] = d psi'_i / d psi_j and second-order
 *  tensor hess[i][j][k] = t(2)_ijk = d2 psi'_i / d psi_j d psi_k (section 3.2), by forward-mode
 *  automatic differentiation with second-order jets through a copy of the map (trace_jet.c):
 *  exact derivatives up to double rounding, no step size. Any output pointer may be NULL. */
px_status_t ex_map_jet(const ex_system_t *sys, const ex_axial_t *ax, const double psi0[4],
                       double out[4], double jac[4][4], double hess[4][4][4]);

/** The exact flux Jacobian of a light pencil (illuminance, 1987 Eqs. 8-9): the area that the
 *  rays of a source at the system's input cover on a receiver plane through O' (the end of the
 *  axial ray) with normal receiver_normal (world coordinates, either sign), per unit solid angle
 *  of a point source at O (parallel = 0: rays psi = (0, 0, xi)) or per unit area across a
 *  parallel beam along z (parallel = 1: psi = (x, 0)). With energy conserved, the illuminance
 *  is E = t_r I / area. Richardson-extrapolated central differences of the receiver hits of
 *  exactly traced rays; `length` scales the position steps. PX_EGRAZING when a ray skims the
 *  receiver, and ex_map()'s statuses. */
px_status_t ex_flux(const ex_system_t *sys, const ex_axial_t *ax, px_vec3_t receiver_normal,
                    int parallel, double length, double *area);

#ifdef __SIZEOF_FLOAT128__
/** ex_flux() from __float128 differences (relative accuracy far below 1e-12 away from
 *  caustics, docs/verification.md). */
px_status_t ex_flux_q(const ex_system_t *sys, const ex_axial_t *ax, px_vec3_t receiver_normal,
                      int parallel, double length, double *area);
/** Exact map in __float128. */
px_status_t ex_map_q(const ex_system_t *sys, const ex_axial_t *ax, const __float128 psi[4],
                     __float128 out[4]);
/** Jacobian at psi = 0 from __float128 Richardson-extrapolated central differences: relative
 *  accuracy far below 1e-12 for all but the most extreme systems (docs/verification.md). */
px_status_t ex_jacobian_q(const ex_system_t *sys, const ex_axial_t *ax, double length,
                          px_mat4_t *j);
/** t(2)_ijk at psi = 0 from __float128 Richardson-extrapolated second differences of ex_map_q
 *  (trace_hessian.c), independent of ex_map_jet(). `length` scales the position steps. */
px_status_t ex_hessian_q(const ex_system_t *sys, const ex_axial_t *ax, double length,
                         double hess[4][4][4]);
#endif

#endif
