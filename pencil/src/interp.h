/* interp.h -- private to ray interpolation (paper section 4.1 (2)): the lattice of an accepted
 * domain and what its files share. interp.c drives the quadtree of lattice cells; interp_error.c
 * estimates their interpolation errors (Eqs. 3-4 against "first and second order
 * interpolations"); interp_plan.c decides how a lattice cell's samples are interpolated;
 * interp_sample.c evaluates its samples; interp_sum.c sums a pixel's samples in closed form;
 * interp_memo.c keeps the lattice points a domain's lattice cells share. */
#ifndef PENCIL_INTERP_H
#define PENCIL_INTERP_H

#include <math.h>

#include "internal.h"
#include "paraxial/vec3.h"

/* A traced lattice point. */
typedef struct {
  const pt_geom_t *g; /* its geometry per node (cap entries) */
  double xi2;         /* |xi|^2 of the point's primary ray in the domain's frame */
  int ok;             /* traced without leaving the domain's paths */
} lattice_point_t;

/* A lattice cell [x0, x0 + w) x [y0, y0 + h) of continuous pixel coordinates, a node of the
 * domain's quadtree. Its corners are always traced; `measured`: the grid g (corners, edge
 * midpoints, centre) is its own; otherwise its error is estimated from its parent's grid pg, of
 * which it is the quarter (qx, qy). */
typedef struct {
  double x0, y0;                  /* top-left corner, in pixels */
  double w, h;                    /* width and height, in pixels */
  lattice_point_t g[3][3];        /* its 3 x 3 grid, [row][column] (corners only when estimated) */
  int measured;                   /* the whole grid g is traced */
  const lattice_point_t (*pg)[3]; /* its parent's grid, or NULL for the root */
  int qx, qy;                     /* which quarter of the parent it is (column, row) */
} lattice_cell_t;

/* How a lattice cell's samples are interpolated (its per-node arrays are C->lattice.plan's). */
typedef struct {
  rt_rgb_t linear_corners[4]; /* brightness of the linear nodes summed at the four corners */
  int nshaded;                /* nodes shaded per sample at their interpolated hits ... */
  int *shaded;                /* ... which */
  uint8_t *shaded_direct;     /* ... per entry: with its direct term */
  uint8_t *shaded_exact;      /* ... per entry: with its exactly traced children */
  int nleaves;                /* textured leaves whose square changes across the lattice cell: the
                                 sample's square picks the interpolated brightness of its
                                 material ... */
  int *leaves;                /* ... which */
  int ntraced;      /* nodes too curved to interpolate over the lattice cell: traced per sample
                       by their matrices (or along their paths), plan.traced */
  int nbiquadratic; /* nodes whose hits are interpolated biquadratically,
                       plan.biquadratic */
  int nfaint;       /* nodes interpolated across a shadow edge (pt__faint_bound) */
  int nhighlight;   /* nodes the highlight guard shaded per sample (interp_plan.c) */
  int nspectral;    /* spectral nodes whose spectral light is interpolated, plan.spec_lin */
  double per_sample_cost; /* node evaluations per sample: traced nodes, nodes shaded per
                             sample, subtrees traced exactly (about 2 rays each) */
  int halve;              /* on failure: 1 (2) when halving the lattice cell across its columns
                             (rows) makes every node's hits interpolable (pt__halving) */
} interp_plan_t;

/* The share of rho an estimated lattice cell's e_int may use. e_int extrapolates the second-order
 * behaviour of the parent's grid onto the quarter; where the map's third-order term matters it
 * underestimates; holding an estimate to half of rho keeps nearly every sample within rho for
 * a modest number of extra lattice points (docs/tuning.md). */
#define PT_EINT_MARGIN 0.5

/* Biquadratic interpolation of a node's hits over a measured quarter lc of a measured lattice cell
 * P, when bilinear interpolation is not accurate enough: P's biquadratic (through its 3 x 3 grid)
 * predicts lc's five new grid points, and its deviation there, d, is P's second-order
 * interpolation error measured at those points. lc's own biquadratic has half P's side, so where
 * the third-order term dominates its error is about d / 8; it is accepted when
 * PT_BIQUAD_FACTOR d + matrix error <= rho (a margin of 4 over d / 8). Certified mode accepts
 * measured errors only: there the quarter is interpolated by P's biquadratic itself, whose error
 * d was measured at the quarter's five new points (as a measured lattice cell's bilinear error is
 * at its midpoints and centre), when PT_BIQUAD_CERT d + matrix error <= rho (with certified mode's
 * margin in rho; PT_BIQUAD_CERT is above 1 because a factor of 1 let the largest measured error
 * rise: docs/tuning.md). */
#define PT_BIQUAD_FACTOR 0.5
/* Certified mode: a measured lattice cell's bilinear interpolation error over the whole lattice
 * cell, from the deviations d_i it measured at the five grid points other than the corners
 * (pt__grid_error: their largest). A second-order map's error is largest at those points, but the
 * biquadratic through the nine points also has u^2 v, u v^2 and u^2 v^2 terms. Its difference from
 * the bilinear interpolation is sum_i d_i L_i(u, v), with L_i the biquadratic Lagrange basis of
 * point i, and max over the lattice cell of sum_i |L_i| is 1.3843 (at u = 0.325, v = 0.68 and its
 * mirror images), so the error can reach 1.38 times the largest measured deviation: without the
 * factor, samples between the grid points exceeded rho in certified mode (scenes/balls.json, once
 * the measure counted every diffuse surface). A node that fails only because of the factor gets the
 * sum itself at the lattice cell's own samples (pt__bilinear_bound_at_samples), which is all the
 * guarantee is about and costs less than the factor alone (docs/tuning.md). PT_BIQUAD_CERT (below)
 * is above this factor, so the biquadratic interpolation's error over a quarter, measured at the
 * same five points, is covered the same way. */
#ifndef PT_BILINEAR_CERT
#define PT_BILINEAR_CERT 1.3843
#endif
#ifndef PT_BIQUAD_CERT
#define PT_BIQUAD_CERT 1.5
#endif

/* Why a lattice cell's samples went to the matrices (pt_stats_t.matrix_samples). */
enum { WHY_OFF = 0, WHY_LEFT = 1, WHY_REACH = 2, WHY_ERROR = 3 };

/* A 3 x 3 grid of vectors or colours, for one node or a brightness sum. */
typedef struct {
  px_vec3_t v[3][3];
} grid3_t;

/* The accepted domain being interpolated: its pixels' accumulators. */
typedef struct {
  int x0, y0, x1, y1; /* the domain, [x0, x1) x [y0, y1) */
  pixel_t *acc;       /* its pixels, row by row (C->lattice.pixels) */
} domain_pixels_t;

static inline pixel_t *pixel_at(const domain_pixels_t *A, int i, int j) {
  return &A->acc[(j - A->y0) * (A->x1 - A->x0) + (i - A->x0)];
}

/* Textured leaves whose square changes across a lattice cell that the summed pixels handle at
 * most (interp_sum.c). */
#define PT_SUMMED_LEAVES 8

/* What the samples of one accepted lattice cell share. */
typedef struct {
  const lattice_cell_t *lc; /* the lattice cell */
  const interp_plan_t *pl;  /* its plan */
  pt_eval_t E;              /* INTERP evaluation with the lattice cell's corners */
  int safe;                 /* certified: misses_nothing() holds for every sample */
  int summed; /* the linear nodes and textured leaves are summed per pixel (sums of weights);
                 nodes in pl->shaded are added per sample */
  /* summed: board coordinates / check of each leaf's corners (bilinear), or of the lattice
   * cell's 3 x 3 grid (biquadratic) */
  double uv[PT_SUMMED_LEAVES][9][2];
  uint8_t biquadratic_leaf[PT_SUMMED_LEAVES]; /* summed: the leaf is biquadratic */
  /* summed, biquadratic leaves: bounds on |d2/du2| and |d2/dv2| of its board coordinates over
   * the grid, per coordinate */
  double curv[PT_SUMMED_LEAVES][2][2];
  double s9;    /* biquadratic: the grid coordinates of lattice cell coordinates (u, v) are */
  double o9[2]; /* o9 + s9 (u, v) (its own grid, or certified its parent's) */
  double off[RT_MAX_SPP_SIDE]; /* (a + 0.5) / s: a sample's offset in its pixel */
  /* 1 / the lattice cell's width and height: the samples' lattice cell coordinates by
   * multiplications, not divisions per sample */
  double inv_w, inv_h;
} sampling_t;

/* Lagrange basis of the nodes 0, 1/2, 1 at t. */
static inline void lagrange3(double t, double L[3]) {
  L[0] = 2.0 * (t - 0.5) * (t - 1.0);
  L[1] = -4.0 * t * (t - 1.0);
  L[2] = 2.0 * t * (t - 0.5);
}

/* Biquadratic weights at lattice cell coordinates (u, v) for a row-major 3 x 3 grid. */
static inline void biquadratic_weights(double u, double v, double w[9]) {
  double lu[3], lv[3];
  lagrange3(u, lu);
  lagrange3(v, lv);
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      w[3 * r + c] = lv[r] * lu[c];
}

static inline void bilinear_weights(double u, double v, double w[4]) {
  w[0] = (1 - u) * (1 - v);
  w[1] = u * (1 - v);
  w[2] = (1 - u) * v;
  w[3] = u * v;
}

static inline rt_rgb_t rgb_lerp4(const double w[4], rt_rgb_t a, rt_rgb_t b, rt_rgb_t c,
                                 rt_rgb_t d) {
  return rt_rgb(w[0] * a.r + w[1] * b.r + w[2] * c.r + w[3] * d.r,
                w[0] * a.g + w[1] * b.g + w[2] * c.g + w[3] * d.g,
                w[0] * a.b + w[1] * b.b + w[2] * c.b + w[3] * d.b);
}

/* Corner c (0 (0,0), 1 (1,0), 2 (0,1), 3 (1,1)) of lattice cell lc. */
static inline const lattice_point_t *corner_of(const lattice_cell_t *lc, int c) {
  int col = c & 1, row = c >> 1;
  if (lc->measured)
    return &lc->g[2 * row][2 * col];
  return &lc->pg[lc->qy + row][lc->qx + col];
}

/* The 3 x 3 grid the lattice cell's error comes from: its own, or its parent's. */
static inline const lattice_point_t (*grid_of(const lattice_cell_t *lc))[3] {
  return lc->measured ? (const lattice_point_t(*)[3])lc->g : lc->pg;
}

/* A node's hit error over a lattice cell in pixel intervals, as Fig. 10's measure counts it
 * (measure.c): the larger of its pixel count in the domain's axial footprint (pt_pixels) and |e|
 * over the largest extent of one pixel on the surface in the lattice cell's own footprint. The
 * axial footprint alone misses where the footprint changes by orders of magnitude inside one domain
 * (a floor seen through a glass ball near the horizon the lens inverts: the axial ray sees the far
 * floor, whose pixels are large, and a sample the near one). */
typedef struct {
  const pt_node_t *n; /* the node, for its axial footprint */
  double inv_s;       /* 1 / the lattice cell's pixel extent on the surface (pt__cell_scale) */
} cell_norm_t;

static inline double norm_cell(const void *ctx, px_vec3_t e) {
  const cell_norm_t *c = ctx;
  return px_max(pt_pixels(c->n, e), px_v3_norm(e) * c->inv_s);
}

static inline double norm_rgb(const void *unused, px_vec3_t e) {
  (void)unused;
  return px_max(fabs(e.x), px_max(fabs(e.y), fabs(e.z)));
}

static inline px_vec3_t rgb_vec(rt_rgb_t c) {
  return (px_vec3_t){c.r, c.g, c.b};
}

/* How many of a grid's nine points reached node k, and how many of those traced it exactly. */
static inline void reach(const lattice_point_t (*R)[3], int k, int *reached, int *exact) {
  *reached = *exact = 0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      *reached += R[r][c].g[k].ok != 0;
      *exact += R[r][c].g[k].ok == 2;
    }
}

/* Node k's hit points at a grid's nine points. */
static inline void hits_of(const lattice_point_t (*R)[3], int k, grid3_t *p) {
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      p->v[r][c] = R[r][c].g[k].p;
}

/* A node's matrix error at a point with |xi|^2 = xi2 (the worst corner's), in pixel intervals
 * on its surface, the smallest interval of the axial footprint's and the lattice cell's
 * (inv_s, norm_cell): C |xi|^2 / |cos| (Eq. 4), or the certified check's; 0 for a path traced
 * exactly. */
static inline double matrix_error(const pt_node_t *n, double xi2, double inv_s) {
  if (n->mode == PT_NODE_PATH)
    return 0.0;
  double e = px_max(n->c * xi2 / n->cos_in, n->e_check); /* on the surface */
  return px_max(e / n->interval, e * inv_s);
}

/* Samples of the grid (global sample indices g = i s + a, at (g + 0.5) / s) in [x0, x0 + w). */
static inline void sample_range(double x0, double w, int s, int *g0, int *g1) {
  *g0 = (int)ceil(x0 * s - 0.5);
  *g1 = (int)ceil((x0 + w) * s - 0.5);
}

/* Samples of lattice cell lc (about w h s^2). */
static inline double samples_in(const pt_ctx_t *C, const lattice_cell_t *lc) {
  int s = C->opt->spp_side;
  return lc->w * lc->h * s * s;
}

/* Lattice cell coordinates of sample column a (row b) of the pixel at column i (row j). */
static inline double sample_u(const sampling_t *S, int i, int a) {
  return (i + S->off[a] - S->lc->x0) * S->inv_w;
}
static inline double sample_v(const sampling_t *S, int j, int b) {
  return (j + S->off[b] - S->lc->y0) * S->inv_h;
}

/* Biquadratic weights of the plan's grid at lattice cell coordinates (u, v). */
static inline void grid_weights(const sampling_t *S, double u, double v, double w[9]) {
  biquadratic_weights(S->o9[0] + S->s9 * u, S->o9[1] + S->s9 * v, w);
}

/* interp_error.c */
double pt__grid_error(const lattice_cell_t *lc, const grid3_t *G,
                      double (*norm)(const void *, px_vec3_t), const void *ctx);
double pt__cell_scale(const lattice_cell_t *lc, const grid3_t *p);
double pt__biquad_deviation(const lattice_cell_t *lc, const cell_norm_t *cn, int k);
double pt__bilinear_bound_at_samples(const pt_ctx_t *C, const lattice_cell_t *lc, const grid3_t *G,
                                     const cell_norm_t *cn);
double pt__faint_bound(const pt_ctx_t *C, const lattice_cell_t *lc, const lattice_point_t (*R)[3],
                       int k);
double pt__weight_error(const pt_ctx_t *C, const lattice_cell_t *lc, const lattice_point_t (*R)[3],
                        int k);
/* With a Fresnel split: node k's weight's interpolation error times a bound on what its subtree
 * brings unweighted, the node's own term left out when `below` (interp_error.c). */
double pt__subtree_weight_error(const pt_ctx_t *C, const lattice_cell_t *lc,
                                const lattice_point_t (*R)[3], int k, int below);
int pt__halving(const pt_ctx_t *C, const lattice_cell_t *lc, double rho, double xi2);

/* interp_plan.c */
int pt__per_sample_pays(const pt_ctx_t *C, const lattice_cell_t *lc, const interp_plan_t *pl,
                        int can_cut);
int pt__make_plan(pt_ctx_t *C, const lattice_cell_t *lc, interp_plan_t *pl, int can_cut, int *why);

/* interp_sum.c */
void pt__sampling_begin(pt_ctx_t *C, const lattice_cell_t *lc, const interp_plan_t *pl,
                        sampling_t *S);
rt_rgb_t pt__summed_sample(const sampling_t *S, double u, double v);
rt_rgb_t pt__pixel_sum(const sampling_t *S, const pixel_t *P, int a0, int a1, int b0, int b1);

/* interp_sample.c */
int pt__misses_nothing_anywhere(const pt_ctx_t *C, const pt_eval_t *E);
void pt__pixel_samples(pt_ctx_t *C, pixel_t *P, sampling_t *S, int why, int a0, int a1, int b0,
                       int b1);

/* interp_memo.c */
lattice_point_t pt__lattice_point(pt_ctx_t *C, double x, double y, pt_geom_t *g, int record_shadow);
void pt__memo_reset(pt_lattice_memo_t *M, int nnode);

#endif
