/* internal.h -- private: the per-thread state of the pencil renderer and the functions shared by
 * its translation units (eval.c: one sample through the domain's paths; cell.c: steps 2-4 of
 * section 4.1 (1) for one domain; render.c: the screen loop). */
#ifndef PENCIL_INTERNAL_H
#define PENCIL_INTERNAL_H

#include <stdint.h>

#include "pencil/edge.h"
#include "pencil/path.h"
#include "pencil/pencil.h"

/** Where one node of one sample met its surface, as computed by the pencil. */
typedef struct {
  px_vec3_t p;     /**< hit point */
  px_vec3_t d;     /**< unit direction of the arriving ray */
  int32_t su, sv;  /**< checker square of the hit (textured nodes), else 0 */
  uint8_t ok;      /**< 0 not reached, 1 computed by the pencil, 2 traced exactly */
  uint8_t fb;      /**< bit k: the child of rt_ray_kind_t k was traced exactly */
} pt_geom_t;

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
  int cap;                /**< ray-tree capacity (plan->tree_nodes) */
  rt_exact_t ex;          /**< the exact tracer (axial, corner, fallback and edge rays) */
  rt_tree_t tree;         /**< the current cell's axial tree */
  rt_tree_t tree2;        /**< corner and measurement trees */
  pt_ctree_t *corner;     /**< corner tree cache of the current domain, (N+1)^2 */
  int dom_x0, dom_y0;     /**< the current domain's top-left pixel */
  pt_node_t *node;        /**< the current cell's paths, one per tree node */
  int nnode;
  px_frame_t frame;       /**< the current cell's input frame at the eye */
  int kt, kr;             /**< nodes on the transmission-first / reflection-first paths to the
                               checkerboard, or -1 */
  pt_path_scratch_t path;
  pt_geom_t *lat;         /**< lattice geometry, (N+1)^2 points x cap nodes */
  rt_rgb_t *latc;         /**< lattice colours */
  uint8_t *latok;         /**< lattice point evaluated without exact fallback */
  pt_geom_t *rec;         /**< one sample's geometry, cap nodes */
  double (*sw)[4];        /**< bilinear weights of the s x s sample pattern */
  pt_stats_t st;
} pt_ctx_t;

enum { PT_EV_MATRIX = 0, PT_EV_INTERP = 1 };

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
  int cur;                /**< node being shaded */
  int fallback;           /**< set when part of the tree was traced exactly */
} pt_eval_t;

/** Radiance of the sample (background when shade = 0 is not asked for). */
rt_rgb_t pt__eval(pt_eval_t *E);

/** xi of the primary ray through continuous pixel coordinates (x, y) in the cell frame. */
void pt__xi(const pt_ctx_t *C, double x, double y, double xi[2]);

/** Steps 2-4 for the cell [x0, x1) x [y0, y1) of the current domain (recursive). */
void pt__cell(pt_ctx_t *C, int x0, int y0, int x1, int y1);

/** Fig. 10 error of one sample with pencil geometry rec (see pencil.h); traces it exactly. */
double pt__measure(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, double *err_t);

/** Record a finished sample error in the statistics (and the caller's buffer). */
void pt__account(pt_ctx_t *C, double err, double err_t, int has_board, float *slot);

#endif
