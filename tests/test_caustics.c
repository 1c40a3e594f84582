/* test_caustics.c -- light through glass in shading (issue 25, core/caustics.h): the effects plan's
 * receivers and lights, a caustic map of the light through a glass slab against its exact value,
 * shading with the map instead of the textbook's attenuated shadow ray, and the exact and pencil
 * renderers with the same map.
 *
 * The slab: a glass box 2 x 0.2 x 2 (kt 0.8, no reflection, no Fresnel split) over a white floor,
 * under a parallel light straight down. At normal incidence a ray crosses the top and the bottom
 * face undeviated, each crossing weighting it by kt: the floor under the slab receives exactly
 * 0.64 I through it and nothing directly, and beside the slab I directly and nothing through it.
 * The textbook's shadow ray instead counts kt once per passage through a closed object (0.8 I). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/caustics.h"
#include "core/shade.h"
#include "io/scene_json.h"
#include "light/illuminance.h"
#include "render/render.h"
#include "renderers/renderer.h"

static void load(const char *json, rt_scene_t *s) {
  char err[512];
  rt_scene_init(s);
  if (io_scene_load_buffer("test.json", json, strlen(json), s, err, sizeof err) != 0)
    fail_msg("%s", err);
  if (rt_scene_prepare(s) != RT_OK)
    fail_msg("prepare");
}

/* The slab scene; `light` is the JSON of the one light, `extra` more settings. */
static void load_slab(rt_scene_t *s, const char *light, const char *extra) {
  char json[4096];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 4, -3], \"look_at\": [0, 0, 0], \"width\": 40, "
           "\"height\": 40},"
           " \"settings\": {\"ambient\": 0, \"max_depth\": 4%s},"
           " \"materials\": {\"white\": {\"kd\": 0.5, \"ka\": 0}, \"glass\": {\"kd\": 0, \"ka\": 0,"
           " \"kt\": 0.8, \"kr\": 0, \"ior\": 1.5}},"
           " \"lights\": [%s],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           " \"normal\": [0, 1, 0], \"material\": \"white\"},"
           " {\"type\": \"polyhedron\", \"name\": \"slab\", \"material\": \"glass\", \"vertices\":"
           " [[-1, 1, -1], [1, 1, -1], [1, 1, 1], [-1, 1, 1], [-1, 1.2, -1], [1, 1.2, -1],"
           " [1, 1.2, 1], [-1, 1.2, 1]], \"faces\": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4],"
           " [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]}]}",
           extra, light);
  load(json, s);
}

static const char down[] = "{\"type\": \"parallel\", \"direction\": [0, -1, 0], \"intensity\": 1}";

/* The plan maps the floor for a parallel light and for a point light with the fall-off, and
 * says why not for a point light without it and for a scene that refuses caustics. */
static void plan_receivers_and_lights(void **state) {
  (void)state;
  rt_scene_t s;
  load_slab(&s, down, "");
  rt_plan_t p = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&p, RT_EFFECT_CAUSTICS));
  assert_int_equal(p.caustic.nplane, 1);
  assert_int_equal(p.caustic.nobject[0], 1);
  assert_int_equal(p.caustic.object[0][0], 0);
  assert_int_equal(p.caustic.lights, 1u);
  assert_int_equal(p.caustic.via, 1);
  assert_non_null(strstr(p.why[RT_EFFECT_CAUSTICS], "'slab'"));
  assert_non_null(strstr(p.why[RT_EFFECT_CAUSTICS], "'floor'"));
  assert_null(p.maps);
  rt_scene_free(&s);

  load_slab(&s, "{\"type\": \"point\", \"position\": [0, 5, 0], \"intensity\": 25}", "");
  p = rt_plan_make(&s, 1);
  assert_false(rt_plan_has(&p, RT_EFFECT_CAUSTICS));
  assert_non_null(strstr(p.why[RT_EFFECT_CAUSTICS], "falloff"));
  rt_scene_free(&s);

  load_slab(&s,
            "{\"type\": \"point\", \"position\": [0, 5, 0], \"intensity\": 25, \"falloff\": "
            "\"inverse-square\"}",
            "");
  p = rt_plan_make(&s, 1);
  assert_true(rt_plan_has(&p, RT_EFFECT_CAUSTICS));
  rt_scene_free(&s);

  load_slab(&s, down, ", \"caustics\": \"off\"");
  p = rt_plan_make(&s, 1);
  assert_false(rt_plan_has(&p, RT_EFFECT_CAUSTICS));
  assert_int_equal(p.caustic.nplane, 0);
  rt_scene_free(&s);
}

/* The map of the light through the slab: 0.64 in every cell under it, 0 in every cell beside it
 * (the direct light is the shadow rays'), by grid-pencils (exactly: a pencil's triangle spreads
 * its flux evenly) and by photons (a regular grid of them: within the count's aliasing), in the
 * cells that do not touch the slab's edge. */
static void slab_map_exact(void **state) {
  (void)state;
  rt_scene_t s;
  load_slab(&s, down, "");
  rt_plan_t p = rt_plan_make(&s, 1);
  /* grid-pencils on 65 rays a side, photons on 1025, and grid-pencils on 301: three bands of
   * the grid's rows (LT_GRID_BAND 128), the pencils across the bands' seams exact too */
  for (int run = 0; run < 3; run++) {
    int method = run == 1;
    lt_caustic_options_t o = {method ? LT_METHOD_PHOTONS : LT_METHOD_GRID_PENCIL,
                              run == 0   ? 65
                              : run == 1 ? 1025
                                         : 301,
                              40,
                              0,
                              NULL,
                              NULL,
                              0};
    rt_caustic_maps_t maps;
    lt_caustic_stats_t st;
    char why[256];
    assert_int_equal(lt_caustic_maps(&s, &p.caustic, &o, &maps, &st, why, sizeof why), RT_OK);
    assert_int_equal(st.maps, 1);
    assert_int_equal(maps.n, 1);
    const rt_caustic_map_t *m = rt_caustic_map_of(&maps, 0, 0);
    assert_non_null(m);
    assert_null(rt_caustic_map_of(&maps, 1, 0)); /* the slab is no receiver */
    assert_non_null(m->e);
    int under = 0, beside = 0;
    double worst_under = 0.0, worst_beside = 0.0;
    for (int j = 0; j < m->height; j++)
      for (int i = 0; i < m->width; i++) {
        /* the cell's extent in x and z (u = x, v = n x u = -z) */
        double u0 = m->u0 + i * m->du, u1 = u0 + m->du, v0 = m->v0 + j * m->dv, v1 = v0 + m->dv;
        /* under: not touching the slab's edge, where pencils divided to the limit leave photons */
        int in = u0 >= -1 + m->du && u1 <= 1 - m->du && v0 >= -1 + m->dv && v1 <= 1 - m->dv;
        int out = u1 <= -1 || u0 >= 1 || v1 <= -1 || v0 >= 1;
        for (int c = 0; c < 3; c++) {
          double e = m->e[3 * ((size_t)j * m->width + i) + c];
          if (in)
            worst_under = fmax(worst_under, fabs(e - 0.64));
          if (out)
            worst_beside = fmax(worst_beside, fabs(e));
        }
        under += in;
        beside += out;
      }
    assert_true(under >= 100 && beside >= 100);
    print_message("%s: worst cell under the slab off 0.64 by %.3g, beside it %.3g\n",
                  method ? "photons" : "grid-pencil", worst_under, worst_beside);
    assert_true(worst_beside == 0.0);
    /* photons: 1025 rays over the 4-unit extent put 25.6 a row into a 0.1 cell, 25 or 26: the
     * count aliases by up to 2 / 25.6 of 0.64 */
    assert_true(worst_under <= (method ? 0.64 * 2 / 25.6 : 1e-9));
    rt_caustic_maps_free(&maps);
  }
  rt_scene_free(&s);
}

/* Shading at floor points with and without the maps: under the slab kd 0.64 (the map; the shadow
 * ray, opaque now, is blocked) against the textbook's kd 0.8; beside it kd (the light directly)
 * either way. */
static void shade_replaces_textbook_shadow(void **state) {
  (void)state;
  rt_scene_t s;
  load_slab(&s, down, "");
  rt_plan_t p = rt_plan_make(&s, 1);
  lt_caustic_options_t o = {LT_METHOD_GRID_PENCIL, 65, 40, 0, NULL, NULL, 0};
  rt_caustic_maps_t maps;
  lt_caustic_stats_t st;
  char why[256];
  assert_int_equal(lt_caustic_maps(&s, &p.caustic, &o, &maps, &st, why, sizeof why), RT_OK);
  rt_plan_t with = p;
  with.maps = &maps;
  const px_vec3_t pts[2] = {px_v3(0.3, 0, 0.2), px_v3(1.6, 0, -0.4)};
  const double expect_with[2] = {0.5 * 0.64, 0.5}, expect_without[2] = {0.5 * 0.8, 0.5};
  for (int k = 0; k < 2; k++) {
    px_vec3_t eye = px_v3(pts[k].x, 3, pts[k].z - 1);
    px_vec3_t d = px_v3_unit(px_v3_sub(pts[k], eye));
    rt_ray_t ray = {eye, d, 0.0, INFINITY, 1.0, -1, 0.0f};
    rt_hit_t hit = {px_v3_norm(px_v3_sub(pts[k], eye)), pts[k], px_v3(0, 1, 0),
                    s.object[0].first_prim, 0};
    rt_surface_t sf;
    rt_shade_surface(&s, &hit, &ray, &sf);
    for (int m = 0; m < 2; m++) {
      const rt_plan_t *pl = m ? &with : &p;
      xr_exact_t ex = xr_exact_make(&s, pl, NULL);
      rt_tracer_t tr = xr_exact_tracer(&ex);
      rt_rgb_t c = rt_shade_direct(&s, pl, &sf, &ray, &tr);
      double e = m ? expect_with[k] : expect_without[k];
      assert_true(fabs(c.r - e) <= 1e-12);
      assert_true(fabs(c.g - e) <= 1e-12);
      assert_true(fabs(c.b - e) <= 1e-12);
    }
  }
  rt_caustic_maps_free(&maps);
  rt_scene_free(&s);
}

/* Render the slab by entry r with the caustic maps by grid-pencils (the same map for both). */
static void render_slab(const rt_scene_t *s, const rn_renderer_t *r, rt_image_t *img,
                        rn_caustic_stats_t *cs) {
  void *opt = malloc(r->options_size);
  void *stats = calloc(1, r->stats_size);
  assert_non_null(opt);
  assert_non_null(stats);
  memcpy(opt, r->defaults, r->options_size);
  rt_plan_t plan = rt_plan_make(s, 4);
  rn_common_t c = RN_COMMON_DEFAULT;
  c.spp_side = 2;
  c.aux = 0;
  c.caustic_method = 1 + LT_METHOD_GRID_PENCIL;
  c.caustic_rays = 65;
  c.caustic_cells = 64;
  assert_int_equal(rt_image_alloc(img, s->camera.width, s->camera.height), RT_OK);
  rn_output_t out = {.image = img, .stats = stats, .caustics = cs};
  assert_int_equal(r->render(s, &plan, &c, opt, &out), RT_OK);
  free(opt);
  free(stats);
}

/* The exact and the pencil renderer with the same map agree within the pencil's brightness
 * tolerance on all but a few edge pixels, and both drew the map's light: the floor seen through
 * the slab (kt^2 of the floor's kd 0.64) is not the textbook's (kt^2 kd 0.8). */
static void renderers_agree_with_maps(void **state) {
  (void)state;
  rt_scene_t s;
  load_slab(&s, down, "");
  rt_image_t a, b;
  rn_caustic_stats_t ca, cb;
  render_slab(&s, rn_find("exact"), &a, &ca);
  render_slab(&s, rn_find("pencil"), &b, &cb);
  assert_int_equal(ca.maps, 1);
  assert_int_equal(cb.maps, 1);
  assert_string_equal(ca.method, "grid-pencil");
  int n = a.width * a.height, big = 0, through = 0;
  double worst = 0.0;
  for (int k = 0; k < n; k++) {
    double d = fabs((double)a.ch[RT_CH_R][k] - b.ch[RT_CH_R][k]);
    worst = fmax(worst, d);
    big += d > 1.0 / 256;
    /* the camera's ray through the slab to the floor under it: 0.64 * 0.5 * 0.64 */
    through += fabs(a.ch[RT_CH_R][k] - 0.64 * 0.5 * 0.64) < 1e-6; /* float pixels */
  }
  print_message("exact vs pencil with one map: worst %.3g, %d of %d pixels over 1/256; %d pixels "
                "show the floor through the slab\n",
                worst, big, n, through);
  assert_true(through >= 100);
  assert_true(big <= n / 50);
  rt_image_free(&a);
  rt_image_free(&b);
  rt_scene_free(&s);
}

/* Under an area light the renderers draw its mesh points' soft light and its caustic map (made
 * with the light's own mesh and the filter): the exact and the pencil renderer agree as with a
 * point light, both made one map of the area light, and its light reaches the floor through
 * the slab (the light is above the slab's middle, so the floor under the slab's middle is lit
 * only through the map: its shadow rays there are opaque). */
static void renderers_agree_under_an_area_light(void **state) {
  (void)state;
  rt_scene_t s;
  load_slab(&s,
            "{\"type\": \"area\", \"center\": [0, 4, 0], \"edge_u\": [0.6, 0, 0], "
            "\"edge_v\": [0, 0, 0.4], \"intensity\": 16, \"samples\": 3}",
            "");
  rt_image_t a, b;
  rn_caustic_stats_t ca, cb;
  render_slab(&s, rn_find("exact"), &a, &ca);
  render_slab(&s, rn_find("pencil"), &b, &cb);
  assert_int_equal(ca.maps, 1);
  assert_int_equal(cb.maps, 1);
  assert_int_equal(ca.empty + cb.empty, 0);
  int n = a.width * a.height, big = 0, lit = 0;
  double worst = 0.0;
  for (int k = 0; k < n; k++) {
    double d = fabs((double)a.ch[RT_CH_R][k] - b.ch[RT_CH_R][k]);
    worst = fmax(worst, d);
    big += d > 1.0 / 256;
    lit += a.ch[RT_CH_R][k] > 0.01;
  }
  print_message("area light: exact vs pencil worst %.3g, %d of %d pixels over 1/256, %d lit\n",
                worst, big, n, lit);
  assert_true(lit > n / 2);
  assert_true(big <= n / 50);
  rt_image_free(&a);
  rt_image_free(&b);
  rt_scene_free(&s);
}

/* A light's map covers the shadows the slab casts from it (lt_light_extent()), which the
 * default square (+-2 around the slab) does not: the ray from the light through the slab's top
 * corner (-1, 1.2, z) meets the floor at x = L + (-1 - L) * h / (h - 1.2) for a light at height
 * h; and with it the light that reaches the floor falls on the map. */
static void map_covers_the_shadows(void **state) {
  (void)state;
  static const struct {
    const char *light;
    double x; /* the far end of the shadow along x */
  } c[] = {
      {"{\"type\": \"point\", \"position\": [6, 2, 0], \"intensity\": 25, \"falloff\": "
       "\"inverse-square\"}",
       6.0 + (-7.0) * 2.0 / 0.8},
      {"{\"type\": \"parallel\", \"direction\": [-3, -1, 0], \"intensity\": 1}", -1.0 - 3.6},
      {"{\"type\": \"area\", \"center\": [4, 2, 0], \"edge_u\": [1, 0, 0], \"edge_v\": "
       "[0, 0, 0.4], \"intensity\": 16, \"samples\": 2}",
       4.5 + (-5.5) * 2.0 / 0.8},
  };
  for (int k = 0; k < 3; k++) {
    rt_scene_t s;
    load_slab(&s, c[k].light, "");
    rt_plan_t p = rt_plan_make(&s, 1);
    assert_true(rt_plan_has(&p, RT_EFFECT_CAUSTICS));
    lt_receiver_t rc;
    char why[256];
    assert_int_equal(
        lt_receiver_make(&s, p.caustic.object[0], p.caustic.nobject[0], &rc, why, sizeof why),
        RT_OK);
    double d[4], e[4];
    assert_true(lt_default_extent(&s, &rc, d));
    assert_true(lt_light_extent(&s, &rc, 0, e));
    print_message("light %d: default u [%.3g, %.3g], the light's [%.3g, %.3g], shadow to %.3g\n", k,
                  d[0], d[1], e[0], e[1], c[k].x);
    assert_true(d[0] > c[k].x);  /* the default misses the shadow's end ... */
    assert_true(e[0] <= c[k].x); /* ... the light's extent has it */
    for (int i = 0; i < 4; i++)  /* and the default square whole */
      assert_true(i % 2 ? e[i] >= d[i] : e[i] <= d[i]);
    lt_caustic_options_t o = {LT_METHOD_GRID_PENCIL, 65, 64, 0, NULL, NULL, 0};
    rt_caustic_maps_t maps;
    lt_caustic_stats_t st;
    assert_int_equal(lt_caustic_maps(&s, &p.caustic, &o, &maps, &st, why, sizeof why), RT_OK);
    const rt_caustic_map_t *m = rt_caustic_map_of(&maps, 0, 0);
    assert_non_null(m);
    assert_true(fabs(m->u0 - e[0]) < 1e-12);
    print_message("light %d: %.3g of the light through the slab fell beside the map\n", k,
                  st.flux_outside);
    /* the point light's 4.9% is light the slab guides inside and sends back out of its near
     * face: it lands at x 7.5 to 8, past the light, in no shadow (exact transport, measured on
     * a map 120 units wide); the default square loses more than half */
    assert_true(st.flux_outside < 0.06);
    lt_map_t dm;
    assert_int_equal(lt_map_alloc(&dm, 64, 64, d[0], d[1], d[2], d[3]), RT_OK);
    lt_options_t lo = LT_OPTIONS_DEFAULT;
    lo.light = 0;
    lo.side = 65;
    lo.indirect = 1;
    lo.area_mesh = s.light[0].samples > 0 ? s.light[0].samples : 1;
    lt_stats_t ls;
    assert_int_equal(lt_illuminance(&s, &rc, &lo, &dm, &ls), RT_OK);
    double lost = ls.flux_outside / (ls.flux_map + ls.flux_outside);
    print_message("light %d: the default square would lose %.3g\n", k, lost);
    assert_true(lost > 0.5);
    lt_map_free(&dm);
    rt_caustic_maps_free(&maps);
    rt_scene_free(&s);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(plan_receivers_and_lights),
      cmocka_unit_test(slab_map_exact),
      cmocka_unit_test(shade_replaces_textbook_shadow),
      cmocka_unit_test(renderers_agree_with_maps),
      cmocka_unit_test(renderers_agree_under_an_area_light),
      cmocka_unit_test(map_covers_the_shadows),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
