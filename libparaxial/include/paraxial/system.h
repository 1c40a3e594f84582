/* system.h -- element system matrices: transfer (Eq. 1), refraction (Eq. 2) and reflection
 * (section 2.2 (3)) for a smooth surface with a general curvature matrix Q and general frames.
 *
 * Conventions (docs/conventions.md has the derivation):
 *  - nu is the unit surface normal at the hit point O oriented along the incident ray,
 *    nu . s > 0. For a refraction it points into the second medium.
 *  - (u1, u2, nu) is right-handed: u1 = u2 x nu. Near O the surface is the set of points
 *    O + u1*t1 + u2*t2 + w nu with w = (1/2) t^t Q t + O(|t|^3).
 *  - Hence Q = I/R for a sphere of radius R, with R > 0 when the centre of curvature lies on
 *    the far side of the surface from the incoming light (a glass ball entered from outside, a
 *    convex mirror) and R < 0 otherwise (a ball left from inside, a concave mirror). A plane
 *    has Q = 0.
 *  - cos(theta) = nu . s and cos(theta') = nu . s'; after a reflection cos(theta') < 0,
 *    which is the paper's "replace theta' by pi - theta".
 */
#ifndef PARAXIAL_SYSTEM_H
#define PARAXIAL_SYSTEM_H

#include "paraxial/frame.h"
#include "paraxial/linalg.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Which form of Eq. (2) to evaluate. */
typedef enum {
  /** Derived by the project and confirmed by exact Snell-law tracing (default). */
  PX_VARIANT_CORRECTED = 0,
  /** Eq. (2) verbatim as printed in the seed text, with Q = diag(1/R) read in the project's
   *  convention for R. Kept to reproduce the paper; see docs/errata.md, E1-E3. */
  PX_VARIANT_PRINTED = 1
} px_variant_t;

/** Parse "corrected" / "printed"; PX_EINVAL otherwise. */
px_status_t px_variant_parse(const char *name, px_variant_t *out);
const char *px_variant_name(px_variant_t v);

typedef enum {
  PX_EVENT_REFRACT = 0, /**< light passes into the medium of index n2 */
  PX_EVENT_REFLECT = 1  /**< light stays in the medium of index n1 */
} px_event_t;

/** The local geometry of a surface where the axial ray meets it. */
typedef struct {
  px_vec3_t s;  /**< incident axial direction, unit */
  px_vec3_t nu; /**< unit normal at O with nu . s > 0 */
  px_vec3_t u1; /**< tangent basis vector, u1 = u2 x nu */
  px_vec3_t u2; /**< tangent basis vector */
  px_mat2_t q;  /**< curvature matrix in (u1, u2), symmetric, units 1/length */
  double n1;    /**< refractive index on the incident side, > 0 */
  double n2;    /**< refractive index on the far side, > 0 (unused for a reflection) */
} px_interface_t;

/** Interface with the paper's tangent basis: u2 = normalised (nu x s), the normal of the plane
 *  of incidence, and u1 = u2 x nu. At normal incidence (plane of incidence undefined) u2 is
 *  taken from `hint` projected onto the tangent plane, or a fixed world axis when the hint is
 *  parallel to nu, so the choice is deterministic. `q_in_u` is given in the resulting (u1, u2)
 *  basis when `q_world` is NULL; otherwise q_world (a 3x3 symmetric shape operator in world
 *  coordinates, row-major) is projected onto (u1, u2). */
px_status_t px_interface_make(px_vec3_t s, px_vec3_t nu, px_vec3_t hint, px_mat2_t q_in_u,
                              const double *q_world, double n1, double n2, px_interface_t *out);

/** Interface in a canonical world position for the calculator: nu = +z, incidence angle
 *  theta (radians, in [0, pi/2)) in the x-z plane, sphere of radius R (0 or +-Inf = plane). */
px_status_t px_interface_canonical(double theta, double radius, double n1, double n2,
                                   px_interface_t *out);

/** Direction of the outgoing axial ray (Snell's law / mirror law) and cos(theta').
 *  PX_ETIR when the refracted ray does not exist. */
px_status_t px_interface_outgoing(const px_interface_t *ifc, px_event_t ev, px_vec3_t *s_out,
                                  double *cos_out);

/** Four 3-vectors as a structure of arrays: lane i is (x[i], y[i], z[i]). */
typedef struct {
  double x[4], y[4], z[4];
} px_vec3x4_t;

/** px_interface_outgoing() for four interfaces of one event at once, lane by lane bit for bit
 *  (cos theta' is not returned): lane i arrives along (s->x[i], s->y[i], s->z[i]) at the normal
 *  nu (oriented as px_interface_t.nu) between indices n1[i] and n2[i] (n2 unused for a
 *  reflection). st[i] gets the lane's status and, where that is PX_OK, out its direction. Lanes
 *  whose bit in `lanes` is clear are not computed (st[i] = PX_EINVAL, out left alone). Four lanes
 *  at a time where px_simd4_available(); otherwise, and for a lane near grazing (the compensated
 *  form of px_interface_outgoing()), lane by lane by px_interface_outgoing(). For walks that carry
 *  several rays along one known path (the pencil renderer's exact walks). */
void px_interface_outgoing4(px_event_t ev, const px_vec3x4_t *s, const px_vec3x4_t *nu,
                            const double n1[4], const double n2[4], unsigned lanes,
                            px_vec3x4_t *out, px_status_t st[4]);

/** 1 when the four-lane functions run four lanes at a time: an x86-64 CPU with AVX2 and FMA
 *  instructions (asked at run time) and a GCC-compatible compiler; 0 where they take the lanes
 *  one by one (with the same results). */
int px_simd4_available(void);

/** The paper's frames for this interface: x2 = x2' = u2 (normal of the plane of incidence),
 *  x1 = x2 x s, x1' = x2' x s' (right-handed, also after a reflection). With them Theta and
 *  Theta' are diag(cos theta, 1) and diag(cos theta', 1). */
px_status_t px_interface_frames(const px_interface_t *ifc, px_event_t ev, px_frame_t *in,
                                px_frame_t *out);

/** The cosines of one refraction or reflection (section 2.2) computed without avoidable
 *  cancellation, with a bound on how well double precision knows them. Shared by the system
 *  matrices and the error coefficients, so that both refuse at the same places. */
typedef struct {
  double c, s;   /**< cos, sin of the incidence angle theta (c > 0) */
  double cp, sp; /**< cos, sin of theta'; cp < 0 after a reflection (theta' = pi - theta) */
  double eta;    /**< n1 / n2 (1 for a reflection) */
  double h;      /**< h = cp - eta c of Eq. (2): (1 - eta^2) / (cp + eta c) where the
                      difference cancels, exactly 0 when n1 = n2 */
  double err;    /**< first-order bound on the relative error of the element's matrix
                      entries (products and quotients of c, cp, h) caused by rounding of
                      the inputs (c and s to a few ulps) and of this computation */
} px_cosines_t;

/** Cosines of the element for the incidence given by c = cos theta and s = sin theta (each
 *  within a few ulps, e.g. from unit vectors or px_cos_sin_deg()), indices n1, n2 (n2 ignored
 *  for a reflection) and the largest curvature |1/R| of the surface (0 for a plane).
 *  cos^2 theta' is (1 - eta s)(1 + eta s) in the ordinary regime and (1 - eta^2) + (eta c)^2
 *  near grazing with eta ~ 1, where the first form cancels (docs/conventions.md).
 *  Errors, in this order: PX_EINVAL (index <= 0, c or s outside [0, 1], curvature < 0 or
 *  NaN), PX_EGRAZING (c or |cp| <= PX_COS_MIN), PX_ETIR, PX_ENONFINITE (curvature >
 *  PX_CURVATURE_MAX), PX_EILLCOND (err > PX_ACCURACY). On error *out is untouched. */
px_status_t px_element_cosines(px_event_t ev, double c, double s, double n1, double n2,
                               double curvature, px_cosines_t *out);

/** cos theta = nu . s and sin theta = |nu x s| of an interface, from its vectors (the dot
 *  product compensated near grazing, where the plain one is only good to 1e-16 absolute),
 *  at most 1: the inputs of px_element_cosines() for px_interface_matrix() and
 *  px_element_coeffs() alike. */
void px_interface_cos_sin(const px_interface_t *ifc, double *c, double *s);

/** cos and sin of an angle given in degrees, each to a few ulps relative even near 90 deg
 *  (from the exact complement 90 - deg there), where cos(deg * pi / 180) loses the digits
 *  the rounding of the radian value takes (1e-16 absolute, 6e-9 relative at 1e-6 deg from
 *  grazing). deg in [0, 90]. */
void px_cos_sin_deg(double deg, double *c, double *s);

/** Eq. (1): transfer by distance z0 along the axial ray: [[1, z0], [0, 1]]. */
px_mat4_t px_transfer_matrix(double z0);

/** Eq. (2) for a refraction (ev = PX_EVENT_REFRACT) or a reflection, from the incident ray
 *  frame `in` (in.z must equal ifc->s) to the outgoing frame `out` (out.z must equal s').
 *  Corrected form, with h = cos(theta') - (n1/n2) cos(theta) (n2 := n1 for a reflection):
 *      A = Theta' Theta^-1            B = 0
 *      C = -h Theta'^-t Q Theta^-1    D = (n1/n2) Theta'^-t Theta^t
 *  Returns PX_ETIR, PX_EGRAZING (|cos| <= PX_COS_MIN), PX_EINVAL (frames not matching the
 *  rays, bad indices), PX_ENONFINITE (a curvature above PX_CURVATURE_MAX, or overflow),
 *  PX_EILLCOND (the matrix cannot be given to PX_ACCURACY: px_element_cosines()); on error
 *  *t is untouched. Near grazing or with n1 ~ n2 the matrix is built from the rotations of
 *  the frames about the rays and the cosines of px_element_cosines() (docs/conventions.md). */
px_status_t px_interface_matrix(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                px_frame_t out, px_variant_t variant, px_mat4_t *t);

/** px_interface_matrix() that also writes, when `err` is not NULL, the bound on the scaled
 *  relative error of the matrix (PX_ACCURACY in status.h defines the measure); the bound is
 *  <= PX_ACCURACY whenever a matrix is returned. */
px_status_t px_interface_matrix_err(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                    px_frame_t out, px_variant_t variant, px_mat4_t *t,
                                    double *err);

/** Convenience for the calculator: the matrix in the paper's frames for a sphere of radius R
 *  (0 or +-Inf = plane) at incidence theta (radians). ev selects refraction or reflection. */
px_status_t px_element_matrix(px_event_t ev, double theta, double n1, double n2, double radius,
                              px_variant_t variant, px_mat4_t *t);

/** px_element_matrix() for the incidence given by its cosine and sine (c, s >= 0, c^2 + s^2 = 1
 *  to rounding; px_cos_sin_deg() for an angle in degrees), writing the error bound to `err`
 *  (may be NULL) as px_interface_matrix_err() does. */
px_status_t px_element_matrix_cs(px_event_t ev, double c, double s, double n1, double n2,
                                 double radius, px_variant_t variant, px_mat4_t *t, double *err);

#ifdef __cplusplus
}
#endif

#endif
