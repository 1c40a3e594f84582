/* illuminance.h -- the illuminance of a surface lit through an optical system (1987 paper,
 * section 4.2, Eqs. 8-9; 1989 paper, section 2.2.1, Eqs. 1, 2 and 6).
 *
 * A light pencil leaves a source, passes through refractions and reflections (system matrix
 * T = [[A, B], [C, D]] from the source's ray frame to the plane normal to the arriving axial ray
 * at the lit point) and falls on a surface whose normal makes the angle alpha with the arriving
 * axial ray. Energy is conserved along the pencil: the flux t_r I dOmega that leaves a point
 * source in the solid angle dOmega = |dxi1 dxi2| falls on the area dS = |dx'1 dx'2| / cos(alpha),
 * and x' = B xi, so
 *     E = t_r I cos(alpha) / |det B|                        point source, Eq. (8);
 *     E = t_r I cos(alpha) / |det A|                        parallel source, Eq. (9),
 * I being the intensity of a point source (flux per unit solid angle) or the irradiance of a
 * parallel beam across its own section (flux per unit area normal to it). Through a transfer of
 * length z alone det B = z^2: the inverse square law.
 *
 * The 1989 paper's Eq. (1) prints E = (n1/n2) t_r I dOmega/dS for a source in a medium of index
 * n1 and a surface in one of index n2. The factor contradicts the conservation of energy that
 * Eq. (1) states (flux is not created or destroyed at an interface beyond what t_r accounts
 * for): it is kept as the PX_VARIANT_PRINTED form, and `pencil verify illuminance` measures it
 * (docs/errata.md, E4).
 *
 * Near a caustic det -> 0 and E grows without bound; the determinant then loses its relative
 * accuracy to cancellation, and PX_ECAUSTIC is returned instead of a number that would not hold
 * PX_ACCURACY.
 */
#ifndef PARAXIAL_ILLUMINANCE_H
#define PARAXIAL_ILLUMINANCE_H

#include "paraxial/linalg.h"
#include "paraxial/status.h"
#include "paraxial/system.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The kind of light source at the start of a system. */
typedef enum {
  PX_SOURCE_POINT = 0,   /**< a point source at the input frame's origin: xi spans the pencil */
  PX_SOURCE_PARALLEL = 1 /**< a parallel beam along the input frame's z: x spans the pencil */
} px_source_t;

/** Parse "point" / "parallel"; PX_EINVAL otherwise. */
px_status_t px_source_parse(const char *name, px_source_t *out);
const char *px_source_name(px_source_t s);

/** Relative accuracy assumed of the entries of a system matrix, per unit of their componentwise
 *  condition: a few units of 2^-53 (the elements are accurate to about that; paraxial/status.h
 *  states the guarantee, PX_ACCURACY, that px_element_matrix() refuses below). */
#define PX_ENTRY_EPS 4.4408920985006262e-16

/** How far above 1 a cosine computed from unit vectors may come by rounding and still be taken
 *  (as 1). */
#define PX_COS_SLACK 1e-12

/** How much a lit area spreads the light that reaches it: the ratio dOmega/dS of Eq. (6) for a
 *  point source, |cos(alpha)| / |det B|, or dS0/dS for a parallel source, |cos(alpha)| / |det A|
 *  (dS0 an area across the beam). t is the system matrix from the source to the plane normal to
 *  the arriving axial ray at the lit point; cos_alpha the cosine between that ray and the lit
 *  surface's normal (either sign).
 *
 *  Near a caustic the block's entries are small differences of larger terms (B = B0 + z D0 for
 *  the last transfer z, and so on through the cascade), so their relative error, and the
 *  determinant's, grows. t_abs bounds those terms: px_cascade_product_abs() of the cascade whose
 *  product is t, or NULL to take |t| (right for a matrix given directly, blind to cancellation
 *  inside a cascade). The condition
 *      kappa = (|d| M00 + |c| M01 + |b| M10 + |a| M11 + |a d| + |b c|) / |a d - b c|,
 *  with [[a, b], [c, d]] the block and M the same block of t_abs, bounds the ratio's relative
 *  error by kappa PX_ENTRY_EPS; it is written to *cond when cond is not NULL (also on
 *  PX_ECAUSTIC). Status: PX_EINVAL (t or t_abs not finite, |cos_alpha| > 1 + PX_COS_SLACK, bad
 * source); PX_EGRAZING (|cos_alpha| <= PX_COS_MIN: the light skims the surface); PX_ECAUSTIC (det =
 * 0, or kappa PX_ENTRY_EPS > PX_ACCURACY: at or too near a caustic for the ratio to be accurate);
 *  PX_ENONFINITE (the ratio overflows). On an error *ratio is not written. */
px_status_t px_spread_ratio(const px_mat4_t *t, const px_mat4_t *t_abs, px_source_t source,
                            double cos_alpha, double *ratio, double *cond);

/** Illuminance E = t_r I ratio (Eqs. 8, 9) with px_spread_ratio()'s arguments and statuses;
 * intensity I >= 0 and transmittance tr in [0, 1] (PX_EINVAL otherwise). PX_VARIANT_PRINTED
 * multiplies by n1/n2 as the 1989 paper's Eq. (1) prints it (n1 the source's medium, n2 the
 * surface's, both > 0); PX_VARIANT_CORRECTED ignores n1 and n2. */
px_status_t px_illuminance(const px_mat4_t *t, const px_mat4_t *t_abs, px_source_t source,
                           double cos_alpha, double intensity, double tr, double n1, double n2,
                           px_variant_t variant, double *e);

#ifdef __cplusplus
}
#endif

#endif
