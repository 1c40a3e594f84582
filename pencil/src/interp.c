/* interp.c -- ray interpolation (paper section 4.1 (2)) inside an accepted cell: "the
 * intersection point and the direction of an interior paraxial ray are linearly interpolated",
 * with the error estimated by "evaluating first and second order interpolations" using one more
 * ray, and "if linearity is assumed for brightness I(x'), the brightness can also be
 * interpolated".
 *
 * The cell's pixel corners (half-pixel steps along a 1-pixel-wide cell) are traced through the
 * paths (lattice points). A sample is interpolated bilinearly from the four points of its lattice
 * cell (a quad), per node: hit point and direction, and the node's brightness W_k direct_k where
 * it is linear (the same checker square at the four points, every light's visibility agreeing
 * over the cell); other nodes are shaded per sample at their interpolated hits. A quad is used only
 * when, for every node, e_int (the second difference with the point beyond the quad, along each
 * axis, in pixels) plus the matrix error at its corners is within rho. A quad that fails is
 * refined: its edge midpoints and centre are traced and its four halves tried again, down to
 * PT_REFINE_LEVELS halvings; then its samples go through the matrices. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "render/vec_inline.h"

/* A quad: a rectangle [x0, x0 + w) x [y0, y0 + h) of continuous pixel coordinates whose corners
 * were traced, with the points beyond it for e_int. */
typedef struct {
  double x0, y0, w, h;
  const pt_geom_t *g[4];     /* corners (0,0), (1,0), (0,1), (1,1): node arrays */
  const pt_geom_t *tx[2][3]; /* along x for the edges y = 0 and y = 1: (a, b, c), the
                                interpolation between b and c, a beyond b */
  const pt_geom_t *ty[2][3]; /* along y for the edges x = 0 and x = 1 */
  int ok;                    /* every point traced without leaving the cell's paths */
  double xi2;                /* largest |xi|^2 of the corners */
} quad_t;

/* How a quad's samples are interpolated. */
typedef struct {
  rt_rgb_t smooth[4]; /* brightness of the linear nodes summed at the four corners */
  int n;              /* nodes shaded per sample */
  int *k;
  uint8_t *direct, *exact; /* per entry: its direct term, its exactly traced children */
  int nt;                  /* textured nodes whose square changes across the quad: the sample's */
  int *kt;                 /* square picks the interpolated brightness of its material */
} plan_t;

/* e_int of the linear interpolation between b and c with the third point a beyond b:
 * |x_a - 2 x_b + x_c| / 8, in pixels on node k's surface. */
static double e_int3(const pt_node_t *n, const pt_geom_t *a, const pt_geom_t *b,
                     const pt_geom_t *c) {
  px_vec3_t s = v3_add(v3_sub(a->p, v3_scale(b->p, 2.0)), c->p);
  return pt_pixels(n, v3_scale(s, 1.0 / 8.0));
}

/* e_int of node k over the quad: along x plus along y; *ok = 0 when a point is missing. */
static double e_int_quad(const pt_ctx_t *C, const quad_t *q, int k, int *ok) {
  const pt_node_t *n = &C->node[k];
  double ex = 0.0, ey = 0.0;
  for (int r = 0; r < 2; r++) {
    const pt_geom_t *a = &q->tx[r][0][k], *b = &q->tx[r][1][k], *c = &q->tx[r][2][k];
    const pt_geom_t *d = &q->ty[r][0][k], *e = &q->ty[r][1][k], *f = &q->ty[r][2][k];
    if (a->ok != 1 || b->ok != 1 || c->ok != 1 || d->ok != 1 || e->ok != 1 || f->ok != 1) {
      *ok = 0;
      return INFINITY;
    }
    ex = fmax(ex, e_int3(n, a, b, c));
    ey = fmax(ey, e_int3(n, d, e, f));
  }
  return ex + ey;
}

/* Certified mode: the quad's centre traced through the paths into C->rec; 0 when it left them. */
static int trace_centre(pt_ctx_t *C, const quad_t *q) {
  pt_eval_t G = {.C = C, .mode = PT_EV_MATRIX, .rec = C->rec};
  pt__xi_of(C, &G, q->x0 + 0.5 * q->w, q->y0 + 0.5 * q->h);
  pt__eval(&G);
  return !G.fallback;
}

/* Whether the quad may be interpolated, and how (see the file comment). In certified mode also
 * the actual interpolation error at the quad's centre (traced), everything within
 * PT_CERTIFIED_MARGIN rho. (A bound of bilinear interpolation from C, (h^2 / 8)(2 C + 2 C) over
 * a cell of side h in xi, was tried as well: it holds but is so loose that it sent a quarter of
 * the image's quads to the matrices without changing any measured error.) */
static int make_plan(pt_ctx_t *C, const quad_t *q, plan_t *pl) {
  uint64_t *why = C->st.matrix_pixels;
  if (!q->ok)
    return (int)(why[1]++ & 0);
  int cert = C->opt->certified;
  if (cert && !trace_centre(C, q))
    return (int)(why[1]++ & 0);
  double rho = C->opt->rho * (cert ? PT_CERTIFIED_MARGIN : 1.0);
  pl->n = pl->nt = 0;
  for (int i = 0; i < 4; i++)
    pl->smooth[i] = rt_rgb(0, 0, 0);
  for (int k = 0; k < C->nnode; k++) {
    const pt_geom_t *g[4] = {&q->g[0][k], &q->g[1][k], &q->g[2][k], &q->g[3][k]};
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
                         : fmax(n->c * q->xi2 / n->cos_in, n->e_check) / n->interval;
      double e_int = e_int_quad(C, q, k, &ok);
      if (cert && ok) {
        if (C->rec[k].ok != 1)
          return (int)(why[2]++ & 0);
        px_vec3_t mid = v3_scale(v3_add(v3_add(g[0]->p, g[1]->p), v3_add(g[2]->p, g[3]->p)), 0.25);
        e_int = fmax(e_int, pt_pixels(n, v3_sub(C->rec[k].p, mid)));
      }
      if (!ok || e_int + e_mat > rho)
        return (int)(why[ok ? 3 : 2]++ & 0);
      int squares = 1;
      if (n->textured)
        for (int i = 1; i < 4; i++)
          squares = squares && g[i]->su == g[0]->su && g[i]->sv == g[0]->sv;
      smooth = n->light_agree == ~0u;
      for (int c = 0; c < 2; c++)
        exact_children |= n->child[c] >= 0 && C->node[n->child[c]].pencil == PT_NODE_EXACT;
      if (smooth && !squares) {
        /* the direct term is linear for each material: the sample's square picks one. Children
         * would be weighted by the material too, so only for leaves */
        if (n->child[0] >= 0)
          return (int)(why[3]++ & 0);
        pl->kt[pl->nt++] = k;
        smooth = 0;
        if (!exact_children)
          continue;
        pl->k[pl->n] = k;
        pl->direct[pl->n] = 0;
        pl->exact[pl->n++] = 1;
        continue;
      }
    }
    if (smooth)
      for (int i = 0; i < 4; i++)
        pl->smooth[i] = rt_rgb_add(pl->smooth[i], g[i]->l);
    if (!smooth || exact_children) {
      pl->k[pl->n] = k;
      pl->direct[pl->n] = (uint8_t)!smooth;
      pl->exact[pl->n++] = (uint8_t)exact_children;
    }
  }
  return 1;
}

static void weights(double u, double v, double w[4]) {
  w[0] = (1 - u) * (1 - v);
  w[1] = u * (1 - v);
  w[2] = (1 - u) * v;
  w[3] = u * v;
}

/* One interpolated sample with weights w (E->g holds the quad's corners). */
static rt_rgb_t interp_sample(pt_eval_t *E, const plan_t *pl, const double w[4]) {
  const rt_rgb_t *c = pl->smooth;
  E->w = w;
  rt_rgb_t sum = rt_rgb(w[0] * c[0].r + w[1] * c[1].r + w[2] * c[2].r + w[3] * c[3].r,
                        w[0] * c[0].g + w[1] * c[1].g + w[2] * c[2].g + w[3] * c[3].g,
                        w[0] * c[0].b + w[1] * c[1].b + w[2] * c[2].b + w[3] * c[3].b);
  for (int m = 0; m < pl->nt; m++) { /* textured leaves: the material of the sample's square */
    int k = pl->kt[m];
    const pt_geom_t *g0 = &E->g[0][k], *g1 = &E->g[1][k], *g2 = &E->g[2][k], *g3 = &E->g[3][k];
    px_vec3_t p =
        v3_axpy(w[0], g0->p, v3_axpy(w[1], g1->p, v3_axpy(w[2], g2->p, v3_scale(g3->p, w[3]))));
    const rt_plane_t *pl0 = &E->C->s->prim[E->C->node[k].prim].plane;
    double u, v;
    rt_plane_coords(pl0, p, &u, &v);
    int par = (int)fmod(fabs(floor(u / pl0->check) + floor(v / pl0->check)), 2.0);
    sum.r +=
        w[0] * g0->lt[par].r + w[1] * g1->lt[par].r + w[2] * g2->lt[par].r + w[3] * g3->lt[par].r;
    sum.g +=
        w[0] * g0->lt[par].g + w[1] * g1->lt[par].g + w[2] * g2->lt[par].g + w[3] * g3->lt[par].g;
    sum.b +=
        w[0] * g0->lt[par].b + w[1] * g1->lt[par].b + w[2] * g2->lt[par].b + w[3] * g3->lt[par].b;
  }
  for (int m = 0; m < pl->n; m++) {
    int k = pl->k[m];
    const pt_geom_t *g0 = &E->g[0][k], *g1 = &E->g[1][k], *g2 = &E->g[2][k], *g3 = &E->g[3][k];
    rt_rgb_t wk = rt_rgb(w[0] * g0->w.r + w[1] * g1->w.r + w[2] * g2->w.r + w[3] * g3->w.r,
                         w[0] * g0->w.g + w[1] * g1->w.g + w[2] * g2->w.g + w[3] * g3->w.g,
                         w[0] * g0->w.b + w[1] * g1->w.b + w[2] * g2->w.b + w[3] * g3->w.b);
    sum = rt_rgb_add(sum, pt__eval_local(E, k, wk, pl->direct[m], pl->exact[m]));
  }
  return sum;
}

/* Certified mode: whether every miss node of an interpolated sample still meets no unbounded
 * plane (its ray interpolated from the quad's corners): a horizon can cross a quad between its
 * corners. Bounded objects were checked by intersecting the rays of the corners and, in certified
 * mode, of the centre with the scene (eval.c); between those points they are not. */
static int misses_nothing(const pt_ctx_t *C, const pt_eval_t *E, const double w[4]) {
  const rt_scene_t *s = C->s;
  for (int k = 0; k < C->nnode; k++) {
    const pt_geom_t *a = &E->g[0][k], *b = &E->g[1][k], *c = &E->g[2][k], *e = &E->g[3][k];
    if (!C->node[k].miss || a->ok != 1)
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

/* Trace the lattice point at (x, y) through the paths into rec; returns 1 when it stayed on them.
 */
static int trace_point(pt_ctx_t *C, double x, double y, pt_geom_t *rec, double *xi2) {
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .rec = rec, .lattice = 1};
  pt__xi_of(C, &E, x, y);
  *xi2 = E.xi[0] * E.xi[0] + E.xi[1] * E.xi[1];
  pt__eval(&E);
  return !E.fallback;
}

static void quad_samples(pt_ctx_t *C, pixel_t *P, const quad_t *q, int level);

/* Refine a failed quad: trace its edge midpoints and centre (a 3 x 3 grid with the corners) and
 * process its four halves, each with third points inside the grid. */
static void refine(pt_ctx_t *C, pixel_t *P, const quad_t *q, int level) {
  pt_geom_t *r = C->ref + (size_t)level * 5 * (size_t)C->cap;
  const pt_geom_t *grid[3][3]; /* [row][column] */
  double xi2[3][3] = {{0}};
  int ok = q->ok;
  grid[0][0] = q->g[0];
  grid[0][2] = q->g[1];
  grid[2][0] = q->g[2];
  grid[2][2] = q->g[3];
  const int mid[5][2] = {{0, 1}, {1, 0}, {1, 1}, {1, 2}, {2, 1}};
  for (int m = 0; m < 5; m++) {
    int row = mid[m][0], col = mid[m][1];
    pt_geom_t *g = r + (size_t)m * (size_t)C->cap;
    ok &= trace_point(C, q->x0 + 0.5 * col * q->w, q->y0 + 0.5 * row * q->h, g, &xi2[row][col]);
    grid[row][col] = g;
  }
  for (int qy = 0; qy < 2; qy++)
    for (int qx = 0; qx < 2; qx++) {
      quad_t s = {q->x0 + 0.5 * qx * q->w,
                  q->y0 + 0.5 * qy * q->h,
                  0.5 * q->w,
                  0.5 * q->h,
                  {grid[qy][qx], grid[qy][qx + 1], grid[qy + 1][qx], grid[qy + 1][qx + 1]},
                  {{NULL}},
                  {{NULL}},
                  ok,
                  q->xi2};
      for (int e = 0; e < 2; e++) { /* the third point is the grid line beyond */
        int row = qy + e, col = qx + e, far = qx ? 0 : 2, farr = qy ? 0 : 2;
        s.tx[e][0] = grid[row][far];
        s.tx[e][1] = grid[row][qx ? 1 : 1];
        s.tx[e][2] = grid[row][qx ? 2 : 0];
        s.ty[e][0] = grid[farr][col];
        s.ty[e][1] = grid[1][col];
        s.ty[e][2] = grid[qy ? 2 : 0][col];
      }
      quad_samples(C, P, &s, level + 1);
    }
}

/* The samples of pixel P inside quad q: interpolated when its plan allows, else refined, else
 * through the matrices. */
static void quad_samples(pt_ctx_t *C, pixel_t *P, const quad_t *q, int level) {
  int s = C->opt->spp_side, planned = -1, partial = 0;
  plan_t pl = {.k = C->loc, .direct = C->locd, .exact = C->loce, .kt = C->loct};
  pt_eval_t E = {.C = C, .mode = PT_EV_INTERP, .shade = 1};
  for (int i = 0; i < 4; i++)
    E.g[i] = q->g[i];
  for (int b = 0; b < s; b++)
    for (int a = 0; a < s; a++) {
      double x = P->i + (a + 0.5) / s, y = P->j + (b + 0.5) / s;
      double u = (x - q->x0) / q->w, v = (y - q->y0) / q->h;
      if (!(u >= 0.0 && u < 1.0 && v >= 0.0 && v < 1.0))
        continue;
      if (planned < 0) {
        planned = make_plan(C, q, &pl);
        /* certified mode does not refine: its extra checks fail where the map is curved, and
         * refining there costs more than the matrices */
        if (!planned && level < (C->opt->certified ? 0 : PT_REFINE_LEVELS)) {
          refine(C, P, q, level);
          return;
        }
      }
      if (!planned) {
        pt__matrix_sample(C, P, a, b);
        continue;
      }
      double w[4];
      weights(u, v, w);
      if (C->opt->certified && !misses_nothing(C, &E, w)) {
        pt__matrix_sample(C, P, a, b);
        continue;
      }
      E.partial = E.fallback = 0;
      P->sum = rt_rgb_add(P->sum, interp_sample(&E, &pl, w));
      P->n[PT_METHOD_INTERP]++;
      partial |= E.partial;
      C->st.fallbacks += (uint64_t)E.fallback;
      if (pl.n == 0 && pl.nt == 0)
        C->st.lerp_samples++;
      if (C->opt->measure) {
        E.w = w;
        pt__geometry(C, &E);
        rt_ray_t r = rt_view_ray(C->view, x, y, C->s->ior);
        P->pmax = pt__measure_sample(C, &r, C->rec, P->i, P->j, a, b, P->pmax);
      }
      E.w = NULL;
    }
  C->st.partial += (uint64_t)partial;
}

/* The lattice of a cell: points (x0 + i hx, y0 + j hy), i <= mx, j <= my. */
typedef struct {
  int x0, y0, mx, my;
  double hx, hy;
} lattice_t;

static size_t lat_index(const lattice_t *L, int i, int j) {
  return (size_t)(j * (L->mx + 1) + i);
}

static const pt_geom_t *lat_at(const pt_ctx_t *C, const lattice_t *L, int i, int j) {
  return &C->lat[lat_index(L, i, j) * (size_t)C->cap];
}

/* Lattice cell (i, j) as a quad, the third points taken from the lattice line beyond it on
 * whichever side exists. */
static quad_t lattice_quad(const pt_ctx_t *C, const lattice_t *L, int i, int j) {
  quad_t q = {L->x0 + i * L->hx,
              L->y0 + j * L->hy,
              L->hx,
              L->hy,
              {lat_at(C, L, i, j), lat_at(C, L, i + 1, j), lat_at(C, L, i, j + 1),
               lat_at(C, L, i + 1, j + 1)},
              {{NULL}},
              {{NULL}},
              1,
              0.0};
  int ia = i >= 1 ? i - 1 : i + 2, ib = i >= 1 ? i : i + 1, ic = i >= 1 ? i + 1 : i;
  int ja = j >= 1 ? j - 1 : j + 2, jb = j >= 1 ? j : j + 1, jc = j >= 1 ? j + 1 : j;
  q.ok = ia <= L->mx && ja <= L->my;
  for (int e = 0; e < 2 && q.ok; e++) {
    q.tx[e][0] = lat_at(C, L, ia, j + e);
    q.tx[e][1] = lat_at(C, L, ib, j + e);
    q.tx[e][2] = lat_at(C, L, ic, j + e);
    q.ty[e][0] = lat_at(C, L, i + e, ja);
    q.ty[e][1] = lat_at(C, L, i + e, jb);
    q.ty[e][2] = lat_at(C, L, i + e, jc);
  }
  for (int dj = 0; dj < 2; dj++)
    for (int di = 0; di < 2; di++) {
      size_t l = lat_index(L, i + di, j + dj);
      q.ok = q.ok && C->latok[l];
      q.xi2 = fmax(q.xi2, C->latxi2[l]);
    }
  return q;
}

void pt__interp_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  lattice_t L = {x0, y0, 0, 0, x1 - x0 >= 2 ? 1.0 : 0.5, y1 - y0 >= 2 ? 1.0 : 0.5};
  L.mx = (int)lrint((x1 - x0) / L.hx);
  L.my = (int)lrint((y1 - y0) / L.hy);
  for (int j = 0; j <= L.my; j++)
    for (int i = 0; i <= L.mx; i++) {
      size_t l = lat_index(&L, i, j);
      C->latok[l] = (uint8_t)trace_point(C, x0 + i * L.hx, y0 + j * L.hy,
                                         C->lat + l * (size_t)C->cap, &C->latxi2[l]);
    }
  int px = (int)lrint(1.0 / L.hx), py = (int)lrint(1.0 / L.hy); /* lattice cells per pixel */
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++) {
      pixel_t P = {i, j, {0, 0, 0}, NAN, {0, 0, 0}, pt__rays_now(C)};
      for (int cj = (j - y0) * py; cj < (j - y0 + 1) * py; cj++)
        for (int ci = (i - x0) * px; ci < (i - x0 + 1) * px; ci++) {
          quad_t q = lattice_quad(C, &L, ci, cj);
          quad_samples(C, &P, &q, 0);
        }
      pt__pixel_done(C, &P);
      if (C->opt->aux)
        pt__aux_matrix(C, i, j);
    }
}
