/* internal.h -- private: the per-thread state of the pencil renderer and the functions shared by
 * its translation units (eval.c: one sample through the domain's paths; domain.c: steps 2-4 of
 * section 4.1 (1) for one domain; render.c: the screen loop). */
#ifndef PENCIL_INTERNAL_H
#define PENCIL_INTERNAL_H

#include <stdint.h>

#include "core/shade_paths.h"
#include "paraxial/vec3.h"
#include "pencil/edge.h"
#include "pencil/path.h"
#include "pencil/pencil.h"

/** pt_geom_t.su, sv of a checker square whose index is beyond int32 or not a number: never the
 *  same square as another hit's. */
#define PT_SQUARE_FAR INT32_MIN

/** Where one node of one sample met its surface, as computed by the pencil, and what it
 *  contributes to the sample's radiance. */
typedef struct {
  px_vec3_t p; /**< hit point */
  px_vec3_t d; /**< unit direction of the arriving ray */
  rt_rgb_t w;  /**< W_k: product of the shade.h child weights from the eye to the node */
  rt_rgb_t l;  /**< W_k * direct_k (W_k * background for a miss); shading only */
  union {
    rt_rgb_t lt[2]; /**< textured nodes at lattice points: W_k * direct_k with the material of
                         the even (0) and the odd (1) checker squares */
    struct {
      rt_rgb_t ls;  /**< W_k times the light its spectral pencils bring (rt_shade_spectral()) */
      uint32_t at;  /**< their events: pt_spec_table_t.ev[at .. at + nev), in the order of */
      uint32_t nev; /**< rt_spectral_rec_t's */
    } sp;           /**< spectral nodes (not textured) at lattice points where ssig != 0 */
  };
  int32_t su, sv; /**< checker square of the hit (textured nodes), else 0; PT_SQUARE_FAR
                       where the index does not fit */
  uint32_t lit;  /**< lattice points: bit l, light l's shadow ray was traced here and met nothing */
  uint32_t dark; /**< ... and was fully blocked */
  uint32_t through;    /**< lattice points: the lights traced here reached partly and the lights
                            blocked, hashed as rt_tree_node_t.through is (what blocks them, their
                            transmittances) */
  uint64_t ssig;       /**< spectral nodes at lattice points: rt_spectral_rec_t.sig of the
                            pencils traced from the point's exact hit (`sp` holds their light),
                            0 where none was recorded or it cannot be interpolated */
  uint8_t ok;          /**< 0 not reached, 1 computed by the pencil, 2 traced exactly */
  uint8_t exact_kinds; /**< bit k: the child of rt_ray_kind_t k was traced exactly */
} pt_geom_t;

/** A node's exact geometry for one sample (exact along the known path, memoised per sample). */
typedef struct {
  px_vec3_t p;    /**< exact hit point */
  px_vec3_t d;    /**< unit direction of the exact arriving ray */
  uint32_t stamp; /**< the evaluation it belongs to */
  int ok;         /**< 0: the sample's ray does not meet the node's primitive */
} pt_xgeom_t;

/** A node's exact geometry for the four samples of a group (pt_group_t), lane i sample i. */
typedef struct {
  px_vec3x4_t p;  /**< exact hit points */
  px_vec3x4_t d;  /**< unit directions of the exact arriving rays */
  uint32_t stamp; /**< the group it belongs to */
  unsigned ok;    /**< bit i: lane i's ray meets the node's primitive along the path */
} pt_xgeom4_t;

/** Up to four consecutive samples of one interpolated pixel whose exact walks are carried
 *  together (eval.c's exact_geom4(), interp_sample.c). */
typedef struct {
  rt_ray_t primary[4]; /**< their primary rays */
  double xi[4][2];     /**< and xi in the domain's frame */
  rt_ray4_t ray4;      /**< the primary rays of the lanes `lanes4` */
  unsigned lanes4;     /**< bit i: primary[i] has tmin 0, tmax infinite and no skip_prim, as
                            rt_prim_intersect4() takes rays (the others are walked alone) */
  int n;               /**< samples in the group */
  uint32_t stamp;      /**< group counter for pt_sample_t.exact4 */
} pt_group_t;

/* A pixel being accumulated. */
typedef struct {
  int i, j;      /**< pixel */
  rt_rgb_t sum;  /**< radiance summed over its samples */
  double pmax;   /**< largest measured error (NaN: none) */
  int n[3];      /**< samples by method */
  uint64_t rays; /**< exact rays traced for its samples */
} pixel_t;

/** The lattice points of the domain being interpolated, by their position: neighbouring lattice
 *  cells share corners and edge midpoints, which depend only on the position and the domain's
 *  paths, so each is traced once per domain. Open addressing over `slot` (a slot is in use when
 *  its `gen` is the current one, so a new domain only bumps `now`). */
typedef struct {
  pt_geom_t *g;   /**< storage: `entries` node records, a point's nodes contiguous */
  size_t entries; /**< node records in g */
  int stride;     /**< records per point: the current domain's node count */
  double *xy;     /**< position of each stored point, 2 per point */
  double *xi2;    /**< |xi|^2 of its primary ray */
  uint8_t *ok;    /**< traced without leaving the domain's paths */
  int n;          /**< points stored */
  int cap;        /**< room this domain (a full memo traces into the caller's storage) */
  int maxpts;     /**< room in xy, xi2 and ok: cap is at most this */
  int32_t *slot;  /**< hash table, nslot entries: index of a stored point */
  uint32_t *gen;  /**< generation of each slot */
  uint32_t now;   /**< the current domain's generation */
  int nslot;      /**< a power of two, at least 2 maxpts */
} pt_lattice_memo_t;

/** The plan of the lattice cell being interpolated, per node of the domain's tree (cap entries
 *  each; interp_plan.c fills them, the lattice cell's samples read them). */
typedef struct {
  int *shaded;            /**< nodes shaded per sample at their interpolated hits */
  uint8_t *shaded_direct; /**< ... with their direct term (per entry of `shaded`) */
  uint8_t *shaded_exact;  /**< ... with their exactly traced children (per entry of `shaded`) */
  int *leaves;            /**< textured leaves whose checker square changes over the lattice cell */
  int *linear;            /**< nodes whose brightness is interpolated (the brightness test) */
  uint8_t *exact_subtree; /**< per node: traced exactly per sample with its subtree (a verify
                               node that a grid point did not confirm, and below) */
  uint8_t *traced;        /**< per node: hits traced per sample by its matrix or along its path
                               (too curved to interpolate) */
  uint8_t *biquadratic; /**< per node: hits interpolated biquadratically from the lattice cell's (or
                             certified: its parent's) 3 x 3 grid */
  uint8_t *faint;       /**< per node: shading interpolated across a shadow edge, its
                             brightness being within a bound (interp_error.c) */
  uint8_t *spec_lin;    /**< per node: a spectral node whose spectral pencils' light is
                             interpolated from the lattice points' (pt_geom_t.sp), not traced per
                             sample (interp_plan.c's spectral_interpolable()) */
  int *spec;            /**< those nodes, listed */
} pt_lattice_plan_t;

/** Events of spectral pencils (rt_spectral_rec_t) one domain's lattice points keep. */
#define PT_SPEC_EVENTS 16384

/** One event of a lattice point's spectral pencils: the bounds of its segments' origins (lo x, y,
 *  z, hi x, y, z) then of their ends, rounded outwards, and the primitives the guard may skip for
 *  it (rt_spectral_rec_t.prim). */
typedef struct {
  float box[12];
  int32_t prim[RT_SPECTRAL_EVENT_PRIMS];
} pt_spec_event_t;

/** The events of the current domain's lattice points (pt_geom_t.sp.at, nev). */
typedef struct {
  pt_spec_event_t *ev; /**< PT_SPEC_EVENTS of them */
  uint32_t n;          /**< in use this domain */
} pt_spec_table_t;

/** Ray interpolation's state for one accepted domain (interp*.c). */
typedef struct {
  pt_geom_t *root;        /**< the root lattice cell's 3 x 3 points x cap nodes */
  pt_geom_t *refine;      /**< refinement grids: PT_LATTICE_LEVELS x 5 points x cap nodes */
  pixel_t *pixels;        /**< the domain's pixels being accumulated, N^2 */
  pt_lattice_memo_t memo; /**< the domain's lattice points by position */
  pt_lattice_plan_t plan; /**< the current lattice cell's plan */
  pt_spec_table_t spec;   /**< the domain's lattice points' spectral events */
  uint8_t *spec_off;      /**< per node (cap): a lattice point of the domain found its spectral
                               pencils' light not to be interpolable (rt_spectral_rec_t.unusable:
                               lights shading their hits, most often), so its other points do
                               not trace them (eval.c's spectral_record()) */
} pt_lattice_t;

/** The exact trees one thread traces into (xr_exact_t.tree points at one while it traces). */
typedef struct {
  rt_tree_t axial;   /**< the current domain's axial ray's tree (step 2) */
  rt_tree_t probe;   /**< single rays': corners, auxiliary channels, the measure's exact tree;
                          the plan's whole tree (plan->tree_nodes), as the exact renderer records,
                          so that auxiliary channels and the measure see every node */
  rt_tree_t side;    /**< the measure's side rays (measure.c), as large as the domain's paths may
                          be (pt_ctx_t.cap): a measured point deeper in the probe's tree has no
                          local footprint (pt_stats_t.local_unknown) */
  px_vec3_t *side_p; /**< their points per probe node, 4 x side.cap */
  uint8_t *side_ok;  /**< ... whether the side ray has the point, 4 x side.cap */
} pt_trees_t;

/** Ray-tree nodes a domain's paths may have (a full binary tree of depth 9). A domain whose
 *  axial or corner tree has more is traced exactly (pt_stats_t.domains_deep): its per-node
 *  buffers (system matrices, lattice records: about 20 kB a node) stay bounded, and a tree that
 *  large has too many edges for pencils to save work (docs/pencil.md, "Deep trees"). */
#define PT_MAX_TREE_NODES 1023

/** Samples a domain needs for its axial ray (and its corners) to be worth tracing: a smaller one
 *  (a pixel or two at 1 spp, made by subdivision at an edge) is traced exactly at once, as the
 *  exact renderer would, instead of paying an axial ray besides its samples. */
#define PT_MIN_DOMAIN_SAMPLES 4

/** The measure's record of the subtrees that one sample's evaluation traced exactly, each under a
 *  root node standing for the pencil node it hangs from (pt__measure compares their points with
 *  the exact tracer's). */
typedef struct {
  rt_tree_t tree;  /**< the subtrees, PT_SUB_TREES x cap nodes */
  int *root;       /**< each subtree's root in `tree` (cap) */
  int *from;       /**< ... the pencil node it hangs from (cap) */
  int *exact_node; /**< ... the exact tree's node on that node's path (pt__measure; cap) */
  int n;           /**< subtrees recorded */
} pt_subtrees_t;

/** Step 3 for the current domain: its corners' trees and their agreement with the axial tree. */
typedef struct {
  pt_ctree_t *tree;  /**< corner tree cache of the current domain, (N+1)^2 */
  pt_cnode_t *nodes; /**< their node storage (one block; entries are swapped) */
  int x0, y0;        /**< the current initial domain's top-left pixel (the cache's origin) */
  int *map;          /**< pt_tree_agree() scratch, 4 x cap */
  uint8_t *agree;    /**< pt_tree_agree() output per axial node, cap */
  uint32_t *light;   /**< pt_tree_agree() output per axial node: lights agreeing, cap */
} pt_corners_t;

/** Step 2 for the current domain: the paths of its axial tree and their system matrices. */
typedef struct {
  pt_node_t *node;           /**< one per tree node (cap) */
  int n;                     /**< nodes of the current domain's tree */
  px_frame_t frame;          /**< the domain's input frame at the eye (xi is measured in it) */
  int transmit, reflect;     /**< nodes on the transmission-first / reflection-first paths to the
                                  checkerboard (auxiliary channels, measure), or -1 */
  pt_path_scratch_t scratch; /**< pt_path_build()'s workspace */
} pt_paths_t;

/** One sample's evaluation: its geometry and exact geometry per node (cap each). */
typedef struct {
  pt_geom_t *geom;     /**< one sample's geometry (auxiliary channels, measure) */
  pt_xgeom_t *exact;   /**< one sample's exact geometry along the paths */
  uint32_t stamp;      /**< evaluation counter for `exact` */
  pt_xgeom4_t *exact4; /**< a group's exact geometry along the paths (opt->simd) */
  pt_group_t group;    /**< the group of samples being evaluated */
} pt_sample_t;

/** Per-thread state: the renderer's inputs (not owned) and the parts that hold the thread's
 *  buffers, each allocated once before the screen loop (pt__ctx_alloc) so that no ray
 *  allocates. */
typedef struct {
  const rt_scene_t *s;      /**< the prepared scene */
  const rt_plan_t *plan;    /**< the render plan (effects, tree size) */
  const rt_view_t *view;    /**< the camera's rays */
  const pt_options_t *opt;  /**< the caller's options */
  rt_image_t *img;          /**< the image being written */
  pt_extra_t *extra;        /**< the caller's extra channels (or NULL) */
  float *sample_error;      /**< the caller's per-sample errors (or NULL) */
  const pt_guards_t *guard; /**< the small-object guard's bounding spheres */
  const pt_guards_t *faces; /**< ... and the scene's polygons one by one (pt_guard_view()) */
  int weights_vary;         /**< the weights W_k vary with the hits (a Fresnel split): a
                                 lattice cell's nodes shaded per sample count the error of
                                 their interpolated W_k (interp_error.c) */
  int cap;                  /**< ray-tree capacity of the domain's parts: plan->tree_nodes,
                                 at most PT_MAX_TREE_NODES */
  size_t bytes;             /**< bytes of the buffers below (pt__ctx_alloc) */
  xr_exact_t ex;            /**< the exact tracer (axial, corner, fallback and edge rays) */
  pt_trees_t trees;         /**< its exact trees */
  pt_subtrees_t sub;        /**< measure: one sample's subtrees traced exactly */
  pt_corners_t corners;     /**< step 3 for the current domain */
  pt_paths_t paths;         /**< step 2 for the current domain */
  pt_lattice_t lattice;     /**< ray interpolation of the current domain */
  pt_sample_t sample;       /**< one sample's evaluation */
  pt_stats_t st;            /**< this thread's counters */
} pt_ctx_t;

/* context.c: each part's buffers for trees of `cap` nodes and domains of n x n pixels; an
 * alloc returns 0 when some allocation failed (its free then frees what was allocated), and a
 * free leaves the part empty. */
int pt__trees_alloc(pt_trees_t *t, int cap, int probe_cap);
void pt__trees_free(pt_trees_t *t);
int pt__subtrees_alloc(pt_subtrees_t *t, int cap);
void pt__subtrees_free(pt_subtrees_t *t);
int pt__corners_alloc(pt_corners_t *c, int cap, int n);
void pt__corners_free(pt_corners_t *c);
int pt__paths_alloc(pt_paths_t *p, int cap);
void pt__paths_free(pt_paths_t *p);
int pt__lattice_alloc(pt_lattice_t *l, int cap, int n);
void pt__lattice_free(pt_lattice_t *l);
int pt__sample_alloc(pt_sample_t *x, int cap);
void pt__sample_free(pt_sample_t *x);
/** Every part of C (its inputs set); 0 on failure, after which pt__ctx_free() frees. */
int pt__ctx_alloc(pt_ctx_t *C, int tree_nodes, int n);
void pt__ctx_free(pt_ctx_t *C);

/** Trace the exact tree of ray r into t for its shape alone (xr_exact_t.halt: no spectral
 *  pencils, no ray past the tree's capacity), its radiance dropped: the axial and corner rays,
 *  the auxiliary channels' and the measure's trees (domain.c). */
void pt__trace_shape(pt_ctx_t *C, rt_tree_t *t, const rt_ray_t *r);

enum { PT_EV_MATRIX = 0, PT_EV_INTERP = 1 };

/** Subtrees traced exactly that one sample's measurement can hold, in whole trees (the subtrees
 *  of one sample are disjoint parts of its tree, so one tree's capacity is enough but for the
 *  root node each adds). */
#define PT_SUB_TREES 2

/** Share of rho that the certified mode's checks may use (the margin covers third-order
 *  variation between the checked points; docs/pencil.md). */
#define PT_CERTIFIED_MARGIN 0.7

/** Share of the brightness tolerance that faint nodes (interp_plan.c) may take together; the
 *  caustic and highlight guards fire when what they bound exceeds it. */
#define PT_FAINT_SHARE 0.5

/** Depth of the quadtree of lattice cells (halvings of the domain) at most. */
#define PT_LATTICE_LEVELS 12

/** One sample's evaluation through the current domain's paths. */
typedef struct {
  pt_ctx_t *C;                  /**< the thread's state (the domain's paths) */
  int mode;                     /**< PT_EV_MATRIX or PT_EV_INTERP */
  double xi[2];                 /**< MATRIX: the sample's xi in the domain's frame */
  rt_ray_t primary;             /**< MATRIX: the sample's primary ray (for an exact fallback) */
  const double *corner_w;       /**< INTERP: bilinear weights of the lattice cell's 4 corners */
  const pt_geom_t *corner[4];   /**< INTERP: their geometry, indexed by node */
  pt_geom_t *geom;              /**< per-node geometry out (cap entries), or NULL */
  int shade;                    /**< 0: geometry only */
  int record_shadow;            /**< 1: trace shadow rays and store them in the nodes (axial
                                     sample) */
  int lattice;                  /**< 1: a lattice point: also fill pt_geom_t.lt of textured
                                     nodes; subtrees leaving the paths are marked, not traced (its
                                     radiance is not used) */
  int cur;                      /**< node being shaded */
  uint32_t stamp;               /**< this evaluation's stamp in C->sample.exact */
  int grouped;                  /**< 1: the sample is lane `lane` of C->sample.group, whose exact
                                     walks are carried together (exact_geom4()) */
  int lane;                     /**< its lane there */
  int fallback;                 /**< set when the sample left the domain's paths (traced exactly
                                     there) */
  int vfail;                    /**< set when a verify node's scene search failed (traced
                                     exactly) */
  const uint8_t *exact_subtree; /**< INTERP: nodes whose subtrees are traced exactly in this
                                     lattice cell (pt_lattice_plan_t) */
  const uint8_t *spec_lin;      /**< INTERP: spectral nodes whose spectral light this lattice
                                     cell interpolates (pt_lattice_plan_t), or NULL */
  const uint8_t *traced;        /**< INTERP: nodes whose hits come from their matrices (or path)
                                     per sample in this lattice cell (xi and primary set), not
                                     interpolated */
  const uint8_t *biquadratic;   /**< INTERP: nodes interpolated biquadratically (grid, grid_w), or
                                     NULL */
  const pt_geom_t *grid[9];     /**< INTERP with biquadratic: the 3 x 3 grid, row-major */
  double grid_w[9];             /**< INTERP with biquadratic: the sample's biquadratic (Lagrange)
                                     weights */
  int record_sub;               /**< measure: subtrees traced exactly are recorded in C->sub
                                     (reset by pt__eval) */
  int exact_spawn;              /**< some node has a child traced exactly per sample: such a node
                                     spawns it from the sample's exact hit (primary set; the
                                     sample's ray carried along the node's path), not from an
                                     interpolated or matrix hit (pt__spawns_exact) */
  int spawnfail;                /**< set when such a node's exact path left the domain's paths
                                     (the sample is then traced exactly) */
  int traced_failed;            /**< set when a traced node's per-sample ray left its path */
  int partial;                  /**< set when a subtree where the corners differ was traced
                                     exactly */
} pt_eval_t;

/** pt_eval_t.exact_spawn for evaluations of the current domain with E's exact_subtree (the lattice
 * cell's plan): whether some node has a child traced exactly per sample. */
int pt__spawns_exact(const pt_eval_t *E);
/** Radiance of the sample (black when shade = 0). */
rt_rgb_t pt__eval(pt_eval_t *E);

/** INTERP mode, one node of one sample: with `direct`, W * direct at node k's interpolated hit
 *  (a miss node: W * background); with `exact_children`, plus the weighted radiance of those of
 *  its children that are traced exactly (children the corners' trees disagree on). */
rt_rgb_t pt__eval_local(pt_eval_t *E, int k, rt_rgb_t w, int direct, int exact_children);

/** xi of the primary ray through continuous pixel coordinates (x, y) in the domain frame. */
void pt__xi(const pt_ctx_t *C, double x, double y, double xi[2]);

/** Steps 2-4 for the (sub)domain [x0, x1) x [y0, y1) of the current initial domain (recursive). */
void pt__domain(pt_ctx_t *C, int x0, int y0, int x1, int y1);

/* sample.c */
/** G->ray4 and G->lanes4 from G->primary[0 .. G->n). */
void pt__group_rays(pt_group_t *G);
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
void pt__exact_domain(pt_ctx_t *C, int x0, int y0, int x1, int y1);
/** Fig. 10 bookkeeping of one sample; returns the pixel's running maximum error. */
double pt__measure_sample(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, int i, int j,
                          int a, int b, double pmax);
/** Geometry-only evaluation of E's sample into C->rec. */
void pt__geometry(pt_ctx_t *C, pt_eval_t *E);
/** Write a finished pixel. */
void pt__pixel_done(pt_ctx_t *C, pixel_t *P);
/** Step 4a's shadow transmittance once per domain: the axial ray through the domain's paths,
 * tracing the shadow rays of the lights whose visibility agrees over the domain and storing them in
 * the nodes (known_cb answers them for every other evaluation of the domain). */
void pt__record_shadows(pt_ctx_t *C, const rt_ray_t *axial);
/** The primary ray and xi of continuous pixel coordinates (x, y) into E. */
void pt__xi_of(const pt_ctx_t *C, pt_eval_t *E, double x, double y);
/** Sample (a, b) of pixel P through the domain's paths (MATRIX evaluation). */
void pt__matrix_sample(pt_ctx_t *C, pixel_t *P, int a, int b);
/** Auxiliary channels of pixel (i, j) from a MATRIX evaluation of its centre. */
void pt__aux_matrix(pt_ctx_t *C, int i, int j);
/** Every sample of pixel (i, j) through the domain's paths. */
void pt__matrix_pixel(pt_ctx_t *C, int i, int j);

/* interp_memo.c */
/** Keep rec's events for the current domain from *at: 0 when the domain's are full. */
int pt__spec_put(pt_ctx_t *C, const rt_spectral_rec_t *rec, uint32_t *at);

/* interp.c */
/** Step 4a with ray interpolation for the accepted domain [x0, x1) x [y0, y1) whose axial ray (its
 *  centre's) is `axial`. */
void pt__interp_domain(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial);

/** The Fig. 10 errors of one sample (measure.c): in pixel intervals, the larger of the domain's
 *  axial footprint's and the point's own (the measure); the same on the transmission-first path
 *  only; |e| / sigma_min (strict); in the axial footprint's intervals alone (the measure of
 *  versions before the local footprint). */
enum { PT_E_PIXELS = 0, PT_E_T = 1, PT_E_STRICT = 2, PT_E_AXIAL = 3, PT_MEASURE_ERRORS = 4 };

/** The step, in a sample's spacing, of the side rays that give a measured point its own pixel
 *  footprint (measure.c). */
#define PT_LOCAL_STEP 0.25

/** Fig. 10 errors of the sample at (sx, sy) in pixels, with primary ray `ray` and pencil geometry
 *  rec (see pencil.h) and the subtrees its evaluation traced exactly (C->sub), tracing it
 *  exactly: e[PT_E_*], each the largest over its measured points (rt_object_measured). Returns
 *  the number of pencil points compared. */
int pt__measure(pt_ctx_t *C, const rt_ray_t *ray, double sx, double sy, const pt_geom_t *rec,
                double e[PT_MEASURE_ERRORS]);

/** Record a finished sample's errors in the statistics (and e[PT_E_PIXELS] in the caller's
 *  buffer). */
void pt__account(pt_ctx_t *C, const double e[PT_MEASURE_ERRORS], int has_points, float *slot);

#endif
