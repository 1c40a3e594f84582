/* pencil.h -- the pencil renderer: ray tracing with a system matrix and ray interpolation
 * (Shinya, Takahashi, Naito 1987, section 4.1 (1) and (2)), measured against exact tracing as in
 * section 5 (Figs. 8-10).
 *
 * The screen is cut into initial domains of N x N pixels (step 1). Each domain's axial ray (its
 * centre) is traced exactly with its ray tree, and every node of that tree gets the system matrix
 * of its path from the eye (step 2, pencil/path.h). The trees of the domain's corners and the
 * projected bounding spheres of the objects decide whether the domain is smooth (step 3); the
 * tolerance of Eq. (3) and the spread limit of Eqs. (4)-(6) decide between matrices for the whole
 * domain, exact tracing, and subdivision (steps 4a-4c). Samples in accepted domains are traced by
 * their matrices, or interpolated (4.1 (2)) from matrix-traced samples at the pixel corners when
 * the e_int estimate allows; shading is the reference renderer's shade.h, so the two renderers
 * differ only in how rays find surfaces. docs/pencil.md describes every choice.
 *
 * The image is an rt_image_t (same channels as the reference renderer) plus the per-pixel
 * channels of pt_extra_t. The scene must be prepared; nothing is allocated per ray.
 */
#ifndef PENCIL_PENCIL_H
#define PENCIL_PENCIL_H

#include <stddef.h>
#include <stdint.h>

#include "render/render.h"

/** Where the constant C of the error function e_x (Eq. 4) comes from. */
typedef enum {
  /** Appendix coefficients as corrected by the project (libparaxial bounds, the default). */
  PT_BOUND_CORRECTED = 0,
  /** Appendix coefficients as printed (libparaxial bounds, PX_VARIANT_PRINTED). */
  PT_BOUND_PRINTED = 1,
  /** Not a bound: the worst second-order error of the path measured by exact tracing of eight
   *  rays on the domain's spread circle (ex_map), scaled to C = e / xi^2. For comparison. */
  PT_BOUND_PROBE = 2
} pt_bound_t;

/** Parse "corrected" / "printed" / "probe"; returns 0 for an unknown name. */
int pt_bound_parse(const char *name, pt_bound_t *out);
const char *pt_bound_name(pt_bound_t b);

/** How a sample (or, in the method channel, most samples of a pixel) was traced. */
typedef enum {
  PT_METHOD_EXACT = 0,  /**< the exact tracer (edges, step 4b, failed checks) */
  PT_METHOD_MATRIX = 1, /**< system matrices of the domain's paths (step 4a) */
  PT_METHOD_INTERP = 2  /**< ray interpolation from matrix-traced pixel corners (4.1 (2)) */
} pt_method_t;

/** What rho (Eq. 3) bounds on each node of a domain's tree (issue 26's image-space tolerance). */
typedef enum {
  PT_TOL_GEOMETRIC = 0, /**< the paper's: rho pixel intervals on every surface (default) */
  PT_TOL_IMAGE = 1      /**< rho / W pixel intervals on a node whose light reaches the pixel
                             with weight W (the largest channel of the product of the reflection
                             and transmission coefficients from the eye, as the domain's axial ray
                             has it), at most rho / weight_floor: a node's geometric error counts
                             as much as the share of the pixel it makes */
} pt_tolerance_t;

/** Default weight floor of PT_TOL_IMAGE: no node's tolerance grows past 64 rho. */
#define PT_WEIGHT_FLOOR (1.0 / 64.0)

/** Default brightness tolerance of ray interpolation: a quarter of an 8-bit display step. */
#define PT_BRIGHTNESS_TOL (1.0 / 1024.0)

typedef struct {
  int spp_side; /**< s: s x s samples per pixel, 1..RT_MAX_SPP_SIDE */
  int threads;  /**< OpenMP threads; 0 = the OpenMP default */
  int domain;   /**< initial domain size N in pixels, 1..32 (paper: 5) */
  double rho;   /**< tolerance ratio of Eq. (3), > 0 (paper: 1/2) */
  pt_bound_t bound;
  int certified;         /**< 1: also require an a-posteriori exact check of every path at the
                              domain's corners and edge midpoints to agree within tau */
  int interp;            /**< 1: ray interpolation (0: every sample by matrices) */
  int measure;           /**< 1: trace every sample exactly as well and measure the Fig. 10 error */
  int aux;               /**< 1: fill the auxiliary channels (pencil's own checkerboard points) */
  double brightness_tol; /**< ray interpolation: largest deviation (any colour channel) of the
                              interpolated brightness from the traced one at a lattice cell's
                              midpoints and centre, >= 0 (the paper assumes linearity) */
  int memo;              /**< ray interpolation: 1 traces a lattice point that neighbouring lattice
                              cells share once per domain and reuses it (the same point: images
                              are identical); 0 traces it for each lattice cell (for checking) */
  /** Called after each finished row of domains with (rows done, rows total), serialised. */
  void (*progress)(void *ctx, int done, int total);
  void *progress_ctx;
  /* read by the renderer table's entry when it makes the plan (renderers/src/pencil.c), not by
   * pt_render(), which draws what the plan says */
  int wavelengths; /**< 0: dispersion by spectral pencils (RT_SPECTRAL_PENCIL); 1: glass at n_d */
  double spectral_tol;      /**< rt_plan_t.spectral_tol for spectral pencils */
  pt_tolerance_t tolerance; /**< what rho bounds per node (default PT_TOL_GEOMETRIC) */
  double weight_floor;      /**< PT_TOL_IMAGE: the smallest weight a node's tolerance is scaled
                                 by, in (0, 1] (default PT_WEIGHT_FLOOR) */
  int simd; /**< 1: an interpolated sample's exact walks along the paths are carried for four
                 samples at once (AVX2 where the CPU has it: px_simd4_available()); 0: one at a
                 time. The image is the same bit for bit. */
  int wavelength_axis;  /**< read with `wavelengths` by the renderer table's entry: spectral
                             pencils linear in 0 Lambda of the scene's one dispersive glass
                             ([P89] 3.3), 1 lambda (rt_plan_spectral_pencils_axis()) */
  int spectral_lattice; /**< ray interpolation under spectral pencils: 1 lattice points trace
                             the spectral pencils of dispersive glass too, and a lattice cell
                             whose points' pencils met the same surfaces with nothing else near
                             them interpolates their light (docs/pencil.md); 0 every sample
                             traces its own */
} pt_options_t;

#define PT_OPTIONS_DEFAULT                                                                         \
  {                                                                                                \
    1, 0, 5, 0.5, PT_BOUND_CORRECTED, 0, 1, 0, 1, PT_BRIGHTNESS_TOL, 1, NULL, NULL, 0,             \
        RT_SPECTRAL_TOL, PT_TOL_GEOMETRIC, PT_WEIGHT_FLOOR, 1, 0, 1                                \
  }

/** Extra per-pixel channels, float32, caller-owned (width x height each, either may be NULL). */
typedef struct {
  float *error;  /**< largest Fig. 10 error of the pixel's samples (measure only; NaN when no
                      sample has a pencil-traced point on a measured surface, or unmeasured) */
  float *method; /**< pt_method_t used for most of the pixel's samples */
  float *rays;   /**< exact rays traced for the pixel's samples (exact pixels, exactly traced
                      subtrees, per-sample shadow rays; not the cells' axial, corner and
                      lattice rays) */
} pt_extra_t;

/** Number of bins of the error histogram; bin k holds errors in [k, k+1) * PT_HIST_STEP, the
 *  last bin everything above (including path mismatches, which count as infinite error). */
#define PT_HIST_BINS 256
#define PT_HIST_STEP 0.01

/** Counters of one render (summed over threads). */
typedef struct {
  uint64_t domains;          /**< domains and sub-domains examined */
  uint64_t domains_edge;     /**< ... found to contain an edge (trees differ, or the guard) */
  uint64_t domains_guard;    /**< ... of which only the small-object guard fired */
  uint64_t domains_accepted; /**< ... traced with matrices (step 4a, possibly with some paths
                                traced exactly: 4b per path) */
  uint64_t domains_split;    /**< ... subdivided for the spread limit (step 4c) */
  uint64_t domains_deep;     /**< ... traced exactly as a whole because the axial or a corner
                                  ray tree has more nodes than a domain's paths may have
                                  (deep reflections: see docs/pencil.md, "Deep trees") */
  uint64_t domains_small;    /**< ... traced exactly because they have fewer samples than an
                                  axial ray and its corners could save (1 spp, at edges) */
  uint64_t paths_exact;      /**< paths of accepted or split cells over their spread limit or
                                  failing the certified check (traced exactly, or split) */
  uint64_t paths_guard;      /**< paths of examined cells traced exactly per sample because a
                                  bounded object came near their segment (small-object guard) */
  uint64_t lights_guard;     /**< node-light pairs of examined cells whose direct term is shaded
                                  per sample because a bounded object may shadow part of the cell */
  uint64_t domains_partial;  /**< accepted cells whose corner trees differ below the primary ray:
                                those subtrees (or shadow rays) are traced exactly per sample */
  uint64_t exact_traces;     /**< exact primary traces for axial and corner rays */
  uint64_t samples[3];       /**< samples by pt_method_t */
  uint64_t fallbacks;    /**< samples that left their cell's paths (an unforeseen exact trace) */
  uint64_t partial;      /**< samples with a subtree traced exactly where the corners differ */
  uint64_t lerp_samples; /**< interpolated samples whose brightness was interpolated too */
  uint64_t matrix_samples[4];    /**< samples of accepted cells traced by matrices because: 0 the
                                     cell has too few samples to interpolate, or interpolation is
                                     off, 1 a lattice point left the cell's paths, 2 the lattice
                                     points reached different nodes, 3 the interpolation error plus
                                     the matrix error exceeds rho, or the brightness is not linear,
                                     on the smallest lattice cell */
  uint64_t lattice_points;       /**< points traced through the paths for ray interpolation */
  uint64_t lattice_reused;       /**< lattice points a cell needed again (a quad's edge midpoint is
                                      its neighbour's): taken from the cell's memo, not traced */
  uint64_t biquad_lattice_cells; /**< lattice cells where some node's hits were interpolated
                              biquadratically (bilinear was not accurate enough) */
  uint64_t
      faint_lattice_cells;          /**< lattice cells where some node's shading was interpolated
                                 across a shadow edge, its whole light term being within a
                                 share of the brightness tolerance (interp_error.c, counted in interp.c) */
  uint64_t highlight_lattice_cells; /**< lattice cells where the highlight guard shaded some
                                         node per sample: a Phong lobe narrower than the grid's
                                         steps may peak between its points (interp_plan.c) */
  uint64_t halved_lattice_cells;    /**< certified mode: lattice cells made by halving a cell whose
                                 nodes were too curved in one direction (interp_error.c, counted in
                                 interp.c) */
  uint64_t spectral_points;         /**< lattice points that traced the spectral pencils of a
                                        dispersive node (opt->spectral_lattice) */
  uint64_t spectral_samples;        /**< samples of lattice cells that interpolated a dispersive
                                         node's spectral light from their points, not tracing it */
  uint64_t spectral_full;           /**< lattice points whose spectral record was not kept: their
                                         domain's store of events was full (PT_SPEC_EVENTS); the
                                         rest of the domain traces that node's light per sample */
  uint64_t walk_steps; /**< steps of exact walks carried for a group of up to four samples at once
                            (opt->simd): one node of the paths for the group */
  uint64_t walk_lanes; /**< the samples those steps carried (lanes per step: walk_lanes /
                            walk_steps) */
  uint64_t walk_left;  /**< lanes of those steps whose ray left the path there: it missed the
                            node's primitive, met something else first, or lacked the child
                            (the sample is then traced exactly); a sample that leaves at two
                            nodes counts twice */
  /* Fig. 10 measurement (measure only) */
  uint64_t measured;       /**< samples measured (all samples of the image) */
  uint64_t with_points;    /**< ... with at least one pencil-traced point on a measured surface
                                (rt_object_measured: the checkerboard in Fig. 8); when 0 the
                                measure has compared nothing */
  uint64_t within;         /**< ... whose error is <= rho (samples without such a point count) */
  uint64_t mismatches;     /**< ... whose exact ray tree lacks a path the pencil used */
  double max_error;        /**< largest finite error */
  double max_error_t;      /**< largest error on the transmission-first path only */
  uint64_t within_t;       /**< samples within rho on the transmission-first path */
  double max_error_strict; /**< largest finite error measured as |e| / sigma_min (the smallest
                                pixel interval over all screen directions) instead of |J+ e| */
  uint64_t within_strict;  /**< samples within rho by that measure */
  double max_error_axial;  /**< largest finite error in the axial footprint's pixel intervals
                                alone (the measure before the local footprint: measure.c) */
  uint64_t within_axial;   /**< samples within rho by that measure */
  uint64_t local_unknown;  /**< measured points without a local footprint (both sides of a
                                screen direction left the path): their axial error stands */
  uint64_t hist[PT_HIST_BINS];
  rt_stats_t rays; /**< rays traced by the exact tracer (axial, corner, edge, fallback,
                        measurement) and shadow rays, as the reference renderer counts */
} pt_stats_t;

/** Render the prepared scene `s` with `plan` by pencil tracing into img (allocated by the
 *  caller at the camera's size); `extra` may be NULL. `sample_error`, when not NULL, receives
 *  the Fig. 10 error of every sample (width * height * s * s floats, pixel-major, INFINITY for a
 *  path mismatch, 0 for exactly traced samples and samples without a measured point); it
 *  needs opt->measure. RT_EINVAL for a bad option or image, RT_ENOTREADY, RT_ENOMEM. */
rt_status_t pt_render(const rt_scene_t *s, const rt_plan_t *plan, const pt_options_t *opt,
                      rt_image_t *img, pt_extra_t *extra, float *sample_error, pt_stats_t *stats);

/** Bytes of the working buffers pt_render() allocates per thread before it starts, for a plan
 *  of `tree_nodes` ray-tree nodes (rt_plan_t.tree_nodes) and domains of `domain` pixels
 *  (pt_options_t.domain); 0 for values out of range. Bounded whatever the depth: a domain's
 *  paths hold at most 1023 nodes (deeper trees are traced exactly), and only the single rays'
 *  tree buffer, as in the exact renderer, grows with tree_nodes. */
size_t pt_thread_bytes(int tree_nodes, int domain);

#endif
