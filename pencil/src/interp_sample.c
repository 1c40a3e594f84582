/* interp_sample.c -- the samples of an accepted lattice cell (paper section 4.1 (2): "the
 * intersection point and the direction of an interior paraxial ray are linearly interpolated"):
 * each sample's hits and brightness interpolated from the lattice cell's corners (bilinear weights,
 * or biquadratic ones over its 3 x 3 grid), its per-sample nodes shaded at their interpolated hits,
 * certified mode's check that an interpolated miss still meets no unbounded plane, and the loop
 * over one pixel's samples in a lattice cell. */
#include <math.h>

#include "interp.h"

/* Parity of the checker square of textured leaf k at the interpolation with weights w. */
static int leaf_parity(const pt_eval_t *E, int k, const double w[4]) {
  const pt_geom_t *g0 = &E->corner[0][k], *g1 = &E->corner[1][k], *g2 = &E->corner[2][k],
                  *g3 = &E->corner[3][k];
  px_vec3_t p = px_v3_axpy(
      w[0], g0->p, px_v3_axpy(w[1], g1->p, px_v3_axpy(w[2], g2->p, px_v3_scale(g3->p, w[3]))));
  if (E->biquadratic && E->biquadratic[k]) { /* biquadratic (E->grid_w) */
    p = (px_vec3_t){0, 0, 0};
    for (int i = 0; i < 9; i++)
      p = px_v3_axpy(E->grid_w[i], E->grid[i][k].p, p);
  }
  const rt_plane_t *pl0 = &E->C->s->prim[E->C->paths.node[k].prim].plane;
  double u, v;
  rt_plane_coords(pl0, p, &u, &v);
  return (int)fmod(fabs(floor(u * pl0->inv_check) + floor(v * pl0->inv_check)), 2.0);
}

/* The nodes of an interpolated sample with weights w that are shaded per sample. */
static rt_rgb_t interp_local(pt_eval_t *E, const interp_plan_t *pl, const double w[4]) {
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  E->corner_w = w;
  for (int m = 0; m < pl->nshaded; m++) {
    int k = pl->shaded[m];
    rt_rgb_t wk =
        rgb_lerp4(w, E->corner[0][k].w, E->corner[1][k].w, E->corner[2][k].w, E->corner[3][k].w);
    sum = rt_rgb_add(sum, pt__eval_local(E, k, wk, pl->shaded_direct[m], pl->shaded_exact[m]));
  }
  return sum;
}

/* One interpolated sample with weights w (E->corner holds the lattice cell's corners). */
static rt_rgb_t interp_sample(pt_eval_t *E, const interp_plan_t *pl, const double w[4]) {
  const rt_rgb_t *c = pl->linear_corners;
  E->corner_w = w;
  rt_rgb_t sum = rgb_lerp4(w, c[0], c[1], c[2], c[3]);
  for (int m = 0; m < pl->nleaves; m++) { /* textured leaves: the material of the sample's square */
    int k = pl->leaves[m], par = leaf_parity(E, k, w);
    sum = rt_rgb_add(sum, rgb_lerp4(w, E->corner[0][k].lt[par], E->corner[1][k].lt[par],
                                    E->corner[2][k].lt[par], E->corner[3][k].lt[par]));
  }
  return rt_rgb_add(sum, interp_local(E, pl, w));
}

/* Whether node k is a miss whose ray an interpolated sample takes from the lattice cell's corners
 * E->corner: computed by the pencil at all four (ok == 1) and not in a subtree traced exactly per
 * sample (C->lattice.plan.exact_subtree). Only then are the corners' rays defined: a node a lattice
 * point did not reach keeps whatever its storage held before. */
static int interpolated_miss(const pt_ctx_t *C, const pt_eval_t *E, int k) {
  if (!C->paths.node[k].miss || (E->exact_subtree && E->exact_subtree[k]))
    return 0;
  for (int i = 0; i < 4; i++)
    if (E->corner[i][k].ok != 1)
      return 0;
  return 1;
}

/* Certified mode: whether every miss node of an interpolated sample still meets no unbounded
 * plane (its ray interpolated from the lattice cell's corners): a horizon can cross a lattice cell
 * between its corners. Bounded objects were checked by intersecting the rays of the lattice points
 * with the scene (eval.c); between those points they are not. */
static int misses_nothing(const pt_ctx_t *C, const pt_eval_t *E, const double w[4]) {
  const rt_scene_t *s = C->s;
  for (int k = 0; k < C->paths.n; k++) {
    const pt_geom_t *a = &E->corner[0][k], *b = &E->corner[1][k], *c = &E->corner[2][k],
                    *e = &E->corner[3][k];
    if (!interpolated_miss(C, E, k))
      continue;
    px_vec3_t o = px_v3_axpy(
        w[0], a->p, px_v3_axpy(w[1], b->p, px_v3_axpy(w[2], c->p, px_v3_scale(e->p, w[3]))));
    px_vec3_t d = px_v3_axpy(
        w[0], a->d, px_v3_axpy(w[1], b->d, px_v3_axpy(w[2], c->d, px_v3_scale(e->d, w[3]))));
    for (int u = 0; u < s->nunbounded; u++) {
      const rt_prim_t *pr = &s->prim[s->unbounded[u]];
      if (pr->kind != RT_PRIM_PLANE)
        continue;
      double side = px_v3_dot(pr->plane.n, px_v3_sub(o, pr->plane.p)),
             towards = px_v3_dot(pr->plane.n, d);
      if (side * towards < 0.0)
        return 0; /* heads for the plane from its side: it would meet it */
    }
  }
  return 1;
}

/* Certified mode: whether misses_nothing() holds for every sample of the lattice cell whose corners
 * are E->corner. side and towards are bilinear in the sample's weights (the ray's origin and its
 * unnormalised direction are interpolated), so they take their extremes at the corners: when the
 * corners agree in sign (with a margin for rounding), so do all the samples. */
int pt__misses_nothing_anywhere(const pt_ctx_t *C, const pt_eval_t *E) {
  const rt_scene_t *s = C->s;
  for (int k = 0; k < C->paths.n; k++) {
    if (!interpolated_miss(C, E, k))
      continue;
    for (int u = 0; u < s->nunbounded; u++) {
      const rt_prim_t *pr = &s->prim[s->unbounded[u]];
      if (pr->kind != RT_PRIM_PLANE)
        continue;
      int pos = 1, neg = 1;
      for (int i = 0; i < 4; i++) {
        const pt_geom_t *g = &E->corner[i][k];
        px_vec3_t r = px_v3_sub(g->p, pr->plane.p);
        double side = px_v3_dot(pr->plane.n, r), towards = px_v3_dot(pr->plane.n, g->d);
        double eps = 1e-9 * (1.0 + px_v3_norm(g->p) + px_v3_norm(pr->plane.p));
        pos = pos && side > eps && towards >= 0.0;
        neg = neg && side < -eps && towards <= 0.0;
      }
      if (!pos && !neg)
        return 0;
    }
  }
  return 1;
}

/* The samples a pixel's loop below visits, numbered in its order (b outer, a inner). */
typedef struct {
  const sampling_t *S;
  const pixel_t *P;
  int a0, a1, b0, count;
  int g0; /* the first sample of the current group (C->sample.group), -1 before the first */
} samples_t;

/* Start the evaluation of sample number idx of the loop, at (x, y): its flags cleared, and its own
 * xi and primary ray when its traced nodes or its exact spawn hits need them. With opt->simd the
 * samples' exact walks are carried in groups of four (eval.c's exact_geom4()): the group of the
 * next four samples from idx on begins where idx is not in the current one (a sample that
 * left for the matrices is skipped, so a group can hold one that is not evaluated). */
static void sample_start(pt_ctx_t *C, pt_eval_t *E, samples_t *L, int idx, double x, double y) {
  E->partial = E->fallback = E->traced_failed = E->spawnfail = 0;
  E->grouped = 0;
  if (!(E->traced || E->exact_spawn))
    return;
  E->stamp = ++C->sample.stamp;
  if (!C->opt->simd) {
    pt__xi_of(C, E, x, y);
    return;
  }
  pt_group_t *G = &C->sample.group;
  if (L->g0 < 0 || idx < L->g0 || idx >= L->g0 + G->n) {
    L->g0 = idx;
    G->n = L->count - idx < 4 ? L->count - idx : 4;
    G->stamp++;
    G->stamp += !G->stamp; /* 0 is no group */
    int w = L->a1 - L->a0;
    for (int i = 0; i < G->n; i++) {
      int a = L->a0 + (idx + i) % w, b = L->b0 + (idx + i) / w;
      pt__xi_of(C, E, L->P->i + L->S->off[a], L->P->j + L->S->off[b]);
      G->primary[i] = E->primary;
      G->xi[i][0] = E->xi[0];
      G->xi[i][1] = E->xi[1];
    }
    pt__group_rays(G);
  }
  E->grouped = 1;
  E->lane = idx - L->g0;
  E->primary = G->primary[E->lane];
  E->xi[0] = G->xi[E->lane][0];
  E->xi[1] = G->xi[E->lane][1];
}

/* The samples a in [a0, a1), b in [b0, b1) of pixel P inside lattice cell lc: interpolated (S), or
 * through the matrices when S is NULL (*why counts them). */
void pt__pixel_samples(pt_ctx_t *C, pixel_t *P, sampling_t *S, int why, int a0, int a1, int b0,
                       int b1) {
  int count = (a1 - a0) * (b1 - b0);
  uint64_t r0 = pt__rays_now(C);
  if (!S) {
    C->st.matrix_samples[why] += (uint64_t)count;
    for (int b = b0; b < b1; b++)
      for (int a = a0; a < a1; a++)
        pt__matrix_sample(C, P, a, b);
    P->rays += pt__rays_now(C) - r0;
    return;
  }
  const lattice_cell_t *lc = S->lc;
  pt_eval_t *E = &S->E;
  int cert = C->opt->certified && !S->safe, summed = S->summed, partial = 0;
  for (int b = b0; b < b1 && summed && cert; b++)
    for (int a = a0; a < a1 && summed; a++) {
      double w[4];
      bilinear_weights(sample_u(S, P->i, a), sample_v(S, P->j, b), w);
      summed = misses_nothing(C, E, w);
    }
  int local = summed && S->pl->nshaded > 0; /* the per-sample nodes on top of the summed rest */
  if (summed) {
    P->sum = rt_rgb_add(P->sum, pt__pixel_sum(S, P, a0, a1, b0, b1));
    P->n[PT_METHOD_INTERP] += count;
    C->st.lerp_samples += local ? 0u : (uint64_t)count;
  }
  samples_t L = {S, P, a0, a1, b0, count, -1};
  for (int b = b0; b < b1 && !(summed && !local && !C->opt->measure); b++)
    for (int a = a0; a < a1; a++) {
      int idx = (b - b0) * (a1 - a0) + (a - a0);
      double x = P->i + S->off[a], y = P->j + S->off[b], w[4];
      double qu = (x - lc->x0) * S->inv_w, qv = (y - lc->y0) * S->inv_h;
      bilinear_weights(qu, qv, w);
      if (E->biquadratic)
        grid_weights(S, qu, qv, E->grid_w);
      if (local) {
        sample_start(C, E, &L, idx, x, y);
        rt_rgb_t v = interp_local(E, S->pl, w);
        if (E->traced_failed) { /* take the sample's summed part back: the whole sample by matrices
                                 */
          rt_rgb_t f = pt__summed_sample(S, qu, qv);
          P->sum = rt_rgb(P->sum.r - f.r, P->sum.g - f.g, P->sum.b - f.b);
          P->n[PT_METHOD_INTERP]--;
          pt__matrix_sample(C, P, a, b);
          continue;
        }
        P->sum = rt_rgb_add(P->sum, v);
        partial |= E->partial;
        C->st.fallbacks += (uint64_t)E->fallback;
      }
      if (!summed) {
        if (cert && !misses_nothing(C, E, w)) {
          pt__matrix_sample(C, P, a, b);
          continue;
        }
        sample_start(C, E, &L, idx, x, y);
        rt_rgb_t v = interp_sample(E, S->pl, w);
        if (E->traced_failed) { /* a traced node's ray left its path: the whole sample by matrices
                                 */
          pt__matrix_sample(C, P, a, b);
          continue;
        }
        P->sum = rt_rgb_add(P->sum, v);
        P->n[PT_METHOD_INTERP]++;
        partial |= E->partial;
        C->st.fallbacks += (uint64_t)E->fallback;
      }
      if (C->opt->measure) {
        E->corner_w = w;
        pt__geometry(C, E);
        E->corner_w = NULL;
        rt_ray_t r = rt_view_ray(C->view, x, y, C->s->ior);
        P->pmax = pt__measure_sample(C, &r, C->sample.geom, P->i, P->j, a, b, P->pmax);
      }
    }
  E->grouped = 0; /* S->E is evaluated elsewhere too: the group is this loop's */
  C->st.partial += (uint64_t)partial;
  P->rays += pt__rays_now(C) - r0;
}
