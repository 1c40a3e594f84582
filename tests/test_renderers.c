/* test_renderers.c -- the renderer table (renderers/renderer.h): entries are well-formed, one
 * option name means one thing across entries, options parse and refuse as documented, and an
 * entry renders exactly what its renderer renders when called directly. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/builtin.h"
#include "pencil/pencil.h"
#include "renderers/renderer.h"

static void entries_are_well_formed(void **state) {
  (void)state;
  assert_true(rn_count() >= 2);
  assert_ptr_equal(rn_exact(), rn_find("exact"));
  assert_null(rn_find("nope"));
  for (int k = 0; k < rn_count(); k++) {
    const rn_renderer_t *r = rn_entry(k);
    assert_ptr_equal(rn_find(r->name), r);
    assert_non_null(r->render);
    assert_non_null(r->report);
    assert_non_null(r->describe);
    assert_true(r->nchannels >= 0 && r->nchannels <= RN_MAX_CHANNELS);
    assert_true(r->error_channel < r->nchannels && r->method_channel < r->nchannels);
    assert_true(r->options_size > 0 && r->defaults);
    for (int j = 0; j < r->noptions; j++) {
      const rn_option_t *o = &r->options[j];
      assert_true(strncmp(o->name, "--", 2) == 0);
      assert_true(o->offset < r->options_size);
      assert_true((o->kind == RN_OPT_FLAG) == (o->metavar == NULL));
      /* the same name in another entry takes a value alike (the parser relies on it) */
      for (int i = 0; i < rn_count(); i++) {
        const rn_option_t *p = rn_option_find(rn_entry(i), o->name);
        if (p)
          assert_int_equal(p->kind == RN_OPT_FLAG, o->kind == RN_OPT_FLAG);
      }
    }
  }
}

static void options_parse_and_refuse(void **state) {
  (void)state;
  const rn_renderer_t *p = rn_find("pencil");
  pt_options_t o;
  char err[256];
  rn_defaults(p, &o);
  assert_int_equal(o.domain, 5);
  assert_int_equal(rn_set(p, &o, "--rho", "0.25", err, sizeof err), 1);
  assert_true(o.rho == 0.25);
  assert_int_equal(rn_set(p, &o, "--rho", "0", err, sizeof err), 0);
  assert_string_equal(err, "--rho: expected a number > 0, got '0'");
  assert_int_equal(rn_set(p, &o, "--rho", "inf", err, sizeof err), 0);
  assert_int_equal(rn_set(p, &o, "--domain", "33", err, sizeof err), 0);
  assert_string_equal(err, "--domain: expected an integer from 1 to 32, got '33'");
  assert_int_equal(rn_set(p, &o, "--domain", "7", err, sizeof err), 1);
  assert_int_equal(o.domain, 7);
  assert_int_equal(rn_set(p, &o, "--bounds", "printed", err, sizeof err), 1);
  assert_int_equal(o.bound, PT_BOUND_PRINTED);
  assert_int_equal(rn_set(p, &o, "--bounds", "exact", err, sizeof err), 0);
  assert_string_equal(err, "--bounds: expected corrected, printed or probe, got 'exact'");
  assert_int_equal(rn_set(p, &o, "--no-interp", NULL, err, sizeof err), 1);
  assert_int_equal(o.interp, 0);
  assert_int_equal(rn_set(p, &o, "--no-interp", "1", err, sizeof err), 0);
  assert_int_equal(rn_set(p, &o, "--brightness-tol", "0", err, sizeof err), 1);
  assert_int_equal(rn_set(rn_exact(), &o, "--rho", "1", err, sizeof err), 0);
  assert_string_equal(err, "the exact renderer has no option --rho");
}

/* Numbers as users write them, one way each; what strtod() would also take (spaces, a leading
 * '+', hexadecimal, inf) is refused, and an underflow is kept rather than called "not finite". */
static void numbers_are_decimal(void **state) {
  (void)state;
  double v = -1.0;
  assert_int_equal(rn_parse_double("1.5", &v), 1);
  assert_true(v == 1.5);
  assert_int_equal(rn_parse_double("-2e-3", &v), 1);
  assert_int_equal(rn_parse_double(".5", &v), 1);
  assert_int_equal(rn_parse_double("5.", &v), 1);
  assert_int_equal(rn_parse_double("3E+2", &v), 1);
  assert_true(v == 300.0);
  assert_int_equal(rn_parse_double("1e-320", &v), 1);
  assert_true(v > 0.0 && v < 1e-300);
  assert_int_equal(rn_parse_double("1e400", &v), -1);
  const char *bad[] = {"",  " 5", "5 ",    "0x10", "inf", "nan", "1e",
                       ".", "-",  "1.2.3", "1e+",  "+5",  "+3E2"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
    assert_int_equal(rn_parse_double(bad[k], &v), 0);
  const rn_renderer_t *p = rn_find("pencil");
  pt_options_t o;
  char err[256];
  rn_defaults(p, &o);
  long l = 0;
  assert_int_equal(rn_parse_long("-12", &l), 1);
  assert_int_equal(l, -12);
  assert_int_equal(rn_parse_long("99999999999999999999", &l), -1);
  const char *badl[] = {"", " 5", "+5", "5 ", "5.0", "0x5", "-", "1e3"};
  for (size_t k = 0; k < sizeof badl / sizeof badl[0]; k++)
    assert_int_equal(rn_parse_long(badl[k], &l), 0);
  assert_int_equal(rn_set(p, &o, "--domain", " 5", err, sizeof err), 0);
  assert_int_equal(rn_set(p, &o, "--domain", "+5", err, sizeof err), 0);
  assert_int_equal(rn_set(p, &o, "--domain", "5.0", err, sizeof err), 0);
  assert_int_equal(rn_set(p, &o, "--rho", "0x1p-1", err, sizeof err), 0);
}

/* An option that acts only with another's values (rn_renderer_t.needs) is found idle, naming
 * both; every dependency names options of its entry, the one it depends on a choice or a flag. */
static void idle_options_named(void **state) {
  (void)state;
  for (int k = 0; k < rn_count(); k++) {
    const rn_renderer_t *r = rn_entry(k);
    for (int j = 0; j < r->nneeds; j++) {
      const rn_option_t *on = rn_option_find(r, r->needs[j].on);
      assert_non_null(rn_option_find(r, r->needs[j].option));
      assert_non_null(on);
      assert_true(on->kind == RN_OPT_CHOICE || on->kind == RN_OPT_FLAG);
    }
  }
  char err[256];
  double opt[64]; /* any entry's options struct, aligned */
  for (int k = 0; k < rn_count(); k++)
    assert_true(rn_entry(k)->options_size <= sizeof opt);
  const rn_renderer_t *x = rn_exact();
  rn_defaults(x, opt);
  assert_int_equal(rn_option_idle(x, opt, "--spectral-tol", err, sizeof err), 1);
  assert_string_equal(
      err, "--spectral-tol has no effect with --wavelengths fan (only with --wavelengths "
           "pencil)");
  assert_int_equal(rn_option_idle(x, opt, "--bins", err, sizeof err), 0);
  assert_int_equal(rn_set(x, opt, "--wavelengths", "pencil", err, sizeof err), 1);
  assert_int_equal(rn_option_idle(x, opt, "--spectral-tol", err, sizeof err), 0);
  assert_int_equal(rn_option_idle(x, opt, "--bins", err, sizeof err), 1);
  const rn_renderer_t *p = rn_find("pencil");
  rn_defaults(p, opt);
  assert_int_equal(rn_option_idle(p, opt, "--brightness-tol", err, sizeof err), 0);
  assert_int_equal(rn_option_idle(p, opt, "--weight-floor", err, sizeof err), 1);
  assert_int_equal(rn_set(p, opt, "--no-interp", NULL, err, sizeof err), 1);
  assert_int_equal(rn_option_idle(p, opt, "--brightness-tol", err, sizeof err), 1);
  assert_non_null(strstr(err, "with --no-interp"));
  assert_int_equal(rn_option_idle(p, opt, "--rho", err, sizeof err), 0);
}

/* The table's pencil entry with --certified gives the image pt_render gives directly. */
static void entry_renders_as_the_renderer(void **state) {
  (void)state;
  rt_scene_t s;
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  s.camera.width = 24;
  s.camera.height = 16;
  rt_plan_t plan = rt_plan_make(&s, 4);
  rt_image_t a, b;
  assert_int_equal(rt_image_alloc(&a, 24, 16), RT_OK);
  assert_int_equal(rt_image_alloc(&b, 24, 16), RT_OK);
  const rn_renderer_t *p = rn_find("pencil");
  pt_options_t o;
  char err[256];
  rn_defaults(p, &o);
  assert_int_equal(rn_set(p, &o, "--certified", NULL, err, sizeof err), 1);
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = 2;
  c.threads = 1;
  rn_output_t out = {.image = &a};
  pt_stats_t st;
  out.stats = &st;
  assert_int_equal(rn_channels_alloc(p, 24, 16, &out), RT_OK); /* blocks left dirty, freed */
  for (int k = 0; k < p->nchannels; k++)
    memset(out.channels[k], 0x7f, 24 * 16 * sizeof(float));
  rn_channels_free(&out);
  assert_int_equal(rn_channels_alloc(p, 24, 16, &out), RT_OK);
  for (int k = 0; k < p->nchannels; k++) /* zero until written, not what malloc left */
    for (int i = 0; i < 24 * 16; i++)
      assert_true(out.channels[k][i] == 0.0f);
  assert_int_equal(p->render(&s, &plan, &c, &o, &out), RT_OK);
  pt_options_t d = PT_OPTIONS_DEFAULT;
  d.spp_side = 2;
  d.threads = 1;
  d.certified = 1;
  assert_int_equal(pt_render(&s, &plan, &d, &b, NULL, NULL, NULL), RT_OK);
  for (int ch = 0; ch < RT_CH_COUNT; ch++)
    for (int k = 0; k < 24 * 16; k++)
      assert_true(memcmp(&a.ch[ch][k], &b.ch[ch][k], sizeof(float)) == 0);
  assert_true(st.samples[0] + st.samples[1] + st.samples[2] == 24 * 16 * 4);
  rn_channels_free(&out);
  for (int k = 0; k < RN_MAX_CHANNELS; k++)
    assert_null(out.channels[k]);
  rt_image_free(&a);
  rt_image_free(&b);
  rt_scene_free(&s);
}

static void nonfinite_pixels_are_found(void **state) {
  (void)state;
  rt_image_t img;
  int x = -1, y = -1, c = -1;
  assert_int_equal(rt_image_alloc(&img, 5, 4), RT_OK);
  for (int ch = 0; ch < 3; ch++)
    for (int k = 0; k < 20; k++)
      img.ch[ch][k] = 0.5f;
  img.ch[RT_CH_Z][3] = INFINITY; /* auxiliary channels may hold infinities (a miss) */
  assert_int_equal(rn_image_nonfinite(&img, &x, &y, &c), 0);
  img.ch[RT_CH_B][2 * 5 + 3] = NAN;
  assert_int_equal(rn_image_nonfinite(&img, &x, &y, &c), 1);
  assert_int_equal(x, 3);
  assert_int_equal(y, 2);
  assert_int_equal(c, 2);
  rt_image_free(&img);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(entries_are_well_formed),       cmocka_unit_test(options_parse_and_refuse),
      cmocka_unit_test(numbers_are_decimal),           cmocka_unit_test(nonfinite_pixels_are_found),
      cmocka_unit_test(entry_renders_as_the_renderer), cmocka_unit_test(idle_options_named),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
