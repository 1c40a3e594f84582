/* bvh.c -- a bounding volume hierarchy over the scene's bounded primitives, built with a binned
 * surface-area heuristic (textbook 9.2: the ray query need not test every object; a hierarchy
 * gives O(log n) typical cost, so 1,000 polygons cost little more per ray than a few spheres).
 * Unbounded planes are kept aside and tested after the traversal. */
#include "bvh.h"

#include <math.h>
#include <stdlib.h>

#include "core/intersect.h"

#define LEAF_MAX 4 /* leaves never need more; below this the SAH is not consulted */
#define NBIN 16

typedef struct {
  double lo[3], hi[3];
} box_t;

typedef struct {
  const rt_scene_t *s;
  struct rt_bvh *b;
  box_t *pb;       /* bounds of each entry of b->order */
  double (*ct)[3]; /* centroids */
} build_t;

static box_t box_empty(void) {
  return (box_t){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
}

static void box_grow(box_t *a, const box_t *b) {
  for (int k = 0; k < 3; k++) {
    a->lo[k] = fmin(a->lo[k], b->lo[k]);
    a->hi[k] = fmax(a->hi[k], b->hi[k]);
  }
}

static double box_area(const box_t *a) {
  double d[3];
  for (int k = 0; k < 3; k++)
    d[k] = a->hi[k] > a->lo[k] ? a->hi[k] - a->lo[k] : 0.0;
  return 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

static void swap_entries(build_t *B, int i, int j) {
  int o = B->b->order[i];
  B->b->order[i] = B->b->order[j];
  B->b->order[j] = o;
  box_t t = B->pb[i];
  B->pb[i] = B->pb[j];
  B->pb[j] = t;
  for (int k = 0; k < 3; k++) {
    double c = B->ct[i][k];
    B->ct[i][k] = B->ct[j][k];
    B->ct[j][k] = c;
  }
}

static int bin_of(double c, double lo, double scale) {
  int k = (int)((c - lo) * scale);
  return k < 0 ? 0 : (k >= NBIN ? NBIN - 1 : k);
}

/* Best SAH split of [start, end) along `axis`: returns the first bin of the right side (1..NBIN-1)
 * or 0 when no split beats a leaf. */
static int sah_split(build_t *B, int start, int end, int axis, double clo, double scale,
                     double parent_area) {
  box_t bb[NBIN];
  int cnt[NBIN] = {0};
  for (int k = 0; k < NBIN; k++)
    bb[k] = box_empty();
  for (int i = start; i < end; i++) {
    int k = bin_of(B->ct[i][axis], clo, scale);
    cnt[k]++;
    box_grow(&bb[k], &B->pb[i]);
  }
  double left_area[NBIN], best = (double)(end - start); /* cost of a leaf, in intersection tests */
  int left_cnt[NBIN], n = 0, split = 0;
  box_t acc = box_empty();
  for (int k = 0; k < NBIN - 1; k++) {
    box_grow(&acc, &bb[k]);
    n += cnt[k];
    left_area[k] = box_area(&acc);
    left_cnt[k] = n;
  }
  acc = box_empty();
  n = 0;
  for (int k = NBIN - 1; k >= 1; k--) {
    box_grow(&acc, &bb[k]);
    n += cnt[k];
    /* traversal cost 1 per node visit; children hit with probability area ratio */
    double cost = 1.0 + (left_area[k - 1] * left_cnt[k - 1] + box_area(&acc) * n) / parent_area;
    if (left_cnt[k - 1] > 0 && n > 0 && cost < best) {
      best = cost;
      split = k;
    }
  }
  return split;
}

static int build_node(build_t *B, int start, int end, int depth) {
  struct rt_bvh *b = B->b;
  int me = b->nnode++;
  rt_bvh_node_t *nd = &b->node[me];
  box_t bounds = box_empty(), cb = box_empty();
  for (int i = start; i < end; i++) {
    box_grow(&bounds, &B->pb[i]);
    box_t c = {{B->ct[i][0], B->ct[i][1], B->ct[i][2]}, {B->ct[i][0], B->ct[i][1], B->ct[i][2]}};
    box_grow(&cb, &c);
  }
  for (int k = 0; k < 3; k++) {
    nd->lo[k] = bounds.lo[k];
    nd->hi[k] = bounds.hi[k];
  }
  int axis = 0;
  for (int k = 1; k < 3; k++)
    if (cb.hi[k] - cb.lo[k] > cb.hi[axis] - cb.lo[axis])
      axis = k;
  double extent = cb.hi[axis] - cb.lo[axis];
  int split = 0;
  if (end - start > LEAF_MAX && extent > 0.0 && depth < RT_BVH_MAX_DEPTH - 1)
    split = sah_split(B, start, end, axis, cb.lo[axis], NBIN / extent, box_area(&bounds));
  if (split == 0) {
    nd->start = start;
    nd->count = end - start;
    return me;
  }
  int mid = start;
  for (int i = start; i < end; i++)
    if (bin_of(B->ct[i][axis], cb.lo[axis], NBIN / extent) < split)
      swap_entries(B, i, mid++);
  build_node(B, start, mid, depth + 1);
  int right = build_node(B, mid, end, depth + 1);
  nd = &b->node[me]; /* (the array does not move, but keep the pointer honest) */
  nd->start = right;
  nd->count = 0;
  return me;
}

/* Copy interior node `ni` of the built tree into pair[] (depth-first, left before right) and
 * return its index there. */
static int make_pairs(struct rt_bvh *b, int ni) {
  const rt_bvh_node_t *nd = &b->node[ni];
  int me = b->npair++;
  const int child[2] = {ni + 1, nd->start};
  for (int c = 0; c < 2; c++) {
    const rt_bvh_node_t *ch = &b->node[child[c]];
    for (int k = 0; k < 3; k++) {
      b->pair[me].lo[k][c] = ch->lo[k];
      b->pair[me].hi[k][c] = ch->hi[k];
    }
    b->pair[me].count[c] = ch->count;
    b->pair[me].ref[c] = ch->count > 0 ? ch->start : make_pairs(b, child[c]);
  }
  return me;
}

void rt_bvh_free(struct rt_bvh *b) {
  if (!b)
    return;
  free(b->node);
  free(b->pair);
  free(b->order);
  free(b);
}

static rt_status_t collect(build_t *B, int **unbounded, int *nunbounded) {
  const rt_scene_t *s = B->s;
  int nb = 0, nu = 0;
  for (int i = 0; i < s->nprim; i++) {
    px_vec3_t lo, hi;
    if (rt_prim_bounds(s, i, &lo, &hi)) {
      B->b->order[nb] = i;
      B->pb[nb] = (box_t){{lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z}};
      for (int k = 0; k < 3; k++)
        B->ct[nb][k] = 0.5 * (B->pb[nb].lo[k] + B->pb[nb].hi[k]);
      nb++;
    } else {
      (*unbounded)[nu++] = i;
    }
  }
  B->b->norder = nb;
  *nunbounded = nu;
  return RT_OK;
}

rt_status_t rt_bvh_build(const rt_scene_t *s, struct rt_bvh **out, int **unbounded,
                         int *nunbounded) {
  size_t n = (size_t)(s->nprim > 0 ? s->nprim : 1);
  build_t B = {s, calloc(1, sizeof(struct rt_bvh)), malloc(n * sizeof(box_t)),
               malloc(n * sizeof(double[3]))};
  *unbounded = malloc(n * sizeof(int));
  if (B.b) {
    B.b->node = malloc((2 * n) * sizeof(rt_bvh_node_t));
    B.b->pair = malloc(n * sizeof(rt_bvh_pair_t)); /* n leaves at most: n - 1 interior nodes */
    B.b->order = malloc(n * sizeof(int));
  }
  rt_status_t st = RT_ENOMEM;
  if (B.b && B.b->node && B.b->pair && B.b->order && B.pb && B.ct && *unbounded) {
    collect(&B, unbounded, nunbounded);
    if (B.b->norder > 0)
      build_node(&B, 0, B.b->norder, 0);
    if (B.b->nnode > 0 && B.b->node[0].count == 0)
      make_pairs(B.b, 0);
    st = RT_OK;
  }
  free(B.pb);
  free(B.ct);
  if (st != RT_OK) {
    rt_bvh_free(B.b);
    free(*unbounded);
    *unbounded = NULL;
    return st;
  }
  *out = B.b;
  return RT_OK;
}

int rt_bvh_box_query(const struct rt_bvh *b, const double lo[3], const double hi[3],
                     int (*visit)(void *ctx, int prim), void *ctx) {
  if (!b || b->nnode == 0)
    return -1;
  int stack[2 * RT_BVH_MAX_DEPTH + 2], sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const rt_bvh_node_t *nd = &b->node[stack[--sp]];
    if (!(lo[0] <= nd->hi[0] && hi[0] >= nd->lo[0] && lo[1] <= nd->hi[1] && hi[1] >= nd->lo[1] &&
          lo[2] <= nd->hi[2] && hi[2] >= nd->lo[2]))
      continue;
    if (nd->count == 0) {
      stack[sp++] = nd->start;
      stack[sp++] = (int)(nd - b->node) + 1;
      continue;
    }
    for (int i = nd->start; i < nd->start + nd->count; i++)
      if (visit(ctx, b->order[i]))
        return b->order[i];
  }
  return -1;
}
