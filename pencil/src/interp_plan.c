/* interp_plan.c -- how a lattice cell's samples are interpolated (paper section 4.1 (2)): per
 * node, whether its hits are interpolated bilinearly, biquadratically or traced per sample, and
 * whether its brightness W_k direct_k is interpolated ("if linearity is assumed for brightness
 * I(x'), the brightness can also be interpolated") or shaded per sample; accepted when every
 * node's interpolation error plus its matrix error (Eq. 4) is within rho (Eq. 3) and the
 * interpolated brightness within the brightness tolerance. The small-object guard on shadows
 * keeps a shadow smaller than the lattice from being interpolated across. */
#include <assert.h>
#include <string.h>

#include "interp.h"

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

/* Node evaluations per sample of own nodes that a quad may spend instead of being cut, in units
 * of the tree's nodes: a cut traces up to 20 points (4 measured quarters) of the whole tree;
 * measured on Fig. 8 at 49 spp (instructions of the render): budget 4: 3.04e9, 8: 2.78e9,
 * 16: 2.58e9, 32: 2.60e9. */
#define PT_OWN_BUDGET 16.0

/* Whether a plan's per-sample work is cheaper than cutting the quad (always when it cannot be
 * cut). */
int pt__own_pays(const pt_ctx_t *C, const lquad_t *q, const plan_t *pl, int can_cut) {
  return !can_cut || pl->own_cost * quad_samples(C, q) <= PT_OWN_BUDGET * C->nnode;
}

/* Whether quad q may be interpolated, and how (see the file comment); on failure *why says
 * what failed. It stops as soon as the per-sample work exceeds what pt__own_pays() allows (the
 * caller cuts such a quad, when it can be cut). */
int pt__make_plan(pt_ctx_t *C, const lquad_t *q, plan_t *pl, int can_cut, int *why) {
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
      double eg = pt__grid_error(q, &p, norm_pixels, n);
      own = !((cert ? PT_BILINEAR_CERT : 1.0) * eg + e_mat <= rho); /* NaN: own */
      if (own && cert && q->measured && eg + e_mat <= rho)          /* the bound at the samples */
        own = !(pt__bilinear_bound_at_samples(C, q, &p, n) + e_mat <= rho);
      /* or biquadratic over a measured quarter (textured nodes: leaves only, whose square is
       * then found per sample) */
      /* (certified: the parent's biquadratic itself, over this quarter, where its deviation
       * from the quarter's five new points - its measured error - is within the margin) */
      int q2 =
          own && q->measured && q->pg && (!n->textured || n->child[0] < 0) &&
          (cert ? PT_BIQUAD_CERT : PT_BIQUAD_FACTOR) * pt__biquad_deviation(q, n, k) + e_mat <= rho;
      if (q2) {
        own = 0;
        C->q2[k] = 1;
        pl->nq2++;
      }
      if (own) { /* cost per sample: a matrix product, or the path traced from the eye */
        C->own[k] = 1;
        pl->nown++;
        pl->own_cost += n->pencil == PT_NODE_PATH ? 1.0 + n->depth : 1.0;
        if (!pt__own_pays(C, q, pl, can_cut)) { /* the caller would cut the quad */
          *why = WHY_ERROR;
          if (cert && q->measured)
            pl->halve = pt__halve_dir(C, q, rho, xi2);
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
        double b = pt__faint_bound(C, q, R, k);
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
      if (!pt__own_pays(C, q, pl, can_cut)) { /* the caller would cut the quad */
        *why = WHY_ERROR;
        return 0;
      }
      pl->k[pl->n] = k;
      pl->direct[pl->n] = (uint8_t)(!smooth && !leaf_texture);
      pl->exact[pl->n++] = (uint8_t)exact_children;
      if (!smooth && !leaf_texture)
        werr += pt__weight_error(C, q, R, k);
    }
  }
  /* brightness: is it linear over the quad? */
  double el = pt__grid_error(q, &sm, norm_rgb, NULL);
  if (pl->nt)
    el += pt_max(pt__grid_error(q, &t0, norm_rgb, NULL), pt__grid_error(q, &t1, norm_rgb, NULL));
  while (!(el + faint + werr <= ltol)) { /* (a NaN error is never accepted) */
    /* not linear: the node whose own brightness is least linear is shaded per sample at its
     * interpolated hit (as at a shadow edge), while the rest is interpolated; the caller
     * weighs that per-sample work against cutting the quad (pt__own_pays) */
    int best = -1, best_leaf = 0;
    double eb = 0.0;
    for (int m = 0; m < nsm; m++) {
      grid3_t b;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
          b.v[r][c] = rgb_vec(R[r][c].g[sml[m]].l);
      double e = pt__grid_error(q, &b, norm_rgb, NULL);
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
      double e =
          pt_max(pt__grid_error(q, &b0, norm_rgb, NULL), pt__grid_error(q, &b1, norm_rgb, NULL));
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
    werr += pt__weight_error(C, q, R, k);
    if (!pt__own_pays(C, q, pl, can_cut)) { /* the caller would cut the quad */
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
    el = pt__grid_error(q, &sm, norm_rgb, NULL);
    if (pl->nt)
      el += pt_max(pt__grid_error(q, &t0, norm_rgb, NULL), pt__grid_error(q, &t1, norm_rgb, NULL));
  }
  return 1;
}
