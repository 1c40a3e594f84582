/* scene.c -- building the scene model: materials, spheres, checkered planes, polygons, lights
 * (textbook 9.1; course notes 1.7.1.5, "mapping a pattern": the checkerboard as a function of
 * the plane's coordinates). Polyhedra are in polyhedron.c, the BVH in bvh.c. */
#include "core/scene.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bvh.h"
#include "core/intersect.h"
#include "paraxial/vec3.h"
#include "scene_impl.h"

const char *rt_strerror(rt_status_t s) {
  switch (s) {
  case RT_OK:
    return "success";
  case RT_ENOMEM:
    return "out of memory";
  case RT_EINVAL:
    return "invalid parameter";
  case RT_EGEOMETRY:
    return "degenerate geometry";
  case RT_ENOTREADY:
    return "scene not prepared (call rt_scene_prepare after the last change)";
  case RT_ECAPACITY:
    return "buffer full";
  }
  return "unknown status";
}

rt_material_t rt_material_default(const char *name) {
  rt_material_t m;
  memset(&m, 0, sizeof m);
  if (name)
    snprintf(m.name, sizeof m.name, "%s", name);
  m.color = rt_rgb(1, 1, 1);
  m.ka = 0.1;
  m.kd = 0.9;
  m.ior = 1.0;
  m.index = px_index_constant(1.0);
  m.transmittance = rt_rgb(1, 1, 1);
  return m;
}

void rt_scene_init(rt_scene_t *s) {
  memset(s, 0, sizeof *s);
  s->camera = (rt_camera_t){{0, 0, -5}, {0, 0, 0}, {0, 1, 0}, 40.0, 64, 64};
  s->ambient = rt_rgb(0.1, 0.1, 0.1);
  s->background = rt_rgb(0, 0, 0);
  s->max_depth = 5;
  s->spp = 1;
  s->shadows = 1;
  s->ior = 1.0;
  s->spectral_bins = RT_DEFAULT_BINS;
}

static void drop_accel(rt_scene_t *s) {
  rt_bvh_free(s->bvh);
  s->bvh = NULL;
  free(s->unbounded);
  s->unbounded = NULL;
  s->nunbounded = 0;
}

void rt_scene_free(rt_scene_t *s) {
  drop_accel(s);
  free(s->material);
  free(s->object);
  free(s->prim);
  free(s->vertex);
  free(s->light);
  rt_scene_init(s);
}

/* Grow *arr (of elements of `size` bytes, *cap allocated) to hold `need`; 0 on ENOMEM. */
static int reserve(void **arr, int *cap, int need, size_t size) {
  if (need <= *cap)
    return 1;
  int nc = *cap ? *cap : 8;
  while (nc < need)
    nc *= 2;
  void *p = realloc(*arr, (size_t)nc * size);
  if (!p)
    return 0;
  *arr = p;
  *cap = nc;
  return 1;
}

#define RESERVE(s, arr, n, extra)                                                                  \
  reserve((void **)&(s)->arr, &(s)->cap_##arr, (s)->n + (extra), sizeof *(s)->arr)

rt_status_t rt_scene_add_material(rt_scene_t *s, const rt_material_t *m, int *index) {
  if (!(m->ior > 0.0) || !isfinite(m->ior) || !(m->phong >= 0.0))
    return RT_EINVAL;
  if (!RESERVE(s, material, nmaterial, 1))
    return RT_ENOMEM;
  s->material[s->nmaterial] = *m;
  /* an index that does not vary is the scalar ior, whatever the caller left in the model */
  if (!px_index_disperses(&m->index))
    s->material[s->nmaterial].index = px_index_constant(m->ior);
  if (index)
    *index = s->nmaterial;
  s->nmaterial++;
  return RT_OK;
}

int rt_scene_find_material(const rt_scene_t *s, const char *name) {
  for (int i = 0; i < s->nmaterial; i++)
    if (strcmp(s->material[i].name, name) == 0)
      return i;
  return -1;
}

/* Append an object with `nprim` primitives (reserved, not filled) and return its index. */
rt_status_t rt__scene_new_object(rt_scene_t *s, rt_object_kind_t kind, int material, int nprim,
                                 int *object) {
  if (material < 0 || material >= s->nmaterial)
    return RT_EINVAL;
  if (!RESERVE(s, object, nobject, 1) || !RESERVE(s, prim, nprim, nprim))
    return RT_ENOMEM;
  drop_accel(s);
  rt_object_t *o = &s->object[s->nobject];
  memset(o, 0, sizeof *o);
  o->kind = kind;
  o->material = material;
  o->material2 = -1;
  o->closed = kind == RT_OBJ_SPHERE || kind == RT_OBJ_POLYHEDRON;
  o->first_prim = s->nprim;
  o->nprim = nprim;
  for (int k = 0; k < nprim; k++) {
    memset(&s->prim[s->nprim + k], 0, sizeof s->prim[0]);
    s->prim[s->nprim + k].object = s->nobject;
  }
  s->nprim += nprim;
  *object = s->nobject++;
  return RT_OK;
}

static int vec_finite(px_vec3_t v) {
  return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

rt_status_t rt_scene_add_sphere(rt_scene_t *s, px_vec3_t c, double r, int material, int *object) {
  if (!(r > 0.0) || !isfinite(r) || !vec_finite(c))
    return RT_EINVAL;
  int o;
  rt_status_t st = rt__scene_new_object(s, RT_OBJ_SPHERE, material, 1, &o);
  if (st != RT_OK)
    return st;
  rt_prim_t *p = &s->prim[s->object[o].first_prim];
  p->kind = RT_PRIM_SPHERE;
  p->sphere = (rt_sphere_t){c, r};
  if (object)
    *object = o;
  return RT_OK;
}

rt_status_t rt_scene_add_plane(rt_scene_t *s, px_vec3_t p, px_vec3_t n, px_vec3_t u_hint,
                               int material, int material2, double check, int *object) {
  px_vec3_t nu;
  if (!vec_finite(p) || px_vec3_normalize(n, &nu) != PX_OK || !vec_finite(u_hint) ||
      !(check > 0.0) || !isfinite(1.0 / check) || !isfinite(check) || material2 >= s->nmaterial)
    return RT_EINVAL;
  px_frame_t f; /* z = normal, x2 = u hint projected into the plane */
  if (px_frame_from_z(nu, u_hint, &f) != PX_OK)
    return RT_EINVAL;
  int o;
  rt_status_t st = rt__scene_new_object(s, RT_OBJ_PLANE, material, 1, &o);
  if (st != RT_OK)
    return st;
  s->object[o].material2 = material2 < 0 ? -1 : material2;
  rt_prim_t *pr = &s->prim[s->object[o].first_prim];
  pr->kind = RT_PRIM_PLANE;
  pr->plane = (rt_plane_t){p, nu, f.x2, px_vec3_cross(nu, f.x2), check, 1.0 / check};
  if (object)
    *object = o;
  return RT_OK;
}

rt_status_t rt_scene_add_light(rt_scene_t *s, const rt_light_t *l) {
  rt_light_t c = *l;
  if (!vec_finite(c.v) || !isfinite(c.intensity.r + c.intensity.g + c.intensity.b))
    return RT_EINVAL;
  if (c.kind == RT_LIGHT_PARALLEL && px_vec3_normalize(l->v, &c.v) != PX_OK)
    return RT_EINVAL;
  if (c.kind == RT_LIGHT_AREA) { /* physical by nature: it falls off as the inverse square */
    px_vec3_t n = px_v3_cross(c.eu, c.ev);
    if (!vec_finite(c.eu) || !vec_finite(c.ev) ||
        !(px_v3_norm(n) > 1e-12 * px_v3_norm(c.eu) * px_v3_norm(c.ev)))
      return RT_EINVAL;
    if (c.samples == 0)
      c.samples = RT_AREA_SAMPLES_DEFAULT;
    if (c.samples < 1 || c.samples > RT_MAX_AREA_SAMPLES)
      return RT_EINVAL;
    c.falloff = RT_FALLOFF_INVERSE_SQUARE;
  } else if (c.falloff != RT_FALLOFF_NONE &&
             (c.falloff != RT_FALLOFF_INVERSE_SQUARE || c.kind != RT_LIGHT_POINT)) {
    return RT_EINVAL; /* only a point light falls off */
  } else {
    c.samples = 0;
  }
  if (!RESERVE(s, light, nlight, 1))
    return RT_ENOMEM;
  drop_accel(s);
  s->light[s->nlight++] = c;
  return RT_OK;
}

void rt_scene_name_object(rt_scene_t *s, int object, const char *name) {
  if (object >= 0 && object < s->nobject)
    snprintf(s->object[object].name, sizeof s->object[object].name, "%s", name);
}

void rt_plane_coords(const rt_plane_t *pl, px_vec3_t p, double *u, double *v) {
  px_vec3_t d = px_v3_sub(p, pl->p);
  *u = px_v3_dot(d, pl->u);
  *v = px_v3_dot(d, pl->v);
}

/* Parity of the integer-valued double k, as fmod(fabs(k), 2.0) gives it but without the libm
 * call: below 2^53 the conversion to int64_t is exact; at and above it every double is even. */
static int checker_parity(double k) {
  double a = fabs(k);
  return a < 0x1p53 ? (int)((int64_t)a & 1) : 0;
}

const rt_material_t *rt__scene_checker_at(const rt_scene_t *s, const rt_object_t *o, int prim,
                                          px_vec3_t p, int *texel) {
  const rt_plane_t *pl = &s->prim[prim].plane;
  double u, v;
  rt_plane_coords(pl, p, &u, &v);
  int parity = checker_parity(floor(u * pl->inv_check) + floor(v * pl->inv_check));
  if (texel)
    *texel = parity;
  return &s->material[parity == 1 ? o->material2 : o->material];
}

/* Faces of a polyhedron above which rt_object_t.alone is not looked for: its convexity test is
 * O(faces x vertices), 4 M products at this size (a few ms), and a finer mesh keeps the scene
 * searches of spectral pencils. */
#define ALONE_MAX_FACES 1024

int rt_polyhedron_convex(const rt_scene_t *s, const rt_object_t *o, double size) {
  double e = 1e-9 * size;
  for (int i = o->first_prim; i < o->first_prim + o->nprim; i++) {
    const rt_polygon_t *f = &s->prim[i].polygon;
    for (int j = o->first_prim; j < o->first_prim + o->nprim; j++) {
      const rt_polygon_t *g = &s->prim[j].polygon;
      for (int k = 0; k < g->count; k++)
        if (px_v3_dot(f->n, s->vertex[g->first + k]) - f->d > e)
          return 0;
    }
  }
  return 1;
}

static int box_meets(const double lo[3], const double hi[3], px_vec3_t a, px_vec3_t b) {
  return a.x <= hi[0] && b.x >= lo[0] && a.y <= hi[1] && b.y >= lo[1] && a.z <= hi[2] &&
         b.z >= lo[2];
}

/* alone()'s test of one primitive of the BVH: another object's whose box meets the object's. */
typedef struct {
  const rt_scene_t *s;
  const rt_object_t *ob;
  double lo[3], hi[3];
} other_t;

static int other_meets(void *ctx, int q) {
  const other_t *o = ctx;
  px_vec3_t a, b;
  if (q >= o->ob->first_prim && q < o->ob->first_prim + o->ob->nprim)
    return 0;
  return !rt_prim_bounds(o->s, q, &a, &b) || box_meets(o->lo, o->hi, a, b);
}

/* rt_object_t.alone of object o, once the BVH is built: its box against the BVH's leaves and
 * the unbounded planes. */
static int alone(const rt_scene_t *s, int o) {
  const rt_object_t *ob = &s->object[o];
  if (!ob->closed || ob->nprim < 1 ||
      !(ob->kind == RT_OBJ_SPHERE ||
        (ob->kind == RT_OBJ_POLYHEDRON && ob->nprim <= ALONE_MAX_FACES)))
    return 0;
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = ob->first_prim; i < ob->first_prim + ob->nprim; i++) {
    px_vec3_t a, b;
    if (!rt_prim_bounds(s, i, &a, &b))
      return 0;
    for (int k = 0; k < 3; k++) {
      lo[k] = fmin(lo[k], px_v3_at(a, k));
      hi[k] = fmax(hi[k], px_v3_at(b, k));
    }
  }
  double size = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
  if (ob->kind == RT_OBJ_POLYHEDRON && !rt_polyhedron_convex(s, ob, size))
    return 0;
  for (int u = 0; u < s->nunbounded; u++) { /* planes: the box's corners on one side, strictly */
    int q = s->unbounded[u];
    if (s->prim[q].kind != RT_PRIM_PLANE)
      return 0;
    const rt_plane_t *pl = &s->prim[q].plane;
    int pos = 0, neg = 0;
    for (int c = 0; c < 8; c++) {
      px_vec3_t v = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
      double d = px_v3_dot(pl->n, px_v3_sub(v, pl->p));
      pos |= d >= 0.0;
      neg |= d <= 0.0;
    }
    if (pos && neg)
      return 0;
  }
  other_t q = {s, ob, {lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  return rt_bvh_box_query(s->bvh, lo, hi, other_meets, &q) < 0;
}

rt_status_t rt_scene_prepare(rt_scene_t *s) {
  const rt_camera_t *c = &s->camera;
  if (!(c->fov_deg > 0.0 && c->fov_deg < 180.0) || c->width < 1 || c->height < 1 ||
      s->max_depth < 0 || s->max_depth > 64 || s->spp < 1 || s->spp > RT_MAX_SPP || !(s->ior > 0.0))
    return RT_EINVAL;
  int side = (int)lrint(sqrt((double)s->spp));
  if (side * side != s->spp) /* s x s sub-pixel grids only */
    return RT_EINVAL;
  drop_accel(s);
  rt_status_t st = rt_bvh_build(s, &s->bvh, &s->unbounded, &s->nunbounded);
  for (int o = 0; o < s->nobject; o++)
    s->object[o].alone = st == RT_OK && alone(s, o);
  return st;
}

int rt_scene_bounds(const rt_scene_t *s, double lo[3], double hi[3]) {
  if (!s->bvh || s->bvh->nnode == 0)
    return 0;
  for (int a = 0; a < 3; a++) {
    lo[a] = s->bvh->node[0].lo[a];
    hi[a] = s->bvh->node[0].hi[a];
  }
  return 1;
}

/* The parameters t in [*t0, *t1] where p + q t <= 0 (narrowing them). */
static void where_nonpositive(double p, double q, double *t0, double *t1) {
  if (q > 0.0)
    *t1 = fmin(*t1, -p / q);
  else if (q < 0.0)
    *t0 = fmax(*t0, -p / q);
  else if (p > 0.0)
    *t0 = INFINITY; /* never */
}

/* Whether the box swept from `from` to `to` (rt_sweep_meets_others()) meets the box [a, b]: on
 * each axis its bounds lo(t), hi(t) are linear in t, and it meets where lo(t) <= b and
 * hi(t) >= a on every axis for one t. */
static int sweep_meets_box(const double from[6], const double to[6], px_vec3_t a, px_vec3_t b) {
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 3; k++) {
    where_nonpositive(from[k] - px_v3_at(b, k), to[k] - from[k], &t0, &t1);
    where_nonpositive(px_v3_at(a, k) - from[3 + k], -(to[3 + k] - from[3 + k]), &t0, &t1);
  }
  return t0 <= t1;
}

/* Whether the swept box meets the plane through p with normal n: the smallest and the largest
 * n.x - n.p over the box at t are linear in t; it meets where the one is <= 0 <= the other. */
static int sweep_meets_plane(const double from[6], const double to[6], px_vec3_t n, px_vec3_t p) {
  double m0 = -px_v3_dot(n, p), m1 = m0, M0 = m0, M1 = m0;
  for (int k = 0; k < 3; k++) {
    double nk = px_v3_at(n, k);
    int lo = nk >= 0.0 ? k : 3 + k, hi = nk >= 0.0 ? 3 + k : k; /* where n.x is least, most */
    m0 += nk * from[lo];
    m1 += nk * to[lo];
    M0 += nk * from[hi];
    M1 += nk * to[hi];
  }
  double t0 = 0.0, t1 = 1.0;
  where_nonpositive(m0, m1 - m0, &t0, &t1);
  where_nonpositive(-M0, -(M1 - M0), &t0, &t1);
  return t0 <= t1;
}

/* rt_sweep_meets_others()'s test of one primitive of the BVH. */
typedef struct {
  const rt_scene_t *s;
  const double *from, *to;
  const int *skip;
  int nskip;
} others_t;

/* Whether q is listed, or a primitive of a listed primitive's object when that object is alone
 * (rt_object_t.alone). */
static int skipped(const rt_scene_t *s, const int *skip, int nskip, int q) {
  int oq = s->prim[q].object;
  for (int i = 0; i < nskip; i++)
    if (skip[i] == q || (s->prim[skip[i]].object == oq && s->object[oq].alone))
      return 1;
  return 0;
}

static int others_meet(void *ctx, int q) {
  const others_t *o = ctx;
  px_vec3_t a, b;
  if (skipped(o->s, o->skip, o->nskip, q))
    return 0;
  return !rt_prim_bounds(o->s, q, &a, &b) || sweep_meets_box(o->from, o->to, a, b);
}

int rt_sweep_meets_others(const rt_scene_t *s, const double from[6], const double to[6],
                          const int *skip, int nskip) {
  double lo[3], hi[3]; /* the swept box's bounds: its ends' */
  for (int a = 0; a < 3; a++) {
    if (!(from[a] <= from[3 + a]) || !(to[a] <= to[3 + a]))
      return 1; /* NaN or an empty box: nothing known */
    lo[a] = fmin(from[a], to[a]);
    hi[a] = fmax(from[3 + a], to[3 + a]);
  }
  for (int u = 0; u < s->nunbounded; u++) {
    int q = s->unbounded[u];
    if (skipped(s, skip, nskip, q))
      continue;
    if (s->prim[q].kind != RT_PRIM_PLANE ||
        sweep_meets_plane(from, to, s->prim[q].plane.n, s->prim[q].plane.p))
      return 1;
  }
  others_t o = {s, from, to, skip, nskip};
  return rt_bvh_box_query(s->bvh, lo, hi, others_meet, &o) >= 0;
}
