/* test_render_shade.c -- the shading module (core/src/shade.c): reflected and
 * refracted directions against reference/'s exact tracer (ex_trace_axial through the same
 * quadrics), shadow attenuation by transparent occluders (textbook 9.1: k_t(1) ... k_t(N) I),
 * the illumination terms, Fresnel and total internal reflection, and the effects plan. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/intersect.h"
#include "core/shade_paths.h"
#include "exact/trace.h"
#include "paraxial/system.h"
#include "paraxial/vec3.h"
#include "render/render.h"

/* Same quadric, same vector laws (both go through px_interface_outgoing), normals from two
 * formulas: agreement to ~1e-15; 1e-13 leaves margin for the longer paths. */
#define DIR_TOL 1e-13
/* After a surface event the renderer starts the child ray RT_SURFACE_OFFSET * (1 + |p|) off the
 * surface (2e-9 here) while the exact tracer starts on it: later hit points and directions move
 * by that much times a geometric factor of order 1 (1/cos of the angles, the curvature). */
#define OFFSET_TOL 2e-8

static int add_mat(rt_scene_t *s, const char *name, double kr, double kt, double ior) {
  rt_material_t m = rt_material_default(name);
  m.kr = kr;
  m.kt = kt;
  m.ior = ior;
  int i;
  assert_int_equal(rt_scene_add_material(s, &m, &i), RT_OK);
  return i;
}

/* The Fresnel glass of the children tests: kr 0.1, kt 0.8, ior 1.5. */
static int add_fresnel_glass(rt_scene_t *s) {
  rt_material_t g = rt_material_default("glass");
  g.kr = 0.1;
  g.kt = 0.8;
  g.ior = 1.5;
  g.fresnel = 1;
  int i;
  assert_int_equal(rt_scene_add_material(s, &g, &i), RT_OK);
  return i;
}

static rt_ray_t ray_to(px_vec3_t o, px_vec3_t target) {
  px_vec3_t d;
  px_vec3_normalize(px_vec3_sub(target, o), &d);
  return (rt_ray_t){o, d, 0.0, INFINITY, 1.0, -1, 0.0f};
}

static void vec_close(px_vec3_t a, px_vec3_t b, double tol) {
  assert_close(a.x, b.x, 0, tol);
  assert_close(a.y, b.y, 0, tol);
  assert_close(a.z, b.z, 0, tol);
}

/* The first child of node `parent` of the given kind, or -1. */
static int child_of(const rt_tree_t *t, int parent, rt_ray_kind_t kind) {
  for (int k = parent + 1; k < t->n; k++)
    if (t->node[k].parent == parent && t->node[k].kind == kind)
      return k;
  return -1;
}

static ex_axial_t exact_path(const rt_ray_t *r, const ex_stage_t *st, size_t n) {
  px_frame_t f;
  assert_int_equal(px_frame_from_z(r->d, px_vec3(0, 1, 0), &f), PX_OK);
  ex_system_t sys = {r->o, f, 1.0, st, n, 0.0, 0.0};
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  return ax;
}

/* Trace `r` in the prepared scene with a recorded tree. */
static void trace_tree(const rt_scene_t *s, const rt_plan_t *plan, const rt_ray_t *r,
                       rt_tree_node_t *buf, int cap, rt_tree_t *t) {
  *t = rt_tree_make(buf, cap);
  xr_exact_t ex = xr_exact_make(s, plan, t);
  xr_exact_primary(&ex, r);
  assert_false(t->overflow);
}

/* Into and out of a glass ball: hit points and directions of the refraction path agree with the
 * exact tracer's two-stage system. */
static void refraction_through_sphere_matches_exact(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  px_vec3_t c = px_vec3(0.2, 0.1, 0.3);
  rt_scene_add_sphere(&s, c, 1.0, add_mat(&s, "glass", 0.1, 0.9, 1.5), NULL);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_ray_t r = ray_to(px_vec3(-0.4, 0.7, -5), px_vec3(0.5, -0.3, 0.3));
  rt_tree_node_t buf[64];
  rt_tree_t t;
  trace_tree(&s, &plan, &r, buf, 64, &t);
  int in = child_of(&t, 0, RT_RAY_REFRACT), out = child_of(&t, in, RT_RAY_REFRACT);
  assert_true(in > 0 && out > in);
  ex_quadric_t q = ex_quadric_sphere(c, 1.0);
  ex_stage_t st[2] = {{q, PX_EVENT_REFRACT, 1.5, 0}, {q, PX_EVENT_REFRACT, 1.0, 0}};
  ex_axial_t ax = exact_path(&r, st, 2);
  vec_close(t.node[0].point, ax.hit[0], 1e-12);
  vec_close(t.node[in].dir, ax.out[0].z, DIR_TOL);
  vec_close(t.node[in].point, ax.hit[1], OFFSET_TOL);
  vec_close(t.node[out].dir, ax.out[1].z, OFFSET_TOL);
  /* the reflected ray at the entry point */
  ex_stage_t sr = {q, PX_EVENT_REFLECT, 1.0, 0};
  ex_axial_t axr = exact_path(&r, &sr, 1);
  vec_close(t.node[child_of(&t, 0, RT_RAY_REFLECT)].dir, axr.out[0].z, DIR_TOL);
  rt_scene_free(&s);
}

static void mirror_sphere_reflection_matches_exact(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  px_vec3_t c = px_vec3(0, 0, 0);
  rt_scene_add_sphere(&s, c, 2.0, add_mat(&s, "mirror", 0.9, 0.0, 1.0), NULL);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  for (int k = 0; k < 20; k++) {
    rt_ray_t r = ray_to(px_vec3(0.3 * k - 3, 1, -8), px_vec3(0.09 * k - 0.9, -0.5, 0));
    rt_tree_node_t buf[16];
    rt_tree_t t;
    trace_tree(&s, &plan, &r, buf, 16, &t);
    ex_stage_t st = {ex_quadric_sphere(c, 2.0), PX_EVENT_REFLECT, 1.0, 0};
    ex_axial_t ax = exact_path(&r, &st, 1);
    int rf = child_of(&t, 0, RT_RAY_REFLECT);
    assert_true(rf > 0);
    vec_close(t.node[rf].dir, ax.out[0].z, DIR_TOL);
    assert_int_equal(child_of(&t, 0, RT_RAY_REFRACT), -1); /* opaque: no refraction */
  }
  rt_scene_free(&s);
}

/* A glass cube (a polyhedron): through two faces, as two exact plane stages. */
static void refraction_through_polyhedron_matches_exact(void **state) {
  (void)state;
  static const px_vec3_t v[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                 {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  static const int f[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
  static const int len[6] = {4, 4, 4, 4, 4, 4};
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(
      rt_scene_add_polyhedron(&s, v, 8, f, len, 6, add_mat(&s, "g", 0.0, 1.0, 1.7), NULL, NULL, 0),
      RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_ray_t r = ray_to(px_vec3(-0.8, 0.5, -4), px_vec3(0.1, 0.2, -1)); /* enters z = -1 */
  rt_tree_node_t buf[64];
  rt_tree_t t;
  trace_tree(&s, &plan, &r, buf, 64, &t);
  int in = child_of(&t, 0, RT_RAY_REFRACT);
  assert_true(in > 0);
  ex_stage_t st[2] = {
      {ex_quadric_plane(px_vec3(0, 0, -1), px_vec3(0, 0, 1)), PX_EVENT_REFRACT, 1.7, 0},
      {ex_quadric_plane(px_vec3(0, 0, 1), px_vec3(0, 0, 1)), PX_EVENT_REFRACT, 1.0, 0}};
  ex_axial_t ax = exact_path(&r, st, 2);
  vec_close(t.node[0].point, ax.hit[0], 1e-12);
  vec_close(t.node[in].dir, ax.out[0].z, DIR_TOL);
  vec_close(t.node[in].point, ax.hit[1], OFFSET_TOL); /* the far face z = 1 */
  int out = child_of(&t, in, RT_RAY_REFRACT);
  assert_true(out > in);
  vec_close(t.node[out].dir, ax.out[1].z, DIR_TOL); /* planes: no curvature, no offset effect */
  rt_scene_free(&s);
}

/* Shadow segments: the product of kt * transmittance over transparent objects passed, once per
 * object; black through an opaque one; nothing beyond the light counts. */
static void shadow_attenuation_is_product_of_kt(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t g1 = rt_material_default("g1"), g2 = rt_material_default("g2");
  g1.kt = 0.6;
  g1.ior = 1.5;
  g1.transmittance = rt_rgb(1.0, 0.5, 0.25);
  g2.kt = 0.5;
  g2.ior = 1.3;
  int m1, m2, mo = add_mat(&s, "opaque", 0, 0, 1);
  rt_scene_add_material(&s, &g1, &m1);
  rt_scene_add_material(&s, &g2, &m2);
  rt_scene_add_sphere(&s, px_vec3(0, 3, 0), 1.0, m1, NULL);
  rt_scene_add_sphere(&s, px_vec3(0, 6, 0), 1.0, m2, NULL);
  rt_scene_add_sphere(&s, px_vec3(5, 3, 0), 1.0, mo, NULL);
  rt_scene_add_sphere(&s, px_vec3(0, 20, 0), 1.0, mo, NULL); /* beyond the light */
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_ray_t up = {px_vec3(0, 0, 0), px_vec3(0, 1, 0), 0.0, 10.0, 1.0, -1, 0.0f};
  rt_rgb_t t = rt_transmittance(&s, &up);
  assert_close(t.r, 0.6 * 0.5, 1e-15, 0);
  assert_close(t.g, 0.3 * 0.5, 1e-15, 0);
  assert_close(t.b, 0.15 * 0.5, 1e-15, 0);
  up.tmax = 4.5; /* only the first ball */
  assert_close(rt_transmittance(&s, &up).r, 0.6, 1e-15, 0);
  rt_ray_t inside = {px_vec3(0, 2.5, 0), px_vec3(0, 1, 0), 0.0, 4.5, 1.0, -1, 0.0f};
  assert_close(rt_transmittance(&s, &inside).r, 0.6, 1e-15, 0); /* starts inside: one exit */
  rt_ray_t side = {px_vec3(5, 0, 0), px_vec3(0, 1, 0), 0.0, 10.0, 1.0, -1, 0.0f};
  assert_true(rt_rgb_max(rt_transmittance(&s, &side)) == 0.0);
  rt_ray_t clear = {px_vec3(-5, 0, 0), px_vec3(0, 1, 0), 0.0, 10.0, 1.0, -1, 0.0f};
  t = rt_transmittance(&s, &clear);
  assert_true(t.r == 1.0 && t.g == 1.0 && t.b == 1.0);
  rt_scene_free(&s);
}

typedef struct {
  int shadow_calls;
} probe_t;

static rt_rgb_t probe_child(void *ctx, const rt_child_t *c, int depth) {
  (void)ctx, (void)c, (void)depth;
  return rt_rgb(0, 0, 0);
}
static void probe_shadow(void *ctx, rt_shadow_t *q) {
  probe_t *p = ctx;
  p->shadow_calls++;
  q->through = rt_rgb(0.25, 0.5, 1.0);
}

/* A shadow callback that records the queries' light indices and targets, and asks the scene. */
typedef struct {
  const rt_scene_t *s;
  int calls, index;
  double tmax_sum;
} area_probe_t;

static void area_shadow(void *ctx, rt_shadow_t *q) {
  area_probe_t *p = ctx;
  p->calls++;
  p->index = q->light;
  p->tmax_sum += q->ray.tmax;
  rt_shadow_occluded(p->s, q);
}

/* An area light (1989 section 2.3) in shading: the sum over its N x N mesh points of a Lambertian
 * point's I0 / N^2 cos(theta) cos(alpha) / r^2 times kd colour, each with its own shadow ray to
 * that point, under an index no per-light cache answers; an opaque ball between the light and
 * the point blocks part of the mesh (a soft shadow: strictly between dark and lit), and the
 * shaded value is the sum over the points its shadow rays found free. */
static void area_light_sums_its_mesh_points(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t m = rt_material_default("m");
  m.color = rt_rgb(0.8, 0.4, 0.2);
  m.ka = 0.0;
  m.kd = 0.6;
  int mi;
  rt_scene_add_material(&s, &m, &mi);
  rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi, -1, 1, NULL);
  const int n = 5;
  rt_light_t l = {RT_LIGHT_AREA, {0.3, 2, -0.2}, {3, 3, 3}, RT_FALLOFF_NONE,
                  {1.2, 0, 0},   {0, 0, 0.8},    n};
  assert_int_equal(rt_scene_add_light(&s, &l), RT_OK);
  assert_int_equal(s.light[0].falloff, RT_FALLOFF_INVERSE_SQUARE);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_ray_t r = ray_to(px_vec3(0, 2, -2), px_vec3(0, 0, 0));
  rt_hit_t h;
  assert_true(rt_intersect(&s, &r, &h));
  rt_surface_t sf;
  rt_shade_surface(&s, &h, &r, &sf);
  area_probe_t probe = {&s, 0, 0, 0.0};
  rt_tracer_t tr = {probe_child, area_shadow, &probe, NULL, NULL, NULL, 0};
  rt_rgb_t c = rt_shade_direct(&s, &plan, &sf, &r, &tr);
  /* the sum by hand: the light faces down (edge_u x edge_v = (0, -0.96, 0)) */
  double want = 0.0, tsum = 0.0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      double x = 0.3 + 1.2 * ((i + 0.5) / n - 0.5), z = -0.2 + 0.8 * ((j + 0.5) / n - 0.5);
      double r2 = x * x + 4.0 + z * z, cosine = 2.0 / sqrt(r2);
      want += 3.0 / (n * n) * cosine * cosine / r2;
      tsum += sqrt(r2);
    }
  assert_close(c.r, 0.6 * 0.8 * want, 1e-13, 0);
  assert_close(c.b, 0.6 * 0.2 * want, 1e-13, 0);
  assert_int_equal(probe.calls, n * n);
  assert_int_equal(probe.index, RT_AREA_SHADOW_INDEX(0));
  assert_close(probe.tmax_sum, tsum, 1e-6, 0); /* each ray ends at its own point */
  /* an opaque ball over part of the light: a soft shadow */
  rt_material_t black = rt_material_default("black");
  int bi;
  rt_scene_add_material(&s, &black, &bi);
  assert_int_equal(rt_scene_add_sphere(&s, px_vec3(0.5, 1.0, 0.0), 0.25, bi, NULL), RT_OK);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_shade_surface(&s, &h, &r, &sf);
  rt_rgb_t soft = rt_shade_direct(&s, &plan, &sf, &r, &tr);
  double free_sum = 0.0;
  int blocked = 0;
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) {
      px_vec3_t pos =
          px_vec3(0.3 + 1.2 * ((i + 0.5) / n - 0.5), 2.0, -0.2 + 0.8 * ((j + 0.5) / n - 0.5));
      double r2 = px_v3_dot(pos, pos), cosine = 2.0 / sqrt(r2);
      rt_ray_t q = {
          px_vec3(0, 1e-9, 0), px_v3_scale(pos, 1.0 / sqrt(r2)), 0.0, sqrt(r2), 1.0, -1, 0.0f};
      rt_hit_t qh;
      if (rt_intersect(&s, &q, &qh))
        blocked++;
      else
        free_sum += 3.0 / (n * n) * cosine * cosine / r2;
    }
  assert_true(blocked > 0 && blocked < n * n);
  assert_true(soft.r > 0.0 && soft.r < c.r);
  assert_close(soft.r, 0.6 * 0.8 * free_sum, 1e-13, 0);
  rt_scene_free(&s);
}

/* Ambient + diffuse with the light's transmittance, against the formula of textbook 9.1; with
 * the inverse-square fall-off the light's term is divided by r^2. */
static void direct_light_follows_illumination_equation(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t m = rt_material_default("m");
  m.color = rt_rgb(0.8, 0.4, 0.2);
  m.ka = 0.3;
  m.kd = 0.6;
  int mi;
  rt_scene_add_material(&s, &m, &mi);
  rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi, -1, 1, NULL);
  s.ambient = rt_rgb(0.5, 0.5, 0.5);
  rt_light_t l = {RT_LIGHT_POINT, {3, 4, 0}, {2, 2, 2}, RT_FALLOFF_NONE, {0, 0, 0}, {0, 0, 0}, 0};
  rt_scene_add_light(&s, &l);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_ray_t r = ray_to(px_vec3(0, 2, -2), px_vec3(0, 0, 0));
  rt_hit_t h;
  assert_true(rt_intersect(&s, &r, &h));
  rt_surface_t sf;
  rt_shade_surface(&s, &h, &r, &sf);
  probe_t probe = {0};
  rt_tracer_t tr = {probe_child, probe_shadow, &probe, NULL, NULL, NULL, 0};
  rt_rgb_t c = rt_shade_direct(&s, &plan, &sf, &r, &tr);
  double cosl = 4.0 / 5.0; /* N.L at the origin for a light at (3, 4, 0) */
  assert_close(c.r, 0.3 * 0.5 * 0.8 + 0.25 * 2 * 0.6 * 0.8 * cosl, 1e-14, 0);
  assert_close(c.g, 0.3 * 0.5 * 0.4 + 0.5 * 2 * 0.6 * 0.4 * cosl, 1e-14, 0);
  assert_close(c.b, 0.3 * 0.5 * 0.2 + 1.0 * 2 * 0.6 * 0.2 * cosl, 1e-14, 0);
  assert_int_equal(probe.shadow_calls, 1);
  s.shadows = 0; /* shadows off in the plan: no shadow query, full light */
  plan = rt_plan_make(&s, 1);
  c = rt_shade_direct(&s, &plan, &sf, &r, &tr);
  assert_int_equal(probe.shadow_calls, 1);
  assert_close(c.b, 0.3 * 0.5 * 0.2 + 2 * 0.6 * 0.2 * cosl, 1e-14, 0);
  /* the same light with the inverse-square fall-off: its term divided by r^2 = 25 */
  s.light[0].falloff = RT_FALLOFF_INVERSE_SQUARE;
  c = rt_shade_direct(&s, &plan, &sf, &r, &tr);
  assert_close(c.b, 0.3 * 0.5 * 0.2 + 2 * 0.6 * 0.2 * cosl / 25.0, 1e-14, 0);
  rt_rgb_t two[2];
  rt_shade_direct2(&s, &plan, &sf, sf.mat, &r, &tr, two);
  assert_memory_equal(&two[0], &c, sizeof c); /* and the checkerboard's path agrees bit for bit */
  /* a parallel light cannot fall off */
  rt_light_t sun = {RT_LIGHT_PARALLEL, {0, -1, 0}, {1, 1, 1}, RT_FALLOFF_INVERSE_SQUARE,
                    {0, 0, 0},         {0, 0, 0},  0};
  assert_int_equal(rt_scene_add_light(&s, &sun), RT_EINVAL);
  rt_scene_free(&s);
}

/* rt_shade_direct2() (a checkerboard's two materials at one point, for the pencil tracer's
 * lattice points) gives each material's direct term bit for bit as rt_shade_direct() alone, with
 * one shadow query per light the surface faces instead of one per material: for pairs where one
 * material has a specular term, neither, or no light term at all (ambient only). */
static void two_materials_shaded_at_once_match_each_alone(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t m[3] = {rt_material_default("shiny"), rt_material_default("matte"),
                        rt_material_default("dull")};
  m[0].color = rt_rgb(0.9, 0.3, 0.1);
  m[0].ka = 0.2, m[0].kd = 0.5, m[0].ks = 0.4, m[0].phong = 7;
  m[1].color = rt_rgb(0.1, 0.6, 0.8);
  m[1].ka = 0.1, m[1].kd = 0.7, m[1].ks = 0.0;
  m[2].color = rt_rgb(0.5, 0.5, 0.5);
  m[2].ka = 0.4, m[2].kd = 0.0, m[2].ks = 0.0; /* ambient only: no light term */
  int mi[3];
  for (int i = 0; i < 3; i++)
    assert_int_equal(rt_scene_add_material(&s, &m[i], &mi[i]), RT_OK);
  rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi[0], -1, 1, NULL);
  s.ambient = rt_rgb(0.5, 0.4, 0.3);
  rt_light_t lights[3] = {
      {RT_LIGHT_POINT, {3, 4, 0}, {2, 2, 2}, RT_FALLOFF_NONE, {0, 0, 0}, {0, 0, 0}, 0},
      {RT_LIGHT_POINT,
       {-1, -3, 1},
       {1, 1, 1},
       RT_FALLOFF_NONE,
       {0, 0, 0},
       {0, 0, 0},
       0}, /* below: faced away from */
      {RT_LIGHT_PARALLEL,
       {0.3, -1, 0.2},
       {0.5, 0.7, 0.9},
       RT_FALLOFF_NONE,
       {0, 0, 0},
       {0, 0, 0},
       0}};
  for (int l = 0; l < 3; l++)
    rt_scene_add_light(&s, &lights[l]);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_ray_t r = ray_to(px_vec3(0.4, 2, -2), px_vec3(0.1, 0, 0.2));
  rt_hit_t h;
  assert_true(rt_intersect(&s, &r, &h));
  const rt_material_t *mat[3] = {&s.material[mi[0]], &s.material[mi[1]], &s.material[mi[2]]};
  int pairs = 0;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) {
      rt_surface_t sf, sb;
      rt_shade_surface(&s, &h, &r, &sf);
      sf.mat = mat[a];
      sb = sf;
      sb.mat = mat[b];
      probe_t p1 = {0}, p2 = {0};
      rt_tracer_t t1 = {probe_child, probe_shadow, &p1, NULL, NULL, NULL, 0};
      rt_tracer_t t2 = {probe_child, probe_shadow, &p2, NULL, NULL, NULL, 0};
      rt_rgb_t alone[2] = {rt_shade_direct(&s, &plan, &sf, &r, &t1),
                           rt_shade_direct(&s, &plan, &sb, &r, &t1)};
      rt_rgb_t both[2];
      memset(both, 0xa5, sizeof both);
      rt_shade_direct2(&s, &plan, &sf, mat[b], &r, &t2, both);
      assert_memory_equal(&both[0], &alone[0], sizeof both[0]);
      assert_memory_equal(&both[1], &alone[1], sizeof both[1]);
      /* two lights face the surface: one query each, unless neither material is lit */
      assert_int_equal(p2.shadow_calls, a == 2 && b == 2 ? 0 : 2);
      assert_int_equal(p1.shadow_calls, (a == 2 ? 0 : 2) + (b == 2 ? 0 : 2));
      pairs += both[0].r != both[1].r; /* the pair's materials do differ in the result */
    }
  assert_int_equal(pairs, 6);
  rt_scene_free(&s);
}

/* A parallel light: the same N.L everywhere on a plane, an unbounded shadow ray (an opaque ball
 * far above still shadows), and the ball's shadow is exactly below it. */
static void parallel_light_and_its_shadow(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t m = rt_material_default("m");
  m.ka = 0.0;
  m.kd = 1.0;
  int mi;
  rt_scene_add_material(&s, &m, &mi);
  rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi, -1, 1, NULL);
  rt_scene_add_sphere(&s, px_vec3(0, 100, 0), 1.0, mi, NULL);
  rt_light_t l = {RT_LIGHT_PARALLEL, {0, -2, 0}, {0.5, 0.5, 0.5}, RT_FALLOFF_NONE, {0, 0, 0},
                  {0, 0, 0},         0}; /* normalised on adding */
  rt_scene_add_light(&s, &l);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  xr_exact_t ex = xr_exact_make(&s, &plan, NULL);
  rt_ray_t lit = ray_to(px_vec3(5, 3, -4), px_vec3(3, 0, 2));
  rt_ray_t dark = ray_to(px_vec3(5, 3, -4), px_vec3(0.2, 0, -0.3));
  assert_close(xr_exact_primary(&ex, &lit).r, 0.5, 1e-15, 0); /* kd C I N.L = 1 * 1 * 0.5 * 1 */
  assert_true(xr_exact_primary(&ex, &dark).r == 0.0);
  assert_int_equal(ex.stats.shadow, 2);
  rt_scene_free(&s);
}

static void fresnel_limits(void **state) {
  (void)state;
  assert_close(rt_fresnel(1, 1, 1.0, 1.5), 0.04, 1e-15, 0); /* ((n1 - n2)/(n1 + n2))^2 */
  assert_close(rt_fresnel(1, 1, 1.5, 1.0), 0.04, 1e-15, 0);
  assert_close(rt_fresnel(1e-9, 0.5, 1.0, 1.5), 1.0, 0, 1e-8); /* grazing: total */
  assert_true(rt_fresnel(0.5, -1, 1.5, 1.0) == 1.0);
  /* an index-matched surface (a ball of index 1 in air, or the far side of one ball inside
   * another): nothing reflects, exactly, whatever rounding does to the transmitted cosine. Left
   * to rounding F was 0 at some angles and about 1e-32 at others, and a reflected child was
   * spawned at some of a pencil's rays and not at its axial ray's. */
  int tiny = 0;
  for (int k = 0; k <= 1000; k++) {
    double ci = k / 1000.0, n = k % 2 ? 1.0 : 1.5;
    double ct = sqrt(1.0 - (n / n) * (n / n) * (1.0 - ci * ci));
    tiny += rt_fresnel(ci, ct, n, n) != 0.0;
    tiny += rt_fresnel(ci, nextafter(ci, 2.0), n, n) != 0.0;
  }
  assert_int_equal(tiny, 0);
}

/* Children of a hit on glass: with Fresnel the weights split kt; from inside beyond the critical
 * angle everything reflects, flagged as TIR; at the depth limit nothing is spawned. */
static void children_weights_fresnel_and_tir(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int gi = add_fresnel_glass(&s);
  rt_scene_add_sphere(&s, px_vec3(0, 0, 0), 1.0, gi, NULL);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&plan, RT_EFFECT_FRESNEL));
  rt_ray_t r = ray_to(px_vec3(0, 0, -5), px_vec3(0, 0, 0)); /* normal incidence: F = 0.04 */
  rt_hit_t h;
  rt_surface_t sf;
  rt_child_t ch[2];
  assert_true(rt_intersect(&s, &r, &h));
  rt_shade_surface(&s, &h, &r, &sf);
  assert_int_equal(rt_shade_children(&s, &plan, &sf, &r, 0, ch), 2);
  assert_int_equal(ch[0].kind, RT_RAY_REFLECT);
  assert_int_equal(ch[1].kind, RT_RAY_REFRACT);
  assert_close(ch[0].weight.r, 0.1 + 0.8 * 0.04, 1e-15, 0);
  assert_close(ch[1].weight.r, 0.8 * 0.96, 1e-15, 0);
  assert_close(ch[1].ray.ior, 1.5, 0, 0);
  assert_int_equal(rt_shade_children(&s, &plan, &sf, &r, plan.max_depth, ch), 0);
  /* inside the ball along x = 0.9: sin(incidence) = 0.9 > 1/1.5, beyond the critical angle */
  rt_ray_t in = {px_vec3(0.9, 0, 0), px_vec3(0, 0, 1), 0, INFINITY, 1.5, -1, 0.0f};
  assert_true(rt_intersect(&s, &in, &h));
  rt_shade_surface(&s, &h, &in, &sf);
  assert_false(sf.entering);
  assert_int_equal(rt_shade_children(&s, &plan, &sf, &in, 0, ch), 1);
  assert_int_equal(ch[0].kind, RT_RAY_REFLECT);
  assert_true(ch[0].tir);
  assert_close(ch[0].weight.r, 0.1 + 0.8, 1e-15, 0);
  rt_scene_free(&s);
}

/* The scene's plan, the same without refraction, and without reflection. */
static void three_plans(const rt_scene_t *s, rt_plan_t plans[3]) {
  for (int p = 0; p < 3; p++)
    plans[p] = rt_plan_make(s, 1);
  plans[1].on &= ~(1u << RT_EFFECT_REFRACTION);
  plans[2].on &= ~(1u << RT_EFFECT_REFLECTION);
}

/* rt_shade_child() returns exactly the child of rt_shade_children() of its kind, bit for bit,
 * and nothing when there is none: both kinds at an entry (Fresnel split), after total internal
 * reflection (the mirror child carries kt, no refracted child), up to the depth limit, for a
 * material without a mirror term (kr = 0, no Fresnel: no reflected child) and in plans without
 * refraction or without reflection (a mirror child then only from the Fresnel share or total
 * internal reflection). rt_shade_child_ray() returns its ray, bit for bit, exactly where it
 * returns one. */
static void one_child_is_the_child_of_its_kind(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int ci = add_mat(&s, "clear", 0.0, 0.9, 1.5), gi = add_fresnel_glass(&s);
  rt_scene_add_sphere(&s, px_vec3(0, 0, 0), 1.0, gi, NULL);
  rt_scene_add_sphere(&s, px_vec3(0, 0, 10), 1.0, ci, NULL);
  /* a glass plane (its children skip it: skip_prim) */
  rt_scene_add_plane(&s, px_vec3(0, -3, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), gi, -1, 1, NULL);
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plans[3];
  three_plans(&s, plans);
  rt_ray_t rays[5] = {
      ray_to(px_vec3(0.3, 0.2, -5), px_vec3(0, 0, 0)), /* enters the glass ball */
      {px_vec3(0.9, 0, 0), px_vec3(0, 0, 1), 0, INFINITY, 1.5, -1, 0.0f}, /* inside it: TIR */
      ray_to(px_vec3(0.2, 0, 5), px_vec3(0, 0, 10)),    /* the clear ball: kr = 0 */
      ray_to(px_vec3(5, 2, 0), px_vec3(5.5, -3, 1)),    /* the glass plane */
      ray_to(px_vec3(0.3, 0.2, -5), px_vec3(0, 0, 0))}; /* a monochromatic ray into the ball */
  rays[4].lambda = 550.0f;
  int seen[3] = {0, 0, 0}; /* children returned: reflected, refracted, with TIR */
  for (int p = 0; p < 3; p++)
    for (int i = 0; i < 5; i++)
      for (int d = 0; d < 3; d++) { /* the first generation, the last, beyond the last */
        int depth = d ? plans[p].max_depth - 2 + d : 0;
        rt_hit_t h;
        rt_surface_t sf;
        rt_child_t ch[2], one;
        assert_true(rt_intersect(&s, &rays[i], &h));
        rt_shade_surface(&s, &h, &rays[i], &sf);
        int n = rt_shade_children(&s, &plans[p], &sf, &rays[i], depth, ch);
        for (int kind = RT_RAY_REFLECT; kind <= RT_RAY_REFRACT; kind++) {
          int m = 0;
          while (m < n && ch[m].kind != (rt_ray_kind_t)kind)
            m++;
          memset(&one, 0xa5, sizeof one);
          int got = rt_shade_child(&s, &plans[p], &sf, &rays[i], depth, kind, &one);
          assert_int_equal(got, m < n);
          rt_ray_t r;
          memset(&r, 0x5a, sizeof r);
          assert_int_equal(rt_shade_child_ray(&s, &plans[p], &sf, &rays[i], depth, kind, &r), got);
          if (!got)
            continue;
          assert_memory_equal(&r.o, &one.ray.o, sizeof r.o);
          assert_memory_equal(&r.d, &one.ray.d, sizeof r.d);
          assert_true(r.tmin == one.ray.tmin && r.tmax == one.ray.tmax && r.ior == one.ray.ior);
          assert_true(r.skip_prim == one.ray.skip_prim && r.lambda == one.ray.lambda);
          assert_memory_equal(&one.ray.o, &ch[m].ray.o, sizeof one.ray.o);
          assert_memory_equal(&one.ray.d, &ch[m].ray.d, sizeof one.ray.d);
          assert_true(one.ray.tmin == ch[m].ray.tmin && one.ray.tmax == ch[m].ray.tmax);
          assert_true(one.ray.ior == ch[m].ray.ior && one.ray.skip_prim == ch[m].ray.skip_prim);
          assert_memory_equal(&one.weight, &ch[m].weight, sizeof one.weight);
          assert_int_equal(one.kind, ch[m].kind);
          assert_int_equal(one.tir, ch[m].tir);
          seen[kind - RT_RAY_REFLECT]++;
          seen[2] += one.tir;
        }
      }
  assert_true(seen[0] > 0 && seen[1] > 0 && seen[2] > 0);
  /* a material made through the C API with a negative transmittance: the mirror child's weight
   * kr - kt |T| may vanish under total internal reflection; the ray-only function asks the
   * weight then, and agrees (the loader refuses such colours) */
  s.material[gi].transmittance = rt_rgb(-1, -1, -1);
  s.material[gi].kr = 0.3;
  s.material[gi].kt = 0.3;
  s.material[gi].fresnel = 0;
  rt_hit_t h;
  rt_surface_t sf;
  rt_child_t one;
  rt_ray_t r;
  assert_true(rt_intersect(&s, &rays[1], &h));
  rt_shade_surface(&s, &h, &rays[1], &sf);
  int got = rt_shade_child(&s, &plans[0], &sf, &rays[1], 0, RT_RAY_REFLECT, &one);
  assert_int_equal(got, 0); /* kr + kt T = 0.3 - 0.3 */
  assert_int_equal(rt_shade_child_ray(&s, &plans[0], &sf, &rays[1], 0, RT_RAY_REFLECT, &r), got);
  rt_scene_free(&s);
}

/* The scene of the walk tests: a Fresnel glass ball, a mirror checkerboard whose other squares
 * are clear glass without a mirror term (a material lookup per hit; kr = 0: the weight decides;
 * rt_shade_walk_ray4() takes its lanes one by one), a glass polygon and a tilted glass plane off
 * the origin, whose n.p sums products (which a compiler contracting them into FMAs would round
 * otherwise in the four-lane code), in a medium of index 1.1 (leaving the glass is not into 1). */
static void walk_scene(rt_scene_t *s) {
  rt_scene_init(s);
  s->ior = 1.1;
  int gi = add_fresnel_glass(s), mi = add_mat(s, "mirror", 0.7, 0.0, 1.0),
      ci = add_mat(s, "clear", 0.0, 0.9, 1.3);
  rt_scene_add_sphere(s, px_vec3(0, 0, 0), 1.0, gi, NULL);
  rt_scene_add_plane(s, px_vec3(0, -3, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi, ci, 0.5, NULL);
  const px_vec3_t quad[4] = {px_vec3(-4, -2, 3), px_vec3(4, -2, 3), px_vec3(4, 4, 3),
                             px_vec3(-4, 4, 3)};
  assert_int_equal(rt_scene_add_polygon(s, quad, 4, gi, NULL), RT_OK);
  rt_scene_add_plane(s, px_vec3(5, 0.7, -0.3), px_vec3(-0.95, 0.3, 0.17), px_vec3(0.3, 0.95, 0), gi,
                     -1, 1, NULL);
  assert_int_equal(rt_scene_prepare(s), RT_OK);
}

#define WALK_RAYS 2000

/* Rays from outside (index 1.1) towards the ball (its rim too), the polygon, the board and the
 * tilted plane, and from inside the ball (1.5) all round: directions about an aim on a Fibonacci
 * sphere. Returns how many (at most WALK_RAYS). */
static int walk_rays(rt_ray_t *rays) {
  const px_vec3_t from[5] = {px_vec3(0.2, 0.5, -5), px_vec3(1.5, 3, 6), px_vec3(3, 2, -2),
                             px_vec3(0.8, 0.1, 0.2), px_vec3(2, 0, -1)};
  const px_vec3_t aim[5] = {px_vec3(0, 0, 0), px_vec3(0.5, 1, 3), px_vec3(3, -3, 0),
                            px_vec3(0.8, 0.1, 0.2), px_vec3(5, 0.5, 0)};
  const double spread[5] = {0.3, 0.5, 0.5, 1.0, 0.5}, ior[5] = {1.1, 1.1, 1.1, 1.5, 1.1};
  int n = 0;
  for (int o = 0; o < 5; o++)
    for (int j = 0; j < 400; j++) {
      double z = 1.0 - (j + 0.5) / 200.0, rho = sqrt(1.0 - z * z), phi = 2.399963229728653 * j;
      px_vec3_t u = px_vec3(rho * cos(phi), rho * sin(phi), z), to = px_vec3_sub(aim[o], from[o]);
      if (o == 3)
        to = px_vec3(0, 0, 0);
      else
        px_vec3_normalize(to, &to);
      rt_ray_t r = {from[o], px_vec3(0, 0, 1), 0.0, INFINITY, ior[o], -1, 0.0f};
      if (px_vec3_normalize(px_vec3_add(to, px_vec3_scale(u, spread[o])), &r.d) == PX_OK)
        rays[n++] = r;
    }
  return n;
}

/* rt_shade_walk_ray() gives rt_shade_child_ray()'s ray at rt_shade_surface()'s record bit for bit,
 * and the same 0, where it does not leave the answer to it (-1): at a Fresnel glass ball entered
 * and left (total internal reflection among the rays from inside), a glass polygon and a mirror
 * checkerboard whose other squares are clear glass without a mirror term (a material lookup per
 * hit; kr = 0: the weight decides), under plans with and without reflection and refraction, from
 * the first generation to beyond the last. */
static void walk_ray_is_the_child_ray(void **state) {
  (void)state;
  rt_scene_t s;
  walk_scene(&s);
  rt_plan_t plans[3];
  three_plans(&s, plans);
  static rt_ray_t rays[WALK_RAYS];
  int nr = walk_rays(rays);
  int seen[4] = {0, 0, 0, 0};            /* returned 0, 1, -1; refraction refused by TIR */
  int compared[RT_RAY_SHADOW + 1] = {0}; /* rays compared, by kind */
  for (int i = 0; i < nr; i++) {
    rt_ray_t ray = rays[i];
    rt_hit_t h;
    if (!rt_intersect(&s, &ray, &h))
      continue;
    rt_surface_t sf;
    rt_shade_surface(&s, &h, &ray, &sf);
    for (int p = 0; p < 3; p++)
      for (int d = 0; d < 3; d++) {
        int depth = d ? plans[p].max_depth - 2 + d : 0;
        for (int kind = RT_RAY_PRIMARY; kind <= RT_RAY_SHADOW; kind++) {
          rt_ray_t r, w;
          memset(&r, 0x5a, sizeof r);
          memset(&w, 0xa5, sizeof w);
          int got = rt_shade_child_ray(&s, &plans[p], &sf, &ray, depth, kind, &r);
          int walked =
              rt_shade_walk_ray(&s, &plans[p], h.prim, h.p, ray.d, ray.ior, depth, kind, &w);
          if (walked < 0) { /* only where the mirror child's weight decides */
            const rt_material_t *m = sf.mat;
            assert_int_equal(kind, RT_RAY_REFLECT);
            assert_false(rt_plan_has(&plans[p], RT_EFFECT_REFLECTION) && m->kr > 0.0 &&
                         m->kt >= 0.0 && m->transmittance.r >= 0.0 && m->transmittance.g >= 0.0 &&
                         m->transmittance.b >= 0.0);
            seen[2]++;
            continue;
          }
          assert_int_equal(walked, got);
          seen[got]++;
          compared[kind] += got;
          seen[3] += !got && kind == RT_RAY_REFRACT && p == 0 && !d && sf.mat->kt > 0.0;
          if (got) /* rt_ray_t has no padding: every field's bits */
            assert_memory_equal(&w, &r, sizeof w);
        }
      }
  }
  assert_true(seen[0] > 0 && seen[1] > 0 && seen[2] > 0 && seen[3] > 0);
  assert_true(compared[RT_RAY_REFLECT] > 0 && compared[RT_RAY_REFRACT] > 0);
  rt_scene_free(&s);
}

/* The four-lane walk functions (libparaxial's px_interface_outgoing4(), core's
 * rt_shade_walk_ray4() and rt_prim_intersect4()) against their scalar functions lane by lane, bit
 * for bit: the pencil renderer's exact walks carry groups of samples with them and must give the
 * rays a walk of one sample gives. On a CPU without AVX2 and FMA the four-lane functions take the
 * lanes one by one through the scalar functions; the comparisons then hold trivially, and
 * snell_of_four_is_snell_of_each says so. */

/* splitmix64: a deterministic stream of doubles in [0, 1) */
static uint64_t rng_state = 0x9e3779b97f4a7c15u;
static double uniform(void) {
  uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1p-53;
}

static px_vec3_t random_unit(void) {
  for (;;) {
    px_vec3_t v = px_vec3(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
    double n = px_vec3_norm(v);
    if (n > 0.1 && n <= 1.0)
      return px_vec3_scale(v, 1.0 / n);
  }
}

static void put(px_vec3x4_t *v, int i, px_vec3_t a) {
  v->x[i] = a.x, v->y[i] = a.y, v->z[i] = a.z;
}

static px_vec3_t get(const px_vec3x4_t *v, int i) {
  return px_vec3(v->x[i], v->y[i], v->z[i]);
}

/* A direction at angle theta (cos c) from the unit normal nu. */
static px_vec3_t at_angle(px_vec3_t nu, double c) {
  px_vec3_t t = px_vec3_cross(nu, random_unit());
  px_vec3_normalize(t, &t);
  return px_vec3_add(px_vec3_scale(nu, c), px_vec3_scale(t, sqrt(fmax(0.0, 1.0 - c * c))));
}

/* px_interface_outgoing4() is px_interface_outgoing() in each lane: ordinary refractions,
 * total internal reflection, refractions near grazing with n1 ~ n2 (the compensated form, which
 * the four-lane function leaves to the scalar one), n1 = n2, reflections, a zero direction
 * (PX_ENONFINITE for a mirror) and lanes not asked for, mixed in one call. */
static void snell_of_four_is_snell_of_each(void **state) {
  (void)state;
  if (!px_simd4_available())
    fprintf(stderr, "note: no AVX2 and FMA here: the four-lane functions take the lanes one by "
                    "one, and these comparisons hold trivially\n");
  int seen[3] = {0, 0, 0}; /* OK near grazing with n1 ~ n2, PX_ETIR, PX_ENONFINITE */
  int compared = 0;
  for (int rep = 0; rep < 20000; rep++) {
    px_event_t ev = rep % 5 == 4 ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
    px_vec3x4_t s, nu, out;
    double n1[4], n2[4];
    unsigned lanes = rep % 7 == 3 ? 0xbu : 0xfu;
    px_status_t st[4];
    for (int i = 0; i < 4; i++) {
      px_vec3_t n = random_unit();
      int kind = (rep + i) % 5;
      double c = uniform();
      n1[i] = 1.0;
      n2[i] = 1.5;
      if (kind == 1) { /* leaving glass: total internal reflection beyond 41.8 degrees */
        n1[i] = 1.5;
        n2[i] = 1.0;
      } else if (kind == 2) { /* near grazing, indices a hair apart either way */
        c = 0.25 * uniform() * uniform();
        n2[i] = 1.0 + (uniform() - 0.5) * 1e-3;
      } else if (kind == 3) { /* equal indices near grazing */
        c = 0.01 * uniform();
        n1[i] = n2[i] = 1.33;
      }
      put(&s, i, at_angle(n, c));
      put(&nu, i, n);
      if (kind == 4 && ev == PX_EVENT_REFLECT && rep % 3 == 0)
        put(&s, i, px_vec3(0, 0, 0));
    }
    memset(&out, 0x5a, sizeof out);
    px_interface_outgoing4(ev, &s, &nu, n1, n2, lanes, &out, st);
    for (int i = 0; i < 4; i++) {
      if (!(lanes & (1u << i))) {
        assert_int_equal(st[i], PX_EINVAL);
        continue;
      }
      px_interface_t f = {.s = get(&s, i), .nu = get(&nu, i), .n1 = n1[i], .n2 = n2[i]};
      px_vec3_t o;
      double co;
      px_status_t want = px_interface_outgoing(&f, ev, &o, &co);
      assert_int_equal(st[i], want);
      if (want == PX_OK) {
        px_vec3_t g = get(&out, i);
        assert_memory_equal(&g, &o, sizeof g);
        compared++;
        double es = n1[i] / n2[i] * px_vec3_norm(px_vec3_cross(f.nu, f.s));
        seen[0] += ev == PX_EVENT_REFRACT && es > 15.0 / 16.0 && px_vec3_dot(f.nu, f.s) < 0.25;
      }
      seen[1] += want == PX_ETIR;
      seen[2] += want == PX_ENONFINITE;
    }
  }
  assert_true(compared > 40000);
  assert_true(seen[0] > 1000 && seen[1] > 1000 && seen[2] > 100);
}

/* rt_shade_walk_ray4() gives each lane what rt_shade_walk_ray() gives it (1 with the same ray, 0,
 * or -1), and 0 in a lane not asked for: the hits of the rays above grouped by primitive four at
 * a time, under plans with and without reflection and refraction, from the first generation to
 * beyond the last. */
static void walk_of_four_is_walk_of_each(void **state) {
  (void)state;
  rt_scene_t s;
  walk_scene(&s);
  rt_plan_t plans[3];
  three_plans(&s, plans);
  static rt_ray_t rays[WALK_RAYS];
  int nr = walk_rays(rays);
  int seen[3] = {0, 0, 0}, per_prim[8] = {0}; /* lanes returning 0, 1, -1; rays by primitive */
  for (int prim = 0; prim < s.nprim; prim++) {
    /* the hits on this primitive, in groups of four */
    px_vec3x4_t p, d;
    double ior[4];
    int k = 0;
    for (int i = 0; i < nr; i++) {
      rt_hit_t h;
      if (!rt_intersect(&s, &rays[i], &h) || h.prim != prim)
        continue;
      put(&p, k, h.p);
      put(&d, k, rays[i].d);
      ior[k] = rays[i].ior;
      per_prim[prim < 8 ? prim : 7]++;
      if (++k < 4)
        continue;
      k = 0;
      unsigned lanes = i % 3 ? 0xfu : 0x6u;
      for (int pl = 0; pl < 3; pl++)
        for (int dd = 0; dd < 3; dd++) {
          int depth = dd ? plans[pl].max_depth - 2 + dd : 0;
          for (int kind = RT_RAY_PRIMARY; kind <= RT_RAY_SHADOW; kind++) {
            rt_ray4_t out;
            int got[4];
            memset(&out, 0xa5, sizeof out);
            rt_shade_walk_ray4(&s, &plans[pl], prim, &p, &d, ior, depth, kind, lanes, &out, got);
            for (int l = 0; l < 4; l++) {
              if (!(lanes & (1u << l))) {
                assert_int_equal(got[l], 0);
                continue;
              }
              rt_ray_t w;
              int want = rt_shade_walk_ray(&s, &plans[pl], prim, get(&p, l), get(&d, l), ior[l],
                                           depth, kind, &w);
              assert_int_equal(got[l], want);
              seen[want < 0 ? 2 : want]++;
              if (want != 1)
                continue;
              px_vec3_t o = get(&out.o, l), dir = get(&out.d, l);
              assert_memory_equal(&o, &w.o, sizeof o);
              assert_memory_equal(&dir, &w.d, sizeof dir);
              assert_memory_equal(&out.ior[l], &w.ior, sizeof w.ior);
              assert_int_equal(out.skip_prim, w.skip_prim);
              assert_true(w.tmin == 0.0 && w.tmax == INFINITY && w.lambda == 0.0f);
            }
          }
        }
    }
  }
  for (int prim = 0; prim < s.nprim; prim++)
    if (per_prim[prim] < 8)
      fail_msg("primitive %d: %d hits", prim, per_prim[prim]);
  assert_true(seen[0] > 0 && seen[1] > 0 && seen[2] > 0);
  rt_scene_free(&s);
}

/* rt_prim_intersect4() gives each lane rt_prim_intersect()'s answer, distance and point bit for
 * bit: the walks' child rays (starting on the surfaces they leave) and a ray parallel to each
 * plane, against every primitive. */
static void intersections_of_four_are_those_of_each(void **state) {
  (void)state;
  rt_scene_t s;
  walk_scene(&s);
  rt_plan_t plan = rt_plan_make(&s, 1);
  static rt_ray_t rays[WALK_RAYS], kids[2 * WALK_RAYS + 2];
  int nr = walk_rays(rays), nk = 0;
  for (int i = 0; i < nr; i++) {
    rt_hit_t h;
    if (!rt_intersect(&s, &rays[i], &h))
      continue;
    for (int kind = RT_RAY_REFLECT; kind <= RT_RAY_REFRACT; kind++)
      if (rt_shade_walk_ray(&s, &plan, h.prim, h.p, rays[i].d, rays[i].ior, 0, kind, &kids[nk]) ==
          1)
        nk++;
  }
  kids[nk++] = (rt_ray_t){px_vec3(0.5, 1, -2), px_vec3(1, 0, 0), 0.0, INFINITY, 1.1, -1, 0.0f};
  kids[nk++] = (rt_ray_t){px_vec3(0.5, 1, 2), px_vec3(0, 1, 0), 0.0, INFINITY, 1.1, -1, 0.0f};
  int hits = 0, misses = 0;
  for (int prim = 0; prim < s.nprim; prim++)
    for (int i = 0; i < nk; i += 4) {
      px_vec3x4_t o, d, at;
      double t[4];
      unsigned lanes = 0;
      for (int l = 0; l < 4 && i + l < nk; l++) {
        put(&o, l, kids[i + l].o);
        put(&d, l, kids[i + l].d);
        lanes |= (i / 4) % 5 == 2 && l == 1 ? 0u : 1u << l;
      }
      unsigned hit = rt_prim_intersect4(&s, prim, &o, &d, lanes, t, &at);
      for (int l = 0; l < 4; l++) {
        if (!(lanes & (1u << l))) {
          assert_false(hit & (1u << l));
          continue;
        }
        double want_t;
        int want = rt_prim_intersect(&s, prim, &kids[i + l], INFINITY, &want_t);
        assert_int_equal((hit >> l) & 1u, want);
        if (!want) {
          misses++;
          continue;
        }
        hits++;
        px_vec3_t q = px_v3_axpy(want_t, kids[i + l].d, kids[i + l].o), g = get(&at, l);
        assert_memory_equal(&t[l], &want_t, sizeof want_t);
        assert_memory_equal(&g, &q, sizeof g);
      }
    }
  assert_true(hits > 500 && misses > 500);
  rt_scene_free(&s);
}

/* The caustics rule: with a light, a mirror and another, diffuse object the plan names the
 * receiver and the object the light comes through, and stays off (no renderer draws caustics
 * yet); without a light, with nothing diffuse besides the mirror, or with the scene's "off", it
 * says so. */
static void plan_names_caustic_paths(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int mirror = add_mat(&s, "mirror", 0.5, 0.0, 1.0), matte = add_mat(&s, "matte", 0, 0, 1);
  s.material[mirror].kd = 0.0; /* a pure mirror: nothing diffuse in it */
  int ball, floor_obj;
  rt_scene_add_sphere(&s, px_vec3(0, 0, 0), 1.0, mirror, &ball);
  rt_scene_add_plane(&s, px_vec3(0, -1, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mirror, -1, 1,
                     &floor_obj);
  rt_scene_name_object(&s, ball, "ball");
  rt_scene_name_object(&s, floor_obj, "floor");
  rt_plan_t plan = rt_plan_make(&s, 1);
  assert_non_null(strstr(plan.why[RT_EFFECT_CAUSTICS], "no light reaches a diffuse surface"));
  rt_light_t l = {RT_LIGHT_POINT, {0, 5, 0}, {1, 1, 1}, RT_FALLOFF_NONE, {0, 0, 0}, {0, 0, 0}, 0};
  assert_int_equal(rt_scene_add_light(&s, &l), RT_OK);
  plan = rt_plan_make(&s, 1);
  assert_non_null(strstr(plan.why[RT_EFFECT_CAUSTICS], "no light reaches a diffuse surface"));
  s.object[floor_obj].material = matte;
  plan = rt_plan_make(&s, 1);
  assert_false(rt_plan_has(&plan, RT_EFFECT_CAUSTICS)); /* the light has no fall-off */
  assert_non_null(strstr(plan.why[RT_EFFECT_CAUSTICS], "may pass 'ball'"));
  assert_non_null(strstr(plan.why[RT_EFFECT_CAUSTICS], "inverse-square"));
  s.light[0].falloff = RT_FALLOFF_INVERSE_SQUARE;
  plan = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&plan, RT_EFFECT_CAUSTICS));
  assert_non_null(strstr(plan.why[RT_EFFECT_CAUSTICS], "through 'ball' onto 'floor'"));
  assert_int_equal(plan.caustic.nplane, 1);
  assert_int_equal(plan.caustic.object[0][0], floor_obj);
  s.caustics = RT_CAUSTICS_OFF;
  plan = rt_plan_make(&s, 1);
  assert_non_null(strstr(plan.why[RT_EFFECT_CAUSTICS], "the scene refuses them"));
  rt_scene_free(&s);
}

/* A scene without transparent materials plans no refraction, and rendering it traces no
 * refracted ray; without mirrors either, the ray tree is one node. */
static void plan_skips_effects_the_scene_does_not_use(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  int mirror = add_mat(&s, "mirror", 0.5, 0.0, 1.0), matte = add_mat(&s, "matte", 0, 0, 1);
  rt_scene_add_sphere(&s, px_vec3(0, 0, 0), 1.0, mirror, NULL);
  rt_scene_add_plane(&s, px_vec3(0, -1, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), matte, -1, 1, NULL);
  s.camera.width = s.camera.height = 8;
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&plan, RT_EFFECT_REFLECTION));
  assert_false(rt_plan_has(&plan, RT_EFFECT_REFRACTION));
  assert_false(rt_plan_has(&plan, RT_EFFECT_SHADOWS)); /* no lights */
  assert_non_null(strstr(plan.why[RT_EFFECT_REFRACTION], "no transparent material"));
  assert_int_equal(plan.tree_nodes, s.max_depth + 1); /* a chain of reflections */
  rt_image_t img;
  xr_options_t opt = XR_OPTIONS_DEFAULT;
  rt_stats_t st;
  assert_int_equal(rt_image_alloc(&img, 8, 8), RT_OK);
  assert_int_equal(xr_render(&s, &plan, &opt, &img, &st), RT_OK);
  assert_true(st.reflect > 0);
  assert_int_equal(st.refract, 0);
  assert_int_equal(st.shadow, 0);
  s.object[0].material = matte;
  plan = rt_plan_make(&s, 1);
  assert_int_equal(plan.on & ((1u << RT_EFFECT_REFLECTION) | (1u << RT_EFFECT_REFRACTION)), 0);
  assert_int_equal(plan.tree_nodes, 1);
  assert_int_equal(xr_render(&s, &plan, &opt, &img, &st), RT_OK);
  assert_int_equal(st.reflect + st.refract + st.shadow, 0);
  assert_int_equal(st.primary, 64);
  rt_image_free(&img);
  rt_scene_free(&s);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(refraction_through_sphere_matches_exact),
      cmocka_unit_test(mirror_sphere_reflection_matches_exact),
      cmocka_unit_test(refraction_through_polyhedron_matches_exact),
      cmocka_unit_test(shadow_attenuation_is_product_of_kt),
      cmocka_unit_test(direct_light_follows_illumination_equation),
      cmocka_unit_test(two_materials_shaded_at_once_match_each_alone),
      cmocka_unit_test(parallel_light_and_its_shadow),
      cmocka_unit_test(fresnel_limits),
      cmocka_unit_test(children_weights_fresnel_and_tir),
      cmocka_unit_test(one_child_is_the_child_of_its_kind),
      cmocka_unit_test(walk_ray_is_the_child_ray),
      cmocka_unit_test(snell_of_four_is_snell_of_each),
      cmocka_unit_test(walk_of_four_is_walk_of_each),
      cmocka_unit_test(intersections_of_four_are_those_of_each),
      cmocka_unit_test(plan_skips_effects_the_scene_does_not_use),
      cmocka_unit_test(plan_names_caustic_paths),
      cmocka_unit_test(area_light_sums_its_mesh_points),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
