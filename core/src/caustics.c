/* caustics.c -- the receivers and lights of caustic maps, and lookups in the maps (caustics.h). */
#include "core/caustics.h"

#include <math.h>
#include <stdlib.h>

#include "paraxial/vec3.h"

static int carries(const rt_scene_t *s, int o) { /* reflects or transmits some light */
  const rt_object_t *ob = &s->object[o];
  const rt_material_t *a = &s->material[ob->material];
  const rt_material_t *b = ob->material2 >= 0 ? &s->material[ob->material2] : a;
  return a->kr > 0.0 || a->kt > 0.0 || b->kr > 0.0 || b->kt > 0.0;
}

static int diffuse(const rt_scene_t *s, int o) {
  const rt_object_t *ob = &s->object[o];
  return s->material[ob->material].kd > 0.0 ||
         (ob->material2 >= 0 && s->material[ob->material2].kd > 0.0);
}

/* The plane n . x = d of a plane or polygon object. */
static void plane_of(const rt_scene_t *s, int o, px_vec3_t *n, double *d) {
  const rt_prim_t *p = &s->prim[s->object[o].first_prim];
  if (p->kind == RT_PRIM_PLANE) {
    *n = p->plane.n;
    *d = px_v3_dot(p->plane.n, p->plane.p);
  } else {
    *n = p->polygon.n;
    *d = p->polygon.d;
  }
}

/* Whether objects a and b lie in one plane: parallel normals and offsets within 1e-10 of the
 * larger offset (or of 1), tighter than the receiver's own test (light/, 1e-9 of the scene). */
static int coplanar(const rt_scene_t *s, int a, int b) {
  px_vec3_t na, nb;
  double da, db;
  plane_of(s, a, &na, &da);
  plane_of(s, b, &nb, &db);
  double c = px_v3_dot(na, nb);
  if (!(fabs(c) >= 1.0 - 1e-12))
    return 0;
  db = c > 0 ? db : -db;
  return fabs(da - db) <= 1e-10 * fmax(1.0, fmax(fabs(da), fabs(db)));
}

int rt_caustic_plan(const rt_scene_t *s, rt_caustic_plan_t *cp) {
  cp->nplane = 0;
  cp->lights = 0;
  cp->via = cp->unmapped = cp->unphysical = -1;
  cp->nunmapped = 0;
  if (s->nlight == 0 || s->max_depth == 0)
    return 0;
  for (int o = 0; o < s->nobject && cp->via < 0; o++)
    if (carries(s, o))
      cp->via = o;
  if (cp->via < 0)
    return 0;
  for (int l = 0; l < s->nlight && l < 32; l++) {
    const rt_light_t *li = &s->light[l];
    if (li->kind == RT_LIGHT_PARALLEL || li->falloff == RT_FALLOFF_INVERSE_SQUARE)
      cp->lights |= 1u << l;
    else if (cp->unphysical < 0)
      cp->unphysical = l;
  }
  for (int o = 0; o < s->nobject; o++) {
    if (!diffuse(s, o))
      continue;
    int kind = s->object[o].kind;
    int g = -1;
    if (kind == RT_OBJ_PLANE || kind == RT_OBJ_POLYGON) {
      for (int k = 0; k < cp->nplane && g < 0; k++)
        if (cp->nobject[k] < RT_CAUSTIC_MAX_JOIN && coplanar(s, cp->object[k][0], o))
          g = k;
      if (g < 0 && cp->nplane < RT_CAUSTIC_MAX_PLANES) {
        g = cp->nplane++;
        cp->nobject[g] = 0;
      }
    }
    if (g < 0) { /* a sphere or a polyhedron, or no room */
      if (cp->unmapped < 0)
        cp->unmapped = o;
      cp->nunmapped++;
      continue;
    }
    cp->object[g][cp->nobject[g]++] = o;
  }
  if (cp->lights == 0)
    return 0;
  return cp->nplane * __builtin_popcount(cp->lights);
}

void rt_caustic_maps_free(rt_caustic_maps_t *m) {
  if (!m)
    return;
  for (int k = 0; k < m->n; k++)
    free(m->map[k].e);
  free(m->map);
  free(m->plane);
  free(m->index);
  m->map = NULL;
  m->plane = m->index = NULL;
  m->n = 0;
}

rt_rgb_t rt_caustic_at(const rt_caustic_map_t *c, px_vec3_t p) {
  px_vec3_t q = px_v3_sub(p, c->p);
  double x = (px_v3_dot(q, c->u) - c->u0) / c->du, y = (px_v3_dot(q, c->v) - c->v0) / c->dv;
  if (!c->e || !(x >= 0.0 && x <= c->width && y >= 0.0 && y <= c->height))
    return rt_rgb(0, 0, 0); /* an empty map, outside the map (or NaN) */
  /* bilinear between centres: i0 <= x - 1/2 < i0 + 1, clamped at the outer half cells */
  x -= 0.5;
  y -= 0.5;
  int i0 = (int)floor(x), j0 = (int)floor(y);
  double fx = x - i0, fy = y - j0;
  int i1 = i0 + 1, j1 = j0 + 1;
  if (i0 < 0)
    i0 = 0, fx = 0.0;
  if (i1 > c->width - 1)
    i1 = c->width - 1;
  if (j0 < 0)
    j0 = 0, fy = 0.0;
  if (j1 > c->height - 1)
    j1 = c->height - 1;
  const double *a = c->e + 3 * ((size_t)j0 * c->width + i0),
               *b = c->e + 3 * ((size_t)j0 * c->width + i1);
  const double *d = c->e + 3 * ((size_t)j1 * c->width + i0),
               *e = c->e + 3 * ((size_t)j1 * c->width + i1);
  double out[3];
  for (int k = 0; k < 3; k++)
    out[k] = (1.0 - fy) * ((1.0 - fx) * a[k] + fx * b[k]) + fy * ((1.0 - fx) * d[k] + fx * e[k]);
  return rt_rgb(out[0], out[1], out[2]);
}

double rt_caustic_range(const rt_caustic_map_t *c, double ulo, double uhi, double vlo, double vhi,
                        double *lo) {
  /* cells whose centres' interpolation can reach the box: one more on each side */
  double x0 = floor((ulo - c->u0) / c->du - 0.5), x1 = ceil((uhi - c->u0) / c->du - 0.5);
  double y0 = floor((vlo - c->v0) / c->dv - 0.5), y1 = ceil((vhi - c->v0) / c->dv - 0.5);
  *lo = 0.0;
  if (!c->e || !(x1 >= 0.0 && x0 <= c->width - 1 && y1 >= 0.0 && y0 <= c->height - 1))
    return 0.0;
  int i0 = x0 < 0 ? 0 : (int)x0, i1 = x1 > c->width - 1 ? c->width - 1 : (int)x1;
  int j0 = y0 < 0 ? 0 : (int)y0, j1 = y1 > c->height - 1 ? c->height - 1 : (int)y1;
  /* a box reaching beyond the map also sees the black outside */
  double hi = 0.0,
         mn = (x0 < 0 || x1 > c->width - 1 || y0 < 0 || y1 > c->height - 1) ? 0.0 : INFINITY;
  for (int j = j0; j <= j1; j++)
    for (int i = i0; i <= i1; i++)
      for (int k = 0; k < 3; k++) {
        double v = c->e[3 * ((size_t)j * c->width + i) + k];
        hi = fmax(hi, v);
        mn = fmin(mn, v);
      }
  *lo = isfinite(mn) ? mn : 0.0;
  return hi;
}
