/* interp_error.c -- the error of ray interpolation over a lattice cell (paper section 4.1 (2):
 * "the error can be estimated by evaluating first and second order interpolations"), in pixel
 * intervals on each node's surface as Eq. (3)'s tolerance measures it, and the matrix error that
 * it is added to: e_x of Eq. (4) at the lattice cell's corners, C |xi|^2 for a pencil from the
 * pinhole (the left side of Eq. 6).
 *
 * A measured lattice cell's error is the deviation of its edge midpoints and centre from the
 * bilinear interpolation of its corners (exact for a second-order map); an estimated one's is the
 * paper's e_int = |(second order interpolation) - (linear interpolation)|, the second difference
 * along the parent's grid lines. Certified mode adds the biquadratic terms a second-order bound
 * misses. Also: bounds on a faint node's brightness and on the error of interpolated weights W_k,
 * and whether halving a lattice cell would do. */
#include <string.h>

#include "interp.h"

/* 1 / the largest extent of one pixel, on a node's surface, in lattice cell lc's own footprint,
 * from the node's hits p on the grid the lattice cell's error comes from. For each quarter of that
 * grid inside the lattice cell, a pixel step along screen x moves the hit by about the shorter of
 * the quarter's two horizontal edges over their length in pixels (likewise along y); the larger
 * of the two is an estimate of sigma_max of the quarter's footprint at its narrower side. Where
 * the footprint changes across the quarter (the ratio of the longer edge to the shorter) it can
 * change as much again inside it (near a horizon seen through a lens, or where a path focuses), so
 * the estimate is divided by that ratio. The smallest over the quarters is taken. Without the
 * ratio, or with the mean of the two edges, samples were left more than rho of their own pixels
 * off (Fig. 8: docs/journal/2026-12-06-local-footprint.md). A measured lattice cell has four such
 * quarters; an estimated one is itself one quarter of its parent's grid. INFINITY (every error
 * then too large) for a degenerate footprint. */
static double edge2(const px_vec3_t (*v)[3], int r0, int c0, int r1, int c1) {
  px_vec3_t d = px_v3_sub(v[r1][c1], v[r0][c0]);
  return px_v3_dot(d, d);
}

double pt__cell_scale(const lattice_cell_t *lc, const grid3_t *p) {
  const px_vec3_t(*v)[3] = p->v;
  int r0 = lc->measured ? 0 : lc->qy, r1 = lc->measured ? 2 : lc->qy + 1;
  int c0 = lc->measured ? 0 : lc->qx, c1 = lc->measured ? 2 : lc->qx + 1;
  double dx = lc->measured ? 0.5 * lc->w : lc->w, dy = lc->measured ? 0.5 * lc->h : lc->h;
  double smin2 = INFINITY;
  for (int r = r0; r < r1; r++)
    for (int c = c0; c < c1; c++) {
      double h0 = edge2(v, r, c, r, c + 1), h1 = edge2(v, r + 1, c, r + 1, c + 1);
      double v0 = edge2(v, r, c, r + 1, c), v1 = edge2(v, r, c + 1, r + 1, c + 1);
      double hx = px_min(h0, h1), hy = px_min(v0, v1);
      double q = px_max(px_max(h0, h1) / hx, px_max(v0, v1) / hy); /* the change, squared */
      smin2 = px_min(smin2, px_max(hx / (dx * dx), hy / (dy * dy)) / q);
    }
  return smin2 > 0.0 && isfinite(smin2) ? 1.0 / sqrt(smin2) : INFINITY;
}

/* The largest deviation, in pixel intervals of node n (norm_cell), of the biquadratic through the
 * parent's grid lc->pg from the measured quarter lc's five new grid points; INFINITY when a point
 * of either grid did not reach node k along the domain's paths. */
double pt__biquad_deviation(const lattice_cell_t *lc, const cell_norm_t *cn, int k) {
  static const int at[5][2] = {{0, 1}, {1, 0}, {1, 1}, {1, 2}, {2, 1}};
  double d = 0.0;
  /* every point of both grids must have met the node through the domain's paths (a parent can
   * have been cut because some of its points did not: their entries are not this node's) */
  for (int i = 0; i < 9; i++)
    if (!lc->pg[i / 3][i % 3].ok || lc->pg[i / 3][i % 3].g[k].ok != 1 || !lc->g[i / 3][i % 3].ok ||
        lc->g[i / 3][i % 3].g[k].ok != 1)
      return INFINITY;
  for (int m = 0; m < 5; m++) {
    double w[9];
    biquadratic_weights(0.5 * lc->qx + 0.25 * at[m][1], 0.5 * lc->qy + 0.25 * at[m][0], w);
    px_vec3_t b = {0, 0, 0};
    for (int i = 0; i < 9; i++)
      b = px_v3_axpy(w[i], lc->pg[i / 3][i % 3].g[k].p, b);
    d = px_max(d, norm_cell(cn, px_v3_sub(lc->g[at[m][0]][at[m][1]].g[k].p, b)));
  }
  return d;
}

/* The deviations of a 3 x 3 grid's five non-corner points from the bilinear interpolation of
 * its corners, measured by `norm`: top, bottom, left, right edge midpoints, centre. */
static void grid_deviations(const grid3_t *G, double (*norm)(const void *, px_vec3_t),
                            const void *ctx, double d[5]) {
  const px_vec3_t(*v)[3] = G->v;
  for (int r = 0; r < 3; r += 2) /* top and bottom edges; left and right edges */
    d[r / 2] = norm(ctx, px_v3_sub(v[r][1], px_v3_scale(px_v3_add(v[r][0], v[r][2]), 0.5)));
  for (int c = 0; c < 3; c += 2)
    d[2 + c / 2] = norm(ctx, px_v3_sub(v[1][c], px_v3_scale(px_v3_add(v[0][c], v[2][c]), 0.5)));
  px_vec3_t m =
      px_v3_scale(px_v3_add(px_v3_add(v[0][0], v[0][2]), px_v3_add(v[2][0], v[2][2])), 0.25);
  d[4] = norm(ctx, px_v3_sub(v[1][1], m));
}

/* Interpolation error of a lattice cell from its grid values G, as a vector measured by `norm`:
 *   measured: the largest deviation of an edge midpoint from the mean of its edge's ends, or of
 *             the centre from the mean of the corners (the bilinear interpolation there);
 *   estimated (quarter (qx, qy) of G): e_int, |x_a - 2 x_b + x_c| / 8 along each of the
 *             quarter's two horizontal grid lines (the larger) plus the same vertically. */
double pt__grid_error(const lattice_cell_t *lc, const grid3_t *G,
                      double (*norm)(const void *, px_vec3_t), const void *ctx) {
  const px_vec3_t(*v)[3] = G->v;
  if (lc->measured) {
    double d[5];
    grid_deviations(G, norm, ctx, d);
    return px_max(px_max(px_max(d[0], d[1]), px_max(d[2], d[3])), d[4]);
  }
  double ex = 0.0, ey = 0.0;
  for (int e = 0; e < 2; e++) {
    int r = lc->qy + e, c = lc->qx + e;
    ex = px_max(ex, norm(ctx, px_v3_add(px_v3_sub(v[r][0], px_v3_scale(v[r][1], 2.0)), v[r][2])));
    ey = px_max(ey, norm(ctx, px_v3_add(px_v3_sub(v[0][c], px_v3_scale(v[1][c], 2.0)), v[2][c])));
  }
  return (ex + ey) / 8.0;
}

/* Certified mode, a measured lattice cell lc whose largest deviation times PT_BILINEAR_CERT is too
 * much: the biquadratic part of its bilinear error at its own samples, sum_i |d_i| |L_i(u, v)| over
 * the five non-corner grid points (d_i in node n's pixel intervals), largest over the samples.
 * The basis is separable: L_i(u, v) = l_c(u) l_r(v) for grid column c and row r. */
double pt__bilinear_bound_at_samples(const pt_ctx_t *C, const lattice_cell_t *lc, const grid3_t *G,
                                     const cell_norm_t *cn) {
  double d[5];
  grid_deviations(G, norm_cell, cn, d);
  double dt = d[0], db = d[1], dl = d[2], dr = d[3], dc = d[4];
  int s = C->opt->spp_side, gx0, gx1, gy0, gy1;
  sample_range(lc->x0, lc->w, s, &gx0, &gx1);
  sample_range(lc->y0, lc->h, s, &gy0, &gy1);
  double worst = 0.0;
  for (int gy = gy0; gy < gy1; gy++) {
    double lv[3];
    lagrange3(((gy + 0.5) / s - lc->y0) / lc->h, lv);
    double row = dt * fabs(lv[0]) + db * fabs(lv[2]) + dc * fabs(lv[1]), col = fabs(lv[1]);
    for (int gx = gx0; gx < gx1; gx++) {
      double lu[3];
      lagrange3(((gx + 0.5) / s - lc->x0) / lc->w, lu);
      worst = px_max(worst, fabs(lu[1]) * row + col * (dl * fabs(lu[0]) + dr * fabs(lu[2])));
    }
  }
  return worst;
}

/* A bound on node k's brightness W_k direct_k over lattice cell lc, whatever hides the lights from
 * part of it. rt_shade_direct() adds to the ambient term ka Ia color, for each light, at most I_l
 * (kd color + ks): the cosine, the transmittance and the Phong factor are at most 1, and lights
 * have no fall-off; a light with the inverse-square fall-off has no such bound without the
 * surface's distance, so with one the bound is infinite and no node counts as faint; a caustic
 * receiver adds kd colour times its maps' largest E. W_k is taken
 * at its largest over the grid plus its interpolation error there (its largest between the points).
 * Such a node's brightness at a sample, and its bilinear interpolation from the lattice cell's
 * corners, both lie between 0 and this bound: a node faint enough (a board seen after several
 * internal reflections in the glass ball, W_k about 5e-4) may be interpolated across a shadow edge,
 * its error counted against the brightness tolerance, instead of being shaded per sample with a
 * shadow ray. */
double pt__faint_bound(const pt_ctx_t *C, const lattice_cell_t *lc, const lattice_point_t (*R)[3],
                       int k) {
  const rt_scene_t *s = C->s;
  const pt_node_t *n = &C->paths.node[k];
  const rt_object_t *o = &s->object[n->object];
  grid3_t w;
  double wmax = 0.0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      w.v[r][c] = rgb_vec(R[r][c].g[k].w);
      wmax = px_max(wmax, norm_rgb(NULL, w.v[r][c]));
    }
  wmax += pt__grid_error(lc, &w, norm_rgb, NULL);
  int spec = rt_plan_has(C->plan, RT_EFFECT_SPECULAR);
  double dmax = 0.0;
  for (int m = 0; m < (n->textured ? 2 : 1); m++) {
    const rt_material_t *mt = &s->material[m ? o->material2 : o->material];
    double d = mt->ka * norm_rgb(NULL, rgb_vec(rt_rgb_mul(s->ambient, mt->color)));
    double lit = mt->kd * norm_rgb(NULL, rgb_vec(mt->color)) + (spec ? mt->ks : 0.0);
    for (int l = 0; l < s->nlight && lit > 0.0; l++) {
      d += s->light[l].falloff != RT_FALLOFF_NONE
               ? INFINITY
               : norm_rgb(NULL, rgb_vec(s->light[l].intensity)) * lit;
      const rt_caustic_map_t *cm =
          C->plan->maps ? rt_caustic_map_of(C->plan->maps, n->object, l) : NULL;
      if (cm) /* a caustic map's kd colour E (a parallel light's; a point light's is infinite) */
        d += cm->emax * mt->kd * norm_rgb(NULL, rgb_vec(mt->color));
    }
    dmax = px_max(dmax, d);
  }
  return wmax > 0.0 ? wmax * dmax : 0.0;
}

/* With a Fresnel split (C->weights_vary) a node's weight W_k varies over the lattice cell, and a
 * node shaded per sample takes the bilinear interpolation of the corners' W_k: its error is W_k's
 * own interpolation error times the node's unweighted brightness (direct_k, both materials of a
 * checkerboard; a miss node's background), at most. Without it W_k is constant over a lattice cell
 * whose points reached the same nodes, and this is 0. (The children a node traces exactly per
 * sample take that W_k too: pt__subtree_weight_error() bounds theirs.) */
double pt__weight_error(const pt_ctx_t *C, const lattice_cell_t *lc, const lattice_point_t (*R)[3],
                        int k) {
  if (!C->weights_vary)
    return 0.0;
  grid3_t w;
  double dmax = 0.0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      const pt_geom_t *g = &R[r][c].g[k];
      w.v[r][c] = rgb_vec(g->w);
      const double wc[3] = {g->w.r, g->w.g, g->w.b};
      const rt_rgb_t *ls[3] = {&g->l, &g->lt[0], &g->lt[1]};
      for (int i = 0; i < (C->paths.node[k].textured ? 3 : 1); i++) {
        const double light[3] = {ls[i]->r, ls[i]->g, ls[i]->b};
        for (int ch = 0; ch < 3; ch++)
          if (wc[ch] > 0.0)
            dmax = px_max(dmax, fabs(light[ch]) / wc[ch]);
      }
    }
  return pt__grid_error(lc, &w, norm_rgb, NULL) * dmax;
}

/* With a Fresnel split: the error of node k's weight W_k interpolated over lattice cell lc (the
 * grid's interpolation error of W_k) times a bound on what the node and its subtree bring
 * unweighted (from its children down when `below`): the larger of the background (a miss) and
 * the largest direct term of any material, D (as pt__faint_bound() bounds a node's, with the
 * caustic maps' largest value per light as a receiver's kd colour E), once for
 * each level from the node's depth (its children's, depth + 1, when `below`) to the depth limit,
 * a level's weights at most g = max(1, kr + kt max(1, T)) of the level above (a total internal
 * reflection hands the mirror child kt untinted, refract.c). Near a total internal reflection at
 * an ancestor W_k rises steeply to the whole share (F -> 1 as the angle nears the critical one),
 * which a bilinear interpolation misses, and the subtree a node traces per sample takes the
 * interpolated W_k, unseen by the brightness test (docs/journal/2026-12-06-self-crossing.md,
 * docs/journal/2026-12-06-weight-below.md). */
double pt__subtree_weight_error(const pt_ctx_t *C, const lattice_cell_t *lc,
                                const lattice_point_t (*R)[3], int k, int below) {
  const rt_scene_t *s = C->s;
  const int depth = C->paths.node[k].depth;
  if (below && depth >= C->plan->max_depth)
    return 0.0; /* no level below */
  grid3_t w;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      w.v[r][c] = rgb_vec(R[r][c].g[k].w);
  double e = pt__grid_error(lc, &w, norm_rgb, NULL);
  if (e == 0.0)
    return 0.0;
  if (!(e > 0.0))
    return INFINITY; /* a NaN error is never accepted */
  int spec = rt_plan_has(C->plan, RT_EFFECT_SPECULAR);
  double d = norm_rgb(NULL, rgb_vec(s->background)), g = 1.0, ce = 0.0;
  const rt_caustic_maps_t *maps = C->plan->maps;
  for (int l = 0; maps && l < s->nlight; l++) { /* a receiver's kd colour E, per light at most */
    double el = 0.0;                            /* the largest of light l's maps */
    for (int i = 0; i < maps->n; i++)
      el = maps->map[i].light == l ? px_max(el, maps->map[i].emax) : el;
    ce += el;
  }
  for (int m = 0; m < s->nmaterial; m++) {
    const rt_material_t *mt = &s->material[m];
    double dm = mt->ka * norm_rgb(NULL, rgb_vec(rt_rgb_mul(s->ambient, mt->color)));
    double lit = mt->kd * norm_rgb(NULL, rgb_vec(mt->color)) + (spec ? mt->ks : 0.0);
    for (int l = 0; l < s->nlight && lit > 0.0; l++)
      dm += s->light[l].falloff != RT_FALLOFF_NONE
                ? INFINITY
                : norm_rgb(NULL, rgb_vec(s->light[l].intensity)) * lit;
    dm += ce * mt->kd * norm_rgb(NULL, rgb_vec(mt->color));
    d = px_max(d, dm);
    double t = px_max(px_max(mt->transmittance.r, mt->transmittance.g), mt->transmittance.b);
    g = px_max(g, mt->kr + mt->kt * px_max(1.0, t));
  }
  double sub = 0.0, gl = below ? g : 1.0;
  for (int lv = depth + (below ? 1 : 0); lv <= C->plan->max_depth; lv++, gl *= g)
    sub += d * gl;
  return e * sub;
}

/* Certified mode: whether halving measured lattice cell lc, across its columns (1: left and right
 * halves) or its rows (2: top and bottom), would make every node's hits interpolable; 0 when
 * neither would. A lattice cell whose nodes are too curved to interpolate is cut into quarters, and
 * in certified mode every quarter is measured: up to 16 new points. A half takes 3. Most such
 * lattice cells in Fig. 8 are curved in one direction (the board seen through the glass ball is
 * compressed vertically): a bilinear interpolation's error is A u(1-u) + B v(1-v), the top and
 * bottom edge midpoints measure A / 4 and the left and right ones B / 4, so halving across the
 * columns leaves about A / 16 + B / 4 at the halves' centres (across the rows A / 4 + B / 16).
 * The halves are measured, so their plans test their own errors. In default mode quarters are
 * first estimated from the parent's grid (e_int) at no cost, and halving did not pay there
 * (docs/tuning.md). */
int pt__halving(const pt_ctx_t *C, const lattice_cell_t *lc, double rho, double xi2) {
  const lattice_point_t(*R)[3] = grid_of(lc);
  const uint8_t *exact_subtree = C->lattice.plan.exact_subtree;
  double f = C->opt->certified ? PT_BILINEAR_CERT : 1.0;
  int okx = 1, oky = 1;
  double ex = 0.0, ey = 0.0;
  for (int k = 0; k < C->paths.n && (okx || oky); k++) {
    const pt_node_t *n = &C->paths.node[k];
    if (exact_subtree[k] || n->miss)
      continue;
    int reached, exact;
    reach(R, k, &reached, &exact);
    if (reached == 0 || exact == 9)
      continue;
    if (reached != 9 || exact != 0)
      return 0;
    grid3_t p;
    hits_of(R, k, &p);
    cell_norm_t cn = {n, pt__cell_scale(lc, &p)};
    double e_mat = matrix_error(n, xi2, cn.inv_s);
    double d[5];
    grid_deviations(&p, norm_cell, &cn, d);
    double eu = px_max(d[0], d[1]), ev = px_max(d[2], d[3]);
    double hx = f * (eu / 4.0 + ev) + e_mat, hy = f * (eu + ev / 4.0) + e_mat;
    okx = okx && hx <= rho;
    oky = oky && hy <= rho;
    ex = px_max(ex, hx);
    ey = px_max(ey, hy);
  }
  if (okx && oky)
    return ex <= ey ? 1 : 2;
  return okx ? 1 : oky ? 2 : 0;
}
