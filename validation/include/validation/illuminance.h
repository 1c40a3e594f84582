/* illuminance.h -- `pencil verify illuminance`: the illuminance formulas of the 1987 paper
 * (Eqs. 8-9, paraxial/illuminance.h) against the exact flux Jacobian of light paths (the area
 * exactly traced rays cover on the receiver per unit of the source's measure, ex_flux_q), over
 * the systems of the matrix sweep with point and parallel sources and receivers at every angle,
 * and a family of receivers approaching caustics. */
#ifndef VALIDATION_ILLUMINANCE_H
#define VALIDATION_ILLUMINANCE_H

#include <stdio.h>

#include "paraxial/illuminance.h"
#include "validation/systems.h"

/** Tolerance on the relative error of dOmega/dS (or dS0/dS) away from caustics: where the
 *  determinant's condition is at most VAL_ILLUM_COND_AWAY. */
#define VAL_ILLUM_TOL 1e-9
#define VAL_ILLUM_COND_AWAY 1e3
/** Nearer caustics the ratio's relative error is at most about cond times the entries' relative
 *  error (first order); this factor covers the second-order rest and the entries' spread. */
#define VAL_ILLUM_COND_FACTOR 4.0

/** One case: a system, a source kind and a receiver. */
typedef struct {
  px_status_t status;       /**< the formula's status (PX_OK, PX_ECAUSTIC, ...) */
  px_status_t exact_status; /**< the exact flux Jacobian's */
  double ratio;             /**< the formula: |cos alpha| / |det B| (or A) */
  double exact;             /**< 1 / (exact area per unit source measure) */
  double cond;              /**< the determinant's condition */
  double rel_err;           /**< |ratio - exact| / exact */
  double formula_err;       /**< the same with the exact Jacobian's block in place of the system
                                 matrix's: the error of Eq. (8) or (9) itself */
  double matrix_err;        /**< scaled relative error of the system matrix (verify matrices) */
  double printed_err;       /**< the same for the 1989 Eq. (1) as printed (factor n1/n2) */
  double n_source, n_receiver, cos_alpha, tail;
  int pass; /**< the formula within VAL_ILLUM_TOL; the system matrix's ratio
                 within VAL_ILLUM_TOL away from caustics and within
                 VAL_ILLUM_COND_FACTOR cond max(matrix_err, PX_ENTRY_EPS) nearer;
                 a PX_ECAUSTIC refusal only where cond says it must */
} val_illum_result_t;

typedef struct {
  int quick;        /**< small sweep (tests) */
  const char *json; /**< summary JSON path or NULL */
  const char *csv;  /**< per-case CSV path or NULL */
  FILE *report;     /**< human-readable table (stdout) or NULL */
} val_illum_opts_t;

/** One case: system v (its tail replaced by `tail` when > 0), source `src`, receiver normal at
 *  angle alpha_deg to the arriving axial ray, turned by phi_deg about it. */
void val_verify_illum_case(const val_system_t *v, px_source_t src, double tail, double alpha_deg,
                           double phi_deg, val_illum_result_t *r);

/** The energy check of the 1989 Eq. (1) on a pool: a point source h1 above a flat water surface
 *  (index n2), the floor h2 below it. The flux that Eq. (8) (or its printed form) puts on the
 *  floor within the image of the cone of half-angle theta0, integrated over the floor, divided
 *  by the flux the source sends into that cone (1 when energy is conserved). */
double val_pool_flux_ratio(double h1, double h2, double n2, double theta0_deg, px_variant_t v);

/** The pool again, counted: a point light h1 above a square of water (index n2, side 2, kt 1) whose
 *  floor is h2 below the surface, the floor's illuminance in a cell x cell square on the axis by
 *  `pencil illuminance`'s grid-pencils (out[0]) and photons (out[1]), beside Eq. (8) (out[2]) and
 *  the printed Eq. (1) (out[3]) for the axial ray. 0 on a failure (message on stderr). */
int val_pool_counted(double h1, double h2, double n2, double cell, double out[4]);

/** Run the sweep; 0 when every case passes, 1 when some fail, -1 on an I/O error. */
int val_verify_illuminance(const val_illum_opts_t *opts);

#endif
