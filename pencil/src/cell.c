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
#include <string.h>

#include "internal.h"
#include "pvec.h"

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

static void write_pixel(pt_ctx_t *C, int i, int j, rt_rgb_t sum, pt_method_t m, double perr) {
  size_t k = pixel_index(C, i, j);
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
      for (int b = 0; b < s; b++)
        for (int a = 0; a < s; a++) {
          rt_ray_t r = rt_view_ray(C->view, i + (a + 0.5) / s, j + (b + 0.5) / s, C->s->ior);
          sum = rt_rgb_add(sum, rt_exact_primary(&C->ex, &r));
          if (C->opt->measure)
            pt__account(C, 0.0, 0.0, 0, error_slot(C, i, j, a, b));
        }
      C->st.samples[PT_METHOD_EXACT] += (uint64_t)(s * s);
      write_pixel(C, i, j, sum, PT_METHOD_EXACT, NAN);
      if (C->opt->aux)
        aux_exact(C, i, j);
    }
}

/* Per-sample bookkeeping of the Fig. 10 measurement; returns the pixel's running maximum. */
static double measure_sample(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, int i, int j,
                             int a, int b, double pmax) {
  double et, e = pt__measure(C, ray, rec, &et);
  int board = 0;
  for (int k = 0; k < C->nnode && !board; k++)
    board = C->node[k].textured && rec[k].ok == 1;
  pt__account(C, e, et, board, error_slot(C, i, j, a, b));
  if (board && (isnan(pmax) || e > pmax))
    pmax = e;
  return pmax;
}

/* Geometry-only evaluation (aux channels, measurement). */
static void geometry(pt_ctx_t *C, pt_eval_t *E) {
  E->shade = 0;
  E->rec = C->rec;
  pt__eval(E);
}

/* Step 4a with matrices: every sample of pixel (i, j) through the paths. */
static void matrix_pixel(pt_ctx_t *C, int i, int j) {
  int s = C->opt->spp_side, measure = C->opt->measure;
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  double pmax = NAN;
  for (int b = 0; b < s; b++)
    for (int a = 0; a < s; a++) {
      pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .rec = measure ? C->rec : NULL};
      E.primary = rt_view_ray(C->view, i + (a + 0.5) / s, j + (b + 0.5) / s, C->s->ior);
      E.xi[0] = pv_dot(C->frame.x1, E.primary.d);
      E.xi[1] = pv_dot(C->frame.x2, E.primary.d);
      sum = rt_rgb_add(sum, pt__eval(&E));
      C->st.fallbacks += (uint64_t)E.fallback;
      if (measure)
        pmax = measure_sample(C, &E.primary, C->rec, i, j, a, b, pmax);
    }
  C->st.samples[PT_METHOD_MATRIX] += (uint64_t)(s * s);
  write_pixel(C, i, j, sum, PT_METHOD_MATRIX, pmax);
  if (C->opt->aux) {
    pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX};
    E.primary = rt_view_ray(C->view, i + 0.5, j + 0.5, C->s->ior);
    E.xi[0] = pv_dot(C->frame.x1, E.primary.d);
    E.xi[1] = pv_dot(C->frame.x2, E.primary.d);
    geometry(C, &E);
    aux_pencil(C, i, j, C->rec);
  }
}

/* e_int (section 4.1 (2)) of the linear interpolation between lattice points b and c, estimated
 * with the third point a on the far side of b: |x_a - 2 x_b + x_c| / 8. */
static double e_int3(const pt_geom_t *a, const pt_geom_t *b, const pt_geom_t *c) {
  px_vec3_t s = pv_add(pv_sub(a->p, pv_scale(b->p, 2.0)), c->p);
  return pv_norm(s) / 8.0;
}

typedef struct {
  int x0, y0, w, h;
  double xi_cell;
} lattice_t;

static const pt_geom_t *lat_at(const pt_ctx_t *C, const lattice_t *L, int i, int j, int k) {
  return &C->lat[(size_t)(j * (L->w + 1) + i) * (size_t)C->cap + (size_t)k];
}

/* Largest e_int of node k over pixel (i, j) of the lattice (local coordinates), along x and
 * along y, each from the lattice line beyond the pixel on whichever side exists. */
static double e_int_pixel(const pt_ctx_t *C, const lattice_t *L, int i, int j, int k, int *ok) {
  int ia = i >= 1 ? i - 1 : i + 2, ib = i >= 1 ? i : i + 1, ic = i >= 1 ? i + 1 : i;
  int ja = j >= 1 ? j - 1 : j + 2, jb = j >= 1 ? j : j + 1, jc = j >= 1 ? j + 1 : j;
  double ex = 0.0, ey = 0.0;
  for (int r = j; r <= j + 1; r++) {
    const pt_geom_t *a = lat_at(C, L, ia, r, k), *b = lat_at(C, L, ib, r, k),
                    *c = lat_at(C, L, ic, r, k);
    if (a->ok != 1 || b->ok != 1 || c->ok != 1)
      *ok = 0;
    else
      ex = fmax(ex, e_int3(a, b, c));
  }
  for (int q = i; q <= i + 1; q++) {
    const pt_geom_t *a = lat_at(C, L, q, ja, k), *b = lat_at(C, L, q, jb, k),
                    *c = lat_at(C, L, q, jc, k);
    if (a->ok != 1 || b->ok != 1 || c->ok != 1)
      *ok = 0;
    else
      ey = fmax(ey, e_int3(a, b, c));
  }
  return ex + ey;
}

/* Whether pixel (i, j) may be interpolated: the 4 lattice points reached the same nodes without
 * exact fallbacks, and for every node the matrix error plus e_int is within tau. *lerp says
 * whether the brightness may be interpolated too: the same checker square at every node. */
static int pixel_interpolable(const pt_ctx_t *C, const lattice_t *L, int i, int j, int *lerp) {
  size_t l00 = (size_t)(j * (L->w + 1) + i), l01 = l00 + (size_t)(L->w + 1);
  if (!C->latok[l00] || !C->latok[l00 + 1] || !C->latok[l01] || !C->latok[l01 + 1])
    return 0;
  *lerp = 1;
  for (int k = 0; k < C->nnode; k++) {
    const pt_geom_t *g[4] = {lat_at(C, L, i, j, k), lat_at(C, L, i + 1, j, k),
                             lat_at(C, L, i, j + 1, k), lat_at(C, L, i + 1, j + 1, k)};
    int reached = (g[0]->ok != 0) + (g[1]->ok != 0) + (g[2]->ok != 0) + (g[3]->ok != 0);
    if (reached == 0)
      continue;
    if (reached != 4 || g[0]->ok != 1 || g[1]->ok != 1 || g[2]->ok != 1 || g[3]->ok != 1)
      return 0;
    const pt_node_t *n = &C->node[k];
    if (n->miss)
      continue;
    int ok = 1;
    double e_mat = n->c * L->xi_cell * L->xi_cell / n->cos_in;
    if (n->e_check > e_mat)
      e_mat = n->e_check;
    if (e_int_pixel(C, L, i, j, k, &ok) + e_mat > n->tau || !ok)
      return 0;
    if (n->textured)
      for (int q = 1; q < 4; q++)
        if (g[q]->su != g[0]->su || g[q]->sv != g[0]->sv)
          *lerp = 0;
  }
  return 1;
}

/* Step 4a with ray interpolation: matrices at the pixel corners of the cell, and every sample
 * interpolated from its pixel's four corners (hit points and directions; the brightness too when
 * the corners see the same checker squares). Pixels that fail the e_int test use matrices. */
static void interp_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1, double xi_cell) {
  lattice_t L = {x0, y0, x1 - x0, y1 - y0, xi_cell};
  int s = C->opt->spp_side, measure = C->opt->measure;
  for (int j = 0; j <= L.h; j++)
    for (int i = 0; i <= L.w; i++) {
      size_t l = (size_t)(j * (L.w + 1) + i);
      pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .rec = C->lat + l * (size_t)C->cap};
      E.primary = rt_view_ray(C->view, x0 + i, y0 + j, C->s->ior);
      E.xi[0] = pv_dot(C->frame.x1, E.primary.d);
      E.xi[1] = pv_dot(C->frame.x2, E.primary.d);
      C->latc[l] = pt__eval(&E);
      C->latok[l] = !E.fallback;
    }
  for (int j = 0; j < L.h; j++)
    for (int i = 0; i < L.w; i++) {
      int lerp = 0;
      if (!pixel_interpolable(C, &L, i, j, &lerp)) {
        matrix_pixel(C, x0 + i, y0 + j);
        continue;
      }
      size_t l00 = (size_t)(j * (L.w + 1) + i), l01 = l00 + (size_t)(L.w + 1);
      const rt_rgb_t c[4] = {C->latc[l00], C->latc[l00 + 1], C->latc[l01], C->latc[l01 + 1]};
      pt_eval_t E = {.C = C, .mode = PT_EV_INTERP};
      E.g[0] = C->lat + l00 * (size_t)C->cap;
      E.g[1] = C->lat + (l00 + 1) * (size_t)C->cap;
      E.g[2] = C->lat + l01 * (size_t)C->cap;
      E.g[3] = C->lat + (l01 + 1) * (size_t)C->cap;
      rt_rgb_t sum = rt_rgb(0, 0, 0);
      double pmax = NAN;
      for (int q = 0; q < s * s; q++) {
        const double *w = C->sw[q];
        E.w = w;
        if (lerp) {
          sum.r += w[0] * c[0].r + w[1] * c[1].r + w[2] * c[2].r + w[3] * c[3].r;
          sum.g += w[0] * c[0].g + w[1] * c[1].g + w[2] * c[2].g + w[3] * c[3].g;
          sum.b += w[0] * c[0].b + w[1] * c[1].b + w[2] * c[2].b + w[3] * c[3].b;
          if (measure)
            geometry(C, &E);
        } else {
          E.shade = 1;
          E.rec = measure ? C->rec : NULL;
          sum = rt_rgb_add(sum, pt__eval(&E));
          C->st.fallbacks += (uint64_t)E.fallback;
        }
        if (measure) {
          int a = q % s, b = q / s;
          rt_ray_t r = rt_view_ray(C->view, x0 + i + (a + 0.5) / s, y0 + j + (b + 0.5) / s,
                                   C->s->ior);
          pmax = measure_sample(C, &r, C->rec, x0 + i, y0 + j, a, b, pmax);
        }
      }
      C->st.samples[PT_METHOD_INTERP] += (uint64_t)(s * s);
      if (lerp)
        C->st.lerp_samples += (uint64_t)(s * s);
      write_pixel(C, x0 + i, y0 + j, sum, PT_METHOD_INTERP, pmax);
      if (C->opt->aux) {
        static const double mid[4] = {0.25, 0.25, 0.25, 0.25};
        E.w = mid;
        geometry(C, &E);
        aux_pencil(C, x0 + i, y0 + j, C->rec);
      }
    }
}

/* Step 4a for an accepted cell. */
static void accept_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial,
                        double xi_cell) {
  /* shadow transmittance once per cell, at the axial ray's nodes */
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .record_shadow = 1};
  E.primary = *axial;
  pt__eval(&E);
  C->kt = rt_tree_follow(&C->tree, RT_RAY_REFRACT);
  C->kr = rt_tree_follow(&C->tree, RT_RAY_REFLECT);
  int s = C->opt->spp_side;
  if (C->opt->interp && s >= 2 && x1 - x0 >= 2 && y1 - y0 >= 2) {
    interp_cell(C, x0, y0, x1, y1, xi_cell);
    return;
  }
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

void pt__cell(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  pt_stats_t *st = &C->st;
  st->cells++;
  double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  rt_ray_t axial = rt_view_ray(C->view, cx, cy, C->s->ior);
  C->ex.tree = &C->tree;
  rt_exact_primary(&C->ex, &axial);
  C->ex.tree = NULL;
  st->exact_traces++;
  /* step 3: smoothness */
  const int xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
  int edge = C->tree.overflow || px_frame_from_z(axial.d, C->view->down, &C->frame) != PX_OK;
  for (int i = 0; i < 4 && !edge; i++)
    edge = !pt_ctree_same(&C->tree, corner(C, xs[i], ys[i]));
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
  C->nnode = C->tree.n;
  double xi_allow = INFINITY;
  int check_ok = 1;
  for (int k = 0; k < C->nnode; k++) {
    if (pt_path_build(C->s, &C->tree, k, &p, &C->path, &C->node[k]) != PX_OK) {
      st->cells_edge++; /* a path that cannot be re-traced: treat as an edge */
      split(C, x0, y0, x1, y1, 2);
      return;
    }
    const pt_node_t *n = &C->node[k];
    if (n->miss)
      continue;
    xi_allow = fmin(xi_allow, n->xi_max);
    if (p.check && !(n->e_check <= n->tau))
      check_ok = 0;
  }
  double dmin = fmin(hypot(p.delta[0][0], p.delta[0][1]), hypot(p.delta[1][0], p.delta[1][1]));
  if (xi_cell <= xi_allow && check_ok) {
    st->cells_accepted++;
    accept_cell(C, x0, y0, x1, y1, &axial, xi_cell);
  } else if (xi_cell <= xi_allow) {
    st->cells_check_failed++;
    split(C, x0, y0, x1, y1, 2);
  } else if (2.0 * xi_allow < dmin) {
    st->cells_narrow++;
    exact_cell(C, x0, y0, x1, y1);
  } else {
    st->cells_split++;
    double k = ceil(xi_cell / xi_allow);
    split(C, x0, y0, x1, y1, k > 64.0 ? 64 : (int)fmax(2.0, k));
  }
}
