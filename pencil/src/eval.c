/* eval.c -- one sample through the domain's paths (paper section 4.1 (1): "paraxial rays are
 * traced by a system matrix"; 4.1 (2): ray interpolation), shaded by the reference renderer's
 * shade.h, so that the two renderers differ only in how rays find surfaces.
 *
 * The Whitted recursion of rt_shade_hit() is evaluated in its unrolled form: the radiance of a
 * sample is the sum over the nodes k of its tree of W_k * direct_k, where direct_k is
 * rt_shade_direct() at node k's hit and W_k the product of the rt_shade_children() weights along
 * the path from the eye. The children's hits come from the domain's paths, not from a scene
 * search: each node's paraxial ray psi' = T psi meets the node's own primitive (MATRIX mode), or
 * its hit point and direction are interpolated from four lattice points (INTERP mode). Keeping
 * W_k and W_k * direct_k per node lets ray interpolation interpolate the brightness of every
 * node on which it is linear and shade only the others (interp_plan.c).
 *
 * Shadow queries return the transmittance recorded once per domain at the axial ray's node for the
 * lights whose visibility agrees at the domain's centre and corners (rt_tree_node_t lit, blocked
 * and, through glass, the transmittance's hash `through`);
 * for the other lights a shadow ray is traced per sample. Whenever a sample leaves the domain's
 * paths (its paraxial ray misses the node's primitive, or shading asks for a child the tree does
 * not have) or reaches a subtree where the corners' trees differ, that part is traced exactly. */
#include <math.h>
#include <stdlib.h>

#include "core/intersect.h"
#include "core/shade_paths.h"
#include "internal.h"
#include "paraxial/vec3.h"

static void mark_exact(pt_eval_t *E, int k) {
  if (!E->geom)
    return;
  E->geom[k].ok = 2;
  const pt_node_t *n = &E->C->paths.node[k];
  for (int c = 0; c < 2; c++)
    if (n->child[c] >= 0)
      mark_exact(E, n->child[c]);
}

/* The transmittance towards light l recorded at the axial ray's node, when there is one (asked
 * by shade.h before it builds the shadow segment; the axial sample records instead). */
static int known_cb(void *ctx, int l, rt_rgb_t *through) {
  const pt_eval_t *E = ctx;
  const pt_node_t *n = &E->C->paths.node[E->cur];
  if (l >= PT_MAX_LIGHTS || !(n->known & (1u << l)) ||
      (E->record_shadow && (n->light_agree & (1u << l))))
    return 0;
  *through = n->through[l];
  return 1;
}

/* A shadow query: the textbook's transmittance, or with `opaque` a caustic receiver's occlusion. */
static inline __attribute__((always_inline)) void shadow_query(pt_eval_t *E, rt_shadow_t *q,
                                                               int opaque) {
  pt_node_t *n = &E->C->paths.node[E->cur];
  if (q->light < PT_MAX_LIGHTS) {
    unsigned bit = 1u << q->light;
    if (E->record_shadow && (n->light_agree & bit)) {
      if (opaque)
        rt_shadow_occluded(E->C->s, q);
      else
        q->through = rt_transmittance(E->C->s, &q->ray);
      n->through[q->light] = q->through;
      n->known |= bit;
      E->C->ex.stats.shadow++;
      return;
    }
  }
  /* a light whose visibility differs across the domain, one the axial ray's surface faced away
   * from, or one beyond PT_MAX_LIGHTS (those known_cb() did not answer): a shadow ray per
   * sample */
  E->C->ex.stats.shadow++;
  if (E->lattice && E->geom && q->light < 32) { /* where the visibility changes over the domain */
    int blocker = -1;
    if (opaque) {
      blocker = rt_shadow_occluded_by(E->C->s, q);
    } else {
      q->through = rt_transmittance_blocker(E->C->s, &q->ray, &blocker);
    }
    pt_geom_t *g = &E->geom[E->cur];
    rt_rgb_t t = q->through;
    int lit = t.r == 1.0 && t.g == 1.0 && t.b == 1.0, dark = t.r == 0.0 && t.g == 0.0 && t.b == 0.0;
    g->lit |= (uint32_t)lit << q->light;
    g->dark |= (uint32_t)dark << q->light;
    if (!lit)
      g->through ^= dark ? rt_blocked_hash(q->light, blocker) : rt_through_hash(q->light, t);
    return;
  }
  if (opaque)
    rt_shadow_occluded(E->C->s, q);
  else
    q->through = rt_transmittance(E->C->s, &q->ray);
}

static void shadow_cb(void *ctx, rt_shadow_t *q) {
  shadow_query(ctx, q, 0);
}

static void occluded_cb(void *ctx, rt_shadow_t *q) {
  shadow_query(ctx, q, 1);
}

/* Radiance along child ray c of pencil node k by the exact tracer (unweighted). With
 * E->record_sub the subtree's rays are recorded in C->sub.tree under a root standing for node k, so
 * that the measure compares its points with the exact tracer's: they start at the pencil's hit
 * of k, which may be interpolated. */
static rt_rgb_t exact_child(pt_eval_t *E, int k, const rt_child_t *c, int depth) {
  pt_ctx_t *C = E->C;
  rt_tracer_t ex = xr_exact_tracer(&C->ex);
  rt_tree_t *t = &C->sub.tree;
  if (!E->record_sub || k < 0)
    return ex.child(ex.ctx, c, depth);
  if (t->n >= t->cap || C->sub.n >= C->cap) { /* not recorded: the measure cannot compare it */
    t->overflow = 1;
    return ex.child(ex.ctx, c, depth);
  }
  int r = t->n++;
  t->node[r] = (rt_tree_node_t){.parent = -1,
                                .object = -1,
                                .prim = -1,
                                .texel = -1,
                                .t = INFINITY,
                                .weight = rt_rgb(1, 1, 1)};
  C->sub.root[C->sub.n] = r;
  C->sub.from[C->sub.n++] = k;
  rt_tree_t *saved = C->ex.tree;
  int saved_node = C->ex.node;
  C->ex.tree = t;
  C->ex.node = r;
  rt_rgb_t l = ex.child(ex.ctx, c, depth);
  C->ex.tree = saved;
  C->ex.node = saved_node;
  return l;
}

/* A checker square index floor(x) as an int32, or PT_SQUARE_FAR when it has none (beyond int32,
 * or NaN: hits far out on the plane, squares below the coordinates' resolution). */
static int32_t square_index(double x) {
  double f = floor(x);
  return fabs(f) < 0x1p31 ? (int32_t)f : PT_SQUARE_FAR;
}

/* Checker square of a hit on a textured plane (the squares of rt__scene_checker_at()). */
static void square_of(const rt_scene_t *s, int prim, px_vec3_t p, int32_t *su, int32_t *sv) {
  const rt_plane_t *pl = &s->prim[prim].plane;
  double u, v;
  rt_plane_coords(pl, p, &u, &v);
  *su = square_index(u * pl->inv_check);
  *sv = square_index(v * pl->inv_check);
}

static void node_surface(const pt_eval_t *E, int k, px_vec3_t hit, px_vec3_t d, rt_ray_t *ray,
                         rt_surface_t *sf);

/* A verify node (path.h): whether ray r, which meets the node's primitive at t, meets nothing
 * else first (for a miss node, t = INFINITY: nothing at all). */
static int verified(pt_eval_t *E, const pt_node_t *n, const rt_ray_t *r, double t) {
  rt_hit_t h;
  if (!rt_intersect(E->C->s, r, &h))
    return !isfinite(t);
  return h.prim == n->prim && fabs(h.t - t) <= 1e-9 * (1.0 + t);
}

/* walk_ray() where it needs the whole surface record: at dispersive glass under spectral pencils,
 * and for a mirror child whose weight decides whether it exists. Out of line, so that the walk's
 * common steps keep a small frame. */
static __attribute__((noinline)) int walk_ray_full(const pt_eval_t *E, int k, const pt_xgeom_t *px,
                                                   int kind, rt_ray_t *out) {
  const pt_ctx_t *C = E->C;
  const pt_node_t *pn = &C->paths.node[k];
  rt_ray_t ray;
  rt_surface_t sf;
  node_surface(E, k, px->p, px->d, &ray, &sf);
  if (pn->spectral && rt_shade_spectral_at(C->plan, sf.mat, pn->depth)) {
    /* dispersive glass under spectral pencils: the tree's only child there is the white
     * mirror child of rt_shade_spectral_mirror() (children() below), whose existence counts
     * total internal reflection only where every wavelength has it */
    rt_child_t m;
    if (kind != RT_RAY_REFLECT ||
        !rt_shade_spectral_mirror(C->s, C->plan, &sf, &ray, pn->depth, &m))
      return 0;
    *out = m.ray;
    return 1;
  }
  /* only the ray of the path's kind, without its weight (shading builds both children) */
  return rt_shade_child_ray(C->s, C->plan, &sf, &ray, pn->depth, (rt_ray_kind_t)kind, out);
}

/* The ray of kind `kind` that shading spawns at node k's exact hit px: rt_shade_child_ray() at
 * node_surface()'s record, by shade_paths.h's rt_shade_walk_ray() where that answers. It builds
 * only what the ray needs, about 150 instructions fewer a step than the record and
 * rt_shade_child_ray() (of about 450 with the primitive test): the walks are a sixth of the
 * pencil's work on Fig. 8. */
static int walk_ray(const pt_eval_t *E, int k, const pt_xgeom_t *px, int kind, rt_ray_t *out) {
  const pt_node_t *pn = &E->C->paths.node[k];
  if (pn->spectral)
    return walk_ray_full(E, k, px, kind, out);
  int got = rt_shade_walk_ray(E->C->s, E->C->plan, pn->prim, px->p, px->d, pn->ior, pn->depth,
                              (rt_ray_kind_t)kind, out);
  return got >= 0 ? got : walk_ray_full(E, k, px, kind, out);
}

/* Lane i of a four-lane vector. */
static px_vec3_t lane_of(const px_vec3x4_t *v, int i) {
  return px_v3(v->x[i], v->y[i], v->z[i]);
}

/* Node k's exact geometry for the samples of the group C->sample.group at once: exact_geom()'s
 * walk lane by lane, bit for bit, its steps and primitive tests four at a time (core's
 * rt_shade_walk_ray4() and rt_prim_intersect4()). A lane whose step needs the whole surface
 * record (walk_ray_full()) is walked alone. Memoised per group. */
static const pt_xgeom4_t *exact_geom4(pt_eval_t *E, int k) {
  pt_ctx_t *C = E->C;
  const pt_group_t *G = &C->sample.group;
  pt_xgeom4_t *x = &C->sample.exact4[k];
  if (x->stamp == G->stamp)
    return x;
  x->stamp = G->stamp;
  x->ok = 0;
  const pt_node_t *n = &C->paths.node[k];
  rt_ray4_t r;
  rt_ray_t one[4];
  unsigned lanes = 0, alone = 0; /* lanes stepped four at a time, and one by one into one[] */
  unsigned entered;              /* the lanes that reached this step on the path */
  if (n->parent >= 0) {
    const pt_xgeom4_t *px = exact_geom4(E, n->parent);
    const pt_node_t *pn = &C->paths.node[n->parent];
    int got[4] = {-1, -1, -1, -1};
    if (!px->ok)
      return x;
    entered = px->ok;
    if (!pn->spectral) {
      const double ior[4] = {pn->ior, pn->ior, pn->ior, pn->ior};
      rt_shade_walk_ray4(C->s, C->plan, pn->prim, &px->p, &px->d, ior, pn->depth, n->kind, px->ok,
                         &r, got);
    }
    for (int i = 0; i < 4; i++) {
      unsigned b = 1u << i;
      if (!(px->ok & b))
        continue;
      if (got[i] == 1) {
        lanes |= b;
      } else if (got[i] < 0) { /* walk_ray() there asks walk_ray_full() */
        pt_xgeom_t g = {lane_of(&px->p, i), lane_of(&px->d, i), 0, 1};
        alone |= (unsigned)walk_ray_full(E, n->parent, &g, n->kind, &one[i]) << i;
      }
    }
  } else { /* the primary rays, four at a time where they are plain (pt__group_rays()) */
    r = G->ray4;
    lanes = G->lanes4;
    entered = (1u << G->n) - 1;
    alone = entered & ~lanes;
    for (int i = 0; i < G->n; i++)
      one[i] = G->primary[i];
  }
  C->st.walk_steps++;
  C->st.walk_lanes += (uint64_t)__builtin_popcount(lanes | alone);
  if (n->miss)
    return x;
  double t[4];
  if (lanes) {
    x->ok = rt_prim_intersect4(C->s, n->prim, &r.o, &r.d, lanes, t, &x->p);
    x->d = r.d;
  }
  for (int i = 0; n->verify && i < 4; i++)
    if (x->ok & (1u << i)) {
      rt_ray_t q = {lane_of(&r.o, i), lane_of(&r.d, i), 0.0, INFINITY, r.ior[i], r.skip_prim, 0.0f};
      if (!verified(E, n, &q, t[i]))
        x->ok &= ~(1u << i);
    }
  for (int i = 0; alone && i < 4; i++) { /* the lanes walked alone: exact_geom()'s own steps */
    const rt_ray_t *q = &one[i];
    if (!(alone & (1u << i)) || !rt_prim_intersect(C->s, n->prim, q, q->tmax, &t[i]) ||
        (n->verify && !verified(E, n, q, t[i])))
      continue;
    px_vec3_t p = px_v3_axpy(t[i], q->d, q->o);
    x->p.x[i] = p.x, x->p.y[i] = p.y, x->p.z[i] = p.z;
    x->d.x[i] = q->d.x, x->d.y[i] = q->d.y, x->d.z[i] = q->d.z;
    x->ok |= 1u << i;
  }
  if (entered & ~x->ok) /* rare */
    C->st.walk_left += (uint64_t)__builtin_popcount(entered & ~x->ok);
  return x;
}

/* Node k's exact geometry for the sample in MATRIX mode: the sample's primary ray carried
 * exactly through the surfaces of the node's path (at each exact hit, the ray of the path's
 * kind from shade_paths.h's rt_shade_child_ray(), the ray rt_shade_children() spawns: walk_ray()),
 * each met as the path's own primitive, without a scene search. Memoised per evaluation; 0 when
 * the ray leaves the path (misses a primitive or lacks the child). */
static const pt_xgeom_t *exact_geom(pt_eval_t *E, int k) {
  pt_ctx_t *C = E->C;
  pt_xgeom_t *x = &C->sample.exact[k];
  if (x->stamp == E->stamp)
    return x;
  x->stamp = E->stamp;
  if (E->grouped) { /* the sample's lane of its group's walk */
    const pt_xgeom4_t *g = exact_geom4(E, k);
    int i = E->lane;
    x->ok = (int)(g->ok >> i) & 1;
    if (x->ok) {
      x->p = lane_of(&g->p, i);
      x->d = lane_of(&g->d, i);
    }
    return x;
  }
  x->ok = 0;
  const pt_node_t *n = &C->paths.node[k];
  rt_ray_t child;
  const rt_ray_t *r = &E->primary;
  if (n->parent >= 0) {
    const pt_xgeom_t *px = exact_geom(E, n->parent);
    if (!px->ok || !walk_ray(E, n->parent, px, n->kind, &child))
      return x;
    r = &child;
  }
  double t;
  if (n->miss || !rt_prim_intersect(C->s, n->prim, r, r->tmax, &t) ||
      (n->verify && !verified(E, n, r, t)))
    return x;
  x->p = px_v3_axpy(t, r->d, r->o);
  x->d = r->d;
  x->ok = 1;
  return x;
}

/* Whether a child of node n is traced exactly per sample in this evaluation (the domain's tree
 * marks it exact, or the lattice cell's plan traces it below an edge). */
static int spawns_exact(const pt_eval_t *E, const pt_node_t *n) {
  if (n->spectral && !(E->spec_lin && E->spec_lin[n - E->C->paths.node]))
    return 1;
  for (int c = 0; c < 2; c++) {
    int kc = n->child[c];
    if (kc >= 0 &&
        (E->C->paths.node[kc].mode == PT_NODE_EXACT || (E->exact_subtree && E->exact_subtree[kc])))
      return 1;
  }
  return 0;
}

/* Node k's hit point and arriving direction for this sample; 0 when the sample's ray misses the
 * node's primitive (it left the domain's paths). `from` is the ray arriving at the node as shading
 * spawned it (NULL for the primary ray). */
static int node_geometry(pt_eval_t *E, int k, const rt_child_t *from, px_vec3_t *hit,
                         px_vec3_t *d) {
  const pt_node_t *n = &E->C->paths.node[k];
  if (E->exact_spawn && !E->lattice && spawns_exact(E, n)) {
    /* the exact tracer takes the rays spawned here: an interpolated (or matrix) hit and
     * direction, though within the tolerance, would put their error into every surface below,
     * where nothing bounds it (a glass polyhedron's facets turn it into another colour: Fig. 11;
     * a ray leaving the glass ball near grazing meets the board hundreds of pixel intervals
     * away). So the sample's own ray carried along the node's path (exact_geom; for the primary
     * node one primitive test). Leaving the path, the sample has left the domain's paths. */
    const pt_xgeom_t *x = exact_geom(E, k);
    E->spawnfail |= !x->ok;
    *hit = x->p;
    *d = x->d;
    return x->ok;
  }
  if (E->mode == PT_EV_INTERP && E->traced && E->traced[k]) { /* this node: per sample */
    if (n->mode == PT_NODE_PATH) {
      const pt_xgeom_t *x = exact_geom(E, k);
      *hit = x->p;
      *d = x->d;
      return x->ok;
    }
    px_vec3_t p;
    return pt_node_ray(n, E->xi, &p, d) && pt_node_hit(E->C->s, n, p, *d, hit);
  }
  /* biquadratic over the lattice cell's grid */
  if (E->mode == PT_EV_INTERP && E->biquadratic && E->biquadratic[k]) {
    px_vec3_t p = {0, 0, 0}, dd = {0, 0, 0};
    for (int i = 0; i < 9; i++) {
      p = px_v3_axpy(E->grid_w[i], E->grid[i][k].p, p);
      dd = px_v3_axpy(E->grid_w[i], E->grid[i][k].d, dd);
    }
    const rt_prim_t *pr = &E->C->s->prim[n->prim];
    if (pr->kind == RT_PRIM_SPHERE) { /* back onto the sphere, as below */
      px_vec3_t r = px_v3_sub(p, pr->sphere.c);
      p = px_v3_axpy(pr->sphere.r / px_v3_norm(r), r, pr->sphere.c);
    }
    *hit = p;
    *d = px_v3_unit(dd);
    return 1;
  }
  if (E->mode == PT_EV_INTERP) {
    const double *w = E->corner_w;
    const pt_geom_t *a = &E->corner[0][k], *b = &E->corner[1][k], *c = &E->corner[2][k],
                    *e = &E->corner[3][k];
    *hit = px_v3_axpy(w[0], a->p,
                      px_v3_axpy(w[1], b->p, px_v3_axpy(w[2], c->p, px_v3_scale(e->p, w[3]))));
    const rt_prim_t *pr = &E->C->s->prim[n->prim];
    if (pr->kind == RT_PRIM_SPHERE) { /* a chord lies inside the sphere: back onto its surface,
                                         so that rays spawned here start on the right side */
      px_vec3_t r = px_v3_sub(*hit, pr->sphere.c);
      *hit = px_v3_axpy(pr->sphere.r / px_v3_norm(r), r, pr->sphere.c);
    }
    *d = px_v3_unit(px_v3_axpy(
        w[0], a->d, px_v3_axpy(w[1], b->d, px_v3_axpy(w[2], c->d, px_v3_scale(e->d, w[3])))));
    return 1;
  }
  if (n->mode == PT_NODE_PATH) { /* exactly along the path */
    int exact_parent = n->parent < 0 || E->C->paths.node[n->parent].mode == PT_NODE_PATH;
    if (from && exact_parent) { /* spawned at an exact hit: the sample's own ray */
      double t;
      if (!rt_prim_intersect(E->C->s, n->prim, &from->ray, from->ray.tmax, &t) ||
          (n->verify && !verified(E, n, &from->ray, t)))
        return 0;
      *hit = px_v3_axpy(t, from->ray.d, from->ray.o);
      *d = from->ray.d;
      E->C->sample.exact[k] = (pt_xgeom_t){*hit, *d, E->stamp, 1};
      return 1;
    }
    const pt_xgeom_t *x = exact_geom(E, k);
    *hit = x->p;
    *d = x->d;
    return x->ok;
  }
  px_vec3_t p;
  return pt_node_ray(n, E->xi, &p, d) && pt_node_hit(E->C->s, n, p, *d, hit);
}

/* The surface record of node k at (hit, d) for shade.h. */
static void node_surface(const pt_eval_t *E, int k, px_vec3_t hit, px_vec3_t d, rt_ray_t *ray,
                         rt_surface_t *sf) {
  const pt_node_t *n = &E->C->paths.node[k];
  rt_hit_t h = {0.0, hit, rt_prim_normal(E->C->s, n->prim, hit), n->prim, n->object};
  *ray = (rt_ray_t){hit, d, 0.0, INFINITY, n->ior, -1, 0.0f};
  rt_shade_surface(E->C->s, &h, ray, sf);
}

static rt_rgb_t eval_node(pt_eval_t *E, int k, rt_rgb_t w, const rt_child_t *from);

/* The children of node k at surface sf: those the domain's paths cover by eval_node(), the others
 * by the exact tracer (geometry-only evaluations just mark them); `only_exact` skips the former
 * (the caller interpolates them). */
static rt_rgb_t children(pt_eval_t *E, int k, const rt_surface_t *sf, const rt_ray_t *ray,
                         rt_rgb_t w, int only_exact) {
  const pt_node_t *n = &E->C->paths.node[k];
  rt_child_t ch[2];
  int nc = -1;
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  if (n->spectral && rt_shade_spectral_at(E->C->plan, sf->mat, n->depth)) {
    /* Dispersive glass under spectral pencils (path.h's pt_node_t.spectral): the tree has no
     * refracted child here. Its light is traced from the sample's hit by rt_shade_spectral(), an
     * exact child shaded per sample (the planner's has_exact_children()), never interpolated:
     * neither the corners' trees nor a lattice cell's brightness test alone could see an edge
     * behind the glass. The white mirror child goes on as any other. */
    if ((E->shade || E->record_sub) && !E->lattice && !(E->spec_lin && E->spec_lin[k])) {
      rt_tracer_t ex = xr_exact_tracer(&E->C->ex);
      sum = rt_rgb_mul(w,
                       rt_shade_spectral(E->C->s, E->C->plan, sf, ray, n->depth, &ex, &ch[0], &nc));
    } else {
      nc = rt_shade_spectral_mirror(E->C->s, E->C->plan, sf, ray, n->depth, &ch[0]);
    }
  }
  if (nc < 0 && only_exact && n->child[0] >= 0 && n->child[1] >= 0) {
    /* both children are in the domain's tree, so the sample cannot have one it lacks: when only
     * one of them is traced exactly, only that one is built (the other is interpolated) */
    int exact[2];
    for (int c = 0; c < 2; c++)
      exact[c] = E->C->paths.node[n->child[c]].mode == PT_NODE_EXACT ||
                 (E->exact_subtree && E->exact_subtree[n->child[c]]);
    if (exact[0] != exact[1])
      nc = rt_shade_child(E->C->s, E->C->plan, sf, ray, n->depth,
                          (rt_ray_kind_t)n->child_kind[exact[0] ? 0 : 1], &ch[0]);
  }
  if (nc < 0)
    nc = rt_shade_children(E->C->s, E->C->plan, sf, ray, n->depth, ch);
  for (int i = 0; i < nc; i++) {
    rt_rgb_t wc = rt_rgb_mul(w, ch[i].weight);
    int kc = n->child_kind[0] == (int)ch[i].kind   ? n->child[0]
             : n->child_kind[1] == (int)ch[i].kind ? n->child[1]
                                                   : -1;
    if (kc >= 0 && E->C->paths.node[kc].mode != PT_NODE_EXACT &&
        !(E->exact_subtree && E->exact_subtree[kc])) {
      if (!only_exact)
        sum = rt_rgb_add(sum, eval_node(E, kc, wc, &ch[i]));
      continue;
    }
    if (kc >= 0) { /* the corners' trees differ below here: traced exactly */
      E->partial = 1;
      mark_exact(E, kc);
    } else { /* a child the domain's tree does not have: the sample left the domain's paths */
      E->fallback = 1;
      if (E->geom)
        E->geom[k].exact_kinds |= (uint8_t)(1u << ch[i].kind);
    }
    /* lattice points record where the paths end, not radiance; a measured geometry-only
     * evaluation traces the subtree for its points */
    if ((E->shade || E->record_sub) && !E->lattice)
      sum = rt_rgb_add(sum, rt_rgb_mul(wc, exact_child(E, k, &ch[i], n->depth + 1)));
  }
  return sum;
}

/* A lattice point at spectral node k (weight w): the light of the spectral pencils traced from
 * the point's exact hit (as a sample's, node_geometry()), weighted, with the bounds of their
 * segments and the signature of what they met (pt_geom_t.sp, ssig), so that the lattice cells
 * it is a corner of may interpolate that light (interp_plan.c's spectral_interpolable()). ssig
 * stays 0 where the pencils cannot be interpolated (rt_spectral_rec_t.unusable) or the point
 * leaves the path. */
static void spectral_record(pt_eval_t *E, int k, rt_rgb_t w, pt_geom_t *g) {
  pt_ctx_t *C = E->C;
  const pt_node_t *n = &C->paths.node[k];
  if (C->lattice.spec_off[k])
    return;
  const pt_xgeom_t *x = exact_geom(E, k);
  if (!x->ok)
    return;
  rt_ray_t ray;
  rt_surface_t sf;
  node_surface(E, k, x->p, x->d, &ray, &sf);
  if (!rt_shade_spectral_at(C->plan, sf.mat, n->depth))
    return;
  rt_tracer_t ex = xr_exact_tracer(&C->ex);
  rt_spectral_rec_t rec;
  rt_child_t m;
  int nm;
  rt_rgb_t ls = rt_shade_spectral_rec(C->s, C->plan, &sf, &ray, n->depth, &ex, &m, &nm, &rec);
  C->st.spectral_points++;
  if (!rec.sig) { /* no point of this domain will do better, as a rule: not traced again */
    C->lattice.spec_off[k] = 1;
    return;
  }
  if (!pt__spec_put(C, &rec, &g->sp.at)) { /* the domain's events are full: none kept after */
    C->st.spectral_full++;
    C->lattice.spec_off[k] = 1;
    return;
  }
  g->sp.ls = rt_rgb_mul(w, ls);
  g->sp.nev = (uint32_t)rec.nev;
  g->ssig = rec.sig;
}

/* The sample's ray left node n's path: an edge the domain's corners saw (verify node) or not. */
static void left(pt_eval_t *E, const pt_node_t *n) {
  if (n->verify)
    E->vfail = E->partial = 1;
  else
    E->fallback = 1;
}

static rt_rgb_t eval_node(pt_eval_t *E, int k, rt_rgb_t w, const rt_child_t *from) {
  pt_ctx_t *C = E->C;
  const pt_node_t *n = &C->paths.node[k];
  pt_geom_t *g = E->geom ? &E->geom[k] : NULL;
  if (n->miss) {
    const rt_ray_t *r = from ? &from->ray : E->mode == PT_EV_MATRIX ? &E->primary : NULL;
    rt_hit_t h;
    /* certified mode: the sample's own ray must still meet nothing (a horizon or an object
     * between the domain's corners would otherwise go unseen) */
    if ((C->opt->certified || n->verify) && r && rt_intersect(C->s, r, &h)) {
      left(E, n);
      mark_exact(E, k);
      if (E->lattice || !(E->shade || (E->record_sub && from)))
        return rt_rgb(0, 0, 0);
      return from ? rt_rgb_mul(w, exact_child(E, n->parent, from, n->depth))
                  : xr_exact_primary(&C->ex, r);
    }
    rt_rgb_t l = rt_rgb_mul(w, C->s->background);
    if (g) {
      *g = (pt_geom_t){.w = w, .l = l, .ok = 1};
      if (r) { /* where the ray leaves from and its direction, for interpolated checks */
        g->p = r->o;
        g->d = r->d;
      }
    }
    return l;
  }
  px_vec3_t hit, d;
  if (!node_geometry(E, k, from, &hit, &d)) { /* left the domain's paths: exact from here */
    left(E, n);
    mark_exact(E, k);
    if (E->lattice || !(E->shade || (E->record_sub && from)))
      return rt_rgb(0, 0, 0);
    return from ? rt_rgb_mul(w, exact_child(E, n->parent, from, n->depth))
                : xr_exact_primary(&C->ex, &E->primary);
  }
  if (g) {
    g->p = hit;
    g->d = d;
    g->w = w;
    g->l = rt_rgb(0, 0, 0);
    g->ok = 1;
    g->exact_kinds = 0;
    g->su = g->sv = 0;
    g->lit = g->dark = g->through = 0;
    g->ssig = 0;
    if (n->textured)
      square_of(C->s, n->prim, hit, &g->su, &g->sv);
  }
  rt_ray_t ray;
  rt_surface_t sf;
  node_surface(E, k, hit, d, &ray, &sf);
  int saved = E->cur;
  E->cur = k;
  rt_rgb_t l = rt_rgb(0, 0, 0);
  if (E->shade) {
    rt_tracer_t tr = {NULL, shadow_cb, E, known_cb, occluded_cb, NULL, 0};
    if (g && E->lattice && n->textured) {
      /* with the direct term of the other square's material too, for interpolation across
       * squares (one shadow query for both) */
      const rt_object_t *o = &C->s->object[n->object];
      int par = sf.texel; /* the square's parity as the core shades it */
      rt_rgb_t both[2];
      rt_shade_direct2(C->s, C->plan, &sf, &C->s->material[par ? o->material : o->material2], &ray,
                       &tr, both);
      l = rt_rgb_mul(w, both[0]);
      g->lt[par] = l;
      g->lt[!par] = rt_rgb_mul(w, both[1]);
    } else {
      l = rt_rgb_mul(w, rt_shade_direct(C->s, C->plan, &sf, &ray, &tr));
    }
    if (g)
      g->l = l;
  }
  rt_rgb_t sum = rt_rgb_add(l, children(E, k, &sf, &ray, w, 0));
  if (g && E->lattice && E->shade && n->spectral && !n->textured && C->opt->spectral_lattice &&
      !C->opt->certified)
    spectral_record(E, k, w, g);
  E->cur = saved;
  return sum;
}

rt_rgb_t pt__eval(pt_eval_t *E) {
  if (E->geom)
    for (int k = 0; k < E->C->paths.n; k++)
      E->geom[k].ok = E->geom[k].exact_kinds = 0;
  if (E->record_sub) {
    E->C->sub.tree.n = E->C->sub.tree.overflow = 0;
    E->C->sub.n = 0;
  }
  E->cur = -1;
  E->fallback = 0;
  E->vfail = 0;
  E->traced_failed = 0;
  E->spawnfail = 0;
  E->partial = 0;
  E->stamp = ++E->C->sample.stamp;
  return eval_node(E, 0, rt_rgb(1, 1, 1), NULL);
}

rt_rgb_t pt__eval_local(pt_eval_t *E, int k, rt_rgb_t w, int direct, int exact_children) {
  if (E->C->paths.node[k].miss) /* the sky: no surface to shade (and no children) */
    return direct ? rt_rgb_mul(w, E->C->s->background) : rt_rgb(0, 0, 0);
  px_vec3_t hit, d;
  if (!node_geometry(E, k, NULL, &hit, &d)) { /* only a traced node's ray can leave its path */
    E->traced_failed = 1;
    return rt_rgb(0, 0, 0);
  }
  rt_ray_t ray;
  rt_surface_t sf;
  node_surface(E, k, hit, d, &ray, &sf);
  int saved = E->cur;
  E->cur = k;
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  if (direct) {
    rt_tracer_t tr = {NULL, shadow_cb, E, known_cb, occluded_cb, NULL, 0};
    sum = rt_rgb_mul(w, rt_shade_direct(E->C->s, E->C->plan, &sf, &ray, &tr));
  }
  if (exact_children)
    sum = rt_rgb_add(sum, children(E, k, &sf, &ray, w, 1));
  E->cur = saved;
  return sum;
}

int pt__spawns_exact(const pt_eval_t *E) {
  const pt_ctx_t *C = E->C;
  for (int k = 0; k < C->paths.n; k++)
    if (!C->paths.node[k].miss && spawns_exact(E, &C->paths.node[k]))
      return 1;
  return 0;
}

void pt__xi(const pt_ctx_t *C, double x, double y, double xi[2]) {
  rt_ray_t r = rt_view_ray(C->view, x, y, 1.0);
  xi[0] = px_v3_dot(C->paths.frame.x1, r.d);
  xi[1] = px_v3_dot(C->paths.frame.x2, r.d);
}
