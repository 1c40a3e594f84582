/* test_star.c -- the cross-screen filter (post/star.h; 1989 paper, section 4): the kernel of
 * Eq. (16) on the pixel grid, the FFT convolution against direct summation, energy, linearity,
 * the parameters' errors and the display curve. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmocka_main.h"
#include "post/star.h"

/* A small plate: on a 64-pixel-wide image, rays of (1.5 - 1) 50 / (36 / 64) = 44.4 pixels a unit
 * of slope, slopes 0.02 and 0.06: a kernel of radius ceil(5.33 x 2.67) = 15. */
static pp_star_t small_plate(void) {
  pp_star_t p = PP_STAR_DEFAULT;
  p.sigma1 = 0.02;
  p.sigma2 = 0.06;
  p.ratio = 0.2;
  return p;
}

static uint64_t rng = 88172645463325252ULL;
static double uniform(void) {
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return (double)(rng >> 11) / 9007199254740992.0;
}

/* An HDR test image: a dim random background with a few spots thousands of times brighter. */
static float *hdr_image(int w, int h) {
  float *im = malloc(sizeof(float) * (size_t)w * h);
  assert_non_null(im);
  for (int k = 0; k < w * h; k++)
    im[k] = (float)(0.1 * uniform());
  for (int s = 0; s < 4; s++)
    im[(size_t)(h / 5 + s * h / 6) * w + (w / 7 + s * w / 5)] =
        (float)(1000.0 + 2000.0 * uniform());
  return im;
}

/* The kernel sums to 1, holds A = 1 - B at its centre, is point-symmetric, and puts each
 * direction's light on its line: one horizontal scratch direction (angle 0) makes a vertical
 * star ray, all of the B in the centre column. The radius follows 5.33 of the wider Gaussian's
 * standard deviations, and the profile's tail beyond it is below 1e-7. */
static void kernel_shape(void **state) {
  (void)state;
  pp_star_t p = small_plate();
  char why[256];
  pp_kernel_t k;
  assert_int_equal(pp_star_kernel(&p, 64, 64, &k, why, sizeof why), 0);
  assert_close(k.scale, 0.5 * 50.0 / (36.0 / 64.0), 1e-14, 0.0);
  assert_int_equal(k.radius, (int)ceil(5.33 * 0.06 * k.scale));
  assert_true(k.tail > 0.0 && k.tail < 1e-7);
  double sum = 0.0;
  for (int q = 0; q < k.side * k.side; q++) {
    sum += k.k[q];
    assert_true(k.k[q] >= 0.0);
    assert_close(k.k[q], k.k[k.side * k.side - 1 - q], 1e-13, 1e-18); /* point symmetry */
  }
  assert_close(sum, 1.0, 1e-13, 0.0);
  assert_true(k.k[(size_t)k.radius * k.side + k.radius] > 1.0 - p.ratio);
  pp_kernel_free(&k);

  p.directions = 1;
  p.angle_deg = 0.0;
  assert_int_equal(pp_star_kernel(&p, 64, 64, &k, why, sizeof why), 0);
  double column = 0.0;
  for (int j = 0; j < k.side; j++)
    column += k.k[(size_t)j * k.side + k.radius];
  assert_close(column, 1.0, 1e-13, 0.0);
  pp_kernel_free(&k);
  /* 45 degrees: the ray runs along the other diagonal (perpendicular), up-left to down-right */
  p.angle_deg = 45.0;
  assert_int_equal(pp_star_kernel(&p, 64, 64, &k, why, sizeof why), 0);
  int R = k.radius;
  double diag = 0.0, anti = 0.0;
  for (int t = -R + 2; t <= R - 2; t++) {
    if (t == 0)
      continue;
    diag += k.k[(size_t)(R + t) * k.side + (R + t)];
    anti += k.k[(size_t)(R - t) * k.side + (R + t)];
  }
  assert_true(diag > 0.05 && anti < 1e-12);
  pp_kernel_free(&k);
}

/* The FFT's linear convolution against direct summation on non-square images with bright spots
 * near the borders: every pixel within 1e-9 of the image's peak (the issue asks 1e-6 relative),
 * and every pixel above a millionth of the peak within 1e-6 of itself. */
static void fft_matches_direct(void **state) {
  (void)state;
  /* the last is wide enough for a grid of a multiple of 32 (good_size() from 256 up) */
  const int sizes[4][2] = {{64, 41}, {37, 64}, {50, 50}, {290, 60}};
  for (int t = 0; t < 4; t++) {
    int w = sizes[t][0], h = sizes[t][1];
    pp_star_t p = small_plate();
    p.directions = t + 1;
    p.angle_deg = 10.0 * t;
    char why[256];
    pp_kernel_t k;
    assert_int_equal(pp_star_kernel(&p, 64, w < h ? w : h, &k, why, sizeof why), 0);
    float *im = hdr_image(w, h), *out = malloc(sizeof(float) * (size_t)w * h);
    double *ref = malloc(sizeof(double) * (size_t)w * h);
    assert_non_null(out);
    assert_non_null(ref);
    im[0] = 5000.0f; /* a spot in the corner: its star leaves the frame */
    const float *in[1] = {im};
    float *o[1] = {out};
    pp_star_flux_t fl;
    assert_int_equal(pp_star_apply(&k, w, h, 1, in, o, 2, &fl, why, sizeof why), 0);
    pp_convolve_direct(&k, w, h, im, ref);
    double peak = 0.0, worst = 0.0, worst_rel = 0.0;
    for (int q = 0; q < w * h; q++)
      peak = fmax(peak, ref[q]);
    for (int q = 0; q < w * h; q++) {
      double d = fabs(out[q] - ref[q]) - 6e-8 * fabs(ref[q]); /* float storage */
      worst = fmax(worst, d / peak);
      if (ref[q] > 1e-6 * peak)
        worst_rel = fmax(worst_rel, fabs(out[q] - ref[q]) / ref[q]);
    }
    print_message("%d x %d, %d direction(s): FFT against direct %.2e of the peak, %.2e relative; "
                  "flux in %.6f, full %.6f, frame %.6f\n",
                  w, h, p.directions, worst, worst_rel, fl.in, fl.full, fl.frame);
    assert_true(worst < 1e-9);
    assert_true(worst_rel < 1e-6);
    assert_true(fl.frame < fl.in); /* the corner's star reaches beyond the frame */
    free(im);
    free(out);
    free(ref);
    pp_kernel_free(&k);
  }
}

/* Energy: the full convolution holds the input's flux within 1e-12 relative, and a spot whose
 * star stays inside the frame keeps all of it in the frame (1e-6, the target). */
static void energy_is_kept(void **state) {
  (void)state;
  int w = 96, h = 80;
  pp_star_t p = small_plate();
  p.directions = 3;
  char why[256];
  pp_kernel_t k;
  assert_int_equal(pp_star_kernel(&p, 64, h, &k, why, sizeof why), 0);
  float *im = calloc((size_t)w * h, sizeof(float)), *out = malloc(sizeof(float) * (size_t)w * h);
  assert_non_null(im);
  assert_non_null(out);
  im[(size_t)(h / 2) * w + w / 2] = 3200.0f;
  im[(size_t)(h / 2 + 3) * w + w / 2 - 5] = 1.0f;
  const float *in[1] = {im};
  float *o[1] = {out};
  pp_star_flux_t fl;
  assert_int_equal(pp_star_apply(&k, w, h, 1, in, o, 1, &fl, why, sizeof why), 0);
  double sum = 0.0;
  for (int q = 0; q < w * h; q++)
    sum += out[q];
  assert_close(fl.full, fl.in, 1e-12, 0.0);
  assert_close(fl.frame, fl.in, 1e-6, 0.0);
  assert_close(sum, fl.in, 1e-6, 0.0);
  assert_true(fl.clamped < 1e-12);
  free(im);
  free(out);
  pp_kernel_free(&k);
}

/* Linearity: the filter of 2 a + 3 b is 2 filter(a) + 3 filter(b), three planes at once, and the
 * output may overwrite the input. */
static void filter_is_linear(void **state) {
  (void)state;
  int w = 48, h = 40;
  pp_star_t p = small_plate();
  char why[256];
  pp_kernel_t k;
  assert_int_equal(pp_star_kernel(&p, 48, h, &k, why, sizeof why), 0);
  float *a = hdr_image(w, h), *b = hdr_image(w, h), *c = malloc(sizeof(float) * (size_t)w * h);
  float *fa = malloc(sizeof(float) * (size_t)w * h), *fb = malloc(sizeof(float) * (size_t)w * h);
  assert_non_null(c);
  assert_non_null(fa);
  assert_non_null(fb);
  for (int q = 0; q < w * h; q++)
    c[q] = 2.0f * a[q] + 3.0f * b[q];
  float *copy_c = malloc(sizeof(float) * (size_t)w * h);
  assert_non_null(copy_c);
  memcpy(copy_c, c, sizeof(float) * (size_t)w * h);
  const float *in[3] = {a, b, c};
  float *out[3] = {fa, fb, c}; /* c in place */
  assert_int_equal(pp_star_apply(&k, w, h, 3, in, out, 2, NULL, why, sizeof why), 0);
  double peak = 0.0, worst = 0.0;
  for (int q = 0; q < w * h; q++) {
    double want = 2.0 * fa[q] + 3.0 * fb[q];
    peak = fmax(peak, want);
    worst = fmax(worst, fabs(c[q] - want));
  }
  assert_true(worst < 1e-6 * peak);
  free(a);
  free(b);
  free(c);
  free(fa);
  free(fb);
  free(copy_c);
  pp_kernel_free(&k);
}

/* Bad parameters are named; a kernel wider than the image is refused with its size; B = 0 is the
 * identity. */
static void bad_parameters(void **state) {
  (void)state;
  char why[256];
  pp_kernel_t k;
  pp_star_t p = PP_STAR_DEFAULT;
  p.ior = 1.0;
  assert_int_equal(pp_star_kernel(&p, 512, 512, &k, why, sizeof why), -1);
  assert_non_null(strstr(why, "ior"));
  p = (pp_star_t)PP_STAR_DEFAULT;
  p.ratio = 1.0;
  assert_int_equal(pp_star_check(&p, why, sizeof why), -1);
  assert_non_null(strstr(why, "ratio"));
  p = (pp_star_t)PP_STAR_DEFAULT;
  p.sigma2 = NAN;
  assert_int_equal(pp_star_check(&p, why, sizeof why), -1);
  assert_non_null(strstr(why, "sigma"));
  p = (pp_star_t)PP_STAR_DEFAULT;
  p.directions = 0;
  assert_int_equal(pp_star_check(&p, why, sizeof why), -1);
  assert_non_null(strstr(why, "directions"));
  p = (pp_star_t)PP_STAR_DEFAULT;
  assert_int_equal(pp_star_kernel(&p, 512, 100, &k, why, sizeof why), -1);
  assert_non_null(strstr(why, "larger than the image"));
  /* B = 0: a 1 x 1 kernel of 1, the image unchanged */
  p.ratio = 0.0;
  assert_int_equal(pp_star_kernel(&p, 512, 100, &k, why, sizeof why), 0);
  assert_int_equal(k.side, 1);
  float im[6] = {1, 2, 3, 4, 5, 6}, out[6] = {0};
  const float *in[1] = {im};
  float *o[1] = {out};
  assert_int_equal(pp_star_apply(&k, 3, 2, 1, in, o, 1, NULL, why, sizeof why), 0);
  for (int q = 0; q < 6; q++)
    assert_close(out[q], im[q], 1e-6, 0.0);
  pp_kernel_free(&k);
}

/* The display curve: 0 to 0, white to 1, monotone, above white clipped. */
static void tone_curve(void **state) {
  (void)state;
  assert_true(pp_tone(0.0f, 1.0, 8.0) == 0.0f);
  assert_close(pp_tone(8.0f, 1.0, 8.0), 1.0, 1e-6, 0.0);
  assert_close(pp_tone(2.0f, 4.0, 8.0), 1.0, 1e-6, 0.0);
  assert_true(pp_tone(100.0f, 1.0, 8.0) == 1.0f);
  assert_true(pp_tone(NAN, 1.0, 8.0) == 0.0f && pp_tone(-1.0f, 1.0, 8.0) == 0.0f);
  float prev = 0.0f;
  for (int q = 1; q < 80; q++) { /* up to white */
    float t = pp_tone(0.1f * q, 1.0, 8.0);
    assert_true(t > prev);
    prev = t;
  }
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(kernel_shape),   cmocka_unit_test(fft_matches_direct),
      cmocka_unit_test(energy_is_kept), cmocka_unit_test(filter_is_linear),
      cmocka_unit_test(bad_parameters), cmocka_unit_test(tone_curve),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
