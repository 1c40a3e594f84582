/* eval.c -- one sample through the domain's paths (paper section 4.1 (1): "paraxial rays are
 * traced by a system matrix"; 4.1 (2): ray interpolation), shaded by the reference renderer's
 * shade.h through an rt_tracer_t whose callbacks use the domain's data:
 *  - a child ray's radiance is the radiance of the matching node of the domain's tree, evaluated
 *    for the same sample (no scene search: the node's own primitive only);
 *  - a shadow query returns the transmittance recorded once per domain at the axial ray's node.
 *    This is valid because the cell was accepted only when the trees of its centre and corners
 *    agree on every light's visibility (rt_tree_node_t lit/blocked), docs/pencil.md.
 * Whenever a sample leaves its domain's paths (its paraxial ray misses the node's primitive, or
 * shading asks for a child the tree does not have) that part of its tree is traced exactly. */
#include <math.h>

#include "internal.h"
#include "pvec.h"
#include "render/intersect.h"

static rt_rgb_t eval_node(pt_eval_t *E, int k, const rt_child_t *from);

static void mark_exact(pt_eval_t *E, int k) {
  if (!E->rec)
    return;
  E->rec[k].ok = 2;
  const pt_node_t *n = &E->C->node[k];
  for (int c = 0; c < 2; c++)
    if (n->child[c] >= 0)
      mark_exact(E, n->child[c]);
}

static rt_rgb_t child_cb(void *ctx, const rt_child_t *child, int depth) {
  pt_eval_t *E = ctx;
  const pt_node_t *p = &E->C->node[E->cur];
  for (int c = 0; c < 2; c++)
    if (p->child[c] >= 0 && p->child_kind[c] == (int)child->kind)
      return eval_node(E, p->child[c], child);
  /* a child the domain's tree does not have: trace it exactly */
  E->fallback = 1;
  if (E->rec)
    E->rec[E->cur].fb |= (uint8_t)(1u << child->kind);
  rt_tracer_t ex = rt_exact_tracer(&E->C->ex);
  return ex.child(ex.ctx, child, depth);
}

static void shadow_cb(void *ctx, rt_shadow_t *q) {
  pt_eval_t *E = ctx;
  pt_node_t *n = &E->C->node[E->cur];
  if (q->light < PT_MAX_LIGHTS) {
    unsigned bit = 1u << q->light;
    if (E->record_shadow) {
      q->through = rt_transmittance(E->C->s, &q->ray);
      n->through[q->light] = q->through;
      n->known |= bit;
      E->C->ex.stats.shadow++;
      return;
    }
    if (n->known & bit) {
      q->through = n->through[q->light];
      return;
    }
  }
  /* a light the axial ray's surface faced away from, or beyond PT_MAX_LIGHTS */
  E->C->ex.stats.shadow++;
  q->through = rt_transmittance(E->C->s, &q->ray);
}

/* The exact radiance for the part of the tree that starts at node k. */
static rt_rgb_t exact_from(pt_eval_t *E, int k, const rt_child_t *from) {
  E->fallback = 1;
  mark_exact(E, k);
  if (!E->shade)
    return E->C->s->background;
  if (from) {
    rt_tracer_t ex = rt_exact_tracer(&E->C->ex);
    return ex.child(ex.ctx, from, E->C->node[k].depth);
  }
  return rt_exact_primary(&E->C->ex, &E->primary);
}

/* Checker square of a hit on a textured plane. */
static void square_of(const rt_scene_t *s, int prim, px_vec3_t p, int32_t *su, int32_t *sv) {
  const rt_plane_t *pl = &s->prim[prim].plane;
  double u, v;
  rt_plane_coords(pl, p, &u, &v);
  *su = (int32_t)floor(u / pl->check);
  *sv = (int32_t)floor(v / pl->check);
}

static rt_rgb_t eval_node(pt_eval_t *E, int k, const rt_child_t *from) {
  pt_ctx_t *C = E->C;
  const pt_node_t *n = &C->node[k];
  if (n->miss) {
    if (E->rec)
      E->rec[k].ok = 1;
    return C->s->background;
  }
  px_vec3_t hit, d;
  if (E->mode == PT_EV_MATRIX) {
    px_vec3_t p;
    if (!pt_node_ray(n, E->xi, &p, &d) || !pt_node_hit(C->s, n, p, d, &hit))
      return exact_from(E, k, from);
  } else {
    const double *w = E->w;
    const pt_geom_t *a = &E->g[0][k], *b = &E->g[1][k], *c = &E->g[2][k], *e = &E->g[3][k];
    hit = pv_axpy(w[0], a->p, pv_axpy(w[1], b->p, pv_axpy(w[2], c->p, pv_scale(e->p, w[3]))));
    d = pv_unit(pv_axpy(w[0], a->d, pv_axpy(w[1], b->d, pv_axpy(w[2], c->d, pv_scale(e->d, w[3])))));
  }
  if (E->rec) {
    pt_geom_t *g = &E->rec[k];
    g->p = hit;
    g->d = d;
    g->ok = 1;
    g->fb = 0;
    g->su = g->sv = 0;
    if (n->textured)
      square_of(C->s, n->prim, hit, &g->su, &g->sv);
  }
  if (!E->shade) {
    for (int c = 0; c < 2; c++)
      if (n->child[c] >= 0)
        eval_node(E, n->child[c], NULL);
    return C->s->background;
  }
  rt_hit_t h = {0.0, hit, rt_prim_normal(C->s, n->prim, hit), n->prim, n->object};
  rt_ray_t ray = {hit, d, 0.0, INFINITY, n->ior, -1};
  rt_surface_t sf;
  rt_shade_surface(C->s, &h, &ray, &sf);
  int saved = E->cur;
  E->cur = k;
  rt_tracer_t tr = {child_cb, shadow_cb, E};
  rt_rgb_t col = rt_shade_hit(C->s, C->plan, &sf, &ray, n->depth, &tr);
  E->cur = saved;
  return col;
}

rt_rgb_t pt__eval(pt_eval_t *E) {
  if (E->rec)
    for (int k = 0; k < E->C->nnode; k++)
      E->rec[k].ok = E->rec[k].fb = 0;
  E->cur = -1;
  E->fallback = 0;
  return eval_node(E, 0, NULL);
}

void pt__xi(const pt_ctx_t *C, double x, double y, double xi[2]) {
  rt_ray_t r = rt_view_ray(C->view, x, y, 1.0);
  xi[0] = pv_dot(C->frame.x1, r.d);
  xi[1] = pv_dot(C->frame.x2, r.d);
}
