/* status.h -- result codes of libparaxial.
 *
 * Every fallible function returns a px_status_t and writes its results through pointers. A
 * non-zero status means the outputs were not written (unless the function's comment says
 * otherwise), so no NaN or Inf escapes without a status that explains it.
 */
#ifndef PARAXIAL_STATUS_H
#define PARAXIAL_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
  PX_OK = 0,      /**< success */
  PX_EINVAL,      /**< a parameter is out of range or not finite (the message names which) */
  PX_ETIR,        /**< total internal reflection: there is no refracted ray */
  PX_EGRAZING,    /**< grazing incidence or exit: cos(theta) or cos(theta') <= PX_COS_MIN */
  PX_ESINGULAR,   /**< a 2x2 block (Theta, Theta', a frame) is singular */
  PX_EMISS,       /**< the ray does not meet the surface */
  PX_ECAPACITY,   /**< a caller-owned buffer is full */
  PX_ENONFINITE,  /**< an intermediate result overflowed; nothing was written */
  PX_ENOCONVERGE, /**< an iteration did not converge */
  PX_EILLCOND,    /**< too ill-conditioned: double precision cannot give the result to
                       PX_ACCURACY (e.g. within a few 1e-5 deg of the critical angle) */
  PX_ECAUSTIC     /**< at or too near a caustic: the pencil's cross-section vanishes (det -> 0)
                       and its illuminance cannot be given to PX_ACCURACY */
} px_status_t;

/** Static, human-readable message for a status; never NULL, thread-safe. */
const char *px_strerror(px_status_t status);

/** The status's identifier ("PX_ECAUSTIC"), for files that scripts read; never NULL. */
const char *px_status_name(px_status_t status);

/** Smallest |cos| of an incidence or exit angle for which a system matrix is returned.
 *  Below it the matrix entries grow like 1/cos and the paraxial region is narrower than
 *  double precision can resolve, so PX_EGRAZING is returned instead. */
#define PX_COS_MIN 1e-10

/** The accuracy every returned system matrix is guaranteed to have: its scaled relative error
 *  max|S - S*| / max|S*| (S = diag(1/L, 1/L, 1, 1) T diag(L, L, 1, 1), L = 1/|Q|, 1 for a
 *  plane; S* the exact matrix of the inputs as given) is below this bound. Where a first-order
 *  error bound of the computation exceeds it, PX_EILLCOND is returned instead of a matrix
 *  (docs/conventions.md, "Numerical limits"; checked by `pencil verify stability`). */
#define PX_ACCURACY 1e-8

/** Largest curvature |1/R| (or |Q| entry, units 1/length) of an element: above it the matrix
 *  entries and the error coefficients (which grow like 1/(R^2 cos^3 theta cos^3 theta')) could
 *  overflow, so PX_ENONFINITE is returned by every function alike. */
#define PX_CURVATURE_MAX 1e120
#ifdef __cplusplus
}
#endif

#endif
