/* test_render_image.c -- whole renders on tiny images: independence of the thread count, the
 * box filter over s x s sub-pixel grids, ray trees (recording changes nothing; trees tell
 * surfaces apart), the auxiliary channels against reference/'s exact tracer, option checks. */
#include <math.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/builtin.h"
#include "core/intersect.h"
#include "exact/trace.h"
#include "render/render.h"

static void fig8(rt_scene_t *s, int w, int h) {
  rt_scene_init(s);
  assert_int_equal(rt_builtin_fig8(s), RT_OK);
  s->camera.width = w;
  s->camera.height = h;
}

static void render(const rt_scene_t *s, int side, int threads, rt_image_t *img, rt_stats_t *st) {
  rt_plan_t plan = rt_plan_make(s, side * side);
  xr_options_t opt = XR_OPTIONS_DEFAULT;
  opt.spp_side = side;
  opt.threads = threads;
  assert_int_equal(rt_image_alloc(img, s->camera.width, s->camera.height), RT_OK);
  assert_int_equal(xr_render(s, &plan, &opt, img, st), RT_OK);
}

/* Pixels are independent and each is computed the same way by whichever thread: bitwise equal
 * images (NaN channels included) for 1 and 2 threads. */
static void image_does_not_depend_on_threads(void **state) {
  (void)state;
  rt_scene_t s;
  fig8(&s, 20, 14);
  rt_image_t a, b;
  rt_stats_t sa, sb;
  render(&s, 2, 1, &a, &sa);
  render(&s, 2, 2, &b, &sb);
  for (int c = 0; c < RT_CH_COUNT; c++)
    assert_memory_equal(a.ch[c], b.ch[c], sizeof(float) * 20 * 14);
  assert_true(rt_stats_total(&sa) == rt_stats_total(&sb));
  assert_int_equal(sa.primary, 20 * 14 * 4 + 20 * 14); /* even s: one extra centre ray */
  rt_image_free(&a);
  rt_image_free(&b);
  rt_scene_free(&s);
}

/* A uniformly coloured view (an unlit plane filling the image: ambient only): every sub-sample
 * has the same radiance, so the box filter returns it for every s; the only difference is the
 * rounding of an average of s^2 equal doubles, far below float resolution. */
static void box_filter_preserves_uniform_colour(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  rt_material_t m = rt_material_default("m");
  m.color = rt_rgb(0.3, 0.6, 0.9);
  m.ka = 1.0;
  int mi;
  rt_scene_add_material(&s, &m, &mi);
  rt_scene_add_plane(&s, px_vec3(0, 0, 0), px_vec3(0, 0, -1), px_vec3(1, 0, 0), mi, -1, 1, NULL);
  s.camera = (rt_camera_t){{0, 0, -3}, {0, 0, 0}, {0, 1, 0}, 30.0, 5, 4};
  assert_int_equal(rt_scene_prepare(&s), RT_OK);
  for (int side = 1; side <= 7; side++) {
    rt_image_t img;
    rt_stats_t st;
    render(&s, side, 1, &img, &st);
    for (int k = 0; k < 20; k++) {
      assert_close(img.ch[RT_CH_R][k], 0.03f, 1e-6, 0);
      assert_close(img.ch[RT_CH_G][k], 0.06f, 1e-6, 0);
      assert_close(img.ch[RT_CH_B][k], 0.09f, 1e-6, 0);
    }
    assert_int_equal(st.primary, (uint64_t)(20 * side * side + (side % 2 ? 0 : 20)));
    rt_image_free(&img);
  }
  rt_scene_free(&s);
}

/* The box filter really averages: with 2 x 2 samples on a checker edge the pixel is the mean of
 * the samples traced one by one. */
static void box_filter_is_the_mean_of_samples(void **state) {
  (void)state;
  rt_scene_t s;
  fig8(&s, 9, 9);
  rt_image_t img;
  rt_stats_t st;
  render(&s, 2, 1, &img, &st);
  rt_view_t v;
  assert_int_equal(rt_view_make(&s.camera, &v), RT_OK);
  rt_plan_t plan = rt_plan_make(&s, 4);
  xr_exact_t ex = xr_exact_make(&s, &plan, NULL);
  for (int j = 0; j < 9; j += 4)
    for (int i = 0; i < 9; i += 3) {
      double sum = 0;
      for (int b = 0; b < 2; b++)
        for (int a = 0; a < 2; a++) {
          rt_ray_t r = rt_view_ray(&v, i + (a + 0.5) / 2, j + (b + 0.5) / 2, 1.0);
          sum += xr_exact_primary(&ex, &r).g;
        }
      assert_close(img.ch[RT_CH_G][j * 9 + i], sum / 4, 1e-6, 1e-7); /* float rounding */
    }
  rt_image_free(&img);
  rt_scene_free(&s);
}

/* Recording a ray tree changes neither the colour nor the counts; the tree of a ray through the
 * glass ball differs from that of a ray on the board, and equals that of a close neighbour. */
static void ray_trees_are_free_and_discriminating(void **state) {
  (void)state;
  rt_scene_t s;
  fig8(&s, 64, 64);
  rt_plan_t plan = rt_plan_make(&s, 1);
  rt_view_t v;
  rt_view_make(&s.camera, &v);
  rt_tree_node_t b1[128], b2[128], b3[128];
  rt_tree_t t1 = rt_tree_make(b1, 128), t2 = rt_tree_make(b2, 128), t3 = rt_tree_make(b3, 128);
  xr_exact_t plain = xr_exact_make(&s, &plan, NULL), rec = xr_exact_make(&s, &plan, &t1);
  rt_ray_t centre = rt_view_ray(&v, 32.5, 30.5, 1.0);
  rt_rgb_t c0 = xr_exact_primary(&plain, &centre), c1 = xr_exact_primary(&rec, &centre);
  assert_memory_equal(&c0, &c1, sizeof c0);
  assert_memory_equal(&plain.stats, &rec.stats, sizeof plain.stats);
  assert_true(t1.n > 3);
  assert_int_equal(t1.node[0].object, 1); /* the glass ball */
  rec.tree = &t2;
  rt_ray_t near = rt_view_ray(&v, 32.5 + 1e-4, 30.5, 1.0);
  xr_exact_primary(&rec, &near);
  assert_true(rt_tree_same(&t1, &t2));
  rec.tree = &t3;
  rt_ray_t floor = rt_view_ray(&v, 2.5, 62.5, 1.0);
  xr_exact_primary(&rec, &floor);
  assert_false(rt_tree_same(&t1, &t3));
  assert_int_equal(t3.node[0].object, 0);
  assert_true(t3.node[0].texel == 0 || t3.node[0].texel == 1);
  rt_scene_free(&s);
}

/* The auxiliary channels of a pixel on the upper half of the ball: the transmission path enters
 * and leaves the ball (pathT.k = 2) and lands on the board where reference/'s exact tracer,
 * through the same sphere and plane as exact quadrics, lands. Tolerance: float32 channels (relative
 * 6e-8 of |u| < 10) plus the renderer's 2e-9 surface offsets magnified along the path: 2e-6
 * absolute. */
static void aux_channels_match_exact_tracer(void **state) {
  (void)state;
  rt_scene_t s;
  fig8(&s, 9, 9);
  rt_image_t img;
  rt_stats_t st;
  render(&s, 3, 1, &img, &st);
  size_t k = 3 * 9 + 4, low = 4 * 9 + 4;
  assert_true(img.ch[RT_CH_ID][k] == 1.0f);
  /* through the lower half the lens sends the path up to the sky: it never meets the board */
  assert_true(img.ch[RT_CH_ID][low] == 1.0f && img.ch[RT_CH_T_K][low] == -1.0f);
  assert_true(isnan(img.ch[RT_CH_T_U][low]));
  assert_true(img.ch[RT_CH_T_K][k] == 2.0f);
  rt_view_t v;
  rt_view_make(&s.camera, &v);
  rt_ray_t r = rt_view_ray(&v, 4.5, 3.5, 1.0);
  ex_quadric_t ball = ex_quadric_sphere(px_vec3(0, 1.5, 0), 1.0);
  ex_stage_t stg[3] = {
      {ball, PX_EVENT_REFRACT, 1.5, 0},
      {ball, PX_EVENT_REFRACT, 1.0, 0},
      {ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 1, 0)), PX_EVENT_REFLECT, 1.0, 0}};
  px_frame_t f;
  px_frame_from_z(r.d, px_vec3(0, 1, 0), &f);
  ex_system_t sys = {r.o, f, 1.0, stg, 3, 0.0, 0.0};
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  double u, w;
  rt_plane_coords(&s.prim[0].plane, ax.hit[2], &u, &w);
  assert_close(img.ch[RT_CH_T_U][k], u, 0, 2e-6);
  assert_close(img.ch[RT_CH_T_V][k], w, 0, 2e-6);
  assert_close(img.ch[RT_CH_Z][k], ax.t[0], 1e-6, 0);
  /* a pixel on the board: both paths are the primary hit itself */
  size_t b = 8 * 9 + 0;
  assert_true(img.ch[RT_CH_ID][b] == 0.0f);
  assert_true(img.ch[RT_CH_T_K][b] == 0.0f && img.ch[RT_CH_R_K][b] == 0.0f);
  assert_true(img.ch[RT_CH_T_U][b] == img.ch[RT_CH_R_U][b]);
  rt_image_free(&img);
  rt_scene_free(&s);
}

typedef struct {
  int calls[6 * 5];    /* per pixel: each pixel is rendered by one thread, so no race */
  int nodes[6 * 5];    /* total tree nodes handed over */
  double green[6 * 5]; /* sum of the samples' green radiance (grid samples only) */
} samples_t;

static void on_sample(void *ctx, int i, int j, int a, int b, const rt_tree_t *t, rt_rgb_t c) {
  samples_t *S = ctx;
  S->calls[j * 6 + i]++;
  S->nodes[j * 6 + i] += t->n;
  if (a >= 0 && b >= 0)
    S->green[j * 6 + i] += c.g;
}

/* With on_sample the caller receives every sample's tree (plus the extra centre ray of even s),
 * from several threads, and the samples average to the pixel. */
static void every_sample_tree_reaches_the_caller(void **state) {
  (void)state;
  rt_scene_t s;
  fig8(&s, 6, 5);
  rt_plan_t plan = rt_plan_make(&s, 4);
  xr_options_t opt = XR_OPTIONS_DEFAULT;
  samples_t S;
  memset(&S, 0, sizeof S);
  opt.spp_side = 2;
  opt.threads = 2;
  opt.on_sample = on_sample;
  opt.sample_ctx = &S;
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, 6, 5), RT_OK);
  assert_int_equal(xr_render(&s, &plan, &opt, &img, NULL), RT_OK);
  for (int k = 0; k < 30; k++) {
    assert_int_equal(S.calls[k], 4 + 1);
    assert_true(S.nodes[k] >= 5);
    assert_close(img.ch[RT_CH_G][k], S.green[k] / 4, 1e-6, 1e-7);
  }
  rt_image_free(&img);
  rt_scene_free(&s);
}

static void bad_options_rejected(void **state) {
  (void)state;
  rt_scene_t s;
  fig8(&s, 4, 4);
  rt_plan_t plan = rt_plan_make(&s, 1);
  xr_options_t opt = XR_OPTIONS_DEFAULT;
  rt_image_t img, small;
  assert_int_equal(rt_image_alloc(&img, 4, 4), RT_OK);
  opt.spp_side = 0;
  assert_int_equal(xr_render(&s, &plan, &opt, &img, NULL), RT_EINVAL);
  opt.spp_side = RT_MAX_SPP_SIDE + 1;
  assert_int_equal(xr_render(&s, &plan, &opt, &img, NULL), RT_EINVAL);
  opt.spp_side = 1;
  assert_int_equal(rt_image_alloc(&small, 3, 4), RT_OK);
  assert_int_equal(xr_render(&s, &plan, &opt, &small, NULL), RT_EINVAL);
  rt_scene_add_sphere(&s, px_vec3(3, 0, 0), 0.5, 0, NULL); /* changed: BVH dropped */
  assert_int_equal(xr_render(&s, &plan, &opt, &img, NULL), RT_ENOTREADY);
  rt_image_free(&small);
  assert_int_equal(rt_image_alloc(&small, 0, 4), RT_EINVAL);
  rt_image_free(&img);
  rt_scene_free(&s);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(image_does_not_depend_on_threads),
      cmocka_unit_test(box_filter_preserves_uniform_colour),
      cmocka_unit_test(box_filter_is_the_mean_of_samples),
      cmocka_unit_test(ray_trees_are_free_and_discriminating),
      cmocka_unit_test(aux_channels_match_exact_tracer),
      cmocka_unit_test(every_sample_tree_reaches_the_caller),
      cmocka_unit_test(bad_options_rejected),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
