/* illuminance.c -- the two methods over a light's grid faces (source.c), in parallel over rows of
 * the grid, each thread depositing into its own copy of the map's fluxes, summed at the end. */
#include "light/illuminance.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "beam/beam.h"
#include "core/image.h"
#include "core/intersect.h"
#include "internal.h"

static double wall_seconds(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int lt_method_parse(const char *name) {
  if (strcmp(name, "grid-pencil") == 0)
    return LT_METHOD_GRID_PENCIL;
  if (strcmp(name, "photons") == 0)
    return LT_METHOD_PHOTONS;
  if (strcmp(name, "polygons") == 0)
    return LT_METHOD_POLYGONS;
  return -1;
}

const char *lt_method_name(lt_method_t m) {
  return m == LT_METHOD_PHOTONS ? "photons" : m == LT_METHOD_POLYGONS ? "polygons" : "grid-pencil";
}

int lt_area_filter_parse(const char *name) {
  static const char *const names[] = {"none", "quadratic", "linear"};
  for (int k = 0; k < 3; k++)
    if (strcmp(name, names[k]) == 0)
      return k;
  return -1;
}

const char *lt_area_filter_name(lt_area_filter_t f) {
  return f == LT_AREA_FILTER_QUADRATIC ? "quadratic"
         : f == LT_AREA_FILTER_LINEAR  ? "linear"
                                       : "none";
}

rt_status_t lt_method_check(const rt_scene_t *s, lt_method_t m, char *why, size_t cap) {
  if (m != LT_METHOD_POLYGONS)
    return RT_OK;
  for (int l = 0; l < s->nlight; l++)
    if (s->light[l].kind == RT_LIGHT_AREA) {
      snprintf(why, cap,
               "light %d is an area light: illuminance polygons take point and parallel lights "
               "(use grid-pencil or photons)",
               l);
      return RT_EINVAL;
    }
  bm_scene_t b;
  rt_status_t st = bm_scene_build(s, &b, why, cap);
  if (st == RT_OK)
    bm_scene_free(&b);
  return st;
}

rt_status_t lt_map_alloc(lt_map_t *m, int width, int height, double u0, double u1, double v0,
                         double v1) {
  memset(m, 0, sizeof *m);
  if (width < 1 || height < 1 || width > LT_MAX_GRID || height > LT_MAX_GRID || !(u1 > u0) ||
      !(v1 > v0) || !isfinite(u1 - u0) || !isfinite(v1 - v0))
    return RT_EINVAL;
  m->e = calloc(3 * (size_t)width * (size_t)height, sizeof *m->e);
  if (!m->e)
    return RT_ENOMEM;
  *m = (lt_map_t){width, height, u0, u1, v0, v1, m->e};
  return RT_OK;
}

void lt_map_free(lt_map_t *m) {
  free(m->e);
  m->e = NULL;
}

/* 1 when object o is a plane or a polygon; its plane's point and normal in *p, *n. */
static int planar(const rt_scene_t *s, int o, px_vec3_t *p, px_vec3_t *n) {
  const rt_object_t *ob = &s->object[o];
  if (ob->nprim != 1)
    return 0;
  const rt_prim_t *pr = &s->prim[ob->first_prim];
  if (pr->kind == RT_PRIM_PLANE) {
    *p = pr->plane.p;
    *n = pr->plane.n;
    return 1;
  }
  if (pr->kind == RT_PRIM_POLYGON) {
    *p = s->vertex[pr->polygon.first];
    *n = pr->polygon.n;
    return 1;
  }
  return 0;
}

rt_status_t lt_receiver_make(const rt_scene_t *s, const int *obj, int n, lt_receiver_t *r,
                             char *why, size_t cap) {
  memset(r, 0, sizeof *r);
  if (n < 1 || n > LT_MAX_RECEIVERS) {
    snprintf(why, cap, "a receiver joins 1 to %d objects, not %d", LT_MAX_RECEIVERS, n);
    return RT_EINVAL;
  }
  px_vec3_t p0 = px_v3(0, 0, 0), n0 = px_v3(0, 0, 1);
  for (int k = 0; k < n; k++) {
    px_vec3_t p, nn;
    if (obj[k] < 0 || obj[k] >= s->nobject || !planar(s, obj[k], &p, &nn)) {
      snprintf(why, cap, "'%s' is not a plane or a polygon (maps are made on flat receivers)",
               obj[k] >= 0 && obj[k] < s->nobject ? s->object[obj[k]].name : "?");
      return RT_EINVAL;
    }
    if (k == 0) {
      p0 = p;
      n0 = nn;
    } else {
      double scale = 1.0 + px_v3_norm(p0) + px_v3_norm(p);
      if (fabs(fabs(px_v3_dot(nn, n0)) - 1.0) > 1e-12 ||
          fabs(px_v3_dot(px_v3_sub(p, p0), n0)) > 1e-9 * scale) {
        snprintf(why, cap, "'%s' and '%s' are not in one plane", s->object[obj[0]].name,
                 s->object[obj[k]].name);
        return RT_EINVAL;
      }
    }
    r->object[r->n++] = obj[k];
  }
  const rt_prim_t *pr = &s->prim[s->object[obj[0]].first_prim];
  r->p = p0;
  r->normal = n0;
  if (pr->kind == RT_PRIM_PLANE) {
    r->u = pr->plane.u;
    r->v = pr->plane.v;
  } else {
    px_vec3_t e = px_v3_sub(s->vertex[pr->polygon.first + 1], s->vertex[pr->polygon.first]);
    e = px_v3_sub(e, px_v3_scale(n0, px_v3_dot(e, n0)));
    r->u = px_v3_unit(e);
    r->v = px_v3_cross(n0, r->u);
  }
  return RT_OK;
}

static void widen(double b[4], double u, double v) {
  b[0] = fmin(b[0], u);
  b[1] = fmax(b[1], u);
  b[2] = fmin(b[2], v);
  b[3] = fmax(b[3], v);
}

/* 1 when receiver r has a plane among its objects (else only polygons). */
static int has_plane(const rt_scene_t *s, const lt_receiver_t *r) {
  for (int k = 0; k < r->n; k++)
    if (s->prim[s->object[r->object[k]].first_prim].kind != RT_PRIM_POLYGON)
      return 1;
  return 0;
}

/* The 8 corners of primitive p's bounding box, when it is bounded and not part of receiver r. */
static int other_box(const rt_scene_t *s, const lt_receiver_t *r, int p, px_vec3_t c[8]) {
  px_vec3_t lo, hi;
  for (int k = 0; k < r->n; k++)
    if (s->prim[p].object == r->object[k])
      return 0;
  if (!rt_prim_bounds(s, p, &lo, &hi))
    return 0;
  for (int k = 0; k < 8; k++)
    c[k] = px_v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
  return 1;
}

int lt_default_extent(const rt_scene_t *s, const lt_receiver_t *r, double ext[4]) {
  double b[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  if (!has_plane(s, r)) { /* polygons only: their bounds */
    for (int k = 0; k < r->n; k++) {
      const rt_prim_t *pr = &s->prim[s->object[r->object[k]].first_prim];
      for (int i = 0; i < pr->polygon.count; i++) {
        px_vec3_t d = px_v3_sub(s->vertex[pr->polygon.first + i], r->p);
        widen(b, px_v3_dot(d, r->u), px_v3_dot(d, r->v));
      }
    }
    memcpy(ext, b, sizeof b);
    return b[1] > b[0] && b[3] > b[2];
  }
  for (int p = 0; p < s->nprim; p++) {
    px_vec3_t c[8];
    if (!other_box(s, r, p, c))
      continue;
    for (int k = 0; k < 8; k++) {
      px_vec3_t d = px_v3_sub(c[k], r->p);
      widen(b, px_v3_dot(d, r->u), px_v3_dot(d, r->v));
    }
  }
  if (!(b[1] >= b[0]))
    return 0;
  double cu = 0.5 * (b[0] + b[1]), cv = 0.5 * (b[2] + b[3]), h = fmax(b[1] - b[0], b[3] - b[2]);
  if (!(h > 0))
    h = 1.0;
  ext[0] = cu - h;
  ext[1] = cu + h;
  ext[2] = cv - h;
  ext[3] = cv + h;
  return 1;
}

/* Where the ray from light point *l through corner c (l NULL: the ray of a parallel light along
 * dir through c) meets the receiver plane, in (u, v); a corner level with a point light or above
 * it (its shadow unbounded) lands `far` out along the shadow's direction. 0 when c casts no
 * shadow on the plane (c beyond the plane, the light behind it or parallel to it). */
static int shadow_point(const lt_receiver_t *r, const px_vec3_t *l, px_vec3_t dir, px_vec3_t c,
                        double far, double *u, double *v) {
  double hc = px_v3_dot(px_v3_sub(c, r->p), r->normal);
  px_vec3_t q;
  if (!l) {
    double dn = px_v3_dot(dir, r->normal);
    if (dn == 0.0 || -hc / dn < 0.0)
      return 0;
    q = px_v3_add(c, px_v3_scale(dir, -hc / dn));
  } else {
    double hl = px_v3_dot(px_v3_sub(*l, r->p), r->normal);
    if (hl == 0.0 || hc * hl < 0.0)
      return 0;
    px_vec3_t d = px_v3_sub(c, *l);
    if (fabs(hc) < fabs(hl) * (1.0 - 1e-9)) {
      q = px_v3_add(*l, px_v3_scale(d, hl / (hl - hc)));
    } else { /* unbounded: the shadow runs away from the light along the plane */
      px_vec3_t t = px_v3_sub(d, px_v3_scale(r->normal, px_v3_dot(d, r->normal)));
      double tn = px_v3_norm(t);
      if (!(tn > 0.0))
        return 0;
      q = px_v3_add(c, px_v3_scale(t, far / tn));
    }
  }
  px_vec3_t e = px_v3_sub(q, r->p);
  *u = px_v3_dot(e, r->u);
  *v = px_v3_dot(e, r->v);
  return 1;
}

int lt_light_extent(const rt_scene_t *s, const lt_receiver_t *r, int light, double ext[4]) {
  if (!lt_default_extent(s, r, ext))
    return 0;
  if (!has_plane(s, r) || light < 0 || light >= s->nlight)
    return 1; /* polygons only: their own bounds, as lt_default_extent() */
  const rt_light_t *L = &s->light[light];
  double cu = 0.5 * (ext[0] + ext[1]), cv = 0.5 * (ext[2] + ext[3]);
  double half = 0.5 * (ext[1] - ext[0]), far = 8.0 * half;
  /* a point light, an area light's four corners, or a parallel light's direction */
  px_vec3_t src[4] = {L->v, L->v, L->v, L->v};
  int nsrc = L->kind == RT_LIGHT_AREA ? 4 : 1, parallel = L->kind == RT_LIGHT_PARALLEL;
  for (int k = 0; k < nsrc && L->kind == RT_LIGHT_AREA; k++)
    src[k] = px_v3_add(L->v, px_v3_add(px_v3_scale(L->eu, (k & 1) ? 0.5 : -0.5),
                                       px_v3_scale(L->ev, (k & 2) ? 0.5 : -0.5)));
  double b[4] = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  for (int p = 0; p < s->nprim; p++) {
    px_vec3_t c[8];
    if (!other_box(s, r, p, c))
      continue;
    for (int k = 0; k < 8; k++) {
      for (int i = 0; i < nsrc; i++) {
        double u, v;
        if (shadow_point(r, parallel ? NULL : &src[i], L->v, c[k], far, &u, &v))
          widen(b, u, v);
      }
    }
  }
  if (!(b[1] >= b[0]))
    return 1;
  /* a quarter more on each side for light a lens spreads past the shadow's edge, within the
   * bound of far around the objects */
  double mu = 0.25 * (b[1] - b[0]), mv = 0.25 * (b[3] - b[2]);
  ext[0] = fmax(cu - far, fmin(ext[0], b[0] - mu));
  ext[1] = fmin(cu + far, fmax(ext[1], b[1] + mu));
  ext[2] = fmax(cv - far, fmin(ext[2], b[2] - mv));
  ext[3] = fmin(cv + far, fmax(ext[3], b[3] + mv));
  return 1;
}

/* The rays of one thread and where their flux goes. */
typedef struct {
  lt_ctx_t C;
  lt_accum_t A;
  int max_split;
  double linear_tol, uniform_tol;
  int area_filter; /* lt_options_t.area_filter */
} worker_t;

static rt_rgb_t flux_of(const lt_face_t *f, double measure, rt_rgb_t w) {
  return rt_rgb_scale(rt_rgb_mul(f->power, w), measure);
}

/* The flux phi of end a at a point: a receiver end deposited as a photon (counted as one when
 * `photon`), an escape or an absorption entered in the ledger. */
static void settle(worker_t *W, const lt_arrival_t *a, rt_rgb_t phi, int photon) {
  lt__settle(&W->A, a, phi, photon);
}

/* ---- photons ------------------------------------------------------------------------------ */

/* Row j of a side x side grid of rays through the centres of the grid's cells, each carrying the
 * flux of its cell (two triangles' measure). */
static void photon_row(worker_t *W, const lt_face_t *f, int side, int j) {
  lt_arrivals_t arr;
  double h = 1.0 / side;
  for (int i = 0; i < side; i++) {
    double a0 = i * h, b0 = j * h, a1 = a0 + h, b1 = b0 + h;
    double p00[2] = {a0, b0}, p10[2] = {a1, b0}, p11[2] = {a1, b1}, p01[2] = {a0, b1};
    double meas = (lt__face_measure(f, p00, p10, p11) + lt__face_measure(f, p00, p11, p01)) *
                  lt__face_weight(f, a0 + 0.5 * h, b0 + 0.5 * h);
    rt_ray_t r = lt__face_ray(f, a0 + 0.5 * h, b0 + 0.5 * h);
    lt__trace(&W->C, &r, &arr);
    for (int k = 0; k < arr.n; k++)
      settle(W, &arr.a[k], flux_of(f, meas, arr.a[k].w), 1);
  }
}

/* ---- grid-pencil tracing ----------------------------------------------------------------- */

/* The arrival of x on path sig, or NULL. Signatures are unique within a tree, and neighbouring
 * rays' trees list their shared paths mostly in the same order, so index `hint` (where the path
 * stands in the asking ray's tree) is looked at first: the same answer as the plain search, in
 * one comparison where the trees agree instead of a scan of up to LT_MAX_ARRIVALS. */
static const lt_arrival_t *find(const lt_arrivals_t *x, uint64_t sig, int hint) {
  if (hint >= 0 && hint < x->n && x->a[hint].sig == sig)
    return &x->a[hint];
  for (int k = 0; k < x->n; k++)
    if (x->a[k].sig == sig)
      return &x->a[k];
  return NULL;
}

/* 1 when some path the three rays share to the receiver lands near the map (its triangle's
 * bounds meet the map's rectangle): only those pencils' linearity matters. */
static int on_map(const worker_t *W, const lt_arrivals_t *x[3]) {
  const lt_map_t *m = W->A.m;
  for (int k = 0; k < x[0]->n; k++) {
    const lt_arrival_t *a = &x[0]->a[k], *b, *c;
    if (a->kind != LT_END_RECEIVER || !(b = find(x[1], a->sig, k)) || !(c = find(x[2], a->sig, k)))
      continue;
    double u0 = fmin(a->u, fmin(b->u, c->u)), u1 = fmax(a->u, fmax(b->u, c->u));
    double v0 = fmin(a->v, fmin(b->v, c->v)), v1 = fmax(a->v, fmax(b->v, c->v));
    if (!(u1 < m->u0 || u0 > m->u1 || v1 < m->v0 || v0 > m->v1))
      return 1;
  }
  return 0;
}

/* 1 when, for every receiver path the corners share, each edge's midpoint ray follows it too and
 * lands within `tol` cells of the midpoint of the corners' landings, and the pencil's flux
 * density over the quarters the midpoints make is within W->uniform_tol of the whole's (the
 * pencil's map to the receiver is linear enough to spread its flux evenly). */
/* Signed area of the receiver triangle a, b, c. */
static double signed_area(const lt_arrival_t *a, const lt_arrival_t *b, const lt_arrival_t *c) {
  return 0.5 * ((b->u - a->u) * (c->v - a->v) - (c->u - a->u) * (b->v - a->v));
}

static int linear(const worker_t *W, const lt_face_t *f, double p[3][2], double pm[3][2],
                  const lt_arrivals_t *x[3], const lt_arrivals_t xm[3], double tol) {
  const lt_map_t *m = W->A.m;
  double su = m->width / (m->u1 - m->u0), sv = m->height / (m->v1 - m->v0);
  double all = 0.0; /* the pencil's light to the receiver (corner 0's weights) */
  for (int k = 0; k < x[0]->n; k++)
    if (x[0]->a[k].kind == LT_END_RECEIVER)
      all += x[0]->a[k].w.r + x[0]->a[k].w.g + x[0]->a[k].w.b;
  for (int k = 0; k < x[0]->n; k++) {
    const lt_arrival_t *c[3] = {&x[0]->a[k], NULL, NULL}, *mid[3];
    if (c[0]->kind != LT_END_RECEIVER || !(c[1] = find(x[1], c[0]->sig, k)) ||
        !(c[2] = find(x[2], c[0]->sig, k)))
      continue;
    /* a path that carries less than the uniformity tolerance's share of the pencil's light can
     * misplace no more than that share however its triangle bends: not worth a division (as
     * unshared paths in pencil()) */
    if (W->uniform_tol > 0 && c[0]->w.r + c[0]->w.g + c[0]->w.b <= W->uniform_tol * all)
      continue;
    for (int e = 0; e < 3; e++) { /* midpoint e lies between corners e and e + 1 */
      if (!(mid[e] = find(&xm[e], c[0]->sig, k)))
        return 0;
      double du = (mid[e]->u - 0.5 * (c[e]->u + c[(e + 1) % 3]->u)) * su;
      double dv = (mid[e]->v - 0.5 * (c[e]->v + c[(e + 1) % 3]->v)) * sv;
      if (fabs(du) > tol || fabs(dv) > tol)
        return 0;
    }
    /* the flux density of the four quarters against the whole's: uniform within W->uniform_tol,
     * none turned over */
    double a = signed_area(c[0], c[1], c[2]), meas = lt__face_measure(f, p[0], p[1], p[2]);
    const lt_arrival_t *q[4][3] = {{c[0], mid[0], mid[2]},
                                   {mid[0], c[1], mid[1]},
                                   {mid[2], mid[1], c[2]},
                                   {mid[0], mid[1], mid[2]}};
    double *qp[4][3] = {
        {p[0], pm[0], pm[2]}, {pm[0], p[1], pm[1]}, {pm[2], pm[1], p[2]}, {pm[0], pm[1], pm[2]}};
    for (int t = 0; t < 4 && W->uniform_tol > 0; t++) {
      double at = signed_area(q[t][0], q[t][1], q[t][2]);
      double mt = lt__face_measure(f, qp[t][0], qp[t][1], qp[t][2]);
      if (!(at * a > 0) || fabs((mt / at) / (meas / a) - 1.0) > W->uniform_tol)
        return 0;
    }
  }
  return 1;
}

/* The receiver landing of path `sig` of the ray from `origin` along d (or 0 when it has none). */
static int landing(worker_t *W, px_vec3_t origin, px_vec3_t d, double ior, uint64_t sig,
                   double uv[2]) {
  rt_ray_t r = {origin, d, 0.0, INFINITY, ior, -1, 0.0f};
  lt_arrivals_t x;
  lt__trace(&W->C, &r, &x);
  const lt_arrival_t *e = find(&x, sig, -1);
  if (!e || e->kind != LT_END_RECEIVER)
    return 0;
  uv[0] = e->u;
  uv[1] = e->v;
  return 1;
}

/* deposit_filtered() where the displacement's patch cannot be trusted (a ray that leaves the path
 * somewhere in the mesh cell, or a landing too far from the patch): the displacements are traced
 * exactly from n x n source positions across the cell (n from the reach, 3..8) and each copy of
 * the pencil lands where its centre ray does; a copy whose ray leaves the path stays where the
 * mesh point puts it. The pencil's light is still spread over the cell, so that it balances the
 * light its filtered neighbours spread over its place (left as it is, it would not). c0: the
 * centre ray's own landing. */
static void resample(worker_t *W, const lt_face_t *f, double p[3][2], uint64_t sig,
                     const double uv[3][2], rt_rgb_t phi, const double c0[2], double reach) {
  int n = (int)fmin(8.0, fmax(3.0, ceil(reach / 2.0)));
  rt_rgb_t share = rt_rgb_scale(phi, 1.0 / ((double)n * n));
  rt_ray_t c =
      lt__face_ray(f, (p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      double a = (i + 0.5) / n - 0.5, b = (j + 0.5) / n - 0.5, at[2], tri[3][2];
      px_vec3_t o =
          px_v3_add(c.o, px_v3_add(px_v3_scale(f->step[0], a), px_v3_scale(f->step[1], b)));
      int ok = landing(W, o, c.d, c.ior, sig, at);
      for (int v = 0; v < 3; v++)
        for (int e = 0; e < 2; e++)
          tri[v][e] = ok ? uv[v][e] + at[e] - c0[e] : uv[v][e];
      lt__deposit_triangle(&W->A, tri, share);
    }
  W->C.st.resampled++;
}

/* The quadratic Lagrange weights of the points -1/2, 0, 1/2 at s in [-1/2, 1/2]. */
static void lagrange3(double s, double w[3]) {
  w[0] = 2.0 * s * (s - 0.5);
  w[1] = 1.0 - 4.0 * s * s;
  w[2] = 2.0 * s * (s + 0.5);
}

/* The space-variant filter of the 1989 paper's Eqs. (9)-(12) for one pencil of an area light's
 * mesh point. The light of the mesh cell around the point is the point's pattern shifted as the
 * source moves over the cell (Eq. 9), the shift the displacement of a ray's landing when the
 * source moves and the ray's direction stays fixed (step 3b): here the pencil's triangle moved
 * by its centre ray's displacement. A pencil of fixed directions carries the same flux from every
 * point of the cell, so the cell's light is the pencil's flux spread over its landings from all
 * of the cell's points. Those landings are interpolated over the cell (lt_area_filter_t):
 *  - LT_AREA_FILTER_QUADRATIC: the biquadratic patch of the landings from 3 x 3 points of the
 *    cell (corners, edge midpoints, centre);
 *  - LT_AREA_FILTER_LINEAR, the printed Eq. (10), v_i = (i/n) Delta_I: the bilinear patch of
 *    the corners' landings. Where the landing is curved in the source's position (a lens's
 *    aberration) each pencil's mean landing is off by the curvature, G'' w^2 / 3 for a landing
 *    G over a cell of half-width w, and over a lens's pattern the error is systematic: light
 *    drifts outwards (docs/illuminance.md, "Area lights", measures it).
 * The spread is a sum of K x K copies, K such that neighbouring copies lie within a cell (at most
 * 16); flux is kept exactly. Where the patch cannot be trusted (the centre ray leaves the path
 * from a point of the cell, or a landing lies off the line through the centre's and its mirror
 * point's by more than half a cell plus a tenth of the reach) the displacements are traced
 * exactly from n x n points instead (resample()); a pencil whose own centre ray does not follow
 * its path is left as it is (counted as unshifted). */
static void deposit_filtered(worker_t *W, const lt_face_t *f, double p[3][2], uint64_t sig,
                             const double uv[3][2], rt_rgb_t phi) {
  const lt_map_t *m = W->A.m;
  int quad = W->area_filter == LT_AREA_FILTER_QUADRATIC;
  double c0[2],
      q[3][3][2]; /* the centre ray's landing; q[i][j]: from s = i/2 - 1/2, t = j/2 - 1/2 */
  rt_ray_t c =
      lt__face_ray(f, (p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3);
  if (!landing(W, c.o, c.d, c.ior, sig, c0)) {
    W->C.st.unshifted++;
    lt__deposit_triangle(&W->A, uv, phi);
    return;
  }
  int ok = 1;
  for (int i = 0; i < 3 && ok; i++)
    for (int j = 0; j < 3 && ok; j++)
      if ((i != 1 && j != 1) || (quad && (i != 1 || j != 1))) {
        px_vec3_t o = px_v3_add(c.o, px_v3_add(px_v3_scale(f->step[0], 0.5 * i - 0.5),
                                               px_v3_scale(f->step[1], 0.5 * j - 0.5)));
        ok = landing(W, o, c.d, c.ior, sig, q[i][j]);
      }
  double du = (m->u1 - m->u0) / m->width, dv = (m->v1 - m->v0) / m->height, reach = 0.0, bend = 0.0;
  for (int i = 0; i < 3 && ok; i++)
    for (int j = 0; j < 3; j++)
      if ((i != 1 && j != 1) || (quad && (i != 1 || j != 1))) {
        reach = fmax(reach, fmax(fabs(q[i][j][0] - c0[0]) / du, fabs(q[i][j][1] - c0[1]) / dv));
        for (int e = 0; e < 2; e++) /* off the line through the centre and the mirror point */
          bend = fmax(bend, fabs(0.5 * (q[i][j][e] + q[2 - i][2 - j][e]) - c0[e]) / (e ? dv : du));
      }
  if (!ok || bend > 0.5 + 0.1 * reach) {
    resample(W, f, p, sig, uv, phi, c0, reach);
    return;
  }
  q[1][1][0] = c0[0];
  q[1][1][1] = c0[1];
  if (!quad) /* the bilinear patch of the corners, as Lagrange data */
    for (int e = 0; e < 2; e++) {
      q[1][0][e] = 0.5 * (q[0][0][e] + q[2][0][e]);
      q[1][2][e] = 0.5 * (q[0][2][e] + q[2][2][e]);
      q[0][1][e] = 0.5 * (q[0][0][e] + q[0][2][e]);
      q[2][1][e] = 0.5 * (q[2][0][e] + q[2][2][e]);
      q[1][1][e] = 0.5 * (q[1][0][e] + q[1][2][e]);
    }
  int k = (int)fmin(16.0, fmax(1.0, ceil(2.0 * reach)));
  rt_rgb_t share = rt_rgb_scale(phi, 1.0 / ((double)k * k));
  for (int s = 0; s < k; s++)
    for (int t = 0; t < k; t++) {
      double ws[3], wt[3], sh[2] = {-c0[0], -c0[1]}, tri[3][2];
      lagrange3((s + 0.5) / k - 0.5, ws);
      lagrange3((t + 0.5) / k - 0.5, wt);
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          for (int e = 0; e < 2; e++)
            sh[e] += ws[i] * wt[j] * q[i][j][e];
      for (int v = 0; v < 3; v++)
        for (int e = 0; e < 2; e++)
          tri[v][e] = uv[v][e] + sh[e];
      lt__deposit_triangle(&W->A, tri, share);
    }
  W->C.st.filtered++;
}

/* The pencil of the triangle of grid parameters p[3] whose rays' ends are x[3]: a receiver
 * triangle for every path the three rays share, its flux spread evenly over it. The pencil is
 * divided into four (its edges' midpoint rays traced), up to `split` times, where the three rays
 * do not all follow the same paths to the receiver (an edge of an object or a shadow inside the
 * pencil), and,
 * with a linearity tolerance, where a receiver triangle near the map is not linear enough (a
 * midpoint ray lands off its edge's midpoint by more than the tolerance: near a rim, a fold, a
 * caustic). Past the limit, the unshared ends count as photons of a third of the pencil each. */
static void pencil(worker_t *W, const lt_face_t *f, double p[3][2], const lt_arrivals_t *x[3],
                   int split) {
  /* only paths to the receiver decide: an escape or an absorption that the three rays do not
   * share changes no cell of the map (it is settled in the ledger as photons) */
  double apart = 0.0, all = 0.0; /* receiver flux of the unshared paths, of all (mean weight) */
  for (int v = 0; v < 3; v++)
    for (int k = 0; k < x[v]->n; k++) {
      const lt_arrival_t *a = &x[v]->a[k];
      if (a->kind != LT_END_RECEIVER)
        continue;
      double w = a->w.r + a->w.g + a->w.b;
      all += w;
      if (!find(x[(v + 1) % 3], a->sig, k) || !find(x[(v + 2) % 3], a->sig, k))
        apart += w;
    }
  /* with a uniformity tolerance, paths that carry less than that share of the pencil's light to
   * the receiver are not worth a division: their ends are settled as photons, close to where
   * they belong (within the pencil's footprint) */
  int shared = apart == 0.0 || (W->uniform_tol > 0 && apart <= W->uniform_tol * all);
  double m[3][2];
  lt_arrivals_t xm[3]; /* 7.7 kB a level, at most 12 levels deep */
  int traced = 0;
  if (split > 0 && (!shared || (W->linear_tol > 0 && on_map(W, x)))) {
    for (int e = 0; e < 3; e++) {
      m[e][0] = 0.5 * (p[e][0] + p[(e + 1) % 3][0]);
      m[e][1] = 0.5 * (p[e][1] + p[(e + 1) % 3][1]);
      rt_ray_t r = lt__face_ray(f, m[e][0], m[e][1]);
      lt__trace(&W->C, &r, &xm[e]);
    }
    traced = 1;
    if (shared && !linear(W, f, p, m, x, xm, W->linear_tol)) {
      shared = 0;
      W->C.st.nonlinear++;
    }
  }
  if (!shared && traced) {
    W->C.st.divided++;
    /* corners p0, p1, p2 and midpoints m0 (p0 p1), m1 (p1 p2), m2 (p2 p0) */
    double t[4][3][2] = {{{p[0][0], p[0][1]}, {m[0][0], m[0][1]}, {m[2][0], m[2][1]}},
                         {{m[0][0], m[0][1]}, {p[1][0], p[1][1]}, {m[1][0], m[1][1]}},
                         {{m[2][0], m[2][1]}, {m[1][0], m[1][1]}, {p[2][0], p[2][1]}},
                         {{m[0][0], m[0][1]}, {m[1][0], m[1][1]}, {m[2][0], m[2][1]}}};
    const lt_arrivals_t *tx[4][3] = {{x[0], &xm[0], &xm[2]},
                                     {&xm[0], x[1], &xm[1]},
                                     {&xm[2], &xm[1], x[2]},
                                     {&xm[0], &xm[1], &xm[2]}};
    for (int k = 0; k < 4; k++)
      pencil(W, f, t[k], tx[k], split - 1);
    return;
  }
  /* a Lambertian source's weight at the pencil's centre: the midpoint rule over its directions */
  double meas =
      lt__face_measure(f, p[0], p[1], p[2]) *
      lt__face_weight(f, (p[0][0] + p[1][0] + p[2][0]) / 3, (p[0][1] + p[1][1] + p[2][1]) / 3);
  for (int v = 0; v < 3; v++)
    for (int k = 0; k < x[v]->n; k++) {
      const lt_arrival_t *a = &x[v]->a[k];
      const lt_arrival_t *b = find(x[(v + 1) % 3], a->sig, k), *c = find(x[(v + 2) % 3], a->sig, k);
      if (b && c) {
        if (v > 0) /* a shared path is settled once, from vertex 0 */
          continue;
        rt_rgb_t w = rt_rgb_scale(rt_rgb_add(a->w, rt_rgb_add(b->w, c->w)), 1.0 / 3.0);
        if (a->kind != LT_END_RECEIVER) {
          settle(W, a, flux_of(f, meas, w), 0);
          continue;
        }
        double uv[3][2] = {{a->u, a->v}, {b->u, b->v}, {c->u, c->v}};
        if (W->area_filter && (f->step[0].x != 0 || f->step[0].y != 0 || f->step[0].z != 0))
          deposit_filtered(W, f, p, a->sig, uv, flux_of(f, meas, w));
        else
          lt__deposit_triangle(&W->A, uv, flux_of(f, meas, w));
        W->C.st.pencils++;
      } else {
        settle(W, a, flux_of(f, meas / 3.0, a->w), 1);
      }
    }
}

/* The pencils of row j of the grid (vertex rows j and j + 1, traced already). */
static void pencil_row(worker_t *W, const lt_face_t *f, int side, int j, const lt_arrivals_t *r0,
                       const lt_arrivals_t *r1) {
  double h = 1.0 / (side - 1);
  for (int i = 0; i + 1 < side; i++) {
    double a0 = i * h, a1 = (i + 1) * h, b0 = j * h, b1 = (j + 1) * h;
    double t1[3][2] = {{a0, b0}, {a1, b0}, {a1, b1}}, t2[3][2] = {{a0, b0}, {a1, b1}, {a0, b1}};
    const lt_arrivals_t *x1[3] = {&r0[i], &r0[i + 1], &r1[i + 1]};
    const lt_arrivals_t *x2[3] = {&r0[i], &r1[i + 1], &r1[i]};
    pencil(W, f, t1, x1, W->max_split);
    pencil(W, f, t2, x2, W->max_split);
  }
}

/* The measure of face f's whole grid, weighted by a Lambertian source's cosine: the exact measure
 * for an isotropic source, else the midpoint rule over 64 x 64 squares (a ledger's emitted flux,
 * to the rule's accuracy). */
static double face_flux(const lt_face_t *f) {
  double c0[2] = {0, 0}, c1[2] = {1, 0}, c2[2] = {1, 1}, c3[2] = {0, 1};
  if (lt__face_weight(f, 0.5, 0.5) == 1.0 && f->lambert.x == 0.0 && f->lambert.y == 0.0 &&
      f->lambert.z == 0.0)
    return lt__face_measure(f, c0, c1, c2) + lt__face_measure(f, c0, c2, c3);
  const int n = 64;
  double sum = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double p00[2] = {(double)i / n, (double)j / n}, p10[2] = {(i + 1.0) / n, (double)j / n};
      double p11[2] = {(i + 1.0) / n, (j + 1.0) / n}, p01[2] = {(double)i / n, (j + 1.0) / n};
      sum += (lt__face_measure(f, p00, p10, p11) + lt__face_measure(f, p00, p11, p01)) *
             lt__face_weight(f, (i + 0.5) / n, (j + 0.5) / n);
    }
  return sum;
}

void lt__stats_add(lt_stats_t *a, const lt_stats_t *b) {
  a->rays += b->rays;
  a->segments += b->segments;
  a->arrivals += b->arrivals;
  a->pencils += b->pencils;
  a->folded += b->folded;
  a->divided += b->divided;
  a->nonlinear += b->nonlinear;
  a->photons += b->photons;
  a->lost += b->lost;
  a->filtered += b->filtered;
  a->unshifted += b->unshifted;
  a->resampled += b->resampled;
  a->flux_emitted += b->flux_emitted;
  a->flux_map += b->flux_map;
  a->flux_outside += b->flux_outside;
  a->flux_escaped += b->flux_escaped;
  a->flux_absorbed += b->flux_absorbed;
}

rt_status_t lt_illuminance(const rt_scene_t *s, const lt_receiver_t *rc, const lt_options_t *o,
                           lt_map_t *m, lt_stats_t *st) {
  if (!s->bvh)
    return RT_ENOTREADY;
  if (rc->n < 1 || rc->n > LT_MAX_RECEIVERS || o->light < -1 || o->light >= s->nlight ||
      o->side < 2 || o->side > LT_MAX_GRID || o->max_split < 0 || o->max_split > 12 ||
      o->threads < 0 || o->area_mesh < 1 || o->area_mesh > LT_MAX_AREA_MESH || o->area_filter < 0 ||
      o->area_filter > LT_AREA_FILTER_LINEAR || !m->e)
    return RT_EINVAL;
  int nt = rt_thread_count(o->threads);
  size_t cells = 3 * (size_t)m->width * (size_t)m->height;
  bm_scene_t planar = {0};
  if (o->method == LT_METHOD_POLYGONS) {
    char why[256];
    rt_status_t fs = bm_scene_build(s, &planar, why, sizeof why);
    if (fs != RT_OK)
      return fs;
  }
  worker_t *W = calloc((size_t)nt, sizeof *W);
  if (!W) {
    bm_scene_free(&planar);
    return RT_ENOMEM;
  }
  rt_status_t status = RT_OK;
  for (int t = 0; t < nt && status == RT_OK; t++) {
    W[t].C = (lt_ctx_t){s, rt_plan_make(s, 1), rc, {0}, o->indirect};
    W[t].A = (lt_accum_t){m, calloc(cells, sizeof(double)), &W[t].C.st};
    W[t].max_split = o->max_split;
    W[t].linear_tol = o->linear_tol;
    W[t].uniform_tol = o->uniform_tol;
    W[t].area_filter = o->area_filter;
    if (!W[t].A.flux)
      status = RT_ENOMEM;
  }
  lt_stats_t total;
  memset(&total, 0, sizeof total);
  double t0 = wall_seconds();
  int side = o->side;
  /* grid-pencils: a band of LT_GRID_BAND + 1 rows of the grid's rays at a time (the band's last
   * row is the next band's first), each ray with its tree's arrivals */
  lt_arrivals_t *grid = NULL;
  int band = side - 1 < LT_GRID_BAND ? side - 1 : LT_GRID_BAND;
  if (status == RT_OK && o->method == LT_METHOD_GRID_PENCIL) {
    grid = malloc((size_t)(band + 1) * (size_t)side * sizeof *grid);
    if (!grid)
      status = RT_ENOMEM;
  }
  int l0 = o->light < 0 ? 0 : o->light, l1 = o->light < 0 ? s->nlight : o->light + 1;
  /* every point source: a light, or each mesh point of an area light */
  for (int l = l0; l < l1 && status == RT_OK; l++)
    for (int sub = 0; sub < lt__subsources(s, l, o->area_mesh) && status == RT_OK; sub++) {
      lt_face_t faces[6];
      int nf = lt__faces(s, rc, m, l, sub, o->area_mesh,
                         o->area_filter && o->method == LT_METHOD_GRID_PENCIL, faces);
      for (int fi = 0; fi < nf; fi++) {
        const lt_face_t *f = &faces[fi];
        /* the flux the grid covers: the face's whole measure (weighted for a Lambertian source) */
        total.flux_emitted += face_flux(f) * (f->power.r + f->power.g + f->power.b) / 3.0;
        if (o->method == LT_METHOD_POLYGONS) {
          const int T = LT_POLYGON_TILES;
          int done = 0;
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
          for (int t = 0; t < T * T; t++) {
            int me = 0;
#ifdef _OPENMP
            me = omp_get_thread_num();
#endif
            int i = t % T, j = t / T;
            double box[4] = {f->hx * (2.0 * i / T - 1), f->hx * (2.0 * (i + 1) / T - 1),
                             f->hy * (2.0 * j / T - 1), f->hy * (2.0 * (j + 1) / T - 1)};
            lt__polygons_tile(&W[me].C, &W[me].A, o, &planar, f, box);
            if (o->progress) {
#pragma omp critical(lt_progress)
              o->progress(o->progress_ctx, ++done, T * T);
            }
          }
          continue;
        }
        int rows = o->method == LT_METHOD_PHOTONS ? side : side - 1, done = 0;
        if (o->method == LT_METHOD_PHOTONS) {
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
          for (int j = 0; j < rows; j++) {
            int me = 0;
#ifdef _OPENMP
            me = omp_get_thread_num();
#endif
            photon_row(&W[me], f, side, j);
            if (o->progress) {
#pragma omp critical(lt_progress)
              o->progress(o->progress_ctx, ++done, rows);
            }
          }
          continue;
        }
        /* grid-pencils, band by band: the band's rows of rays (its first kept from the last
         * band), then the pencils between them */
        for (int j0 = 0; j0 < rows; j0 += band) {
          int j1 = j0 + band < rows ? j0 + band : rows; /* rays of rows j0 .. j1 */
          if (j0 > 0)
            memcpy(grid, grid + (size_t)band * side, (size_t)side * sizeof *grid);
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
          for (int j = j0 > 0 ? j0 + 1 : 0; j <= j1; j++) {
            int me = 0;
#ifdef _OPENMP
            me = omp_get_thread_num();
#endif
            for (int i = 0; i < side; i++) {
              rt_ray_t r = lt__face_ray(f, (double)i / (side - 1), (double)j / (side - 1));
              lt__trace(&W[me].C, &r, &grid[(size_t)(j - j0) * side + i]);
            }
          }
#pragma omp parallel for num_threads(nt) schedule(dynamic, 1)
          for (int j = j0; j < j1; j++) {
            int me = 0;
#ifdef _OPENMP
            me = omp_get_thread_num();
#endif
            pencil_row(&W[me], f, side, j, grid + (size_t)(j - j0) * side,
                       grid + (size_t)(j - j0 + 1) * side);
            if (o->progress) {
#pragma omp critical(lt_progress)
              o->progress(o->progress_ctx, ++done, rows);
            }
          }
        }
      }
    }
  free(grid);
  if (status == RT_OK) {
    double cell = (m->u1 - m->u0) / m->width * (m->v1 - m->v0) / m->height;
    memset(m->e, 0, cells * sizeof *m->e);
    for (int t = 0; t < nt; t++) {
      for (size_t k = 0; k < cells; k++)
        m->e[k] += W[t].A.flux[k];
      lt__stats_add(&total, &W[t].C.st);
    }
    for (size_t k = 0; k < cells; k++)
      m->e[k] /= cell;
  }
  for (int t = 0; t < nt; t++)
    free(W[t].A.flux);
  free(W);
  bm_scene_free(&planar);
  total.seconds = wall_seconds() - t0;
  if (st)
    *st = total;
  return status;
}
