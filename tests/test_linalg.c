/* test_linalg.c -- 2x2 / 4x4 blocks and frames (libparaxial/linalg.h, frame.h). */
#include <math.h>

#include "cmocka_main.h"
#include "paraxial/paraxial.h"

static void inverse_of_rotation_is_transpose(void **state) {
  (void)state;
  px_mat2_t r = px_mat2(cos(0.3), -sin(0.3), sin(0.3), cos(0.3)), inv;
  assert_int_equal(px_mat2_inverse(r, &inv), PX_OK);
  px_mat2_t t = px_mat2_transpose(r);
  for (int i = 0; i < 2; i++)
    for (int j = 0; j < 2; j++)
      assert_close(inv.m[i][j], t.m[i][j], 1e-15, 1e-15);
}

static void singular_inverse_is_reported(void **state) {
  (void)state;
  px_mat2_t out = px_mat2(7, 7, 7, 7);
  assert_int_equal(px_mat2_inverse(px_mat2(1, 2, 2, 4), &out), PX_ESINGULAR);
  assert_true(out.m[0][0] == 7); /* untouched on error */
}

static void norm2_matches_singular_value(void **state) {
  (void)state;
  /* diag(3, -5) rotated: singular values 5 and 3 */
  px_mat2_t r = px_mat2(cos(1.1), -sin(1.1), sin(1.1), cos(1.1));
  px_mat2_t a = px_mat2_mul(px_mat2_mul(r, px_mat2_diag(3, -5)), px_mat2_transpose(r));
  assert_close(px_mat2_norm2(a), 5.0, 1e-14, 0);
}

static void mat4_product_of_transfers_adds(void **state) {
  (void)state;
  px_mat4_t t = px_mat4_mul(px_transfer_matrix(2.5), px_transfer_matrix(-0.5));
  px_mat4_t e = px_transfer_matrix(2.0);
  for (int i = 0; i < 4; i++)
    for (int j = 0; j < 4; j++)
      assert_close(t.m[i][j], e.m[i][j], 1e-15, 1e-15);
}

static void frame_from_parallel_hint_is_deterministic(void **state) {
  (void)state;
  px_frame_t a, b;
  assert_int_equal(px_frame_from_z(px_vec3(0, 0, 2), px_vec3(0, 0, 1), &a), PX_OK);
  assert_int_equal(px_frame_from_z(px_vec3(0, 0, 1), px_vec3(0, 0, 0), &b), PX_OK);
  assert_true(px_frame_defect(a) < 1e-15);
  assert_close(px_vec3_dot(a.x2, b.x2), 1.0, 1e-15, 0);
}

static void frame_rejects_zero_direction(void **state) {
  (void)state;
  px_frame_t f;
  assert_int_equal(px_frame_from_z(px_vec3(0, 0, 0), px_vec3(1, 0, 0), &f), PX_ESINGULAR);
  assert_int_equal(px_frame_from_z(px_vec3(NAN, 0, 1), px_vec3(1, 0, 0), &f), PX_ESINGULAR);
}

static void rotated_frame_stays_orthonormal(void **state) {
  (void)state;
  px_frame_t f;
  px_frame_from_z(px_vec3(0.2, -0.7, 0.4), px_vec3(1, 1, 0), &f);
  px_frame_t g = px_frame_rotate(f, 2.2);
  assert_true(px_frame_defect(g) < 1e-14);
  assert_close(px_vec3_dot(g.x1, f.x1), cos(2.2), 1e-14, 1e-14);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(inverse_of_rotation_is_transpose),
      cmocka_unit_test(singular_inverse_is_reported),
      cmocka_unit_test(norm2_matches_singular_value),
      cmocka_unit_test(mat4_product_of_transfers_adds),
      cmocka_unit_test(frame_from_parallel_hint_is_deterministic),
      cmocka_unit_test(frame_rejects_zero_direction),
      cmocka_unit_test(rotated_frame_stays_orthonormal),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
