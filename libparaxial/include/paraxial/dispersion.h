/* dispersion.h -- wavelength as a fifth ray coordinate (the 1989 paper, section 3.2.1): refractive
 * index models n(lambda), and the extended system matrix of Eq. (13),
 *
 *     (x', xi', delta-lambda) = [[A, B, x_lambda], [C, D, xi_lambda], [0, 0, 1]] (x, xi,
 * delta-lambda)
 *
 * where A..D are the 4 x 4 system matrix's blocks (system.h) and (x_lambda, xi_lambda) the change
 * of the ray vector with wavelength, in the 4 x 4's frames (docs/conventions.md). Wavelengths and
 * delta-lambda are in nm, dn/dlambda in 1/nm. docs/spectral.md is the design; docs/errata.md has
 * the printed Eq. (14)'s suspects as found.
 *
 * The wavelength column of one element:
 *  - transfer and reflection: zero (Eq. 1 and the mirror law have no index);
 *  - refraction: x_lambda = 0 (the reference planes pass through the hit point, which does not
 *    move with the wavelength), and, differentiating the tangential Snell law
 *    n2 (u . s') = n1 (u . s) at a fixed point and normal,
 *        xi_lambda = Theta'^-T (dn1 (u . s) - dn2 (u . s')) / n2,
 *    with (u . s) = (u1 . s, u2 . s) and Theta'_ij = x'_i . u_j; in the paper's frames
 *    (xi1, xi2)_lambda = ((dn1 sin theta - dn2 sin theta') / (n2 cos theta'), 0).
 *    PX_VARIANT_PRINTED evaluates the printed Eq. (14) instead: delta theta' =
 *    (n / n'_0)(sin theta / cos theta')(dn'/dlambda) delta lambda (only the far medium
 *    dispersing), whose sign and power of n'_0 differ.
 *
 * Pure arithmetic on values: no allocation, no I/O, thread-safe. */
#ifndef PARAXIAL_DISPERSION_H
#define PARAXIAL_DISPERSION_H

#include "paraxial/cascade.h"
#include "paraxial/system.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The helium d-line (nm): where catalogues quote n_d and the Abbe number V_d, and the
 *  wavelength a plain index means. */
#define PX_LAMBDA_D 587.5618
/** The hydrogen F and C lines (nm) of the Abbe number V_d = (n_d - 1) / (n_F - n_C). */
#define PX_LAMBDA_F 486.1327
#define PX_LAMBDA_C 656.2725

/** Sellmeier terms a model may have (water's published fit has four). */
#define PX_SELLMEIER_TERMS 4

typedef enum {
  PX_INDEX_CONSTANT = 0, /**< n = a */
  PX_INDEX_CAUCHY = 1,   /**< n = a + b[0] / l^2 + b[1] / l^4, l in um (b in um^2, um^4) */
  PX_INDEX_SELLMEIER = 2 /**< n^2 = 1 + sum_i b[i] l^2 / (l^2 - c[i]), l in um, c in um^2 */
} px_index_kind_t;

/** A refractive index as a function of wavelength, valid on [lo_nm, hi_nm]. */
typedef struct {
  px_index_kind_t kind;
  int nterm; /**< Sellmeier terms, 1..PX_SELLMEIER_TERMS */
  double a, b[PX_SELLMEIER_TERMS], c[PX_SELLMEIER_TERMS]; /**< the coefficients of the kind */
  double lo_nm, hi_nm;                                    /**< the range the model holds on */
} px_index_t;

/** A constant index n on every wavelength. */
px_index_t px_index_constant(double n);

/** n and dn/dlambda (1/nm; either pointer may be NULL) at lambda_nm. PX_EINVAL outside the
 *  model's range (never extrapolated: fits diverge outside theirs) or for a bad model,
 *  PX_ENONFINITE at a Sellmeier pole or where n^2 <= 0. */
px_status_t px_index_eval(const px_index_t *m, double lambda_nm, double *n, double *dn_dlambda);

/** The two-term Cauchy model through n_d at the d-line with n_F - n_C = (n_d - 1) / V_d on the F
 *  and C lines, range 380..780 nm. PX_EINVAL for n_d <= 1 or V_d <= 0 (or not finite). */
px_status_t px_index_from_abbe(double nd, double vd, px_index_t *out);

/** A material of the small catalogue by name (Sellmeier models, range in the entry):
 *  "N-BK7", "F2" and "SF11" (Schott's published coefficients), "fused-silica" (Malitson,
 *  J. Opt. Soc. Am. 55, 1205, 1965), "diamond" (Peter, Z. Phys. 15, 358, 1923) and "water"
 *  (distilled, 20.0 C, absolute index: Daimon and Masumura, Appl. Opt. 46, 3811, 2007);
 *  docs/spectral.md lists them with their n_d and V_d. PX_EINVAL for another name. */
px_status_t px_index_named(const char *name, px_index_t *out);

/** The catalogue's names, comma-separated, for messages. */
const char *px_index_names(void);

/** 1 when the model's index varies with wavelength. */
int px_index_disperses(const px_index_t *m);

/** The extended system matrix: the 4 x 4 block and the wavelength column; the last row is
 *  (0 0 0 0 1). */
typedef struct {
  px_mat4_t t; /**< A, B / C, D: the 4 x 4 system matrix, bit for bit */
  px_ray4_t w; /**< (x1, x2, xi1, xi2)_lambda = d psi' / d lambda, per nm */
} px_mat5_t;

px_mat5_t px_mat5_identity(void);
/** The matrix of block t and column w. */
px_mat5_t px_mat5_from4(px_mat4_t t, px_ray4_t w);
/** b after a: [[Tb, wb], [0, 1]] [[Ta, wa], [0, 1]] = [[Tb Ta, Tb wa + wb], [0, 1]]; the block is
 *  px_mat4_mul's, bit for bit. */
px_mat5_t px_mat5_mul(px_mat5_t b, px_mat5_t a);
/** T psi + w dlambda. */
px_ray4_t px_mat5_apply(px_mat5_t t, px_ray4_t psi, double dlambda);
int px_mat5_isfinite(px_mat5_t t);

/** The wavelength column of a refraction or reflection (zero for a reflection) in the outgoing
 *  frame `out` (out.z = s'), for dn1 = dn/dlambda of the incident medium and dn2 of the far one
 *  at the axial ray's wavelength (ifc->n1, ifc->n2). Errors as px_interface_matrix()
 *  (PX_ETIR, PX_EGRAZING, PX_EINVAL for a frame that does not match s' or non-finite dn). */
px_status_t px_interface_column(const px_interface_t *ifc, px_event_t ev, px_frame_t out,
                                double dn1, double dn2, px_variant_t variant, px_ray4_t *w);

/** px_interface_matrix() and px_interface_column() together. */
px_status_t px_interface_matrix5(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                 px_frame_t out, double dn1, double dn2, px_variant_t variant,
                                 px_mat5_t *t);

/** For the calculator: px_element_matrix_cs() extended by the column, in the paper's frames.
 *  err may be NULL. */
px_status_t px_element_matrix5_cs(px_event_t ev, double c, double s, double n1, double n2,
                                  double dn1, double dn2, double radius, px_variant_t variant,
                                  px_mat5_t *t, double *err);

/** The extended matrix of a cascade (cascade.h): every element's block as px_cascade_product()
 *  multiplies them (so out->t is its result bit for bit) and the columns of its refractions and
 *  reflections from dn1[i], dn2[i] (dn/dlambda, 1/nm, of the media before and after element i;
 *  ignored for transfers; NULL for all 0). px_interface_column()'s errors. */
px_status_t px_cascade_product5(const px_cascade_t *c, const double *dn1, const double *dn2,
                                px_variant_t variant, px_mat5_t *out);

/** The paper's non-linear wavelength scale (section 3.3): where every dispersive medium of a
 *  scene is one glass, Lambda(lambda) = lambda_0 + (n(lambda) - n(lambda_0)) / n'(lambda_0) makes
 *  the index exactly linear in Lambda (dn/dLambda = n'(lambda_0), constant), equal to lambda to
 *  first order at lambda_0 (dLambda/dlambda = 1 there), so that the 5 x 5 matrix's column,
 *  computed as today, is also d psi'/d Lambda at lambda_0 and the extended matrix's linear model
 *  carries only the refraction's own non-linearity, not the index's. For the same glass scaled
 *  (n_m = n_m0 + k_m (n - n_0), e.g. Cauchy models of one Abbe number) it serves every medium. */
typedef struct {
  px_index_t glass; /**< the scene's one dispersive glass */
  double lambda0;   /**< the axial wavelength, nm (PX_LAMBDA_D for the renderers) */
  double n0, dn0;   /**< n and dn/dlambda at lambda0 (dn0 != 0) */
} px_wavescale_t;

/** The scale of glass about lambda0. PX_EINVAL for a glass that does not disperse at lambda0 or
 *  lambda0 outside its range; px_index_eval()'s errors. */
px_status_t px_wavescale_make(const px_index_t *glass, double lambda0, px_wavescale_t *out);

/** Lambda (nm) of lambda (nm, in the glass's range); px_index_eval()'s errors. */
px_status_t px_wavescale_to(const px_wavescale_t *w, double lambda, double *Lambda);

/** lambda of Lambda, by bisection on the glass's range, within 1e-10 nm; n is taken to be
 *  monotone there (normal dispersion, as every catalogue glass over 380-780 nm). PX_EINVAL when
 *  Lambda is outside the image of [lo_nm, hi_nm]. */
px_status_t px_wavescale_from(const px_wavescale_t *w, double Lambda, double *lambda);

/** A transfer's extended matrix: its column is zero (x_lambda' = x_lambda + z0 xi_lambda comes
 *  from the block). */
px_mat5_t px_transfer_matrix5(double z0);

#ifdef __cplusplus
}
#endif

#endif
