/* measure.c -- the error of Fig. 10 (paper section 5): "the distance between ray-object
 * (checkerboard) intersections obtained by the pencil tracer and by the ray tracer normalized by
 * one pixel interval on the checkerboard".
 *
 * Measured surfaces are those with a diffuse term (rt_object_measured): in Fig. 8 only the
 * checkerboard, the paper's surface; elsewhere e.g. Fig. 11's rectangle or a matte ball, so that
 * a scene without a checkerboard is not reported as error-free because nothing was compared.
 * For a sample, every measured point the pencil computed (any node of its tree on a measured
 * surface, matrix-traced or interpolated) is compared with the point of the same path in the exact
 * tracer's tree of the same ray (paths matched by their sequence of reflections/refractions):
 * error = |J+ (p_pencil - p_exact)|, the distance in pixel intervals on the surface: J is the
 * pixel footprint of that path on the surface (one pixel step along screen x and y, from the path's
 * system matrix at the domain's axial ray, pt_node_t.j), so that where the footprint is stretched
 * (a board seen at a grazing angle) a distance along the stretch counts in the stretched
 * interval. The strict variant divides |p_pencil - p_exact| by the smallest pixel interval over
 * all directions instead. The sample's error is the largest over its measured points; a
 * measured point of either tree without a counterpart in the other (the pencil missed an edge) is
 * an infinite error. A subtree the pencil traced exactly per sample starts at the pencil's hit of
 * the node it hangs from, which may be interpolated: its points (recorded in C->sub.tree) are
 * compared in the same way, in the pixel intervals of the domain's node on the same path (a subtree
 * off the domain's paths has none: there only its surfaces are compared). Samples traced exactly
 * from the eye have no error. With the image-space tolerance (pencil.h, pt_tolerance_t) a
 * point's error is divided by its node's tol_scale, so that "within rho" means within the
 * node's own tolerance; the geometric tolerance's scale is 1. */
#include <math.h>

#include "internal.h"
#include "paraxial/vec3.h"

/* The kinds of the rays from node x of tree t up to node `stop`, which is not included, deepest
 * first, into kinds[64]; their number, or -1 when `stop` is not an ancestor of x. */
static int kinds_up(const rt_tree_t *t, int x, int stop, int kinds[64]) {
  int m = 0;
  for (; x != stop; x = t->node[x].parent) {
    if (x < 0 || m == 64)
      return -1;
    kinds[m++] = t->node[x].kind;
  }
  return m;
}

/* From node `from` of tree b down the rays of kinds[m - 1], ..., kinds[0]: the node reached, or
 * -1; *last (when not NULL) = the deepest node matched, *next = the kind of the first step not
 * matched (-1 when all were). */
static int follow_down(const rt_tree_t *b, int from, const int *kinds, int m, int *last,
                       int *next) {
  int cur = from, miss = -1;
  for (int step = m - 1; step >= 0 && cur >= 0; step--) {
    int found = -1;
    for (int j = cur + 1; j < b->n && found < 0; j++)
      if (b->node[j].parent == cur && b->node[j].kind == kinds[step])
        found = j;
    if (found < 0)
      miss = kinds[step];
    else if (last)
      *last = found;
    cur = found;
  }
  if (next)
    *next = miss;
  return cur;
}

/* Follow the path of node k of tree `a` (its kinds from the root) in tree `b`. Returns the
 * matching node of b, or -1; *last = deepest node of b matched (-1 if not even the root) and
 * *next = the kind of the first step not matched. */
static int follow(const rt_tree_t *a, int k, const rt_tree_t *b, int *last, int *next) {
  int kinds[64], m = kinds_up(a, k, -1, kinds);
  *last = -1;
  *next = -1;
  if (b->n == 0 || m < 1)
    return -1;
  *last = 0; /* both roots are primary rays */
  return follow_down(b, 0, kinds, m - 1, last, next);
}

/* The recorded subtree i (C->sub.tree): its points against the exact tree X, whose node on the path
 * of the pencil node the subtree hangs from is xk (-1: none). Its measured points without a
 * counterpart on the same primitive are infinite errors; the others are measured in the pixel
 * intervals of the domain's node on the same path, when it has one. Returns the points compared. */
static int measure_sub(const pt_ctx_t *C, int i, const rt_tree_t *X, int xk, double e[3]) {
  const rt_tree_t *S = &C->sub.tree, *A = &C->trees.axial;
  int r = C->sub.root[i], end = i + 1 < C->sub.n ? C->sub.root[i + 1] : S->n, points = 0;
  for (int x = r + 1; x < end; x++) {
    const rt_tree_node_t *sn = &S->node[x];
    if (sn->object < 0 || !rt_object_measured(C->s, sn->object))
      continue;
    int kinds[64], m = kinds_up(S, x, r, kinds);
    int xx = m >= 0 && xk >= 0 ? follow_down(X, xk, kinds, m, NULL, NULL) : -1;
    int ka = m >= 0 ? follow_down(A, C->sub.from[i], kinds, m, NULL, NULL) : -1;
    double d = INFINITY, strict = INFINITY;
    if (xx >= 0 && X->node[xx].prim == sn->prim) {
      d = strict = 0.0;
      if (ka >= 0 && C->paths.node[ka].measured && C->paths.node[ka].prim == sn->prim) {
        const pt_node_t *n = &C->paths.node[ka];
        px_vec3_t v = px_v3_sub(sn->point, X->node[xx].point);
        d = pt_pixels(n, v) / n->tol_scale;
        strict = px_v3_norm(v) / n->interval / n->tol_scale;
      }
    }
    e[0] = fmax(e[0], d);
    e[2] = fmax(e[2], strict);
    if (ka >= 0 && ka == C->paths.transmit)
      e[1] = fmax(e[1], d);
    points++;
  }
  return points;
}

/* Whether exact node x lies in the part of X that recorded subtree i stands for (under the exact
 * node xk of the pencil node it hangs from, through the subtree's first ray), and then whether
 * the subtree has a node on the same path and primitive: 1 yes, 0 no, -1 not its part. */
static int sub_has(const pt_ctx_t *C, int i, const rt_tree_t *X, int xk, int x) {
  const rt_tree_t *S = &C->sub.tree;
  int r = C->sub.root[i], kinds[64], m = xk >= 0 ? kinds_up(X, x, xk, kinds) : -1;
  if (m <= 0 || r + 1 >= S->n || S->node[r + 1].parent != r || S->node[r + 1].kind != kinds[m - 1])
    return -1;
  int s = follow_down(S, r, kinds, m, NULL, NULL);
  return s >= 0 && S->node[s].prim == X->node[x].prim;
}

int pt__measure(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, double e[3]) {
  pt__trace_shape(C, &C->trees.probe, ray); /* its points are compared, not its radiance */
  const rt_tree_t *A = &C->trees.axial, *X = &C->trees.probe;
  e[0] = e[1] = e[2] = 0.0;
  int last, next, points = 0;
  /* pencil -> exact */
  for (int k = 0; k < C->paths.n; k++) {
    const pt_node_t *n = &C->paths.node[k];
    if (!n->measured || rec[k].ok != 1)
      continue;
    points++;
    int x = follow(A, k, X, &last, &next);
    double d = INFINITY, strict = INFINITY;
    if (x >= 0 && X->node[x].prim == n->prim) {
      px_vec3_t v = px_v3_sub(rec[k].p, X->node[x].point);
      d = pt_pixels(n, v) / n->tol_scale;
      strict = px_v3_norm(v) / n->interval / n->tol_scale;
    }
    e[0] = fmax(e[0], d);
    e[2] = fmax(e[2], strict);
    if (k == C->paths.transmit)
      e[1] = d;
  }
  /* the subtrees traced exactly, where the exact tree has their nodes' counterparts (a
   * recording that overflowed is not compared) */
  int nsub = C->sub.tree.overflow ? 0 : C->sub.n;
  for (int i = 0; i < nsub; i++) {
    C->sub.exact_node[i] = follow(A, C->sub.from[i], X, &last, &next);
    points += measure_sub(C, i, X, C->sub.exact_node[i], e);
  }
  /* exact -> pencil: measured points the pencil did not compute and did not trace exactly (or
   * whose subtree traced exactly has no such point) */
  for (int x = 0; x < X->n; x++) {
    if (X->node[x].object < 0 || !rt_object_measured(C->s, X->node[x].object))
      continue;
    int claimed = -1;
    for (int i = 0; i < nsub && claimed < 0; i++)
      claimed = sub_has(C, i, X, C->sub.exact_node[i], x);
    if (claimed == 0)
      e[0] = e[2] = INFINITY;
    if (claimed >= 0)
      continue;
    int k = follow(X, x, A, &last, &next), lost = 0;
    if (k >= 0)
      lost = rec[k].ok == 0 || (C->paths.node[k].prim != X->node[x].prim && rec[k].ok != 2);
    else
      lost =
          last < 0 || !(rec[last].ok == 2 || (next >= 0 && (rec[last].exact_kinds >> next) & 1u));
    if (lost)
      e[0] = e[2] = INFINITY;
  }
  return points;
}

void pt__account(pt_ctx_t *C, const double e[3], int has_points, float *slot) {
  pt_stats_t *st = &C->st;
  double rho = C->opt->rho;
  st->measured++;
  st->with_points += (uint64_t)(has_points != 0);
  st->within += (uint64_t)(e[0] <= rho);
  st->within_t += (uint64_t)(e[1] <= rho);
  st->within_strict += (uint64_t)(e[2] <= rho);
  if (isinf(e[0]))
    st->mismatches++;
  else if (e[0] > st->max_error)
    st->max_error = e[0];
  if (isfinite(e[1]) && e[1] > st->max_error_t)
    st->max_error_t = e[1];
  if (isfinite(e[2]) && e[2] > st->max_error_strict)
    st->max_error_strict = e[2];
  double bin = e[0] / PT_HIST_STEP;
  st->hist[bin < PT_HIST_BINS - 1 ? (int)bin : PT_HIST_BINS - 1]++;
  if (slot)
    *slot = (float)e[0];
}
