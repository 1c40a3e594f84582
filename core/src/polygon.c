/* polygon.c -- planar polygons and closed polyhedra, convex or not (issue 4; the paper's Fig. 11
 * polyhedron of 100 polygons). A polyhedron is accepted only when it is closed and
 * consistently oriented, so that "inside" is well defined for refraction and for shadow rays;
 * its faces are then turned outwards by the sign of the enclosed volume. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_impl.h"

/* A vertex may lie this far off its polygon's plane, relative to the polygon's size: a few
 * hundred ulps of the coordinates, so hand-written decimals pass and a bent polygon does not. */
#define PLANAR_TOL 1e-9

rt_status_t rt__scene_push_vertices(rt_scene_t *s, const px_vec3_t *v, int n, int *first) {
  if (n > s->cap_vertex - s->nvertex) {
    int nc = s->cap_vertex ? s->cap_vertex : 64;
    while (nc < s->nvertex + n)
      nc *= 2;
    px_vec3_t *p = realloc(s->vertex, (size_t)nc * sizeof *p);
    if (!p)
      return RT_ENOMEM;
    s->vertex = p;
    s->cap_vertex = nc;
  }
  memcpy(s->vertex + s->nvertex, v, (size_t)n * sizeof *v);
  *first = s->nvertex;
  s->nvertex += n;
  return RT_OK;
}

/* Newell's normal: twice the vector area, exact for any planar polygon, convex or not. */
static px_vec3_t newell(const px_vec3_t *v, int n) {
  px_vec3_t a = {0, 0, 0};
  for (int i = 0; i < n; i++) {
    px_vec3_t p = v[i], q = v[(i + 1) % n];
    a.x += (p.y - q.y) * (p.z + q.z);
    a.y += (p.z - q.z) * (p.x + q.x);
    a.z += (p.x - q.x) * (p.y + q.y);
  }
  return a;
}

rt_status_t rt__polygon_setup(const rt_scene_t *s, int first, int n, rt_polygon_t *pr,
                              const char **why) {
  const px_vec3_t *v = s->vertex + first;
  double size = 0.0;
  for (int i = 1; i < n; i++)
    size = fmax(size, px_vec3_norm(px_vec3_sub(v[i], v[0])));
  px_vec3_t a = newell(v, n);
  double area2 = px_vec3_norm(a);
  if (n < 3 || !(size > 0.0) || !isfinite(size) || !(area2 > 1e-12 * size * size)) {
    *why = "the polygon has (almost) zero area";
    return RT_EGEOMETRY;
  }
  px_vec3_t nu = px_vec3_scale(a, 1.0 / area2);
  double d = 0.0;
  for (int i = 0; i < n; i++)
    d += px_vec3_dot(nu, v[i]) / n;
  for (int i = 0; i < n; i++)
    if (fabs(px_vec3_dot(nu, v[i]) - d) > PLANAR_TOL * size) {
      *why = "the polygon is not planar";
      return RT_EGEOMETRY;
    }
  double ax = fabs(nu.x), ay = fabs(nu.y), az = fabs(nu.z);
  *pr = (rt_polygon_t){nu, d, first, n, ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2)};
  return RT_OK;
}

rt_status_t rt_scene_add_polygon(rt_scene_t *s, const px_vec3_t *v, int n, int material,
                                 int *object) {
  if (n < 3 || material < 0 || material >= s->nmaterial)
    return RT_EINVAL;
  int first, nv0 = s->nvertex, o;
  rt_status_t st = rt__scene_push_vertices(s, v, n, &first);
  rt_polygon_t pg;
  const char *why = NULL;
  if (st == RT_OK)
    st = rt__polygon_setup(s, first, n, &pg, &why);
  if (st == RT_OK)
    st = rt__scene_new_object(s, RT_OBJ_POLYGON, material, 1, &o);
  if (st != RT_OK) {
    s->nvertex = nv0;
    return st;
  }
  rt_prim_t *p = &s->prim[s->object[o].first_prim];
  p->kind = RT_PRIM_POLYGON;
  p->polygon = pg;
  if (object)
    *object = o;
  return RT_OK;
}

/* Directed edge a -> b keyed by the undirected pair. */
typedef struct {
  int lo, hi, forward, face;
} edge_t;

static int edge_cmp(const void *x, const void *y) {
  const edge_t *a = x, *b = y;
  if (a->lo != b->lo)
    return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi)
    return a->hi < b->hi ? -1 : 1;
  return a->forward - b->forward;
}

/* Every edge used exactly twice, in opposite directions. 0 and a reason otherwise. */
static int check_closed(const int *idx, const int *len, int nface, int nidx, char *why,
                        size_t cap) {
  edge_t *e = malloc((size_t)nidx * sizeof *e);
  if (!e) {
    snprintf(why, cap, "out of memory");
    return 0;
  }
  int k = 0;
  for (int f = 0, off = 0; f < nface; off += len[f], f++)
    for (int i = 0; i < len[f]; i++) {
      int a = idx[off + i], b = idx[off + (i + 1) % len[f]];
      e[k++] = (edge_t){a < b ? a : b, a < b ? b : a, a < b, f};
    }
  qsort(e, (size_t)nidx, sizeof *e, edge_cmp);
  int ok = 1;
  for (int i = 0; i < nidx && ok;) {
    int j = i;
    while (j < nidx && e[j].lo == e[i].lo && e[j].hi == e[i].hi)
      j++;
    if (e[i].lo == e[i].hi) {
      snprintf(why, cap, "face %d repeats vertex %d", e[i].face, e[i].lo);
      ok = 0;
    } else if (j - i != 2) {
      snprintf(why, cap,
               "edge %d-%d is used by %d face(s); a closed polyhedron uses every edge "
               "exactly twice",
               e[i].lo, e[i].hi, j - i);
      ok = 0;
    } else if (e[i].forward == e[i + 1].forward) {
      snprintf(why, cap,
               "faces %d and %d traverse edge %d-%d in the same direction; faces must "
               "be ordered consistently",
               e[i].face, e[i + 1].face, e[i].lo, e[i].hi);
      ok = 0;
    }
    i = j;
  }
  free(e);
  return ok;
}

/* Six times the signed volume enclosed by the faces (fan triangles against the origin). */
static double volume6(const px_vec3_t *v, const int *idx, const int *len, int nface) {
  double vol = 0.0;
  for (int f = 0, off = 0; f < nface; off += len[f], f++)
    for (int i = 1; i + 1 < len[f]; i++)
      vol += px_vec3_dot(v[idx[off]], px_vec3_cross(v[idx[off + i]], v[idx[off + i + 1]]));
  return vol;
}

static rt_status_t fail(char *why, size_t cap, rt_status_t st, const char *fmt, int a) {
  if (why)
    snprintf(why, cap, fmt, a);
  return st;
}

/* Check indices and closure; on success *flip says whether faces must be reversed. */
static rt_status_t validate(const px_vec3_t *v, int nv, const int *idx, const int *len, int nface,
                            int *nidx, int *flip, char *why, size_t cap) {
  char tmp[200];
  *nidx = 0;
  if (nface < 4)
    return fail(why, cap, RT_EGEOMETRY, "a closed polyhedron needs at least 4 faces, got %d",
                nface);
  for (int f = 0; f < nface; f++) {
    if (len[f] < 3)
      return fail(why, cap, RT_EGEOMETRY, "face %d has fewer than 3 vertices", f);
    for (int i = 0; i < len[f]; i++)
      if (idx[*nidx + i] < 0 || idx[*nidx + i] >= nv)
        return fail(why, cap, RT_EINVAL, "face %d refers to a vertex that does not exist", f);
    *nidx += len[f];
  }
  if (!check_closed(idx, len, nface, *nidx, tmp, sizeof tmp)) {
    if (why)
      snprintf(why, cap, "%s", tmp);
    return RT_EGEOMETRY;
  }
  double vol = volume6(v, idx, len, nface);
  if (!(fabs(vol) > 0.0) || !isfinite(vol))
    return fail(why, cap, RT_EGEOMETRY, "the polyhedron encloses no volume (%d faces)", nface);
  *flip = vol < 0.0;
  return RT_OK;
}

/* Copy face f's vertices (reversed when flip) to the scene and set its polygon up. */
static rt_status_t add_face(rt_scene_t *s, const px_vec3_t *v, const int *fi, int n, int flip,
                            rt_polygon_t *pg, const char **msg) {
  px_vec3_t buf[64], *tmp = n <= 64 ? buf : malloc((size_t)n * sizeof *tmp);
  if (!tmp)
    return RT_ENOMEM;
  for (int i = 0; i < n; i++)
    tmp[i] = v[fi[flip ? n - 1 - i : i]];
  int first;
  rt_status_t st = rt__scene_push_vertices(s, tmp, n, &first);
  if (tmp != buf)
    free(tmp);
  return st == RT_OK ? rt__polygon_setup(s, first, n, pg, msg) : st;
}

rt_status_t rt_scene_add_polyhedron(rt_scene_t *s, const px_vec3_t *v, int nv, const int *face_idx,
                                    const int *face_len, int nface, int material, int *object,
                                    char *why, size_t cap) {
  int nidx, flip;
  if (material < 0 || material >= s->nmaterial)
    return fail(why, cap, RT_EINVAL, "material %d does not exist", material);
  rt_status_t st = validate(v, nv, face_idx, face_len, nface, &nidx, &flip, why, cap);
  if (st != RT_OK)
    return st;
  rt_polygon_t *pg = malloc((size_t)nface * sizeof *pg);
  if (!pg)
    return RT_ENOMEM;
  int nv0 = s->nvertex, o = -1;
  for (int f = 0, off = 0; f < nface && st == RT_OK; off += face_len[f], f++) {
    const char *msg = NULL;
    st = add_face(s, v, face_idx + off, face_len[f], flip, &pg[f], &msg);
    if (st == RT_EGEOMETRY && why)
      snprintf(why, cap, "face %d: %s", f, msg);
  }
  if (st == RT_OK)
    st = rt__scene_new_object(s, RT_OBJ_POLYHEDRON, material, nface, &o);
  if (st != RT_OK) {
    s->nvertex = nv0;
    free(pg);
    return st;
  }
  for (int f = 0; f < nface; f++) {
    rt_prim_t *p = &s->prim[s->object[o].first_prim + f];
    p->kind = RT_PRIM_POLYGON;
    p->polygon = pg[f];
  }
  free(pg);
  if (object)
    *object = o;
  return RT_OK;
}
