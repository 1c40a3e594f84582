/* test_exact.c -- the exact tracer (reference/): quadric geometry, misses, TIR, the exact map
 * and its Jacobian in double and __float128. */
#include <math.h>

#include "cmocka_main.h"
#include "exact/trace.h"

static void sphere_curvature_signs(void **state) {
  (void)state;
  ex_quadric_t q = ex_quadric_sphere(px_vec3(0, 0, 2.0), 2.0);
  px_interface_t in, out;
  /* entering the ball from outside (from -z): centre on the far side, Q = +I/R */
  assert_int_equal(ex_quadric_interface(&q, px_vec3(0, 0, 0), px_vec3(0.1, 0, 1), px_vec3(0, 1, 0),
                                        1.0, 1.5, &in),
                   PX_OK);
  assert_close(in.q.m[0][0], 0.5, 1e-15, 0);
  assert_close(in.q.m[1][1], 0.5, 1e-15, 0);
  assert_true(px_vec3_dot(in.nu, in.s) > 0);
  /* leaving it from inside (towards -z): Q = -I/R */
  assert_int_equal(ex_quadric_interface(&q, px_vec3(0, 0, 0), px_vec3(0.1, 0, -1), px_vec3(0, 1, 0),
                                        1.5, 1.0, &out),
                   PX_OK);
  assert_close(out.q.m[0][0], -0.5, 1e-15, 0);
}

static void oblique_cylinder_has_nondiagonal_q(void **state) {
  (void)state;
  double beta = 0.5, r = 3.0;
  ex_quadric_t q = ex_quadric_cylinder(px_vec3(0, 0, r), px_vec3(cos(beta), sin(beta), 0), r);
  px_interface_t ifc;
  assert_int_equal(ex_quadric_interface(&q, px_vec3(0, 0, 0), px_vec3(0.3, 0, 1), px_vec3(0, 1, 0),
                                        1.0, 1.5, &ifc),
                   PX_OK);
  assert_true(fabs(ifc.q.m[0][1]) > 0.05);
  assert_close(ifc.q.m[0][1], ifc.q.m[1][0], 1e-14, 1e-14);
  /* eigenvalues 1/r and 0: trace 1/r, determinant 0 */
  assert_close(ifc.q.m[0][0] + ifc.q.m[1][1], 1.0 / r, 1e-14, 0);
  assert_close(px_mat2_det(ifc.q), 0.0, 0, 1e-15);
}

static ex_system_t one_surface(const ex_stage_t *st, double th, double n1) {
  px_frame_t f;
  px_vec3_t s = px_vec3(sin(th), 0, cos(th));
  px_frame_from_z(s, px_vec3(0, 1, 0), &f);
  return (ex_system_t){px_vec3(0, 0, 0), f, n1, st, 1, 0.0, 0.0};
}

static void missing_the_surface_is_reported(void **state) {
  (void)state;
  ex_stage_t st = {ex_quadric_sphere(px_vec3(5, 5, 5), 1.0), PX_EVENT_REFRACT, 1.5, 0};
  ex_system_t sys = one_surface(&st, 0.0, 1.0);
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_EMISS);
}

static void axial_ray_maps_to_zero(void **state) {
  (void)state;
  ex_stage_t st = {ex_quadric_sphere(px_vec3(0, 0, -1.0), 1.0), PX_EVENT_REFRACT, 1.0, 1};
  ex_system_t sys = one_surface(&st, 0.4, 1.5);
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  double z[4] = {0, 0, 0, 0}, out[4];
  assert_int_equal(ex_map(&sys, &ax, z, out), PX_OK);
  for (int i = 0; i < 4; i++)
    assert_close(out[i], 0.0, 0, 1e-15);
}

static void tir_of_a_paraxial_ray_is_reported(void **state) {
  (void)state;
  double crit = asin(1.0 / 1.5);
  ex_stage_t st = {ex_quadric_plane(px_vec3(0, 0, 0), px_vec3(0, 0, 1)), PX_EVENT_REFRACT, 1.0, 1};
  ex_system_t sys = one_surface(&st, crit - 1e-4, 1.5);
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  double psi[4] = {0, 0, 2e-3, 0}, out[4];
  assert_int_equal(ex_map(&sys, &ax, psi, out), PX_ETIR);
  psi[2] = -2e-3;
  assert_int_equal(ex_map(&sys, &ax, psi, out), PX_OK);
}

static void quad_jacobian_matches_matrix_on_ellipsoid(void **state) {
  (void)state;
  const px_vec3_t axes[3] = {px_vec3(1, 0, 0), px_vec3(0, 1, 0), px_vec3(0, 0, 1)};
  ex_quadric_t q = ex_quadric_ellipsoid(px_vec3(0, 0, 0), axes, 1.0, 2.0, 0.5);
  px_vec3_t o = px_vec3(0.6, 0.8 * 2.0 * 0.6, 0.5 * sqrt(1 - 0.36 - 0.64 * 0.36));
  px_vec3_t inward;
  px_vec3_normalize(px_vec3_scale(ex_quadric_half_gradient(&q, o), -1), &inward);
  px_vec3_t s;
  px_vec3_normalize(px_vec3_add(inward, px_vec3(0.3, -0.2, 0.1)), &s);
  px_frame_t f;
  px_frame_from_z(s, px_vec3(1, 2, 3), &f);
  ex_stage_t st = {q, PX_EVENT_REFRACT, 1.5, 1};
  ex_system_t sys = {o, f, 1.0, &st, 1, 0.0, 0.3};
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_OK);
  px_element_t buf[4];
  px_cascade_t c;
  assert_int_equal(ex_axial_cascade(&sys, &ax, PX_VARIANT_CORRECTED, buf, 4, &c), PX_OK);
  px_mat4_t t = px_cascade_product(&c), jq, jd;
  assert_int_equal(ex_jacobian_q(&sys, &ax, 0.5, &jq), PX_OK);
  assert_int_equal(ex_jacobian(&sys, &ax, 0.5, &jd), PX_OK);
  double norm = px_mat4_maxabs(jq);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++) {
      assert_close(t.m[i][j], jq.m[i][j], 0, 1e-10 * norm);
      assert_close(jd.m[i][j], jq.m[i][j], 0, 1e-6 * norm); /* double differences: ~1e-8 */
    }
}

static void too_many_stages_rejected(void **state) {
  (void)state;
  ex_stage_t st[EX_MAX_STAGES + 1] = {0};
  ex_system_t sys = one_surface(st, 0.0, 1.0);
  sys.nstage = EX_MAX_STAGES + 1;
  ex_axial_t ax;
  assert_int_equal(ex_trace_axial(&sys, &ax), PX_EINVAL);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sphere_curvature_signs),
      cmocka_unit_test(oblique_cylinder_has_nondiagonal_q),
      cmocka_unit_test(missing_the_surface_is_reported),
      cmocka_unit_test(axial_ray_maps_to_zero),
      cmocka_unit_test(tir_of_a_paraxial_ray_is_reported),
      cmocka_unit_test(quad_jacobian_matches_matrix_on_ellipsoid),
      cmocka_unit_test(too_many_stages_rejected),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
