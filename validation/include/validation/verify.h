/* verify.h -- `pencil verify matrices`: every system matrix of the sweep against the Jacobian
 * of the exact map (quad-precision Richardson differences). */
#ifndef VALIDATION_VERIFY_H
#define VALIDATION_VERIFY_H

#include <stdio.h>

#include "validation/systems.h"

/** Tolerance on the scaled relative error of a system matrix (docs/verification.md). */
#define VAL_MATRIX_TOL 1e-9

typedef struct {
  px_status_t status;      /**< PX_OK, or why no matrix was produced (TIR for expect_tir) */
  int pass;                /**< 1 when the corrected matrix agrees within VAL_MATRIX_TOL, or the
                                system expects TIR and both sides report it */
  double rel_err;          /**< corrected variant: max over blocks */
  double block_err[4];     /**< corrected: A, B, C, D */
  double printed_err;      /**< printed variant: max over blocks */
  double printed_block[4]; /**< printed: A, B, C, D */
  double jac_norm;         /**< max |entry| of the scaled exact Jacobian */
} val_matrix_result_t;

/** Compare one system's matrices (both variants) with the exact Jacobian. */
void val_verify_matrix(const val_system_t *v, val_matrix_result_t *r);

typedef struct {
  int quick;        /**< small sweep (tests) */
  const char *json; /**< summary JSON path or NULL */
  const char *csv;  /**< per-system CSV path or NULL */
  FILE *report;     /**< human-readable table (stdout) or NULL */
} val_matrices_opts_t;

/** Run the sweep; returns 0 when every system passes, 1 when some fail, -1 on an I/O error
 *  (message on stderr, naming the file). */
int val_verify_matrices(const val_matrices_opts_t *opts);

/** t with the position-direction blocks scaled by the system's length L (B / L, C * L), so that
 *  the four 2x2 blocks are dimensionless and comparable: the scale in which matrix errors are
 *  "scaled relative" (docs/verification.md). */
px_mat4_t val_mat4_scaled(px_mat4_t t, double L);

#endif
