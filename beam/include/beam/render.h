/* render.h -- beam tracing from the eye (1987 paper, section 4.1 (3)): the image of a polygonal
 * scene made by pencils bounded by polygon edges instead of rays.
 *
 * The screen is cut into tiles; each tile is the parameter polygon of a beam from the pinhole
 * (beam/beam.h: its parameters are the tangents of the camera's image plane, so that a pixel is
 * a square of parameters). A beam is partitioned by the faces its rays meet first (hidden-
 * surface removal in parameter space: the faces mapped to the screen exactly before the first
 * face, by the generalised perspective transformation P = S A^-1 of Eq. (7) after it), and each
 * piece follows its face's reflected and refracted children to the scene's depth limit, the
 * beam tree. A piece is drawn by coverage: it is clipped to every sub-pixel cell it overlaps
 * (s x s cells a pixel), and the cell's share of it is shaded once, at the share's centroid, by
 * the renderers' shared shading (core/shade.h, with exact shadow rays), with the weights of its
 * path's faces taken at the same point. Geometric edges are therefore anti-aliased by their
 * exact area (to the model's accuracy) whatever s is; s sets how finely shading (shadows,
 * checker squares, highlights) is sampled, as the exact renderer's s x s grid does.
 *
 * Error control, which the paper left undone ("errors can be estimated by Eq. (4), and dividing
 * the pencil can assure image accuracy though this has not been implemented yet"): after its
 * first face the error of a piece's linear models (the partition's and the drawing's) over the
 * whole piece is bounded by Eq. (4) with the corrected coefficients of the Appendix, plus the
 * terms the second-order form leaves out (bm_model_bound()), in pixel intervals on the piece's
 * face (Eq. 3's tolerance, the piece's pixel footprint there), and must be at most rho; a piece
 * whose error cannot be bounded (grazing, a singular map) is traced exactly, counted. What a
 * bound on the linear map cannot say, which face the rays meet and where the children change,
 * is checked against exact tracing (Snell's law face by face along its path) at the piece's
 * vertices and edge midpoints: the exact ray must meet the piece's face within rho of its edges,
 * and its children must be the centroid's (no total internal reflection boundary inside); its
 * distance from the models' points, which the bound covers, is compared with the bound, and a
 * larger one is counted as a violation (evidence against the bound) and treated as a failure.
 * With certified, every sample cell's centre inside the piece is checked too, and its exact ray
 * must follow the piece's path to the piece's face exactly. `bound` = BT_BOUND_PROBE is the
 * check without a bound: the probes' distances within rho, which says nothing of the interior.
 * A piece that fails is divided in two and partitioned again, up to 2 x max_split divisions
 * along its path; past that, and for slivers and beams whose model fails (grazing, a focus),
 * each cell's share is traced exactly from the face on (counted).
 *
 * Curved objects are not beams' business: a scene with a sphere is refused, with the reason.
 *
 * Prefix bt_. Above beam/ (the beams) and reference/render (the exact tracer of the fallback). */
#ifndef BEAM_RENDER_H
#define BEAM_RENDER_H

#include <stdint.h>

#include "core/image.h"
#include "core/plan.h"
#include "core/scene.h"

/** What decides whether a piece's linear model is accurate enough. */
typedef enum {
  BT_BOUND_CORRECTED = 0, /**< the error bound of Eqs. (4)-(6) with the corrected coefficients
                               (bm_model_bound()) over the whole piece, <= rho */
  BT_BOUND_PRINTED = 1,   /**< the same with the printed coefficients of A-1 (docs/errata.md) */
  BT_BOUND_PROBE = 2      /**< no bound: the exact rays at the piece's vertices and edge
                               midpoints, within rho (does not cover the interior) */
} bt_bound_t;

typedef struct {
  double rho;     /**< tolerance ratio of Eq. (3): model against exact, pixel intervals; > 0 */
  int max_split;  /**< a piece is divided at most 2 x max_split times along its path, 0..30 */
  int certified;  /**< 1: also check every sample cell's centre in a piece */
  int bound;      /**< a bt_bound_t */
  int tile;       /**< pixels per side of a root beam, 1..256 */
  int exact_side; /**< e: what is traced exactly is sampled on an e x e grid a cell, 1..16 */
  int spp_side;   /**< s: s x s shading cells per pixel, 1..RT_MAX_SPP_SIDE */
  int threads;    /**< OpenMP threads; 0 = the OpenMP default */
  int aux;        /**< 1: fill the auxiliary channels from exact centre-ray trees */
  int measure;    /**< 1: measure the Fig. 10 error of every sample (bt_stats_t, bt_extra_t) */
  /** Called after each finished tile with (done, total), serialised; may be NULL. */
  void (*progress)(void *ctx, int done, int total);
  void *progress_ctx;
  /** --wavelengths (renderers/src/beam.c), read where the plan asks for dispersion: 0 dispersion
   *  image solids; 1 the glass at n_d (the plan's dispersion is then off); 2 the light refracted
   *  into dispersive glass traced from each cell share's point by spectral pencils. */
  int wavelengths;
  /** Bytes the dispersion image solids may take (their records, entries and cell shares, and
   *  the copies made when the threads' are merged); 0: no limit. Past it the render stops with
   *  RT_ENOMEM (bt_stats_t.solid_over_budget). */
  size_t memory_budget;
} bt_options_t;

#define BT_OPTIONS_DEFAULT                                                                         \
  { 0.5, 8, 0, BT_BOUND_CORRECTED, 16, 4, 1, 0, 1, 0, NULL, NULL, 0, 0 }

/** What the dispersion image solids take per sample of the image, an estimate for
 *  rn_memory_estimate(): what bt_options_t.memory_budget counts of them on the prism at 1024 x
 *  1024, 4 spp, is 230 bytes a sample (docs/journal/2026-12-05-sphere-band.md). Not a bound:
 *  their records grow more slowly than the image (370 bytes a sample at 256 x 256, 740 at 96 x
 *  96), and a scene whose glass is seen through glass holds more entries a sample. Where the
 *  estimate falls short, the budget (all the memory left) is what holds. */
#define BT_SOLID_SAMPLE_BYTES 256
/** ... and under --wavelengths pencils, which records no solids but keeps the points (98 bytes a
 *  sample of resident memory on the prism at 1024 x 1024). */
#define BT_SOLID_POINT_BYTES 128

/** Bins of the Fig. 10 error histogram (as the renderer table's). */
#define BT_HIST_BINS 256
#define BT_HIST_STEP 0.01

/** What a beam render did (summed over threads). */
typedef struct {
  uint64_t beams;       /**< beams partitioned (roots, children and divided parts) */
  uint64_t pieces;      /**< pieces drawn by their linear model */
  uint64_t divided;     /**< pieces divided because the model failed the checks */
  uint64_t crowded;     /**< beams divided before their partition: too many faces */
  uint64_t dense;       /**< beams traced exactly: fewer than 4 cells a face or a piece */
  uint64_t exact;       /**< pieces and beams traced exactly per cell (past max_split, or the
                             model or the partition failed) */
  uint64_t slivers;     /**< pieces too small to model (a quarter of a cell), traced exactly */
  uint64_t fragments;   /**< cell shares shaded from a model */
  uint64_t exact_cells; /**< cell shares traced exactly */
  uint64_t checks;      /**< exact rays traced to check models */
  double max_error;     /**< the largest checked error of an accepted piece, pixel intervals */
  /* the bound (bt_bound_t other than BT_BOUND_PROBE) */
  uint64_t bounded;    /**< pieces whose models' error was bounded (bm_model_bound()) */
  uint64_t unbounded;  /**< pieces whose error could not be bounded (grazing, a singular map, too
                            wide a spread): traced exactly */
  uint64_t violations; /**< pieces where an exact check ray strayed further than the bound said:
                            divided as a failure, and counted as evidence against the bound */
  double max_bound;    /**< the largest bound of an accepted piece, pixel intervals */
  double max_ratio;    /**< the largest checked error over its piece's bound (<= 1 while the
                            bound holds) */
  rt_stats_t rays;     /**< rays of the exact tracer: shadow rays, exact shares, aux trees */
  /* The Fig. 10 measure (options.measure), one sample at each cell's centre: the error of every
   * point a piece's model put on a measured surface (rt_object_measured()) against the exact
   * tracer's point of the same path and primitive, |J+ e| in pixel intervals of the piece's
   * footprint; a point without a counterpart in the exact tree, or an exact point on a measured
   * surface that no piece accounted for, is an infinite error (a mismatch). Points of shares
   * traced exactly have none. The sample's error is the largest of its points'. */
  uint64_t measured;      /**< samples measured */
  uint64_t with_points;   /**< ... with a model's point on a measured surface */
  uint64_t within;        /**< ... whose error is <= rho */
  uint64_t within_t;      /**< ... within rho on the transmission-first path */
  uint64_t within_strict; /**< ... within rho measured as |e| / the smallest pixel interval */
  uint64_t mismatches;    /**< ... with an infinite error */
  uint64_t samples_exact; /**< ... whose centre lies in a share traced exactly from the eye */
  double fig10_max, fig10_max_t, fig10_max_strict; /**< the largest finite errors */
  uint64_t hist[BT_HIST_BINS]; /**< errors in bins of BT_HIST_STEP, the last one everything
                                    above (mismatches included) */
  /* Dispersion image solids (a plan with RT_EFFECT_DISPERSION; render.c, docs/beam.md) */
  uint64_t solids;        /**< white refractions into dispersive glass drawn as solids */
  uint64_t solid_records; /**< pieces and exact regions of the subtrees drawn by solids */
  uint64_t solid_fine;    /**< of the white refractions, those traced instead: an entry of the
                               same path and face had a subtree of more pieces than points (or
                               ran out of memory) */
  uint64_t solid_failed;  /**< of solid_records, pieces whose solid failed its checks */
  uint64_t solid_wexact;  /**< of solid_records, pieces whose weights are traced at each point */
  uint64_t solid_dark;    /**< of solid_records' children leaving the glass, those dark over the
                               piece's box (not visited at its points) */
  uint64_t solid_skipped; /**< of solid_fine, entries that recorded nothing: their group was known
                               too fine when they were met (this count, and with it the beams,
                               pieces and rays counted, depend on the order the threads meet the
                               entries; the image does not) */
  uint64_t solid_over_budget; /**< 1 when the solids ran past bt_options_t.memory_budget (the
                                   render then fails with RT_ENOMEM) */
  uint64_t solid_points;      /**< cell shares drawn from the solids' wavelength intervals */
  uint64_t solid_exact;       /**< cell shares traced exactly instead (spectral pencils) */
  uint64_t solid_traced;      /**< spectral pencils for the wavelengths a share's solids leave */
} bt_stats_t;

/** Per-sample and per-pixel outputs of a measured render; either may be NULL. */
typedef struct {
  float *sample_error; /**< width * height * s^2, pixel-major: sample (a, b) of pixel (i, j) at
                            (j * width + i) * s^2 + b * s + a */
  float *error;        /**< width * height: each pixel's largest sample error */
} bt_extra_t;

/** Render the prepared scene with plan into img (allocated at the camera's size), and with
 *  o->measure the measure into extra (may be NULL) and stats. RT_EINVAL
 *  with the reason in why[cap] for a bad option or a scene with curved objects, RT_ENOTREADY
 *  for an unprepared scene, RT_ENOMEM. stats may be NULL. The image does not depend on the
 *  thread count. */
rt_status_t bt_render(const rt_scene_t *s, const rt_plan_t *plan, const bt_options_t *o,
                      rt_image_t *img, const bt_extra_t *extra, bt_stats_t *stats, char *why,
                      size_t cap);

#endif
