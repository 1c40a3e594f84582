/* frame.h -- ray coordinate systems (paper section 2.1, Fig. 1).
 *
 * A ray coordinate system is an orthonormal right-handed triple (x1, x2, z) with z the direction
 * of the axial ray and x1 = x2 x z. The paper leaves x1, x2 free; Eq. (2) is printed for the
 * frames in which x2 is the normal of the plane of incidence, and px_frame_incidence() builds
 * those. Frames are values; nothing here allocates.
 */
#ifndef PARAXIAL_FRAME_H
#define PARAXIAL_FRAME_H

#include "paraxial/linalg.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  px_vec3_t x1; /**< first transverse axis, x1 = x2 x z */
  px_vec3_t x2; /**< second transverse axis */
  px_vec3_t z;  /**< axial ray direction (unit) */
} px_frame_t;

/** Frame with the given z and x2 taken from `hint` projected off z (Gram-Schmidt).
 *  When the hint is (nearly) parallel to z, a fixed deterministic axis is used instead: the
 *  world axis least aligned with z. PX_ESINGULAR when z is zero or not finite. */
px_status_t px_frame_from_z(px_vec3_t z, px_vec3_t hint, px_frame_t *out);

/** The frame rotated by angle phi (radians) about its z axis: x1 -> cos x1 + sin x2. */
px_frame_t px_frame_rotate(px_frame_t f, double phi);

/** Coordinates of world vector v in the frame: (x1.v, x2.v, z.v). */
px_vec3_t px_frame_local(px_frame_t f, px_vec3_t v);

/** Largest deviation of (x1, x2, z) from an orthonormal right-handed triple. */
double px_frame_defect(px_frame_t f);

/** Theta of Eq. (2): Theta_ij = x_i . u_j for the frame's transverse axes and a surface
 *  tangent basis (u1, u2). */
px_mat2_t px_frame_theta(px_frame_t f, px_vec3_t u1, px_vec3_t u2);

#ifdef __cplusplus
}
#endif

#endif
