/* edge.c -- the smoothness condition (paper section 4.1 (1), step 3): ray-tree comparison without
 * checker squares, and the cone guard against small objects vanishing (the paper's suggestion:
 * "estimating the distances between an axial ray and object surfaces, as in ... ray tracing with
 * cones"; here with bounding spheres). */
#include "pencil/edge.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/intersect.h"
#include "paraxial/vec3.h"

static pt_cnode_t compact(const rt_tree_node_t *a) {
  return (pt_cnode_t){.parent = a->parent,
                      .object = a->object,
                      .prim = a->prim,
                      .lit = a->lit,
                      .blocked = a->blocked,
                      .through = a->through,
                      .kind = a->kind,
                      .flags = a->flags};
}

static int same(const pt_cnode_t *a, const pt_cnode_t *b) {
  return a->parent == b->parent && a->kind == b->kind && a->flags == b->flags &&
         a->object == b->object && a->prim == b->prim && a->lit == b->lit &&
         a->blocked == b->blocked && a->through == b->through;
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
      /* both reach lights through glass or see them blocked, not with the same transmittances
       * or not by the same objects: only the lights lit at both stay (a lit gap may run between
       * two objects' shadows; a node that faces away from a light, through 0, is not compared
       * with one that reaches it partly: as before) */
      if (ok && y->through != x->through && x->through && y->through)
        lt &= x->lit & y->lit;
    }
    agree[k] = (uint8_t)ok;
    light[k] = ok ? lt : 0u;
    all = all && ok && lt == ~0u;
  }
  return all;
}

/* Faces of a polyhedron above which its convexity is not tested (O(faces x vertices)): it holds
 * nothing known, as a non-convex one. */
#define GUARD_MAX_FACES 4096

/* The centroid of the vertices of primitives [first, first + count) (polygons). */
static px_vec3_t vertex_centroid(const rt_scene_t *s, int first, int count) {
  px_vec3_t sum = {0.0, 0.0, 0.0};
  int nv = 0;
  for (int i = first; i < first + count; i++) {
    const rt_polygon_t *f = &s->prim[i].polygon;
    for (int k = 0; k < f->count; k++)
      sum = px_v3_add(sum, s->vertex[f->first + k]);
    nv += f->count;
  }
  return px_v3_scale(sum, 1.0 / nv);
}

/* What object ob holds (pt_bsphere_t.in, w, n), b->r its bounding radius: for a convex polyhedron
 * (every vertex on the inner side of every face, within 1e-9 of its size; normals outward) the
 * ball about the vertices' centroid to the nearest face's plane, which the intersection of the
 * faces' half-spaces holds; for a convex polygon the disc about its vertices' centroid to the
 * nearest edge's line. Otherwise w stays 0. */
static void held(const rt_scene_t *s, const rt_object_t *ob, pt_bsphere_t *b) {
  double e = 1e-9 * b->r;
  if (ob->kind == RT_OBJ_POLYHEDRON && ob->nprim >= 4 && ob->nprim <= GUARD_MAX_FACES) {
    if (!rt_polyhedron_convex(s, ob, b->r))
      return;
    px_vec3_t m = vertex_centroid(s, ob->first_prim, ob->nprim);
    double w = INFINITY;
    for (int i = ob->first_prim; i < ob->first_prim + ob->nprim; i++) {
      const rt_polygon_t *f = &s->prim[i].polygon;
      w = fmin(w, f->d - px_v3_dot(f->n, m));
    }
    if (w > 0.0) {
      b->in = m;
      b->w = w;
    }
  } else if (ob->kind == RT_OBJ_POLYGON && ob->nprim == 1) {
    const rt_polygon_t *f = &s->prim[ob->first_prim].polygon;
    px_vec3_t m = vertex_centroid(s, ob->first_prim, 1);
    double w = INFINITY;
    for (int k = 0; k < f->count; k++) {
      px_vec3_t a = s->vertex[f->first + k],
                d = px_v3_sub(s->vertex[f->first + (k + 1) % f->count], a);
      px_vec3_t in = px_v3_cross(f->n, d); /* in the plane, across the edge */
      double len = px_v3_norm(in);
      if (!(len > 0.0))
        return;
      in = px_v3_scale(in, 1.0 / len);
      double dm = px_v3_dot(in, px_v3_sub(m, a)), side = dm >= 0.0 ? 1.0 : -1.0;
      for (int j = 0; j < f->count; j++)
        if (side * px_v3_dot(in, px_v3_sub(s->vertex[f->first + j], a)) < -e)
          return; /* not convex */
      w = fmin(w, fabs(dm));
    }
    if (w > 0.0) {
      b->in = m;
      b->w = w;
      b->n = f->n;
    }
  }
}

/* The bounding sphere of object o (not a plane) and what it holds into *b; 0 when it has none. */
static int object_sphere(const rt_scene_t *s, int o, pt_bsphere_t *b) {
  const rt_object_t *ob = &s->object[o];
  if (ob->kind == RT_OBJ_PLANE)
    return 0;
  if (ob->kind == RT_OBJ_SPHERE) {
    const rt_sphere_t *sp = &s->prim[ob->first_prim].sphere;
    *b = pt_bsphere_ball(sp->c, sp->r, o);
    return 1;
  }
  px_vec3_t lo = px_v3(INFINITY, INFINITY, INFINITY), hi = px_v3(-INFINITY, -INFINITY, -INFINITY);
  for (int p = ob->first_prim; p < ob->first_prim + ob->nprim; p++) {
    px_vec3_t a, c;
    if (!rt_prim_bounds(s, p, &a, &c))
      continue;
    lo = px_v3(fmin(lo.x, a.x), fmin(lo.y, a.y), fmin(lo.z, a.z));
    hi = px_v3(fmax(hi.x, c.x), fmax(hi.y, c.y), fmax(hi.z, c.z));
  }
  if (!(lo.x <= hi.x))
    return 0;
  px_vec3_t c = px_v3_scale(px_v3_add(lo, hi), 0.5);
  *b = (pt_bsphere_t){c, 0.5 * px_v3_norm(px_v3_sub(hi, lo)), o, c, 0.0, {0.0, 0.0, 0.0}, -1};
  held(s, ob, b);
  return 1;
}

int pt_guard_spheres(const rt_scene_t *s, pt_bsphere_t *out, int cap) {
  int n = 0;
  for (int o = 0; o < s->nobject && n < cap; o++)
    n += object_sphere(s, o, &out[n]);
  return n;
}

/* ---- the hierarchy ------------------------------------------------------------------------ */

/* Spheres a leaf holds at most. */
#define GUARD_LEAF 4

/* The sphere about the box of b[0..n) holding all of them, grown by a margin for rounding: the
 * queries below skip a node on tests whose rounding the margin covers. */
static void enclose(const pt_bsphere_t *b, int n, pt_gnode_t *nd) {
  px_vec3_t lo = b[0].c, hi = b[0].c;
  for (int i = 1; i < n; i++) {
    lo = px_v3(fmin(lo.x, b[i].c.x), fmin(lo.y, b[i].c.y), fmin(lo.z, b[i].c.z));
    hi = px_v3(fmax(hi.x, b[i].c.x), fmax(hi.y, b[i].c.y), fmax(hi.z, b[i].c.z));
  }
  nd->c = px_v3_scale(px_v3_add(lo, hi), 0.5);
  double r = 0.0;
  for (int i = 0; i < n; i++) { /* a NaN radius makes the node's NaN: it is always visited */
    double reach = px_v3_norm(px_v3_sub(b[i].c, nd->c)) + b[i].r;
    r = r > reach ? r : reach;
  }
  nd->r = r * (1.0 + 1e-9) + 1e-9 * (1.0 + px_v3_norm(nd->c));
}

/* A sphere's centre's coordinate `axis` (0 x, 1 y, 2 z), NaN as infinity: a total order. */
static double key_of(const pt_bsphere_t *b, int axis) {
  double v = axis == 0 ? b->c.x : axis == 1 ? b->c.y : b->c.z;
  return v == v ? v : INFINITY;
}

/* Reorders a[0..n) so that a[m] is where sorting by key_of(axis) would put it, no sphere before it
 * with a larger key and none after it with a smaller one (Hoare's selection, the median of three
 * as pivot): the halves of a split in O(n), where sorting each node's spheres had made building
 * the faces' guards of a 10,000-face mesh cost 55e6 instructions. */
static void select_nth(pt_bsphere_t *a, int n, int m, int axis) {
  int lo = 0, hi = n - 1;
  while (hi > lo) {
    double x = key_of(&a[lo], axis), y = key_of(&a[lo + (hi - lo) / 2], axis),
           z = key_of(&a[hi], axis);
    double pivot = fmax(fmin(x, y), fmin(fmax(x, y), z));
    int i = lo, j = hi;
    while (i <= j) {
      while (key_of(&a[i], axis) < pivot)
        i++;
      while (key_of(&a[j], axis) > pivot)
        j--;
      if (i <= j) {
        pt_bsphere_t t = a[i];
        a[i++] = a[j];
        a[j--] = t;
      }
    }
    if (m <= j)
      hi = j;
    else if (m >= i)
      lo = i;
    else
      return;
  }
}

/* Node k over b[first .. first + n): split in halves along the longest side of the centres' box.
 * The queries are exact whatever the split; a good one only makes them visit fewer nodes. */
static void build(pt_guards_t *g, int k, int first, int n) {
  pt_gnode_t *nd = &g->node[k];
  enclose(g->b + first, n, nd);
  if (n <= GUARD_LEAF) {
    nd->first = first;
    nd->count = n;
    return;
  }
  px_vec3_t lo = g->b[first].c, hi = lo;
  for (int i = first + 1; i < first + n; i++) {
    lo = px_v3(fmin(lo.x, g->b[i].c.x), fmin(lo.y, g->b[i].c.y), fmin(lo.z, g->b[i].c.z));
    hi = px_v3(fmax(hi.x, g->b[i].c.x), fmax(hi.y, g->b[i].c.y), fmax(hi.z, g->b[i].c.z));
  }
  px_vec3_t ext = px_v3_sub(hi, lo);
  int m = n / 2;
  select_nth(g->b + first, n, m, ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2);
  int left = g->nnode;
  g->nnode += 2;
  nd->first = left;
  nd->count = 0;
  build(g, left, first, m);
  build(g, left + 1, first + m, n - m);
}

int pt_guards_make(const pt_bsphere_t *b, int n, pt_guards_t *g) {
  *g = (pt_guards_t){0};
  if (n <= 0)
    return 1;
  g->b = malloc((size_t)n * sizeof *g->b);
  g->node = malloc((size_t)(2 * n) * sizeof *g->node); /* at most 2n - 1 nodes */
  if (!g->b || !g->node) {
    pt_guards_free(g);
    return 0;
  }
  memcpy(g->b, b, (size_t)n * sizeof *b);
  g->n = n;
  g->nnode = 1;
  build(g, 0, 0, n);
  return 1;
}

int pt_guards_of_scene(const rt_scene_t *s, pt_guards_t *g) {
  *g = (pt_guards_t){0};
  if (s->nobject <= 0)
    return 1;
  pt_bsphere_t *b = malloc((size_t)s->nobject * sizeof *b);
  if (!b)
    return 0;
  int ok = pt_guards_make(b, pt_guard_spheres(s, b, s->nobject), g);
  free(b);
  return ok;
}

/* An edge of a polygon for edges_across(): its ends in lexicographic order, the vertex slot it
 * starts from, its polygon and its direction (the face across it runs the other way: a polyhedron
 * that touches itself along an edge pairs the right faces). */
typedef struct {
  px_vec3_t lo, hi;
  int slot, prim;
  int up; /* 1 when the polygon runs from lo to hi */
} edge_t;

static int lex(px_vec3_t a, px_vec3_t b) {
  return a.x != b.x   ? (a.x > b.x) - (a.x < b.x)
         : a.y != b.y ? (a.y > b.y) - (a.y < b.y)
                      : (a.z > b.z) - (a.z < b.z);
}

/* A hash of an edge's ends (their coordinates' bits; -0 and 0 differ, as no vertex is copied
 * with another sign). */
static size_t ends_hash(const edge_t *e) {
  const double c[6] = {e->lo.x, e->lo.y, e->lo.z, e->hi.x, e->hi.y, e->hi.z};
  uint64_t h = 1469598103934665603ull;
  for (int i = 0; i < 6; i++) {
    uint64_t bits;
    memcpy(&bits, &c[i], sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
    h ^= h >> 29;
  }
  return (size_t)h;
}

static int by_ends(const void *pa, const void *pb) {
  const edge_t *a = pa, *b = pb;
  int c = lex(a->lo, b->lo);
  return c ? c : lex(a->hi, b->hi);
}

/* The largest height of polygon f's vertices over the plane of polygon g (n . v - d). */
static double above(const rt_scene_t *s, const rt_polygon_t *f, const rt_polygon_t *g) {
  double h = -INFINITY;
  for (int k = 0; k < f->count; k++)
    h = fmax(h, px_v3_dot(g->n, s->vertex[f->first + k]) - g->d);
  return h;
}

/* The signed solid angle of triangle a, b, c seen from m (Van Oosterom and Strackee: tan(omega / 2)
 * = a . (b x c) / (|a||b||c| + (a . b)|c| + (a . c)|b| + (b . c)|a|), relative to m). */
static double solid_angle(px_vec3_t m, px_vec3_t a, px_vec3_t b, px_vec3_t c) {
  px_vec3_t A = px_v3_sub(a, m), B = px_v3_sub(b, m), C = px_v3_sub(c, m);
  double la = px_v3_norm(A), lb = px_v3_norm(B), lc = px_v3_norm(C);
  double num = px_v3_dot(A, px_v3_cross(B, C));
  double den = la * lb * lc + px_v3_dot(A, B) * lc + px_v3_dot(A, C) * lb + px_v3_dot(B, C) * la;
  return 2.0 * atan2(num, den);
}

/* Whether polyhedron o, every edge of which `across` pairs, is convex: convex at every edge
 * (neither face's vertices above the other's plane, within 1e-9 of its size), its vertices'
 * centroid m inside every face's plane, and its faces' solid angle from m 4 pi (it wraps m once,
 * which local convexity alone does not say). O(faces x vertices of a face), where the test of
 * every vertex against every face (rt_polyhedron_convex()) is O(faces x vertices): the guard of
 * objects gives that one up above GUARD_MAX_FACES. */
static int wraps_convex(const rt_scene_t *s, const rt_object_t *ob, const int *across) {
  px_vec3_t m = vertex_centroid(s, ob->first_prim, ob->nprim);
  double size = 0.0, omega = 0.0;
  for (int p = ob->first_prim; p < ob->first_prim + ob->nprim; p++) {
    const rt_polygon_t *f = &s->prim[p].polygon;
    for (int k = 0; k < f->count; k++)
      size = fmax(size, px_v3_norm(px_v3_sub(s->vertex[f->first + k], m)));
  }
  double tol = 1e-9 * size;
  for (int p = ob->first_prim; p < ob->first_prim + ob->nprim; p++) {
    const rt_polygon_t *f = &s->prim[p].polygon;
    if (!(px_v3_dot(f->n, m) - f->d < -tol))
      return 0;
    for (int k = 0; k < f->count; k++) {
      int q = across[f->first + k];
      if (q < 0 || !(above(s, &s->prim[q].polygon, f) <= tol))
        return 0;
      if (k >= 1 && k + 1 < f->count)
        omega += solid_angle(m, s->vertex[f->first], s->vertex[f->first + k],
                             s->vertex[f->first + k + 1]);
    }
  }
  return fabs(fabs(omega) - 4.0 * M_PI) < 1e-6 * 4.0 * M_PI;
}

/* The faces across the edges of the polyhedra not known convex (convex[o] 0) into across[] (one per
 * vertex slot, -1 elsewhere): an edge's two faces share its ends' coordinates exactly
 * (rt_scene_add_polyhedron() copies each face's vertices from the same input), so sorting the
 * edges by their ends pairs them. A polyhedron found convex after all (wraps_convex()) gets
 * convex[o] 1 and no pairs. 0 when out of memory. */
static int edges_across(const rt_scene_t *s, double *convex, int *across) {
  for (int i = 0; i < s->nvertex; i++)
    across[i] = -1;
  int ne = 0;
  for (int p = 0; p < s->nprim; p++)
    if (s->prim[p].kind == RT_PRIM_POLYGON &&
        s->object[s->prim[p].object].kind == RT_OBJ_POLYHEDRON && !convex[s->prim[p].object])
      ne += s->prim[p].polygon.count;
  if (ne == 0)
    return 1;
  edge_t *e = malloc((size_t)ne * sizeof *e);
  if (!e)
    return 0;
  ne = 0;
  for (int p = 0; p < s->nprim; p++) {
    if (!(s->prim[p].kind == RT_PRIM_POLYGON &&
          s->object[s->prim[p].object].kind == RT_OBJ_POLYHEDRON && !convex[s->prim[p].object]))
      continue;
    const rt_polygon_t *f = &s->prim[p].polygon;
    for (int k = 0; k < f->count; k++) {
      px_vec3_t a = s->vertex[f->first + k], b = s->vertex[f->first + (k + 1) % f->count];
      int ab = lex(a, b) <= 0;
      e[ne++] = (edge_t){ab ? a : b, ab ? b : a, f->first + k, p, ab};
    }
  }
  /* pairs by a hash of the ends (open addressing, a table at most half full): an edge waits in
   * it until the one with the same ends and object comes */
  size_t cap = 16;
  while (cap < 2 * (size_t)ne)
    cap *= 2;
  int *table = malloc(cap * sizeof *table);
  if (!table) {
    free(e);
    return 0;
  }
  for (size_t i = 0; i < cap; i++)
    table[i] = -1;
  for (int i = 0; i < ne; i++) {
    size_t h = ends_hash(&e[i]) & (cap - 1);
    for (;; h = (h + 1) & (cap - 1)) {
      int j = table[h];
      if (j < 0) {
        table[h] = i;
        break;
      }
      if (j < ne && by_ends(&e[i], &e[j]) == 0 && e[i].up != e[j].up &&
          s->prim[e[i].prim].object == s->prim[e[j].prim].object) {
        across[e[i].slot] = e[j].prim;
        across[e[j].slot] = e[i].prim;
        table[h] = ne; /* taken: a tombstone, so that later probes pass on */
        break;
      }
    }
  }
  free(table);
  free(e);
  for (int o = 0; o < s->nobject; o++) {
    const rt_object_t *ob = &s->object[o];
    if (ob->kind != RT_OBJ_POLYHEDRON || convex[o] || !wraps_convex(s, ob, across))
      continue;
    convex[o] = 1.0;
    for (int p = ob->first_prim; p < ob->first_prim + ob->nprim; p++)
      for (int k = 0; k < s->prim[p].polygon.count; k++)
        across[s->prim[p].polygon.first + k] = -1;
  }
  return 1;
}

int pt_guards_of_faces(const rt_scene_t *s, const pt_guards_t *objects, pt_guards_t *g) {
  *g = (pt_guards_t){0};
  int n = 0;
  for (int p = 0; p < s->nprim; p++)
    n += s->prim[p].kind == RT_PRIM_POLYGON;
  if (n == 0)
    return 1;
  pt_bsphere_t *b = malloc((size_t)n * sizeof *b);
  double *convex = calloc((size_t)s->nobject, sizeof *convex);
  int *across = malloc((size_t)(s->nvertex > 0 ? s->nvertex : 1) * sizeof *across);
  if (!b || !convex || !across) {
    free(b);
    free(convex);
    free(across);
    return 0;
  }
  for (int i = 0; i < objects->n; i++) { /* 1: the object hides nothing of itself */
    const pt_bsphere_t *o = &objects->b[i];
    const rt_object_t *ob = &s->object[o->object];
    convex[o->object] = (ob->kind == RT_OBJ_POLYGON && ob->nprim == 1) ||
                                (ob->kind == RT_OBJ_POLYHEDRON && o->w > 0.0) /* held() */
                            ? 1.0
                            : 0.0;
  }
  if (!edges_across(s, convex, across)) {
    free(b);
    free(convex);
    free(across);
    return 0;
  }
  n = 0;
  for (int p = 0; p < s->nprim; p++) {
    if (s->prim[p].kind != RT_PRIM_POLYGON)
      continue;
    const rt_polygon_t *f = &s->prim[p].polygon;
    px_vec3_t lo = s->vertex[f->first], hi = lo;
    for (int k = 1; k < f->count; k++) {
      px_vec3_t v = s->vertex[f->first + k];
      lo = px_v3(fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z));
      hi = px_v3(fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z));
    }
    px_vec3_t c = px_v3_scale(px_v3_add(lo, hi), 0.5);
    double r = 0.0;
    for (int k = 0; k < f->count; k++)
      r = fmax(r, px_v3_norm(px_v3_sub(s->vertex[f->first + k], c)));
    b[n++] =
        (pt_bsphere_t){c, r, s->prim[p].object, c, convex[s->prim[p].object], {0.0, 0.0, 0.0}, p};
  }
  int ok = pt_guards_make(b, n, g), any = 0;
  free(b);
  free(convex);
  for (int i = 0; i < s->nvertex && !any; i++)
    any = across[i] >= 0;
  if (ok &&
      any) /* none when no polyhedron may hide its own faces: their guards then cost nothing */
    g->across = across;
  else
    free(across);
  return ok;
}

void pt_guards_free(pt_guards_t *g) {
  free(g->b);
  free(g->node);
  free(g->across);
  *g = (pt_guards_t){0};
}

/* ---- the queries --------------------------------------------------------------------------- */

/* Margin of the angular tests that skip a node: acos() of a cosine near 1 is good to about
 * 1e-8 radians only. */
#define GUARD_ANGLE_SLACK 1e-6

/* Angle between v (length dist) and the unit axis. */
static double angle_to(px_vec3_t v, double dist, px_vec3_t axis) {
  return acos(fmax(-1.0, fmin(1.0, px_v3_dot(v, axis) / dist)));
}

enum { Q_FIRES, Q_SEGMENT, Q_CONE, Q_SHADOW, Q_VIEW, Q_SELF, Q_OWN };

/* A half-space of pt_guard_view(): the points x with n.(x - o) + rel |x - eye| >= 0 (n a unit
 * normal; rel > 0 grows it by that share of the distance from the eye, rel < 0 shrinks it). */
typedef struct {
  px_vec3_t n, o;
  double rel;
} half_t;

/* Vertices a polygon may have on the way through the clips: one of more gives up (fires). */
#define VIEW_MAX_VERTICES 256

typedef struct {
  int kind;
  px_vec3_t p, q, axis; /* the apex or start, the segment's end, the unit axis */
  double r, half, len2; /* apex radius, half-angle, |q - p|^2 */
  int skip_a, skip_b;   /* objects whose spheres do not count */
  /* Q_SHADOW */
  const rt_light_t *light;
  int parallel;
  double dist, gap; /* the light to p (INFINITY for a parallel light); the narrowed gap */
  double gap0;      /* the gap not narrowed */
  /* Q_VIEW: the front (h[0], when nh is 5) and the pyramid's four sides, the primitive met;
   * Q_SELF: the pencil's half-spaces and the light's side of the face, the face, its object
   * (skip_a), the faces' guards (for `across`) */
  const rt_scene_t *s;
  half_t h[8];
  int nh, face, face_b; /* Q_OWN: the faces the pencil starts and ends on (-1: none) */
  const pt_guards_t *g;
} query_t;

/* may() for the queries of half-spaces (Q_VIEW, Q_SELF, Q_OWN): 0 when sphere (c, R) lies outside
 * one of them by more than R (none of it is inside). Apart from may(), so that the other queries'
 * test stays small enough to be inlined. */
static int may_halves(const query_t *q, px_vec3_t c, double R) {
  px_vec3_t v = px_v3_sub(c, q->p); /* |v| at most its coordinates' sum */
  double slack = R * (1.0 + 1e-9) + 1e-9 * (fabs(v.x) + fabs(v.y) + fabs(v.z) + R);
  for (int i = 0; i < q->nh; i++)
    if (px_v3_dot(q->h[i].n, px_v3_sub(c, q->h[i].o)) < -slack)
      return 0;
  return 1;
}

/* Whether sphere (c, R) may hold a sphere that fires (1 also when unsure: NaN). */
static int may(const query_t *q, px_vec3_t c, double R) {
  switch (q->kind) {
  case Q_FIRES: {
    px_vec3_t v = px_v3_sub(c, q->p);
    double dist = px_v3_norm(v);
    return !(dist > R) ||
           !(angle_to(v, dist, q->axis) >= asin(fmin(1.0, R / dist)) + q->half + GUARD_ANGLE_SLACK);
  }
  case Q_SEGMENT: {
    px_vec3_t pq = px_v3_sub(q->q, q->p), v = px_v3_sub(c, q->p);
    double t = q->len2 > 0.0 ? fmax(0.0, fmin(1.0, px_v3_dot(v, pq) / q->len2)) : 0.0;
    double dist = px_v3_norm(px_v3_sub(v, px_v3_scale(pq, t)));
    return !(dist > (R + q->r) * (1.0 + 1e-9) + 1e-9 * dist);
  }
  case Q_CONE: {
    px_vec3_t v = px_v3_sub(c, q->p);
    double dist = px_v3_norm(v), grown = R + q->r;
    return !(dist > grown) || !(angle_to(v, dist, q->axis) >=
                                asin(fmin(1.0, grown / dist)) + q->half + GUARD_ANGLE_SLACK);
  }
  default: { /* Q_SHADOW */
    if (q->parallel) {
      px_vec3_t w = px_v3_sub(c, q->p);
      double t = px_v3_dot(w, q->axis), rho = px_v3_norm(px_v3_sub(w, px_v3_scale(q->axis, t)));
      double m = (R + q->r) * (1.0 + 1e-9) + 1e-9 * px_v3_norm(w);
      return !(t < -m) && !(rho >= m);
    }
    px_vec3_t v = px_v3_sub(c, q->light->v);
    double dc = px_v3_norm(v);
    if (!(dc > R))
      return 1;
    if (dc - R >= (q->dist + q->r) * (1.0 + 1e-9) + 1e-9 * dc)
      return 0;
    return !(angle_to(v, dc, q->axis) >= asin(fmin(1.0, R / dc)) + q->half + GUARD_ANGLE_SLACK);
  }
  }
}

/* The angular radius from a point light at L of the shadow of what b holds (at most): a ball's
 * exactly (a sphere's is its own, as before); a disc's across its narrow side, its radius times
 * the least cosine between its normal and a ray from L into b's bounding sphere (v = b->c - L,
 * dc = |v|, gamma its angular radius), over the farthest distance. 0 when it holds nothing. */
static double held_angle(const pt_bsphere_t *b, px_vec3_t L, px_vec3_t v, double dc, double gamma) {
  if (!(b->w > 0.0))
    return 0.0;
  if (!(px_v3_dot(b->n, b->n) > 0.0)) {
    double d = px_v3_norm(px_v3_sub(b->in, L));
    return d > b->w ? asin(b->w / d) : M_PI_2;
  }
  double tilt = acos(fmin(1.0, fabs(px_v3_dot(b->n, v)) / dc)) + gamma; /* from the normal */
  double cmin = tilt < M_PI_2 ? cos(tilt) : 0.0;
  return asin(fmin(1.0, b->w * cmin / (dc + b->r)));
}

/* The gap a shadow of b must outgrow: the narrowed one for a sphere, whose shadow on a plane is an
 * ellipse that must fit between the points whole; the gap itself for what other objects hold,
 * whose shadow may be a long strip that passes between the points, however long. */
static double gap_for(const query_t *q, const pt_bsphere_t *b) {
  int round = b->w == b->r && !(px_v3_dot(b->n, b->n) > 0.0);
  return round ? q->gap : q->gap0;
}

/* Polygon in[0..n) clipped by half-space h into out[VIEW_MAX_VERTICES]; -1 when a vertex's side
 * is NaN or the result would not fit (a polygon that is not convex can come out half as large
 * again: two vertices for every run of vertices inside). f is scratch for n values. The distance
 * from the eye in h's margin is bounded by the sum of the coordinates' sizes (at most sqrt 3
 * times it). */
static int clip(const half_t *h, px_vec3_t eye, const px_vec3_t *in, int n, px_vec3_t *out,
                double *f) {
  for (int i = 0; i < n; i++) {
    px_vec3_t e = px_v3_sub(in[i], eye);
    f[i] = px_v3_dot(h->n, px_v3_sub(in[i], h->o)) + h->rel * (fabs(e.x) + fabs(e.y) + fabs(e.z));
    if (isnan(f[i]))
      return -1;
  }
  int m = 0;
  for (int i = 0; i < n; i++) {
    int j = i + 1 < n ? i + 1 : 0;
    if (m + 2 > VIEW_MAX_VERTICES)
      return -1;
    if (f[i] >= 0.0)
      out[m++] = in[i];
    if ((f[i] >= 0.0) != (f[j] >= 0.0))
      out[m++] = px_v3_add(in[i], px_v3_scale(px_v3_sub(in[j], in[i]), f[i] / (f[i] - f[j])));
  }
  return m;
}

/* Whether what is left of v[0..n) (a polygon, or a segment when n is 2) inside half-spaces
 * h[0..nh) is not empty (1 also when unsure, or when it has more than VIEW_MAX_VERTICES
 * vertices at any step). */
static int left_inside(const query_t *q, const half_t *h, int nh, const px_vec3_t *v, int n) {
  if (n > VIEW_MAX_VERTICES)
    return 1;
  px_vec3_t buf[2][VIEW_MAX_VERTICES];
  double f[VIEW_MAX_VERTICES];
  const px_vec3_t *in = v;
  for (int i = 0; i < nh && n > 0; i++) {
    n = clip(&h[i], q->p, in, n, buf[i & 1], f);
    if (n < 0)
      return 1;
    in = buf[i & 1];
  }
  return n > 0;
}

/* Whether polygon `prim` reaches into the pyramid of a Q_VIEW query, in front of what it met. */
static int polygon_in_view(const query_t *q, int prim) {
  const rt_polygon_t *f = &q->s->prim[prim].polygon;
  return left_inside(q, q->h, q->nh, &q->s->vertex[f->first], f->count);
}

/* Whether polygon `prim` faces the light of a Q_SELF query (q->axis towards a parallel light,
 * q->light's position for a point light). */
static int faces_light(const query_t *q, int prim) {
  const rt_polygon_t *f = &q->s->prim[prim].polygon;
  return q->parallel ? px_v3_dot(f->n, q->axis) > 0.0 : px_v3_dot(f->n, q->light->v) - f->d > 0.0;
}

/* Whether an edge of polygon `prim` on its object's silhouette from the light (the polygon faces
 * the light, the one across the edge does not, or there is none) passes through the pencil of a
 * Q_SELF query (1 also when unsure). */
static int silhouette_in_pencil(const query_t *q, int prim) {
  if (!faces_light(q, prim))
    return 0; /* its edges on the silhouette are those of the faces facing the light too */
  const rt_polygon_t *f = &q->s->prim[prim].polygon;
  for (int k = 0; k < f->count; k++) {
    int other = q->g->across ? q->g->across[f->first + k] : -1;
    if (other >= 0 && faces_light(q, other))
      continue;
    px_vec3_t e[2] = {q->s->vertex[f->first + k], q->s->vertex[f->first + (k + 1) % f->count]};
    if (left_inside(q, q->h, q->nh, e, 2))
      return 1;
  }
  return 0;
}

/* Whether polygon f is convex: every turn along its vertices on the same side of its normal
 * (within 1e-9 of its edges' products). The scene's polygons do not cross themselves, so turns
 * of one sign make it convex. */
static int polygon_convex(const rt_scene_t *s, const rt_polygon_t *f) {
  for (int k = 0; k < f->count; k++) {
    px_vec3_t a = s->vertex[f->first + k], b = s->vertex[f->first + (k + 1) % f->count],
              c = s->vertex[f->first + (k + 2) % f->count];
    px_vec3_t u = px_v3_sub(b, a), w = px_v3_sub(c, b);
    double turn = px_v3_dot(px_v3_cross(u, w), f->n);
    if (!(turn >= -1e-9 * px_v3_norm(u) * px_v3_norm(w)))
      return 0;
  }
  return 1;
}

/* Whether sphere b fires: the tests of the scans over every sphere. */
static int fires(const query_t *q, const pt_bsphere_t *b) {
  switch (q->kind) {
  case Q_FIRES: {
    px_vec3_t v = px_v3_sub(b->c, q->p);
    double dist = px_v3_norm(v);
    if (dist <= b->r)
      return 0; /* the eye is inside: the object surrounds every cone */
    double gamma = asin(b->r / dist), ang = angle_to(v, dist, q->axis);
    return ang < gamma + q->half && ang + q->half > gamma; /* meets the cone, not containing it */
  }
  case Q_SEGMENT: {
    if (b->object == q->skip_a || b->object == q->skip_b)
      return 0;
    px_vec3_t pq = px_v3_sub(q->q, q->p), v = px_v3_sub(b->c, q->p);
    double t = q->len2 > 0.0 ? fmax(0.0, fmin(1.0, px_v3_dot(v, pq) / q->len2)) : 0.0;
    double dist = px_v3_norm(px_v3_sub(v, px_v3_scale(pq, t))); /* to the nearest point */
    return !(dist > b->r + q->r);                               /* a NaN radius fires */
  }
  case Q_SELF:
    return b->object == q->skip_a && b->prim != q->face && may_halves(q, b->c, b->r) &&
           silhouette_in_pencil(q, b->prim);
  case Q_OWN: /* a face of a non-convex end's object, not an end's own face */
    return b->w == 0.0 && (b->object == q->skip_a || b->object == q->skip_b) &&
           b->prim != q->face && b->prim != q->face_b && may_halves(q, b->c, b->r) &&
           polygon_in_view(q, b->prim);
  case Q_VIEW: /* not the face met, nor another of its object when that is convex */
    return b->prim != q->face && !(b->w > 0.0 && b->object == q->skip_a) &&
           may_halves(q, b->c, b->r) && polygon_in_view(q, b->prim);
  case Q_CONE: {
    if (b->object == q->skip_a)
      return 0;
    px_vec3_t v = px_v3_sub(b->c, q->p);
    double dist = px_v3_norm(v), grown = b->r + q->r;
    if (!(dist > grown)) /* also a NaN radius */
      return 1;
    double gamma = asin(grown / dist), ang = angle_to(v, dist, q->axis);
    return !(ang > gamma + q->half); /* also a NaN half-angle */
  }
  default: { /* Q_SHADOW */
    if (b->object == q->skip_a)
      return 0;
    double R = b->r;
    if (q->parallel) { /* the cylinder of radius r about the ray from p */
      px_vec3_t w = px_v3_sub(b->c, q->p);
      double t = px_v3_dot(w, q->axis), rho = px_v3_norm(px_v3_sub(w, px_v3_scale(q->axis, t)));
      if (t < -(R + q->r) || !(rho < R + q->r))
        return 0; /* behind the hits, or beside the rays */
      /* its shadow too wide to fall between the traced rays (wholly towards the light) */
      double held = b->w * (px_v3_dot(b->n, b->n) > 0.0 ? fabs(px_v3_dot(b->n, q->axis)) : 1.0);
      return !(held >= gap_for(q, b) && t - R > q->r);
    }
    px_vec3_t v = px_v3_sub(b->c, q->light->v);
    double dc = px_v3_norm(v);
    if (!(dc > R))
      return 1; /* the light is inside it */
    if (dc - R >= q->dist + q->r)
      return 0; /* wholly beyond the hits */
    double gamma = asin(R / dc), ang = angle_to(v, dc, q->axis);
    if (!(ang < gamma + q->half))
      return 0; /* beside the rays */
    /* its shadow too wide to fall between the traced rays (wholly between them and the light) */
    return !(held_angle(b, q->light->v, v, dc, gamma) >= asin(fmin(1.0, gap_for(q, b) / q->dist)) &&
             dc + R < q->dist - q->r);
  }
  }
}

/* Whether some sphere of g fires, visiting the nodes that may hold one. */
static int any_fires(const pt_guards_t *g, const query_t *q) {
  if (g->nnode == 0) { /* no hierarchy: every sphere */
    for (int i = 0; i < g->n; i++)
      if (fires(q, &g->b[i]))
        return 1;
    return 0;
  }
  /* halving splits: at most 31 levels for an int count of spheres, and a visit leaves at most
   * one pending node a level besides the two it pushes */
  int stack[64], sp = 0;
  stack[sp++] = 0;
  while (sp > 0) {
    const pt_gnode_t *nd = &g->node[stack[--sp]];
    if (!(q->kind >= Q_VIEW ? may_halves(q, nd->c, nd->r) : may(q, nd->c, nd->r)))
      continue;
    if (nd->count > 0) {
      for (int i = nd->first; i < nd->first + nd->count; i++)
        if (fires(q, &g->b[i]))
          return 1;
    } else {
      stack[sp++] = nd->first + 1;
      stack[sp++] = nd->first;
    }
  }
  return 0;
}

int pt_guard_fires(const pt_guards_t *g, px_vec3_t eye, px_vec3_t axis, double half) {
  query_t q = {.kind = Q_FIRES, .p = eye, .axis = axis, .half = half};
  return any_fires(g, &q);
}

/* The front of a Q_VIEW query (h, *has 0 when there is none): the eye's side of the plane of
 * `prim` met by the corner rays d[0..3], or for a sphere the points no farther along the axis than
 * the farthest corner's hit (the nearest hit is quasi-convex over the directions: the largest over
 * the pyramid is at a corner), shrunk by 1e-9 of the distance from the eye. */
static void front_of(const rt_scene_t *s, int prim, px_vec3_t eye, const px_vec3_t d[4],
                     px_vec3_t axis, half_t *h, int *has) {
  *has = 0;
  if (prim < 0)
    return;
  const rt_prim_t *pr = &s->prim[prim];
  px_vec3_t n, o;
  if (pr->kind == RT_PRIM_SPHERE) {
    px_vec3_t wc = px_v3_sub(pr->sphere.c, eye);
    if (!(px_v3_dot(wc, wc) > pr->sphere.r * pr->sphere.r))
      return; /* the eye inside: the exit's distance is largest towards the centre, not at a
                 corner; no front */
    double far = 0.0;
    for (int i = 0; i < 4; i++) {
      px_vec3_t u = px_v3_unit(d[i]), w = px_v3_sub(pr->sphere.c, eye);
      double b = px_v3_dot(u, w), disc = b * b - (px_v3_dot(w, w) - pr->sphere.r * pr->sphere.r);
      if (!(disc >= 0.0))
        return; /* a corner ray that misses it after all: no front */
      double sq = sqrt(disc), t = b - sq > 0.0 ? b - sq : b + sq;
      far = fmax(far, t);
    }
    n = px_v3_scale(axis, -1.0);
    o = px_v3_add(eye, px_v3_scale(axis, far));
  } else {
    n = pr->kind == RT_PRIM_PLANE ? pr->plane.n : pr->polygon.n;
    o = pr->kind == RT_PRIM_PLANE ? pr->plane.p : px_v3_scale(pr->polygon.n, pr->polygon.d);
    double side = px_v3_dot(n, px_v3_sub(eye, o));
    if (!(side != 0.0))
      return; /* the eye in its plane (or NaN): no front */
    if (side < 0.0)
      n = px_v3_scale(n, -1.0);
  }
  *h = (half_t){n, o, -1e-9};
  *has = 1;
}

int pt_guard_view(const pt_guards_t *objects, const pt_guards_t *faces, const rt_scene_t *s,
                  px_vec3_t eye, const px_vec3_t d[4], px_vec3_t axis, double half, int prim) {
  if (objects->n && pt_guard_fires(objects, eye, axis, half))
    return 1;
  const rt_polygon_t *own =
      prim >= 0 && s->prim[prim].kind == RT_PRIM_POLYGON ? &s->prim[prim].polygon : NULL;
  int concave = own && !polygon_convex(s, own);
  if (!faces->n && !concave)
    return 0;
  query_t q = {.kind = Q_VIEW,
               .p = eye,
               .axis = axis,
               .half = half,
               .s = s,
               .face = prim,
               .skip_a = prim >= 0 ? s->prim[prim].object : -1};
  int front; /* first, where there is one: it leaves out the faces behind `prim` in one pass */
  front_of(s, prim, eye, d, axis, &q.h[0], &front);
  for (int i = 0; i < 4; i++) { /* the sides, through the eye, facing the axis */
    px_vec3_t n = px_v3_cross(d[i], d[(i + 1) % 4]);
    double len = px_v3_norm(n);
    if (!(len > 0.0))
      return 1;
    n = px_v3_scale(n, (px_v3_dot(n, axis) < 0.0 ? -1.0 : 1.0) / len);
    q.h[front + i] = (half_t){n, eye, 1e-9};
  }
  q.nh = 4 + front;
  if (concave) { /* its own edges inside the pyramid's sides: a notch the corners do not see */
    for (int k = 0; k < own->count; k++) {
      px_vec3_t e[2] = {s->vertex[own->first + k], s->vertex[own->first + (k + 1) % own->count]};
      if (left_inside(&q, q.h + front, 4, e, 2))
        return 1;
    }
  }
  return faces->n && any_fires(faces, &q);
}

/* Two unit vectors perpendicular to unit u and to each other. */
static void perpendiculars(px_vec3_t u, px_vec3_t *e1, px_vec3_t *e2) {
  px_vec3_t t = fabs(u.x) < 0.6 ? px_v3(1, 0, 0) : px_v3(0, 1, 0);
  *e1 = px_v3_unit(px_v3_cross(u, t));
  *e2 = px_v3_cross(u, *e1);
}

/* Adds to q the four sides of the square pyramid about unit axis u with its apex r / sh behind o
 * (sh the sine of its half-angle): the half-spaces nu . (x - o) + r >= 0 for nu = u sh - s ch,
 * s = +-e1, +-e2 (nu . (o - apex) is r). It holds the circular cone of that half-angle from the
 * apex, so the rays from every point within r of o in those directions; with sh 0, the square
 * prism r about the line through o. Written from o, so that no far apex rounds. */
static void add_square(query_t *q, px_vec3_t o, px_vec3_t u, double sh, double r) {
  px_vec3_t e1, e2;
  perpendiculars(u, &e1, &e2);
  double ch = sqrt(fmax(0.0, 1.0 - sh * sh));
  const px_vec3_t side[4] = {e1, px_v3_scale(e1, -1.0), e2, px_v3_scale(e2, -1.0)};
  for (int i = 0; i < 4; i++) {
    px_vec3_t nu = px_v3_sub(px_v3_scale(u, sh), px_v3_scale(side[i], ch));
    q->h[q->nh++] = (half_t){nu, px_v3_sub(o, px_v3_scale(nu, r)), 1e-9};
  }
}

int pt_guard_self_shadow(const pt_guards_t *faces, const rt_scene_t *s, int prim, px_vec3_t p,
                         double r, const rt_light_t *light) {
  if (!faces->n || !faces->across || prim < 0 || s->prim[prim].kind != RT_PRIM_POLYGON)
    return 0;
  int o = s->prim[prim].object;
  if (s->object[o].kind != RT_OBJ_POLYHEDRON)
    return 0;
  const rt_polygon_t *f = &s->prim[prim].polygon;
  int open = 0; /* does the object hold any edge of a silhouette at all (a face not convex)? */
  for (int k = 0; k < f->count && !open; k++)
    open = faces->across[f->first + k] >= 0;
  if (!open)
    return 0; /* a convex polyhedron's faces have no pairs: it does not shadow itself */
  if (!(r >= 0.0))
    return 1;
  query_t q = {
      .kind = Q_SELF, .p = p, .s = s, .face = prim, .skip_a = o, .g = faces, .light = light};
  q.parallel = light->kind == RT_LIGHT_PARALLEL;
  px_vec3_t n = f->n;
  if (q.parallel) { /* the square prism about the ray from p to the light, from r behind p */
    q.axis = px_v3_scale(light->v, -1.0);
    add_square(&q, p, q.axis, 0.0, r);
    q.h[q.nh++] = (half_t){q.axis, px_v3_sub(p, px_v3_scale(q.axis, r)), 1e-9};
    double facing = px_v3_dot(n, q.axis);
    if (!(facing != 0.0)) /* edge-on: no direct light to shadow (NaN: unsure) */
      return facing == facing ? 0 : 1;
    if (facing < 0.0) /* lit from inside (a hit from within a transparent object) */
      n = px_v3_scale(n, -1.0);
  } else { /* the square pyramid from the light about the cone through the ball about p */
    px_vec3_t d = px_v3_sub(p, light->v);
    double dist = px_v3_norm(d);
    if (!(dist > r))
      return 1;
    px_vec3_t u = px_v3_scale(d, 1.0 / dist);
    q.axis = u;
    add_square(&q, light->v, u, r / dist, 0.0);
    q.h[q.nh++] = (half_t){u, light->v, 1e-9};
    q.h[q.nh++] =
        (half_t){px_v3_scale(u, -1.0), px_v3_add(light->v, px_v3_scale(u, dist + r)), 1e-9};
    double facing = px_v3_dot(n, light->v) - f->d;
    if (!(facing != 0.0))
      return facing == facing ? 0 : 1;
    if (facing < 0.0)
      n = px_v3_scale(n, -1.0);
  }
  /* the light's side of the face's plane (outside, or inside for a hit from within the object),
   * shrunk: the faces sharing its edges stay out */
  q.h[q.nh++] = (half_t){n, px_v3_scale(f->n, f->d), -1e-9};
  return any_fires(faces, &q);
}

/* The object of primitive `prim` when it is a polygon of a polyhedron whose faces may hide each
 * other (pt_guards_of_faces() paired its edges), else -1. */
static int own_object(const pt_guards_t *faces, const rt_scene_t *s, int prim) {
  if (prim < 0 || !faces->across || s->prim[prim].kind != RT_PRIM_POLYGON)
    return -1;
  const rt_polygon_t *f = &s->prim[prim].polygon;
  for (int k = 0; k < f->count; k++)
    if (faces->across[f->first + k] >= 0)
      return s->prim[prim].object;
  return -1;
}

/* The half-space on the side of polygon `prim`'s plane that direction v points to, shrunk (so that
 * the faces sharing its edges stay out); 0 when v runs along the plane (none). */
static int side_of(const rt_scene_t *s, int prim, px_vec3_t v, half_t *h) {
  const rt_polygon_t *f = &s->prim[prim].polygon;
  double c = px_v3_dot(f->n, v);
  if (!(c != 0.0))
    return 0;
  px_vec3_t n = c > 0.0 ? f->n : px_v3_scale(f->n, -1.0);
  *h = (half_t){n, px_v3_scale(f->n, f->d), -1e-9};
  return 1;
}

int pt_guard_own_segment(const pt_guards_t *faces, const rt_scene_t *s, px_vec3_t p, px_vec3_t q,
                         double r, int prim_a, int prim_b) {
  int oa = own_object(faces, s, prim_a), ob = own_object(faces, s, prim_b);
  if (oa < 0 && ob < 0)
    return 0;
  px_vec3_t d = px_v3_sub(q, p);
  double len = px_v3_norm(d);
  if (!(len > 0.0) || !(r >= 0.0))
    return 1;
  px_vec3_t u = px_v3_scale(d, 1.0 / len);
  query_t Q = {.kind = Q_OWN,
               .p = p,
               .s = s,
               .skip_a = oa,
               .skip_b = ob,
               .face = prim_a,
               .face_b = prim_b,
               .g = faces};
  add_square(&Q, p, u, 0.0, r); /* the square prism about the segment, r from it */
  Q.h[Q.nh++] = (half_t){u, px_v3_sub(p, px_v3_scale(u, r)), 1e-9};
  Q.h[Q.nh++] = (half_t){px_v3_scale(u, -1.0), px_v3_add(q, px_v3_scale(u, r)), 1e-9};
  if (prim_a >= 0 && s->prim[prim_a].kind == RT_PRIM_POLYGON)
    Q.nh += side_of(s, prim_a, u, &Q.h[Q.nh]);
  if (prim_b >= 0 && s->prim[prim_b].kind == RT_PRIM_POLYGON)
    Q.nh += side_of(s, prim_b, px_v3_scale(u, -1.0), &Q.h[Q.nh]);
  return any_fires(faces, &Q);
}

int pt_guard_own_cone(const pt_guards_t *faces, const rt_scene_t *s, px_vec3_t p, double r,
                      px_vec3_t axis, double half, int prim) {
  int o = own_object(faces, s, prim);
  if (o < 0)
    return 0;
  if (!(r >= 0.0) || !(half >= 0.0) || !(half < 0.5 * M_PI - 1e-6))
    return 1;
  query_t Q = {.kind = Q_OWN,
               .p = p,
               .s = s,
               .skip_a = o,
               .skip_b = -1,
               .face = prim,
               .face_b = -1,
               .g = faces};
  /* the square pyramid about the cone of half-angle `half` from r / sin(half) behind p, which
   * holds the rays from every point within r of p (a prism r about the ray when it is 0) */
  add_square(&Q, p, axis, sin(half), r);
  Q.h[Q.nh++] = (half_t){axis, px_v3_sub(p, px_v3_scale(axis, r)), 1e-9};
  if (s->prim[prim].kind == RT_PRIM_POLYGON)
    Q.nh += side_of(s, prim, axis, &Q.h[Q.nh]);
  return any_fires(faces, &Q);
}

int pt_guard_segment(const pt_guards_t *g, px_vec3_t p, px_vec3_t q, double r, int skip_a,
                     int skip_b) {
  px_vec3_t pq = px_v3_sub(q, p);
  query_t Q = {.kind = Q_SEGMENT,
               .p = p,
               .q = q,
               .r = r,
               .len2 = px_v3_dot(pq, pq),
               .skip_a = skip_a,
               .skip_b = skip_b};
  return any_fires(g, &Q);
}

int pt_guard_cone(const pt_guards_t *g, px_vec3_t p, double r, px_vec3_t axis, double half,
                  int skip) {
  query_t q = {.kind = Q_CONE, .p = p, .r = r, .axis = axis, .half = half, .skip_a = skip};
  return any_fires(g, &q);
}

int pt_guard_shadow(const pt_guards_t *g, px_vec3_t p, double r, double gap,
                    const px_vec3_t *normal, const rt_light_t *light, int skip) {
  if (!(r >= 0.0) || !(gap >= 0.0))
    return 1;
  query_t q = {.kind = Q_SHADOW, .p = p, .r = r, .skip_a = skip, .light = light};
  q.parallel = light->kind == RT_LIGHT_PARALLEL;
  q.axis = px_v3_scale(light->v, -1.0); /* parallel: towards the light */
  q.dist = INFINITY;
  if (!q.parallel) { /* the cone from the light through the ball of radius r about p */
    px_vec3_t d = px_v3_sub(p, light->v);
    q.dist = px_v3_norm(d);
    if (!(q.dist > r))
      return 1;
    q.axis = px_v3_scale(d, 1.0 / q.dist);
    q.half = asin(r / q.dist);
  }
  /* on a plane a shadow is stretched by 1 / cos of the light's incidence: a gap holds it only
   * when its narrow width, the light's view of the gap shrunk by that cosine, exceeds it */
  q.gap = normal ? gap * fabs(px_v3_dot(*normal, q.axis)) : gap;
  q.gap0 = gap;
  return any_fires(g, &q);
}
