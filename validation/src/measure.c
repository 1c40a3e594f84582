/* measure.c -- timing and measuring a renderer of the table against the exact renderer (1987
 * paper, section 5): Fig. 9's CPU-time ratio (val_time_pair: medians of interleaved renders in
 * one process) and Fig. 10's error of every sample with the images compared (val_measure). */
#include "validation/figures.h"
#include "validation/timing.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/output.h"

static int side_of(int spp) {
  return (int)lrint(sqrt((double)spp));
}

int val_time_pair(const rt_scene_t *s, val_method_t m, int spp, int threads, int runs,
                  val_timing_t *out) {
  return val_time_peer(s, m, spp, threads, runs, NULL, out);
}

int val_time_peer(const rt_scene_t *s, val_method_t m, int spp, int threads, int runs,
                  const val_peer_t *peer, val_timing_t *out) {
  enum { MAXR = 101 };
  double ec[MAXR], ew[MAXR], pc[MAXR], pw[MAXR], qc[MAXR], qw[MAXR];
  if (runs < 1 || runs > MAXR)
    return -1;
  /* one plan for both renderers: what the pencil renderer draws (dispersion off) */
  rt_plan_t plan = rn_plan_make(rn_find("pencil"), s, spp, NULL);
  rt_image_t img;
  if (rt_image_alloc(&img, s->camera.width, s->camera.height) != RT_OK)
    return fprintf(stderr, "%s: a timed render at %d spp: cannot allocate a %dx%d image\n",
                   io_command(), spp, s->camera.width, s->camera.height),
           -1;
  const rn_renderer_t *x = rn_exact();
  rn_common_t c = RN_COMMON_DEFAULT; /* timed renders: no auxiliary channels, no measure */
  c.spp_side = side_of(spp);
  c.threads = threads;
  c.aux = 0;
  rt_stats_t xst; /* the exact entry's statistics are rt_stats_t (renderers/src/exact.c) */
  memset(&xst, 0, sizeof xst);
  rn_output_t out_x = {.image = &img, .stats = &xst}, out_m = {.image = &img};
  unsigned char xopt[64];     /* the exact renderer's options (its defaults) */
  int peer_ok = peer != NULL; /* the peer is still timed */
  int rc = x->options_size <= sizeof xopt ? 0 : -1;
  if (rc == 0)
    rn_defaults(x, xopt);
  else
    fprintf(stderr, "%s: internal error: the exact renderer's options outgrow their buffer\n",
            io_command());
  for (int r = 0; r < runs && rc == 0; r++) {
    double c0 = val_cpu_seconds(), w0 = val_wall_seconds();
    rt_status_t st = x->render(s, &plan, &c, xopt, &out_x);
    if (st != RT_OK) {
      fprintf(stderr, "%s: the exact render at %d spp failed: %s%s%s\n", io_command(), spp,
              rt_strerror(st), out_x.why[0] ? ": " : "", out_x.why);
      rc = -1;
    }
    ec[r] = val_cpu_seconds() - c0;
    ew[r] = val_wall_seconds() - w0;
    c0 = val_cpu_seconds();
    w0 = val_wall_seconds();
    st = rc == 0 ? m.r->render(s, &plan, &c, m.options, &out_m) : RT_OK;
    if (st != RT_OK) {
      fprintf(stderr, "%s: the %s render at %d spp failed: %s%s%s\n", io_command(), m.r->name, spp,
              rt_strerror(st), out_m.why[0] ? ": " : "", out_m.why);
      rc = -1;
    }
    pc[r] = val_cpu_seconds() - c0;
    pw[r] = val_wall_seconds() - w0;
    w0 = val_wall_seconds();
    if (rc == 0 && peer_ok && peer->run(peer->ctx, spp, &qc[r], &out->peer_rays) != 0)
      peer_ok = 0; /* it said why; the pair goes on without it */
    qw[r] = val_wall_seconds() - w0;
  }
  rt_image_free(&img);
  if (rc != 0)
    return -1; /* it said why */
  out->exact_rays = rt_stats_total(&xst);
  if (!peer_ok)
    out->peer_rays = 0;
  out->peer_s = peer_ok ? val_median(qc, runs) : NAN;
  out->peer_wall = peer_ok ? val_median(qw, runs) : NAN;
  out->spp = spp;
  out->exact_s = val_median(ec, runs);
  out->exact_wall = val_median(ew, runs);
  out->pencil_s = val_median(pc, runs);
  out->pencil_wall = val_median(pw, runs);
  out->ratio = out->pencil_s / out->exact_s;
  return peer && !peer_ok ? 1 : 0;
}

static int cmp_float(const void *a, const void *b) {
  float x = *(const float *)a, y = *(const float *)b;
  return (x > y) - (x < y);
}

int val_image_bias(const rt_scene_t *s, const rt_image_t *P, const rt_image_t *X, double *bias,
                   int *object) {
  int no = s->nobject + 1; /* slot 0: the background */
  double *sum = calloc((size_t)no, sizeof *sum);
  long *cnt = calloc((size_t)no, sizeof *cnt);
  *bias = 0.0;
  *object = -2;
  int rc = sum && cnt ? 0 : -1;
  if (sum && cnt) {
    size_t np = (size_t)X->width * (size_t)X->height;
    for (size_t k = 0; k < np; k++) {
      int o = (int)X->ch[RT_CH_ID][k] + 1;
      if (o < 0 || o >= no)
        continue;
      for (int c = 0; c < 3; c++)
        sum[o] += (double)P->ch[c][k] - (double)X->ch[c][k];
      cnt[o]++;
    }
    for (int o = 0; o < no; o++) {
      double m = cnt[o] >= VAL_BIAS_PIXELS ? fabs(sum[o] / (3.0 * (double)cnt[o])) : -1.0;
      if (m > *bias || (m >= 0.0 && *object == -2)) {
        *bias = m;
        *object = o - 1;
      }
    }
  }
  free(sum);
  free(cnt);
  return rc;
}

/* The exact render of a measurement: aux channels on (the image's id channel judges bias). */
static int render_exact(const rt_scene_t *s, const rt_plan_t *plan, int side, int threads,
                        rt_image_t *img) {
  const rn_renderer_t *x = rn_exact();
  unsigned char xopt[64]; /* the exact renderer's options (its defaults) */
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = side;
  c.threads = threads;
  rn_output_t out = {.image = img};
  if (x->options_size > sizeof xopt)
    return 0;
  rn_defaults(x, xopt);
  return x->render(s, plan, &c, xopt, &out) == RT_OK;
}

/* Fill out's statistics from its counters, the per-sample errors and the two images. */
static void compare(const rt_scene_t *s, const float *err, size_t n, const rt_image_t *P,
                    const rt_image_t *X, val_errors_t *out) {
  const rn_errors_t *e = &out->counts;
  int w = s->camera.width, h = s->camera.height;
  out->samples = e->measured;
  out->samples_with_points = e->with_points;
  out->fraction_within = (double)e->within / (double)e->measured;
  out->max_error = e->max_error;
  out->mismatches = e->mismatches;
  out->fraction_within_strict = (double)e->within_strict / (double)e->measured;
  out->max_error_strict = e->max_error_strict;
  out->fraction_within_t = (double)e->within_t / (double)e->measured;
  out->max_error_t = e->max_error_t;
  out->fraction_within_axial = (double)e->within_axial / (double)e->measured;
  out->max_error_axial = e->max_error_axial;
  float *sorted = malloc(n * sizeof *sorted);
  if (sorted) {
    memcpy(sorted, err, n * sizeof *sorted);
    qsort(sorted, n, sizeof *sorted, cmp_float);
    out->p99 = sorted[(size_t)floor(0.99 * (double)(n - 1))];
    free(sorted);
  }
  double sq = 0.0, mx = 0.0;
  for (size_t k = 0; k < (size_t)w * (size_t)h; k++)
    for (int c = 0; c < 3; c++) {
      double d = (double)P->ch[c][k] - (double)X->ch[c][k];
      sq += d * d;
      mx = fmax(mx, fabs(d));
    }
  out->image_rms = sqrt(sq / (3.0 * w * h));
  out->image_max = mx;
  val_image_bias(s, P, X, &out->image_bias, &out->image_bias_object);
}

int val_measure(const rt_scene_t *s, val_method_t m, int spp, int threads, val_errors_t *out,
                float *sample_error, rt_image_t *img, float *const *channels,
                rt_image_t *exact_img) {
  int w = s->camera.width, h = s->camera.height;
  size_t n = (size_t)w * (size_t)h * (size_t)spp;
  memset(out, 0, sizeof *out);
  if (!m.r->errors) {
    fprintf(stderr, "%s: the %s renderer has nothing to measure\n", io_command(), m.r->name);
    return -1;
  }
  float *err = sample_error ? sample_error : malloc(n * sizeof *err);
  void *stats = calloc(1, m.r->stats_size);
  rt_image_t pi = {0}, ei = {0}, *P = img ? img : &pi, *X = exact_img ? exact_img : &ei;
  int own_p = !img, own_x = !exact_img, rc = -1;
  if (own_p)
    rt_image_alloc(&pi, w, h);
  if (own_x)
    rt_image_alloc(&ei, w, h);
  /* one plan for both renderers: what the pencil renderer draws (dispersion off) */
  rt_plan_t plan = rn_plan_make(rn_find("pencil"), s, spp, NULL);
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = side_of(spp);
  c.threads = threads;
  c.measure = 1;
  rn_output_t o = {.image = P, .sample_error = err, .stats = stats};
  for (int k = 0; channels && k < m.r->nchannels; k++)
    o.channels[k] = channels[k];
  if (err && stats && P->ch[0] && X->ch[0] && m.r->render(s, &plan, &c, m.options, &o) == RT_OK &&
      render_exact(s, &plan, c.spp_side, threads, X)) {
    m.r->errors(stats, &out->counts);
    out->rho = m.r->rho ? m.r->rho(m.options) : 0.0;
    compare(s, err, n, P, X, out);
    rc = 0;
  } else {
    fprintf(stderr, "%s: a measured render failed\n", io_command());
  }
  if (!sample_error)
    free(err);
  free(stats);
  if (own_p)
    rt_image_free(&pi);
  if (own_x)
    rt_image_free(&ei);
  return rc;
}
