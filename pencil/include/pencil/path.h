/* path.h -- the paths of a pencil's ray tree and their system matrices (paper section 4.1 (1),
 * step 2: "trace [the axial ray] with the conventional ray tracer. Calculate the system matrix"),
 * the tolerance of Eq. (3) and the spread limit of Eqs. (4)-(6).
 *
 * Every node of the axial ray's tree (rt_tree_t from the exact tracer) is reached from the eye by
 * a path of refractions and reflections. For each node, pt_path_build() describes that path as
 * an exact optical system (ex_system_t: origin = the eye, input frame = the axial primary ray's
 * frame, one stage per surface met before the node, tail = the distance to the node's hit) and
 * lets reference/ trace its axial ray and build its cascade (ex_trace_axial, ex_axial_cascade:
 * products verified against exact tracing to 1e-11). The product T maps a ray vector at the eye,
 * psi = (0, 0, xi1, xi2) (a pinhole pencil), to psi' = T psi in the ray frame at the node's hit.
 *
 * Tolerances are taken on the node's surface (the tangent plane at the axial hit), where Fig. 10
 * measures: the pixel interval there is |(t1 t2) delta| of Eq. (3) carried along the ray onto the
 * tangent plane, and an error e in the plane normal to the ray becomes at most e / |cos| on it.
 * Nothing here allocates; all buffers are caller-owned.
 */
#ifndef PENCIL_PATH_H
#define PENCIL_PATH_H

#include "exact/trace.h"
#include "pencil/pencil.h"
#include "render/raytree.h"
#include "render/scene.h"

/** Lights whose shadow transmittance a domain records once (lights beyond are traced per
 *  sample); the ray tree records visibility for the first 32 lights as well. */
#define PT_MAX_LIGHTS 32

/** One node of the domain's tree with its path's system matrix. */
typedef struct {
  int parent;      /**< tree index of the parent, -1 for the primary ray */
  int kind;        /**< rt_ray_kind_t of the ray arriving at the node */
  int depth;       /**< reflections/refractions before the node */
  int miss;        /**< 1 when the axial ray met nothing (background) */
  int object, prim;/**< surface met, -1 on a miss */
  int textured;    /**< 1 when the surface is a checkerboard (texel >= 0) */
  int child[2];    /**< tree indices of the children, -1 when absent */
  int child_kind[2]; /**< their rt_ray_kind_t */
  double ior;      /**< index of the medium the arriving ray travels in */
  /* psi' = T psi for psi = (0, 0, xi) at the eye: x' = B xi, xi' = D xi (Eqs. 1-2 cascaded) */
  px_mat2_t b;     /**< upper right block of T, scene units per unit of xi */
  px_mat2_t d;     /**< lower right block of T, dimensionless */
  px_vec3_t o;     /**< O': the axial hit point (origin of the output ray frame) */
  px_vec3_t e1, e2, ez; /**< output ray frame (world), ez along the arriving axial ray */
  px_vec3_t n;     /**< unit surface normal at O', facing the arriving ray */
  double cos_in;   /**< |n . ez|, cosine of the incidence angle of the axial ray */
  double interval; /**< one pixel interval on the surface (Eq. 3's |(t1 t2) delta| carried onto
                        the tangent plane; the smaller of the two screen directions), scene units */
  double tau;      /**< rho * interval: the tolerance of Eq. (3) on the surface */
  double c;        /**< C of Eq. (4) for this path (x0 = 0), scene units; 0 for a transfer */
  double xi_max;   /**< spread limit of Eq. (6) on the surface: sqrt(tau cos / C), INFINITY
                        when C = 0 */
  double e_check;  /**< certified mode: largest exact error on the cell boundary (surface units,
                        from ex_map at the corners and edge midpoints), else -1 */
  unsigned known;  /**< bit l: through[l] recorded for light l */
  rt_rgb_t through[PT_MAX_LIGHTS]; /**< shadow transmittance of the axial hit, per light */
} pt_node_t;

/** Scratch for pt_path_build() (large: keep one per thread). */
typedef struct {
  ex_stage_t stage[EX_MAX_STAGES];
  ex_system_t sys;
  ex_axial_t ax;
  px_element_t elem[2 * EX_MAX_STAGES + 2];
} pt_path_scratch_t;

/** What pt_path_build() needs to know about the pencil. */
typedef struct {
  px_vec3_t eye;      /**< the pinhole */
  px_frame_t frame;   /**< input ray frame at the eye, z = the axial primary direction */
  double delta[2][2]; /**< xi-increments of one pixel step along the two screen axes */
  double rho;         /**< Eq. (3) */
  pt_bound_t bound;   /**< source of C */
  double xi_cell;     /**< the cell's spread: largest |xi| of its samples (for the probe) */
  const double (*check)[2]; /**< certified mode: xi of the 8 boundary points (corner, edge
                                 midpoint, corner, midpoint, ... in order round the cell), or
                                 NULL */
} pt_pencil_t;

/** Describe node k of `tree` (from the exact tracer, traced from p->eye along p->frame.z) as a
 *  path: fills *out except `known`/`through`. PX_EMISS, PX_ETIR, PX_EGRAZING when the path's
 *  axial ray cannot be re-traced through its quadrics (the cell is then treated as an edge);
 *  PX_EINVAL for a tree deeper than EX_MAX_STAGES or a non-quadric surface. */
px_status_t pt_path_build(const rt_scene_t *s, const rt_tree_t *tree, int k, const pt_pencil_t *p,
                          pt_path_scratch_t *w, pt_node_t *out);

/** Eq. (3) on the surface: one pixel interval = min over i of |proj(B delta_i)|, where proj
 *  carries a displacement v of the plane normal to ez along ez onto the plane normal to n. */
double pt_surface_interval(px_mat2_t b, const double delta[2][2], px_vec3_t e1, px_vec3_t e2,
                           px_vec3_t ez, px_vec3_t n);

/** Eq. (6) on the surface: the largest xi0 with C xi0^2 / cos <= tau (INFINITY for C = 0, 0 for
 *  tau <= 0). */
double pt_spread_limit(double c, double tau, double cos_in);

/** The paraxial ray of a sample: psi' = T (0, 0, xi) turned into a world ray through
 *  O' + x1' e1 + x2' e2 with unit direction xi1' e1 + xi2' e2 + sqrt(1 - |xi'|^2) ez.
 *  Returns 0 when |xi'| >= 1. */
int pt_node_ray(const pt_node_t *n, const double xi[2], px_vec3_t *p, px_vec3_t *d);

/** Where the ray (p, d) meets the node's own primitive near p (no scene search): the root
 *  nearest p for a sphere, the plane point for a plane, and for a polygon only when the point
 *  is inside it. Returns 0 when it does not. */
int pt_node_hit(const rt_scene_t *s, const pt_node_t *n, px_vec3_t p, px_vec3_t d,
                px_vec3_t *hit);

#endif
