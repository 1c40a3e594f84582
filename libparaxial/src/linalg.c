/* linalg.c -- 3-vectors, 2x2 blocks and 4x4 system matrices (section 2.1). */
#include "paraxial/linalg.h"

#include <math.h>

#include "fma_clones.h"

/* The functions that call fma() are cloned for CPUs with FMA instructions (PX_FMA_CLONES,
 * fma_clones.h): the pencil tracer multiplies system matrices and takes dot products per lattice
 * cell and path so often that each libm fma() call costing more than its arithmetic showed in
 * its profile (docs/tuning.md). Results are identical: fma() is correctly rounded either way. */

px_vec3_t px_vec3(double x, double y, double z) {
  return (px_vec3_t){x, y, z};
}
px_vec3_t px_vec3_add(px_vec3_t a, px_vec3_t b) {
  return px_v3_add(a, b);
}
px_vec3_t px_vec3_sub(px_vec3_t a, px_vec3_t b) {
  return px_v3_sub(a, b);
}
px_vec3_t px_vec3_scale(px_vec3_t a, double s) {
  return px_v3_scale(a, s);
}
PX_FMA_CLONES px_vec3_t px_vec3_axpy(double s, px_vec3_t x, px_vec3_t y) {
  return px_v3_axpy_fma(s, x, y);
}
PX_FMA_CLONES double px_vec3_dot(px_vec3_t a, px_vec3_t b) {
  return px_v3_dot_fma(a, b);
}
PX_FMA_CLONES px_vec3_t px_vec3_cross(px_vec3_t a, px_vec3_t b) {
  return px_v3_cross(a, b);
}
PX_FMA_CLONES double px_vec3_norm(px_vec3_t a) {
  return px_v3_norm_fma(a);
}
PX_FMA_CLONES px_status_t px_vec3_normalize(px_vec3_t a, px_vec3_t *out) {
  return px_v3_normalize(a, out);
}

px_mat2_t px_mat2(double a, double b, double c, double d) {
  return (px_mat2_t){{{a, b}, {c, d}}};
}
px_mat2_t px_mat2_identity(void) {
  return px_mat2(1, 0, 0, 1);
}
px_mat2_t px_mat2_zero(void) {
  return px_mat2(0, 0, 0, 0);
}
px_mat2_t px_mat2_diag(double a, double d) {
  return px_mat2(a, 0, 0, d);
}

PX_FMA_CLONES px_mat2_t px_mat2_mul(px_mat2_t a, px_mat2_t b) {
  px_mat2_t r;
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      r.m[i][j] = fma(a.m[i][0], b.m[0][j], a.m[i][1] * b.m[1][j]);
  return r;
}
px_mat2_t px_mat2_add(px_mat2_t a, px_mat2_t b) {
  return px_mat2(a.m[0][0] + b.m[0][0], a.m[0][1] + b.m[0][1], a.m[1][0] + b.m[1][0],
                 a.m[1][1] + b.m[1][1]);
}
px_mat2_t px_mat2_scale(px_mat2_t a, double s) {
  return px_mat2(a.m[0][0] * s, a.m[0][1] * s, a.m[1][0] * s, a.m[1][1] * s);
}
px_mat2_t px_mat2_transpose(px_mat2_t a) {
  return px_mat2(a.m[0][0], a.m[1][0], a.m[0][1], a.m[1][1]);
}
PX_FMA_CLONES double px_mat2_det(px_mat2_t a) {
  return px_diff_products(a.m[0][0], a.m[1][1], a.m[0][1], a.m[1][0]);
}

PX_FMA_CLONES px_status_t px_mat2_inverse(px_mat2_t a, px_mat2_t *out) {
  double det = px_diff_products(a.m[0][0], a.m[1][1], a.m[0][1], a.m[1][0]); /* px_mat2_det */
  if (!(fabs(det) > 1e-300) || !isfinite(det))
    return PX_ESINGULAR;
  px_mat2_t r = px_mat2_scale(px_mat2(a.m[1][1], -a.m[0][1], -a.m[1][0], a.m[0][0]), 1.0 / det);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      if (!isfinite(r.m[i][j]))
        return PX_ESINGULAR;
  *out = r;
  return PX_OK;
}

double px_mat2_norm2(px_mat2_t a) {
  /* eigenvalues of the symmetric a a^t: (tr +- sqrt(tr^2 - 4 det)) / 2, written stably */
  double p = a.m[0][0] * a.m[0][0] + a.m[0][1] * a.m[0][1];
  double q = a.m[1][0] * a.m[1][0] + a.m[1][1] * a.m[1][1];
  double r = a.m[0][0] * a.m[1][0] + a.m[0][1] * a.m[1][1];
  double half_diff = 0.5 * (p - q);
  double lmax = 0.5 * (p + q) + hypot(half_diff, r);
  return sqrt(lmax);
}

double px_mat2_maxabs(px_mat2_t a) {
  double m = 0.0;
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      m = fmax(m, fabs(a.m[i][j]));
  return m;
}

px_mat4_t px_mat4_identity(void) {
  px_mat4_t t = {{{0}}};
  for (int i = 0; i < 4; i++)
    t.m[i][i] = 1.0;
  return t;
}

px_mat4_t px_mat4_blocks(px_mat2_t a, px_mat2_t b, px_mat2_t c, px_mat2_t d) {
  px_mat4_t t;
  const px_mat2_t *blk[2][2] = {{&a, &b}, {&c, &d}};
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      t.m[i][j] = blk[i / 2][j / 2]->m[i % 2][j % 2];
  return t;
}

px_mat2_t px_mat4_block(px_mat4_t t, int r, int c) {
  return px_mat2(t.m[2 * r][2 * c], t.m[2 * r][2 * c + 1], t.m[2 * r + 1][2 * c],
                 t.m[2 * r + 1][2 * c + 1]);
}

PX_FMA_CLONES px_mat4_t px_mat4_mul(px_mat4_t a, px_mat4_t b) {
  px_mat4_t r;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      double s = 0.0;
      for (int k = 0; k < 4; k++)
        s = fma(a.m[i][k], b.m[k][j], s);
      r.m[i][j] = s;
    }
  return r;
}

PX_FMA_CLONES px_ray4_t px_mat4_apply(px_mat4_t t, px_ray4_t psi) {
  px_ray4_t r;
  for (int i = 0; i < 4; i++) {
    double s = 0.0;
    for (int k = 0; k < 4; k++)
      s = fma(t.m[i][k], psi.v[k], s);
    r.v[i] = s;
  }
  return r;
}

double px_mat4_maxabs(px_mat4_t a) {
  double m = 0.0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      m = fmax(m, fabs(a.m[i][j]));
  return m;
}

int px_mat4_isfinite(px_mat4_t a) {
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      if (!isfinite(a.m[i][j]))
        return 0;
  return 1;
}
