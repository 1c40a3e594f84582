/* faces.c -- the scene as convex faces for beams: a convex polygon is one face, a concave one is
 * cut into triangles (ear clipping in the polygon's plane), a plane is an unbounded face. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "beam/beam.h"
#include "core/intersect.h"

void bm_scene_free(bm_scene_t *b) {
  free(b->face);
  free(b->vertex);
  free(b->face_of_prim);
  memset(b, 0, sizeof *b);
}

/* Convex polygons with more vertices are cut into triangles, so that a face clipped by a plane
 * and projected fits a px_poly2_t. */
#define BM_FACE_MAX 24

/* 2-D coordinates of the polygon's vertices in its plane (axes e1, e2 with e1 x e2 = n). */
static void plane_axes(px_vec3_t n, px_vec3_t *e1, px_vec3_t *e2) {
  px_vec3_t t = fabs(n.x) < 0.6 ? px_v3(1, 0, 0) : px_v3(0, 1, 0);
  *e1 = px_v3_unit(px_v3_cross(t, n));
  *e2 = px_v3_cross(n, *e1);
}

static double cross2(const double a[2], const double b[2], const double c[2]) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* 1 when the counter-clockwise 2-D polygon q[idx[0..n-1]] turns left at every vertex. */
static int convex2(double (*q)[2], const int *idx, int n) {
  for (int k = 0; k < n; k++)
    if (cross2(q[idx[k]], q[idx[(k + 1) % n]], q[idx[(k + 2) % n]]) < 0)
      return 0;
  return 1;
}

/* Ear clipping of the counter-clockwise simple polygon q[0..n-1]: triangles' vertex indices
 * into tri (3 each); returns the count, or -1 when no ear is found (not simple). */
static int ear_clip(double (*q)[2], int n, int *idx, int *tri) {
  for (int k = 0; k < n; k++)
    idx[k] = k;
  int m = n, nt = 0;
  while (m > 3) {
    int found = 0;
    for (int k = 0; k < m && !found; k++) {
      int a = idx[(k + m - 1) % m], b = idx[k], c = idx[(k + 1) % m];
      if (cross2(q[a], q[b], q[c]) <= 0)
        continue; /* reflex or flat */
      int empty = 1;
      for (int j = 0; j < m && empty; j++) {
        int p = idx[j];
        if (p == a || p == b || p == c)
          continue;
        empty = !(cross2(q[a], q[b], q[p]) >= 0 && cross2(q[b], q[c], q[p]) >= 0 &&
                  cross2(q[c], q[a], q[p]) >= 0);
      }
      if (!empty)
        continue;
      tri[3 * nt] = a;
      tri[3 * nt + 1] = b;
      tri[3 * nt + 2] = c;
      nt++;
      memmove(idx + k, idx + k + 1, (size_t)(m - k - 1) * sizeof *idx);
      m--;
      found = 1;
    }
    if (!found)
      return -1;
  }
  tri[3 * nt] = idx[0];
  tri[3 * nt + 1] = idx[1];
  tri[3 * nt + 2] = idx[2];
  return nt + 1;
}

rt_status_t bm_scene_build(const rt_scene_t *s, bm_scene_t *b, char *why, size_t cap) {
  memset(b, 0, sizeof *b);
  int nf = 0, nv = 0;
  for (int p = 0; p < s->nprim; p++) {
    const rt_prim_t *pr = &s->prim[p];
    if (pr->kind == RT_PRIM_SPHERE) {
      const rt_object_t *ob = &s->object[pr->object];
      snprintf(why, cap,
               "object '%s' is a sphere: beams need planar faces (polygons, polyhedra, "
               "planes)",
               ob->name[0] ? ob->name : "(unnamed)");
      return RT_EINVAL;
    }
    int c = pr->kind == RT_PRIM_POLYGON ? pr->polygon.count : 0;
    nf += c > 3 ? c - 2 : 1; /* at most count - 2 triangles */
    nv += c > 3 ? 3 * (c - 2) : c;
  }
  b->face = calloc((size_t)nf + 1, sizeof *b->face);
  b->vertex = calloc((size_t)nv + 1, sizeof *b->vertex);
  b->face_of_prim = calloc((size_t)s->nprim + 1, sizeof *b->face_of_prim);
  int maxc = 3;
  for (int p = 0; p < s->nprim; p++)
    if (s->prim[p].kind == RT_PRIM_POLYGON && s->prim[p].polygon.count > maxc)
      maxc = s->prim[p].polygon.count;
  double(*q)[2] = malloc((size_t)maxc * sizeof *q);
  int *idx = malloc((size_t)maxc * sizeof *idx), *tri = malloc(3 * (size_t)maxc * sizeof *tri);
  if (!b->face || !b->vertex || !b->face_of_prim || !q || !idx || !tri) {
    free(q);
    free(idx);
    free(tri);
    bm_scene_free(b);
    return RT_ENOMEM;
  }
  px_vec3_t lo = px_v3(INFINITY, INFINITY, INFINITY), hi = px_v3(-INFINITY, -INFINITY, -INFINITY);
  rt_status_t st = RT_OK;
  for (int p = 0; p < s->nprim && st == RT_OK; p++) {
    const rt_prim_t *pr = &s->prim[p];
    b->face_of_prim[p] = b->nface;
    if (pr->kind == RT_PRIM_PLANE) {
      b->face[b->nface++] =
          (bm_face_t){p,          pr->object, pr->plane.n,    px_v3_dot(pr->plane.n, pr->plane.p),
                      b->nvertex, 0,          px_v3(0, 0, 0), 0.0};
      continue;
    }
    px_vec3_t a, z;
    if (rt_prim_bounds(s, p, &a, &z)) {
      lo = px_v3(fmin(lo.x, a.x), fmin(lo.y, a.y), fmin(lo.z, a.z));
      hi = px_v3(fmax(hi.x, z.x), fmax(hi.y, z.y), fmax(hi.z, z.z));
    }
    const rt_polygon_t *pg = &pr->polygon;
    const px_vec3_t *v = s->vertex + pg->first;
    px_vec3_t e1, e2;
    plane_axes(pg->n, &e1, &e2);
    for (int k = 0; k < pg->count; k++) {
      q[k][0] = px_v3_dot(v[k], e1);
      q[k][1] = px_v3_dot(v[k], e2);
    }
    /* counter-clockwise about n in (e1, e2): the scene orders vertices so; check the area */
    double area = 0;
    for (int k = 1; k + 1 < pg->count; k++)
      area += cross2(q[0], q[k], q[k + 1]);
    int flip = area < 0;
    if (flip)
      for (int k = 0; k < pg->count; k++)
        q[k][1] = -q[k][1]; /* mirror, so that the ear clipper sees it counter-clockwise */
    for (int k = 0; k < pg->count; k++)
      idx[k] = k;
    if (pg->count <= BM_FACE_MAX && convex2(q, idx, pg->count)) {
      bm_face_t *f = &b->face[b->nface++];
      *f = (bm_face_t){p, pr->object, pg->n, pg->d, b->nvertex, pg->count, px_v3(0, 0, 0), 0.0};
      for (int k = 0; k < pg->count; k++)
        b->vertex[b->nvertex++] = v[flip ? pg->count - 1 - k : k];
      continue;
    }
    int nt = ear_clip(q, pg->count, idx, tri);
    if (nt < 0) {
      snprintf(why, cap, "object '%s': a polygon that is not simple cannot be cut into triangles",
               s->object[pr->object].name);
      st = RT_EINVAL;
      break;
    }
    for (int t = 0; t < nt; t++) {
      bm_face_t *f = &b->face[b->nface++];
      *f = (bm_face_t){p, pr->object, pg->n, pg->d, b->nvertex, 3, px_v3(0, 0, 0), 0.0};
      for (int k = 0; k < 3; k++) {
        int i = tri[3 * t + (flip ? 2 - k : k)];
        b->vertex[b->nvertex++] = v[i];
      }
    }
  }
  b->face_of_prim[s->nprim] = b->nface;
  for (int k = 0; k < b->nface && st == RT_OK; k++) {
    bm_face_t *f = &b->face[k];
    if (f->count == 0) {
      f->radius = INFINITY;
      continue;
    }
    px_vec3_t c = px_v3(0, 0, 0);
    for (int i = 0; i < f->count; i++)
      c = px_v3_add(c, b->vertex[f->first + i]);
    f->c = px_v3_scale(c, 1.0 / f->count);
    for (int i = 0; i < f->count; i++)
      f->radius = fmax(f->radius, px_v3_norm(px_v3_sub(b->vertex[f->first + i], f->c)));
  }
  free(q);
  free(idx);
  free(tri);
  if (st != RT_OK) {
    bm_scene_free(b);
    return st;
  }
  double ext = fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
  b->scale = isfinite(ext) && ext > 0 ? ext : 1.0;
  return RT_OK;
}
