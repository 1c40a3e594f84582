/* illuminance.h -- illuminance maps: the light that point and parallel sources deliver to a
 * receiver surface directly and through chains of specular reflections and refractions (1989
 * paper, section 2.2; 1987 paper, section 4.2), by one of the methods of the 1989 paper's
 * Table 1:
 *  - photons: backward ray tracing (Arvo 1986; 1989 Eqs. 3-4): rays leave the source on a grid,
 *    each carrying the flux of its share of the source, and the flux arriving in each cell of
 *    the map is counted;
 *  - grid-pencil tracing (1989 section 2.2.3): the same grid, every two neighbouring rays and a
 *    diagonal one the edges of a pencil whose triangle on the receiver carries the pencil's flux
 *    (Eq. 7: E = t_r I delta omega0 / delta S); triangles whose edge rays do not follow the same
 *    path are divided, down to a limit below which their rays count as photons;
 *  - polygons: pencil tracing of polyhedra (1987 section 4.2, 1989 section 2.2.2): the light's
 *    beams cut at the edges of the planar faces they meet (beam/beam.h) and carried through
 *    them by system matrices; a piece on the receiver is an illuminance polygon x'_i = B xi_i.
 * The receiver is a plane object or polygons in one plane; a cell (i, j) of a W x H map covers [u0
 * + i du, u0 + (i+1) du] x [v0 + j dv, v0 + (j+1) dv] in the receiver's coordinates
 * (lt_receiver_t). E is flux per unit area in the scene's units (a parallel light of intensity I
 * gives I cos(alpha) on an unobstructed receiver, a point light I cos(alpha) / r^2), counted on
 * either side of the receiver, in R, G and B.
 *
 * Prefix lt_. Above core/ (scene, BVH, shading's reflected and refracted rays): the light is
 * carried by the same rt_shade_children() as the renderers' rays, so kr, kt, transmittance
 * colours, Fresnel and total internal reflection are the renderers'. */
#ifndef LIGHT_ILLUMINANCE_H
#define LIGHT_ILLUMINANCE_H

#include <stdint.h>

#include "core/caustics.h"
#include "core/scene.h"

typedef enum {
  LT_METHOD_GRID_PENCIL = 0, /**< grid-pencil tracing (default) */
  LT_METHOD_PHOTONS = 1,     /**< backward ray tracing: photon counting */
  LT_METHOD_POLYGONS = 2     /**< pencil tracing of polyhedra: illuminance polygons */
} lt_method_t;

/** "grid-pencil" / "photons" / "polygons"; -1 for another name. */
int lt_method_parse(const char *name);
const char *lt_method_name(lt_method_t m);

/** RT_OK when method m can trace scene s; RT_EINVAL with the reason in why[cap] otherwise (the
 *  polygons method needs planar faces, a sphere is refused by name, and point or parallel
 *  lights: an area light is refused). */
rt_status_t lt_method_check(const rt_scene_t *s, lt_method_t m, char *why, size_t cap);

/** The polygons method starts from LT_POLYGON_TILES x LT_POLYGON_TILES beams per grid face of a
 *  light (the units of work shared among threads). */
#define LT_POLYGON_TILES 8

/** The map: W x H cells over [u0, u1] x [v0, v1] of the receiver's texture coordinates; e holds
 *  3 W H values, R, G, B of cell (i, j) at 3 (j W + i). */
typedef struct {
  int width, height;
  double u0, u1, v0, v1;
  double *e;
} lt_map_t;

/** Allocate a zeroed map; RT_EINVAL for a size outside 1..LT_MAX_GRID or an empty extent,
 *  RT_ENOMEM. */
rt_status_t lt_map_alloc(lt_map_t *m, int width, int height, double u0, double u1, double v0,
                         double v1);
void lt_map_free(lt_map_t *m);

/** Largest side of a map and of the source's ray grid. */
#define LT_MAX_GRID 16384

/** Most objects one receiver may join. */
#define LT_MAX_RECEIVERS 16

/** A receiver: objects in one plane, and the plane's coordinates. A plane object lends its
 *  texture axes (origin its point, u its u axis, v = normal x u); otherwise the first polygon
 *  does: origin its first vertex, u along its first edge, v = normal x u. */
typedef struct {
  int object[LT_MAX_RECEIVERS]; /**< object indices */
  int n;
  px_vec3_t p, normal, u, v; /**< origin, unit normal, unit axes */
} lt_receiver_t;

/** The receiver of objects obj[0 .. n-1] (planes and polygons, all in one plane within 1e-9 of
 *  the scene's size). RT_EINVAL with the reason in why[cap] for another kind of object (a
 *  sphere, a polyhedron), objects not in one plane, n outside 1..LT_MAX_RECEIVERS. */
rt_status_t lt_receiver_make(const rt_scene_t *s, const int *obj, int n, lt_receiver_t *r,
                             char *why, size_t cap);

typedef struct {
  lt_method_t method;
  int light;          /**< index of the one light to trace, or -1 for all */
  int side;           /**< rays per side of the source's grid (side x side per grid face), >= 2;
                           not used by the polygons method */
  int max_split;      /**< grid-pencil: times a pencil may be divided (each into four); polygons:
                           a beam may be halved 2 x max_split times along its path */
  double linear_tol;  /**< grid-pencil: a pencil near the map is divided when an edge's midpoint
                           ray lands more than this many cells off the midpoint of its corners'
                           landings (0: no test, the 1989 paper's plain grid-pencil tracing) */
  double uniform_tol; /**< ... or when the flux density of a quarter of it (the midpoints' four
                           triangles) differs from the whole's by more than this share, or a
                           quarter is turned over (0: no such test; needs linear_tol > 0) */
  int threads;        /**< OpenMP threads; 0 = the default */
  void (*progress)(void *ctx, int done, int total);
  void *progress_ctx;
  int indirect;    /**< 1: only light that met at least one other surface before the receiver (a
                        caustic map: the renderer's shadow rays give the direct light) */
  int area_mesh;   /**< an area light is traced as area_mesh x area_mesh Lambertian point sources
                        at its mesh cells' centres (1989 section 2.3), 1..LT_MAX_AREA_MESH */
  int area_filter; /**< grid-pencil, area lights: an lt_area_filter_t, how each mesh point's
                        light is spread over its mesh cell by the space-variant filter of the
                        1989 Eqs. (9)-(12) (LT_AREA_FILTER_NONE sums the mesh points' maps as
                        they are) */
} lt_options_t;

/** The space-variant filter of an area light's mesh points (1989 Eqs. 9-12): each pencil's
 *  light spread over the positions of the source in the point's mesh cell, moved by its centre
 *  ray's displacement (the ray's direction fixed, as the paper's shift vectors Delta_I, Delta_J
 *  have it), the displacement interpolated over the cell. */
typedef enum {
  LT_AREA_FILTER_NONE = 0,      /**< no filter: the mesh points' maps summed as they are */
  LT_AREA_FILTER_QUADRATIC = 1, /**< the biquadratic patch of the displacements from 3 x 3
                                     points of the cell (this project's form) */
  LT_AREA_FILTER_LINEAR = 2     /**< the printed Eq. (10), linear in the move: the bilinear patch
                                     of the corners' displacements; drifts light outwards where
                                     the landing is curved in the source's position */
} lt_area_filter_t;

/** "none" / "quadratic" / "linear"; -1 for another name. */
int lt_area_filter_parse(const char *name);
const char *lt_area_filter_name(lt_area_filter_t f);

/** Largest side of an area light's mesh. */
#define LT_MAX_AREA_MESH 256

#define LT_OPTIONS_DEFAULT                                                                         \
  { LT_METHOD_GRID_PENCIL, -1, 129, 6, 0.05, 0.02, 0, NULL, NULL, 0, 8, 0 }

typedef struct {
  uint64_t rays;        /**< source rays traced (grid points and division points) */
  uint64_t segments;    /**< ray segments traced (every reflection and refraction) */
  uint64_t arrivals;    /**< ray paths that reached the receiver (an arrival of each pass) */
  uint64_t pencils;     /**< receiver triangles deposited as pencils (grid-pencil) */
  uint64_t folded;      /**< ... of which turned over (past a caustic): deposited, not dropped */
  uint64_t divided;     /**< pencil divisions (grid-pencil) */
  uint64_t nonlinear;   /**< ... of which for a receiver triangle not linear enough */
  uint64_t photons;     /**< arrivals deposited as photons (photons; grid-pencil at the limit) */
  uint64_t lost;        /**< ends of rays' trees dropped because a tree had too many */
  uint64_t filtered;    /**< area filter: pencils spread along their shift vectors */
  uint64_t unshifted;   /**< ... deposited as they are: their own centre ray left the path */
  uint64_t resampled;   /**< ... whose displacements were traced from n x n points of the mesh
                             cell: the patch could not be trusted (a landing far off it, or
                             the centre ray leaving the path from a point of the cell) */
  double flux_emitted;  /**< flux the traced grid covers (mean of R, G, B; scene units) */
  double flux_map;      /**< flux deposited inside the map */
  double flux_outside;  /**< flux that reached the receiver outside the map */
  double flux_escaped;  /**< flux that left the scene */
  double flux_absorbed; /**< flux that surfaces kept (the receiver's included) or the depth
                             limit stopped; escaped + absorbed = emitted, less what `lost` lost */
  double seconds;       /**< wall-clock time */
} lt_stats_t;

/** The illuminance map of receiver r of the prepared scene s into m (zeroed first). RT_EINVAL
 *  for an empty receiver, a light index out of range, or options out of range; RT_ENOTREADY for
 *  an unprepared scene; RT_ENOMEM. */
rt_status_t lt_illuminance(const rt_scene_t *s, const lt_receiver_t *r, const lt_options_t *o,
                           lt_map_t *m, lt_stats_t *st);

/** How lt_caustic_maps() makes a render's maps. */
typedef struct {
  lt_method_t method; /**< the renderer's: photons for the exact one, grid-pencil for pencils */
  int side;           /**< rays per side of each light's grid faces (not for polygons), >= 2 */
  int cells;          /**< cells along the longer side of each map, 1..LT_MAX_GRID */
  int threads;        /**< OpenMP threads; 0 = the default */
  void (*progress)(void *ctx, int done, int total); /**< after each map; may be NULL */
  void *progress_ctx;
  int area_filter; /**< an area light's filter (lt_area_filter_t; grid-pencil only; the
                        renderers pass none), its mesh the light's own N x N sample points
                        (rt_light_t.samples), each with side / N rays a side (at least 33 for
                        grid-pencils, 17 for photons) and grid-pencils divided log2(N) levels
                        less deep (at least 2) */
} lt_caustic_options_t;

/** What lt_caustic_maps() did, summed over its maps. */
typedef struct {
  int maps;            /**< maps made (planes times lights) */
  int empty;           /**< ... of which no light reached */
  int unmapped;        /**< receiver planes left out: a plane without bounded objects to map
                            around (lt_default_extent() has none); they keep the textbook shadow */
  lt_stats_t st;       /**< the maps' counters, summed (seconds: the whole) */
  double flux_outside; /**< share of the light reaching receiver planes that fell beside the maps
                            (lost to the image: a wider extent or more cells would keep it) */
} lt_caustic_stats_t;

/** The maps of plan cp (rt_plan_t.caustic) for the prepared scene s into *out (released with
 *  rt_caustic_maps_free()): for each receiver plane its default extent (lt_default_extent()),
 *  and for each mapped light the light that reaches the plane after at least one reflection or
 *  refraction (lt_options_t.indirect), by o->method with the illuminance options' defaults.
 *  RT_EINVAL with the reason in why[cap] (receiver objects not in one plane, a method that
 *  cannot trace the scene, options out of range); RT_ENOMEM. */
rt_status_t lt_caustic_maps(const rt_scene_t *s, const rt_caustic_plan_t *cp,
                            const lt_caustic_options_t *o, rt_caustic_maps_t *out,
                            lt_caustic_stats_t *st, char *why, size_t cap);

/** The memory lt_caustic_maps() needs at its peak for plan cp and options o, in bytes: every map
 *  kept (at most o->cells squared, three doubles a cell), each thread's accumulator of one map,
 *  and for grid-pencils the traced rays of one band of 129 rows of a light's grid (a mesh
 *  point's for an area light), each with its tree's arrivals. For a render's memory check
 *  before the maps are made. */
size_t lt_caustic_bytes(const rt_scene_t *s, const rt_caustic_plan_t *cp,
                        const lt_caustic_options_t *o);

/** The default extent of a receiver's map: the bounds of its polygons in (u, v) when it has only
 *  polygons; with a plane, a square around the projection of the scene's other bounded objects
 *  (their bounding box) onto the plane, twice its larger side, so that their shadows and
 *  caustics under lights not too low fall inside. 0 when there is neither (the caller must give
 *  an extent). */
int lt_default_extent(const rt_scene_t *s, const lt_receiver_t *r, double ext[4]);

/** The extent of light `light`'s map on receiver r, as a render's caustic maps have it: with
 *  polygons only, theirs (lt_default_extent()); with a plane, lt_default_extent()'s square widened
 *  to the shadows the other bounded objects' bounding boxes cast from the light (an area light's
 *  four corners, a parallel light's direction) and a quarter of their size more on each side,
 *  so that light a lens spreads past a shadow's edge falls inside; at most 8 times the square's
 *  half-side from its centre along each axis, where a low light's shadows run far. 0 as
 *  lt_default_extent(). */
int lt_light_extent(const rt_scene_t *s, const lt_receiver_t *r, int light, double ext[4]);

#endif
