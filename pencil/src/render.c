/* render.c -- the screen loop of the pencil renderer (paper section 4.1 (1), step 1: "divide the
 * screen into n x m initial domains"), domains shared among OpenMP threads. Each thread owns its
 * scratch (trees, paths, lattice), allocated before the loop, so that no ray allocates. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "internal.h"

/* One initial domain. Corner trees are cached per domain; the left column of a domain is the
 * right column of the one before it in the row, so those trees move over (dx > 0). */
static void initial_domain(pt_ctx_t *C, int dx, int dy) {
  int n = C->opt->domain, side = n + 1;
  C->corners.x0 = dx * n;
  C->corners.y0 = dy * n;
  for (int r = 0; r < side; r++) {
    pt_ctree_t *row = C->corners.tree + r * side;
    if (dx > 0) { /* swap, so that every entry keeps a buffer of its own */
      pt_ctree_t t = row[0];
      row[0] = row[n];
      row[n] = t;
    } else {
      row[0].n = -1;
    }
    for (int i = 1; i < side; i++)
      row[i].n = -1;
  }
  int x1 = C->corners.x0 + n, y1 = C->corners.y0 + n;
  if (x1 > C->img->width)
    x1 = C->img->width;
  if (y1 > C->img->height)
    y1 = C->img->height;
  pt__domain(C, C->corners.x0, C->corners.y0, x1, y1);
}

static void stats_add(pt_stats_t *a, const pt_stats_t *b) {
  a->domains += b->domains;
  a->domains_edge += b->domains_edge;
  a->domains_guard += b->domains_guard;
  a->domains_accepted += b->domains_accepted;
  a->domains_split += b->domains_split;
  a->domains_deep += b->domains_deep;
  a->domains_small += b->domains_small;
  a->paths_exact += b->paths_exact;
  a->paths_guard += b->paths_guard;
  a->lights_guard += b->lights_guard;
  a->domains_partial += b->domains_partial;
  a->partial += b->partial;
  a->exact_traces += b->exact_traces;
  for (int m = 0; m < 3; m++)
    a->samples[m] += b->samples[m];
  a->fallbacks += b->fallbacks;
  a->lerp_samples += b->lerp_samples;
  for (int r = 0; r < 4; r++)
    a->matrix_samples[r] += b->matrix_samples[r];
  a->lattice_points += b->lattice_points;
  a->lattice_reused += b->lattice_reused;
  a->spectral_points += b->spectral_points;
  a->spectral_samples += b->spectral_samples;
  a->spectral_full += b->spectral_full;
  a->walk_steps += b->walk_steps;
  a->walk_lanes += b->walk_lanes;
  a->walk_left += b->walk_left;
  a->biquad_lattice_cells += b->biquad_lattice_cells;
  a->faint_lattice_cells += b->faint_lattice_cells;
  a->highlight_lattice_cells += b->highlight_lattice_cells;
  a->halved_lattice_cells += b->halved_lattice_cells;
  a->measured += b->measured;
  a->with_points += b->with_points;
  a->within += b->within;
  a->within_t += b->within_t;
  a->mismatches += b->mismatches;
  a->max_error = fmax(a->max_error, b->max_error);
  a->max_error_t = fmax(a->max_error_t, b->max_error_t);
  a->max_error_strict = fmax(a->max_error_strict, b->max_error_strict);
  a->within_strict += b->within_strict;
  a->max_error_axial = fmax(a->max_error_axial, b->max_error_axial);
  a->within_axial += b->within_axial;
  a->local_unknown += b->local_unknown;
  for (int k = 0; k < PT_HIST_BINS; k++)
    a->hist[k] += b->hist[k];
}

static int options_ok(const pt_options_t *o) {
  return o->spp_side >= 1 && o->spp_side <= RT_MAX_SPP_SIDE && o->threads >= 0 && o->domain >= 1 &&
         o->domain <= 32 && o->rho > 0.0 && isfinite(o->rho) && (unsigned)o->bound <= 2u &&
         o->brightness_tol >= 0.0 && isfinite(o->brightness_tol) && (unsigned)o->tolerance <= 1u &&
         o->weight_floor > 0.0 && o->weight_floor <= 1.0;
}

rt_status_t pt_render(const rt_scene_t *s, const rt_plan_t *plan, const pt_options_t *opt,
                      rt_image_t *img, pt_extra_t *extra, float *sample_error, pt_stats_t *stats) {
  rt_view_t view;
  if (!s->bvh)
    return RT_ENOTREADY;
  if (!options_ok(opt) || (sample_error && !opt->measure) ||
      rt_view_make(&s->camera, &view) != RT_OK || img->width != s->camera.width ||
      img->height != s->camera.height)
    return RT_EINVAL;
  int nt = rt_thread_count(opt->threads), n = opt->domain;
  int nx = (img->width + n - 1) / n, ny = (img->height + n - 1) / n;
  pt_guards_t guard, faces;
  int guarded = pt_guards_of_scene(s, &guard);
  guarded = pt_guards_of_faces(s, &guard, &faces) && guarded;
  pt_ctx_t *ctx = calloc((size_t)nt, sizeof *ctx);
  rt_status_t st = guarded && ctx ? RT_OK : RT_ENOMEM;
  for (int t = 0; t < nt && st == RT_OK; t++) {
    ctx[t] = (pt_ctx_t){.s = s,
                        .plan = plan,
                        .view = &view,
                        .opt = opt,
                        .img = img,
                        .extra = extra,
                        .sample_error = sample_error,
                        .guard = &guard,
                        .faces = &faces,
                        .weights_vary = rt_plan_has(plan, RT_EFFECT_FRESNEL),
                        .ex = xr_exact_make(s, plan, NULL)};
    if (!pt__ctx_alloc(&ctx[t], plan->tree_nodes, n))
      st = RT_ENOMEM;
  }
  pt_stats_t total;
  memset(&total, 0, sizeof total);
  rt_stats_t *rays = &total.rays;
  if (st == RT_OK) {
    int done = 0;
#pragma omp parallel num_threads(nt)
    {
      int me = 0;
#ifdef _OPENMP
      me = omp_get_thread_num();
#endif
      pt_ctx_t *C = &ctx[me];
#pragma omp for schedule(dynamic, 1)
      for (int dy = 0; dy < ny; dy++) {
        for (int dx = 0; dx < nx; dx++)
          initial_domain(C, dx, dy);
        if (opt->progress) {
#pragma omp critical(pt_progress)
          opt->progress(opt->progress_ctx, ++done, ny);
        }
      }
    }
    for (int t = 0; t < nt; t++) {
      stats_add(&total, &ctx[t].st);
      rt_stats_add(rays, &ctx[t].ex.stats);
    }
  }
  for (int t = 0; ctx && t < nt; t++)
    pt__ctx_free(&ctx[t]);
  free(ctx);
  pt_guards_free(&guard);
  pt_guards_free(&faces);
  if (stats)
    *stats = total;
  return st;
}
