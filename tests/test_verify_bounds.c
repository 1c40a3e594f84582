/* test_verify_bounds.c -- `pencil verify bounds` on a few chosen systems (the whole quick sweep
 * runs in cli_verify_bounds.sh): the corrected A-1 holds and is attained where the derivation
 * says, the printed A-1 fails where docs/errata.md says, the third-order case through a
 * sphere's centre, and the Ceres shim on a problem with a known answer. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ceres_shim.h"
#include "cmocka_main.h"
#include "validation/bounds.h"

static val_system_t *sweep;
static size_t nsweep;

static int setup(void **state) {
  (void)state;
  sweep = val_bounds_sweep(1, &nsweep);
  return sweep ? 0 : -1;
}

static int teardown(void **state) {
  (void)state;
  free(sweep);
  return 0;
}

static const val_system_t *find(const char *label) {
  for (size_t i = 0; i < nsweep; i++)
    if (strcmp(sweep[i].label, label) == 0)
      return &sweep[i];
  fail_msg("no system '%s' in the quick sweep", label);
  return NULL;
}

static void corrected_holds(const val_bounds_result_t *r) {
  for (int q = 0; q < VAL_NCOEF; q++)
    if (!isnan(r->ratio[0][q]))
      assert_true(r->ratio[0][q] >= 1 - VAL_BOUND_SLACK);
  assert_true(isnan(r->ratio_ex[0]) || r->ratio_ex[0] >= 1 - VAL_BOUND_SLACK);
  assert_true(isnan(r->ratio_exi[0]) || r->ratio_exi[0] >= 1 - VAL_BOUND_SLACK);
}

/* A concave glass surface entered at 60 deg in rotated frames: corrected a, b, f are attained
 * exactly (ratio 1, the true worst case is along x1); printed a and b are right too, printed f
 * is short by n/n' = 1/1.5. */
static void sphere_refraction(void **state) {
  (void)state;
  val_bounds_result_t r;
  val_verify_bounds_one(find("refract sphere n 1->1.5 theta 60 R -1 rotated"), 1, &r);
  assert_int_equal(r.status, PX_OK);
  corrected_holds(&r);
  assert_close(r.ratio[0][0], 1.0, 1e-9, 0);       /* a */
  assert_close(r.ratio[0][1], 1.0, 1e-9, 0);       /* b */
  assert_close(r.ratio[0][5], 1.0, 1e-9, 0);       /* f */
  assert_close(r.ratio[1][0], 1.0, 1e-9, 0);       /* printed a: right for a sphere */
  assert_close(r.ratio[1][5], 1.0 / 1.5, 1e-9, 0); /* printed f: factor n/n' too many */
  assert_true(r.tensor_diff < 1e-9);
  /* the fit touches the sampled exact errors: the envelope agrees within 2% where attained */
  assert_int_equal(r.fitted, 1);
  assert_true(r.fit_excess[0] <= VAL_FIT_TOL && r.fit_dev[0] <= VAL_FIT_TOL);
  assert_true(r.fit_excess[1] <= VAL_FIT_TOL && r.fit_dev[1] <= VAL_FIT_TOL);
  /* and the fitted constants are no larger than the corrected ones (a, f attained) */
  assert_true(r.fit.a <= r.bound[0].a * (1 + VAL_FIT_TOL));
  assert_true(r.fit.f <= r.bound[0].f * (1 + VAL_FIT_TOL));
}

/* A convex mirror: printed a and d are negative (cos theta' < 0), so they "bound" nothing. */
static void mirror_printed_signs(void **state) {
  (void)state;
  val_bounds_result_t r;
  val_verify_bounds_one(find("reflect sphere theta 30 R 1"), 0, &r);
  assert_int_equal(r.status, PX_OK);
  corrected_holds(&r);
  assert_close(r.ratio[1][0], -1.0, 1e-9, 0); /* printed a = -true a */
  assert_true(r.ratio[1][3] < 0);             /* printed d < 0 */
}

/* Pinhole -> glass sphere through its centre -> plane: t(2) = 0, the full error is third order,
 * Eq. (6) alone has no limit (the cap), with the third-order term the limit is finite and the
 * full error there stays near tau. */
static void sphere_centre_third_order(void **state) {
  (void)state;
  val_bounds_result_t r;
  val_verify_bounds_one(find("aim: pinhole -> sphere n 1.5 R 1 aim 0.00 -> plane at 3"), 0, &r);
  assert_int_equal(r.status, PX_OK);
  assert_true(r.pinhole && r.second_order_vanishes);
  assert_true(r.err_at_probe > 1e-6);
  assert_true(r.k3 > 1.0);
  assert_int_equal(r.regime[0], PX_SPREAD_CAP);
  assert_int_equal(r.regime[1], PX_SPREAD_THIRD_ORDER);
  assert_true(isfinite(r.spread[1]) && r.spread[1] < VAL_ONSET_MAX);
  /* k3 comes from spreads of 1e-3..4e-3; at ~3e-2 higher orders add a few per cent */
  assert_true(r.err_over_tau[1] < 1.1);
}

/* aimed off the centre, the corrected C holds until the third-order onset, which is finite */
static void off_centre_onset(void **state) {
  (void)state;
  val_bounds_result_t r;
  val_verify_bounds_one(find("aim: pinhole -> sphere n 1.5 R 1 aim 0.30 -> plane at 3"), 0, &r);
  assert_int_equal(r.status, PX_OK);
  corrected_holds(&r);
  assert_false(r.second_order_vanishes);
  assert_true(r.onset[0] > 1e-3 && r.onset[0] < VAL_ONSET_MAX);
  assert_true(r.spread[0] < r.onset[0]); /* Eq. (6) stays below the onset here */
}

static int quad_cost(void *user, const double *p, double *r, double *jac) {
  const double *t = user; /* residuals p0 + p1 x - t(x) at x = 0, 1, 2 */
  for (int i = 0; i < 3; i++) {
    r[i] = p[0] + p[1] * i - t[i];
    if (jac) {
      jac[2 * i] = 1.0;
      jac[2 * i + 1] = i;
    }
  }
  return 1;
}

/* The shim: an unconstrained fit recovers an exact line; a lower bound is respected */
static void ceres_shim_bounds(void **state) {
  (void)state;
  double t[3] = {1.0, 3.0, 5.0}, p[2] = {0, 0};
  val_ceres_summary_t s;
  assert_int_equal(val_ceres_solve_bounded(2, p, NULL, NULL, 3, quad_cost, t, NULL, &s), 0);
  assert_true(s.usable);
  assert_close(p[0], 1.0, 0, 1e-9);
  assert_close(p[1], 2.0, 0, 1e-9);
  double t2[3] = {1.0, -1.0, -3.0}, q[2] = {0.5, 0.5}, lo[2] = {-INFINITY, 0};
  /* tolerances as in fit_envelope.c: Ceres' defaults stop at a 1e-6 relative cost change */
  val_ceres_options_t opt = {200, 1e-14, 1e-16, 1e-14};
  assert_int_equal(val_ceres_solve_bounded(2, q, lo, NULL, 3, quad_cost, t2, &opt, &s), 0);
  assert_true(s.usable);
  assert_true(q[1] >= 0.0 && q[1] < 1e-9); /* the slope would be -2; it stops at the bound */
  /* with the slope at 0, p0 = the mean of t2; the cost is quadratic in the parameter error, so
   * the relative cost tolerance of 1e-14 leaves ~1e-7 in p0 */
  assert_close(s.final_cost, 4.0, 1e-12, 0);
  assert_close(q[0], -1.0, 0, 1e-6);
  assert_int_equal(val_ceres_solve_bounded(0, q, lo, NULL, 3, quad_cost, t2, NULL, &s), -1);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sphere_refraction),         cmocka_unit_test(mirror_printed_signs),
      cmocka_unit_test(sphere_centre_third_order), cmocka_unit_test(off_centre_onset),
      cmocka_unit_test(ceres_shim_bounds),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, setup, teardown);
}
