/* polygon.c -- convex polygon clipping in a parameter plane (paraxial/polygon.h). Splitting by a
 * line is Sutherland and Hodgman's single-plane step; intersection and subtraction are repeated
 * splits along the clip polygon's edges. */
#include "paraxial/polygon.h"

#include <math.h>
#include <stddef.h>

double px_poly2_area(const px_poly2_t *p) {
  if (p->n < 3)
    return 0.0;
  double a = 0.0, x0 = p->v[0][0], y0 = p->v[0][1];
  for (int k = 1; k + 1 < p->n; k++)
    a += (p->v[k][0] - x0) * (p->v[k + 1][1] - y0) - (p->v[k + 1][0] - x0) * (p->v[k][1] - y0);
  return 0.5 * a;
}

px_status_t px_poly2_centroid(const px_poly2_t *p, double c[2]) {
  double a = 0.0, cx = 0.0, cy = 0.0, x0 = p->v[0][0], y0 = p->v[0][1];
  for (int k = 1; k + 1 < p->n; k++) {
    double ax = p->v[k][0] - x0, ay = p->v[k][1] - y0;
    double bx = p->v[k + 1][0] - x0, by = p->v[k + 1][1] - y0;
    double t = ax * by - bx * ay; /* twice the fan triangle's area */
    a += t;
    cx += t * (ax + bx);
    cy += t * (ay + by);
  }
  if (!(a > 0.0) || !isfinite(a))
    return PX_ESINGULAR;
  c[0] = x0 + cx / (3.0 * a);
  c[1] = y0 + cy / (3.0 * a);
  return PX_OK;
}

int px_poly2_is_convex(const px_poly2_t *p) {
  if (p->n < 3 || p->n > PX_POLY_MAX)
    return 0;
  for (int k = 0; k < p->n; k++)
    if (!isfinite(p->v[k][0]) || !isfinite(p->v[k][1]))
      return 0;
  if (!(px_poly2_area(p) > 0.0))
    return 0;
  double turn = 0.0; /* a star's turns are all left too, but it goes round more than once */
  for (int k = 0; k < p->n; k++) {
    const double *a = p->v[k], *b = p->v[(k + 1) % p->n], *c = p->v[(k + 2) % p->n];
    double ex = b[0] - a[0], ey = b[1] - a[1], fx = c[0] - b[0], fy = c[1] - b[1];
    double cr = ex * fy - ey * fx;
    if (cr < -1e-12 * hypot(ex, ey) * hypot(fx, fy))
      return 0;
    turn += atan2(cr, ex * fx + ey * fy);
  }
  return turn < 3.0 * M_PI;
}

px_status_t px_poly2_split(const px_poly2_t *p, double a, double b, double c, px_poly2_t *in,
                           px_poly2_t *out) {
  if (!isfinite(a) || !isfinite(b) || !isfinite(c) || (a == 0.0 && b == 0.0))
    return PX_EINVAL;
  px_poly2_t lo = {0}, hi = {0};
  for (int k = 0; k < p->n; k++) {
    const double *u = p->v[k], *w = p->v[(k + 1) % p->n];
    double du = a * u[0] + b * u[1] - c, dw = a * w[0] + b * w[1] - c;
    int cross = (du < 0.0 && dw > 0.0) || (du > 0.0 && dw < 0.0);
    if (lo.n + (du <= 0.0) + cross > PX_POLY_MAX || hi.n + (du >= 0.0) + cross > PX_POLY_MAX)
      return PX_ECAPACITY;
    if (du <= 0.0) {
      lo.v[lo.n][0] = u[0];
      lo.v[lo.n++][1] = u[1];
    }
    if (du >= 0.0) {
      hi.v[hi.n][0] = u[0];
      hi.v[hi.n++][1] = u[1];
    }
    if (cross) {
      double t = du / (du - dw), x = u[0] + t * (w[0] - u[0]), y = u[1] + t * (w[1] - u[1]);
      lo.v[lo.n][0] = hi.v[hi.n][0] = x;
      lo.v[lo.n++][1] = hi.v[hi.n++][1] = y;
    }
  }
  if (!(px_poly2_area(&lo) > 0.0)) /* fewer than 3 vertices, or collinear ones */
    lo.n = 0;
  if (!(px_poly2_area(&hi) > 0.0))
    hi.n = 0;
  if (in)
    *in = lo;
  if (out)
    *out = hi;
  return PX_OK;
}

/* Relative length below which an edge bounds nothing (edge_line()). */
#define PX_EDGE_REL 1e-9

/* The line of clip's edge k as a x + b y <= c for the inside (left of a counter-clockwise edge);
 * 0 for an edge shorter than PX_EDGE_REL times the polygon's extent (`extent`, the larger side of
 * its bounding box), which bounds nothing: the direction of so short an edge is rounding (a
 * clipped piece's two nearly equal vertices, 8.7e-18 apart, gave a line across the polygon, and
 * a subtraction that left part of the polygon in), while its neighbours' lines bound the polygon
 * to within its length. */
static int edge_line(const px_poly2_t *clip, int k, double extent, double *a, double *b,
                     double *c) {
  const double *u = clip->v[k], *w = clip->v[(k + 1) % clip->n];
  double ex = w[0] - u[0], ey = w[1] - u[1];
  if (fabs(ex) <= PX_EDGE_REL * extent && fabs(ey) <= PX_EDGE_REL * extent)
    return 0; /* (a NaN is kept: the split refuses its line) */
  /* left of u -> w: ex (y - uy) - ey (x - ux) >= 0, i.e. ey x - ex y <= ey ux - ex uy */
  *a = ey;
  *b = -ex;
  *c = ey * u[0] - ex * u[1];
  return 1;
}

/* The larger side of p's bounding box. */
static double extent_of(const px_poly2_t *p) {
  double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
  for (int k = 0; k < p->n; k++)
    for (int i = 0; i < 2; i++) {
      lo[i] = fmin(lo[i], p->v[k][i]);
      hi[i] = fmax(hi[i], p->v[k][i]);
    }
  return p->n > 0 ? fmax(hi[0] - lo[0], hi[1] - lo[1]) : 0.0;
}

px_status_t px_poly2_intersect(const px_poly2_t *p, const px_poly2_t *clip, px_poly2_t *out) {
  px_poly2_t cur = *p;
  double extent = extent_of(clip);
  if (clip->n < 3)
    cur.n = 0; /* an empty clip polygon covers nothing */
  for (int k = 0; k < clip->n && cur.n > 0; k++) {
    double a, b, c;
    if (!edge_line(clip, k, extent, &a, &b, &c))
      continue;
    px_poly2_t next;
    px_status_t st = px_poly2_split(&cur, a, b, c, &next, NULL);
    if (st != PX_OK)
      return st;
    cur = next;
  }
  *out = cur;
  return PX_OK;
}

px_status_t px_poly2_subtract(const px_poly2_t *p, const px_poly2_t *clip, double min_area,
                              px_poly2_t *out, int cap, int *count) {
  px_poly2_t cur = *p;
  int m = 0;
  double extent = extent_of(clip);
  for (int k = 0; clip->n >= 3 && k < clip->n && cur.n > 0; k++) {
    double a, b, c;
    if (!edge_line(clip, k, extent, &a, &b, &c))
      continue;
    px_poly2_t inside, beyond;
    px_status_t st = px_poly2_split(&cur, a, b, c, &inside, &beyond);
    if (st != PX_OK)
      return st;
    if (beyond.n > 0 && px_poly2_area(&beyond) > min_area) {
      if (m >= cap)
        return PX_ECAPACITY;
      out[m++] = beyond;
    }
    cur = inside;
  }
  if (clip->n < 3 && p->n >= 3 && px_poly2_area(p) > min_area) { /* nothing to take away */
    if (cap < 1)
      return PX_ECAPACITY;
    out[m++] = *p;
  }
  *count = m;
  return PX_OK;
}

px_poly2_t px_poly2_map(const px_poly2_t *p, px_mat2_t m, const double off[2]) {
  px_poly2_t r = {p->n, {{0}}};
  int flip = px_mat2_det(m) < 0.0;
  for (int k = 0; k < p->n; k++) {
    const double *v = p->v[flip ? p->n - 1 - k : k];
    r.v[k][0] = m.m[0][0] * v[0] + m.m[0][1] * v[1] + off[0];
    r.v[k][1] = m.m[1][0] * v[0] + m.m[1][1] * v[1] + off[1];
  }
  return r;
}
