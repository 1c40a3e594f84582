/* dispersion.h -- `pencil verify dispersion`: the wavelength column of the 1989 Eq. (13)
 * (paraxial/dispersion.h) against exact tracing differentiated in wavelength.
 *
 * Every system of the matrix sweep (validation/systems.h: refractions and reflections on planes,
 * spheres both ways round, cylinders and ellipsoids, rotated frames, near the critical angle,
 * cascades) is given dispersive media twice, a glass of low dispersion (V_d = 64.17, N-BK7's)
 * and one of high dispersion (V_d = 20, a dense flint): each medium of index n > 1 becomes the
 * Cauchy model with n_d = n (paraxial/dispersion.h), air stays constant, and the axial ray is
 * traced at the d-line. The column of the cascade's 5 x 5 product is compared with the exact
 * one, the sum over the media of d psi'/d n_m dn_m/dlambda, each derivative by Richardson central
 * differences of the exact map (ex_map_q, __float128) at psi = 0 with the axial record fixed, in
 * steps of 2^-26 and 2^-27 of the index (exact in double): the scaled relative error (positions
 * over the system's length) must be within VAL_DISP_TOL. The printed Eq. (14)
 * is measured the same way. A tolerance sweep says how far in wavelength the linear model holds
 * (the paper's "dn/dlambda roughly constant"): the exact ray vector at delta-lambda from -200 to
 * +190 nm against the column times delta-lambda. */
#ifndef VALIDATION_DISPERSION_H
#define VALIDATION_DISPERSION_H

#include <stdio.h>

/** Tolerance on the column's scaled relative error. */
#define VAL_DISP_TOL 1e-9

typedef struct {
  int quick;        /**< the small sweep (tests) */
  const char *json; /**< summary JSON path or NULL */
  const char *csv;  /**< per-system CSV path or NULL */
  FILE *report;     /**< human-readable table (stdout) or NULL */
} val_disp_opts_t;

/** Run it: 0 when every column is within VAL_DISP_TOL, 1 when one is not, -1 on an I/O error. */
int val_verify_dispersion(const val_disp_opts_t *o);

#endif
