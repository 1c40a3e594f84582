/* walk4.c -- four rays along one known path at a time: rt_shade_walk_ray() and
 * rt_prim_intersect() lane by lane bit for bit, with AVX2 and FMA where the CPU has them
 * (px_simd4_available()), else by the scalar functions lane by lane. The pencil renderer's exact
 * walks carry the samples of a lattice cell along the same nodes (pencil/src/eval.c), so the four
 * lanes share the primitive, its material and the event; only the points and directions differ.
 *
 * Bit for bit: every expression is the scalar one's, in the same order, products and sums rounded
 * apart (the build contracts nothing into an FMA), fma() only where the scalar code calls it
 * (px_interface_outgoing4() in libparaxial). tests/test_render_shade.c (the cases `*_of_four_*`)
 * compares the lanes with the scalar functions. */
#include <math.h>

#include "core/intersect.h"
#include "core/shade_paths.h"
#include "prim.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(PX_NO_SIMD4)
#define RT_SIMD4 1
#include <immintrin.h>
#endif

static void walk_ray_lanes(const rt_scene_t *s, const rt_plan_t *plan, int prim,
                           const px_vec3x4_t *p, const px_vec3x4_t *d, const double ior[4],
                           int depth, rt_ray_kind_t kind, unsigned lanes, rt_ray4_t *out,
                           int got[4]) {
  for (int i = 0; i < 4; i++) {
    got[i] = 0;
    if (!(lanes & (1u << i)))
      continue;
    rt_ray_t r;
    got[i] = rt_shade_walk_ray(s, plan, prim, px_v3(p->x[i], p->y[i], p->z[i]),
                               px_v3(d->x[i], d->y[i], d->z[i]), ior[i], depth, kind, &r);
    if (got[i] == 1) {
      out->o.x[i] = r.o.x, out->o.y[i] = r.o.y, out->o.z[i] = r.o.z;
      out->d.x[i] = r.d.x, out->d.y[i] = r.d.y, out->d.z[i] = r.d.z;
      out->ior[i] = r.ior;
    }
  }
  out->skip_prim = s->prim[prim].kind != RT_PRIM_SPHERE ? prim : -1;
}

#ifdef RT_SIMD4
#define V __m256d
#define LD _mm256_loadu_pd
#define ST _mm256_storeu_pd
#define SET1 _mm256_set1_pd
#define ADD _mm256_add_pd
#define SUB _mm256_sub_pd
#define MUL _mm256_mul_pd
#define NEG(a) _mm256_xor_pd(a, SET1(-0.0)) /* unary minus: the sign bit */
#define LT(a, b) _mm256_cmp_pd(a, b, _CMP_LT_OQ)
#define GT(a, b) _mm256_cmp_pd(a, b, _CMP_GT_OQ)
#define MASK(a) ((unsigned)_mm256_movemask_pd(a))

/* px_v3_dot(): (a.x b.x + a.y b.y) + a.z b.z */
#define DOT(ax, ay, az, bx, by, bz) ADD(ADD(MUL(ax, bx), MUL(ay, by)), MUL(az, bz))

__attribute__((target("avx2,fma"))) static void
walk_ray_avx2(const rt_scene_t *s, const rt_material_t *m, px_event_t ev, double side, int prim,
              const px_vec3x4_t *p, const px_vec3x4_t *d, const double ior[4], unsigned lanes,
              rt_ray4_t *out, int got[4]) {
  const rt_prim_t *pr = &s->prim[prim];
  V px = LD(p->x), py = LD(p->y), pz = LD(p->z), dx = LD(d->x), dy = LD(d->y), dz = LD(d->z);
  V nx, ny, nz;
  if (pr->kind == RT_PRIM_SPHERE) { /* rt_prim_normal_at(): (p - c) * (1 / |p - c|) */
    V cx = SUB(px, SET1(pr->sphere.c.x)), cy = SUB(py, SET1(pr->sphere.c.y)),
      cz = SUB(pz, SET1(pr->sphere.c.z));
    V inv = _mm256_div_pd(SET1(1.0), _mm256_sqrt_pd(DOT(cx, cy, cz, cx, cy, cz)));
    nx = MUL(cx, inv), ny = MUL(cy, inv), nz = MUL(cz, inv);
  } else {
    px_vec3_t n = rt_prim_normal_at(pr, px_v3(0, 0, 0));
    nx = SET1(n.x), ny = SET1(n.y), nz = SET1(n.z);
  }
  V dn = DOT(nx, ny, nz, dx, dy, dz), front = LT(dn, _mm256_setzero_pd());
  /* nf: the normal facing the ray (n, or n scaled by -1, which flips the sign bit) */
  V fx = _mm256_blendv_pd(NEG(nx), nx, front), fy = _mm256_blendv_pd(NEG(ny), ny, front),
    fz = _mm256_blendv_pd(NEG(nz), nz, front);
  V vior = LD(ior);
  V n2 = ev == PX_EVENT_REFLECT ? vior : _mm256_blendv_pd(SET1(s->ior), SET1(m->ior), front);
  /* rt__offset_origin(): 1 + the largest |coordinate|; max_pd(a, b) is a > b ? a : b */
  V ax = _mm256_andnot_pd(SET1(-0.0), px), ay = _mm256_andnot_pd(SET1(-0.0), py),
    az = _mm256_andnot_pd(SET1(-0.0), pz);
  V big = _mm256_blendv_pd(_mm256_max_pd(ay, az), _mm256_max_pd(ax, az), GT(ax, ay));
  V c = MUL(SET1(side * RT_SURFACE_OFFSET), ADD(SET1(1.0), big));
  ST(out->o.x, ADD(MUL(c, fx), px));
  ST(out->o.y, ADD(MUL(c, fy), py));
  ST(out->o.z, ADD(MUL(c, fz), pz));
  px_vec3x4_t nu;
  ST(nu.x, NEG(fx));
  ST(nu.y, NEG(fy));
  ST(nu.z, NEG(fz));
  double n2s[4];
  ST(n2s, n2);
  px_status_t st[4];
  px_interface_outgoing4(ev, d, &nu, ior, n2s, lanes, &out->d, st);
  for (int i = 0; i < 4; i++) {
    got[i] = st[i] == PX_OK;
    out->ior[i] = n2s[i];
  }
  out->skip_prim = pr->kind != RT_PRIM_SPHERE ? prim : -1;
}
#endif

void rt_shade_walk_ray4(const rt_scene_t *s, const rt_plan_t *plan, int prim, const px_vec3x4_t *p,
                        const px_vec3x4_t *d, const double ior[4], int depth, rt_ray_kind_t kind,
                        unsigned lanes, rt_ray4_t *out, int got[4]) {
#ifdef RT_SIMD4
  const rt_object_t *o = &s->object[s->prim[prim].object];
  if (px_simd4_available() && o->material2 < 0) { /* one material for every lane */
    const rt_material_t *m = &s->material[o->material];
    int all = 0;
    if (depth >= plan->max_depth || (kind != RT_RAY_REFRACT && kind != RT_RAY_REFLECT))
      all = 0;
    else if (kind == RT_RAY_REFRACT && !(rt_plan_has(plan, RT_EFFECT_REFRACTION) && m->kt > 0.0))
      all = 0;
    else if (kind == RT_RAY_REFLECT &&
             !(rt_plan_has(plan, RT_EFFECT_REFLECTION) && m->kr > 0.0 && m->kt >= 0.0 &&
               m->transmittance.r >= 0.0 && m->transmittance.g >= 0.0 && m->transmittance.b >= 0.0))
      all = -1; /* rt_shade_walk_ray(): the mirror child's weight decides */
    else {
      int refract = kind == RT_RAY_REFRACT;
      walk_ray_avx2(s, m, refract ? PX_EVENT_REFRACT : PX_EVENT_REFLECT, refract ? -1.0 : 1.0, prim,
                    p, d, ior, lanes, out, got);
      for (int i = 0; i < 4; i++)
        got[i] = (lanes & (1u << i)) ? got[i] : 0;
      return;
    }
    for (int i = 0; i < 4; i++)
      got[i] = (lanes & (1u << i)) ? all : 0;
    out->skip_prim = s->prim[prim].kind != RT_PRIM_SPHERE ? prim : -1;
    return;
  }
#endif
  walk_ray_lanes(s, plan, prim, p, d, ior, depth, kind, lanes, out, got);
}

static unsigned intersect_lanes(const rt_scene_t *s, int prim, const px_vec3x4_t *o,
                                const px_vec3x4_t *d, unsigned lanes, double t[4], px_vec3x4_t *p) {
  unsigned hit = 0;
  for (int i = 0; i < 4; i++) {
    if (!(lanes & (1u << i)))
      continue;
    rt_ray_t r = {px_v3(o->x[i], o->y[i], o->z[i]),
                  px_v3(d->x[i], d->y[i], d->z[i]),
                  0.0,
                  INFINITY,
                  1.0,
                  -1,
                  0.0f};
    if (prim_hit(s, prim, &r, INFINITY, &t[i])) {
      px_vec3_t q = px_v3_axpy(t[i], r.d, r.o);
      p->x[i] = q.x, p->y[i] = q.y, p->z[i] = q.z;
      hit |= 1u << i;
    }
  }
  return hit;
}

#ifdef RT_SIMD4
__attribute__((target("avx2,fma"))) static unsigned
intersect_avx2(const rt_scene_t *s, int prim, const px_vec3x4_t *o, const px_vec3x4_t *d,
               unsigned lanes, double t[4], px_vec3x4_t *p) {
  const rt_prim_t *pr = &s->prim[prim];
  V ox = LD(o->x), oy = LD(o->y), oz = LD(o->z), dx = LD(d->x), dy = LD(d->y), dz = LD(d->z);
  V zero = _mm256_setzero_pd(), inf = SET1(INFINITY);
  if (pr->kind == RT_PRIM_SPHERE) { /* sphere_roots() and prim_hit()'s choice of root */
    V r = SET1(pr->sphere.r);
    V cx = SUB(ox, SET1(pr->sphere.c.x)), cy = SUB(oy, SET1(pr->sphere.c.y)),
      cz = SUB(oz, SET1(pr->sphere.c.z));
    V b = DOT(cx, cy, cz, dx, dy, dz), nb = NEG(b);
    V qx = ADD(MUL(nb, dx), cx), qy = ADD(MUL(nb, dy), cy), qz = ADD(MUL(nb, dz), cz);
    V pn = _mm256_sqrt_pd(DOT(qx, qy, qz, qx, qy, qz));
    V disc = MUL(SUB(r, pn), ADD(r, pn));
    unsigned meets = ~MASK(LT(disc, zero)) & 15u;
    V sq = _mm256_sqrt_pd(disc); /* NaN where disc < 0: those lanes are dropped */
    V sign = SET1(-0.0);
    V q = SUB(nb, _mm256_or_pd(_mm256_andnot_pd(sign, sq), _mm256_and_pd(sign, b)));
    V len = _mm256_sqrt_pd(DOT(cx, cy, cz, cx, cy, cz));
    V prod = MUL(SUB(len, r), ADD(len, r));
    V t2 = _mm256_blendv_pd(zero, _mm256_div_pd(prod, q), _mm256_cmp_pd(q, zero, _CMP_NEQ_UQ));
    V r0 = _mm256_min_pd(q, t2), r1 = _mm256_max_pd(q, t2);
    V in0 = _mm256_and_pd(GT(r0, zero), LT(r0, inf)),
      in1 = _mm256_and_pd(GT(r1, zero), LT(r1, inf));
    V tt = _mm256_blendv_pd(r1, r0, in0);
    ST(t, tt);
    ST(p->x, ADD(MUL(tt, dx), ox)); /* px_v3_axpy(t, d, o) */
    ST(p->y, ADD(MUL(tt, dy), oy));
    ST(p->z, ADD(MUL(tt, dz), oz));
    return lanes & meets & MASK(_mm256_or_pd(in0, in1));
  }
  /* plane_t(): (d - n.o) / n.d, 0 when parallel */
  px_vec3_t n = pr->kind == RT_PRIM_PLANE ? pr->plane.n : pr->polygon.n;
  double dd = pr->kind == RT_PRIM_PLANE ? px_v3_dot(pr->plane.n, pr->plane.p) : pr->polygon.d;
  V nx = SET1(n.x), ny = SET1(n.y), nz = SET1(n.z);
  V den = DOT(nx, ny, nz, dx, dy, dz);
  V tt = _mm256_div_pd(SUB(SET1(dd), DOT(nx, ny, nz, ox, oy, oz)), den);
  unsigned hit = lanes & ~MASK(_mm256_cmp_pd(den, zero, _CMP_EQ_OQ)) &
                 MASK(_mm256_and_pd(GT(tt, zero), LT(tt, inf)));
  ST(t, tt);
  ST(p->x, ADD(MUL(tt, dx), ox)); /* px_v3_axpy(t, d, o) */
  ST(p->y, ADD(MUL(tt, dy), oy));
  ST(p->z, ADD(MUL(tt, dz), oz));
  if (pr->kind == RT_PRIM_POLYGON)
    for (int i = 0; i < 4; i++)
      if ((hit & (1u << i)) && !polygon_inside(s, &pr->polygon, px_v3(p->x[i], p->y[i], p->z[i])))
        hit &= ~(1u << i);
  return hit;
}
#endif

unsigned rt_prim_intersect4(const rt_scene_t *s, int prim, const px_vec3x4_t *o,
                            const px_vec3x4_t *d, unsigned lanes, double t[4], px_vec3x4_t *hit) {
#ifdef RT_SIMD4
  if (px_simd4_available())
    return intersect_avx2(s, prim, o, d, lanes, t, hit);
#endif
  return intersect_lanes(s, prim, o, d, lanes, t, hit);
}
