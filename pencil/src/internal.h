/* internal.h -- private: the per-thread state of the pencil renderer and the functions shared by
 * its translation units (eval.c: one sample through the domain's paths; cell.c: steps 2-4 of
 * section 4.1 (1) for one domain; render.c: the screen loop). */
#ifndef PENCIL_INTERNAL_H
#define PENCIL_INTERNAL_H

#include <stdint.h>

#include "pencil/edge.h"
#include "pencil/path.h"
#include "pencil/pencil.h"

/** Where one node of one sample met its surface, as computed by the pencil, and what it
 *  contributes to the sample's radiance. */
typedef struct {
  px_vec3_t p;    /**< hit point */
  px_vec3_t d;    /**< unit direction of the arriving ray */
  rt_rgb_t w;     /**< W_k: product of the shade.h child weights from the eye to the node */
  rt_rgb_t l;     /**< W_k * direct_k (W_k * background for a miss); shading only */
  rt_rgb_t lt[2]; /**< textured nodes at lattice points: W_k * direct_k with the material of
                       the even (0) and the odd (1) checker squares */
  int32_t su, sv; /**< checker square of the hit (textured nodes), else 0 */
  uint32_t lit;  /**< lattice points: bit l, light l's shadow ray was traced here and met nothing */
  uint32_t dark; /**< ... and was fully blocked */
  uint8_t ok;    /**< 0 not reached, 1 computed by the pencil, 2 traced exactly */
  uint8_t fb;    /**< bit k: the child of rt_ray_kind_t k was traced exactly */
} pt_geom_t;

/** A node's exact geometry for one sample (exact along the known path, memoised per sample). */
typedef struct {
  px_vec3_t p, d;
  uint32_t stamp; /**< the evaluation it belongs to */
  int ok;         /**< 0: the sample's ray does not meet the node's primitive */
} pt_xgeom_t;

/* A pixel being accumulated. */
typedef struct {
  int i, j;      /**< pixel */
  rt_rgb_t sum;  /**< radiance summed over its samples */
  double pmax;   /**< largest measured error (NaN: none) */
  int n[3];      /**< samples by method */
  uint64_t rays; /**< exact rays traced for its samples */
} pixel_t;

/** The lattice points of the cell being interpolated, by their position: neighbouring lattice
 *  cells share edge midpoints, which depend only on the position and the cell's paths, so each is
 *  traced once per cell. Open addressing over `slot` (a slot is in use when its `gen` is the
 *  current one, so a new cell only bumps `now`). */
typedef struct {
  pt_geom_t *g;   /**< storage: `entries` node records, a point's nodes contiguous */
  size_t entries; /**< node records in g */
  int stride;     /**< records per point: the current cell's node count */
  double *xy;     /**< position of each stored point, 2 per point */
  double *xi2;    /**< |xi|^2 of its primary ray */
  uint8_t *ok;    /**< traced without leaving the cell's paths */
  int n, cap;     /**< points stored / room this cell (a full memo traces into the caller's
                       storage) */
  int maxpts;     /**< room in xy, xi2 and ok: cap is at most this */
  int32_t *slot;  /**< hash table, nslot entries: index of a stored point */
  uint32_t *gen;  /**< generation of each slot */
  uint32_t now;   /**< the current cell's generation */
  int nslot;      /**< a power of two, at least 2 maxpts */
} pt_lmemo_t;

/** Per-thread state; every buffer is allocated once before the screen loop. */
typedef struct {
  const rt_scene_t *s;
  const rt_plan_t *plan;
  const rt_view_t *view;
  const pt_options_t *opt;
  rt_image_t *img;
  pt_extra_t *extra;
  float *sample_error;
  const pt_bsphere_t *guard;
  int nguard;
  int cap;                  /**< ray-tree capacity (plan->tree_nodes) */
  rt_exact_t ex;            /**< the exact tracer (axial, corner, fallback and edge rays) */
  rt_tree_t tree;           /**< the current cell's axial tree */
  rt_tree_t tree2;          /**< corner and measurement trees */
  rt_tree_t sub;            /**< measure: the subtrees one sample's evaluation traced exactly,
                                 each under a root node standing for the pencil node it hangs
                                 from (PT_SUB_TREES x cap nodes; pt__measure compares their
                                 points with the exact tracer's) */
  int *sub_root, *sub_from; /**< ... each subtree's root in `sub` and its pencil node (cap) */
  int *sub_xk;              /**< ... pt__measure: the exact tree's node on that node's path (cap) */
  int nsub;
  pt_ctree_t *corner;       /**< corner tree cache of the current domain, (N+1)^2 */
  pt_cnode_t *corner_nodes; /**< their node storage (one block; entries are swapped) */
  int dom_x0, dom_y0;       /**< the current domain's top-left pixel */
  pt_node_t *node;          /**< the current cell's paths, one per tree node */
  int *map;                 /**< pt_tree_agree() scratch, 4 x cap */
  uint8_t *agree;           /**< pt_tree_agree() output, cap */
  uint32_t *light;          /**< pt_tree_agree() output, cap */
  int nnode;
  px_frame_t frame; /**< the current cell's input frame at the eye */
  double dpix;      /**< the current cell's larger pixel step |delta_i| in xi */
  int kt, kr;       /**< nodes on the transmission-first / reflection-first paths to the
                         checkerboard, or -1 */
  pt_path_scratch_t path;
  pt_geom_t *lat;       /**< the root quad's 3 x 3 lattice points x cap nodes */
  pixel_t *acc;         /**< the interpolated cell's pixels, N^2 */
  int *loc;             /**< per-pixel plan: nodes shaded per sample (cap) */
  uint8_t *locd, *loce; /**< ... with their direct term / with exactly traced children */
  int *loct;            /**< per-quad plan: textured nodes whose square changes (cap) */
  int *lsm;             /**< per-quad plan: the nodes whose brightness is interpolated (cap) */
  uint8_t *xsub;        /**< per-quad plan: verify nodes (and below) traced exactly (cap) */
  uint8_t *own;         /**< per-quad plan: nodes traced per sample by matrix or path (cap) */
  uint8_t *q2;          /**< per-quad plan: nodes whose hits are interpolated biquadratically
                             from the quad's 3 x 3 grid (cap) */
  uint8_t *faint;       /**< per-quad plan: nodes whose shading is interpolated across a shadow
                             edge, their brightness being within a bound (interp.c) (cap) */
  pt_geom_t *ref;       /**< refinement grids: PT_QUAD_LEVELS x 5 points x cap nodes */
  pt_lmemo_t memo;      /**< the current cell's lattice points by position (interp.c) */
  pt_geom_t *rec;       /**< one sample's geometry, cap nodes */
  pt_xgeom_t *xg;       /**< one sample's exact geometry along the paths, cap nodes */
  int vary_w;           /**< the weights W_k vary with the hits (a Fresnel split): a lattice
                             cell's nodes shaded per sample count the error of their interpolated
                             W_k (interp.c) */
  uint32_t stamp;       /**< evaluation counter for xg */
  pt_stats_t st;
} pt_ctx_t;

enum { PT_EV_MATRIX = 0, PT_EV_INTERP = 1 };

/** Subtrees traced exactly that one sample's measurement can hold, in whole trees (the subtrees
 *  of one sample are disjoint parts of its tree, so one tree's capacity is enough but for the
 *  root node each adds). */
#define PT_SUB_TREES 2

/** Share of rho that the certified mode's checks may use (the margin covers third-order
 *  variation between the checked points; docs/pencil.md). */
#define PT_CERTIFIED_MARGIN 0.7

/** max(a, b) without a libm call (fmax() is one; make_plan() made 2.2 million of them at 49 spp
 *  on Fig. 8), and NaN-propagating where fmax() drops a NaN: an error that is NaN stays NaN, and
 *  the tests that use it are written to reject it (!(e <= tol)). */
static inline double pt_max(double a, double b) {
  return a > b || a != a ? a : b;
}

/** Depth of the quadtree of lattice cells (halvings of the cell) at most. */
#define PT_QUAD_LEVELS 12

/** One sample's evaluation through the current cell's paths. */
typedef struct {
  pt_ctx_t *C;
  int mode;               /**< PT_EV_MATRIX or PT_EV_INTERP */
  double xi[2];           /**< MATRIX: the sample's xi in the cell frame */
  rt_ray_t primary;       /**< MATRIX: the sample's primary ray (for an exact fallback) */
  const double *w;        /**< INTERP: bilinear weights of the 4 lattice points */
  const pt_geom_t *g[4];  /**< INTERP: their geometry, indexed by node */
  pt_geom_t *rec;         /**< per-node geometry out (cap entries), or NULL */
  int shade;              /**< 0: geometry only */
  int record_shadow;      /**< 1: trace shadow rays and store them in the nodes (axial sample) */
  int lattice;            /**< 1: a lattice point: also fill pt_geom_t.lt of textured nodes;
                               subtrees leaving the paths are marked, not traced (its radiance
                               is not used) */
  int cur;                /**< node being shaded */
  uint32_t stamp;         /**< this evaluation's xg stamp */
  int fallback;           /**< set when the sample left the cell's paths (traced exactly there) */
  int vfail;              /**< set when a verify node's scene search failed (traced exactly) */
  const uint8_t *xsub;    /**< INTERP: nodes whose subtrees are traced exactly in this quad */
  const uint8_t *own;     /**< INTERP: nodes whose hits come from their matrices (or path) per
                               sample in this quad (xi and primary set), not interpolated */
  const uint8_t *q2;      /**< INTERP: nodes interpolated biquadratically (g9, w9), or NULL */
  const pt_geom_t *g9[9]; /**< INTERP with q2: the quad's 3 x 3 grid, row-major */
  double w9[9];           /**< INTERP with q2: the sample's biquadratic (Lagrange) weights */
  int record_sub;         /**< measure: subtrees traced exactly are recorded in C->sub (reset
                               by pt__eval) */
  int exact_spawn;        /**< some node has a child traced exactly per sample: such a node
                               spawns it from the sample's exact hit (primary set; the sample's
                               ray carried along the node's path), not from an interpolated or
                               matrix hit (pt__spawns_exact) */
  int spawnfail;          /**< set when such a node's exact path left the cell's paths (the
                               sample is then traced exactly) */
  int ownfail;            /**< set when such a node's per-sample ray left its path */
  int partial;            /**< set when a subtree where the corners differ was traced exactly */
} pt_eval_t;

/** pt_eval_t.exact_spawn for evaluations of the current cell with E's xsub (the quad's plan):
 *  whether some node has a child traced exactly per sample. */
int pt__spawns_exact(const pt_eval_t *E);
/** Radiance of the sample (black when shade = 0). */
rt_rgb_t pt__eval(pt_eval_t *E);

/** INTERP mode, one node of one sample: with `direct`, W * direct at node k's interpolated hit
 *  (a miss node: W * background); with `exact_children`, plus the weighted radiance of those of
 *  its children that are traced exactly (children the corners' trees disagree on). */
rt_rgb_t pt__eval_local(pt_eval_t *E, int k, rt_rgb_t w, int direct, int exact_children);

/** xi of the primary ray through continuous pixel coordinates (x, y) in the cell frame. */
void pt__xi(const pt_ctx_t *C, double x, double y, double xi[2]);

/** Steps 2-4 for the cell [x0, x1) x [y0, y1) of the current domain (recursive). */
void pt__cell(pt_ctx_t *C, int x0, int y0, int x1, int y1);

/* sample.c */
size_t pt__pixel_index(const pt_ctx_t *C, int i, int j);
float *pt__error_slot(pt_ctx_t *C, int i, int j, int a, int b);
uint64_t pt__rays_now(const pt_ctx_t *C);
/** Write the pixel's radiance (sum over its samples), method, error and exact-ray channels. */
void pt__write_pixel(pt_ctx_t *C, int i, int j, rt_rgb_t sum, pt_method_t m, double perr,
                     uint64_t rays);
/** Auxiliary channels of pixel (i, j) from an exact tree of its centre ray. */
void pt__aux_exact(pt_ctx_t *C, int i, int j);
/** Auxiliary channels from the pencil's geometry of the pixel's centre ray. */
void pt__aux_pencil(pt_ctx_t *C, int i, int j, const pt_geom_t *rec);
/** Every sample of the pixels of [x0, x1) x [y0, y1) by the exact tracer. */
void pt__exact_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1);
/** Fig. 10 bookkeeping of one sample; returns the pixel's running maximum error. */
double pt__measure_sample(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, int i, int j,
                          int a, int b, double pmax);
/** Geometry-only evaluation of E's sample into C->rec. */
void pt__geometry(pt_ctx_t *C, pt_eval_t *E);
/** Write a finished pixel. */
void pt__pixel_done(pt_ctx_t *C, pixel_t *P);
/** Step 4a's shadow transmittance once per cell: the axial ray through the cell's paths, tracing
 *  the shadow rays of the lights whose visibility agrees over the cell and storing them in the
 *  nodes (known_cb answers them for every other evaluation of the cell). */
void pt__record_shadows(pt_ctx_t *C, const rt_ray_t *axial);
/** The primary ray and xi of continuous pixel coordinates (x, y) into E. */
void pt__xi_of(const pt_ctx_t *C, pt_eval_t *E, double x, double y);
/** Sample (a, b) of pixel P through the cell's paths (MATRIX evaluation). */
void pt__matrix_sample(pt_ctx_t *C, pixel_t *P, int a, int b);
/** Auxiliary channels of pixel (i, j) from a MATRIX evaluation of its centre. */
void pt__aux_matrix(pt_ctx_t *C, int i, int j);
/** Every sample of pixel (i, j) through the cell's paths. */
void pt__matrix_pixel(pt_ctx_t *C, int i, int j);

/* interp.c */
/** Step 4a with ray interpolation for the accepted cell [x0, x1) x [y0, y1) whose axial ray (its
 *  centre's) is `axial`. */
void pt__interp_cell(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial);

/** Fig. 10 errors of one sample with pencil geometry rec (see pencil.h) and the subtrees its
 *  evaluation traced exactly (C->sub), tracing it exactly: e[0] the largest over its measured
 *  points (pt_surface_measured) in pixels (|J+ e|), e[1] the same on the transmission-first path
 *  only, e[2] the largest |e| / sigma_min (strict). Returns the number of pencil points
 *  compared. */
int pt__measure(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, double e[3]);

/** Record a finished sample's errors in the statistics (and e[0] in the caller's buffer). */
void pt__account(pt_ctx_t *C, const double e[3], int has_points, float *slot);

#endif
