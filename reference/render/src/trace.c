/* trace.c -- the exact (conventional) tracer: textbook 9.1 Trace(r, d), finding surfaces by
 * intersecting every ray with the scene through the BVH, shading with shade.c, and recording
 * the ray tree when the caller asks for it (course notes 1.7.2: the ray tree). */
#include <math.h>

#include "core/intersect.h"
#include "render/render.h"

static rt_rgb_t trace_ray(xr_exact_t *ex, const rt_ray_t *ray, int depth, const rt_child_t *from);

static rt_rgb_t child_cb(void *ctx, const rt_child_t *child, int depth) {
  return trace_ray(ctx, &child->ray, depth, child);
}

/* A shadow query, textbook (transmittance) or opaque (a caustic receiver's), recorded in the tree.
 */
static inline __attribute__((always_inline)) void shadow_query(xr_exact_t *ex, rt_shadow_t *q,
                                                               int opaque) {
  ex->stats.shadow++;
  int record = ex->tree && ex->node >= 0 && q->light < 32, blocker = -1;
  if (opaque) {
    blocker = rt_shadow_occluded_by(ex->scene, q);
  } else if (record) {
    q->through = rt_transmittance_blocker(ex->scene, &q->ray, &blocker);
  } else {
    q->through = rt_transmittance(ex->scene, &q->ray);
  }
  if (record) {
    rt_tree_node_t *nd = &ex->tree->node[ex->node];
    if (q->through.r == 1.0 && q->through.g == 1.0 && q->through.b == 1.0) {
      nd->lit |= 1u << q->light;
    } else if (!(rt_rgb_max(q->through) > 0.0)) {
      nd->blocked |= 1u << q->light;
      nd->through ^= rt_blocked_hash(q->light, blocker);
    } else {
      nd->through ^= rt_through_hash(q->light, q->through);
    }
  }
}

static void shadow_cb(void *ctx, rt_shadow_t *q) {
  shadow_query(ctx, q, 0);
}

static void occluded_cb(void *ctx, rt_shadow_t *q) {
  shadow_query(ctx, q, 1);
}

static void count_cb(void *ctx, int what) {
  xr_exact_t *ex = ctx;
  if (what == RT_RAY_REFRACT)
    ex->stats.refract++;
  else if (what == RT_RAY_REFLECT)
    ex->stats.reflect++;
  else if (what == RT_RAY_SHADOW)
    ex->stats.shadow++;
  else if (what >= RT_COUNT_SPECTRAL && what < RT_COUNT_SPECTRAL + 3)
    ex->stats.spectral[what - RT_COUNT_SPECTRAL]++;
}

rt_tracer_t xr_exact_tracer(xr_exact_t *ex) {
  return (rt_tracer_t){child_cb,    shadow_cb, ex,      NULL,
                       occluded_cb, count_cb,  ex->halt}; /* every segment */
}

xr_exact_t xr_exact_make(const rt_scene_t *s, const rt_plan_t *plan, rt_tree_t *tree) {
  return (xr_exact_t){s, plan, tree, -1, {0, 0, 0, 0, {0, 0, 0}}, 0};
}

/* Append a node for `ray` (parent = the node being shaded); -1 when the buffer is full or the
 * parent was itself dropped. */
static int record(xr_exact_t *ex, const rt_ray_t *ray, int depth, const rt_child_t *from) {
  rt_tree_t *t = ex->tree;
  if ((depth > 0 && ex->node < 0) || t->n >= t->cap) {
    t->overflow = 1;
    return -1;
  }
  rt_tree_node_t *nd = &t->node[t->n];
  *nd = (rt_tree_node_t){.parent = depth > 0 ? ex->node : -1,
                         .kind = (uint8_t)(from ? from->kind : RT_RAY_PRIMARY),
                         .depth = (uint8_t)depth,
                         .flags = (uint8_t)(from && from->tir ? RT_NODE_TIR : 0),
                         .object = -1,
                         .prim = -1,
                         .texel = -1,
                         .origin = ray->o,
                         .dir = ray->d,
                         .t = INFINITY,
                         .weight = rt_rgb(1, 1, 1)};
  if (from)
    nd->weight = rt_rgb_mul(t->node[ex->node].weight, from->weight);
  return t->n++;
}

static void record_hit(xr_exact_t *ex, int node, const rt_surface_t *sf, int depth) {
  rt_tree_node_t *nd = &ex->tree->node[node];
  nd->object = sf->hit.object;
  nd->prim = sf->hit.prim;
  nd->texel = sf->texel;
  nd->t = sf->hit.t;
  nd->point = sf->hit.p;
  nd->normal = sf->nf;
  if (depth >= ex->plan->max_depth && (sf->mat->kr > 0.0 || sf->mat->kt > 0.0) &&
      ex->plan->max_depth > 0)
    nd->flags |= RT_NODE_DEPTH_LIMIT;
}

static rt_rgb_t trace_ray(xr_exact_t *ex, const rt_ray_t *ray, int depth, const rt_child_t *from) {
  if (!from)
    ex->stats.primary++;
  else if (from->kind == RT_RAY_REFRACT)
    ex->stats.refract++;
  else
    ex->stats.reflect++;
  int node = ex->tree ? record(ex, ray, depth, from) : -1;
  if (ex->halt && ex->tree && ex->tree->overflow)
    return rt_rgb(0, 0, 0);
  rt_hit_t hit;
  if (!rt_intersect(ex->scene, ray, &hit)) {
    if (node >= 0)
      ex->tree->node[node].flags |= RT_NODE_MISS;
    return ex->scene->background;
  }
  rt_surface_t sf;
  rt_shade_surface(ex->scene, &hit, ray, &sf);
  if (node >= 0)
    record_hit(ex, node, &sf, depth);
  int saved = ex->node;
  ex->node = node;
  rt_tracer_t tr = xr_exact_tracer(ex);
  rt_rgb_t c = rt_shade_hit(ex->scene, ex->plan, &sf, ray, depth, &tr);
  ex->node = saved;
  return c;
}

rt_rgb_t xr_exact_primary(xr_exact_t *ex, const rt_ray_t *ray) {
  if (ex->tree) {
    ex->tree->n = 0;
    ex->tree->overflow = 0;
  }
  ex->node = -1;
  return trace_ray(ex, ray, 0, NULL);
}
