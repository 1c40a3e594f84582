/* test_system.c -- element system matrices (Eqs. 1-2) and their hard cases: normal and grazing
 * incidence, total internal reflection and the critical angle, flat surfaces, extreme radii,
 * invalid parameters, the printed variant, cascades. Independent references are closed forms
 * (Snell's law in the plane of incidence, mirror and surface focal lengths). */
#include <math.h>

#include "cmocka_main.h"
#include "paraxial/paraxial.h"

#define DEG (M_PI / 180.0)

static px_mat4_t refract(double th_deg, double n1, double n2, double r) {
  px_mat4_t t;
  assert_int_equal(
      px_element_matrix(PX_EVENT_REFRACT, th_deg * DEG, n1, n2, r, PX_VARIANT_CORRECTED, &t),
      PX_OK);
  assert_true(px_mat4_isfinite(t));
  return t;
}

static void refraction_matches_closed_form(void **state) {
  (void)state;
  double th = 30 * DEG, n1 = 1.0, n2 = 1.5, r = 2.0;
  double tp = asin(n1 / n2 * sin(th)), c = cos(th), cp = cos(tp), h = cp - n1 / n2 * c;
  px_mat4_t t = refract(30, n1, n2, r);
  assert_close(t.m[0][0], cp / c, 1e-15, 0);
  assert_close(t.m[1][1], 1.0, 1e-15, 0);
  assert_close(t.m[2][0], -h / (r * c * cp), 1e-15, 0);
  assert_close(t.m[3][1], -h / r, 1e-15, 0);
  assert_close(t.m[2][2], n1 / n2 * c / cp, 1e-15, 0);
  assert_close(t.m[3][3], n1 / n2, 1e-15, 0);
  assert_true(t.m[0][2] == 0 && t.m[1][3] == 0 && t.m[0][1] == 0 && t.m[2][1] == 0);
}

/* a single surface focuses a parallel pencil at f' = n2 R / (n2 - n1) (paraxial optics) */
static void surface_focal_length(void **state) {
  (void)state;
  double n1 = 1.0, n2 = 1.5, r = 0.7;
  px_mat4_t t = px_mat4_mul(px_transfer_matrix(n2 * r / (n2 - n1)), refract(0, n1, n2, r));
  assert_close(t.m[0][0], 0.0, 0, 1e-15);
  assert_close(t.m[1][1], 0.0, 0, 1e-15);
}

/* a concave mirror (R < 0 in the project's convention) focuses at |R|/2 */
static void concave_mirror_focal_length(void **state) {
  (void)state;
  px_mat4_t m;
  assert_int_equal(px_element_matrix(PX_EVENT_REFLECT, 0, 1, 1, -3.0, PX_VARIANT_CORRECTED, &m),
                   PX_OK);
  px_mat4_t t = px_mat4_mul(px_transfer_matrix(1.5), m);
  assert_close(t.m[0][0], 0.0, 0, 1e-15);
  assert_close(t.m[1][1], 0.0, 0, 1e-15);
  assert_close(m.m[2][2], -1.0, 1e-15, 0); /* x1' = x2' x z' flips after the mirror */
  assert_close(m.m[3][3], 1.0, 1e-15, 0);
}

static void normal_incidence_is_finite_and_continuous(void **state) {
  (void)state;
  px_mat4_t a = refract(0, 1.0, 1.5, -4.0), b = refract(1e-7, 1.0, 1.5, -4.0);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      assert_close(a.m[i][j], b.m[i][j], 1e-12, 1e-12);
}

static void grazing_incidence_returns_status(void **state) {
  (void)state;
  px_mat4_t t = px_mat4_identity();
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, 90 * DEG, 1, 1.5, 1, 0, &t), PX_EGRAZING);
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, (90 - 1e-12) * DEG, 1, 1.5, 1, 0, &t),
                   PX_EGRAZING);
  assert_int_equal(px_element_matrix(PX_EVENT_REFLECT, 90 * DEG, 1, 1, 1, 0, &t), PX_EGRAZING);
  assert_true(t.m[0][0] == 1.0 && t.m[0][1] == 0.0); /* untouched */
  px_mat4_t g = refract(89.9, 1.0, 1.5, 1e-3);       /* close to grazing: finite */
  assert_true(fabs(g.m[2][0]) > 1e3);
}

static void total_internal_reflection_returns_status(void **state) {
  (void)state;
  px_mat4_t t = px_mat4_identity();
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, 45 * DEG, 1.5, 1.0, 1, 0, &t), PX_ETIR);
  double crit = asin(1.0 / 1.5);
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, crit + 1e-9, 1.5, 1.0, 1, 0, &t), PX_ETIR);
  assert_true(t.m[0][0] == 1.0);
}

static void near_critical_angle_is_finite_or_refused(void **state) {
  (void)state;
  double crit = asin(1.0 / 1.5) / DEG;
  px_mat4_t t = refract(crit - 1e-3, 1.5, 1.0, 0.5); /* cos(theta') ~ 4e-3: finite, large */
  assert_true(fabs(t.m[2][2]) > 1e2);
  px_mat4_t u;
  /* cos(theta') ~ 1e-4: cos^2 theta' = (1 - eta s)(1 + eta s) carries the rounding of s
   * (~4e-16) divided by 1e-8, more than PX_ACCURACY: refused, not returned inaccurate */
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, (crit - 1e-6) * DEG, 1.5, 1.0, 0.5, 0, &u),
                   PX_EILLCOND);
  px_status_t s = px_element_matrix(PX_EVENT_REFRACT, asin(1.0 / 1.5), 1.5, 1.0, 0.5, 0, &u);
  assert_true(s == PX_EGRAZING || s == PX_ETIR); /* cos(theta') = 0 up to rounding */
}

static void flat_surface_has_no_power(void **state) {
  (void)state;
  px_mat4_t t = refract(40, 1.33, 1.0, INFINITY);
  for (int i = 2; i < 4; i++)
    for (int j = 0; j < 2; j++)
      assert_true(t.m[i][j] == 0.0);
}

static void extreme_radii_scale_as_one_over_r(void **state) {
  (void)state;
  static const double r[] = {1e-6, -1e-6, 1e6, -1e6};
  px_mat4_t one = refract(20, 1.0, 2.42, 1.0);
  for (int k = 0; k < 4; k++) {
    px_mat4_t t = refract(20, 1.0, 2.42, r[k]);
    assert_close(t.m[2][0] * r[k], one.m[2][0], 1e-14, 0);
    assert_close(t.m[3][1] * r[k], one.m[3][1], 1e-14, 0);
  }
}

static void invalid_parameters_are_rejected(void **state) {
  (void)state;
  px_mat4_t t;
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, 0.1, 1, 1.5, 0.0, 0, &t), PX_EINVAL);
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, NAN, 1, 1.5, 1, 0, &t), PX_EINVAL);
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, 0.1, -1, 1.5, 1, 0, &t), PX_EINVAL);
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, 0.1, 1, 0, 1, 0, &t), PX_EINVAL);
  assert_int_equal(px_element_matrix(PX_EVENT_REFRACT, -0.1, 1, 1.5, 1, 0, &t), PX_EINVAL);
}

static void frames_must_match_the_rays(void **state) {
  (void)state;
  px_interface_t ifc;
  px_frame_t in, out;
  px_mat4_t t;
  assert_int_equal(px_interface_canonical(0.5, 1.0, 1.0, 1.5, &ifc), PX_OK);
  assert_int_equal(px_interface_frames(&ifc, PX_EVENT_REFRACT, &in, &out), PX_OK);
  assert_int_equal(px_interface_matrix(&ifc, PX_EVENT_REFRACT, out, in, 0, &t), PX_EINVAL);
}

/* Eq. (2) verbatim: B = 1 (identity), C = +h Theta'^-1 Q Theta^-1, D with Theta'^-1 */
static void printed_variant_is_verbatim(void **state) {
  (void)state;
  px_mat4_t c = refract(30, 1.0, 1.5, 2.0), p;
  assert_int_equal(
      px_element_matrix(PX_EVENT_REFRACT, 30 * DEG, 1.0, 1.5, 2.0, PX_VARIANT_PRINTED, &p), PX_OK);
  assert_true(p.m[0][2] == 1.0 && p.m[1][3] == 1.0);
  assert_close(p.m[2][0], -c.m[2][0], 1e-15, 0);
  assert_close(p.m[3][3], c.m[3][3], 1e-15, 0);
}

/* with frames rotated about the rays, Theta' is not symmetric and Theta'^-t != Theta'^-1 */
static void rotated_frames_transform_by_rotation(void **state) {
  (void)state;
  px_interface_t ifc;
  px_frame_t in, out;
  px_mat4_t t0, t;
  assert_int_equal(px_interface_canonical(0.6, -2.0, 1.33, 1.0, &ifc), PX_OK);
  assert_int_equal(px_interface_frames(&ifc, PX_EVENT_REFRACT, &in, &out), PX_OK);
  assert_int_equal(px_interface_matrix(&ifc, PX_EVENT_REFRACT, in, out, 0, &t0), PX_OK);
  double a = 0.4, b = -1.1;
  assert_int_equal(px_interface_matrix(&ifc, PX_EVENT_REFRACT, px_frame_rotate(in, a),
                                       px_frame_rotate(out, b), 0, &t),
                   PX_OK);
  /* coordinates in a frame rotated by phi are R(-phi) times the old ones */
  px_mat2_t ra = px_mat2(cos(a), -sin(a), sin(a), cos(a));
  px_mat2_t rb = px_mat2(cos(b), sin(b), -sin(b), cos(b));
  px_mat4_t pin = px_mat4_blocks(ra, px_mat2_zero(), px_mat2_zero(), ra);
  px_mat4_t pout = px_mat4_blocks(rb, px_mat2_zero(), px_mat2_zero(), rb);
  px_mat4_t e = px_mat4_mul(pout, px_mat4_mul(t0, pin));
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      assert_close(t.m[i][j], e.m[i][j], 1e-13, 1e-13);
}

static void cascade_partial_products_compose(void **state) {
  (void)state;
  px_element_t buf[5];
  px_cascade_t c;
  px_cascade_init(&c, buf, 5);
  px_interface_t ifc;
  px_frame_t in, out;
  assert_int_equal(px_interface_canonical(0.3, 1.5, 1.0, 1.5, &ifc), PX_OK);
  px_interface_frames(&ifc, PX_EVENT_REFRACT, &in, &out);
  assert_int_equal(px_cascade_push_transfer(&c, 2.0, in), PX_OK);
  assert_int_equal(px_cascade_push_interface(&c, &ifc, PX_EVENT_REFRACT, in, out, 0), PX_OK);
  assert_int_equal(px_cascade_push_transfer(&c, 0.7, out), PX_OK);
  px_mat4_t full = px_cascade_product(&c);
  for (size_t i = 1; i <= c.n; i++) {
    px_mat4_t p = px_mat4_mul(px_cascade_after(&c, i),
                              px_mat4_mul(c.elem[i - 1].t, px_cascade_before(&c, i)));
    for (int r = 0; r < 4; r++)
      for (int k = 0; k < 4; k++)
        assert_close(p.m[r][k], full.m[r][k], 1e-15, 1e-15);
  }
  px_cascade_init(&c, buf, 1);
  assert_int_equal(px_cascade_push_transfer(&c, 1.0, in), PX_OK);
  assert_int_equal(px_cascade_push_transfer(&c, 1.0, in), PX_ECAPACITY);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(refraction_matches_closed_form),
      cmocka_unit_test(surface_focal_length),
      cmocka_unit_test(concave_mirror_focal_length),
      cmocka_unit_test(normal_incidence_is_finite_and_continuous),
      cmocka_unit_test(grazing_incidence_returns_status),
      cmocka_unit_test(total_internal_reflection_returns_status),
      cmocka_unit_test(near_critical_angle_is_finite_or_refused),
      cmocka_unit_test(flat_surface_has_no_power),
      cmocka_unit_test(extreme_radii_scale_as_one_over_r),
      cmocka_unit_test(invalid_parameters_are_rejected),
      cmocka_unit_test(frames_must_match_the_rays),
      cmocka_unit_test(printed_variant_is_verbatim),
      cmocka_unit_test(rotated_frames_transform_by_rotation),
      cmocka_unit_test(cascade_partial_products_compose),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
