/* edge.h -- the smoothness condition of the pencil tracer (paper section 4.1 (1), step 3): "the
 * smoothness condition is roughly checked by comparing the ray trees among the neighboring
 * domains", and a guard against "an object smaller than the initial domain area ... vanish[ing]
 * from the image" by "estimating the distances between an axial ray and object surfaces, as in
 * the case of ray tracing with cones".
 *
 * Trees are compared on what bends or blocks rays: shape, surfaces (object and primitive), flags
 * and light visibility. Checker squares are not compared (rt_tree_same() does compare them): a
 * texture changes colour, not the path of a ray, so a pencil stays valid across it; the colour is
 * looked up at each sample's own hit point (docs/pencil.md).
 *
 * Corner trees are kept in a compact form (pt_ctree_t) so that a domain can cache the trees of
 * its corner lattice. Nothing allocates.
 */
#ifndef PENCIL_EDGE_H
#define PENCIL_EDGE_H

#include <stdint.h>

#include "core/raytree.h"
#include "core/scene.h"

/** What the comparison looks at, per node. */
typedef struct {
  int32_t parent, object, prim;
  uint32_t lit, blocked, through;
  uint8_t kind, flags;
} pt_cnode_t;

/** A compact ray tree over a caller-owned node array. */
typedef struct {
  pt_cnode_t *node;
  int cap, n;
  int valid; /**< 0: not traced yet, or the tree overflowed (never equal to anything) */
} pt_ctree_t;

/** Copy the comparison fields of `t` into c (c->cap must be >= t->n; else c->valid = 0). */
void pt_ctree_from(pt_ctree_t *c, const rt_tree_t *t);

/** 1 when the trees have the same shape, surfaces, flags and light visibility (checker squares
 *  ignored); 0 when they differ or either overflowed. */
int pt_tree_same_paths(const rt_tree_t *a, const rt_tree_t *b);
/** The same between a full tree and a compact one. */
int pt_ctree_same(const rt_tree_t *a, const pt_ctree_t *b);

/** 1 when the primary rays of two compact trees met the same surface and primitive with the
 *  same flags (node 0 of both; two empty trees agree, an invalid one agrees with nothing). */
int pt_ctree_same_root(const pt_ctree_t *a, const pt_ctree_t *b);

/** Node-by-node agreement of tree `a` (the cell's axial tree) with `nc` compact trees (its
 *  corners), each node of a followed in them along its path (the kinds of rays from the root):
 *  agree[k] = 1 when node k and all its ancestors met the same object and primitive with the
 *  same flags in every tree; light[k] = the lights (bit l, l < 32) whose visibility bits at node
 *  k are the same in every tree and, where both reach lights through glass, whose transmittances
 *  are too (rt_tree_node_t.through: where both are set and differ, the lights neither lit nor
 *  blocked at both drop out; a node that reaches no light partly is not compared, as before); 0
 *  where agree[k] is 0. Returns 1 when every node agrees with all its lights and the trees have
 *  the same size (the cell is free of edges). `map` is scratch for nc * a->n ints. A tree that
 *  overflowed agrees nowhere. */
int pt_tree_agree(const rt_tree_t *a, const pt_ctree_t *const *c, int nc, int *map, uint8_t *agree,
                  uint32_t *light);

/** A bounding sphere of a bounded object, and what its shadow is at least as wide as: a ball
 *  (w > 0, n zero) or a disc (n its unit normal) of radius w about `in` that the object holds.
 *  w 0: nothing known (the object may be thin anywhere). A sphere's is itself. */
typedef struct {
  px_vec3_t c;
  double r;
  int object;
  px_vec3_t in; /**< centre of the ball or disc held */
  double w;     /**< its radius */
  px_vec3_t n;  /**< a disc's unit normal; zero for a ball */
  int prim;     /**< the polygon it bounds (pt_guards_of_faces()); -1 about a whole object */
} pt_bsphere_t;

/** A bounded sphere (c, r) of `object` that is itself the object: a ball of radius r inside. */
static inline pt_bsphere_t pt_bsphere_ball(px_vec3_t c, double r, int object) {
  return (pt_bsphere_t){c, r, object, c, r, {0.0, 0.0, 0.0}, -1};
}

/** Bounding spheres of the scene's bounded objects (spheres exactly; polygons and polyhedra
 *  around their bounding boxes) into out[cap], each with what it holds: a sphere itself; a
 *  convex polyhedron the ball about its vertices' centroid that touches its nearest face; a convex
 *  polygon the disc about its vertices' centroid that touches its nearest edge; a non-convex one
 *  nothing (w 0). Returns how many were written (s->nobject is always enough). */
int pt_guard_spheres(const rt_scene_t *s, pt_bsphere_t *out, int cap);

/** A node of the guards' hierarchy: a sphere holding every sphere below it; a leaf holds
 *  spheres first .. first + count - 1, an inner node (count 0) the nodes `first` and `first + 1`.
 */
typedef struct {
  px_vec3_t c;
  double r;
  int first, count;
} pt_gnode_t;

/** The guard's bounding spheres and a hierarchy of spheres over them, so that each query below
 *  visits the spheres near its pencil, not all of them: the guard's cost does not grow with the
 *  number of objects that are nowhere near. A query answers exactly as a scan over every sphere
 *  would (an inner node is skipped only when no sphere inside it can make the query fire, with a
 *  margin for rounding). */
typedef struct {
  pt_bsphere_t *b;  /**< the spheres, in the hierarchy's order */
  int n;            /**< their number */
  pt_gnode_t *node; /**< the hierarchy; node 0 is the root (none when n is 0) */
  int nnode;        /**< nodes; 0 with n > 0: the spheres are scanned one by one (a reference
                         for the hierarchy's tests) */
  int *across;      /**< the faces' guards (pt_guards_of_faces()): per vertex slot of the scene,
                         the primitive across the edge from that vertex of its polygon to the
                         next, for the faces of polyhedra that are not convex; -1 elsewhere;
                         NULL when there are none */
} pt_guards_t;

/** The guards of n spheres b (copied); 0 when out of memory (g then empty). */
int pt_guards_make(const pt_bsphere_t *b, int n, pt_guards_t *g);
/** The guards of the scene's bounded objects (pt_guard_spheres); 0 when out of memory. */
int pt_guards_of_scene(const rt_scene_t *s, pt_guards_t *g);
void pt_guards_free(pt_guards_t *g);

/** The small-object guard for primary rays: 1 when the silhouette of some bounding sphere may
 *  cross the cone of directions from `eye` with unit axis `axis` and half-angle `half` (radians),
 *  i.e. the sphere's angular disk neither misses the cone nor contains it. Such a cone may hold
 *  an object, or part of one, that none of its traced rays met. */
int pt_guard_fires(const pt_guards_t *g, px_vec3_t eye, px_vec3_t axis, double half);

/** The guards of the scene's polygons, one by one (a face of a polyhedron, or a polygon object):
 *  the sphere about each polygon's vertices, with `prim` its primitive, `object` its object, and
 *  w 1 when that object hides nothing of itself (one polygon, or a polyhedron that `objects`, the
 *  scene's guards, find convex), else 0; 0 when out of memory. For pt_guard_view(). */
int pt_guards_of_faces(const rt_scene_t *s, const pt_guards_t *objects, pt_guards_t *g);

/** The guard of what a domain's primary rays see: 1 when a ray of the pyramid from `eye` through
 *  the domain's corner directions d[0..3] (in order around it; `axis` and `half` a cone that
 *  holds them, as for pt_guard_fires()) may meet something before primitive `prim`, which every
 *  corner ray met first (-1: every one met nothing), though no corner ray did:
 *  - the silhouette of an object's bounding sphere crossing the cone (`objects`, as
 *    pt_guard_fires(), which alone is exact for spheres only);
 *  - a polygon of `faces` other than `prim` that reaches into the pyramid in front of `prim`:
 *    before its plane for a polygon or a plane, nearer than the farthest corner's hit along
 *    `axis` for a sphere the eye is outside of, anywhere ahead for nothing or a sphere about
 *    the eye; the polygon clipped by those half-spaces, the pyramid grown and the front shrunk
 *    by 1e-9 of the distance from the eye. A corner ray met `prim` first, so a face that meets
 *    it only at `prim`'s plane (one sharing an edge) hides nothing;
 *  - the boundary of `prim` itself inside the pyramid, when `prim` is a polygon that is not
 *    convex (a notch between the corners).
 *  A thin object (a rod, a plate seen edge-on, a comb's fins) whose bounding sphere's disk holds
 *  the whole cone, and a non-convex object's own faces, slip between the corners unseen by the
 *  bounding spheres; they do not slip past this. A polygon that would have more than 256
 *  vertices at some step of the clip fires whenever its sphere meets the pyramid. */
int pt_guard_view(const pt_guards_t *objects, const pt_guards_t *faces, const rt_scene_t *s,
                  px_vec3_t eye, const px_vec3_t d[4], px_vec3_t axis, double half, int prim);

/** The guard of the shadow an object casts on itself, which pt_guard_shadow() leaves out (it
 *  skips the hit's own object): 1 when an edge of the silhouette, seen from `light`, of the object
 *  that polygon `prim` belongs to, a polyhedron that is not convex, passes through the pencil of
 *  shadow rays from within `r` of p (on `prim`) towards the light, on the light's side of
 *  `prim`'s plane. Its faces are thin as far as the guard knows, so the gap between the traced
 *  points does not enter. The pencil: a square prism about the ray to a parallel light (from r
 *  behind p), a square pyramid about the cone to a point light (between the light and r beyond
 *  p), each holding the round pencil; the silhouette: the edges between a face that faces the light
 *  and one that does not (`faces->across`; an edge with nothing across counts). The light's side
 *  is the outside or, for a hit from within a transparent object, the inside. 0 for any other
 *  primitive, or when the light lies in `prim`'s plane. */
int pt_guard_self_shadow(const pt_guards_t *faces, const rt_scene_t *s, int prim, px_vec3_t p,
                         double r, const rt_light_t *light);

/** The guard of a non-convex polyhedron's own faces for a secondary segment, which
 *  pt_guard_segment() leaves out (it skips the objects the segment joins): 1 when a face of the
 *  object of polygon `prim_a` (where the segment starts, at p) or `prim_b` (where it ends, at q),
 *  where that object is a polyhedron that is not convex, other than those two faces, reaches into
 *  the square prism r about the segment (from r before p to r past q), on the side of `prim_a`'s
 *  plane the segment leaves to and of `prim_b`'s it comes from (-1, or another primitive: no
 *  such side). */
int pt_guard_own_segment(const pt_guards_t *faces, const rt_scene_t *s, px_vec3_t p, px_vec3_t q,
                         double r, int prim_a, int prim_b);

/** The same for a ray that leaves the scene from polygon `prim` at p: the square pyramid about the
 *  cone of directions within `half` of unit `axis` from within r of p, on the side of `prim`'s
 *  plane the axis points to (1 also for a half-angle of 90 degrees or more, or NaN). */
int pt_guard_own_cone(const pt_guards_t *faces, const rt_scene_t *s, px_vec3_t p, double r,
                      px_vec3_t axis, double half, int prim);

/** The small-object guard for a secondary ray segment: 1 when some bounding sphere, other than
 *  those of objects `skip_a` and `skip_b` (where the segment starts and ends), comes within
 *  `r` of the segment from p to q: the segment's pencil, every ray from a ball of radius r about
 *  p to one about q, lies in that capsule, so an object outside it cannot meet the pencil. */
int pt_guard_segment(const pt_guards_t *g, px_vec3_t p, px_vec3_t q, double r, int skip_a,
                     int skip_b);

/** The same for a ray that leaves the scene: 1 when some bounding sphere, other than that of
 *  object `skip`, may meet a ray from within `r` of p in a direction within `half` radians of the
 *  unit `axis` (the sphere, grown by r, seen from p, overlaps that cone; or p is within r of it).
 */
int pt_guard_cone(const pt_guards_t *g, px_vec3_t p, double r, px_vec3_t axis, double half,
                  int skip);

/** The same for shadow rays from within `r` of the hit p towards `light` (point or parallel),
 *  traced at points
 *  that leave no disc of radius above `gap` free of them. 1 when some bounding sphere other than
 *  object `skip`'s meets the cone (cylinder) of those rays and could hide its shadow between
 *  the traced points: the shadow of the ball or disc the object holds narrower, seen from the
 *  light, than the gap (a ball's angular radius below the gap's; a disc's narrowed by the
 *  cosine between its normal and the light, the least over the bounding sphere; for a parallel
 *  light, radii), the gap narrowed by the cosine of the light's incidence when the points lie on
 *  a plane of unit `normal` (NULL for a curved surface). A wider shadow has an edge across the
 *  pencil, which the traced points' visibility sees, as the corners see other edges; a long thin
 *  object's does not, however large its bounding sphere. */
int pt_guard_shadow(const pt_guards_t *g, px_vec3_t p, double r, double gap,
                    const px_vec3_t *normal, const rt_light_t *light, int skip);

#endif
