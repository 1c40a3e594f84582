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

#include "core/camera.h"
#include "core/image.h"
#include "core/plan.h"
#include "core/raytree.h"
#include "core/scene.h"
#include "core/shade.h"

/** The exact tracer's per-thread state: an rt_tracer_t for shade.h plus an optional ray tree. */
typedef struct {
  const rt_scene_t *scene;
  const rt_plan_t *plan;
  rt_tree_t *tree; /**< NULL: record nothing */
  int node;        /**< tree node of the ray being shaded (recording only) */
  rt_stats_t stats;
  int halt; /**< 1: the caller wants only the shape of a tree that fits (the pencil renderer's
                 axial and corner rays): once the tree has overflowed no further ray is traced,
                 and shading skips what only makes radiance (rt_tracer_t.shape: spectral
                 pencils); the radiance returned is then incomplete */
} xr_exact_t;

/** A tracer over a prepared scene; tree may be NULL. */
xr_exact_t xr_exact_make(const rt_scene_t *s, const rt_plan_t *plan, rt_tree_t *tree);

/** Radiance along a primary ray (textbook Trace(r, 0)); records the sample's tree from scratch
 *  when the tracer has one. */
rt_rgb_t xr_exact_primary(xr_exact_t *ex, const rt_ray_t *ray);

/** The shade.h callbacks of the exact tracer, with ctx = the xr_exact_t. */
rt_tracer_t xr_exact_tracer(xr_exact_t *ex);

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
  /** 1: wavelength supersampling as Takagi et al. (the 1989 paper's [9]): under a plan with bins
   *  (RT_EFFECT_DISPERSION), every sample's primary ray is traced once per bin, monochromatic at
   *  the bin's centre, and the results summed with the bins' RGB weights, instead of fanning out
   *  where a white ray refracts. The image is the fan's (each ray's wavelength meets the same
   *  indices); the cost is the bins' count times the whole tree. The tree recorded for the
   *  auxiliary channels and on_sample is the middle bin's. */
  int per_wavelength;
} xr_options_t;

#define XR_OPTIONS_DEFAULT                                                                         \
  { 1, 0, 1, NULL, NULL, NULL, NULL, 0 }

/** Render the prepared scene with `plan` into img (allocated by the caller at the camera's
 *  size). Pixels are independent, so the image does not depend on the thread count.
 *  RT_EINVAL for a bad option or image size, RT_ENOTREADY for an unprepared scene, RT_ENOMEM. */
rt_status_t xr_render(const rt_scene_t *s, const rt_plan_t *plan, const xr_options_t *opt,
                      rt_image_t *img, rt_stats_t *stats);

#endif
