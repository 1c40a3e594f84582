/* renderer.h -- the renderer table: every renderer of the project as one entry (its name, its
 * options, its render function, the image channels it adds, what it reports), so that the
 * `pencil render --method NAME` command, the benchmarks, the figure drivers and the rho sweep
 * take an entry instead of knowing each renderer.
 *
 * Adding a renderer means writing one file with its entry (renderers/src/NAME.c) and listing
 * that entry in the table (renderers/src/table.c). An entry is constant data; its functions are
 * thread-safe as far as the renderer behind them is (each render call is independent).
 *
 * The entries' options are described by rn_option_t records, so that one command-line parser
 * (cli/) and the validation drivers (which set options by name, e.g. "--rho") handle every
 * renderer alike.
 */
#ifndef RENDERERS_RENDERER_H
#define RENDERERS_RENDERER_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/image.h"
#include "core/plan.h"

/** Most extra channels an entry adds to the image. */
#define RN_MAX_CHANNELS 4
/** Most header attributes an entry adds to an image file (rn_renderer_t.describe). */
#define RN_MAX_ATTRS 9
/** Bins of the error histogram of rn_errors_t: bin k holds errors in [k, k+1) * RN_HIST_STEP
 *  pixel intervals, the last bin everything above (path mismatches count as infinite). */
#define RN_HIST_BINS 256
#define RN_HIST_STEP 0.01

/** How an entry's option is written on the command line and stored in its options struct. */
typedef enum {
  RN_OPT_FLAG = 0, /**< no value; stores flag_value in an int field */
  RN_OPT_INT,      /**< an integer in [lo, hi], stored in an int field */
  RN_OPT_DOUBLE,   /**< a finite number in [lo, hi] (or (lo, hi] when lo_open), double field */
  RN_OPT_CHOICE    /**< one of choices[] (NULL-terminated), its index stored in an int field */
} rn_opt_kind_t;

/** One option of a renderer. */
typedef struct {
  const char *name;           /**< the long option, "--rho" */
  rn_opt_kind_t kind;         /**< how it is parsed and stored */
  size_t offset;              /**< offset of its field in the entry's options struct */
  int flag_value;             /**< RN_OPT_FLAG: the value stored when given */
  double lo, hi;              /**< RN_OPT_INT, RN_OPT_DOUBLE: the allowed range */
  int lo_open;                /**< RN_OPT_DOUBLE: 1 when lo itself is excluded (> lo) */
  const char *const *choices; /**< RN_OPT_CHOICE: the accepted names, NULL-terminated */
  const char *metavar;        /**< how --help shows the value ("R"), NULL for a flag */
  const char *help;           /**< one or more lines of --help text (no trailing newline) */
} rn_option_t;

/** An option of a renderer that has an effect only when another of its options holds certain
 *  values (--spectral-tol only with --wavelengths pencil): given otherwise it is refused, naming
 *  both (rn_option_idle()). */
typedef struct {
  const char *option; /**< the dependent option, "--spectral-tol" */
  const char *on;     /**< the option it depends on, a choice or a flag: "--wavelengths" */
  unsigned values;    /**< bit k set: `option` has an effect when `on`'s int field holds k (a
                           choice's index; a flag's stored value) */
  const char *when;   /**< those values as a user writes them: "--wavelengths pencil" */
} rn_needs_t;

/** What every renderer is asked for, whatever its own options. */
typedef struct {
  int spp_side; /**< s: s x s samples per pixel, 1..RT_MAX_SPP_SIDE */
  int threads;  /**< OpenMP threads; 0 = the OpenMP default */
  int aux;      /**< 1: fill the auxiliary channels of rt_image_t (centre-ray trees) */
  int measure;  /**< 1: also measure the Fig. 10 error of every sample (needs
                     rn_renderer_t.errors; 0 for timed renders) */
  /** Called after each finished row of work with (done, total), serialised; may be NULL. */
  void (*progress)(void *ctx, int done, int total);
  void *progress_ctx;
  /* The caustic maps a render makes when its plan has RT_EFFECT_CAUSTICS (core/caustics.h); 0 is
   * each renderer's default: */
  int caustic_method; /**< 1 + lt_method_t: 0 the renderer's (exact: photons, as backward ray
                           tracing; pencil: grid-pencil) */
  int caustic_rays;   /**< rays per side of each light's grid faces; 0: RN_CAUSTIC_PHOTON_RAYS
                           for photons, RN_CAUSTIC_PENCIL_RAYS for grid-pencil */
  int caustic_cells;  /**< cells along the longer side of each map; 0: RN_CAUSTIC_CELLS */
  /** Bytes a renderer may take beyond its image, channels and threads' buffers for what it builds
   *  as it goes (rn_renderer_t.image_bytes); 0: no limit. `pencil render` gives it what the
   *  memory allowed (--max-memory, or the memory available) leaves after those. */
  size_t memory_budget;
} rn_common_t;

/** Defaults of the caustic maps: cells along a map's longer side, rays per side of a light's grid
 *  faces for photon counting (about 4.2 million photons a face) and for grid-pencil tracing (its
 *  pencils divide where the light needs it). */
#define RN_CAUSTIC_CELLS 512
#define RN_CAUSTIC_PHOTON_RAYS 2049
#define RN_CAUSTIC_PENCIL_RAYS 129

/** The defaults: 1 spp, OpenMP's threads, auxiliary channels, no measurement, no progress,
 *  each renderer's caustic maps. */
#define RN_COMMON_DEFAULT                                                                          \
  { 1, 0, 1, 0, NULL, NULL, 0, 0, 0, 0 }

/** What a render's caustic maps took (rn_output_t.caustics). */
typedef struct {
  int maps;           /**< maps made (receiver planes times lights); 0 without caustics */
  int empty;          /**< ... of which no light reached */
  const char *method; /**< "photons", "grid-pencil" or "polygons" */
  int rays, cells;    /**< rays per side, cells along the longer side */
  uint64_t traced;    /**< light rays traced */
  double seconds;     /**< wall-clock time of the maps (included in the render's) */
  double outside;     /**< share of the mapped light that fell beside the maps */
  char why[200];      /**< when the maps could not be made, the reason */
} rn_caustic_stats_t;

/** Where a render goes; everything caller-owned. */
typedef struct {
  rt_image_t *image;                /**< allocated at the camera's size (required) */
  float *channels[RN_MAX_CHANNELS]; /**< the entry's extra channels, width * height floats
                                         each, in the order of rn_renderer_t.channels; any may
                                         be NULL (not written) */
  float *sample_error; /**< measure only: the Fig. 10 error of every sample (width * height *
                            spp floats, pixel-major), or NULL */
  void *stats;         /**< rn_renderer_t.stats_size bytes for the entry's counters, or NULL */
  rn_caustic_stats_t *caustics; /**< what the caustic maps took, or NULL */
  char why[200]; /**< when render() fails, the reason if the renderer has one (else empty):
                      "object 'ball' is a sphere: ..." */
} rn_output_t;

/** The Fig. 10 error counters of a measured render, whichever renderer made it: samples whose
 *  points on surfaces with a diffuse term lie within rho of the exact tracer's (pixel
 *  intervals), and how samples were traced. */
typedef struct {
  uint64_t measured;           /**< samples measured (all samples of the image) */
  uint64_t with_points;        /**< ... with at least one point on a measured surface (0: the
                                    measure compared nothing) */
  uint64_t within;             /**< ... whose error is <= rho */
  uint64_t mismatches;         /**< ... whose exact ray tree lacks a path the renderer used */
  double max_error;            /**< largest finite error */
  uint64_t within_t;           /**< samples within rho on the transmission-first path */
  double max_error_t;          /**< largest error on that path */
  uint64_t within_strict;      /**< samples within rho measured as |e| / smallest pixel interval */
  double max_error_strict;     /**< largest error by that measure */
  uint64_t within_axial;       /**< samples within rho in the axial footprint's pixel intervals
                                    alone (pencil: the measure before the local footprint; beam:
                                    the same as within) */
  double max_error_axial;      /**< largest error by that measure */
  uint64_t local_unknown;      /**< measured points without a local footprint */
  uint64_t hist[RN_HIST_BINS]; /**< error histogram (RN_HIST_STEP bins) */
  uint64_t samples_exact;      /**< samples traced exactly */
  uint64_t samples_matrix;     /**< samples traced by system matrices */
  uint64_t samples_interpolated; /**< samples by ray interpolation */
} rn_errors_t;

/** A header attribute of an image file: "pencil:rho" = "0.5". */
typedef struct {
  const char *key; /**< static string */
  char value[64];  /**< formatted value */
} rn_attr_t;

/** What a finished render reports on its closing lines (rn_renderer_t.report). */
typedef struct {
  const rt_scene_t *scene; /**< the scene rendered */
  int spp;                 /**< samples per pixel */
  double seconds;          /**< wall-clock time of the render */
  const char *out;         /**< the output file */
  const rn_common_t *common;
  const void *options; /**< the entry's options */
  const void *stats;   /**< the entry's counters */
} rn_report_t;

/** One renderer. */
typedef struct {
  const char *name;           /**< --method NAME */
  const char *summary;        /**< one line for `pencil render --help` */
  const char *description;    /**< a paragraph for `pencil render --method NAME --help` */
  size_t options_size;        /**< size of its options struct */
  const void *defaults;       /**< an options struct holding the defaults */
  const rn_option_t *options; /**< its options */
  int noptions;
  const char *const *channels; /**< names of the extra EXR channels it adds (may be NULL) */
  int nchannels;               /**< 0 .. RN_MAX_CHANNELS */
  int error_channel;           /**< index of the channel holding each pixel's largest Fig. 10 error
                                    (measured renders), or -1 */
  int method_channel;          /**< index of the channel holding how each pixel was traced (0 exact,
                                    1 system matrices, 2 interpolated), or -1 */
  size_t stats_size;           /**< size of its counters */
  /** Render the prepared scene with plan into out (see rn_output_t). RT_EINVAL for a bad
   *  option or image, RT_ENOTREADY for an unprepared scene, RT_ENOMEM. */
  rt_status_t (*render)(const rt_scene_t *s, const rt_plan_t *plan, const rn_common_t *common,
                        const void *options, rn_output_t *out);
  /** Header attributes describing the options (beside scene, method and spp, which the caller
   *  writes); returns how many were written to attrs (at most RN_MAX_ATTRS). */
  int (*describe)(const void *options, rn_attr_t *attrs);
  /** Print the closing lines of a render to f. */
  void (*report)(FILE *f, const rn_report_t *r);
  /** The Fig. 10 counters from a measured render's stats; NULL when the renderer is exact (its
   *  error is zero by construction and nothing is measured). */
  void (*errors)(const void *stats, rn_errors_t *out);
  /** The options' tolerance ratio rho (Eq. 3) against which errors are counted; NULL when the
   *  renderer has none. */
  double (*rho)(const void *options);
  /** Bytes of the working buffers the renderer allocates for each thread before it starts
   *  (ray trees, per-domain state), for plan, common and its options; NULL when it has none. */
  size_t (*thread_bytes)(const rt_plan_t *plan, const rn_common_t *common, const void *options);
  /** Bytes, estimated, of what the renderer builds for the whole image as it goes (the beam
   *  renderer's dispersion image solids) at width x height, for plan, common and its options;
   *  NULL when it builds nothing of the kind. Past rn_common_t.memory_budget it fails with
   *  RT_ENOMEM and says why, rather than take more. */
  size_t (*image_bytes)(const rt_plan_t *plan, const rn_common_t *common, const void *options,
                        int width, int height);
  /** 1 when the renderer draws RT_EFFECT_DISPERSION (the spectral fan of core/src/shade.c); a plan
   *  made by rn_plan_make() for another renderer has it off, with the reason. */
  int dispersion;
  /** Adjust the plan to the options (the exact renderer's --wavelengths and --bins); may be
   *  NULL. Called by rn_plan_make(). */
  void (*adapt_plan)(rt_plan_t *plan, const rt_scene_t *s, const void *options);
  const rn_needs_t *needs; /**< options with an effect only with others' values (may be NULL) */
  int nneeds;
} rn_renderer_t;

/** The table, in the order `pencil render --help` lists it; rn_count() entries. */
const rn_renderer_t *rn_entry(int k);
int rn_count(void);
/** The entry called `name`, or NULL. */
const rn_renderer_t *rn_find(const char *name);
/** The exact renderer's entry (the reference every other renderer is timed and measured
 *  against). */
const rn_renderer_t *rn_exact(void);

/** The effects plan of scene s for renderer r with its options (NULL: its defaults) at spp samples
 *  per pixel: rt_plan_make(), with the effects r does not draw turned off and the reason saying so
 *  (dispersion: rendered at n_d), adjusted to the options (rn_renderer_t.adapt_plan). Renderers
 *  refuse a plan asking for an effect they do not draw (RT_EINVAL, out->why). */
rt_plan_t rn_plan_make(const rn_renderer_t *r, const rt_scene_t *s, int spp, const void *options);

/** The option of `r` called `name` ("--rho"), or NULL. */
const rn_option_t *rn_option_find(const rn_renderer_t *r, const char *name);

/** Parse `text` for option o and store it in the options struct `options`. Returns 1, or 0
 *  with "OPTION: expected ..., got 'TEXT'" in err[cap]. A flag takes text == NULL. */
int rn_option_set(const rn_option_t *o, void *options, const char *text, char *err, size_t cap);

/** rn_option_find() and rn_option_set() in one: 0 also when `r` has no such option (err says
 *  so). For drivers that set, e.g., "--rho" on whichever renderer they were given. */
int rn_set(const rn_renderer_t *r, void *options, const char *name, const char *text, char *err,
           size_t cap);

/** Parse a decimal number as users write one, the one rule of every number the pencil command
 *  takes: an optional '-', digits with an optional point, an optional exponent (1e-3, 2E+5), and
 *  nothing else (no spaces, no leading '+', no hexadecimal, no "inf" or "nan"). Values too small
 *  for a normal double are kept (subnormal or zero); values too large for a double are refused.
 *  Returns 1 with *out set, 0 for text that is not such a number, -1 for a number beyond the
 *  range of a double. */
int rn_parse_double(const char *text, double *out);
/** Parse a decimal integer by the same rule: an optional '-' and digits only. Returns 1 with
 *  *out set, 0 for text that is not one, -1 beyond the range of a long. */
int rn_parse_long(const char *text, long *out);

/** Whether option `name` of r, given, has no effect with the other options as set in `options`
 *  (rn_renderer_t.needs): 1 with "--spectral-tol has no effect with --wavelengths fan (only with
 *  --wavelengths pencil)" in err[cap], else 0 (also for an option without a dependency). */
int rn_option_idle(const rn_renderer_t *r, const void *options, const char *name, char *err,
                   size_t cap);

/** Find the first pixel of img whose R, G or B is NaN or infinite (row-major from the top):
 *  1 with its column, row and channel (0 R, 1 G, 2 B), or 0 when every value is finite. A
 *  renderer's output is checked before it is written, so that no non-finite value reaches a
 *  file unannounced. */
int rn_image_nonfinite(const rt_image_t *img, int *x, int *y, int *channel);

/** Bytes a render of width x height pixels by r needs, allocated before it starts: the image
 *  and its auxiliary channels, r's extra channels, the per-sample errors of a measured render
 *  (when with_sample_errors), the 8-bit preview, and r's working buffers for each of the
 *  threads common->threads resolves to (rn_renderer_t.thread_bytes). The scene itself and
 *  its BVH, already loaded, are not counted. Saturates at SIZE_MAX. */
size_t rn_memory_estimate(const rn_renderer_t *r, const rt_plan_t *plan, const rn_common_t *common,
                          const void *options, int width, int height, int with_sample_errors);

/** The memory renderer r's caustic maps of scene s need at their peak (lt_caustic_bytes() with
 *  the common options or r's defaults: photons for the exact renderer, grid-pencils for the
 *  others); 0 when plan has no caustics. Not part of rn_memory_estimate(), which knows no scene. */
size_t rn_caustic_bytes(const rn_renderer_t *r, const rt_scene_t *s, const rt_plan_t *plan,
                        const rn_common_t *c);

/** Copy the entry's defaults into options (options_size bytes). */
void rn_defaults(const rn_renderer_t *r, void *options);

/** Write the --help lines of r's options to f, two-column, with `indent` spaces. */
void rn_print_options(FILE *f, const rn_renderer_t *r, int indent);

/** Allocate the extra channels of r in out->channels (width * height floats each, zero until a
 *  render writes them, the rest NULL). RT_OK or RT_ENOMEM (then none is allocated). */
rt_status_t rn_channels_alloc(const rn_renderer_t *r, int width, int height, rn_output_t *out);
/** Free what rn_channels_alloc() allocated and NULL the pointers. */
void rn_channels_free(rn_output_t *out);

#endif
