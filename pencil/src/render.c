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

#define PT_MAX_GUARD 4096

static void ctx_free(pt_ctx_t *C) {
  free(C->tree.node);
  free(C->tree2.node);
  free(C->sub.node);
  free(C->sub_root);
  free(C->sub_from);
  free(C->sub_xk);
  free(C->corner_nodes);
  free(C->corner);
  free(C->node);
  free(C->map);
  free(C->agree);
  free(C->light);
  free(C->lat);
  free(C->acc);
  free(C->loc);
  free(C->locd);
  free(C->loce);
  free(C->loct);
  free(C->lsm);
  free(C->xsub);
  free(C->own);
  free(C->q2);
  free(C->faint);
  free(C->rec);
  free(C->xg);
  free(C->ref);
  free(C->memo.g);
  free(C->memo.xy);
  free(C->memo.xi2);
  free(C->memo.ok);
  free(C->memo.slot);
  free(C->memo.gen);
}

/* Allocate one thread's scratch; 0 on failure (partial allocations are freed by ctx_free). */
static int ctx_alloc(pt_ctx_t *C, int cap, int n) {
  size_t side = (size_t)n + 1, corners = side * side;
  C->cap = cap;
  C->tree = rt_tree_make(malloc((size_t)cap * sizeof(rt_tree_node_t)), cap);
  C->tree2 = rt_tree_make(malloc((size_t)cap * sizeof(rt_tree_node_t)), cap);
  C->sub = rt_tree_make(malloc((size_t)PT_SUB_TREES * (size_t)cap * sizeof(rt_tree_node_t)),
                        PT_SUB_TREES * cap);
  C->sub_root = malloc((size_t)cap * sizeof *C->sub_root);
  C->sub_from = malloc((size_t)cap * sizeof *C->sub_from);
  C->sub_xk = malloc((size_t)cap * sizeof *C->sub_xk);
  C->corner = calloc(corners, sizeof *C->corner);
  pt_cnode_t *cn = malloc(corners * (size_t)cap * sizeof *cn);
  C->node = malloc((size_t)cap * sizeof *C->node);
  C->map = malloc(4 * (size_t)cap * sizeof *C->map);
  C->agree = malloc((size_t)cap);
  C->light = malloc((size_t)cap * sizeof *C->light);
  C->lat = malloc(9 * (size_t)cap * sizeof *C->lat);
  C->acc = malloc((size_t)n * (size_t)n * sizeof *C->acc);
  C->loc = malloc((size_t)cap * sizeof *C->loc);
  C->locd = malloc((size_t)cap);
  C->loce = malloc((size_t)cap);
  C->loct = malloc((size_t)cap * sizeof *C->loct);
  C->lsm = malloc((size_t)cap * sizeof *C->lsm);
  C->xsub = calloc((size_t)cap, 1);
  C->own = calloc((size_t)cap, 1);
  C->q2 = calloc((size_t)cap, 1);
  C->faint = calloc((size_t)cap, 1);
  C->rec = calloc((size_t)cap, sizeof *C->rec);
  C->xg = calloc((size_t)cap, sizeof *C->xg);
  C->ref = malloc((size_t)PT_QUAD_LEVELS * 5 * (size_t)cap * sizeof *C->ref);
  /* lattice memo: a 5 x 5 domain at 49 spp needs at most 33 x 33 points; 8 MiB of node records
   * (at least one whole tree), a point taking as many as its cell's tree has nodes */
  size_t mcap = 2048, entries = ((size_t)8 << 20) / sizeof(pt_geom_t);
  if (entries < (size_t)cap)
    entries = (size_t)cap;
  size_t nslot = 1;
  while (nslot < 2 * mcap)
    nslot *= 2;
  C->memo = (pt_lmemo_t){.entries = entries, .maxpts = (int)mcap, .nslot = (int)nslot};
  C->memo.g = malloc(entries * sizeof(pt_geom_t));
  C->memo.xy = malloc(2 * mcap * sizeof *C->memo.xy);
  C->memo.xi2 = malloc(mcap * sizeof *C->memo.xi2);
  C->memo.ok = malloc(mcap);
  C->memo.slot = malloc(nslot * sizeof *C->memo.slot);
  C->memo.gen = calloc(nslot, sizeof *C->memo.gen);
  if (!C->tree.node || !C->tree2.node || !C->sub.node || !C->sub_root || !C->sub_from ||
      !C->sub_xk || !C->corner || !cn || !C->node || !C->lat || !C->acc || !C->rec || !C->xg ||
      !C->ref || !C->map || !C->agree || !C->light || !C->loc || !C->locd || !C->loce || !C->loct ||
      !C->lsm || !C->xsub || !C->own || !C->q2 || !C->faint || !C->memo.g || !C->memo.xy ||
      !C->memo.xi2 || !C->memo.ok || !C->memo.slot || !C->memo.gen) {
    C->corner_nodes = cn;
    return 0;
  }
  C->corner_nodes = cn;
  for (size_t i = 0; i < corners; i++)
    C->corner[i] = (pt_ctree_t){cn + i * (size_t)cap, cap, -1, 0};
  return 1;
}

/* One initial domain. Corner trees are cached per domain; the left column of a domain is the
 * right column of the one before it in the row, so those trees move over (dx > 0). */
static void domain(pt_ctx_t *C, int dx, int dy) {
  int n = C->opt->domain, side = n + 1;
  C->dom_x0 = dx * n;
  C->dom_y0 = dy * n;
  for (int r = 0; r < side; r++) {
    pt_ctree_t *row = C->corner + r * side;
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
  int x1 = C->dom_x0 + n, y1 = C->dom_y0 + n;
  if (x1 > C->img->width)
    x1 = C->img->width;
  if (y1 > C->img->height)
    y1 = C->img->height;
  pt__cell(C, C->dom_x0, C->dom_y0, x1, y1);
}

static void stats_add(pt_stats_t *a, const pt_stats_t *b) {
  a->cells += b->cells;
  a->cells_edge += b->cells_edge;
  a->cells_guard += b->cells_guard;
  a->cells_accepted += b->cells_accepted;
  a->cells_split += b->cells_split;
  a->paths_exact += b->paths_exact;
  a->paths_guard += b->paths_guard;
  a->lights_guard += b->lights_guard;
  a->cells_partial += b->cells_partial;
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
  a->biquad_cells += b->biquad_cells;
  a->faint_cells += b->faint_cells;
  a->halved_cells += b->halved_cells;
  a->measured += b->measured;
  a->with_points += b->with_points;
  a->within += b->within;
  a->within_t += b->within_t;
  a->mismatches += b->mismatches;
  a->max_error = fmax(a->max_error, b->max_error);
  a->max_error_t = fmax(a->max_error_t, b->max_error_t);
  a->max_error_strict = fmax(a->max_error_strict, b->max_error_strict);
  a->within_strict += b->within_strict;
  for (int k = 0; k < PT_HIST_BINS; k++)
    a->hist[k] += b->hist[k];
}

static int options_ok(const pt_options_t *o) {
  return o->spp_side >= 1 && o->spp_side <= RT_MAX_SPP_SIDE && o->threads >= 0 && o->domain >= 1 &&
         o->domain <= 32 && o->rho > 0.0 && isfinite(o->rho) && (unsigned)o->bound <= 2u &&
         o->brightness_tol >= 0.0 && isfinite(o->brightness_tol);
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
  pt_bsphere_t *guard = malloc(PT_MAX_GUARD * sizeof *guard);
  pt_ctx_t *ctx = calloc((size_t)nt, sizeof *ctx);
  rt_status_t st = guard && ctx ? RT_OK : RT_ENOMEM;
  int nguard = guard ? pt_guard_spheres(s, guard, PT_MAX_GUARD) : 0;
  for (int t = 0; t < nt && st == RT_OK; t++) {
    ctx[t] = (pt_ctx_t){.s = s,
                        .plan = plan,
                        .view = &view,
                        .opt = opt,
                        .img = img,
                        .extra = extra,
                        .sample_error = sample_error,
                        .guard = guard,
                        .nguard = nguard,
                        .vary_w = rt_plan_has(plan, RT_EFFECT_FRESNEL),
                        .ex = rt_exact_make(s, plan, NULL)};
    if (!ctx_alloc(&ctx[t], plan->tree_nodes, n))
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
          domain(C, dx, dy);
        if (opt->progress) {
#pragma omp critical(pt_progress)
          opt->progress(opt->progress_ctx, ++done, ny);
        }
      }
    }
    for (int t = 0; t < nt; t++) {
      stats_add(&total, &ctx[t].st);
      rays->primary += ctx[t].ex.stats.primary;
      rays->reflect += ctx[t].ex.stats.reflect;
      rays->refract += ctx[t].ex.stats.refract;
      rays->shadow += ctx[t].ex.stats.shadow;
    }
  }
  for (int t = 0; ctx && t < nt; t++)
    ctx_free(&ctx[t]);
  free(ctx);
  free(guard);
  if (stats)
    *stats = total;
  return st;
}
