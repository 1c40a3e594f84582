/* measure.c -- the error of Fig. 10 (paper section 5): "the distance between ray-object
 * (checkerboard) intersections obtained by the pencil tracer and by the ray tracer normalized by
 * one pixel interval on the checkerboard".
 *
 * For a sample, every checkerboard point the pencil computed (any node of its tree on a textured
 * plane, matrix-traced or interpolated) is compared with the point of the same path in the exact
 * tracer's tree of the same ray (paths matched by their sequence of reflections/refractions):
 * error = |p_pencil - p_exact| / interval, where interval is one pixel interval on the board along
 * that path (pt_node_t.interval: the smaller of the two screen directions, from the path's system
 * matrix at the cell's axial ray). The sample's error is the largest over its board points; a
 * board point of either tree without a counterpart in the other (the pencil missed an edge) is an
 * infinite error. Parts of a tree the pencil traced exactly have no error. */
#include <math.h>

#include "internal.h"
#include "pvec.h"

/* Follow the path of node k of tree `a` (its kinds from the root) in tree `b`. Returns the
 * matching node of b, or -1; *last = deepest node of b matched (-1 if not even the root) and
 * *next = the kind of the first step not matched. */
static int follow(const rt_tree_t *a, int k, const rt_tree_t *b, int *last, int *next) {
  int kinds[64], m = 0;
  for (int x = k; x >= 0 && m < 64; x = a->node[x].parent)
    kinds[m++] = a->node[x].kind;
  *last = -1;
  *next = -1;
  if (b->n == 0)
    return -1;
  int cur = 0;
  *last = 0;
  for (int step = m - 2; step >= 0; step--) {
    int found = -1;
    for (int j = cur + 1; j < b->n && found < 0; j++)
      if (b->node[j].parent == cur && b->node[j].kind == kinds[step])
        found = j;
    if (found < 0) {
      *next = kinds[step];
      return -1;
    }
    cur = found;
    *last = cur;
  }
  return cur;
}

double pt__measure(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, double *err_t) {
  C->ex.tree = &C->tree2;
  rt_exact_primary(&C->ex, ray);
  C->ex.tree = NULL;
  const rt_tree_t *A = &C->tree, *X = &C->tree2;
  double err = 0.0;
  *err_t = 0.0;
  int last, next;
  /* pencil -> exact */
  for (int k = 0; k < C->nnode; k++) {
    const pt_node_t *n = &C->node[k];
    if (!n->textured || rec[k].ok != 1)
      continue;
    int e = follow(A, k, X, &last, &next);
    double d = INFINITY;
    if (e >= 0 && X->node[e].prim == n->prim)
      d = pv_norm(pv_sub(rec[k].p, X->node[e].point)) / n->interval;
    err = fmax(err, d);
    if (k == C->kt)
      *err_t = d;
  }
  /* exact -> pencil: board points the pencil did not compute and did not trace exactly */
  for (int e = 0; e < X->n; e++) {
    if (X->node[e].texel < 0)
      continue;
    int k = follow(X, e, A, &last, &next);
    if (k >= 0) {
      if (rec[k].ok == 0 || (C->node[k].prim != X->node[e].prim && rec[k].ok != 2))
        err = INFINITY;
    } else if (last < 0 || !(rec[last].ok == 2 || (next >= 0 && (rec[last].fb >> next) & 1u))) {
      err = INFINITY;
    }
  }
  return err;
}

void pt__account(pt_ctx_t *C, double err, double err_t, int has_board, float *slot) {
  pt_stats_t *st = &C->st;
  double rho = C->opt->rho;
  st->measured++;
  st->with_board += (uint64_t)(has_board != 0);
  st->within += (uint64_t)(err <= rho);
  st->within_t += (uint64_t)(err_t <= rho);
  if (isinf(err))
    st->mismatches++;
  else if (err > st->max_error)
    st->max_error = err;
  if (isfinite(err_t) && err_t > st->max_error_t)
    st->max_error_t = err_t;
  double bin = err / PT_HIST_STEP;
  st->hist[bin < PT_HIST_BINS - 1 ? (int)bin : PT_HIST_BINS - 1]++;
  if (slot)
    *slot = (float)err;
}
