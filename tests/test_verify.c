/* test_verify.c -- the verification sweep on a small configuration: every corrected matrix
 * agrees with exact tracing, every expected TIR is reported by both sides, and the printed
 * Eq. (2) disagrees where docs/errata.md says it does; and the benchmarks' per-pixel difference. */
#include <math.h>
#include <stdlib.h>

#include "cmocka_main.h"
#include "core/intersect.h"
#include "io/scene_json.h"
#include "validation/compare.h"
#include "validation/illum_bench.h"
#include "validation/illuminance.h"
#include "validation/verify.h"

static void quick_sweep_passes(void **state) {
  (void)state;
  size_t n = 0;
  val_system_t *sw = val_sweep_build(1, 1, &n);
  assert_non_null(sw);
  assert_true(n > 100);
  size_t tir = 0, fam[VAL_FAMILY_COUNT] = {0};
  for (size_t i = 0; i < n; i++) {
    val_matrix_result_t r;
    val_verify_matrix(&sw[i], &r);
    if (!r.pass)
      fail_msg("system %zu (%s): %s, rel err %.3e", i, sw[i].label, px_strerror(r.status),
               r.rel_err);
    tir += sw[i].expect_tir;
    fam[sw[i].family]++;
  }
  assert_true(tir > 0);
  for (int f = 0; f < VAL_FAMILY_COUNT; f++)
    assert_true(fam[f] > 0);
  free(sw);
}

static void full_sweep_has_over_2000_systems(void **state) {
  (void)state;
  size_t n = 0;
  val_system_t *sw = val_sweep_build(1, 0, &n);
  assert_non_null(sw);
  assert_true(n >= 2000);
  free(sw);
}

/* Errata E1 (B = identity as printed) shows on every system; E2 (sign of h Q) on every curved
 * surface; E3 (Theta'^-1 for Theta'^-t) only with rotated frames. */
static void printed_form_fails_where_documented(void **state) {
  (void)state;
  size_t n = 0;
  val_system_t *sw = val_sweep_build(1, 1, &n);
  for (size_t i = 0; i < n; i++) {
    const val_system_t *v = &sw[i];
    if (v->expect_tir || v->family == VAL_FAMILY_TRANSFER || v->family == VAL_FAMILY_CASCADE)
      continue;
    val_matrix_result_t r;
    val_verify_matrix(v, &r);
    int ok = r.printed_block[1] > 1e-6 /* B = 1 shows as 1/L >= 1e-3 in scaled units */
             && r.printed_block[0] < VAL_MATRIX_TOL; /* A agrees */
    if (v->family != VAL_FAMILY_PLANE && v->theta_deg < 89)
      ok = ok && r.printed_block[2] > 1e-6; /* C: sign */
    if (!v->rotated)
      ok = ok && r.printed_block[3] < VAL_MATRIX_TOL; /* D agrees in the paper's frames */
    if (!ok)
      fail_msg("system %zu (%s): printed A %.3g B %.3g C %.3g D %.3g", i, v->label,
               r.printed_block[0], r.printed_block[1], r.printed_block[2], r.printed_block[3]);
  }
  free(sw);
}

/* Eqs. (8)-(9) against the exact flux Jacobian on the quick sweep (both sources, receivers at 0
 * to 89.9 degrees, receivers nearing caustics): no failure. The energy check of the 1989
 * Eq. (1): Eq. (8) puts on a pool's floor the flux the light sends into the cone; the printed
 * index factor loses n1/n2 of it. */
static void illuminance_quick_sweep_passes(void **state) {
  (void)state;
  val_illum_opts_t o = {1, NULL, NULL, NULL};
  assert_int_equal(val_verify_illuminance(&o), 0);
  double c = val_pool_flux_ratio(2.0, 1.0, 1.333, 40.0, PX_VARIANT_CORRECTED);
  double p = val_pool_flux_ratio(2.0, 1.0, 1.333, 40.0, PX_VARIANT_PRINTED);
  print_message("pool flux ratio: Eq. (8) %.15f, printed Eq. (1) %.15f\n", c, p);
  assert_close(c, 1.0, 1e-10, 0.0);
  assert_close(p, 1.0 / 1.333, 1e-9, 0.0);
  /* counted by the light library on the pool's floor under the light: Eq. (8) holds to the
   * cell's own averaging (0.1%), the printed factor is a quarter off */
  double k[4];
  assert_true(val_pool_counted(2.0, 1.0, 1.333, 0.2, k));
  print_message("counted: grid-pencil %.5f, photons %.5f; Eq. (8) %.5f, printed %.5f\n", k[0], k[1],
                k[2], k[3]);
  assert_close(k[0], k[2], 5e-3, 0.0);
  assert_close(k[1], k[2], 3e-2, 0.0);
  assert_true(fabs(k[3] - k[0]) > 0.2 * k[0]);
}

/* The exact reference of the illuminance benchmark (val_ring_map) on cases it must get exactly:
 * a ball of index 1 bends nothing, so a point light 8 above the floor gives the inverse square
 * law H / d^3 and a parallel light gives 1 everywhere. The cells' smoothness follows. */
static void ring_map_reference_without_refraction(void **state) {
  (void)state;
  for (int point = 0; point < 2; point++) {
    lt_map_t m;
    unsigned char smooth[16 * 16];
    assert_int_equal(lt_map_alloc(&m, 16, 16, -2, 2, -2, 2), RT_OK);
    val_ring_map(1.0, 1.0, 2.5, point ? 8.0 : 0.0, 200000, &m, smooth);
    double worst = 0.0;
    int nsmooth = 0;
    for (int j = 0; j < 16; j++)
      for (int i = 0; i < 16; i++) {
        double x = 0.0; /* the cell average by 20 x 20 midpoints */
        for (int a = 0; a < 20; a++)
          for (int b = 0; b < 20; b++) {
            double u = -2 + (i + (a + 0.5) / 20) * 0.25, v = -2 + (j + (b + 0.5) / 20) * 0.25;
            double d2 = u * u + v * v + 64.0;
            x += (point ? 8.0 / (d2 * sqrt(d2)) : 1.0) / 400.0;
          }
        worst = fmax(worst, fabs(m.e[3 * (j * 16 + i)] - x) / x);
        nsmooth += smooth[j * 16 + i];
      }
    print_message("ring map, %s light, no refraction: worst %.3e, %d of 256 cells smooth\n",
                  point ? "point" : "parallel", worst, nsmooth);
    assert_true(worst < 2e-5);
    assert_int_equal(nsmooth, 256);
    lt_map_free(&m);
  }
}

/* A lamp inside a glass globe: a point light 0.4 above the centre of a ball of index 1.5 (kt 1,
 * kr 0) whose centre is 2.5 above the floor. The light's rays start in the glass
 * (rt_medium_ior()), so they refract where they leave it. The grid-pencil map against the exact
 * reference from meridional rays (val_ring_map(), extended to a source inside), within 2% on
 * the cells where the exact field is smooth, and its flux within 1%. Started in the scene's
 * medium, as they once were, the rays went straight through the exit: the map was 20% low at
 * the centre, 22% off at worst and a quarter of its flux short. */
static void lamp_inside_a_glass_ball(void **state) {
  (void)state;
  static const char json[] =
      "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
      " \"settings\": {\"max_depth\": 8},"
      " \"materials\": {\"white\": {\"kd\": 0.8},"
      "  \"glass\": {\"ka\": 0, \"kd\": 0, \"kr\": 0, \"kt\": 1, \"ior\": 1.5}},"
      " \"lights\": [{\"type\": \"point\", \"position\": [0, 2.9, 0], \"intensity\": 1,"
      "  \"falloff\": \"inverse-square\"}],"
      " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
      "  \"normal\": [0, 1, 0], \"material\": \"white\"},"
      "  {\"type\": \"sphere\", \"name\": \"ball\", \"center\": [0, 2.5, 0], \"radius\": 1,"
      "   \"material\": \"glass\"}]}";
  rt_scene_t s;
  char err[512];
  rt_scene_init(&s);
  assert_int_equal(io_scene_load_buffer("lamp", json, sizeof json - 1, &s, err, sizeof err), 0);
  assert_true(rt_medium_ior(&s, px_vec3(0, 2.9, 0)) == 1.5);
  assert_true(rt_medium_ior(&s, px_vec3(0, 5, 0)) == s.ior);
  assert_true(rt_medium_ior(&s, px_vec3(0.3, 2.2, -0.4)) == 1.5);
  int floor_obj = 0;
  lt_receiver_t rc;
  assert_int_equal(lt_receiver_make(&s, &floor_obj, 1, &rc, err, sizeof err), RT_OK);
  enum { W = 32 };
  lt_map_t ref, m;
  unsigned char smooth[W * W];
  assert_int_equal(lt_map_alloc(&ref, W, W, -4, 4, -4, 4), RT_OK);
  assert_int_equal(lt_map_alloc(&m, W, W, -4, 4, -4, 4), RT_OK);
  val_ring_map(1.0, 1.5, 2.5, 2.9, 400000, &ref, smooth);
  lt_options_t o = LT_OPTIONS_DEFAULT;
  o.method = LT_METHOD_GRID_PENCIL;
  lt_stats_t st;
  assert_int_equal(lt_illuminance(&s, &rc, &o, &m, &st), RT_OK);
  double worst = 0.0, centre = 0.0, centre_ref = 0.0, flux = 0.0, flux_ref = 0.0;
  int compared = 0;
  for (int k = 0; k < W * W; k++) {
    double e = m.e[3 * k], x = ref.e[3 * k];
    if (k == (W / 2) * W + W / 2)
      centre = e, centre_ref = x;
    flux += e;
    flux_ref += x;
    if (!smooth[k] || !(x > 0.0))
      continue;
    worst = fmax(worst, fabs(e - x) / x);
    compared++;
  }
  print_message("lamp inside a glass ball: %d smooth cells, worst %.4f; at the centre %.5f "
                "against %.5f; flux on the map %.5f against %.5f\n",
                compared, worst, centre, centre_ref, flux, flux_ref);
  assert_true(compared >= 40);
  assert_true(worst < 0.02);
  assert_true(fabs(flux - flux_ref) < 0.01 * flux_ref);
  lt_map_free(&ref);
  lt_map_free(&m);
  rt_scene_free(&s);
}

/* The benchmarks' per-pixel difference (validation/compare.h): per pixel the largest channel of
 * |a - b|, its mean, RMS, 99th percentile and largest, on 100 pixels whose differences are known:
 * pixel k differs by k / 100 in one channel (which channel turns with k) and by less in another. */
static void image_diff_by_largest_channel(void **state) {
  (void)state;
  rt_image_t a, b;
  assert_int_equal(rt_image_alloc(&a, 10, 10), RT_OK);
  assert_int_equal(rt_image_alloc(&b, 10, 10), RT_OK);
  double sum = 0.0, s2 = 0.0;
  for (int k = 0; k < 100; k++) {
    int c = RT_CH_R + k % 3;
    double e = k / 100.0;
    for (int q = RT_CH_R; q <= RT_CH_B; q++)
      a.ch[q][k] = b.ch[q][k] = 0.5f;
    a.ch[c][k] = (float)(0.5 + (k % 2 ? e : -e));
    a.ch[RT_CH_R + (k + 1) % 3][k] = (float)(0.5 + 0.5 * e);
    sum += (double)fabsf(a.ch[c][k] - 0.5f);
    s2 += (double)(a.ch[c][k] - 0.5f) * (a.ch[c][k] - 0.5f);
  }
  val_diff_t d;
  assert_int_equal(val_image_diff(&a, &b, &d), 0);
  assert_float_equal(d.mean, sum / 100.0, 1e-12);
  assert_float_equal(d.rms, sqrt(s2 / 100.0), 1e-12);
  assert_float_equal(d.max, (double)fabsf(a.ch[RT_CH_R + 99 % 3][99] - 0.5f), 1e-12);
  assert_float_equal(d.p99, (double)fabsf(a.ch[RT_CH_R + 98 % 3][98] - 0.5f), 1e-12);
  assert_int_equal(val_image_diff(&a, &a, &d), 0);
  assert_true(d.mean == 0.0 && d.rms == 0.0 && d.p99 == 0.0 && d.max == 0.0);
  rt_image_free(&a);
  rt_image_free(&b);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(quick_sweep_passes),
      cmocka_unit_test(image_diff_by_largest_channel),
      cmocka_unit_test(illuminance_quick_sweep_passes),
      cmocka_unit_test(ring_map_reference_without_refraction),
      cmocka_unit_test(lamp_inside_a_glass_ball),
      cmocka_unit_test(full_sweep_has_over_2000_systems),
      cmocka_unit_test(printed_form_fails_where_documented),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
