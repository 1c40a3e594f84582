/* interp.c -- ray interpolation (paper section 4.1 (2)) inside an accepted cell: "the
 * intersection point and the direction of an interior paraxial ray are linearly interpolated",
 * with the error estimated by "evaluating first and second order interpolations" using one more
 * ray, and "if linearity is assumed for brightness I(x'), the brightness can also be
 * interpolated".
 *
 * The cell is covered by a quadtree of lattice cells (quads). The root quad is the whole cell:
 * its corners, edge midpoints and centre (a 3 x 3 grid) are traced through the cell's paths
 * (lattice points). A quad whose grid was traced is *measured*: the deviation of each midpoint
 * from the linear interpolation of its edge's ends, and of the centre from the bilinear
 * interpolation of the corners, is the interpolation error itself at those points, and for a
 * second-order map the largest over the quad (the error of bilinear interpolation is
 * A u (1 - u) + B v (1 - v), largest at a midpoint or the centre). A quad that fails is cut into
 * four; each quarter is first judged by the paper's e_int, the second difference along its
 * edges with the third point the parent's grid line beyond it (free: those points are traced),
 * and only when that fails are its own five interior points traced and the quarter measured.
 * Certified mode accepts measured quads only. A quad is accepted when, for every node reached,
 * the interpolation error plus the matrix error at its corners is within rho pixels and the
 * brightness interpolated over it (the sum of its linear nodes) deviates from the traced
 * brightness by at most the brightness tolerance.
 *
 * The samples of an accepted quad are interpolated bilinearly from its four corners, per node:
 * hit point and direction, and the brightness W_k direct_k where it is linear (the same checker
 * square at the four corners, every light's visibility agreeing over the cell; a textured leaf
 * whose square changes across the quad takes the brightness of the sample's square's material).
 * Other nodes (a shadow edge, subtrees traced exactly) are shaded per sample at their
 * interpolated hits, except a faint node, whose whole brightness is within a share of the
 * tolerance and is interpolated across its shadow edge (faint_bound). When nothing is shaded
 * per sample and every sample of a pixel lies in one checker square on each textured leaf, the
 * pixel's sum over its samples is the bilinear form with the summed weights: the same sum,
 * computed without visiting each sample. A quad too small to be worth cutting (fewer samples
 * than the points a cut would trace) sends its samples through the matrices. */
#include <assert.h>
#include <math.h>
#include <string.h>

#include "internal.h"
#include "pencil/edge.h"
#include "render/vec_inline.h"

/* A traced lattice point. */
typedef struct {
  const pt_geom_t *g; /* node array (cap entries) */
  double xi2;         /* |xi|^2 of the point's primary ray in the cell frame */
  int ok;             /* traced without leaving the cell's paths */
} point_t;

/* A quad [x0, x0 + w) x [y0, y0 + h) of continuous pixel coordinates. Its corners are always
 * traced; `measured`: the grid g (corners, edge midpoints, centre) is its own; otherwise its
 * error is estimated from its parent's grid pg, of which it is the quarter (qx, qy). */
typedef struct {
  double x0, y0, w, h;
  point_t g[3][3]; /* [row][column] */
  int measured;
  const point_t (*pg)[3];
  int qx, qy;
} lquad_t;

/* How a quad's samples are interpolated. */
typedef struct {
  rt_rgb_t smooth[4]; /* brightness of the linear nodes summed at the four corners */
  int n;              /* nodes shaded per sample */
  int *k;
  uint8_t *direct, *exact; /* per entry: its direct term, its exactly traced children */
  int nt;                  /* textured leaves whose square changes across the quad: the sample's */
  int *kt;                 /* square picks the interpolated brightness of its material */
  int nown;                /* nodes too curved to interpolate over the quad: traced per sample
                              by their matrices (or along their paths), C->own */
  int nq2;                 /* nodes whose hits are interpolated biquadratically, C->q2 */
  int nfaint;              /* nodes interpolated across a shadow edge (faint_bound) */
  double own_cost;         /* node evaluations per sample: own nodes, nodes shaded per sample,
                              subtrees traced exactly (about 2 rays each) */
  int halve;               /* on failure: 1 (2) when halving the quad across its columns (rows)
                              makes every node's hits interpolable (halve_dir) */
} plan_t;

/* The share of rho an estimated quad's e_int may use. e_int extrapolates the second-order
 * behaviour of the parent's grid onto the quarter; where the map's third-order term matters it
 * underestimates. Measured on Fig. 8 (256 x 256, 9 spp): accepting estimates up to rho leaves
 * 99.91% of the samples within rho (largest 0.86); up to rho / 2, 99.996% (largest 0.54), for
 * 20% more lattice points at 49 spp (docs/pencil.md). */
#define PT_EINT_MARGIN 0.5

/* Biquadratic interpolation of a node's hits over a measured quarter q of a measured quad P,
 * when bilinear interpolation is not accurate enough: P's biquadratic (through its 3 x 3 grid)
 * predicts q's five new grid points, and its deviation there, d, is P's second-order
 * interpolation error measured at those points. q's own biquadratic has half P's side, so where
 * the third-order term dominates its error is about d / 8; it is accepted when
 * PT_BIQUAD_FACTOR d + matrix error <= rho (a margin of 4 over d / 8). Certified mode accepts
 * measured errors only: there the quarter is interpolated by P's biquadratic itself, whose error
 * d was measured at the quarter's five new points (as a measured quad's bilinear error is at its
 * midpoints and centre), when PT_BIQUAD_CERT d + matrix error <= rho (with certified mode's
 * margin in rho; PT_BIQUAD_CERT 1.5 leaves the largest measured error of the 49-spp Fig. 8
 * render unchanged at 0.41, 1.0 let it rise to 0.48). */
#define PT_BIQUAD_FACTOR 0.5
/* Certified mode: a measured quad's bilinear interpolation error over the whole quad, from the
 * deviations d_i it measured at the five grid points other than the corners (grid_error: their
 * largest). A second-order map's error is largest at those points, but the biquadratic through
 * the nine points also has u^2 v, u v^2 and u^2 v^2 terms. Its difference from the bilinear
 * interpolation is sum_i d_i L_i(u, v), with L_i the biquadratic Lagrange basis of point i, and
 * max over the quad of sum_i |L_i| is 1.3843 (at u = 0.325, v = 0.68 and its mirror images), so
 * the error can reach 1.38 times the largest measured deviation. Found when the measure came to
 * count every diffuse surface: on scenes/balls.json (4 spp) the matte ball seen through the glass
 * ball at depth 3 had a 2.5-pixel quad with deviations up to 0.311 and samples at (0.7, 0.7)
 * off by 0.549, so 3 samples were over rho. With the factor none are. A node that fails only
 * because of the factor gets the sum itself at the quad's own samples
 * (bilinear_bound_at_samples), which is all the guarantee is about: Fig. 8 at 49 spp costs
 * 2.206e9 instructions instead of 2.162e9 (+2.0%; the factor alone 2.227e9), its largest error
 * 0.392 instead of 0.409. PT_BIQUAD_CERT (below) is above this factor, so the biquadratic
 * interpolation's error over a quarter, measured at the same five points, is covered the same
 * way. */
#ifndef PT_BILINEAR_CERT
#define PT_BILINEAR_CERT 1.3843
#endif
#ifndef PT_BIQUAD_CERT
#define PT_BIQUAD_CERT 1.5
#endif

/* Lagrange basis of the nodes 0, 1/2, 1 at t. */
static void lagrange3(double t, double L[3]) {
  L[0] = 2.0 * (t - 0.5) * (t - 1.0);
  L[1] = -4.0 * t * (t - 1.0);
  L[2] = 2.0 * t * (t - 0.5);
}

/* Biquadratic weights at quad coordinates (u, v) for a row-major 3 x 3 grid. */
static void weights9(double u, double v, double w[9]) {
  double lu[3], lv[3];
  lagrange3(u, lu);
  lagrange3(v, lv);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      w[3 * r + c] = lv[r] * lu[c];
}

/* The largest deviation, in pixel intervals of node n, of the biquadratic through the parent's
 * grid q->pg from the measured quarter q's five new grid points; INFINITY when a point of
 * either grid did not reach node k along the cell's paths. */
static double biquad_deviation(const lquad_t *q, const pt_node_t *n, int k) {
  static const int at[5][2] = {{0, 1}, {1, 0}, {1, 1}, {1, 2}, {2, 1}};
  double d = 0.0;
  /* every point of both grids must have met the node through the cell's paths (a parent can
   * have been cut because some of its points did not: their entries are not this node's) */
  for (int i = 0; i < 9; i++)
    if (!q->pg[i / 3][i % 3].ok || q->pg[i / 3][i % 3].g[k].ok != 1 || !q->g[i / 3][i % 3].ok ||
        q->g[i / 3][i % 3].g[k].ok != 1)
      return INFINITY;
  for (int m = 0; m < 5; m++) {
    double w[9];
    weights9(0.5 * q->qx + 0.25 * at[m][1], 0.5 * q->qy + 0.25 * at[m][0], w);
    px_vec3_t b = {0, 0, 0};
    for (int i = 0; i < 9; i++)
      b = v3_axpy(w[i], q->pg[i / 3][i % 3].g[k].p, b);
    d = pt_max(d, pt_pixels(n, v3_sub(q->g[at[m][0]][at[m][1]].g[k].p, b)));
  }
  return d;
}

/* Why a quad's samples went to the matrices (pt_stats_t.matrix_samples). */
enum { WHY_OFF = 0, WHY_LEFT = 1, WHY_REACH = 2, WHY_ERROR = 3 };

/* Corner c (0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1)) of quad q. */
static const point_t *corner_of(const lquad_t *q, int c) {
  int col = c & 1, row = c >> 1;
  if (q->measured)
    return &q->g[2 * row][2 * col];
  return &q->pg[q->qy + row][q->qx + col];
}

/* The 3 x 3 grid the quad's error comes from: its own, or its parent's. */
static const point_t (*grid_of(const lquad_t *q))[3] {
  return q->measured ? (const point_t(*)[3])q->g : q->pg;
}

/* A 3 x 3 grid of vectors or colours, for one node or a brightness sum. */
typedef struct {
  px_vec3_t v[3][3];
} grid3_t;

/* The deviations of a 3 x 3 grid's five non-corner points from the bilinear interpolation of
 * its corners, measured by `norm`: top, bottom, left, right edge midpoints, centre. */
static void grid_deviations(const grid3_t *G, double (*norm)(const void *, px_vec3_t),
                            const void *ctx, double d[5]) {
  const px_vec3_t(*v)[3] = G->v;
  for (int r = 0; r < 3; r += 2) /* top and bottom edges; left and right edges */
    d[r / 2] = norm(ctx, v3_sub(v[r][1], v3_scale(v3_add(v[r][0], v[r][2]), 0.5)));
  for (int c = 0; c < 3; c += 2)
    d[2 + c / 2] = norm(ctx, v3_sub(v[1][c], v3_scale(v3_add(v[0][c], v[2][c]), 0.5)));
  px_vec3_t m = v3_scale(v3_add(v3_add(v[0][0], v[0][2]), v3_add(v[2][0], v[2][2])), 0.25);
  d[4] = norm(ctx, v3_sub(v[1][1], m));
}

/* Interpolation error of a quad from its grid values G, as a vector measured by `norm`:
 *   measured: the largest deviation of an edge midpoint from the mean of its edge's ends, or of
 *             the centre from the mean of the corners (the bilinear interpolation there);
 *   estimated (quarter (qx, qy) of G): e_int, |x_a - 2 x_b + x_c| / 8 along each of the
 *             quarter's two horizontal grid lines (the larger) plus the same vertically. */
static double grid_error(const lquad_t *q, const grid3_t *G,
                         double (*norm)(const void *, px_vec3_t), const void *ctx) {
  const px_vec3_t(*v)[3] = G->v;
  if (q->measured) {
    double d[5];
    grid_deviations(G, norm, ctx, d);
    return pt_max(pt_max(pt_max(d[0], d[1]), pt_max(d[2], d[3])), d[4]);
  }
  double ex = 0.0, ey = 0.0;
  for (int e = 0; e < 2; e++) {
    int r = q->qy + e, c = q->qx + e;
    ex = pt_max(ex, norm(ctx, v3_add(v3_sub(v[r][0], v3_scale(v[r][1], 2.0)), v[r][2])));
    ey = pt_max(ey, norm(ctx, v3_add(v3_sub(v[0][c], v3_scale(v[1][c], 2.0)), v[2][c])));
  }
  return (ex + ey) / 8.0;
}

static double norm_pixels(const void *node, px_vec3_t e) {
  return pt_pixels(node, e);
}

static void sample_range(double x0, double w, int s, int *g0, int *g1);

/* Certified mode, a measured quad q whose largest deviation times PT_BILINEAR_CERT is too much:
 * the biquadratic part of its bilinear error at its own samples, sum_i |d_i| |L_i(u, v)| over
 * the five non-corner grid points (d_i in node n's pixel intervals), largest over the samples.
 * The basis is separable: L_i(u, v) = l_c(u) l_r(v) for grid column c and row r. */
static double bilinear_bound_at_samples(const pt_ctx_t *C, const lquad_t *q, const grid3_t *G,
                                        const pt_node_t *n) {
  double d[5];
  grid_deviations(G, norm_pixels, n, d);
  double dt = d[0], db = d[1], dl = d[2], dr = d[3], dc = d[4];
  int s = C->opt->spp_side, gx0, gx1, gy0, gy1;
  sample_range(q->x0, q->w, s, &gx0, &gx1);
  sample_range(q->y0, q->h, s, &gy0, &gy1);
  double worst = 0.0;
  for (int gy = gy0; gy < gy1; gy++) {
    double lv[3];
    lagrange3(((gy + 0.5) / s - q->y0) / q->h, lv);
    double row = dt * fabs(lv[0]) + db * fabs(lv[2]) + dc * fabs(lv[1]), col = fabs(lv[1]);
    for (int gx = gx0; gx < gx1; gx++) {
      double lu[3];
      lagrange3(((gx + 0.5) / s - q->x0) / q->w, lu);
      worst = pt_max(worst, fabs(lu[1]) * row + col * (dl * fabs(lu[0]) + dr * fabs(lu[2])));
    }
  }
  return worst;
}

static double norm_rgb(const void *unused, px_vec3_t e) {
  (void)unused;
  return pt_max(fabs(e.x), pt_max(fabs(e.y), fabs(e.z)));
}

static px_vec3_t rgb_vec(rt_rgb_t c) {
  return (px_vec3_t){c.r, c.g, c.b};
}

/* Whether node k's shadow rays found the same lights unblocked and the same fully blocked at
 * the nine points of grid R. */
static int same_visibility(const point_t (*R)[3], int k) {
  const pt_geom_t *b = &R[0][0].g[k];
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      if (R[r][c].g[k].lit != b->lit || R[r][c].g[k].dark != b->dark)
        return 0;
  return 1;
}

static int own_pays(const pt_ctx_t *C, const lquad_t *q, const plan_t *pl, int can_cut);

/* The small-object guard on the shadows of node k over a quad's grid R, for the lights whose
 * cell-level guard fired (pt_node_t.light_guard): the grid's points agreeing on a light's
 * visibility do not show that it is the same between them when an object smaller than the
 * pencil of their shadow rays comes near it (its whole shadow could fall between the points).
 * The pencil: the ball about the grid's centre hit through the farthest of its points; the gap:
 * the largest disc that can lie between the points; both grown by half again (cell.c's
 * PT_GUARD_INFLATE). Cutting the quad shrinks them until the guard no longer fires; else the
 * node's direct term is shaded per sample. */
static int shadow_guarded(const pt_ctx_t *C, const point_t (*R)[3], int k) {
  const pt_node_t *n = &C->node[k];
  px_vec3_t c = R[1][1].g[k].p;
  double r = 0.0, h = 0.0; /* reach from the centre; longest side between neighbouring points */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const px_vec3_t p = R[i][j].g[k].p;
      r = fmax(r, v3_norm(v3_sub(p, c)));
      if (j < 2)
        h = fmax(h, v3_norm(v3_sub(R[i][j + 1].g[k].p, p)));
      if (i < 2)
        h = fmax(h, v3_norm(v3_sub(R[i + 1][j].g[k].p, p)));
    }
  /* a disc free of the nine points lies within a grid square: radius at most h / sqrt 2; both
   * grown by half again for the map's curvature between the points */
  r *= 1.5;
  h *= 1.5 / sqrt(2.0);
  const px_vec3_t *plane = C->s->prim[n->prim].kind == RT_PRIM_PLANE ? &n->n : NULL;
  for (int l = 0; l < C->s->nlight && l < 32; l++)
    if ((n->light_guard & (1u << l)) &&
        pt_guard_shadow(C->guard, C->nguard, c, r, h, plane, &C->s->light[l], n->object))
      return 1;
  return 0;
}

/* Share of the brightness tolerance that faint nodes (below) may take together. */
#define PT_FAINT_SHARE 0.5

/* A bound on node k's brightness W_k direct_k over quad q, whatever hides the lights from part
 * of it. rt_shade_direct() adds to the ambient term ka Ia color, for each light, at most
 * I_l (kd color + ks): the cosine, the transmittance and the Phong factor are at most 1, and
 * lights have no fall-off. W_k is taken at its largest over the grid plus its interpolation
 * error there (its largest between the points). Such a node's brightness at a sample, and its
 * bilinear interpolation from the quad's corners, both lie between 0 and this bound: a node
 * faint enough (a board seen after several internal reflections in the glass ball, W_k about
 * 5e-4) may be interpolated across a shadow edge, its error counted against the brightness
 * tolerance, instead of being shaded per sample with a shadow ray. */
static double faint_bound(const pt_ctx_t *C, const lquad_t *q, const point_t (*R)[3], int k) {
  const rt_scene_t *s = C->s;
  const pt_node_t *n = &C->node[k];
  const rt_object_t *o = &s->object[n->object];
  grid3_t w;
  double wmax = 0.0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      w.v[r][c] = rgb_vec(R[r][c].g[k].w);
      wmax = pt_max(wmax, norm_rgb(NULL, w.v[r][c]));
    }
  wmax += grid_error(q, &w, norm_rgb, NULL);
  int spec = rt_plan_has(C->plan, RT_EFFECT_SPECULAR);
  double dmax = 0.0;
  for (int m = 0; m < (n->textured ? 2 : 1); m++) {
    const rt_material_t *mt = &s->material[m ? o->material2 : o->material];
    double d = mt->ka * norm_rgb(NULL, rgb_vec(rt_rgb_mul(s->ambient, mt->color)));
    for (int l = 0; l < s->nlight; l++)
      d += norm_rgb(NULL, rgb_vec(s->light[l].intensity)) *
           (mt->kd * norm_rgb(NULL, rgb_vec(mt->color)) + (spec ? mt->ks : 0.0));
    dmax = pt_max(dmax, d);
  }
  return wmax * dmax;
}

/* With a Fresnel split (C->vary_w) a node's weight W_k varies over the quad, and a node shaded
 * per sample takes the bilinear interpolation of the corners' W_k: its error is W_k's own
 * interpolation error times the node's unweighted brightness (direct_k, both materials of a
 * checkerboard; a miss node's background), at most. Without it W_k is constant over a quad
 * whose points reached the same nodes, and this is 0. (The children a node traces exactly per
 * sample take that W_k too; their error is not counted.) */
static double weight_error(const pt_ctx_t *C, const lquad_t *q, const point_t (*R)[3], int k) {
  if (!C->vary_w)
    return 0.0;
  grid3_t w;
  double dmax = 0.0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      const pt_geom_t *g = &R[r][c].g[k];
      w.v[r][c] = rgb_vec(g->w);
      const double wc[3] = {g->w.r, g->w.g, g->w.b};
      const rt_rgb_t *ls[3] = {&g->l, &g->lt[0], &g->lt[1]};
      for (int i = 0; i < (C->node[k].textured ? 3 : 1); i++) {
        const double lc[3] = {ls[i]->r, ls[i]->g, ls[i]->b};
        for (int ch = 0; ch < 3; ch++)
          if (wc[ch] > 0.0)
            dmax = pt_max(dmax, fabs(lc[ch]) / wc[ch]);
      }
    }
  return grid_error(q, &w, norm_rgb, NULL) * dmax;
}

/* How many of a grid's nine points reached node k, and how many of those traced it exactly. */
static void reach(const point_t (*R)[3], int k, int *reached, int *exact) {
  *reached = *exact = 0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      *reached += R[r][c].g[k].ok != 0;
      *exact += R[r][c].g[k].ok == 2;
    }
}

/* Node k's hit points at a grid's nine points. */
static void hits_of(const point_t (*R)[3], int k, grid3_t *p) {
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      p->v[r][c] = R[r][c].g[k].p;
}

/* A node's matrix error at a point with |xi|^2 = xi2 (the worst corner's), in pixel intervals
 * on its surface: C |xi|^2 / |cos| (Eq. 4), or the certified check's; 0 for a path traced
 * exactly. */
static double matrix_error(const pt_node_t *n, double xi2) {
  return n->pencil == PT_NODE_PATH ? 0.0
                                   : pt_max(n->c * xi2 / n->cos_in, n->e_check) / n->interval;
}

/* Certified mode: whether halving measured quad q, across its columns (1: left and right
 * halves) or its rows (2: top and bottom), would make every node's hits interpolable; 0 when
 * neither would. A quad whose nodes are too curved to interpolate is cut into quarters, and in
 * certified mode every quarter is measured: up to 16 new points. A half takes 3. Most such
 * quads in Fig. 8 are curved in one direction (the board seen through the glass ball is
 * compressed vertically): a bilinear interpolation's error is A u(1-u) + B v(1-v), the top and
 * bottom edge midpoints measure A / 4 and the left and right ones B / 4, so halving across the
 * columns leaves about A / 16 + B / 4 at the halves' centres (across the rows A / 4 + B / 16).
 * The halves are measured, so their plans test their own errors. In default mode quarters are
 * first estimated from the parent's grid (e_int) at no cost, and halving did not pay there
 * (docs/pencil.md, "Tenth pass"). */
static int halve_dir(const pt_ctx_t *C, const lquad_t *q, double rho, double xi2) {
  const point_t(*R)[3] = grid_of(q);
  const uint8_t *xsub = C->xsub;
  double f = C->opt->certified ? PT_BILINEAR_CERT : 1.0;
  int okx = 1, oky = 1;
  double ex = 0.0, ey = 0.0;
  for (int k = 0; k < C->nnode && (okx || oky); k++) {
    const pt_node_t *n = &C->node[k];
    if (xsub[k] || n->miss)
      continue;
    int reached, exact;
    reach(R, k, &reached, &exact);
    if (reached == 0 || exact == 9)
      continue;
    if (reached != 9 || exact != 0)
      return 0;
    grid3_t p;
    hits_of(R, k, &p);
    double e_mat = matrix_error(n, xi2);
    double d[5];
    grid_deviations(&p, norm_pixels, n, d);
    double eu = pt_max(d[0], d[1]), ev = pt_max(d[2], d[3]);
    double hx = f * (eu / 4.0 + ev) + e_mat, hy = f * (eu + ev / 4.0) + e_mat;
    okx = okx && hx <= rho;
    oky = oky && hy <= rho;
    ex = pt_max(ex, hx);
    ey = pt_max(ey, hy);
  }
  if (okx && oky)
    return ex <= ey ? 1 : 2;
  return okx ? 1 : oky ? 2 : 0;
}

/* Whether quad q may be interpolated, and how (see the file comment); on failure *why says
 * what failed. It stops as soon as the per-sample work exceeds what own_pays() allows (the
 * caller cuts such a quad, when it can be cut). */
static int make_plan(pt_ctx_t *C, const lquad_t *q, plan_t *pl, int can_cut, int *why) {
  const point_t(*R)[3] = grid_of(q);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      if (!R[r][c].ok) {
        *why = WHY_LEFT;
        return 0;
      }
  int cert = C->opt->certified;
  double rho =
      C->opt->rho * (cert ? PT_CERTIFIED_MARGIN : 1.0) * (q->measured ? 1.0 : PT_EINT_MARGIN);
  double ltol = C->opt->brightness_tol * (cert ? PT_CERTIFIED_MARGIN : 1.0);
  double xi2 = 0.0;
  for (int i = 0; i < 4; i++)
    xi2 = pt_max(xi2, corner_of(q, i)->xi2);
  grid3_t sm, t0, t1; /* brightness of the linear nodes; of the textured leaves per material */
  memset(&sm, 0, sizeof sm);
  t0 = t1 = sm;
  pl->n = pl->nt = pl->nown = pl->nq2 = pl->nfaint = pl->halve = 0;
  pl->own_cost = 0.0;
  for (int i = 0; i < 4; i++)
    pl->smooth[i] = rt_rgb(0, 0, 0);
  memset(C->own, 0, (size_t)C->nnode);
  memset(C->q2, 0, (size_t)C->nnode);
  memset(C->faint, 0, (size_t)C->nnode);
  /* a verify node (below an edge the corners saw) that some grid point did not confirm is traced
   * exactly per sample in this quad, with its subtree */
  uint8_t *xsub = C->xsub;
  int *sml = C->lsm, nsm = 0; /* the linear nodes summed in sm */
  double faint = 0.0;         /* the faint nodes' bounds, summed */
  double werr = 0.0;          /* the weight errors of the nodes shaded per sample, summed */
  for (int k = 0; k < C->nnode; k++) {
    const pt_node_t *n = &C->node[k];
    xsub[k] = n->parent >= 0 && xsub[n->parent];
    for (int r = 0; r < 3 && n->verify && !xsub[k]; r++)
      for (int c = 0; c < 3; c++)
        xsub[k] |= R[r][c].g[k].ok != 1;
  }
  for (int k = 0; k < C->nnode; k++) {
    int reached, exact;
    if (xsub[k])
      continue;
    reach(R, k, &reached, &exact);
    if (reached == 0 || exact == 9)
      continue; /* not reached, or traced exactly per sample through its parent */
    if (reached != 9 || exact != 0) {
      *why = WHY_REACH;
      return 0;
    }
    const pt_node_t *n = &C->node[k];
    int smooth = 1, exact_children = 0, leaf_texture = 0, own = 0, is_faint = 0;
    if (!n->miss) {
      grid3_t p;
      hits_of(R, k, &p);
      double e_mat = matrix_error(n, xi2);
      /* too curved to interpolate here: this node is traced per sample (the caller decides
       * whether that is cheaper than cutting the quad) */
      double eg = grid_error(q, &p, norm_pixels, n);
      own = !((cert ? PT_BILINEAR_CERT : 1.0) * eg + e_mat <= rho); /* NaN: own */
      if (own && cert && q->measured && eg + e_mat <= rho) /* the bound at the samples */
        own = !(bilinear_bound_at_samples(C, q, &p, n) + e_mat <= rho);
      /* or biquadratic over a measured quarter (textured nodes: leaves only, whose square is
       * then found per sample) */
      /* (certified: the parent's biquadratic itself, over this quarter, where its deviation
       * from the quarter's five new points - its measured error - is within the margin) */
      int q2 =
          own && q->measured && q->pg && (!n->textured || n->child[0] < 0) &&
          (cert ? PT_BIQUAD_CERT : PT_BIQUAD_FACTOR) * biquad_deviation(q, n, k) + e_mat <= rho;
      if (q2) {
        own = 0;
        C->q2[k] = 1;
        pl->nq2++;
      }
      if (own) { /* cost per sample: a matrix product, or the path traced from the eye */
        C->own[k] = 1;
        pl->nown++;
        pl->own_cost += n->pencil == PT_NODE_PATH ? 1.0 + n->depth : 1.0;
        if (!own_pays(C, q, pl, can_cut)) { /* the caller would cut the quad */
          *why = WHY_ERROR;
          if (cert && q->measured)
            pl->halve = halve_dir(C, q, rho, xi2);
          return 0;
        }
      }
      /* a textured node interpolated biquadratically: its points may leave the corners' convex
       * hull, so its square is found per sample */
      int squares = !(n->textured && C->q2[k]);
      if (n->textured)
        for (int i = 1; i < 4; i++) {
          const pt_geom_t *a = &corner_of(q, i)->g[k], *b = &corner_of(q, 0)->g[k];
          squares = squares && a->su == b->su && a->sv == b->sv;
        }
      /* every light's visibility agrees at the cell's centre and corners, or at least at the
       * nine points of the grid (then the brightness test below checks the shading between);
       * not where the small-object guard saw a shadow that may fall between them */
      smooth = !own && (n->light_agree == ~0u || same_visibility(R, k)) &&
               !(n->light_guard && shadow_guarded(C, R, k));
      /* a shadow edge on a faint node: interpolated, its bound counted against the tolerance
       * (a textured node whose square changes over the quad only as a leaf, as below) */
      if (!own && !smooth && (squares || n->child[0] < 0)) {
        double b = faint_bound(C, q, R, k);
        if (faint + b <= PT_FAINT_SHARE * ltol) {
          faint += b;
          smooth = is_faint = 1;
          C->faint[k] = 1;
          pl->nfaint++;
        }
      }
      for (int c = 0; c < 2; c++)
        exact_children |=
            n->child[c] >= 0 && (C->node[n->child[c]].pencil == PT_NODE_EXACT || xsub[n->child[c]]);
      if (smooth && !squares && !own) {
        /* the direct term is linear for each material: the sample's square picks one. Children
         * would be weighted by the material too, so only for leaves */
        if (n->child[0] >= 0) {
          *why = WHY_ERROR;
          return 0;
        }
        assert(n->textured); /* only a checkerboard has squares to pick per sample */
        pl->kt[pl->nt++] = k;
        smooth = 0;
        leaf_texture = 1;
        for (int r = 0; r < 3 && !is_faint; r++) /* a faint leaf's error is its bound */
          for (int c = 0; c < 3; c++) {
            t0.v[r][c] = v3_add(t0.v[r][c], rgb_vec(R[r][c].g[k].lt[0]));
            t1.v[r][c] = v3_add(t1.v[r][c], rgb_vec(R[r][c].g[k].lt[1]));
          }
      }
    }
    if (smooth && !is_faint) { /* the test below: a faint node's error is its bound */
      sml[nsm++] = k;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
          sm.v[r][c] = v3_add(sm.v[r][c], rgb_vec(R[r][c].g[k].l));
    }
    if (smooth) {
      for (int i = 0; i < 4; i++)
        pl->smooth[i] = rt_rgb_add(pl->smooth[i], corner_of(q, i)->g[k].l);
    }
    if (leaf_texture && !exact_children)
      continue;
    if (!smooth || exact_children) {
      if (!smooth && !own && !leaf_texture)
        pl->own_cost += 1.0; /* shaded per sample (a shadow edge) */
      if (exact_children)
        for (int c = 0; c < 2; c++)
          pl->own_cost += n->child[c] >= 0 && xsub[n->child[c]] ? 2.0 : 0.0;
      if (!own_pays(C, q, pl, can_cut)) { /* the caller would cut the quad */
        *why = WHY_ERROR;
        return 0;
      }
      pl->k[pl->n] = k;
      pl->direct[pl->n] = (uint8_t)(!smooth && !leaf_texture);
      pl->exact[pl->n++] = (uint8_t)exact_children;
      if (!smooth && !leaf_texture)
        werr += weight_error(C, q, R, k);
    }
  }
  /* brightness: is it linear over the quad? */
  double el = grid_error(q, &sm, norm_rgb, NULL);
  if (pl->nt)
    el += pt_max(grid_error(q, &t0, norm_rgb, NULL), grid_error(q, &t1, norm_rgb, NULL));
  while (!(el + faint + werr <= ltol)) { /* (a NaN error is never accepted) */
    /* not linear: the node whose own brightness is least linear is shaded per sample at its
     * interpolated hit (as at a shadow edge), while the rest is interpolated; the caller
     * weighs that per-sample work against cutting the quad (own_pays) */
    int best = -1, best_leaf = 0;
    double eb = 0.0;
    for (int m = 0; m < nsm; m++) {
      grid3_t b;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
          b.v[r][c] = rgb_vec(R[r][c].g[sml[m]].l);
      double e = grid_error(q, &b, norm_rgb, NULL);
      if (e > eb)
        eb = e, best = m, best_leaf = 0;
    }
    for (int m = 0; m < pl->nt; m++) {
      grid3_t b0, b1;
      if (C->faint[pl->kt[m]])
        continue;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
          b0.v[r][c] = rgb_vec(R[r][c].g[pl->kt[m]].lt[0]);
          b1.v[r][c] = rgb_vec(R[r][c].g[pl->kt[m]].lt[1]);
        }
      double e = pt_max(grid_error(q, &b0, norm_rgb, NULL), grid_error(q, &b1, norm_rgb, NULL));
      if (e > eb)
        eb = e, best = m, best_leaf = 1;
    }
    if (best < 0) {
      *why = WHY_ERROR;
      return 0;
    }
    int k = best_leaf ? pl->kt[best] : sml[best];
    if (best_leaf) {
      pl->kt[best] = pl->kt[--pl->nt];
    } else {
      sml[best] = sml[--nsm];
      for (int i = 0; i < 4; i++)
        pl->smooth[i] = rt_rgb_add(pl->smooth[i], rt_rgb_scale(corner_of(q, i)->g[k].l, -1.0));
    }
    int m = 0;
    while (m < pl->n && pl->k[m] != k)
      m++;
    if (m == pl->n) {
      pl->k[pl->n] = k;
      pl->exact[pl->n++] = 0;
    }
    pl->direct[m] = 1;
    pl->own_cost += 1.0;
    werr += weight_error(C, q, R, k);
    if (!own_pays(C, q, pl, can_cut)) { /* the caller would cut the quad */
      *why = WHY_ERROR;
      return 0;
    }
    /* the remaining sums */
    memset(&sm, 0, sizeof sm);
    t0 = t1 = sm;
    for (int j = 0; j < nsm; j++)
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
          sm.v[r][c] = v3_add(sm.v[r][c], rgb_vec(R[r][c].g[sml[j]].l));
    for (int j = 0; j < pl->nt; j++)
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
          t0.v[r][c] = v3_add(t0.v[r][c], rgb_vec(R[r][c].g[pl->kt[j]].lt[0]));
          t1.v[r][c] = v3_add(t1.v[r][c], rgb_vec(R[r][c].g[pl->kt[j]].lt[1]));
        }
    el = grid_error(q, &sm, norm_rgb, NULL);
    if (pl->nt)
      el += pt_max(grid_error(q, &t0, norm_rgb, NULL), grid_error(q, &t1, norm_rgb, NULL));
  }
  return 1;
}

static void weights(double u, double v, double w[4]) {
  w[0] = (1 - u) * (1 - v);
  w[1] = u * (1 - v);
  w[2] = (1 - u) * v;
  w[3] = u * v;
}

static rt_rgb_t rgb_lerp4(const double w[4], rt_rgb_t a, rt_rgb_t b, rt_rgb_t c, rt_rgb_t d) {
  return rt_rgb(w[0] * a.r + w[1] * b.r + w[2] * c.r + w[3] * d.r,
                w[0] * a.g + w[1] * b.g + w[2] * c.g + w[3] * d.g,
                w[0] * a.b + w[1] * b.b + w[2] * c.b + w[3] * d.b);
}

/* Parity of the checker square of textured leaf k at the interpolation with weights w. */
static int leaf_parity(const pt_eval_t *E, int k, const double w[4]) {
  const pt_geom_t *g0 = &E->g[0][k], *g1 = &E->g[1][k], *g2 = &E->g[2][k], *g3 = &E->g[3][k];
  px_vec3_t p =
      v3_axpy(w[0], g0->p, v3_axpy(w[1], g1->p, v3_axpy(w[2], g2->p, v3_scale(g3->p, w[3]))));
  if (E->q2 && E->q2[k]) { /* biquadratic (E->w9) */
    p = (px_vec3_t){0, 0, 0};
    for (int i = 0; i < 9; i++)
      p = v3_axpy(E->w9[i], E->g9[i][k].p, p);
  }
  const rt_plane_t *pl0 = &E->C->s->prim[E->C->node[k].prim].plane;
  double u, v;
  rt_plane_coords(pl0, p, &u, &v);
  return (int)fmod(fabs(floor(u * pl0->inv_check) + floor(v * pl0->inv_check)), 2.0);
}

/* The nodes of an interpolated sample with weights w that are shaded per sample. */
static rt_rgb_t interp_local(pt_eval_t *E, const plan_t *pl, const double w[4]) {
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  E->w = w;
  for (int m = 0; m < pl->n; m++) {
    int k = pl->k[m];
    rt_rgb_t wk = rgb_lerp4(w, E->g[0][k].w, E->g[1][k].w, E->g[2][k].w, E->g[3][k].w);
    sum = rt_rgb_add(sum, pt__eval_local(E, k, wk, pl->direct[m], pl->exact[m]));
  }
  return sum;
}

/* One interpolated sample with weights w (E->g holds the quad's corners). */
static rt_rgb_t interp_sample(pt_eval_t *E, const plan_t *pl, const double w[4]) {
  const rt_rgb_t *c = pl->smooth;
  E->w = w;
  rt_rgb_t sum = rgb_lerp4(w, c[0], c[1], c[2], c[3]);
  for (int m = 0; m < pl->nt; m++) { /* textured leaves: the material of the sample's square */
    int k = pl->kt[m], par = leaf_parity(E, k, w);
    sum = rt_rgb_add(sum, rgb_lerp4(w, E->g[0][k].lt[par], E->g[1][k].lt[par], E->g[2][k].lt[par],
                                    E->g[3][k].lt[par]));
  }
  return rt_rgb_add(sum, interp_local(E, pl, w));
}

/* Whether node k is a miss whose ray an interpolated sample takes from the quad's corners E->g:
 * computed by the pencil at all four (ok == 1) and not in a subtree traced exactly per sample
 * (C->xsub). Only then are the corners' rays defined: a node a lattice point did not reach
 * keeps whatever its storage held before. */
static int interpolated_miss(const pt_ctx_t *C, const pt_eval_t *E, int k) {
  if (!C->node[k].miss || (E->xsub && E->xsub[k]))
    return 0;
  for (int i = 0; i < 4; i++)
    if (E->g[i][k].ok != 1)
      return 0;
  return 1;
}

/* Certified mode: whether every miss node of an interpolated sample still meets no unbounded
 * plane (its ray interpolated from the quad's corners): a horizon can cross a quad between its
 * corners. Bounded objects were checked by intersecting the rays of the lattice points with the
 * scene (eval.c); between those points they are not. */
static int misses_nothing(const pt_ctx_t *C, const pt_eval_t *E, const double w[4]) {
  const rt_scene_t *s = C->s;
  for (int k = 0; k < C->nnode; k++) {
    const pt_geom_t *a = &E->g[0][k], *b = &E->g[1][k], *c = &E->g[2][k], *e = &E->g[3][k];
    if (!interpolated_miss(C, E, k))
      continue;
    px_vec3_t o =
        v3_axpy(w[0], a->p, v3_axpy(w[1], b->p, v3_axpy(w[2], c->p, v3_scale(e->p, w[3]))));
    px_vec3_t d =
        v3_axpy(w[0], a->d, v3_axpy(w[1], b->d, v3_axpy(w[2], c->d, v3_scale(e->d, w[3]))));
    for (int u = 0; u < s->nunbounded; u++) {
      const rt_prim_t *pr = &s->prim[s->unbounded[u]];
      if (pr->kind != RT_PRIM_PLANE)
        continue;
      double side = v3_dot(pr->plane.n, v3_sub(o, pr->plane.p)), towards = v3_dot(pr->plane.n, d);
      if (side * towards < 0.0)
        return 0; /* heads for the plane from its side: it would meet it */
    }
  }
  return 1;
}

/* Certified mode: whether misses_nothing() holds for every sample of the quad whose corners are
 * E->g. side and towards are bilinear in the sample's weights (the ray's origin and its
 * unnormalised direction are interpolated), so they take their extremes at the corners: when the
 * corners agree in sign (with a margin for rounding), so do all the samples. */
static int misses_nothing_quad(const pt_ctx_t *C, const pt_eval_t *E) {
  const rt_scene_t *s = C->s;
  for (int k = 0; k < C->nnode; k++) {
    if (!interpolated_miss(C, E, k))
      continue;
    for (int u = 0; u < s->nunbounded; u++) {
      const rt_prim_t *pr = &s->prim[s->unbounded[u]];
      if (pr->kind != RT_PRIM_PLANE)
        continue;
      int pos = 1, neg = 1;
      for (int i = 0; i < 4; i++) {
        const pt_geom_t *g = &E->g[i][k];
        px_vec3_t r = v3_sub(g->p, pr->plane.p);
        double side = v3_dot(pr->plane.n, r), towards = v3_dot(pr->plane.n, g->d);
        double eps = 1e-9 * (1.0 + v3_norm(g->p) + v3_norm(pr->plane.p));
        pos = pos && side > eps && towards >= 0.0;
        neg = neg && side < -eps && towards <= 0.0;
      }
      if (!pos && !neg)
        return 0;
    }
  }
  return 1;
}

/* Slot of position (x, y) in the memo's hash table: its own, or the empty one where it would go. */
static int memo_slot(const pt_lmemo_t *M, double x, double y) {
  uint64_t a, b;
  memcpy(&a, &x, sizeof a);
  memcpy(&b, &y, sizeof b);
  uint64_t h = (a ^ (b * 0x9E3779B97F4A7C15ull)) * 0xBF58476D1CE4E5B9ull;
  int mask = M->nslot - 1, i = (int)((h >> 32) & (uint64_t)mask);
  for (;; i = (i + 1) & mask) { /* never full: nslot >= 2 cap */
    if (M->gen[i] != M->now)
      return i;
    const double *p = &M->xy[2 * M->slot[i]];
    if (p[0] == x && p[1] == y)
      return i;
  }
}

/* The lattice point at (x, y) traced through the paths: the cell's memo holds it when a
 * neighbouring quad traced it already (the evaluation depends on nothing but the position and the
 * cell's paths, so it is the same point); otherwise it is traced into the memo, or into g (cap
 * nodes) when the memo is full. record_shadow: the point is the cell's axial ray, whose evaluation
 * also records the cell's shadow transmittances (pt__record_shadows). */
static point_t trace_point(pt_ctx_t *C, double x, double y, pt_geom_t *g, int record_shadow) {
  pt_lmemo_t *M = &C->memo;
  int s = memo_slot(M, x, y);
  if (M->gen[s] == M->now && C->opt->memo) {
    int i = M->slot[s];
    C->st.lattice_reused++;
    return (point_t){M->g + (size_t)i * (size_t)M->stride, M->xi2[i], M->ok[i]};
  }
  int i = M->n < M->cap ? M->n++ : -1;
  if (i >= 0)
    g = M->g + (size_t)i * (size_t)M->stride;
  pt_eval_t E = {.C = C,
                 .mode = PT_EV_MATRIX,
                 .shade = 1,
                 .rec = g,
                 .lattice = 1,
                 .record_shadow = record_shadow};
  pt__xi_of(C, &E, x, y);
  pt__eval(&E);
  C->st.lattice_points++;
  point_t pt = {g, E.xi[0] * E.xi[0] + E.xi[1] * E.xi[1], !E.fallback};
  if (i >= 0) {
    M->xy[2 * i] = x;
    M->xy[2 * i + 1] = y;
    M->xi2[i] = pt.xi2;
    M->ok[i] = (uint8_t)pt.ok;
    M->slot[s] = i;
    M->gen[s] = M->now;
  }
  return pt;
}

/* Start the memo for a new cell (its points depend on the cell's paths) whose trees have nnode
 * nodes: a point's records are stored contiguously, nnode of them, so that the grids make_plan()
 * reads are compact (with the tree's capacity as the stride, a point of the 13-node Fig. 8 tree
 * took 21 KB for 2 KB of records). */
static void memo_reset(pt_lmemo_t *M, int nnode) {
  M->n = 0;
  M->stride = nnode > 0 ? nnode : 1;
  size_t room = M->entries / (size_t)M->stride;
  M->cap = room < (size_t)M->maxpts ? (int)room : M->maxpts;
  if (++M->now == 0) { /* wrapped: old generations could look current */
    memset(M->gen, 0, (size_t)M->nslot * sizeof *M->gen);
    M->now = 1;
  }
}

/* The cell being interpolated: its pixels' accumulators. */
typedef struct {
  int x0, y0, x1, y1;
  pixel_t *acc;
} cellacc_t;

static pixel_t *pixel_at(const cellacc_t *A, int i, int j) {
  return &A->acc[(j - A->y0) * (A->x1 - A->x0) + (i - A->x0)];
}

/* Samples of the grid (global sample indices g = i s + a, at (g + 0.5) / s) in [x0, x0 + w). */
static void sample_range(double x0, double w, int s, int *g0, int *g1) {
  *g0 = (int)ceil(x0 * s - 0.5);
  *g1 = (int)ceil((x0 + w) * s - 0.5);
}

/* Textured leaves whose square changes across a quad handled by the fast path at most. */
#define PT_FAST_LEAVES 8

/* What the samples of one accepted quad share. */
typedef struct {
  const lquad_t *q;
  const plan_t *pl;
  pt_eval_t E;                       /* INTERP evaluation with the quad's corners */
  int safe;                          /* certified: misses_nothing() holds for every sample */
  int fast;                          /* the linear nodes and textured leaves are summed per pixel
                                        (sums of weights); nodes in pl->k are added per sample */
  double uv[PT_FAST_LEAVES][9][2];   /* fast: board coordinates / check of each leaf's corners
                                        (bilinear), or of the quad's 3 x 3 grid (biquadratic) */
  uint8_t q2leaf[PT_FAST_LEAVES];    /* fast: the leaf is interpolated biquadratically */
  double curv[PT_FAST_LEAVES][2][2]; /* ... bounds on |d2/du2| and |d2/dv2| of its board
                                        coordinates over the grid, per coordinate */
  double s9, o9[2];                  /* biquadratic: grid coordinates of quad coordinates (u, v) are
                                        o9 + s9 (u, v) (the quad's own grid, or certified its parent's) */
  double off[RT_MAX_SPP_SIDE];       /* (a + 0.5) / s: a sample's offset in its pixel */
  double inv_w, inv_h;               /* 1 / the quad's width and height: the samples' quad
                                        coordinates by multiplications, not divisions per sample */
} qctx_t;

/* Quad coordinates of sample column a (row b) of the pixel at column i (row j). */
static inline double quad_u(const qctx_t *Q, int i, int a) {
  return (i + Q->off[a] - Q->q->x0) * Q->inv_w;
}
static inline double quad_v(const qctx_t *Q, int j, int b) {
  return (j + Q->off[b] - Q->q->y0) * Q->inv_h;
}

/* Biquadratic weights of the plan's grid at quad coordinates (u, v). */
static void qweights9(const qctx_t *Q, double u, double v, double w[9]) {
  weights9(Q->o9[0] + Q->s9 * u, Q->o9[1] + Q->s9 * v, w);
}

static void qctx_make(pt_ctx_t *C, const lquad_t *q, const plan_t *pl, qctx_t *Q) {
  Q->q = q;
  Q->pl = pl;
  int s = C->opt->spp_side;
  for (int a = 0; a < s; a++)
    Q->off[a] = (a + 0.5) / s;
  Q->inv_w = 1.0 / q->w;
  Q->inv_h = 1.0 / q->h;
  Q->E = (pt_eval_t){
      .C = C, .mode = PT_EV_INTERP, .shade = 1, .xsub = C->xsub, .own = pl->nown ? C->own : NULL};
  Q->E.exact_spawn = pt__spawns_exact(&Q->E);
  for (int i = 0; i < 4; i++)
    Q->E.g[i] = corner_of(q, i)->g;
  Q->s9 = 1.0;
  Q->o9[0] = Q->o9[1] = 0.0;
  if (pl->nq2) { /* measured quarters only: the quad's own grid, certified its parent's */
    int par = C->opt->certified;
    Q->E.q2 = C->q2;
    for (int i = 0; i < 9; i++)
      Q->E.g9[i] = par ? q->pg[i / 3][i % 3].g : q->g[i / 3][i % 3].g;
    if (par) {
      Q->s9 = 0.5;
      Q->o9[0] = 0.5 * q->qx;
      Q->o9[1] = 0.5 * q->qy;
    }
  }
  Q->fast = pl->nt <= PT_FAST_LEAVES;
  Q->safe = !C->opt->certified || misses_nothing_quad(C, &Q->E);
  for (int m = 0; m < pl->nt && Q->fast; m++) {
    int k = pl->kt[m], q2 = pl->nq2 && C->q2[k];
    const rt_plane_t *bp = &C->s->prim[C->node[k].prim].plane;
    Q->q2leaf[m] = (uint8_t)q2;
    for (int i = 0; i < (q2 ? 9 : 4); i++) {
      px_vec3_t p = q2 ? Q->E.g9[i][k].p : Q->E.g[i][k].p;
      rt_plane_coords(bp, p, &Q->uv[m][i][0], &Q->uv[m][i][1]);
      Q->uv[m][i][0] *= bp->inv_check;
      Q->uv[m][i][1] *= bp->inv_check;
    }
    for (int t = 0; t < 2 && q2; t++) { /* second differences of the grid; 1.25 bounds the sum
                                           of |Lagrange weights| of three nodes on [0, 1] */
      double cu = 0.0, cv = 0.0;
      const double(*g)[2] = Q->uv[m];
      for (int r = 0; r < 3; r++) {
        cu = pt_max(cu, fabs(4.0 * (g[3 * r][t] - 2.0 * g[3 * r + 1][t] + g[3 * r + 2][t])));
        cv = pt_max(cv, fabs(4.0 * (g[r][t] - 2.0 * g[3 + r][t] + g[6 + r][t])));
      }
      Q->curv[m][t][0] = 1.25 * cu;
      Q->curv[m][t][1] = 1.25 * cv;
    }
  }
}

/* floor(x), by truncation where that is exact (|x| < 2^52, the usual case: board coordinates in
 * checker squares). Called per sample in pixels that straddle a square edge: 3.5% of the 49-spp
 * Fig. 8 render's instructions went to this line with libm's floor. */
static inline double floor_fast(double x) {
  if (!(fabs(x) < 4503599627370496.0))
    return floor(x);
  double t = (double)(int64_t)x;
  return t > x ? t - 1.0 : t;
}

/* Checker parity of leaf m of the fast path at quad coordinates (u, v) (the board coordinates
 * are affine in the hit point, so interpolating them is interpolating the point). */
static int fast_parity(const qctx_t *Q, int m, double u, double v, double sq[2]) {
  const double(*c)[2] = Q->uv[m];
  if (Q->q2leaf[m]) {
    double w[9];
    qweights9(Q, u, v, w);
    for (int t = 0; t < 2; t++) {
      double x = 0.0;
      for (int i = 0; i < 9; i++)
        x += w[i] * c[i][t];
      sq[t] = floor_fast(x);
    }
  } else {
    double w[4];
    weights(u, v, w);
    for (int t = 0; t < 2; t++)
      sq[t] = floor_fast(w[0] * c[0][t] + w[1] * c[1][t] + w[2] * c[2][t] + w[3] * c[3][t]);
  }
  return (int)((int64_t)(sq[0] + sq[1]) & 1);
}

/* The summed part (linear nodes and textured leaves) of one sample with weights w, as fast_sum
 * counts it. */
static rt_rgb_t fast_sample(const qctx_t *Q, double u, double v) {
  const plan_t *pl = Q->pl;
  double w[4];
  weights(u, v, w);
  rt_rgb_t sum = rgb_lerp4(w, pl->smooth[0], pl->smooth[1], pl->smooth[2], pl->smooth[3]);
  for (int m = 0; m < pl->nt; m++) {
    const pt_geom_t *g0 = &Q->E.g[0][pl->kt[m]], *g1 = &Q->E.g[1][pl->kt[m]],
                    *g2 = &Q->E.g[2][pl->kt[m]], *g3 = &Q->E.g[3][pl->kt[m]];
    double sq[2];
    int p = fast_parity(Q, m, u, v, sq);
    sum = rt_rgb_add(sum, rgb_lerp4(w, g0->lt[p], g1->lt[p], g2->lt[p], g3->lt[p]));
  }
  return sum;
}

/* Fast path: pixel P's samples a in [a0, a1), b in [b0, b1). The sum of the bilinear
 * interpolations is the bilinear form with the summed weights, and the weights are separable;
 * a textured leaf adds the brightness of each sample's material, so its weights are summed per
 * material - per sample only when its square is not one over the samples (the interpolated
 * board point is bilinear in the sample position, so its square is one when it is one at the
 * four extreme samples: squares are convex). */
static rt_rgb_t fast_sum(const qctx_t *Q, const pixel_t *P, int a0, int a1, int b0, int b1) {
  const plan_t *pl = Q->pl;
  double su = 0.0, sv = 0.0, na = a1 - a0, nb = b1 - b0;
  for (int a = a0; a < a1; a++)
    su += quad_u(Q, P->i, a);
  for (int b = b0; b < b1; b++)
    sv += quad_v(Q, P->j, b);
  const double W[4] = {(na - su) * (nb - sv), su * (nb - sv), (na - su) * sv, su * sv};
  rt_rgb_t sum = rgb_lerp4(W, pl->smooth[0], pl->smooth[1], pl->smooth[2], pl->smooth[3]);
  double ua = quad_u(Q, P->i, a0), ub = quad_u(Q, P->i, a1 - 1);
  double va = quad_v(Q, P->j, b0), vb = quad_v(Q, P->j, b1 - 1);
  for (int m = 0; m < pl->nt; m++) {
    const pt_geom_t *g0 = &Q->E.g[0][pl->kt[m]], *g1 = &Q->E.g[1][pl->kt[m]],
                    *g2 = &Q->E.g[2][pl->kt[m]], *g3 = &Q->E.g[3][pl->kt[m]];
    double sq[2], sq0[2];
    const double ue[4] = {ua, ub, ua, ub}, ve[4] = {va, va, vb, vb};
    int par = fast_parity(Q, m, ua, va, sq0), one = 1;
    for (int e = 1; e < 4 && one; e++) {
      fast_parity(Q, m, ue[e], ve[e], sq);
      one = sq[0] == sq0[0] && sq[1] == sq0[1];
    }
    if (one && Q->q2leaf[m]) {
      /* a biquadratic leaf's points are not convex combinations of the extreme samples': they
       * deviate from the bilinear interpolation of those by at most (du^2 |f_uu| + dv^2
       * |f_vv|) / 8, so the extreme samples must keep that far from their square's edges */
      for (int t = 0; t < 2 && one; t++) {
        double du = Q->s9 * (ub - ua), dv = Q->s9 * (vb - va);
        double margin = (du * du * Q->curv[m][t][0] + dv * dv * Q->curv[m][t][1]) / 8.0;
        for (int e = 0; e < 4 && one; e++) {
          const double(*c)[2] = Q->uv[m];
          double w[9], x = 0.0;
          qweights9(Q, ue[e], ve[e], w);
          for (int i = 0; i < 9; i++)
            x += w[i] * c[i][t];
          one = x - sq0[t] >= margin && sq0[t] + 1.0 - x >= margin;
        }
      }
    }
    if (one) {
      sum = rt_rgb_add(sum, rgb_lerp4(W, g0->lt[par], g1->lt[par], g2->lt[par], g3->lt[par]));
      continue;
    }
    /* per sample: its material's summed weights, row by row (the weights are separable: a row
     * needs the count and the sum of u of its samples of each material) */
    double Wp[2][4] = {{0}};
    const double(*c)[2] = Q->uv[m];
    for (int b = b0; b < b1; b++) {
      double v = quad_v(Q, P->j, b), n[2] = {0, 0}, su_p[2] = {0, 0};
      /* a bilinear leaf's board coordinates are linear in u along the row: x = x0 + u dx */
      double x0[2], dx[2];
      for (int t = 0; t < 2; t++) {
        x0[t] = (1 - v) * c[0][t] + v * c[2][t];
        dx[t] = (1 - v) * (c[1][t] - c[0][t]) + v * (c[3][t] - c[2][t]);
      }
      int one_square = 0;
      if (!Q->q2leaf[m]) {
        /* x is monotonic in u (so is each rounding step), u in a, and floor in x: when the
         * row's two end samples are in one square, so is every sample between them, and the
         * row adds its count and its sum of u (su, summed in the same order) at once */
        double f[2][2];
        for (int t = 0; t < 2; t++) {
          f[0][t] = floor_fast(x0[t] + ua * dx[t]);
          f[1][t] = floor_fast(x0[t] + ub * dx[t]);
        }
        if (f[0][0] == f[1][0] && f[0][1] == f[1][1]) {
          int p = (int)((int64_t)(f[0][0] + f[0][1]) & 1);
          n[p] = na;
          su_p[p] = su;
          one_square = 1;
        }
      }
      for (int a = a0; a < a1 && !one_square; a++) {
        double u = quad_u(Q, P->i, a);
        int p;
        if (Q->q2leaf[m]) {
          p = fast_parity(Q, m, u, v, sq);
        } else {
          double f0 = floor_fast(x0[0] + u * dx[0]), f1 = floor_fast(x0[1] + u * dx[1]);
          p = (int)((int64_t)(f0 + f1) & 1);
        }
        n[p] += 1.0;
        su_p[p] += u;
      }
      for (int p = 0; p < 2; p++) {
        Wp[p][0] += (n[p] - su_p[p]) * (1 - v);
        Wp[p][1] += su_p[p] * (1 - v);
        Wp[p][2] += (n[p] - su_p[p]) * v;
        Wp[p][3] += su_p[p] * v;
      }
    }
    for (int p = 0; p < 2; p++)
      sum = rt_rgb_add(sum, rgb_lerp4(Wp[p], g0->lt[p], g1->lt[p], g2->lt[p], g3->lt[p]));
  }
  return sum;
}

/* Start the evaluation of the sample at (x, y): its flags cleared, and its own xi and primary ray
 * when its own nodes or its exact spawn hits need them. */
static void sample_start(pt_ctx_t *C, pt_eval_t *E, double x, double y) {
  E->partial = E->fallback = E->ownfail = E->spawnfail = 0;
  if (E->own || E->exact_spawn) {
    pt__xi_of(C, E, x, y);
    E->stamp = ++C->stamp;
  }
}

/* The samples a in [a0, a1), b in [b0, b1) of pixel P inside quad q: interpolated (Q), or
 * through the matrices when Q is NULL (*why counts them). */
static void quad_pixel(pt_ctx_t *C, pixel_t *P, qctx_t *Q, int why, int a0, int a1, int b0,
                       int b1) {
  int count = (a1 - a0) * (b1 - b0);
  uint64_t r0 = pt__rays_now(C);
  if (!Q) {
    C->st.matrix_samples[why] += (uint64_t)count;
    for (int b = b0; b < b1; b++)
      for (int a = a0; a < a1; a++)
        pt__matrix_sample(C, P, a, b);
    P->rays += pt__rays_now(C) - r0;
    return;
  }
  const lquad_t *q = Q->q;
  pt_eval_t *E = &Q->E;
  int cert = C->opt->certified && !Q->safe, fast = Q->fast, partial = 0;
  for (int b = b0; b < b1 && fast && cert; b++)
    for (int a = a0; a < a1 && fast; a++) {
      double w[4];
      weights(quad_u(Q, P->i, a), quad_v(Q, P->j, b), w);
      fast = misses_nothing(C, E, w);
    }
  int local = fast && Q->pl->n > 0; /* the per-sample nodes on top of the summed rest */
  if (fast) {
    P->sum = rt_rgb_add(P->sum, fast_sum(Q, P, a0, a1, b0, b1));
    P->n[PT_METHOD_INTERP] += count;
    C->st.lerp_samples += local ? 0u : (uint64_t)count;
  }
  for (int b = b0; b < b1 && !(fast && !local && !C->opt->measure); b++)
    for (int a = a0; a < a1; a++) {
      double x = P->i + Q->off[a], y = P->j + Q->off[b], w[4];
      double qu = (x - q->x0) * Q->inv_w, qv = (y - q->y0) * Q->inv_h;
      weights(qu, qv, w);
      if (E->q2)
        qweights9(Q, qu, qv, E->w9);
      if (local) {
        sample_start(C, E, x, y);
        rt_rgb_t v = interp_local(E, Q->pl, w);
        if (E->ownfail) { /* take the sample's summed part back: the whole sample by matrices */
          rt_rgb_t f = fast_sample(Q, qu, qv);
          P->sum = rt_rgb(P->sum.r - f.r, P->sum.g - f.g, P->sum.b - f.b);
          P->n[PT_METHOD_INTERP]--;
          pt__matrix_sample(C, P, a, b);
          continue;
        }
        P->sum = rt_rgb_add(P->sum, v);
        partial |= E->partial;
        C->st.fallbacks += (uint64_t)E->fallback;
      }
      if (!fast) {
        if (cert && !misses_nothing(C, E, w)) {
          pt__matrix_sample(C, P, a, b);
          continue;
        }
        sample_start(C, E, x, y);
        rt_rgb_t v = interp_sample(E, Q->pl, w);
        if (E->ownfail) { /* an own node's ray left its path: the whole sample by matrices */
          pt__matrix_sample(C, P, a, b);
          continue;
        }
        P->sum = rt_rgb_add(P->sum, v);
        P->n[PT_METHOD_INTERP]++;
        partial |= E->partial;
        C->st.fallbacks += (uint64_t)E->fallback;
      }
      if (C->opt->measure) {
        E->w = w;
        pt__geometry(C, E);
        E->w = NULL;
        rt_ray_t r = rt_view_ray(C->view, x, y, C->s->ior);
        P->pmax = pt__measure_sample(C, &r, C->rec, P->i, P->j, a, b, P->pmax);
      }
    }
  C->st.partial += (uint64_t)partial;
  P->rays += pt__rays_now(C) - r0;
}

/* Every sample of quad q, interpolated with plan pl or (pl NULL) through the matrices. */
static void quad_emit(pt_ctx_t *C, const cellacc_t *A, const lquad_t *q, const plan_t *pl,
                      int why) {
  int s = C->opt->spp_side, gx0, gx1, gy0, gy1;
  sample_range(q->x0, q->w, s, &gx0, &gx1);
  sample_range(q->y0, q->h, s, &gy0, &gy1);
  if (gx0 >= gx1 || gy0 >= gy1)
    return;
  qctx_t Q;
  if (pl)
    qctx_make(C, q, pl, &Q);
  C->st.biquad_cells += (uint64_t)(pl && pl->nq2);
  C->st.faint_cells += (uint64_t)(pl && pl->nfaint);
  for (int j = gy0 / s; j <= (gy1 - 1) / s; j++)
    for (int i = gx0 / s; i <= (gx1 - 1) / s; i++) {
      int a0 = gx0 - i * s, a1 = gx1 - i * s, b0 = gy0 - j * s, b1 = gy1 - j * s;
      quad_pixel(C, pixel_at(A, i, j), pl ? &Q : NULL, why, a0 > 0 ? a0 : 0, a1 < s ? a1 : s,
                 b0 > 0 ? b0 : 0, b1 < s ? b1 : s);
    }
}

/* Samples of quad q (about w h s^2). */
static double quad_samples(const pt_ctx_t *C, const lquad_t *q) {
  int s = C->opt->spp_side;
  return q->w * q->h * s * s;
}

/* A quad is cut only when it holds more samples than this: a measured quarter traces 5 points. */
#define PT_CUT_SAMPLES 10.0

static void quad_process(pt_ctx_t *C, const cellacc_t *A, lquad_t *q, int level);

/* Node evaluations per sample of own nodes that a quad may spend instead of being cut, in units
 * of the tree's nodes: a cut traces up to 20 points (4 measured quarters) of the whole tree;
 * measured on Fig. 8 at 49 spp (instructions of the render): budget 4: 3.04e9, 8: 2.78e9,
 * 16: 2.58e9, 32: 2.60e9. */
#define PT_OWN_BUDGET 16.0

/* Whether a plan's per-sample work is cheaper than cutting the quad (always when it cannot be
 * cut). */
static int own_pays(const pt_ctx_t *C, const lquad_t *q, const plan_t *pl, int can_cut) {
  return !can_cut || pl->own_cost * quad_samples(C, q) <= PT_OWN_BUDGET * C->nnode;
}

/* Trace the five interior points of q (its corners are set) at refinement level `level`. */
static void measure(pt_ctx_t *C, lquad_t *q, int level) {
  pt_geom_t *pool = C->ref + (size_t)level * 5 * (size_t)C->cap;
  const int at[5][2] = {{0, 1}, {1, 0}, {1, 1}, {1, 2}, {2, 1}};
  for (int m = 0; m < 5; m++) {
    int r = at[m][0], c = at[m][1];
    q->g[r][c] = trace_point(C, q->x0 + 0.5 * c * q->w, q->y0 + 0.5 * r * q->h,
                             pool + (size_t)m * (size_t)C->cap, 0);
  }
  q->measured = 1;
}

/* Cut a failed measured quad into its quarters. */
static void cut(pt_ctx_t *C, const cellacc_t *A, const lquad_t *q, int level) {
  for (int qy = 0; qy < 2; qy++)
    for (int qx = 0; qx < 2; qx++) {
      lquad_t s;
      memset(&s, 0, sizeof s);
      s.x0 = q->x0 + 0.5 * qx * q->w;
      s.y0 = q->y0 + 0.5 * qy * q->h;
      s.w = 0.5 * q->w;
      s.h = 0.5 * q->h;
      s.pg = (const point_t(*)[3])q->g;
      s.qx = qx;
      s.qy = qy;
      for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++)
          s.g[2 * r][2 * c] = q->g[qy + r][qx + c];
      quad_process(C, A, &s, level + 1);
    }
}

/* Halve measured quad q (halve_dir's direction `dir`): each half keeps three of q's grid lines
 * and traces its three new midpoints. */
static void halve(pt_ctx_t *C, const cellacc_t *A, const lquad_t *q, int level, int dir) {
  pt_geom_t *pool = C->ref + (size_t)(level + 1) * 5 * (size_t)C->cap;
  for (int h = 0; h < 2; h++) {
    lquad_t s;
    memset(&s, 0, sizeof s);
    if (dir == 1) {
      s.x0 = q->x0 + 0.5 * h * q->w;
      s.y0 = q->y0;
      s.w = 0.5 * q->w;
      s.h = q->h;
      for (int r = 0; r < 3; r++) {
        s.g[r][0] = q->g[r][h];
        s.g[r][2] = q->g[r][h + 1];
        s.g[r][1] = trace_point(C, s.x0 + 0.5 * s.w, q->y0 + 0.5 * r * q->h,
                                pool + (size_t)r * (size_t)C->cap, 0);
      }
    } else {
      s.x0 = q->x0;
      s.y0 = q->y0 + 0.5 * h * q->h;
      s.w = q->w;
      s.h = 0.5 * q->h;
      for (int c = 0; c < 3; c++) {
        s.g[0][c] = q->g[h][c];
        s.g[2][c] = q->g[h + 1][c];
        s.g[1][c] = trace_point(C, q->x0 + 0.5 * c * q->w, s.y0 + 0.5 * s.h,
                                pool + (size_t)c * (size_t)C->cap, 0);
      }
    }
    s.measured = 1;
    C->st.halved_cells++;
    quad_process(C, A, &s, level + 1);
  }
}

/* Accept quad q, cut it, or send its samples to the matrices. An estimated quad (not measured)
 * that fails is measured first. */
static void quad_process(pt_ctx_t *C, const cellacc_t *A, lquad_t *q, int level) {
  plan_t pl = {.k = C->loc, .direct = C->locd, .exact = C->loce, .kt = C->loct};
  int why = WHY_ERROR;
  int can_cut = level + 1 < PT_QUAD_LEVELS && quad_samples(C, q) > PT_CUT_SAMPLES;
  if (!q->measured && !C->opt->certified && make_plan(C, q, &pl, 1, &why) &&
      own_pays(C, q, &pl, 1)) {
    quad_emit(C, A, q, &pl, 0);
    return;
  }
  if (!q->measured) {
    if (!can_cut) { /* measuring costs 5 points: more than its samples through the matrices */
      quad_emit(C, A, q, NULL, why);
      return;
    }
    measure(C, q, level);
  }
  if (make_plan(C, q, &pl, can_cut, &why) && own_pays(C, q, &pl, can_cut)) {
    quad_emit(C, A, q, &pl, 0);
    return;
  }
  if (can_cut && pl.halve)
    halve(C, A, q, level, pl.halve);
  else if (can_cut)
    cut(C, A, q, level);
  else
    quad_emit(C, A, q, NULL, why);
}

void pt__interp_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial) {
  cellacc_t A = {x0, y0, x1, y1, C->acc};
  memo_reset(&C->memo, C->nnode);
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++)
      *pixel_at(&A, i, j) = (pixel_t){i, j, {0, 0, 0}, NAN, {0, 0, 0}, 0};
  lquad_t q;
  memset(&q, 0, sizeof q);
  q.x0 = x0;
  q.y0 = y0;
  q.w = x1 - x0;
  q.h = y1 - y0;
  if (quad_samples(C, &q) < 2.0 * 9.0) { /* a 3 x 3 grid would cost more than the samples */
    pt__record_shadows(C, axial);
    quad_emit(C, &A, &q, NULL, WHY_OFF);
  } else {
    /* the grid's centre is the cell's axial ray: traced first, it records the cell's shadow
     * transmittances (pt__record_shadows) and is then found in the memo */
    trace_point(C, x0 + 0.5 * q.w, y0 + 0.5 * q.h, C->lat + (size_t)4 * (size_t)C->cap, 1);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        q.g[r][c] = trace_point(C, x0 + 0.5 * c * q.w, y0 + 0.5 * r * q.h,
                                C->lat + (size_t)(3 * r + c) * (size_t)C->cap, 0);
    q.measured = 1;
    quad_process(C, &A, &q, 0);
  }
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++) {
      pt__pixel_done(C, pixel_at(&A, i, j));
      if (C->opt->aux)
        pt__aux_matrix(C, i, j);
    }
}
