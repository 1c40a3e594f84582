/* path.c -- the paths of the axial ray's tree and their system matrices (paper section 4.1 (1),
 * step 2), the tolerance of Eq. (3) carried onto each node's surface, the constant C of Eq. (4)
 * and the spread limit of Eq. (6).
 *
 * A node's path is handed to reference/ as an exact optical system, so that the matrices come
 * from the verified ex_trace_axial() + ex_axial_cascade() rather than from a second
 * implementation of Eqs. (1)-(2). */
#include "pencil/path.h"

#include <math.h>

#include "bound.h"
#include "core/intersect.h"
#include "paraxial/bounds.h"
#include "paraxial/vec3.h"

/* The quadric of a primitive: sphere, or the plane of a plane or polygon. */
static ex_quadric_t prim_quadric(const rt_scene_t *s, int prim) {
  const rt_prim_t *p = &s->prim[prim];
  if (p->kind == RT_PRIM_SPHERE)
    return ex_quadric_sphere(p->sphere.c, p->sphere.r);
  if (p->kind == RT_PRIM_PLANE)
    return ex_quadric_plane(p->plane.p, p->plane.n);
  return ex_quadric_plane(px_v3_scale(p->polygon.n, p->polygon.d), p->polygon.n);
}

/* Index after a refraction at tree node a, by rt_shade_surface()'s rule: the object's index when
 * the ray enters it (meets the outward side), the scene's when it leaves. */
static double index_after(const rt_scene_t *s, const rt_tree_node_t *a) {
  px_vec3_t n = rt_prim_normal(s, a->prim, a->point);
  int entering = px_v3_dot(n, a->dir) < 0.0;
  return entering ? rt_scene_material_at(s, a->prim, a->point, NULL)->ior : s->ior;
}

double pt_footprint(px_mat2_t b, const double delta[2][2], px_vec3_t e1, px_vec3_t e2, px_vec3_t ez,
                    px_vec3_t n, px_vec3_t j[2], double ginv[3]) {
  double cz = px_v3_dot(n, ez);
  for (int i = 0; i < 2; i++) {
    double x1 = b.m[0][0] * delta[i][0] + b.m[0][1] * delta[i][1];
    double x2 = b.m[1][0] * delta[i][0] + b.m[1][1] * delta[i][1];
    px_vec3_t v = px_v3_add(px_v3_scale(e1, x1), px_v3_scale(e2, x2));
    /* slide along ez onto the tangent plane: v - (n.v / n.ez) ez */
    j[i] = cz != 0.0 ? px_v3_axpy(-px_v3_dot(n, v) / cz, ez, v) : v;
  }
  double g00 = px_v3_dot(j[0], j[0]), g01 = px_v3_dot(j[0], j[1]), g11 = px_v3_dot(j[1], j[1]);
  double det = g00 * g11 - g01 * g01;
  double lmin = 0.5 * (g00 + g11 - hypot(g00 - g11, 2.0 * g01));
  if (!(det > 1e-24 * (g00 + g11) * (g00 + g11)) || !(lmin > 0.0)) {
    ginv[0] = ginv[1] = ginv[2] = INFINITY;
    return 0.0;
  }
  ginv[0] = g11 / det;
  ginv[1] = -g01 / det;
  ginv[2] = g00 / det;
  return sqrt(lmin);
}

double pt_pixels(const pt_node_t *n, px_vec3_t e) {
  double r0 = px_v3_dot(n->j[0], e), r1 = px_v3_dot(n->j[1], e);
  double a0 = n->ginv[0] * r0 + n->ginv[1] * r1, a1 = n->ginv[1] * r0 + n->ginv[2] * r1;
  return sqrt(a0 * a0 + a1 * a1); /* pixel counts: far from overflow, hypot's care not needed */
}

double pt_spread_limit(double c, double k3, double tau, double cos_in) {
  double xi;
  if (!(tau > 0.0) || !(cos_in > 0.0) || !(c >= 0.0) ||
      px_spread_limit(c, k3, tau * cos_in, PT_SPREAD_CAP, &xi, NULL) != PX_OK)
    return 0.0;
  return xi;
}

int pt_node_ray(const pt_node_t *n, const double xi[2], px_vec3_t *p, px_vec3_t *d) {
  double x1 = n->b.m[0][0] * xi[0] + n->b.m[0][1] * xi[1];
  double x2 = n->b.m[1][0] * xi[0] + n->b.m[1][1] * xi[1];
  double s1 = n->d.m[0][0] * xi[0] + n->d.m[0][1] * xi[1];
  double s2 = n->d.m[1][0] * xi[0] + n->d.m[1][1] * xi[1];
  double c2 = 1.0 - s1 * s1 - s2 * s2;
  if (!(c2 > 0.0))
    return 0;
  *p = px_v3_axpy(x1, n->e1, px_v3_axpy(x2, n->e2, n->o));
  *d = px_v3_axpy(s1, n->e1, px_v3_axpy(s2, n->e2, px_v3_scale(n->ez, sqrt(c2))));
  return 1;
}

int pt_node_hit(const rt_scene_t *s, const pt_node_t *n, px_vec3_t p, px_vec3_t d, px_vec3_t *hit) {
  const rt_prim_t *pr = &s->prim[n->prim];
  if (pr->kind == RT_PRIM_SPHERE) { /* |p + t d - c|^2 = r^2, the root nearest t = 0 */
    px_vec3_t oc = px_v3_sub(p, pr->sphere.c);
    double b = px_v3_dot(oc, d);
    double c = (px_v3_norm(oc) - pr->sphere.r) * (px_v3_norm(oc) + pr->sphere.r);
    double disc = b * b - c;
    if (disc < 0.0)
      return 0;
    double q = -b - copysign(sqrt(disc), b); /* larger-magnitude root; the other is c / q */
    double t = q != 0.0 ? c / q : 0.0;
    if (fabs(q) < fabs(t))
      t = q;
    *hit = px_v3_axpy(t, d, p);
    return 1;
  }
  px_vec3_t nn = pr->kind == RT_PRIM_PLANE ? pr->plane.n : pr->polygon.n;
  double off = pr->kind == RT_PRIM_PLANE ? px_v3_dot(nn, pr->plane.p) : pr->polygon.d;
  double den = px_v3_dot(nn, d);
  if (den == 0.0)
    return 0;
  double t = (off - px_v3_dot(nn, p)) / den;
  *hit = px_v3_axpy(t, d, p);
  if (pr->kind == RT_PRIM_POLYGON) { /* inside test: a short segment straddling the plane */
    double h = 1e-6 * (1.0 + fabs(hit->x) + fabs(hit->y) + fabs(hit->z));
    rt_ray_t seg = {px_v3_axpy(-h, d, *hit), d, 0.0, 2.0 * h, 1.0, -1, 0.0f};
    double tt;
    if (!rt_prim_intersect(s, n->prim, &seg, 2.0 * h, &tt))
      return 0;
  }
  return 1;
}

/* Exact error of the linear map in the plane normal to the output axis at the eye direction xi:
 * the x part of ex_map(psi) - T (0, 0, xi), where w's system carries psi to the node (the whole
 * path from the eye, psi = (0, 0, xi), or one step of it). The exact ray vector at the node goes
 * to out (may be NULL). */
static px_status_t exact_error(const pt_path_scratch_t *w, const pt_node_t *n, const double psi[4],
                               const double xi[2], double e[2], double *out) {
  double tmp[4];
  if (!out)
    out = tmp;
  px_status_t st = ex_map(&w->sys, &w->ax, psi, out);
  if (st != PX_OK)
    return st;
  e[0] = out[0] - (n->b.m[0][0] * xi[0] + n->b.m[0][1] * xi[1]);
  e[1] = out[1] - (n->b.m[1][0] * xi[0] + n->b.m[1][1] * xi[1]);
  return PX_OK;
}

/* The probe "constant": the worst exact error on the spread circle |xi| = xi_domain over
 * xi_domain^2 (not a bound; for comparison with the Appendix bounds). w holds the whole path. */
static px_status_t probe_c(const pt_path_scratch_t *w, const pt_node_t *n, double xi_domain,
                           double *c) {
  double worst = 0.0;
  if (!(xi_domain > 0.0)) {
    *c = 0.0;
    return PX_OK;
  }
  for (int j = 0; j < 8; j++) {
    double xi[2] = {xi_domain * cos(j * M_PI / 4), xi_domain * sin(j * M_PI / 4)}, e[2];
    double psi[4] = {0.0, 0.0, xi[0], xi[1]};
    px_status_t st = exact_error(w, n, psi, xi, e, NULL);
    if (st != PX_OK)
      return st;
    worst = fmax(worst, hypot(e[0], e[1]));
  }
  *c = worst / (xi_domain * xi_domain);
  return PX_OK;
}

/* Certified mode: the exact error at the 8 boundary points, each edge's error interpolated by
 * the quadratic through its corner, midpoint and corner (exact for a second-order error), and
 * the largest magnitude along the four edges, carried onto the surface (/ cos).
 * The exact map of the whole path is the composition of its steps' exact maps, as its matrix is
 * the product of theirs (section 2.2, T_k = S_k T_parent): each ex_map ends with the ray vector
 * in the step's output frame, which is the next step's input frame. So each boundary ray is
 * carried one step, w's system (the parent's surface and the transfer to the node), from the
 * parent's exact ray vector (psi = (0, 0, xi) at the eye for the primary ray), and kept in
 * n->xcheck for the node's children: one step per node and point instead of the whole path. */
static px_status_t check_boundary(const pt_path_scratch_t *w, const pt_node_t *parent, pt_node_t *n,
                                  const double (*pts)[2], double *out) {
  double e[8][2], worst = 0.0;
  for (int j = 0; j < 8; j++) {
    double eye[4] = {0.0, 0.0, pts[j][0], pts[j][1]};
    px_status_t st =
        exact_error(w, n, parent ? parent->xcheck[j] : eye, pts[j], e[j], n->xcheck[j]);
    if (st != PX_OK)
      return st;
  }
  /* squared magnitudes; the quadratic's t = 1 point of an edge is the next edge's t = 0 */
  for (int k = 0; k < 16; k++) {
    double t = k / 16.0, la = (1 - t) * (1 - 2 * t), lm = 4 * t * (1 - t), lb = t * (2 * t - 1);
    for (int edge = 0; edge < 4; edge++) {
      const double *a = e[2 * edge], *m = e[2 * edge + 1], *b = e[(2 * edge + 2) % 8];
      double v0 = la * a[0] + lm * m[0] + lb * b[0], v1 = la * a[1] + lm * m[1] + lb * b[1];
      double v = v0 * v0 + v1 * v1;
      worst = v > worst ? v : worst; /* fmax(worst, v): a NaN v is ignored */
    }
  }
  *out = sqrt(worst) / n->cos_in;
  return PX_OK;
}

/* Stages for the surfaces met before node k; returns how many, or -1 when the path is too
 * long. *ior gets the index of the medium the node's ray travels in. */
static int path_stages(const rt_scene_t *s, const rt_tree_t *tree, int k, ex_stage_t *stage,
                       double *ior) {
  int chain[EX_MAX_STAGES + 1], m = 0;
  for (int a = k; a >= 0; a = tree->node[a].parent) {
    if (m > EX_MAX_STAGES)
      return -1;
    chain[m++] = a;
  }
  double n = s->ior;
  for (int j = m - 1; j >= 1; j--) {
    const rt_tree_node_t *a = &tree->node[chain[j]], *next = &tree->node[chain[j - 1]];
    ex_stage_t *st = &stage[m - 1 - j];
    st->surface = prim_quadric(s, a->prim);
    st->at_origin = 0;
    if (next->kind == RT_RAY_REFRACT) {
      st->event = PX_EVENT_REFRACT;
      n = index_after(s, a);
    } else {
      st->event = PX_EVENT_REFLECT;
    }
    st->n_after = n;
  }
  *ior = n;
  return m - 1;
}

void pt_path_topology(const rt_scene_t *s, const rt_tree_t *tree, int k, const pt_node_t *parent,
                      pt_node_t *out) {
  const rt_tree_node_t *nd = &tree->node[k];
  out->parent = nd->parent;
  out->kind = nd->kind;
  out->depth = nd->depth;
  out->miss = (nd->flags & RT_NODE_MISS) != 0;
  out->object = nd->object;
  out->prim = nd->prim;
  out->textured = nd->texel >= 0;
  out->measured = nd->object >= 0 && rt_object_measured(s, nd->object);
  out->child[0] = out->child[1] = -1;
  out->child_kind[0] = out->child_kind[1] = -1;
  for (int j = k + 1, c = 0; j < tree->n && c < 2; j++)
    if (tree->node[j].parent == k) {
      out->child[c] = j;
      out->child_kind[c++] = tree->node[j].kind;
    }
  if (!parent)
    out->ior = s->ior;
  else if (nd->kind == RT_RAY_REFRACT)
    out->ior = index_after(s, &tree->node[nd->parent]);
  else
    out->ior = parent->ior;
  out->mode = 0;
  out->spectral = 0;
  out->verify = 0;
  out->highlight = 0;
  out->light_agree = 0;
  out->light_guard = 0;
  out->known = 0;
  out->c = 0.0;
  out->xi_max = INFINITY;
  out->tau = INFINITY;
  out->tol_scale = 1.0;
  out->interval = INFINITY;
  out->e_check = -1.0;
  out->nstep = 0;
}

/* The step from the parent's hit to node k as a one-stage system in w (the root: a transfer
 * from the eye). */
static void step_matrix(const rt_scene_t *s, const rt_tree_t *tree, int k, const pt_node_t *parent,
                        const pt_pencil_t *p, const pt_node_t *out, pt_path_scratch_t *w) {
  const rt_tree_node_t *nd = &tree->node[k];
  if (!parent) {
    w->sys = (ex_system_t){p->eye, p->frame, s->ior, w->stage, 0, nd->t, 0.0};
    return;
  }
  ex_stage_t *st = &w->stage[0];
  st->surface = prim_quadric(s, parent->prim);
  st->at_origin = 1;
  st->event = nd->kind == RT_RAY_REFRACT ? PX_EVENT_REFRACT : PX_EVENT_REFLECT;
  st->n_after = out->ior;
  px_frame_t f = {parent->e1, parent->e2, parent->ez};
  w->sys = (ex_system_t){parent->o, f, parent->ior, w->stage, 1, nd->t, 0.0};
}

px_status_t pt_path_full(const rt_scene_t *s, const rt_tree_t *tree, int k, const pt_pencil_t *p,
                         pt_path_scratch_t *w) {
  double ior;
  int nstage = path_stages(s, tree, k, w->stage, &ior);
  if (nstage < 0)
    return PX_EINVAL;
  w->sys = (ex_system_t){p->eye, p->frame, s->ior, w->stage, (size_t)nstage, tree->node[k].t, 0.0};
  return ex_trace_axial(&w->sys, &w->ax);
}

/* [B; D] of T_k = S [B_p; D_p] (only the columns acting on xi are needed for a pinhole). */
static void chain(px_mat4_t sm, const pt_node_t *parent, pt_node_t *out) {
  px_mat2_t sa = px_mat4_block(sm, 0, 0), sb = px_mat4_block(sm, 0, 1);
  px_mat2_t sc = px_mat4_block(sm, 1, 0), sd = px_mat4_block(sm, 1, 1);
  if (!parent) {
    out->b = sb;
    out->d = sd;
    return;
  }
  out->b = px_mat2_add(px_mat2_mul(sa, parent->b), px_mat2_mul(sb, parent->d));
  out->d = px_mat2_add(px_mat2_mul(sc, parent->b), px_mat2_mul(sd, parent->d));
}

px_status_t pt_path_build(const rt_scene_t *s, const rt_tree_t *tree, int k, pt_node_t *nodes,
                          const pt_pencil_t *p, pt_path_scratch_t *w) {
  const rt_tree_node_t *nd = &tree->node[k];
  pt_node_t *out = &nodes[k];
  const pt_node_t *parent = nd->parent >= 0 ? &nodes[nd->parent] : NULL;
  if (out->miss)
    return PX_OK;
  step_matrix(s, tree, k, parent, p, out, w);
  px_status_t st = ex_trace_axial(&w->sys, &w->ax);
  if (st != PX_OK)
    return st;
  /* the re-traced axial ray must end where the renderer's did */
  if (px_v3_norm(px_v3_sub(w->ax.out_origin, nd->point)) > 1e-7 * (1.0 + w->ax.length))
    return PX_EMISS;
  px_cascade_t cas;
  st = ex_axial_cascade(&w->sys, &w->ax, PX_VARIANT_CORRECTED, out->step, 3, &cas);
  if (st != PX_OK)
    return st;
  out->nstep = (int)cas.n;
  px_mat4_t sm = px_cascade_product(&cas);
  chain(sm, parent, out);
  if (!px_mat4_isfinite(px_mat4_blocks(out->b, out->b, out->d, out->d)))
    return PX_ENONFINITE;
  out->o = w->ax.out_origin;
  out->e1 = w->ax.out_frame.x1;
  out->e2 = w->ax.out_frame.x2;
  out->ez = w->ax.out_frame.z;
  out->n = nd->normal;
  out->cos_in = fabs(px_v3_dot(out->n, out->ez));
  if (!(out->cos_in > PX_COS_MIN))
    return PX_EGRAZING;
  out->interval =
      pt_footprint(out->b, p->delta, out->e1, out->e2, out->ez, out->n, out->j, out->ginv);
  out->tau = p->rho * out->interval;
  if (p->check) { /* w still holds the step from the parent */
    st = check_boundary(w, parent, out, p->check, &out->e_check);
    if (st != PX_OK)
      return st;
  }
  if (p->bound == PT_BOUND_PROBE) {
    st = pt_path_full(s, tree, k, p, w);
    if (st == PX_OK)
      st = probe_c(w, out, p->xi_domain, &out->c);
  } else {
    st = pt__bound_step(parent, sm, p->bound, out, &out->c);
  }
  if (st != PX_OK)
    return st;
  out->xi_max = pt_spread_limit(out->c, parent ? 0.0 : 0.77 * nd->t, out->tau, out->cos_in);
  return PX_OK;
}
