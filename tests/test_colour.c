/* test_colour.c -- colour/colour.h: the CIE 1931 observer read from colord-data, the sRGB
 * matrices derived from the primaries, CIELAB, CIEDE2000 against Sharma, Wu and Dalal's (2005)
 * published test pairs, and the spectral bins' RGB weights. */
#include <math.h>
#include <stdio.h>

#include "cmocka_main.h"
#include "colour/colour.h"

/* The table as CIE 015 tabulates it: 360-830 nm, y-bar's peak 1 at 555 nm, the other functions'
 * peaks where the standard puts them, and the three integrals equal (the observer is normalised so
 * that light of equal energy is at x = y = 1/3). Linear between rows. */
static void observer_table(void **state) {
  (void)state;
  double lo, hi, v[3], a[3], b[3];
  cs_cmf_range(&lo, &hi);
  assert_true(lo == 360.0 && hi == 830.0);
  cs_cmf(555.0, v);
  assert_true(v[1] == 1.0);
  cs_cmf(600.0, v);
  assert_close(v[0], 1.0622, 0.0, 1e-12);
  cs_cmf(445.0, v);
  assert_close(v[2], 1.7826, 0.0, 1e-12);
  cs_cmf(555.0, a);
  cs_cmf(560.0, b);
  cs_cmf(557.5, v);
  for (int c = 0; c < 3; c++)
    assert_close(v[c], 0.5 * (a[c] + b[c]), 1e-15, 0.0);
  cs_cmf(359.0, v);
  assert_true(v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0);
  double s[3];
  cs_cmf_integral(360.0, 830.0, s);
  double sum = s[0] + s[1] + s[2];
  print_message("integrals %.6f %.6f %.6f nm; equal energy at x %.6f, y %.6f\n", s[0], s[1], s[2],
                s[0] / sum, s[1] / sum);
  assert_close(s[0] / sum, 1.0 / 3.0, 0.0, 1e-4);
  assert_close(s[1] / sum, 1.0 / 3.0, 0.0, 1e-4);
  assert_close(s[1], 106.857, 0.0, 0.01);
}

/* The integral is exact for the piecewise-linear functions: against Simpson's rule on 200,000
 * steps over spans that start and end between rows, and additive over adjacent spans. */
static void observer_integral(void **state) {
  (void)state;
  const double spans[4][2] = {{380.0, 780.0}, {401.3, 402.9}, {358.0, 372.6}, {777.7, 840.0}};
  for (int t = 0; t < 4; t++) {
    double got[3], want[3] = {0, 0, 0};
    cs_cmf_integral(spans[t][0], spans[t][1], got);
    double a = fmax(spans[t][0], 360.0), b = fmin(spans[t][1], 830.0); /* 0 outside */
    int n = 200000;
    double h = (b - a) / n;
    for (int k = 0; k <= n; k++) {
      double v[3], wgt = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
      cs_cmf(a + k * h, v);
      for (int c = 0; c < 3; c++)
        want[c] += wgt * v[c] * h / 3.0;
    }
    for (int c = 0; c < 3; c++)
      assert_close(got[c], want[c], 1e-9, 1e-15); /* Simpson's error at the rows' kinks */
  }
  double whole[3], left[3], right[3];
  cs_cmf_integral(380.0, 780.0, whole);
  cs_cmf_integral(380.0, 512.34, left);
  cs_cmf_integral(512.34, 780.0, right);
  for (int c = 0; c < 3; c++)
    assert_close(left[c] + right[c], whole[c], 1e-14, 0.0);
}

/* The sRGB matrices derived from the primaries and D65 against IEC 61966-2-1's printed sRGB-to-XYZ
 * matrix (rounded to four decimals); each other's inverse; the white maps to (1, 1, 1). (The
 * standard's printed XYZ-to-sRGB matrix, 3.2406 ..., is the inverse of the rounded one and differs
 * from the exact inverse by up to 4e-4.) */
static void srgb_matrices(void **state) {
  (void)state;
  const double printed[3][3] = {
      {0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}};
  double m[3][3], mi[3][3], w[3];
  cs_srgb_from_xyz(m);
  cs_xyz_from_srgb(mi);
  cs_white_d65(w);
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 3; j++) {
      assert_close(mi[i][j], printed[i][j], 0.0, 5e-5);
      double id = 0.0;
      for (int k = 0; k < 3; k++)
        id += m[i][k] * mi[k][j];
      assert_close(id, i == j ? 1.0 : 0.0, 0.0, 1e-14);
    }
    assert_close(m[i][0] * w[0] + m[i][1] * w[1] + m[i][2] * w[2], 1.0, 1e-14, 0.0);
  }
}

/* CIELAB: the white is (100, 0, 0), black (0, 0, 0), and the sRGB primaries land where the
 * colorimetry literature tabulates them (D65: red 53.24, 80.09, 67.20; green 87.73, -86.18,
 * 83.18; blue 32.30, 79.19, -107.86). */
static void cielab(void **state) {
  (void)state;
  const double rgb[5][3] = {{1, 1, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double want[5][3] = {{100, 0, 0},
                             {0, 0, 0},
                             {53.24, 80.09, 67.20},
                             {87.73, -86.18, 83.18},
                             {32.30, 79.19, -107.86}};
  for (int t = 0; t < 5; t++) {
    double lab[3];
    cs_lab_from_srgb(rgb[t], lab);
    for (int c = 0; c < 3; c++)
      assert_close(lab[c], want[t][c], 0.0, t < 2 ? 1e-9 : 0.02);
  }
}

/* CIEDE2000 against pairs of Sharma, Wu and Dalal's (2005) Table 1, which exercise the hue
 * rotation term, the mean hue across 0/360 degrees and achromatic colours; the table's values are
 * rounded to four decimals. Symmetric, and 0 for equal colours. */
static void delta_e2000(void **state) {
  (void)state;
  const double pairs[][7] = {
      {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
      {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
      {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
      {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
      {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
      {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
      {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
      {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
      {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
      {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
      {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
      {84.2500, 5.7400, 96.0000, 84.4600, 8.8800, 96.4900, 1.6743},
      {84.2500, 5.7400, 96.0000, 84.5200, 5.7500, 93.0900, 0.5887},
      {84.2500, 5.7400, 96.0000, 84.3700, 5.8600, 99.4200, 0.6395},
  };
  for (size_t t = 0; t < sizeof pairs / sizeof pairs[0]; t++) {
    double d = cs_delta_e2000(pairs[t], pairs[t] + 3), e = cs_delta_e2000(pairs[t] + 3, pairs[t]);
    assert_close(d, pairs[t][6], 0.0, 5.01e-5);
    assert_close(d, e, 1e-13, 0.0);
    assert_true(cs_delta_e2000(pairs[t], pairs[t]) == 0.0);
  }
}

/* The bins' RGB weights: each channel's sum is 1 for any count (so equal-energy light is white),
 * halving a bin splits its weight exactly, the centres are the bins' middles, green's weight peaks
 * near 550 nm and red's has its negative lobe; bad arguments are refused. */
static void bin_weights(void **state) {
  (void)state;
  const int counts[4] = {1, 9, 40, 400};
  static double centre[400], w[400][3], w2[800][3], c2[800];
  for (int t = 0; t < 4; t++) {
    int n = counts[t];
    assert_int_equal(cs_bins(n, CS_LAMBDA_LO, CS_LAMBDA_HI, centre, w), 0);
    double sum[3] = {0, 0, 0};
    for (int i = 0; i < n; i++)
      for (int c = 0; c < 3; c++)
        sum[c] += w[i][c];
    for (int c = 0; c < 3; c++)
      assert_close(sum[c], 1.0, 1e-13, 0.0);
    assert_close(centre[0], CS_LAMBDA_LO + 200.0 / n, 1e-15, 0.0);
  }
  assert_int_equal(cs_bins(40, 380, 780, centre, w), 0);
  assert_int_equal(cs_bins(80, 380, 780, c2, w2), 0);
  int peak = 0, negative = 0;
  for (int i = 0; i < 40; i++) {
    for (int c = 0; c < 3; c++)
      assert_close(w2[2 * i][c] + w2[2 * i + 1][c], w[i][c], 1e-12, 1e-15);
    if (w[i][1] > w[peak][1])
      peak = i;
    negative |= w[i][0] < 0.0;
  }
  assert_true(fabs(centre[peak] - 550.0) < 20.0);
  assert_true(negative);
  assert_int_equal(cs_bins(0, 380, 780, centre, w), -1);
  assert_int_equal(cs_bins(4, 780, 380, centre, w), -1);
  assert_int_equal(cs_bins(4, 300, 780, centre, w), -1);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(observer_table), cmocka_unit_test(observer_integral),
      cmocka_unit_test(srgb_matrices),  cmocka_unit_test(cielab),
      cmocka_unit_test(delta_e2000),    cmocka_unit_test(bin_weights),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
