/* refract.c -- the refracted child of a transparent surface (textbook 9.1, "r_t = ray towards
 * the inverse direction of refraction"), by px_interface_outgoing() (Snell's law in vector form,
 * paper section 2.2), with constant coefficients or a Fresnel split of kt. Entered only when the
 * effects plan has refraction. */
#include <math.h>

#include "paraxial/vec3.h"

#include "shade_impl.h"

double rt_fresnel(double ci, double ct, double n1, double n2) {
  if (ct < 0.0 || !(ci >= 0.0))
    return 1.0;
  if (n1 == n2) /* no interface: ct is ci up to rounding, which would leave F at 1e-32 or 0 */
    return 0.0;
  double rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
  double rp = (n1 * ct - n2 * ci) / (n1 * ct + n2 * ci);
  double f = 0.5 * (rs * rs + rp * rp);
  return isfinite(f) ? f : 1.0;
}

int rt__shade_refract(const rt_scene_t *s, const rt_surface_t *sf, const rt_ray_t *ray,
                      rt_child_t *child, rt_rgb_t *extra_reflect, int *tir) {
  const rt_material_t *m = sf->mat;
  rt_rgb_t wt = rt_rgb_scale(m->transmittance, m->kt);
  double n2 = sf->n2; /* a monochromatic ray's: spectral() in shade.c set it at its wavelength */
  px_interface_t ifc = {.s = ray->d, .nu = px_v3_scale(sf->nf, -1.0), .n1 = sf->n1, .n2 = n2};
  px_vec3_t dir;
  double co;
  px_status_t st = px_interface_outgoing(&ifc, PX_EVENT_REFRACT, &dir, &co);
  if (st != PX_OK) { /* total internal reflection: the transmitted share reflects */
    *extra_reflect = rt_rgb_add(*extra_reflect, wt);
    *tir = 1;
    return 0;
  }
  if (m->fresnel) {
    double f = rt_fresnel(-px_v3_dot(sf->nf, ray->d), co, sf->n1, n2);
    *extra_reflect = rt_rgb_add(*extra_reflect, rt_rgb(m->kt * f, m->kt * f, m->kt * f));
    wt = rt_rgb_scale(wt, 1.0 - f);
  }
  if (!child) /* the caller wants the reflected share only */
    return 1;
  int skip = s->prim[sf->hit.prim].kind != RT_PRIM_SPHERE ? sf->hit.prim : -1;
  child->ray = (rt_ray_t){rt__offset_origin(sf, -1.0), dir, 0.0, INFINITY, n2, skip, ray->lambda};
  child->weight = wt;
  child->kind = RT_RAY_REFRACT;
  child->tir = 0;
  return 1;
}

/* rt__shade_refract()'s ray alone, the same expressions (kept apart from it: sharing them as
 * inline helpers cost the exact renderer 0.14% more instructions, from register allocation). */
int rt__refract_ray(const rt_scene_t *s, const rt_surface_t *sf, const rt_ray_t *ray,
                    rt_ray_t *out) {
  double n2 = sf->n2;
  px_interface_t ifc = {.s = ray->d, .nu = px_v3_scale(sf->nf, -1.0), .n1 = sf->n1, .n2 = n2};
  px_vec3_t dir;
  double co;
  if (px_interface_outgoing(&ifc, PX_EVENT_REFRACT, &dir, &co) != PX_OK)
    return 0;
  int skip = s->prim[sf->hit.prim].kind != RT_PRIM_SPHERE ? sf->hit.prim : -1;
  *out = (rt_ray_t){rt__offset_origin(sf, -1.0), dir, 0.0, INFINITY, n2, skip, ray->lambda};
  return 1;
}
