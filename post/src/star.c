/* star.c -- the cross-screen filter of star.h: the kernel of the 1989 paper's Eq. (16) on the
 * pixel grid, and the linear convolution by FFT (FFTW3). */
#include "post/star.h"

#include <fftw3.h>
#include <math.h>
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

/* The smallest n' >= n whose only prime factors are 2, 3, 5 and 7 (FFTW's fast sizes). */
static int good_size(int n) {
  for (int m = n > 1 ? n : 1;; m++) {
    int r = m;
    for (int q = 2; q <= 7; q++)
      while (r % q == 0)
        r /= q;
    if (r == 1)
      return m;
  }
}

size_t pp_star_bytes(const pp_kernel_t *k, int w, int h) {
  size_t mx = (size_t)good_size(w + k->radius), my = (size_t)good_size(h + k->radius);
  size_t nc = (mx / 2 + 1) * my;
  return mx * my * sizeof(double) + nc * (sizeof(fftw_complex) + sizeof(double));
}

int pp_star_apply(const pp_kernel_t *k, int w, int h, int n, const float *const *in, float **out,
                  int threads, pp_star_flux_t *flux, char *why, size_t cap) {
  int R = k->radius, mx = good_size(w + R), my = good_size(h + R), hx = mx / 2 + 1;
  size_t nr = (size_t)mx * my, nc = (size_t)hx * my;
  double *rb = fftw_malloc(nr * sizeof *rb), *kr = malloc(nc * sizeof *kr);
  fftw_complex *ps = fftw_malloc(nc * sizeof *ps);
  fftw_plan fwd = NULL, back = NULL;
  int rc = -1, nt = threads > 0 ? threads : 1;
  if (!rb || !kr || !ps) {
    snprintf(why, cap, "out of memory for an FFT grid of %d x %d", mx, my);
    goto done;
  }
#pragma omp critical(pp_fftw_planner) /* FFTW's planner is not thread-safe */
  {
    static int threaded = 0;
    if (!threaded)
      threaded = fftw_init_threads() ? 1 : -1;
    if (threaded > 0)
      fftw_plan_with_nthreads(threads > 0 ? threads : 1);
    fwd = fftw_plan_dft_r2c_2d(my, mx, rb, ps, FFTW_ESTIMATE);
    back = fftw_plan_dft_c2r_2d(my, mx, ps, rb, FFTW_ESTIMATE);
  }
  if (!fwd || !back) {
    snprintf(why, cap, "FFTW could not plan a %d x %d transform", mx, my);
    goto done;
  }
  /* the kernel's spectrum, its centre at the origin (offsets wrap around), scaled by the
   * inverse transform's 1 / (mx my). The kernel is point-symmetric, so its spectrum is real:
   * the imaginary parts are rounding and are dropped. */
  memset(rb, 0, nr * sizeof *rb);
  for (int dy = -R; dy <= R; dy++)
    for (int dx = -R; dx <= R; dx++)
      rb[(size_t)((dy + my) % my) * mx + (size_t)((dx + mx) % mx)] =
          k->k[(size_t)(dy + R) * k->side + (size_t)(dx + R)];
  fftw_execute_dft_r2c(fwd, rb, ps);
  double norm = 1.0 / ((double)mx * (double)my);
#pragma omp parallel for num_threads(nt) schedule(static)
  for (size_t q = 0; q < nc; q++)
    kr[q] = ps[q][0] * norm;
  for (int c = 0; c < n; c++) {
    double fin = 0.0, peak = 0.0;
    const float *src = in[c];
    /* the plane into the top-left of the grid, zeros elsewhere */
#pragma omp parallel for num_threads(nt) schedule(static) reduction(+ : fin) reduction(max : peak)
    for (int y = 0; y < my; y++) {
      double *row = rb + (size_t)y * mx;
      int x = 0;
      if (y < h)
        for (; x < w; x++) {
          double v = src[(size_t)y * w + x];
          row[x] = v;
          fin += v;
          peak = fmax(peak, v);
        }
      memset(row + x, 0, (size_t)(mx - x) * sizeof *row);
    }
    fftw_execute_dft_r2c(fwd, rb, ps);
#pragma omp parallel for num_threads(nt) schedule(static)
    for (size_t q = 0; q < nc; q++) {
      ps[q][0] *= kr[q];
      ps[q][1] *= kr[q];
    }
    fftw_execute_dft_c2r(back, ps, rb);
    double full = 0.0, frame = 0.0, low = 0.0;
    float *dst = out[c];
#pragma omp parallel for num_threads(nt) schedule(static) reduction(+ : full, frame) \
    reduction(min : low)
    for (int y = 0; y < my; y++) {
      const double *row = rb + (size_t)y * mx;
      for (int x = 0; x < mx; x++) {
        double v = row[x];
        full += v;
        if (y >= h || x >= w)
          continue;
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
done:
  if (fwd)
    fftw_destroy_plan(fwd);
  if (back)
    fftw_destroy_plan(back);
  fftw_free(rb);
  free(kr);
  fftw_free(ps);
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
