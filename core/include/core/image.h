/* image.h -- the image every renderer writes: float RGB and the auxiliary accuracy channels
 * computed from each pixel's centre-ray tree (1987 paper, section 5, Fig. 10: errors are
 * distances between checkerboard points found by two tracers, so the channels let a file be
 * judged without the renderer), and the ray counts every renderer reports. */
#ifndef CORE_IMAGE_H
#define CORE_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "core/raytree.h"
#include "core/scene.h"

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
  /** OpenEXR channel `spectral`, only where the render draws dispersion (rt_image_want_spectral(),
   *  else NULL): for the centre ray, 1 where its tree refracts at dispersive glass below the depth
   *  limit (the spectrum drawn there: by the fan, spectral pencils or image solids), else 0 */
  float *spectral;
} rt_image_t;

rt_status_t rt_image_alloc(rt_image_t *img, int width, int height);
/** Add the `spectral` plane to an allocated image (zeros); RT_ENOMEM leaves the image as it was. */
rt_status_t rt_image_want_spectral(rt_image_t *img);
void rt_image_free(rt_image_t *img);
/** Fill the auxiliary channels (Z, id, both paths' checkerboard u, v and event counts, and
 *  `spectral` when the image has it) of pixel index k from the ray tree of that pixel's centre
 *  ray. Shared by every renderer, so that the channels mean the same whichever method made the
 *  image. */
void rt_image_set_aux(rt_image_t *img, const rt_scene_t *s, size_t k, const rt_tree_t *t);
/** The `spectral` channel alone (rt_image_set_aux() sets it too), where a renderer writes the
 *  other channels from its own geometry; nothing when the image has no such plane. */
void rt_image_set_spectral(rt_image_t *img, const rt_scene_t *s, size_t k, const rt_tree_t *t);

/** Ray counts (all generations, summed over threads). */
typedef struct {
  uint64_t primary; /**< eye rays, including the extra centre rays of even s */
  uint64_t reflect;
  uint64_t refract;
  uint64_t shadow;
  /** Dispersion by spectral pencils (core/src/wpencil.c): [0] white rays drawn by them where
   *  they refract at dispersive glass, [1] the pencils they became after cuts, [2] those of [0]
   *  whose spectrum was never cut and stayed within a quarter pixel on every surface: where
   *  dispersion was not needed ([P89] 3.2.4's selective test, corrected). Not rays:
   *  rt_stats_total() leaves them out. */
  uint64_t spectral[3];
} rt_stats_t;

/** a += b, every count. */
static inline void rt_stats_add(rt_stats_t *a, const rt_stats_t *b) {
  a->primary += b->primary;
  a->reflect += b->reflect;
  a->refract += b->refract;
  a->shadow += b->shadow;
  for (int i = 0; i < 3; i++)
    a->spectral[i] += b->spectral[i];
}

static inline uint64_t rt_stats_total(const rt_stats_t *s) {
  return s->primary + s->reflect + s->refract + s->shadow;
}

/** One line on what spectral pencils did (rt_stats_t.spectral), "" when they did nothing. */
void rt_stats_spectral_line(const rt_stats_t *s, char *buf, size_t cap);

/** Threads a render with `requested` threads uses: requested when > 0, else the OpenMP
 *  default (1 without OpenMP). */
int rt_thread_count(int requested);

#endif
