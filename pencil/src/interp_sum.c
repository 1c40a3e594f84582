/* interp_sum.c -- a pixel's samples summed in closed form (paper section 4.1 (2), with the
 * brightness linear over a lattice cell): the sum of the bilinear interpolations of a pixel's
 * samples is the bilinear form with the summed (separable) weights, and a textured leaf adds its
 * two materials' brightness with the weights of the samples on each, counted per row where a
 * checker square edge crosses the pixel. The same sum as visiting each sample. */
#include <math.h>
#include <stdint.h>

#include "interp.h"

void pt__sampling_begin(pt_ctx_t *C, const lattice_cell_t *lc, const interp_plan_t *pl,
                        sampling_t *S) {
  S->lc = lc;
  S->pl = pl;
  int s = C->opt->spp_side;
  for (int a = 0; a < s; a++)
    S->off[a] = (a + 0.5) / s;
  S->inv_w = 1.0 / lc->w;
  S->inv_h = 1.0 / lc->h;
  S->E = (pt_eval_t){.C = C,
                     .mode = PT_EV_INTERP,
                     .shade = 1,
                     .exact_subtree = C->lattice.plan.exact_subtree,
                     .spec_lin = pl->nspectral ? C->lattice.plan.spec_lin : NULL,
                     .traced = pl->ntraced ? C->lattice.plan.traced : NULL};
  S->E.exact_spawn = pt__spawns_exact(&S->E);
  for (int i = 0; i < 4; i++)
    S->E.corner[i] = corner_of(lc, i)->g;
  S->s9 = 1.0;
  S->o9[0] = S->o9[1] = 0.0;
  if (pl->nbiquadratic) { /* measured quarters only: the lattice cell's own grid, certified its
                             parent's */
    int par = C->opt->certified;
    S->E.biquadratic = C->lattice.plan.biquadratic;
    for (int i = 0; i < 9; i++)
      S->E.grid[i] = par ? lc->pg[i / 3][i % 3].g : lc->g[i / 3][i % 3].g;
    if (par) {
      S->s9 = 0.5;
      S->o9[0] = 0.5 * lc->qx;
      S->o9[1] = 0.5 * lc->qy;
    }
  }
  S->summed = pl->nleaves <= PT_SUMMED_LEAVES;
  S->safe = !C->opt->certified || pt__misses_nothing_anywhere(C, &S->E);
  for (int m = 0; m < pl->nleaves && S->summed; m++) {
    int k = pl->leaves[m], q2 = pl->nbiquadratic && C->lattice.plan.biquadratic[k];
    const rt_plane_t *bp = &C->s->prim[C->paths.node[k].prim].plane;
    S->biquadratic_leaf[m] = (uint8_t)q2;
    for (int i = 0; i < (q2 ? 9 : 4); i++) {
      px_vec3_t p = q2 ? S->E.grid[i][k].p : S->E.corner[i][k].p;
      rt_plane_coords(bp, p, &S->uv[m][i][0], &S->uv[m][i][1]);
      S->uv[m][i][0] *= bp->inv_check;
      S->uv[m][i][1] *= bp->inv_check;
    }
    for (int t = 0; t < 2 && q2; t++) { /* second differences of the grid; 1.25 bounds the sum
                                           of |Lagrange weights| of three nodes on [0, 1] */
      double cu = 0.0, cv = 0.0;
      const double(*g)[2] = S->uv[m];
      for (int r = 0; r < 3; r++) {
        cu = px_max(cu, fabs(4.0 * (g[3 * r][t] - 2.0 * g[3 * r + 1][t] + g[3 * r + 2][t])));
        cv = px_max(cv, fabs(4.0 * (g[r][t] - 2.0 * g[3 + r][t] + g[6 + r][t])));
      }
      S->curv[m][t][0] = 1.25 * cu;
      S->curv[m][t][1] = 1.25 * cv;
    }
  }
}

/* floor(x), by truncation where that is exact (|x| < 2^52, the usual case: board coordinates in
 * checker squares). Called per sample in pixels that straddle a square edge, where libm's floor
 * was a noticeable share of the render (docs/tuning.md). */
static inline double floor_fast(double x) {
  if (!(fabs(x) < 4503599627370496.0))
    return floor(x);
  double t = (double)(int64_t)x;
  return t > x ? t - 1.0 : t;
}

/* Checker parity of leaf m of the summed path at lattice cell coordinates (u, v) (the board
 * coordinates are affine in the hit point, so interpolating them is interpolating the point). */
static int summed_parity(const sampling_t *S, int m, double u, double v, double sq[2]) {
  const double(*c)[2] = S->uv[m];
  if (S->biquadratic_leaf[m]) {
    double w[9];
    grid_weights(S, u, v, w);
    for (int t = 0; t < 2; t++) {
      double x = 0.0;
      for (int i = 0; i < 9; i++)
        x += w[i] * c[i][t];
      sq[t] = floor_fast(x);
    }
  } else {
    double w[4];
    bilinear_weights(u, v, w);
    for (int t = 0; t < 2; t++)
      sq[t] = floor_fast(w[0] * c[0][t] + w[1] * c[1][t] + w[2] * c[2][t] + w[3] * c[3][t]);
  }
  return (int)((int64_t)(sq[0] + sq[1]) & 1);
}

/* The summed part (linear nodes and textured leaves) of one sample with weights w, as pt__pixel_sum
 * counts it. */
rt_rgb_t pt__summed_sample(const sampling_t *S, double u, double v) {
  const interp_plan_t *pl = S->pl;
  double w[4];
  bilinear_weights(u, v, w);
  rt_rgb_t sum = rgb_lerp4(w, pl->linear_corners[0], pl->linear_corners[1], pl->linear_corners[2],
                           pl->linear_corners[3]);
  for (int m = 0; m < pl->nleaves; m++) {
    const pt_geom_t *g0 = &S->E.corner[0][pl->leaves[m]], *g1 = &S->E.corner[1][pl->leaves[m]],
                    *g2 = &S->E.corner[2][pl->leaves[m]], *g3 = &S->E.corner[3][pl->leaves[m]];
    double sq[2];
    int p = summed_parity(S, m, u, v, sq);
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
rt_rgb_t pt__pixel_sum(const sampling_t *S, const pixel_t *P, int a0, int a1, int b0, int b1) {
  const interp_plan_t *pl = S->pl;
  double su = 0.0, sv = 0.0, na = a1 - a0, nb = b1 - b0;
  for (int a = a0; a < a1; a++)
    su += sample_u(S, P->i, a);
  for (int b = b0; b < b1; b++)
    sv += sample_v(S, P->j, b);
  const double W[4] = {(na - su) * (nb - sv), su * (nb - sv), (na - su) * sv, su * sv};
  rt_rgb_t sum = rgb_lerp4(W, pl->linear_corners[0], pl->linear_corners[1], pl->linear_corners[2],
                           pl->linear_corners[3]);
  double ua = sample_u(S, P->i, a0), ub = sample_u(S, P->i, a1 - 1);
  double va = sample_v(S, P->j, b0), vb = sample_v(S, P->j, b1 - 1);
  for (int m = 0; m < pl->nleaves; m++) {
    const pt_geom_t *g0 = &S->E.corner[0][pl->leaves[m]], *g1 = &S->E.corner[1][pl->leaves[m]],
                    *g2 = &S->E.corner[2][pl->leaves[m]], *g3 = &S->E.corner[3][pl->leaves[m]];
    double sq[2], sq0[2];
    const double ue[4] = {ua, ub, ua, ub}, ve[4] = {va, va, vb, vb};
    int par = summed_parity(S, m, ua, va, sq0), one = 1;
    for (int e = 1; e < 4 && one; e++) {
      summed_parity(S, m, ue[e], ve[e], sq);
      one = sq[0] == sq0[0] && sq[1] == sq0[1];
    }
    if (one && S->biquadratic_leaf[m]) {
      /* a biquadratic leaf's points are not convex combinations of the extreme samples': they
       * deviate from the bilinear interpolation of those by at most (du^2 |f_uu| + dv^2
       * |f_vv|) / 8, so the extreme samples must keep that far from their square's edges */
      for (int t = 0; t < 2 && one; t++) {
        double du = S->s9 * (ub - ua), dv = S->s9 * (vb - va);
        double margin = (du * du * S->curv[m][t][0] + dv * dv * S->curv[m][t][1]) / 8.0;
        for (int e = 0; e < 4 && one; e++) {
          const double(*c)[2] = S->uv[m];
          double w[9], x = 0.0;
          grid_weights(S, ue[e], ve[e], w);
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
    const double(*c)[2] = S->uv[m];
    for (int b = b0; b < b1; b++) {
      double v = sample_v(S, P->j, b), n[2] = {0, 0}, su_p[2] = {0, 0};
      /* a bilinear leaf's board coordinates are linear in u along the row: x = x0 + u dx */
      double x0[2], dx[2];
      for (int t = 0; t < 2; t++) {
        x0[t] = (1 - v) * c[0][t] + v * c[2][t];
        dx[t] = (1 - v) * (c[1][t] - c[0][t]) + v * (c[3][t] - c[2][t]);
      }
      int one_square = 0;
      if (!S->biquadratic_leaf[m]) {
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
        double u = sample_u(S, P->i, a);
        int p;
        if (S->biquadratic_leaf[m]) {
          p = summed_parity(S, m, u, v, sq);
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
