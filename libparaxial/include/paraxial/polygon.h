/* polygon.h -- convex polygons in a plane of ray parameters (the xi-space of a pencil, or any 2-D
 * parameter space of a bundle of rays): the clipping that pencil tracing of polyhedra needs when
 * it divides a pencil at the edges of a polygon mapped into that space (1987 paper, section 4.2;
 * 1989 paper, section 2.2.2: "pencils are divided at polygon edges mapped into xi-space by
 * B^-1"), and that beam tracing needs for its beams (1987 section 4.1 (3)).
 *
 * Every polygon here is convex and counter-clockwise (positive signed area); the operations keep
 * it so: a convex polygon clipped by a half-plane or another convex polygon stays convex, and
 * the part of it outside a convex polygon is returned as convex pieces, one per edge of the clip
 * polygon at most. Values in caller-owned structs; nothing allocates.
 */
#ifndef PARAXIAL_POLYGON_H
#define PARAXIAL_POLYGON_H

#include "paraxial/linalg.h"
#include "paraxial/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most vertices a polygon holds. A convex n-gon clipped by a half-plane has at most n + 1. */
#define PX_POLY_MAX 32

/** A convex, counter-clockwise polygon: v[0 .. n-1], (x, y) each. */
typedef struct {
  int n;
  double v[PX_POLY_MAX][2];
} px_poly2_t;

/** Signed area (shoelace formula, about the first vertex so that an offset polygon loses no
 *  digits): positive for a counter-clockwise polygon, 0 for fewer than 3 vertices. */
double px_poly2_area(const px_poly2_t *p);

/** Centroid of the polygon's area; PX_ESINGULAR when the area is not positive. */
px_status_t px_poly2_centroid(const px_poly2_t *p, double c[2]);

/** 1 when p has >= 3 vertices, all finite, is counter-clockwise and convex (no turn to the right
 *  beyond rounding: a cross product of consecutive edges below -1e-12 of their lengths'
 *  product), 0 otherwise. */
int px_poly2_is_convex(const px_poly2_t *p);

/** The parts of p where a x + b y <= c (*in) and >= c (*out); either pointer may be NULL. A
 *  part that is empty has n = 0. PX_ECAPACITY when a part would exceed PX_POLY_MAX vertices
 *  (p with PX_POLY_MAX already); PX_EINVAL for a, b, c not finite or a = b = 0. */
px_status_t px_poly2_split(const px_poly2_t *p, double a, double b, double c, px_poly2_t *in,
                           px_poly2_t *out);

/** p inside the convex counter-clockwise polygon `clip` (Sutherland-Hodgman over clip's edges);
 *  n = 0 when they do not overlap. PX_ECAPACITY, PX_EINVAL as px_poly2_split(). */
px_status_t px_poly2_intersect(const px_poly2_t *p, const px_poly2_t *clip, px_poly2_t *out);

/** p outside `clip`, as convex pieces out[0 .. *count-1]: piece k is the part of p beyond clip's
 *  edge k and within its edges before k, so the pieces and p inside clip tile p. Pieces of area
 *  at most `min_area` are dropped (slivers a clip edge grazing p leaves). PX_ECAPACITY when more
 *  than `cap` pieces remain or a piece would exceed PX_POLY_MAX vertices. */
px_status_t px_poly2_subtract(const px_poly2_t *p, const px_poly2_t *clip, double min_area,
                              px_poly2_t *out, int cap, int *count);

/** The image of p under x -> m x + off, counter-clockwise again (the order is reversed when
 *  det m < 0). */
px_poly2_t px_poly2_map(const px_poly2_t *p, px_mat2_t m, const double off[2]);

#ifdef __cplusplus
}
#endif

#endif
