/* render.c -- the pixel loop of the conventional renderer: an s x s grid of primary rays per
 * pixel averaged by a box filter (course notes 1.7.5, supersampling; paper section 5 uses 9 and
 * up to 49 rays per pixel), rows shared among OpenMP threads. Each thread owns its tracer state
 * and ray-tree buffer, allocated before the loop, so no ray allocates. */
#include "render/render.h"

#include <math.h>
#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "core/intersect.h"

typedef struct {
  const rt_scene_t *s;
  const rt_plan_t *plan;
  const rt_view_t *view;
  const xr_options_t *opt;
  rt_image_t *img;
} job_t;

/* One sample; records its tree when the centre ray's aux channels or the caller want it. */
static rt_rgb_t sample(const job_t *J, xr_exact_t *ex, rt_tree_t *tree, int record, int i, int j,
                       int a, int b) {
  int s = J->opt->spp_side;
  double x = a < 0 ? i + 0.5 : i + (a + 0.5) / s, y = b < 0 ? j + 0.5 : j + (b + 0.5) / s;
  rt_ray_t r = rt_view_ray(J->view, x, y, J->s->ior);
  rt_rgb_t c = rt_rgb(0, 0, 0);
  int nb = J->opt->per_wavelength ? J->plan->bins : 0;
  for (int k = 0; k < nb; k++) { /* Takagi's wavelength supersampling */
    r.lambda = (float)J->plan->bin_lambda[k];
    ex->tree = record && k == nb / 2 ? tree : NULL;
    c = rt_rgb_add(c, rt_rgb_mul(J->plan->bin_weight[k], xr_exact_primary(ex, &r)));
  }
  if (nb == 0) {
    ex->tree = record ? tree : NULL;
    c = xr_exact_primary(ex, &r);
  }
  ex->tree = NULL;
  if (record && J->opt->on_sample)
    J->opt->on_sample(J->opt->sample_ctx, i, j, a, b, tree, c);
  return c;
}

static void render_pixel(const job_t *J, xr_exact_t *ex, rt_tree_t *tree, int i, int j) {
  int s = J->opt->spp_side, aux = J->opt->aux && tree, every = J->opt->on_sample && tree;
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  int have_centre = 0;
  for (int b = 0; b < s; b++)
    for (int a = 0; a < s; a++) {
      int centre = (s & 1) && a == s / 2 && b == s / 2;
      sum = rt_rgb_add(sum, sample(J, ex, tree, every || (centre && aux), i, j, a, b));
      if (centre && aux) {
        rt_image_set_aux(J->img, J->s, (size_t)j * J->img->width + i, tree);
        have_centre = 1;
      }
    }
  if (aux && !have_centre) { /* even s: no sample at the centre; trace one for the record */
    sample(J, ex, tree, 1, i, j, -1, -1);
    rt_image_set_aux(J->img, J->s, (size_t)j * J->img->width + i, tree);
  }
  size_t k = (size_t)j * (size_t)J->img->width + (size_t)i;
  double w = 1.0 / (s * s);
  J->img->ch[RT_CH_R][k] = (float)(sum.r * w);
  J->img->ch[RT_CH_G][k] = (float)(sum.g * w);
  J->img->ch[RT_CH_B][k] = (float)(sum.b * w);
}

static void render_rows(const job_t *J, rt_tree_node_t **buf, int nt, rt_stats_t *total) {
  int done = 0, height = J->img->height;
#pragma omp parallel num_threads(nt)
  {
    int me = 0;
#ifdef _OPENMP
    me = omp_get_thread_num();
#endif
    rt_tree_t tree = rt_tree_make(buf[me], J->plan->tree_nodes);
    xr_exact_t ex = xr_exact_make(J->s, J->plan, NULL);
#pragma omp for schedule(dynamic, 1)
    for (int j = 0; j < height; j++) {
      for (int i = 0; i < J->img->width; i++)
        render_pixel(J, &ex, buf[me] ? &tree : NULL, i, j);
      if (J->opt->progress) {
#pragma omp critical(rt_progress)
        J->opt->progress(J->opt->progress_ctx, ++done, height);
      }
    }
#pragma omp critical(rt_stats)
    rt_stats_add(total, &ex.stats);
  }
}

rt_status_t xr_render(const rt_scene_t *s, const rt_plan_t *plan, const xr_options_t *opt,
                      rt_image_t *img, rt_stats_t *stats) {
  rt_view_t view;
  if (!s->bvh)
    return RT_ENOTREADY;
  if (opt->spp_side < 1 || opt->spp_side > RT_MAX_SPP_SIDE || opt->threads < 0 ||
      rt_view_make(&s->camera, &view) != RT_OK || img->width != s->camera.width ||
      img->height != s->camera.height)
    return RT_EINVAL;
  int nt = rt_thread_count(opt->threads);
  rt_tree_node_t **buf = calloc((size_t)nt, sizeof *buf);
  rt_status_t st = buf ? RT_OK : RT_ENOMEM;
  for (int t = 0; t < nt && st == RT_OK && (opt->aux || opt->on_sample); t++)
    if (!(buf[t] = malloc((size_t)plan->tree_nodes * sizeof **buf)))
      st = RT_ENOMEM;
  rt_stats_t total = {0, 0, 0, 0, {0, 0, 0}};
  if (st == RT_OK) {
    job_t J = {s, plan, &view, opt, img};
    render_rows(&J, buf, nt, &total);
  }
  for (int t = 0; buf && t < nt; t++)
    free(buf[t]);
  free(buf);
  if (stats)
    *stats = total;
  return st;
}
