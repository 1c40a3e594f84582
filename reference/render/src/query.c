/* query.c -- the scene queries of the exact tracer: the nearest hit (textbook 9.1 Intersect(r))
 * through the BVH (9.2), and the transmittance of a shadow segment through transparent
 * occluders, "k_t(1) k_t(2) ... k_t(N) I instead of I" (9.1). Nothing here allocates. */
#include <math.h>

#include "render/vec_inline.h"

#include "bvh.h"
#include "prim.h"
#include "render/intersect.h"

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
    t0 = maxd(mind(a, b), t0);
    t1 = mind(maxd(a, b), t1);
  }
  return t0 <= t1 ? t0 : INFINITY;
}

static void fill_hit(const rt_scene_t *s, const rt_ray_t *ray, int prim, double t, rt_hit_t *h) {
  h->t = t;
  h->p = v3_axpy(t, ray->d, ray->o);
  h->n = prim_normal(&s->prim[prim], h->p);
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
 * stack with their entry distance and are skipped once a nearer hit is known. */
static void traverse_nearest(const rt_scene_t *s, const rt_ray_t *ray, double *best, int *found) {
  const struct rt_bvh *b = s->bvh;
  slab_ray_t sr = slab_ray(ray);
  struct {
    int node;
    double t;
  } stack[RT_BVH_MAX_DEPTH + 1];
  int sp = 0, ni = 0;
  if (box_entry(&b->node[0], &sr, ray->tmin, *best) == INFINITY)
    return;
  for (;;) {
    const rt_bvh_node_t *nd = &b->node[ni];
    if (nd->count > 0) {
      for (int i = nd->start; i < nd->start + nd->count; i++)
        test_prim(s, b->order[i], ray, best, found);
    } else {
      int l = ni + 1, r = nd->start;
      double tl = box_entry(&b->node[l], &sr, ray->tmin, *best);
      double tr = box_entry(&b->node[r], &sr, ray->tmin, *best);
      if (tl != INFINITY && tr != INFINITY) {
        int near = tl <= tr ? l : r;
        stack[sp].node = tl <= tr ? r : l;
        stack[sp++].t = tl <= tr ? tr : tl;
        ni = near;
        continue;
      }
      if (tl != INFINITY || tr != INFINITY) {
        ni = tl != INFINITY ? l : r;
        continue;
      }
    }
    do { /* the next waiting node that may still hold a nearer hit */
      if (--sp < 0)
        return;
    } while (!(stack[sp].t < *best));
    ni = stack[sp].node;
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
  px_vec3_t p = v3_axpy(t, ray->d, ray->o);
  const rt_material_t *m = rt_scene_material_at(s, prim, p, NULL);
  if (!(m->kt > 0.0)) {
    *tr = rt_rgb(0, 0, 0);
    return 0;
  }
  const rt_prim_t *pr = &s->prim[prim];
  /* outward normal, unnormalised for a sphere: only the sign of its dot with d is needed */
  px_vec3_t out = pr->kind == RT_PRIM_SPHERE ? v3_sub(p, pr->sphere.c) : prim_normal(pr, p);
  if (s->object[pr->object].closed && v3_dot(out, ray->d) < 0.0)
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

rt_rgb_t rt_transmittance(const rt_scene_t *s, const rt_ray_t *ray) {
  rt_rgb_t tr = rt_rgb(1, 1, 1);
  for (int i = 0; i < s->nunbounded; i++)
    if (!cross_prim(s, s->unbounded[i], ray, &tr))
      return tr;
  const struct rt_bvh *b = s->bvh;
  if (!b || b->norder == 0)
    return tr;
  slab_ray_t sr = slab_ray(ray);
  int stack[RT_BVH_MAX_DEPTH + 1], sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const rt_bvh_node_t *nd = &b->node[stack[--sp]];
    if (box_entry(nd, &sr, ray->tmin, ray->tmax) == INFINITY)
      continue;
    if (nd->count == 0) {
      stack[sp++] = nd->start;
      stack[sp++] = (int)(nd - b->node) + 1;
      continue;
    }
    for (int i = nd->start; i < nd->start + nd->count; i++)
      if (!cross_prim(s, b->order[i], ray, &tr))
        return tr;
  }
  return tr;
}
