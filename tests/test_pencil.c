/* test_pencil.c -- the pencil renderer (paper section 4.1 (1)-(2)): system matrices of a ray
 * tree's paths against the whole-path cascade and exact tracing, the incremental Appendix (3)
 * bound against libparaxial's, the edge test (tree agreement, checker squares ignored, the
 * small-object guard), domain subdivision, the interpolation error, and pencil against exact
 * images on tiny renders. Scenes, renders and image comparisons shared by the cases are the
 * fixtures of pencil_fixtures.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bound.h"
#include "cmocka_main.h"
#include "core/builtin.h"
#include "core/camera.h"
#include "exact/trace.h"
#include "internal.h"
#include "interp.h"
#include "io/scene_json.h"
#include "pencil/edge.h"
#include "pencil/path.h"
#include "pencil/pencil.h"
#include "render/render.h"
#include "validation/figures.h"

#include "pencil_fixtures.h"

/* One cell's worth of state: the exact tree of the ray through pixel (x, y) and its paths. */
typedef struct {
  rt_scene_t s;
  rt_plan_t plan;
  rt_view_t view;
  rt_tree_node_t buf[256];
  rt_tree_t tree;
  pt_node_t node[256];
  pt_pencil_t p;
  double chk[8][2]; /**< certified mode's boundary points, when p.check is set */
  pt_path_scratch_t w;
} cell_t;

static void xi_at(const cell_t *c, double x, double y, double xi[2]) {
  rt_ray_t r = rt_view_ray(&c->view, x, y, 1.0);
  xi[0] = px_vec3_dot(c->p.frame.x1, r.d);
  xi[1] = px_vec3_dot(c->p.frame.x2, r.d);
}

/* The cell's paths; with half > 0 in certified mode, for the cell of half-side `half` pixels
 * around (x, y) (the boundary points in pt__domain's order: corner, edge midpoint, corner, ...). */
static void build_cell_checked(cell_t *c, double x, double y, pt_bound_t bound, double half) {
  fx_fig8(&c->s, 256, 256);
  c->plan = rt_plan_make(&c->s, 1);
  assert_int_equal(rt_view_make(&c->s.camera, &c->view), RT_OK);
  assert_true(c->plan.tree_nodes <= 256);
  c->tree = rt_tree_make(c->buf, c->plan.tree_nodes);
  xr_exact_t ex = xr_exact_make(&c->s, &c->plan, &c->tree);
  rt_ray_t axial = rt_view_ray(&c->view, x, y, c->s.ior);
  xr_exact_primary(&ex, &axial);
  memset(&c->p, 0, sizeof c->p);
  c->p.eye = c->view.eye;
  assert_int_equal(px_frame_from_z(axial.d, c->view.down, &c->p.frame), PX_OK);
  double a[2], b[2], d[2], e[2];
  xi_at(c, x + 0.5, y, a);
  xi_at(c, x - 0.5, y, b);
  xi_at(c, x, y + 0.5, d);
  xi_at(c, x, y - 0.5, e);
  c->p.delta[0][0] = a[0] - b[0];
  c->p.delta[0][1] = a[1] - b[1];
  c->p.delta[1][0] = d[0] - e[0];
  c->p.delta[1][1] = d[1] - e[1];
  c->p.rho = 0.5;
  c->p.bound = bound;
  c->p.xi_domain = 0.005;
  if (half > 0.0) {
    const double px[8] = {-1, 0, 1, 1, 1, 0, -1, -1}, py[8] = {-1, -1, -1, 0, 1, 1, 1, 0};
    for (int j = 0; j < 8; j++)
      xi_at(c, x + half * px[j], y + half * py[j], c->chk[j]);
    c->p.check = (const double(*)[2])c->chk;
  }
  for (int k = 0; k < c->tree.n; k++) {
    int par = c->tree.node[k].parent;
    pt_path_topology(&c->s, &c->tree, k, par >= 0 ? &c->node[par] : NULL, &c->node[k]);
    assert_int_equal(pt_path_build(&c->s, &c->tree, k, c->node, &c->p, &c->w), PX_OK);
  }
}

static void build_cell(cell_t *c, double x, double y, pt_bound_t bound) {
  build_cell_checked(c, x, y, bound, 0.0);
}

/* A pixel on the glass ball: its tree goes through several refractions and reflections. */
#define BALL_X 128.5
#define BALL_Y 100.5

/* The node's matrix is built edge by edge (T_k = S_k T_parent, each step one verified
 * ex_axial_cascade); the whole path as one ex_system must give the same product. Both multiply
 * the same element matrices in the same frames; they differ by rounding and by re-tracing the
 * axial ray from the parent's hit instead of from the eye (~1e-13 relative on these paths), so
 * 1e-9 of the largest entry is a wide margin that a wrong frame or a missing element exceeds by
 * orders of magnitude. */
static void path_matrices_match_whole_path_cascade(void **state) {
  (void)state;
  static cell_t c;
  build_cell(&c, BALL_X, BALL_Y, PT_BOUND_CORRECTED);
  int checked = 0, deepest = 0;
  for (int k = 0; k < c.tree.n; k++) {
    const pt_node_t *n = &c.node[k];
    if (n->miss)
      continue;
    assert_int_equal(pt_path_full(&c.s, &c.tree, k, &c.p, &c.w), PX_OK);
    px_element_t el[2 * EX_MAX_STAGES + 2];
    px_cascade_t cas;
    assert_int_equal(ex_axial_cascade(&c.w.sys, &c.w.ax, PX_VARIANT_CORRECTED, el, 34, &cas),
                     PX_OK);
    px_mat4_t t = px_cascade_product(&cas);
    px_mat2_t b = px_mat4_block(t, 0, 1), d = px_mat4_block(t, 1, 1);
    double scale = fmax(px_mat2_maxabs(b), px_mat2_maxabs(d));
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2; j++) {
        assert_close(n->b.m[i][j], b.m[i][j], 0.0, 1e-9 * scale);
        assert_close(n->d.m[i][j], d.m[i][j], 0.0, 1e-9 * scale);
      }
    checked++;
    deepest = n->depth > deepest ? n->depth : deepest;
  }
  assert_true(checked >= 5);
  assert_true(deepest >= 3);
  rt_scene_free(&c.s);
}

/* C grown along the tree (Appendix (3) terms whose T_i^a is multiplied by each new step) against
 * px_pencil_constants() on the assembled cascade: the same sum in another order, so equal to
 * rounding (1e-9 relative), for both variants. */
static void incremental_bound_equals_pencil_constants(void **state) {
  (void)state;
  static cell_t c;
  const pt_bound_t v[2] = {PT_BOUND_CORRECTED, PT_BOUND_PRINTED};
  for (int i = 0; i < 2; i++) {
    build_cell(&c, BALL_X, BALL_Y, v[i]);
    int nonzero = 0;
    for (int k = 0; k < c.tree.n; k++) {
      if (c.node[k].miss)
        continue;
      double ref;
      assert_int_equal(pt__bound_c(c.node, k, v[i], &ref), PX_OK);
      assert_close(c.node[k].c, ref, 1e-9, 1e-300);
      nonzero += c.node[k].c > 0.0;
    }
    assert_true(nonzero >= 3);
    rt_scene_free(&c.s);
  }
}

/* The corrected bound holds for actual rays: for |xi| = 1e-4 (a few hundredths of a pixel) the
 * exact position error of the linear map in the node's output plane is at most C |xi|^2. The
 * third-order remainder is O(|xi|^3), a relative 1e-4 here; 2% of slack covers it. */
static void matrix_error_within_bound(void **state) {
  (void)state;
  static cell_t c;
  build_cell(&c, BALL_X, BALL_Y, PT_BOUND_CORRECTED);
  int checked = 0;
  for (int k = 0; k < c.tree.n; k++) {
    const pt_node_t *n = &c.node[k];
    if (n->miss || n->depth == 0)
      continue;
    assert_int_equal(pt_path_full(&c.s, &c.tree, k, &c.p, &c.w), PX_OK);
    for (int j = 0; j < 8; j++) {
      double xi[2] = {1e-4 * cos(j * M_PI / 4), 1e-4 * sin(j * M_PI / 4)};
      double psi[4] = {0, 0, xi[0], xi[1]}, out[4];
      if (ex_map(&c.w.sys, &c.w.ax, psi, out) != PX_OK)
        continue;
      double e = hypot(out[0] - (n->b.m[0][0] * xi[0] + n->b.m[0][1] * xi[1]),
                       out[1] - (n->b.m[1][0] * xi[0] + n->b.m[1][1] * xi[1]));
      assert_true(e <= 1.02 * n->c * 1e-8 + 1e-13);
      checked++;
    }
  }
  assert_true(checked >= 16);
  rt_scene_free(&c.s);
}

/* Certified mode carries each boundary ray one step per node (the parent's exact ray vector
 * through the parent's surface to the node); the whole path as one ex_system, traced from the
 * eye, must give the same exact ray vectors. They differ by rounding and by the output frames
 * (chained from the parent's versus re-traced from the eye, ~1e-13 rad as in the matrix test
 * above) times the ray's offset x (B xi, up to ~1 scene unit for a 5 x 5 cell on the ball):
 * 1e-10 absolute, and 1e-9 for the directions, are wide margins that a wrong frame, a missing
 * or repeated surface (an error of order x itself) exceeds by orders of magnitude. e_check is
 * the largest error along the boundary, so at least that of each boundary point. */
static void certified_check_matches_whole_path(void **state) {
  (void)state;
  static cell_t c;
  build_cell_checked(&c, BALL_X, BALL_Y, PT_BOUND_CORRECTED, 2.5);
  int checked = 0, deepest = 0;
  for (int k = 0; k < c.tree.n; k++) {
    const pt_node_t *n = &c.node[k];
    if (n->miss)
      continue;
    assert_int_equal(pt_path_full(&c.s, &c.tree, k, &c.p, &c.w), PX_OK);
    double worst = 0.0;
    for (int j = 0; j < 8; j++) {
      double psi[4] = {0, 0, c.chk[j][0], c.chk[j][1]}, out[4];
      assert_int_equal(ex_map(&c.w.sys, &c.w.ax, psi, out), PX_OK);
      for (int i = 0; i < 4; i++)
        assert_close(n->xcheck[j][i], out[i], 0.0, i < 2 ? 1e-10 : 1e-9);
      worst = fmax(worst, hypot(out[0] - (n->b.m[0][0] * psi[2] + n->b.m[0][1] * psi[3]),
                                out[1] - (n->b.m[1][0] * psi[2] + n->b.m[1][1] * psi[3])));
    }
    assert_true(isfinite(n->e_check));
    assert_true(n->e_check >= worst / n->cos_in * (1.0 - 1e-6));
    checked++;
    deepest = n->depth > deepest ? n->depth : deepest;
  }
  assert_true(checked >= 5);
  assert_true(deepest >= 3);
  rt_scene_free(&c.s);
}

/* At xi = 0 the paraxial ray is the axial ray, which meets the node's primitive at O'. The
 * renderer starts secondary rays RT_SURFACE_OFFSET (1e-9 (1 + |p|)) off each surface, so its hit
 * points drift from an offset-free path by a few 1e-9 per bounce, magnified along the path:
 * 1e-6 scene units (1e-4 of a pixel on the ball at 256 x 256) bounds that, while a wrong frame or
 * matrix would be off by the pixel scale. */
static void axis_ray_meets_axial_hit(void **state) {
  (void)state;
  static cell_t c;
  build_cell(&c, BALL_X, BALL_Y, PT_BOUND_CORRECTED);
  for (int k = 0; k < c.tree.n; k++) {
    const pt_node_t *n = &c.node[k];
    if (n->miss)
      continue;
    const double zero[2] = {0, 0};
    px_vec3_t p, d, hit;
    assert_true(pt_node_ray(n, zero, &p, &d));
    assert_true(pt_node_hit(&c.s, n, p, d, &hit));
    assert_close(px_vec3_norm(px_vec3_sub(hit, c.tree.node[k].point)), 0.0, 0.0, 1e-6);
    assert_close(px_vec3_dot(d, c.tree.node[k].dir), 1.0, 1e-12, 0.0);
  }
  rt_scene_free(&c.s);
}

/* Trees of single rays for the edge test. */
static void trace_tree(const rt_scene_t *s, const rt_plan_t *plan, const rt_view_t *v, double x,
                       double y, rt_tree_t *t) {
  xr_exact_t ex = xr_exact_make(s, plan, t);
  rt_ray_t r = rt_view_ray(v, x, y, s->ior);
  xr_exact_primary(&ex, &r);
}

/* Step 3: trees that differ only in checker squares agree (texture does not bend rays), a ray
 * off the ball disagrees with one on it at the primary node, two close rays on the ball agree
 * at the primary node. The corners' own test, pt_ctree_same_root(), says the same at the primary
 * node without the axial tree, and an invalid (overflowed) tree agrees with nothing. */
static void tree_agreement_edges_not_textures(void **state) {
  (void)state;
  rt_scene_t s;
  fx_fig8(&s, 256, 256);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_view_t v;
  rt_view_make(&s.camera, &v);
  static rt_tree_node_t ba[256], bb[256];
  static pt_cnode_t cb[256], cab[256];
  rt_tree_t a = rt_tree_make(ba, plan.tree_nodes), b = rt_tree_make(bb, plan.tree_nodes);
  pt_ctree_t c = {cb, 256, 0, 0}, ca = {cab, 256, 0, 0};
  const pt_ctree_t *cs[1] = {&c};
  int map[256];
  uint8_t agree[256];
  uint32_t light[256];
  /* two board points on different squares: find them along the bottom row */
  trace_tree(&s, &plan, &v, 2.5, 250.5, &a);
  double x = 2.5;
  do {
    x += 1.0;
    trace_tree(&s, &plan, &v, x, 250.5, &b);
  } while (b.node[0].texel == a.node[0].texel && x < 250);
  assert_int_not_equal(b.node[0].texel, a.node[0].texel);
  assert_false(rt_tree_same(&a, &b));
  pt_ctree_from(&c, &b);
  assert_true(pt_tree_agree(&a, cs, 1, map, agree, light));
  assert_true(pt_tree_same_paths(&a, &b));
  pt_ctree_from(&ca, &a);
  assert_true(pt_ctree_same_root(&ca, &c));
  /* on and off the ball */
  trace_tree(&s, &plan, &v, BALL_X, BALL_Y, &a);
  trace_tree(&s, &plan, &v, 20.5, BALL_Y, &b);
  pt_ctree_from(&c, &b);
  assert_false(pt_tree_agree(&a, cs, 1, map, agree, light));
  assert_int_equal(agree[0], 0);
  pt_ctree_from(&ca, &a);
  assert_false(pt_ctree_same_root(&ca, &c));
  assert_false(pt_ctree_same_root(&c, &ca));
  /* two close rays on the ball */
  trace_tree(&s, &plan, &v, BALL_X + 0.25, BALL_Y, &b);
  pt_ctree_from(&c, &b);
  pt_tree_agree(&a, cs, 1, map, agree, light);
  assert_int_equal(agree[0], 1);
  assert_int_equal(light[0], ~0u);
  assert_true(pt_ctree_same_root(&ca, &c));
  ca.valid = 0;
  assert_false(pt_ctree_same_root(&ca, &c));
  rt_scene_free(&s);
}

/* Guards of the one sphere b, valid until eight more calls (a ring of them). */
static const pt_guards_t *one(const pt_bsphere_t *b) {
  static pt_guards_t ring[8];
  static int next;
  pt_guards_t *g = &ring[next++ % 8];
  pt_guards_free(g);
  assert_true(pt_guards_make(b, 1, g));
  return g;
}

/* The small-object guard: a sphere much smaller than the cone inside it fires; one far outside
 * does not; a cone inside a large sphere's disk does not (no silhouette crosses it). For a
 * secondary segment: a sphere within the capsule's radius fires, unless it is one of the two
 * objects the segment joins. */
static void guard_catches_small_objects(void **state) {
  (void)state;
  px_vec3_t eye = px_vec3(0, 0, 0), axis = px_vec3(0, 0, 1);
  pt_bsphere_t small = pt_bsphere_ball(px_vec3(0.02, 0, 10), 0.01, 0);
  pt_bsphere_t far = pt_bsphere_ball(px_vec3(5, 0, 10), 0.01, 0);
  pt_bsphere_t big = pt_bsphere_ball(px_vec3(0, 0, 10), 5.0, 0);
  assert_true(pt_guard_fires(one(&small), eye, axis, 0.01));
  assert_false(pt_guard_fires(one(&far), eye, axis, 0.01));
  assert_false(pt_guard_fires(one(&big), eye, axis, 0.01));
  assert_true(pt_guard_fires(one(&big), eye, px_vec3(sin(0.5), 0, cos(0.5)), 0.05));
  /* a secondary segment's capsule: near its middle, beyond its end, one of its own objects */
  px_vec3_t p = px_vec3(0, 0, 0), q = px_vec3(0, 0, 4);
  pt_bsphere_t mid = pt_bsphere_ball(px_vec3(0.3, 0, 2), 0.1, 7),
               end = pt_bsphere_ball(px_vec3(0, 0, 4.35), 0.1, 7);
  assert_true(pt_guard_segment(one(&mid), p, q, 0.25, 1, 2));
  assert_false(pt_guard_segment(one(&mid), p, q, 0.15, 1, 2));
  assert_false(pt_guard_segment(one(&mid), p, q, 0.25, 7, 2));
  assert_false(pt_guard_segment(one(&mid), p, q, 0.25, 1, 7));
  assert_false(pt_guard_segment(one(&end), p, q, 0.2, 1, 2)); /* 0.35 from q: beyond 0.1 + 0.2 */
  assert_true(pt_guard_segment(one(&end), p, q, 0.3, 1, 2));
  assert_true(pt_guard_segment(one(&mid), p, q, NAN, 1, 2)); /* an unknown radius fires */
  /* a ray leaving the scene: its cone from within r of p */
  px_vec3_t z = px_vec3(0, 0, 1);
  pt_bsphere_t ahead = pt_bsphere_ball(px_vec3(0.5, 0, 10), 0.1, 7),
               behind = pt_bsphere_ball(px_vec3(0, 0, -10), 0.1, 7);
  assert_true(pt_guard_cone(one(&ahead), p, 0.0, z, 0.05, 1));  /* 0.05 rad from the axis */
  assert_false(pt_guard_cone(one(&ahead), p, 0.0, z, 0.02, 1)); /* the disk is 0.04-0.06 off */
  assert_true(pt_guard_cone(one(&ahead), p, 0.2, z, 0.02, 1));  /* grown by the apex radius */
  assert_false(pt_guard_cone(one(&ahead), p, 0.0, z, 0.05, 7)); /* the ray's own start */
  assert_false(pt_guard_cone(one(&behind), p, 0.0, z, 0.5, 1)); /* behind the rays */
  assert_true(pt_guard_cone(one(&ahead), p, 0.0, z, NAN, 1));   /* an unknown spread fires */
  /* shadow rays from within 0.1 of the origin to a light at (0, 0, 10): an occluder smaller than
   * the gap between the traced points fires, a larger one or one beside the rays does not */
  rt_light_t lamp = {RT_LIGHT_POINT, {0, 0, 10}, {1, 1, 1}, RT_FALLOFF_NONE,
                     {0, 0, 0},      {0, 0, 0},  0};
  rt_light_t sun = {RT_LIGHT_PARALLEL, {0, 0, -1}, {1, 1, 1}, RT_FALLOFF_NONE,
                    {0, 0, 0},         {0, 0, 0},  0};
  pt_bsphere_t tiny = pt_bsphere_ball(px_vec3(0.02, 0, 5), 0.01, 7),
               wide = pt_bsphere_ball(px_vec3(0.1, 0, 5), 1.0, 7);
  pt_bsphere_t aside = pt_bsphere_ball(px_vec3(3, 0, 5), 0.01, 7),
               past = pt_bsphere_ball(px_vec3(0, 0, -3), 0.01, 7);
  assert_true(pt_guard_shadow(one(&tiny), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_false(
      pt_guard_shadow(one(&tiny), p, 0.1, 0.05, NULL, &lamp, 7)); /* the hit's own object */
  assert_false(pt_guard_shadow(one(&wide), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_false(pt_guard_shadow(one(&aside), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_false(pt_guard_shadow(one(&past), p, 0.1, 0.05, NULL, &lamp, 1)); /* beyond the hits */
  assert_true(pt_guard_shadow(one(&tiny), p, 0.1, 0.05, NULL, &sun, 1));   /* a parallel light */
  assert_false(pt_guard_shadow(one(&wide), p, 0.1, 0.05, NULL, &sun, 1));
  assert_false(pt_guard_shadow(one(&past), p, 0.1, 0.05, NULL, &sun, 1));
  assert_true(
      pt_guard_shadow(one(&aside), p, NAN, 0.05, NULL, &lamp, 1)); /* an unknown reach fires */
  /* on a plane lit at 60 degrees a shadow is twice as long as wide: one that fits the light's
   * view of the gap no longer fits the gap */
  pt_bsphere_t medium = pt_bsphere_ball(px_vec3(0.02, 0, 5), 0.02, 7);
  px_vec3_t tilted = px_vec3(sin(M_PI / 3), 0, cos(M_PI / 3));
  assert_true(pt_guard_shadow(one(&medium), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_false(pt_guard_shadow(one(&medium), p, 0.1, 0.05, &tilted, &lamp, 1));
  /* a thin object: a bounding sphere as wide as `wide` but holding a ball of radius 0.01, and a
   * polygon's disc seen edge-on from the light, fire as small ones do */
  pt_bsphere_t rod = pt_bsphere_ball(px_vec3(0.1, 0, 5), 1.0, 7), plate = rod;
  rod.w = 0.01;
  assert_true(pt_guard_shadow(one(&rod), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_true(pt_guard_shadow(one(&rod), p, 0.1, 0.05, NULL, &sun, 1));
  plate.n = px_vec3(1, 0, 0); /* the disc of radius 1 in a plane through the light's rays */
  assert_true(pt_guard_shadow(one(&plate), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_true(pt_guard_shadow(one(&plate), p, 0.1, 0.05, NULL, &sun, 1));
  plate.n = px_vec3(0, 0, 1); /* facing the light: as wide as its disc */
  assert_false(pt_guard_shadow(one(&plate), p, 0.1, 0.05, NULL, &lamp, 1));
  assert_false(pt_guard_shadow(one(&plate), p, 0.1, 0.05, NULL, &sun, 1));
  /* on a tilted plane the gap is narrowed for a sphere's round shadow only (`medium` above, which
   * no longer fires there): a thin object holding the same ball does, as its strip may run
   * between the points whatever the tilt */
  pt_bsphere_t slim = pt_bsphere_ball(px_vec3(0.02, 0, 5), 1.0, 7);
  slim.w = 0.02;
  assert_false(pt_guard_shadow(one(&slim), p, 0.1, 0.035, NULL, &lamp, 1));
  assert_true(pt_guard_shadow(one(&slim), p, 0.1, 0.05, &tilted, &lamp, 1));
  /* spheres of the Fig. 8 scene: one, exact */
  rt_scene_t s;
  fx_fig8(&s, 8, 8);
  pt_bsphere_t b[4];
  assert_int_equal(pt_guard_spheres(&s, b, 4), 1);
  assert_close(b[0].r, 1.0, 0.0, 0.0);
  rt_scene_free(&s);
}

/* Vertices a test polygon of view_fires() may have. */
#define VIEW_VERTICES 300

/* pt_guard_view() in a scene of polygons v[k][0..n[k]), k < m (and a sphere first when r > 0:
 * centre c, radius r), from the origin through the corners (+-w, +-w, 1); `met` the primitive
 * every corner met (-1: none). Only the faces are asked, not the objects' spheres. */
static int view_fires_wide(const px_vec3_t (*v)[VIEW_VERTICES], const int *n, int m, px_vec3_t c,
                           double r, int met, double w) {
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t white = rt_material_default("white");
  int mw;
  rt_scene_add_material(&s, &white, &mw);
  if (r > 0.0)
    rt_scene_add_sphere(&s, c, r, mw, NULL);
  for (int k = 0; k < m; k++)
    assert_int_equal(rt_scene_add_polygon(&s, v[k], n[k], mw, NULL), RT_OK);
  pt_guards_t none = {0}, faces;
  assert_true(pt_guards_of_faces(&s, &none, &faces));
  const px_vec3_t d[4] = {px_vec3(-w, -w, 1), px_vec3(w, -w, 1), px_vec3(w, w, 1),
                          px_vec3(-w, w, 1)};
  int fired = pt_guard_view(&none, &faces, &s, px_vec3(0, 0, 0), d, px_vec3(0, 0, 1),
                            asin(w * sqrt(2.0) / sqrt(1.0 + 2.0 * w * w)), met);
  pt_guards_free(&faces);
  rt_scene_free(&s);
  return fired;
}

/* ... through the corners (+-0.01, +-0.01, 1). */
static int view_fires(const px_vec3_t (*v)[VIEW_VERTICES], const int *n, int m, px_vec3_t c,
                      double r, int met) {
  return view_fires_wide(v, n, m, c, r, met, 0.01);
}

/* The guard of what primary rays see: the corners (+-0.01, +-0.01, 1) from the origin all meet
 * the square F at z = 10 (x from -1 to 0.11, y from -1 to 1), whose pyramid there is 0.2 wide.
 * A small square in the pyramid before F fires; behind F's plane, or beside the pyramid, it does
 * not; a face along F's edge at x = 0.11, outside the pyramid, does not, leaning over it towards
 * the eye it does, leaning away it does not. With a sphere met instead, what lies nearer than its
 * farthest corner hit fires (a strip before the sphere near that corner, farther than the nearest
 * corner's hit), what lies beyond does not; with nothing met, anything ahead fires.
 * F not convex: a notch between the corners fires, one beside them does not. */
static void view_guard_sees_faces_in_front(void **state) {
  (void)state;
  static px_vec3_t v[2][VIEW_VERTICES];
  px_vec3_t o = px_vec3(0, 0, 0);
  int n[2] = {4, 4};
  const double fx[4] = {-1, -1, 0.11, 0.11}, fy[4] = {-1, 1, 1, -1};
  for (int k = 0; k < 4; k++)
    v[0][k] = px_vec3(fx[k], fy[k], 10.0);
  const double sx[4] = {-0.01, -0.01, 0.01, 0.01}, sy[4] = {-0.01, 0.01, 0.01, -0.01};
  for (int k = 0; k < 4; k++) /* a small square in the pyramid, 5 from the eye */
    v[1][k] = px_vec3(sx[k], sy[k], 5.0);
  assert_true(view_fires(v, n, 2, o, 0, 0));
  for (int k = 0; k < 4; k++) /* behind F */
    v[1][k].z = 15.0;
  assert_false(view_fires(v, n, 2, o, 0, 0));
  for (int k = 0; k < 4; k++) /* before F, beside the pyramid */
    v[1][k] = px_vec3(sx[k] + 0.2, sy[k], 5.0);
  assert_false(view_fires(v, n, 2, o, 0, 0));
  /* faces along F's edge x = 0.11: towards the eye, leaning over, leaning away */
  const double lean[3] = {0.0, -0.5, 0.5};
  const int want[3] = {0, 1, 0};
  for (int i = 0; i < 3; i++) {
    v[1][0] = px_vec3(0.11, -1, 10), v[1][1] = px_vec3(0.11, 1, 10);
    v[1][2] = px_vec3(0.11 + lean[i], 1, 10 - (i == 2 ? -1.0 : 1.0));
    v[1][3] = px_vec3(0.11 + lean[i], -1, 10 - (i == 2 ? -1.0 : 1.0));
    assert_int_equal(view_fires(v, n, 2, o, 0, 0), want[i]);
  }
  /* a sphere of radius 5 about (4, 0, 20) met: the corners' hits 16.79 to 17.25 away, 17.25 on
   * the side of -x; a strip there 17.1 away is before the sphere */
  px_vec3_t c = px_vec3(4, 0, 20);
  const double bx[4] = {-0.168, -0.168, -0.15, -0.15};
  for (int k = 0; k < 4; k++)
    v[0][k] = px_vec3(bx[k], sy[k], 17.1);
  assert_true(view_fires(v, n, 1, c, 5.0, 0));
  for (int k = 0; k < 4; k++)
    v[0][k].z = 17.4;
  assert_false(view_fires(v, n, 1, c, 5.0, 0));
  for (int k = 0; k < 4; k++) /* nothing met: anything ahead */
    v[0][k].z = 1000.0;
  assert_true(view_fires(v, n, 1, o, 0, -1));
  /* F not convex: a U open at the top, its notch 0.04 wide about x = x0 */
  const double x0s[2] = {0.0, 0.5};
  for (int i = 0; i < 2; i++) {
    double x0 = x0s[i];
    const double ux[8] = {-1, 1, 1, x0 + 0.02, x0 + 0.02, x0 - 0.02, x0 - 0.02, -1};
    const double uy[8] = {-1, -1, 1, 1, -0.5, -0.5, 1, 1};
    for (int k = 0; k < 8; k++)
      v[0][k] = px_vec3(ux[k], uy[k], 10.0);
    n[0] = 8;
    assert_int_equal(view_fires(v, n, 1, o, 0, 0), i == 0);
  }
  /* the eye inside a sphere of radius 10.5 about (0, 0, 10), the corners 10 degrees out: their
   * exits 19.9 away, the axis's 20.5. A square on the axis 20.2 away is before the sphere's wall
   * there, farther than every corner's hit: it fires (the farthest corner is no bound inside) */
  for (int k = 0; k < 4; k++)
    v[0][k] = px_vec3(sx[k], sy[k], 20.2);
  n[0] = 4;
  assert_true(view_fires_wide(v, n, 1, px_vec3(0, 0, 10), 10.5, 0, 0.18));
  /* a saw of 124 teeth before F, whose tips a side of the pyramid cuts: clipped, it would have
   * more vertices than the clip holds (about 375 from 251); it fires, and nothing is written past
   * the buffers (the ASan build) */
  for (int k = 0; k < 4; k++)
    v[0][k] = px_vec3(fx[k], fy[k], 10.0);
  int m = 0; /* its teeth across y = -0.05, the pyramid's side there, cut before the others */
  v[1][m++] = px_vec3(-1.0, 1.0, 5.0);
  for (int t = 0; t < 124; t++) {
    double x = -1.0 + 2.0 * t / 124.0;
    v[1][m++] = px_vec3(x, -0.04, 5.0);
    v[1][m++] = px_vec3(x + 1.0 / 124.0, -0.06, 5.0);
  }
  v[1][m++] = px_vec3(1.0, -0.04, 5.0);
  v[1][m++] = px_vec3(1.0, 1.0, 5.0);
  n[0] = 4;
  n[1] = m;
  assert_true(m <= 256);
  assert_true(view_fires(v, n, 2, o, 0, 0));
}

/* A uniform number in [a, b) from a 64-bit LCG (the test's own, so that it runs the same
 * everywhere). */
static double uniform(uint64_t *x, double a, double b) {
  *x = *x * 6364136223846793005ull + 1442695040888963407ull;
  return a + (b - a) * (double)(*x >> 11) * 0x1p-53;
}

static px_vec3_t random_unit(uint64_t *x) {
  px_vec3_t v;
  do
    v = px_vec3(uniform(x, -1, 1), uniform(x, -1, 1), uniform(x, -1, 1));
  while (px_v3_dot(v, v) > 1.0 || px_v3_dot(v, v) < 1e-6);
  return px_v3_unit(v);
}

/* The guards' hierarchy answers every query as the scan over every sphere does (guards without
 * nodes): 400 spheres of radii from 1e-3 to 1 in a box of side 20, and 4,000 queries of each
 * kind, a quarter of them (segments, cones, parallel shadows) tuned to within a relative 1e-12 of
 * where a chosen sphere starts to fire, which the hierarchy's margins must cover. Both answers
 * occur, and a scene's every object is guarded, past the 4,096 the renderer once held. */
static void guard_hierarchy_answers_as_the_scan(void **state) {
  (void)state;
  enum { N = 400, Q = 4000 };
  static pt_bsphere_t b[N];
  uint64_t x = 12345;
  for (int i = 0; i < N; i++)
    b[i] =
        pt_bsphere_ball(px_vec3(uniform(&x, -10, 10), uniform(&x, -10, 10), uniform(&x, -10, 10)),
                        exp(uniform(&x, log(1e-3), 0.0)), i % 50);
  pt_guards_t g, flat = {b, N, NULL, 0, NULL}; /* flat: the spheres one by one, no hierarchy */
  assert_true(pt_guards_make(b, N, &g));
  assert_int_equal(g.n, N);
  int seen[4][2] = {{0}}, tuned[4] = {0};
  rt_light_t lamp = {RT_LIGHT_POINT, {0, 0, 0}, {1, 1, 1}, RT_FALLOFF_NONE,
                     {0, 0, 0},      {0, 0, 0}, 0};
  for (int kind = 0; kind < 4; kind++)
    for (int k = 0; k < Q; k++) {
      px_vec3_t p = px_vec3(uniform(&x, -12, 12), uniform(&x, -12, 12), uniform(&x, -12, 12));
      px_vec3_t q = px_v3_axpy(uniform(&x, 0.1, 8.0), random_unit(&x), p);
      px_vec3_t axis = random_unit(&x);
      double r = exp(uniform(&x, log(1e-4), log(0.5))), half = exp(uniform(&x, log(1e-4), -1.0));
      double gap = exp(uniform(&x, log(1e-4), -1.0));
      int skip = (int)uniform(&x, 0, 50), skip2 = (int)uniform(&x, 0, 50);
      const pt_bsphere_t *t = &b[(int)uniform(&x, 0, N)]; /* tuned: on its firing boundary */
      int tune = k % 4 == 0;
      double eps = uniform(&x, -1e-12, 1e-12);
      if (tune && kind == 1) { /* the capsule just reaching t */
        px_vec3_t pq = px_v3_sub(q, p), v = px_v3_sub(t->c, p);
        double s = fmax(0.0, fmin(1.0, px_v3_dot(v, pq) / px_v3_dot(pq, pq)));
        r = fmax(0.0, px_v3_norm(px_v3_sub(v, px_v3_scale(pq, s))) - t->r) * (1.0 + eps);
        skip = skip2 = -1;
      }
      if (tune && (kind == 0 || kind == 2)) { /* the cone's rim on t's disk */
        px_vec3_t v = px_v3_sub(t->c, p);
        double d = px_v3_norm(v), grown = t->r + (kind == 2 ? r : 0.0);
        if (d > grown) {
          double gamma = asin(grown / d);
          axis = px_v3_unit(px_v3_axpy(0.3, random_unit(&x), px_v3_scale(v, 1.0 / d)));
          half = fmax(0.0,
                      (acos(fmax(-1.0, fmin(1.0, px_v3_dot(v, axis) / d))) - gamma) * (1.0 + eps));
        }
        skip = -1;
      }
      if (kind == 3) { /* shadow pencils of width about a sphere's */
        r = uniform(&x, 0.05, 2.0);
        gap = uniform(&x, 0.01, 1.0);
      }
      lamp.kind = kind == 3 && (k / 4) % 2 ? RT_LIGHT_PARALLEL : RT_LIGHT_POINT;
      lamp.v = lamp.kind == RT_LIGHT_PARALLEL ? axis : q;
      if (tune && kind == 3 && lamp.kind == RT_LIGHT_PARALLEL) {
        /* the cylinder of radius r about the ray from p towards the light just touching t */
        px_vec3_t u = px_v3_unit(
            px_v3_sub(random_unit(&x), px_v3_scale(axis, px_v3_dot(random_unit(&x), axis))));
        u = px_v3_unit(px_v3_sub(u, px_v3_scale(axis, px_v3_dot(u, axis))));
        p = px_v3_axpy(-(t->r + r) * (1.0 + eps), u, px_v3_axpy(uniform(&x, 0.0, 3.0), axis, t->c));
        skip = -1;
      }
      const pt_guards_t *o = &flat;
      int want = kind == 0   ? pt_guard_fires(o, p, axis, half)
                 : kind == 1 ? pt_guard_segment(o, p, q, r, skip, skip2)
                 : kind == 2 ? pt_guard_cone(o, p, r, axis, half, skip)
                             : pt_guard_shadow(o, p, r, gap, NULL, &lamp, skip);
      int got = kind == 0   ? pt_guard_fires(&g, p, axis, half)
                : kind == 1 ? pt_guard_segment(&g, p, q, r, skip, skip2)
                : kind == 2 ? pt_guard_cone(&g, p, r, axis, half, skip)
                            : pt_guard_shadow(&g, p, r, gap, NULL, &lamp, skip);
      if (got != want)
        fail_msg("query kind %d, number %d: the hierarchy says %d, the scan %d", kind, k, got,
                 want);
      /* the chosen sphere alone, where its node's sphere is as tight as can be */
      pt_guards_t flat1 = {(pt_bsphere_t *)t, 1, NULL, 0, NULL};
      const pt_guards_t *h1 = one(t);
      int want1 = kind == 0   ? pt_guard_fires(&flat1, p, axis, half)
                  : kind == 1 ? pt_guard_segment(&flat1, p, q, r, skip, skip2)
                  : kind == 2 ? pt_guard_cone(&flat1, p, r, axis, half, skip)
                              : pt_guard_shadow(&flat1, p, r, gap, NULL, &lamp, skip);
      int got1 = kind == 0   ? pt_guard_fires(h1, p, axis, half)
                 : kind == 1 ? pt_guard_segment(h1, p, q, r, skip, skip2)
                 : kind == 2 ? pt_guard_cone(h1, p, r, axis, half, skip)
                             : pt_guard_shadow(h1, p, r, gap, NULL, &lamp, skip);
      if (got1 != want1)
        fail_msg("query kind %d, number %d, its sphere alone: the hierarchy says %d, the scan %d",
                 kind, k, got1, want1);
      tuned[kind] += tune && want1;
      seen[kind][got]++;
    }
  for (int kind = 0; kind < 4; kind++) /* both answers; tuned queries that fire */
    assert_true(seen[kind][0] > Q / 20 && seen[kind][1] > Q / 20 && tuned[kind] > Q / 40);
  pt_guards_free(&g);
  /* every object of a scene, beyond the 4,096 the renderer once held */
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t m = rt_material_default("white");
  int mi;
  assert_int_equal(rt_scene_add_material(&s, &m, &mi), RT_OK);
  for (int i = 0; i < 5000; i++)
    assert_int_equal(rt_scene_add_sphere(&s, px_vec3(i % 100, i / 100, 10.0), 0.25, mi, NULL),
                     RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  assert_true(pt_guards_of_scene(&s, &g));
  assert_int_equal(g.n, 5000);
  int last = 0; /* the last object is among them */
  for (int i = 0; i < g.n; i++)
    last |= g.b[i].object == 4999;
  assert_true(last);
  pt_guards_free(&g);
  rt_scene_free(&s);
}

/* Step 1 and steps 3-4: on the bare board every initial domain is smooth and accepted whole;
 * with the ball, domains on its outline are subdivided and some pixels traced exactly, but only
 * a minority. Both with ray interpolation (the default, also at one sample per pixel) and with
 * every sample through the matrices (--no-interp), where the accepted cells' samples are all
 * matrix-traced. */
static void subdivision_only_at_edges(void **state) {
  (void)state;
  for (int interp = 1; interp >= 0; interp--) {
    rt_scene_t s;
    pt_options_t o = PT_OPTIONS_DEFAULT;
    o.interp = interp;
    fx_board(&s, 40, 40);
    pt_stats_t st = fx_pencil_stats(&s, 1, 1, &o);
    assert_int_equal(st.domains, 64); /* 8 x 8 domains of 5 x 5 pixels */
    assert_int_equal(st.domains_accepted, 64);
    assert_int_equal(st.domains_edge, 0);
    assert_int_equal(st.samples[PT_METHOD_EXACT], 0);
    assert_true(interp ? st.samples[PT_METHOD_INTERP] == 40 * 40
                       : st.samples[PT_METHOD_MATRIX] == 40 * 40);
    rt_scene_free(&s);
    fx_fig8(&s, 40, 40);
    st = fx_pencil_stats(&s, 1, 1, &o);
    assert_true(st.domains > 64);
    assert_true(st.domains_edge > 0);
    assert_true(st.samples[PT_METHOD_EXACT] > 0);
    assert_true(st.samples[PT_METHOD_EXACT] < 40 * 40 / 4);
    rt_scene_free(&s);
  }
}

/* Ray interpolation (4.1 (2)) on the bare board: nearly every sample is interpolated, from a
 * lattice coarser than the pixels (the board seen from the camera is a projective map, nearly
 * linear over a 5 x 5 domain), and every one lands within rho = 1/2 pixel of the exact point.
 * With a tiny rho the lattice must be refined (more points than pixels) and still be too coarse
 * everywhere, so that no sample's board point is interpolated (they come from the matrix). */
static void interpolation_error_on_board(void **state) {
  (void)state;
  rt_scene_t s;
  fx_board(&s, 40, 40);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  pt_stats_t st = fx_pencil_stats(&s, 2, 1, &o);
  assert_true(st.samples[PT_METHOD_INTERP] > 40 * 40 * 4 * 9 / 10);
  assert_true(st.lattice_points < 40 * 40);
  assert_int_equal(st.within, st.measured);
  assert_true(st.max_error <= 0.5);
  assert_int_equal(st.mismatches, 0);
  o.rho = 1e-4;
  st = fx_pencil_stats(&s, 2, 1, &o);
  assert_true(st.lattice_points + st.lattice_reused > 40 * 40); /* points the cells used */
  assert_true(st.lerp_samples == 0); /* the board's hits come from its matrix per sample */
  assert_int_equal(st.within, st.measured);
  rt_scene_free(&s);
}

/* Biquadratic interpolation (interp.h, PT_BIQUAD_FACTOR) takes over where bilinear is not
 * accurate enough, on the glass ball of Fig. 8 at 49 spp, and the samples stay within rho as
 * the issue requires of the default mode (>= 99.8%, largest error under 2 rho). Certified mode,
 * which accepts measured errors only, interpolates a quarter by its parent's biquadratic where
 * that deviates from the quarter's own five new points (its measured error) by little enough,
 * and keeps every sample within rho. */
static void biquadratic_cells_stay_within_rho(void **state) {
  (void)state;
  enum { W = 64, H = 64 };
  rt_scene_t s;
  fx_fig8(&s, W, H);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  pt_stats_t st = fx_pencil_stats(&s, 7, 1, &o);
  assert_true(st.biquad_lattice_cells > 0);
  assert_true(st.within >= st.measured * 998 / 1000);
  assert_true(st.max_error < 2.0 * o.rho);
  o.certified = 1;
  st = fx_pencil_stats(&s, 7, 1, &o);
  assert_true(st.biquad_lattice_cells > 0);
  assert_int_equal(st.within, st.measured);
  /* the sweep's settings (9 spp, rho from 0.05 to 1/2) in both modes: a biquadratic node that is
   * not textured must not be taken for a textured leaf (it once picked a "checker square" on
   * the sphere: NaN, and an out-of-range material index) */
  const double rhos[3] = {0.05, 0.25, 0.5};
  for (int c = 0; c < 2; c++)
    for (int r = 0; r < 3; r++) {
      o.certified = c;
      o.rho = rhos[r];
      rt_image_t p;
      fx_render_pencil(&s, 3, 1, &o, &p, NULL, &st);
      assert_true(st.within >= st.measured * (c ? 1000 : 998) / 1000);
      for (int k = 0; k < W * H; k++)
        assert_true(isfinite(p.ch[0][k]) && p.ch[0][k] >= 0.0f && p.ch[0][k] < 4.0f);
      rt_image_free(&p);
    }
  rt_scene_free(&s);
}

/* Pencil against exact tracing on a tiny Fig. 8 render at 4 spp. The Fig. 10 error must hold for
 * at least 99.5% of samples (the paper: 99.8% at 256 x 256), and for all of them in certified
 * mode. The images are compared at rho = 0.05, where they resolve the checkerboard (a pixel's
 * board point moves less than half a square to its neighbours): towards the horizon one pixel
 * covers several squares and any sub-pixel error, even far below rho, changes its aliased colour.
 * There, a sample changes colour only when its board point lies within its error (<= rho pixel)
 * of a square edge: that changes its pixel by one sample's share, 1/4 of the contrast (~0.8), so
 * at most 0.25, in at most 1% of the pixels; over the image the RMS stays below 0.01. (At
 * rho = 1/2 every sample within half a pixel of a square edge may change colour, and along an
 * edge that runs with the pixel rows a whole row of pixels does: docs/pencil.md.) */
static void pencil_image_matches_exact(void **state) {
  (void)state;
  enum { W = 48, H = 48 };
  rt_scene_t s;
  fx_fig8(&s, W, H);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  pt_stats_t st = fx_pencil_stats(&s, 2, 1, &o);
  assert_true(st.within >= st.measured * 995 / 1000);
  o.rho = 0.05;
  rt_image_t p;
  fx_render_pencil(&s, 2, 1, &o, &p, NULL, &st);
  assert_true(st.within >= st.measured * 995 / 1000);
  fx_diff_t d = fx_board_difference(&s, &p, 2);
  assert_true(d.n > W * H / 3);
  assert_true(d.rms < 0.01);
  assert_true(d.big <= d.n / 100);
  assert_true(d.worst <= 0.25);
  rt_image_free(&p);
  o.rho = 0.5;
  o.certified = 1;
  st = fx_pencil_stats(&s, 2, 1, &o);
  assert_int_equal(st.within, st.measured);
  assert_int_equal(st.mismatches, 0);
  rt_scene_free(&s);
}

/* The image-space tolerance (pt_tolerance_t): with a weight floor of 1 every node's tolerance is
 * rho and the image is the geometric one to the bit; with the default floor the ball's inner
 * paths (weights 0.75 x 0.15 and less) get wider tolerances, so that fewer lattice points are
 * traced, while every measured point stays within its own tolerance as often as the geometric
 * mode's are within rho (the measure divides by the node's scale), and the image against the
 * exact one stays as close: a node of weight W erring by rho / W moves its share W of the pixel
 * about as much as a weight-1 node erring by rho does (measured at 256 x 256 and 49 spp: RMS
 * 0.01406 -> 0.01414 over the image, docs/journal/2026-12-03-edges.md). */
static void image_tolerance_weights_nodes(void **state) {
  (void)state;
  enum { W = 64, H = 64, SIDE = 3 };
  rt_scene_t s;
  fx_fig8(&s, W, H);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  rt_image_t g, i1, im;
  pt_stats_t sg, s1, si;
  fx_render_pencil(&s, SIDE, 1, &o, &g, NULL, &sg);
  o.tolerance = PT_TOL_IMAGE;
  o.weight_floor = 1.0;
  fx_render_pencil(&s, SIDE, 1, &o, &i1, NULL, &s1);
  fx_assert_images_equal(&g, &i1);
  assert_int_equal(s1.lattice_points, sg.lattice_points);
  o.weight_floor = PT_WEIGHT_FLOOR;
  fx_render_pencil(&s, SIDE, 1, &o, &im, NULL, &si);
  fx_diff_t dg = fx_exact_difference(&s, &g, SIDE), di = fx_exact_difference(&s, &im, SIDE);
  print_message("lattice points %llu -> %llu, paths exact %llu -> %llu; against exact: RMS %.5f "
                "-> %.5f, worst %.4f -> %.4f, pixels off by > 0.1: %d -> %d\n",
                (unsigned long long)sg.lattice_points, (unsigned long long)si.lattice_points,
                (unsigned long long)sg.paths_exact, (unsigned long long)si.paths_exact, dg.rms,
                di.rms, dg.worst, di.worst, dg.big, di.big);
  assert_true(si.lattice_points < sg.lattice_points);
  assert_true(si.paths_exact < sg.paths_exact);
  assert_true(di.rms <= 1.05 * dg.rms);
  assert_true(di.big <= dg.big + dg.big / 20 + 1);
  /* measured: within their own tolerances as the geometric mode's points are within rho */
  pt_options_t m = o;
  m.measure = 1;
  pt_stats_t mi = fx_pencil_stats(&s, SIDE, 1, &m);
  m.tolerance = PT_TOL_GEOMETRIC;
  pt_stats_t mg = fx_pencil_stats(&s, SIDE, 1, &m);
  print_message("within: image %.5f%%, geometric %.5f%%\n", 100.0 * mi.within / mi.measured,
                100.0 * mg.within / mg.measured);
  assert_true(mi.measured == mg.measured && mi.within >= mi.measured * 9999 / 10000);
  assert_int_equal(mi.mismatches, 0);
  rt_image_free(&g);
  rt_image_free(&i1);
  rt_image_free(&im);
  rt_scene_free(&s);
}

/* Fig. 8 lit by its light with the inverse-square fall-off (intensity 67 at unit distance: about
 * 1 at the board, 8.2 away): the pencil image still matches the exact one as closely as without
 * it (the same thresholds), though no node may now be interpolated as faint (pt__faint_bound has
 * no bound for such a light), and the fall-off shows: the board's near and far ends differ from
 * the no-fall-off image by different factors. */
static void pencil_image_matches_exact_with_falloff(void **state) {
  (void)state;
  enum { W = 48, H = 48 };
  rt_scene_t s;
  fx_fig8(&s, W, H);
  rt_image_t flat;
  fx_render_exact(&s, 1, 1, &flat);
  s.light[0].falloff = RT_FALLOFF_INVERSE_SQUARE;
  s.light[0].intensity = rt_rgb(67, 67, 67);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.rho = 0.05;
  rt_image_t p, e;
  pt_stats_t st;
  fx_render_pencil(&s, 2, 1, &o, &p, NULL, &st);
  fx_diff_t d = fx_board_difference(&s, &p, 2);
  print_message("fall-off: %d pixels, rms %.2e, worst %.3f, %d big\n", d.n, d.rms, d.worst, d.big);
  assert_true(d.n > W * H / 3);
  assert_true(d.rms < 0.01);
  assert_true(d.big <= d.n / 100);
  assert_true(d.worst <= 0.25);
  fx_render_exact(&s, 1, 1, &e);
  double lo = INFINITY, hi = 0.0; /* ratio of the lit images over the board's pixels */
  for (int k = 0; k < W * H; k++) {
    double a = e.ch[RT_CH_R][k], b = flat.ch[RT_CH_R][k];
    if (b > 0.2 && a > 0.0) {
      lo = fmin(lo, a / b);
      hi = fmax(hi, a / b);
    }
  }
  assert_true(hi > 1.1 * lo);
  rt_image_free(&p);
  rt_image_free(&e);
  rt_image_free(&flat);
  rt_scene_free(&s);
}

/* The largest sample grid (RT_MAX_SPP_SIDE^2 = 1024 per pixel, beyond the paper's 49, for Fig. 9
 * extended): the quadtree goes deeper than at 49 spp and the lattice memo fills up sooner. On
 * the glass ball of Fig. 8 every sample is still accounted for, none loses an edge, the area
 * within rho is the paper's 99.8% at least (certified: all), and the image is the exact one's
 * (RMS < 0.01). */
static void largest_sample_grid(void **state) {
  (void)state;
  enum { W = 12, H = 12, S = RT_MAX_SPP_SIDE };
  rt_scene_t s;
  fx_fig8(&s, W, H);
  s.camera.look_at = px_vec3(0.0, 1.0, 0.0); /* the ball fills the view */
  s.camera.fov_deg = 20.0;
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  for (int cert = 0; cert <= 1; cert++) {
    pt_options_t o = PT_OPTIONS_DEFAULT;
    o.measure = 1;
    o.certified = cert;
    rt_image_t p;
    pt_stats_t st;
    fx_render_pencil(&s, S, 2, &o, &p, NULL, &st);
    uint64_t all = (uint64_t)W * H * S * S;
    assert_true(st.samples[0] + st.samples[1] + st.samples[2] == all);
    assert_true(st.measured == all);
    assert_int_equal(st.mismatches, 0);
    assert_true(cert ? st.within == st.measured : st.within >= 0.998 * (double)st.measured);
    double rms = fx_exact_difference(&s, &p, S).rms;
    print_message("certified %d: %.5f%% within rho, max %.3f, exact samples %llu, rms %.4f\n", cert,
                  100.0 * (double)st.within / (double)st.measured, st.max_error,
                  (unsigned long long)st.samples[PT_METHOD_EXACT], rms);
    assert_true(rms < 0.01);
    rt_image_free(&p);
  }
  rt_scene_free(&s);
}

/* Rays spawned at interpolated hits: a bilinear interpolation of points on a sphere lies inside
 * it (a chord), by about footprint^2 / (8 r), far more than the renderer's 1e-9 surface offset;
 * unless the point is put back on the surface, reflected rays start inside a mirror ball and
 * see its inside. Over the pixels where the exact renderer's centre ray meets the mirror ball,
 * the images must agree as they do on the board: a sample changes only where its reflected
 * board point lies within its error of a square edge (RMS < 0.05, at most 3% of the ball's
 * pixels off by more than 0.3); seeing the inside gave an RMS of 0.077 with 4% off. */
static void mirror_ball_reflections_match_exact(void **state) {
  (void)state;
  enum { W = 48, H = 48 };
  rt_scene_t s;
  fx_board(&s, W, H);
  int ball = fx_add_mirror_ball(&s);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_image_t p, e;
  fx_render_pencil(&s, 2, 1, NULL, &p, NULL, NULL);
  fx_render_exact(&s, 2, 1, &e);
  fx_diff_t d = fx_object_difference(&e, &p, ball, 0.3);
  print_message("ball pixels %d, rms %g, off by > 0.3: %d\n", d.n, d.rms, d.big);
  assert_true(d.n > W * H / 10);
  assert_true(d.rms < 0.05);
  assert_true(d.big <= 3 * d.n / 100);
  rt_image_free(&p);
  rt_image_free(&e);
  rt_scene_free(&s);
}

/* The board, a mirror ball and a small matte ball at c of radius r, seen from the fx_board()
 * camera aimed at the mirror ball. */
static void mirror_and_small_ball(rt_scene_t *s, int w, int h, px_vec3_t c, double r) {
  fx_board(s, w, h);
  fx_add_mirror_ball(s);
  rt_material_t dull = rt_material_default("dull");
  int md, small;
  rt_scene_add_material(s, &dull, &md);
  rt_scene_add_sphere(s, c, r, md, &small);
  s->camera.fov_deg = 25.0;
  assert_int_equal(rt_scene_prepare(s), RT_OK);
}

/* The small-object guard on secondary segments: a small ball seen only in a mirror ball, its
 * reflection about a pixel wide, so that cells' corner trees all see the board past it. Without
 * the guard the pencil computes board points the exact tracer does not reach (16 path mismatches
 * of the 32,400 samples at the time of writing: an infinite Fig. 10 error); with it those segments
 * are traced exactly per sample, in both modes, and every sample's paths are the exact tracer's.
 * Then a ball behind the camera, seen only in the mirror against the sky (reflected rays that
 * leave the scene at the cells' traced rays): without the guard on those rays 6 pixels of the
 * default mode's image differed from the exact image by 0.26 to 0.62 (the ball's reflection
 * missing); with it none differs by more than 0.25 (what remains is checker squares flipping
 * where a sample's board point is within its error of a square's edge: 2 of 9 samples, 0.2). */
static void guard_catches_objects_seen_in_mirrors(void **state) {
  (void)state;
  enum { W = 60, H = 60 };
  rt_scene_t s;
  mirror_and_small_ball(&s, W, H, px_vec3(0.8, 0.3, -2.0), 0.12);
  for (int cert = 0; cert <= 1; cert++) {
    pt_options_t o = PT_OPTIONS_DEFAULT;
    o.certified = cert;
    o.measure = 1;
    pt_stats_t st = fx_pencil_stats(&s, 3, 1, &o);
    print_message("certified %d: %llu guarded paths, %llu mismatches of %llu samples\n", cert,
                  (unsigned long long)st.paths_guard, (unsigned long long)st.mismatches,
                  (unsigned long long)st.measured);
    assert_true(st.paths_guard > 0);
    assert_int_equal(st.mismatches, 0);
  }
  rt_scene_free(&s);
  mirror_and_small_ball(&s, W, H, px_vec3(0.0, 8.0, -10.0), 1.5);
  rt_image_t p;
  pt_stats_t st;
  fx_render_pencil(&s, 3, 1, NULL, &p, NULL, &st);
  double worst = fx_exact_difference(&s, &p, 3).worst;
  print_message("against the sky: %llu guarded paths, largest pixel difference %g\n",
                (unsigned long long)st.paths_guard, worst);
  assert_true(st.paths_guard > 0);
  assert_true(worst <= 0.25);
  rt_image_free(&p);
  rt_scene_free(&s);
}

/* The small-object guard on shadows: a small ball above the board casts a shadow about a pixel
 * wide (40 x 40 pixels, 9 spp), between the corners of the cells around it, which all see the
 * light. Without the guard the shadow was lost: the pencil's image differed from the exact one
 * by up to 0.42 there (the corners' agreement let every lattice point take the axial ray's
 * transmittance). With it, the cells' shadow rays are traced at the lattice points and the
 * lattice is refined (or the direct term shaded per sample) until its points are closer than
 * the shadow is wide: no pixel differs by more than 0.2 (checker squares flipping at a square's
 * edge, as on the bare board). */
static void guard_catches_small_shadows(void **state) {
  (void)state;
  enum { W = 40, H = 40 };
  rt_scene_t s;
  fx_board(&s, W, H);
  rt_material_t dull = rt_material_default("dull");
  int md, small;
  rt_scene_add_material(&s, &dull, &md);
  rt_scene_add_sphere(&s, px_vec3(0.3, 0.5, -0.5), 0.12, md, &small);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  for (int cert = 0; cert <= 1; cert++) {
    rt_image_t p;
    pt_stats_t st;
    pt_options_t o = PT_OPTIONS_DEFAULT;
    o.certified = cert;
    fx_render_pencil(&s, 3, 1, &o, &p, NULL, &st);
    double worst = fx_exact_difference(&s, &p, 3).worst;
    print_message("certified %d: %llu guarded shadows, largest pixel difference %g\n", cert,
                  (unsigned long long)st.lights_guard, worst);
    assert_true(st.lights_guard > 0);
    assert_true(worst <= 0.2);
    rt_image_free(&p);
  }
  rt_scene_free(&s);
}

/* A shadow edge on a faint node is interpolated across, its error bounded (interp_error.c,
 * pt__faint_bound): in Fig. 8 the board seen after four internal reflections in the glass ball has
 * W_k = 0.75 0.15^4 0.75 = 2.8e-4, so its brightness is at most W_k (ka Ia + kd I) 0.9 =
 * 2.6e-4, within half the default brightness tolerance (4.9e-4). Not with a tenth of that
 * tolerance, nor when the ball reflects more (kr = 0.5: W_k = 0.035 for the same node); in
 * every case the image stays as close to the exact one as elsewhere. */
static void faint_shadow_edges_interpolated(void **state) {
  (void)state;
  enum { W = 48, H = 48 };
  for (int c = 0; c < 3; c++) {
    rt_scene_t s;
    fx_fig8(&s, W, H);
    pt_options_t o = PT_OPTIONS_DEFAULT;
    if (c == 1)
      o.brightness_tol /= 10.0;
    for (int m = 0; m < s.nmaterial && c == 2; m++)
      if (s.material[m].kt > 0.0)
        s.material[m].kr = 0.5;
    rt_image_t p;
    pt_stats_t st;
    fx_render_pencil(&s, 3, 1, &o, &p, NULL, &st);
    fx_diff_t d = fx_board_difference(&s, &p, 3);
    print_message("case %d: %llu lattice cells with faint shadow edges; against the exact image "
                  "RMS %.4f, %d of %d pixels over 0.1, largest %.3f\n",
                  c, (unsigned long long)st.faint_lattice_cells, d.rms, d.big, d.n, d.worst);
    if (c == 0)
      assert_true(st.faint_lattice_cells > 0);
    else
      assert_int_equal(st.faint_lattice_cells, 0);
    assert_true(d.n > W * H / 3);
    assert_true(d.rms < 0.01);
    assert_true(d.big <= d.n / 100);
    assert_true(d.worst <= 0.25);
    rt_image_free(&p);
    rt_scene_free(&s);
  }
}

/* Fig. 8 with a Fresnel split at the glass (`"fresnel": true`): the weights W_k of the ball's
 * nodes then vary over a lattice cell, fastest towards the rim, where the reflected sky's
 * brightness W_R * background is far from linear. Nodes shaded per sample (the brightness
 * fallback picks such a node) must take the sample's own W_k, and a miss node its background:
 * with the corners' W_k interpolated, and a miss node shaded as a surface, the ball came out
 * darker than the exact image by 0.011 on average (up to 0.39 near the rim). Measured on the
 * pixels whose centre ray meets the ball, where the checkerboard's flips (rho = 1/2) are rare:
 * their mean and RMS difference from the exact image, as without Fresnel. */
static void fresnel_weights_match_exact(void **state) {
  (void)state;
  enum { W = 64, H = 64 };
  for (int fresnel = 0; fresnel <= 1; fresnel++) {
    rt_scene_t s;
    fx_fig8(&s, W, H);
    for (int m = 0; m < s.nmaterial; m++)
      if (s.material[m].kt > 0.0)
        s.material[m].fresnel = fresnel;
    rt_plan_t plan = rt_plan_make(&s, 4);
    assert_int_equal(rt_plan_has(&plan, RT_EFFECT_FRESNEL), fresnel);
    rt_image_t e, p;
    fx_render_exact(&s, 2, 1, &e);
    for (int cert = 0; cert <= 1; cert++) {
      pt_options_t o = PT_OPTIONS_DEFAULT;
      o.certified = cert;
      pt_stats_t st;
      fx_render_pencil(&s, 2, 1, &o, &p, NULL, &st);
      fx_diff_t d = fx_object_difference(&e, &p, 1, 0.1); /* the glass ball */
      print_message("fresnel %d certified %d: %d ball pixels, mean difference %.5f, RMS %.4f\n",
                    fresnel, cert, d.n, d.mean, d.rms);
      assert_true(d.n > W * H / 10);
      assert_true(fabs(d.mean) < 0.003);
      assert_true(d.rms < 0.035);
      rt_image_free(&p);
    }
    rt_image_free(&e);
    rt_scene_free(&s);
  }
}

/* Every scene of scenes/ (scaled to 96 pixels wide, 4 spp), both modes: on each object that
 * covers at least 100 pixels (by the exact image's centre rays), the pencil image's mean
 * difference from the exact one stays within 0.003. The checkerboard's flips at rho = 1/2 move
 * single pixels both ways and average out; a systematic error does not (balls.json's glass
 * ball, with a Fresnel split, was darker by 0.075 before fresnel_weights_match_exact's fix). */
static void every_scene_unbiased_per_object(void **state) {
  (void)state;
  const char *names[] = {"fig8", "balls", "mesh1000", "fig11"};
  for (int sc = 0; sc < 4; sc++) {
    rt_scene_t s;
    fx_scene_file(names[sc], 96, &s);
    rt_image_t e;
    fx_render_exact(&s, 2, 2, &e);
    for (int cert = 0; cert <= 1; cert++) {
      pt_options_t o = PT_OPTIONS_DEFAULT;
      o.certified = cert;
      rt_image_t p;
      pt_stats_t st;
      fx_render_pencil(&s, 2, 2, &o, &p, NULL, &st);
      for (int obj = -1; obj < s.nobject; obj++) {
        fx_diff_t d = fx_object_difference(&e, &p, obj, 0.1);
        if (d.n < 100)
          continue;
        print_message("%s certified %d object %d: %d pixels, mean difference %.5f\n", names[sc],
                      cert, obj, d.n, d.mean);
        assert_true(fabs(d.mean) < 0.003);
      }
      rt_image_free(&p);
    }
    rt_image_free(&e);
    rt_scene_free(&s);
  }
}

/* Fig. 11's glass torus (scenes/fig11.json at 192 x 192, 1 spp): a cell whose primary hits agree
 * on a facet but whose trees below differ traces those subtrees exactly per sample, spawned at
 * the sample's primary hit. That hit was interpolated - within the tolerance, but through up to
 * six facets of a polyhedron that is not convex its error turned 9 of the torus's pixels into
 * other colours, by up to 0.68 (an interpolated direction's error of ~1e-5 rad suffices near a
 * facet edge), and Fig. 10's measure did not see it: it took the subtree for exact. Now such
 * subtrees start at the sample's exact hit (pt_eval_t.exact_spawn), the torus is the exact image
 * in both modes, and the measure compares the subtrees' points too: the rectangle seen through
 * the torus gives most samples a measured point (without the subtrees' points 47% of them at
 * 512 x 512, with them 68%), all within rho. */
static void exact_subtrees_start_at_exact_hits_and_are_measured(void **state) {
  (void)state;
  rt_scene_t s;
  fx_scene_file("fig11", 192, &s);
  int torus = -1;
  for (int i = 0; i < s.nobject; i++)
    if (strcmp(s.object[i].name, "glass torus") == 0)
      torus = i;
  assert_true(torus >= 0);
  rt_image_t e;
  fx_render_exact(&s, 1, 2, &e);
  for (int cert = 0; cert <= 1; cert++) {
    pt_options_t o = PT_OPTIONS_DEFAULT;
    o.certified = cert;
    o.measure = 1;
    rt_image_t p;
    pt_stats_t st;
    fx_render_pencil(&s, 1, 2, &o, &p, NULL, &st);
    fx_diff_t d = fx_object_difference(&e, &p, torus, 0.1);
    print_message("fig11 192x192 certified %d: %d torus pixels, %llu partly exact cells, largest "
                  "difference %.3g; %llu of %llu samples with measured points, %llu within rho\n",
                  cert, d.n, (unsigned long long)st.domains_partial, d.worst,
                  (unsigned long long)st.with_points, (unsigned long long)st.measured,
                  (unsigned long long)st.within);
    assert_true(d.n > 5000 && st.domains_partial > 0);
    assert_true(d.worst < 0.01);
    /* most samples not traced exactly (those have no pencil points) have a measured point;
     * without the subtrees' points it was 46% of all samples, when 1-pixel domains at 1 spp
     * were still pencil-traced */
    uint64_t pencil_samples = st.measured - st.samples[PT_METHOD_EXACT];
    print_message("  %llu of %llu samples not traced exactly have measured points\n",
                  (unsigned long long)st.with_points, (unsigned long long)pencil_samples);
    assert_true(st.with_points * 100 > pencil_samples * 55);
    assert_int_equal(st.within, st.measured);
    assert_int_equal(st.mismatches, 0);
    rt_image_free(&p);
  }
  rt_image_free(&e);
  rt_scene_free(&s);
}

/* A certified render's statistics: something was measured, and every sample within rho. */
static void all_within(const char *what, const pt_stats_t *st) {
  print_message("%s certified: %llu halves, %llu of %llu samples within rho, largest %.3f\n", what,
                (unsigned long long)st->halved_lattice_cells, (unsigned long long)st->within,
                (unsigned long long)st->measured, st->max_error);
  assert_true(st->with_points > 0);
  assert_int_equal(st->within, st->measured);
}

/* Certified mode halves a measured lattice cell whose nodes are too curved in one direction
 * only (interp_error.c, pt__halving) instead of cutting it into four measured quarters: it fires on
 * Fig. 8 at 49 spp, where the board seen through the glass ball is compressed vertically, and
 * every sample stays within rho there and on scenes/balls.json; the default mode, whose
 * quarters are first estimated at no cost, never halves. */
static void certified_halves_stay_within_rho(void **state) {
  (void)state;
  rt_scene_t s;
  fx_fig8(&s, 64, 64);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  pt_stats_t st = fx_pencil_stats(&s, 7, 1, &o);
  assert_int_equal(st.halved_lattice_cells, 0);
  o.certified = 1;
  st = fx_pencil_stats(&s, 7, 1, &o);
  all_within("fig8 64x64 49 spp", &st);
  assert_true(st.halved_lattice_cells > 0);
  assert_true(st.max_error <= o.rho);
  rt_scene_free(&s);
  fx_scene_file("balls", 128, &s);
  st = fx_pencil_stats(&s, 4, 2, &o);
  all_within("balls 128 wide 16 spp", &st);
  rt_scene_free(&s);
}

/* val_image_bias (bench pencil, figures): the largest mean difference over one object's
 * pixels. Fig. 8 at 32 x 32: an image equal to the exact one has none; the ball's pixels all
 * brighter by 0.02 give 0.02 on object 1; half of them brighter and half darker by 0.04, as
 * the checkerboard's flips are, give none; objects of fewer than VAL_BIAS_PIXELS pixels are
 * not judged. */
static void image_bias_finds_systematic_errors(void **state) {
  (void)state;
  enum { W = 32, H = 32 };
  rt_scene_t s;
  fx_fig8(&s, W, H);
  rt_image_t x, p;
  fx_render_exact(&s, 1, 1, &x);
  assert_int_equal(rt_image_alloc(&p, W, H), RT_OK);
  int nball = 0;
  for (int k = 0; k < W * H; k++)
    nball += x.ch[RT_CH_ID][k] == 1.0f;
  assert_true(nball >= VAL_BIAS_PIXELS);
  double bias;
  int obj;
  for (int c = 0; c < 3; c++) /* case 1: equal */
    memcpy(p.ch[c], x.ch[c], sizeof(float) * W * H);
  assert_int_equal(val_image_bias(&s, &p, &x, &bias, &obj), 0);
  assert_true(bias == 0.0 && obj >= -1);
  for (int k = 0; k < W * H; k++) /* case 2: the ball brighter */
    if (x.ch[RT_CH_ID][k] == 1.0f)
      for (int c = 0; c < 3; c++)
        p.ch[c][k] = x.ch[c][k] + 0.02f;
  assert_int_equal(val_image_bias(&s, &p, &x, &bias, &obj), 0);
  assert_int_equal(obj, 1);
  assert_true(fabs(bias - 0.02) < 1e-6);
  int m = 0; /* case 3: both ways, in equal numbers */
  for (int k = 0; k < W * H; k++)
    if (x.ch[RT_CH_ID][k] == 1.0f && m < nball / 2 * 2) {
      for (int c = 0; c < 3; c++)
        p.ch[c][k] = x.ch[c][k] + (m % 2 ? -0.04f : 0.04f);
      m++;
    } else if (x.ch[RT_CH_ID][k] == 1.0f) {
      for (int c = 0; c < 3; c++)
        p.ch[c][k] = x.ch[c][k];
    }
  assert_int_equal(val_image_bias(&s, &p, &x, &bias, &obj), 0);
  assert_true(bias < 1e-6);
  rt_image_free(&p);
  rt_image_free(&x);
  rt_scene_free(&s);
}

/* pt_max (internal.h), the lattice's error maximum: the larger operand, and NaN when either
 * is NaN (fmax would drop it), so that an error computed as NaN is rejected, not accepted. */
static void error_maximum_keeps_nan(void **state) {
  (void)state;
  assert_true(px_max(1.0, 2.0) == 2.0);
  assert_true(px_max(2.0, 1.0) == 2.0);
  assert_true(px_max(-1.0, INFINITY) == INFINITY);
  assert_true(isnan(px_max(NAN, 1.0)));
  assert_true(isnan(px_max(1.0, NAN)));
  assert_true(isnan(px_max(px_max(0.0, NAN), 3.0)));
  assert_false(px_max(NAN, 0.0) <= 0.5); /* a test written as e <= tol rejects it */
}

/* Which surfaces the Fig. 10 measure compares (rt_object_measured): those with a diffuse term.
 * In Fig. 8 that is the checkerboard alone, the paper's surface (the glass has kd = 0). A plane
 * without a texture under the glass ball is measured too, so that a scene without a checkerboard
 * does not pass as error-free because nothing was compared; a scene of glass alone has no
 * measured point, and says so (with_points = 0). */
static void measure_counts_diffuse_surfaces(void **state) {
  (void)state;
  rt_scene_t s;
  fx_fig8(&s, 32, 32);
  assert_true(rt_object_measured(&s, 0));  /* the checkerboard */
  assert_false(rt_object_measured(&s, 1)); /* the glass ball */
  rt_scene_free(&s);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  for (int plain = 1; plain >= 0; plain--) {
    rt_scene_init(&s);
    rt_material_t grey = rt_material_default("grey"), glass = rt_material_default("glass");
    glass.ka = glass.kd = 0.0;
    glass.ks = 0.6;
    glass.kr = 0.15;
    glass.kt = 0.75;
    glass.ior = 1.5;
    int mg, ml, ball;
    assert_int_equal(rt_scene_add_material(&s, &grey, &mg), RT_OK);
    assert_int_equal(rt_scene_add_material(&s, &glass, &ml), RT_OK);
    if (plain) /* no material2: one colour, no checkerboard anywhere */
      assert_int_equal(rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0),
                                          mg, -1, 1.0, NULL),
                       RT_OK);
    assert_int_equal(rt_scene_add_sphere(&s, px_vec3(0.0, 1.5, 0.0), 1.0, ml, &ball), RT_OK);
    rt_light_t l = {RT_LIGHT_POINT, {-5.0, 6.0, -2.5}, {1, 1, 1}, RT_FALLOFF_NONE,
                    {0, 0, 0},      {0, 0, 0},         0};
    rt_scene_add_light(&s, &l);
    s.camera = (rt_camera_t){{0.0, 3.0, -6.0}, {0.0, 0.9, 0.0}, {0, 1, 0}, 40.0, 32, 32};
    assert_int_equal(rt_scene_prepare(&s), RT_OK);
    pt_stats_t st = fx_pencil_stats(&s, 2, 1, &o);
    print_message("plain plane %d: %llu of %llu samples with measured points, max %g\n", plain,
                  (unsigned long long)st.with_points, (unsigned long long)st.measured,
                  st.max_error);
    assert_int_equal(st.measured, 32 * 32 * 4);
    if (plain) {
      assert_true(st.with_points > st.measured / 2); /* the plane fills most of the view */
      assert_true(st.max_error > 0.0);               /* its points were compared */
      assert_true(st.within >= st.measured * 998 / 1000);
    } else {
      assert_int_equal(st.with_points, 0);
      assert_true(st.max_error == 0.0);
    }
    rt_scene_free(&s);
  }
}

/* Domains are independent and each is processed by one thread: bitwise equal images and the
 * same counters for 1 and 2 threads. */
static void image_does_not_depend_on_threads(void **state) {
  (void)state;
  rt_scene_t s;
  fx_fig8(&s, 30, 22);
  rt_image_t a, b;
  pt_stats_t sa, sb;
  static float ma[30 * 22], mb[30 * 22];
  pt_extra_t xa = {NULL, ma, NULL}, xb = {NULL, mb, NULL};
  fx_render_pencil(&s, 3, 1, NULL, &a, &xa, &sa);
  fx_render_pencil(&s, 3, 2, NULL, &b, &xb, &sb);
  fx_assert_images_equal(&a, &b);
  assert_memory_equal(ma, mb, sizeof ma);
  assert_true(sa.domains == sb.domains && sa.samples[0] == sb.samples[0] &&
              sa.samples[1] == sb.samples[1] && sa.samples[2] == sb.samples[2]);
  rt_image_free(&a);
  rt_image_free(&b);
  rt_scene_free(&s);
}

/* Lattice points shared by neighbouring lattice cells are traced once per cell and reused
 * (interp_memo.c): the image and every decision must be those of tracing each lattice cell's points
 * anew, in both modes. The reused points live in other storage than the re-traced ones, so this
 * also fails when an evaluation reads what a lattice point did not write (certified mode once
 * read the rays of miss nodes that a corner had not reached). */
static void lattice_memo_changes_nothing(void **state) {
  (void)state;
  rt_scene_t s;
  fx_fig8(&s, 96, 96);
  for (int cert = 0; cert <= 1; cert++) {
    rt_image_t a, b;
    pt_stats_t sa, sb;
    pt_options_t o = PT_OPTIONS_DEFAULT;
    o.certified = cert;
    fx_render_pencil(&s, 3, 1, &o, &a, NULL, &sa);
    o.memo = 0;
    fx_render_pencil(&s, 3, 1, &o, &b, NULL, &sb);
    fx_assert_images_equal(&a, &b);
    assert_true(sa.lattice_reused > 0);
    assert_int_equal(sb.lattice_reused, 0);
    assert_int_equal(sa.lattice_points + sa.lattice_reused, sb.lattice_points);
    assert_true(sa.samples[0] == sb.samples[0] && sa.samples[1] == sb.samples[1] &&
                sa.samples[2] == sb.samples[2] && sa.partial == sb.partial);
    rt_image_free(&a);
    rt_image_free(&b);
  }
  rt_scene_free(&s);
}

/* The exact walks of an interpolated sample's nodes are carried for four samples at once
 * (opt->simd, eval.c's exact_geom4(); AVX2 where the CPU has it): the image, every channel and
 * every decision must be those of walking each sample alone, on the glass ball (spheres and a
 * plane), the same ball reflecting by Fresnel alone (kr 0: a mirror step is walked one sample at
 * a time, walk_ray_full()), a glass polyhedron (polygons) and the balls of spheres-10, in both
 * modes, on two threads against one; and the groups must have carried steps (more than two
 * samples a step on average). The images are float32: a walk differing in its last bits need not
 * show here, which test_render_shade.c's comparisons of the lanes do see. */
/* Scene s at side x side samples a pixel with the exact walks in groups of four (two threads)
 * and one sample at a time (one thread), in mode `cert`: the same image, samples, partial and
 * fallback samples, lattice points and exact rays. The grouped render's statistics in *sa. */
static void simd_changes_nothing(const rt_scene_t *s, int side, int cert, pt_stats_t *sa) {
  rt_image_t a, b;
  pt_stats_t sb;
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.certified = cert;
  fx_render_pencil(s, side, 2, &o, &a, NULL, sa);
  o.simd = 0;
  fx_render_pencil(s, side, 1, &o, &b, NULL, &sb);
  fx_assert_images_equal(&a, &b);
  assert_true(sb.walk_steps == 0 && sb.walk_lanes == 0 && sb.walk_left == 0);
  assert_true(sa->samples[0] == sb.samples[0] && sa->samples[1] == sb.samples[1] &&
              sa->samples[2] == sb.samples[2] && sa->partial == sb.partial &&
              sa->fallbacks == sb.fallbacks && sa->lattice_points == sb.lattice_points);
  assert_true(rt_stats_total(&sa->rays) == rt_stats_total(&sb.rays));
  rt_image_free(&a);
  rt_image_free(&b);
}

static void walks_of_four_change_nothing(void **state) {
  (void)state;
  const char *files[4] = {NULL, NULL, "fig11", "spheres-10"};
  for (int f = 0; f < 4; f++)
    for (int cert = 0; cert <= 1; cert++) {
      rt_scene_t s;
      if (files[f])
        fx_scene_file(files[f], 64, &s);
      else
        fx_fig8(&s, 64, 64);
      for (int m = 0; f == 1 && m < s.nmaterial; m++)
        if (s.material[m].kt > 0.0) {
          s.material[m].kr = 0.0;
          s.material[m].fresnel = 1;
        }
      pt_stats_t sa;
      simd_changes_nothing(&s, 4, cert, &sa);
      assert_true(sa.walk_steps > 0 && sa.walk_lanes > 2 * sa.walk_steps);
      rt_scene_free(&s);
    }
}

/* Scene s from the JSON text `json` (a test's inline scene, named `name` in errors). */
#define LOAD_INLINE(name, json, s)                                                                 \
  do {                                                                                             \
    char err_[512];                                                                                \
    rt_scene_init(s);                                                                              \
    assert_int_equal(io_scene_load_buffer(name, json, sizeof json - 1, s, err_, sizeof err_), 0);  \
  } while (0)

/* Lanes of a group that leave their path part way (pt_stats_t.walk_left), which no other scene here
 * makes happen: a big glass ball near the eye and a small one behind it, seen through it. In the
 * small ball's image (x 35 to 37 at 40 x 40, just inside the big ball's right rim) a sample's path
 * goes into and out of the big ball, into the small one, reflects inside it, out, and meets the big
 * ball again (node 19, depth 5; that node's reflection is traced exactly in those domains, so every
 * sample there walks the path to it). After four curved refractions the pixels where that last ray
 * meets the big ball are no convex set: a thin band at x = 35 and a patch from about 35.4 on, with
 * a gap narrower than half a pixel between. The one-pixel lattice cells at x 35, y 16 and 17 have
 * their grid line x = 35 in the band and x = 35.5 in the patch: all nine points meet the ball,
 * while the samples at x = 35.1 and 35.3 miss it at that last step of their group's walk (their
 * x->ok bits stay clear) and are traced exactly from there. The scene, size and sample grid come
 * from a search for such lanes, and other sizes or grids need not put a sample in the gap: 20 lanes
 * leave at 5 x 5 samples a pixel in the default mode, and 6 at 4 x 4 in certified mode (which
 * plans other lattice cells since they test the lattice cell's own footprint: at 5 x 5 none leave
 * there now). Such a lane must end as the one-sample walk (opt->simd 0) ends it: the same image,
 * samples, fallbacks and exact rays. */
static const char glass_behind_glass[] =
    "{\"camera\": {\"eye\": [0, 2.5, -5], \"look_at\": [0, 1, 0], \"up\": [0, 1, 0], \"fov\": 40,"
    " \"width\": 40, \"height\": 40},"
    " \"settings\": {\"ambient\": 1, \"background\": [0.35, 0.55, 0.85], \"max_depth\": 6,"
    " \"caustics\": \"off\"},"
    " \"materials\": {\"white\": {\"color\": [0.9, 0.9, 0.9], \"ka\": 0.2, \"kd\": 0.8},"
    "  \"red\": {\"color\": [0.85, 0.12, 0.1], \"ka\": 0.2, \"kd\": 0.8},"
    "  \"glass\": {\"ka\": 0, \"kd\": 0, \"ks\": 0.6, \"phong\": 80, \"kr\": 0.15, \"kt\": 0.75,"
    "  \"ior\": 1.5}},"
    " \"lights\": [{\"type\": \"point\", \"position\": [-5, 6, -2.5], \"intensity\": 1}],"
    " \"objects\": ["
    "  {\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"material\": \"white\","
    "   \"checker\": {\"size\": 1, \"material\": \"red\", \"u\": [1, 0, 0]}},"
    "  {\"type\": \"sphere\", \"center\": [-0.35, 1.45, -0.8], \"radius\": 1, \"material\": "
    "\"glass\"},"
    "  {\"type\": \"sphere\", \"center\": [0.55, 0.8, 1.65], \"radius\": 0.5, \"material\": "
    "\"glass\"}]}";

static void lanes_leaving_walks_of_four_change_nothing(void **state) {
  (void)state;
  rt_scene_t s;
  LOAD_INLINE("glass_behind_glass", glass_behind_glass, &s);
  for (int cert = 0; cert <= 1; cert++) {
    pt_stats_t sa;
    simd_changes_nothing(&s, cert ? 4 : 5, cert, &sa);
    print_message("certified %d: %llu lanes left their path in %llu steps\n", cert,
                  (unsigned long long)sa.walk_left, (unsigned long long)sa.walk_steps);
    assert_true(sa.walk_left > 0); /* the scene still makes lanes leave */
  }
  rt_scene_free(&s);
}

/* Two glass balls above a white floor, the light above both: the floor sees it through the high
 * ball (transmittance kt = 0.75) in a ring and through both (0.5625) in the disc inside it. Both
 * are "partly" to the lit and blocked bits, so before rt_tree_node_t.through a domain whose
 * centre and corners all saw the light through glass reused its centre's transmittance for every
 * sample, and the disc's edge came out in blocks (up to 0.13 off on the floor at 48 x 48). */
static const char nested_glass_shadows[] =
    "{\"camera\": {\"eye\": [0, 7, -5], \"look_at\": [0, 0, 0.5], \"up\": [0, 1, 0], \"fov\": 35,"
    " \"width\": 48, \"height\": 48},"
    " \"settings\": {\"ambient\": 1, \"background\": [0.35, 0.55, 0.85], \"max_depth\": 4,"
    " \"caustics\": \"off\"},"
    " \"materials\": {\"white\": {\"color\": [0.9, 0.9, 0.9], \"ka\": 0.2, \"kd\": 0.8},"
    "  \"glass\": {\"ka\": 0, \"kd\": 0, \"ks\": 0.6, \"phong\": 80, \"kr\": 0.15, \"kt\": 0.75,"
    "  \"ior\": 1.5}},"
    " \"lights\": [{\"type\": \"point\", \"position\": [0.5, 9, 4], \"intensity\": 1}],"
    " \"objects\": ["
    "  {\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"material\": \"white\"},"
    "  {\"type\": \"sphere\", \"center\": [0, 1.5, 2.2], \"radius\": 0.5, \"material\": \"glass\"},"
    "  {\"type\": \"sphere\", \"center\": [0.15, 4.5, 3.0], \"radius\": 0.9, \"material\": "
    "\"glass\"}]}";

/* pt_tree_agree() on one node: a light both reach through glass agrees only with the same
 * transmittance; one the other node faces away from is not compared (as before). And the exact
 * tracer records the floor's two transmittances in nested_glass_shadows. */
static void lights_through_other_glass_disagree(void **state) {
  (void)state;
  static rt_tree_node_t na[1];
  static pt_cnode_t nc[1];
  rt_tree_t a = rt_tree_make(na, 1);
  a.n = 1;
  na[0] = (rt_tree_node_t){.parent = -1,
                           .kind = RT_RAY_PRIMARY,
                           .object = 0,
                           .prim = 0,
                           .texel = -1,
                           .through = rt_through_hash(0, rt_rgb(0.75, 0.75, 0.75))};
  pt_ctree_t c = {nc, 1, 0, 0};
  const pt_ctree_t *cs[1] = {&c};
  int map[1];
  uint8_t agree[1];
  uint32_t light[1];
  rt_tree_node_t b = na[0];
  rt_tree_t tb = rt_tree_make(&b, 1);
  tb.n = 1;
  pt_ctree_from(&c, &tb);
  assert_true(pt_tree_agree(&a, cs, 1, map, agree, light)); /* the same transmittance */
  assert_int_equal(light[0], ~0u);
  b.through = rt_through_hash(0, rt_rgb(0.5625, 0.5625, 0.5625)); /* through two balls */
  pt_ctree_from(&c, &tb);
  assert_false(pt_tree_agree(&a, cs, 1, map, agree, light));
  assert_int_equal(agree[0], 1);      /* the same surface ... */
  assert_int_equal(light[0] & 1u, 0); /* ... but not the same light */
  b.through = 0;                      /* the corner faces away from the light: not compared */
  pt_ctree_from(&c, &tb);
  assert_true(pt_tree_agree(&a, cs, 1, map, agree, light));
  /* two lights: light 1 lit at both stays, light 0 through other glass drops */
  na[0].lit = b.lit = 2u;
  b.through = rt_through_hash(0, rt_rgb(0.5625, 0.5625, 0.5625));
  pt_ctree_from(&c, &tb);
  assert_false(pt_tree_agree(&a, cs, 1, map, agree, light));
  assert_int_equal(light[0] & 3u, 2u);
  /* light 0 through glass at one and faced away from at the other, light 1 the reverse: both
   * drop */
  na[0].lit = b.lit = 0u;
  b.through = rt_through_hash(1, rt_rgb(0.75, 0.75, 0.75));
  pt_ctree_from(&c, &tb);
  assert_false(pt_tree_agree(&a, cs, 1, map, agree, light));
  assert_int_equal(light[0] & 3u, 0u);
  /* the tracer: floor points in the ring and in the disc */
  rt_scene_t s;
  LOAD_INLINE("nested_glass_shadows", nested_glass_shadows, &s);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_view_t v;
  rt_view_make(&s.camera, &v);
  static rt_tree_node_t buf[64];
  rt_tree_t t = rt_tree_make(buf, 64);
  uint32_t one = rt_through_hash(0, rt_rgb(0.75, 0.75, 0.75)),
           two = rt_through_hash(0, rt_rgb(0.5625, 0.5625, 0.5625));
  int ring = 0, disc = 0;
  for (int j = 0; j < s.camera.height; j++)
    for (int i = 0; i < s.camera.width; i++) {
      trace_tree(&s, &plan, &v, i + 0.5, j + 0.5, &t);
      if (t.node[0].object != 0)
        continue;
      ring += t.node[0].through == one;
      disc += t.node[0].through == two;
    }
  print_message("floor pixels seeing the light through one ball %d, through both %d\n", ring, disc);
  assert_true(ring > 20 && disc > 20);
  rt_scene_free(&s);
}

/* Scene s by the exact and the pencil renderer at side x side samples a pixel: the largest
 * difference in R, G or B over the pixels where the exact image sees object `object` here and,
 * when `around`, at the 8 neighbours too (away from other objects' images and their rims);
 * *object_px counts them. */
static double object_seen_off(const rt_scene_t *s, int side, int object, int around,
                              int *object_px) {
  rt_image_t e, p;
  fx_render_exact(s, side, 2, &e);
  fx_render_pencil(s, side, 2, NULL, &p, NULL, NULL);
  int w = e.width, h = e.height, off = 0;
  double most = 0.0;
  *object_px = 0;
  for (int j = 1; j + 1 < h; j++)
    for (int i = 1; i + 1 < w; i++) {
      int flat = 1; /* the object here (and around) */
      for (int dj = -around; dj <= around; dj++)
        for (int di = -around; di <= around; di++)
          flat = flat && e.ch[RT_CH_ID][(size_t)(j + dj) * w + (size_t)(i + di)] == (float)object;
      if (!flat)
        continue;
      (*object_px)++;
      size_t k = (size_t)j * w + (size_t)i;
      for (int c = RT_CH_R; c <= RT_CH_B; c++) {
        double d = fabs((double)p.ch[c][k] - (double)e.ch[c][k]);
        most = fmax(most, d);
        off += c == RT_CH_R && d > 1.0 / 32.0;
      }
    }
  print_message("object %d's pixels %d, off by more than 1/32: %d, largest %.5f\n", object,
                *object_px, off, most);
  rt_image_free(&e);
  rt_image_free(&p);
  return most;
}

/* object_seen_off() over the pixels where the object is seen here and around. */
static double object_off(const rt_scene_t *s, int side, int object, int *object_px) {
  return object_seen_off(s, side, object, 1, object_px);
}

/* object_off() of the floor, object 0. */
static double floor_off(const rt_scene_t *s, int side, int *floor_px) {
  return object_off(s, side, 0, floor_px);
}

/* The pencil renderer on nested_glass_shadows: no floor pixel (away from the balls' images) more
 * than 1/32 off the exact renderer's; before rt_tree_node_t.through, 19 were, by up to 0.13. */
static void nested_glass_shadows_not_reused(void **state) {
  (void)state;
  rt_scene_t s;
  LOAD_INLINE("nested_glass_shadows", nested_glass_shadows, &s);
  int floor_px;
  assert_true(floor_off(&s, 2, &floor_px) <= 1.0 / 32.0);
  assert_true(floor_px > 1000);
  rt_scene_free(&s);
}

/* The light probes' scenes (docs/journal/2026-12-05-silent-light.md): a white floor (object 0)
 * and a blue material, returned, for what stands over it. */
static int floor_scene(rt_scene_t *s) {
  rt_scene_init(s);
  rt_material_t white = rt_material_default("white"), blue = rt_material_default("blue");
  white.color = rt_rgb(0.8, 0.8, 0.8);
  blue.color = rt_rgb(0.1, 0.2, 0.9);
  int mw, mb;
  rt_scene_add_material(s, &white, &mw);
  rt_scene_add_material(s, &blue, &mb);
  rt_scene_add_plane(s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mw, -1, 1.0, NULL);
  return mb;
}

/* ... seen from above and in front at 96 x 96, and prepared. */
static void floor_scene_ready(rt_scene_t *s) {
  s->camera = (rt_camera_t){{0.0, 3.0, -6.0}, {0.0, 0.0, 0.5}, {0, 1, 0}, 40.0, 96, 96};
  assert_int_equal(rt_scene_prepare(s), RT_OK);
}

/* Boxes from lo[b] to hi[b], b < n <= 4, as one polyhedron (material m) in scene s. */
static void add_boxes(rt_scene_t *s, const px_vec3_t *lo, const px_vec3_t *hi, int n, int m) {
  static const int box[24] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4,
                              2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  px_vec3_t v[32];
  int idx[96], len[24];
  assert_true(n <= 4);
  for (int b = 0; b < n; b++) {
    for (int k = 0; k < 8; k++)
      v[8 * b + k] =
          px_vec3(k & 1 ? hi[b].x : lo[b].x, k & 2 ? hi[b].y : lo[b].y, k & 4 ? hi[b].z : lo[b].z);
    for (int k = 0; k < 24; k++)
      idx[24 * b + k] = 8 * b + box[k];
    for (int f = 0; f < 6; f++)
      len[6 * b + f] = 4;
  }
  assert_int_equal(rt_scene_add_polyhedron(s, v, 8 * n, idx, len, 6 * n, m, NULL, NULL, 0), RT_OK);
}

/* A box from lo to hi (material m) in scene s. */
static void add_box(rt_scene_t *s, px_vec3_t lo, px_vec3_t hi, int m) {
  add_boxes(s, &lo, &hi, 1, m);
}

/* The shadow of a long thin object: a rod 0.04 thick and 6 long, 3.5 above the floor, under a
 * parallel light. Its bounding sphere (radius 3) is far larger than the gaps between the traced
 * points, but its shadow is narrower than they are: what it holds (the ball of radius 0.02 about
 * its centre) decides the guard. Before that, stretches of the shadow were lost between the
 * points: 40 pixels, up to 0.64, at 96 x 96, 9 spp. */
static void thin_objects_keep_their_shadows(void **state) {
  (void)state;
  rt_scene_t s;
  int mb = floor_scene(&s);
  add_box(&s, px_vec3(-0.52, 3.48, -2.5), px_vec3(-0.48, 3.52, 3.5), mb);
  rt_light_t sun = {RT_LIGHT_PARALLEL, {0.05, -1.0, 0.02}, {1, 1, 1}, RT_FALLOFF_NONE,
                    {0, 0, 0},         {0, 0, 0},          0};
  assert_int_equal(rt_scene_add_light(&s, &sun), RT_OK);
  floor_scene_ready(&s);
  pt_bsphere_t b[2];
  assert_int_equal(pt_guard_spheres(&s, b, 2), 1);
  assert_close(b[0].w, 0.02, 1e-12, 1e-12); /* the ball it holds */
  int floor_px;
  assert_true(floor_off(&s, 3, &floor_px) <= 1.0 / 32.0);
  assert_true(floor_px > 5000);
  rt_scene_free(&s);
}

/* A lit gap 0.06 wide between the shadows of two slabs 1 thick: every traced point sees the light
 * blocked, but by one slab or the other (rt_blocked_hash() in rt_tree_node_t.through and
 * pt_geom_t.through), so the domains and lattice cells across the gap disagree. Before, the gap
 * was lost between the points: 36 pixels off by up to 0.64 at 96 x 96, 4 spp. */
static void gaps_between_shadows_kept(void **state) {
  (void)state;
  rt_scene_t s;
  int mb = floor_scene(&s);
  add_box(&s, px_vec3(-1.97, 2.95, -1.0), px_vec3(0.03, 3.95, 2.0), mb);
  add_box(&s, px_vec3(0.09, 2.95, -1.0), px_vec3(2.09, 3.95, 2.0), mb);
  rt_light_t l = {RT_LIGHT_POINT, {0.0, 8.0, 0.5}, {1, 1, 1}, RT_FALLOFF_NONE,
                  {0, 0, 0},      {0, 0, 0},       0};
  assert_int_equal(rt_scene_add_light(&s, &l), RT_OK);
  floor_scene_ready(&s);
  int floor_px;
  assert_true(floor_off(&s, 2, &floor_px) <= 1.0 / 32.0);
  assert_true(floor_px > 3000);
  rt_scene_free(&s);
}

/* A scene with more lights than the trees' visibility masks hold (PT_MAX_LIGHTS): 32 dark ones
 * first, then the one that casts the shadows of seven small balls onto the floor. Light 32 has no
 * bit in the masks, so that the corners' and the lattice points' agreement says nothing about it;
 * before the planner knew, the balls' shadows between the lattice points were interpolated away
 * (up to 0.41 off at 96 x 96, 9 spp). */
static void lights_past_the_masks_keep_their_shadows(void **state) {
  (void)state;
  rt_scene_t s;
  int mb = floor_scene(&s);
  for (int i = 0; i < 7; i++)
    rt_scene_add_sphere(&s, px_vec3(-1.5 + 0.5 * i, 2.0, 0.3 * i), 0.03, mb, NULL);
  rt_light_t l = {RT_LIGHT_POINT, {0.0, 30.0, 0.0}, {0, 0, 0}, RT_FALLOFF_NONE,
                  {0, 0, 0},      {0, 0, 0},        0};
  for (int i = 0; i < PT_MAX_LIGHTS; i++)
    assert_int_equal(rt_scene_add_light(&s, &l), RT_OK);
  l.v = px_vec3(-0.5, 6.0, 0.5);
  l.intensity = rt_rgb(1, 1, 1);
  assert_int_equal(rt_scene_add_light(&s, &l), RT_OK);
  floor_scene_ready(&s);
  int floor_px;
  assert_true(floor_off(&s, 2, &floor_px) <= 1.0 / 32.0);
  assert_true(floor_px > 5000);
  rt_scene_free(&s);
}

/* A plate 4 x 3 x 0.2 at height 3 with a slot 2 long and `gap` wide through it along z (material
 * m): one closed polyhedron, not convex, over a 3 x 3 grid of columns whose middle one is open. */
static void add_slotted_plate(rt_scene_t *s, double gap, int m) {
  const double xs[4] = {-2.0, -0.5 * gap, 0.5 * gap, 2.0}, zs[4] = {-1.5, -1.0, 1.0, 1.5};
  px_vec3_t v[32];
  for (int k = 0; k < 2; k++)
    for (int j = 0; j < 4; j++)
      for (int i = 0; i < 4; i++)
        v[k * 16 + j * 4 + i] = px_vec3(xs[i], 3.0 + 0.2 * k, zs[j]);
#define VX(i, j, k) ((k)*16 + (j)*4 + (i))
  int idx[4 * 40], len[40], nf = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      if (i == 1 && j == 1)
        continue; /* the slot */
      const int top[4] = {VX(i, j, 1), VX(i, j + 1, 1), VX(i + 1, j + 1, 1), VX(i + 1, j, 1)};
      const int bot[4] = {VX(i, j, 0), VX(i + 1, j, 0), VX(i + 1, j + 1, 0), VX(i, j + 1, 0)};
      memcpy(&idx[4 * nf], top, sizeof top), len[nf++] = 4;
      memcpy(&idx[4 * nf], bot, sizeof bot), len[nf++] = 4;
      /* the sides facing the outside or the slot: (di, dj) and the edge's ends (a, b) */
      const int side[4][6] = {{-1, 0, i, j, i, j + 1},
                              {1, 0, i + 1, j + 1, i + 1, j},
                              {0, -1, i + 1, j, i, j},
                              {0, 1, i, j + 1, i + 1, j + 1}};
      for (int e = 0; e < 4; e++) {
        int ni = i + side[e][0], nj = j + side[e][1];
        if (ni >= 0 && ni < 3 && nj >= 0 && nj < 3 && !(ni == 1 && nj == 1))
          continue;
        const int q[4] = {VX(side[e][2], side[e][3], 0), VX(side[e][4], side[e][5], 0),
                          VX(side[e][4], side[e][5], 1), VX(side[e][2], side[e][3], 1)};
        memcpy(&idx[4 * nf], q, sizeof q), len[nf++] = 4;
      }
    }
#undef VX
  assert_int_equal(rt_scene_add_polyhedron(s, v, 32, idx, len, nf, m, NULL, NULL, 0), RT_OK);
}

/* A lit gap inside one object's shadow: a slot 0.03 wide through a plate, under a parallel light,
 * seen on the floor as a lit strip about half a pixel wide. Every traced point beside the strip
 * is blocked by the same object, so nothing but the shadow guard tells of the gap: a plate that
 * is not convex holds nothing known and counts as thin, so the guard fires and the floor is
 * shaded per sample near it. Given its bounding ball as what it holds instead, the strip was lost:
 * 12 pixels off by more than 1/32, up to 0.36, at 96 x 96, 4 spp. */
static void slots_in_shadows_kept(void **state) {
  (void)state;
  rt_scene_t s;
  int mb = floor_scene(&s);
  add_slotted_plate(&s, 0.03, mb);
  rt_light_t sun = {RT_LIGHT_PARALLEL, {0.02, -1.0, 0.01}, {1, 1, 1}, RT_FALLOFF_NONE,
                    {0, 0, 0},         {0, 0, 0},          0};
  assert_int_equal(rt_scene_add_light(&s, &sun), RT_OK);
  floor_scene_ready(&s);
  int floor_px;
  assert_true(floor_off(&s, 2, &floor_px) <= 1.0 / 32.0);
  assert_true(floor_px > 5000);
  rt_scene_free(&s);
}

/* The pencil renderer's Fig. 10 measure of s at 3 x 3 samples a pixel: every sample within rho
 * and none with a path its exact tree lacks (a face lost between the traced rays). */
static void measured_all_within(const rt_scene_t *s) {
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  pt_stats_t st = fx_pencil_stats(s, 3, 2, &o);
  print_message("path mismatches %llu, within rho %llu of %llu\n",
                (unsigned long long)st.mismatches, (unsigned long long)st.within,
                (unsigned long long)st.measured);
  assert_int_equal(st.mismatches, 0);
  assert_int_equal(st.within, st.measured);
}

/* tests/data/pencil_star_tir.json, a glass star prism over a white floor at 192 x 192, 1 spp
 * (not prepared). */
/* Scene tests/data/NAME into s. */
static void load_data_scene(const char *name, rt_scene_t *s) {
  char path[1024], err[512];
  snprintf(path, sizeof path, "%s/tests/data/%s", PENCIL_SOURCE_DIR, name);
  rt_scene_init(s);
  assert_int_equal(io_scene_load(path, s, err, sizeof err), 0);
}

static void load_star(rt_scene_t *s) {
  load_data_scene("pencil_star_tir.json", s);
}

/* A total internal reflection inside a lattice cell (tests/data/pencil_star_tir.json, a glass star
 * prism without Fresnel): the reflected node's weight is kr at seven grid points and kr + kt at
 * two, its ray and surface the same at all nine, so the scene search confirmed it and the bilinear
 * weight (0.54 against the exact 0.085) scaled its subtree traced per sample: 29 pixels of the
 * star more than 1/32 too bright, up to 0.235, with --measure silent. A grid whose points' weights
 * differ does not confirm the node now. */
static void weight_jump_not_interpolated(void **state) {
  (void)state;
  rt_scene_t s;
  load_star(&s);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  int star_px;
  double most = object_seen_off(&s, 1, 1, 0, &star_px);
  assert_true(star_px > 2000);
  assert_true(most <= 1.0 / 32.0);
  rt_scene_free(&s);
}

/* The same star with a Fresnel split (kr 0, kt 1, the light twice as bright): the reflected node's
 * weight rises continuously but steeply to 1 at the critical angle, and bilinear interpolation
 * over the cell missed it: 43 pixels of the star more than 1/32 too bright, up to 0.155. Now a
 * verify node whose weight's interpolation error, times a bound on what its subtree brings, is
 * over the brightness tolerance is traced per sample. That left 4 pixels of another cell 0.065 too
 * dark: a node that is not a verify node handed its interpolated weight to the children it traced
 * per sample, uncounted. Their error is counted now too, and no pixel of the star is more than
 * 1/32 off (docs/journal/2026-12-06-weight-below.md). */
static void fresnel_weight_near_the_critical_angle(void **state) {
  (void)state;
  rt_scene_t s;
  load_star(&s);
  int glass = rt_scene_find_material(&s, "glass");
  assert_true(glass >= 0 && s.nlight == 1);
  s.material[glass].fresnel = 1;
  s.material[glass].kr = 0.0;
  s.material[glass].kt = 1.0;
  s.light[0].intensity = rt_rgb(2.0, 2.0, 2.0);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_image_t e, p;
  fx_render_exact(&s, 1, 2, &e);
  fx_render_pencil(&s, 1, 2, NULL, &p, NULL, NULL);
  int off = 0;
  double most = 0.0;
  for (size_t k = 0; k < (size_t)e.width * e.height; k++)
    if (e.ch[RT_CH_ID][k] == 1.0f) {
      double d = 0.0;
      for (int c = RT_CH_R; c <= RT_CH_B; c++)
        d = fmax(d, fabs((double)p.ch[c][k] - (double)e.ch[c][k]));
      off += d > 1.0 / 32.0;
      most = fmax(most, d);
    }
  print_message("star pixels off by more than 1/32: %d, largest %.4f\n", off, most);
  assert_true(off == 0 && most <= 1.0 / 32.0);
  rt_image_free(&e);
  rt_image_free(&p);
  rt_scene_free(&s);
}

/* A Fresnel ball of index 1 in air (found by a helper's probe of certified mode): its surface
 * reflects nothing, but rounding left F at about 1e-32 at some rays and 0 at others, so a
 * domain's axial ray spawned no reflected child while some of its samples' exact trees did, and
 * Fig. 10's measure counted their board points as missed paths: certified mode reported 99.12%
 * within rho and 326 mismatches at 96 x 96, 4 spp, with the image right. rt_fresnel() is now 0
 * for n1 == n2, and certified mode keeps its promise there. */
static void index_matched_fresnel_surface_measured(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t white = rt_material_default("white"), red = rt_material_default("red"),
                clear = rt_material_default("clear");
  red.color = rt_rgb(0.85, 0.12, 0.1);
  clear.ka = clear.kd = 0.0;
  clear.kt = 1.0;
  clear.ior = 1.0;
  clear.fresnel = 1;
  int mw, mr, mc;
  assert_int_equal(rt_scene_add_material(&s, &white, &mw), RT_OK);
  assert_int_equal(rt_scene_add_material(&s, &red, &mr), RT_OK);
  assert_int_equal(rt_scene_add_material(&s, &clear, &mc), RT_OK);
  assert_int_equal(rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mw,
                                      mr, 1.0, NULL),
                   RT_OK);
  assert_int_equal(rt_scene_add_sphere(&s, px_vec3(0.0, 1.5, 0.0), 1.0, mc, NULL), RT_OK);
  rt_light_t l = {RT_LIGHT_POINT, {-5.0, 6.0, -2.5}, {1, 1, 1}, RT_FALLOFF_NONE,
                  {0, 0, 0},      {0, 0, 0},         0};
  assert_int_equal(rt_scene_add_light(&s, &l), RT_OK);
  s.camera = (rt_camera_t){{0.0, 3.0, -6.0}, {0.0, 0.9, 0.0}, {0, 1, 0}, 40.0, 64, 64};
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  o.certified = 1;
  pt_stats_t st = fx_pencil_stats(&s, 2, 1, &o);
  print_message("index-matched Fresnel ball, certified: %llu of %llu within rho, %llu mismatches\n",
                (unsigned long long)st.within, (unsigned long long)st.measured,
                (unsigned long long)st.mismatches);
  assert_true(st.with_points > st.measured / 2);
  assert_int_equal(st.mismatches, 0);
  assert_true(st.within == st.measured);
  rt_scene_free(&s);
}

/* A floor seen through a glass ball near the horizon the lens inverts (tests/data/
 * pencil_ball_horizon.json, found by a helper's probe): inside one domain the footprint of the
 * floor grows by orders of magnitude, and where the domain's axial ray sees the far floor an
 * interpolation many of a sample's own pixels off was a fraction of one of the axial ray's. At
 * 96 x 96, 4 spp 51 pixels were more than 1/32 off exact, up to 0.218, and Fig. 10's measure, in
 * the axial ray's pixels alone, said 100% within rho. The measure now counts each point in its own
 * pixels too (99.56% within, largest 7.6, with the planner as it was), and the planner the lattice
 * cell's own footprint (pt__cell_scale). */
static void floor_through_a_lens_near_its_horizon(void **state) {
  (void)state;
  rt_scene_t s;
  load_data_scene("pencil_ball_horizon.json", &s);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.measure = 1;
  rt_image_t e, p;
  pt_stats_t st;
  fx_render_exact(&s, 2, 2, &e);
  fx_render_pencil(&s, 2, 2, &o, &p, NULL, &st);
  fx_diff_t d = fx_object_difference(&e, &p, 1, 1.0 / 32.0);
  print_message("ball: %d pixels off by more than 1/32, largest %.4f; %llu of %llu samples within "
                "rho, largest %.3f, %llu points without a local footprint\n",
                d.big, d.worst, (unsigned long long)st.within, (unsigned long long)st.measured,
                st.max_error, (unsigned long long)st.local_unknown);
  assert_true(d.n > 1000 && st.with_points > st.measured / 3);
  assert_int_equal(d.big, 0);
  assert_true(st.within == st.measured && st.mismatches == 0);
  assert_true(st.local_unknown < st.with_points / 100);
  rt_image_free(&e);
  rt_image_free(&p);
  rt_scene_free(&s);
}

/* pt__cell_scale() on an affine footprint (a pixel step along x moves a hit by a, along y by b):
 * every edge per pixel is a or b and nothing changes across a quarter, so the lattice cell's pixel
 * is exactly max(|a|, |b|), for a measured lattice cell (its own grid, steps of half its size) and
 * an estimated one (a quarter of its parent's grid, steps of its whole size), in cells wider than
 * high (steps taken along the wrong axis would give 0.3 instead of 0.2); where the footprint
 * changes across a quarter the pixel is divided by the change; a grid whose points coincide has
 * no pixel (every error infinite). */
static void lattice_cell_pixel(void **state) {
  (void)state;
  const px_vec3_t o = {1.0, 0.0, 2.0}, a = {0.09, 0.0, 0.12}, b = {0.0, 0.0, -0.2};
  lattice_cell_t lc;
  memset(&lc, 0, sizeof lc);
  grid3_t p;
  for (int kind = 0; kind < 2; kind++) {
    lc.measured = kind == 0;
    lc.w = 4.0;
    lc.h = 2.0;
    lc.qx = 1;
    lc.qy = 0;
    double sx = lc.measured ? 0.5 * lc.w : lc.w, sy = lc.measured ? 0.5 * lc.h : lc.h;
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        p.v[r][c] = px_v3_axpy(c * sx, a, px_v3_axpy(r * sy, b, o));
    double inv_s = pt__cell_scale(&lc, &p);
    print_message("%s lattice cell: 1 / pixel %.15g, expected %.15g\n",
                  lc.measured ? "measured" : "estimated", inv_s, 1.0 / px_v3_norm(b));
    assert_true(fabs(inv_s * px_v3_norm(b) - 1.0) <= 1e-12);
    /* the y steps grow by half from one grid column to the next: a quarter's right edge is 1.5
     * times its left one, and the pixel is the shorter edge's over that ratio or less */
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        p.v[r][c] = px_v3_axpy(c * sx, a, px_v3_axpy(r * sy * (1.0 + 0.5 * c), b, o));
    double c0 = lc.measured ? 0.0 : lc.qx, shorter = 1.0 + 0.5 * c0,
           ratio = (shorter + 0.5) / shorter;
    assert_true(pt__cell_scale(&lc, &p) * px_v3_norm(b) * shorter >= ratio - 1e-12);
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++)
        p.v[r][c] = o;
    assert_true(isinf(pt__cell_scale(&lc, &p)));
  }
}

/* Thin things seen directly, which the bounding spheres do not tell of: a domain's corner rays all
 * meet one face, and the guard of what primary rays see (pt_guard_view()) finds what lies in
 * front of it in the domain's pyramid though no corner ray met it. At 96 x 96, 9 spp:
 * - a rod 0.02 thick and 5 long over the floor: its bounding sphere's disk holds the cones of the
 *   domains across it, so no silhouette of a sphere crosses them. Before the guard it was lost
 *   from all 94 of its pixels (by 0.22);
 * - the same rod over a plate, both one polyhedron (the object's own faces, which no bounding
 *   sphere can guard): 288 samples' paths were missing from their exact trees (Fig. 10's
 *   measure). Its shadow on the plate, cast by the object on itself, needs the shadow guard's
 *   own test (pt_guard_self_shadow()): without it 93 of the object's pixels were off, by 0.25.
 *   Made a mirror, the rod seen in the plate needs the secondary guards' own test
 *   (pt_guard_own_cone() against the sky, pt_guard_own_segment() under a roof): without it 564
 *   samples' paths were missing, and 94 pixels off by 0.13;
 * - a polygon standing before the floor, not convex, with slots 0.02 wide cut into it from above:
 *   the corners meet the polygon on both sides of a slot, and the floor seen through it was lost
 *   from 29 of the polygon's pixels, by up to 0.30, with 199 samples' paths missing. */
static void thin_objects_seen(void **state) {
  (void)state;
  rt_light_t sun = {RT_LIGHT_PARALLEL, {0.3, -1.0, 0.2}, {1, 1, 1}, RT_FALLOFF_NONE,
                    {0, 0, 0},         {0, 0, 0},        0};
  rt_scene_t s;
  int mb = floor_scene(&s);
  add_box(&s, px_vec3(-2.5, 0.5, 0.3), px_vec3(2.5, 0.52, 0.32), mb);
  assert_int_equal(rt_scene_add_light(&s, &sun), RT_OK);
  floor_scene_ready(&s);
  int rod_px;
  assert_true(object_seen_off(&s, 3, 1, 0, &rod_px) <= 1.0 / 32.0);
  assert_true(rod_px > 50);
  rt_scene_free(&s);
  /* a rod and a plate in one polyhedron */
  mb = floor_scene(&s);
  px_vec3_t lo[2] = {px_vec3(-2.5, 0.9, 0.3), px_vec3(-8.0, 0.2, -1.0)},
            hi[2] = {px_vec3(2.5, 0.92, 0.32), px_vec3(8.0, 0.4, 12.0)};
  add_boxes(&s, lo, hi, 2, mb);
  assert_int_equal(rt_scene_add_light(&s, &sun), RT_OK);
  floor_scene_ready(&s);
  measured_all_within(&s);
  int own_px;
  assert_true(object_seen_off(&s, 3, 1, 0, &own_px) <= 1.0 / 32.0);
  assert_true(own_px > 4000);
  rt_scene_free(&s);
  /* ... and as a mirror, the rod seen in the plate against the sky (rays that leave the scene),
   * then under a roof (segments) */
  for (int roofed = 0; roofed < 2; roofed++) {
    floor_scene(&s);
    rt_material_t mirror = rt_material_default("mirror");
    mirror.color = rt_rgb(0.1, 0.2, 0.9);
    mirror.kd = 0.2;
    mirror.kr = 0.7;
    int mm;
    rt_scene_add_material(&s, &mirror, &mm);
    s.background = rt_rgb(0.6, 0.7, 0.9);
    add_boxes(&s, lo, hi, 2, mm);
    const px_vec3_t roof[4] = {px_vec3(-20, 4, 2), px_vec3(20, 4, 2), px_vec3(20, 4, 30),
                               px_vec3(-20, 4, 30)};
    if (roofed)
      assert_int_equal(rt_scene_add_polygon(&s, roof, 4, 0, NULL), RT_OK);
    assert_int_equal(rt_scene_add_light(&s, &sun), RT_OK);
    floor_scene_ready(&s);
    measured_all_within(&s);
    assert_true(object_seen_off(&s, 3, 1, 0, &own_px) <= 1.0 / 32.0);
    rt_scene_free(&s);
  }
  /* a polygon with four slots */
  mb = floor_scene(&s);
  const double xs[4] = {-1.2, -0.4, 0.4, 1.2}, t = 0.02;
  px_vec3_t v[20];
  int n = 0;
  v[n++] = px_vec3(-2.0, 0.1, 1.0);
  v[n++] = px_vec3(2.0, 0.1, 1.0);
  v[n++] = px_vec3(2.0, 1.6, 1.0);
  for (int k = 3; k >= 0; k--) {
    v[n++] = px_vec3(xs[k] + 0.5 * t, 1.6, 1.0);
    v[n++] = px_vec3(xs[k] + 0.5 * t, 0.6, 1.0);
    v[n++] = px_vec3(xs[k] - 0.5 * t, 0.6, 1.0);
    v[n++] = px_vec3(xs[k] - 0.5 * t, 1.6, 1.0);
  }
  v[n++] = px_vec3(-2.0, 1.6, 1.0);
  assert_int_equal(rt_scene_add_polygon(&s, v, n, mb, NULL), RT_OK);
  assert_int_equal(rt_scene_add_light(&s, &sun), RT_OK);
  floor_scene_ready(&s);
  int slotted_px;
  assert_true(object_seen_off(&s, 3, 1, 0, &slotted_px) <= 1.0 / 32.0);
  assert_true(slotted_px > 1000);
  measured_all_within(&s);
  rt_scene_free(&s);
}

/* How many of scene s's polygon edges the faces' guards pair with the face across them. */
static int edges_paired(const rt_scene_t *s) {
  pt_guards_t objects, faces;
  assert_true(pt_guards_of_scene(s, &objects));
  assert_true(pt_guards_of_faces(s, &objects, &faces));
  int paired = 0;
  for (int i = 0; i < s->nvertex; i++)
    paired += faces.across && faces.across[i] >= 0;
  pt_guards_free(&faces);
  pt_guards_free(&objects);
  return paired;
}

/* The faces' guards pair the edges of polyhedra that may hide their own faces, and of no other:
 * two boxes in one polyhedron (not convex: all 48 edge slots paired), one box (convex by the
 * objects' guard: none), a faceted sphere of 10,000 faces, whose convexity the objects' guard
 * does not test (above GUARD_MAX_FACES), found convex by its edges, its centre and its solid
 * angle (none). */
static void faces_guard_pairs_own_edges(void **state) {
  (void)state;
  rt_scene_t s;
  int m = floor_scene(&s);
  px_vec3_t lo[2] = {px_vec3(0, 0, 0), px_vec3(2, 0, 0)},
            hi[2] = {px_vec3(1, 1, 1), px_vec3(3, 1, 1)};
  add_boxes(&s, lo, hi, 2, m);
  assert_int_equal(edges_paired(&s), 48);
  rt_scene_free(&s);
  m = floor_scene(&s);
  add_boxes(&s, lo, hi, 1, m);
  assert_int_equal(edges_paired(&s), 0);
  rt_scene_free(&s);
  m = floor_scene(&s);
  assert_int_equal(rt_scene_add_faceted_sphere(&s, px_vec3(0, 1, 0), 1.0, 100, 100, m, NULL),
                   RT_OK);
  assert_true(s.object[1].nprim > 4096);
  assert_int_equal(edges_paired(&s), 0);
  rt_scene_free(&s);
}

/* The guard of the shadow an object casts on itself, on two boxes in one polyhedron: A = [0, 1]^3
 * and a slat B = [2, 3] x [0.45, 0.55] x [0, 1], a point light at (3.5, 0.5, 0.5) beyond B, and
 * the shadow rays' pencil from within 0.6 of a point of A. From A's face x = 1, which faces the
 * light, B's silhouette runs through the pencil: it fires. From A's face x = 0 hit from inside (the
 * light on the inner side of its plane, the shadow rays through A), it fires too. With the light
 * at (-5, 0.5, 0.5) instead, nothing of the object lies between the face x = 0 and it. */
static void self_shadow_guard_sees_both_sides(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t white = rt_material_default("white");
  int m;
  rt_scene_add_material(&s, &white, &m);
  px_vec3_t lo[2] = {px_vec3(0, 0, 0), px_vec3(2, 0.45, 0)},
            hi[2] = {px_vec3(1, 1, 1), px_vec3(3, 0.55, 1)};
  add_boxes(&s, lo, hi, 2, m);
  pt_guards_t objects, faces;
  assert_true(pt_guards_of_scene(&s, &objects));
  assert_true(pt_guards_of_faces(&s, &objects, &faces));
  int x0 = -1, x1 = -1; /* A's faces x = 0 and x = 1 */
  for (int p = 0; p < 6; p++) {
    const rt_polygon_t *f = &s.prim[p].polygon;
    x0 = f->n.x < -0.5 ? p : x0;
    x1 = f->n.x > 0.5 ? p : x1;
  }
  assert_true(x0 >= 0 && x1 >= 0);
  rt_light_t lamp = {RT_LIGHT_POINT, {3.5, 0.5, 0.5}, {1, 1, 1}, RT_FALLOFF_NONE,
                     {0, 0, 0},      {0, 0, 0},       0};
  assert_true(pt_guard_self_shadow(&faces, &s, x1, px_vec3(1, 0.5, 0.5), 0.6, &lamp));
  assert_true(pt_guard_self_shadow(&faces, &s, x0, px_vec3(0, 0.5, 0.5), 0.6, &lamp));
  lamp.v = px_vec3(-5, 0.5, 0.5);
  assert_false(pt_guard_self_shadow(&faces, &s, x0, px_vec3(0, 0.5, 0.5), 0.6, &lamp));
  pt_guards_free(&faces);
  pt_guards_free(&objects);
  rt_scene_free(&s);
}

/* A ball of Phong exponent `phong` over the white floor, under a point light. */
static void highlight_scene(rt_scene_t *s, double phong) {
  floor_scene(s);
  rt_material_t shiny = rt_material_default("shiny");
  shiny.color = rt_rgb(0.1, 0.2, 0.9);
  shiny.kd = 0.6;
  shiny.ks = 0.8;
  shiny.phong = phong;
  int ms;
  rt_scene_add_material(s, &shiny, &ms);
  rt_scene_add_sphere(s, px_vec3(0.0, 1.0, 0.5), 1.0, ms, NULL);
  rt_light_t l = {RT_LIGHT_POINT, {2.0, 10.0, 2.0}, {1, 1, 1}, RT_FALLOFF_NONE,
                  {0, 0, 0},      {0, 0, 0},        0};
  assert_int_equal(rt_scene_add_light(s, &l), RT_OK);
  floor_scene_ready(s);
}

/* A highlight narrower than the lattice points' spacing: a ball of Phong exponent 1,000 under a
 * point light. The brightness test sees the highlight only where a lattice point falls in it;
 * the highlight guard (interp_plan.c) shades the ball per sample where the light's direction may
 * come near the mirror directions between the points. Before the guard the highlight was lost: 4
 * of the ball's pixels off by more than 1/32, up to 0.15, at 96 x 96, 9 spp (a broader highlight,
 * Phong 100, was right without it). */
static void narrow_highlights_kept(void **state) {
  (void)state;
  rt_scene_t s;
  highlight_scene(&s, 1000.0);
  int ball_px;
  assert_true(object_off(&s, 3, 1, &ball_px) <= 1.0 / 32.0);
  assert_true(ball_px > 1000);
  pt_stats_t st = fx_pencil_stats(&s, 3, 1, NULL);
  assert_true(st.highlight_lattice_cells > 0);
  rt_scene_free(&s);
}

static void bad_options_rejected(void **state) {
  (void)state;
  rt_scene_t s;
  fx_fig8(&s, 8, 8);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_image_t img;
  static float err[8 * 8];
  assert_int_equal(rt_image_alloc(&img, 8, 8), RT_OK);
  pt_options_t o = PT_OPTIONS_DEFAULT;
  o.domain = 0;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o.domain = 33;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o = (pt_options_t)PT_OPTIONS_DEFAULT;
  o.rho = 0.0;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o = (pt_options_t)PT_OPTIONS_DEFAULT;
  o.spp_side = RT_MAX_SPP_SIDE + 1;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o = (pt_options_t)PT_OPTIONS_DEFAULT;
  o.tolerance = PT_TOL_IMAGE;
  o.weight_floor = 0.0;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o.weight_floor = 1.5;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o.weight_floor = NAN;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o = (pt_options_t)PT_OPTIONS_DEFAULT;
  o.tolerance = (pt_tolerance_t)2;
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, NULL, NULL), RT_EINVAL);
  o = (pt_options_t)PT_OPTIONS_DEFAULT; /* per-sample errors need measure */
  assert_int_equal(pt_render(&s, &plan, &o, &img, NULL, err, NULL), RT_EINVAL);
  pt_bound_t b;
  assert_false(pt_bound_parse("exact", &b));
  assert_true(pt_bound_parse("printed", &b) && b == PT_BOUND_PRINTED);
  rt_image_free(&img);
  rt_scene_free(&s);
}

/* A glass ball in a closed box of mirrors at depth 32 (issue 20's case): about 1,000 rays per
 * sample, more than a domain's paths may hold (PT_MAX_TREE_NODES). Such domains are traced
 * exactly as a whole: their pixels equal the exact renderer's bit for bit, and the whole render
 * traces few more exact rays than the exact renderer (before: twice as many, the auxiliary
 * channels re-tracing every exact pixel's centre ray, and 191 MB of buffers touched a thread). */
static const char mirror_box[] =
    "{\"camera\": {\"eye\": [0, 0, -3.5], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov\": 60,"
    " \"width\": 20, \"height\": 20},"
    " \"settings\": {\"ambient\": 1, \"background\": [0.35, 0.55, 0.85], \"max_depth\": 32},"
    " \"materials\": {\"mirror\": {\"color\": [0.9, 0.9, 0.9], \"ka\": 0.1, \"kd\": 0.2, \"kr\": "
    "0.7},"
    "  \"glass\": {\"ka\": 0, \"kd\": 0, \"ks\": 0.6, \"phong\": 80, \"kr\": 0.15, \"kt\": 0.75,"
    "  \"ior\": 1.5}},"
    " \"lights\": [{\"type\": \"point\", \"position\": [0.5, 3, -1], \"intensity\": 1}],"
    " \"objects\": ["
    "  {\"type\": \"plane\", \"point\": [0, -4, 0], \"normal\": [0, 1, 0], \"material\": "
    "\"mirror\"},"
    "  {\"type\": \"plane\", \"point\": [0, 4, 0], \"normal\": [0, -1, 0], \"material\": "
    "\"mirror\"},"
    "  {\"type\": \"plane\", \"point\": [-4, 0, 0], \"normal\": [1, 0, 0], \"material\": "
    "\"mirror\"},"
    "  {\"type\": \"plane\", \"point\": [4, 0, 0], \"normal\": [-1, 0, 0], \"material\": "
    "\"mirror\"},"
    "  {\"type\": \"plane\", \"point\": [0, 0, 4], \"normal\": [0, 0, -1], \"material\": "
    "\"mirror\"},"
    "  {\"type\": \"plane\", \"point\": [0, 0, -4], \"normal\": [0, 0, 1], \"material\": "
    "\"mirror\"},"
    "  {\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, \"material\": \"glass\"}]}";

static void deep_trees_traced_exactly_at_exact_cost(void **state) {
  (void)state;
  rt_scene_t s;
  LOAD_INLINE("mirror_box", mirror_box, &s);
  rt_plan_t plan = rt_plan_make(&s, 1);
  assert_true(plan.tree_nodes > PT_MAX_TREE_NODES);
  int w = s.camera.width, h = s.camera.height;
  rt_image_t e, p;
  rt_stats_t ers;
  xr_options_t eo = XR_OPTIONS_DEFAULT;
  eo.threads = 1;
  assert_int_equal(rt_image_alloc(&e, w, h), RT_OK);
  assert_int_equal(xr_render(&s, &plan, &eo, &e, &ers), RT_OK);
  static float method[20 * 20];
  pt_extra_t x = {NULL, method, NULL};
  pt_stats_t st;
  fx_render_pencil(&s, 1, 1, NULL, &p, &x, &st);
  uint64_t er = rt_stats_total(&ers), pr = rt_stats_total(&st.rays);
  int exact_px = 0;
  for (int k = 0; k < w * h; k++)
    if (method[k] == (float)PT_METHOD_EXACT) {
      exact_px++;
      for (int c = RT_CH_R; c <= RT_CH_B; c++)
        assert_memory_equal(&p.ch[c][k], &e.ch[c][k], sizeof(float));
    }
  print_message("deep domains %llu, exact pixels %d of %d, exact rays %llu against %llu (%.3f)\n",
                (unsigned long long)st.domains_deep, exact_px, w * h, (unsigned long long)pr,
                (unsigned long long)er, (double)pr / (double)er);
  assert_true(st.domains_deep > 0);
  assert_true(exact_px >= w * h / 4);
  assert_true((double)pr <= 1.15 * (double)er);
  rt_image_free(&p);
  rt_image_free(&e);
  rt_scene_free(&s);
}

/* pt_thread_bytes() is exactly what pt__ctx_alloc() asks for, and is bounded whatever the
 * depth (a plan of 131,071 nodes took 2.5 GB of buffers a thread before the paths were capped). */
static void thread_bytes_match_allocation(void **state) {
  (void)state;
  const int nodes[4] = {1, 127, 1023, (1 << 17) - 1}, domains[4] = {5, 5, 1, 32};
  for (int i = 0; i < 4; i++) {
    pt_ctx_t C;
    memset(&C, 0, sizeof C);
    assert_true(pt__ctx_alloc(&C, nodes[i], domains[i]));
    pt__ctx_free(&C);
    print_message("tree nodes %d, domain %d: %zu bytes\n", nodes[i], domains[i], C.bytes);
    assert_int_equal(C.bytes, pt_thread_bytes(nodes[i], domains[i]));
  }
  assert_true(pt_thread_bytes((1 << 17) - 1, 32) < ((size_t)80 << 20));
  assert_int_equal(pt_thread_bytes(0, 5), 0);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(path_matrices_match_whole_path_cascade),
      cmocka_unit_test(incremental_bound_equals_pencil_constants),
      cmocka_unit_test(matrix_error_within_bound),
      cmocka_unit_test(certified_check_matches_whole_path),
      cmocka_unit_test(axis_ray_meets_axial_hit),
      cmocka_unit_test(tree_agreement_edges_not_textures),
      cmocka_unit_test(guard_catches_small_objects),
      cmocka_unit_test(guard_hierarchy_answers_as_the_scan),
      cmocka_unit_test(view_guard_sees_faces_in_front),
      cmocka_unit_test(faces_guard_pairs_own_edges),
      cmocka_unit_test(self_shadow_guard_sees_both_sides),
      cmocka_unit_test(guard_catches_objects_seen_in_mirrors),
      cmocka_unit_test(guard_catches_small_shadows),
      cmocka_unit_test(faint_shadow_edges_interpolated),
      cmocka_unit_test(error_maximum_keeps_nan),
      cmocka_unit_test(fresnel_weights_match_exact),
      cmocka_unit_test(every_scene_unbiased_per_object),
      cmocka_unit_test(exact_subtrees_start_at_exact_hits_and_are_measured),
      cmocka_unit_test(image_bias_finds_systematic_errors),
      cmocka_unit_test(certified_halves_stay_within_rho),
      cmocka_unit_test(subdivision_only_at_edges),
      cmocka_unit_test(interpolation_error_on_board),
      cmocka_unit_test(biquadratic_cells_stay_within_rho),
      cmocka_unit_test(pencil_image_matches_exact),
      cmocka_unit_test(image_tolerance_weights_nodes),
      cmocka_unit_test(pencil_image_matches_exact_with_falloff),
      cmocka_unit_test(largest_sample_grid),
      cmocka_unit_test(mirror_ball_reflections_match_exact),
      cmocka_unit_test(measure_counts_diffuse_surfaces),
      cmocka_unit_test(image_does_not_depend_on_threads),
      cmocka_unit_test(lattice_memo_changes_nothing),
      cmocka_unit_test(walks_of_four_change_nothing),
      cmocka_unit_test(lanes_leaving_walks_of_four_change_nothing),
      cmocka_unit_test(lights_through_other_glass_disagree),
      cmocka_unit_test(nested_glass_shadows_not_reused),
      cmocka_unit_test(lights_past_the_masks_keep_their_shadows),
      cmocka_unit_test(narrow_highlights_kept),
      cmocka_unit_test(slots_in_shadows_kept),
      cmocka_unit_test(weight_jump_not_interpolated),
      cmocka_unit_test(fresnel_weight_near_the_critical_angle),
      cmocka_unit_test(index_matched_fresnel_surface_measured),
      cmocka_unit_test(floor_through_a_lens_near_its_horizon),
      cmocka_unit_test(lattice_cell_pixel),
      cmocka_unit_test(thin_objects_seen),
      cmocka_unit_test(thin_objects_keep_their_shadows),
      cmocka_unit_test(gaps_between_shadows_kept),
      cmocka_unit_test(bad_options_rejected),
      cmocka_unit_test(deep_trees_traced_exactly_at_exact_cost),
      cmocka_unit_test(thread_bytes_match_allocation),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
