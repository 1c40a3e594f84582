/* internal.h -- the light library's shared parts: the light's grid faces (source.c), the
 * transport of one light ray to the receiver (transport.c), and the deposits into the map
 * (deposit.c). */
#ifndef LIGHT_INTERNAL_H
#define LIGHT_INTERNAL_H

#include "core/plan.h"
#include "core/shade.h"
#include "light/illuminance.h"

/** Rows of grid-pencils made from one band of the grid's rays: the band's rays (LT_GRID_BAND + 1
 *  rows, about 3.6 KB a ray with its tree's arrivals) are all that is held at once. */
#define LT_GRID_BAND 128

/** Most receiver arrivals one source ray's tree may have; more are dropped and counted. */
#define LT_MAX_ARRIVALS 64

/** What an end of a light ray's tree is. */
enum { LT_END_RECEIVER = 0, LT_END_ESCAPED = 1, LT_END_ABSORBED = 2 };

/** One end of a light ray's tree: a path that reached the receiver (a path may go on after it,
 *  when the receiver reflects or transmits), one that left the scene, or the flux a surface kept
 *  (what its reflected and refracted children do not carry on, or all of it at the depth
 *  limit). Every unit of flux a ray carries ends in exactly one escape or absorption, so the
 *  two methods can keep a ledger of the flux. */
typedef struct {
  uint64_t sig; /**< the path: a hash of the (object, primitive, kind) of every segment and the
                     end's kind */
  int kind;     /**< LT_END_* */
  double u, v;  /**< receiver ends: where the path met the receiver, in its texture coordinates */
  rt_rgb_t w;   /**< the flux it carries per unit of the source's flux: the product of the
                     weights (kr, kt T, Fresnel) along the path, times what the surface kept for an
                     absorption */
} lt_arrival_t;

typedef struct {
  int n;
  lt_arrival_t a[LT_MAX_ARRIVALS];
} lt_arrivals_t;

/** One grid face of a light: a point light's square of directions through z + a x + b y
 *  (a, b in [-h, h]), or a parallel light's square of origins c + a x + b y (a in [-hx, hx], b in
 *  [-hy, hy]) behind the scene, travelling along z. */
typedef struct {
  int parallel;
  px_vec3_t origin; /**< point: the light; parallel: the grid's centre */
  px_vec3_t x, y, z;
  double hx, hy;     /**< half sides (tangents for a point light) */
  rt_rgb_t power;    /**< the light's intensity I */
  px_vec3_t lambert; /**< a Lambertian emitter's unit normal (an area light's mesh point): the
                          intensity is power times max(0, cos) of the ray's angle to it
                          (lt__face_weight()); zero for an isotropic source */
  px_vec3_t step[2]; /**< an area light's mesh point: the source's move to its neighbours along
                          each edge (edge / mesh), for the shift vectors of the 1989 Eqs. (9)-(10);
                          zero otherwise */
  double ior;        /**< the index of the medium its rays start in (rt_medium_ior() at a point
                          light or mesh point: a lamp inside a glass globe; the scene's for a
                          parallel light, which starts behind everything) */
} lt_face_t;

/** Faces of light l that cover every ray that can reach the receiver's map (at most 6); 0 when
 *  none can. For an area light, the faces of its mesh point `sub` of mesh x mesh (row-major):
 *  a Lambertian point source at the mesh cell's centre with its share of the intensity; with
 *  `spread` (the area filter) the targets grow by the mesh cell's size, so that the faces hold
 *  every direction the cell's other points need (their rays are the centre's, shifted). */
int lt__faces(const rt_scene_t *s, const lt_receiver_t *r, const lt_map_t *m, int l, int sub,
              int mesh, int spread, lt_face_t out[6]);

/** The intensity weight of the ray of grid parameters (a, b) of face f: 1 for an isotropic
 *  source, max(0, cos) of its angle to f->lambert for a Lambertian one. */
double lt__face_weight(const lt_face_t *f, double a, double b);

/** Point sources light l is traced as: mesh x mesh for an area light, else 1. */
static inline int lt__subsources(const rt_scene_t *s, int l, int mesh) {
  return s->light[l].kind == RT_LIGHT_AREA ? mesh * mesh : 1;
}

/** The ray of grid parameters (a, b) in [0, 1]^2 of face f. */
rt_ray_t lt__face_ray(const lt_face_t *f, double a, double b);

/** The source measure (solid angle, or area across the beam) of the triangle of face parameters
 *  p0, p1, p2 (each [a, b]). */
double lt__face_measure(const lt_face_t *f, const double p0[2], const double p1[2],
                        const double p2[2]);

/** The transport context of one thread. */
typedef struct {
  const rt_scene_t *s;
  rt_plan_t plan;
  const lt_receiver_t *r;
  lt_stats_t st;
  int indirect; /**< lt_options_t.indirect: no receiver ends at depth 0 */
} lt_ctx_t;

/** a += b, every counter and flux of the stats (the seconds excepted). */
void lt__stats_add(lt_stats_t *a, const lt_stats_t *b);

/** Trace a light ray and collect its tree's arrivals on the receiver (out->n set). */
void lt__trace(lt_ctx_t *C, const rt_ray_t *ray, lt_arrivals_t *out);

/** lt__trace() for a ray that is already generation `depth` of its tree and carries weight w
 *  (a beam's ray after its path; the arrivals' weights include w). */
void lt__trace_from(lt_ctx_t *C, const rt_ray_t *ray, rt_rgb_t w, int depth, lt_arrivals_t *out);

/** A thread's accumulation: flux per cell (R, G, B). */
typedef struct {
  const lt_map_t *m;
  double *flux; /**< 3 W H */
  lt_stats_t *st;
} lt_accum_t;

/** Deposit flux `phi` at (u, v) (a photon). */
void lt__deposit_point(lt_accum_t *A, double u, double v, rt_rgb_t phi);

/** Deposit flux `phi` spread evenly over the convex receiver polygon uv[0 .. n-1] (a fan of
 *  triangles, each with its share of the area). */
void lt__deposit_polygon(lt_accum_t *A, const double (*uv)[2], int n, rt_rgb_t phi);

/** Deposit the illuminance of a polygon by Gouraud interpolation (the 1989 paper's illuminance
 *  polygons): the fan of triangles (c, uv[k], uv[k+1]) of the convex receiver polygon uv[0 ..
 *  n-1] about c, E linear over each from ec at c and e[k] at the vertices, times colour w; each
 *  cell takes the exact integral over its part. The flux deposited is the integral of E. */
void lt__deposit_gouraud(lt_accum_t *A, const double (*uv)[2], const double *e, int n,
                         const double c[2], double ec, rt_rgb_t w);

/** Settle the flux phi of end a: a receiver end deposited at its point (counted as a photon when
 *  `photon`), an escape or an absorption entered in the ledger of A->st. */
void lt__settle(lt_accum_t *A, const lt_arrival_t *a, rt_rgb_t phi, int photon);

/** Deposit flux `phi` spread evenly over the receiver triangle (u, v)[3] (exact coverage of the
 *  cells); a triangle of zero area deposits at its centroid. */
void lt__deposit_triangle(lt_accum_t *A, const double uv[3][2], rt_rgb_t phi);

/** The illuminance polygons of one tile of a grid face: the beams of parameter square
 *  [x0, x1] x [y0, y1] (tangents for a point light, positions across a parallel beam; the face's
 *  own units) traced through the planar faces `faces` (a bm_scene_t), deposited in A. */
void lt__polygons_tile(lt_ctx_t *C, lt_accum_t *A, const lt_options_t *o, const void *faces,
                       const lt_face_t *f, const double box[4]);

#endif
