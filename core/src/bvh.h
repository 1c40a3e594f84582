/* bvh.h -- private: the bounding volume hierarchy over the bounded primitives (textbook 9.2,
 * "acceleration of intersection calculations"; here a binned surface-area-heuristic BVH). */
#ifndef RENDER_BVH_H
#define RENDER_BVH_H

#include "core/scene.h"

/* The binary tree as built: one box per node, depth-first (the left child follows its parent). */
typedef struct {
  double lo[3], hi[3]; /**< bounds of everything below */
  int start;           /**< leaf: first entry of bvh->order; interior: index of the right child
                            (the left child is the next node) */
  int count;           /**< leaf: number of primitives (> 0); interior: 0 */
} rt_bvh_node_t;

/* The same tree as traversed: each interior node holds the boxes of its two children side by
 * side, [axis][child], so that a ray tests both with one pass of 2-wide arithmetic (the same
 * operations, lane by lane, as one box at a time) and one node fetch. */
typedef struct {
  double lo[3][2], hi[3][2]; /**< bounds of the left (0) and right (1) child */
  int ref[2];                /**< leaf child: first entry of bvh->order; interior child: its
                                  index in bvh->pair */
  int count[2];              /**< leaf child: number of primitives (> 0); interior child: 0 */
} rt_bvh_pair_t;

struct rt_bvh {
  rt_bvh_node_t *node; /**< node[0] is the root: its box, and its primitives when a leaf */
  int nnode;
  rt_bvh_pair_t *pair; /**< interior nodes in traversal layout; pair[0] is the root's */
  int npair;
  int *order; /**< primitive indices, grouped by leaf */
  int norder;
};

/** Longest root-to-leaf path the traversal stack must hold. */
#define RT_BVH_MAX_DEPTH 64

/** Build over the bounded primitives of s; the planes go to *unbounded. */
rt_status_t rt_bvh_build(const rt_scene_t *s, struct rt_bvh **out, int **unbounded,
                         int *nunbounded);
void rt_bvh_free(struct rt_bvh *b);

/** The bounded primitives in the leaves of b whose boxes meet the box [lo, hi], each passed to
 *  visit() until it returns nonzero; returns that primitive, or -1 when none did (or b is NULL
 *  or empty). */
int rt_bvh_box_query(const struct rt_bvh *b, const double lo[3], const double hi[3],
                     int (*visit)(void *ctx, int prim), void *ctx);

#endif
