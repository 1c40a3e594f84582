/* render.c -- beam tracing from the eye (beam/render.h): tiles of the screen as beams, their
 * partition by faces, the beam tree through reflections and refractions, coverage of sub-pixel
 * cells, error control against exact tracing and the exact fallback. */
#include "beam/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "beam/beam.h"
#include "core/camera.h"
#include "core/intersect.h"
#include "core/shade.h"
#include "core/shade_paths.h"
#include "render/render.h"

#include "render_impl.h"

/* A piece that fails its checks over at most this many cells is traced exactly, not divided. */
#define BT_FEW_CELLS 4
/* A piece of less area than this share of a cell is traced exactly (a sliver): its model, checks
 * and beam tree would cost more than the exact rays of its share. */
#define BT_SMALL 0.25
/* A region over more cells than that which overlaps more faces than this is divided before it is
 * partitioned. */
#define BT_CROWD 24
/* A beam whose faces or pieces would have fewer cells each than this is traced exactly: a piece
 * costs its model, bound, partition and a dozen check rays, more than the exact rays of a few
 * cells (the cost against facet count, docs/journal/2026-12-03-beam-bounds.md). */
#define BT_DENSE 4
/* Rounding between a model's point and the exact ray's, in pixel intervals: a checked distance
 * this much over a piece's bound is not yet evidence against the bound. */
#define BT_SLACK 1e-6

/* ---- cells ---------------------------------------------------------------------------------- */

/* Clip the convex polygon p to the axis-aligned box [x0, x1] x [y0, y1]: its area and centroid
 * there; 0 when nothing is left. */
int bt__clip_box(const px_poly2_t *p, double x0, double x1, double y0, double y1, double *area,
                 double c[2]) {
  double a[PX_POLY_MAX + 8][2], b[PX_POLY_MAX + 8][2];
  int n = p->n;
  for (int k = 0; k < n; k++) {
    a[k][0] = p->v[k][0];
    a[k][1] = p->v[k][1];
  }
  /* four half-planes: sign * v[axis] <= sign * bound */
  const int axis[4] = {0, 0, 1, 1};
  const double sign[4] = {-1, 1, -1, 1}, bound[4] = {-x0, x1, -y0, y1};
  double(*in)[2] = a, (*out)[2] = b;
  for (int e = 0; e < 4 && n > 0; e++) {
    int m = 0;
    for (int k = 0; k < n; k++) {
      const double *u = in[k], *w = in[(k + 1) % n];
      double du = sign[e] * u[axis[e]] - bound[e], dw = sign[e] * w[axis[e]] - bound[e];
      if (du <= 0) {
        out[m][0] = u[0];
        out[m++][1] = u[1];
      }
      if ((du < 0 && dw > 0) || (du > 0 && dw < 0)) {
        double t = du / (du - dw);
        out[m][0] = u[0] + t * (w[0] - u[0]);
        out[m++][1] = u[1] + t * (w[1] - u[1]);
      }
    }
    n = m;
    double(*t)[2] = in;
    in = out;
    out = t;
  }
  if (n < 3)
    return 0;
  double s = 0, cx = 0, cy = 0;
  for (int k = 0; k < n; k++) {
    const double *u = in[k], *w = in[(k + 1) % n];
    double cr = u[0] * w[1] - w[0] * u[1];
    s += cr;
    cx += (u[0] + w[0]) * cr;
    cy += (u[1] + w[1]) * cr;
  }
  if (!(fabs(s) > 0.0))
    return 0;
  *area = 0.5 * fabs(s);
  c[0] = cx / (3.0 * s);
  c[1] = cy / (3.0 * s);
  return 1;
}

/* The tile's cells that polygon r overlaps: [*i0, *i1) x [*j0, *j1) in tile cells. */
void bt__cell_range(const tile_t *T, const px_poly2_t *r, int *i0, int *i1, int *j0, int *j1) {
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int k = 0; k < r->n; k++)
    for (int a = 0; a < 2; a++) {
      lo[a] = fmin(lo[a], r->v[k][a]);
      hi[a] = fmax(hi[a], r->v[k][a]);
    }
  double u0 = (lo[0] - T->a0) / T->cell - T->cx0, u1 = (hi[0] - T->a0) / T->cell - T->cx0;
  double v0 = (lo[1] - T->b0) / T->cell - T->cy0, v1 = (hi[1] - T->b0) / T->cell - T->cy0;
  *i0 = (int)fmax(0.0, floor(u0));
  *i1 = (int)fmin((double)T->tcw, ceil(u1));
  *j0 = (int)fmax(0.0, floor(v0));
  *j1 = (int)fmin((double)T->tch, ceil(v1));
}

/* 1 when p lies in the convex polygon r (either orientation). Edges
 * shorter than a billionth of the polygon's extent have no direction to speak of (the clipping
 * leaves such between vertices that coincide to rounding) and are passed over. */
int bt__inside(const px_poly2_t *r, const double p[2]) {
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int k = 0; k < r->n; k++)
    for (int a = 0; a < 2; a++) {
      lo[a] = fmin(lo[a], r->v[k][a]);
      hi[a] = fmax(hi[a], r->v[k][a]);
    }
  double least = 1e-9 * fmax(hi[0] - lo[0], hi[1] - lo[1]);
  int pos = 0, neg = 0;
  for (int k = 0; k < r->n; k++) {
    const double *u = r->v[k], *w = r->v[(k + 1) % r->n];
    double len = hypot(w[0] - u[0], w[1] - u[1]);
    if (!(len > least))
      continue;
    double d = ((w[0] - u[0]) * (p[1] - u[1]) - (w[1] - u[1]) * (p[0] - u[0])) / len;
    pos += d > 0.0;
    neg += d < 0.0;
  }
  return !(pos && neg);
}

/* Add colour c over share `area` of tile cell (i, j). */
static void deposit(tile_t *T, int i, int j, double area, rt_rgb_t c) {
  double k = area / (T->cell * T->cell);
  double *a = T->acc + 3 * ((size_t)j * (size_t)T->tcw + (size_t)i);
  a[0] += k * c.r;
  a[1] += k * c.g;
  a[2] += k * c.b;
}

/* ---- rays along a path ---------------------------------------------------------------------- */

rt_ray_kind_t bt__kind_of(const bm_step_t *st) {
  return st->event == PX_EVENT_REFRACT ? RT_RAY_REFRACT : RT_RAY_REFLECT;
}

/* The surface where ray r meets face f's plane; 0 when it does not ahead. */
int bt__face_surface(const tile_t *T, const bm_face_t *f, const rt_ray_t *r, rt_surface_t *sf) {
  double den = px_v3_dot(f->n, r->d), t = (f->d - px_v3_dot(f->n, r->o)) / den;
  if (!(den != 0.0) || !(t > 0.0) || !isfinite(t))
    return 0;
  rt_hit_t hit = {t, px_v3_axpy(t, r->d, r->o), f->n, f->prim, f->object};
  rt_shade_surface(T->s, &hit, r, sf);
  return 1;
}

/* The ray of parameters p after the first j steps of path by model m (unit direction). */
rt_ray_t bt__model_ray(const tile_t *T, const bm_model_t *m, const bm_path_t *path, int j,
                       const double p[2]) {
  px_vec3_t o, d;
  bm_model_ray(m, &T->src, p, &o, &d);
  return (rt_ray_t){
      o,        px_v3_unit(d),           0.0,
      INFINITY, j ? m->ior : T->src.ior, j ? T->b->face[path->step[j - 1].face].prim : -1,
      0.0f};
}

/* The weight of path's n steps at parameters p, by the models ms[0 .. n-1] (the paraxial ray of
 * each prefix meeting its face): the product of the children's weights there. 0 when a step has
 * no such child at p. */
int bt__model_weight(const tile_t *T, const bm_model_t *ms, const bm_path_t *path, int n,
                     const double p[2], rt_rgb_t *w) {
  *w = rt_rgb(1, 1, 1);
  for (int j = 0; j < n; j++) {
    rt_ray_t r = bt__model_ray(T, &ms[j], path, j, p);
    rt_surface_t sf;
    rt_child_t c;
    if (!bt__face_surface(T, &T->b->face[path->step[j].face], &r, &sf) ||
        !rt_shade_child(T->s, T->plan, &sf, &r, j, bt__kind_of(&path->step[j]), &c))
      return 0;
    *w = rt_rgb_mul(*w, c.weight);
  }
  return 1;
}

/* The exact ray of parameters p after path's n steps (each face's plane in turn, the children of
 * shade.h, which the exact tracer follows) and the product of the weights: 0 when a step has no
 * such child or misses its plane. */
int bt__exact_path(const tile_t *T, const bm_path_t *path, const double p[2], rt_ray_t *r,
                   rt_rgb_t *w) {
  *r = bm_source_ray(&T->src, p);
  *w = rt_rgb(1, 1, 1);
  for (int j = 0; j < path->n; j++) {
    rt_surface_t sf;
    rt_child_t c;
    if (!bt__face_surface(T, &T->b->face[path->step[j].face], r, &sf) ||
        !rt_shade_child(T->s, T->plan, &sf, r, j, bt__kind_of(&path->step[j]), &c))
      return 0;
    *w = rt_rgb_mul(*w, c.weight);
    *r = c.ray;
  }
  return 1;
}

/* The index of material m at wavelength offset du on the solids' axis (dispersive glass is linear
 * in it, [P89] 3.3; T->solids). */
double bt__index_at(const tile_t *T, const rt_material_t *m, double du) {
  return T->solids && px_index_disperses(&m->index) ? m->ior + T->plan->wave.scale.dn0 * du
                                                    : m->ior;
}

/* bt__exact_path() at wavelength offset du: each medium's index there (bt__index_at()), so that
 * each step's Fresnel weight and total internal reflection are the wavelength's. */
int bt__exact_path_at(const tile_t *T, const bm_path_t *path, const double p[2], double du,
                      rt_ray_t *r, rt_rgb_t *w) {
  *r = bm_source_ray(&T->src, p);
  *w = rt_rgb(1, 1, 1);
  for (int j = 0; j < path->n; j++) {
    rt_surface_t sf;
    rt_child_t c;
    if (!bt__face_surface(T, &T->b->face[path->step[j].face], r, &sf))
      return 0;
    if (sf.entering)
      sf.n2 = bt__index_at(T, sf.mat, du);
    else
      sf.n1 = bt__index_at(T, sf.mat, du);
    r->ior = sf.n1;
    if (!rt_shade_child(T->s, T->plan, &sf, r, j, bt__kind_of(&path->step[j]), &c))
      return 0;
    *w = rt_rgb_mul(*w, c.weight);
    *r = c.ray;
  }
  return 1;
}

/* The models of path's prefixes 0 .. n at parameters c. */
static px_status_t prefix_models(const tile_t *T, const bm_path_t *path, const double c[2],
                                 bm_model_t *ms) {
  bm_path_t pre = {0};
  for (int j = 0; j <= path->n; j++) {
    pre.n = j;
    if (j > 0)
      pre.step[j - 1] = path->step[j - 1];
    px_status_t st = bm_model(T->b, &T->src, &pre, c, &ms[j]);
    if (st != PX_OK)
      return st;
  }
  return PX_OK;
}

/* ---- the Fig. 10 measure -------------------------------------------------------------------- */

/* The centre of tile cell (i, j). */
static void cell_centre(const tile_t *T, int i, int j, double p[2]) {
  p[0] = T->a0 + (T->cx0 + i + 0.5) * T->cell;
  p[1] = T->b0 + (T->cy0 + j + 0.5) * T->cell;
}

/* The exact tree of ray parameters p into T->probe. */
static void probe(tile_t *T, const double p[2]) {
  rt_ray_t r = bm_source_ray(&T->src, p);
  xr_exact_primary(&T->mex, &r);
}

/* The node of T->probe on path (each step's face's primitive met, then the step's kind), or -1;
 * *transmit = 1 when the path is the tree's transmission-first one up to there (a reflection only
 * where no refraction was spawned: rt_tree_follow()). */
static int probe_follow(const tile_t *T, const bm_path_t *path, int *transmit) {
  const rt_tree_t *t = &T->probe;
  *transmit = 1;
  if (t->n == 0 || t->overflow)
    return -1;
  int x = 0;
  for (int j = 0; j < path->n; j++) {
    if (t->node[x].prim != T->b->face[path->step[j].face].prim)
      return -1;
    int kind = bt__kind_of(&path->step[j]), next = -1, refract = 0;
    for (int c = x + 1; c < t->n; c++)
      if (t->node[c].parent == x) {
        refract |= t->node[c].kind == RT_RAY_REFRACT;
        if (t->node[c].kind == kind)
          next = c;
      }
    if (kind != RT_RAY_REFRACT && refract)
      *transmit = 0;
    if (next < 0)
      return -1;
    x = next;
  }
  return x;
}

/* Record error e (strict es; on the transmission-first path when t) at tile cell k. */
static void record(tile_t *T, size_t k, double e, double es, int t) {
  double *c = T->err + 3 * k;
  c[0] = fmax(c[0], e);
  if (t)
    c[1] = fmax(c[1], e);
  c[2] = fmax(c[2], es);
  T->pts[k] |= 1;
}

/* |J+|: the largest singular value of the 2 x 3 pseudo-inverse of rows u, v (bt__footprint()), so
 * that |J+ e| <= |J+| |e| turns a length on the face into pixel intervals at most. */
static double pinv_norm(px_vec3_t u, px_vec3_t v) {
  double uu = px_v3_dot(u, u), uv = px_v3_dot(u, v), vv = px_v3_dot(v, v);
  return sqrt(0.5 * (uu + vv) + sqrt(0.25 * (uu - vv) * (uu - vv) + uv * uv));
}

/* The samples of accepted piece r (face f, NULL for none; drawn by model md; footprint rows u, v):
 * its points against the exact trees'. */
static void measure_model(tile_t *T, const px_poly2_t *r, const bm_path_t *path, const bm_face_t *f,
                          const bm_model_t *md, px_vec3_t u, px_vec3_t v) {
  double jp = pinv_norm(u, v); /* for the strict measure */
  int measured = f && rt_object_measured(T->s, f->object);
  int i0, i1, j0, j1;
  bt__cell_range(T, r, &i0, &i1, &j0, &j1);
  for (int j = j0; j < j1; j++)
    for (int i = i0; i < i1; i++) {
      double p[2];
      cell_centre(T, i, j, p);
      if (!bt__inside(r, p))
        continue;
      size_t k = (size_t)j * T->tcw + i;
      probe(T, p);
      int t, x = probe_follow(T, path, &t);
      const rt_tree_node_t *nd = x >= 0 ? &T->probe.node[x] : NULL;
      if (!f) { /* the background: the exact ray must meet nothing */
        if (nd && nd->object < 0)
          T->seen[k * T->nodes + x] = 1;
        continue;
      }
      if (nd && nd->prim == f->prim) {
        T->seen[k * T->nodes + x] = 1;
        px_vec3_t xm;
        double s;
        if (!measured || bm_model_hit(md, &T->src, p, f->n, f->d, &xm, &s) != PX_OK)
          continue;
        px_vec3_t dx = px_v3_sub(xm, nd->point);
        record(T, k, hypot(px_v3_dot(u, dx), px_v3_dot(v, dx)), px_v3_norm(dx) * jp, t);
      } else if (measured) {
        record(T, k, INFINITY, INFINITY, t); /* the model's point has no counterpart */
      }
    }
}

/* The samples of region r traced exactly along path from its start: the exact tree's nodes from
 * the path's on are accounted for (no error). */
static void measure_exact(tile_t *T, const px_poly2_t *r, const bm_path_t *path) {
  int i0, i1, j0, j1;
  bt__cell_range(T, r, &i0, &i1, &j0, &j1);
  for (int j = j0; j < j1; j++)
    for (int i = i0; i < i1; i++) {
      double p[2];
      cell_centre(T, i, j, p);
      if (!bt__inside(r, p))
        continue;
      size_t k = (size_t)j * T->tcw + i;
      if (path->n == 0)
        T->pts[k] |= 2;
      probe(T, p);
      int t, x = probe_follow(T, path, &t);
      if (x < 0)
        continue;
      /* the subtree of x: the nodes after it deeper than it (depth-first order) */
      T->seen[k * T->nodes + x] = 1;
      for (int c = x + 1; c < T->probe.n && T->probe.node[c].depth > T->probe.node[x].depth; c++)
        T->seen[k * T->nodes + c] = 1;
    }
}

/* The tile's samples into the counters and the outputs: an exact point on a measured surface that
 * no piece accounted for is a mismatch. */
static void measure_tile(tile_t *T, const bt_extra_t *x, int width) {
  int sp = T->o->spp_side;
  double rho = T->o->rho;
  bt_stats_t *st = &T->st;
  for (int j = 0; j < T->tch; j++)
    for (int i = 0; i < T->tcw; i++) {
      size_t k = (size_t)j * T->tcw + i;
      double p[2], *e = T->err + 3 * k;
      cell_centre(T, i, j, p);
      probe(T, p);
      for (int n = 0; n < T->probe.n; n++) {
        const rt_tree_node_t *nd = &T->probe.node[n];
        if (nd->object >= 0 && rt_object_measured(T->s, nd->object) && !T->seen[k * T->nodes + n])
          e[0] = e[1] = e[2] = INFINITY;
      }
      st->measured++;
      st->with_points += (T->pts[k] & 1) != 0;
      st->samples_exact += (T->pts[k] & 2) != 0;
      st->within += e[0] <= rho;
      st->within_t += e[1] <= rho;
      st->within_strict += e[2] <= rho;
      if (isinf(e[0]))
        st->mismatches++;
      else
        st->fig10_max = fmax(st->fig10_max, e[0]);
      if (isfinite(e[1]))
        st->fig10_max_t = fmax(st->fig10_max_t, e[1]);
      if (isfinite(e[2]))
        st->fig10_max_strict = fmax(st->fig10_max_strict, e[2]);
      double bin = e[0] / BT_HIST_STEP;
      st->hist[bin < BT_HIST_BINS - 1 ? (int)bin : BT_HIST_BINS - 1]++;
      int pi = (T->cx0 + i) / sp, pj = (T->cy0 + j) / sp, a = (T->cx0 + i) % sp,
          b = (T->cy0 + j) % sp;
      size_t px = (size_t)pj * width + pi;
      if (x && x->sample_error)
        x->sample_error[px * sp * sp + (size_t)(b * sp + a)] = (float)e[0];
      if (x && x->error)
        x->error[px] = (a == 0 && b == 0) ? (float)e[0] : fmaxf(x->error[px], (float)e[0]);
    }
}

/* ---- the exact fallback --------------------------------------------------------------------- */

/* The exact radiance along path's continuation at parameters p, with the path's weight. */
static rt_rgb_t exact_at(tile_t *T, const bm_path_t *path, const double p[2]) {
  rt_ray_t ray;
  rt_rgb_t w;
  if (!bt__exact_path(T, path, p, &ray, &w))
    return rt_rgb(0, 0, 0); /* no light comes back along this path at p */
  if (path->n == 0)
    return xr_exact_primary(&T->ex, &ray);
  T->ex.node = -1;
  rt_child_t ch = {ray, rt_rgb(1, 1, 1), bt__kind_of(&path->step[path->n - 1]), 0};
  return rt_rgb_mul(w, T->tr.child(T->tr.ctx, &ch, path->n));
}

/* Every cell share of region r traced exactly from the start of path on: the path's exact rays
 * at the points of an e x e grid in the cell that lie in the share (e = exact_side), averaged,
 * or at the share's centroid when none does. */
static void exact_region(tile_t *T, const px_poly2_t *r, const bm_path_t *path) {
  int i0, i1, j0, j1, e = T->o->exact_side;
  if (T->o->measure)
    measure_exact(T, r, path);
  if (T->collect) { /* inside a solid's subtree: its cells are traced exactly there */
    bt__solid_record(T, r, path, BT_REC_EXACT, NULL, 0, NULL);
    return;
  }
  bt__cell_range(T, r, &i0, &i1, &j0, &j1);
  for (int j = j0; j < j1; j++)
    for (int i = i0; i < i1; i++) {
      double x0 = T->a0 + (T->cx0 + i) * T->cell, y0 = T->b0 + (T->cy0 + j) * T->cell, area, c[2];
      if (!bt__clip_box(r, x0, x0 + T->cell, y0, y0 + T->cell, &area, c))
        continue;
      T->st.exact_cells++;
      rt_rgb_t sum = rt_rgb(0, 0, 0);
      int in = 0;
      for (int b2 = 0; b2 < e; b2++)
        for (int a2 = 0; a2 < e; a2++) {
          double p[2] = {x0 + (a2 + 0.5) * T->cell / e, y0 + (b2 + 0.5) * T->cell / e};
          if (!bt__inside(r, p))
            continue;
          sum = rt_rgb_add(sum, exact_at(T, path, p));
          in++;
        }
      if (in == 0) {
        sum = exact_at(T, path, c);
        in = 1;
      }
      deposit(T, i, j, area, rt_rgb_scale(sum, 1.0 / in));
    }
}

/* ---- pieces --------------------------------------------------------------------------------- */

/* The kinds of the children at a surface as a small code: bit 0 reflection, bit 1 its total
 * internal reflection, bit 2 refraction. */
static int children_code(const tile_t *T, const rt_surface_t *sf, const rt_ray_t *r, int depth,
                         rt_child_t ch[2], int *n) {
  *n = rt_shade_children(T->s, T->plan, sf, r, depth, ch);
  int code = 0;
  for (int k = 0; k < *n; k++)
    code |= ch[k].kind == RT_RAY_REFRACT ? 4 : (1 | (ch[k].tir ? 2 : 0));
  return code;
}

/* The pixel footprint of model m on face f at c: the points one pixel step along screen x and y
 * away, as the columns of a 3 x 2 matrix; its pseudo-inverse's rows in *u, *v. 0 when the map
 * is singular there. */
int bt__footprint(const tile_t *T, const bm_model_t *m, const bm_face_t *f, const double c[2],
                  px_vec3_t *u, px_vec3_t *v) {
  double h = 1e-3 * T->pixel, s;
  px_vec3_t x[4];
  const double dp[4][2] = {{h, 0}, {-h, 0}, {0, h}, {0, -h}};
  for (int k = 0; k < 4; k++) {
    double p[2] = {c[0] + dp[k][0], c[1] + dp[k][1]};
    if (bm_model_hit(m, &T->src, p, f->n, f->d, &x[k], &s) != PX_OK)
      return 0;
  }
  double k = T->pixel / (2.0 * h);
  px_vec3_t ja = px_v3_scale(px_v3_sub(x[0], x[1]), k), jb = px_v3_scale(px_v3_sub(x[2], x[3]), k);
  double aa = px_v3_dot(ja, ja), ab = px_v3_dot(ja, jb), bb = px_v3_dot(jb, jb),
         det = aa * bb - ab * ab;
  if (!(det > 1e-300) || !isfinite(det))
    return 0;
  /* (J^T J)^-1 J^T */
  *u = px_v3_scale(px_v3_sub(px_v3_scale(ja, bb), px_v3_scale(jb, ab)), 1.0 / det);
  *v = px_v3_scale(px_v3_sub(px_v3_scale(jb, aa), px_v3_scale(ja, ab)), 1.0 / det);
  return 1;
}

/* How far point x (in face f's plane) lies outside f's polygon: the largest distance beyond an
 * edge, as a vector along that edge's outward normal (zero inside; zero for a plane). */
static px_vec3_t outside(const tile_t *T, const bm_face_t *f, px_vec3_t x) {
  px_vec3_t best = px_v3(0, 0, 0);
  double worst = 0.0;
  const px_vec3_t *v = T->b->vertex + f->first;
  for (int k = 0; k < f->count; k++) {
    px_vec3_t e = px_v3_sub(v[(k + 1) % f->count], v[k]), out = px_v3_unit(px_v3_cross(e, f->n));
    double d = px_v3_dot(out, px_v3_sub(x, v[k]));
    if (d > worst) {
      worst = d;
      best = px_v3_scale(out, d);
    }
  }
  return best;
}

/* How deep point x lies inside the polygon of primitive prim (the deepest of its faces): the
 * distance to the nearest edge, as a vector; zero when outside every face or for a plane. */
static px_vec3_t depth_inside(const tile_t *T, int prim, px_vec3_t x) {
  px_vec3_t best = px_v3(0, 0, 0);
  double deepest = 0.0;
  for (int g = T->b->face_of_prim[prim]; g >= 0 && g < T->b->nface && T->b->face[g].prim == prim;
       g++) {
    const bm_face_t *f = &T->b->face[g];
    const px_vec3_t *v = T->b->vertex + f->first;
    double least = INFINITY;
    px_vec3_t at = px_v3(0, 0, 0);
    for (int k = 0; k < f->count; k++) {
      px_vec3_t e = px_v3_sub(v[(k + 1) % f->count], v[k]), in = px_v3_unit(px_v3_cross(f->n, e));
      double d = px_v3_dot(in, px_v3_sub(x, v[k]));
      if (d < least) {
        least = d;
        at = px_v3_scale(in, d);
      }
    }
    if (f->count > 0 && least > deepest) {
      deepest = least;
      best = at;
    }
  }
  return best;
}

/* A plane pl that an exact ray meets before point x of face f: the shortest move of x within f's
 * plane to pl's line across it, as a vector into *in; 0 when the planes are parallel. */
static int plane_ahead(const bm_face_t *pl, const bm_face_t *f, px_vec3_t x, px_vec3_t *in) {
  px_vec3_t nt = px_v3_sub(pl->n, px_v3_scale(f->n, px_v3_dot(pl->n, f->n)));
  double nn = px_v3_dot(nt, nt);
  if (!(nn > 1e-24))
    return 0;
  *in = px_v3_scale(nt, (pl->d - px_v3_dot(pl->n, x)) / nn);
  return 1;
}

/* Check one point p of a piece along path: on face f (NULL: the piece meets nothing), the
 * models' points (mp, the partition's, and md, the drawing's) against the exact ray's, in pixel
 * intervals (u, v), at most `limit` (the largest into *em; over it sets *over). The exact ray must
 * meet f (within rho of its polygon's edges: a point that lands beside f counts by how far, one
 * that meets another face first by how deep inside that face, or a plane by how far along f it
 * must move to pass in front of it; the largest into *ee, over rho failing), and its
 * children there must have code `code`. A `strict` point (a sample's, in certified mode) allows no
 * edge error: its exact ray must meet f itself first (or nothing, for a piece that meets nothing),
 * so that the sample's path is the piece's. */
static int check_point(tile_t *T, const bm_path_t *path, const bm_model_t *mp, const bm_model_t *md,
                       const bm_face_t *f, px_vec3_t u, px_vec3_t v, int code, const double p[2],
                       int strict, double limit, double *em, double *ee, int *over) {
  rt_ray_t r;
  rt_rgb_t w;
  rt_surface_t sf;
  T->st.checks++;
  if (!bt__exact_path(T, path, p, &r, &w))
    return 0;
  double m = 0.0, e = 0.0, tf = INFINITY;
  if (f) {
    px_vec3_t xm[2];
    double s;
    if (!bt__face_surface(T, f, &r, &sf) ||
        bm_model_hit(mp, &T->src, p, f->n, f->d, &xm[0], &s) != PX_OK ||
        bm_model_hit(md, &T->src, p, f->n, f->d, &xm[1], &s) != PX_OK)
      return 0;
    for (int k = 0; k < 2; k++) {
      px_vec3_t dx = px_v3_sub(xm[k], sf.hit.p);
      m = fmax(m, hypot(px_v3_dot(u, dx), px_v3_dot(v, dx)));
    }
    px_vec3_t off = outside(T, f, sf.hit.p);
    e = hypot(px_v3_dot(u, off), px_v3_dot(v, off));
    tf = sf.hit.t;
  }
  rt_hit_t h;
  T->ex.stats.primary++;
  int hit = rt_intersect(T->s, &r, &h);
  if (strict && (f ? !hit || h.prim != f->prim : hit))
    return 0; /* a sample's exact ray must follow the piece's path itself */
  if (hit && (!f || h.prim != f->prim) && h.t < tf) {
    int g = T->b->face_of_prim[h.prim];
    px_vec3_t in;
    if (g < 0)
      e = INFINITY;
    else if (T->b->face[g].count > 0) {
      in = depth_inside(T, h.prim, h.p);
      e = fmax(e, hypot(px_v3_dot(u, in), px_v3_dot(v, in)));
    } else if (f && plane_ahead(&T->b->face[g], f, sf.hit.p, &in))
      e = fmax(e, hypot(px_v3_dot(u, in), px_v3_dot(v, in)));
    else
      e = INFINITY; /* a plane met first that nothing on f escapes */
  }
  *em = fmax(*em, m);
  *ee = fmax(*ee, e);
  if (path->n > 0 && !(m <= limit)) {
    *over = 1;
    return 0;
  }
  if (!(e <= T->o->rho))
    return 0; /* from the eye too: faces that cut into each other, a plane in front */
  if (!f)
    return 1;
  rt_child_t ch[2];
  int n;
  return children_code(T, &sf, &r, path->n, ch, &n) == code;
}

/* The checks of piece r (face f, NULL for none; along path; the partition's model mp, the
 * drawing's md at the piece's centroid c; children code `code` there): 1 when the models may
 * draw it, with the largest checked error in *err and the rows of the footprint's pseudo-inverse
 * in *pu, *pv (bt__footprint()); 0 when it fails; -1 when the models' error cannot be bounded. The
 * pixel intervals are those on f, or across the beam one unit of depth on for a piece that meets
 * nothing (whose models place nothing: only its edges, the faces' around it, are checked). */
static int piece_ok(tile_t *T, const px_poly2_t *r, const bm_path_t *path, const bm_model_t *mp,
                    const bm_model_t *md, const bm_face_t *f, const double c[2], int code,
                    double *err, px_vec3_t *pu, px_vec3_t *pv) {
  px_vec3_t u, v;
  *err = 0.0;
  if (f) {
    if (!bt__footprint(T, md, f, c, &u, &v))
      return 0;
  } else { /* a plane across the axial ray, one unit ahead */
    bm_face_t across = {.n = md->root ? T->src.z : md->d, .count = 0};
    px_vec3_t o = md->root ? T->src.o : md->o;
    across.d = px_v3_dot(across.n, o) + 1.0;
    if (!bt__footprint(T, md, &across, c, &u, &v))
      return 0;
  }
  *pu = u;
  *pv = v;
  /* the bound of both models' error over the piece, on f */
  double limit = T->o->rho, eb = 0.0;
  int bounded = f && path->n > 0 && T->o->bound != BT_BOUND_PROBE;
  if (bounded) {
    px_variant_t var = T->o->bound == BT_BOUND_PRINTED ? PX_VARIANT_PRINTED : PX_VARIANT_CORRECTED;
    bm_bound_t bp, bd;
    if (bm_model_bound(T->b, &T->src, path, mp, r, f->n, f->d, var, &bp) != PX_OK ||
        bm_model_bound(T->b, &T->src, path, md, r, f->n, f->d, var, &bd) != PX_OK)
      return -1;
    T->st.bounded++;
    eb = pinv_norm(u, v) * fmax(bp.err, bd.err);
    if (!(eb <= T->o->rho))
      return 0;
    limit = eb + BT_SLACK;
  }
  double em = 0.0, ee = 0.0;
  int over = 0, ok = 1;
  for (int k = 0; ok && k < r->n; k++) {
    int j = (k + 1) % r->n;
    double mid[2] = {0.5 * (r->v[k][0] + r->v[j][0]), 0.5 * (r->v[k][1] + r->v[j][1])};
    ok = check_point(T, path, mp, md, f, u, v, code, r->v[k], 0, limit, &em, &ee, &over) &&
         check_point(T, path, mp, md, f, u, v, code, mid, 0, limit, &em, &ee, &over);
  }
  if (ok && T->o->certified) { /* every cell centre inside the piece */
    int i0, i1, j0, j1;
    bt__cell_range(T, r, &i0, &i1, &j0, &j1);
    for (int j = j0; ok && j < j1; j++)
      for (int i = i0; ok && i < i1; i++) {
        double p[2] = {T->a0 + (T->cx0 + i + 0.5) * T->cell, T->b0 + (T->cy0 + j + 0.5) * T->cell};
        ok = !bt__inside(r, p) ||
             check_point(T, path, mp, md, f, u, v, code, p, 1, limit, &em, &ee, &over);
      }
  }
  if (bounded) {
    T->st.violations += (uint64_t)over;
    if (eb > BT_SLACK)
      T->st.max_ratio = fmax(T->st.max_ratio, em / eb);
    if (ok)
      T->st.max_bound = fmax(T->st.max_bound, eb);
  }
  *err = fmax(em, ee);
  return ok;
}

/* Region r along path failed (its model, checks or partition): divided in two and each half
 * partitioned again (near: the faces its parts need), while `worth` it and the divisions along
 * the path allow; traced exactly otherwise. */
static void divide(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int splits,
                   const int *near, int nnear, int level, int worth) {
  px_poly2_t half[2];
  if (worth && splits < 2 * T->o->max_split && bm_halve(r, half)) {
    T->st.divided++;
    bt__beam(T, &half[0], path, splits + 1, near, nnear, level + 1);
    bt__beam(T, &half[1], path, splits + 1, near, nnear, level + 1);
  } else {
    T->st.exact++;
    exact_region(T, r, path);
  }
}

/* Piece r of a beam along path (partitioned by model mp), meeting face g first (-1: none, the
 * background). */
static void piece(tile_t *T, const px_poly2_t *r, const bm_path_t *path, const bm_model_t *mp,
                  int g, int splits, const int *near, int nnear, int level) {
  const bm_face_t *f = g >= 0 ? &T->b->face[g] : NULL;
  int n = path->n;
  double c[2];
  bm_model_t ms[BT_LEVELS];
  if (px_poly2_centroid(r, c) != PX_OK)
    return;
  int ok = prefix_models(T, path, c, ms) == PX_OK;
  /* the children at the centroid */
  rt_ray_t rc;
  rt_surface_t sc;
  rt_child_t ch[2];
  int nch = 0, code = 0;
  if (ok && f) {
    rc = bt__model_ray(T, &ms[n], path, n, c);
    ok = bt__face_surface(T, f, &rc, &sc);
    if (ok)
      code = children_code(T, &sc, &rc, n, ch, &nch);
  }
  double err = 0.0;
  px_vec3_t u, v;
  if (ok)
    ok = piece_ok(T, r, path, mp, &ms[n], f, c, code, &err, &u, &v);
  if (ok < 0) { /* the models' error cannot be bounded: rays */
    T->st.unbounded++;
    T->st.exact++;
    exact_region(T, r, path);
    return;
  }
  if (!ok) {
    /* a piece over a few cells is traced exactly: cheaper than dividing it */
    int i0, i1, j0, j1;
    bt__cell_range(T, r, &i0, &i1, &j0, &j1);
    divide(T, r, path, splits, near, nnear, level, (i1 - i0) * (j1 - j0) > BT_FEW_CELLS);
    return;
  }
  T->st.pieces++;
  T->st.max_error = fmax(T->st.max_error, err);
  if (T->o->measure)
    measure_model(T, r, path, f, &ms[n], u, v);
  /* the piece's own shading (the background's colour), cell share by cell share */
  int i0, i1, j0, j1;
  bt__cell_range(T, r, &i0, &i1, &j0, &j1);
  bm_step_t kid[2];
  for (int k = 0; k < nch; k++) {
    kid[k] = (bm_step_t){g, ch[k].kind == RT_RAY_REFRACT ? PX_EVENT_REFRACT : PX_EVENT_REFLECT,
                         ch[k].ray.ior, 0.0};
    if (T->solids && kid[k].event == PX_EVENT_REFRACT && sc.entering &&
        px_index_disperses(&sc.mat->index))
      /* the scale's glass: n is linear in u ([P89] 3.3); without the scale (--wavelengths
       * pencils with glasses that differ) any nonzero value marks the entry, which nothing
       * else reads */
      kid[k].dn2 = T->plan->wave.scaled ? T->plan->wave.scale.dn0 : 1.0;
  }
  if (T->collect) { /* inside a solid's subtree: drawn by its wavelength intervals */
    /* leaving dispersive glass, total internal reflection and the Fresnel weights change with
     * the wavelength: the solids follow both children whichever exist at u_c */
    int nkid = nch;
    if (f && !sc.entering && sc.mat->kt > 0.0 && px_index_disperses(&sc.mat->index))
      for (int e = 0; e < 2; e++) {
        px_event_t ev = e ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
        int have = 0;
        for (int k = 0; k < nkid; k++)
          have |= kid[k].event == ev;
        if (!have)
          kid[nkid++] = (bm_step_t){g, ev, ev == PX_EVENT_REFRACT ? sc.n2 : sc.n1, 0.0};
      }
    bt__solid_record(T, r, path, g, ms, nkid, kid);
    j1 = j0;
  }
  for (int j = j0; j < j1; j++)
    for (int i = i0; i < i1; i++) {
      double x0 = T->a0 + (T->cx0 + i) * T->cell, y0 = T->b0 + (T->cy0 + j) * T->cell, area, p[2];
      rt_rgb_t w, L = T->s->background;
      if (!bt__clip_box(r, x0, x0 + T->cell, y0, y0 + T->cell, &area, p))
        continue;
      T->st.fragments++;
      if (!bt__model_weight(T, ms, path, n, p, &w))
        continue;
      if (f) {
        rt_ray_t ray = bt__model_ray(T, &ms[n], path, n, p);
        rt_surface_t sf;
        if (!bt__face_surface(T, f, &ray, &sf))
          continue;
        T->ex.node = -1;
        L = rt_shade_direct(T->s, T->plan, &sf, &ray, &T->tr);
      }
      deposit(T, i, j, area, rt_rgb_mul(w, L));
    }
  /* its children: the beam tree */
  for (int k = 0; k < nch; k++) {
    bm_path_t next = *path;
    bm_step_t st = kid[k];
    if (st.dn2 != 0.0 && !T->collect) { /* a white ray enters dispersive glass */
      bt__solid(T, r, path, g, &st, &sc, splits, level);
      continue;
    }
    next.step[next.n++] = st;
    bt__beam(T, r, &next, splits, NULL, 0, level + 1);
  }
}

/* Append to pcs, as pieces of face -1, what of region r the pieces pcs[0 .. n-1] leave: the
 * rays that meet nothing. 0 when the subtraction runs out of room (the caller traces r
 * exactly). */
static int add_background(tile_t *T, const px_poly2_t *r, bm_pieces_t *pcs) {
  enum { CAP = 64 };
  px_poly2_t left[CAP], cut[PX_POLY_MAX];
  int nleft = 1, npieces = pcs->n;
  left[0] = *r;
  double total = px_poly2_area(r), covered = 0.0;
  for (int k = 0; k < npieces; k++)
    covered += px_poly2_area(&pcs->p[k].region);
  if (covered >= total * (1.0 - 1e-12))
    return 1; /* the pieces tile r */
  double tiny = 1e-9 * T->cell * T->cell;
  for (int k = 0; k < npieces && nleft > 0; k++) {
    px_poly2_t next[CAP];
    int nnext = 0;
    for (int i = 0; i < nleft; i++) {
      int nc = 0;
      if (px_poly2_subtract(&left[i], &pcs->p[k].region, tiny, cut, PX_POLY_MAX, &nc) != PX_OK)
        return 0;
      if (nnext + nc > CAP)
        return 0;
      for (int j = 0; j < nc; j++)
        next[nnext++] = cut[j];
    }
    memcpy(left, next, (size_t)nnext * sizeof *left);
    nleft = nnext;
  }
  for (int i = 0; i < nleft; i++) {
    if (pcs->n == pcs->cap) {
      int cap = pcs->cap ? 2 * pcs->cap : 16;
      bm_piece_t *q = realloc(pcs->p, (size_t)cap * sizeof *q);
      if (!q)
        return 0;
      pcs->p = q;
      pcs->cap = cap;
    }
    pcs->p[pcs->n].face = px_poly2_area(&left[i]) > T->min_area ? -1 : -2;
    pcs->p[pcs->n++].region = left[i];
  }
  return 1;
}

/* The beam of parameter polygon r whose rays follow path: partitioned by the faces they meet
 * next (among faces[0 .. nfaces-1] when faces is not NULL), each piece drawn and followed. */
void bt__beam(tile_t *T, const px_poly2_t *r, const bm_path_t *path, int splits, const int *faces,
              int nfaces, int level) {
  double c[2];
  bm_model_t m;
  if (T->collect && T->climit <= 0)
    return; /* a solid's subtree too fine to record: its points are traced (solids.c) */
  if (px_poly2_centroid(r, c) != PX_OK)
    return; /* no area */
  T->st.beams++;
  if (path->n >= BM_MAX_STEPS || level >= T->levels ||
      bm_model(T->b, &T->src, path, c, &m) != PX_OK) {
    T->st.exact++;
    exact_region(T, r, path);
    return;
  }
  bm_pieces_t pcs = {0};
  int unsure = 0, nnear = 0, crowded = 0, *near = T->near + (size_t)level * (size_t)T->b->nface;
  /* a region larger than a few cells that overlaps many faces is divided first */
  int i0, i1, j0, j1;
  bt__cell_range(T, r, &i0, &i1, &j0, &j1);
  int cap = (i1 - i0) * (j1 - j0) > BT_FEW_CELLS ? BT_CROWD : 0;
  if (bm_partition_capped(T->b, &T->src, &m, r, T->min_area, faces, nfaces, near, &nnear, &pcs,
                          &unsure, cap, &crowded) != RT_OK ||
      (!crowded && !add_background(T, r, &pcs))) {
    bm_pieces_free(&pcs);
    T->st.exact++;
    exact_region(T, r, path);
    return;
  }
  /* faces (crowded) or pieces so small against the cells that rays are cheaper */
  int cells = (i1 - i0) * (j1 - j0);
  if ((crowded ? nnear : pcs.n) * BT_DENSE > cells && cells > BT_FEW_CELLS) {
    bm_pieces_free(&pcs);
    T->st.dense++;
    T->st.exact++;
    exact_region(T, r, path);
    return;
  }
  px_poly2_t half[2];
  if (crowded && bm_halve(r, half)) { /* not a division of the error control: no split counted */
    bm_pieces_free(&pcs);
    T->st.crowded++;
    bt__beam(T, &half[0], path, splits, near, nnear, level + 1);
    bt__beam(T, &half[1], path, splits, near, nnear, level + 1);
    return;
  }
  if (unsure || crowded) {
    bm_pieces_free(&pcs);
    divide(T, r, path, splits, near, nnear, level, 1);
    return;
  }
  for (int k = 0; k < pcs.n; k++) {
    if (pcs.p[k].face == -2 || px_poly2_area(&pcs.p[k].region) < BT_SMALL * T->cell * T->cell) {
      T->st.slivers++;
      exact_region(T, &pcs.p[k].region, path);
    } else {
      piece(T, &pcs.p[k].region, path, &m, pcs.p[k].face, splits, near, nnear, level);
    }
  }
  bm_pieces_free(&pcs);
}

/* ---- the image ------------------------------------------------------------------------------ */

static void add_stats(bt_stats_t *to, const bt_stats_t *from) {
  to->beams += from->beams;
  to->pieces += from->pieces;
  to->divided += from->divided;
  to->crowded += from->crowded;
  to->dense += from->dense;
  to->exact += from->exact;
  to->slivers += from->slivers;
  to->fragments += from->fragments;
  to->exact_cells += from->exact_cells;
  to->checks += from->checks;
  to->max_error = fmax(to->max_error, from->max_error);
  to->bounded += from->bounded;
  to->unbounded += from->unbounded;
  to->violations += from->violations;
  to->max_bound = fmax(to->max_bound, from->max_bound);
  to->max_ratio = fmax(to->max_ratio, from->max_ratio);
  rt_stats_add(&to->rays, &from->rays);
  to->measured += from->measured;
  to->with_points += from->with_points;
  to->within += from->within;
  to->within_t += from->within_t;
  to->within_strict += from->within_strict;
  to->mismatches += from->mismatches;
  to->samples_exact += from->samples_exact;
  to->fig10_max = fmax(to->fig10_max, from->fig10_max);
  to->fig10_max_t = fmax(to->fig10_max_t, from->fig10_max_t);
  to->fig10_max_strict = fmax(to->fig10_max_strict, from->fig10_max_strict);
  for (int k = 0; k < BT_HIST_BINS; k++)
    to->hist[k] += from->hist[k];
  to->solids += from->solids;
  to->solid_records += from->solid_records;
  to->solid_fine += from->solid_fine;
  to->solid_failed += from->solid_failed;
  to->solid_wexact += from->solid_wexact;
  to->solid_dark += from->solid_dark;
  to->solid_skipped += from->solid_skipped;
  to->solid_over_budget |= from->solid_over_budget;
  to->solid_points += from->solid_points;
  to->solid_exact += from->solid_exact;
  to->solid_traced += from->solid_traced;
}

rt_status_t bt_render(const rt_scene_t *s, const rt_plan_t *plan, const bt_options_t *o,
                      rt_image_t *img, const bt_extra_t *extra, bt_stats_t *stats, char *why,
                      size_t cap) {
  why[0] = '\0';
  if (stats) /* nothing stale on an early failure (solid_over_budget is read then) */
    memset(stats, 0, sizeof *stats);
  if (!s->bvh)
    return RT_ENOTREADY;
  if (!(o->rho > 0.0) || !isfinite(o->rho) || o->max_split < 0 || o->max_split > 30 ||
      o->bound < BT_BOUND_CORRECTED || o->bound > BT_BOUND_PROBE || o->tile < 1 || o->tile > 256 ||
      o->exact_side < 1 || o->exact_side > 16 || o->spp_side < 1 || o->spp_side > RT_MAX_SPP_SIDE ||
      o->threads < 0) {
    snprintf(why, cap, "beam options out of range");
    return RT_EINVAL;
  }
  int solids = rt_plan_has(plan, RT_EFFECT_DISPERSION);
  if (solids &&
      (plan->spectral != RT_SPECTRAL_PENCIL || (o->wavelengths != 2 && !plan->wave.scaled))) {
    snprintf(why, cap,
             "dispersion by beams needs the plan's wavelength axis (rt_plan_spectral_pencils()), "
             "and image solids need it to be Lambda of one glass: every dispersive material of the "
             "scene sharing it");
    return RT_EINVAL;
  }
  rt_view_t view;
  if (rt_view_make(&s->camera, &view) != RT_OK || img->width != s->camera.width ||
      img->height != s->camera.height) {
    snprintf(why, cap, "the camera or the image size is invalid");
    return RT_EINVAL;
  }
  bm_scene_t b;
  rt_status_t st = bm_scene_build(s, &b, why, cap);
  if (st != RT_OK)
    return st;
  int sp = o->spp_side, W = view.width, H = view.height, ts = o->tile;
  int tx = (W + ts - 1) / ts, ty = (H + ts - 1) / ts, ntiles = tx * ty, done = 0;
  double pixel = 2.0 * view.half_h / H;
  bt_stats_t total;
  memset(&total, 0, sizeof total);
  /* levels of recursion: path steps, divisions of each piece and of each partition, and the
   * divisions of crowded regions down to a few cells (at most 2 log2 of a tile's cells) */
  int levels = BT_LEVELS + 4 * o->max_split + 4 + 48;
  int nt = rt_thread_count(o->threads);
  int failed = 0;
  rt_tree_node_t *trees = NULL;
  if (o->aux && !(trees = malloc((size_t)nt * (size_t)plan->tree_nodes * sizeof *trees))) {
    bm_scene_free(&b);
    return RT_ENOMEM;
  }
  /* the solids' face tests: each face edge's inward normal in the face's plane, by vertex */
  px_vec3_t *edge_in = NULL;
  if (solids) {
    if (!(edge_in = malloc((size_t)(b.nvertex > 0 ? b.nvertex : 1) * sizeof *edge_in))) {
      free(trees);
      bm_scene_free(&b);
      return RT_ENOMEM;
    }
    for (int f = 0; f < b.nface; f++) {
      const bm_face_t *F = &b.face[f];
      const px_vec3_t *v = b.vertex + F->first;
      for (int e = 0; e < F->count; e++)
        edge_in[F->first + e] = px_v3_cross(F->n, px_v3_sub(v[(e + 1) % F->count], v[e]));
    }
  }
  sd_store_t all; /* the solids of every thread, drawn after every tile */
  memset(&all, 0, sizeof all);
  sd_fine_t fine = {0}; /* the groups known too fine, shared */
  size_t sused = 0;     /* bytes the solids hold, shared */
#pragma omp parallel num_threads(nt)
  {
    int tid = 0;
#ifdef _OPENMP
    tid = omp_get_thread_num();
#endif
    tile_t T = {.s = s,
                .plan = plan,
                .o = o,
                .b = &b,
                .src = {0, view.eye, view.right, view.down, view.forward, s->ior},
                .a0 = -view.half_w,
                .b0 = -view.half_h,
                .cell = pixel / sp,
                .pixel = pixel,
                .min_area = 1e-6 * (pixel / sp) * (pixel / sp),
                .levels = levels,
                .solids = solids,
                .edge_in = edge_in,
                .fine = solids ? &fine : NULL,
                .sused = &sused,
                .failed = &failed};
    if (solids) { /* the range's ends, u_c (the d-line) and halfway between */
      double ua = plan->wave.u_edge[0], ub = plan->wave.u_edge[RT_MAX_BINS],
             uc = plan->wave.scale.lambda0;
      for (int k = 0; k <= BT_SOLID_SEGS; k++) {
        int h = BT_SOLID_SEGS / 2;
        T.u[k] = k <= h ? ua + (uc - ua) * k / h : uc + (ub - uc) * (k - h) / h;
      }
    }
    T.acc = malloc((size_t)ts * ts * sp * sp * 3 * sizeof(double));
    T.near = malloc((size_t)levels * (size_t)(b.nface > 0 ? b.nface : 1) * sizeof(int));
    T.ex = xr_exact_make(s, plan, NULL);
    T.tr = xr_exact_tracer(&T.ex);
    size_t tcells = (size_t)ts * ts * sp * sp;
    rt_tree_node_t *probe_nodes = NULL;
    if (o->measure) {
      T.nodes = plan->tree_nodes;
      probe_nodes = malloc((size_t)T.nodes * sizeof *probe_nodes);
      T.probe = rt_tree_make(probe_nodes, T.nodes);
      T.mex = xr_exact_make(s, plan, &T.probe);
      T.err = malloc(tcells * 3 * sizeof *T.err);
      T.pts = malloc(tcells);
      T.seen = malloc(tcells * (size_t)T.nodes);
      if (!probe_nodes || !T.err || !T.pts || !T.seen) {
#pragma omp atomic write
        failed = 1;
      }
    }
    rt_tree_t tree = trees ? rt_tree_make(trees + (size_t)tid * plan->tree_nodes, plan->tree_nodes)
                           : rt_tree_make(NULL, 0);
    if (!T.acc || !T.near) {
#pragma omp atomic write
      failed = 1;
    }
#pragma omp for schedule(dynamic, 1)
    for (int t = 0; t < ntiles; t++) {
      int failed_now;
#pragma omp atomic read
      failed_now = failed;
      if (failed_now)
        continue;
      int px0 = (t % tx) * ts, py0 = (t / tx) * ts;
      int pw = px0 + ts <= W ? ts : W - px0, ph = py0 + ts <= H ? ts : H - py0;
      T.cx0 = px0 * sp;
      T.cy0 = py0 * sp;
      T.tcw = pw * sp;
      T.tch = ph * sp;
      memset(T.acc, 0, (size_t)T.tcw * T.tch * 3 * sizeof(double));
      if (o->measure) {
        size_t nc = (size_t)T.tcw * T.tch;
        memset(T.err, 0, nc * 3 * sizeof *T.err);
        memset(T.pts, 0, nc);
        memset(T.seen, 0, nc * (size_t)T.nodes);
      }
      double x0 = T.a0 + T.cx0 * T.cell, x1 = T.a0 + (T.cx0 + T.tcw) * T.cell;
      double y0 = T.b0 + T.cy0 * T.cell, y1 = T.b0 + (T.cy0 + T.tch) * T.cell;
      px_poly2_t root = {4, {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
      bm_path_t path = {0};
      bt__beam(&T, &root, &path, 0, NULL, 0, 0);
      if (o->measure)
        measure_tile(&T, extra, W);
      /* the tile's cells into its pixels (a box filter over the s x s cells) */
      for (int j = 0; j < ph; j++)
        for (int i = 0; i < pw; i++) {
          double sum[3] = {0, 0, 0};
          for (int b2 = 0; b2 < sp; b2++)
            for (int a2 = 0; a2 < sp; a2++) {
              const double *a = T.acc + 3 * ((size_t)(j * sp + b2) * T.tcw + (size_t)(i * sp + a2));
              sum[0] += a[0];
              sum[1] += a[1];
              sum[2] += a[2];
            }
          size_t k = (size_t)(py0 + j) * W + (size_t)(px0 + i);
          for (int c = 0; c < 3; c++)
            img->ch[RT_CH_R + c][k] = (float)(sum[c] / (sp * sp));
          if (trees) { /* the auxiliary channels from the exact centre ray's tree */
            T.ex.tree = &tree;
            rt_ray_t cr = rt_view_ray(&view, px0 + i + 0.5, py0 + j + 0.5, s->ior);
            xr_exact_primary(&T.ex, &cr);
            rt_image_set_aux(img, s, k, &tree);
            T.ex.tree = NULL;
          }
        }
      if (o->progress) {
#pragma omp critical(bt_progress)
        o->progress(o->progress_ctx, ++done, ntiles);
      }
    }
    if (solids && !bt__solids_draw(&T, &all, img, W, H, sp)) {
#pragma omp atomic write
      failed = 1;
    }
    T.st.rays = T.ex.stats;
#pragma omp critical(bt_stats)
    add_stats(&total, &T.st);
    free(T.acc);
    free(T.near);
    free(T.rec);
    free(T.smod);
    free(T.ent);
    free(T.pt);
    free(probe_nodes);
    free(T.err);
    free(T.pts);
    free(T.seen);
  }
  free(trees);
  free(edge_in);
  free(fine.ent);
  bm_scene_free(&b);
  bt__store_free(&all);
  if (stats) /* on failure too: solid_over_budget says why */
    *stats = total;
  return failed ? RT_ENOMEM : RT_OK;
}
