/* cell.c -- the procedure of section 4.1 (1) for one domain, steps 2-4:
 *   2) trace the axial ray (the cell's centre) exactly with its tree; a system matrix per path;
 *   3) smoothness: the trees of the centre and the four corners must agree (edge.h), and the
 *      small-object guard must not fire; otherwise subdivide, and trace 1-pixel cells exactly;
 *   4) tolerance (Eq. 3) and spread limit (Eqs. 4-6) per path:
 *      a) the cell's spread is within every path's limit: trace its samples with the matrices,
 *         or interpolate them (4.1 (2)) from matrix-traced pixel corners when e_int allows;
 *      b) the allowed pencil is narrower than a pixel: trace the cell exactly;
 *      c) otherwise divide the cell so that each part's spread is within the limit; repeat 2-4.
 * In certified mode step 4a also needs every path's exact error on the cell boundary (ex_map at
 * the corners and edge midpoints) to be within tau. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "pvec.h"
#include "render/intersect.h"

/* Share of rho that the certified mode's checks may use. */
#define PT_CERTIFIED_MARGIN 0.8

static const pt_ctree_t *corner(pt_ctx_t *C, int x, int y) {
  int side = C->opt->domain + 1;
  pt_ctree_t *ct = &C->corner[(y - C->dom_y0) * side + (x - C->dom_x0)];
  if (ct->n < 0) {
    rt_ray_t r = rt_view_ray(C->view, x, y, C->s->ior);
    C->ex.tree = &C->tree2;
    rt_exact_primary(&C->ex, &r);
    C->ex.tree = NULL;
    pt_ctree_from(ct, &C->tree2);
    C->st.exact_traces++;
  }
  return ct;
}

static size_t pixel_index(const pt_ctx_t *C, int i, int j) {
  return (size_t)j * (size_t)C->img->width + (size_t)i;
}

static float *error_slot(pt_ctx_t *C, int i, int j, int a, int b) {
  int s = C->opt->spp_side;
  if (!C->sample_error)
    return NULL;
  return C->sample_error + pixel_index(C, i, j) * (size_t)(s * s) + (size_t)(b * s + a);
}

static uint64_t rays_now(const pt_ctx_t *C) { return rt_stats_total(&C->ex.stats); }

static void write_pixel(pt_ctx_t *C, int i, int j, rt_rgb_t sum, pt_method_t m, double perr,
                        uint64_t rays0) {
  size_t k = pixel_index(C, i, j);
  if (C->extra && C->extra->rays)
    C->extra->rays[k] = (float)(rays_now(C) - rays0);
  double w = 1.0 / (C->opt->spp_side * C->opt->spp_side);
  C->img->ch[RT_CH_R][k] = (float)(sum.r * w);
  C->img->ch[RT_CH_G][k] = (float)(sum.g * w);
  C->img->ch[RT_CH_B][k] = (float)(sum.b * w);
  if (C->extra && C->extra->method)
    C->extra->method[k] = (float)m;
  if (C->extra && C->extra->error)
    C->extra->error[k] = (float)perr;
}

/* Auxiliary channels of pixel (i, j) from an exact tree of its centre ray (as the reference
 * renderer writes them). */
static void aux_exact(pt_ctx_t *C, int i, int j) {
  rt_ray_t r = rt_view_ray(C->view, i + 0.5, j + 0.5, C->s->ior);
  C->ex.tree = &C->tree2;
  rt_exact_primary(&C->ex, &r);
  C->ex.tree = NULL;
  const rt_tree_t *t = &C->tree2;
  size_t k = pixel_index(C, i, j);
  C->img->ch[RT_CH_Z][k] = (float)t->node[0].t;
  C->img->ch[RT_CH_ID][k] = (float)t->node[0].object;
  const rt_ray_kind_t prefer[2] = {RT_RAY_REFRACT, RT_RAY_REFLECT};
  const rt_channel_t base[2] = {RT_CH_T_U, RT_CH_R_U};
  for (int p = 0; p < 2; p++) {
    int n = rt_tree_follow(t, prefer[p]);
    double u = NAN, v = NAN;
    if (n >= 0)
      rt_plane_coords(&C->s->prim[t->node[n].prim].plane, t->node[n].point, &u, &v);
    C->img->ch[base[p]][k] = (float)u;
    C->img->ch[base[p] + 1][k] = (float)v;
    C->img->ch[base[p] + 2][k] = n >= 0 ? (float)t->node[n].depth : -1.0f;
  }
}

/* Auxiliary channels from the pencil's own geometry of the pixel's centre ray (rec), so that
 * the pencil image's checkerboard points can be compared with the exact image's. */
static void aux_pencil(pt_ctx_t *C, int i, int j, const pt_geom_t *rec) {
  const int kk[2] = {C->kt, C->kr};
  if (rec[0].ok != 1 || (kk[0] >= 0 && rec[kk[0]].ok != 1) || (kk[1] >= 0 && rec[kk[1]].ok != 1)) {
    aux_exact(C, i, j);
    return;
  }
  size_t k = pixel_index(C, i, j);
  const pt_node_t *root = &C->node[0];
  C->img->ch[RT_CH_Z][k] = root->miss ? INFINITY : (float)pv_norm(pv_sub(rec[0].p, C->view->eye));
  C->img->ch[RT_CH_ID][k] = (float)root->object;
  const rt_channel_t base[2] = {RT_CH_T_U, RT_CH_R_U};
  for (int p = 0; p < 2; p++) {
    double u = NAN, v = NAN;
    if (kk[p] >= 0)
      rt_plane_coords(&C->s->prim[C->node[kk[p]].prim].plane, rec[kk[p]].p, &u, &v);
    C->img->ch[base[p]][k] = (float)u;
    C->img->ch[base[p] + 1][k] = (float)v;
    C->img->ch[base[p] + 2][k] = kk[p] >= 0 ? (float)C->node[kk[p]].depth : -1.0f;
  }
}

/* Step 3 failed or 4b: every sample of the pixels of the cell by the exact tracer. */
static void exact_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  int s = C->opt->spp_side;
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++) {
      rt_rgb_t sum = rt_rgb(0, 0, 0);
      uint64_t rays0 = rays_now(C);
      for (int b = 0; b < s; b++)
        for (int a = 0; a < s; a++) {
          rt_ray_t r = rt_view_ray(C->view, i + (a + 0.5) / s, j + (b + 0.5) / s, C->s->ior);
          sum = rt_rgb_add(sum, rt_exact_primary(&C->ex, &r));
          if (C->opt->measure) {
            const double zero[3] = {0.0, 0.0, 0.0};
            pt__account(C, zero, 0, error_slot(C, i, j, a, b));
          }
        }
      C->st.samples[PT_METHOD_EXACT] += (uint64_t)(s * s);
      write_pixel(C, i, j, sum, PT_METHOD_EXACT, NAN, rays0);
      if (C->opt->aux)
        aux_exact(C, i, j);
    }
}

/* Per-sample bookkeeping of the Fig. 10 measurement; returns the pixel's running maximum. */
static double measure_sample(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, int i, int j,
                             int a, int b, double pmax) {
  double e[3];
  pt__measure(C, ray, rec, e);
  int board = 0;
  for (int k = 0; k < C->nnode && !board; k++)
    board = C->node[k].textured && rec[k].ok == 1;
  pt__account(C, e, board, error_slot(C, i, j, a, b));
  if (board && (isnan(pmax) || e[0] > pmax))
    pmax = e[0];
  return pmax;
}

/* Geometry-only evaluation into C->rec (aux channels, measurement); E is left as it was. */
static void geometry(pt_ctx_t *C, pt_eval_t *E) {
  pt_eval_t G = *E;
  G.shade = 0;
  G.rec = C->rec;
  pt__eval(&G);
}

/* A pixel being accumulated. */
typedef struct {
  int i, j;        /**< pixel */
  rt_rgb_t sum;    /**< radiance summed over its samples */
  double pmax;     /**< largest measured error (NaN: none) */
  int n[3];        /**< samples by method */
  uint64_t rays0;  /**< exact ray count when the pixel began */
} pixel_t;

static void pixel_done(pt_ctx_t *C, pixel_t *P) {
  pt_method_t m = P->n[PT_METHOD_INTERP] >= P->n[PT_METHOD_MATRIX] ? PT_METHOD_INTERP
                                                                   : PT_METHOD_MATRIX;
  for (int k = 0; k < 3; k++)
    C->st.samples[k] += (uint64_t)P->n[k];
  write_pixel(C, P->i, P->j, P->sum, m, P->pmax, P->rays0);
}

static void xi_of(const pt_ctx_t *C, pt_eval_t *E, double x, double y) {
  E->primary = rt_view_ray(C->view, x, y, C->s->ior);
  E->xi[0] = pv_dot(C->frame.x1, E->primary.d);
  E->xi[1] = pv_dot(C->frame.x2, E->primary.d);
}

/* Step 4a with matrices: sample (a, b) of pixel P through the paths. */
static void matrix_sample(pt_ctx_t *C, pixel_t *P, int a, int b) {
  int s = C->opt->spp_side;
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .rec = C->opt->measure ? C->rec : NULL};
  xi_of(C, &E, P->i + (a + 0.5) / s, P->j + (b + 0.5) / s);
  P->sum = rt_rgb_add(P->sum, pt__eval(&E));
  P->n[PT_METHOD_MATRIX]++;
  C->st.fallbacks += (uint64_t)E.fallback;
  C->st.partial += (uint64_t)E.partial;
  if (C->opt->measure)
    P->pmax = measure_sample(C, &E.primary, C->rec, P->i, P->j, a, b, P->pmax);
}

static void aux_matrix(pt_ctx_t *C, int i, int j) {
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX};
  xi_of(C, &E, i + 0.5, j + 0.5);
  geometry(C, &E);
  aux_pencil(C, i, j, C->rec);
}

/* Step 4a with matrices for every sample of pixel (i, j). */
static void matrix_pixel(pt_ctx_t *C, int i, int j) {
  int s = C->opt->spp_side;
  pixel_t P = {i, j, {0, 0, 0}, NAN, {0, 0, 0}, rays_now(C)};
  for (int b = 0; b < s; b++)
    for (int a = 0; a < s; a++)
      matrix_sample(C, &P, a, b);
  pixel_done(C, &P);
  if (C->opt->aux)
    aux_matrix(C, i, j);
}

/* The interpolation lattice of a cell: points (x0 + i hx, y0 + j hy), i <= mx, j <= my, with
 * steps of a pixel, or half a pixel along an axis where the cell is one pixel wide (so that every
 * lattice cell has a third point beyond it for e_int). */
typedef struct {
  int x0, y0, mx, my;
  double hx, hy;
} lattice_t;

static size_t lat_index(const lattice_t *L, int i, int j) { return (size_t)(j * (L->mx + 1) + i); }

static const pt_geom_t *lat_at(const pt_ctx_t *C, const lattice_t *L, int i, int j, int k) {
  return &C->lat[lat_index(L, i, j) * (size_t)C->cap + (size_t)k];
}

/* e_int (section 4.1 (2)) of the linear interpolation between lattice points b and c, estimated
 * with the third point a beyond b: (x_a - 2 x_b + x_c) / 8, in pixels on node k's surface. */
static double e_int3(const pt_node_t *n, const pt_geom_t *a, const pt_geom_t *b,
                     const pt_geom_t *c) {
  px_vec3_t s = pv_add(pv_sub(a->p, pv_scale(b->p, 2.0)), c->p);
  return pt_pixels(n, pv_scale(s, 1.0 / 8.0));
}

/* Largest e_int of node k over lattice cell (i, j), along x plus along y, each from the lattice
 * line beyond the cell on whichever side exists. *ok = 0 when a third point is missing. */
static double e_int_cell(const pt_ctx_t *C, const lattice_t *L, int i, int j, int k, int *ok) {
  const pt_node_t *n = &C->node[k];
  int ia = i >= 1 ? i - 1 : i + 2, ib = i >= 1 ? i : i + 1, ic = i >= 1 ? i + 1 : i;
  int ja = j >= 1 ? j - 1 : j + 2, jb = j >= 1 ? j : j + 1, jc = j >= 1 ? j + 1 : j;
  double ex = 0.0, ey = 0.0;
  if (ia > L->mx || ja > L->my) {
    *ok = 0;
    return INFINITY;
  }
  for (int r = j; r <= j + 1; r++) {
    const pt_geom_t *a = lat_at(C, L, ia, r, k), *b = lat_at(C, L, ib, r, k),
                    *c = lat_at(C, L, ic, r, k);
    if (a->ok != 1 || b->ok != 1 || c->ok != 1)
      *ok = 0;
    else
      ex = fmax(ex, e_int3(n, a, b, c));
  }
  for (int q = i; q <= i + 1; q++) {
    const pt_geom_t *a = lat_at(C, L, q, ja, k), *b = lat_at(C, L, q, jb, k),
                    *c = lat_at(C, L, q, jc, k);
    if (a->ok != 1 || b->ok != 1 || c->ok != 1)
      *ok = 0;
    else
      ey = fmax(ey, e_int3(n, a, b, c));
  }
  return ex + ey;
}

/* How the samples of one lattice cell are interpolated: the brightness of the nodes on which it
 * is linear summed at the four corners, and the nodes shaded per sample. */
typedef struct {
  rt_rgb_t smooth[4];
  int n;                   /**< nodes in k[] */
  int *k;                  /**< nodes shaded per sample (C->loc) */
  uint8_t *direct, *exact; /**< per entry: its direct term, its exactly traced children */
} cell_plan_t;

/* Whether lattice cell (i, j) may be interpolated: its 4 points reached the same nodes without
 * leaving the cell's paths, and for every node the matrix error (bound, or the certified check,
 * at the worst of the 4 points) plus e_int is within rho pixels. A node's brightness is linear
 * over the lattice cell when its corners saw the same checker square and every light's
 * visibility agrees over the cell; the other nodes, and nodes with children traced exactly, are
 * shaded per sample at their interpolated hits. */
static void xi_of(const pt_ctx_t *C, pt_eval_t *E, double x, double y);

static int cell_plan(pt_ctx_t *C, const lattice_t *L, int i, int j, cell_plan_t *pl) {
  const size_t lq[4] = {lat_index(L, i, j), lat_index(L, i + 1, j), lat_index(L, i, j + 1),
                        lat_index(L, i + 1, j + 1)};
  uint64_t *why = C->st.matrix_pixels;
  for (int q = 0; q < 4; q++)
    if (!C->latok[lq[q]])
      return (int)(why[1]++ & 0);
  if (C->opt->certified) { /* the a-posteriori check of interpolation: the lattice cell's centre
                              traced (matrices / exactly along the paths) into C->rec */
    pt_eval_t G = {.C = C, .mode = PT_EV_MATRIX, .rec = C->rec};
    xi_of(C, &G, L->x0 + (i + 0.5) * L->hx, L->y0 + (j + 0.5) * L->hy);
    pt__eval(&G);
    if (G.fallback)
      return (int)(why[1]++ & 0);
  }
  double xi2 = fmax(fmax(C->latxi2[lq[0]], C->latxi2[lq[1]]), fmax(C->latxi2[lq[2]], C->latxi2[lq[3]]));
  /* certified mode keeps a margin for what the checks do not see (third-order variation
   * between the checked points): 0.8 rho */
  double rho = C->opt->rho * (C->opt->certified ? PT_CERTIFIED_MARGIN : 1.0);
  pl->n = 0;
  for (int q = 0; q < 4; q++)
    pl->smooth[q] = rt_rgb(0, 0, 0);
  for (int k = 0; k < C->nnode; k++) {
    const pt_geom_t *g[4] = {lat_at(C, L, i, j, k), lat_at(C, L, i + 1, j, k),
                             lat_at(C, L, i, j + 1, k), lat_at(C, L, i + 1, j + 1, k)};
    int reached = (g[0]->ok != 0) + (g[1]->ok != 0) + (g[2]->ok != 0) + (g[3]->ok != 0);
    int exact = (g[0]->ok == 2) + (g[1]->ok == 2) + (g[2]->ok == 2) + (g[3]->ok == 2);
    if (reached == 0 || exact == 4)
      continue; /* not reached, or traced exactly per sample through its parent */
    if (reached != 4 || exact != 0)
      return (int)(why[2]++ & 0);
    const pt_node_t *n = &C->node[k];
    int smooth = 1, exact_children = 0;
    if (!n->miss) {
      int ok = 1;
      double e_mat = n->pencil == PT_NODE_PATH
                         ? 0.0
                         : fmax(n->c * xi2 / n->cos_in, n->e_check) / n->interval;
      double e_int = e_int_cell(C, L, i, j, k, &ok);
      if (C->opt->certified) { /* and the bound of bilinear interpolation over the lattice cell
                                  (|second derivatives| <= 2 C give (h^2 / 8)(2 C + 2 C)), and the
                                  interpolation's actual error at the centre */
        double h = fmax(L->hx, L->hy) * C->dpix;
        e_int = fmax(e_int, 0.5 * n->c * h * h / n->cos_in / n->interval);
        if (C->rec[k].ok != 1)
          return (int)(why[2]++ & 0);
        px_vec3_t mid = pv_scale(pv_add(pv_add(g[0]->p, g[1]->p), pv_add(g[2]->p, g[3]->p)), 0.25);
        e_int = fmax(e_int, pt_pixels(n, pv_sub(C->rec[k].p, mid)));
      }
      if (e_int + e_mat > rho || !ok)
        return (int)(why[ok ? 3 : 2]++ & 0);
      if (n->textured)
        for (int q = 1; q < 4; q++)
          smooth = smooth && g[q]->su == g[0]->su && g[q]->sv == g[0]->sv;
      smooth = smooth && n->light_agree == ~0u;
      for (int c = 0; c < 2; c++)
        exact_children |= n->child[c] >= 0 && C->node[n->child[c]].pencil == PT_NODE_EXACT;
    }
    if (smooth)
      for (int q = 0; q < 4; q++)
        pl->smooth[q] = rt_rgb_add(pl->smooth[q], g[q]->l);
    if (!smooth || exact_children) {
      pl->k[pl->n] = k;
      pl->direct[pl->n] = (uint8_t)!smooth;
      pl->exact[pl->n++] = (uint8_t)exact_children;
    }
  }
  return 1;
}

/* One interpolated sample at local coordinates (u, v) of a planned lattice cell. */
static rt_rgb_t interp_sample(pt_eval_t *E, const cell_plan_t *pl, double u, double v) {
  const double w[4] = {(1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v};
  const rt_rgb_t *c = pl->smooth;
  E->w = w;
  rt_rgb_t sum = rt_rgb(w[0] * c[0].r + w[1] * c[1].r + w[2] * c[2].r + w[3] * c[3].r,
                        w[0] * c[0].g + w[1] * c[1].g + w[2] * c[2].g + w[3] * c[3].g,
                        w[0] * c[0].b + w[1] * c[1].b + w[2] * c[2].b + w[3] * c[3].b);
  for (int m = 0; m < pl->n; m++) {
    int k = pl->k[m];
    const pt_geom_t *g0 = &E->g[0][k], *g1 = &E->g[1][k], *g2 = &E->g[2][k], *g3 = &E->g[3][k];
    rt_rgb_t wk = rt_rgb(w[0] * g0->w.r + w[1] * g1->w.r + w[2] * g2->w.r + w[3] * g3->w.r,
                         w[0] * g0->w.g + w[1] * g1->w.g + w[2] * g2->w.g + w[3] * g3->w.g,
                         w[0] * g0->w.b + w[1] * g1->w.b + w[2] * g2->w.b + w[3] * g3->w.b);
    sum = rt_rgb_add(sum, pt__eval_local(E, k, wk, pl->direct[m], pl->exact[m]));
  }
  E->w = NULL;
  return sum;
}

/* Certified mode: whether every miss node of an interpolated sample still meets nothing (its
 * ray interpolated from the lattice points and intersected with the scene). */
static int misses_nothing(const pt_ctx_t *C, const pt_eval_t *E, double u, double v) {
  const double w[4] = {(1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v};
  for (int k = 0; k < C->nnode; k++) {
    const pt_geom_t *a = &E->g[0][k], *b = &E->g[1][k], *c = &E->g[2][k], *e = &E->g[3][k];
    if (!C->node[k].miss || a->ok != 1)
      continue;
    px_vec3_t o = pv_axpy(w[0], a->p, pv_axpy(w[1], b->p, pv_axpy(w[2], c->p, pv_scale(e->p, w[3]))));
    px_vec3_t d = pv_axpy(w[0], a->d, pv_axpy(w[1], b->d, pv_axpy(w[2], c->d, pv_scale(e->d, w[3]))));
    rt_ray_t r = {o, pv_unit(d), 0.0, INFINITY, C->node[k].ior, -1};
    rt_hit_t h;
    if (rt_intersect(C->s, &r, &h))
      return 0;
  }
  return 1;
}

/* The samples of pixel P inside lattice cell (ci, cj): interpolated when the cell's plan
 * allows, else by matrices. */
static void lattice_cell_samples(pt_ctx_t *C, const lattice_t *L, int ci, int cj, pixel_t *P) {
  int s = C->opt->spp_side, measure = C->opt->measure, planned = -1, partial = 0;
  cell_plan_t pl = {.k = C->loc, .direct = C->locd, .exact = C->loce};
  pt_eval_t E = {.C = C, .mode = PT_EV_INTERP, .shade = 1};
  for (int q = 0; q < 4; q++)
    E.g[q] = C->lat + lat_index(L, ci + (q & 1), cj + (q >> 1)) * (size_t)C->cap;
  for (int b = 0; b < s; b++)
    for (int a = 0; a < s; a++) {
      double x = P->i + (a + 0.5) / s, y = P->j + (b + 0.5) / s;
      double fx = (x - L->x0) / L->hx, fy = (y - L->y0) / L->hy;
      int si = (int)fx < L->mx ? (int)fx : L->mx - 1, sj = (int)fy < L->my ? (int)fy : L->my - 1;
      if (si != ci || sj != cj)
        continue;
      if (planned < 0)
        planned = cell_plan(C, L, ci, cj, &pl);
      if (!planned) {
        matrix_sample(C, P, a, b);
        continue;
      }
      if (C->opt->certified && !misses_nothing(C, &E, fx - si, fy - sj)) {
        matrix_sample(C, P, a, b);
        continue;
      }
      E.partial = E.fallback = 0;
      P->sum = rt_rgb_add(P->sum, interp_sample(&E, &pl, fx - si, fy - sj));
      P->n[PT_METHOD_INTERP]++;
      partial |= E.partial;
      C->st.fallbacks += (uint64_t)E.fallback;
      if (pl.n == 0)
        C->st.lerp_samples++;
      if (measure) {
        const double w[4] = {(1 - (fx - si)) * (1 - (fy - sj)), (fx - si) * (1 - (fy - sj)),
                             (1 - (fx - si)) * (fy - sj), (fx - si) * (fy - sj)};
        E.w = w;
        geometry(C, &E);
        E.w = NULL;
        rt_ray_t r = rt_view_ray(C->view, x, y, C->s->ior);
        P->pmax = measure_sample(C, &r, C->rec, P->i, P->j, a, b, P->pmax);
      }
    }
  C->st.partial += partial ? (uint64_t)(s * s) : 0u;
}

/* Step 4a with ray interpolation: matrices at the lattice points of the cell, and every sample
 * interpolated from the four points around it: hit points and directions, and the brightness of
 * every node on which it is linear (cell_plan). Lattice cells that fail e_int use matrices. */
static void interp_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  lattice_t L = {x0, y0, 0, 0, x1 - x0 >= 2 ? 1.0 : 0.5, y1 - y0 >= 2 ? 1.0 : 0.5};
  L.mx = (int)lrint((x1 - x0) / L.hx);
  L.my = (int)lrint((y1 - y0) / L.hy);
  for (int j = 0; j <= L.my; j++)
    for (int i = 0; i <= L.mx; i++) {
      size_t l = lat_index(&L, i, j);
      pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .rec = C->lat + l * (size_t)C->cap};
      xi_of(C, &E, x0 + i * L.hx, y0 + j * L.hy);
      C->latxi2[l] = E.xi[0] * E.xi[0] + E.xi[1] * E.xi[1];
      pt__eval(&E);
      C->latok[l] = !E.fallback;
    }
  int px = (int)lrint(1.0 / L.hx), py = (int)lrint(1.0 / L.hy); /* lattice cells per pixel */
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++) {
      pixel_t P = {i, j, {0, 0, 0}, NAN, {0, 0, 0}, rays_now(C)};
      for (int cj = (j - y0) * py; cj < (j - y0 + 1) * py; cj++)
        for (int ci = (i - x0) * px; ci < (i - x0 + 1) * px; ci++)
          lattice_cell_samples(C, &L, ci, cj, &P);
      pixel_done(C, &P);
      if (C->opt->aux) {
        if (P.n[PT_METHOD_INTERP] == 0) {
          aux_matrix(C, i, j);
          continue;
        }
        double fx = (i + 0.5 - x0) / L.hx, fy = (j + 0.5 - y0) / L.hy;
        int ci = (int)fx < L.mx ? (int)fx : L.mx - 1, cj = (int)fy < L.my ? (int)fy : L.my - 1;
        double u = fx - ci, v = fy - cj;
        const double w[4] = {(1 - u) * (1 - v), u * (1 - v), (1 - u) * v, u * v};
        pt_eval_t E = {.C = C, .mode = PT_EV_INTERP, .w = w};
        for (int q = 0; q < 4; q++)
          E.g[q] = C->lat + lat_index(&L, ci + (q & 1), cj + (q >> 1)) * (size_t)C->cap;
        geometry(C, &E);
        aux_pencil(C, i, j, C->rec);
      }
    }
}

/* Step 4a for an accepted cell. */
static void accept_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial) {
  /* shadow transmittance once per cell, at the axial ray's nodes */
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .record_shadow = 1};
  E.primary = *axial;
  pt__eval(&E);
  C->kt = rt_tree_follow(&C->tree, RT_RAY_REFRACT);
  C->kr = rt_tree_follow(&C->tree, RT_RAY_REFLECT);
  if (C->opt->interp && C->opt->spp_side >= 2) {
    interp_cell(C, x0, y0, x1, y1);
    return;
  }
  C->st.matrix_pixels[0] += (uint64_t)((x1 - x0) * (y1 - y0));
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++)
      matrix_pixel(C, i, j);
}

/* Divide the cell into about k x k parts (each at least a pixel) and process them; a 1-pixel
 * cell is traced exactly instead. */
static void split(pt_ctx_t *C, int x0, int y0, int x1, int y1, int k) {
  int w = x1 - x0, h = y1 - y0;
  if (w <= 1 && h <= 1) {
    exact_cell(C, x0, y0, x1, y1);
    return;
  }
  int kx = w > 1 ? (k < w ? k : w) : 1, ky = h > 1 ? (k < h ? k : h) : 1;
  for (int j = 0; j < ky; j++)
    for (int i = 0; i < kx; i++)
      pt__cell(C, x0 + i * w / kx, y0 + j * h / ky, x0 + (i + 1) * w / kx, y0 + (j + 1) * h / ky);
}

static double xi_norm(const pt_ctx_t *C, double x, double y) {
  double xi[2];
  pt__xi(C, x, y, xi);
  return hypot(xi[0], xi[1]);
}

/* Step 2 for every node whose path agrees at the corners: topology for all, matrices for the
 * agreeing ones (a node whose path cannot be re-traced is treated as disagreeing, and so are its
 * descendants). Then step 4 per path: a path is traced with its matrix when the cell's spread is
 * within its limit (4a) and, in certified mode, its exact check passed; otherwise exactly along
 * its known path (4b; and 4c unless the cell is subdivided, see pt__cell). *over counts the
 * paths over their limit whose pencil is not narrower than a pixel (4c candidates), *paths the
 * agreeing non-miss paths; the return value is the smallest limit among the 4c candidates. In
 * *cost: exact rays per sample that subtrees below disagreeing nodes need. */
static double build_paths(pt_ctx_t *C, const pt_pencil_t *p, double xi_cell, double dmin,
                          double *cost, int *over, int *paths, int *partial) {
  double need = INFINITY;
  *cost = 0.0;
  *over = *paths = *partial = 0;
  C->nnode = C->tree.n;
  int *size = C->loc; /* subtree sizes, scratch */
  for (int k = C->nnode - 1; k >= 0; k--) {
    size[k] = 1;
    for (int j = k + 1; j < C->nnode; j++)
      if (C->tree.node[j].parent == k)
        size[k] += size[j];
  }
  for (int k = 0; k < C->nnode; k++) {
    pt_node_t *n = &C->node[k];
    int par = C->tree.node[k].parent;
    pt_path_topology(C->s, &C->tree, k, par >= 0 ? &C->node[par] : NULL, n);
    n->light_agree = C->light[k];
    int parent_ok = par < 0 || C->node[par].pencil != PT_NODE_EXACT;
    int mode = C->agree[k] && parent_ok ? PT_NODE_MATRIX : PT_NODE_EXACT;
    if (!C->agree[k] && parent_ok) { /* an edge below the primary ray */
      need = fmin(need, 0.5 * xi_cell);
      *cost += size[k];
    }
    if (mode && pt_path_build(C->s, &C->tree, k, C->node, p, &C->path) != PX_OK)
      mode = PT_NODE_EXACT;
    if (mode && !n->miss) {
      (*paths)++;
      int checked = !p->check || n->e_check <= PT_CERTIFIED_MARGIN * n->tau;
      if (xi_cell > n->xi_max || !checked) {
        mode = PT_NODE_PATH;
        C->st.paths_exact++;
        if (!(2.0 * n->xi_max < dmin) && xi_cell > n->xi_max) { /* not 4b */
          (*over)++;
          need = fmin(need, n->xi_max);
        }
      }
    }
    n->pencil = mode;
    if (mode == PT_NODE_EXACT || n->light_agree != ~0u)
      *partial = 1;
  }
  return need;
}

void pt__cell(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  pt_stats_t *st = &C->st;
  st->cells++;
  double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  rt_ray_t axial = rt_view_ray(C->view, cx, cy, C->s->ior);
  C->ex.tree = &C->tree;
  rt_exact_primary(&C->ex, &axial);
  C->ex.tree = NULL;
  st->exact_traces++;
  /* step 3: smoothness, node by node; the primary ray must meet the same surface everywhere */
  const int xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
  const pt_ctree_t *ct[4];
  for (int i = 0; i < 4; i++)
    ct[i] = corner(C, xs[i], ys[i]);
  pt_tree_agree(&C->tree, ct, 4, C->map, C->agree, C->light);
  int edge = C->tree.n == 0 || !C->agree[0] ||
             px_frame_from_z(axial.d, C->view->down, &C->frame) != PX_OK;
  double xi_cell = 0.0;
  for (int i = 0; i < 4 && !edge; i++)
    xi_cell = fmax(xi_cell, xi_norm(C, xs[i], ys[i]));
  if (!edge && C->nguard &&
      pt_guard_fires(C->guard, C->nguard, C->view->eye, axial.d, asin(fmin(1.0, xi_cell)))) {
    edge = 1;
    st->cells_guard++;
  }
  if (edge) {
    st->cells_edge++;
    split(C, x0, y0, x1, y1, 2);
    return;
  }
  /* step 2: a system matrix per path; step 4: tolerance and spread limit */
  double a[2], b[2], c[2], d[2], chk[8][2];
  pt__xi(C, cx + 0.5, cy, a);
  pt__xi(C, cx - 0.5, cy, b);
  pt__xi(C, cx, cy + 0.5, c);
  pt__xi(C, cx, cy - 0.5, d);
  pt_pencil_t p = {C->view->eye, C->frame, {{a[0] - b[0], a[1] - b[1]}, {c[0] - d[0], c[1] - d[1]}},
                   C->opt->rho, C->opt->bound, xi_cell, NULL};
  if (C->opt->certified) {
    const double px[8] = {x0, cx, x1, x1, x1, cx, x0, x0}, py[8] = {y0, y0, y0, cy, y1, y1, y1, cy};
    for (int i = 0; i < 8; i++)
      pt__xi(C, px[i], py[i], chk[i]);
    p.check = (const double(*)[2])chk;
  }
  int partial, over, paths;
  double cost, dmin = fmin(hypot(p.delta[0][0], p.delta[0][1]), hypot(p.delta[1][0], p.delta[1][1]));
  C->dpix = fmax(hypot(p.delta[0][0], p.delta[0][1]), hypot(p.delta[1][0], p.delta[1][1]));
  double need = build_paths(C, &p, xi_cell, dmin, &cost, &over, &paths, &partial);
  if (C->node[0].pencil == PT_NODE_EXACT) { /* the primary path cannot be re-traced */
    st->cells_edge++;
    split(C, x0, y0, x1, y1, 2);
    return;
  }
  /* 4c: subdivide when most paths are over their limit (the pencil is too wide for this cell),
   * or when the subtrees below an edge would cost more exact rays per sample than about
   * k^2 (5 + nodes) rays for k x k smaller cells (axial and corner trees, matrices) */
  int w = x1 - x0, h = y1 - y0, s = C->opt->spp_side;
  double k = ceil(xi_cell / need);
  if (isfinite(need) && (w > 1 || h > 1) &&
      (2 * over > paths || k * k * (5.0 + C->nnode) < cost * w * h * s * s)) {
    st->cells_split++;
    split(C, x0, y0, x1, y1, k > 64.0 ? 64 : (int)fmax(2.0, k));
    return;
  }
  st->cells_accepted++;
  st->cells_partial += (uint64_t)partial;
  accept_cell(C, x0, y0, x1, y1, &axial);
}
