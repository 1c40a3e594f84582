/* interp_plan.c -- how a lattice cell's samples are interpolated (paper section 4.1 (2)): per
 * node, whether its hits are interpolated bilinearly, biquadratically or traced per sample, and
 * whether its brightness W_k direct_k is interpolated ("if linearity is assumed for brightness
 * I(x'), the brightness can also be interpolated") or shaded per sample; accepted when every
 * node's interpolation error plus its matrix error (Eqs. 4-6) is within the tolerance of Eq. (3)
 * (rho pixel intervals) and the interpolated brightness within the brightness tolerance. The
 * small-object guard on shadows keeps a shadow smaller than the lattice from being interpolated
 * across. */
#include <assert.h>
#include <string.h>

#include "interp.h"

/* Whether node k's shadow rays found the same lights unblocked and the same fully blocked at
 * the nine points of grid R. */
static int same_visibility(const lattice_point_t (*R)[3], int k) {
  const pt_geom_t *b = &R[0][0].g[k];
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      if (R[r][c].g[k].lit != b->lit || R[r][c].g[k].dark != b->dark ||
          R[r][c].g[k].through != b->through)
        return 0;
  return 1;
}

/* The small-object guard on the shadows of node k over a lattice cell's grid R, for the lights
 * whose domain-level guard fired (pt_node_t.light_guard): the grid's points agreeing on a light's
 * visibility do not show that it is the same between them when an object smaller than the
 * pencil of their shadow rays comes near it (its whole shadow could fall between the points).
 * The pencil: the ball about the grid's centre hit through the farthest of its points; the gap:
 * the largest disc that can lie between the points; both grown by half again (domain.c's
 * PT_GUARD_INFLATE). Cutting the lattice cell shrinks them until the guard no longer fires; else
 * the node's direct term is shaded per sample. */
static int shadow_guarded(const pt_ctx_t *C, const lattice_point_t (*R)[3], int k) {
  const pt_node_t *n = &C->paths.node[k];
  px_vec3_t c = R[1][1].g[k].p;
  double r = 0.0, h = 0.0; /* reach from the centre; longest side between neighbouring points */
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      const px_vec3_t p = R[i][j].g[k].p;
      r = fmax(r, px_v3_norm(px_v3_sub(p, c)));
      if (j < 2)
        h = fmax(h, px_v3_norm(px_v3_sub(R[i][j + 1].g[k].p, p)));
      if (i < 2)
        h = fmax(h, px_v3_norm(px_v3_sub(R[i + 1][j].g[k].p, p)));
    }
  /* a disc free of the nine points lies within a grid square: radius at most h / sqrt 2; both
   * grown by half again for the map's curvature between the points */
  r *= 1.5;
  h *= 1.5 / sqrt(2.0);
  const px_vec3_t *plane = C->s->prim[n->prim].kind == RT_PRIM_PLANE ? &n->n : NULL;
  for (int l = 0; l < C->s->nlight && l < 32; l++)
    if ((n->light_guard & (1u << l)) &&
        (pt_guard_shadow(C->guard, c, r, h, plane, &C->s->light[l], n->object) ||
         pt_guard_self_shadow(C->faces, C->s, n->prim, c, r, &C->s->light[l])))
      return 1;
  return 0;
}

/* Node evaluations per sample (traced nodes, nodes shaded per sample) that a lattice cell may
 * spend instead of being cut, in units of the tree's nodes: a cut traces up to 20 points (4
 * measured quarters) of the whole tree. The budget is where the render's cost was lowest among
 * the budgets tried (docs/tuning.md). */
#define PT_PER_SAMPLE_BUDGET 16.0

/* Whether a plan's per-sample work is cheaper than cutting the lattice cell (always when it cannot
 * be cut). */
int pt__per_sample_pays(const pt_ctx_t *C, const lattice_cell_t *lc, const interp_plan_t *pl,
                        int can_cut) {
  return !can_cut || pl->per_sample_cost * samples_in(C, lc) <= PT_PER_SAMPLE_BUDGET * C->paths.n;
}

/* What pt__make_plan() carries from one step to the next for one lattice cell. */
typedef struct {
  pt_ctx_t *C;                   /* the thread's state */
  const lattice_cell_t *lc;      /* the lattice cell */
  const lattice_point_t (*R)[3]; /* the 3 x 3 grid its errors come from (grid_of) */
  interp_plan_t *pl;             /* the plan being made */
  int can_cut;  /* the caller can cut the lattice cell instead (pt__per_sample_pays) */
  int cert;     /* certified mode */
  double rho;   /* the share of rho (Eq. 3) the hits' errors may use */
  double ltol;  /* the brightness tolerance */
  double xi2;   /* the largest |xi|^2 of the lattice cell's corners, for the matrix error (Eq. 4) */
  int *linear;  /* the nodes whose brightness is interpolated (C->lattice.plan.linear) ... */
  int nlinear;  /* ... and their number */
  double faint; /* the faint nodes' bounds, summed */
  int *spec;    /* the spectral nodes whose light is interpolated (C->lattice.plan.spec) ... */
  int nspec;    /* ... and their number */
  double werr;  /* the weight errors of the nodes shaded per sample, summed */
} planning_t;

/* Step 1: whether every point of grid R was traced without leaving the domain's paths. */
static int grid_on_paths(const lattice_point_t (*R)[3]) {
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      if (!R[r][c].ok)
        return 0;
  return 1;
}

/* Step 2: the tolerances of lattice cell lc, and an empty plan. */
static void plan_begin(planning_t *P, pt_ctx_t *C, const lattice_cell_t *lc, interp_plan_t *pl,
                       int can_cut) {
  int cert = C->opt->certified;
  *P = (planning_t){.C = C, .lc = lc, .R = grid_of(lc), .pl = pl, .can_cut = can_cut, .cert = cert};
  P->rho = C->opt->rho * (cert ? PT_CERTIFIED_MARGIN : 1.0) * (lc->measured ? 1.0 : PT_EINT_MARGIN);
  P->ltol = C->opt->brightness_tol * (cert ? PT_CERTIFIED_MARGIN : 1.0);
  for (int i = 0; i < 4; i++)
    P->xi2 = px_max(P->xi2, corner_of(lc, i)->xi2);
  P->linear = C->lattice.plan.linear;
  pl->nshaded = pl->nleaves = pl->ntraced = pl->nbiquadratic = pl->nfaint = pl->halve = 0;
  pl->nhighlight = pl->nspectral = 0;
  P->spec = C->lattice.plan.spec;
  pl->per_sample_cost = 0.0;
  for (int i = 0; i < 4; i++)
    pl->linear_corners[i] = rt_rgb(0, 0, 0);
  memset(C->lattice.plan.traced, 0, (size_t)C->paths.n);
  memset(C->lattice.plan.biquadratic, 0, (size_t)C->paths.n);
  memset(C->lattice.plan.faint, 0, (size_t)C->paths.n);
  memset(C->lattice.plan.spec_lin, 0, (size_t)C->paths.n);
}

/* Step 3: a verify node (below an edge the corners saw) that some grid point did not confirm is
 * traced exactly per sample in this lattice cell, with its subtree (C->lattice.plan.exact_subtree).
 * The scene search confirms the node's surface, not its weight: a total internal reflection at an
 * ancestor spawns the same reflected ray as a partial one, with weight kr + kt instead of kr, so a
 * grid that confirms the node everywhere can still straddle that edge. Without a Fresnel split
 * W_k is then the same product of constants at every point on the node's path, bit for bit; a
 * grid whose points' W_k differ is not confirmed either (its interpolated W_k would weight the
 * node's direct term and its children traced exactly per sample). With a Fresnel split W_k varies
 * anyway, steeply near the critical angle: a grid is not confirmed when W_k's interpolation error
 * could carry more than what is left of the brightness tolerance (pt__subtree_weight_error()),
 * and the error of one that is counted against it. */
static void mark_exact_subtrees(planning_t *P) {
  pt_ctx_t *C = P->C;
  const lattice_point_t(*R)[3] = P->R;
  uint8_t *exact = C->lattice.plan.exact_subtree;
  for (int k = 0; k < C->paths.n; k++) {
    const pt_node_t *n = &C->paths.node[k];
    exact[k] = n->parent >= 0 && exact[n->parent];
    for (int r = 0; r < 3 && n->verify && !exact[k]; r++)
      for (int c = 0; c < 3; c++)
        exact[k] |= R[r][c].g[k].ok != 1;
    if (n->verify && !exact[k] && !C->weights_vary) {
      const rt_rgb_t w0 = R[0][0].g[k].w;
      for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
          const rt_rgb_t w = R[r][c].g[k].w;
          exact[k] |= w.r != w0.r || w.g != w0.g || w.b != w0.b;
        }
    }
    if (n->verify && !exact[k] && C->weights_vary) { /* with Fresnel: by the weight's error */
      double e = pt__subtree_weight_error(C, P->lc, R, k, 0);
      if (e <= P->ltol - P->werr)
        P->werr += e; /* within the budget: counted there */
      else
        exact[k] = 1;
    }
  }
}

/* Step 4a, node k's hits: interpolated bilinearly (0), biquadratically over a measured quarter
 * (0, C->lattice.plan.biquadratic set) or, too curved for either, traced per sample (1,
 * C->lattice.plan.traced set); -1 when that per-sample work costs more than cutting the lattice
 * cell (pt__per_sample_pays), with certified mode's halving direction in the plan. */
static int plan_hits(planning_t *P, int k) {
  pt_ctx_t *C = P->C;
  const lattice_cell_t *lc = P->lc;
  const pt_node_t *n = &C->paths.node[k];
  interp_plan_t *pl = P->pl;
  int cert = P->cert;
  double rho = P->rho * n->tol_scale; /* this node's share (the image-space tolerance) */
  grid3_t p;
  hits_of(P->R, k, &p);
  cell_norm_t cn = {n, pt__cell_scale(lc, &p)};
  double e_mat = matrix_error(n, P->xi2, cn.inv_s);
  double eg = pt__grid_error(lc, &p, norm_cell, &cn);
  int traced = !((cert ? PT_BILINEAR_CERT : 1.0) * eg + e_mat <= rho); /* NaN: traced */
  if (traced && cert && lc->measured && eg + e_mat <= rho) /* the bound at the samples */
    traced = !(pt__bilinear_bound_at_samples(C, lc, &p, &cn) + e_mat <= rho);
  /* or biquadratic over a measured quarter (textured nodes: leaves only, whose square is then
   * found per sample); certified: the parent's biquadratic itself, over this quarter, where its
   * deviation from the quarter's five new points - its measured error - is within the margin */
  int q2 =
      traced && lc->measured && lc->pg && (!n->textured || n->child[0] < 0) &&
      (cert ? PT_BIQUAD_CERT : PT_BIQUAD_FACTOR) * pt__biquad_deviation(lc, &cn, k) + e_mat <= rho;
  if (q2) {
    traced = 0;
    C->lattice.plan.biquadratic[k] = 1;
    pl->nbiquadratic++;
  }
  if (traced) { /* cost per sample: a matrix product, or the path traced from the eye */
    C->lattice.plan.traced[k] = 1;
    pl->ntraced++;
    pl->per_sample_cost += n->mode == PT_NODE_PATH ? 1.0 + n->depth : 1.0;
    if (!pt__per_sample_pays(C, lc, pl, P->can_cut)) {
      if (cert && lc->measured)
        pl->halve = pt__halving(C, lc, rho, P->xi2);
      return -1;
    }
  }
  return traced;
}

/* Whether textured node k's hits lie in one checker square at the lattice cell's four corners (a
 * node interpolated biquadratically may leave the corners' convex hull: its square is found per
 * sample). 1 for a node that is not textured. */
static int one_square(const planning_t *P, int k) {
  const pt_node_t *n = &P->C->paths.node[k];
  int squares = !(n->textured && P->C->lattice.plan.biquadratic[k]);
  if (n->textured)
    for (int i = 1; i < 4; i++) {
      const pt_geom_t *a = &corner_of(P->lc, i)->g[k], *b = &corner_of(P->lc, 0)->g[k];
      squares = squares && a->su == b->su && a->sv == b->sv && a->su != PT_SQUARE_FAR &&
                a->sv != PT_SQUARE_FAR;
    }
  return squares;
}

/* The caustic guard on node k over a lattice cell's grid R: when the node's surface is a caustic
 * receiver (core/caustics.h), kd colour E of its maps joins its direct term, and E may have a
 * focus or an edge between the grid's points, where the brightness test does not look. The map
 * bounds it: over the cells the grid's points reach (one cell more on each side, bilinear
 * interpolation's reach), E lies between the map's smallest and largest values there, and so do
 * its interpolation from the corners and its value at a sample. When that span, weighted by the
 * node's largest W_k and kd colour, exceeds the share of the brightness tolerance that faint nodes
 * may take, the node's direct term is shaded per sample. */
static int caustic_guarded(const planning_t *P, int k) {
  const pt_ctx_t *C = P->C;
  const rt_caustic_maps_t *maps = C->plan->maps;
  if (!maps)
    return 0;
  const pt_node_t *n = &C->paths.node[k];
  double span = 0.0;
  for (int l = 0; l < C->s->nlight; l++) {
    const rt_caustic_map_t *cm = rt_caustic_map_of(maps, n->object, l);
    if (!cm || !cm->e)
      continue;
    double b[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        px_vec3_t q = px_v3_sub(P->R[r][c].g[k].p, cm->p);
        double u = px_v3_dot(q, cm->u), v = px_v3_dot(q, cm->v);
        b[0] = px_min(b[0], u);
        b[1] = px_max(b[1], u);
        b[2] = px_min(b[2], v);
        b[3] = px_max(b[3], v);
      }
    double lo, hi = rt_caustic_range(cm, b[0], b[1], b[2], b[3], &lo);
    span += hi - lo;
  }
  if (!(span > 0.0))
    return span != 0.0; /* NaN: guarded */
  const rt_object_t *o = &C->s->object[n->object];
  double kd = 0.0, w = 0.0;
  for (int m = 0; m < (n->textured ? 2 : 1); m++) {
    const rt_material_t *mt = &C->s->material[m ? o->material2 : o->material];
    kd = px_max(kd, mt->kd * norm_rgb(NULL, rgb_vec(mt->color)));
  }
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      w = px_max(w, norm_rgb(NULL, rgb_vec(P->R[r][c].g[k].w)));
  return w * kd * span > PT_FAINT_SHARE * P->ltol;
}

/* The smallest dot product of v[1][1] with the grid's vectors v (the cosine of their cone's
 * half-angle about it), and of neighbouring ones (*step: the cosine of the longest step). */
static double cone_cos(px_vec3_t (*v)[3], double *step) {
  double cc = 1.0, cs = 1.0;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      cc = px_min(cc, px_v3_dot(v[r][c], v[1][1]));
      if (c < 2)
        cs = px_min(cs, px_v3_dot(v[r][c], v[r][c + 1]));
      if (r < 2)
        cs = px_min(cs, px_v3_dot(v[r][c], v[r + 1][c]));
    }
  *step = cs;
  return cc;
}

/* Bounds on the angle between unit vectors from its cosine c, without acos: at most
 * 2 tan(angle / 2) (angle_above), at least 2 sin(angle / 2), the chord (angle_below). */
static double angle_above(double c) {
  return c > -1.0 ? 2.0 * sqrt(px_max(0.0, 1.0 - c) / (1.0 + c)) : INFINITY;
}
static double angle_below(double c) {
  return sqrt(px_max(0.0, 2.0 - 2.0 * c));
}

/* The highlight guard on node k over a lattice cell's grid R. Phong's term ks (R.V)^n (shade.c's
 * light_term) peaks where the light's direction L meets the mirror direction m of the arriving
 * ray, in a lobe about 1 / sqrt(n) wide in angle. The brightness test looks at the grid's nine
 * points only: it sees a lobe the grid resolves, but a lobe narrower than the grid's steps in m
 * can lie between the points unseen. So the guard fires where both hold:
 * - the grid does not resolve the lobe: a point of the cell may lie farther than 1 / sqrt(n) in
 *   angle from every grid point (half a grid square's diagonal, from the longest steps of m and L
 *   between neighbouring points, grown by half again as shadow_guarded() grows its pencil);
 * - a peak there may matter: the angle between m and L over the cell is at least the larger of
 *   the centre's angle less the half-angles of the cones of m and L about the centre's (through
 *   the farthest point's), and the grid's least angle less that step; (R.V)^n is at most that
 *   angle's cosine to the n, and its excess over the largest (R.V)^n the grid saw, weighted by
 *   the node's largest W_k, ks and the light's intensity and summed over the lights, exceeds the
 *   share of the brightness tolerance that faint nodes may take.
 * Then the node's direct term is shaded per sample. Lights every grid point found blocked are
 * left to the shadow tests; area lights are shaded per sample anyway. The domain's first step
 * (domain.c's highlight_guard(), pt_node_t.highlight) leaves out the nodes whose highlights cannot
 * matter anywhere in the domain. */
static __attribute__((noinline)) int highlight_guarded(const planning_t *P, int k) {
  const pt_ctx_t *C = P->C;
  const rt_scene_t *s = C->s;
  const pt_node_t *n = &C->paths.node[k];
  const rt_object_t *o = &s->object[n->object];
  const rt_material_t *mt[2] = {&s->material[o->material],
                                n->textured ? &s->material[o->material2] : NULL};
  double ks = 0.0, narrow = 0.0, w = 0.0, in = 0.0; /* largest ks, narrowest lobe's exponent */
  for (int i = 0; i < 2; i++)
    if (mt[i] && mt[i]->ks > 0.0) {
      ks = px_max(ks, mt[i]->ks);
      narrow = px_max(narrow, mt[i]->phong);
    }
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++)
      w = px_max(w, norm_rgb(NULL, rgb_vec(P->R[r][c].g[k].w)));
  for (int l = 0; l < s->nlight; l++) /* with inverse-square fall-off: bounded below */
    in += s->light[l].falloff == RT_FALLOFF_NONE ? norm_rgb(NULL, rgb_vec(s->light[l].intensity))
                                                 : INFINITY;
  double tol = PT_FAINT_SHARE * P->ltol;
  if (!(ks > 0.0) || w * ks * in <= tol)
    return 0; /* no highlight could matter */
  /* first whether the grid resolves the narrowest lobe for every light, from the hits alone:
   * between neighbouring points m turns by at most the arriving rays' turn plus twice the
   * normals' (2 asin(chord / 2r) on a sphere, 0 on a flat surface); L by at most hs / D for a
   * step of hs and a light at least D away */
  const rt_prim_t *pr = &s->prim[n->prim];
  const px_vec3_t pc = P->R[1][1].g[k].p;
  double hs = 0.0, hd = 1.0, reach = 0.0; /* longest step of the hits, of d (its cosine) */
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      const pt_geom_t *g = &P->R[r][c].g[k];
      reach = px_max(reach, px_v3_norm(px_v3_sub(g->p, pc)));
      for (int e = 0; e < 2; e++)
        if (e ? r < 2 : c < 2) {
          const pt_geom_t *h = e ? &P->R[r + 1][c].g[k] : &P->R[r][c + 1].g[k];
          hs = px_max(hs, px_v3_norm(px_v3_sub(h->p, g->p)));
          hd = px_min(hd, px_v3_dot(h->d, g->d));
        }
    }
  reach *= 1.5;
  double turn =
      pr->kind != RT_PRIM_SPHERE ? 0.0 : 2.0 * asin(px_min(1.0, hs / (2.0 * pr->sphere.r)));
  double hl_most = 0.0;
  for (int l = 0; l < s->nlight; l++)
    if (s->light[l].kind == RT_LIGHT_POINT) {
      double dc = px_v3_norm(px_v3_sub(s->light[l].v, pc)) - reach;
      hl_most = px_max(hl_most, dc > 0.0 ? hs / dc : INFINITY);
    }
  if (1.5 * (angle_above(hd) + 2.0 * turn + hl_most) / sqrt(2.0) <= 1.0 / sqrt(narrow))
    return 0;
  /* the mirror directions, their cone about the centre's and their longest step */
  px_vec3_t m[3][3];
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      const pt_geom_t *g = &P->R[r][c].g[k];
      px_vec3_t nu = rt_prim_normal_at(pr, g->p);
      m[r][c] = px_v3_axpy(-2.0 * px_v3_dot(g->d, nu), nu, g->d);
    }
  double hm, tm = 1.5 * angle_above(cone_cos(m, &hm));
  hm = angle_above(hm);
  double span = 0.0, dmin = INFINITY;
  for (int l = 0; l < s->nlight; l++) {
    const rt_light_t *li = &s->light[l];
    if (li->kind == RT_LIGHT_AREA)
      continue;
    int dark = l < PT_MAX_LIGHTS;
    px_vec3_t L[3][3];
    double rv = -1.0; /* the grid's largest R.V */
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        const pt_geom_t *g = &P->R[r][c].g[k];
        dark = dark && (g->dark >> l & 1u);
        if (li->kind == RT_LIGHT_PARALLEL) {
          L[r][c] = px_v3_scale(li->v, -1.0);
        } else {
          px_vec3_t v = px_v3_sub(li->v, g->p);
          double dist = px_v3_norm(v);
          dmin = px_min(dmin, dist);
          L[r][c] = px_v3_scale(v, 1.0 / dist);
        }
        rv = px_max(rv, px_v3_dot(m[r][c], L[r][c]));
      }
    if (dark)
      continue;
    double hl, tl = 1.5 * angle_above(cone_cos(L, &hl));
    double step = 1.5 * (hm + angle_above(hl)) / sqrt(2.0); /* to the nearest grid point */
    double amin =
        px_max(angle_below(px_v3_dot(m[1][1], L[1][1])) - tm - tl, angle_below(rv) - step);
    double li_in = norm_rgb(NULL, rgb_vec(li->intensity));
    if (li->falloff == RT_FALLOFF_INVERSE_SQUARE) {
      double d = dmin - reach; /* the nearest the cell comes to the light */
      li_in = d > 0.0 ? li_in / (d * d) : INFINITY;
    }
    double most = 0.0; /* the larger of the two materials' */
    for (int i = 0; i < 2; i++) {
      if (!mt[i] || !(mt[i]->ks > 0.0) || step * sqrt(mt[i]->phong) <= 1.0)
        continue; /* no highlight, or one the grid resolves */
      double hi = amin <= 0.0 ? 1.0 : amin >= 0.5 * M_PI ? 0.0 : pow(cos(amin), mt[i]->phong);
      double seen = rv > 0.0 ? pow(rv, mt[i]->phong) : 0.0;
      double e = mt[i]->ks * li_in * px_max(hi - seen, 0.0);
      most = e > most || e != e ? e : most; /* NaN kept */
    }
    span += most;
  }
  if (!(span > 0.0))
    return span != 0.0; /* NaN: guarded */
  return w * span > tol;
}

/* Step 4b, node k's brightness: whether it is linear over the lattice cell (every light's
 * visibility agrees at the domain's centre and corners, or at least at the nine points of the grid
 * - the brightness test then checks the shading between - and the small-object guard saw no shadow
 * that may fall between them). If not, a faint node (a textured one only as a leaf) is
 * interpolated across its shadow edge, its bound counted against the tolerance (*faint set). */
static int plan_linear(planning_t *P, int k, int squares, int *faint) {
  pt_ctx_t *C = P->C;
  const pt_node_t *n = &C->paths.node[k];
  /* lights past PT_MAX_LIGHTS have no bit in the trees' or the points' visibility masks: with
   * them nothing says a shadow does not fall between the points */
  int smooth = C->s->nlight <= PT_MAX_LIGHTS &&
               (n->light_agree == ~0u || same_visibility(P->R, k)) &&
               !(n->light_guard && shadow_guarded(C, P->R, k)) && !caustic_guarded(P, k) &&
               !C->plan->area_lights; /* soft shadows: traced per sample, unseen by the lattice */
  if (smooth && n->highlight && highlight_guarded(P, k)) {
    smooth = 0;
    P->pl->nhighlight++;
  }
  *faint = 0;
  if (!smooth && (squares || n->child[0] < 0)) {
    double b = pt__faint_bound(C, P->lc, P->R, k);
    if (P->faint + b <= PT_FAINT_SHARE * P->ltol) {
      P->faint += b;
      smooth = *faint = 1;
      C->lattice.plan.faint[k] = 1;
      P->pl->nfaint++;
    }
  }
  return smooth;
}

/* Step 4b': whether spectral node k's spectral light is interpolated over the lattice cell from
 * its grid's points (pt_geom_t.sp, recorded by eval.c's spectral_record()) instead of traced per
 * sample from each sample's hit. The points' pencils must have met the same surfaces in the same
 * way (one signature at all nine points: the same primitives, sides, checker squares and total
 * internal reflections, no shading by lights, which could put a shadow or a highlight between
 * them), their light must pass the grid error test at the faint nodes' share of the brightness
 * tolerance, and no other primitive may come near the volume their pencils sweep: a thin object
 * between the points' pencils (a slit in front of a screen, which every point misses) would
 * otherwise be interpolated away, as a small object between a domain's corner rays would. Per
 * event, the segments between the points are taken to lie in the box swept from the union of
 * the nine points' origin boxes to the union of their end boxes, each grown by half again about
 * its centre for the pencils' curvature between the points (as shadow_guarded() grows its
 * pencil: a margin, not a bound); only the primitives that event's segments leave and reach
 * (and the other faces of a convex object among them that nothing else enters,
 * rt_object_t.alone) are not tested against it (rt_sweep_meets_others()). The edges of the
 * surfaces met are not guarded: there the light's grid test decides, as for any node. */
static int spectral_interpolable(planning_t *P, int k) {
  pt_ctx_t *C = P->C;
  const lattice_point_t(*R)[3] = P->R;
  const uint64_t sig = R[0][0].g[k].ssig;
  const uint32_t nev = R[0][0].g[k].sp.nev;
  if (!sig || P->cert || !C->opt->spectral_lattice)
    return 0;
  grid3_t ls;
  for (int r = 0; r < 3; r++)
    for (int c = 0; c < 3; c++) {
      if (R[r][c].g[k].ssig != sig || R[r][c].g[k].sp.nev != nev)
        return 0;
      ls.v[r][c] = rgb_vec(R[r][c].g[k].sp.ls);
    }
  if (!(pt__grid_error(P->lc, &ls, norm_rgb, NULL) <= PT_FAINT_SHARE * P->ltol))
    return 0; /* NaN too */
  const pt_spec_event_t *ev = C->lattice.spec.ev;
  for (uint32_t e = 0; e < nev; e++) { /* per event: its segments' sweep */
    double b[12];
    int skip[9 * RT_SPECTRAL_EVENT_PRIMS], nskip = 0;
    for (int a = 0; a < 12; a++)
      b[a] = a % 6 < 3 ? INFINITY : -INFINITY;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        const pt_spec_event_t *x = &ev[R[r][c].g[k].sp.at + e];
        for (int a = 0; a < 12; a++)
          b[a] = a % 6 < 3 ? fmin(b[a], x->box[a]) : fmax(b[a], x->box[a]);
        for (int q = 0; q < RT_SPECTRAL_EVENT_PRIMS && x->prim[q] >= 0; q++)
          skip[nskip++] = x->prim[q];
      }
    for (int h = 0; h < 12; h += 6) /* each box grown by half again about its centre */
      for (int a = 0; a < 3; a++) {
        double m = 0.5 * (b[h + a] + b[h + 3 + a]), d = 0.75 * (b[h + 3 + a] - b[h + a]);
        b[h + a] = m - d;
        b[h + 3 + a] = m + d;
      }
    if (rt_sweep_meets_others(C->s, b, b + 6, skip, nskip))
      return 0;
  }
  return 1;
}

/* Whether a child of node k is traced exactly per sample (the domain's tree marks it exact, or
 * this lattice cell's plan traces it below an edge), or its spectral pencils are. */
static int has_exact_children(const pt_ctx_t *C, int k) {
  const pt_node_t *n = &C->paths.node[k];
  int exact_children = n->spectral && !C->lattice.plan.spec_lin[k]; /* from each sample's hit */
  for (int c = 0; c < 2; c++)
    exact_children |= n->child[c] >= 0 && (C->paths.node[n->child[c]].mode == PT_NODE_EXACT ||
                                           C->lattice.plan.exact_subtree[n->child[c]]);
  return exact_children;
}

/* Step 4c: node k is shaded per sample at its interpolated hits (its direct term when `direct`,
 * its exactly traced children when `exact_children`); 0 when the per-sample work then costs more
 * than cutting the lattice cell, or when, with a Fresnel split, the error of the interpolated W_k
 * that the children traced per sample take, times a bound on what they bring
 * (pt__subtree_weight_error()), exceeds what is left of the brightness tolerance (a verify node's
 * was counted with its own in step 3). */
static int plan_shaded(planning_t *P, int k, int direct, int traced, int exact_children) {
  pt_ctx_t *C = P->C;
  const pt_node_t *n = &C->paths.node[k];
  interp_plan_t *pl = P->pl;
  if (direct && !traced)
    pl->per_sample_cost += 1.0; /* shaded per sample (a shadow edge) */
  if (exact_children)
    for (int c = 0; c < 2; c++)
      pl->per_sample_cost +=
          n->child[c] >= 0 && C->lattice.plan.exact_subtree[n->child[c]] ? 2.0 : 0.0;
  if (!pt__per_sample_pays(C, P->lc, pl, P->can_cut))
    return 0;
  if (exact_children && C->weights_vary && !n->verify) { /* they take the interpolated W_k */
    double e = pt__subtree_weight_error(C, P->lc, P->R, k, 1);
    if (!(e <= P->ltol - P->werr))
      return 0; /* NaN too */
    P->werr += e;
  }
  pl->shaded[pl->nshaded] = k;
  pl->shaded_direct[pl->nshaded] = (uint8_t)direct;
  pl->shaded_exact[pl->nshaded++] = (uint8_t)exact_children;
  if (direct)
    P->werr += pt__weight_error(C, P->lc, P->R, k);
  return 1;
}

/* Step 4, node k of the domain's tree: how its hits and its brightness are interpolated; 0 (and
 * *why) when the lattice cell cannot be interpolated. */
static int plan_node(planning_t *P, int k, int *why) {
  pt_ctx_t *C = P->C;
  interp_plan_t *pl = P->pl;
  int reached, exact;
  if (C->lattice.plan.exact_subtree[k])
    return 1;
  reach(P->R, k, &reached, &exact);
  if (reached == 0 || exact == 9)
    return 1; /* not reached, or traced exactly per sample through its parent */
  if (reached != 9 || exact != 0) {
    *why = WHY_REACH;
    return 0;
  }
  const pt_node_t *n = &C->paths.node[k];
  int smooth = 1, exact_children = 0, leaf_texture = 0, traced = 0, faint = 0;
  *why = WHY_ERROR; /* what any failure below is */
  if (!n->miss) {
    traced = plan_hits(P, k);
    if (traced < 0)
      return 0;
    int squares = one_square(P, k);
    smooth = !traced && plan_linear(P, k, squares, &faint);
    if (n->spectral && spectral_interpolable(P, k)) {
      C->lattice.plan.spec_lin[k] = 1;
      pl->nspectral++;
      P->spec[P->nspec++] = k;
      for (int i = 0; i < 4; i++)
        pl->linear_corners[i] = rt_rgb_add(pl->linear_corners[i], corner_of(P->lc, i)->g[k].sp.ls);
    }
    exact_children = has_exact_children(C, k);
    if (smooth && !squares && !traced) {
      /* the direct term is linear for each material: the sample's square picks one. Children
       * would be weighted by the material too, so only for leaves */
      if (n->child[0] >= 0)
        return 0;
      assert(n->textured); /* only a checkerboard has squares to pick per sample */
      pl->leaves[pl->nleaves++] = k;
      smooth = 0;
      leaf_texture = 1;
    }
  }
  if (smooth && !faint) /* the brightness test: a faint node's error is its bound */
    P->linear[P->nlinear++] = k;
  if (smooth)
    for (int i = 0; i < 4; i++)
      pl->linear_corners[i] = rt_rgb_add(pl->linear_corners[i], corner_of(P->lc, i)->g[k].l);
  if (leaf_texture && !exact_children)
    return 1;
  if (!smooth || exact_children)
    return plan_shaded(P, k, !smooth && !leaf_texture, traced, exact_children);
  return 1;
}

/* The deviation of the brightness interpolated over the lattice cell from the traced one at its
 * grid: that of the linear nodes' sum, plus for the textured leaves whose square changes the larger
 * of their two materials' sums. Leaves whose flag is set in `skip` (when not NULL) are left out
 * of those sums. (pt__make_plan() skips the faint leaves, whose error is their bound, on its first
 * test only, and counts them in its later tests: kept as it was, images being compared bit for
 * bit across this restructuring.) */
static double brightness_error(const planning_t *P, const uint8_t *skip) {
  const lattice_point_t(*R)[3] = P->R;
  const interp_plan_t *pl = P->pl;
  grid3_t sm, t0, t1; /* brightness of the linear nodes; of the textured leaves per material */
  memset(&sm, 0, sizeof sm);
  t0 = t1 = sm;
  for (int j = 0; j < P->nlinear; j++)
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        sm.v[r][c] = px_v3_add(sm.v[r][c], rgb_vec(R[r][c].g[P->linear[j]].l));
  for (int j = 0; j < P->nspec; j++) /* the spectral light interpolated with them */
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        sm.v[r][c] = px_v3_add(sm.v[r][c], rgb_vec(R[r][c].g[P->spec[j]].sp.ls));
  for (int j = 0; j < pl->nleaves; j++)
    for (int r = 0; r < 3 && !(skip && skip[pl->leaves[j]]); r++)
      for (int c = 0; c < 3; c++) {
        t0.v[r][c] = px_v3_add(t0.v[r][c], rgb_vec(R[r][c].g[pl->leaves[j]].lt[0]));
        t1.v[r][c] = px_v3_add(t1.v[r][c], rgb_vec(R[r][c].g[pl->leaves[j]].lt[1]));
      }
  double el = pt__grid_error(P->lc, &sm, norm_rgb, NULL);
  if (pl->nleaves)
    el += px_max(pt__grid_error(P->lc, &t0, norm_rgb, NULL),
                 pt__grid_error(P->lc, &t1, norm_rgb, NULL));
  return el;
}

/* The interpolated node whose own brightness is least linear over the lattice cell: index m into
 * the linear nodes (*leaf 0) or into the plan's textured leaves (*leaf 1, faint ones left out); -1
 * when none deviates. */
static int least_linear(const planning_t *P, int *leaf) {
  const lattice_point_t(*R)[3] = P->R;
  const interp_plan_t *pl = P->pl;
  int best = -1;
  double eb = 0.0;
  *leaf = 0;
  for (int m = 0; m < P->nlinear; m++) {
    grid3_t b;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        b.v[r][c] = rgb_vec(R[r][c].g[P->linear[m]].l);
    double e = pt__grid_error(P->lc, &b, norm_rgb, NULL);
    if (e > eb)
      eb = e, best = m, *leaf = 0;
  }
  for (int m = 0; m < pl->nleaves; m++) {
    grid3_t b0, b1;
    if (P->C->lattice.plan.faint[pl->leaves[m]])
      continue;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) {
        b0.v[r][c] = rgb_vec(R[r][c].g[pl->leaves[m]].lt[0]);
        b1.v[r][c] = rgb_vec(R[r][c].g[pl->leaves[m]].lt[1]);
      }
    double e = px_max(pt__grid_error(P->lc, &b0, norm_rgb, NULL),
                      pt__grid_error(P->lc, &b1, norm_rgb, NULL));
    if (e > eb)
      eb = e, best = m, *leaf = 1;
  }
  return best;
}

/* Step 5b: the brightness of node `best` (least_linear's) is shaded per sample at its
 * interpolated hits (as at a shadow edge) while the rest is interpolated; 0 when that costs more
 * than cutting the lattice cell. */
static int shade_least_linear(planning_t *P, int best, int leaf) {
  pt_ctx_t *C = P->C;
  interp_plan_t *pl = P->pl;
  int k = leaf ? pl->leaves[best] : P->linear[best];
  if (leaf) {
    pl->leaves[best] = pl->leaves[--pl->nleaves];
  } else {
    P->linear[best] = P->linear[--P->nlinear];
    for (int i = 0; i < 4; i++)
      pl->linear_corners[i] =
          rt_rgb_add(pl->linear_corners[i], rt_rgb_scale(corner_of(P->lc, i)->g[k].l, -1.0));
  }
  int m = 0;
  while (m < pl->nshaded && pl->shaded[m] != k)
    m++;
  if (m == pl->nshaded) {
    pl->shaded[pl->nshaded] = k;
    pl->shaded_exact[pl->nshaded++] = 0;
  }
  pl->shaded_direct[m] = 1;
  pl->per_sample_cost += 1.0;
  P->werr += pt__weight_error(C, P->lc, P->R, k);
  return pt__per_sample_pays(C, P->lc, pl, P->can_cut);
}

/* Whether lattice cell lc may be interpolated, and how (see interp.c's comment); on failure *why
 * says what failed. It stops as soon as the per-sample work exceeds what pt__per_sample_pays()
 * allows (the caller cuts such a lattice cell, when it can be cut). The steps: 1 the grid stayed on
 * the domain's paths; 2 tolerances; 3 subtrees traced exactly; 4 per node, its hits (Eqs. 3-4 with
 * the interpolation error), its brightness, its per-sample shading; 5 the brightness
 * interpolated over the lattice cell within the tolerance, shading the least linear nodes per
 * sample until it is. */
int pt__make_plan(pt_ctx_t *C, const lattice_cell_t *lc, interp_plan_t *pl, int can_cut, int *why) {
  if (!grid_on_paths(grid_of(lc))) {
    *why = WHY_LEFT;
    return 0;
  }
  planning_t P;
  plan_begin(&P, C, lc, pl, can_cut);
  mark_exact_subtrees(&P);
  int failed; /* *why is written on failure only */
  for (int k = 0; k < C->paths.n; k++)
    if (!plan_node(&P, k, &failed)) {
      *why = failed;
      return 0;
    }
  /* step 5a: is the brightness linear over the lattice cell? (a NaN error is never accepted) */
  for (double el = brightness_error(&P, C->lattice.plan.faint); !(el + P.faint + P.werr <= P.ltol);
       el = brightness_error(&P, NULL)) {
    int leaf, best = least_linear(&P, &leaf);
    if (best < 0 || !shade_least_linear(&P, best, leaf)) {
      *why = WHY_ERROR;
      return 0;
    }
  }
  return 1;
}
