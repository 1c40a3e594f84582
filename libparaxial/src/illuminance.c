/* illuminance.c -- Eqs. (8)-(9) of the 1987 paper (section 4.2) and the 1989 paper's Eq. (1) as
 * printed; see paraxial/illuminance.h for the derivation and docs/errata.md (E4) for the index
 * factor. */
#include "paraxial/illuminance.h"

#include <math.h>
#include <string.h>

px_status_t px_source_parse(const char *name, px_source_t *out) {
  if (name && strcmp(name, "point") == 0)
    *out = PX_SOURCE_POINT;
  else if (name && strcmp(name, "parallel") == 0)
    *out = PX_SOURCE_PARALLEL;
  else
    return PX_EINVAL;
  return PX_OK;
}

const char *px_source_name(px_source_t s) {
  return s == PX_SOURCE_PARALLEL ? "parallel" : "point";
}

px_status_t px_spread_ratio(const px_mat4_t *t, const px_mat4_t *t_abs, px_source_t source,
                            double cos_alpha, double *ratio, double *cond) {
  if (!t || !ratio || (source != PX_SOURCE_POINT && source != PX_SOURCE_PARALLEL) ||
      !px_mat4_isfinite(*t) || (t_abs && !px_mat4_isfinite(*t_abs)) ||
      !(fabs(cos_alpha) <= 1.0 + PX_COS_SLACK))
    return PX_EINVAL;
  double c = fmin(fabs(cos_alpha), 1.0);
  if (c <= PX_COS_MIN)
    return PX_EGRAZING;
  int col = source == PX_SOURCE_POINT ? 2 : 0; /* B (x' from xi) or A (x' from x) */
  double a = t->m[0][col], b = t->m[0][col + 1], cc = t->m[1][col], d = t->m[1][col + 1];
  const px_mat4_t *m = t_abs ? t_abs : t;
  double m00 = fabs(m->m[0][col]), m01 = fabs(m->m[0][col + 1]), m10 = fabs(m->m[1][col]),
         m11 = fabs(m->m[1][col + 1]);
  double ad = a * d, bc = b * cc, det = ad - bc;
  double mag = fabs(d) * m00 + fabs(cc) * m01 + fabs(b) * m10 + fabs(a) * m11 + fabs(ad) + fabs(bc);
  if (!isfinite(ad) || !isfinite(bc) || !isfinite(mag))
    return PX_ENONFINITE;
  if (cond)
    *cond = det != 0.0 ? mag / fabs(det) : INFINITY;
  if (det == 0.0 || mag * PX_ENTRY_EPS > PX_ACCURACY * fabs(det))
    return PX_ECAUSTIC;
  double r = c / fabs(det);
  if (!isfinite(r))
    return PX_ENONFINITE;
  *ratio = r;
  return PX_OK;
}

px_status_t px_illuminance(const px_mat4_t *t, const px_mat4_t *t_abs, px_source_t source,
                           double cos_alpha, double intensity, double tr, double n1, double n2,
                           px_variant_t variant, double *e) {
  if (!e || !(intensity >= 0.0) || !isfinite(intensity) || !(tr >= 0.0 && tr <= 1.0) ||
      (variant != PX_VARIANT_CORRECTED && variant != PX_VARIANT_PRINTED))
    return PX_EINVAL;
  if (variant == PX_VARIANT_PRINTED && !(n1 > 0.0 && n2 > 0.0 && isfinite(n1) && isfinite(n2)))
    return PX_EINVAL;
  double r;
  px_status_t st = px_spread_ratio(t, t_abs, source, cos_alpha, &r, NULL);
  if (st != PX_OK)
    return st;
  double v = tr * intensity * r;
  if (variant == PX_VARIANT_PRINTED)
    v *= n1 / n2;
  if (!isfinite(v))
    return PX_ENONFINITE;
  *e = v;
  return PX_OK;
}
