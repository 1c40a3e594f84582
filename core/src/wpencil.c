/* wpencil.c -- spectral pencils: dispersion by one axial ray per interval of wavelengths ([P89]
 * section 3.2; docs/spectral.md, section 3).
 *
 * Where a white ray refracts at a dispersive glass, the fan (shade.c) traces one ray per bin. A
 * spectral pencil traces one axial ray, at the centre u_c of an interval [u_a, u_b] of the
 * wavelength axis u (the plan's rt_wavescale_t: Lambda of the scene's one glass, [P89] 3.3, or
 * lambda), and carries beside it the wavelength column of Eq. (13) as world vectors: do and dd,
 * the derivatives in u of the ray's origin and unit direction. A neighbouring wavelength's ray is
 * the model's, o + do h, d + dd h (h = u - u_c). The column is chained surface by surface:
 *   transfer to a hit at distance t, facing normal m:  dp = P - d (P.m) / (d.m), P = do + t dd
 *     (where the neighbours meet the tangent plane: x_lambda of Eq. 13);
 *   refraction d' = eta d + (eta c1 - c2) m, c1 = -d.m, c2 = sqrt(1 - eta^2 (1 - c1^2)), and its
 *     derivative in d, m and eta: deta from dn/du of both media, dm = dp / r on a sphere, 0 on
 *     planes and polygons (xi_lambda of Eq. 13; tests/test_wpencil.c checks it against
 *     differences of Snell's law);
 *   reflection d' = d - 2 (d.m) m and its derivative.
 * At each hit the model's rays at the interval's ends are checked, without tracing them on: they
 * must meet the hit's primitive (inside the polygon, on the sphere) from the same side with
 * nothing nearer (a scene search up to it; none inside a convex object that nothing else enters,
 * rt_object_t.alone, where the band between the ends needs no test either), in the same checker
 * square, with the same total
 * internal reflection, and their exact points and children's directions (Snell's law at the
 * end's wavelength) must be within tol times the dispersive shift the model predicts there. Where
 * the ends land over a pixel apart (a pixel as the path sees it: the footprint of one pixel, a ray
 * differential chained beside the column), nothing may lie in the band between them and the
 * direct term must agree (wedge_blocker(), light_agrees()). Where an end fails, the interval is cut
 * where the check turns (bisection on the model) or halfway, and the part cut off is traced as a
 * pencil of its own from the same origin, its axial ray the model's ray at its centre: the
 * dispersion image solid of [P89] 3.2.2 clipped against the surface's edges. A pencil's radiance is
 * the axial ray's times the integral of the colour weights over its interval ([P89] 3.2.3's R = int
 * t r L dlambda, the plan's 1-nm table), so that colour changes smoothly across a band.
 *
 * Not checked: a shadow or highlight between the ends that the direct term at the ends does not
 * show. The subtree is not recorded in the caller's ray tree; its rays (the scene searches at the
 * ends included) are counted through the tracer's count().
 */
#include <math.h>
#include <string.h>

#include "bvh.h"
#include "colour/colour.h"
#include "core/intersect.h"
#include "core/shade_paths.h"
#include "paraxial/vec3.h"
#include "shade_impl.h"
#include "wpencil_math.h"

/** Pencils one white ray's spectrum may be cut into below its refraction. */
#define WP_BUDGET 256
/** Parts the white ray's refraction itself may be cut into (total internal reflection, the
 *  linear model), a budget of its own: rt_shade_spectral_mirror() cuts as rt_shade_spectral()
 *  does, whatever the latter's tracing spent. */
#define WP_WHITE_BUDGET 64
/** Narrowest interval cut off, as a fraction of the visible range. */
#define WP_MIN_FRACTION (1.0 / 1024.0)
/** Bisection steps for a cut. */
#define WP_BISECT 20
/** An error of the model under this many pixels (of the points: the footprint's, wp_hit_t.pix;
 *  of the directions: rt_plan_t.pixel_angle) passes the check whatever the relative tolerance. */
#define WP_PIXELS 0.25
/** Where a pencil's ends land more than this many pixels apart (wp_hit_t.pix) on a surface,
 *  what lies between them is checked too (wedge_blocker(), light_agrees(), a concave polygon). */
#define WP_SPREAD_PIXELS 1.0
/** Largest difference of the direct term at a pencil's end from its axial hit's, relative. */
#define WP_LIGHT_TOL 0.02
/** A pencil whose weight below the white ray's hit is under this is not cut: its colour can be
 *  wrong by at most this share of the radiance it carries. */
#define WP_MIN_WEIGHT 0.05

typedef struct {
  rt_ray_t ray;                /* the axial ray, at wavelength ray.lambda */
  const rt_material_t *inside; /* the medium it travels in; NULL: the scene's (settings.ior) */
  px_vec3_t d_o, d_d;          /* d origin / du, d direction / du */
  double ua, ub, uc;           /* the interval and the axial ray's u */
  rt_ray_kind_t kind;
  double weight; /* largest channel of the weights from the white ray's hit to this ray */
  /* one pixel's footprint (a ray differential, Igehy 1999): the derivatives of the origin and of
   * the unit direction along two orthogonal image directions, a pixel long each, chained through
   * every surface as the column is (wavelength fixed); where the white ray refracted it is the
   * pinhole's, the path from the eye taken as straight. Through a curved glass it magnifies or
   * shrinks: a pixel seen through the path, not straight from the eye. */
  px_vec3_t f_o[2], f_d[2];
  const rt_sphere_t *from; /* the sphere the ray leaves, or NULL (a plane, or do = 0) */
  int from_prim;           /* the primitive the ray leaves */
  int in_obj; /* the object the ray travels inside when it is alone (rt_object_t.alone), or -1:
                 its own surface is then the first thing every ray of the pencil meets */
} wp_t;

typedef struct {
  const rt_scene_t *s;
  const rt_plan_t *plan;
  const rt_tracer_t *tr; /* the caller's: count() */
  rt_tracer_t inner;     /* shadows of the pencils' hits, traced here */
  int budget, wbudget;   /* cuts left below the refraction, and of the refraction itself */
  double min_width;
  /* a material whose index is the scale's glass (u = Lambda), or NULL; every dispersive
   * transparent material shares its model (rt_plan_spectral_pencils) */
  const rt_material_t *glass;
  int trace; /* 0: only the shares that reflect (rt__wp_refract with tr NULL) */
  int shows; /* the spectrum was cut, or spread over more than a quarter pixel somewhere */
  rt_spectral_rec_t *rec; /* rt_shade_spectral_rec()'s record, or NULL */
} wp_run_t;

/* ---- the record of what the pencils met (rt_shade_spectral_rec()) --------------------------- */

static void rec_unusable(const wp_run_t *R, int why) {
  if (R->rec && !R->rec->unusable)
    R->rec->unusable = why;
}

/* Grow box b (lo x, y, z, hi x, y, z) to hold p. */
static void rec_grow(const wp_run_t *R, double b[6], px_vec3_t p) {
  for (int a = 0; a < 3; a++) {
    double v = px_v3_at(p, a);
    if (!isfinite(v))
      rec_unusable(R, 5);
    b[a] = fmin(b[a], v);
    b[3 + a] = fmax(b[3 + a], v);
  }
}

/* A segment from o, leaving primitive `from` (-1: none), to e, that ends at event i
 * (rec_event()'s; -1: none). */
static void rec_seg(const wp_run_t *R, int i, int from, px_vec3_t o, px_vec3_t e) {
  rt_spectral_rec_t *r = R->rec;
  if (!r || i < 0)
    return;
  rec_grow(R, r->from[i], o);
  rec_grow(R, r->to[i], e);
  int k = 0;
  while (k < RT_SPECTRAL_EVENT_PRIMS && r->prim[i][k] >= 0 && r->prim[i][k] != from)
    k++;
  if (from < 0 || (k < RT_SPECTRAL_EVENT_PRIMS && r->prim[i][k] == from))
    return;
  if (k == RT_SPECTRAL_EVENT_PRIMS)
    rec_unusable(R, 1);
  else
    r->prim[i][k] = from;
}

/* A ray that meets nothing, event i: from its origin to where it leaves the scene's bounds
 * (nothing bounded lies beyond; rt_sweep_meets_others() tests the planes), or to its origin when
 * it never enters them. */
static void rec_ray(const wp_run_t *R, int i, int from, const rt_ray_t *ray) {
  double lo[3], hi[3], t0 = 0.0, t1 = INFINITY;
  if (!R->rec)
    return;
  px_vec3_t e = ray->o;
  if (rt_scene_bounds(R->s, lo, hi)) {
    for (int a = 0; a < 3; a++) {
      double o = px_v3_at(ray->o, a), d = px_v3_at(ray->d, a);
      if (d == 0.0) {
        if (o < lo[a] || o > hi[a])
          t1 = -INFINITY;
        continue;
      }
      double ta = (lo[a] - o) / d, tb = (hi[a] - o) / d;
      t0 = fmax(t0, fmin(ta, tb));
      t1 = fmin(t1, fmax(ta, tb));
    }
    if (t0 <= t1 && isfinite(t1))
      e = px_v3_axpy(t1, ray->d, ray->o);
  }
  rec_seg(R, i, from, ray->o, e);
}

/* splitmix64's finaliser. */
static uint64_t mix64(uint64_t h) {
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBull;
  return h ^ (h >> 31);
}

/* A checker square's index as an integer (a far or undefined one as the same marker). */
static uint64_t square_word(double x) {
  return fabs(x) < 0x1p62 ? (uint64_t)(int64_t)x : 0x8000000000000000ull;
}

/* An event: a generation, a primitive (-1: a miss), a ray kind, flags (a side, total internal
 * reflection, the white ray's fate) and a checker square (su, sv; 0 where none), hashed and kept
 * once; its index in the record (-1: none kept). */
static int rec_event(wp_run_t *R, int depth, int prim, int kind, unsigned flags, double su,
                     double sv) {
  rt_spectral_rec_t *r = R->rec;
  if (!r)
    return -1;
  uint64_t h = mix64((uint64_t)(uint32_t)prim << 32 | (uint64_t)(uint32_t)depth << 16 |
                     (uint64_t)(kind & 0xff) << 8 | (uint64_t)(flags & 0xff));
  h = mix64(h ^ square_word(su));
  h = mix64(h ^ square_word(sv) * 0x9E3779B97F4A7C15ull);
  for (int i = 0; i < r->nev; i++)
    if (r->ev[i] == h)
      return i;
  if (r->nev == RT_SPECTRAL_REC_EVENTS) {
    rec_unusable(R, 1);
    return -1;
  }
  int i = r->nev++;
  r->ev[i] = h;
  for (int a = 0; a < 3; a++) {
    r->from[i][a] = r->to[i][a] = INFINITY;
    r->from[i][3 + a] = r->to[i][3 + a] = -INFINITY;
  }
  r->prim[i][0] = prim;
  for (int k = 1; k < RT_SPECTRAL_EVENT_PRIMS; k++)
    r->prim[i][k] = -1;
  return i;
}

/* ---- the wavelength axis ------------------------------------------------------------------- */

/* Segment i of the table holding u, and the fraction along it. */
static int segment(const rt_wavescale_t *w, double u, double *f) {
  int lo = 0, hi = RT_MAX_BINS;
  if (!(u > w->u_edge[0])) {
    *f = 0.0;
    return 0;
  }
  if (!(u < w->u_edge[hi])) {
    *f = 1.0;
    return hi - 1;
  }
  while (hi - lo > 1) {
    int mid = (lo + hi) / 2;
    if (w->u_edge[mid] <= u)
      lo = mid;
    else
      hi = mid;
  }
  *f = (u - w->u_edge[lo]) / (w->u_edge[lo + 1] - w->u_edge[lo]);
  return lo;
}

static double lambda_of(const rt_wavescale_t *w, double u) {
  double f;
  int i = segment(w, u, &f);
  return CS_LAMBDA_LO + (i + f) * ((CS_LAMBDA_HI - CS_LAMBDA_LO) / RT_MAX_BINS);
}

static rt_rgb_t cum_at(const rt_wavescale_t *w, double u) {
  double f;
  int i = segment(w, u, &f);
  return rt_rgb_add(rt_rgb_scale(w->cum[i], 1.0 - f), rt_rgb_scale(w->cum[i + 1], f));
}

rt_rgb_t rt_wave_weight(const rt_wavescale_t *w, double ua, double ub) {
  rt_rgb_t a = cum_at(w, ua), b = cum_at(w, ub);
  return rt_rgb(b.r - a.r, b.g - a.g, b.b - a.b);
}

/* Index of medium m (NULL: the scene's) at u (lambda its wavelength), and its derivative in u.
 * The scale's own glass is linear in Lambda ([P89] 3.3): n = n0 + n'(lambda0) (u - lambda0),
 * without evaluating its model; another glass by its model and dlambda/du. */
static void index_du(const wp_run_t *R, const rt_material_t *m, double u, double lambda, double *n,
                     double *dn) {
  *dn = 0.0;
  if (!m) {
    *n = R->s->ior;
    return;
  }
  const rt_wavescale_t *w = &R->plan->wave;
  if (m == R->glass) {
    *n = w->scale.n0 + w->scale.dn0 * (u - w->scale.lambda0);
    *dn = w->scale.dn0;
    return;
  }
  double dl = 0.0;
  if (px_index_eval(&m->index, lambda, n, &dl) != PX_OK || !(*n > 0.0)) {
    *n = m->ior; /* the loader checked every model over 380-780 nm: not reached */
    return;
  }
  double dl_du = 1.0; /* dlambda/du: n'(lambda0) / n'(lambda) of the scale's glass */
  double dg;
  if (w->scaled && px_index_eval(&w->scale.glass, lambda, NULL, &dg) == PX_OK && dg != 0.0)
    dl_du = w->scale.dn0 / dg;
  *dn = dl * dl_du;
}

/* The model's ray of pencil w at u. Leaving a sphere, its origin is taken back from the tangent
 * plane to the sphere (at the axial origin's distance from the centre, which keeps the offset's
 * side): the tangent plane lies outside the sphere by |do h|^2 / 2r, which would put the origin of
 * a ray reflected inside it outside. */
static rt_ray_t model_ray(const wp_t *w, double u) {
  double h = u - w->uc;
  rt_ray_t r = w->ray;
  r.o = px_v3_axpy(h, w->d_o, r.o);
  if (w->from) {
    px_vec3_t q = px_v3_sub(r.o, w->from->c);
    r.o = px_v3_axpy(px_v3_norm(px_v3_sub(w->ray.o, w->from->c)) / px_v3_norm(q), q, w->from->c);
  }
  r.d = wp_unit(px_v3_axpy(h, w->d_d, r.d));
  return r;
}

/* ---- checks at the interval's ends --------------------------------------------------------- */

/* What the axial hit and the column say, for check(). */
typedef struct {
  const wp_t *w;
  rt_hit_t hit;
  px_vec3_t m;                /* facing normal */
  double side;                /* m = side * hit.n */
  px_vec3_t dp;               /* the hit's column */
  double pix;                 /* a pixel's size here: the footprint's smaller stretch */
  px_vec3_t fp[2];            /* the footprint at the hit */
  int checker;                /* 1: a checkerboard plane */
  double su, sv;              /* its square */
  int reflect, refract, tir;  /* children checked; total internal reflection at the axial */
  px_vec3_t dr, ddr, dt, ddt; /* the children's directions and derivatives */
  const rt_material_t *next;  /* the medium beyond the surface */
  const rt_surface_t *sf;     /* the axial hit for shading */
  rt_rgb_t direct;            /* its direct term */
  int ev;                     /* its event in the run's record (rec_event()), or -1 */
} wp_hit_t;

static void square_of(const rt_scene_t *s, int prim, px_vec3_t p, double *su, double *sv) {
  const rt_plane_t *pl = &s->prim[prim].plane;
  double u, v;
  rt_plane_coords(pl, p, &u, &v);
  *su = floor(u * pl->inv_check);
  *sv = floor(v * pl->inv_check);
}

/* 1 when |a - b|, the model's error at an end, exceeds both tol times the shift it predicts there
 * and the floor. */
static int too_far(px_vec3_t a, px_vec3_t b, double shift, double tol, double floor_) {
  double e = px_v3_norm(px_v3_sub(a, b));
  return e > tol * shift && e > floor_;
}

/* The footprint (origins f_o, directions f_d) carried a distance t along unit direction d to the
 * tangent plane of facing normal m: as the column, dp = P - d (P.m) / (d.m), P = f_o + t f_d. */
static void fp_transfer(const px_vec3_t f_o[2], const px_vec3_t f_d[2], double t, px_vec3_t d,
                        px_vec3_t m, px_vec3_t out[2]) {
  for (int k = 0; k < 2; k++) {
    px_vec3_t P = px_v3_axpy(t, f_d[k], f_o[k]);
    out[k] = px_v3_axpy(-px_v3_dot(P, m) / px_v3_dot(d, m), d, P);
  }
}

/* A pixel's size on a surface where its footprint is f: the smaller singular value of [f0 f1], the
 * shortest distance there that a pixel's worth of image spans (0 at a focus). */
static double fp_pixel(const px_vec3_t f[2]) {
  /* s_min^2 = |f0 x f1|^2 / s_max^2: no cancellation where the footprint is long and thin */
  double a = px_v3_dot(f[0], f[0]), c = px_v3_dot(f[1], f[1]), b = px_v3_dot(f[0], f[1]);
  double smax2 = 0.5 * (a + c + sqrt((a - c) * (a - c) + 4.0 * b * b));
  px_vec3_t x = px_v3_cross(f[0], f[1]);
  double s2 = smax2 > 0.0 ? px_v3_dot(x, x) / smax2 : 0.0;
  return s2 > 0.0 ? sqrt(s2) : 0.0; /* NaN (grazing) as 0 */
}

/* The pinhole's footprint of a ray from the eye, unfolded straight to o along unit d: directions a
 * pixel's angle apart across d, origins as far apart as the path's length to o makes them. */
static void fp_pinhole(const rt_scene_t *s, const rt_plan_t *plan, px_vec3_t o, px_vec3_t d,
                       px_vec3_t f_o[2], px_vec3_t f_d[2]) {
  px_vec3_t a = fabs(d.x) < 0.6 ? (px_vec3_t){1, 0, 0} : (px_vec3_t){0, 1, 0};
  px_vec3_t e1 = wp_unit(px_v3_cross(d, a)), e2 = px_v3_cross(d, e1);
  double dist = px_v3_norm(px_v3_sub(o, s->camera.eye));
  f_d[0] = px_v3_scale(e1, plan->pixel_angle);
  f_d[1] = px_v3_scale(e2, plan->pixel_angle);
  f_o[0] = px_v3_scale(f_d[0], dist);
  f_o[1] = px_v3_scale(f_d[1], dist);
}

/* What check() finds at a model ray: 0 when it agrees with the axial hit's. */
enum {
  WP_OFF = 1,    /* it misses the primitive or meets it from the other side */
  WP_SQUARE = 2, /* another checker square */
  WP_TIR = 3,    /* the other side of total internal reflection */
  WP_LINEAR = 4, /* (only with lin) the model errs by more than the tolerance */
  WP_SPREAD = 5  /* (only with lin) over WP_SPREAD_PIXELS apart, with something between the ends */
};

/* Tell the caller's tracer of a ray or an event (rt_tracer_t.count()). */
static void count(const wp_run_t *R, int what) {
  if (R->tr && R->tr->count)
    R->tr->count(R->tr->ctx, what);
}

/* ---- what lies between the ends ----------------------------------------------------------- */

/* Whether primitive k is a concave polygon (turning both ways round its normal). */
static int concave(const rt_scene_t *s, int k) {
  const rt_prim_t *pr = &s->prim[k];
  if (pr->kind != RT_PRIM_POLYGON)
    return 0;
  const px_vec3_t *v = s->vertex + pr->polygon.first;
  int c = pr->polygon.count, pos = 0, neg = 0;
  for (int i = 0; i < c; i++) {
    double t = px_v3_dot(
        px_v3_cross(px_v3_sub(v[(i + 1) % c], v[i]), px_v3_sub(v[(i + 2) % c], v[(i + 1) % c])),
        pr->polygon.n);
    pos |= t > 0.0;
    neg |= t < 0.0;
  }
  return pos && neg;
}

/* Whether the segment a-b, its ends excluded, crosses primitive q. */
static int segment_meets(const rt_scene_t *s, int q, px_vec3_t a, px_vec3_t b) {
  px_vec3_t d = px_v3_sub(b, a);
  double len = px_v3_norm(d), t;
  if (!(len > 0.0))
    return 0;
  rt_ray_t r = {a, px_v3_scale(d, 1.0 / len), 1e-9 * len, len * (1.0 - 1e-9), 1.0, -1, 0.0f};
  return rt_prim_intersect(s, q, &r, r.tmax, &t);
}

/* Whether the segment a-b crosses the triangle v (Moller and Trumbore's test). */
static int segment_crosses_triangle(px_vec3_t a, px_vec3_t b, const px_vec3_t v[3]) {
  px_vec3_t d = px_v3_sub(b, a), e1 = px_v3_sub(v[1], v[0]), e2 = px_v3_sub(v[2], v[0]);
  px_vec3_t pv = px_v3_cross(d, e2);
  double det = px_v3_dot(e1, pv);
  if (fabs(det) < 1e-300)
    return 0;
  px_vec3_t tv = px_v3_sub(a, v[0]);
  double u = px_v3_dot(tv, pv) / det;
  if (u < 0.0 || u > 1.0)
    return 0;
  px_vec3_t qv = px_v3_cross(tv, e1);
  double w = px_v3_dot(d, qv) / det, t = px_v3_dot(e2, qv) / det;
  return w >= 0.0 && u + w <= 1.0 && t > 0.0 && t < 1.0;
}

/* Whether triangle v meets primitive q: for a polygon, an edge of either crosses the other; for a
 * sphere, its surface comes nearer the triangle than the radius while not every corner lies
 * inside; for a plane, corners on both sides. */
static int triangle_meets(const rt_scene_t *s, int q, const px_vec3_t v[3]) {
  const rt_prim_t *pr = &s->prim[q];
  if (pr->kind == RT_PRIM_POLYGON) { /* all on one side of its plane (touching at most): apart */
    double d[3], scale = 0.0;
    for (int i = 0; i < 3; i++) {
      d[i] = px_v3_dot(pr->polygon.n, v[i]) - pr->polygon.d;
      scale = fmax(scale, fabs(px_v3_dot(pr->polygon.n, v[i])) + fabs(pr->polygon.d));
    }
    double eps = 1e-9 * (1.0 + scale);
    if ((d[0] >= -eps && d[1] >= -eps && d[2] >= -eps) ||
        (d[0] <= eps && d[1] <= eps && d[2] <= eps))
      return 0;
  }
  for (int i = 0; i < 3; i++)
    if (pr->kind != RT_PRIM_PLANE && segment_meets(s, q, v[i], v[(i + 1) % 3]))
      return 1;
  if (pr->kind == RT_PRIM_PLANE) {
    int pos = 0, neg = 0;
    for (int i = 0; i < 3; i++) {
      double d = px_v3_dot(pr->plane.n, px_v3_sub(v[i], pr->plane.p));
      pos |= d > 0.0;
      neg |= d < 0.0;
    }
    return pos && neg;
  }
  if (pr->kind == RT_PRIM_POLYGON) {
    const rt_polygon_t *pg = &pr->polygon;
    const px_vec3_t *pv = s->vertex + pg->first;
    for (int i = 0; i < pg->count; i++)
      if (segment_crosses_triangle(pv[i], pv[(i + 1) % pg->count], v))
        return 1;
    return 0;
  }
  /* a sphere: the triangle's nearest point to the centre, by its plane and its edges */
  const rt_sphere_t *sp = &pr->sphere;
  int inside = 1;
  for (int i = 0; i < 3; i++)
    inside &= px_v3_norm(px_v3_sub(v[i], sp->c)) < sp->r;
  if (inside)
    return 0;
  px_vec3_t n = px_v3_cross(px_v3_sub(v[1], v[0]), px_v3_sub(v[2], v[0]));
  double nn = px_v3_norm(n);
  if (nn > 0.0) {
    n = px_v3_scale(n, 1.0 / nn);
    px_vec3_t c = px_v3_axpy(-px_v3_dot(n, px_v3_sub(sp->c, v[0])), n, sp->c);
    if (fabs(px_v3_dot(n, px_v3_sub(sp->c, v[0]))) < sp->r) {
      int in = 1; /* c inside the triangle: same side of every edge */
      for (int i = 0; i < 3; i++)
        in &= px_v3_dot(px_v3_cross(px_v3_sub(v[(i + 1) % 3], v[i]), px_v3_sub(c, v[i])), n) >= 0.0;
      if (in)
        return 1;
    }
  }
  return 0; /* an edge crossing the sphere was found above */
}

/* wedge_blocker()'s test of one primitive of the BVH (rt_bvh_box_query()). */
typedef struct {
  const rt_scene_t *s;
  px_vec3_t tri[6]; /* the band's two triangles */
  int skip[2];      /* the hit's primitive and the one the rays leave */
  /* per skip[i]: its object when none of that object's faces can meet the band
   * (rt__wp_beside_face()), -1 when they can, -2 until a face of it is met in the BVH */
  int skip_obj[2];
} wedge_t;

static int wedge_meets(void *ctx, int q) {
  wedge_t *w = ctx;
  if (q == w->skip[0] || q == w->skip[1])
    return 0;
  for (int i = 0; i < 2; i++)
    if (w->skip[i] >= 0 && w->s->prim[q].object == w->s->prim[w->skip[i]].object) {
      if (w->skip_obj[i] == -2) {
        const px_vec3_t corner[4] = {w->tri[0], w->tri[1], w->tri[2], w->tri[5]};
        w->skip_obj[i] = rt__wp_beside_face(w->s, w->skip[i], corner, 4);
      }
      if (w->skip_obj[i] >= 0)
        return 0;
    }
  return triangle_meets(w->s, q, w->tri) || triangle_meets(w->s, q, w->tri + 3);
}

/* shade_impl.h. The band's triangles are the convex hull of the points, so they lie in that
 * closed half-space, where the convex body has nothing but face q itself: no other face of it can
 * come between the band's rays (a pencil leaving a face outward, or reaching one from outside).
 * rt_polyhedron_convex() makes the faces' normals point outward. */
int rt__wp_beside_face(const rt_scene_t *s, int q, const px_vec3_t *v, int n) {
  if (q < 0 || s->prim[q].kind != RT_PRIM_POLYGON || !s->object[s->prim[q].object].alone)
    return -1;
  const rt_polygon_t *pg = &s->prim[q].polygon;
  for (int i = 0; i < n; i++) {
    double d = px_v3_dot(pg->n, v[i]) - pg->d;
    double eps = 1e-9 * (1.0 + fabs(px_v3_dot(pg->n, v[i])) + fabs(pg->d));
    if (d < -eps)
      return -1;
  }
  return s->prim[q].object;
}

/* A primitive other than the hit's and the one the rays leave that lies between the axial ray
 * and the model's ray at an end (origin o, point p), or -1: the two triangles of the band they
 * span, its corners the origins and the points, tested against every primitive in the BVH
 * leaves whose boxes meet theirs, and the planes. With it, a pencil spread over more than
 * WP_SPREAD_PIXELS need not be cut where nothing lies between its ends (a thin slit in front of a
 * screen does, which the ends alone do not see). */
static int wedge_blocker(const wp_run_t *R, const wp_hit_t *H, px_vec3_t o, px_vec3_t p) {
  const rt_scene_t *s = R->s;
  const wp_t *w = H->w;
  px_vec3_t tri[2][3] = {{w->ray.o, o, p}, {w->ray.o, p, H->hit.p}};
  double lo[3], hi[3];
  for (int a = 0; a < 3; a++) {
    lo[a] = INFINITY;
    hi[a] = -INFINITY;
  }
  for (int t = 0; t < 2; t++)
    for (int i = 0; i < 3; i++)
      for (int a = 0; a < 3; a++) {
        lo[a] = fmin(lo[a], px_v3_at(tri[t][i], a));
        hi[a] = fmax(hi[a], px_v3_at(tri[t][i], a));
      }
  int skip0 = H->hit.prim, skip1 = w->from_prim;
  for (int u = 0; u < s->nunbounded; u++) {
    int q = s->unbounded[u];
    if (q != skip0 && q != skip1 && (triangle_meets(s, q, tri[0]) || triangle_meets(s, q, tri[1])))
      return q;
  }
  wedge_t q = {s,
               {tri[0][0], tri[0][1], tri[0][2], tri[1][0], tri[1][1], tri[1][2]},
               {skip0, skip1},
               {-2, -2}}; /* the planes' test in triangle_meets() rejects most */
  return rt_bvh_box_query(s->bvh, lo, hi, wedge_meets, &q);
}

/* Whether the direct term at the model's point p (ray r, facing normal me) is within
 * WP_LIGHT_TOL of the axial hit's, relative to the larger plus 1/1024: the axial's stands for the
 * whole interval, so a shadow edge or a highlight between the ends needs a cut. */
static int light_agrees(const wp_run_t *R, const wp_hit_t *H, const rt_ray_t *r, px_vec3_t p,
                        px_vec3_t me) {
  rt_surface_t sf = *H->sf;
  sf.hit.p = p;
  sf.hit.n = px_v3_scale(me, H->side);
  sf.nf = me;
  rt_rgb_t l = rt_shade_direct(R->s, R->plan, &sf, r, &R->inner), c = H->direct;
  double d = fmax(fabs(l.r - c.r), fmax(fabs(l.g - c.g), fabs(l.b - c.b)));
  return d <= WP_LIGHT_TOL * fmax(rt_rgb_max(l), rt_rgb_max(c)) + 1.0 / 1024.0;
}

/* Whether the pencil of H travels inside an object that is alone (rt_object_t.alone) and H is on
 * its surface: a convex body that nothing else enters, so that a ray from inside meets this
 * surface first, and the band between two of its rays lies inside it, where nothing is. */
static int inside_alone(const wp_hit_t *H) {
  return H->w->in_obj >= 0 && H->w->in_obj == H->hit.object && H->side < 0.0;
}

/* The geometric part of check(): the model's ray r meets the hit's primitive from the same side,
 * nothing nearer (lin: a scene search, *occ set to what it meets; else only *occ), in the same
 * square; *p and *me its exact point and facing normal there. 0 or check()'s code. What lies
 * between the axial ray and the end's is wedge_blocker()'s. */
static int meets(const wp_run_t *R, const wp_hit_t *H, const rt_ray_t *r, int lin, int *occ,
                 px_vec3_t *p, px_vec3_t *me) {
  const rt_scene_t *s = R->s;
  double t, t2;
  if (!rt_prim_intersect(s, H->hit.prim, r, INFINITY, &t))
    return WP_OFF;
  rt_ray_t q = *r;
  q.tmax = t * (1.0 - 1e-9);
  rt_hit_t h2;
  lin = lin && !inside_alone(H); /* else nothing can hide the hit */
  if (lin)
    count(R, H->w->kind);
  if (lin && rt_intersect(s, &q, &h2) && h2.prim != H->hit.prim) {
    *occ = h2.prim;
    return WP_OFF;
  }
  if (!lin && *occ >= 0 && rt_prim_intersect(s, *occ, &q, q.tmax, &t2))
    return WP_OFF;
  *p = px_v3_axpy(t, r->d, r->o);
  rec_seg(R, H->ev, H->w->from_prim, r->o, *p);
  *me = px_v3_scale(rt_prim_normal(s, H->hit.prim, *p), H->side);
  if (!(px_v3_dot(*me, r->d) < 0.0))
    return WP_OFF;
  if (H->checker) {
    double su, sv;
    square_of(s, H->hit.prim, *p, &su, &sv);
    if (su != H->su || sv != H->sv)
      return WP_SQUARE;
  }
  return 0;
}

/* The model's ray at u against the axial hit H. lin (at an end): a scene search for what hides the
 * hit from it, *occ set to that primitive, the model's error, and what lies between; else
 * (bisecting) only the primitive *occ (>= 0) hides. */
static int check(const wp_run_t *R, const wp_hit_t *H, double u, int lin, int *occ) {
  const wp_t *w = H->w;
  rt_ray_t r = model_ray(w, u);
  double h = u - w->uc;
  px_vec3_t p, me;
  int why = meets(R, H, &r, lin, occ, &p, &me);
  if (why)
    return why;
  double tol = R->plan->spectral_tol;
  double eps_d = WP_PIXELS * R->plan->pixel_angle, eps_p = WP_PIXELS * H->pix;
  int fail = 0;
  if (H->refract) {
    double lambda = lambda_of(&R->plan->wave, u), n1, n2, dn;
    index_du(R, w->inside, u, lambda, &n1, &dn);
    index_du(R, H->next, u, lambda, &n2, &dn);
    px_vec3_t o, dummy, zero = {0, 0, 0};
    double ct;
    int ok = wp_refract_du(r.d, zero, me, zero, n1 / n2, 0.0, &o, &dummy, &ct);
    if (ok != !H->tir)
      return WP_TIR;
    if (lin && ok &&
        too_far(o, wp_unit(px_v3_axpy(h, H->ddt, H->dt)), px_v3_norm(H->ddt) * fabs(h), tol, eps_d))
      fail = WP_LINEAR;
  }
  if (!lin)
    return 0;
  double scale = 1.0 + fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z)));
  if (too_far(p, px_v3_axpy(h, H->dp, H->hit.p), px_v3_norm(H->dp) * fabs(h), tol,
              fmax(eps_p, 1e-9 * scale)))
    fail = WP_LINEAR;
  if (H->reflect) {
    px_vec3_t o = px_v3_axpy(-2.0 * px_v3_dot(r.d, me), me, r.d);
    if (too_far(o, wp_unit(px_v3_axpy(h, H->ddr, H->dr)), px_v3_norm(H->ddr) * fabs(h), tol, eps_d))
      fail = WP_LINEAR;
  }
  /* over a pixel apart: something could lie between the ends (a concave polygon's own edge, any
   * other surface in the band they span), and the direct term at the end must agree */
  if (!fail && px_v3_norm(H->dp) * fabs(h) > WP_SPREAD_PIXELS * H->pix &&
      (concave(R->s, H->hit.prim) || (!inside_alone(H) && wedge_blocker(R, H, r.o, p) >= 0) ||
       !light_agrees(R, H, &r, p, me)))
    fail = WP_SPREAD;
  return fail;
}

/* Where between u_ok (passes) and u_bad (fails the topology) the check turns, by bisection on the
 * model's rays. */
static double bisect(const wp_run_t *R, const wp_hit_t *H, double u_ok, double u_bad, int occ) {
  for (int k = 0; k < WP_BISECT && fabs(u_bad - u_ok) > 0.125 * R->min_width; k++) {
    double mid = 0.5 * (u_ok + u_bad);
    if (check(R, H, mid, 0, &occ) != 0)
      u_bad = mid;
    else
      u_ok = mid;
  }
  return 0.5 * (u_ok + u_bad);
}

/* ---- tracing ------------------------------------------------------------------------------- */

static void shadow_cb(void *ctx, rt_shadow_t *q) {
  wp_run_t *R = ctx;
  count(R, RT_RAY_SHADOW);
  q->through = rt_transmittance(R->s, &q->ray);
}

static void occluded_cb(void *ctx, rt_shadow_t *q) {
  wp_run_t *R = ctx;
  count(R, RT_RAY_SHADOW);
  rt_shadow_occluded(R->s, q);
}

/* Pencil w re-centred on [ua, ub] (inside its interval), its axial ray the model's. */
static wp_t recentre(const wp_run_t *R, const wp_t *w, double ua, double ub) {
  wp_t p = *w;
  p.ua = ua;
  p.ub = ub;
  p.uc = 0.5 * (ua + ub);
  p.ray = model_ray(w, p.uc);
  p.d_d = px_v3_axpy(-px_v3_dot(p.ray.d, w->d_d), p.ray.d, w->d_d); /* across the new axis */
  double lambda = lambda_of(&R->plan->wave, p.uc), dn;
  p.ray.lambda = (float)lambda;
  index_du(R, w->inside, p.uc, lambda, &p.ray.ior, &dn);
  return p;
}

static rt_rgb_t trace(wp_run_t *R, wp_t *w, int depth);

/* Cut [cut, ue] off pencil w (cut between its axial u and the end ue), trace it as a pencil of its
 * own adding its radiance to *c, and shrink w to the rest; 0 when nothing was cut (too narrow, or
 * the budget is spent). */
static int cut_off(wp_run_t *R, wp_t *w, double cut, double ue, int depth, rt_rgb_t *c) {
  if (fabs(cut - w->uc) < 0.5 * R->min_width) /* the axial ray sits at the edge */
    cut = w->uc + copysign(0.5 * R->min_width, ue - w->uc);
  if (fabs(ue - cut) < R->min_width)
    return 0; /* too narrow to cut off: the pencil keeps it */
  if (R->budget <= 0) {
    rec_unusable(R, 4);
    return 0;
  }
  R->budget--;
  R->shows = 1;
  wp_t piece = recentre(R, w, fmin(cut, ue), fmax(cut, ue));
  if (ue < w->uc)
    w->ua = cut;
  else
    w->ub = cut;
  count(R, w->kind);
  count(R, RT_COUNT_SPECTRAL + 1);
  *c = rt_rgb_add(*c, trace(R, &piece, depth));
  return 1;
}

/* A pencil whose axial ray meets nothing: cut off the ends whose model rays meet something (where
 * they begin to, by bisection against what they meet). */
static rt_rgb_t miss(wp_run_t *R, wp_t *w, int depth) {
  rt_rgb_t c = rt_rgb(0, 0, 0);
  for (int e = 0; e < 2 && w->weight >= WP_MIN_WEIGHT; e++) {
    for (;;) {
      double ue = e ? w->ub : w->ua, a = w->uc, b = ue, t;
      rt_ray_t r = model_ray(w, ue);
      rt_hit_t h;
      if (ue == w->uc)
        break;
      count(R, w->kind);
      if (!rt_intersect(R->s, &r, &h))
        break;
      for (int k = 0; k < WP_BISECT && fabs(b - a) > 0.125 * R->min_width; k++) {
        double mid = 0.5 * (a + b);
        r = model_ray(w, mid);
        if (rt_prim_intersect(R->s, h.prim, &r, INFINITY, &t))
          b = mid;
        else
          a = mid;
      }
      if (!cut_off(R, w, 0.5 * (a + b), ue, depth, &c))
        break;
    }
  }
  if (R->rec) {
    int i = rec_event(R, depth, -1, w->kind, 0, 0.0, 0.0);
    rt_ray_t ends[2] = {model_ray(w, w->ua), model_ray(w, w->ub)};
    rec_ray(R, i, w->from_prim, &w->ray);
    rec_ray(R, i, w->from_prim, &ends[0]);
    rec_ray(R, i, w->from_prim, &ends[1]);
  }
  return rt_rgb_add(c, rt_rgb_mul(rt_wave_weight(&R->plan->wave, w->ua, w->ub), R->s->background));
}

/* The child of pencil w at its hit H (sf) on side `side` of the surface (+1 reflected, -1
 * refracted), direction d and its derivative dd (its footprint's fd), in medium `inside` of index
 * n: traced as a pencil over w's interval and weighted by wc. */
static rt_rgb_t child(wp_run_t *R, const wp_t *w, const rt_surface_t *sf, const wp_hit_t *H,
                      double side, px_vec3_t d, px_vec3_t dd, const px_vec3_t fd[2], double n,
                      const rt_material_t *inside, rt_ray_kind_t kind, rt_rgb_t wc, int depth) {
  const rt_prim_t *pr = &R->s->prim[H->hit.prim];
  wp_t ch = *w;
  ch.ray = (rt_ray_t){rt__offset_origin(sf, side),
                      d,
                      0.0,
                      INFINITY,
                      n,
                      pr->kind != RT_PRIM_SPHERE ? H->hit.prim : -1,
                      w->ray.lambda};
  ch.inside = inside;
  ch.d_o = H->dp;
  ch.d_d = dd;
  ch.kind = kind;
  ch.from = pr->kind == RT_PRIM_SPHERE ? &pr->sphere : NULL;
  ch.from_prim = H->hit.prim;
  /* a ray refracted into an object that is alone travels inside it; one reflected inside stays */
  ch.in_obj = side < 0.0 ? (H->side > 0.0 && R->s->object[H->hit.object].alone ? H->hit.object : -1)
                         : (inside_alone(H) ? w->in_obj : -1);
  ch.f_o[0] = H->fp[0];
  ch.f_o[1] = H->fp[1];
  ch.f_d[0] = fd[0];
  ch.f_d[1] = fd[1];
  ch.weight = w->weight * rt_rgb_max(wc);
  count(R, kind);
  return rt_rgb_mul(wc, trace(R, &ch, depth + 1));
}

static rt_rgb_t trace(wp_run_t *R, wp_t *w, int depth) {
  const rt_scene_t *s = R->s;
  const rt_plan_t *plan = R->plan;
  rt_hit_t hit;
  if (!rt_intersect(s, &w->ray, &hit))
    return miss(R, w, depth);
  rt_surface_t sf;
  rt_shade_surface(s, &hit, &w->ray, &sf);
  const rt_material_t *mat = sf.mat;
  wp_hit_t H = {.w = w, .hit = hit, .m = sf.nf, .side = sf.entering ? 1.0 : -1.0};
  H.next = sf.entering ? mat : NULL;
  double lambda = w->ray.lambda, n1 = w->ray.ior, n2, dn1, dn2, dummy;
  index_du(R, w->inside, w->uc, lambda, &dummy, &dn1);
  index_du(R, H.next, w->uc, lambda, &n2, &dn2);
  sf.n2 = n2;
  /* the column at the hit */
  px_vec3_t P = px_v3_axpy(hit.t, w->d_d, w->d_o), dm = {0, 0, 0};
  H.dp = px_v3_axpy(-px_v3_dot(P, H.m) / px_v3_dot(w->ray.d, H.m), w->ray.d, P);
  const rt_prim_t *pr = &s->prim[hit.prim];
  px_vec3_t dmf[2] = {{0, 0, 0}, {0, 0, 0}};
  fp_transfer(w->f_o, w->f_d, hit.t, w->ray.d, H.m, H.fp);
  H.pix = fp_pixel(H.fp);
  if (pr->kind == RT_PRIM_SPHERE) {
    dm = px_v3_scale(H.dp, H.side / pr->sphere.r);
    for (int k = 0; k < 2; k++)
      dmf[k] = px_v3_scale(H.fp[k], H.side / pr->sphere.r);
  }
  if (pr->kind == RT_PRIM_PLANE && s->object[hit.object].material2 >= 0) {
    H.checker = 1;
    square_of(s, hit.prim, hit.p, &H.su, &H.sv);
  }
  int more = depth < plan->max_depth;
  int refract = more && rt_plan_has(plan, RT_EFFECT_REFRACTION) && mat->kt > 0.0;
  H.reflect = more && (refract || (rt_plan_has(plan, RT_EFFECT_REFLECTION) && mat->kr > 0.0));
  H.refract = refract;
  wp_reflect_du(w->ray.d, w->d_d, H.m, dm, &H.dr, &H.ddr);
  /* selective dispersion ([P89] 3.2.4, corrected): whether the spectrum shows, more than a
   * quarter pixel apart on some surface */
  if (px_v3_norm(H.dp) * fmax(w->uc - w->ua, w->ub - w->uc) > WP_PIXELS * H.pix)
    R->shows = 1;
  double cos_t = 0.0;
  if (refract) {
    double deta = (dn1 * n2 - n1 * dn2) / (n2 * n2);
    H.tir = !wp_refract_du(w->ray.d, w->d_d, H.m, dm, n1 / n2, deta, &H.dt, &H.ddt, &cos_t);
  }
  H.sf = &sf;
  H.ev = -1;
  if (R->rec) {
    H.ev = rec_event(R, depth, hit.prim, w->kind, (H.side > 0.0) | (unsigned)H.tir << 1,
                     H.checker ? H.su : 0.0, H.checker ? H.sv : 0.0);
    rec_seg(R, H.ev, w->from_prim, w->ray.o, hit.p);
    if (s->nlight > 0 && (mat->kd > 0.0 || mat->ks > 0.0))
      rec_unusable(R, 2);
    if (concave(s, hit.prim))
      rec_unusable(R, 3);
  }
  H.direct = rt_shade_direct(s, plan, &sf, &w->ray, &R->inner);
  /* the ends */
  rt_rgb_t c = rt_rgb(0, 0, 0);
  for (int e = 0; e < 2 && w->weight >= WP_MIN_WEIGHT; e++) {
    for (;;) { /* until the end passes: each cut halves the model's error at least */
      double ue = e ? w->ub : w->ua;
      int occ = -1, why = ue != w->uc ? check(R, &H, ue, 1, &occ) : 0;
      if (!why)
        break;
      double cut = why >= WP_LINEAR ? 0.5 * (w->uc + ue) : bisect(R, &H, w->uc, ue, occ);
      if (!cut_off(R, w, cut, ue, depth, &c))
        break;
    }
  }
  /* this pencil: direct light at the axial hit, then the children */
  rt_rgb_t W = rt_wave_weight(&plan->wave, w->ua, w->ub);
  c = rt_rgb_add(c, rt_rgb_mul(W, H.direct));
  if (!more)
    return c;
  rt_rgb_t wr = rt_rgb(0, 0, 0), wt = rt_rgb(0, 0, 0);
  if (rt_plan_has(plan, RT_EFFECT_REFLECTION))
    wr = rt_rgb(mat->kr, mat->kr, mat->kr);
  if (refract) {
    wt = rt_rgb_scale(mat->transmittance, mat->kt);
    if (H.tir) {
      wr = rt_rgb_add(wr, wt);
      wt = rt_rgb(0, 0, 0);
    } else if (mat->fresnel) {
      double f = rt_fresnel(-px_v3_dot(H.m, w->ray.d), cos_t, n1, n2);
      wr = rt_rgb_add(wr, rt_rgb(mat->kt * f, mat->kt * f, mat->kt * f));
      wt = rt_rgb_scale(wt, 1.0 - f);
    }
  }
  /* the children's footprints, for those traced */
  px_vec3_t fd[2], o;
  if (rt_rgb_max(wr) > 0.0) {
    for (int k = 0; k < 2; k++)
      wp_reflect_du(w->ray.d, w->f_d[k], H.m, dmf[k], &o, &fd[k]);
    c = rt_rgb_add(
        c, child(R, w, &sf, &H, 1.0, H.dr, H.ddr, fd, n1, w->inside, RT_RAY_REFLECT, wr, depth));
  }
  if (rt_rgb_max(wt) > 0.0) { /* not totally reflected: wt is 0 then */
    for (int k = 0; k < 2; k++) {
      double ck;
      wp_refract_du(w->ray.d, w->f_d[k], H.m, dmf[k], n1 / n2, 0.0, &o, &fd[k], &ck);
    }
    c = rt_rgb_add(
        c, child(R, w, &sf, &H, -1.0, H.dt, H.ddt, fd, n2, H.next, RT_RAY_REFRACT, wt, depth));
  }
  return c;
}

/* The record's events in the order of their hashes (two records of the same events then list
 * them alike) and its signature: the sum of their distinct hashes, never 0. */
static void rec_finish(rt_spectral_rec_t *r) {
  for (int i = 1; i < r->nev; i++) /* insertion sort: a few events */
    for (int j = i; j > 0 && r->ev[j - 1] > r->ev[j]; j--) {
      uint64_t h = r->ev[j];
      r->ev[j] = r->ev[j - 1];
      r->ev[j - 1] = h;
      for (int a = 0; a < 6; a++) {
        double f = r->from[j][a], t = r->to[j][a];
        r->from[j][a] = r->from[j - 1][a];
        r->to[j][a] = r->to[j - 1][a];
        r->from[j - 1][a] = f;
        r->to[j - 1][a] = t;
      }
      for (int k = 0; k < RT_SPECTRAL_EVENT_PRIMS; k++) {
        int q = r->prim[j][k];
        r->prim[j][k] = r->prim[j - 1][k];
        r->prim[j - 1][k] = q;
      }
    }
  uint64_t sig = 0x2545F4914F6CDD1Dull * (uint64_t)(r->nev + 1);
  for (int i = 0; i < r->nev; i++)
    sig += r->ev[i];
  r->sig = r->unusable ? 0 : sig ? sig : 1;
}

/* ---- where a white ray refracts ------------------------------------------------------------ */

/* Snell's law for the white ray at u: 1 and the direction, 0 on total internal reflection; the
 * indices on both sides in n[0], n[1]. */
static int white_at(const wp_run_t *R, const rt_surface_t *sf, const rt_ray_t *ray,
                    const rt_material_t *inside, const rt_material_t *next, double u,
                    px_vec3_t *dir, px_vec3_t *ddir, double n[2], double *cos_t) {
  double lambda = lambda_of(&R->plan->wave, u), dn1, dn2;
  index_du(R, inside, u, lambda, &n[0], &dn1);
  index_du(R, next, u, lambda, &n[1], &dn2);
  px_vec3_t zero = {0, 0, 0};
  return wp_refract_du(ray->d, zero, sf->nf, zero, n[0] / n[1],
                       (dn1 * n[1] - n[0] * dn2) / (n[1] * n[1]), dir, ddir, cos_t);
}

static rt_rgb_t white(wp_run_t *R, const rt_surface_t *sf, const rt_ray_t *ray, double ua,
                      double ub, int depth, rt_rgb_t *wr, int *all_tir) {
  const rt_plan_t *plan = R->plan;
  const rt_material_t *mat = sf->mat;
  const rt_material_t *next = sf->entering ? mat : NULL, *inside = sf->entering ? NULL : mat;
  double uc = 0.5 * (ua + ub), n[2], ct;
  px_vec3_t dt, ddt;
  int ok = white_at(R, sf, ray, inside, next, uc, &dt, &ddt, n, &ct);
  double cut = NAN;
  for (int e = 0; e < 2 && isnan(cut); e++) {
    double ue = e ? ub : ua, ne[2], cte;
    px_vec3_t de, dde;
    int oke = white_at(R, sf, ray, inside, next, ue, &de, &dde, ne, &cte);
    if (oke != ok) { /* total internal reflection begins inside: find where */
      double a = uc, b = ue;
      for (int k = 0; k < WP_BISECT && fabs(b - a) > 0.125 * R->min_width; k++) {
        double mid = 0.5 * (a + b);
        if (white_at(R, sf, ray, inside, next, mid, &de, &dde, ne, &cte) == ok)
          a = mid;
        else
          b = mid;
      }
      cut = 0.5 * (a + b);
    } else if (ok &&
               too_far(de, wp_unit(px_v3_axpy(ue - uc, ddt, dt)), px_v3_norm(ddt) * fabs(ue - uc),
                       plan->spectral_tol, WP_PIXELS * plan->pixel_angle)) {
      cut = uc;
    }
  }
  if (!isnan(cut) && ub - ua > 2.0 * R->min_width && R->wbudget <= 0)
    rec_unusable(R, 4);
  if (!isnan(cut) && ub - ua > 2.0 * R->min_width && R->wbudget > 0) {
    cut = fmin(fmax(cut, ua + R->min_width), ub - R->min_width);
    R->wbudget--;
    R->shows = 1;
    rt_rgb_t lo = white(R, sf, ray, ua, cut, depth, wr, all_tir); /* in this order: the budget */
    return rt_rgb_add(lo, white(R, sf, ray, cut, ub, depth, wr, all_tir));
  }
  rt_rgb_t W = rt_wave_weight(&plan->wave, ua, ub);
  rt_rgb_t wt = rt_rgb_scale(mat->transmittance, mat->kt);
  if (R->rec) { /* the white ray's refraction, or its total internal reflection */
    int i = rec_event(R, depth, sf->hit.prim, RT_RAY_REFRACT, 4u | (unsigned)ok << 3, 0.0, 0.0);
    rec_seg(R, i, -1, sf->hit.p, sf->hit.p);
  }
  if (!ok) {
    *wr = rt_rgb_add(*wr, rt_rgb_mul(W, wt));
    return rt_rgb(0, 0, 0);
  }
  *all_tir = 0;
  if (mat->fresnel) {
    double f = rt_fresnel(-px_v3_dot(sf->nf, ray->d), ct, n[0], n[1]);
    *wr = rt_rgb_add(*wr, rt_rgb_scale(W, mat->kt * f));
    wt = rt_rgb_scale(wt, 1.0 - f);
  }
  int skip = R->s->prim[sf->hit.prim].kind != RT_PRIM_SPHERE ? sf->hit.prim : -1;
  double lambda = lambda_of(&plan->wave, uc);
  wp_t w = {.ray = {rt__offset_origin(sf, -1.0), dt, 0.0, INFINITY, n[1], skip, (float)lambda},
            .inside = next,
            .d_o = {0, 0, 0},
            .d_d = ddt,
            .ua = ua,
            .ub = ub,
            .uc = uc,
            .kind = RT_RAY_REFRACT,
            .from_prim = sf->hit.prim,
            .in_obj = sf->entering && R->s->object[sf->hit.object].alone ? sf->hit.object : -1,
            .weight = rt_rgb_max(wt)};
  if (!R->trace)
    return rt_rgb(0, 0, 0);
  /* the footprint: the pinhole's at the hit, on its tangent plane, refracted at u_c */
  px_vec3_t fo[2], fd[2];
  fp_pinhole(R->s, plan, sf->hit.p, ray->d, fo, fd);
  fp_transfer(fo, fd, 0.0, ray->d, sf->nf, w.f_o);
  const rt_prim_t *pr = &R->s->prim[sf->hit.prim];
  for (int k = 0; k < 2; k++) {
    px_vec3_t dmf = {0, 0, 0}, o;
    if (pr->kind == RT_PRIM_SPHERE)
      dmf = px_v3_scale(w.f_o[k], (sf->entering ? 1.0 : -1.0) / pr->sphere.r);
    double c;
    wp_refract_du(ray->d, fd[k], sf->nf, dmf, n[0] / n[1], 0.0, &o, &w.f_d[k], &c);
  }
  count(R, RT_RAY_REFRACT);
  count(R, RT_COUNT_SPECTRAL + 1);
  return rt_rgb_mul(wt, trace(R, &w, depth + 1));
}

/* A run's state (its inner tracer's ctx is the caller's to set, once the run has its place). */
static wp_run_t run_make(const rt_scene_t *s, const rt_plan_t *plan, const rt_tracer_t *tr,
                         const rt_material_t *glass, int trace) {
  const rt_wavescale_t *w = &plan->wave;
  wp_run_t R = {s,
                plan,
                tr,
                {NULL, shadow_cb, NULL, NULL, NULL, NULL, 0},
                WP_BUDGET,
                WP_WHITE_BUDGET,
                WP_MIN_FRACTION * (w->u_edge[RT_MAX_BINS] - w->u_edge[0]),
                glass,
                trace,
                0,
                NULL};
  if (tr && tr->occluded)
    R.inner.occluded = occluded_cb;
  return R;
}

rt_rgb_t rt_shade_spectral_ray(const rt_scene_t *s, const rt_plan_t *plan, const rt_ray_t *ray,
                               px_vec3_t d_o, px_vec3_t d_d, double ua, double ub,
                               const rt_material_t *inside, const rt_material_t *glass,
                               double weight, int depth, const rt_tracer_t *tr) {
  const rt_wavescale_t *ws = &plan->wave;
  wp_run_t R = run_make(s, plan, tr, ws->scaled ? glass : NULL, 1);
  R.inner.ctx = &R;
  double uc = 0.5 * (ua + ub), lambda = lambda_of(ws, uc), dn;
  wp_t w = {.ray = *ray,
            .inside = inside,
            .d_o = d_o,
            .d_d = px_v3_axpy(-px_v3_dot(ray->d, d_d), ray->d, d_d),
            .ua = ua,
            .ub = ub,
            .uc = uc,
            .kind = RT_RAY_REFRACT,
            .from_prim = ray->skip_prim,
            .in_obj = -1,
            .weight = weight};
  fp_pinhole(s, plan, ray->o, ray->d, w.f_o, w.f_d);
  w.ray.lambda = (float)lambda;
  index_du(&R, inside, uc, lambda, &w.ray.ior, &dn);
  count(&R, RT_RAY_REFRACT);
  count(&R, RT_COUNT_SPECTRAL + 1);
  return trace(&R, &w, depth);
}

rt_rgb_t rt__wp_refract(const rt_scene_t *s, const rt_plan_t *plan, const rt_surface_t *sf,
                        const rt_ray_t *ray, int depth, const rt_tracer_t *tr, rt_rgb_t *wr,
                        int *all_tir, rt_spectral_rec_t *rec) {
  const rt_wavescale_t *w = &plan->wave;
  wp_run_t R = run_make(s, plan, tr, NULL, tr != NULL);
  R.inner.ctx = &R;
  if (rec) {
    rec->nev = rec->unusable = 0;
    rec->sig = 0;
    R.rec = tr ? rec : NULL;
  }
  if (w->scaled && px_index_disperses(&sf->mat->index))
    R.glass = sf->mat;
  *all_tir = 1;
  count(&R, RT_COUNT_SPECTRAL);
  rt_rgb_t c = white(&R, sf, ray, w->u_edge[0], w->u_edge[RT_MAX_BINS], depth, wr, all_tir);
  if (R.trace && !R.shows)
    count(&R, RT_COUNT_SPECTRAL + 2);
  if (R.rec)
    rec_finish(rec);
  return c;
}
