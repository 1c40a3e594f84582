/* beam.c -- the source's rays, a beam's linear model along its path (Eqs. 1-2 with Q = 0), the
 * exact rays it is checked against, the generalised perspective projection (Eq. 7) and the
 * hidden-surface partition of a parameter polygon (beam/beam.h). */
#include "beam/beam.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

rt_ray_t bm_source_ray(const bm_source_t *src, const double p[2]) {
  rt_ray_t r = {src->o, src->z, 0.0, INFINITY, src->ior, -1, 0.0f};
  px_vec3_t t = px_v3_add(px_v3_scale(src->x, p[0]), px_v3_scale(src->y, p[1]));
  if (src->parallel)
    r.o = px_v3_add(src->o, t);
  else
    r.d = px_v3_unit(px_v3_add(src->z, t));
  return r;
}

double bm_source_measure(const bm_source_t *src, const px_poly2_t *p) {
  if (src->parallel)
    return fabs(px_poly2_area(p));
  /* fan of spherical triangles about vertex 0: tan(omega / 2) = |a . (b x c)| / (1 + a.b + b.c
   * + c.a) for unit a, b, c (Van Oosterom and Strackee 1983) */
  double omega = 0.0;
  px_vec3_t a = bm_source_ray(src, p->v[0]).d;
  for (int k = 1; k + 1 < p->n; k++) {
    px_vec3_t b = bm_source_ray(src, p->v[k]).d, c = bm_source_ray(src, p->v[k + 1]).d;
    double num = fabs(px_v3_dot(a, px_v3_cross(b, c)));
    double den = 1.0 + px_v3_dot(a, b) + px_v3_dot(b, c) + px_v3_dot(c, a);
    omega += 2.0 * atan2(num, den);
  }
  return omega;
}

/* Jacobians of the source ray vector (x, xi) in frame f at parameters pc with respect to the
 * parameters: a parallel source moves the origin (jx), an apex turns the direction (jxi). */
static void source_jacobians(const bm_source_t *src, const double pc[2], px_frame_t f,
                             px_mat2_t *jx, px_mat2_t *jxi) {
  px_mat2_t j = px_mat2(px_v3_dot(f.x1, src->x), px_v3_dot(f.x1, src->y), px_v3_dot(f.x2, src->x),
                        px_v3_dot(f.x2, src->y));
  if (src->parallel) {
    *jx = j;
    *jxi = px_mat2_zero();
    return;
  }
  /* d = w / |w|, w = z + a x + b y: dd/da = (x - d (d . x)) / |w|, and x1, x2 are normal to d */
  double w = px_v3_norm(
      px_v3_add(src->z, px_v3_add(px_v3_scale(src->x, pc[0]), px_v3_scale(src->y, pc[1]))));
  *jx = px_mat2_zero();
  *jxi = px_mat2_scale(j, 1.0 / w);
}

/* The outgoing direction at a plane of normal nu (nu . d > 0): Snell's law n1 -> n2, or the
 * mirror law. PX_ETIR. */
static px_status_t bend(px_vec3_t d, px_vec3_t nu, px_event_t ev, double n1, double n2,
                        px_vec3_t *out) {
  double c = px_v3_dot(nu, d);
  if (ev == PX_EVENT_REFLECT) {
    *out = px_v3_axpy(-2.0 * c, nu, d);
    return PX_OK;
  }
  double eta = n1 / n2, k = 1.0 - eta * eta * (1.0 - c) * (1.0 + c);
  if (k < 0.0)
    return PX_ETIR;
  *out = px_v3_unit(px_v3_axpy(sqrt(k) - eta * c, nu, px_v3_scale(d, eta)));
  return PX_OK;
}

/* Distance along unit d from o to face f's plane; 0 when it is not ahead. */
static int plane_ahead(const bm_face_t *f, px_vec3_t o, px_vec3_t d, double *t) {
  double den = px_v3_dot(f->n, d), tt = (f->d - px_v3_dot(f->n, o)) / den;
  if (!(den != 0.0) || !(tt > 0.0) || !isfinite(tt))
    return 0;
  *t = tt;
  return 1;
}

px_status_t bm_exact_at(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                        const double p[2], double du, px_vec3_t *pts, px_vec3_t *o, px_vec3_t *d) {
  rt_ray_t r = bm_source_ray(src, p);
  double ior = src->ior;
  for (int k = 0; k < path->n; k++) {
    const bm_step_t *st = &path->step[k];
    const bm_face_t *f = &b->face[st->face];
    double t, n2 = st->n2 + st->dn2 * du;
    if (!plane_ahead(f, r.o, r.d, &t))
      return PX_EMISS;
    r.o = px_v3_axpy(t, r.d, r.o);
    if (pts)
      pts[k] = r.o;
    px_vec3_t nu = px_v3_dot(f->n, r.d) > 0 ? f->n : px_v3_scale(f->n, -1.0);
    px_status_t s = bend(r.d, nu, st->event, ior, n2, &r.d);
    if (s != PX_OK)
      return s;
    if (st->event == PX_EVENT_REFRACT)
      ior = n2;
  }
  *o = r.o;
  *d = r.d;
  return PX_OK;
}

px_status_t bm_exact(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                     const double p[2], px_vec3_t *o, px_vec3_t *d) {
  return bm_exact_at(b, src, path, p, 0.0, NULL, o, d);
}

/* bm_model(), and when cas is not NULL the path's elements appended to it (a transfer to each
 * face, then the face's refraction or reflection): the cascade of the Appendix's error analysis. */
static px_status_t trace_model(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                               const double pc[2], bm_model_t *m, px_cascade_t *cas) {
  memset(m, 0, sizeof *m);
  m->pc[0] = pc[0];
  m->pc[1] = pc[1];
  m->root = path->n == 0;
  m->last_face = path->n ? path->step[path->n - 1].face : -1;
  rt_ray_t r = bm_source_ray(src, pc);
  px_frame_t f;
  px_status_t st = px_frame_from_z(r.d, src->y, &f);
  if (st != PX_OK)
    return st;
  px_vec3_t o = r.o, d = f.z;
  double ior = src->ior;
  px_mat2_t jx, jxi;
  source_jacobians(src, pc, f, &jx, &jxi);
  px_mat4_t t = px_mat4_identity();
  for (int k = 0; k < path->n; k++) {
    const bm_step_t *sp = &path->step[k];
    const bm_face_t *fc = &b->face[sp->face];
    double len;
    if (!plane_ahead(fc, o, d, &len))
      return PX_EMISS;
    t = px_mat4_mul(px_transfer_matrix(len), t);
    o = px_v3_axpy(len, d, o);
    px_vec3_t nu = px_v3_dot(fc->n, d) > 0 ? fc->n : px_v3_scale(fc->n, -1.0);
    double n2 = sp->event == PX_EVENT_REFRACT ? sp->n2 : ior;
    px_interface_t ifc;
    st = px_interface_make(d, nu, f.x2, px_mat2_zero(), NULL, ior, n2, &ifc);
    px_vec3_t dout;
    double cout;
    if (st == PX_OK)
      st = px_interface_outgoing(&ifc, sp->event, &dout, &cout);
    px_frame_t fo;
    if (st == PX_OK)
      st = px_frame_from_z(dout, f.x2, &fo);
    px_mat4_t e;
    if (st == PX_OK)
      st = px_interface_matrix(&ifc, sp->event, f, fo, PX_VARIANT_CORRECTED, &e);
    if (st == PX_OK && cas) {
      st = px_cascade_push_transfer(cas, len, f);
      if (st == PX_OK)
        st = px_cascade_push_interface(cas, &ifc, sp->event, f, fo, PX_VARIANT_CORRECTED);
    }
    if (st != PX_OK)
      return st;
    t = px_mat4_mul(e, t);
    f = fo;
    d = fo.z;
    ior = n2;
  }
  px_mat2_t a = px_mat4_block(t, 0, 0), bb = px_mat4_block(t, 0, 1), c = px_mat4_block(t, 1, 0),
            dd = px_mat4_block(t, 1, 1);
  m->g0 = px_mat2_add(px_mat2_mul(a, jx), px_mat2_mul(bb, jxi));
  m->h = px_mat2_add(px_mat2_mul(c, jx), px_mat2_mul(dd, jxi));
  m->t = t;
  m->o = o;
  m->d = d;
  m->f = f;
  m->ior = ior;
  return PX_OK;
}

px_status_t bm_model(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                     const double pc[2], bm_model_t *m) {
  return trace_model(b, src, path, pc, m, NULL);
}

/* The linear transfer x' = x + L xi in ray coordinates (xi the sine-like projection of the unit
 * direction) against the exact x + L xi / sqrt(1 - |xi|^2): the difference is at most
 * BM_TRANSFER_K3 L |xi|^3 for |xi| <= BM_SPREAD_CAP ((1 - xi^2)^(-1/2) - 1 <= xi^2 / 2
 * (1 - xi^2)^(-3/2) <= 0.77 xi^2 there). */
#define BM_TRANSFER_K3 0.77

px_status_t bm_model_bound(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                           const bm_model_t *m, const px_poly2_t *r, px_vec3_t n, double dd,
                           px_variant_t variant, bm_bound_t *out) {
  memset(out, 0, sizeof *out);
  if (m->root)
    return PX_OK; /* before the first face the projection is exact */
  /* the spread of r about the axial ray: |delta| over the vertices (the largest |delta| of a
   * convex polygon is at a vertex) */
  double dmax = 0.0;
  for (int k = 0; k < r->n; k++)
    dmax = fmax(dmax, hypot(r->v[k][0] - m->pc[0], r->v[k][1] - m->pc[1]));
  if (!isfinite(dmax))
    return PX_EINVAL;
  /* the cascade of the path, and the transfer to the plane */
  px_element_t elem[2 * BM_MAX_STEPS + 1];
  px_cascade_t cas;
  px_cascade_init(&cas, elem, sizeof elem / sizeof elem[0]);
  bm_model_t again;
  px_status_t st = trace_model(b, src, path, m->pc, &again, &cas);
  if (st != PX_OK)
    return st;
  double den = px_v3_dot(n, m->d), cos_f = fabs(den) / px_v3_norm(n);
  if (!(cos_f > PX_COS_MIN))
    return PX_EGRAZING;
  double len = (dd - px_v3_dot(n, m->o)) / den;
  if (!(len > 0.0) || !isfinite(len))
    return PX_EMISS;
  st = px_cascade_push_transfer(&cas, len, m->f);
  if (st != PX_OK)
    return st;
  px_pencil_t k;
  st = px_pencil_constants(&cas, NULL, variant, &k);
  if (st != PX_OK)
    return st;
  px_mat4_t t = px_cascade_product(&cas);
  double na = px_mat2_norm2(px_mat4_block(t, 0, 0)), nb = px_mat2_norm2(px_mat4_block(t, 0, 1)),
         nd = px_mat2_norm2(px_mat4_block(t, 1, 1));
  double x0 = 0.0, xi0 = 0.0, conv = 0.0;
  if (src->parallel) {
    x0 = dmax; /* the parameters are the ray's offset itself: no conversion error */
  } else {
    /* xi = P Delta / |w + Delta| for w = z + pc x + pc y (|w| = L) and Delta = delta x + delta
     * y, against the model's P Delta / L: the difference is |P Delta| (2 |w . Delta| +
     * |Delta|^2) / (L |w + Delta| (L + |w + Delta|)), with |w + Delta| >= max(1, L - |Delta|)
     * and |w . Delta| <= sqrt(L^2 - 1) |Delta| */
    double L = sqrt(1.0 + m->pc[0] * m->pc[0] + m->pc[1] * m->pc[1]);
    double w = fmax(1.0, L - dmax);
    xi0 = dmax / w;
    conv = dmax * (2.0 * sqrt(L * L - 1.0) * dmax + dmax * dmax) / (L * w * (L + w));
  }
  out->xi0 = xi0;
  out->x0 = x0;
  out->c = k.c;
  double ex = fmax(0.0, px_pencil_ex(&k, x0, xi0)), exi = fmax(0.0, px_pencil_exi(&k, x0, xi0));
  out->second = ex;
  /* the third-order error of every transfer (the Appendix's bounds are second-order), carried
   * to the plane by the position block of what follows it */
  double third = 0.0;
  px_mat4_t after[2 * BM_MAX_STEPS + 1], before = px_mat4_identity(); /* T_i^a, T_i^b */
  after[cas.n - 1] = px_mat4_identity();
  for (size_t i = cas.n - 1; i > 0; i--)
    after[i - 1] = px_mat4_mul(after[i], elem[i].t);
  for (size_t i = 1; i <= cas.n; before = px_mat4_mul(elem[i - 1].t, before), i++) {
    if (elem[i - 1].kind != PX_ELEMENT_TRANSFER)
      continue;
    double spread = px_mat2_norm2(px_mat4_block(before, 1, 0)) * x0 +
                    px_mat2_norm2(px_mat4_block(before, 1, 1)) * xi0;
    if (!(spread <= BM_SPREAD_CAP))
      return PX_EILLCOND;
    third += BM_TRANSFER_K3 * fabs(elem[i - 1].distance) *
             px_mat2_norm2(px_mat4_block(after[i - 1], 0, 0)) * spread * spread * spread;
  }
  out->third = third;
  out->conversion = nb * conv;
  double pos = ex + third + nb * conv, dir = exi + nd * conv;
  /* from the plane across the ray at the axial ray's point to the plane n . x = dd: a point at
   * transverse offset x slides |x| tan(theta) along its ray, where the directions differ by
   * dir, and a transverse displacement grows by at most 1 / cos(theta) */
  double reach = na * x0 + nb * xi0 + pos;
  double slide = reach * sqrt(fmax(0.0, 1.0 - cos_f * cos_f)) / cos_f;
  out->err = (pos + dir * slide) / cos_f;
  if (!isfinite(out->err))
    return PX_ENONFINITE;
  return PX_OK;
}

px_status_t bm_project(const bm_model_t *m, const bm_source_t *src, px_vec3_t v, double p[2]) {
  if (m->root) {
    px_vec3_t r = px_v3_sub(v, src->o);
    double rz = px_v3_dot(r, src->z);
    if (!(rz > 0.0))
      return PX_EMISS;
    double k = src->parallel ? 1.0 : 1.0 / rz;
    p[0] = px_v3_dot(r, src->x) * k;
    p[1] = px_v3_dot(r, src->y) * k;
    return isfinite(p[0]) && isfinite(p[1]) ? PX_OK : PX_EMISS;
  }
  px_vec3_t r = px_v3_sub(v, m->o);
  double s = px_v3_dot(r, m->d);
  if (!(s > 0.0))
    return PX_EMISS;
  px_mat2_t g = px_mat2_add(m->g0, px_mat2_scale(m->h, s)), gi;
  if (px_mat2_inverse(g, &gi) != PX_OK)
    return PX_ESINGULAR;
  double x1 = px_v3_dot(r, m->f.x1), x2 = px_v3_dot(r, m->f.x2);
  p[0] = m->pc[0] + gi.m[0][0] * x1 + gi.m[0][1] * x2;
  p[1] = m->pc[1] + gi.m[1][0] * x1 + gi.m[1][1] * x2;
  return isfinite(p[0]) && isfinite(p[1]) ? PX_OK : PX_ESINGULAR;
}

void bm_model_ray(const bm_model_t *m, const bm_source_t *src, const double p[2], px_vec3_t *o,
                  px_vec3_t *d) {
  if (m->root) {
    rt_ray_t r = bm_source_ray(src, p);
    *o = r.o;
    *d = r.d;
    return;
  }
  double e0 = p[0] - m->pc[0], e1 = p[1] - m->pc[1];
  double x1 = m->g0.m[0][0] * e0 + m->g0.m[0][1] * e1, x2 = m->g0.m[1][0] * e0 + m->g0.m[1][1] * e1;
  double k1 = m->h.m[0][0] * e0 + m->h.m[0][1] * e1, k2 = m->h.m[1][0] * e0 + m->h.m[1][1] * e1;
  *o = px_v3_add(m->o, px_v3_add(px_v3_scale(m->f.x1, x1), px_v3_scale(m->f.x2, x2)));
  /* the paraxial direction with a unit component along d: the line parameter is the depth */
  *d = px_v3_add(m->d, px_v3_add(px_v3_scale(m->f.x1, k1), px_v3_scale(m->f.x2, k2)));
}

px_status_t bm_model_hit(const bm_model_t *m, const bm_source_t *src, const double p[2],
                         px_vec3_t n, double dd, px_vec3_t *x, double *s) {
  px_vec3_t o, d;
  bm_model_ray(m, src, p, &o, &d);
  double den = px_v3_dot(n, d), t = (dd - px_v3_dot(n, o)) / den;
  if (!(den != 0.0) || !(t > 0.0) || !isfinite(t))
    return PX_EMISS;
  *x = px_v3_axpy(t, d, o);
  *s = m->root ? t * px_v3_dot(d, src->z) : t;
  return PX_OK;
}

int bm_halve(const px_poly2_t *r, px_poly2_t half[2]) {
  double c[2];
  if (px_poly2_centroid(r, c) != PX_OK)
    return 0;
  double best = -1, ax = 1, ay = 0;
  for (int i = 0; i < r->n; i++)
    for (int j = i + 1; j < r->n; j++) {
      double dx = r->v[j][0] - r->v[i][0], dy = r->v[j][1] - r->v[i][1], l = dx * dx + dy * dy;
      if (l > best) {
        best = l;
        ax = dx;
        ay = dy;
      }
    }
  return px_poly2_split(r, ax, ay, ax * c[0] + ay * c[1], &half[0], &half[1]) == PX_OK &&
         half[0].n >= 3 && half[1].n >= 3;
}

void bm_pieces_free(bm_pieces_t *l) {
  free(l->p);
  memset(l, 0, sizeof *l);
}

static rt_status_t push(bm_pieces_t *l, int face, const px_poly2_t *r) {
  if (l->n == l->cap) {
    int cap = l->cap ? 2 * l->cap : 16;
    bm_piece_t *p = realloc(l->p, (size_t)cap * sizeof *p);
    if (!p)
      return RT_ENOMEM;
    l->p = p;
    l->cap = cap;
  }
  l->p[l->n].face = face;
  l->p[l->n++].region = *r;
  return RT_OK;
}

/* Convex hull (Andrew's monotone chain) of q[0..n-1] into h, counter-clockwise; n <= PX_POLY_MAX */
static void hull(double (*q)[2], int n, px_poly2_t *h) {
  /* insertion sort by x, then y */
  for (int i = 1; i < n; i++)
    for (int j = i;
         j > 0 && (q[j][0] < q[j - 1][0] || (q[j][0] == q[j - 1][0] && q[j][1] < q[j - 1][1]));
         j--) {
      double t0 = q[j][0], t1 = q[j][1];
      q[j][0] = q[j - 1][0];
      q[j][1] = q[j - 1][1];
      q[j - 1][0] = t0;
      q[j - 1][1] = t1;
    }
  double w[2 * PX_POLY_MAX][2];
  int k = 0;
  for (int i = 0; i < n; i++) { /* lower */
    while (k >= 2 && (w[k - 1][0] - w[k - 2][0]) * (q[i][1] - w[k - 2][1]) -
                             (w[k - 1][1] - w[k - 2][1]) * (q[i][0] - w[k - 2][0]) <=
                         0)
      k--;
    w[k][0] = q[i][0];
    w[k++][1] = q[i][1];
  }
  for (int i = n - 2, lo = k + 1; i >= 0; i--) { /* upper */
    while (k >= lo && (w[k - 1][0] - w[k - 2][0]) * (q[i][1] - w[k - 2][1]) -
                              (w[k - 1][1] - w[k - 2][1]) * (q[i][0] - w[k - 2][0]) <=
                          0)
      k--;
    w[k][0] = q[i][0];
    w[k++][1] = q[i][1];
  }
  h->n = k > 1 ? k - 1 : 0;
  if (h->n > PX_POLY_MAX)
    h->n = 0;
  for (int i = 0; i < h->n; i++) {
    h->v[i][0] = w[i][0];
    h->v[i][1] = w[i][1];
  }
  if (h->n < 3)
    h->n = 0;
}

/* A face ahead of the model, projected: its polygon P in parameters and Q = P within the
 * region. */
typedef struct {
  int face;
  px_poly2_t p, q;
  double box[4]; /* Q's bounds */
} cand_t;

static void bounds(const px_poly2_t *p, double box[4]) {
  box[0] = box[2] = INFINITY;
  box[1] = box[3] = -INFINITY;
  for (int k = 0; k < p->n; k++) {
    box[0] = fmin(box[0], p->v[k][0]);
    box[1] = fmax(box[1], p->v[k][0]);
    box[2] = fmin(box[2], p->v[k][1]);
    box[3] = fmax(box[3], p->v[k][1]);
  }
}

static int boxes_meet(const double a[4], const double b[4]) {
  return a[0] < b[1] && b[0] < a[1] && a[2] < b[3] && b[2] < a[3];
}

/* Project face f; 0 when no part of it is ahead, -1 when it cannot be projected. */
static int project_face(const bm_scene_t *b, const bm_source_t *src, const bm_model_t *m,
                        const bm_face_t *f, const px_poly2_t *region, px_poly2_t *out) {
  if (f->count == 0) {
    /* a plane: the rays of the region that go towards it, n . dir(p) of the sign that brings the
     * origin nearer, a half-plane of parameters since dir(p) is linear in p (z + a x + b y for an
     * apex; the paraxial d + F H (p - pc) after faces, from one origin to first order; for a
     * parallel root the origin moves instead) */
    px_vec3_t o = m->root ? src->o : m->o;
    double side = px_v3_dot(f->n, o) - f->d;
    double c0, ca, cb; /* n . dir(p) = c0 + ca p0 + cb p1 */
    if (m->root && src->parallel) {
      /* each ray starts at o + a x + b y: it meets the plane ahead when its own start's side
       * and n . z have opposite signs, again a half-plane */
      double cz = px_v3_dot(f->n, src->z);
      if (cz == 0.0)
        return 0;
      double nx = px_v3_dot(f->n, src->x) * cz, ny = px_v3_dot(f->n, src->y) * cz;
      if (nx == 0.0 && ny == 0.0) {
        if (!(side * cz < 0.0))
          return 0;
        *out = *region;
        return 1;
      }
      if (px_poly2_split(region, nx, ny, -side * cz, out, NULL) != PX_OK)
        return -1;
      return out->n >= 3 ? 1 : 0;
    }
    if (side == 0.0)
      return 0; /* the origin lies in the plane */
    if (m->root) {
      c0 = px_v3_dot(f->n, src->z);
      ca = px_v3_dot(f->n, src->x);
      cb = px_v3_dot(f->n, src->y);
    } else {
      double k1 = px_v3_dot(f->n, m->f.x1), k2 = px_v3_dot(f->n, m->f.x2);
      ca = k1 * m->h.m[0][0] + k2 * m->h.m[1][0];
      cb = k1 * m->h.m[0][1] + k2 * m->h.m[1][1];
      c0 = px_v3_dot(f->n, m->d) - ca * m->pc[0] - cb * m->pc[1];
    }
    /* towards the plane: side * (n . dir) < 0 */
    if (ca == 0.0 && cb == 0.0) {
      if (!(side * c0 < 0.0))
        return 0;
      *out = *region;
      return 1;
    }
    double sg = side > 0 ? 1.0 : -1.0;
    if (px_poly2_split(region, sg * ca, sg * cb, -sg * c0, out, NULL) != PX_OK)
      return -1;
    return out->n >= 3 ? 1 : 0;
  }
  /* clip to the half-space ahead of the origin: (v - o) . a >= eps */
  px_vec3_t o = m->root ? src->o : m->o, a = m->root ? src->z : m->d;
  double eps = 1e-9 * b->scale;
  px_vec3_t in[PX_POLY_MAX + 1], v[PX_POLY_MAX + 2];
  int n = 0;
  const px_vec3_t *fv = b->vertex + f->first;
  for (int k = 0; k < f->count; k++)
    in[k] = fv[k];
  for (int k = 0; k < f->count; k++) {
    px_vec3_t u = in[k], w = in[(k + 1) % f->count];
    double du = px_v3_dot(px_v3_sub(u, o), a) - eps, dw = px_v3_dot(px_v3_sub(w, o), a) - eps;
    if (du >= 0)
      v[n++] = u;
    if ((du < 0 && dw > 0) || (du > 0 && dw < 0))
      v[n++] = px_v3_add(u, px_v3_scale(px_v3_sub(w, u), du / (du - dw)));
  }
  if (n < 3)
    return 0;
  if (n > PX_POLY_MAX)
    return -1;
  double q[PX_POLY_MAX][2];
  for (int k = 0; k < n; k++) {
    px_status_t st = bm_project(m, src, v[k], q[k]);
    if (st == PX_EMISS)
      return 0;
    if (st != PX_OK)
      return -1;
  }
  hull(q, n, out);
  return out->n >= 3 ? 1 : 0;
}

/* Distance along the model's axis to face f at parameters p; INFINITY when not ahead. */
static double depth(const bm_source_t *src, const bm_model_t *m, const bm_face_t *f,
                    const double p[2]) {
  px_vec3_t x;
  double s;
  return bm_model_hit(m, src, p, f->n, f->d, &x, &s) == PX_OK ? s : INFINITY;
}

/* Whether faces f and g cross over their projections' overlap `both`: each is nearer at some of
 * its vertices, by more than rounding (faces that meet along an edge tie there). Then the one
 * nearer at the overlap's centroid does not hide the other everywhere: two objects that cut into
 * each other, such as a box sunk into a floor, whose buried part was drawn over the floor. Asked
 * of faces of different objects, and of one object's faces that share no vertex (a polyhedron
 * that cuts into itself): faces that meet along an edge or at a corner tie there, and a reflected
 * or refracted beam's model ties them only to within its error (see apart()). */
static int crossing(const bm_source_t *src, const bm_model_t *m, const bm_face_t *f,
                    const bm_face_t *g, const px_poly2_t *both) {
  int nearer_f = 0, nearer_g = 0;
  for (int k = 0; k < both->n; k++) {
    double sf = depth(src, m, f, both->v[k]), sg = depth(src, m, g, both->v[k]);
    double tie = 1e-9 * fmax(fabs(sf), fabs(sg));
    nearer_f |= sf < sg - tie;
    nearer_g |= sg < sf - tie;
  }
  return nearer_f && nearer_g;
}

/* Whether faces f and g of scene b may cut into each other: of different objects, or of one
 * object and of different primitives sharing no vertex. The faces of one primitive (the triangles
 * of a polygon that is not convex) lie in one plane; a polyhedron's faces that meet at an edge or
 * a corner tie there, where a beam's model orders them only to within its error (on Fig. 11's
 * torus, 8e-4 in depth: testing those too divided thousands of regions for nothing). */
static int apart(const bm_scene_t *b, const bm_face_t *f, const bm_face_t *g) {
  if (f->object != g->object)
    return 1;
  if (f->prim == g->prim)
    return 0;
  const px_vec3_t *vf = b->vertex + f->first, *vg = b->vertex + g->first;
  for (int i = 0; i < f->count; i++)
    for (int j = 0; j < g->count; j++)
      if (vf[i].x == vg[j].x && vf[i].y == vg[j].y && vf[i].z == vg[j].z)
        return 0;
  return 1;
}

/* Replace the pieces l[from ..] by their parts outside polygon c. */
static rt_status_t subtract_all(bm_pieces_t *l, int from, const px_poly2_t *c, int face) {
  int end = l->n;
  for (int k = from; k < end; k++) {
    if (l->p[k].face == -3)
      continue; /* removed by an earlier polygon */
    px_poly2_t cut[PX_POLY_MAX];
    int nc = 0;
    if (px_poly2_subtract(&l->p[k].region, c, 0.0, cut, PX_POLY_MAX, &nc) != PX_OK) {
      nc = 0; /* more vertices than a polygon holds: keep it whole (a sliver of error) */
      continue;
    }
    /* the piece becomes its first part outside, the rest are appended */
    if (nc == 0) {
      l->p[k].face = -3; /* removed */
      continue;
    }
    l->p[k].region = cut[0];
    for (int j = 1; j < nc; j++)
      if (push(l, face, &cut[j]) != RT_OK)
        return RT_ENOMEM;
  }
  /* the appended parts need the same treatment only for later polygons: they are outside c */
  return RT_OK;
}

static rt_status_t compact_into(bm_pieces_t *tmp, int from, int face, double min_area,
                                bm_pieces_t *out) {
  for (int k = from; k < tmp->n; k++) {
    if (tmp->p[k].face == -3)
      continue;
    double a = px_poly2_area(&tmp->p[k].region);
    if (!(a > 0.0))
      continue;
    if (push(out, a > min_area ? face : -2, &tmp->p[k].region) != RT_OK)
      return RT_ENOMEM;
  }
  return RT_OK;
}

rt_status_t bm_partition(const bm_scene_t *b, const bm_source_t *src, const bm_model_t *m,
                         const px_poly2_t *region, double min_area, const int *faces, int nfaces,
                         int *near, int *nnear, bm_pieces_t *out, int *unsure) {
  return bm_partition_capped(b, src, m, region, min_area, faces, nfaces, near, nnear, out, unsure,
                             0, NULL);
}

rt_status_t bm_partition_capped(const bm_scene_t *b, const bm_source_t *src, const bm_model_t *m,
                                const px_poly2_t *region, double min_area, const int *faces,
                                int nfaces, int *near, int *nnear, bm_pieces_t *out, int *unsure,
                                int max_faces, int *crowded) {
  if (crowded)
    *crowded = 0;
  cand_t *cand = NULL;
  int nc = 0, cc = 0;
  double rbox[4];
  bounds(region, rbox);
  int skip_prim = m->last_face >= 0 ? b->face[m->last_face].prim : -1;
  double gw = 0.5 * (rbox[1] - rbox[0]), gh = 0.5 * (rbox[3] - rbox[2]);
  double grown[4] = {rbox[0] - gw, rbox[1] + gw, rbox[2] - gh, rbox[3] + gh};
  if (nnear)
    *nnear = 0;
  /* the region's rays stay within a cone about the axial ray: lateral offset at most
   * spread_x + depth * spread_d (first order; exact for the root), doubled for safety */
  double spread_x = 0.0, spread_d = 0.0;
  px_vec3_t o0 = m->o, d0 = m->d;
  for (int k = 0; k < region->n; k++) {
    double e0 = region->v[k][0] - m->pc[0], e1 = region->v[k][1] - m->pc[1];
    if (m->root) {
      rt_ray_t rk = bm_source_ray(src, region->v[k]);
      spread_x = fmax(spread_x, px_v3_norm(px_v3_sub(rk.o, o0)));
      double c = px_v3_dot(rk.d, d0);
      spread_d = fmax(spread_d, c > 0 ? px_v3_norm(px_v3_cross(rk.d, d0)) / c : INFINITY);
    } else {
      spread_x = fmax(spread_x, hypot(m->g0.m[0][0] * e0 + m->g0.m[0][1] * e1,
                                      m->g0.m[1][0] * e0 + m->g0.m[1][1] * e1));
      spread_d = fmax(spread_d, hypot(m->h.m[0][0] * e0 + m->h.m[0][1] * e1,
                                      m->h.m[1][0] * e0 + m->h.m[1][1] * e1));
    }
  }
  rt_status_t status = RT_OK;
  int nf = faces ? nfaces : b->nface;
  for (int kk = 0; kk < nf; kk++) {
    int k = faces ? faces[kk] : kk;
    const bm_face_t *f = &b->face[k];
    if (f->prim == skip_prim)
      continue; /* a ray leaving a plane cannot meet it again */
    if (f->count > 0) {
      px_vec3_t rc = px_v3_sub(f->c, o0);
      double depth_c = px_v3_dot(rc, d0);
      if (depth_c < -f->radius)
        continue; /* wholly behind */
      double lateral = px_v3_norm(px_v3_axpy(-depth_c, d0, rc));
      if (isfinite(spread_d) &&
          lateral > 2.0 * (spread_x + fmax(depth_c + f->radius, 0.0) * spread_d) + f->radius +
                        1e-9 * b->scale)
        continue; /* outside the region's cone */
    }
    px_poly2_t p;
    int r = project_face(b, src, m, f, region, &p);
    if (r < 0) {
      *unsure = 1;
      if (near)
        near[(*nnear)++] = k; /* cannot tell: keep it for the divided parts */
    }
    if (r <= 0)
      continue;
    double pbox[4];
    bounds(&p, pbox);
    if (near && boxes_meet(pbox, grown))
      near[(*nnear)++] = k;
    if (!boxes_meet(pbox, rbox))
      continue;
    px_poly2_t q;
    if (px_poly2_intersect(region, &p, &q) != PX_OK) {
      *unsure = 1;
      continue;
    }
    if (!(px_poly2_area(&q) > 0.0))
      continue;
    if (max_faces > 0 && nc >= max_faces) {
      *crowded = 1; /* go on for the near list only */
      continue;
    }
    if (nc == cc) {
      cc = cc ? 2 * cc : 32;
      cand_t *c2 = realloc(cand, (size_t)cc * sizeof *c2);
      if (!c2) {
        free(cand);
        return RT_ENOMEM;
      }
      cand = c2;
    }
    cand[nc].face = k;
    cand[nc].p = p;
    cand[nc].q = q;
    bounds(&q, cand[nc].box);
    nc++;
  }
  if (crowded && *crowded) {
    free(cand);
    return RT_OK;
  }
  bm_pieces_t tmp = {0};
  /* each face's visible part: Q less every nearer face's polygon where they overlap */
  for (int i = 0; i < nc && status == RT_OK; i++) {
    tmp.n = 0;
    status = push(&tmp, cand[i].face, &cand[i].q);
    for (int j = 0; j < nc && status == RT_OK; j++) {
      if (j == i || !boxes_meet(cand[i].box, cand[j].box))
        continue;
      px_poly2_t both;
      double c[2];
      if (px_poly2_intersect(&cand[i].q, &cand[j].q, &both) != PX_OK ||
          px_poly2_centroid(&both, c) != PX_OK)
        continue;
      double si = depth(src, m, &b->face[cand[i].face], c),
             sj = depth(src, m, &b->face[cand[j].face], c);
      if (i < j && apart(b, &b->face[cand[i].face], &b->face[cand[j].face]) &&
          crossing(src, m, &b->face[cand[i].face], &b->face[cand[j].face], &both))
        *unsure = 1; /* the nearer at the centroid is not the nearer everywhere */
      if (sj < si || (sj == si && j < i))
        status = subtract_all(&tmp, 0, &cand[j].p, cand[i].face);
    }
    if (status == RT_OK)
      status = compact_into(&tmp, 0, cand[i].face, min_area, out);
  }
  bm_pieces_free(&tmp);
  free(cand);
  return status;
}
