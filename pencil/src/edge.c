/* edge.c -- the smoothness condition (paper section 4.1 (1), step 3): ray-tree comparison without
 * checker squares, and the cone guard against small objects vanishing (the paper's suggestion:
 * "estimating the distances between an axial ray and object surfaces, as in ... ray tracing with
 * cones"; here with bounding spheres). */
#include "pencil/edge.h"

#include <math.h>

#include "core/intersect.h"
#include "paraxial/vec3.h"

static pt_cnode_t compact(const rt_tree_node_t *a) {
  return (pt_cnode_t){a->parent, a->object, a->prim, a->lit, a->blocked, a->kind, a->flags};
}

static int same(const pt_cnode_t *a, const pt_cnode_t *b) {
  return a->parent == b->parent && a->kind == b->kind && a->flags == b->flags &&
         a->object == b->object && a->prim == b->prim && a->lit == b->lit &&
         a->blocked == b->blocked;
}

void pt_ctree_from(pt_ctree_t *c, const rt_tree_t *t) {
  c->valid = !t->overflow && t->n <= c->cap;
  c->n = c->valid ? t->n : 0;
  for (int k = 0; k < c->n; k++)
    c->node[k] = compact(&t->node[k]);
}

int pt_tree_same_paths(const rt_tree_t *a, const rt_tree_t *b) {
  if (a->n != b->n || a->overflow || b->overflow)
    return 0;
  for (int k = 0; k < a->n; k++) {
    pt_cnode_t x = compact(&a->node[k]), y = compact(&b->node[k]);
    if (!same(&x, &y))
      return 0;
  }
  return 1;
}

int pt_ctree_same(const rt_tree_t *a, const pt_ctree_t *b) {
  if (!b->valid || a->overflow || a->n != b->n)
    return 0;
  for (int k = 0; k < a->n; k++) {
    pt_cnode_t x = compact(&a->node[k]);
    if (!same(&x, &b->node[k]))
      return 0;
  }
  return 1;
}

int pt_ctree_same_root(const pt_ctree_t *a, const pt_ctree_t *b) {
  if (!a->valid || !b->valid || (a->n == 0) != (b->n == 0))
    return 0;
  return a->n == 0 || (a->node[0].object == b->node[0].object &&
                       a->node[0].prim == b->node[0].prim && a->node[0].flags == b->node[0].flags);
}

/* The child of node m of c whose ray is of `kind`, or -1. */
static int child_of(const pt_ctree_t *c, int m, int kind) {
  for (int j = m + 1; j < c->n; j++)
    if (c->node[j].parent == m && c->node[j].kind == kind)
      return j;
  return -1;
}

int pt_tree_agree(const rt_tree_t *a, const pt_ctree_t *const *c, int nc, int *map, uint8_t *agree,
                  uint32_t *light) {
  int all = !a->overflow;
  for (int i = 0; i < nc; i++)
    all = all && c[i]->valid && c[i]->n == a->n;
  for (int k = 0; k < a->n; k++) {
    const rt_tree_node_t *x = &a->node[k];
    int p = x->parent, ok = !a->overflow && (p < 0 || agree[p]);
    uint32_t lt = ~0u;
    for (int i = 0; i < nc && ok; i++) {
      int m = !c[i]->valid || c[i]->n == 0 ? -1
              : p < 0                      ? 0
                                           : child_of(c[i], map[i * a->n + p], x->kind);
      map[i * a->n + k] = m;
      const pt_cnode_t *y = m >= 0 ? &c[i]->node[m] : NULL;
      ok = y && y->object == x->object && y->prim == x->prim && y->flags == x->flags;
      if (ok)
        lt &= ~((y->lit ^ x->lit) | (y->blocked ^ x->blocked));
    }
    agree[k] = (uint8_t)ok;
    light[k] = ok ? lt : 0u;
    all = all && ok && lt == ~0u;
  }
  return all;
}

int pt_guard_spheres(const rt_scene_t *s, pt_bsphere_t *out, int cap) {
  int n = 0;
  for (int o = 0; o < s->nobject && n < cap; o++) {
    const rt_object_t *ob = &s->object[o];
    if (ob->kind == RT_OBJ_PLANE)
      continue;
    if (ob->kind == RT_OBJ_SPHERE) {
      const rt_sphere_t *sp = &s->prim[ob->first_prim].sphere;
      out[n++] = (pt_bsphere_t){sp->c, sp->r, o};
      continue;
    }
    px_vec3_t lo = px_v3(INFINITY, INFINITY, INFINITY), hi = px_v3(-INFINITY, -INFINITY, -INFINITY);
    for (int p = ob->first_prim; p < ob->first_prim + ob->nprim; p++) {
      px_vec3_t a, b;
      if (!rt_prim_bounds(s, p, &a, &b))
        continue;
      lo = px_v3(fmin(lo.x, a.x), fmin(lo.y, a.y), fmin(lo.z, a.z));
      hi = px_v3(fmax(hi.x, b.x), fmax(hi.y, b.y), fmax(hi.z, b.z));
    }
    if (!(lo.x <= hi.x))
      continue;
    px_vec3_t c = px_v3_scale(px_v3_add(lo, hi), 0.5);
    out[n++] = (pt_bsphere_t){c, 0.5 * px_v3_norm(px_v3_sub(hi, lo)), o};
  }
  return n;
}

int pt_guard_fires(const pt_bsphere_t *b, int n, px_vec3_t eye, px_vec3_t axis, double half) {
  for (int i = 0; i < n; i++) {
    px_vec3_t v = px_v3_sub(b[i].c, eye);
    double dist = px_v3_norm(v);
    if (dist <= b[i].r)
      continue; /* the eye is inside: the object surrounds every cone */
    double gamma = asin(b[i].r / dist);
    double ang = acos(fmax(-1.0, fmin(1.0, px_v3_dot(v, axis) / dist)));
    if (ang < gamma + half && ang + half > gamma)
      return 1; /* intersects the cone without containing it */
  }
  return 0;
}

int pt_guard_segment(const pt_bsphere_t *b, int n, px_vec3_t p, px_vec3_t q, double r, int skip_a,
                     int skip_b) {
  px_vec3_t pq = px_v3_sub(q, p);
  double len2 = px_v3_dot(pq, pq);
  for (int i = 0; i < n; i++) {
    if (b[i].object == skip_a || b[i].object == skip_b)
      continue;
    px_vec3_t v = px_v3_sub(b[i].c, p);
    double t = len2 > 0.0 ? fmax(0.0, fmin(1.0, px_v3_dot(v, pq) / len2)) : 0.0;
    double dist =
        px_v3_norm(px_v3_sub(v, px_v3_scale(pq, t))); /* centre to the nearest segment point */
    if (!(dist > b[i].r + r))                         /* a NaN radius fires */
      return 1;
  }
  return 0;
}

int pt_guard_cone(const pt_bsphere_t *b, int n, px_vec3_t p, double r, px_vec3_t axis, double half,
                  int skip) {
  for (int i = 0; i < n; i++) {
    if (b[i].object == skip)
      continue;
    px_vec3_t v = px_v3_sub(b[i].c, p);
    double dist = px_v3_norm(v), grown = b[i].r + r;
    if (!(dist > grown)) /* also a NaN radius */
      return 1;
    double gamma = asin(grown / dist);
    double ang = acos(fmax(-1.0, fmin(1.0, px_v3_dot(v, axis) / dist)));
    if (!(ang > gamma + half)) /* also a NaN half-angle */
      return 1;
  }
  return 0;
}

int pt_guard_shadow(const pt_bsphere_t *b, int n, px_vec3_t p, double r, double gap,
                    const px_vec3_t *normal, const rt_light_t *light, int skip) {
  if (!(r >= 0.0) || !(gap >= 0.0))
    return 1;
  int parallel = light->kind == RT_LIGHT_PARALLEL;
  px_vec3_t axis = px_v3_scale(light->v, -1.0); /* parallel: towards the light */
  double dist = INFINITY, half = 0.0;
  if (!parallel) { /* the cone from the light through the ball of radius r about p */
    px_vec3_t d = px_v3_sub(p, light->v);
    dist = px_v3_norm(d);
    if (!(dist > r))
      return 1;
    axis = px_v3_scale(d, 1.0 / dist);
    half = asin(r / dist);
  }
  /* on a plane a shadow is stretched by 1 / cos of the light's incidence: a gap holds it only
   * when its narrow width, the light's view of the gap shrunk by that cosine, exceeds it */
  if (normal)
    gap *= fabs(px_v3_dot(*normal, axis));
  for (int i = 0; i < n; i++) {
    if (b[i].object == skip)
      continue;
    double R = b[i].r;
    if (parallel) { /* the cylinder of radius r about the ray from p */
      px_vec3_t w = px_v3_sub(b[i].c, p);
      double t = px_v3_dot(w, axis), rho = px_v3_norm(px_v3_sub(w, px_v3_scale(axis, t)));
      if (t < -(R + r) || !(rho < R + r))
        continue; /* behind the hits, or beside the rays */
      if (R >= gap && t - R > r)
        continue; /* too large to fall between the traced rays (wholly towards the light) */
      return 1;
    }
    px_vec3_t v = px_v3_sub(b[i].c, light->v);
    double dc = px_v3_norm(v);
    if (!(dc > R))
      return 1; /* the light is inside it */
    if (dc - R >= dist + r)
      continue; /* wholly beyond the hits */
    double gamma = asin(R / dc), ang = acos(fmax(-1.0, fmin(1.0, px_v3_dot(v, axis) / dc)));
    if (!(ang < gamma + half))
      continue; /* beside the rays */
    if (gamma >= asin(fmin(1.0, gap / dist)) && dc + R < dist - r)
      continue; /* too large to fall between the traced rays (wholly between them and the light) */
    return 1;
  }
  return 0;
}
