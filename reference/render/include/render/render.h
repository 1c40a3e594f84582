/* render.h -- the conventional (exact, Whitted) renderer: primary rays through an s x s
 * sub-pixel grid, nearest hits through the BVH, shading by shade.h, recursion to the depth
 * limit (textbook 9.1 Trace; course notes 1.7.5 supersampling), multi-threaded with OpenMP.
 *
 * The image carries, besides RGB, auxiliary channels computed from the ray tree of each
 * pixel's centre ray, so that a pencil renderer's accuracy can be recomputed independently
 * (paper section 5, Fig. 10: distance between the checkerboard points found by the two
 * tracers, in units of the pixel interval on the board).
 */
#ifndef RENDER_RENDER_H
#define RENDER_RENDER_H

#include <stdint.h>

#include "render/camera.h"
#include "render/plan.h"
#include "render/raytree.h"
#include "render/scene.h"
#include "render/shade.h"

/** Image channels, float32 each. Names are the OpenEXR channel names. */
typedef enum {
  RT_CH_R = 0, /**< box-filtered linear radiance, red */
  RT_CH_G,     /**< green */
  RT_CH_B,     /**< blue */
  RT_CH_Z,     /**< centre ray: distance from the eye to the first hit (INFINITY on a miss) */
  RT_CH_ID,    /**< centre ray: object index of the first hit, -1 on a miss */
  RT_CH_T_U,   /**< centre ray, transmission-first path: checkerboard u (NaN: never met) */
  RT_CH_T_V,   /**< ... checkerboard v */
  RT_CH_T_K,   /**< ... reflections/refractions before the board (-1: never met) */
  RT_CH_R_U,   /**< reflection-first path: checkerboard u */
  RT_CH_R_V,   /**< ... checkerboard v */
  RT_CH_R_K,   /**< ... reflections/refractions before the board (-1: never met) */
  RT_CH_COUNT
} rt_channel_t;

/** OpenEXR name of a channel: "R", "G", "B", "Z", "id", "pathT.u", ... */
const char *rt_channel_name(rt_channel_t c);

typedef struct {
  int width, height;
  float *ch[RT_CH_COUNT]; /**< ch[c][j * width + i], row j from the top; owned by the image */
} rt_image_t;

rt_status_t rt_image_alloc(rt_image_t *img, int width, int height);
void rt_image_free(rt_image_t *img);
/** Fill the auxiliary channels (Z, id, both paths' checkerboard u, v and event counts) of pixel
 *  index k from the ray tree of that pixel's centre ray. Shared by every renderer, so that the
 *  channels mean the same whichever method made the image. */
void rt_image_set_aux(rt_image_t *img, const rt_scene_t *s, size_t k, const rt_tree_t *t);

/** Ray counts (all generations, summed over threads). */
typedef struct {
  uint64_t primary; /**< eye rays, including the extra centre rays of even s */
  uint64_t reflect;
  uint64_t refract;
  uint64_t shadow;
} rt_stats_t;

static inline uint64_t rt_stats_total(const rt_stats_t *s) {
  return s->primary + s->reflect + s->refract + s->shadow;
}

/** The exact tracer's per-thread state: an rt_tracer_t for shade.h plus an optional ray tree. */
typedef struct {
  const rt_scene_t *scene;
  const rt_plan_t *plan;
  rt_tree_t *tree; /**< NULL: record nothing */
  int node;        /**< tree node of the ray being shaded (recording only) */
  rt_stats_t stats;
} rt_exact_t;

/** A tracer over a prepared scene; tree may be NULL. */
rt_exact_t rt_exact_make(const rt_scene_t *s, const rt_plan_t *plan, rt_tree_t *tree);

/** Radiance along a primary ray (textbook Trace(r, 0)); records the sample's tree from scratch
 *  when the tracer has one. */
rt_rgb_t rt_exact_primary(rt_exact_t *ex, const rt_ray_t *ray);

/** The shade.h callbacks of the exact tracer, with ctx = the rt_exact_t. */
rt_tracer_t rt_exact_tracer(rt_exact_t *ex);

typedef struct {
  int spp_side; /**< s: s x s samples per pixel, 1..RT_MAX_SPP_SIDE */
  int threads;  /**< OpenMP threads; 0 = the OpenMP default */
  int aux;      /**< 1: fill the auxiliary channels (traces trees of centre rays) */
  /** Called after each finished row with (rows done, rows total), serialised; may be NULL. */
  void (*progress)(void *ctx, int done, int total);
  void *progress_ctx;
  /** When not NULL, every sample's ray tree is recorded and handed over: pixel (i, j),
   *  sub-sample (a, b) of the s x s grid (a = b = -1 for the extra centre ray of even s), the
   *  sample's radiance. Called from the rendering threads, concurrently: the callee must only
   *  touch per-pixel state or synchronise itself. The tree is valid during the call only. */
  void (*on_sample)(void *ctx, int i, int j, int a, int b, const rt_tree_t *tree, rt_rgb_t c);
  void *sample_ctx;
} rt_render_options_t;

#define RT_RENDER_OPTIONS_DEFAULT                                                                  \
  { 1, 0, 1, NULL, NULL, NULL, NULL }

/** Threads a render with `requested` threads uses: requested when > 0, else the OpenMP
 *  default (1 without OpenMP). */
int rt_thread_count(int requested);

/** Render the prepared scene with `plan` into img (allocated by the caller at the camera's
 *  size). Pixels are independent, so the image does not depend on the thread count.
 *  RT_EINVAL for a bad option or image size, RT_ENOTREADY for an unprepared scene, RT_ENOMEM. */
rt_status_t rt_render(const rt_scene_t *s, const rt_plan_t *plan, const rt_render_options_t *opt,
                      rt_image_t *img, rt_stats_t *stats);

#endif
