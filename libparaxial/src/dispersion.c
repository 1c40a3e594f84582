/* dispersion.c -- index models and the extended system matrix of the 1989 Eq. (13)
 * (dispersion.h). */
#include "paraxial/dispersion.h"

#include <math.h>
#include <string.h>

px_index_t px_index_constant(double n) {
  px_index_t m;
  memset(&m, 0, sizeof m);
  m.kind = PX_INDEX_CONSTANT;
  m.a = n;
  m.lo_nm = 0.0;
  m.hi_nm = INFINITY;
  return m;
}

px_status_t px_index_eval(const px_index_t *m, double lambda_nm, double *n, double *dn_dlambda) {
  if (!isfinite(lambda_nm) || !(lambda_nm > 0.0) || !(lambda_nm >= m->lo_nm) ||
      !(lambda_nm <= m->hi_nm))
    return PX_EINVAL;
  double l = lambda_nm * 1e-3, l2 = l * l, nn, dn; /* um; dn per um */
  switch (m->kind) {
  case PX_INDEX_CONSTANT:
    nn = m->a;
    dn = 0.0;
    break;
  case PX_INDEX_CAUCHY:
    nn = m->a + m->b[0] / l2 + m->b[1] / (l2 * l2);
    dn = -2.0 * m->b[0] / (l2 * l) - 4.0 * m->b[1] / (l2 * l2 * l);
    break;
  case PX_INDEX_SELLMEIER: {
    if (m->nterm < 1 || m->nterm > PX_SELLMEIER_TERMS)
      return PX_EINVAL;
    double s = 1.0, ds = 0.0; /* n^2 and d(n^2)/dl */
    for (int i = 0; i < m->nterm; i++) {
      double den = l2 - m->c[i];
      if (!(fabs(den) > 1e-12))
        return PX_ENONFINITE;
      s += m->b[i] * l2 / den;
      ds += -2.0 * l * m->b[i] * m->c[i] / (den * den);
    }
    if (!(s > 0.0))
      return PX_ENONFINITE;
    nn = sqrt(s);
    dn = ds / (2.0 * nn);
    break;
  }
  default:
    return PX_EINVAL;
  }
  if (!isfinite(nn) || !(nn > 0.0) || !isfinite(dn))
    return PX_ENONFINITE;
  if (n)
    *n = nn;
  if (dn_dlambda)
    *dn_dlambda = dn * 1e-3; /* per nm */
  return PX_OK;
}

px_status_t px_index_from_abbe(double nd, double vd, px_index_t *out) {
  if (!isfinite(nd) || !(nd > 1.0) || !isfinite(vd) || !(vd > 0.0))
    return PX_EINVAL;
  double lf = PX_LAMBDA_F * 1e-3, lc = PX_LAMBDA_C * 1e-3, ld = PX_LAMBDA_D * 1e-3;
  double b = (nd - 1.0) / (vd * (1.0 / (lf * lf) - 1.0 / (lc * lc)));
  memset(out, 0, sizeof *out);
  out->kind = PX_INDEX_CAUCHY;
  out->a = nd - b / (ld * ld);
  out->b[0] = b;
  out->lo_nm = 380.0;
  out->hi_nm = 780.0;
  return PX_OK;
}

/* The catalogue: Sellmeier B_i and C_i (um^2) as their sources print them. */
static const struct {
  const char *name;
  int nterm;
  double b[PX_SELLMEIER_TERMS], c[PX_SELLMEIER_TERMS], lo_nm, hi_nm;
} catalogue[] = {
    /* Schott optical glass data sheets */
    {"N-BK7",
     3,
     {1.03961212, 0.231792344, 1.01046945},
     {0.00600069867, 0.0200179144, 103.560653},
     300.0,
     2500.0},
    {"F2",
     3,
     {1.34533359, 0.209073176, 0.937357162},
     {0.00997743871, 0.0470450767, 111.886764},
     320.0,
     2500.0},
    {"SF11",
     3,
     {1.73759695, 0.313747346, 1.89878101},
     {0.013188707, 0.0623068142, 155.23629},
     370.0,
     2500.0},
    /* Malitson 1965: C_i are the squares of 0.0684043, 0.1162414 and 9.896161 um */
    {"fused-silica",
     3,
     {0.6961663, 0.4079426, 0.8974794},
     {0.0684043 * 0.0684043, 0.1162414 * 0.1162414, 9.896161 * 9.896161},
     210.0,
     3710.0},
    /* Peter 1923: C_i the squares of 0.1060 and 0.1750 um; measured 226-644 nm, used to 780 */
    {"diamond", 2, {4.3356, 0.3306}, {0.1060 * 0.1060, 0.1750 * 0.1750}, 380.0, 780.0},
    /* Daimon and Masumura 2007, distilled water at 20.0 C, measured 182-1129 nm: the index
     * relative to vacuum (the Schott entries are relative to air, which is 2.7e-4 lower here) */
    {"water",
     4,
     {5.684027565e-1, 1.726177391e-1, 2.086189578e-2, 1.130748688e-1},
     {5.101829712e-3, 1.821153936e-2, 2.620722293e-2, 1.069792721e1},
     182.0,
     1129.0},
};

px_status_t px_index_named(const char *name, px_index_t *out) {
  for (size_t k = 0; name && k < sizeof catalogue / sizeof catalogue[0]; k++)
    if (strcmp(name, catalogue[k].name) == 0) {
      memset(out, 0, sizeof *out);
      out->kind = PX_INDEX_SELLMEIER;
      out->nterm = catalogue[k].nterm;
      for (int i = 0; i < PX_SELLMEIER_TERMS; i++) {
        out->b[i] = catalogue[k].b[i];
        out->c[i] = catalogue[k].c[i];
      }
      out->lo_nm = catalogue[k].lo_nm;
      out->hi_nm = catalogue[k].hi_nm;
      return PX_OK;
    }
  return PX_EINVAL;
}

const char *px_index_names(void) {
  return "N-BK7, F2, SF11, fused-silica, diamond, water";
}

int px_index_disperses(const px_index_t *m) {
  switch (m->kind) {
  case PX_INDEX_CAUCHY:
    return m->b[0] != 0.0 || m->b[1] != 0.0;
  case PX_INDEX_SELLMEIER:
    return 1;
  default:
    return 0;
  }
}

px_mat5_t px_mat5_identity(void) {
  px_mat5_t r = {px_mat4_identity(), {{0, 0, 0, 0}}};
  return r;
}

px_mat5_t px_mat5_from4(px_mat4_t t, px_ray4_t w) {
  px_mat5_t r = {t, w};
  return r;
}

px_mat5_t px_mat5_mul(px_mat5_t b, px_mat5_t a) {
  px_mat5_t r;
  r.t = px_mat4_mul(b.t, a.t);
  r.w = px_mat4_apply(b.t, a.w);
  for (int i = 0; i < 4; i++)
    r.w.v[i] += b.w.v[i];
  return r;
}

px_ray4_t px_mat5_apply(px_mat5_t t, px_ray4_t psi, double dlambda) {
  px_ray4_t r = px_mat4_apply(t.t, psi);
  for (int i = 0; i < 4; i++)
    r.v[i] += t.w.v[i] * dlambda;
  return r;
}

int px_mat5_isfinite(px_mat5_t t) {
  if (!px_mat4_isfinite(t.t))
    return 0;
  for (int i = 0; i < 4; i++)
    if (!isfinite(t.w.v[i]))
      return 0;
  return 1;
}

px_mat5_t px_transfer_matrix5(double z0) {
  return px_mat5_from4(px_transfer_matrix(z0), (px_ray4_t){{0, 0, 0, 0}});
}

px_status_t px_interface_column(const px_interface_t *ifc, px_event_t ev, px_frame_t out,
                                double dn1, double dn2, px_variant_t variant, px_ray4_t *w) {
  if (!isfinite(dn1) || !isfinite(dn2))
    return PX_EINVAL;
  px_vec3_t sp;
  double cp;
  px_status_t st = px_interface_outgoing(ifc, ev, &sp, &cp);
  if (st != PX_OK)
    return st;
  if (!(fabs(cp) > PX_COS_MIN) || !(px_vec3_dot(ifc->nu, ifc->s) > PX_COS_MIN))
    return PX_EGRAZING;
  if (px_vec3_norm(px_vec3_sub(out.z, sp)) > 1e-9)
    return PX_EINVAL; /* the frame is not the outgoing ray's */
  memset(w, 0, sizeof *w);
  if (ev == PX_EVENT_REFLECT)
    return PX_OK; /* the mirror law has no index */
  /* Theta'^T xi_lambda = r, Theta'_ij = x'_i . u_j: the tangential Snell law differentiated */
  px_vec3_t u[2] = {ifc->u1, ifc->u2};
  double r[2];
  for (int j = 0; j < 2; j++)
    r[j] = variant == PX_VARIANT_PRINTED
               ? dn2 * px_vec3_dot(u[j], sp) /* the printed Eq. (14): -n2 times the far medium's */
               : (dn1 * px_vec3_dot(u[j], ifc->s) - dn2 * px_vec3_dot(u[j], sp)) / ifc->n2;
  px_mat2_t tt = px_mat2(px_vec3_dot(out.x1, u[0]), px_vec3_dot(out.x2, u[0]),
                         px_vec3_dot(out.x1, u[1]), px_vec3_dot(out.x2, u[1])); /* Theta'^T */
  px_mat2_t inv;
  if (px_mat2_inverse(tt, &inv) != PX_OK)
    return PX_ESINGULAR;
  w->v[2] = inv.m[0][0] * r[0] + inv.m[0][1] * r[1];
  w->v[3] = inv.m[1][0] * r[0] + inv.m[1][1] * r[1];
  return isfinite(w->v[2]) && isfinite(w->v[3]) ? PX_OK : PX_ENONFINITE;
}

px_status_t px_interface_matrix5(const px_interface_t *ifc, px_event_t ev, px_frame_t in,
                                 px_frame_t out, double dn1, double dn2, px_variant_t variant,
                                 px_mat5_t *t) {
  px_mat4_t m;
  px_ray4_t w;
  px_status_t st = px_interface_matrix(ifc, ev, in, out, variant, &m);
  if (st == PX_OK)
    st = px_interface_column(ifc, ev, out, dn1, dn2, variant, &w);
  if (st == PX_OK)
    *t = px_mat5_from4(m, w);
  return st;
}

px_status_t px_element_matrix5_cs(px_event_t ev, double c, double s, double n1, double n2,
                                  double dn1, double dn2, double radius, px_variant_t variant,
                                  px_mat5_t *t, double *err) {
  px_mat4_t m;
  px_status_t st = px_element_matrix_cs(ev, c, s, n1, n2, radius, variant, &m, err);
  if (st != PX_OK)
    return st;
  /* the same interface and frames as px_element_matrix_cs() */
  double k = isinf(radius) ? 0.0 : 1.0 / radius;
  px_interface_t ifc;
  px_frame_t in, out;
  px_ray4_t w;
  st = px_interface_make(px_vec3(s, 0.0, c), px_vec3(0, 0, 1), px_vec3(0, 1, 0), px_mat2_diag(k, k),
                         NULL, n1, ev == PX_EVENT_REFLECT ? n1 : n2, &ifc);
  if (st == PX_OK)
    st = px_interface_frames(&ifc, ev, &in, &out);
  if (st == PX_OK)
    st = px_interface_column(&ifc, ev, out, dn1, dn2, variant, &w);
  if (st == PX_OK)
    *t = px_mat5_from4(m, w);
  return st;
}

px_status_t px_cascade_product5(const px_cascade_t *c, const double *dn1, const double *dn2,
                                px_variant_t variant, px_mat5_t *out) {
  px_mat5_t r = px_mat5_identity();
  for (size_t i = 0; i < c->n; i++) {
    const px_element_t *e = &c->elem[i];
    px_ray4_t w = {{0, 0, 0, 0}};
    if (e->kind != PX_ELEMENT_TRANSFER) {
      px_event_t ev = e->kind == PX_ELEMENT_REFLECT ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
      px_status_t st = px_interface_column(&e->ifc, ev, e->out, dn1 ? dn1[i] : 0.0,
                                           dn2 ? dn2[i] : 0.0, variant, &w);
      if (st != PX_OK)
        return st;
    }
    r = px_mat5_mul(px_mat5_from4(e->t, w), r);
  }
  if (!px_mat5_isfinite(r))
    return PX_ENONFINITE;
  *out = r;
  return PX_OK;
}

px_status_t px_wavescale_make(const px_index_t *glass, double lambda0, px_wavescale_t *out) {
  double n0, dn0;
  px_status_t st = px_index_eval(glass, lambda0, &n0, &dn0);
  if (st != PX_OK)
    return st;
  if (!(dn0 != 0.0) || !isfinite(dn0))
    return PX_EINVAL;
  *out = (px_wavescale_t){*glass, lambda0, n0, dn0};
  return PX_OK;
}

px_status_t px_wavescale_to(const px_wavescale_t *w, double lambda, double *Lambda) {
  double n;
  px_status_t st = px_index_eval(&w->glass, lambda, &n, NULL);
  if (st != PX_OK)
    return st;
  *Lambda = w->lambda0 + (n - w->n0) / w->dn0;
  return PX_OK;
}

px_status_t px_wavescale_from(const px_wavescale_t *w, double Lambda, double *lambda) {
  double a = w->glass.lo_nm, b = w->glass.hi_nm, La, Lb;
  if (px_wavescale_to(w, a, &La) != PX_OK || px_wavescale_to(w, b, &Lb) != PX_OK)
    return PX_EINVAL;
  if (!(La < Lb) || !(Lambda >= La && Lambda <= Lb))
    return PX_EINVAL; /* Lambda increases with lambda for a glass with n' of one sign */
  for (int it = 0; it < 200 && b - a > 1e-13 * fmax(1.0, fabs(b)); it++) {
    double m = 0.5 * (a + b), Lm;
    if (px_wavescale_to(w, m, &Lm) != PX_OK)
      return PX_EINVAL;
    if (Lm < Lambda)
      a = m;
    else
      b = m;
  }
  *lambda = 0.5 * (a + b);
  return PX_OK;
}
