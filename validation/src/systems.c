/* systems.c -- the verification sweep (issue: incidence 0 .. within 0.1 deg of grazing and of
 * the critical angle; n1/n2 both ways; radii 1e-3 .. 1e3 of both signs; planes; cylinders and
 * ellipsoids with rotated frames; reflections; cascades). Deterministic: GSL's mt19937 with a
 * fixed seed. */
#include "validation/systems.h"

#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *family_names[VAL_FAMILY_COUNT] = {"transfer", "plane",     "sphere",
                                                     "cylinder", "ellipsoid", "cascade"};

const char *val_family_name(val_family_t f) {
  return f < VAL_FAMILY_COUNT ? family_names[f] : "?";
}

ex_system_t val_system_bind(const val_system_t *v) {
  ex_system_t s = v->sys;
  s.stage = v->stage;
  return s;
}

typedef struct {
  val_system_t *v;
  size_t n, cap;
  gsl_rng *rng;
} sweep_t;

static val_system_t *add(sweep_t *w) {
  if (w->n == w->cap) {
    size_t cap = w->cap ? 2 * w->cap : 1024;
    val_system_t *p = realloc(w->v, cap * sizeof *p);
    if (!p)
      return NULL;
    w->v = p;
    w->cap = cap;
  }
  val_system_t *v = &w->v[w->n++];
  memset(v, 0, sizeof *v);
  v->radius = INFINITY;
  return v;
}

static double uniform(sweep_t *w, double a, double b) {
  return a + (b - a) * gsl_rng_uniform(w->rng);
}

/* Incident frame for direction s at a surface of normal nu: x2 = normal of the plane of
 * incidence (the paper's frame), or that frame rotated by a random angle. */
static px_frame_t incident_frame(sweep_t *w, px_vec3_t s, px_vec3_t nu, int rotated) {
  px_frame_t f;
  px_frame_from_z(s, px_vec3_cross(nu, s), &f);
  return rotated ? px_frame_rotate(f, uniform(w, -M_PI, M_PI)) : f;
}

/* One refraction or reflection at O = 0 on `surface` with normal +z there (pointing along the
 * incident light), incidence theta in the plane at azimuth `az`. */
static void single(sweep_t *w, val_system_t *v, ex_quadric_t surface, double az) {
  double th = v->theta_deg * M_PI / 180.0;
  px_vec3_t nu = px_vec3(0, 0, 1);
  px_vec3_t s = px_vec3(sin(th) * cos(az), sin(th) * sin(az), cos(th));
  v->stage[0] = (ex_stage_t){surface, v->event, v->n2, 1};
  v->sys = (ex_system_t){px_vec3(0, 0, 0),
                         incident_frame(w, s, nu, v->rotated),
                         v->n1,
                         NULL,
                         1,
                         0.0,
                         v->rotated ? uniform(w, -M_PI, M_PI) : 0.0};
  if (v->event == PX_EVENT_REFRACT)
    v->expect_tir = (v->n1 / v->n2) * sin(th) > 1.0;
}

static const double index_pairs[][2] = {{1.0, 1.5},  {1.5, 1.0},  {1.0, 1.33}, {1.33, 1.0},
                                        {1.0, 2.42}, {2.42, 1.0}, {1.33, 1.5}, {1.5, 1.33}};
enum { NPAIRS = sizeof index_pairs / sizeof index_pairs[0] };

/* incidence angles: 0 .. 89.99 deg, and near the critical angle when there is one */
static size_t angles(double n1, double n2, double *out) {
  static const double base[] = {0.0,  1e-6, 5.0,  15.0, 30.0, 45.0,
                                60.0, 75.0, 85.0, 89.0, 89.9, 89.99};
  size_t k = 0;
  for (size_t i = 0; i < sizeof base / sizeof base[0]; i++)
    out[k++] = base[i];
  if (n1 > n2) {
    double c = asin(n2 / n1) * 180.0 / M_PI;
    out[k++] = c - 0.1;
    out[k++] = c - 0.01;
    out[k++] = c - 0.001;
    out[k++] = c + 0.1; /* beyond: total internal reflection, no matrix */
  }
  return k;
}

static const double radii[] = {1e-3, 1e-1, 1.0, 1e1, 1e3};

/* Surface number r of the single-element families through O = 0 with normal +z: r = -1 is the
 * plane z = 0, r >= 0 the sphere of radius +-radii[r / 2] (odd r negative), centre (0, 0, R). */
static ex_quadric_t plane_or_sphere(val_system_t *v, int r) {
  if (r < 0) {
    v->family = VAL_FAMILY_PLANE;
    v->length = 1.0;
    return ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 0, 1));
  }
  double R = radii[r / 2] * (r % 2 ? -1.0 : 1.0);
  v->family = VAL_FAMILY_SPHERE;
  v->radius = R;
  v->length = fabs(R);
  return ex_quadric_sphere(px_vec3(0, 0, R), fabs(R));
}

static int add_spheres_and_planes(sweep_t *w, int quick) {
  double th[20];
  for (int p = 0; p < NPAIRS; p++) {
    if (quick && p > 1)
      break;
    double n1 = index_pairs[p][0], n2 = index_pairs[p][1];
    size_t na = angles(n1, n2, th);
    for (size_t a = 0; a < na; a++)
      for (int r = -1; r < (int)(2 * (sizeof radii / sizeof radii[0])); r++)
        for (int rot = 0; rot < 2; rot++) {
          if (quick && ((r + 1) % 3 != 0 || a % 3 != 0))
            continue;
          val_system_t *v = add(w);
          if (!v)
            return -1;
          v->event = PX_EVENT_REFRACT;
          v->theta_deg = th[a];
          v->n1 = n1;
          v->n2 = n2;
          v->rotated = rot;
          single(w, v, plane_or_sphere(v, r), rot ? uniform(w, 0, 2 * M_PI) : 0.0);
          snprintf(v->label, sizeof v->label, "refract %s n %.3g->%.3g theta %.6g R %.3g%s",
                   val_family_name(v->family), n1, n2, th[a], v->radius, rot ? " rotated" : "");
        }
  }
  return 0;
}

static int add_mirrors(sweep_t *w, int quick) {
  static const double th[] = {0.0, 10.0, 30.0, 45.0, 60.0, 80.0, 89.0, 89.9};
  for (size_t a = 0; a < sizeof th / sizeof th[0]; a++)
    for (int r = -1; r < (int)(2 * (sizeof radii / sizeof radii[0])); r++)
      for (int rot = 0; rot < 2; rot++) {
        if (quick && (a % 2 || r % 2))
          continue;
        val_system_t *v = add(w);
        if (!v)
          return -1;
        v->event = PX_EVENT_REFLECT;
        v->theta_deg = th[a];
        v->n1 = v->n2 = 1.0;
        v->rotated = rot;
        single(w, v, plane_or_sphere(v, r), rot ? uniform(w, 0, 2 * M_PI) : 0.0);
        snprintf(v->label, sizeof v->label, "reflect %s theta %.6g R %.3g%s",
                 val_family_name(v->family), th[a], v->radius, rot ? " rotated" : "");
      }
  return 0;
}

/* Cylinders with the axis at a random angle in the tangent plane: Q not diagonal in (u1, u2). */
static int add_cylinders(sweep_t *w, int count) {
  for (int i = 0; i < count; i++) {
    val_system_t *v = add(w);
    if (!v)
      return -1;
    const double *pair = index_pairs[i % NPAIRS];
    v->family = VAL_FAMILY_CYLINDER;
    v->event = i % 4 == 3 ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
    v->n1 = pair[0];
    v->n2 = v->event == PX_EVENT_REFLECT ? pair[0] : pair[1];
    double crit = v->n1 > v->n2 ? asin(v->n2 / v->n1) * 180 / M_PI - 0.1 : 89.9;
    v->theta_deg = uniform(w, 0.0, crit);
    double R = pow(10.0, uniform(w, -3, 3)) * (i % 2 ? -1.0 : 1.0);
    v->radius = R;
    v->length = fabs(R);
    v->rotated = i % 3 != 0;
    double beta = uniform(w, 0, M_PI);
    ex_quadric_t q =
        ex_quadric_cylinder(px_vec3(0, 0, R), px_vec3(cos(beta), sin(beta), 0), fabs(R));
    single(w, v, q, uniform(w, 0, 2 * M_PI));
    snprintf(v->label, sizeof v->label, "%s cylinder n %.3g->%.3g theta %.4f R %.3g axis %.1f deg",
             v->event == PX_EVENT_REFLECT ? "reflect" : "refract", v->n1, v->n2, v->theta_deg, R,
             beta * 180 / M_PI);
  }
  return 0;
}

/* Ellipsoids at a random point, entered from outside or left from inside: general Q and
 * non-zero third derivatives. */
static int add_ellipsoids(sweep_t *w, int count) {
  for (int i = 0; i < count; i++) {
    val_system_t *v = add(w);
    if (!v)
      return -1;
    const double *pair = index_pairs[i % NPAIRS];
    v->family = VAL_FAMILY_ELLIPSOID;
    v->event = i % 5 == 4 ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
    v->n1 = pair[0];
    v->n2 = v->event == PX_EVENT_REFLECT ? pair[0] : pair[1];
    double scale = pow(10.0, uniform(w, -2, 2));
    double ax[3] = {scale * uniform(w, 0.3, 3), scale * uniform(w, 0.3, 3),
                    scale * uniform(w, 0.3, 3)};
    const px_vec3_t axes[3] = {px_vec3(1, 0, 0), px_vec3(0, 1, 0), px_vec3(0, 0, 1)};
    ex_quadric_t q = ex_quadric_ellipsoid(px_vec3(0, 0, 0), axes, ax[0], ax[1], ax[2]);
    double u = uniform(w, 0, 2 * M_PI), c = uniform(w, -0.95, 0.95), sn = sqrt(1 - c * c);
    px_vec3_t o = px_vec3(ax[0] * sn * cos(u), ax[1] * sn * sin(u), ax[2] * c);
    px_vec3_t outward;
    px_vec3_normalize(ex_quadric_half_gradient(&q, o), &outward);
    int from_inside = i % 2;
    px_vec3_t nu = from_inside ? outward : px_vec3_scale(outward, -1.0);
    double crit = v->n1 > v->n2 && v->event == PX_EVENT_REFRACT
                      ? asin(v->n2 / v->n1) * 180 / M_PI - 0.1
                      : 89.9;
    v->theta_deg = uniform(w, 0.0, crit);
    double th = v->theta_deg * M_PI / 180.0;
    px_frame_t b;
    px_frame_from_z(nu, px_vec3(uniform(w, -1, 1), uniform(w, -1, 1), uniform(w, -1, 1)), &b);
    px_vec3_t s = px_vec3_add(px_vec3_scale(nu, cos(th)), px_vec3_scale(b.x1, sin(th)));
    v->rotated = i % 3 != 0;
    v->length = fmin(ax[0], fmin(ax[1], ax[2]));
    v->stage[0] = (ex_stage_t){q, v->event, v->n2, 1};
    v->sys = (ex_system_t){o,   incident_frame(w, s, nu, v->rotated),      v->n1, NULL, 1,
                           0.0, v->rotated ? uniform(w, -M_PI, M_PI) : 0.0};
    snprintf(v->label, sizeof v->label,
             "%s ellipsoid %s n %.3g->%.3g theta %.4f axes %.3g %.3g %.3g",
             v->event == PX_EVENT_REFLECT ? "reflect" : "refract",
             from_inside ? "from inside" : "from outside", v->n1, v->n2, v->theta_deg, ax[0], ax[1],
             ax[2]);
  }
  return 0;
}

/* pinhole -> glass sphere (in and out, optionally one internal reflection) -> plane */
static int add_cascades(sweep_t *w, int count) {
  for (int i = 0; i < count; i++) {
    val_system_t *v = add(w);
    if (!v)
      return -1;
    v->family = VAL_FAMILY_CASCADE;
    double r = pow(10.0, uniform(w, -1, 1));
    double n = (double[]){1.33, 1.5, 2.42}[i % 3];
    double dist = r * uniform(w, 2, 10);
    double impact = uniform(w, 0.0, 0.9) * r; /* aim: impact parameter on the sphere */
    int internal = i % 4 == 3;
    px_vec3_t pin = px_vec3(0, 0, -dist);
    px_vec3_t aim = px_vec3(impact, 0, 0);
    px_vec3_t dir;
    px_vec3_normalize(px_vec3_sub(aim, pin), &dir);
    ex_quadric_t sph = ex_quadric_sphere(px_vec3(0, 0, 0), r);
    size_t k = 0;
    v->stage[k++] = (ex_stage_t){sph, PX_EVENT_REFRACT, n, 0};
    if (internal)
      v->stage[k++] = (ex_stage_t){sph, PX_EVENT_REFLECT, n, 0};
    v->stage[k++] = (ex_stage_t){sph, PX_EVENT_REFRACT, 1.0, 0};
    double floor_dist = r * uniform(w, 1.5, 6);
    v->rotated = i % 2;
    px_frame_t f;
    px_frame_from_z(dir, px_vec3(0, 1, 0), &f);
    if (v->rotated)
      f = px_frame_rotate(f, uniform(w, -M_PI, M_PI));
    v->sys = (ex_system_t){pin, f, 1.0, NULL, k, floor_dist, 0.0};
    v->length = r;
    v->n1 = 1.0;
    v->n2 = n;
    v->radius = r;
    snprintf(v->label, sizeof v->label,
             "pinhole -> sphere n %.3g R %.3g impact %.3f%s -> plane at %.3g%s", n, r, impact / r,
             internal ? " (internal reflection)" : "", floor_dist, v->rotated ? " rotated" : "");
  }
  return 0;
}

static int add_transfers(sweep_t *w) {
  static const double d[] = {1e-3, 1.0, 1e3, -2.0};
  for (size_t i = 0; i < sizeof d / sizeof d[0]; i++) {
    val_system_t *v = add(w);
    if (!v)
      return -1;
    v->family = VAL_FAMILY_TRANSFER;
    v->n1 = v->n2 = 1.0;
    v->length = fabs(d[i]);
    px_frame_t f;
    px_frame_from_z(px_vec3(0.3, -0.2, 1), px_vec3(0, 1, 0), &f);
    v->sys = (ex_system_t){px_vec3(1, 2, 3), f, 1.0, NULL, 0, d[i], 0.0};
    snprintf(v->label, sizeof v->label, "transfer %.3g", d[i]);
  }
  return 0;
}

val_system_t *val_sweep_build(int scale, int quick, size_t *count) {
  sweep_t w = {NULL, 0, 0, gsl_rng_alloc(gsl_rng_mt19937)};
  if (!w.rng)
    return NULL;
  gsl_rng_set(w.rng, 19870727u);
  if (scale < 1)
    scale = 1;
  int ncyl = quick ? 24 : 240 * scale, nell = quick ? 24 : 240 * scale;
  int ncas = quick ? 16 : 160 * scale;
  int err = add_transfers(&w) || add_spheres_and_planes(&w, quick) || add_mirrors(&w, quick) ||
            add_cylinders(&w, ncyl) || add_ellipsoids(&w, nell) || add_cascades(&w, ncas);
  gsl_rng_free(w.rng);
  if (err) {
    free(w.v);
    return NULL;
  }
  *count = w.n;
  return w.v;
}
