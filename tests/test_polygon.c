/* test_polygon.c -- convex polygons in a parameter plane (paraxial/polygon.h): area and centroid
 * (exact far from the origin, PX_ESINGULAR without area), the convexity test, splitting by a
 * line (through vertices and edges, a missed line, bad lines, the vertex capacity), intersection
 * and subtraction (exact overlaps, and on 1000 random pairs: the pieces and the intersection
 * tile p, are convex and do not overlap), the sliver threshold, the piece capacity, and mapping
 * (area times det, counter-clockwise again under a reflection). */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "cmocka_main.h"
#include "paraxial/paraxial.h"

static px_poly2_t poly(int n, const double (*v)[2]) {
  px_poly2_t p;
  memset(&p, 0, sizeof p);
  p.n = n;
  for (int k = 0; k < n; k++) {
    p.v[k][0] = v[k][0];
    p.v[k][1] = v[k][1];
  }
  return p;
}

/* The axis-aligned rectangle [x0, x1] x [y0, y1], counter-clockwise from (x0, y0). */
static px_poly2_t rect(double x0, double y0, double x1, double y1) {
  const double v[4][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  return poly(4, v);
}

/* The regular n-gon of circumradius r about (cx, cy), its first vertex at angle phi. */
static px_poly2_t regular(int n, double cx, double cy, double r, double phi) {
  px_poly2_t p;
  memset(&p, 0, sizeof p);
  p.n = n;
  for (int k = 0; k < n; k++) {
    double t = phi + 2.0 * M_PI * k / n;
    p.v[k][0] = cx + r * cos(t);
    p.v[k][1] = cy + r * sin(t);
  }
  return p;
}

/* A fixed-seed 64-bit LCG (Knuth's MMIX constants): uniform doubles in [0, 1). */
static uint64_t lcg_state = 0x9e3779b97f4a7c15u;
static double uniform(void) {
  lcg_state = lcg_state * 6364136223846793005u + 1442695040888963407u;
  return (double)(lcg_state >> 11) * 0x1.0p-53;
}
static double uniform_in(double lo, double hi) {
  return lo + (hi - lo) * uniform();
}

static double cross(const double o[2], const double a[2], const double b[2]) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* The convex hull (Andrew's monotone chain, collinear points dropped) of m points, CCW. */
static px_poly2_t hull(int m, double (*pt)[2]) {
  for (int i = 1; i < m; i++) /* insertion sort by (x, y) */
    for (int j = i; j > 0 && (pt[j][0] < pt[j - 1][0] ||
                              (pt[j][0] == pt[j - 1][0] && pt[j][1] < pt[j - 1][1]));
         j--) {
      double tx = pt[j][0], ty = pt[j][1];
      pt[j][0] = pt[j - 1][0];
      pt[j][1] = pt[j - 1][1];
      pt[j - 1][0] = tx;
      pt[j - 1][1] = ty;
    }
  double h[2 * PX_POLY_MAX][2];
  int k = 0;
  for (int i = 0; i < m; i++) { /* lower hull */
    while (k >= 2 && cross(h[k - 2], h[k - 1], pt[i]) <= 0.0)
      k--;
    h[k][0] = pt[i][0];
    h[k++][1] = pt[i][1];
  }
  for (int i = m - 2, lo = k + 1; i >= 0; i--) { /* upper hull */
    while (k >= lo && cross(h[k - 2], h[k - 1], pt[i]) <= 0.0)
      k--;
    h[k][0] = pt[i][0];
    h[k++][1] = pt[i][1];
  }
  return poly(k - 1, (const double(*)[2])h);
}

/* A random convex polygon: a regular polygon of random centre, radius and rotation, or the hull
 * of random points in a disc, alternately; at most 12 vertices. */
static px_poly2_t random_convex(int which) {
  double cx = uniform_in(-1.0, 1.0), cy = uniform_in(-1.0, 1.0), r = uniform_in(0.1, 1.5);
  if (which % 2 == 0)
    return regular(3 + (int)(uniform() * 10.0), cx, cy, r, uniform_in(0.0, 2.0 * M_PI));
  for (;;) {
    double pt[12][2];
    int m = 3 + (int)(uniform() * 10.0);
    for (int i = 0; i < m; i++) {
      double t = uniform_in(0.0, 2.0 * M_PI), s = r * sqrt(uniform());
      pt[i][0] = cx + s * cos(t);
      pt[i][1] = cy + s * sin(t);
    }
    px_poly2_t p = hull(m, pt);
    if (p.n >= 3 && px_poly2_area(&p) > 1e-3 * r * r)
      return p;
  }
}

static double overlap_area(const px_poly2_t *p, const px_poly2_t *q) {
  px_poly2_t r;
  assert_int_equal(px_poly2_intersect(p, q, &r), PX_OK);
  return px_poly2_area(&r);
}

static void area_and_centroid(void **state) {
  (void)state;
  double c[2];
  px_poly2_t sq = rect(0.0, 0.0, 1.0, 1.0);
  assert_close(px_poly2_area(&sq), 1.0, 1e-16, 0.0);
  assert_int_equal(px_poly2_centroid(&sq, c), PX_OK);
  assert_close(c[0], 0.5, 1e-15, 0.0);
  assert_close(c[1], 0.5, 1e-15, 0.0);
  /* the same square starting at another vertex */
  const double sv[4][2] = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
  sq = poly(4, sv);
  assert_close(px_poly2_area(&sq), 1.0, 1e-16, 0.0);
  const double tv[3][2] = {{1, 1}, {4, 1}, {1, 3}};
  px_poly2_t tri = poly(3, tv);
  assert_close(px_poly2_area(&tri), 3.0, 1e-15, 0.0);
  assert_int_equal(px_poly2_centroid(&tri, c), PX_OK);
  assert_close(c[0], 2.0, 1e-15, 0.0);
  assert_close(c[1], 5.0 / 3.0, 1e-15, 0.0);
  /* clockwise: negative area */
  const double cw[3][2] = {{1, 1}, {1, 3}, {4, 1}};
  px_poly2_t tcw = poly(3, cw);
  assert_close(px_poly2_area(&tcw), -3.0, 1e-15, 0.0);
  /* far from the origin the products of coordinates (1e16) have ulp 2: about the first vertex
   * the area loses no digit */
  double o = 1e8;
  px_poly2_t far = rect(o, o, o + 1.0, o + 1.0);
  assert_close(px_poly2_area(&far), 1.0, 1e-15, 0.0);
  assert_int_equal(px_poly2_centroid(&far, c), PX_OK);
  assert_close(c[0] - o, 0.5, 0.0, 1e-12);
  assert_close(c[1] - o, 0.5, 0.0, 1e-12);
  const double fv[3][2] = {{o + 0.125, o - 0.25}, {o + 0.625, o + 0.5}, {o - 0.375, o + 0.25}};
  px_poly2_t ftri = poly(3, fv);
  /* twice the area: 0.5 * 0.5 - (-0.5) * 0.75 = 0.625 */
  assert_close(px_poly2_area(&ftri), 0.3125, 1e-15, 0.0);
  assert_int_equal(px_poly2_centroid(&ftri, c), PX_OK);
  assert_close(c[0] - o, 0.125, 0.0, 1e-12);
  assert_close(c[1] - o, 0.5 / 3.0, 0.0, 1.5e-8); /* o + 1/6 to the ulp of 1e8, 1.49e-8 */
  /* a regular 7-gon: (n/2) r^2 sin(2 pi/n), its centroid the centre */
  px_poly2_t hept = regular(7, -2.0, 3.0, 1.5, 0.3);
  assert_close(px_poly2_area(&hept), 3.5 * 2.25 * sin(2.0 * M_PI / 7.0), 1e-14, 0.0);
  assert_int_equal(px_poly2_centroid(&hept, c), PX_OK);
  assert_close(c[0], -2.0, 0.0, 1e-14);
  assert_close(c[1], 3.0, 0.0, 1e-14);
  /* no area: fewer than 3 vertices, collinear, clockwise */
  const double lv[3][2] = {{0, 0}, {1, 1}, {2, 2}};
  px_poly2_t line = poly(3, lv);
  assert_true(px_poly2_area(&line) == 0.0);
  c[0] = c[1] = -7.0;
  assert_int_equal(px_poly2_centroid(&line, c), PX_ESINGULAR);
  assert_true(c[0] == -7.0 && c[1] == -7.0); /* nothing written */
  assert_int_equal(px_poly2_centroid(&tcw, c), PX_ESINGULAR);
  px_poly2_t two = poly(2, sv);
  assert_true(px_poly2_area(&two) == 0.0);
  assert_int_equal(px_poly2_centroid(&two, c), PX_ESINGULAR);
  px_poly2_t none = poly(0, sv);
  assert_true(px_poly2_area(&none) == 0.0);
  assert_int_equal(px_poly2_centroid(&none, c), PX_ESINGULAR);
}

static void convexity(void **state) {
  (void)state;
  px_poly2_t sq = rect(0.0, 0.0, 1.0, 1.0);
  assert_true(px_poly2_is_convex(&sq));
  px_poly2_t hept = regular(7, 1e8, -1e8, 1e-3, 0.1);
  assert_true(px_poly2_is_convex(&hept));
  px_poly2_t big = regular(PX_POLY_MAX, 0.0, 0.0, 1.0, 0.0);
  assert_true(px_poly2_is_convex(&big));
  /* a vertex in the middle of an edge is still convex */
  const double mid[5][2] = {{0, 0}, {0.5, 0}, {1, 0}, {1, 1}, {0, 1}};
  px_poly2_t m = poly(5, mid);
  assert_true(px_poly2_is_convex(&m));
  /* clockwise */
  const double cw[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  px_poly2_t c = poly(4, cw);
  assert_false(px_poly2_is_convex(&c));
  /* an arrow head: counter-clockwise, positive area, a right turn at (0.5, 0.3) */
  const double arrow[4][2] = {{0, 0}, {0.5, 0.3}, {1, 0}, {0.5, 1}};
  px_poly2_t a = poly(4, arrow);
  assert_true(px_poly2_area(&a) > 0.0);
  assert_false(px_poly2_is_convex(&a));
  /* a right turn just beyond the 1e-12 tolerance, and one within it */
  const double dent[4][2] = {{0, 0}, {0.5, 1e-11}, {1, 0}, {0.5, 1}};
  px_poly2_t d = poly(4, dent);
  assert_false(px_poly2_is_convex(&d));
  const double flat[4][2] = {{0, 0}, {0.5, 1e-14}, {1, 0}, {0.5, 1}};
  d = poly(4, flat);
  assert_true(px_poly2_is_convex(&d));
  /* not finite */
  px_poly2_t bad = sq;
  bad.v[2][1] = NAN;
  assert_false(px_poly2_is_convex(&bad));
  bad = sq;
  bad.v[0][0] = -INFINITY;
  assert_false(px_poly2_is_convex(&bad));
  /* too few vertices, too many, no area */
  px_poly2_t few = sq;
  few.n = 2;
  assert_false(px_poly2_is_convex(&few));
  few.n = 0;
  assert_false(px_poly2_is_convex(&few));
  px_poly2_t many = big;
  many.n = PX_POLY_MAX + 1;
  assert_false(px_poly2_is_convex(&many));
  const double lv[3][2] = {{0, 0}, {1, 1}, {2, 2}};
  px_poly2_t line = poly(3, lv);
  assert_false(px_poly2_is_convex(&line));
}

static void split_by_a_line(void **state) {
  (void)state;
  px_poly2_t sq = rect(0.0, 0.0, 1.0, 1.0), in, out;
  /* x <= 0.25 */
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, 0.25, &in, &out), PX_OK);
  assert_int_equal(in.n, 4);
  assert_int_equal(out.n, 4);
  assert_close(px_poly2_area(&in), 0.25, 1e-15, 0.0);
  assert_close(px_poly2_area(&out), 0.75, 1e-15, 0.0);
  assert_close(px_poly2_area(&in) + px_poly2_area(&out), px_poly2_area(&sq), 1e-15, 0.0);
  assert_true(px_poly2_is_convex(&in));
  assert_true(px_poly2_is_convex(&out));
  for (int k = 0; k < in.n; k++)
    assert_true(in.v[k][0] <= 0.25);
  for (int k = 0; k < out.n; k++)
    assert_true(out.v[k][0] >= 0.25);
  /* the same line written -x >= -0.25 swaps the parts */
  px_poly2_t in2, out2;
  assert_int_equal(px_poly2_split(&sq, -2.0, 0.0, -0.5, &in2, &out2), PX_OK);
  assert_close(px_poly2_area(&in2), 0.75, 1e-15, 0.0);
  assert_close(px_poly2_area(&out2), 0.25, 1e-15, 0.0);
  /* an oblique line through the middle of a hexagon: halves */
  px_poly2_t hex = regular(6, 3.0, -1.0, 2.0, 0.2);
  double a = cos(0.7), b = sin(0.7);
  assert_int_equal(px_poly2_split(&hex, a, b, a * 3.0 - b, &in, &out), PX_OK);
  assert_close(px_poly2_area(&in), 0.5 * px_poly2_area(&hex), 1e-14, 0.0);
  assert_close(px_poly2_area(&out), 0.5 * px_poly2_area(&hex), 1e-14, 0.0);
  assert_true(px_poly2_is_convex(&in));
  assert_true(px_poly2_is_convex(&out));
  /* a line missing the polygon: one part whole, the other empty */
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, -1.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 0);
  assert_int_equal(out.n, 4);
  assert_memory_equal(out.v, sq.v, sizeof(double) * 2 * 4);
  assert_int_equal(px_poly2_split(&sq, 1.0, 1.0, 5.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 4);
  assert_int_equal(out.n, 0);
  /* through two opposite vertices exactly: two triangles sharing the diagonal */
  assert_int_equal(px_poly2_split(&sq, 1.0, 1.0, 1.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 3);
  assert_int_equal(out.n, 3);
  assert_true(px_poly2_area(&in) == 0.5);
  assert_true(px_poly2_area(&out) == 0.5);
  assert_true(px_poly2_is_convex(&in));
  assert_true(px_poly2_is_convex(&out));
  /* touching one vertex only: that side is empty, not a point */
  assert_int_equal(px_poly2_split(&sq, 1.0, 1.0, 0.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 0);
  assert_int_equal(out.n, 4);
  /* along an edge: that side is empty, not a segment */
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, 1.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 4);
  assert_int_equal(out.n, 0);
  assert_int_equal(px_poly2_split(&sq, 0.0, -1.0, 0.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 4);
  assert_int_equal(out.n, 0);
  /* through one vertex and across the opposite edges */
  assert_int_equal(px_poly2_split(&sq, 1.0, -2.0, 0.0, &in, &out), PX_OK);
  assert_int_equal(in.n, 4);
  assert_int_equal(out.n, 3);
  assert_close(px_poly2_area(&out), 0.25, 1e-15, 0.0); /* (0,0), (1,0), (1,0.5) */
  assert_close(px_poly2_area(&in), 0.75, 1e-15, 0.0);
  /* either part may be NULL */
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, 0.25, NULL, &out), PX_OK);
  assert_close(px_poly2_area(&out), 0.75, 1e-15, 0.0);
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, 0.25, &in, NULL), PX_OK);
  assert_close(px_poly2_area(&in), 0.25, 1e-15, 0.0);
  /* far from the origin */
  px_poly2_t far = rect(1e8, 1e8, 1e8 + 1.0, 1e8 + 1.0);
  assert_int_equal(px_poly2_split(&far, 1.0, 0.0, 1e8 + 0.25, &in, &out), PX_OK);
  assert_close(px_poly2_area(&in), 0.25, 1e-15, 0.0);
  assert_close(px_poly2_area(&out), 0.75, 1e-15, 0.0);
}

static void split_bad_lines(void **state) {
  (void)state;
  px_poly2_t sq = rect(0.0, 0.0, 1.0, 1.0), in, out;
  in.n = out.n = -5;
  assert_int_equal(px_poly2_split(&sq, 0.0, 0.0, 0.5, &in, &out), PX_EINVAL);
  assert_int_equal(px_poly2_split(&sq, 0.0, 0.0, 0.0, &in, &out), PX_EINVAL);
  assert_int_equal(px_poly2_split(&sq, NAN, 1.0, 0.5, &in, &out), PX_EINVAL);
  assert_int_equal(px_poly2_split(&sq, 1.0, INFINITY, 0.5, &in, &out), PX_EINVAL);
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, NAN, &in, &out), PX_EINVAL);
  assert_int_equal(px_poly2_split(&sq, 1.0, 0.0, -INFINITY, &in, &out), PX_EINVAL);
  assert_int_equal(in.n, -5); /* nothing written */
  assert_int_equal(out.n, -5);
  /* a clip polygon with a non-finite vertex gives a non-finite line */
  px_poly2_t clip = rect(0.0, 0.0, 0.5, 0.5), r;
  clip.v[1][0] = NAN;
  assert_int_equal(px_poly2_intersect(&sq, &clip, &r), PX_EINVAL);
  px_poly2_t pieces[4];
  int count;
  assert_int_equal(px_poly2_subtract(&sq, &clip, 0.0, pieces, 4, &count), PX_EINVAL);
}

/* A part of more than PX_POLY_MAX vertices cannot be held: a regular PX_POLY_MAX-gon with one
 * vertex cut off would have PX_POLY_MAX + 1. Fewer vertices split through. */
static void split_capacity(void **state) {
  (void)state;
  px_poly2_t big = regular(PX_POLY_MAX, 0.0, 0.0, 1.0, 0.0), in, out;
  /* x <= 0.999 cuts off the vertex (1, 0) alone (its neighbours have x = cos(2 pi/32) ~ 0.981) */
  assert_true(big.v[1][0] < 0.99 && big.v[PX_POLY_MAX - 1][0] < 0.99);
  assert_int_equal(px_poly2_split(&big, 1.0, 0.0, 0.999, &in, &out), PX_ECAPACITY);
  assert_int_equal(px_poly2_split(&big, -1.0, 0.0, -0.999, NULL, &out), PX_ECAPACITY);
  px_poly2_t r;
  px_poly2_t clip = rect(-2.0, -2.0, 0.999, 2.0);
  assert_int_equal(px_poly2_intersect(&big, &clip, &r), PX_ECAPACITY);
  px_poly2_t pieces[4];
  int count;
  assert_int_equal(px_poly2_subtract(&big, &clip, 0.0, pieces, 4, &count), PX_ECAPACITY);
  /* one vertex fewer: cutting off the first vertex gives PX_POLY_MAX exactly */
  px_poly2_t p31 = regular(PX_POLY_MAX - 1, 0.0, 0.0, 1.0, 0.0);
  assert_int_equal(px_poly2_split(&p31, 1.0, 0.0, 0.999, &in, &out), PX_OK);
  assert_int_equal(in.n, PX_POLY_MAX);
  assert_int_equal(out.n, 3);
  assert_true(px_poly2_is_convex(&in));
  assert_true(px_poly2_is_convex(&out));
  assert_close(px_poly2_area(&in) + px_poly2_area(&out), px_poly2_area(&p31), 1e-14, 0.0);
  /* a line through the centre of the PX_POLY_MAX-gon and two of its vertices: halves */
  assert_int_equal(px_poly2_split(&big, 0.0, 1.0, 0.0, &in, &out), PX_OK);
  assert_true(px_poly2_is_convex(&in));
  assert_true(px_poly2_is_convex(&out));
  assert_close(px_poly2_area(&in), 0.5 * px_poly2_area(&big), 1e-14, 0.0);
  assert_close(px_poly2_area(&out), 0.5 * px_poly2_area(&big), 1e-14, 0.0);
}

static void intersect_exact_cases(void **state) {
  (void)state;
  px_poly2_t a = rect(0.0, 0.0, 2.0, 2.0), b = rect(1.0, 1.0, 3.0, 3.0), r;
  assert_int_equal(px_poly2_intersect(&a, &b, &r), PX_OK);
  assert_true(px_poly2_area(&r) == 1.0);
  assert_true(px_poly2_is_convex(&r));
  for (int k = 0; k < r.n; k++) {
    assert_true(r.v[k][0] >= 1.0 && r.v[k][0] <= 2.0);
    assert_true(r.v[k][1] >= 1.0 && r.v[k][1] <= 2.0);
  }
  assert_int_equal(px_poly2_intersect(&b, &a, &r), PX_OK);
  assert_true(px_poly2_area(&r) == 1.0);
  /* a square and its rotation by 45 degrees about the common centre: an octagon of area
   * 2 (sqrt 2 - 1) s^2 for side s = 2 */
  px_poly2_t d = regular(4, 1.0, 1.0, sqrt(2.0), 0.0);
  assert_int_equal(px_poly2_intersect(&a, &d, &r), PX_OK);
  assert_int_equal(r.n, 8);
  assert_true(px_poly2_is_convex(&r));
  assert_close(px_poly2_area(&r), 8.0 * (sqrt(2.0) - 1.0), 1e-14, 0.0);
  /* disjoint */
  px_poly2_t c = rect(5.0, 0.0, 6.0, 1.0);
  assert_int_equal(px_poly2_intersect(&a, &c, &r), PX_OK);
  assert_int_equal(r.n, 0);
  assert_true(px_poly2_area(&r) == 0.0);
  /* disjoint but with overlapping bounding boxes: a triangle beyond the square's corner */
  const double tv[3][2] = {{2.5, 2.0}, {3.0, 2.0}, {2.0, 3.0}};
  px_poly2_t t = poly(3, tv);
  assert_int_equal(px_poly2_intersect(&a, &t, &r), PX_OK);
  assert_int_equal(r.n, 0);
  /* touching along an edge or at a corner: nothing */
  px_poly2_t e = rect(2.0, 0.0, 3.0, 2.0);
  assert_int_equal(px_poly2_intersect(&a, &e, &r), PX_OK);
  assert_int_equal(r.n, 0);
  px_poly2_t k = rect(2.0, 2.0, 3.0, 3.0);
  assert_int_equal(px_poly2_intersect(&a, &k, &r), PX_OK);
  assert_int_equal(r.n, 0);
  /* a clip containing p: p unchanged */
  px_poly2_t p = regular(9, 0.5, 0.25, 0.2, 1.0), big = rect(-10.0, -10.0, 10.0, 10.0);
  assert_int_equal(px_poly2_intersect(&p, &big, &r), PX_OK);
  assert_int_equal(r.n, p.n);
  assert_true(px_poly2_area(&r) == px_poly2_area(&p));
  assert_memory_equal(r.v, p.v, sizeof(double) * 2 * (size_t)p.n);
  /* p containing the clip: the clip */
  px_poly2_t small = rect(0.5, 0.5, 1.5, 1.25);
  assert_int_equal(px_poly2_intersect(&a, &small, &r), PX_OK);
  assert_true(px_poly2_area(&r) == 0.75);
  assert_int_equal(r.n, 4);
  /* with itself */
  assert_int_equal(px_poly2_intersect(&p, &p, &r), PX_OK);
  assert_close(px_poly2_area(&r), px_poly2_area(&p), 1e-14, 0.0);
  /* far from the origin */
  px_poly2_t fa = rect(1e8, 1e8, 1e8 + 2.0, 1e8 + 2.0),
             fb = rect(1e8 + 1.0, 1e8 + 1.5, 1e8 + 3.0, 1e8 + 3.0);
  assert_int_equal(px_poly2_intersect(&fa, &fb, &r), PX_OK);
  assert_close(px_poly2_area(&r), 0.5, 1e-15, 0.0);
}

/* A clip polygon whose two nearly equal vertices make an edge of rounding's length (1.4e-17,
 * beside sides of 1): its direction says nothing, here the square's diagonal. Such an edge bounds
 * nothing: the pieces left are p less the square, none reaching into it. Before, the diagonal cut
 * the square and left half of it in a piece (the beam renderer's slotted plate drawn with the
 * background over it, docs/journal/2026-12-06-highlight-guard.md). */
static void subtract_ignores_rounding_edges(void **state) {
  (void)state;
  px_poly2_t p = rect(-1.0, -1.0, 2.0, 2.0), sq = rect(0.0, 0.0, 1.0, 1.0), out[8];
  px_poly2_t clip = {5, {{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}, {1e-17, 1e-17}}};
  int count = -1;
  assert_int_equal(px_poly2_subtract(&p, &clip, 0.0, out, 8, &count), PX_OK);
  double total = 0.0;
  for (int k = 0; k < count; k++) {
    px_poly2_t in;
    assert_int_equal(px_poly2_intersect(&out[k], &sq, &in), PX_OK);
    assert_true(in.n == 0 || px_poly2_area(&in) <= 1e-15);
    total += px_poly2_area(&out[k]);
  }
  assert_close(total, 8.0, 1e-14, 0.0);
  /* and an intersection with it is the square */
  px_poly2_t r;
  assert_int_equal(px_poly2_intersect(&p, &clip, &r), PX_OK);
  assert_close(px_poly2_area(&r), 1.0, 1e-14, 0.0);
}

static void subtract_exact_cases(void **state) {
  (void)state;
  /* a unit square inside [-1, 2]^2: one piece beyond each of its edges */
  px_poly2_t p = rect(-1.0, -1.0, 2.0, 2.0), clip = rect(0.0, 0.0, 1.0, 1.0), out[4];
  int count = -1;
  assert_int_equal(px_poly2_subtract(&p, &clip, 0.0, out, 4, &count), PX_OK);
  assert_int_equal(count, 4);
  /* piece 0 beyond y = 0; piece 1 beyond x = 1 within y >= 0; piece 2 beyond y = 1 within
   * x <= 1; piece 3 beyond x = 0 within 0 <= y <= 1 */
  assert_true(px_poly2_area(&out[0]) == 3.0);
  assert_true(px_poly2_area(&out[1]) == 2.0);
  assert_true(px_poly2_area(&out[2]) == 2.0);
  assert_true(px_poly2_area(&out[3]) == 1.0);
  for (int k = 0; k < 4; k++)
    assert_true(px_poly2_is_convex(&out[k]));
  /* a clip containing p: nothing left */
  count = -1;
  assert_int_equal(px_poly2_subtract(&clip, &p, 0.0, out, 4, &count), PX_OK);
  assert_int_equal(count, 0);
  /* p minus itself: nothing */
  count = -1;
  assert_int_equal(px_poly2_subtract(&p, &p, 0.0, out, 4, &count), PX_OK);
  assert_int_equal(count, 0);
  /* a disjoint clip: p whole, as the piece beyond the clip edge that separates them */
  px_poly2_t far = rect(5.0, -1.0, 6.0, 2.0);
  assert_int_equal(px_poly2_subtract(&p, &far, 0.0, out, 4, &count), PX_OK);
  assert_int_equal(count, 1);
  assert_true(px_poly2_area(&out[0]) == 9.0);
  assert_int_equal(out[0].n, 4);
  /* a clip over one side: one piece */
  px_poly2_t half = rect(0.5, -5.0, 5.0, 5.0);
  assert_int_equal(px_poly2_subtract(&p, &half, 0.0, out, 4, &count), PX_OK);
  assert_int_equal(count, 1);
  assert_true(px_poly2_area(&out[0]) == 4.5);
  for (int k = 0; k < out[0].n; k++)
    assert_true(out[0].v[k][0] <= 0.5);
}

/* More pieces than `cap`: PX_ECAPACITY, whatever the order. */
static void subtract_capacity(void **state) {
  (void)state;
  px_poly2_t p = rect(-1.0, -1.0, 2.0, 2.0), clip = rect(0.0, 0.0, 1.0, 1.0), out[4];
  int count = -1;
  for (int cap = 0; cap < 4; cap++)
    assert_int_equal(px_poly2_subtract(&p, &clip, 0.0, out, cap, &count), PX_ECAPACITY);
  assert_int_equal(px_poly2_subtract(&p, &clip, 0.0, out, 4, &count), PX_OK);
  assert_int_equal(count, 4);
  /* an octagon clip inside p: 8 pieces */
  px_poly2_t oct = regular(8, 0.5, 0.5, 0.5, 0.1), many[8];
  assert_int_equal(px_poly2_subtract(&p, &oct, 0.0, many, 7, &count), PX_ECAPACITY);
  assert_int_equal(px_poly2_subtract(&p, &oct, 0.0, many, 8, &count), PX_OK);
  assert_int_equal(count, 8);
  /* the pieces that min_area drops (areas 3, 2, 2, 1 here) do not count */
  assert_int_equal(px_poly2_subtract(&p, &clip, 1.5, out, 3, &count), PX_OK);
  assert_int_equal(count, 3);
  assert_int_equal(px_poly2_subtract(&p, &clip, 1.5, out, 2, &count), PX_ECAPACITY);
  assert_int_equal(px_poly2_subtract(&p, &clip, 2.5, out, 1, &count), PX_OK);
  assert_int_equal(count, 1);
  assert_true(px_poly2_area(&out[0]) == 3.0);
  assert_int_equal(px_poly2_subtract(&p, &clip, 2.5, out, 0, &count), PX_ECAPACITY);
  assert_int_equal(px_poly2_subtract(&p, &clip, 3.0, out, 0, &count), PX_OK);
  assert_int_equal(count, 0);
}

/* A clip edge grazing a corner of p leaves a triangle of area eps^2 / 2 beyond it: kept below
 * min_area, dropped at min_area above its area. */
static void subtract_drops_slivers(void **state) {
  (void)state;
  px_poly2_t p = rect(0.0, 0.0, 1.0, 1.0), out[3];
  for (double eps = 1e-3; eps >= 1e-7; eps *= 0.1) {
    /* a triangle whose first edge lies on x + y = eps, its inside x + y > eps, the rest of p
     * well within its other edges */
    const double cv[3][2] = {{-5.0, 5.0 + eps}, {5.0 + eps, -5.0}, {10.0, 10.0}};
    px_poly2_t clip = poly(3, cv);
    assert_true(px_poly2_is_convex(&clip));
    double sliver = 0.5 * eps * eps;
    int count = -1;
    assert_int_equal(px_poly2_subtract(&p, &clip, 0.0, out, 3, &count), PX_OK);
    assert_int_equal(count, 1);
    assert_int_equal(out[0].n, 3);
    assert_close(px_poly2_area(&out[0]), sliver, 1e-6, 0.0);
    assert_true(px_poly2_is_convex(&out[0]));
    px_poly2_t r;
    assert_int_equal(px_poly2_intersect(&p, &clip, &r), PX_OK);
    assert_close(px_poly2_area(&r) + px_poly2_area(&out[0]), 1.0, 1e-15, 0.0);
    count = -1;
    assert_int_equal(px_poly2_subtract(&p, &clip, 0.5 * sliver, out, 3, &count), PX_OK);
    assert_int_equal(count, 1);
    assert_close(px_poly2_area(&out[0]), sliver, 1e-6, 0.0);
    count = -1;
    assert_int_equal(px_poly2_subtract(&p, &clip, 2.0 * sliver, out, 3, &count), PX_OK);
    assert_int_equal(count, 0);
    /* only the sliver is dropped: a piece larger than min_area beyond another edge stays */
    px_poly2_t wide = rect(0.0, 0.0, 12.0, 1.0);
    count = -1;
    assert_int_equal(px_poly2_subtract(&wide, &clip, 2.0 * sliver, out, 3, &count), PX_OK);
    assert_int_equal(count, 1);
    assert_true(px_poly2_area(&out[0]) > 1.0);
    for (int k = 0; k < out[0].n; k++)
      assert_true(out[0].v[k][0] > 5.0);
  }
}

/* For random pairs of convex polygons: p inside clip and the pieces of p outside it tile p
 * (their areas sum to p's), every piece is convex, the pieces do not overlap each other or the
 * clip, and intersection is symmetric in area. */
static void random_pairs_tile(void **state) {
  (void)state;
  lcg_state = 0x243f6a8885a308d3u;
  int nonempty = 0, partial = 0;
  for (int trial = 0; trial < 1000; trial++) {
    px_poly2_t p = random_convex(trial), clip = random_convex(trial / 2);
    assert_true(px_poly2_is_convex(&p));
    assert_true(px_poly2_is_convex(&clip));
    double ap = px_poly2_area(&p), tol = 1e-12 * ap;
    px_poly2_t in, in2, pieces[PX_POLY_MAX];
    int count = -1;
    assert_int_equal(px_poly2_intersect(&p, &clip, &in), PX_OK);
    assert_int_equal(px_poly2_intersect(&clip, &p, &in2), PX_OK);
    double ain = px_poly2_area(&in);
    assert_true(ain >= 0.0);
    if (in.n > 0) {
      nonempty++;
      assert_true(px_poly2_is_convex(&in));
    }
    assert_close(ain, px_poly2_area(&in2), 1e-12, 1e-12 * ap);
    assert_true(ain <= ap * (1.0 + 1e-12));
    assert_true(ain <= px_poly2_area(&clip) * (1.0 + 1e-12));
    assert_int_equal(px_poly2_subtract(&p, &clip, 0.0, pieces, PX_POLY_MAX, &count), PX_OK);
    assert_true(count >= 0 && count <= clip.n);
    if (count > 0 && in.n > 0)
      partial++;
    double sum = ain;
    for (int i = 0; i < count; i++) {
      assert_true(px_poly2_is_convex(&pieces[i]));
      sum += px_poly2_area(&pieces[i]);
      assert_true(overlap_area(&pieces[i], &clip) <= tol);
      for (int j = 0; j < i; j++)
        assert_true(overlap_area(&pieces[i], &pieces[j]) <= tol);
      /* inside p */
      assert_close(overlap_area(&pieces[i], &p), px_poly2_area(&pieces[i]), 1e-12, tol);
    }
    assert_close(sum, ap, 1e-12, 0.0);
  }
  /* the sample covers the cases: overlapping pairs, and p partly outside the clip */
  assert_true(nonempty > 300);
  assert_true(partial > 300);
}

static void map_keeps_area_times_det(void **state) {
  (void)state;
  px_poly2_t sq = rect(0.0, 0.0, 1.0, 1.0), hept = regular(7, 0.3, -0.2, 0.8, 0.4);
  double c0[2], c1[2], off[2] = {5.0, -3.0};
  /* rotation by 30 degrees and scale by 2: det 4 */
  double cs = 2.0 * cos(M_PI / 6.0), sn = 2.0 * sin(M_PI / 6.0);
  px_mat2_t rot = px_mat2(cs, -sn, sn, cs);
  px_poly2_t m = px_poly2_map(&sq, rot, off);
  assert_int_equal(m.n, 4);
  assert_close(px_poly2_area(&m), 4.0, 1e-15, 0.0);
  assert_true(px_poly2_is_convex(&m));
  assert_close(m.v[0][0], 5.0, 1e-15, 0.0); /* (0, 0) -> off */
  assert_close(m.v[0][1], -3.0, 1e-15, 0.0);
  assert_close(m.v[1][0], 5.0 + cs, 1e-15, 0.0); /* (1, 0) -> off + first column */
  assert_close(m.v[1][1], -3.0 + sn, 1e-15, 0.0);
  m = px_poly2_map(&hept, rot, off);
  assert_close(px_poly2_area(&m), 4.0 * px_poly2_area(&hept), 1e-14, 0.0);
  assert_true(px_poly2_is_convex(&m));
  /* the centroid maps with the polygon */
  assert_int_equal(px_poly2_centroid(&hept, c0), PX_OK);
  assert_int_equal(px_poly2_centroid(&m, c1), PX_OK);
  assert_close(c1[0], cs * c0[0] - sn * c0[1] + off[0], 0.0, 1e-14);
  assert_close(c1[1], sn * c0[0] + cs * c0[1] + off[1], 0.0, 1e-14);
  /* a reflection with shear and scale: det -3 */
  px_mat2_t refl = px_mat2(-1.0, 0.5, 0.0, 3.0);
  assert_true(px_mat2_det(refl) == -3.0);
  m = px_poly2_map(&sq, refl, off);
  assert_int_equal(m.n, 4);
  assert_close(px_poly2_area(&m), 3.0, 1e-15, 0.0);
  assert_true(px_poly2_is_convex(&m));
  m = px_poly2_map(&hept, refl, off);
  assert_int_equal(m.n, 7);
  assert_close(px_poly2_area(&m), 3.0 * px_poly2_area(&hept), 1e-14, 0.0);
  assert_true(px_poly2_is_convex(&m));
  /* the same vertices, in reverse order */
  for (int k = 0; k < 7; k++) {
    const double *v = hept.v[6 - k];
    assert_close(m.v[k][0], -v[0] + 0.5 * v[1] + off[0], 0.0, 1e-15);
    assert_close(m.v[k][1], 3.0 * v[1] + off[1], 0.0, 1e-15);
  }
  assert_int_equal(px_poly2_centroid(&m, c1), PX_OK);
  assert_close(c1[0], -c0[0] + 0.5 * c0[1] + off[0], 0.0, 1e-14);
  assert_close(c1[1], 3.0 * c0[1] + off[1], 0.0, 1e-14);
  /* a mirror in the x axis */
  m = px_poly2_map(&sq, px_mat2_diag(1.0, -1.0), off);
  assert_true(px_poly2_area(&m) == 1.0);
  assert_true(px_poly2_is_convex(&m));
  /* mapped polygons clip as before, scaled by |det| */
  px_poly2_t a = rect(0.0, 0.0, 2.0, 2.0), b = rect(1.0, 1.0, 3.0, 3.0), r;
  px_poly2_t ma = px_poly2_map(&a, refl, off), mb = px_poly2_map(&b, refl, off);
  assert_int_equal(px_poly2_intersect(&ma, &mb, &r), PX_OK);
  assert_close(px_poly2_area(&r), 3.0, 1e-14, 0.0);
  /* an empty polygon stays empty */
  px_poly2_t none = sq;
  none.n = 0;
  m = px_poly2_map(&none, refl, off);
  assert_int_equal(m.n, 0);
}

/* Edge cases a first version got wrong: the capacity test counted one vertex too many (and
 * depended on where the list started), a star passed as convex, a touching polygon left a part of
 * zero area, and an empty clip polygon was taken as the whole plane. */
static void edge_cases(void **state) {
  (void)state;
  px_poly2_t p31 = regular(PX_POLY_MAX - 1, 0.0, 0.0, 1.0, 0.0), rot = p31, in, out;
  for (int k = 0; k < p31.n; k++) { /* the vertex to cut off last in the list */
    rot.v[k][0] = p31.v[(k + 1) % p31.n][0];
    rot.v[k][1] = p31.v[(k + 1) % p31.n][1];
  }
  double x0 = p31.v[0][0] - 1e-3; /* cuts off vertex 0 (at angle 0) only */
  assert_int_equal(px_poly2_split(&rot, 1.0, 0.0, x0, &in, &out), PX_OK);
  assert_int_equal(in.n, PX_POLY_MAX); /* 30 vertices kept and 2 new */
  px_poly2_t p32 = regular(PX_POLY_MAX, 0.0, 0.0, 1.0, 0.0), big = rect(-5, -5, 5, 5), r;
  assert_int_equal(px_poly2_intersect(&p32, &big, &r), PX_OK); /* a line missing it */
  assert_int_equal(r.n, PX_POLY_MAX);
  px_poly2_t star = regular(5, 0.0, 0.0, 1.0, 0.0), penta = star;
  for (int k = 0; k < 5; k++) {
    star.v[k][0] = penta.v[(2 * k) % 5][0];
    star.v[k][1] = penta.v[(2 * k) % 5][1];
  }
  assert_true(px_poly2_area(&star) > 0.0);
  assert_false(px_poly2_is_convex(&star));
  const double col[5][2] = {{0, 0}, {1, 0}, {1, 0.5}, {1, 1}, {0, 1}};
  px_poly2_t p = poly(5, col), touch = rect(1, 0, 2, 1);
  assert_int_equal(px_poly2_intersect(&p, &touch, &r), PX_OK);
  assert_int_equal(r.n, 0);
  assert_int_equal(px_poly2_split(&p, -1.0, 0.0, -1.0, &in, &out), PX_OK); /* x >= 1 */
  assert_int_equal(in.n, 0);
  px_poly2_t empty = {0}, sq = rect(0, 0, 1, 1), pieces[4];
  assert_int_equal(px_poly2_intersect(&sq, &empty, &r), PX_OK);
  assert_int_equal(r.n, 0);
  int n = -1;
  assert_int_equal(px_poly2_subtract(&sq, &empty, 0.0, pieces, 4, &n), PX_OK);
  assert_int_equal(n, 1);
  assert_true(px_poly2_area(&pieces[0]) == 1.0);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(area_and_centroid),
      cmocka_unit_test(edge_cases),
      cmocka_unit_test(convexity),
      cmocka_unit_test(split_by_a_line),
      cmocka_unit_test(split_bad_lines),
      cmocka_unit_test(split_capacity),
      cmocka_unit_test(intersect_exact_cases),
      cmocka_unit_test(subtract_exact_cases),
      cmocka_unit_test(subtract_capacity),
      cmocka_unit_test(subtract_drops_slivers),
      cmocka_unit_test(subtract_ignores_rounding_edges),
      cmocka_unit_test(random_pairs_tile),
      cmocka_unit_test(map_keeps_area_times_det),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
