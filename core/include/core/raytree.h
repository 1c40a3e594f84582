/* raytree.h -- the ray tree of one image sample (textbook 9.1: "the family of rays corresponding
 * to a pixel forms a binary tree"; course notes 1.7.2, the ray-tree node list).
 *
 * A caller that wants ray trees hands the tracer an rt_tree_t over its own node array; with
 * NULL the tracer records nothing and pays one predictable branch per ray. The pencil renderer
 * compares the trees of neighbouring samples to find the edges between pencil domains: two
 * samples belong to the same domain when their trees have the same shape, the same surfaces
 * (object and primitive), the same checker squares and the same light visibility.
 */
#ifndef RENDER_RAYTREE_H
#define RENDER_RAYTREE_H

#include <stdint.h>

#include "core/types.h"

/** Node flags. */
enum {
  RT_NODE_MISS = 1u << 0,       /**< the ray met nothing (background) */
  RT_NODE_TIR = 1u << 1,        /**< a reflection carrying refracted weight after total
                                     internal reflection */
  RT_NODE_DEPTH_LIMIT = 1u << 2 /**< children were due but the depth limit stopped them */
};

/** One ray of the tree, in depth-first order (a child follows its parent). */
typedef struct {
  int32_t parent;   /**< index of the parent node, -1 for the primary ray */
  uint8_t kind;     /**< rt_ray_kind_t: PRIMARY, REFLECT or REFRACT */
  uint8_t depth;    /**< generation: 0 for the primary ray */
  uint8_t flags;    /**< RT_NODE_* */
  int32_t object;   /**< object met, -1 on a miss */
  int32_t prim;     /**< primitive met, -1 on a miss */
  int32_t texel;    /**< checker square parity at the hit, -1 without texture */
  uint32_t lit;     /**< bit l: light l (l < 32) reaches the point unattenuated */
  uint32_t blocked; /**< bit l: light l is fully blocked; neither bit: partly (through glass)
                         or the surface faces away from it */
  uint32_t through; /**< the lights reached partly, with their transmittances, and the lights
                         blocked, with what blocks them: rt_through_hash()es and
                         rt_blocked_hash()es combined by exclusive or; 0 for none */
  px_vec3_t origin; /**< ray origin */
  px_vec3_t dir;    /**< unit direction */
  double t;         /**< distance to the hit (INFINITY on a miss) */
  px_vec3_t point;  /**< hit point */
  px_vec3_t normal; /**< normal at the hit facing the ray */
  rt_rgb_t weight;  /**< product of coefficients from the eye to this ray */
} rt_tree_node_t;

/** A caller-owned node buffer. */
typedef struct {
  rt_tree_node_t *node; /**< cap nodes, owned by the caller */
  int cap;
  int n;        /**< nodes recorded for the current sample */
  int overflow; /**< 1 when nodes were dropped because the buffer was full */
} rt_tree_t;

/** Wrap a buffer of `cap` nodes (rt_plan_t.tree_nodes always suffices). */
static inline rt_tree_t rt_tree_make(rt_tree_node_t *buf, int cap) {
  return (rt_tree_t){buf, cap, 0, 0};
}

/** A hash of light l reached partly with transmittance t, for rt_tree_node_t.through: two points
 *  that see a light through glass see it alike only when the transmittance is the same (through
 *  one ball or through two, kt T or (kt T)^2), which the lit and blocked bits do not tell. */
static inline uint32_t rt_through_hash(int l, rt_rgb_t t) {
  uint64_t h = 0x9E3779B97F4A7C15ULL * (uint64_t)(l + 1);
  const double c[3] = {t.r, t.g, t.b};
  for (int i = 0; i < 3; i++) {
    uint64_t b;
    __builtin_memcpy(&b, &c[i], sizeof b);
    h = (h ^ b) * 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
  }
  return (uint32_t)(h ^ (h >> 32));
}

/** A hash of light l blocked by object `object`, for rt_tree_node_t.through: two points in
 *  shadow see the light alike only when the same object blocks it. Between the shadows of two
 *  objects a lit gap may run that no traced point sees, however wide the objects are. */
static inline uint32_t rt_blocked_hash(int l, int object) {
  uint64_t h = 0xC2B2AE3D27D4EB4FULL * (uint64_t)(l + 1) ^ (uint64_t)(uint32_t)object;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return (uint32_t)h | 1u; /* never 0: 0 is "none" */
}

/** Follow the path that starts at the primary ray and at every node continues with its child
 *  of kind `prefer` if it has one, else with its other child; return the index of the first
 *  node on it that met a textured surface (texel >= 0, e.g. the checkerboard), or -1. The
 *  node's depth is the number of reflections/refractions before it. Used for the auxiliary
 *  EXR channels that locate where a pixel's paths meet the checkerboard. */
int rt_tree_follow(const rt_tree_t *t, rt_ray_kind_t prefer);

/** 1 when two trees have the same shape, surfaces, checker squares and light visibility. */
int rt_tree_same(const rt_tree_t *a, const rt_tree_t *b);

#endif
