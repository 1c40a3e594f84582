/* query.c -- the scene queries of the exact tracer: the nearest hit (textbook 9.1 Intersect(r))
 * through the BVH (9.2), and the transmittance of a shadow segment through transparent
 * occluders, "k_t(1) k_t(2) ... k_t(N) I instead of I" (9.1). Nothing here allocates. */
#include <math.h>

#include "paraxial/vec3.h"

#include "bvh.h"
#include "core/intersect.h"
#include "prim.h"

typedef struct {
  double o[3], inv[3];
} slab_ray_t;

static slab_ray_t slab_ray(const rt_ray_t *r) {
  return (slab_ray_t){{r->o.x, r->o.y, r->o.z}, {1.0 / r->d.x, 1.0 / r->d.y, 1.0 / r->d.z}};
}

/* Entry distance into the node's box if the ray meets it within [t0, t1], else INFINITY. A zero
 * direction component gives inv = +-inf, which the slab formula handles; only a ray lying exactly
 * in a box face and parallel to it (0 * inf = NaN) may be rejected, and such a ray can at most
 * graze the box. */
static double box_entry(const rt_bvh_node_t *nd, const slab_ray_t *r, double t0, double t1) {
  for (int k = 0; k < 3; k++) {
    double a = (nd->lo[k] - r->o[k]) * r->inv[k], b = (nd->hi[k] - r->o[k]) * r->inv[k];
    t0 = ordered_max(ordered_min(a, b), t0);
    t1 = ordered_min(ordered_max(a, b), t1);
  }
  return t0 <= t1 ? t0 : INFINITY;
}

/* Two doubles operated on lane by lane: SSE2 (part of every x86-64) where available, plain pairs
 * elsewhere. Each lane does exactly what box_entry() does: minpd(a, b) is a < b ? a : b and
 * maxpd(a, b) is a > b ? a : b, NaN included, as ordered_min() and ordered_max(). */
#if defined(__SSE2__)
#include <emmintrin.h>
typedef __m128d v2d_t;
static inline v2d_t v2_load(const double p[2]) {
  return _mm_loadu_pd(p);
}
static inline v2d_t v2_splat(double a) {
  return _mm_set1_pd(a);
}
static inline v2d_t v2_min(v2d_t a, v2d_t b) {
  return _mm_min_pd(a, b);
}
static inline v2d_t v2_max(v2d_t a, v2d_t b) {
  return _mm_max_pd(a, b);
}
static inline v2d_t v2_sub(v2d_t a, v2d_t b) {
  return _mm_sub_pd(a, b);
}
static inline v2d_t v2_mul(v2d_t a, v2d_t b) {
  return _mm_mul_pd(a, b);
}
static inline void v2_store(double p[2], v2d_t a) {
  _mm_storeu_pd(p, a);
}
#else
typedef struct {
  double v[2];
} v2d_t;
static inline v2d_t v2_load(const double p[2]) {
  return (v2d_t){{p[0], p[1]}};
}
static inline v2d_t v2_splat(double a) {
  return (v2d_t){{a, a}};
}
static inline v2d_t v2_min(v2d_t a, v2d_t b) {
  return (v2d_t){{ordered_min(a.v[0], b.v[0]), ordered_min(a.v[1], b.v[1])}};
}
static inline v2d_t v2_max(v2d_t a, v2d_t b) {
  return (v2d_t){{ordered_max(a.v[0], b.v[0]), ordered_max(a.v[1], b.v[1])}};
}
static inline v2d_t v2_sub(v2d_t a, v2d_t b) {
  return (v2d_t){{a.v[0] - b.v[0], a.v[1] - b.v[1]}};
}
static inline v2d_t v2_mul(v2d_t a, v2d_t b) {
  return (v2d_t){{a.v[0] * b.v[0], a.v[1] * b.v[1]}};
}
static inline void v2_store(double p[2], v2d_t a) {
  p[0] = a.v[0];
  p[1] = a.v[1];
}
#endif

/* box_entry() for both children of an interior node at once: t[c] is the entry distance into
 * child c's box within [t0, t1], or INFINITY. */
static void pair_entry(const rt_bvh_pair_t *pr, const slab_ray_t *r, double t0, double t1,
                       double t[2]) {
  v2d_t lo = v2_splat(t0), hi = v2_splat(t1);
  for (int k = 0; k < 3; k++) {
    v2d_t o = v2_splat(r->o[k]), inv = v2_splat(r->inv[k]);
    v2d_t a = v2_mul(v2_sub(v2_load(pr->lo[k]), o), inv);
    v2d_t b = v2_mul(v2_sub(v2_load(pr->hi[k]), o), inv);
    lo = v2_max(v2_min(a, b), lo);
    hi = v2_min(v2_max(a, b), hi);
  }
  double l[2], h[2];
  v2_store(l, lo);
  v2_store(h, hi);
  for (int c = 0; c < 2; c++)
    t[c] = l[c] <= h[c] ? l[c] : INFINITY;
}

static void fill_hit(const rt_scene_t *s, const rt_ray_t *ray, int prim, double t, rt_hit_t *h) {
  h->t = t;
  h->p = px_v3_axpy(t, ray->d, ray->o);
  h->n = rt_prim_normal_at(&s->prim[prim], h->p);
  h->prim = prim;
  h->object = s->prim[prim].object;
}

static void test_prim(const rt_scene_t *s, int prim, const rt_ray_t *ray, double *best,
                      int *found) {
  double t;
  if (prim != ray->skip_prim && prim_hit(s, prim, ray, *best, &t)) {
    *best = t;
    *found = prim;
  }
}

/* Nearest hit among the BVH's primitives: depth-first, near child first; far children wait on a
 * stack with their entry distance and are skipped once a nearer hit is known. A node is named by
 * (ref, count) as in rt_bvh_pair_t: a leaf's primitives or an interior node's pair. */
static void traverse_nearest(const rt_scene_t *s, const rt_ray_t *ray, double *best, int *found) {
  const struct rt_bvh *b = s->bvh;
  slab_ray_t sr = slab_ray(ray);
  struct {
    int ref, count;
    double t;
  } stack[RT_BVH_MAX_DEPTH + 1];
  int sp = 0, ref = 0, count = b->node[0].count;
  if (count > 0)
    ref = b->node[0].start;
  if (box_entry(&b->node[0], &sr, ray->tmin, *best) == INFINITY)
    return;
  for (;;) {
    if (count > 0) {
      for (int i = ref; i < ref + count; i++)
        test_prim(s, b->order[i], ray, best, found);
    } else {
      const rt_bvh_pair_t *pr = &b->pair[ref];
      double t[2];
      pair_entry(pr, &sr, ray->tmin, *best, t);
      if (t[0] != INFINITY && t[1] != INFINITY) {
        int near = t[0] <= t[1] ? 0 : 1;
        stack[sp].ref = pr->ref[1 - near];
        stack[sp].count = pr->count[1 - near];
        stack[sp++].t = t[1 - near];
        ref = pr->ref[near];
        count = pr->count[near];
        continue;
      }
      if (t[0] != INFINITY || t[1] != INFINITY) {
        int c = t[0] != INFINITY ? 0 : 1;
        ref = pr->ref[c];
        count = pr->count[c];
        continue;
      }
    }
    do { /* the next waiting node that may still hold a nearer hit */
      if (--sp < 0)
        return;
      /* entries below sp were pushed above; cppcheck cannot follow the stack pointer */
      // cppcheck-suppress uninitvar
    } while (!(stack[sp].t < *best));
    ref = stack[sp].ref;
    count = stack[sp].count;
  }
}

int rt_intersect(const rt_scene_t *s, const rt_ray_t *ray, rt_hit_t *hit) {
  double best = ray->tmax;
  int found = -1;
  if (s->bvh && s->bvh->norder > 0)
    traverse_nearest(s, ray, &best, &found);
  for (int i = 0; i < s->nunbounded; i++)
    test_prim(s, s->unbounded[i], ray, &best, &found);
  if (found < 0)
    return 0;
  fill_hit(s, ray, found, best, hit);
  return 1;
}

/* rt_medium_object()'s probe: the hit, or 0 when p is in no closed object. */
static int medium_hit(const rt_scene_t *s, px_vec3_t p, rt_hit_t *h) {
  /* a direction along no axis or diagonal, so that the probe seldom grazes an edge */
  const px_vec3_t d = {0.3713906763541037, 0.8356290217967333, 0.4045580306149813};
  rt_ray_t r = {p, d, 0.0, INFINITY, s->ior, -1, 0.0f};
  return rt_intersect(s, &r, h) && s->object[h->object].closed && px_v3_dot(h->n, d) > 0.0;
}

int rt_medium_object(const rt_scene_t *s, px_vec3_t p) {
  rt_hit_t h;
  return medium_hit(s, p, &h) ? h.object : -1;
}

double rt_medium_ior(const rt_scene_t *s, px_vec3_t p) {
  rt_hit_t h;
  return medium_hit(s, p, &h) ? rt_scene_material_at(s, h.prim, h.p, NULL)->ior : s->ior;
}

int rt_intersect_brute(const rt_scene_t *s, const rt_ray_t *ray, rt_hit_t *hit) {
  double best = ray->tmax;
  int found = -1;
  for (int i = 0; i < s->nprim; i++)
    test_prim(s, i, ray, &best, &found);
  if (found < 0)
    return 0;
  fill_hit(s, ray, found, best, hit);
  return 1;
}

/* Multiply *tr by what crossing `prim` at distance t lets through; 0 when that is nothing. */
static int attenuate(const rt_scene_t *s, int prim, const rt_ray_t *ray, double t, rt_rgb_t *tr) {
  px_vec3_t p = px_v3_axpy(t, ray->d, ray->o);
  const rt_material_t *m = rt_scene_material_at(s, prim, p, NULL);
  if (!(m->kt > 0.0)) {
    *tr = rt_rgb(0, 0, 0);
    return 0;
  }
  const rt_prim_t *pr = &s->prim[prim];
  /* outward normal, unnormalised for a sphere: only the sign of its dot with d is needed */
  px_vec3_t out =
      pr->kind == RT_PRIM_SPHERE ? px_v3_sub(p, pr->sphere.c) : rt_prim_normal_at(pr, p);
  if (s->object[pr->object].closed && px_v3_dot(out, ray->d) < 0.0)
    return 1; /* entering a closed object: its factor is applied once, on the way out */
  *tr = rt_rgb_mul(*tr, rt_rgb_scale(m->transmittance, m->kt));
  return rt_rgb_max(*tr) > 0.0;
}

static int cross_prim(const rt_scene_t *s, int prim, const rt_ray_t *ray, rt_rgb_t *tr) {
  double t[2];
  if (prim == ray->skip_prim)
    return 1;
  int n = prim_crossings(s, prim, ray, t);
  for (int k = 0; k < n; k++)
    if (!attenuate(s, prim, ray, t[k], tr))
      return 0;
  return 1;
}

/* rt_transmittance(), and with `blocker` the object that blocked the light (-1 when none did). */
static inline __attribute__((always_inline)) rt_rgb_t
transmittance(const rt_scene_t *s, const rt_ray_t *ray, int *blocker) {
  rt_rgb_t tr = rt_rgb(1, 1, 1);
  if (blocker)
    *blocker = -1;
  for (int i = 0; i < s->nunbounded; i++)
    if (!cross_prim(s, s->unbounded[i], ray, &tr)) {
      if (blocker)
        *blocker = s->prim[s->unbounded[i]].object;
      return tr;
    }
  const struct rt_bvh *b = s->bvh;
  if (!b || b->norder == 0)
    return tr;
  /* every leaf whose box the segment meets, left subtree before right */
  slab_ray_t sr = slab_ray(ray);
  if (box_entry(&b->node[0], &sr, ray->tmin, ray->tmax) == INFINITY)
    return tr;
  struct {
    int ref, count;
  } stack[RT_BVH_MAX_DEPTH + 2];
  int sp = 0;
  stack[sp].ref = b->node[0].count > 0 ? b->node[0].start : 0;
  stack[sp++].count = b->node[0].count;
  while (sp > 0) {
    sp--;
    int ref = stack[sp].ref, count = stack[sp].count;
    if (count == 0) {
      const rt_bvh_pair_t *pr = &b->pair[ref];
      double t[2];
      pair_entry(pr, &sr, ray->tmin, ray->tmax, t);
      for (int c = 1; c >= 0; c--) /* right pushed first, so the left is visited first */
        if (t[c] != INFINITY) {
          stack[sp].ref = pr->ref[c];
          stack[sp++].count = pr->count[c];
        }
      continue;
    }
    for (int i = ref; i < ref + count; i++)
      if (!cross_prim(s, b->order[i], ray, &tr)) {
        if (blocker)
          *blocker = s->prim[b->order[i]].object;
        return tr;
      }
  }
  return tr;
}

rt_rgb_t rt_transmittance(const rt_scene_t *s, const rt_ray_t *ray) {
  return transmittance(s, ray, NULL);
}

rt_rgb_t rt_transmittance_blocker(const rt_scene_t *s, const rt_ray_t *ray, int *blocker) {
  return transmittance(s, ray, blocker);
}
