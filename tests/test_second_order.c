/* test_second_order.c -- the second-order tensor t(2) of the exact map (section 3.2) three ways:
 * forward-mode jets (ex_map_jet), __float128 second differences (ex_hessian_q) and, for single
 * elements, the analytic term of libparaxial (px_element_second_order with the quadric's cubic
 * term). Plus the case the paper's estimate cannot see: a sphere met through its centre, where
 * every second-order term vanishes but the third-order error does not. */
#include <math.h>
#include <stdlib.h>

#include "cmocka_main.h"
#include "validation/systems.h"

/* entry of t(2) made dimensionless with the system's length L: position inputs weighted by L,
 * position outputs by 1/L (as the matrices' check does for T). */
static double scaled(double h[4][4][4], int i, int j, int k, double L) {
  double s = (i < 2 ? 1.0 / L : 1.0) * (j < 2 ? L : 1.0) * (k < 2 ? L : 1.0);
  return h[i][j][k] * s;
}

static double tensor_diff(double a[4][4][4], double b[4][4][4], double L, double *norm) {
  double d = 0.0, n = 0.0;
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      for (int k = 0; k < 4; k++) {
        d = fmax(d, fabs(scaled(a, i, j, k, L) - scaled(b, i, j, k, L)));
        n = fmax(n, fabs(scaled(b, i, j, k, L)));
      }
  *norm = n;
  return d;
}

/* Jets against quad differences on the whole quick sweep (188 systems: every family, angles
 * to 0.001 deg of the critical angle, radii 1e-3..1e3). Tolerance 1e-7 of the tensor's scale:
 * the jets are exact up to double rounding amplified by the conditioning of the map (the
 * matrices' own check reaches 5e-14); the differences are good to ~1e-13 except within 0.01 deg
 * of the critical angle, where the fourth derivatives grow like 1/cos^7 theta'. */
static void jets_agree_with_quad_differences_on_quick_sweep(void **state) {
  (void)state;
  size_t n = 0, checked = 0;
  val_system_t *sw = val_sweep_build(1, 1, &n);
  assert_non_null(sw);
  double worst = 0.0;
  for (size_t s = 0; s < n; s++) {
    if (sw[s].expect_tir)
      continue;
    ex_system_t sys = val_system_bind(&sw[s]);
    ex_axial_t ax;
    assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
    double hj[4][4][4], hq[4][4][4], jac[4][4], zero[4] = {0, 0, 0, 0};
    assert_int_equal(ex_map_jet(&sys, &ax, zero, NULL, jac, hj), PX_OK);
    assert_int_equal(ex_hessian_q(&sys, &ax, sw[s].length, hq), PX_OK);
    double norm, d = tensor_diff(hj, hq, sw[s].length, &norm);
    double rel = d / fmax(norm, 1.0);        /* scaled entries are O(1) where they do not vanish */
    if (sw[s].family == VAL_FAMILY_TRANSFER) /* straight lines: t(2) = 0 exactly */
      assert_true(norm == 0.0 || norm < 1e-12);
    else if (!(rel <= 1e-7))
      fail_msg("system %zu (%s): jets vs quad differences %.3e of %.3e", s, sw[s].label, d, norm);
    worst = fmax(worst, rel);
    /* the jets' Jacobian is the exact one: compare with the quad Jacobian (matrices issue) */
    px_mat4_t jq;
    assert_int_equal(ex_jacobian_q(&sys, &ax, sw[s].length, &jq), PX_OK);
    for (int i = 0; i < 4; i++)
      for (int j = 0; j < 4; j++)
        assert_close(jac[i][j], jq.m[i][j], 1e-7, 1e-7 * px_mat4_maxabs(jq));
    checked++;
  }
  assert_true(checked > 150);
  print_message("worst scaled relative difference %.3e over %zu systems\n", worst, checked);
  free(sw);
}

/* The analytic element term (libparaxial) against the jets, for every single element of the
 * quick sweep, ellipsoids included (cubic term from ex_quadric_cubic). */
static void analytic_element_term_matches_jets(void **state) {
  (void)state;
  size_t n = 0, checked = 0, with_cubic = 0;
  val_system_t *sw = val_sweep_build(1, 1, &n);
  assert_non_null(sw);
  for (size_t s = 0; s < n; s++) {
    const val_system_t *v = &sw[s];
    if (v->expect_tir || v->family == VAL_FAMILY_TRANSFER || v->family == VAL_FAMILY_CASCADE)
      continue;
    ex_system_t sys = val_system_bind(v);
    ex_axial_t ax;
    assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
    px_element_t buf[4];
    px_cascade_t c;
    assert_int_equal(ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 4, &c), PX_OK);
    /* the interface element; a transfer of rounding length (|t| ~ 1e-17 L) may precede it */
    size_t ie = 0;
    for (size_t i = 0; i < c.n; i++)
      if (buf[i].kind == PX_ELEMENT_TRANSFER)
        assert_true(fabs(buf[i].distance) < 1e-12 * v->length);
      else
        ie = i;
    double cubic[4];
    assert_int_equal(ex_quadric_cubic(&v->stage[0].surface, ax.hit[0], &ax.ifc[0], cubic), PX_OK);
    with_cubic += px_d3m(cubic) * v->length * v->length > 1e-6;
    double h[4][4][4], zero[4] = {0, 0, 0, 0};
    assert_int_equal(ex_map_jet(&sys, &ax, zero, NULL, NULL, h), PX_OK);
    /* psi = e_j + e_k: Delta psi = 1/2 (H_jj + H_kk) + H_jk */
    for (int j = 0; j < 4; j++)
      for (int k = j; k < 4; k++) {
        px_ray4_t psi = {{0, 0, 0, 0}}, d;
        double sj = j < 2 ? v->length : 1.0, sk = k < 2 ? v->length : 1.0;
        psi.v[j] += sj;
        psi.v[k] += sk;
        assert_int_equal(px_element_second_order(&buf[ie], cubic, psi, &d), PX_OK);
        double scale = 0.0;
        for (int i = 0; i < 4; i++) {
          double ref =
              j == k ? 2.0 * h[i][j][j] * sj * sj
                     : 0.5 * (h[i][j][j] * sj * sj + h[i][k][k] * sk * sk) + h[i][j][k] * sj * sk;
          double o = i < 2 ? 1.0 / v->length : 1.0;
          scale = fmax(scale, fabs(ref * o));
          if (!(fabs(d.v[i] - ref) * o <= 1e-8 * (1.0 + scale) + 1e-8 * fabs(ref * o)))
            fail_msg("system %zu (%s) psi e%d+e%d component %d: analytic %.12g jets %.12g", s,
                     v->label, j, k, i, d.v[i], ref);
        }
      }
    checked++;
  }
  assert_true(checked > 100);
  assert_true(with_cubic > 5); /* ellipsoids exercise the cubic term */
  free(sw);
}

/* pinhole -> glass sphere aimed at the centre -> plane: t(2) = 0 (the map is odd by symmetry),
 * yet the exact error of the linear map grows like xi^3 (spherical aberration). */
static void sphere_through_centre_has_third_order_error_only(void **state) {
  (void)state;
  ex_quadric_t sph = ex_quadric_sphere(px_vec3(0, 0, 0), 1.0);
  ex_stage_t st[2] = {{sph, PX_EVENT_REFRACT, 1.5, 0}, {sph, PX_EVENT_REFRACT, 1.0, 0}};
  px_frame_t f;
  assert_int_equal(px_frame_from_z(px_vec3(0, 0, 1), px_vec3(0, 1, 0), &f), PX_OK);
  ex_system_t sys = {px_vec3(0, 0, -5), f, 1.0, st, 2, 4.0, 0.0};
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  double h[4][4][4], jac[4][4], zero[4] = {0, 0, 0, 0};
  assert_int_equal(ex_map_jet(&sys, &ax, zero, NULL, jac, h), PX_OK);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      for (int k = 0; k < 4; k++)
        assert_close(h[i][j][k], 0.0, 0, 1e-12);
  double err[2];
  for (int m = 0; m < 2; m++) {
    double xi = m == 0 ? 1e-2 : 2e-2, psi[4] = {0, 0, xi, 0}, out[4];
    assert_int_equal(ex_map(&sys, &ax, psi, out), PX_OK);
    err[m] = fabs(out[0] - jac[0][2] * xi);
  }
  assert_true(err[0] > 1e-7);                  /* a real error ... */
  assert_close(err[1] / err[0], 8.0, 0.01, 0); /* ... of third order */
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(jets_agree_with_quad_differences_on_quick_sweep),
      cmocka_unit_test(analytic_element_term_matches_jets),
      cmocka_unit_test(sphere_through_centre_has_third_order_error_only),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
