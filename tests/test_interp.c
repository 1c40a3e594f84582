/* test_interp.c -- ray interpolation and e_int (section 4.1 (2)). */
#include <math.h>

#include "cmocka_main.h"
#include "paraxial/interp.h"

/* the printed second-order formula reproduces any quadratic exactly */
static void quadratic_is_exact_on_parabolas(void **state) {
  (void)state;
  double f[3], out;
  for (int k = -1; k <= 1; k++)
    f[k + 1] = 3.0 * k * k - 2.0 * k + 0.5;
  for (double a = -1.0; a <= 1.0; a += 0.125) {
    px_interp_quadratic(1, &f[0], &f[1], &f[2], a, &out);
    assert_close(out, 3.0 * a * a - 2.0 * a + 0.5, 1e-15, 1e-15);
  }
}

/* e_int is the linear interpolation's true error when the data are quadratic */
static void e_int_equals_linear_error_on_parabolas(void **state) {
  (void)state;
  double xm1[2] = {1.0, 4.0}, x0[2] = {0.0, 0.0}, x1[2] = {1.0, 4.0}, lin[2];
  for (double a = 0.0; a <= 1.0; a += 0.1) {
    px_interp_linear(2, x0, x1, a, lin);
    double truth = hypot(a * a - lin[0], 4 * a * a - lin[1]);
    assert_close(px_interp_error(2, xm1, x0, x1, a), truth, 1e-14, 1e-15);
  }
  assert_close(px_interp_error_max(2, xm1, x0, x1), px_interp_error(2, xm1, x0, x1, 0.5), 1e-15, 0);
}

static void linear_data_has_no_interpolation_error(void **state) {
  (void)state;
  double xm1[3] = {-1, 2, 5}, x0[3] = {0, 3, 7}, x1[3] = {1, 4, 9};
  assert_close(px_interp_error_max(3, xm1, x0, x1), 0.0, 0, 1e-15);
}

static void bilinear_hits_corners_and_centre(void **state) {
  (void)state;
  double c00 = 1, c10 = 2, c01 = 3, c11 = 7, out;
  px_interp_bilinear(1, &c00, &c10, &c01, &c11, 1, 1, &out);
  assert_close(out, 7, 0, 1e-15);
  px_interp_bilinear(1, &c00, &c10, &c01, &c11, 0.5, 0.5, &out);
  assert_close(out, 13.0 / 4.0, 1e-15, 0);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(quadratic_is_exact_on_parabolas),
      cmocka_unit_test(e_int_equals_linear_error_on_parabolas),
      cmocka_unit_test(linear_data_has_no_interpolation_error),
      cmocka_unit_test(bilinear_hits_corners_and_centre),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
