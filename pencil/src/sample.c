/* sample.c -- what every way of tracing a sample shares (paper section 4.1 (1), section 5): the
 * pixel being accumulated, samples traced through the domain's system matrices, samples and pixels
 * traced exactly (edges and step 4b), the auxiliary channels, and the Fig. 10 bookkeeping. */
#include <math.h>

#include "internal.h"
#include "paraxial/vec3.h"

size_t pt__pixel_index(const pt_ctx_t *C, int i, int j) {
  return (size_t)j * (size_t)C->img->width + (size_t)i;
}

float *pt__error_slot(pt_ctx_t *C, int i, int j, int a, int b) {
  int s = C->opt->spp_side;
  if (!C->sample_error)
    return NULL;
  return C->sample_error + pt__pixel_index(C, i, j) * (size_t)(s * s) + (size_t)(b * s + a);
}

uint64_t pt__rays_now(const pt_ctx_t *C) {
  return rt_stats_total(&C->ex.stats);
}

void pt__write_pixel(pt_ctx_t *C, int i, int j, rt_rgb_t sum, pt_method_t m, double perr,
                     uint64_t rays) {
  size_t k = pt__pixel_index(C, i, j);
  if (C->extra && C->extra->rays)
    C->extra->rays[k] = (float)rays;
  double w = 1.0 / (C->opt->spp_side * C->opt->spp_side);
  C->img->ch[RT_CH_R][k] = (float)(sum.r * w);
  C->img->ch[RT_CH_G][k] = (float)(sum.g * w);
  C->img->ch[RT_CH_B][k] = (float)(sum.b * w);
  if (C->extra && C->extra->method)
    C->extra->method[k] = (float)m;
  if (C->extra && C->extra->error)
    C->extra->error[k] = (float)perr;
}

/* Auxiliary channels of pixel (i, j) from an exact tree of its centre ray (as the reference
 * renderer writes them; the tree's shape alone: xr_exact_t.halt). */
void pt__aux_exact(pt_ctx_t *C, int i, int j) {
  rt_ray_t r = rt_view_ray(C->view, i + 0.5, j + 0.5, C->s->ior);
  pt__trace_shape(C, &C->trees.probe, &r);
  const rt_tree_t *t = &C->trees.probe;
  rt_image_set_aux(C->img, C->s, pt__pixel_index(C, i, j), t);
}

/* Auxiliary channels from the pencil's own pt__geometry of the pixel's centre ray (rec), so that
 * the pencil image's checkerboard points can be compared with the exact image's. */
void pt__aux_pencil(pt_ctx_t *C, int i, int j, const pt_geom_t *rec) {
  const int kk[2] = {C->paths.transmit, C->paths.reflect};
  if (rec[0].ok != 1 || (kk[0] >= 0 && rec[kk[0]].ok != 1) || (kk[1] >= 0 && rec[kk[1]].ok != 1)) {
    pt__aux_exact(C, i, j);
    return;
  }
  size_t k = pt__pixel_index(C, i, j);
  const pt_node_t *root = &C->paths.node[0];
  if (C->img->spectral) {
    /* `spectral` from the centre ray's exact tree's shape: below a node traced per sample the
     * ray's tree may meet glass the domain's does not, and the pencil's hit may lie in another
     * checker square than the exact one (the other channels keep the pencil's points) */
    rt_ray_t r = rt_view_ray(C->view, i + 0.5, j + 0.5, C->s->ior);
    pt__trace_shape(C, &C->trees.probe, &r);
    rt_image_set_spectral(C->img, C->s, k, &C->trees.probe);
  }
  C->img->ch[RT_CH_Z][k] =
      root->miss ? INFINITY : (float)px_v3_norm(px_v3_sub(rec[0].p, C->view->eye));
  C->img->ch[RT_CH_ID][k] = (float)root->object;
  const rt_channel_t base[2] = {RT_CH_T_U, RT_CH_R_U};
  for (int p = 0; p < 2; p++) {
    double u = NAN, v = NAN;
    if (kk[p] >= 0)
      rt_plane_coords(&C->s->prim[C->paths.node[kk[p]].prim].plane, rec[kk[p]].p, &u, &v);
    C->img->ch[base[p]][k] = (float)u;
    C->img->ch[base[p] + 1][k] = (float)v;
    C->img->ch[base[p] + 2][k] = kk[p] >= 0 ? (float)C->paths.node[kk[p]].depth : -1.0f;
  }
}

/* Step 3 failed or 4b: every sample of the pixels of the domain by the exact tracer. */
void pt__exact_domain(pt_ctx_t *C, int x0, int y0, int x1, int y1) {
  int s = C->opt->spp_side;
  for (int j = y0; j < y1; j++)
    for (int i = x0; i < x1; i++) {
      rt_rgb_t sum = rt_rgb(0, 0, 0);
      uint64_t rays0 = pt__rays_now(C);
      int have_centre = 0;
      for (int b = 0; b < s; b++)
        for (int a = 0; a < s; a++) {
          rt_ray_t r = rt_view_ray(C->view, i + (a + 0.5) / s, j + (b + 0.5) / s, C->s->ior);
          /* odd s: the centre sample's tree gives the auxiliary channels, as the exact renderer
           * records them, instead of a second trace of the same ray */
          int centre = C->opt->aux && (s & 1) && a == s / 2 && b == s / 2;
          C->ex.tree = centre ? &C->trees.probe : NULL;
          sum = rt_rgb_add(sum, xr_exact_primary(&C->ex, &r));
          C->ex.tree = NULL;
          if (centre) {
            rt_image_set_aux(C->img, C->s, pt__pixel_index(C, i, j), &C->trees.probe);
            have_centre = 1;
          }
          if (C->opt->measure) {
            const double zero[PT_MEASURE_ERRORS] = {0.0, 0.0, 0.0, 0.0};
            pt__account(C, zero, 0, pt__error_slot(C, i, j, a, b));
          }
        }
      C->st.samples[PT_METHOD_EXACT] += (uint64_t)(s * s);
      pt__write_pixel(C, i, j, sum, PT_METHOD_EXACT, NAN, pt__rays_now(C) - rays0);
      if (C->opt->aux && !have_centre)
        pt__aux_exact(C, i, j);
    }
}

/* Per-sample bookkeeping of the Fig. 10 measurement; returns the pixel's running maximum. */
double pt__measure_sample(pt_ctx_t *C, const rt_ray_t *ray, const pt_geom_t *rec, int i, int j,
                          int a, int b, double pmax) {
  int s = C->opt->spp_side;
  double e[PT_MEASURE_ERRORS];
  int points = pt__measure(C, ray, i + (a + 0.5) / s, j + (b + 0.5) / s, rec, e);
  pt__account(C, e, points, pt__error_slot(C, i, j, a, b));
  if (points && (isnan(pmax) || e[PT_E_PIXELS] > pmax))
    pmax = e[PT_E_PIXELS];
  return pmax;
}

/* Geometry-only evaluation into C->sample.geom (aux channels, measurement); E is left as it was. */
void pt__geometry(pt_ctx_t *C, pt_eval_t *E) {
  pt_eval_t G = *E;
  G.shade = 0;
  G.geom = C->sample.geom;
  G.record_sub = C->opt->measure;
  pt__eval(&G);
}

void pt__pixel_done(pt_ctx_t *C, pixel_t *P) {
  pt_method_t m =
      P->n[PT_METHOD_INTERP] >= P->n[PT_METHOD_MATRIX] ? PT_METHOD_INTERP : PT_METHOD_MATRIX;
  for (int k = 0; k < 3; k++)
    C->st.samples[k] += (uint64_t)P->n[k];
  pt__write_pixel(C, P->i, P->j, P->sum, m, P->pmax, P->rays);
}

void pt__record_shadows(pt_ctx_t *C, const rt_ray_t *axial) {
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX, .shade = 1, .record_shadow = 1};
  E.primary = *axial;
  pt__eval(&E);
}

void pt__xi_of(const pt_ctx_t *C, pt_eval_t *E, double x, double y) {
  E->primary = rt_view_ray(C->view, x, y, C->s->ior);
  E->xi[0] = px_v3_dot(C->paths.frame.x1, E->primary.d);
  E->xi[1] = px_v3_dot(C->paths.frame.x2, E->primary.d);
}

void pt__group_rays(pt_group_t *G) {
  G->lanes4 = 0;
  G->ray4.skip_prim = -1;
  for (int i = 0; i < G->n; i++) {
    const rt_ray_t *q = &G->primary[i];
    if (!(q->tmin == 0.0 && q->tmax == INFINITY && q->skip_prim == -1))
      continue; /* walked alone */
    G->ray4.o.x[i] = q->o.x, G->ray4.o.y[i] = q->o.y, G->ray4.o.z[i] = q->o.z;
    G->ray4.d.x[i] = q->d.x, G->ray4.d.y[i] = q->d.y, G->ray4.d.z[i] = q->d.z;
    G->ray4.ior[i] = q->ior;
    G->lanes4 |= 1u << i;
  }
}

/* Step 4a with matrices: sample (a, b) of pixel P through the paths. */
void pt__matrix_sample(pt_ctx_t *C, pixel_t *P, int a, int b) {
  int s = C->opt->spp_side;
  pt_eval_t E = {.C = C,
                 .mode = PT_EV_MATRIX,
                 .shade = 1,
                 .geom = C->opt->measure ? C->sample.geom : NULL,
                 .record_sub = C->opt->measure};
  pt__xi_of(C, &E, P->i + (a + 0.5) / s, P->j + (b + 0.5) / s);
  E.exact_spawn = pt__spawns_exact(&E);
  rt_rgb_t v = pt__eval(&E);
  if (E.spawnfail) { /* a node's exact path left the domain's paths: the whole sample exactly */
    P->sum = rt_rgb_add(P->sum, xr_exact_primary(&C->ex, &E.primary));
    P->n[PT_METHOD_EXACT]++;
    if (C->opt->measure) {
      const double zero[PT_MEASURE_ERRORS] = {0.0, 0.0, 0.0, 0.0};
      pt__account(C, zero, 0, pt__error_slot(C, P->i, P->j, a, b));
    }
    return;
  }
  P->sum = rt_rgb_add(P->sum, v);
  P->n[PT_METHOD_MATRIX]++;
  C->st.fallbacks += (uint64_t)E.fallback;
  C->st.partial += (uint64_t)E.partial;
  if (C->opt->measure)
    P->pmax = pt__measure_sample(C, &E.primary, C->sample.geom, P->i, P->j, a, b, P->pmax);
}

void pt__aux_matrix(pt_ctx_t *C, int i, int j) {
  pt_eval_t E = {.C = C, .mode = PT_EV_MATRIX};
  pt__xi_of(C, &E, i + 0.5, j + 0.5);
  pt__geometry(C, &E);
  pt__aux_pencil(C, i, j, C->sample.geom);
}

/* Step 4a with matrices for every sample of pixel (i, j). */
void pt__matrix_pixel(pt_ctx_t *C, int i, int j) {
  int s = C->opt->spp_side;
  pixel_t P = {i, j, {0, 0, 0}, NAN, {0, 0, 0}, 0};
  uint64_t rays0 = pt__rays_now(C);
  for (int b = 0; b < s; b++)
    for (int a = 0; a < s; a++)
      pt__matrix_sample(C, &P, a, b);
  P.rays = pt__rays_now(C) - rays0;
  pt__pixel_done(C, &P);
  if (C->opt->aux)
    pt__aux_matrix(C, i, j);
}
