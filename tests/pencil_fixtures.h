/* pencil_fixtures.h -- fixtures shared by the pencil renderer's tests (tests/test_pencil.c): the
 * scenes they render (Fig. 8, the bare board, scenes/NAME.json, a mirror ball), one render by
 * each renderer (exact and pencil) with the test's options, and the comparisons of a pencil
 * image with the exact one (over the whole image, over the pixels where the checkerboard is
 * resolved, over one object's pixels). Every fixture fails the running cmocka case on an error;
 * images are allocated by the fixture and freed by the caller (rt_image_free). */
#ifndef PENCIL_TESTS_PENCIL_FIXTURES_H
#define PENCIL_TESTS_PENCIL_FIXTURES_H

#include "core/scene.h"
#include "pencil/pencil.h"
#include "render/render.h"

/* ---- scenes ---------------------------------------------------------------------------- */

/** The built-in Fig. 8 scene at w x h pixels (prepared). */
void fx_fig8(rt_scene_t *s, int w, int h);

/** The Fig. 8 stage without the glass ball: a lit checkerboard, seen more steeply than in
 *  Fig. 8 so that no horizon (an edge) is in view (prepared). */
void fx_board(rt_scene_t *s, int w, int h);

/** scenes/NAME.json, its image rescaled to `width` pixels across (the aspect kept). */
void fx_scene_file(const char *name, int width, rt_scene_t *s);

/** Adds to the fx_board() stage a mirror ball of radius 1 at (0, 1, 0) and aims the camera at
 *  it (the scene is left unprepared). Returns the ball's object index. */
int fx_add_mirror_ball(rt_scene_t *s);

/* ---- renders --------------------------------------------------------------------------- */

/** The exact renderer's image of s at side x side samples per pixel, into e. */
void fx_render_exact(const rt_scene_t *s, int side, int threads, rt_image_t *e);

/** The pencil renderer's image of s at side x side samples per pixel with options `base`
 *  (NULL: PT_OPTIONS_DEFAULT; its spp_side and threads are replaced), into img; x and st may be
 *  NULL. */
void fx_render_pencil(const rt_scene_t *s, int side, int threads, const pt_options_t *base,
                      rt_image_t *img, pt_extra_t *x, pt_stats_t *st);

/** fx_render_pencil()'s statistics alone (the image is rendered and freed). */
pt_stats_t fx_pencil_stats(const rt_scene_t *s, int side, int threads, const pt_options_t *base);

/* ---- comparisons with the exact image -------------------------------------------------- */

/** Differences of a pencil image from the exact one over a set of pixels (every channel R, G,
 *  B of each). */
typedef struct {
  int n;        /**< pixels compared */
  double mean;  /**< mean difference (pencil - exact) over their channels */
  double rms;   /**< RMS difference over their channels */
  double worst; /**< largest |difference| of any channel */
  int big;      /**< pixels with some channel off by more than the caller's threshold */
} fx_diff_t;

/** Image p against the exact renderer's image of s at side x side samples per pixel, over the
 *  pixels where the checkerboard (transmission path) moves by less than half a square to the
 *  next pixel, so that a square edge is not inside most of them; `big` counts pixels off by
 *  more than 0.1. */
fx_diff_t fx_board_difference(const rt_scene_t *s, const rt_image_t *p, int side);

/** Image p against the exact renderer's image of s at side x side samples per pixel, over every
 *  pixel; `big` counts pixels off by more than 0.1. */
fx_diff_t fx_exact_difference(const rt_scene_t *s, const rt_image_t *p, int side);

/** Image p against the exact image e over the pixels whose centre ray meets object obj first
 *  in e (-1: nothing); `big` counts pixels off by more than `big_above`. */
fx_diff_t fx_object_difference(const rt_image_t *e, const rt_image_t *p, int obj, double big_above);

/** Fails unless images a and b (of one size) are bitwise equal in every channel. */
void fx_assert_images_equal(const rt_image_t *a, const rt_image_t *b);

#endif
