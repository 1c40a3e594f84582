/* domain.c -- the procedure of section 4.1 (1) for one domain, steps 2-4:
 *   2) trace the axial ray (the domain's centre) exactly with its tree; a system matrix per path;
 *   3) smoothness: the trees of the centre and the four corners must agree (edge.h), and the
 *      small-object guard must not fire; otherwise subdivide, and trace 1-pixel domains exactly;
 *   4) tolerance (Eq. 3) and spread limit (Eqs. 4-6) per path:
 *      a) the domain's spread is within every path's limit: trace its samples with the matrices,
 *         or interpolate them (4.1 (2)) from matrix-traced pixel corners when e_int allows;
 *      b) the allowed pencil is narrower than a pixel: trace the domain exactly;
 *      c) otherwise divide the domain so that each part's spread is within the limit; repeat 2-4.
 * A domain whose axial or corner tree has more than PT_MAX_TREE_NODES nodes is traced exactly as a
 * whole (a deep tree: every sample would cost what the exact renderer pays, plus the matrices).
 * In certified mode step 4a also needs every path's exact error on the domain boundary (ex_map at
 * the corners and edge midpoints) to be within tau. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/intersect.h"
#include "core/shade.h"
#include "core/shade_paths.h"
#include "internal.h"
#include "paraxial/vec3.h"

/* Whether accepted domains are ray-interpolated (4.1 (2)) rather than traced by matrices. */
static int interpolating(const pt_ctx_t *C) {
  return C->opt->interp;
}

void pt__trace_shape(pt_ctx_t *C, rt_tree_t *t, const rt_ray_t *r) {
  C->ex.tree = t;
  C->ex.halt = 1;
  xr_exact_primary(&C->ex, r);
  C->ex.tree = NULL;
  C->ex.halt = 0;
}

static const pt_ctree_t *corner(pt_ctx_t *C, int x, int y) {
  int side = C->opt->domain + 1;
  pt_ctree_t *ct = &C->corners.tree[(y - C->corners.y0) * side + (x - C->corners.x0)];
  if (ct->n < 0) { /* traced no further than the paths may hold (the tree alone is wanted) */
    rt_ray_t r = rt_view_ray(C->view, x, y, C->s->ior);
    rt_tree_t t = rt_tree_make(C->trees.probe.node, C->cap);
    pt__trace_shape(C, &t, &r);
    pt_ctree_from(ct, &t);
    C->st.exact_traces++;
  }
  return ct;
}

/* Step 4a for an accepted domain. */
static void accept_domain(pt_ctx_t *C, int x0, int y0, int x1, int y1, const rt_ray_t *axial) {
  C->paths.transmit = rt_tree_follow(&C->trees.axial, RT_RAY_REFRACT);
  C->paths.reflect = rt_tree_follow(&C->trees.axial, RT_RAY_REFLECT);
  if (interpolating(C)) { /* its root lattice point at the centre records the shadows */
    pt__interp_domain(C, x0, y0, x1, y1, axial);
    return;
  }
  pt__record_shadows(C, axial);
  C->st.matrix_samples[0] +=
      (uint64_t)((x1 - x0) * (y1 - y0) * C->opt->spp_side * C->opt->spp_side);
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++)
      pt__matrix_pixel(C, i, j);
}

/* Divide the domain into about k x k parts (each at least a pixel) and process them; a 1-pixel
 * domain is traced exactly instead. */
static void subdivide(pt_ctx_t *C, int x0, int y0, int x1, int y1, int k) {
  int w = x1 - x0, h = y1 - y0;
  if (w <= 1 && h <= 1) {
    pt__exact_domain(C, x0, y0, x1, y1);
    return;
  }
  int kx = w > 1 ? (k < w ? k : w) : 1, ky = h > 1 ? (k < h ? k : h) : 1;
  for (int j = 0; j < ky; j++)
    for (int i = 0; i < kx; i++)
      pt__domain(C, x0 + i * w / kx, y0 + j * h / ky, x0 + (i + 1) * w / kx, y0 + (j + 1) * h / ky);
}

static double xi_norm(const pt_ctx_t *C, double x, double y) {
  double xi[2];
  pt__xi(C, x, y, xi);
  return hypot(xi[0], xi[1]);
}

/* Margin on the radius of a node's hits over the domain taken from its matrix at 8 boundary points
 * (corners and edge midpoints): the boundary between them may bulge, and the paraxial rays are
 * only first-order (a path over its spread limit is off by more than the tolerance, still far
 * less than the radius). */
#define PT_GUARD_INFLATE 1.5

/* The domain's boundary points, corners and edge midpoints, and their primary xi (computed when
 * first asked for: certified mode's check, or the guard below). */
typedef struct {
  double x[8], y[8]; /* the points in pixels: corner, edge midpoint, corner, ... round the domain */
  double xi[8][2];   /* their primary rays' xi in the domain's frame (when `have`) */
  int have;          /* xi is computed */
} boundary_t;

static boundary_t boundary_of(int x0, int y0, int x1, int y1) {
  double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  return (boundary_t){{x0, cx, x1, x1, x1, cx, x0, x0}, {y0, y0, y0, cy, y1, y1, y1, cy}, {{0}}, 0};
}

static const double (*boundary_xi(const pt_ctx_t *C, boundary_t *b))[2] {
  for (int i = 0; i < 8 && !b->have; i++)
    pt__xi(C, b->x[i], b->y[i], b->xi[i]);
  b->have = 1;
  return (const double(*)[2])b->xi;
}

/* Radius about n->o of node n's hits for the domain's boundary rays (primary xi), from its
 * matrix, on the surface (/ cos of incidence); memoised in n->guard_r. */
static double hit_radius(const pt_ctx_t *C, pt_node_t *n, boundary_t *b) {
  if (n->guard_r >= 0.0)
    return n->guard_r;
  const double(*bxi)[2] = boundary_xi(C, b);
  double r = 0.0;
  for (int j = 0; j < 8 && isfinite(r); j++) {
    px_vec3_t p, d;
    r = pt_node_ray(n, bxi[j], &p, &d) ? fmax(r, px_v3_norm(px_v3_sub(p, n->o))) : INFINITY;
  }
  n->guard_r = PT_GUARD_INFLATE * r / n->cos_in;
  return n->guard_r;
}

/* Half-angle about `axis` of the directions of miss node n's rays over the domain: each boundary
 * ray is carried by its parent's matrix to the parent's surface and given the child of n's kind
 * there, as shade.h spawns it; INFINITY when one of them does not meet the surface or has no
 * such child (the guard then fires). */
static double miss_spread(pt_ctx_t *C, const pt_node_t *n, const pt_node_t *par, px_vec3_t axis,
                          boundary_t *b) {
  const double(*bxi)[2] = boundary_xi(C, b);
  double cmin = 1.0;
  for (int j = 0; j < 8; j++) {
    px_vec3_t p, d, hit;
    if (!pt_node_ray(par, bxi[j], &p, &d) || !pt_node_hit(C->s, par, p, d, &hit))
      return INFINITY;
    rt_hit_t h = {0.0, hit, rt_prim_normal(C->s, par->prim, hit), par->prim, par->object};
    rt_ray_t ray = {hit, d, 0.0, INFINITY, par->ior, -1, 0.0f};
    rt_surface_t sf;
    rt_child_t ch;
    rt_shade_surface(C->s, &h, &ray, &sf);
    if (!rt_shade_child(C->s, C->plan, &sf, &ray, par->depth, (rt_ray_kind_t)n->kind, &ch))
      return INFINITY;
    cmin = fmin(cmin, px_v3_dot(ch.ray.d, axis));
  }
  return PT_GUARD_INFLATE * acos(fmax(-1.0, cmin));
}

/* The small-object guard for node k's segment, from its parent's hit to its own (step 3 for
 * what the domain's rays meet after the eye; the primary cone is pt__domain's guard): a bounded
 * object near the segment's pencil, other than the two it joins, may lie between the traced rays,
 * hiding the node from some samples while every traced tree agrees (found on scenes/balls.json:
 * the small ball seen after five reflections inside the glass ball, as path mismatches). For a
 * ray that leaves the scene (a miss node) the pencil is the cone of its directions from the
 * parent's hits: an object that cone comes near may be seen by samples between the traced rays
 * (a small ball reflected against the sky, tests/test_pencil.c). */
static int segment_guarded(pt_ctx_t *C, int k, boundary_t *b) {
  pt_node_t *n = &C->paths.node[k], *par = &C->paths.node[n->parent];
  int any = 0, own = C->faces->across != NULL; /* other objects; the ends' own faces */
  for (int i = 0; i < C->guard->n && !any; i++)
    any = C->guard->b[i].object != n->object && C->guard->b[i].object != par->object;
  if (!any && !own)
    return 0;
  if (n->miss) {
    px_vec3_t axis = C->trees.axial.node[k].dir;
    double r = hit_radius(C, par, b), half = miss_spread(C, n, par, axis, b);
    return (any && pt_guard_cone(C->guard, par->o, r, axis, half, par->object)) ||
           (own && pt_guard_own_cone(C->faces, C->s, par->o, r, axis, half, par->prim));
  }
  double r = fmax(hit_radius(C, par, b), hit_radius(C, n, b));
  return (any && pt_guard_segment(C->guard, par->o, n->o, r, par->object, n->object)) ||
         (own && pt_guard_own_segment(C->faces, C->s, par->o, n->o, r, par->prim, n->prim));
}

/* The small-object guard for node n's shadow rays: a light whose visibility the domain's corners
 * agree on may still be cut off from part of the domain's hits by a bounded object whose shadow
 * is narrower than the gaps between them (a small ball's shadow between the corners is otherwise
 * lost: tests/test_pencil.c), or by the node's own object where it is not convex (an edge of its
 * silhouette from the light in the pencil, pt_guard_self_shadow()). Such a light no longer counts
 * as agreeing for the node: the lattice points trace their shadow rays, and interp_plan.c's
 * shadow_guarded() decides per lattice cell. A light they disagree on is guarded too, where the
 * test fires: a thin object's shadow that crosses a corner runs on between the lattice points of
 * other cells. */
static void shadow_guard(pt_ctx_t *C, pt_node_t *n, boundary_t *b) {
  int any = 0, self = C->faces->across != NULL; /* other objects; its own (not convex) */
  for (int i = 0; i < C->guard->n && !any; i++)
    any = C->guard->b[i].object != n->object;
  double r = -1.0;
  for (int l = 0; (any || self) && l < C->s->nlight && l < 32; l++) {
    uint32_t bit = 1u << l;
    if (r < 0.0)
      r = hit_radius(C, n, b); /* the corners and the centre leave no larger gap */
    const px_vec3_t *plane = C->s->prim[n->prim].kind == RT_PRIM_PLANE ? &n->n : NULL;
    if ((any && pt_guard_shadow(C->guard, n->o, r, r / PT_GUARD_INFLATE, plane, &C->s->light[l],
                                n->object)) ||
        (self && pt_guard_self_shadow(C->faces, C->s, n->prim, n->o, r, &C->s->light[l]))) {
      C->st.lights_guard += (n->light_agree & bit) != 0;
      n->light_agree &= ~bit;
      n->light_guard |= bit;
    }
  }
}

/* The highlight guard's first step, for the whole domain (interp_plan.c's highlight_guarded() is
 * the second, per lattice cell): sets n->highlight unless no Phong highlight of node k's surface
 * can reach the share of the brightness tolerance the guard allows anywhere among the domain's
 * hits. The mirror directions of the domain's boundary rays (from the node's matrix, met with its
 * surface) lie in a cone about the axial ray's, grown by PT_GUARD_INFLATE; the light's directions
 * in the cone that the hits' ball (hit_radius()) subtends from it. The angle between the two is at
 * least the axial angle less both half-angles, and (R.V)^n at most its cosine to the n; W_k is at
 * most 1. */
/* A bound on W_k over the domain: each surface above node k passes on at most kr + kt T of its
 * light to either child (the mirror child takes the refraction's share under Fresnel or total
 * internal reflection), the larger of a checkerboard's two materials. */
static double weight_bound(const pt_ctx_t *C, int k) {
  double w = 1.0;
  for (int j = C->paths.node[k].parent; j >= 0; j = C->paths.node[j].parent) {
    const pt_node_t *a = &C->paths.node[j];
    const rt_object_t *o = &C->s->object[a->object];
    double most = 0.0;
    for (int i = 0; i < (a->textured ? 2 : 1); i++) {
      const rt_material_t *m = &C->s->material[i ? o->material2 : o->material];
      double t = fmax(m->transmittance.r, fmax(m->transmittance.g, m->transmittance.b));
      most = fmax(most, m->kr + m->kt * t);
    }
    w *= most;
  }
  return w;
}

static void highlight_guard(pt_ctx_t *C, pt_node_t *n, int k, boundary_t *b) {
  const rt_scene_t *s = C->s;
  n->highlight = 0;
  if (!rt_plan_has(C->plan, RT_EFFECT_SPECULAR))
    return;
  const rt_object_t *o = &s->object[n->object];
  double ks = 0.0, phong = INFINITY; /* the largest ks, the broadest lobe */
  for (int i = 0; i < (n->textured ? 2 : 1); i++) {
    const rt_material_t *m = &s->material[i ? o->material2 : o->material];
    if (m->ks > 0.0) {
      ks = fmax(ks, m->ks);
      phong = fmin(phong, m->phong);
    }
  }
  if (!(ks > 0.0))
    return;
  const rt_prim_t *pr = &s->prim[n->prim];
  px_vec3_t d0 = C->trees.axial.node[k].dir, nu = rt_prim_normal_at(pr, n->o);
  px_vec3_t m0 = px_v3_axpy(-2.0 * px_v3_dot(d0, nu), nu, d0);
  const double(*bxi)[2] = boundary_xi(C, b);
  double cmin = 1.0, r = 0.0;
  for (int j = 0; j < 8; j++) {
    px_vec3_t p, d, hit;
    if (!pt_node_ray(n, bxi[j], &p, &d) || !pt_node_hit(s, n, p, d, &hit)) {
      n->highlight = 1;
      return;
    }
    r = fmax(r, px_v3_norm(px_v3_sub(p, n->o))); /* as hit_radius() finds it */
    nu = rt_prim_normal_at(pr, hit);
    cmin = fmin(cmin, px_v3_dot(px_v3_axpy(-2.0 * px_v3_dot(d, nu), nu, d), m0));
  }
  if (n->guard_r < 0.0)
    n->guard_r = PT_GUARD_INFLATE * r / n->cos_in;
  r = n->guard_r;
  double tm = PT_GUARD_INFLATE * acos(fmax(-1.0, cmin)), sum = 0.0;
  for (int l = 0; l < s->nlight; l++) {
    const rt_light_t *li = &s->light[l];
    if (li->kind == RT_LIGHT_AREA)
      continue; /* shaded per sample (interp_plan.c) */
    px_vec3_t L = px_v3_scale(li->v, -1.0);
    double tl = 0.0, in = fmax(li->intensity.r, fmax(li->intensity.g, li->intensity.b));
    if (li->kind == RT_LIGHT_POINT) {
      L = px_v3_sub(li->v, n->o);
      double dist = px_v3_norm(L);
      L = px_v3_scale(L, 1.0 / dist);
      tl = r < dist ? asin(r / dist) : M_PI;
      if (li->falloff == RT_FALLOFF_INVERSE_SQUARE)
        in = r < dist ? in / ((dist - r) * (dist - r)) : INFINITY;
    }
    double amin = acos(fmax(-1.0, fmin(1.0, px_v3_dot(m0, L)))) - tm - tl;
    sum += ks * in * (amin <= 0.0 ? 1.0 : amin >= 0.5 * M_PI ? 0.0 : pow(cos(amin), phong));
  }
  /* the tolerance of a certified lattice cell, the smaller; a NaN sets the flag */
  n->highlight =
      !(weight_bound(C, k) * sum <= PT_FAINT_SHARE * PT_CERTIFIED_MARGIN * C->opt->brightness_tol);
}

/* Node k's tolerance in units of rho (pt_node_t.tol_scale): with the image-space tolerance,
 * 1 / W for the weight W with which its light reaches the pixel (the axial ray's, its largest
 * channel), W taken at least the option's floor and at most 1. */
static double tol_scale(const pt_ctx_t *C, int k) {
  if (C->opt->tolerance != PT_TOL_IMAGE)
    return 1.0;
  rt_rgb_t w = C->trees.axial.node[k].weight;
  double m = fmax(w.r, fmax(w.g, w.b)); /* fmax and fmin drop a NaN: then 1 / 1 */
  return 1.0 / fmax(fmin(m, 1.0), C->opt->weight_floor);
}

/* Step 2 for every node whose path agrees at the corners: topology for all, matrices for the
 * agreeing ones (a node whose path cannot be re-traced is treated as disagreeing, and so are its
 * descendants). Then step 4 per path: a path is traced with its matrix when the domain's spread is
 * within its limit (4a) and, in certified mode, its exact check passed; otherwise exactly along
 * its known path (4b; and 4c unless the domain is subdivided, see pt__domain). *over counts the
 * paths over their limit whose pencil is not narrower than a pixel (4c candidates), *paths the
 * agreeing non-miss paths; the return value is the smallest limit among the 4c candidates. In
 * *cost: exact rays per sample that subtrees below disagreeing nodes need. */
static double build_paths(pt_ctx_t *C, const pt_pencil_t *p, boundary_t *b, double xi_domain,
                          double dmin, double *cost, int *over, int *paths, int *partial) {
  double need = INFINITY;
  *cost = 0.0;
  *over = *paths = *partial = 0;
  C->paths.n = C->trees.axial.n;
  int *size = C->lattice.plan.shaded; /* subtree sizes, scratch (children follow their parents) */
  for (int k = 0; k < C->paths.n; k++)
    size[k] = 1;
  for (int k = C->paths.n - 1; k > 0; k--)
    size[C->trees.axial.node[k].parent] += size[k];
  for (int k = 0; k < C->paths.n; k++) {
    pt_node_t *n = &C->paths.node[k];
    int par = C->trees.axial.node[k].parent;
    pt_path_topology(C->s, &C->trees.axial, k, par >= 0 ? &C->paths.node[par] : NULL, n);
    if (C->plan->spectral == RT_SPECTRAL_PENCIL && !n->miss && n->object >= 0) {
      const rt_object_t *o = &C->s->object[n->object];
      n->spectral = rt_shade_spectral_at(C->plan, &C->s->material[o->material], n->depth) ||
                    (o->material2 >= 0 &&
                     rt_shade_spectral_at(C->plan, &C->s->material[o->material2], n->depth));
    }
    n->light_agree = C->corners.light[k];
    int parent_ok = par < 0 || C->paths.node[par].mode != PT_NODE_EXACT;
    /* with ray interpolation, a node below an edge is traced along its path at the lattice
     * points with a scene search that must confirm it (the lattice then finds the edge) */
    int verify = !C->corners.agree[k] && parent_ok && par >= 0 && interpolating(C);
    int mode = (C->corners.agree[k] || verify) && parent_ok ? PT_NODE_MATRIX : PT_NODE_EXACT;
    if (!C->corners.agree[k] && parent_ok) { /* an edge below the primary ray */
      need = fmin(need, 0.5 * xi_domain);
      *cost += size[k];
    }
    n->guard_r = -1.0;
    n->tol_scale = tol_scale(C, k);
    pt_pencil_t pk = *p;
    pk.rho = p->rho * n->tol_scale;
    if (mode &&
        pt_path_build(C->s, &C->trees.axial, k, C->paths.node, &pk, &C->paths.scratch) != PX_OK)
      mode = PT_NODE_EXACT;
    if (mode && par >= 0 && segment_guarded(C, k, b)) {
      /* traced exactly per sample (a scene search), as below an edge */
      mode = PT_NODE_EXACT;
      C->st.paths_guard++;
      need = fmin(need, 0.5 * xi_domain);
      *cost += size[k];
    }
    if (mode && !n->miss && rt_plan_has(C->plan, RT_EFFECT_SHADOWS))
      shadow_guard(C, n, b);
    if (mode && !n->miss && interpolating(C))
      highlight_guard(C, n, k, b);
    if (mode && verify) {
      mode = PT_NODE_PATH;
      n->verify = 1;
      *partial = 1;
    }
    if (mode == PT_NODE_MATRIX && !n->miss) {
      (*paths)++;
      int checked = !p->check || n->e_check <= PT_CERTIFIED_MARGIN * n->tau;
      if (xi_domain > n->xi_max || !checked) {
        mode = PT_NODE_PATH;
        C->st.paths_exact++;
        if (!(2.0 * n->xi_max < dmin) && xi_domain > n->xi_max) { /* not 4b */
          (*over)++;
          need = fmin(need, n->xi_max);
        }
      }
    }
    n->mode = mode;
    if (mode == PT_NODE_EXACT || n->light_agree != ~0u)
      *partial = 1;
  }
  /* a path traced exactly needs exact hits on the way: its ancestors are traced along their
   * paths too (which costs no more than their matrices: shade.h computes the reflected and
   * refracted directions anyway) */
  for (int k = 0; k < C->paths.n; k++)
    if (C->paths.node[k].mode == PT_NODE_PATH)
      for (int a = C->paths.node[k].parent; a >= 0 && C->paths.node[a].mode == PT_NODE_MATRIX;
           a = C->paths.node[a].parent)
        C->paths.node[a].mode = PT_NODE_PATH;
  return need;
}

void pt__domain(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  pt_stats_t *st = &C->st;
  st->domains++;
  int spp = C->opt->spp_side * C->opt->spp_side;
  if ((x1 - x0) * (y1 - y0) * spp < PT_MIN_DOMAIN_SAMPLES) { /* the axial ray would cost more
                                                               than the pencil can save */
    st->domains_small++;
    pt__exact_domain(C, x0, y0, x1, y1);
    return;
  }
  double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  rt_ray_t axial = rt_view_ray(C->view, cx, cy, C->s->ior);
  /* step 3 first where it needs no axial tree: the corners must meet one surface first (the
   * primary node agrees nowhere else), and the guard looks at the primary cone alone */
  const int xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
  const pt_ctree_t *ct[4];
  int deep = 0, edge = px_frame_from_z(axial.d, C->view->down, &C->paths.frame) != PX_OK;
  for (int i = 0; i < 4 && !deep; i++) {
    ct[i] = corner(C, xs[i], ys[i]);
    deep = !ct[i]->valid; /* a corner tree is invalid only when it has more than cap nodes */
  }
  for (int i = 1; i < 4 && !edge && !deep; i++)
    edge = !pt_ctree_same_root(ct[0], ct[i]);
  double xi_domain = 0.0;
  for (int i = 0; i < 4 && !edge && !deep; i++)
    xi_domain = fmax(xi_domain, xi_norm(C, xs[i], ys[i]));
  if (!edge && !deep && C->guard->n && !C->faces->n && /* no polygons: spheres alone */
      pt_guard_fires(C->guard, C->view->eye, axial.d, asin(fmin(1.0, xi_domain)))) {
    edge = 1;
    st->domains_guard++;
  } else if (!edge && !deep && C->faces->n) {
    px_vec3_t d[4];
    for (int i = 0; i < 4; i++)
      d[i] = rt_view_ray(C->view, xs[i], ys[i], C->s->ior).d;
    if (pt_guard_view(C->guard, C->faces, C->s, C->view->eye, d, axial.d,
                      asin(fmin(1.0, xi_domain)), ct[0]->n ? ct[0]->node[0].prim : -1)) {
      edge = 1;
      st->domains_guard++;
    }
  }
  if (!edge && !deep) { /* step 2's axial tree (unfinished when too deep for the paths), and
                           step 3 node by node */
    pt__trace_shape(C, &C->trees.axial, &axial);
    st->exact_traces++;
    deep = C->trees.axial.overflow;
    if (!deep) {
      pt_tree_agree(&C->trees.axial, ct, 4, C->corners.map, C->corners.agree, C->corners.light);
      edge = C->trees.axial.n == 0 || !C->corners.agree[0];
    }
  }
  if (deep) { /* more nodes than the paths may have: no pencil, and no subdivision either */
    st->domains_deep++;
    pt__exact_domain(C, x0, y0, x1, y1);
    return;
  }
  if (edge) {
    st->domains_edge++;
    subdivide(C, x0, y0, x1, y1, 2);
    return;
  }
  /* step 2: a system matrix per path; step 4: tolerance and spread limit */
  double a[2], b[2], c[2], d[2];
  pt__xi(C, cx + 0.5, cy, a);
  pt__xi(C, cx - 0.5, cy, b);
  pt__xi(C, cx, cy + 0.5, c);
  pt__xi(C, cx, cy - 0.5, d);
  pt_pencil_t p = {
      C->view->eye, C->paths.frame, {{a[0] - b[0], a[1] - b[1]}, {c[0] - d[0], c[1] - d[1]}},
      C->opt->rho,  C->opt->bound,  xi_domain,
      NULL};
  boundary_t bnd = boundary_of(x0, y0, x1, y1);
  if (C->opt->certified)
    p.check = boundary_xi(C, &bnd);
  int partial, over, paths;
  double cost,
      dmin = fmin(hypot(p.delta[0][0], p.delta[0][1]), hypot(p.delta[1][0], p.delta[1][1]));
  double need = build_paths(C, &p, &bnd, xi_domain, dmin, &cost, &over, &paths, &partial);
  if (C->paths.node[0].mode == PT_NODE_EXACT) { /* the primary path cannot be re-traced */
    st->domains_edge++;
    subdivide(C, x0, y0, x1, y1, 2);
    return;
  }
  /* 4c: subdivide when most paths are over their limit (the pencil is too wide for this domain),
   * or when the subtrees below an edge would cost more exact rays per sample than about
   * k^2 (5 + nodes) rays for k x k smaller domains (axial and corner trees, matrices). Not with
   * ray interpolation: there only the lattice points are traced through the paths, those of a
   * path over its limit exactly along it (4b), and the lattice's own error test decides how
   * finely to interpolate; smaller domains would rebuild every path for the same points, and an
   * edge below the primary ray mostly runs on through the smaller domains: slower, and no more
   * accurate (docs/tuning.md) */
  int w = x1 - x0, h = y1 - y0, s = C->opt->spp_side;
  double k = ceil(xi_domain / need);
  if (isfinite(need) && (w > 1 || h > 1) && !interpolating(C) &&
      (2 * over > paths || k * k * (5.0 + C->paths.n) < cost * w * h * s * s)) {
    st->domains_split++;
    subdivide(C, x0, y0, x1, y1, k > 64.0 ? 64 : (int)fmax(2.0, k));
    return;
  }
  st->domains_accepted++;
  st->domains_partial += (uint64_t)partial;
  accept_domain(C, x0, y0, x1, y1, &axial);
}
