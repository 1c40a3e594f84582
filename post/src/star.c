/* star.c -- the cross-screen filter of star.h: the kernel of the 1989 paper's Eq. (16) on the
 * pixel grid, and the linear convolution by FFT (FFTW3). */
#include "post/star.h"

#include <fftw3.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The profile's tail beyond the kernel's radius, at most. */
#define TAIL 1e-7
/* Sub-pixel segments a pixel along a star ray. */
#define STEPS 8

int pp_star_check(const pp_star_t *p, char *why, size_t cap) {
  const char *bad = NULL;
  if (p->directions < 1 || p->directions > 16)
    bad = "directions must be 1..16";
  else if (!isfinite(p->angle_deg))
    bad = "angle must be finite";
  else if (!(p->ratio >= 0.0 && p->ratio < 1.0))
    bad = "ratio (B) must be in [0, 1)";
  else if (!(p->sigma1 > 0.0) || !isfinite(p->sigma1) || !(p->sigma2 > 0.0) || !isfinite(p->sigma2))
    bad = "sigma1 and sigma2 must be finite and > 0";
  else if (!(p->weight2 >= 0.0 && p->weight2 <= 1.0))
    bad = "weight2 must be in [0, 1]";
  else if (!(p->ior > 1.0) || !isfinite(p->ior))
    bad = "ior must be finite and > 1";
  else if (!(p->focal_mm > 0.0) || !isfinite(p->focal_mm))
    bad = "focal must be finite and > 0";
  else if (!(p->frame_mm > 0.0) || !isfinite(p->frame_mm))
    bad = "frame must be finite and > 0";
  if (!bad)
    return 0;
  snprintf(why, cap, "%s", bad);
  return -1;
}

/* Mass of N(0, s) beyond |u| > t. */
static double beyond(double t, double s) {
  return erfc(t / (s * M_SQRT2));
}

/* Mass of the profile (1 - w2) N(0, s1) + w2 N(0, s2) (pixels) in [a, b]. */
static double mass(double a, double b, double s1, double s2, double w2) {
  double m1 = 0.5 * (erf(b / (s1 * M_SQRT2)) - erf(a / (s1 * M_SQRT2)));
  double m2 = 0.5 * (erf(b / (s2 * M_SQRT2)) - erf(a / (s2 * M_SQRT2)));
  return (1.0 - w2) * m1 + w2 * m2;
}

int pp_star_kernel(const pp_star_t *p, int width, int max_side, pp_kernel_t *k, char *why,
                   size_t cap) {
  memset(k, 0, sizeof *k);
  if (pp_star_check(p, why, cap) != 0)
    return -1;
  if (width < 1 || max_side < 1) {
    snprintf(why, cap, "the image is empty");
    return -1;
  }
  double scale = (p->ior - 1.0) * p->focal_mm / (p->frame_mm / width);
  double s1 = p->sigma1 * scale, s2 = p->sigma2 * scale, w2 = p->weight2;
  /* the radius: the wider component's tail below TAIL (5.33 standard deviations) */
  double widest = fmax(w2 < 1.0 ? s1 : 0.0, w2 > 0.0 ? s2 : 0.0);
  double r = p->ratio > 0.0 ? ceil(5.33 * widest) : 0.0;
  if (!(r <= 0.5 * (max_side - 1))) {
    snprintf(why, cap,
             "the kernel (%.0f pixels across: rays of %.3g pixels a unit of slope, slopes to "
             "%.3g) is larger than the image (%d pixels): lower sigma, focal or ior",
             2.0 * r + 1.0, scale, 5.33 * widest / scale, max_side);
    return -1;
  }
  int R = (int)r, side = 2 * R + 1;
  k->k = calloc((size_t)side * side, sizeof *k->k);
  if (!k->k) {
    snprintf(why, cap, "out of memory for a kernel of %d x %d", side, side);
    return -1;
  }
  k->radius = R;
  k->side = side;
  k->scale = scale;
  k->k[(size_t)R * side + R] = 1.0 - p->ratio; /* A: the unscratched plate */
  if (R == 0)
    return 0;
  k->tail = (1.0 - w2) * beyond(R, s1) + w2 * beyond(R, s2);
  double per = p->ratio / p->directions / (1.0 - k->tail), h = 1.0 / STEPS;
  for (int d = 0; d < p->directions; d++) {
    /* the star ray is perpendicular to its scratches; y up on the image, rows down */
    double phi = (p->angle_deg + 180.0 * d / p->directions + 90.0) * M_PI / 180.0;
    double cx = cos(phi), cy = -sin(phi);
    for (int m = 0; m < 2 * R * STEPS; m++) {
      double a = -R + m * h, u = a + 0.5 * h, w = per * mass(a, a + h, s1, s2, w2);
      double x = R + u * cx, y = R + u * cy;
      int i = (int)floor(x), j = (int)floor(y);
      double fx = x - i, fy = y - j;
      /* |u| <= R - h / 2 keeps i, j in [0, side - 2] */
      k->k[(size_t)j * side + i] += w * (1.0 - fx) * (1.0 - fy);
      k->k[(size_t)j * side + i + 1] += w * fx * (1.0 - fy);
      k->k[(size_t)(j + 1) * side + i] += w * (1.0 - fx) * fy;
      k->k[(size_t)(j + 1) * side + i + 1] += w * fx * fy;
    }
  }
  return 0;
}

void pp_kernel_free(pp_kernel_t *k) {
  free(k->k);
  memset(k, 0, sizeof *k);
}

/* The FFT's length for at least n samples: the smallest n' >= n with no prime factor above 5
 * and, from 256 up, a factor of 32, since FFTW's radix-2 codelets are the fastest (measured:
 * 5,760 forward and back in 0.63 s where 5,625 = 3^2 5^4 took 0.73 s; journal of 2026-12-03). */
static int good_size(int n) {
  for (int m = n > 1 ? n : 1;; m++) {
    if (m >= 256 && m % 32 != 0)
      continue;
    int r = m;
    for (int q = 2; q <= 5; q++)
      while (r % q == 0)
        r /= q;
    if (r == 1)
      return m;
  }
}

/* Columns a thread transforms together: 8 complex values (two cache lines) of each row at once. */
#define BATCH 8

/* The grids of a w x h image and kernel k: the FFT lengths mx, my, the half spectrum's width hx,
 * and the threads' column buffers. */
typedef struct {
  int mx, my, hx;
} grid_t;

static grid_t grid_of(const pp_kernel_t *k, int w, int h) {
  grid_t g = {good_size(w + k->radius), good_size(h + k->radius), 0};
  g.hx = g.mx / 2 + 1;
  return g;
}

size_t pp_star_bytes(const pp_kernel_t *k, int w, int h, int threads) {
  grid_t g = grid_of(k, w, h);
  size_t rows = (size_t)(h > k->side ? h : k->side);
  size_t nt = (size_t)(threads < 1 ? 1 : threads > 64 ? 64 : threads);
  return rows * (size_t)g.hx * sizeof(fftw_complex) + (size_t)g.hx * g.my * sizeof(double) +
         nt * ((size_t)BATCH * g.my * sizeof(fftw_complex) + (size_t)(g.mx + 2) * sizeof(double)) +
         (size_t)k->side * sizeof(int);
}

/* The linear convolution of one plane by the kernel's real spectrum, pruned: the plane fills the
 * top-left h x w of an my x mx grid, so only its h rows are transformed along x (the others are
 * zero), the hx columns of the half spectrum are transformed along y a batch at a time (gathered
 * into a contiguous buffer, multiplied by the kernel's column, transformed back), and only the h
 * rows the image keeps are transformed back along x. S holds max(h, kernel side) x hx values (the
 * kernel's rows pass through it first); spec is the kernel's
 * spectrum, column q at spec + q my, scaled by 1 / (mx my). full gets the whole grid's sum. */
typedef struct {
  grid_t g;
  int w, h, nt;
  fftw_plan row_f, row_b, col_f, col_b;
  fftw_complex *S;
  double *spec;
} pruned_t;

/* Transform the first `rows` rows of S along y (whose other rows are zero) and, with spec, multiply
 * and transform back into the same rows; without spec, keep the real part of the forward transform
 * times norm as the spectrum (the kernel's pass). full (may be NULL) gets the grid's DC term. */
static void columns(pruned_t *p, int rows, const int *at, double norm, double *full,
                    fftw_complex *const *buf) {
  int my = p->g.my, hx = p->g.hx, nb = (hx + BATCH - 1) / BATCH;
  double dc = 0.0;
#pragma omp parallel for num_threads(p->nt) schedule(dynamic, 1) reduction(+ : dc)
  for (int b = 0; b < nb; b++) {
    fftw_complex *cb = buf[omp_get_thread_num()];
    int q0 = b * BATCH, nq = hx - q0 < BATCH ? hx - q0 : BATCH;
    memset(cb, 0, (size_t)BATCH * my * sizeof *cb);
    for (int y = 0; y < rows; y++) {
      const fftw_complex *src = p->S + (size_t)y * hx + q0;
      size_t yy = (size_t)(at ? at[y] : y);
      for (int j = 0; j < nq; j++) {
        cb[(size_t)j * my + yy][0] = src[j][0];
        cb[(size_t)j * my + yy][1] = src[j][1];
      }
    }
    fftw_execute_dft(p->col_f, cb, cb);
    if (!full) { /* the kernel's pass: keep its (real) spectrum */
      for (int j = 0; j < nq; j++)
        for (int y = 0; y < my; y++)
          p->spec[(size_t)(q0 + j) * my + y] = cb[(size_t)j * my + y][0] * norm;
      continue;
    }
    for (int j = 0; j < nq; j++) {
      const double *ks = p->spec + (size_t)(q0 + j) * my;
      fftw_complex *c = cb + (size_t)j * my;
      for (int y = 0; y < my; y++) {
        c[y][0] *= ks[y];
        c[y][1] *= ks[y];
      }
    }
    if (q0 == 0)
      dc += cb[0][0];
    fftw_execute_dft(p->col_b, cb, cb);
    for (int y = 0; y < p->h; y++) {
      fftw_complex *dst = p->S + (size_t)y * hx + q0;
      for (int j = 0; j < nq; j++) {
        dst[j][0] = cb[(size_t)j * my + y][0];
        dst[j][1] = cb[(size_t)j * my + y][1];
      }
    }
  }
  if (full) /* the grid's sum: the DC term times mx my (the spectrum carries 1 / (mx my)) */
    *full = dc * (double)p->g.mx * (double)p->g.my;
}

int pp_star_apply(const pp_kernel_t *k, int w, int h, int n, const float *const *in, float **out,
                  int threads, pp_star_flux_t *flux, char *why, size_t cap) {
  int R = k->radius, side = k->side;
  pruned_t p = {
      grid_of(k, w, h), w, h, threads > 0 ? threads : 1, NULL, NULL, NULL, NULL, NULL, NULL};
  int mx = p.g.mx, my = p.g.my, hx = p.g.hx, nt = p.nt, rc = -1;
  size_t rows = (size_t)(h > side ? h : side);
  p.S = fftw_malloc(rows * hx * sizeof *p.S);
  p.spec = malloc((size_t)hx * my * sizeof *p.spec);
  fftw_complex *buf[64] = {NULL};
  double *rbuf[64] = {NULL};
  int *at = malloc((size_t)side * sizeof *at);
  if (nt > 64)
    nt = p.nt = 64;
  int ok = p.S && p.spec && at;
  for (int t = 0; ok && t < nt; t++) {
    buf[t] = fftw_malloc((size_t)BATCH * my * sizeof *buf[t]);
    rbuf[t] = fftw_malloc((size_t)(mx + 2) * sizeof *rbuf[t]);
    ok = buf[t] && rbuf[t];
  }
  if (!ok) {
    snprintf(why, cap, "out of memory for an FFT grid of %d x %d", mx, my);
    goto done;
  }
#pragma omp critical(pp_fftw_planner) /* FFTW's planner is not thread-safe */
  {
    fftw_complex *cb = buf[0];
    double *rb = rbuf[0];
    fftw_complex *rc_ = (fftw_complex *)(void *)rbuf[0];
    p.row_f = fftw_plan_dft_r2c_1d(mx, rb, rc_, FFTW_ESTIMATE);
    p.row_b = fftw_plan_dft_c2r_1d(mx, rc_, rb, FFTW_ESTIMATE);
    p.col_f = fftw_plan_many_dft(1, &my, BATCH, cb, NULL, 1, my, cb, NULL, 1, my, FFTW_FORWARD,
                                 FFTW_ESTIMATE);
    p.col_b = fftw_plan_many_dft(1, &my, BATCH, cb, NULL, 1, my, cb, NULL, 1, my, FFTW_BACKWARD,
                                 FFTW_ESTIMATE);
  }
  if (!p.row_f || !p.row_b || !p.col_f || !p.col_b) {
    snprintf(why, cap, "FFTW could not plan transforms of %d and %d", mx, my);
    goto done;
  }
  /* the kernel's spectrum: its centre at the origin (offsets wrap around), its 2R + 1 rows along x
   * into S, then along y, scaled by the inverse transform's 1 / (mx my). The kernel is
   * point-symmetric, so its spectrum is real: the imaginary parts are rounding and are dropped. */
#pragma omp parallel for num_threads(nt) schedule(static)
  for (int dy = -R; dy <= R; dy++) {
    double *rb = rbuf[omp_get_thread_num()];
    memset(rb, 0, (size_t)(mx + 2) * sizeof *rb);
    for (int dx = -R; dx <= R; dx++)
      rb[(dx + mx) % mx] = k->k[(size_t)(dy + R) * side + (size_t)(dx + R)];
    fftw_execute_dft_r2c(p.row_f, rb, (fftw_complex *)(void *)rb);
    memcpy(p.S + (size_t)(dy + R) * hx, rb, (size_t)hx * sizeof *p.S);
    at[dy + R] = (dy + my) % my;
  }
  columns(&p, side, at, 1.0 / ((double)mx * (double)my), NULL, buf);
  for (int c = 0; c < n; c++) {
    double fin = 0.0, peak = 0.0, full = 0.0, frame = 0.0, low = 0.0;
    const float *src = in[c];
    float *dst = out[c];
    /* the plane's rows along x; the rows below it are zero and are not stored */
#pragma omp parallel for num_threads(nt) schedule(static) reduction(+ : fin) reduction(max : peak)
    for (int y = 0; y < h; y++) {
      double *rb = rbuf[omp_get_thread_num()];
      for (int x = 0; x < w; x++) {
        double v = src[(size_t)y * w + x];
        rb[x] = v;
        fin += v;
        peak = fmax(peak, v);
      }
      memset(rb + w, 0, (size_t)(mx + 2 - w) * sizeof *rb);
      fftw_execute_dft_r2c(p.row_f, rb, (fftw_complex *)(void *)rb);
      memcpy(p.S + (size_t)y * hx, rb, (size_t)hx * sizeof *p.S);
    }
    columns(&p, h, NULL, 1.0, &full, buf);
    /* back along x, the h rows the image keeps */
#pragma omp parallel for num_threads(nt) schedule(static) reduction(+ : frame) reduction(min : low)
    for (int y = 0; y < h; y++) {
      double *rb = rbuf[omp_get_thread_num()];
      memcpy(rb, p.S + (size_t)y * hx, (size_t)hx * sizeof *p.S);
      fftw_execute_dft_c2r(p.row_b, (fftw_complex *)(void *)rb, rb);
      for (int x = 0; x < w; x++) {
        double v = rb[x];
        if (v < 0.0) { /* rounding below a non-negative kernel's non-negative result */
          low = fmin(low, v);
          v = 0.0;
        }
        frame += v;
        dst[(size_t)y * w + x] = (float)v;
      }
    }
    if (flux)
      flux[c] = (pp_star_flux_t){fin, full, frame, low < 0.0 && peak > 0.0 ? -low / peak : 0.0};
  }
  rc = 0;
done :
#pragma omp critical(pp_fftw_planner)
{
  if (p.row_f)
    fftw_destroy_plan(p.row_f);
  if (p.row_b)
    fftw_destroy_plan(p.row_b);
  if (p.col_f)
    fftw_destroy_plan(p.col_f);
  if (p.col_b)
    fftw_destroy_plan(p.col_b);
}
  for (int t = 0; t < nt; t++) {
    fftw_free(buf[t]);
    fftw_free(rbuf[t]);
  }
  fftw_free(p.S);
  free(p.spec);
  free(at);
  return rc;
}

void pp_convolve_direct(const pp_kernel_t *k, int w, int h, const float *in, double *out) {
  int R = k->radius;
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++) {
      double s = 0.0;
      for (int dy = -R; dy <= R; dy++) {
        int sy = y - dy;
        if (sy < 0 || sy >= h)
          continue;
        for (int dx = -R; dx <= R; dx++) {
          int sx = x - dx;
          if (sx >= 0 && sx < w)
            s += (double)in[(size_t)sy * w + sx] * k->k[(size_t)(dy + R) * k->side + (dx + R)];
        }
      }
      out[(size_t)y * w + x] = s;
    }
}

float pp_tone(float linear, double exposure, double white) {
  double l = isfinite(linear) ? fmax(0.0, linear * exposure) : 0.0;
  double t = l * (1.0 + l / (white * white)) / (1.0 + l);
  return (float)fmin(t, 1.0);
}
