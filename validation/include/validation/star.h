/* star.h -- `pencil verify star`: the cross-screen filter's derivation (1989 paper, section 4.1)
 * against a simulated plate.
 *
 * A parallel bundle along the axis meets a glass plate of index n whose front face has the unit
 * normal N (tilted by a scratch) and whose back face is flat; an ideal lens of focal length d
 * images the leaving direction u at d (u_x, u_y) / u_z. The paper linearises Snell's law there:
 * (x, y) = (n - 1) d (N_x, N_y), which gives the kernel of Eq. (16). The simulation refracts
 * exactly at both faces (vector Snell's law, total internal reflection at the back face when the
 * tilt is too steep) and compares:
 *  - the landing point against the linear one, over tilt slopes from 1e-4 to past total internal
 *    reflection, for several indices and an oblique tilt direction: the first-order agreement
 *    (the derivation's claim), the sign convention of N, and the slopes where the linearisation
 *    errs by 1% and 10%;
 *  - the star's profile along a ray for the plate's two-Gaussian slope distribution: the exact
 *    landing distribution against Eq. (16)'s, both histogrammed on the same bins: the total
 *    variation distance, the ratio of RMS widths, and the light lost to total internal
 *    reflection. */
#ifndef VALIDATION_STAR_H
#define VALIDATION_STAR_H

#include <stdio.h>

/** The exact landing point of the bundle through a front face of unit normal N = (s cos phi,
 *  s sin phi, -1) / sqrt(1 + s^2) (facing the light), on the focal plane of a lens of focal
 *  length d, in x[2]: 0 when the back face reflects it totally. */
int val_star_exact(double n, double s, double phi, double d, double x[2]);

typedef struct {
  int quick;        /**< fewer slopes and plates (tests) */
  const char *json; /**< summary JSON path or NULL */
  const char *csv;  /**< per-slope CSV path or NULL */
  FILE *report;     /**< human-readable table (stdout) or NULL */
} val_star_opts_t;

/** Run it: 0 when the linearisation agrees with exact refraction to first order (relative error
 *  below 1e-6 at a slope of 1e-4 for every index and direction) and both landing distributions
 *  hold the same light; 1 when not; -1 on an I/O error. */
int val_verify_star(const val_star_opts_t *o);

#endif
