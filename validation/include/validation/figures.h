/* figures.h -- the experiments of the paper's section 5 with the pencil renderer (issue 5):
 * Fig. 8 (the pencil-traced image), Fig. 9 (CPU time of pencil over exact tracing against
 * samples per pixel), Fig. 10 (distribution of the checkerboard error), and the rho sweep (what
 * accuracy costs in time, for both bound variants and the certified mode).
 *
 * Times are process CPU seconds (CLOCK_PROCESS_CPUTIME_ID, the paper's "CPU time"), wall seconds
 * beside them; each is the median of `runs` renders, the exact and pencil renders interleaved in
 * the same process with the same build and thread count. Timed renders write no auxiliary
 * channels and measure nothing; errors come from separate measured renders. Everything is written
 * under one output directory (docs/pencil.md lists the files).
 */
#ifndef VALIDATION_FIGURES_H
#define VALIDATION_FIGURES_H

#include <stdio.h>

#include "renderers/renderer.h"
#include "validation/status.h"

#define VAL_MAX_SPP 12
#define VAL_MAX_RHO 16

/** Median times of one configuration. */
typedef struct {
  int spp;
  double exact_s, pencil_s;       /**< median process CPU seconds */
  double exact_wall, pencil_wall; /**< median wall seconds */
  double ratio;                   /**< pencil_s / exact_s */
  uint64_t exact_rays;            /**< rays of one exact render (rt_stats_total(): primary,
                                       reflected, refracted, shadow; every run traces the same) */
  double peer_s, peer_wall;       /**< val_time_peer(): the peer's median seconds (its own
                                       clock) and median wall seconds; NaN without a peer */
  uint64_t peer_rays;             /**< the peer's own count of the rays of one render, 0
                                       without a peer */
} val_timing_t;

/** A renderer to time or measure: an entry of the renderer table and its options (an options
 *  struct of the entry's, e.g. made by rn_defaults() and rn_set()). */
typedef struct {
  const rn_renderer_t *r; /**< the entry */
  const void *options;    /**< its options (r->options_size bytes) */
} val_method_t;

/** Time `runs` renders of scene s by the exact renderer and by m at spp samples per pixel
 *  (interleaved, no auxiliary channels, nothing measured) and keep the medians: exact_s is the
 *  exact renderer's, pencil_s m's. Returns 0, or -1 when a render failed (message on
 *  stderr). */
int val_time_pair(const rt_scene_t *s, val_method_t m, int spp, int threads, int runs,
                  val_timing_t *out);

/** A renderer outside this process timed beside the pair (issue 26's peer, POV-Ray): run()
 *  renders the scene at spp samples per pixel and gives the CPU seconds by its own clock in
 *  *seconds and the rays it counted in *rays; 0, or -1 after a message on stderr. */
typedef struct {
  int (*run)(void *ctx, int spp, double *seconds, uint64_t *rays);
  void *ctx; /**< run()'s */
} val_peer_t;

/** val_time_pair() with the peer's render after the exact and m's in each run (so that the three
 *  are interleaved), its medians in out->peer_s and out->peer_wall, the last run's rays in
 *  out->peer_rays. peer NULL: val_time_pair(). Returns 0; 1 when the peer failed (its run() said
 *  why): the pair is timed without it and out->peer_s, peer_wall are NaN; -1 when a render of the
 *  pair failed. */
int val_time_peer(const rt_scene_t *s, val_method_t m, int spp, int threads, int runs,
                  const val_peer_t *peer, val_timing_t *out);

/** Objects covering fewer pixels than this are not judged by val_errors_t.image_bias. */
#define VAL_BIAS_PIXELS 100

/** Error statistics of one measured pencil render (Fig. 10). */
typedef struct {
  double rho;
  uint64_t samples;             /**< every sample of the image */
  uint64_t samples_with_points; /**< ... with a pencil-traced point on a measured surface (the
                                     checkerboard in Fig. 8; rt_object_measured): 0 means the
                                     measure compared nothing and fraction_within says nothing */
  double fraction_within;       /**< samples with error <= rho (image area) */
  double p99;                   /**< 99th percentile of the per-sample error (pixels) */
  double max_error;             /**< largest finite error (pixels) */
  uint64_t mismatches;          /**< samples whose exact tree lacks a path the pencil used */
  double fraction_within_strict, max_error_strict; /**< |e| / sigma_min instead */
  double fraction_within_t, max_error_t;           /**< transmission-first path only */
  double fraction_within_axial, max_error_axial;   /**< in the axial footprint's pixel intervals
                                                        alone (before the local footprint) */
  double image_rms;      /**< RMS of the RGB difference from the exact image */
  double image_max;      /**< largest per-pixel |RGB difference| */
  double image_bias;     /**< largest |mean RGB difference| over the pixels whose centre ray (in the
                              exact image) meets one object, among objects with at least
                              VAL_BIAS_PIXELS such pixels: a systematic error the checkerboard's
                              flips at rho = 1/2 (which go both ways) do not average out */
  int image_bias_object; /**< that object's index, -1 the background (none: -2) */
  rn_errors_t counts;    /**< the renderer's Fig. 10 counters (histogram, samples by method) */
} val_errors_t;

/** The largest |mean RGB difference| of image P from the exact image X (with its id channel)
 *  over the pixels of one object of s, among objects (-1: the background) with at least
 *  VAL_BIAS_PIXELS pixels; *object gets that object, -2 when none has that many. 0, or -1 when
 *  out of memory (then *bias = 0, *object = -2). */
int val_image_bias(const rt_scene_t *s, const rt_image_t *P, const rt_image_t *X, double *bias,
                   int *object);

/** Render s by m with measurement (m.r->errors must not be NULL) and compare the image with an
 *  exact render. sample_error (w * h * spp floats), the images and `channels` may be NULL;
 *  when not, they receive the per-sample errors, m's image, m's extra channels (an array of
 *  m.r->nchannels caller-allocated planes) and the exact image. threads: of both renders. */
int val_measure(const rt_scene_t *s, val_method_t m, int spp, int threads, val_errors_t *out,
                float *sample_error, rt_image_t *img, float *const *channels,
                rt_image_t *exact_img);

typedef struct {
  const rn_renderer_t *method; /**< the renderer compared with exact tracing (default pencil);
                                    the drivers set its --rho, --certified, --bounds and
                                    --brightness-tol by name */
  const char *out_dir;         /**< output directory (created) */
  const char *scene;           /**< scene file, or NULL for the built-in Fig. 8 scene */
  int quick;                   /**< small image and fewer points (tests) */
  int threads;                 /**< threads for every render (default 1) */
  int runs;                    /**< timed renders per configuration, >= 3 */
  int width, height;           /**< 0: the scene's (quick: 96 x 96) */
  int spp[VAL_MAX_SPP];        /**< Fig. 9 sample counts, increasing; the targets are taken at 49
                                when it is one of them, else at the largest */
  int nspp;
  double rho[VAL_MAX_RHO]; /**< sweep */
  int nrho;
  int sweep_spp;      /**< samples per pixel of the sweep */
  int sweep;          /**< 1: run the sweep too */
  const char *plot;   /**< plotting script (run as /usr/bin/python3 PLOT DIR) or NULL */
  FILE *log;          /**< progress and the comparison table (stdout) */
  int shard, nshards; /**< nshards > 0: run only work item j with j mod nshards = shard - 1 and
                           record its results in DIR/shards/ (the outputs come from --merge) */
  unsigned only;      /**< 0: every figure; else a mask of VAL_ONLY_* (`--only`): run those
                           figures alone and write their outputs */
  int merge;          /**< 1: run nothing; merge DIR/shards/ into the outputs of one run (the
                           configuration comes from the shard files) */
  int peer;           /**< 1: time POV-Ray 3.7 beside Fig. 9 (`--peer povray`, issue 26;
                           validation/povray.h): fig9.csv and summary.json get its columns; left
                           out with a note when povray is not installed or the scene cannot be
                           exported */
  void (*progress)(void *ctx, int done, int total); /**< or NULL: called with the work items done
                                                       of this run's total before each item and
                                                       once at the end (done == total) */
  void *progress_ctx;
} val_figures_opts_t;

/** Figures that `--only` selects (val_figures_opts_t.only). */
enum {
  VAL_ONLY_FIG8 = 1u,    /**< Figs. 8 and 10: the measured render, images, error map, histogram */
  VAL_ONLY_FIG9 = 2u,    /**< Fig. 9: the time ratios */
  VAL_ONLY_TARGETS = 4u, /**< the 49-spp targets and the no-accuracy ratios */
  VAL_ONLY_SWEEP = 8u    /**< the rho sweep */
};

/** Defaults for `pencil figures`: Fig. 9 at 1, 4, ..., 49 spp, 3 runs, 1 thread, the sweep at
 *  rho 0.05 ... 2 with 9 spp. */
void val_figures_defaults(val_figures_opts_t *o);

/** Run Figs. 8-10 (and the sweep) and write DIR/summary.json, CSV files, EXR/PNG images and
 *  plots, and print the comparison with the paper (which says when a target was missed).
 *  Returns 0, VAL_ESCENE or VAL_EOUTPUT (nothing written), or -1 on another error (message on
 *  stderr naming the file). */
int val_figures(const val_figures_opts_t *o);

/** The rho sweep alone: DIR/sweep.csv (+ sweep.json) and its plot. 0, VAL_ESCENE or
 *  VAL_EOUTPUT (nothing written), or -1 on an error. */
int val_sweep(const val_figures_opts_t *o);

#endif
