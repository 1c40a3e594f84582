/* source.c -- the grid of rays a light sends: the parameterisation of its faces and the source
 * measure (solid angle or beam area) of a triangle of grid parameters.
 *
 * Only rays that can reach the map matter: those aimed at the map's rectangle on the receiver
 * directly, or at an object that reflects or transmits light. A point light outside the box of
 * those targets gets one face, the square of directions through the box (a frustum); a point light
 * inside it, or with an unbounded reflecting or transmitting object in the scene, gets the six
 * faces of a cube around it. A parallel light gets one face across its beam, over the box's
 * shadow (an unbounded reflecting plane is not followed beyond that box: docs/illuminance.md).
 * An area light is traced as a mesh of Lambertian point sources, one at each mesh cell's centre
 * with the cell's share of the intensity (the 1989 paper's section 2.3: "divide an area source
 * into a mesh"). */
#include <math.h>

#include "core/intersect.h"
#include "internal.h"

/* Grow the box lo..hi by p. */
static void grow(px_vec3_t *lo, px_vec3_t *hi, px_vec3_t p) {
  *lo = px_v3(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
  *hi = px_v3(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
}

/* The box of the targets: the map's rectangle and every bounded object that reflects or
 * transmits; *unbounded set when such an object has no bounds (a plane). */
static void targets(const rt_scene_t *s, const lt_receiver_t *rc, const lt_map_t *m, px_vec3_t *lo,
                    px_vec3_t *hi, int *unbounded) {
  *lo = px_v3(INFINITY, INFINITY, INFINITY);
  *hi = px_v3(-INFINITY, -INFINITY, -INFINITY);
  *unbounded = 0;
  for (int k = 0; k < 4; k++) {
    double u = k & 1 ? m->u1 : m->u0, v = k & 2 ? m->v1 : m->v0;
    grow(lo, hi, px_v3_add(rc->p, px_v3_add(px_v3_scale(rc->u, u), px_v3_scale(rc->v, v))));
  }
  for (int o = 0; o < s->nobject; o++) {
    const rt_object_t *ob = &s->object[o];
    const rt_material_t *m1 = &s->material[ob->material];
    const rt_material_t *m2 = ob->material2 >= 0 ? &s->material[ob->material2] : m1;
    int own = 0;
    for (int k = 0; k < rc->n; k++)
      own |= rc->object[k] == o;
    if (own || (m1->kr <= 0 && m1->kt <= 0 && m2->kr <= 0 && m2->kt <= 0))
      continue;
    for (int p = ob->first_prim; p < ob->first_prim + ob->nprim; p++) {
      px_vec3_t a, b;
      if (!rt_prim_bounds(s, p, &a, &b)) {
        *unbounded = 1;
        continue;
      }
      grow(lo, hi, a);
      grow(lo, hi, b);
    }
  }
}

/* A frame with z along d. */
static void frame_of(px_vec3_t d, px_vec3_t *x, px_vec3_t *y) {
  px_vec3_t t = fabs(d.x) < 0.6 ? px_v3(1, 0, 0) : px_v3(0, 1, 0);
  *x = px_v3_unit(px_v3_cross(t, d));
  *y = px_v3_cross(d, *x);
}

int lt__faces(const rt_scene_t *s, const lt_receiver_t *rc, const lt_map_t *m, int l, int sub,
              int mesh, int spread, lt_face_t out[6]) {
  rt_light_t mp = s->light[l]; /* an area light's mesh point as a point light */
  const rt_light_t *L = &s->light[l];
  px_vec3_t lambert = px_v3(0, 0, 0), step[2] = {px_v3(0, 0, 0), px_v3(0, 0, 0)};
  if (L->kind == RT_LIGHT_AREA) {
    step[0] = px_v3_scale(L->eu, 1.0 / mesh);
    step[1] = px_v3_scale(L->ev, 1.0 / mesh);
    int i = sub % mesh, j = sub / mesh;
    double a = (i + 0.5) / mesh - 0.5, b = (j + 0.5) / mesh - 0.5;
    mp.kind = RT_LIGHT_POINT;
    mp.v = px_v3_add(L->v, px_v3_add(px_v3_scale(L->eu, a), px_v3_scale(L->ev, b)));
    mp.intensity = rt_rgb_scale(L->intensity, 1.0 / ((double)mesh * mesh));
    lambert = px_v3_unit(px_v3_cross(L->eu, L->ev));
    L = &mp;
  }
  px_vec3_t lo, hi;
  int unbounded;
  targets(s, rc, m, &lo, &hi, &unbounded);
  if (spread && s->light[l].kind == RT_LIGHT_AREA) { /* the mesh cell's other points' rays */
    double g = px_v3_norm(step[0]) + px_v3_norm(step[1]);
    lo = px_v3_sub(lo, px_v3(g, g, g));
    hi = px_v3_add(hi, px_v3(g, g, g));
  }
  px_vec3_t c = px_v3_scale(px_v3_add(lo, hi), 0.5);
  if (L->kind == RT_LIGHT_PARALLEL) {
    lt_face_t f = {1,     c, px_v3(0, 0, 0), px_v3(0, 0, 0), L->v,
                   0,     0, L->intensity,   lambert,        {step[0], step[1]},
                   s->ior};
    frame_of(L->v, &f.x, &f.y);
    double far = 0.0;
    for (int k = 0; k < 8; k++) {
      px_vec3_t p = px_v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      px_vec3_t r = px_v3_sub(p, c);
      f.hx = fmax(f.hx, fabs(px_v3_dot(r, f.x)));
      f.hy = fmax(f.hy, fabs(px_v3_dot(r, f.y)));
      far = fmax(far, fabs(px_v3_dot(r, f.z)));
    }
    double pad = 1e-6 * (f.hx + f.hy) + 1e-12;
    f.hx += pad;
    f.hy += pad;
    f.origin = px_v3_sub(c, px_v3_scale(f.z, 2.0 * far + pad)); /* behind every target */
    out[0] = f;
    return 1;
  }
  /* a point light: one frustum when every corner of the box is within 60 degrees of its centre */
  px_vec3_t z = px_v3_sub(c, L->v);
  double zl = px_v3_norm(z), h = 0.0;
  int frustum = !unbounded && zl > 0;
  if (frustum) {
    z = px_v3_scale(z, 1.0 / zl);
    px_vec3_t x, y;
    frame_of(z, &x, &y);
    for (int k = 0; k < 8 && frustum; k++) {
      px_vec3_t p = px_v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
      px_vec3_t r = px_v3_sub(p, L->v);
      double rz = px_v3_dot(r, z);
      if (!(rz > 0.5 * px_v3_norm(r))) {
        frustum = 0;
        break;
      }
      h = fmax(h, fmax(fabs(px_v3_dot(r, x)), fabs(px_v3_dot(r, y))) / rz);
    }
    if (frustum) {
      out[0] = (lt_face_t){0,
                           L->v,
                           x,
                           y,
                           z,
                           h * (1 + 1e-6),
                           h * (1 + 1e-6),
                           L->intensity,
                           lambert,
                           {step[0], step[1]},
                           rt_medium_ior(s, L->v)};
      return 1;
    }
  }
  static const px_vec3_t axes[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  double ior = rt_medium_ior(s, L->v);
  for (int k = 0; k < 6; k++) {
    lt_face_t f = {0,   L->v,         px_v3(0, 0, 0), px_v3(0, 0, 0),     axes[k], 1.0,
                   1.0, L->intensity, lambert,        {step[0], step[1]}, ior};
    frame_of(axes[k], &f.x, &f.y);
    out[k] = f;
  }
  return 6;
}

double lt__face_weight(const lt_face_t *f, double a, double b) {
  if (f->lambert.x == 0.0 && f->lambert.y == 0.0 && f->lambert.z == 0.0)
    return 1.0;
  px_vec3_t d = px_v3_unit(px_v3_add(f->z, px_v3_add(px_v3_scale(f->x, (2 * a - 1) * f->hx),
                                                     px_v3_scale(f->y, (2 * b - 1) * f->hy))));
  return fmax(0.0, px_v3_dot(d, f->lambert));
}

rt_ray_t lt__face_ray(const lt_face_t *f, double a, double b) {
  double x = (2 * a - 1) * f->hx, y = (2 * b - 1) * f->hy;
  rt_ray_t r = {f->origin, f->z, 0.0, INFINITY, f->ior, -1, 0.0f};
  if (f->parallel)
    r.o = px_v3_add(f->origin, px_v3_add(px_v3_scale(f->x, x), px_v3_scale(f->y, y)));
  else
    r.d = px_v3_unit(px_v3_add(f->z, px_v3_add(px_v3_scale(f->x, x), px_v3_scale(f->y, y))));
  return r;
}

double lt__face_measure(const lt_face_t *f, const double p0[2], const double p1[2],
                        const double p2[2]) {
  const double *p[3] = {p0, p1, p2};
  if (f->parallel) { /* the triangle's area across the beam */
    double ax = 2 * f->hx * (p[1][0] - p[0][0]), ay = 2 * f->hy * (p[1][1] - p[0][1]);
    double bx = 2 * f->hx * (p[2][0] - p[0][0]), by = 2 * f->hy * (p[2][1] - p[0][1]);
    return 0.5 * fabs(ax * by - ay * bx);
  }
  /* the solid angle of the three directions (Van Oosterom and Strackee) */
  px_vec3_t d[3];
  for (int k = 0; k < 3; k++)
    d[k] = px_v3_unit(px_v3_add(f->z, px_v3_add(px_v3_scale(f->x, (2 * p[k][0] - 1) * f->hx),
                                                px_v3_scale(f->y, (2 * p[k][1] - 1) * f->hy))));
  double num = fabs(px_v3_dot(d[0], px_v3_cross(d[1], d[2])));
  double den = 1 + px_v3_dot(d[0], d[1]) + px_v3_dot(d[1], d[2]) + px_v3_dot(d[2], d[0]);
  return 2 * atan2(num, den);
}
