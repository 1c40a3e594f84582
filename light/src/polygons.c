/* polygons.c -- illuminance polygons: pencil tracing of polyhedra for light (1987 paper, section
 * 4.2; 1989 paper, section 2.2.2). A light's beam is cut at the edges of the faces it meets, the
 * faces mapped into the beam's parameter plane (beam/beam.h: exact before the first face, the
 * generalised perspective transformation of the path's system matrix after it); each piece
 * follows its face's reflected and refracted children, and a piece that reaches the receiver is
 * an illuminance polygon x'_i = B xi_i carrying the piece's flux, spread over it (E = t_r I
 * omega / S, which is Eq. (8)'s t_r I cos(alpha) / |det B| to first order).
 *
 * A piece is checked before it is used: the exact rays of its vertices, traced along its path
 * (Snell's law at each face's plane), must meet the face where the linear model puts them, to
 * within a share --uniform-tol of the piece's flux (the error times the piece's perimeter on the
 * face, against its area) and, on the receiver, within --linear-tol cells; their reflected and
 * refracted children there must be the axial ray's, with weights within --uniform-tol. A piece
 * that fails is divided in two across its longest extent and traced again from its path's
 * start, up to 2 x --max-split times along a path; past that, and for slivers, the piece's
 * centroid ray carries its flux as a photon. */
#include <math.h>
#include <string.h>

#include "beam/beam.h"
#include "core/intersect.h"
#include "internal.h"
#include <stdlib.h>

typedef struct {
  lt_ctx_t *C;
  lt_accum_t *A;
  const lt_options_t *o;
  const bm_scene_t *b;
  bm_source_t src;
  rt_rgb_t power;
  double cell;     /* the map's smaller cell side */
  double min_area; /* pieces of less parameter area are slivers, traced as photons */
} pg_t;

static double mean(rt_rgb_t c) {
  return (c.r + c.g + c.b) / 3.0;
}

static int on_receiver(const pg_t *P, int object) {
  for (int k = 0; k < P->C->r->n; k++)
    if (P->C->r->object[k] == object)
      return 1;
  return 0;
}

/* The children at a point x of face g hit along direction d in medium ior. */
static int children(const pg_t *P, int g, px_vec3_t o, px_vec3_t d, double ior, px_vec3_t x,
                    int depth, rt_child_t ch[2]) {
  const bm_face_t *f = &P->b->face[g];
  rt_ray_t ray = {o, d, 0.0, INFINITY, ior, -1, 0.0f};
  rt_hit_t hit = {px_v3_norm(px_v3_sub(x, o)), x, f->n, f->prim, f->object};
  rt_surface_t sf;
  rt_shade_surface(P->C->s, &hit, &ray, &sf);
  return rt_shade_children(P->C->s, &P->C->plan, &sf, &ray, depth, ch);
}

/* The photon of a piece: its centroid's exact ray after the path, traced on by the transport
 * with the path's weight, every end settled with the piece's flux. */
static void photon(pg_t *P, const px_poly2_t *r, const bm_path_t *path, rt_rgb_t w, int depth) {
  double c[2];
  if (px_poly2_centroid(r, c) != PX_OK) {
    c[0] = r->v[0][0];
    c[1] = r->v[0][1];
  }
  double meas = bm_source_measure(&P->src, r);
  rt_ray_t ray = bm_source_ray(&P->src, c);
  if (path->n > 0) {
    px_vec3_t o, d;
    if (bm_exact(P->b, &P->src, path, c, &o, &d) != PX_OK) {
      P->C->st.lost++;
      return;
    }
    double ior = P->src.ior;
    for (int k = 0; k < path->n; k++)
      if (path->step[k].event == PX_EVENT_REFRACT)
        ior = path->step[k].n2;
    ray = (rt_ray_t){o, d, 0.0, INFINITY, ior, P->b->face[path->step[path->n - 1].face].prim, 0.0f};
  }
  lt_arrivals_t arr;
  lt__trace_from(P->C, &ray, w, depth, &arr);
  for (int k = 0; k < arr.n; k++)
    lt__settle(P->A, &arr.a[k], rt_rgb_scale(rt_rgb_mul(P->power, arr.a[k].w), meas), 1);
}

static void beam(pg_t *P, const px_poly2_t *r, const bm_path_t *path, rt_rgb_t w, int splits,
                 const int *faces, int nfaces);

/* The plane through the values e[k] at the vertices of r (least squares for more than three),
 * at the centroid c: what E would be there if it were linear over the piece. */
static double linear_at_centroid(const px_poly2_t *r, const double c[2], const double *e) {
  double s[3][3] = {{0}}, t[3] = {0};
  for (int k = 0; k < r->n; k++) {
    double x[3] = {1.0, r->v[k][0] - c[0], r->v[k][1] - c[1]};
    for (int i = 0; i < 3; i++) {
      t[i] += x[i] * e[k];
      for (int j = 0; j < 3; j++)
        s[i][j] += x[i] * x[j];
    }
  }
  /* the constant term by Cramer's rule */
  double det = s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) -
               s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0]) +
               s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0]);
  double num = t[0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) -
               s[0][1] * (t[1] * s[2][2] - s[1][2] * t[2]) +
               s[0][2] * (t[1] * s[2][1] - s[1][1] * t[2]);
  return det != 0.0 ? num / det : t[0] / r->n;
}

/* Eq. (8) generalised, per unit of the source's intensity: E = rho cos(alpha) / |det G(s)| at
 * the face for the rays of parameters p along path, with G(s) = G0 + s H the transverse spread
 * of the pencil there (B for a point source: x' = B xi), cos(alpha) the ray's against the face's
 * normal and rho the source measure per unit of parameter area (1 / |w|^3 for tangents a, b:
 * |w|^2 = 1 + a^2 + b^2; 1 across a parallel beam). 0 when the model fails. */
static int illuminance_at(const pg_t *P, const bm_path_t *path, const double p[2],
                          const bm_face_t *f, double *e) {
  bm_model_t mp;
  if (bm_model(P->b, &P->src, path, p, &mp) != PX_OK)
    return 0;
  double den = px_v3_dot(mp.d, f->n), s = (f->d - px_v3_dot(f->n, mp.o)) / den;
  if (!(den != 0.0) || !(s > 0.0) || !isfinite(s))
    return 0;
  double det = fabs(px_mat2_det(px_mat2_add(mp.g0, px_mat2_scale(mp.h, s))));
  double rho = P->src.parallel ? 1.0 : pow(1.0 + p[0] * p[0] + p[1] * p[1], -1.5);
  *e = rho * fabs(den) / det;
  return isfinite(*e) && *e > 0.0;
}

/* The piece r of the beam along `path` that meets face g first. */
static void piece(pg_t *P, const px_poly2_t *r, const bm_path_t *path, const bm_model_t *m, int g,
                  rt_rgb_t w, int splits, const int *near, int nnear) {
  const bm_face_t *f = &P->b->face[g];
  lt_stats_t *st = &P->C->st;
  int depth = path->n;
  /* the piece's own axial ray and children at g */
  double c[2];
  bm_model_t ma;
  px_vec3_t xa = px_v3(0, 0, 0);
  double sa;
  int ok = px_poly2_centroid(r, c) == PX_OK && bm_model(P->b, &P->src, path, c, &ma) == PX_OK &&
           bm_model_hit(&ma, &P->src, c, f->n, f->d, &xa, &sa) == PX_OK;
  st->rays += ok;
  rt_child_t ca[2];
  int nca = 0;
  if (ok) {
    px_vec3_t oa = ma.root ? bm_source_ray(&P->src, c).o : ma.o,
              da = ma.root ? bm_source_ray(&P->src, c).d : ma.d;
    nca = children(P, g, oa, da, ma.ior, xa, depth, ca);
  }
  /* the vertices: exact against linear, and their children */
  double y[PX_POLY_MAX][3], err = 0.0, ev[PX_POLY_MAX], ec = 0.0, scale = 1.0;
  px_vec3_t yc = xa;
  int nonlinear = 0;
  for (int k = 0; k < r->n && ok; k++) {
    px_vec3_t o, d, x, yk;
    double s;
    if (path->n == 0) {
      rt_ray_t q = bm_source_ray(&P->src, r->v[k]);
      o = q.o;
      d = q.d;
    } else if (bm_exact(P->b, &P->src, path, r->v[k], &o, &d) != PX_OK) {
      ok = 0;
      break;
    }
    st->rays++;
    double den = px_v3_dot(f->n, d), t = (f->d - px_v3_dot(f->n, o)) / den;
    if (!(den != 0.0) || !(t > 0.0) || !isfinite(t) ||
        bm_model_hit(m, &P->src, r->v[k], f->n, f->d, &yk, &s) != PX_OK) {
      ok = 0;
      break;
    }
    x = px_v3_axpy(t, d, o);
    err = fmax(err, px_v3_norm(px_v3_sub(x, yk)));
    y[k][0] = yk.x;
    y[k][1] = yk.y;
    y[k][2] = yk.z;
    rt_child_t ck[2];
    int nk = children(P, g, o, d, ma.ior, x, depth, ck);
    if (nk != nca) {
      ok = 0;
      break;
    }
    for (int j = 0; j < nk && ok; j++) {
      double tol = P->o->uniform_tol * rt_rgb_max(ca[j].weight);

      ok = ck[j].kind == ca[j].kind && ck[j].tir == ca[j].tir &&
           fabs(ck[j].weight.r - ca[j].weight.r) <= tol &&
           fabs(ck[j].weight.g - ca[j].weight.g) <= tol &&
           fabs(ck[j].weight.b - ca[j].weight.b) <= tol;
    }
  }
  int receiver = on_receiver(P, f->object), on_map = 0;
  if (ok && receiver) { /* only pieces that can reach the map need its accuracy */
    const lt_receiver_t *rc = P->C->r;
    const lt_map_t *mp = P->A->m;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int k = 0; k < r->n; k++) {
      px_vec3_t q = px_v3_sub(px_v3(y[k][0], y[k][1], y[k][2]), rc->p);
      double u = px_v3_dot(q, rc->u), v = px_v3_dot(q, rc->v);
      lo[0] = fmin(lo[0], u);
      hi[0] = fmax(hi[0], u);
      lo[1] = fmin(lo[1], v);
      hi[1] = fmax(hi[1], v);
    }
    on_map = hi[0] >= mp->u0 - P->cell && lo[0] <= mp->u1 + P->cell && hi[1] >= mp->v0 - P->cell &&
             lo[1] <= mp->v1 + P->cell;
  }
  if (ok) { /* the error's sliver against the piece's area on the face */
    double area = 0.0, perim = 0.0;
    for (int k = 0; k < r->n; k++) {
      int j = (k + 1) % r->n;
      px_vec3_t a = px_v3(y[k][0] - y[0][0], y[k][1] - y[0][1], y[k][2] - y[0][2]);
      px_vec3_t b = px_v3(y[j][0] - y[0][0], y[j][1] - y[0][1], y[j][2] - y[0][2]);
      area += 0.5 * px_v3_dot(px_v3_cross(a, b), f->n);
      perim += px_v3_norm(px_v3_sub(b, a));
    }
    if (P->o->uniform_tol > 0 && err * perim > P->o->uniform_tol * fabs(area))
      ok = 0;
    if (ok && on_map) {
      /* Eq. (8) at the centroid and the vertices, for Gouraud interpolation: E must be near
       * linear over the piece (the centroid's against the vertices' mean) and its integral
       * near the piece's exact flux */
      ok = illuminance_at(P, path, c, f, &ec) &&
           bm_model_hit(m, &P->src, c, f->n, f->d, &yc, &sa) == PX_OK;
      for (int k = 0; k < r->n && ok; k++)
        ok = illuminance_at(P, path, r->v[k], f, &ev[k]);
      double lin_e = ok ? linear_at_centroid(r, c, ev) : 0.0;
      /* ... and at the midpoints of its edges, where interpolation along an edge errs most */
      double worst_mid = 0.0;
      for (int k = 0; k < r->n && ok; k++) {
        int j = (k + 1) % r->n;
        double pm[2] = {0.5 * (r->v[k][0] + r->v[j][0]), 0.5 * (r->v[k][1] + r->v[j][1])}, em;
        ok = illuminance_at(P, path, pm, f, &em);
        worst_mid = fmax(worst_mid, fabs(em - 0.5 * (ev[k] + ev[j])) / em);
      }
      double integral = 0.0;
      for (int k = 0; k < r->n && ok; k++) {
        int j = (k + 1) % r->n;
        px_vec3_t a = px_v3(y[k][0] - yc.x, y[k][1] - yc.y, y[k][2] - yc.z);
        px_vec3_t b = px_v3(y[j][0] - yc.x, y[j][1] - yc.y, y[j][2] - yc.z);
        integral += 0.5 * fabs(px_v3_dot(px_v3_cross(a, b), f->n)) * (ec + ev[k] + ev[j]) / 3.0;
      }
      double flux = bm_source_measure(&P->src, r);
      /* E is interpolated within a quarter of the share at the centroid (against the plane
       * through the vertices' values) and at the edges' midpoints, and its integral is the
       * exact flux within as much: the cells come within about that quarter (0.5% at the
       * default; docs/illuminance.md) */
      double tol = 0.25 * P->o->uniform_tol;
      if (ok && tol > 0)
        ok =
            fabs(ec - lin_e) <= tol * ec && worst_mid <= tol && fabs(integral - flux) <= tol * flux;
      if (ok)
        scale = flux / integral;
      nonlinear = !ok;
    }
    if (ok && on_map && P->o->linear_tol > 0 && err > P->o->linear_tol * P->cell) {
      nonlinear = 1;
      ok = 0;
    }
  }
  if (!ok) {
    px_poly2_t half[2];
    if (splits < 2 * P->o->max_split && bm_halve(r, half)) {
      st->divided++;
      st->nonlinear += (uint64_t)nonlinear;
      /* each half is traced again from its path's start: its own axial ray and partition */
      for (int k = 0; k < 2; k++) {
        bm_path_t pre = *path;
        beam(P, &half[k], &pre, w, splits + 1, near, nnear);
      }
      return;
    }
    photon(P, r, path, w, depth);
    return;
  }
  rt_rgb_t flux = rt_rgb_scale(rt_rgb_mul(P->power, w), bm_source_measure(&P->src, r));
  if (receiver && P->C->indirect && depth == 0) {
    /* direct light on a caustic map's receiver: the renderer's shadow rays have it */
  } else if (receiver && !on_map) {
    st->flux_outside += mean(flux); /* beside the map: where does not matter */
  } else if (receiver) {
    double uv[PX_POLY_MAX][2], cu[2];
    const lt_receiver_t *rc = P->C->r;
    for (int k = 0; k < r->n; k++) {
      px_vec3_t q = px_v3_sub(px_v3(y[k][0], y[k][1], y[k][2]), rc->p);
      uv[k][0] = px_v3_dot(q, rc->u);
      uv[k][1] = px_v3_dot(q, rc->v);
      ev[k] *= scale;
    }
    px_vec3_t q = px_v3_sub(yc, rc->p);
    cu[0] = px_v3_dot(q, rc->u);
    cu[1] = px_v3_dot(q, rc->v);
    lt__deposit_gouraud(P->A, (const double(*)[2])uv, ev, r->n, cu, ec * scale,
                        rt_rgb_mul(P->power, w));
  }
  int counted = receiver && !(P->C->indirect && depth == 0);
  st->pencils += (uint64_t)counted;
  st->arrivals += (uint64_t)counted;
  rt_rgb_t kept = rt_rgb(1, 1, 1);
  for (int k = 0; k < nca; k++)
    kept = rt_rgb(kept.r - ca[k].weight.r, kept.g - ca[k].weight.g, kept.b - ca[k].weight.b);
  kept = rt_rgb(fmax(kept.r, 0.0), fmax(kept.g, 0.0), fmax(kept.b, 0.0));
  st->flux_absorbed += mean(rt_rgb_mul(flux, kept));
  for (int k = 0; k < nca; k++) {
    bm_path_t next = *path;
    next.step[next.n++] = (bm_step_t){
        g, ca[k].kind == RT_RAY_REFRACT ? PX_EVENT_REFRACT : PX_EVENT_REFLECT, ca[k].ray.ior, 0.0};
    beam(P, r, &next, rt_rgb_mul(w, ca[k].weight), splits, NULL, 0);
  }
}

/* The beam of parameter polygon r whose rays follow `path`: partitioned by the faces they meet
 * next. */
static void beam(pg_t *P, const px_poly2_t *r, const bm_path_t *path, rt_rgb_t w, int splits,
                 const int *faces, int nfaces) {
  lt_stats_t *st = &P->C->st;
  double c[2];
  bm_model_t m;
  if (px_poly2_centroid(r, c) != PX_OK)
    return; /* no area: no flux */
  if (path->n >= BM_MAX_STEPS || bm_model(P->b, &P->src, path, c, &m) != PX_OK) {
    photon(P, r, path, w, path->n);
    return;
  }
  st->rays++;
  st->segments++;
  bm_pieces_t pcs = {0};
  int unsure = 0, nnear = 0;
  int *near = malloc((size_t)P->b->nface * sizeof *near);
  if (!near) {
    photon(P, r, path, w, path->n);
    return;
  }
  if (bm_partition(P->b, &P->src, &m, r, P->min_area, faces, nfaces, near, &nnear, &pcs, &unsure) !=
      RT_OK) {
    bm_pieces_free(&pcs);
    free(near);
    photon(P, r, path, w, path->n);
    return;
  }
  px_poly2_t half[2];
  if (unsure && splits < 2 * P->o->max_split && bm_halve(r, half)) {
    bm_pieces_free(&pcs);
    st->divided++;
    beam(P, &half[0], path, w, splits + 1, near, nnear);
    beam(P, &half[1], path, w, splits + 1, near, nnear);
    free(near);
    return;
  }
  double rest = bm_source_measure(&P->src, r);
  for (int k = 0; k < pcs.n; k++)
    rest -= bm_source_measure(&P->src, &pcs.p[k].region);
  /* what meets no face leaves the scene */
  st->flux_escaped += fmax(rest, 0.0) * mean(rt_rgb_mul(P->power, w));
  for (int k = 0; k < pcs.n; k++) {
    if (pcs.p[k].face < 0 && px_poly2_area(&pcs.p[k].region) < 1e-6 * P->min_area)
      continue; /* below the ledger's rounding */
    if (pcs.p[k].face < 0)
      photon(P, &pcs.p[k].region, path, w, path->n);
    else
      piece(P, &pcs.p[k].region, path, &m, pcs.p[k].face, w, splits, near, nnear);
  }
  bm_pieces_free(&pcs);
  free(near);
}

void lt__polygons_tile(lt_ctx_t *C, lt_accum_t *A, const lt_options_t *o, const void *faces,
                       const lt_face_t *f, const double box[4]) {
  const lt_map_t *mp = A->m;
  pg_t P = {C,
            A,
            o,
            faces,
            {f->parallel, f->origin, f->x, f->y, f->z, f->ior},
            f->power,
            fmin((mp->u1 - mp->u0) / mp->width, (mp->v1 - mp->v0) / mp->height),
            1e-9 * (box[1] - box[0]) * (box[3] - box[2])};
  px_poly2_t r = {4, {{box[0], box[2]}, {box[1], box[2]}, {box[1], box[3]}, {box[0], box[3]}}};
  bm_path_t path = {0};
  beam(&P, &r, &path, rt_rgb(1, 1, 1), 0, NULL, 0);
}
