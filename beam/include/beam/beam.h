/* beam.h -- pencils of polyhedra: bundles of rays bounded by polygon edges, carried through the
 * planar faces of a scene by system matrices (1987 paper, section 4.1 (3) and section 4.2; 1989
 * paper, section 2.2.2). Shared by the light's illuminance polygons (light/, `--method polygons`)
 * and beam tracing from the eye (the renderers).
 *
 * A source sends the rays of a parameter plane: from an apex (a point light, a pinhole) the ray of
 * parameters (a, b) has direction z + a x + b y (a and b are tangents, so that the straight edges
 * of a polygon project to straight edges); a parallel source sends it from o + a x + b y along z.
 * A beam is a convex polygon of parameters (paraxial/polygon.h) and the path its rays follow: the
 * faces they meet and whether they are reflected or refracted there. Its axial ray is the ray of
 * the polygon's centroid, traced exactly along the path; the path's system matrix T (Eqs. 1-2,
 * planar faces: Q = 0) maps a parameter offset delta from the centroid to the paraxial ray after
 * the last face: position x = G0 delta and direction xi = H delta in the axial ray's frame, with
 * G0 = A Jx + B Jxi and H = C Jx + D Jxi for the source's own Jacobians Jx (parallel) or Jxi
 * (apex).
 *
 * A point v lies on the paraxial ray of delta when (G0 + s H) delta = F^T (v - O) with
 * s = d . (v - O): the generalised perspective transformation of the 1987 paper's Eq. (7) (the
 * transfer to the point's own depth, inverted), which maps a face's vertices into the parameter
 * plane (the paper's "polygon edges mapped into xi-space by B^-1"). Before the first face the map
 * is exact: a central or parallel projection. Where the linear model is not good enough the caller
 * divides the beam, measuring the model against exact tracing (bm_exact()).
 *
 * Prefix bm_. Above core/ (the scene) and libparaxial (matrices, polygons). */
#ifndef BEAM_BEAM_H
#define BEAM_BEAM_H

#include "core/scene.h"
#include "paraxial/paraxial.h"

/** Most faces (reflections and refractions) on a beam's path: the scene format's max_depth. */
#define BM_MAX_STEPS 32

/** A convex face of the scene: a polygon (a concave one is cut into triangles) or a plane. */
typedef struct {
  int prim, object;
  px_vec3_t n;      /**< unit normal (the primitive's: outward for a polyhedron) */
  double d;         /**< n . x = d */
  int first, count; /**< vertices bm_scene_t.vertex[first ..], counter-clockwise about n; count 0
                         for an unbounded plane */
  px_vec3_t c;      /**< centre of a sphere around it (the vertices' mean) */
  double radius;    /**< its radius (INFINITY for a plane) */
} bm_face_t;

typedef struct {
  bm_face_t *face;
  int nface;
  px_vec3_t *vertex;
  int nvertex;
  int *face_of_prim; /**< the first face of each primitive, -1 for a sphere */
  double scale;      /**< the scene's size (its bounded primitives' box), for tolerances */
} bm_scene_t;

/** The convex faces of scene s. RT_EINVAL with the reason in why[cap] when an object a beam could
 *  meet is curved (a sphere): "object 'ball' is a sphere: ...". RT_ENOMEM. */
rt_status_t bm_scene_build(const rt_scene_t *s, bm_scene_t *b, char *why, size_t cap);
void bm_scene_free(bm_scene_t *b);

/** Where a beam's rays start. */
typedef struct {
  int parallel;         /**< 0: from the apex o; 1: from o + a x + b y along z */
  px_vec3_t o, x, y, z; /**< x, y, z orthonormal, right-handed */
  double ior;           /**< index of the medium the rays start in */
} bm_source_t;

/** The ray of parameters p (unit direction; tmin 0). */
rt_ray_t bm_source_ray(const bm_source_t *src, const double p[2]);

/** The source measure of a parameter polygon: the solid angle of its rays (apex; the spherical
 *  polygon of the tangent-plane polygon, a fan of Van Oosterom-Strackee triangles) or its area
 *  across the beam (parallel). */
double bm_source_measure(const bm_source_t *src, const px_poly2_t *p);

/** One face of a path and what the rays do there. */
typedef struct {
  int face;
  px_event_t event; /**< PX_EVENT_REFRACT or PX_EVENT_REFLECT */
  double n2;        /**< the index of the medium after the face (the incident one for a
                         reflection) */
  double dn2;       /**< d n2 / du on the renderer's wavelength axis u where a refraction
                         enters a dispersive medium (n2 is its index at the axis's u_c); 0
                         otherwise. Only the beam renderer's dispersion image solids read it. */
} bm_step_t;

typedef struct {
  int n;
  bm_step_t step[BM_MAX_STEPS];
} bm_path_t;

/** A beam's linear model after its path: the axial ray and the maps of the parameter offset. */
typedef struct {
  double pc[2];    /**< the axial ray's parameters (the polygon's centroid) */
  int root;        /**< 1 before the first face: projections are exact (central or parallel) */
  px_vec3_t o, d;  /**< the axial ray after the path: its last hit (the source's origin for the
                        root) and unit direction */
  double ior;      /**< the medium it travels in */
  px_frame_t f;    /**< its ray frame (f.z = d) */
  px_mat2_t g0, h; /**< position and direction of the paraxial ray of offset delta in f:
                        x = g0 delta, xi = h delta */
  px_mat4_t t;     /**< the path's system matrix in f (identity for the root) */
  int last_face;   /**< the path's last face (the axial ray leaves it), -1 for the root */
} bm_model_t;

/** The model of the rays of parameters near pc along path: the axial ray traced exactly face by
 *  face (plane intersections, Snell's law or the mirror law), the matrices of Eqs. (1)-(2) in
 *  the corrected form. PX_EMISS when the axial ray does not meet a face's plane ahead of it,
 *  PX_ETIR, PX_EGRAZING, PX_EILLCOND as px_interface_matrix(). */
px_status_t bm_model(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                     const double pc[2], bm_model_t *m);

/** The exact ray of parameters p along path (no search: each face's plane in turn), after its
 *  last face: origin on the face, unit direction, medium. PX_EMISS, PX_ETIR. */
px_status_t bm_exact(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                     const double p[2], px_vec3_t *o, px_vec3_t *d);

/** bm_exact() at another wavelength: each refraction's n2 + dn2 du (bm_step_t.dn2), the point
 *  where the ray meets each face in pts[0 .. path->n - 1] when pts is not NULL. A medium entered
 *  with a dispersion keeps its index at du until the next refraction. */
px_status_t bm_exact_at(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                        const double p[2], double du, px_vec3_t *pts, px_vec3_t *o, px_vec3_t *d);

/** The parameters of the paraxial ray through point v (Eq. 7 inverted, or the exact projection
 *  for the root). PX_EMISS when v is not ahead of the model's origin, PX_ESINGULAR when
 *  G0 + s H is singular there (a focus). */
px_status_t bm_project(const bm_model_t *m, const bm_source_t *src, px_vec3_t v, double p[2]);

/** The paraxial ray of parameters p: origin *o and direction *d, with a unit component along the
 *  axial direction after faces (normalise it for a ray), the exact ray for the root. */
void bm_model_ray(const bm_model_t *m, const bm_source_t *src, const double p[2], px_vec3_t *o,
                  px_vec3_t *d);

/** Where the paraxial ray of parameters p meets the plane n . x = dd (the exact ray for the
 *  root); its depth in *s: along the axial direction after faces, along the source's z for the
 *  root (comparable between faces on one ray either way). PX_EMISS when it does not meet it
 *  ahead. */
px_status_t bm_model_hit(const bm_model_t *m, const bm_source_t *src, const double p[2],
                         px_vec3_t n, double dd, px_vec3_t *x, double *s);

/** The most spread (|xi|, in any segment of a path) the bound below allows: beyond it the
 *  transfers' third-order term is not bounded by BM_TRANSFER_K3 (beam.c). */
#define BM_SPREAD_CAP 0.5

/** An error bound of a beam's linear model and its parts (bm_model_bound()). */
typedef struct {
  double err;        /**< the bound on the distance between the model's and the exact ray's
                          points on the plane, for every ray of the polygon (world length) */
  double x0, xi0;    /**< the spread of Eq. (4): largest |x| and |xi| at the source */
  double c;          /**< the pencil constant C of Eq. (4) along the path and on to the plane */
  double second;     /**< e_x of Eq. (4) at (x0, xi0): the second-order position error */
  double third;      /**< the transfers' third-order position error */
  double conversion; /**< the position error of the linearised parameters-to-xi map (apex) */
} bm_bound_t;

/** The error of model m (along path) over parameter polygon r, where its rays meet the plane
 *  n . x = dd: the pencil constants A-F of Eq. (4) for the path's cascade and the transfer to
 *  the plane (Appendix (3) with the element coefficients of `variant`: PX_VARIANT_CORRECTED or
 *  the printed A-1, clamped at 0 where it goes negative), at the spread of r about the model's
 *  axial ray, plus what the second-order form leaves out: the transfers' third-order term, the
 *  linearised map from the source's parameters to ray coordinates, and the slide from the plane
 *  across the ray onto the plane (Eq. 3's surface, 1 / cos of the incidence on it). Zero for a
 *  root model (exact). PX_EMISS when the plane is not ahead, PX_EGRAZING when the axial ray
 *  skims it or an element is grazing, PX_ETIR, PX_EILLCOND when a segment's spread exceeds
 *  BM_SPREAD_CAP or an element's coefficients are ill-conditioned (px_error_coeffs()): a beam
 *  whose error cannot be bounded. */
px_status_t bm_model_bound(const bm_scene_t *b, const bm_source_t *src, const bm_path_t *path,
                           const bm_model_t *m, const px_poly2_t *r, px_vec3_t n, double dd,
                           px_variant_t variant, bm_bound_t *out);

/** Split polygon r in two across its longest extent (the farthest pair of vertices), through its
 *  centroid: how a beam whose model fails is divided. 0 when r has no centroid or a half would
 *  have fewer than 3 vertices. */
int bm_halve(const px_poly2_t *r, px_poly2_t half[2]);

/** One piece of a partition: a convex polygon of parameters and the face its rays meet first
 *  (-1: none). */
typedef struct {
  int face;
  px_poly2_t region;
} bm_piece_t;

/** A growable list of pieces (caller-owned; zero it first, bm_pieces_free() it last). */
typedef struct {
  bm_piece_t *p;
  int n, cap;
} bm_pieces_t;
void bm_pieces_free(bm_pieces_t *l);

/** Hidden-surface removal in parameter space (Heckbert and Hanrahan's beam tracing, with the
 *  projection of the model): `region` cut into convex pieces by the face each piece's rays meet
 *  first along the model's segment, appended to out. Every face ahead of the model's origin is
 *  projected (clipped first to the half-space ahead), and where two projections overlap the
 *  nearer at the overlap's centroid hides the other. The pieces tile the part of the region that
 *  meets a face (what meets none is not returned: its measure is the region's less the pieces');
 *  pieces of area
 *  at most `min_area` are returned with face -2 (slivers; the caller may trace them as rays).
 *  *unsure is set to 1 when a face ahead could not be projected (it straddles a focus), so that
 *  the partition may be wrong there. Only faces[0 .. nfaces-1] are considered when `faces` is not
 *  NULL (all faces otherwise). When `near` is not NULL (room for every face) it receives the
 *  faces whose projections come within half the region's size of it, *nnear of them: what a part
 *  of the region, divided off and partitioned again along the same path, needs to consider.
 *  RT_ENOMEM. */
rt_status_t bm_partition(const bm_scene_t *b, const bm_source_t *src, const bm_model_t *m,
                         const px_poly2_t *region, double min_area, const int *faces, int nfaces,
                         int *near, int *nnear, bm_pieces_t *out, int *unsure);

/** bm_partition() that gives up when more than max_faces faces (> 0) project into the region:
 *  then *crowded is 1, nothing is appended to out (the near list is complete), and the caller
 *  divides the region, whose parts meet fewer faces each; the partition's cost grows with the
 *  square of the faces it overlaps. */
rt_status_t bm_partition_capped(const bm_scene_t *b, const bm_source_t *src, const bm_model_t *m,
                                const px_poly2_t *region, double min_area, const int *faces,
                                int nfaces, int *near, int *nnear, bm_pieces_t *out, int *unsure,
                                int max_faces, int *crowded);

#endif
