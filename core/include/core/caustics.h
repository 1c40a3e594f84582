/* caustics.h -- light through specular and transparent objects in shading (issue 25): which
 * receivers and lights the effects plan maps (rt_caustic_plan_t), and the illuminance maps a
 * renderer makes for them before it traces (rt_caustic_maps_t, filled by light/'s
 * lt_caustic_maps()).
 *
 * With caustics on, a diffuse surface that is a mapped receiver of light l is lit by l in two
 * parts that do not overlap:
 *  - directly, where its shadow ray towards l meets nothing at all (rt_shadow_t.opaque): a
 *    transparent object in the way blocks it instead of attenuating it by kt, as the textbook's
 *    shadow ray does;
 *  - through the scene's reflecting and refracting objects, by the map of the light that reached
 *    the receiver after at least one reflection or refraction: E (flux per unit area, R, G, B),
 *    which adds kd colour E to the diffuse term (the 1987 paper's Eq. 8 when the maps come from
 *    pencils; 1989 section 2: the maps as shading).
 * The textbook's attenuated straight shadow ray through glass is thereby replaced, not added to.
 * A map does not say from which side light arrived or from which direction, so the map's light
 * has no specular (Phong) term and is added on whichever side the surface is seen from.
 *
 * Maps are physical (a point light's E falls as 1 / r^2), so only lights whose shading is
 * physical too are mapped: parallel lights and point lights with the inverse-square fall-off.
 * Receivers are planes and polygons with a diffuse term, grouped by the plane they lie in (one
 * map per plane and light). Prefix rt_caustic. */
#ifndef CORE_CAUSTICS_H
#define CORE_CAUSTICS_H

#include "core/scene.h"

/** Most receiver planes the plan maps, and objects one plane may join. */
#define RT_CAUSTIC_MAX_PLANES 8
#define RT_CAUSTIC_MAX_JOIN 16

/** What the plan found: receiver planes and lights to map, and what it left out and why. */
typedef struct {
  int nplane;                                             /**< receiver planes mapped */
  int object[RT_CAUSTIC_MAX_PLANES][RT_CAUSTIC_MAX_JOIN]; /**< their objects */
  int nobject[RT_CAUSTIC_MAX_PLANES];
  unsigned lights; /**< bit l: light l is mapped (lights 0..31) */
  int via;         /**< the first reflecting or transparent object, -1 when none */
  int unmapped;    /**< the first diffuse object that cannot be a receiver (a sphere or a
                        polyhedron) or did not fit, -1 when none; it keeps the textbook shadow */
  int nunmapped;   /**< how many such objects */
  int unphysical;  /**< the first light left out (a point light without fall-off), -1 */
} rt_caustic_plan_t;

/** The receivers and lights scene s would map when light can reach a diffuse surface through a
 *  reflecting or transparent object (by materials; geometry is the maps' business): fills *cp
 *  and returns the number of planes times lights mapped (0: nothing to map). */
int rt_caustic_plan(const rt_scene_t *s, rt_caustic_plan_t *cp);

/** One map: the light one receiver plane receives from one light after at least one reflection
 *  or refraction. Cell (i, j) of W x H covers [u0 + i du, u0 + (i+1) du] x [v0 + j dv, ...] in
 *  the plane's coordinates (origin p, unit axes u, v); e holds R, G, B of cell (i, j) at
 *  3 (j W + i). */
typedef struct {
  int light, plane; /**< the light, and the receiver plane (index into rt_caustic_plan_t) */
  px_vec3_t p, u, v;
  int width, height;
  double u0, v0, du, dv;
  double *e;   /**< owned by the maps; NULL when the light delivered nothing to the map (the
                    receiver is still mapped: its shadow rays towards the light are opaque) */
  double emax; /**< the largest value of any channel of any cell */
} rt_caustic_map_t;

/** The maps of a render, made by the renderer before it traces (lt_caustic_maps()) and passed
 *  to shading through rt_plan_t.maps. */
typedef struct rt_caustic_maps {
  int nobject, nlight;
  int *plane; /**< per object: its receiver plane, -1 when it has none */
  int *index; /**< per plane and light, index[plane * nlight + light]: its map, -1 for none
                   (the light is not mapped, or delivered nothing there) */
  int n;
  rt_caustic_map_t *map;
} rt_caustic_maps_t;

/** Release what the maps own (the struct itself is the caller's). */
void rt_caustic_maps_free(rt_caustic_maps_t *m);

/** The map of light l on object `object`, or NULL when the object is not a receiver of l. */
static inline const rt_caustic_map_t *rt_caustic_map_of(const rt_caustic_maps_t *m, int object,
                                                        int l) {
  int g = m->plane[object];
  if (g < 0)
    return NULL;
  int k = m->index[g * m->nlight + l];
  return k >= 0 ? &m->map[k] : NULL;
}

/** E at point p of the map's plane: bilinear between cell centres (each cell's value its mean
 *  illuminance), constant beyond the outer centres, black outside the map and for an empty map. */
rt_rgb_t rt_caustic_at(const rt_caustic_map_t *c, px_vec3_t p);

/** The largest E (any channel) over the cells within [ulo, uhi] x [vlo, vhi] of the map's
 *  plane, and the smallest (*lo); both 0 when the box misses the map. */
double rt_caustic_range(const rt_caustic_map_t *c, double ulo, double uhi, double vlo, double vhi,
                        double *lo);

#endif
