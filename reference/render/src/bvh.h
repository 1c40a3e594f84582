/* bvh.h -- private: the bounding volume hierarchy over the bounded primitives (textbook 9.2,
 * "acceleration of intersection calculations"; here a binned surface-area-heuristic BVH). */
#ifndef RENDER_BVH_H
#define RENDER_BVH_H

#include "render/scene.h"

typedef struct {
  double lo[3], hi[3]; /**< bounds of everything below */
  int start;           /**< leaf: first entry of bvh->order; interior: index of the right child
                            (the left child is the next node) */
  int count;           /**< leaf: number of primitives (> 0); interior: 0 */
} rt_bvh_node_t;

struct rt_bvh {
  rt_bvh_node_t *node;
  int nnode;
  int *order; /**< primitive indices, grouped by leaf */
  int norder;
};

/** Longest root-to-leaf path the traversal stack must hold. */
#define RT_BVH_MAX_DEPTH 64

/** Build over the bounded primitives of s; the planes go to *unbounded. */
rt_status_t rt_bvh_build(const rt_scene_t *s, struct rt_bvh **out, int **unbounded,
                         int *nunbounded);
void rt_bvh_free(struct rt_bvh *b);

#endif
