/* test_spectral.c -- the spectral fan of core/shade.c (issue 22; docs/spectral.md, section 3): a
 * white ray refracting at a dispersive glass becomes one monochromatic refracted ray per bin, each
 * obeying Snell's law with the index at its wavelength, weighted by the bins' RGB weights; a glass
 * that does not disperse renders through the fan as in RGB; the effects plan turns the fan on for
 * the exact renderer only, and the other renderers refuse a plan that asks for it. */
#include <math.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/builtin.h"
#include "core/intersect.h"
#include "core/shade.h"
#include "render/render.h"
#include "renderers/renderer.h"

/* The children rt_shade_hit() hands to the tracer, each returning radiance 1. */
typedef struct {
  int n;
  rt_child_t child[64];
} seen_t;

static rt_rgb_t keep_child(void *ctx, const rt_child_t *c, int depth) {
  (void)depth;
  seen_t *s = ctx;
  if (s->n < 64)
    s->child[s->n++] = *c;
  return rt_rgb(1, 1, 1);
}

static void lit(void *ctx, rt_shadow_t *q) {
  (void)ctx;
  q->through = rt_rgb(1, 1, 1);
}

/* The Fig. 8 scene with its ball of SF11 (Schott's Sellmeier model). */
static void dispersive_fig8(rt_scene_t *s) {
  rt_scene_init(s);
  assert_int_equal(rt_builtin_fig8(s), RT_OK);
  int g = rt_scene_find_material(s, "glass");
  assert_true(g >= 0);
  assert_int_equal(px_index_named("SF11", &s->material[g].index), PX_OK);
  assert_int_equal(px_index_eval(&s->material[g].index, PX_LAMBDA_D, &s->material[g].ior, NULL),
                   PX_OK);
}

/* |n1 (d - (d.n) n) - n2 (d' - (d'.n) n)|: the tangential Snell law's residual. */
static double snell_residual(px_vec3_t d, px_vec3_t dp, px_vec3_t n, double n1, double n2) {
  px_vec3_t t1 = px_v3_axpy(-px_v3_dot(d, n), n, d), t2 = px_v3_axpy(-px_v3_dot(dp, n), n, dp);
  return px_v3_norm(px_v3_sub(px_v3_scale(t1, n1), px_v3_scale(t2, n2)));
}

/* A white ray entering the SF11 ball: one white mirror child of weight kr, and one refracted child
 * per bin, at the bin's wavelength, obeying Snell's law with SF11's index there (within 1e-14),
 * its weight the bin's RGB weight times kt T; the weights sum to kt T per channel, so the shaded
 * value is the direct term plus kr + kt T times the children's radiance of 1. A monochromatic ray
 * meeting the same point takes the index at its own wavelength and makes no fan. */
static void fan_children(void **state) {
  (void)state;
  rt_scene_t s;
  dispersive_fig8(&s);
  rt_plan_t plan = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&plan, RT_EFFECT_DISPERSION));
  assert_int_equal(plan.bins, RT_DEFAULT_BINS);
  rt_ray_t ray = {
      px_vec3(0.3, 3.0, -6.0), px_v3_unit(px_vec3(-0.3, -1.3, 6.0)), 0.0, INFINITY, 1.0, -1, 0.0f};
  rt_hit_t hit;
  assert_true(rt_intersect(&s, &ray, &hit));
  rt_surface_t sf;
  rt_shade_surface(&s, &hit, &ray, &sf);
  assert_true(sf.entering && sf.mat->kt > 0.0);
  seen_t seen = {0};
  rt_tracer_t tr = {keep_child, lit, &seen, NULL, NULL, NULL, 0};
  rt_rgb_t c = rt_shade_hit(&s, &plan, &sf, &ray, 0, &tr);
  rt_rgb_t direct = rt_shade_direct(&s, &plan, &sf, &ray, &tr);
  assert_int_equal(seen.n, plan.bins + 1);
  rt_rgb_t sum = rt_rgb(0, 0, 0);
  int refracted = 0, reflected = 0;
  double worst = 0.0;
  for (int k = 0; k < seen.n; k++) {
    const rt_child_t *ch = &seen.child[k];
    if (ch->kind == RT_RAY_REFLECT) {
      reflected++;
      assert_true(ch->ray.lambda == 0.0f);
      assert_close(ch->weight.r, sf.mat->kr, 1e-15, 0.0);
      assert_close(ch->weight.b, sf.mat->kr, 1e-15, 0.0);
      continue;
    }
    int i = refracted++;
    assert_true(ch->ray.lambda == (float)plan.bin_lambda[i]);
    double n2;
    assert_int_equal(px_index_eval(&sf.mat->index, plan.bin_lambda[i], &n2, NULL), PX_OK);
    assert_close(ch->ray.ior, n2, 1e-15, 0.0);
    worst = fmax(worst, snell_residual(ray.d, ch->ray.d, sf.nf, 1.0, n2));
    rt_rgb_t want = rt_rgb_mul(plan.bin_weight[i], rt_rgb_scale(sf.mat->transmittance, sf.mat->kt));
    assert_close(ch->weight.r, want.r, 1e-15, 1e-18);
    assert_close(ch->weight.g, want.g, 1e-15, 1e-18);
    sum = rt_rgb_add(sum, ch->weight);
  }
  assert_int_equal(reflected, 1);
  assert_int_equal(refracted, plan.bins);
  assert_true(worst < 1e-14);
  /* the bins' directions differ: SF11 spreads 380-780 nm over about a degree here */
  double spread = acos(px_v3_dot(seen.child[0].ray.d, seen.child[plan.bins - 1].ray.d));
  print_message("Snell residual %.2e, spread of the fan %.3f degrees\n", worst,
                spread * 180 / M_PI);
  assert_true(spread > 0.1 * M_PI / 180.0 && spread < 5.0 * M_PI / 180.0);
  assert_close(sum.r, sf.mat->kt, 1e-14, 0.0);
  assert_close(sum.g, sf.mat->kt, 1e-14, 0.0);
  assert_close(sum.b, sf.mat->kt, 1e-14, 0.0);
  assert_close(c.g, direct.g + sf.mat->kr + sf.mat->kt, 1e-14, 0.0);
  /* a monochromatic ray: two children, no fan, the refracted one by the index at its wavelength */
  rt_ray_t mono = ray;
  mono.lambda = 450.0f;
  rt_shade_surface(&s, &hit, &mono, &sf);
  double n450;
  assert_int_equal(px_index_eval(&sf.mat->index, 450.0, &n450, NULL), PX_OK);
  seen.n = 0;
  rt_shade_hit(&s, &plan, &sf, &mono, 0, &tr);
  assert_int_equal(seen.n, 2);
  for (int k = 0; k < 2; k++) {
    const rt_child_t *ch = &seen.child[k];
    assert_true(ch->ray.lambda == 450.0f);
    if (ch->kind == RT_RAY_REFRACT) {
      assert_close(ch->ray.ior, n450, 1e-15, 0.0);
      assert_true(snell_residual(mono.d, ch->ray.d, sf.nf, 1.0, n450) < 1e-14);
    }
  }
  rt_scene_free(&s);
}

/* A glass whose index varies by 1e-9 over the visible range goes through the fan (the plan cannot
 * tell) and renders as the same glass of constant index in RGB: every pixel within 1e-6 of it, on
 * a board of one colour (no checker edge for a ray moved by 1e-9 to cross). */
static void fan_of_a_glass_that_does_not_disperse(void **state) {
  (void)state;
  rt_scene_t s[2];
  rt_image_t img[2];
  rt_stats_t st[2];
  for (int k = 0; k < 2; k++) {
    rt_scene_init(&s[k]);
    assert_int_equal(rt_builtin_fig8(&s[k]), RT_OK);
    s[k].camera.width = s[k].camera.height = 48;
    int g = rt_scene_find_material(&s[k], "glass"), r = rt_scene_find_material(&s[k], "red");
    s[k].material[r].color = s[k].material[rt_scene_find_material(&s[k], "white")].color;
    if (k == 1) { /* Cauchy A + B / l^2 with B = 1e-10 um^2, A making n_d = 1.5 */
      px_index_t *m = &s[k].material[g].index;
      memset(m, 0, sizeof *m);
      m->kind = PX_INDEX_CAUCHY;
      m->b[0] = 1e-10;
      m->a = 1.5 - 1e-10 / (PX_LAMBDA_D * PX_LAMBDA_D * 1e-6);
      m->lo_nm = 380.0;
      m->hi_nm = 780.0;
    }
    s[k].spectral_bins = 8;
    rt_plan_t plan = rt_plan_make(&s[k], 1);
    assert_int_equal(rt_plan_has(&plan, RT_EFFECT_DISPERSION), k);
    xr_options_t opt = XR_OPTIONS_DEFAULT;
    opt.threads = 2;
    assert_int_equal(rt_image_alloc(&img[k], 48, 48), RT_OK);
    assert_int_equal(xr_render(&s[k], &plan, &opt, &img[k], &st[k]), RT_OK);
  }
  double worst = 0.0;
  for (int c = RT_CH_R; c <= RT_CH_B; c++)
    for (int q = 0; q < 48 * 48; q++)
      worst = fmax(worst, fabs(img[0].ch[c][q] - img[1].ch[c][q]));
  print_message("RGB against 8 bins of a glass varying by 1e-9: %.2e at most; refracted rays "
                "%llu against %llu\n",
                worst, (unsigned long long)st[1].refract, (unsigned long long)st[0].refract);
  assert_true(st[1].refract > 4 * st[0].refract); /* the fan was taken */
  assert_true(worst < 1e-6);
  for (int k = 0; k < 2; k++) {
    rt_image_free(&img[k]);
    rt_scene_free(&s[k]);
  }
}

/* The plan: dispersion on with the scene's bins, the ray-tree bound counting the fans (depth 6,
 * 40 bins: 4,807 nodes); rn_plan_make() gives the beam renderer its wavelength axis (image solids)
 * or, asked, draws its glass at n_d with the reason; keeps
 * the fan for the exact one and gives the pencil renderer spectral pencils (no fan in the bound:
 * 127 nodes), or turns it off with --wavelengths off; the pencil renderer refuses a plan that asks
 * for the fan; no dispersion without refraction, or when every index is a number. */
static void plan_turns_the_fan_on_for_exact_only(void **state) {
  (void)state;
  rt_scene_t s;
  dispersive_fig8(&s);
  rt_plan_t p = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&p, RT_EFFECT_DISPERSION));
  assert_int_equal(p.tree_nodes, 4807);
  assert_non_null(strstr(p.why[RT_EFFECT_DISPERSION], "40 wavelength bins"));
  rt_plan_t px = rn_plan_make(rn_find("exact"), &s, 1, NULL);
  assert_true(rt_plan_has(&px, RT_EFFECT_DISPERSION) && px.bins == 40);
  const char *others[2] = {"beam", "pencil"};
  unsigned char opt[4096];
  char err[200];
  { /* beams: dispersion image solids on the plan's wavelength axis, or at n_d when asked */
    const rn_renderer_t *r = rn_find(others[0]);
    rt_plan_t q = rn_plan_make(r, &s, 1, NULL);
    assert_true(rt_plan_has(&q, RT_EFFECT_DISPERSION) && q.spectral == RT_SPECTRAL_PENCIL);
    assert_true(q.wave.scaled);
    assert_non_null(strstr(q.why[RT_EFFECT_DISPERSION], "dispersion image solids"));
    assert_true(r->options_size <= sizeof opt);
    rn_defaults(r, opt);
    assert_int_equal(rn_set(r, opt, "--wavelengths", "off", err, sizeof err), 1);
    q = rn_plan_make(r, &s, 1, opt);
    assert_false(rt_plan_has(&q, RT_EFFECT_DISPERSION));
    assert_int_equal(q.bins, 0);
    assert_int_equal(q.tree_nodes, 127); /* the binary tree of depth 6 */
    assert_non_null(strstr(q.why[RT_EFFECT_DISPERSION], others[0]));
    assert_non_null(strstr(q.why[RT_EFFECT_DISPERSION], "n_d = 1.7847"));
  }
  const rn_renderer_t *pen = rn_find("pencil");
  assert_true(pen->options_size <= sizeof opt);
  rn_defaults(pen, opt);
  rt_plan_t q = rn_plan_make(pen, &s, 1, NULL);
  assert_true(rt_plan_has(&q, RT_EFFECT_DISPERSION) && q.spectral == RT_SPECTRAL_PENCIL);
  assert_int_equal(q.tree_nodes, 127);
  assert_non_null(strstr(q.why[RT_EFFECT_DISPERSION], "spectral pencils"));
  assert_int_equal(rn_set(pen, opt, "--wavelengths", "off", err, sizeof err), 1);
  q = rn_plan_make(pen, &s, 1, opt);
  assert_false(rt_plan_has(&q, RT_EFFECT_DISPERSION));
  assert_non_null(strstr(q.why[RT_EFFECT_DISPERSION], others[1]));
  assert_non_null(strstr(q.why[RT_EFFECT_DISPERSION], "n_d = 1.7847"));
  rn_defaults(pen, opt);
  rn_common_t c = RN_COMMON_DEFAULT;
  c.aux = 0;
  rt_image_t img;
  assert_int_equal(rt_image_alloc(&img, s.camera.width, s.camera.height), RT_OK);
  rn_output_t out;
  memset(&out, 0, sizeof out);
  out.image = &img;
  assert_int_equal(pen->render(&s, &p, &c, opt, &out), RT_EINVAL);
  assert_non_null(strstr(out.why, "spectral fan"));
  rt_image_free(&img);
  s.material[rt_scene_find_material(&s, "glass")].kt = 0.0;
  p = rt_plan_make(&s, 1);
  assert_false(rt_plan_has(&p, RT_EFFECT_DISPERSION));
  rt_scene_free(&s);
  rt_scene_init(&s);
  assert_int_equal(rt_builtin_fig8(&s), RT_OK);
  p = rt_plan_make(&s, 1);
  assert_false(rt_plan_has(&p, RT_EFFECT_DISPERSION));
  assert_non_null(strstr(p.why[RT_EFFECT_DISPERSION], "no transparent material"));
  rt_scene_free(&s);
}

/* The exact renderer's --wavelengths: Takagi et al.'s wavelength supersampling (each primary ray
 * once per bin) gives the fan's image (each ray meets the same indices: within float rounding),
 * at several times its rays; "off" gives the image of the same glass with its index at the d-line
 * as a number, bit for bit, also under a plan made without the options; --bins sets the bins. */
static void wavelengths_primary_equals_the_fan(void **state) {
  (void)state;
  rt_scene_t s, plain;
  dispersive_fig8(&s);
  s.camera.width = s.camera.height = 40;
  rt_scene_init(&plain);
  assert_int_equal(rt_builtin_fig8(&plain), RT_OK);
  plain.camera = s.camera;
  int g = rt_scene_find_material(&plain, "glass");
  plain.material[g].ior = s.material[g].ior;
  plain.material[g].index = px_index_constant(s.material[g].ior);
  const rn_renderer_t *x = rn_find("exact");
  const char *modes[3] = {"fan", "primary", "off"};
  rt_image_t img[4];
  rt_stats_t st[4];
  for (int k = 0; k < 4; k++) {
    unsigned char opt[64];
    char err[200];
    rn_defaults(x, opt);
    const rt_scene_t *sc = k < 3 ? &s : &plain;
    if (k < 3) {
      assert_int_equal(rn_set(x, opt, "--wavelengths", modes[k], err, sizeof err), 1);
      assert_int_equal(rn_set(x, opt, "--bins", "9", err, sizeof err), 1);
    }
    rt_plan_t p = rn_plan_make(x, sc, 1, opt);
    assert_int_equal(p.bins, k < 2 ? 9 : 0);
    if (k == 1)
      assert_non_null(strstr(p.why[RT_EFFECT_DISPERSION], "every primary ray traced at 9"));
    if (k == 2)
      assert_non_null(strstr(p.why[RT_EFFECT_DISPERSION], "--wavelengths off"));
    rn_common_t c = RN_COMMON_DEFAULT;
    c.aux = 0;
    c.threads = 2;
    assert_int_equal(rt_image_alloc(&img[k], 40, 40), RT_OK);
    rn_output_t out;
    memset(&out, 0, sizeof out);
    out.image = &img[k];
    out.stats = &st[k];
    assert_int_equal(x->render(sc, &p, &c, opt, &out), RT_OK);
  }
  double fan_primary = 0.0, off_plain = 0.0, fan_plain = 0.0;
  for (int ch = RT_CH_R; ch <= RT_CH_B; ch++)
    for (int q = 0; q < 40 * 40; q++) {
      fan_primary = fmax(fan_primary, fabs(img[0].ch[ch][q] - img[1].ch[ch][q]));
      off_plain = fmax(off_plain, fabs(img[2].ch[ch][q] - img[3].ch[ch][q]));
      fan_plain = fmax(fan_plain, fabs(img[0].ch[ch][q] - img[3].ch[ch][q]));
    }
  print_message("fan against primary %.2e (rays %llu against %llu); off against the number %.2e; "
                "fan against the number %.2e\n",
                fan_primary, (unsigned long long)rt_stats_total(&st[0]),
                (unsigned long long)rt_stats_total(&st[1]), off_plain, fan_plain);
  { /* --wavelengths off holds under a plan made without the options (rt_plan_make) */
    unsigned char opt[64];
    char err[200];
    rn_defaults(x, opt);
    assert_int_equal(rn_set(x, opt, "--wavelengths", "off", err, sizeof err), 1);
    rt_plan_t p = rt_plan_make(&s, 1);
    assert_true(rt_plan_has(&p, RT_EFFECT_DISPERSION));
    rn_common_t c = RN_COMMON_DEFAULT;
    c.aux = 0;
    rt_image_t im;
    assert_int_equal(rt_image_alloc(&im, 40, 40), RT_OK);
    rn_output_t out;
    memset(&out, 0, sizeof out);
    out.image = &im;
    assert_int_equal(x->render(&s, &p, &c, opt, &out), RT_OK);
    for (int ch = RT_CH_R; ch <= RT_CH_B; ch++)
      assert_memory_equal(im.ch[ch], img[3].ch[ch], sizeof(float) * 40 * 40);
    rt_image_free(&im);
  }
  assert_true(fan_primary < 1e-5);
  assert_true(off_plain == 0.0);
  assert_true(fan_plain > 1e-3); /* the dispersion shows */
  assert_true(rt_stats_total(&st[1]) > 3 * rt_stats_total(&st[2]));
  for (int k = 0; k < 4; k++)
    rt_image_free(&img[k]);
  rt_scene_free(&s);
  rt_scene_free(&plain);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fan_children),
      cmocka_unit_test(fan_of_a_glass_that_does_not_disperse),
      cmocka_unit_test(plan_turns_the_fan_on_for_exact_only),
      cmocka_unit_test(wavelengths_primary_equals_the_fan),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
