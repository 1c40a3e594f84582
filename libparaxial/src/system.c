/* system.c -- element system matrices: transfer (Eq. 1), refraction (Eq. 2) and reflection
 * (section 2.2 (3)). The corrected form is derived in docs/conventions.md from the vector form
 * of Snell's law, n1 (d x N) = n2 (d' x N), linearised about the axial ray; the printed form is
 * Eq. (2) verbatim (docs/errata.md). */
#include "paraxial/system.h"

#include <math.h>
#include <string.h>

#include "fma_clones.h"

/* Rays and frames are accepted when they agree to this many units of the last place of a unit
 * vector times 1e6: loose enough for frames carried through a long cascade, tight enough to
 * catch a frame passed for the wrong ray. */
#define DIRECTION_MATCH 1e-9
/* Below this sin(theta) the plane of incidence is taken as undefined (normal incidence). */
#define SIN_NORMAL 1e-12

px_status_t px_variant_parse(const char *name, px_variant_t *out) {
  if (name && strcmp(name, "corrected") == 0) {
    *out = PX_VARIANT_CORRECTED;
    return PX_OK;
  }
  if (name && strcmp(name, "printed") == 0) {
    *out = PX_VARIANT_PRINTED;
    return PX_OK;
  }
  return PX_EINVAL;
}

const char *px_variant_name(px_variant_t v) {
  return v == PX_VARIANT_PRINTED ? "printed" : "corrected";
}

static int vec3_isfinite(px_vec3_t v) {
  return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

static int index_ok(double n) {
  return isfinite(n) && n > 0.0;
}

px_status_t px_interface_make(px_vec3_t s, px_vec3_t nu, px_vec3_t hint, px_mat2_t q_in_u,
                              const double *q_world, double n1, double n2, px_interface_t *out) {
  px_interface_t r;
  if (!index_ok(n1) || !index_ok(n2) || !vec3_isfinite(hint))
    return PX_EINVAL;
  if (px_vec3_normalize(s, &r.s) != PX_OK || px_vec3_normalize(nu, &r.nu) != PX_OK)
    return PX_EINVAL;
  double sign = 1.0;
  double c = px_vec3_dot(r.nu, r.s);
  if (c < 0.0) { /* orient nu along the incident ray; the height w = (1/2) t^t Q t flips sign */
    r.nu = px_vec3_scale(r.nu, -1.0);
    sign = -1.0;
    c = -c;
  }
  if (!(c > PX_COS_MIN))
    return PX_EGRAZING;
  px_vec3_t p = px_vec3_cross(r.nu, r.s);
  if (px_vec3_norm(p) > SIN_NORMAL) {
    px_vec3_normalize(p, &r.u2);
  } else { /* normal incidence: the plane of incidence is undefined, take u2 from the hint */
    px_frame_t f;
    if (px_frame_from_z(r.nu, hint, &f) != PX_OK)
      return PX_EINVAL;
    r.u2 = f.x2;
  }
  r.u1 = px_vec3_cross(r.u2, r.nu);
  if (q_world) {
    const px_vec3_t u[2] = {r.u1, r.u2};
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) {
        const double *m = q_world;
        px_vec3_t su = px_vec3(m[0] * u[j].x + m[1] * u[j].y + m[2] * u[j].z,
                               m[3] * u[j].x + m[4] * u[j].y + m[5] * u[j].z,
                               m[6] * u[j].x + m[7] * u[j].y + m[8] * u[j].z);
        r.q.m[i][j] = sign * px_vec3_dot(u[i], su);
      }
  } else {
    r.q = px_mat2_scale(q_in_u, sign);
  }
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      if (!isfinite(r.q.m[i][j]))
        return PX_EINVAL;
  r.n1 = n1;
  r.n2 = n2;
  *out = r;
  return PX_OK;
}

px_status_t px_interface_canonical(double theta, double radius, double n1, double n2,
                                   px_interface_t *out) {
  if (!isfinite(theta) || theta < 0.0 || theta > M_PI / 2 || isnan(radius) || radius == 0.0)
    return PX_EINVAL;
  double k = isinf(radius) ? 0.0 : 1.0 / radius;
  px_vec3_t s = px_vec3(sin(theta), 0.0, cos(theta));
  return px_interface_make(s, px_vec3(0, 0, 1), px_vec3(0, 1, 0), px_mat2_diag(k, k), NULL, n1, n2,
                           out);
}

PX_FMA_CLONES /* per ray in the renderers: see fma_clones.h */
    px_status_t
    px_interface_outgoing(const px_interface_t *ifc, px_event_t ev, px_vec3_t *s_out,
                          double *cos_out) {
  double ci = px_v3_dot_fma(ifc->nu, ifc->s);
  px_vec3_t d;
  double co;
  if (ev == PX_EVENT_REFLECT) {
    d = px_v3_axpy_fma(-2.0 * ci, ifc->nu, ifc->s);
    co = -ci;
  } else {
    double eta = ifc->n1 / ifc->n2;
    double sin_i = px_v3_norm_fma(px_v3_cross(ifc->nu, ifc->s));
    double k = (1.0 - eta * sin_i) * (1.0 + eta * sin_i); /* cos^2(theta'), no cancellation */
    if (k < 0.0)
      return PX_ETIR;
    co = sqrt(k);
    d = px_v3_add(px_v3_scale(ifc->s, eta), px_v3_scale(ifc->nu, co - eta * ci));
  }
  if (px_v3_normalize(d, s_out) != PX_OK)
    return PX_ENONFINITE;
  *cos_out = co;
  return PX_OK;
}

px_status_t px_interface_frames(const px_interface_t *ifc, px_event_t ev, px_frame_t *in,
                                px_frame_t *out) {
  px_vec3_t so;
  double co;
  px_status_t st = px_interface_outgoing(ifc, ev, &so, &co);
  if (st != PX_OK)
    return st;
  in->z = ifc->s;
  in->x2 = ifc->u2;
  in->x1 = px_vec3_cross(ifc->u2, ifc->s);
  out->z = so;
  out->x2 = ifc->u2;
  out->x1 = px_vec3_cross(ifc->u2, so);
  return PX_OK;
}

px_mat4_t px_transfer_matrix(double z0) {
  px_mat4_t t = px_mat4_identity(); /* Eq. (1) */
  t.m[0][2] = z0;
  t.m[1][3] = z0;
  return t;
}

static int same_direction(px_vec3_t a, px_vec3_t b) {
  return px_vec3_norm(px_vec3_sub(a, b)) <= DIRECTION_MATCH;
}

px_status_t px_interface_matrix(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                px_frame_t out, px_variant_t variant, px_mat4_t *t) {
  if (!index_ok(ifc->n1) || (ev == PX_EVENT_REFRACT && !index_ok(ifc->n2)))
    return PX_EINVAL;
  double ci = px_vec3_dot(ifc->nu, ifc->s);
  if (!(ci > PX_COS_MIN))
    return PX_EGRAZING;
  px_vec3_t so;
  double co;
  px_status_t st = px_interface_outgoing(ifc, ev, &so, &co);
  if (st != PX_OK)
    return st;
  if (!(fabs(co) > PX_COS_MIN))
    return PX_EGRAZING;
  if (!same_direction(in.z, ifc->s) || !same_direction(out.z, so) || px_frame_defect(in) > 1e-9 ||
      px_frame_defect(out) > 1e-9)
    return PX_EINVAL;

  px_mat2_t th = px_frame_theta(in, ifc->u1, ifc->u2);   /* Theta,  det = cos(theta)  */
  px_mat2_t thp = px_frame_theta(out, ifc->u1, ifc->u2); /* Theta', det = cos(theta') */
  px_mat2_t th_inv, thp_inv;
  if (px_mat2_inverse(th, &th_inv) != PX_OK || px_mat2_inverse(thp, &thp_inv) != PX_OK)
    return PX_ESINGULAR;
  double eta = ev == PX_EVENT_REFLECT ? 1.0 : ifc->n1 / ifc->n2;
  double h = co - eta * ci; /* h of Eq. (2); -2 cos(theta) for a reflection */

  px_mat2_t a = px_mat2_mul(thp, th_inv), b, c, d;
  if (variant == PX_VARIANT_PRINTED) { /* Eq. (2) verbatim */
    b = px_mat2_identity();
    c = px_mat2_scale(px_mat2_mul(px_mat2_mul(thp_inv, ifc->q), th_inv), h);
    d = px_mat2_scale(px_mat2_mul(thp_inv, px_mat2_transpose(th)), eta);
  } else { /* corrected: docs/errata.md E1-E3 */
    px_mat2_t thp_invt = px_mat2_transpose(thp_inv);
    b = px_mat2_zero();
    c = px_mat2_scale(px_mat2_mul(px_mat2_mul(thp_invt, ifc->q), th_inv), -h);
    d = px_mat2_scale(px_mat2_mul(thp_invt, px_mat2_transpose(th)), eta);
  }
  px_mat4_t r = px_mat4_blocks(a, b, c, d);
  if (!px_mat4_isfinite(r))
    return PX_ENONFINITE;
  *t = r;
  return PX_OK;
}

px_status_t px_element_matrix(px_event_t ev, double theta, double n1, double n2, double radius,
                              px_variant_t variant, px_mat4_t *t) {
  px_interface_t ifc;
  px_frame_t in, out;
  px_status_t st =
      px_interface_canonical(theta, radius, n1, ev == PX_EVENT_REFLECT ? n1 : n2, &ifc);
  if (st == PX_OK)
    st = px_interface_frames(&ifc, ev, &in, &out);
  if (st == PX_OK)
    st = px_interface_matrix(&ifc, ev, in, out, variant, t);
  return st;
}
