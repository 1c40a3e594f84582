/* test_bounds.c -- error estimation (section 3, Appendix A-1 and (3)): the element coefficients
 * in both variants, their physical dimensions, the analytic second-order term they bound, the
 * general cascade form, the tolerance (Eq. 3), the acceptance test (Eq. 5) and the spread limit
 * (Eq. 6) with its third-order and cap regimes. The exact-tracing checks are in
 * test_second_order.c. */
#include <math.h>

#include "cmocka_main.h"
#include "paraxial/paraxial.h"

#define DEG (M_PI / 180.0)

static px_coeffs_t coeffs(px_event_t ev, double th_deg, double n1, double n2, double r, double d3m,
                          px_variant_t v) {
  px_element_geom_t g = {ev, th_deg * DEG, n1, n2, r, d3m};
  px_coeffs_t k;
  assert_int_equal(px_error_coeffs(&g, v, &k), PX_OK);
  return k;
}

/* The printed b of A-1 equals the derived one, S (1 - eta^2) / (c^2 c'): an identity between two
 * different-looking closed forms, so agreement to rounding is a real check of both. */
static void printed_b_equals_derived_b(void **state) {
  (void)state;
  for (double th = 0; th < 80; th += 7.5) {
    px_coeffs_t p = coeffs(PX_EVENT_REFRACT, th, 1.0, 1.5, 2.0, 0, PX_VARIANT_PRINTED);
    px_coeffs_t c = coeffs(PX_EVENT_REFRACT, th, 1.0, 1.5, 2.0, 0, PX_VARIANT_CORRECTED);
    assert_close(p.b, c.b, 1e-13, 1e-15);
    double s = sin(th * DEG), eta = 1 / 1.5, cp = sqrt(1 - eta * eta * s * s);
    assert_close(c.b, s * (1 - eta * eta) / (cos(th * DEG) * cos(th * DEG) * cp), 1e-14, 1e-15);
  }
}

/* f: the printed form carries one factor n/n' too many (docs/errata.md) */
static void printed_f_has_extra_index_ratio(void **state) {
  (void)state;
  px_coeffs_t p = coeffs(PX_EVENT_REFRACT, 40, 1.0, 1.5, 2.0, 0, PX_VARIANT_PRINTED);
  px_coeffs_t c = coeffs(PX_EVENT_REFRACT, 40, 1.0, 1.5, 2.0, 0, PX_VARIANT_CORRECTED);
  assert_close(p.f, c.f / 1.5, 1e-14, 0);
  double s = sin(40 * DEG), eta = 1 / 1.5, cp = sqrt(1 - eta * eta * s * s);
  assert_close(c.f, 0.5 * eta * s * (1 - eta * eta) / (cp * cp * cp), 1e-14, 0);
}

/* Dimensions: scaling the surface by L scales a, e by 1/L and d by 1/L^2 (b, f unchanged). The
 * printed d scales as 1/L^3: the R^3 erratum. Powers of two make the ratios exact. */
static void coefficients_have_physical_dimensions(void **state) {
  (void)state;
  for (int v = 0; v < 2; v++) {
    px_coeffs_t k1 = coeffs(PX_EVENT_REFRACT, 35, 1.0, 1.5, 1.0, 0, (px_variant_t)v);
    px_coeffs_t k4 = coeffs(PX_EVENT_REFRACT, 35, 1.0, 1.5, 4.0, 0, (px_variant_t)v);
    assert_close(k4.a, k1.a / 4, 1e-15, 0);
    assert_close(k4.b, k1.b, 1e-15, 0);
    assert_close(k4.e, k1.e / 4, 1e-15, 0);
    assert_close(k4.f, k1.f, 1e-15, 0);
    assert_close(k4.d, k1.d / (v == PX_VARIANT_PRINTED ? 64 : 16), 1e-15, 0);
  }
}

/* The printed A-1 read verbatim for a mirror (theta' = pi - theta: cos theta' < 0) gives a
 * negative a: the printed form is not a magnitude there (docs/errata.md). */
static void printed_mirror_a_is_negative(void **state) {
  (void)state;
  px_coeffs_t p = coeffs(PX_EVENT_REFLECT, 30, 1.0, 1.0, 2.0, 0, PX_VARIANT_PRINTED);
  px_coeffs_t c = coeffs(PX_EVENT_REFLECT, 30, 1.0, 1.0, 2.0, 0, PX_VARIANT_CORRECTED);
  assert_true(p.a < 0);
  assert_true(c.a > 0 && c.d > 0 && c.e > 0);
  assert_close(c.b, 0.0, 0, 1e-16); /* a mirror has no x-xi term in Delta x */
  assert_close(c.f, 0.0, 0, 1e-16); /* nor a xi^2 term in Delta xi */
}

static void transfer_and_sphere_at_normal_incidence_have_no_error(void **state) {
  (void)state;
  px_coeffs_t c = coeffs(PX_EVENT_REFRACT, 0, 1.0, 1.5, 0.3, 0, PX_VARIANT_CORRECTED);
  assert_true(c.a == 0 && c.b == 0 && c.c == 0 && c.d == 0 && c.e == 0 && c.f == 0);
  px_element_t buf[1];
  px_cascade_t cas;
  px_frame_t f;
  assert_int_equal(px_frame_from_z(px_vec3(0, 0, 1), px_vec3(0, 1, 0), &f), PX_OK);
  px_cascade_init(&cas, buf, 1);
  assert_int_equal(px_cascade_push_transfer(&cas, 3.0, f), PX_OK);
  px_pencil_t k;
  assert_int_equal(px_pencil_constants(&cas, NULL, PX_VARIANT_CORRECTED, &k), PX_OK);
  assert_true(k.a == 0 && k.b == 0 && k.c == 0 && k.d == 0 && k.e == 0 && k.f == 0);
  px_ray4_t d;
  assert_int_equal(px_element_second_order(&buf[0], NULL, (px_ray4_t){{1, 2, .3, .1}}, &d), PX_OK);
  assert_true(d.v[0] == 0 && d.v[1] == 0 && d.v[2] == 0 && d.v[3] == 0);
}

static void bad_parameters_return_status(void **state) {
  (void)state;
  px_coeffs_t k = {7, 7, 7, 7, 7, 7};
  px_element_geom_t g = {PX_EVENT_REFRACT, 50 * DEG, 1.5, 1.0, 1.0, 0};
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_CORRECTED, &k), PX_ETIR);
  g.theta = M_PI / 2; /* grazing, as px_element_matrix reports it */
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_CORRECTED, &k), PX_EGRAZING);
  g.theta = M_PI / 2 + 1e-9;
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_CORRECTED, &k), PX_EINVAL);
  g = (px_element_geom_t){PX_EVENT_REFRACT, 0.1, 1.0, 1.5, 0.0, 0};
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_PRINTED, &k), PX_EINVAL);
  g.radius = NAN;
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_PRINTED, &k), PX_EINVAL);
  g.radius = 1.0;
  g.d3m = -1;
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_PRINTED, &k), PX_EINVAL);
  g.d3m = 0;
  g.n2 = 0;
  assert_int_equal(px_error_coeffs(&g, PX_VARIANT_PRINTED, &k), PX_EINVAL);
  assert_true(k.a == 7); /* untouched on error */
  /* the critical angle itself: cos theta' = 0 is grazing exit */
  g = (px_element_geom_t){PX_EVENT_REFRACT, asin(1 / 1.5), 1.5, 1.0, 1.0, 0};
  px_status_t st = px_error_coeffs(&g, PX_VARIANT_CORRECTED, &k);
  assert_true(st == PX_EGRAZING || st == PX_ETIR || (st == PX_OK && isfinite(k.f)));
}

/* A refraction or reflection element on a quadric-like surface with curvature q (in (u1, u2))
 * at incidence theta, in frames rotated by phi_in / phi_out about the rays. */
static px_element_t element(px_event_t ev, double th, double n1, double n2, px_mat2_t q,
                            double phi_in, double phi_out) {
  px_interface_t ifc;
  px_frame_t in, out;
  assert_int_equal(px_interface_make(px_vec3(sin(th), 0, cos(th)), px_vec3(0, 0, 1),
                                     px_vec3(0, 1, 0), q, NULL, n1, n2, &ifc),
                   PX_OK);
  assert_int_equal(px_interface_frames(&ifc, ev, &in, &out), PX_OK);
  px_element_t buf[1];
  px_cascade_t c;
  px_cascade_init(&c, buf, 1);
  assert_int_equal(px_cascade_push_interface(&c, &ifc, ev, px_frame_rotate(in, phi_in),
                                             px_frame_rotate(out, phi_out), PX_VARIANT_CORRECTED),
                   PX_OK);
  return buf[0];
}

/* The corrected coefficients bound the analytic second-order term in every direction, for
 * general Q (a saddle, non-diagonal in the frames), a cubic term, rotated frames, refraction
 * both ways and reflection. Directions on a 24 x 24 x 6 grid of (angle x, angle xi, ratio). */
static void corrected_coefficients_bound_the_second_order_term(void **state) {
  (void)state;
  const double cubic[4] = {0.3, -0.2, 0.15, 0.4};
  const px_mat2_t q = px_mat2(0.5, 0.35, 0.35, -0.8);
  struct {
    px_event_t ev;
    double th, n1, n2;
  } cases[] = {{PX_EVENT_REFRACT, 0.3, 1.0, 1.5}, {PX_EVENT_REFRACT, 1.2, 1.0, 2.42},
               {PX_EVENT_REFRACT, 0.6, 1.5, 1.0}, {PX_EVENT_REFRACT, 0.0, 1.33, 1.0},
               {PX_EVENT_REFLECT, 0.9, 1.0, 1.0}, {PX_EVENT_REFLECT, 1.45, 1.0, 1.0}};
  for (size_t n = 0; n < sizeof cases / sizeof cases[0]; n++) {
    px_element_t e = element(cases[n].ev, cases[n].th, cases[n].n1, cases[n].n2, q, 0.4, -1.1);
    px_element_geom_t g;
    assert_int_equal(px_element_geom(&e, px_d3m(cubic), &g), PX_OK);
    assert_close(g.radius, 1.0 / px_mat2_norm2(q), 1e-15, 0);
    px_coeffs_t k;
    assert_int_equal(px_error_coeffs(&g, PX_VARIANT_CORRECTED, &k), PX_OK);
    double worst_x = 0, worst_xi = 0;
    for (int i = 0; i < 24; i++)
      for (int j = 0; j < 24; j++)
        for (int r = 0; r < 6; r++) {
          double x0 = r < 5 ? 1.0 : 0.0, xi0 = r * 0.2, a = i * M_PI / 12, b = j * M_PI / 12;
          px_ray4_t psi = {{x0 * cos(a), x0 * sin(a), xi0 * cos(b), xi0 * sin(b)}}, d;
          assert_int_equal(px_element_second_order(&e, cubic, psi, &d), PX_OK);
          px_pencil_t pk = k;
          worst_x = fmax(worst_x, hypot(d.v[0], d.v[1]) / px_pencil_ex(&pk, x0, xi0));
          worst_xi = fmax(worst_xi, hypot(d.v[2], d.v[3]) / px_pencil_exi(&pk, x0, xi0));
        }
    /* a bound: the ratio never exceeds 1 (beyond rounding); and it is not vacuous: some
     * direction reaches a fair fraction of it */
    assert_true(worst_x <= 1 + 1e-12);
    assert_true(worst_xi <= 1 + 1e-12);
    assert_true(worst_xi > 0.2);
  }
}

/* For a sphere at oblique incidence, a and b are attained with x (and xi) along x1. */
static void corrected_a_b_f_attained_on_a_sphere(void **state) {
  (void)state;
  double th = 0.5, n1 = 1.0, n2 = 1.5, r = 2.0;
  px_element_t e = element(PX_EVENT_REFRACT, th, n1, n2, px_mat2_diag(1 / r, 1 / r), 0, 0);
  px_coeffs_t k = coeffs(PX_EVENT_REFRACT, th / DEG, n1, n2, r, 0, PX_VARIANT_CORRECTED);
  px_ray4_t d, dxx, dxi;
  assert_int_equal(px_element_second_order(&e, NULL, (px_ray4_t){{1, 0, 0, 0}}, &dxx), PX_OK);
  assert_close(hypot(dxx.v[0], dxx.v[1]), k.a, 1e-14, 0);
  assert_int_equal(px_element_second_order(&e, NULL, (px_ray4_t){{0, 0, 1, 0}}, &dxi), PX_OK);
  assert_close(hypot(dxi.v[2], dxi.v[3]), k.f, 1e-14, 0);
  assert_close(hypot(dxi.v[0], dxi.v[1]), 0.0, 0, 1e-16); /* c = 0 */
  /* the bilinear part: Delta(x + xi) - Delta(x) - Delta(xi) */
  assert_int_equal(px_element_second_order(&e, NULL, (px_ray4_t){{1, 0, 1, 0}}, &d), PX_OK);
  assert_close(hypot(d.v[0] - dxx.v[0] - dxi.v[0], d.v[1] - dxx.v[1] - dxi.v[1]), k.b, 1e-13, 0);
}

/* One element alone: T^a = T^b = 1, so lambda = mu = (1, 0, 0, 1) and A-F = a-f. A transfer d
 * before it: T^b = [[1, d], [0, 1]], mu = (1, d, 0, 1), so C = a d^2 + b d + c. */
static void cascade_form_reduces_to_element_and_transfer(void **state) {
  (void)state;
  double th = 0.4, r = 1.5, dist = 3.0;
  px_interface_t ifc;
  px_frame_t in, out;
  assert_int_equal(px_interface_canonical(th, r, 1.0, 1.5, &ifc), PX_OK);
  assert_int_equal(px_interface_frames(&ifc, PX_EVENT_REFRACT, &in, &out), PX_OK);
  px_element_t buf[3];
  px_cascade_t c;
  px_cascade_init(&c, buf, 3);
  assert_int_equal(
      px_cascade_push_interface(&c, &ifc, PX_EVENT_REFRACT, in, out, PX_VARIANT_CORRECTED), PX_OK);
  px_coeffs_t k = coeffs(PX_EVENT_REFRACT, th / DEG, 1.0, 1.5, r, 0, PX_VARIANT_CORRECTED);
  px_pencil_t p;
  assert_int_equal(px_pencil_constants(&c, NULL, PX_VARIANT_CORRECTED, &p), PX_OK);
  assert_close(p.a, k.a, 1e-15, 0);
  assert_close(p.b, k.b, 1e-15, 0);
  assert_close(p.d, k.d, 1e-15, 0);
  assert_close(p.e, k.e, 1e-15, 0);
  assert_close(p.f, k.f, 1e-15, 0);
  px_cascade_init(&c, buf, 3);
  assert_int_equal(px_cascade_push_transfer(&c, dist, in), PX_OK);
  assert_int_equal(
      px_cascade_push_interface(&c, &ifc, PX_EVENT_REFRACT, in, out, PX_VARIANT_CORRECTED), PX_OK);
  double lam[4], mu[4];
  assert_int_equal(px_cascade_weights(&c, 2, lam, mu), PX_OK);
  assert_close(mu[1], dist, 1e-15, 0);
  assert_close(lam[0], 1.0, 1e-15, 0);
  assert_close(lam[1], 0.0, 0, 0);
  assert_int_equal(px_cascade_weights(&c, 3, lam, mu), PX_EINVAL);
  assert_int_equal(px_pencil_constants(&c, NULL, PX_VARIANT_CORRECTED, &p), PX_OK);
  assert_close(p.c, k.a * dist * dist + k.b * dist + k.c, 1e-14, 0);
  assert_close(p.f, k.d * dist * dist + k.e * dist + k.f, 1e-14, 0);
}

static void tolerance_and_acceptance(void **state) {
  (void)state;
  px_mat4_t t = px_transfer_matrix(10.0);
  double tau;
  /* a direction interval of 1e-3 rad: the footprint at distance 10 is 1e-2, tau = rho * 1e-2 */
  assert_int_equal(px_tolerance(t, (px_ray4_t){{0, 0, 1e-3, 0}}, 0.5, &tau), PX_OK);
  assert_close(tau, 5e-3, 1e-15, 0);
  assert_int_equal(px_tolerance(t, (px_ray4_t){{3e-3, 0, 0, 4e-3}}, 1.0, &tau), PX_OK);
  assert_close(tau, hypot(3e-3, 4e-2), 1e-15, 0);
  assert_int_equal(px_tolerance(t, (px_ray4_t){{0, 0, 1e-3, 0}}, 0.0, &tau), PX_EINVAL);
  assert_int_equal(px_tolerance(t, (px_ray4_t){{0, 0, NAN, 0}}, 0.5, &tau), PX_EINVAL);
  px_pencil_t k = {1, 2, 3, 0, 0, 0};
  /* e_x = 0.25 + 0.25 + 0.1875, exact in binary: the test is at the boundary */
  assert_true(px_pencil_accept(&k, 0.5, 0.25, 0.6875));
  assert_false(px_pencil_accept(&k, 0.5, 0.25, nextafter(0.6875, 0)));
}

static void spread_limit_regimes(void **state) {
  (void)state;
  double xi;
  px_spread_regime_t why;
  /* Eq. (6): C xi^2 = tau */
  assert_int_equal(px_spread_limit(4.0, 0.0, 1e-4, 1.0, &xi, &why), PX_OK);
  assert_close(xi, 5e-3, 1e-14, 0);
  assert_int_equal(why, PX_SPREAD_SECOND_ORDER);
  /* C = 0 (axial ray through a sphere's centre): the third-order term decides */
  assert_int_equal(px_spread_limit(0.0, 8.0, 1e-6, 1.0, &xi, &why), PX_OK);
  assert_close(xi, 5e-3, 1e-13, 0);
  assert_int_equal(why, PX_SPREAD_THIRD_ORDER);
  /* both: the root of C xi^2 + k3 xi^3 = tau */
  assert_int_equal(px_spread_limit(1.0, 1.0, 2.0, 10.0, &xi, &why), PX_OK);
  assert_close(xi, 1.0, 1e-14, 0);
  /* nothing limits: the cap, finite, and said so */
  assert_int_equal(px_spread_limit(0.0, 0.0, 1e-6, 0.25, &xi, &why), PX_OK);
  assert_true(xi == 0.25 && why == PX_SPREAD_CAP);
  assert_int_equal(px_spread_limit(1e-300, 0.0, 1.0, 0.25, &xi, &why), PX_OK);
  assert_true(xi == 0.25 && why == PX_SPREAD_CAP);
  assert_int_equal(px_spread_limit(1.0, 0.0, 1.0, INFINITY, &xi, &why), PX_EINVAL);
  assert_int_equal(px_spread_limit(-1.0, 0.0, 1.0, 1.0, &xi, &why), PX_EINVAL);
  assert_int_equal(px_spread_limit(1.0, 0.0, 0.0, 1.0, &xi, &why), PX_EINVAL);
  assert_int_equal(px_spread_limit(1.0, NAN, 1.0, 1.0, &xi, NULL), PX_EINVAL);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(printed_b_equals_derived_b),
      cmocka_unit_test(printed_f_has_extra_index_ratio),
      cmocka_unit_test(coefficients_have_physical_dimensions),
      cmocka_unit_test(printed_mirror_a_is_negative),
      cmocka_unit_test(transfer_and_sphere_at_normal_incidence_have_no_error),
      cmocka_unit_test(bad_parameters_return_status),
      cmocka_unit_test(corrected_coefficients_bound_the_second_order_term),
      cmocka_unit_test(corrected_a_b_f_attained_on_a_sphere),
      cmocka_unit_test(cascade_form_reduces_to_element_and_transfer),
      cmocka_unit_test(tolerance_and_acceptance),
      cmocka_unit_test(spread_limit_regimes),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
