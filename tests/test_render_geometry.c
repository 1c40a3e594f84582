/* test_render_geometry.c -- the renderer's ray-surface intersections (core/) against
 * reference/'s exact tracer (ex_quadric roots through ex_trace_axial), concave polygons, the
 * closed-polyhedron checks, and the BVH against brute force. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/builtin.h"
#include "core/intersect.h"
#include "exact/trace.h"

/* Two independent double-precision evaluations of the same root: the sphere formulas differ
 * (rt: distance of the line from the centre; ex: general quadric), each good to a few ulps of
 * the coordinates (~1e-15 here), so 1e-12 absolute on unit-size scenes leaves a wide margin yet
 * catches any wrong root or normal. */
#define HIT_TOL 1e-12

/* Deterministic pseudo-random numbers in [-1, 1) (no global state). */
static double rnd(unsigned *s) {
  *s = *s * 1664525u + 1013904223u;
  return (*s >> 8) * (2.0 / 16777216.0) - 1.0;
}

static int mat_add(rt_scene_t *s) {
  int m;
  rt_material_t mat = rt_material_default("m");
  assert_int_equal(rt_scene_add_material(s, &mat, &m), RT_OK);
  return m;
}

static rt_ray_t ray_to(px_vec3_t o, px_vec3_t target) {
  px_vec3_t d;
  px_vec3_normalize(px_vec3_sub(target, o), &d);
  return (rt_ray_t){o, d, 0.0, INFINITY, 1.0, -1, 0.0f};
}

/* The exact tracer's first hit of the ray with quadric q. */
static px_vec3_t exact_hit(const ex_quadric_t *q, const rt_ray_t *r) {
  ex_stage_t st = {*q, PX_EVENT_REFRACT, 1.5, 0};
  px_frame_t f;
  assert_int_equal(px_frame_from_z(r->d, px_vec3(0, 1, 0), &f), PX_OK);
  ex_system_t sys = {r->o, f, 1.0, &st, 1, 0.0, 0.0};
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  return ax.hit[0];
}

static void assert_vec_close(px_vec3_t a, px_vec3_t b, double tol) {
  assert_close(a.x, b.x, 0, tol);
  assert_close(a.y, b.y, 0, tol);
  assert_close(a.z, b.z, 0, tol);
}

static void sphere_hits_match_exact_quadric(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  px_vec3_t c = px_vec3(0.3, 1.2, -0.4);
  assert_int_equal(rt_scene_add_sphere(&s, c, 0.8, mat_add(&s), NULL), RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  ex_quadric_t q = ex_quadric_sphere(c, 0.8);
  unsigned seed = 1;
  for (int k = 0; k < 200; k++) {
    px_vec3_t o = px_vec3(4 * rnd(&seed), 4 * rnd(&seed), -6.0);
    px_vec3_t target = px_vec3_add(c, px_vec3(0.55 * rnd(&seed), 0.55 * rnd(&seed), 0));
    rt_ray_t r = ray_to(o, target);
    rt_hit_t h;
    assert_true(rt_intersect(&s, &r, &h));
    assert_vec_close(h.p, exact_hit(&q, &r), HIT_TOL);
    assert_close(ex_quadric_eval(&q, h.p), 0.0, 0, 1e-14);
    /* outward normal: along the quadric's gradient, away from the centre */
    assert_true(px_vec3_dot(h.n, px_vec3_sub(h.p, c)) > 0.0);
    assert_close(px_vec3_norm(h.n), 1.0, 1e-15, 0);
  }
  rt_scene_free(&s);
}

static void plane_hits_match_exact_quadric(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  px_vec3_t p = px_vec3(0, -0.5, 0), n = px_vec3(0.1, 1.0, -0.2);
  assert_int_equal(rt_scene_add_plane(&s, p, n, px_vec3(1, 0, 0), mat_add(&s), -1, 1.0, NULL),
                   RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  ex_quadric_t q = ex_quadric_plane(p, n);
  unsigned seed = 7;
  for (int k = 0; k < 200; k++) {
    rt_ray_t r =
        ray_to(px_vec3(rnd(&seed), 3.0, rnd(&seed)), px_vec3(5 * rnd(&seed), -0.5, 5 * rnd(&seed)));
    rt_hit_t h;
    assert_true(rt_intersect(&s, &r, &h));
    assert_vec_close(h.p, exact_hit(&q, &r), 1e-11); /* |p| up to ~6: a few ulps of that */
  }
  rt_ray_t up = ray_to(px_vec3(0, 3, 0), px_vec3(0, 4, 0)); /* pointing away: a miss */
  rt_hit_t h;
  assert_false(rt_intersect(&s, &up, &h));
  rt_scene_free(&s);
}

/* An L-shaped (concave) hexagon in z = 0: inside points in both arms, outside in the notch. */
static void concave_polygon_inside_test(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  px_vec3_t v[6] = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  assert_int_equal(rt_scene_add_polygon(&s, v, 6, mat_add(&s), NULL), RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  const double in[][2] = {{0.5, 0.5}, {1.5, 0.5}, {0.5, 1.5}, {0.9, 1.9}};
  const double out[][2] = {{1.5, 1.5}, {1.9, 1.9}, {-0.1, 0.5}, {2.1, 0.5}};
  ex_quadric_t q = ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 0, 1));
  for (int k = 0; k < 4; k++) {
    rt_ray_t r = ray_to(px_vec3(0.3, 0.2, -3), px_vec3(in[k][0], in[k][1], 0));
    rt_hit_t h;
    assert_true(rt_intersect(&s, &r, &h));
    assert_vec_close(h.p, exact_hit(&q, &r), HIT_TOL);
    rt_ray_t r2 = ray_to(px_vec3(0.3, 0.2, -3), px_vec3(out[k][0], out[k][1], 0));
    assert_false(rt_intersect(&s, &r2, &h));
  }
  rt_scene_free(&s);
}

static void bent_polygon_rejected(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  px_vec3_t v[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 1e-6}, {0, 1, 0}};
  assert_int_equal(rt_scene_add_polygon(&s, v, 4, mat_add(&s), NULL), RT_EGEOMETRY);
  px_vec3_t line[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  assert_int_equal(rt_scene_add_polygon(&s, line, 3, 0, NULL), RT_EGEOMETRY);
  assert_int_equal(s.nobject, 0);
  assert_int_equal(s.nvertex, 0);
  rt_scene_free(&s);
}

static const px_vec3_t cube_v[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
/* faces wound inwards (clockwise seen from outside): the loader must flip them */
static const int cube_in[24] = {0, 1, 2, 3, 4, 7, 6, 5, 0, 4, 5, 1,
                                1, 5, 6, 2, 2, 6, 7, 3, 3, 7, 4, 0};
static const int quad_len[6] = {4, 4, 4, 4, 4, 4};

static void polyhedron_is_oriented_outwards(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int obj;
  char why[200];
  assert_int_equal(rt_scene_add_polyhedron(&s, cube_v, 8, cube_in, quad_len, 6, mat_add(&s), &obj,
                                           why, sizeof why),
                   RT_OK);
  px_vec3_t centre = px_vec3(0.5, 0.5, 0.5);
  for (int f = 0; f < 6; f++) {
    const rt_polygon_t *pg = &s.prim[s.object[obj].first_prim + f].polygon;
    px_vec3_t on_face = s.vertex[pg->first];
    assert_true(px_vec3_dot(pg->n, px_vec3_sub(on_face, centre)) > 0.49);
  }
  assert_true(s.object[obj].closed);
  rt_scene_free(&s);
}

/* rt_object_t.alone: a convex closed object that no other primitive's box or plane meets. The cube
 * and a far sphere over a plane below them are alone; a plane through the cube's box, a sphere
 * inside it, and a dent in the cube (its faces as triangles, one corner pushed in) make it not;
 * a plane never is. */
static void objects_alone(void **state) {
  (void)state;
  for (int c = 0; c < 4; c++) {
    rt_scene_t s;
    rt_scene_init(&s);
    int m = mat_add(&s), cube, ball, floor_, x;
    char why[200];
    px_vec3_t v[8];
    memcpy(v, cube_v, sizeof v);
    int tri[36], len[12];
    for (int f = 0; f < 6; f++) { /* each quad as two triangles (a, b, c), (a, c, d) */
      const int *q = cube_in + 4 * f;
      int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
      memcpy(tri + 6 * f, t, sizeof t);
      len[2 * f] = len[2 * f + 1] = 3;
    }
    if (c == 3)
      v[6] = px_vec3(0.7, 0.7, 0.7); /* the corner (1, 1, 1) pushed in */
    assert_int_equal(rt_scene_add_polyhedron(&s, v, 8, tri, len, 12, m, &cube, why, sizeof why),
                     RT_OK);
    assert_int_equal(rt_scene_add_sphere(&s, px_vec3(5, 2, 0.5), 1.0, m, &ball), RT_OK);
    assert_int_equal(rt_scene_add_plane(&s, px_vec3(0, c == 1 ? 0.5 : -0.25, 0), px_vec3(0, 1, 0),
                                        px_vec3(1, 0, 0), m, -1, 1.0, &floor_),
                     RT_OK);
    if (c == 2)
      assert_int_equal(rt_scene_add_sphere(&s, px_vec3(0.5, 0.5, 0.5), 0.1, m, &x), RT_OK);
    assert_int_equal(rt_scene_prepare(&s), RT_OK);
    assert_int_equal(s.object[cube].alone, c == 0);
    assert_int_equal(s.object[ball].alone, 1);
    assert_int_equal(s.object[floor_].alone, 0);
    rt_scene_free(&s);
  }
}

/* rt_sweep_meets_others(): a slit, a polygon at x = 2 over y in [0.9, 1.1]. Segments from a small
 * box about (0, 0, 0) to one about (4, 0, 0) pass below it; so do segments from about (0, 1.5, 0)
 * down to about (4, -1.5, 0), which are at y = 0 where x = 2, though the two boxes' common bounds
 * hold the slit (the test the sweep replaces); segments that cross y = 1 at x = 2 meet it. A listed
 * primitive is skipped, and with it the rest of its object when that object is alone (the cube: its
 * other faces), not otherwise; a plane counts where it cuts the sweep, not where it cuts only the
 * common bounds. */
static void sweep_meets_others(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int m = mat_add(&s), cube, slit, floor_;
  char why[200];
  const px_vec3_t sv[4] = {{2, 0.9, -1}, {2, 1.1, -1}, {2, 1.1, 1}, {2, 0.9, 1}};
  assert_int_equal(rt_scene_add_polygon(&s, sv, 4, m, &slit), RT_OK);
  px_vec3_t v[8];
  for (int i = 0; i < 8; i++) /* the unit cube moved to x in [10, 11] */
    v[i] = px_v3_add(cube_v[i], px_vec3(10, 0, 0));
  assert_int_equal(
      rt_scene_add_polyhedron(&s, v, 8, cube_in, quad_len, 6, m, &cube, why, sizeof why), RT_OK);
  assert_int_equal(rt_scene_add_plane(&s, px_vec3(0, -3, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), m,
                                      -1, 1.0, &floor_),
                   RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  int sp = s.object[slit].first_prim, cp = s.object[cube].first_prim,
      fp = s.object[floor_].first_prim;
  assert_true(s.object[cube].alone);
  const double a[6] = {-0.05, -0.05, -0.05, 0.05, 0.05, 0.05};
  const double b[6] = {3.95, -0.05, -0.05, 4.05, 0.05, 0.05};
  const double up[6] = {3.95, 1.95, -0.05, 4.05, 2.05, 0.05};   /* crosses y = 1 at x = 2 */
  const double down[6] = {3.95, -3.5, -0.05, 4.05, -2.5, 0.05}; /* below the floor at its end */
  assert_int_equal(rt_sweep_meets_others(&s, a, b, NULL, 0), 0);
  const double hi[6] = {-0.05, 1.45, -0.05, 0.05, 1.55, 0.05};
  const double lo[6] = {3.95, -1.55, -0.05, 4.05, -1.45, 0.05};
  assert_int_equal(rt_sweep_meets_others(&s, hi, lo, NULL, 0), 0);
  assert_int_equal(rt_sweep_meets_others(&s, a, up, NULL, 0), 1);
  assert_int_equal(rt_sweep_meets_others(&s, a, up, &sp, 1), 0); /* the slit listed */
  assert_int_equal(rt_sweep_meets_others(&s, a, down, &fp, 1), 0);
  assert_int_equal(rt_sweep_meets_others(&s, a, down, NULL, 0), 1); /* the floor cut */
  /* into the cube from outside (x 9 to 10.5): its faces unless one of them is listed */
  const double c0[6] = {9, 0.4, 0.4, 9.1, 0.6, 0.6}, c1[6] = {10.5, 0.4, 0.4, 10.6, 0.6, 0.6};
  assert_int_equal(rt_sweep_meets_others(&s, c0, c1, NULL, 0), 1);
  int other = cp + 3;
  assert_int_equal(rt_sweep_meets_others(&s, c0, c1, &other, 1), 0);
  const double bad[6] = {1, 0, 0, 0, 0, 0}; /* empty */
  assert_int_equal(rt_sweep_meets_others(&s, bad, b, NULL, 0), 1);
  rt_scene_free(&s);
}

static void open_or_inconsistent_polyhedron_rejected(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int m = mat_add(&s);
  char why[200];
  /* five faces: the top edges are used once */
  assert_int_equal(
      rt_scene_add_polyhedron(&s, cube_v, 8, cube_in, quad_len, 5, m, NULL, why, sizeof why),
      RT_EGEOMETRY);
  assert_non_null(strstr(why, "exactly twice"));
  int flipped[24];
  memcpy(flipped, cube_in, sizeof flipped);
  flipped[4] = 4, flipped[5] = 5, flipped[6] = 6, flipped[7] = 7; /* one face reversed */
  assert_int_equal(
      rt_scene_add_polyhedron(&s, cube_v, 8, flipped, quad_len, 6, m, NULL, why, sizeof why),
      RT_EGEOMETRY);
  assert_non_null(strstr(why, "same direction"));
  int bad[24];
  memcpy(bad, cube_in, sizeof bad);
  bad[0] = 8;
  assert_int_equal(
      rt_scene_add_polyhedron(&s, cube_v, 8, bad, quad_len, 6, m, NULL, why, sizeof why),
      RT_EINVAL);
  assert_int_equal(s.nobject, 0);
  rt_scene_free(&s);
}

/* A ray through a closed polyhedron meets its outward faces entering then leaving. */
static void polyhedron_entry_and_exit(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(
      rt_scene_add_polyhedron(&s, cube_v, 8, cube_in, quad_len, 6, mat_add(&s), NULL, NULL, 0),
      RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_ray_t r = ray_to(px_vec3(0.3, 0.4, -2), px_vec3(0.6, 0.5, 3));
  rt_hit_t h1, h2;
  assert_true(rt_intersect(&s, &r, &h1));
  assert_true(px_vec3_dot(h1.n, r.d) < 0); /* entering */
  ex_quadric_t front = ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 0, 1));
  assert_vec_close(h1.p, exact_hit(&front, &r), HIT_TOL);
  r.skip_prim = h1.prim;
  assert_true(rt_intersect(&s, &r, &h2));
  assert_true(px_vec3_dot(h2.n, r.d) > 0); /* leaving */
  assert_close(h2.p.z, 1.0, 0, HIT_TOL);
  rt_scene_free(&s);
}

/* The BVH finds exactly what testing every primitive finds, on the 1,000-polygon scene plus
 * small spheres scattered through it. */
static void bvh_matches_brute_force(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_mesh(&s, 25, 40), RT_OK);
  unsigned seed = 3;
  for (int k = 0; k < 30; k++)
    rt_scene_add_sphere(&s, px_vec3(2 * rnd(&seed), 1.5 + rnd(&seed), 2 * rnd(&seed)), 0.1, 0,
                        NULL);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  int hits = 0;
  for (int k = 0; k < 2000; k++) {
    px_vec3_t o = px_vec3(3 * rnd(&seed), 1.5 + 2 * rnd(&seed), 3 * rnd(&seed));
    px_vec3_t d = px_vec3(rnd(&seed), rnd(&seed), rnd(&seed));
    if (px_vec3_normalize(d, &d) != PX_OK)
      continue;
    rt_ray_t r = {o, d, 0.0, INFINITY, 1.0, -1, 0.0f};
    rt_hit_t a, b;
    int fa = rt_intersect(&s, &r, &a), fb = rt_intersect_brute(&s, &r, &b);
    assert_int_equal(fa, fb);
    if (fa) {
      assert_int_equal(a.prim, b.prim);
      assert_true(a.t == b.t); /* the same primitive test on the same ray: bitwise equal */
      hits++;
    }
  }
  assert_true(hits > 1000);
  rt_scene_free(&s);
}

static void faceted_sphere_has_requested_faces(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int obj;
  assert_int_equal(
      rt_scene_add_faceted_sphere(&s, px_vec3(0, 0, 0), 1.0, 25, 40, mat_add(&s), &obj), RT_OK);
  assert_int_equal(s.object[obj].nprim, 1000);
  assert_int_equal(rt_scene_add_faceted_sphere(&s, px_vec3(0, 0, 0), 1.0, 1, 40, 0, NULL),
                   RT_EINVAL);
  rt_scene_free(&s);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sphere_hits_match_exact_quadric),
      cmocka_unit_test(plane_hits_match_exact_quadric),
      cmocka_unit_test(concave_polygon_inside_test),
      cmocka_unit_test(bent_polygon_rejected),
      cmocka_unit_test(polyhedron_is_oriented_outwards),
      cmocka_unit_test(objects_alone),
      cmocka_unit_test(sweep_meets_others),
      cmocka_unit_test(open_or_inconsistent_polyhedron_rejected),
      cmocka_unit_test(polyhedron_entry_and_exit),
      cmocka_unit_test(bvh_matches_brute_force),
      cmocka_unit_test(faceted_sphere_has_requested_faces),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
