/* linalg.h -- the small value types of pencil tracing: 3-vectors, 2x2 blocks, 4x4 system
 * matrices and 4-component ray vectors psi = (x1, x2, xi1, xi2) (paper section 2.1).
 *
 * All types are plain structs passed and returned by value. Nothing here allocates.
 */
#ifndef PARAXIAL_LINALG_H
#define PARAXIAL_LINALG_H

#include "paraxial/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  double x, y, z;
} px_vec3_t;

/** 2x2 block, row-major: m[row][col]. */
typedef struct {
  double m[2][2];
} px_mat2_t;

/** 4x4 system matrix, row-major; rows and columns ordered x1, x2, xi1, xi2. */
typedef struct {
  double m[4][4];
} px_mat4_t;

/** Ray vector psi = (x1, x2, xi1, xi2): position in the x1-x2 plane and the projection of the
 *  unit direction onto that plane (paper section 2.1). */
typedef struct {
  double v[4];
} px_ray4_t;

/* 3-vectors */
px_vec3_t px_vec3(double x, double y, double z);
px_vec3_t px_vec3_add(px_vec3_t a, px_vec3_t b);
px_vec3_t px_vec3_sub(px_vec3_t a, px_vec3_t b);
px_vec3_t px_vec3_scale(px_vec3_t a, double s);
px_vec3_t px_vec3_axpy(double s, px_vec3_t x, px_vec3_t y); /**< s*x + y */
double px_vec3_dot(px_vec3_t a, px_vec3_t b);
px_vec3_t px_vec3_cross(px_vec3_t a, px_vec3_t b);
double px_vec3_norm(px_vec3_t a);
/** Unit vector along a; PX_ESINGULAR when |a| is zero or not finite. */
px_status_t px_vec3_normalize(px_vec3_t a, px_vec3_t *out);

/* 2x2 blocks */
px_mat2_t px_mat2(double a, double b, double c, double d);
px_mat2_t px_mat2_identity(void);
px_mat2_t px_mat2_zero(void);
px_mat2_t px_mat2_diag(double a, double d);
px_mat2_t px_mat2_mul(px_mat2_t a, px_mat2_t b);
px_mat2_t px_mat2_add(px_mat2_t a, px_mat2_t b);
px_mat2_t px_mat2_scale(px_mat2_t a, double s);
px_mat2_t px_mat2_transpose(px_mat2_t a);
/** ad - bc with an FMA-compensated difference of products. */
double px_mat2_det(px_mat2_t a);
/** Inverse; PX_ESINGULAR when |det| <= 1e-300 or the result is not finite. */
px_status_t px_mat2_inverse(px_mat2_t a, px_mat2_t *out);
/** Largest singular value (spectral norm) = sqrt of the larger eigenvalue of a a^t. */
double px_mat2_norm2(px_mat2_t a);
/** Largest |entry|. */
double px_mat2_maxabs(px_mat2_t a);

/* 4x4 system matrices */
px_mat4_t px_mat4_identity(void);
/** Assemble from 2x2 blocks [[A, B], [C, D]]. */
px_mat4_t px_mat4_blocks(px_mat2_t a, px_mat2_t b, px_mat2_t c, px_mat2_t d);
/** Block (r, c) with r, c in {0, 1}: (0,0)=A, (0,1)=B, (1,0)=C, (1,1)=D. */
px_mat2_t px_mat4_block(px_mat4_t t, int r, int c);
px_mat4_t px_mat4_mul(px_mat4_t a, px_mat4_t b);
px_ray4_t px_mat4_apply(px_mat4_t t, px_ray4_t psi);
double px_mat4_maxabs(px_mat4_t a);
/** 1 when every entry is finite. */
int px_mat4_isfinite(px_mat4_t a);

#ifdef __cplusplus
}
#endif

#endif
