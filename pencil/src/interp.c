/* interp.c -- ray interpolation (paper section 4.1 (2)) inside an accepted domain: "the
 * intersection point and the direction of an interior paraxial ray are linearly interpolated",
 * with the error estimated by "evaluating first and second order interpolations" using one more
 * ray, and "if linearity is assumed for brightness I(x'), the brightness can also be
 * interpolated".
 *
 * The domain is covered by a quadtree of lattice cells. The root lattice cell is the whole domain:
 * its corners, edge midpoints and centre (a 3 x 3 grid) are traced through the domain's paths
 * (lattice points). A lattice cell whose grid was traced is *measured*: the deviation of each
 * midpoint from the linear interpolation of its edge's ends, and of the centre from the bilinear
 * interpolation of the corners, is the interpolation error itself at those points, and for a
 * second-order map the largest over the lattice cell (the error of bilinear interpolation is
 * A u (1 - u) + B v (1 - v), largest at a midpoint or the centre). A lattice cell that fails is cut
 * into four; each quarter is first judged by the paper's e_int, the second difference along its
 * edges with the third point the parent's grid line beyond it (free: those points are traced),
 * and only when that fails are its own five interior points traced and the quarter measured.
 * Certified mode accepts measured lattice cells only. A lattice cell is accepted when, for every
 * node reached, the interpolation error plus the matrix error at its corners is within rho pixels
 * and the brightness interpolated over it (the sum of its linear nodes) deviates from the traced
 * brightness by at most the brightness tolerance.
 *
 * The samples of an accepted lattice cell are interpolated bilinearly from its four corners, per
 * node: hit point and direction, and the brightness W_k direct_k where it is linear (the same
 * checker square at the four corners, every light's visibility agreeing over the domain; a textured
 * leaf whose square changes across the lattice cell takes the brightness of the sample's square's
 * material). Other nodes (a shadow edge, subtrees traced exactly) are shaded per sample at their
 * interpolated hits, except a faint node, whose whole brightness is within a share of the
 * tolerance and is interpolated across its shadow edge (faint_bound). When nothing is shaded
 * per sample and every sample of a pixel lies in one checker square on each textured leaf, the
 * pixel's sum over its samples is the bilinear form with the summed weights: the same sum,
 * computed without visiting each sample. A lattice cell too small to be worth cutting (fewer
 * samples than the points a cut would trace) sends its samples through the matrices. */
#include <assert.h>
#include <math.h>
#include <string.h>

#include "interp.h"

/* Every sample of lattice cell lc, interpolated with plan pl or (pl NULL) through the matrices. */
static void emit_samples(pt_ctx_t *C, const domain_pixels_t *A, const lattice_cell_t *lc,
                         const interp_plan_t *pl, int why) {
  int s = C->opt->spp_side, gx0, gx1, gy0, gy1;
  sample_range(lc->x0, lc->w, s, &gx0, &gx1);
  sample_range(lc->y0, lc->h, s, &gy0, &gy1);
  if (gx0 >= gx1 || gy0 >= gy1)
    return;
  sampling_t S;
  if (pl)
    pt__sampling_begin(C, lc, pl, &S);
  C->st.biquad_lattice_cells += (uint64_t)(pl && pl->nbiquadratic);
  C->st.faint_lattice_cells += (uint64_t)(pl && pl->nfaint);
  C->st.highlight_lattice_cells += (uint64_t)(pl && pl->nhighlight);
  if (pl && pl->nspectral)
    C->st.spectral_samples += (uint64_t)(gx1 - gx0) * (uint64_t)(gy1 - gy0);
  for (int j = gy0 / s; j <= (gy1 - 1) / s; j++)
    for (int i = gx0 / s; i <= (gx1 - 1) / s; i++) {
      int a0 = gx0 - i * s, a1 = gx1 - i * s, b0 = gy0 - j * s, b1 = gy1 - j * s;
      pt__pixel_samples(C, pixel_at(A, i, j), pl ? &S : NULL, why, a0 > 0 ? a0 : 0, a1 < s ? a1 : s,
                        b0 > 0 ? b0 : 0, b1 < s ? b1 : s);
    }
}

/* A lattice cell is cut only when it holds more samples than this: a measured quarter traces 5
 * points. */
#define PT_CUT_SAMPLES 10.0

static void process_lattice_cell(pt_ctx_t *C, const domain_pixels_t *A, lattice_cell_t *lc,
                                 int level);

/* Trace the five interior points of lc (its corners are set) at refinement level `level`. */
static void measure_lattice_cell(pt_ctx_t *C, lattice_cell_t *lc, int level) {
  pt_geom_t *pool = C->lattice.refine + (size_t)level * 5 * (size_t)C->cap;
  const int at[5][2] = {{0, 1}, {1, 0}, {1, 1}, {1, 2}, {2, 1}};
  for (int m = 0; m < 5; m++) {
    int r = at[m][0], c = at[m][1];
    lc->g[r][c] = pt__lattice_point(C, lc->x0 + 0.5 * c * lc->w, lc->y0 + 0.5 * r * lc->h,
                                    pool + (size_t)m * (size_t)C->cap, 0);
  }
  lc->measured = 1;
}

/* Cut a failed measured lattice cell into its quarters. */
static void quarter(pt_ctx_t *C, const domain_pixels_t *A, const lattice_cell_t *lc, int level) {
  for (int qy = 0; qy < 2; qy++)
    for (int qx = 0; qx < 2; qx++) {
      lattice_cell_t part;
      memset(&part, 0, sizeof part);
      part.x0 = lc->x0 + 0.5 * qx * lc->w;
      part.y0 = lc->y0 + 0.5 * qy * lc->h;
      part.w = 0.5 * lc->w;
      part.h = 0.5 * lc->h;
      part.pg = (const lattice_point_t(*)[3])lc->g;
      part.qx = qx;
      part.qy = qy;
      for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++)
          part.g[2 * r][2 * c] = lc->g[qy + r][qx + c];
      process_lattice_cell(C, A, &part, level + 1);
    }
}

/* Halve measured lattice cell lc (pt__halving's direction `dir`): each half keeps three of lc's
 * grid lines and traces its three new midpoints. */
static void halve(pt_ctx_t *C, const domain_pixels_t *A, const lattice_cell_t *lc, int level,
                  int dir) {
  pt_geom_t *pool = C->lattice.refine + (size_t)(level + 1) * 5 * (size_t)C->cap;
  for (int h = 0; h < 2; h++) {
    lattice_cell_t part;
    memset(&part, 0, sizeof part);
    if (dir == 1) {
      part.x0 = lc->x0 + 0.5 * h * lc->w;
      part.y0 = lc->y0;
      part.w = 0.5 * lc->w;
      part.h = lc->h;
      for (int r = 0; r < 3; r++) {
        part.g[r][0] = lc->g[r][h];
        part.g[r][2] = lc->g[r][h + 1];
        part.g[r][1] = pt__lattice_point(C, part.x0 + 0.5 * part.w, lc->y0 + 0.5 * r * lc->h,
                                         pool + (size_t)r * (size_t)C->cap, 0);
      }
    } else {
      part.x0 = lc->x0;
      part.y0 = lc->y0 + 0.5 * h * lc->h;
      part.w = lc->w;
      part.h = 0.5 * lc->h;
      for (int c = 0; c < 3; c++) {
        part.g[0][c] = lc->g[h][c];
        part.g[2][c] = lc->g[h + 1][c];
        part.g[1][c] = pt__lattice_point(C, lc->x0 + 0.5 * c * lc->w, part.y0 + 0.5 * part.h,
                                         pool + (size_t)c * (size_t)C->cap, 0);
      }
    }
    part.measured = 1;
    C->st.halved_lattice_cells++;
    process_lattice_cell(C, A, &part, level + 1);
  }
}

/* Accept lattice cell lc, cut it, or send its samples to the matrices. An estimated lattice cell
 * (not measured) that fails is measured first. */
static void process_lattice_cell(pt_ctx_t *C, const domain_pixels_t *A, lattice_cell_t *lc,
                                 int level) {
  interp_plan_t pl = {.shaded = C->lattice.plan.shaded,
                      .shaded_direct = C->lattice.plan.shaded_direct,
                      .shaded_exact = C->lattice.plan.shaded_exact,
                      .leaves = C->lattice.plan.leaves};
  int why = WHY_ERROR;
  int can_cut = level + 1 < PT_LATTICE_LEVELS && samples_in(C, lc) > PT_CUT_SAMPLES;
  if (!lc->measured && !C->opt->certified && pt__make_plan(C, lc, &pl, 1, &why) &&
      pt__per_sample_pays(C, lc, &pl, 1)) {
    emit_samples(C, A, lc, &pl, 0);
    return;
  }
  if (!lc->measured) {
    if (!can_cut) { /* measuring costs 5 points: more than its samples through the matrices */
      emit_samples(C, A, lc, NULL, why);
      return;
    }
    measure_lattice_cell(C, lc, level);
  }
  if (pt__make_plan(C, lc, &pl, can_cut, &why) && pt__per_sample_pays(C, lc, &pl, can_cut)) {
    emit_samples(C, A, lc, &pl, 0);
    return;
  }
  if (can_cut && pl.halve)
    halve(C, A, lc, level, pl.halve);
  else if (can_cut)
    quarter(C, A, lc, level);
  else
    emit_samples(C, A, lc, NULL, why);
}

void pt__interp_domain(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial) {
  domain_pixels_t A = {x0, y0, x1, y1, C->lattice.pixels};
  pt__memo_reset(&C->lattice.memo, C->paths.n);
  C->lattice.spec.n = 0;
  memset(C->lattice.spec_off, 0, (size_t)C->paths.n);
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++)
      *pixel_at(&A, i, j) = (pixel_t){i, j, {0, 0, 0}, NAN, {0, 0, 0}, 0};
  lattice_cell_t lc;
  memset(&lc, 0, sizeof lc);
  lc.x0 = x0;
  lc.y0 = y0;
  lc.w = x1 - x0;
  lc.h = y1 - y0;
  if (samples_in(C, &lc) < 2.0 * 9.0) { /* a 3 x 3 grid would cost more than the samples */
    pt__record_shadows(C, axial);
    emit_samples(C, &A, &lc, NULL, WHY_OFF);
  } else {
    /* the grid's centre is the domain's axial ray: traced first, it records the domain's shadow
     * transmittances (pt__record_shadows) and is then found in the memo */
    pt__lattice_point(C, x0 + 0.5 * lc.w, y0 + 0.5 * lc.h,
                      C->lattice.root + (size_t)4 * (size_t)C->cap, 1);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        lc.g[r][c] = pt__lattice_point(C, x0 + 0.5 * c * lc.w, y0 + 0.5 * r * lc.h,
                                       C->lattice.root + (size_t)(3 * r + c) * (size_t)C->cap, 0);
    lc.measured = 1;
    process_lattice_cell(C, &A, &lc, 0);
  }
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++) {
      pt__pixel_done(C, pixel_at(&A, i, j));
      if (C->opt->aux)
        pt__aux_matrix(C, i, j);
    }
}
