/* test_illuminance.c -- Eqs. (8)-(9) in libparaxial (paraxial/illuminance.h): the inverse square
 * law through a transfer, cos(alpha) for a parallel beam, a lens's gain, the caustic status and
 * its condition, the printed 1989 Eq. (1)'s index factor, and the statuses of bad input. */
#include <math.h>
#include <string.h>

#include "cmocka_main.h"
#include "paraxial/paraxial.h"

/* The cascade of a transfer d0, a refraction at a sphere of radius R (normal incidence, paper
 * frames) from n1 to n2, and a transfer d1. */
static px_status_t lens(double d0, double R, double n1, double n2, double d1, px_element_t buf[3],
                        px_cascade_t *c) {
  px_cascade_init(c, buf, 3);
  px_interface_t ifc;
  px_frame_t in, out, f;
  px_status_t st = px_interface_canonical(0.0, R, n1, n2, &ifc);
  if (st == PX_OK)
    st = px_interface_frames(&ifc, PX_EVENT_REFRACT, &in, &out);
  if (st == PX_OK)
    st = px_frame_from_z(ifc.s, in.x2, &f);
  if (st == PX_OK)
    st = px_cascade_push_transfer(c, d0, in);
  if (st == PX_OK)
    st = px_cascade_push_interface(c, &ifc, PX_EVENT_REFRACT, in, out, PX_VARIANT_CORRECTED);
  if (st == PX_OK)
    st = px_cascade_push_transfer(c, d1, out);
  return st;
}

static void inverse_square_law_through_a_transfer(void **state) {
  (void)state;
  px_frame_t f;
  assert_int_equal(px_frame_from_z(px_vec3(0, 0, 1), px_vec3(0, 1, 0), &f), PX_OK);
  px_element_t buf[1];
  px_cascade_t c;
  px_cascade_init(&c, buf, 1);
  assert_int_equal(px_cascade_push_transfer(&c, 3.0, f), PX_OK);
  px_mat4_t t = px_cascade_product(&c), ta = px_cascade_product_abs(&c);
  double r, k, e;
  assert_int_equal(px_spread_ratio(&t, &ta, PX_SOURCE_POINT, 0.5, &r, &k), PX_OK);
  assert_close(r, 0.5 / 9.0, 1e-16, 0.0); /* cos(alpha) / z^2 */
  assert_true(k >= 1.0 && k < 4.0);
  assert_int_equal(px_spread_ratio(&t, &ta, PX_SOURCE_PARALLEL, -0.5, &r, NULL), PX_OK);
  assert_close(r, 0.5, 1e-16, 0.0); /* a parallel beam: cos(alpha), whatever the distance */
  assert_int_equal(
      px_illuminance(&t, &ta, PX_SOURCE_POINT, 1.0, 2.0, 0.25, 1.0, 1.0, PX_VARIANT_CORRECTED, &e),
      PX_OK);
  assert_close(e, 0.25 * 2.0 / 9.0, 1e-16, 0.0);
}

/* A ball lens focuses a parallel beam: det A = 0 at the paraxial focus n2 R / (n2 - n1). Nearing
 * it the beam concentrates like 1/|1 - d1/f|^2; at it, and too near it for the determinant to
 * be accurate, PX_ECAUSTIC, which |T| alone (NULL) cannot see. */
static void caustic_refused_with_its_condition(void **state) {
  (void)state;
  double R = 1.0, n1 = 1.0, n2 = 1.5, f = n2 * R / (n2 - n1);
  px_element_t buf[3];
  px_cascade_t c;
  double r, k;
  assert_int_equal(lens(0.0, R, n1, n2, 0.5 * f, buf, &c), PX_OK);
  px_mat4_t t = px_cascade_product(&c), ta = px_cascade_product_abs(&c);
  assert_int_equal(px_spread_ratio(&t, &ta, PX_SOURCE_PARALLEL, 1.0, &r, &k), PX_OK);
  /* the sagittal and tangential directions both shrink by 1 - d1/f = 1/2 */
  assert_close(r, 4.0, 1e-12, 0.0);
  assert_int_equal(lens(0.0, R, n1, n2, f * (1 + 1e-10), buf, &c), PX_OK);
  t = px_cascade_product(&c);
  ta = px_cascade_product_abs(&c);
  assert_int_equal(px_spread_ratio(&t, &ta, PX_SOURCE_PARALLEL, 1.0, &r, &k), PX_ECAUSTIC);
  assert_true(k * PX_ENTRY_EPS > PX_ACCURACY);
  assert_int_equal(px_spread_ratio(&t, NULL, PX_SOURCE_PARALLEL, 1.0, &r, &k), PX_OK);
  /* a point source at the lens's vertex: B = 0 right after it, a caustic of the point itself */
  assert_int_equal(lens(0.0, R, n1, n2, 0.0, buf, &c), PX_OK);
  t = px_cascade_product(&c);
  assert_int_equal(px_spread_ratio(&t, NULL, PX_SOURCE_POINT, 1.0, &r, &k), PX_ECAUSTIC);
  assert_true(isinf(k));
}

/* The 1989 Eq. (1) as printed scales E by n1/n2; the corrected form does not depend on them. */
static void printed_index_factor(void **state) {
  (void)state;
  double R = 2.0;
  px_element_t buf[3];
  px_cascade_t c;
  assert_int_equal(lens(1.0, R, 1.0, 1.333, 0.7, buf, &c), PX_OK);
  px_mat4_t t = px_cascade_product(&c), ta = px_cascade_product_abs(&c);
  double ec, ep, ec2;
  assert_int_equal(px_illuminance(&t, &ta, PX_SOURCE_POINT, 0.8, 1.0, 1.0, 1.0, 1.333,
                                  PX_VARIANT_CORRECTED, &ec),
                   PX_OK);
  assert_int_equal(
      px_illuminance(&t, &ta, PX_SOURCE_POINT, 0.8, 1.0, 1.0, 7.0, 3.0, PX_VARIANT_CORRECTED, &ec2),
      PX_OK);
  assert_int_equal(
      px_illuminance(&t, &ta, PX_SOURCE_POINT, 0.8, 1.0, 1.0, 1.0, 1.333, PX_VARIANT_PRINTED, &ep),
      PX_OK);
  assert_true(ec == ec2);
  assert_close(ep / ec, 1.0 / 1.333, 1e-15, 0.0);
}

static void bad_input_statuses(void **state) {
  (void)state;
  px_mat4_t t = px_mat4_identity(), bad = t;
  t.m[0][2] = t.m[1][3] = 2.0;
  bad.m[1][1] = NAN;
  double r = -1.0, e = -1.0;
  assert_int_equal(px_spread_ratio(&bad, NULL, PX_SOURCE_POINT, 1.0, &r, NULL), PX_EINVAL);
  assert_int_equal(px_spread_ratio(&t, &bad, PX_SOURCE_POINT, 1.0, &r, NULL), PX_EINVAL);
  assert_int_equal(px_spread_ratio(&t, NULL, PX_SOURCE_POINT, 1.0001, &r, NULL), PX_EINVAL);
  assert_int_equal(px_spread_ratio(&t, NULL, (px_source_t)7, 1.0, &r, NULL), PX_EINVAL);
  assert_int_equal(px_spread_ratio(&t, NULL, PX_SOURCE_POINT, 1e-11, &r, NULL), PX_EGRAZING);
  assert_true(r == -1.0); /* nothing written on an error */
  assert_int_equal(px_spread_ratio(&t, NULL, PX_SOURCE_POINT, 1.0 + 1e-15, &r, NULL), PX_OK);
  assert_close(r, 0.25, 1e-16, 0.0); /* a cosine rounded above 1 is taken as 1 */
  assert_int_equal(
      px_illuminance(&t, NULL, PX_SOURCE_POINT, 1.0, 1.0, 1.5, 1.0, 1.0, PX_VARIANT_CORRECTED, &e),
      PX_EINVAL); /* transmittance above 1 */
  assert_int_equal(
      px_illuminance(&t, NULL, PX_SOURCE_POINT, 1.0, -1.0, 1.0, 1.0, 1.0, PX_VARIANT_CORRECTED, &e),
      PX_EINVAL);
  assert_int_equal(
      px_illuminance(&t, NULL, PX_SOURCE_POINT, 1.0, 1.0, 1.0, 0.0, 1.0, PX_VARIANT_PRINTED, &e),
      PX_EINVAL); /* the printed form needs both indices */
  px_mat4_t huge = t;
  huge.m[0][2] = huge.m[1][3] = 1e-200;
  assert_int_equal(px_spread_ratio(&huge, NULL, PX_SOURCE_POINT, 1.0, &r, NULL), PX_ECAUSTIC);
  huge.m[0][2] = 1e200;
  huge.m[1][3] = 1e200;
  assert_int_equal(px_spread_ratio(&huge, NULL, PX_SOURCE_POINT, 1.0, &r, NULL), PX_ENONFINITE);
  px_source_t s;
  assert_int_equal(px_source_parse("parallel", &s), PX_OK);
  assert_int_equal(s, PX_SOURCE_PARALLEL);
  assert_int_equal(px_source_parse("area", &s), PX_EINVAL);
  assert_string_equal(px_status_name(PX_ECAUSTIC), "PX_ECAUSTIC");
  assert_string_equal(px_status_name((px_status_t)99), "PX_EUNKNOWN");
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(inverse_square_law_through_a_transfer),
      cmocka_unit_test(caustic_refused_with_its_condition),
      cmocka_unit_test(printed_index_factor),
      cmocka_unit_test(bad_input_statuses),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
