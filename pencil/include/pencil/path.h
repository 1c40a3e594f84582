/* path.h -- the paths of a pencil's ray tree and their system matrices (paper section 4.1 (1),
 * step 2: "trace [the axial ray] with the conventional ray tracer. Calculate the system matrix"),
 * the tolerance of Eq. (3) and the spread limit of Eqs. (4)-(6).
 *
 * Every node of the axial ray's tree (rt_tree_t from the exact tracer) is reached from the eye by
 * a path of refractions and reflections. pt_path_build() describes each edge of the tree (the
 * parent's surface and the transfer to the node's hit) as a one-stage exact optical system
 * (ex_system_t: origin = the parent's hit, input frame = the parent's output frame, the parent's
 * surface with at_origin set, tail = the distance to the node's hit) and lets reference/ trace
 * it and build its cascade (ex_trace_axial, ex_axial_cascade: verified against exact tracing to
 * 1e-11); the node's system matrix is that step times its parent's, T_k = S_k T_parent, i.e. the
 * cascade of the whole path (section 2.2). pt_path_full() builds the same path as one system
 * (one stage per surface), whose exact map (ex_map) the probe uses; the tests check that both
 * give the same T. The certified check composes the exact map the same way as the matrices:
 * each boundary ray's exact ray vector at the parent, carried through the node's step by ex_map
 * (the tests check it against the whole path's ex_map). T maps a ray vector at the eye,
 * psi = (0, 0, xi1, xi2) (a pinhole pencil), to psi' = T psi in the ray frame at the node's hit.
 *
 * Tolerances are taken on the node's surface (the tangent plane at the axial hit), where Fig. 10
 * measures. The pixel footprint there is J = [j1 j2], j_i = |(t1 t2) delta_i| of Eq. (3) for a
 * one-pixel step delta_i along screen axis i, carried along the ray onto the tangent plane. An
 * error e on the surface is |J+ e| pixels (J+ the pseudo-inverse); the smallest pixel interval
 * over all screen directions is sigma_min(J), so |e| <= rho sigma_min guarantees |J+ e| <= rho,
 * and an error e in the plane normal to the ray is at most e / |cos| on the surface.
 * Nothing here allocates; all buffers are caller-owned.
 */
#ifndef PENCIL_PATH_H
#define PENCIL_PATH_H

#include "core/raytree.h"
#include "core/scene.h"
#include "exact/trace.h"
#include "pencil/pencil.h"

/** Lights whose shadow transmittance a domain records once (lights beyond are traced per
 *  sample); the ray tree records visibility for the first 32 lights as well. */
#define PT_MAX_LIGHTS 32

/** How a node of a cell's tree is traced for the cell's samples (section 4.1 (1), step 4). */
typedef enum {
  /** Its subtree by the exact tracer: the trees of the cell's corners differ at or above it
   *  (an edge, step 3). */
  PT_NODE_EXACT = 0,
  /** With its system matrix: the node and its ancestors met the same surfaces at the corners,
   *  and the cell's spread is within its spread limit (step 4a; certified mode: and its exact
   *  check passed). */
  PT_NODE_MATRIX = 1,
  /** Exactly along its known path: the sample's own ray (from shade.h at the parent's hit)
   *  meets the node's primitive, without a scene search (steps 4b and 4c when subdividing does
   *  not pay). The corners agree on the surfaces as for MATRIX, or (verify) the node's hit is
   *  confirmed by a scene search. */
  PT_NODE_PATH = 2
} pt_node_mode_t;

/** One refraction or reflection of a path, as the general cascade form of Appendix (3) sees it
 *  (element i of the path's cascade): its error coefficients a-f and the weights from the
 *  partial products before it (T_i^b, fixed) and after it (T_i^a, which grows with the path). */
typedef struct {
  px_mat4_t ta;  /**< T_i^a: product of the elements after i, up to the node */
  double mb, md; /**< mu_2, mu_4: |B|_2 and |D|_2 of T_i^b (the blocks a pinhole pencil sees) */
  double k[6];   /**< a, b, c, d, e, f of the element (px_error_coeffs, the run's variant) */
} pt_term_t;

/** One node of the domain's tree with its path's system matrix. */
typedef struct {
  int parent;           /**< tree index of the parent, -1 for the primary ray */
  int kind;             /**< rt_ray_kind_t of the ray arriving at the node */
  int depth;            /**< reflections/refractions before the node */
  int miss;             /**< 1 when the axial ray met nothing (background) */
  int object, prim;     /**< surface met, -1 on a miss */
  int textured;         /**< 1 when the surface is a checkerboard (texel >= 0) */
  int measured;         /**< 1 when the error measure counts hits on the surface: it has a
                             diffuse term (rt_object_measured) */
  int child[2];         /**< tree indices of the children, -1 when absent */
  int child_kind[2];    /**< their rt_ray_kind_t */
  int mode;             /**< pt_node_mode_t: how the samples' rays of this node are traced */
  int spectral;         /**< 1: the node's glass disperses under a plan with spectral pencils
                             (rt_shade_spectral_at()): its refracted light is traced per sample
                             by spectral pencils from the sample's own hit, an exact child */
  int verify;           /**< PATH with ray interpolation where the corners' trees differ at or
                             above the node: the exact ray along the path must meet the node's
                             own surface first in a scene search, else it is traced exactly */
  int highlight;        /**< 1: a Phong highlight may lie among the domain's hits (domain.c's
                             highlight_guard()): interp_plan.c's highlight guard tests each
                             lattice cell */
  uint32_t light_agree; /**< bit l: light l's visibility is the same at the centre and corners */
  uint32_t light_guard; /**< bit l: a bounded object may shadow part of the cell's hits from light
                             l although the corners agree (small-object guard): the direct term
                             is shaded per sample */
  double ior;           /**< index of the medium the arriving ray travels in */
  /* psi' = T psi for psi = (0, 0, xi) at the eye: x' = B xi, xi' = D xi (Eqs. 1-2 cascaded) */
  px_mat2_t b;          /**< upper right block of T, scene units per unit of xi */
  px_mat2_t d;          /**< lower right block of T, dimensionless */
  px_vec3_t o;          /**< O': the axial hit point (origin of the output ray frame) */
  px_vec3_t e1, e2, ez; /**< output ray frame (world), ez along the arriving axial ray */
  px_vec3_t n;          /**< unit surface normal at O', facing the arriving ray */
  double cos_in;        /**< |n . ez|, cosine of the incidence angle of the axial ray */
  px_vec3_t j[2];   /**< pixel footprint on the surface: displacement per pixel along screen x, y */
  double ginv[3];   /**< (J^T J)^-1 as (00, 01, 11), for pt_pixels() */
  double interval;  /**< sigma_min(J): the smallest pixel interval on the surface, scene units */
  double tau;       /**< rho * interval: the tolerance of Eq. (3) on the surface (rho times
                         tol_scale) */
  double tol_scale; /**< the node's tolerance in units of rho: 1, or with the image-space
                         tolerance 1 / max(W, floor) (pencil.h, pt_tolerance_t); set by the
                         renderer before pt_path_build(), which takes rho as given */
  double c;         /**< C of Eq. (4) for this path (x0 = 0), scene units; 0 for a transfer */
  double xi_max;    /**< spread limit of Eq. (6) on the surface: sqrt(tau cos / C), at most
                         PT_SPREAD_CAP (pt_spread_limit) */
  double e_check;   /**< certified mode: largest exact error on the cell boundary (surface units,
                         from ex_map at the corners and edge midpoints), else -1 */
  double xcheck[8][4]; /**< certified mode: the exact ray vectors of the 8 boundary rays in the
                            node's output frame (ex_map's psi'), which its children's checks
                            carry on by one step */
  double guard_r;      /**< radius about o of the node's hits over the cell, for the small-object
                            guard of secondary segments (pencil/src/domain.c); < 0: not computed */
  unsigned known;      /**< bit l: through[l] recorded for light l */
  rt_rgb_t through[PT_MAX_LIGHTS]; /**< shadow transmittance of the axial hit, per light */
  int nstep; /**< elements of the step from the parent (transfer; interface + transfer) */
  px_element_t step[3]; /**< the step's cascade elements (the path's cascade is the chain of
                             its nodes' steps) */
  int nterm;            /**< refractions/reflections on the path (= depth) with bound terms */
  pt_term_t term[EX_MAX_STAGES]; /**< their Appendix (3) terms (corrected/printed bounds) */
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
  px_vec3_t eye;            /**< the pinhole */
  px_frame_t frame;         /**< input ray frame at the eye, z = the axial primary direction */
  double delta[2][2];       /**< xi-increments of one pixel step along the two screen axes */
  double rho;               /**< Eq. (3) */
  pt_bound_t bound;         /**< source of C */
  double xi_domain;         /**< the cell's spread: largest |xi| of its samples (for the probe) */
  const double (*check)[2]; /**< certified mode: xi of the 8 boundary points (corner, edge
                                 midpoint, corner, midpoint, ... in order round the cell), or
                                 NULL */
} pt_pencil_t;

/** Topology of node k of `tree` (parent, children, surface, medium) into *out, with no matrix
 *  yet (mode = 0, tau = xi_max = INFINITY). `parent` is the already filled parent node (NULL
 *  for the root). */
void pt_path_topology(const rt_scene_t *s, const rt_tree_t *tree, int k, const pt_node_t *parent,
                      pt_node_t *out);

/** The system matrix of node k (traced from p->eye along p->frame.z) from its parent's, its
 *  tolerance, C and spread limit, into nodes[k]; nodes[] must hold the topology of k and its
 *  ancestors and the matrices of its ancestors. PX_EMISS, PX_ETIR, PX_EGRAZING when the path's
 *  axial ray cannot be re-traced through its quadrics (the node is then treated as an edge). */
px_status_t pt_path_build(const rt_scene_t *s, const rt_tree_t *tree, int k, pt_node_t *nodes,
                          const pt_pencil_t *p, pt_path_scratch_t *w);

/** The whole path of node k as one exact system in w->sys / w->ax (stages for every surface met
 *  before the node, traced from p->eye), for ex_map(). PX_EINVAL for a path longer than
 *  EX_MAX_STAGES. */
px_status_t pt_path_full(const rt_scene_t *s, const rt_tree_t *tree, int k, const pt_pencil_t *p,
                         pt_path_scratch_t *w);

/** Eq. (3) on the surface: the footprint j_i = proj(B delta_i) for the pixel steps delta_i,
 *  where proj carries a displacement of the plane normal to ez along ez onto the plane normal
 *  to n; writes j[2] and ginv and returns sigma_min(J) (0 for a degenerate footprint). */
double pt_footprint(px_mat2_t b, const double delta[2][2], px_vec3_t e1, px_vec3_t e2, px_vec3_t ez,
                    px_vec3_t n, px_vec3_t j[2], double ginv[3]);

/** A surface displacement e in pixels: |J+ e| with the node's footprint. */
double pt_pixels(const pt_node_t *n, px_vec3_t e);

/** Largest spread |xi| a pencil may have whatever its C (px_spread_limit's cap): where C = 0
 *  only the third-order error limits, which the second-order bounds do not cover. For the
 *  primary ray (a transfer of length z from the pinhole) it is known: the linear map puts the
 *  ray at z xi instead of z xi / sqrt(1 - xi^2), an error below k3 xi^3 with k3 = 0.77 z for
 *  |xi| <= PT_SPREAD_CAP (z/2 times (1 - xi^2)^(-3/2) <= 1.54). Deeper paths with C = 0 (plane
 *  mirrors, a ray through a sphere's centre) have no such term here and stop at the cap. */
#define PT_SPREAD_CAP 0.5

/** Eq. (6) on the surface, extended by a third-order term: the largest xi0 <= PT_SPREAD_CAP with
 *  (C xi0^2 + k3 xi0^3) / cos <= tau (px_spread_limit; 0 for tau <= 0). */
double pt_spread_limit(double c, double k3, double tau, double cos_in);

/** The paraxial ray of a sample: psi' = T (0, 0, xi) turned into a world ray through
 *  O' + x1' e1 + x2' e2 with unit direction xi1' e1 + xi2' e2 + sqrt(1 - |xi'|^2) ez.
 *  Returns 0 when |xi'| >= 1. */
int pt_node_ray(const pt_node_t *n, const double xi[2], px_vec3_t *p, px_vec3_t *d);

/** Where the ray (p, d) meets the node's own primitive near p (no scene search): the root
 *  nearest p for a sphere, the plane point for a plane, and for a polygon only when the point
 *  is inside it. Returns 0 when it does not. */
int pt_node_hit(const rt_scene_t *s, const pt_node_t *n, px_vec3_t p, px_vec3_t d, px_vec3_t *hit);

#endif
