/* pencil_fixtures.c -- fixtures shared by the pencil renderer's tests (pencil_fixtures.h). */
#include <math.h>
#include <stdio.h>

#include "cmocka_main.h"
#include "core/builtin.h"
#include "core/camera.h"
#include "io/scene_json.h"
#include "pencil_fixtures.h"

void fx_fig8(rt_scene_t *s, int w, int h) {
  rt_scene_init(s);
  assert_int_equal(rt_builtin_fig8(s), RT_OK);
  s->camera.width = w;
  s->camera.height = h;
}

void fx_board(rt_scene_t *s, int w, int h) {
  rt_scene_init(s);
  rt_material_t white = rt_material_default("white"), red = rt_material_default("red");
  red.color = rt_rgb(0.85, 0.12, 0.1);
  int mw, mr;
  rt_scene_add_material(s, &white, &mw);
  rt_scene_add_material(s, &red, &mr);
  rt_scene_add_plane(s, px_vec3(0, 0, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mw, mr, 1.0, NULL);
  rt_light_t l = {RT_LIGHT_POINT, {-5.0, 6.0, -2.5}, {1, 1, 1}, RT_FALLOFF_NONE,
                  {0, 0, 0},      {0, 0, 0},         0};
  rt_scene_add_light(s, &l);
  /* looking down more steeply than Fig. 8, so that no horizon (an edge) is in view */
  s->camera = (rt_camera_t){{0.0, 3.0, -6.0}, {0.0, 0.0, 0.0}, {0, 1, 0}, 40.0, w, h};
  assert_int_equal(rt_scene_prepare(s), RT_OK);
}

void fx_scene_file(const char *name, int width, rt_scene_t *s) {
  char path[1024], err[512];
  snprintf(path, sizeof path, "%s/scenes/%s.json", PENCIL_SOURCE_DIR, name);
  rt_scene_init(s);
  assert_int_equal(io_scene_load(path, s, err, sizeof err), 0);
  s->camera.height = (int)lrint((double)width * s->camera.height / s->camera.width);
  s->camera.width = width;
}

int fx_add_mirror_ball(rt_scene_t *s) {
  rt_material_t m = rt_material_default("mirror");
  m.ka = 0.05;
  m.kd = 0.1;
  m.kr = 0.8;
  int mm, ball;
  rt_scene_add_material(s, &m, &mm);
  rt_scene_add_sphere(s, px_vec3(0.0, 1.0, 0.0), 1.0, mm, &ball);
  s->camera.look_at = px_vec3(0.0, 1.0, 0.0);
  return ball;
}

void fx_render_exact(const rt_scene_t *s, int side, int threads, rt_image_t *e) {
  rt_plan_t plan = rt_plan_make(s, side * side);
  xr_options_t eo = XR_OPTIONS_DEFAULT;
  eo.spp_side = side;
  eo.threads = threads;
  assert_int_equal(rt_image_alloc(e, s->camera.width, s->camera.height), RT_OK);
  assert_int_equal(xr_render(s, &plan, &eo, e, NULL), RT_OK);
}

void fx_render_pencil(const rt_scene_t *s, int side, int threads, const pt_options_t *base,
                      rt_image_t *img, pt_extra_t *x, pt_stats_t *st) {
  rt_plan_t plan = rt_plan_make(s, side * side);
  pt_options_t o = base ? *base : (pt_options_t)PT_OPTIONS_DEFAULT;
  o.spp_side = side;
  o.threads = threads;
  assert_int_equal(rt_image_alloc(img, s->camera.width, s->camera.height), RT_OK);
  assert_int_equal(pt_render(s, &plan, &o, img, x, NULL, st), RT_OK);
}

pt_stats_t fx_pencil_stats(const rt_scene_t *s, int side, int threads, const pt_options_t *base) {
  rt_image_t img;
  pt_stats_t st;
  fx_render_pencil(s, side, threads, base, &img, NULL, &st);
  rt_image_free(&img);
  return st;
}

/* How far pixel k's transmission-path checkerboard point moves to its right and lower
 * neighbours, in squares (the exact image's aux channels); INFINITY off the board. */
static double board_step(const rt_image_t *e, int k, int w, int h) {
  int i = k % w, j = k / w;
  const float *u = e->ch[RT_CH_T_U], *v = e->ch[RT_CH_T_V];
  if (i + 1 >= w || j + 1 >= h || !isfinite(u[k]) || !isfinite(u[k + 1]) || !isfinite(u[k + w]))
    return INFINITY;
  return fmax(hypot(u[k + 1] - u[k], v[k + 1] - v[k]), hypot(u[k + w] - u[k], v[k + w] - v[k]));
}

/* Running sums of a comparison. */
typedef struct {
  fx_diff_t d;
  double sum, sq; /* of the differences and their squares */
} diff_acc_t;

/* Pixel k of p against e into A (`big` above big_above). */
static void diff_add(diff_acc_t *A, const rt_image_t *e, const rt_image_t *p, int k,
                     double big_above) {
  double m = 0.0;
  for (int c = 0; c < 3; c++) {
    double d = (double)p->ch[c][k] - (double)e->ch[c][k];
    A->sum += d;
    A->sq += d * d;
    m = fmax(m, fabs(d));
  }
  A->d.big += m > big_above;
  A->d.worst = fmax(A->d.worst, m);
  A->d.n++;
}

static fx_diff_t diff_end(diff_acc_t *A) {
  A->d.mean = A->d.n ? A->sum / (3.0 * A->d.n) : 0.0;
  A->d.rms = A->d.n ? sqrt(A->sq / (3.0 * A->d.n)) : 0.0;
  return A->d;
}

fx_diff_t fx_board_difference(const rt_scene_t *s, const rt_image_t *p, int side) {
  int w = s->camera.width, h = s->camera.height;
  rt_image_t e;
  fx_render_exact(s, side, 1, &e);
  diff_acc_t A = {{0, 0.0, 0.0, 0.0, 0}, 0.0, 0.0};
  for (int k = 0; k < w * h; k++)
    if (board_step(&e, k, w, h) < 0.5)
      diff_add(&A, &e, p, k, 0.1);
  rt_image_free(&e);
  return diff_end(&A);
}

fx_diff_t fx_exact_difference(const rt_scene_t *s, const rt_image_t *p, int side) {
  rt_image_t e;
  fx_render_exact(s, side, 1, &e);
  diff_acc_t A = {{0, 0.0, 0.0, 0.0, 0}, 0.0, 0.0};
  for (int k = 0; k < e.width * e.height; k++)
    diff_add(&A, &e, p, k, 0.1);
  rt_image_free(&e);
  return diff_end(&A);
}

fx_diff_t fx_object_difference(const rt_image_t *e, const rt_image_t *p, int obj,
                               double big_above) {
  diff_acc_t A = {{0, 0.0, 0.0, 0.0, 0}, 0.0, 0.0};
  for (int k = 0; k < e->width * e->height; k++)
    if (e->ch[RT_CH_ID][k] == (float)obj)
      diff_add(&A, e, p, k, big_above);
  return diff_end(&A);
}

void fx_assert_images_equal(const rt_image_t *a, const rt_image_t *b) {
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  for (int c = 0; c < RT_CH_COUNT; c++)
    assert_memory_equal(a->ch[c], b->ch[c], sizeof(float) * (size_t)a->width * (size_t)a->height);
}
