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
 * error = the distance in pixel intervals on the surface, in two footprints, the larger of the two:
 * (1) the domain's axial ray's, |J+ (p_pencil - p_exact)| with J the path's pixel footprint from
 * its system matrices (one pixel step along screen x and y, pt_node_t.j), so that where the
 * footprint is stretched (a board seen at a grazing angle) a distance along the stretch counts in
 * the stretched interval; PT_E_AXIAL keeps it alone, the measure of earlier versions. (2) The
 * point's own, the "one pixel interval" at the point itself: |e| over the largest extent of its
 * own footprint (local_pixels() says why not |J+ e|), J from exact rays PT_LOCAL_STEP of a
 * sample's spacing to either side along screen x and y, followed along the same path to the same
 * primitive (central differences, one-sided where a side leaves the path). Where the footprint
 * changes by orders of magnitude inside one domain (a floor seen through a glass ball near the
 * horizon the lens inverts) an error of many of a sample's own pixels can be a fraction of the
 * axial ray's one; the point's own footprint sees it. A point whose own footprint cannot be formed
 * (both sides of a direction leave the path) keeps the axial error and is counted
 * (pt_stats_t.local_unknown).
 * The strict variant divides |p_pencil - p_exact| by the smallest pixel interval over
 * all directions (of the axial footprint) instead. The sample's error is the largest over its
 * measured points; a measured point of either tree without a counterpart in the other (the
 * pencil missed an edge) is an infinite error. A subtree the pencil traced exactly per sample
 * starts at the sample's own exact hit of the node it hangs from (pt_eval_t.exact_spawn; it once
 * started at the interpolated one): its points (recorded in C->sub.tree) are compared in the same
 * way, a check of that, in the pixel intervals of the domain's node on the same path and of the
 * exact point's own (a subtree off the domain's paths has none: there only its surfaces are
 * compared; its points were all found exact, docs/journal/2026-12-06-convex-band.md). Samples
 * traced exactly from the eye have no error. With the image-space tolerance (pencil.h,
 * pt_tolerance_t) a point's error is divided by its node's tol_scale, so that "within rho" means
 * within the node's own tolerance; the geometric tolerance's scale is 1. */
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

/* The side rays of the sample at (sx, sy): PT_LOCAL_STEP of a sample's spacing to either side
 * along screen x (sides 0 and 1) and y (2 and 3), traced exactly; for every measured node x of the
 * sample's exact tree X, the side ray's point on the same path and primitive, when it has one
 * (C->trees.side_p and side_ok, side d at d * side.cap + x, for x < side.cap). */
typedef struct {
  double sx, sy, h; /* the sample, and the step in pixels */
  int traced;       /* the side rays are traced (on the first measured point) */
} sides_t;

static void trace_sides(pt_ctx_t *C, const rt_tree_t *X, sides_t *S) {
  static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  pt_trees_t *T = &C->trees;
  size_t stride = (size_t)T->side.cap;
  int n = X->n < T->side.cap ? X->n : T->side.cap;
  for (int d = 0; d < 4; d++) {
    rt_ray_t r = rt_view_ray(C->view, S->sx + dx[d] * S->h, S->sy + dy[d] * S->h, C->s->ior);
    pt__trace_shape(C, &T->side, &r);
    for (int x = 0; x < n; x++) {
      uint8_t ok = 0;
      if (X->node[x].object >= 0 && rt_object_measured(C->s, X->node[x].object)) {
        int last, next, y = follow(X, x, &T->side, &last, &next);
        if (y >= 0 && T->side.node[y].prim == X->node[x].prim) {
          T->side_p[(size_t)d * stride + (size_t)x] = T->side.node[y].point;
          ok = 1;
        }
      }
      T->side_ok[(size_t)d * stride + (size_t)x] = ok;
    }
  }
  S->traced = 1;
}

/* Error v at exact node x of X in the pixel intervals of x's own footprint: |v| / sigma_max(J),
 * J from central differences of the side rays' points (one-sided where one side left the path);
 * -1 when a direction has neither side or the footprint is degenerate. Not |J+ v|: near a fold of
 * the map from the screen to the surface (the board seen through a glass ball near its rim, in
 * Fig. 8) J is nearly of rank one, and |J+ v| counts an error of a few thousandths of a
 * checker square as thousands of pixels; |v| / sigma_max is the error in units of the pixel's
 * largest extent on the surface, which is finite there and, where the footprint is round,
 * the same as |J+ v|. */
static double local_pixels(pt_ctx_t *C, const rt_tree_t *X, int x, px_vec3_t v, sides_t *S) {
  const pt_trees_t *T = &C->trees;
  if (x >= T->side.cap) /* deeper than the side trees hold: no side rays for it */
    return -1.0;
  if (!S->traced)
    trace_sides(C, X, S);
  size_t stride = (size_t)T->side.cap;
  px_vec3_t c = X->node[x].point, j[2];
  for (int a = 0; a < 2; a++) {
    size_t ip = (size_t)(2 * a) * stride + (size_t)x, im = ip + stride;
    int p = T->side_ok[ip], m = T->side_ok[im];
    if (p && m)
      j[a] = px_v3_scale(px_v3_sub(T->side_p[ip], T->side_p[im]), 0.5 / S->h);
    else if (p || m)
      j[a] = px_v3_scale(p ? px_v3_sub(T->side_p[ip], c) : px_v3_sub(c, T->side_p[im]), 1.0 / S->h);
    else
      return -1.0;
  }
  double g00 = px_v3_dot(j[0], j[0]), g01 = px_v3_dot(j[0], j[1]), g11 = px_v3_dot(j[1], j[1]);
  double smax = sqrt(0.5 * (g00 + g11 + hypot(g00 - g11, 2.0 * g01)));
  if (!(smax > 0.0) || !isfinite(smax))
    return -1.0;
  return px_v3_norm(v) / smax;
}

/* The errors of pencil point p against exact node x of X, with the domain's node n on the same
 * path (NULL: none, only the surfaces are compared): e[PT_E_AXIAL] in n's pixel intervals, the
 * larger of that and the local one (PT_E_PIXELS), the strict one; all divided by n's tol_scale. */
static void point_errors(pt_ctx_t *C, const rt_tree_t *X, int x, const pt_node_t *n, px_vec3_t p,
                         sides_t *S, double d[PT_MEASURE_ERRORS]) {
  for (int i = 0; i < PT_MEASURE_ERRORS; i++)
    d[i] = 0.0;
  if (!n)
    return;
  px_vec3_t v = px_v3_sub(p, X->node[x].point);
  int same = v.x == 0.0 && v.y == 0.0 && v.z == 0.0; /* a point traced exactly: no side rays */
  double ax = pt_pixels(n, v) / n->tol_scale, loc = same ? 0.0 : local_pixels(C, X, x, v, S);
  if (loc < 0.0)
    C->st.local_unknown++;
  d[PT_E_AXIAL] = ax;
  d[PT_E_PIXELS] = px_max(ax, loc / n->tol_scale);
  d[PT_E_STRICT] = px_v3_norm(v) / n->interval / n->tol_scale;
}

static void take_errors(double e[PT_MEASURE_ERRORS], const double d[PT_MEASURE_ERRORS],
                        int transmit) {
  e[PT_E_PIXELS] = fmax(e[PT_E_PIXELS], d[PT_E_PIXELS]);
  e[PT_E_STRICT] = fmax(e[PT_E_STRICT], d[PT_E_STRICT]);
  e[PT_E_AXIAL] = fmax(e[PT_E_AXIAL], d[PT_E_AXIAL]);
  if (transmit)
    e[PT_E_T] = fmax(e[PT_E_T], d[PT_E_PIXELS]);
}

/* The recorded subtree i (C->sub.tree): its points against the exact tree X, whose node on the path
 * of the pencil node the subtree hangs from is xk (-1: none). Its measured points without a
 * counterpart on the same primitive are infinite errors; the others are measured in the pixel
 * intervals of the domain's node on the same path, when it has one. Returns the points compared. */
static int measure_sub(pt_ctx_t *C, int i, const rt_tree_t *X, int xk, sides_t *S,
                       double e[PT_MEASURE_ERRORS]) {
  const rt_tree_t *Sub = &C->sub.tree, *A = &C->trees.axial;
  int r = C->sub.root[i], end = i + 1 < C->sub.n ? C->sub.root[i + 1] : Sub->n, points = 0;
  for (int x = r + 1; x < end; x++) {
    const rt_tree_node_t *sn = &Sub->node[x];
    if (sn->object < 0 || !rt_object_measured(C->s, sn->object))
      continue;
    int kinds[64], m = kinds_up(Sub, x, r, kinds);
    int xx = m >= 0 && xk >= 0 ? follow_down(X, xk, kinds, m, NULL, NULL) : -1;
    int ka = m >= 0 ? follow_down(A, C->sub.from[i], kinds, m, NULL, NULL) : -1;
    double d[PT_MEASURE_ERRORS] = {INFINITY, INFINITY, INFINITY, INFINITY};
    if (xx >= 0 && X->node[xx].prim == sn->prim) {
      const pt_node_t *n =
          ka >= 0 && C->paths.node[ka].measured && C->paths.node[ka].prim == sn->prim
              ? &C->paths.node[ka]
              : NULL;
      point_errors(C, X, xx, n, sn->point, S, d);
    }
    take_errors(e, d, ka >= 0 && ka == C->paths.transmit);
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

int pt__measure(pt_ctx_t *C, const rt_ray_t *ray, double sx, double sy, const pt_geom_t *rec,
                double e[PT_MEASURE_ERRORS]) {
  pt__trace_shape(C, &C->trees.probe, ray); /* its points are compared, not its radiance */
  const rt_tree_t *A = &C->trees.axial, *X = &C->trees.probe;
  sides_t S = {sx, sy, PT_LOCAL_STEP / C->opt->spp_side, 0};
  for (int i = 0; i < PT_MEASURE_ERRORS; i++)
    e[i] = 0.0;
  int last, next, points = 0;
  /* pencil -> exact */
  for (int k = 0; k < C->paths.n; k++) {
    const pt_node_t *n = &C->paths.node[k];
    if (!n->measured || rec[k].ok != 1)
      continue;
    points++;
    int x = follow(A, k, X, &last, &next);
    double d[PT_MEASURE_ERRORS] = {INFINITY, INFINITY, INFINITY, INFINITY};
    if (x >= 0 && X->node[x].prim == n->prim)
      point_errors(C, X, x, n, rec[k].p, &S, d);
    take_errors(e, d, k == C->paths.transmit);
  }
  /* the subtrees traced exactly, where the exact tree has their nodes' counterparts (a
   * recording that overflowed is not compared) */
  int nsub = C->sub.tree.overflow ? 0 : C->sub.n;
  for (int i = 0; i < nsub; i++) {
    C->sub.exact_node[i] = follow(A, C->sub.from[i], X, &last, &next);
    points += measure_sub(C, i, X, C->sub.exact_node[i], &S, e);
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
      e[PT_E_PIXELS] = e[PT_E_STRICT] = e[PT_E_AXIAL] = INFINITY;
    if (claimed >= 0)
      continue;
    int k = follow(X, x, A, &last, &next), lost = 0;
    if (k >= 0)
      lost = rec[k].ok == 0 || (C->paths.node[k].prim != X->node[x].prim && rec[k].ok != 2);
    else
      lost =
          last < 0 || !(rec[last].ok == 2 || (next >= 0 && (rec[last].exact_kinds >> next) & 1u));
    if (lost)
      e[PT_E_PIXELS] = e[PT_E_STRICT] = e[PT_E_AXIAL] = INFINITY;
  }
  return points;
}

void pt__account(pt_ctx_t *C, const double e[PT_MEASURE_ERRORS], int has_points, float *slot) {
  pt_stats_t *st = &C->st;
  double rho = C->opt->rho;
  st->measured++;
  st->with_points += (uint64_t)(has_points != 0);
  st->within += (uint64_t)(e[PT_E_PIXELS] <= rho);
  st->within_t += (uint64_t)(e[PT_E_T] <= rho);
  st->within_strict += (uint64_t)(e[PT_E_STRICT] <= rho);
  st->within_axial += (uint64_t)(e[PT_E_AXIAL] <= rho);
  if (isinf(e[PT_E_PIXELS]))
    st->mismatches++;
  else if (e[PT_E_PIXELS] > st->max_error)
    st->max_error = e[PT_E_PIXELS];
  if (isfinite(e[PT_E_T]) && e[PT_E_T] > st->max_error_t)
    st->max_error_t = e[PT_E_T];
  if (isfinite(e[PT_E_STRICT]) && e[PT_E_STRICT] > st->max_error_strict)
    st->max_error_strict = e[PT_E_STRICT];
  if (isfinite(e[PT_E_AXIAL]) && e[PT_E_AXIAL] > st->max_error_axial)
    st->max_error_axial = e[PT_E_AXIAL];
  double bin = e[PT_E_PIXELS] / PT_HIST_STEP;
  st->hist[bin < PT_HIST_BINS - 1 ? (int)bin : PT_HIST_BINS - 1]++;
  if (slot)
    *slot = (float)e[PT_E_PIXELS];
}
