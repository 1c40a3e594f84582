/* frame.c -- ray coordinate systems (section 2.1, Fig. 1). */
#include "paraxial/frame.h"

#include <math.h>

/* The world axis least aligned with z: a deterministic fallback when a hint is unusable. */
static px_vec3_t least_aligned_axis(px_vec3_t z) {
  double ax = fabs(z.x), ay = fabs(z.y), az = fabs(z.z);
  if (ax <= ay && ax <= az)
    return px_vec3(1, 0, 0);
  if (ay <= az)
    return px_vec3(0, 1, 0);
  return px_vec3(0, 0, 1);
}

px_status_t px_frame_from_z(px_vec3_t z, px_vec3_t hint, px_frame_t *out) {
  px_vec3_t zn, x2;
  if (px_vec3_normalize(z, &zn) != PX_OK)
    return PX_ESINGULAR;
  px_vec3_t h = px_vec3_axpy(-px_vec3_dot(hint, zn), zn, hint);
  /* a hint within ~1e-6 rad of z is rejected: its projection would be mostly rounding error */
  if (!(px_vec3_norm(h) > 1e-6 * px_vec3_norm(hint)) || px_vec3_normalize(h, &x2) != PX_OK) {
    px_vec3_t a = least_aligned_axis(zn);
    h = px_vec3_axpy(-px_vec3_dot(a, zn), zn, a);
    if (px_vec3_normalize(h, &x2) != PX_OK)
      return PX_ESINGULAR;
  }
  out->z = zn;
  out->x2 = x2;
  out->x1 = px_vec3_cross(x2, zn);
  return PX_OK;
}

px_frame_t px_frame_rotate(px_frame_t f, double phi) {
  double c = cos(phi), s = sin(phi);
  px_frame_t r = f;
  r.x1 = px_vec3_add(px_vec3_scale(f.x1, c), px_vec3_scale(f.x2, s));
  r.x2 = px_vec3_add(px_vec3_scale(f.x1, -s), px_vec3_scale(f.x2, c));
  return r;
}

px_vec3_t px_frame_local(px_frame_t f, px_vec3_t v) {
  return px_vec3(px_vec3_dot(f.x1, v), px_vec3_dot(f.x2, v), px_vec3_dot(f.z, v));
}

double px_frame_defect(px_frame_t f) {
  double d = 0.0;
  d = fmax(d, fabs(px_vec3_dot(f.x1, f.x1) - 1.0));
  d = fmax(d, fabs(px_vec3_dot(f.x2, f.x2) - 1.0));
  d = fmax(d, fabs(px_vec3_dot(f.z, f.z) - 1.0));
  d = fmax(d, fabs(px_vec3_dot(f.x1, f.x2)));
  d = fmax(d, fabs(px_vec3_dot(f.x1, f.z)));
  d = fmax(d, fabs(px_vec3_dot(f.x2, f.z)));
  d = fmax(d, px_vec3_norm(px_vec3_sub(px_vec3_cross(f.x2, f.z), f.x1)));
  return d;
}

px_mat2_t px_frame_theta(px_frame_t f, px_vec3_t u1, px_vec3_t u2) {
  return px_mat2(px_vec3_dot(f.x1, u1), px_vec3_dot(f.x1, u2), px_vec3_dot(f.x2, u1),
                 px_vec3_dot(f.x2, u2));
}
