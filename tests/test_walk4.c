/* test_walk4.c -- the four-lane walk functions (libparaxial's px_interface_outgoing4(), core's
 * rt_shade_walk_ray4() and rt_prim_intersect4()) against their scalar functions lane by lane, bit
 * for bit: the pencil renderer's exact walks carry groups of samples with them and must give the
 * rays a walk of one sample gives. On a CPU without AVX2 and FMA the four-lane functions take the
 * lanes one by one through the scalar functions; the comparisons then hold trivially, and the
 * first case says so. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cmocka_main.h"
#include "core/intersect.h"
#include "core/shade_paths.h"
#include "paraxial/system.h"
#include "paraxial/vec3.h"
#include "render/render.h"

/* splitmix64: a deterministic stream of doubles in [0, 1) */
static uint64_t rng_state = 0x9e3779b97f4a7c15u;
static double uniform(void) {
  uint64_t z = (rng_state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1p-53;
}

static px_vec3_t random_unit(void) {
  for (;;) {
    px_vec3_t v = px_vec3(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
    double n = px_vec3_norm(v);
    if (n > 0.1 && n <= 1.0)
      return px_vec3_scale(v, 1.0 / n);
  }
}

static void put(px_vec3x4_t *v, int i, px_vec3_t a) {
  v->x[i] = a.x, v->y[i] = a.y, v->z[i] = a.z;
}

static px_vec3_t get(const px_vec3x4_t *v, int i) {
  return px_vec3(v->x[i], v->y[i], v->z[i]);
}

/* A direction at angle theta (cos c) from the unit normal nu. */
static px_vec3_t at_angle(px_vec3_t nu, double c) {
  px_vec3_t t = px_vec3_cross(nu, random_unit());
  px_vec3_normalize(t, &t);
  return px_vec3_add(px_vec3_scale(nu, c), px_vec3_scale(t, sqrt(fmax(0.0, 1.0 - c * c))));
}

/* px_interface_outgoing4() is px_interface_outgoing() in each lane: ordinary refractions,
 * total internal reflection, refractions near grazing with n1 ~ n2 (the compensated form, which
 * the four-lane function leaves to the scalar one), n1 = n2, reflections, a zero direction
 * (PX_ENONFINITE for a mirror) and lanes not asked for, mixed in one call. */
static void snell_of_four_is_snell_of_each(void **state) {
  (void)state;
  if (!px_simd4_available())
    fprintf(stderr, "note: no AVX2 and FMA here: the four-lane functions take the lanes one by "
                    "one, and these comparisons hold trivially\n");
  int seen[3] = {0, 0, 0}; /* OK near grazing with n1 ~ n2, PX_ETIR, PX_ENONFINITE */
  int compared = 0;
  for (int rep = 0; rep < 20000; rep++) {
    px_event_t ev = rep % 5 == 4 ? PX_EVENT_REFLECT : PX_EVENT_REFRACT;
    px_vec3x4_t s, nu, out;
    double n1[4], n2[4];
    unsigned lanes = rep % 7 == 3 ? 0xbu : 0xfu;
    px_status_t st[4];
    for (int i = 0; i < 4; i++) {
      px_vec3_t n = random_unit();
      int kind = (rep + i) % 5;
      double c = uniform();
      n1[i] = 1.0;
      n2[i] = 1.5;
      if (kind == 1) { /* leaving glass: total internal reflection beyond 41.8 degrees */
        n1[i] = 1.5;
        n2[i] = 1.0;
      } else if (kind == 2) { /* near grazing, indices a hair apart either way */
        c = 0.25 * uniform() * uniform();
        n2[i] = 1.0 + (uniform() - 0.5) * 1e-3;
      } else if (kind == 3) { /* equal indices near grazing */
        c = 0.01 * uniform();
        n1[i] = n2[i] = 1.33;
      }
      put(&s, i, at_angle(n, c));
      put(&nu, i, n);
      if (kind == 4 && ev == PX_EVENT_REFLECT && rep % 3 == 0)
        put(&s, i, px_vec3(0, 0, 0));
    }
    memset(&out, 0x5a, sizeof out);
    px_interface_outgoing4(ev, &s, &nu, n1, n2, lanes, &out, st);
    for (int i = 0; i < 4; i++) {
      if (!(lanes & (1u << i))) {
        assert_int_equal(st[i], PX_EINVAL);
        continue;
      }
      px_interface_t f = {.s = get(&s, i), .nu = get(&nu, i), .n1 = n1[i], .n2 = n2[i]};
      px_vec3_t o;
      double co;
      px_status_t want = px_interface_outgoing(&f, ev, &o, &co);
      assert_int_equal(st[i], want);
      if (want == PX_OK) {
        px_vec3_t g = get(&out, i);
        assert_memory_equal(&g, &o, sizeof g);
        compared++;
        double es = n1[i] / n2[i] * px_vec3_norm(px_vec3_cross(f.nu, f.s));
        seen[0] += ev == PX_EVENT_REFRACT && es > 15.0 / 16.0 && px_vec3_dot(f.nu, f.s) < 0.25;
      }
      seen[1] += want == PX_ETIR;
      seen[2] += want == PX_ENONFINITE;
    }
  }
  assert_true(compared > 40000);
  assert_true(seen[0] > 1000 && seen[1] > 1000 && seen[2] > 100);
}

static int add_mat(rt_scene_t *s, const char *name, double kr, double kt, double ior, int fresnel) {
  rt_material_t m = rt_material_default(name);
  m.kr = kr;
  m.kt = kt;
  m.ior = ior;
  m.fresnel = fresnel;
  int i;
  assert_int_equal(rt_scene_add_material(s, &m, &i), RT_OK);
  return i;
}

/* A scene of every primitive kind: a glass ball, a glass polygon, a tilted glass plane of one
 * material and a mirror checkerboard whose other squares are clear glass (a material per lane:
 * rt_shade_walk_ray4() takes its lanes one by one), in a medium of index 1.1. */
static void walk_scene(rt_scene_t *s) {
  rt_scene_init(s);
  s->ior = 1.1;
  int gi = add_mat(s, "glass", 0.1, 0.8, 1.5, 1), mi = add_mat(s, "mirror", 0.7, 0.0, 1.0, 0),
      ci = add_mat(s, "clear", 0.0, 0.9, 1.3, 0);
  rt_scene_add_sphere(s, px_vec3(0, 0, 0), 1.0, gi, NULL);
  rt_scene_add_plane(s, px_vec3(0, -3, 0), px_vec3(0, 1, 0), px_vec3(1, 0, 0), mi, ci, 0.5, NULL);
  /* tilted, off the origin: its n.p sums products (which a contracting compiler would fuse) */
  rt_scene_add_plane(s, px_vec3(5, 0.7, -0.3), px_vec3(-0.95, 0.3, 0.17), px_vec3(0.3, 0.95, 0), gi,
                     -1, 1, NULL);
  const px_vec3_t quad[4] = {px_vec3(-4, -2, 3), px_vec3(4, -2, 3), px_vec3(4, 4, 3),
                             px_vec3(-4, 4, 3)};
  assert_int_equal(rt_scene_add_polygon(s, quad, 4, gi, NULL), RT_OK);
  assert_int_equal(rt_scene_prepare(s), RT_OK);
}

/* Rays from outside towards the ball, the polygon, the planes, and from inside the ball all round
 * (index 1.5): directions about an aim on a Fibonacci sphere, as test_render_shade.c's. */
static int walk_rays(rt_ray_t *rays, int cap) {
  const px_vec3_t from[5] = {px_vec3(0.2, 0.5, -5), px_vec3(1.5, 3, 6), px_vec3(3, 2, -2),
                             px_vec3(0.8, 0.1, 0.2), px_vec3(2, 0, -1)};
  const px_vec3_t aim[5] = {px_vec3(0, 0, 0), px_vec3(0.5, 1, 3), px_vec3(3, -3, 0),
                            px_vec3(0.8, 0.1, 0.2), px_vec3(5, 0.5, 0)};
  const double spread[5] = {0.3, 0.5, 0.5, 1.0, 0.5}, ior[5] = {1.1, 1.1, 1.1, 1.5, 1.1};
  int n = 0;
  for (int o = 0; o < 5; o++)
    for (int j = 0; j < 400 && n < cap; j++) {
      double z = 1.0 - (j + 0.5) / 200.0, rho = sqrt(1.0 - z * z), phi = 2.399963229728653 * j;
      px_vec3_t u = px_vec3(rho * cos(phi), rho * sin(phi), z), to = px_vec3_sub(aim[o], from[o]);
      if (o == 3)
        to = px_vec3(0, 0, 0);
      else
        px_vec3_normalize(to, &to);
      rt_ray_t r = {from[o], px_vec3(0, 0, 1), 0.0, INFINITY, ior[o], -1, 0.0f};
      if (px_vec3_normalize(px_vec3_add(to, px_vec3_scale(u, spread[o])), &r.d) == PX_OK)
        rays[n++] = r;
    }
  return n;
}

/* rt_shade_walk_ray4() gives each lane what rt_shade_walk_ray() gives it (1 with the same ray, 0,
 * or -1), and 0 in a lane not asked for: the hits of the rays above grouped by primitive four at
 * a time, under plans with and without reflection and refraction, from the first generation to
 * beyond the last. */
static void walk_of_four_is_walk_of_each(void **state) {
  (void)state;
  rt_scene_t s;
  walk_scene(&s);
  rt_plan_t plans[3] = {rt_plan_make(&s, 1), rt_plan_make(&s, 1), rt_plan_make(&s, 1)};
  plans[1].on &= ~(1u << RT_EFFECT_REFRACTION);
  plans[2].on &= ~(1u << RT_EFFECT_REFLECTION);
  static rt_ray_t rays[2000];
  int nr = walk_rays(rays, 2000);
  int seen[3] = {0, 0, 0}, per_prim[8] = {0}; /* lanes returning 0, 1, -1; rays by primitive */
  for (int prim = 0; prim < s.nprim; prim++) {
    /* the hits on this primitive, in groups of four */
    px_vec3x4_t p, d;
    double ior[4];
    int k = 0;
    for (int i = 0; i < nr; i++) {
      rt_hit_t h;
      if (!rt_intersect(&s, &rays[i], &h) || h.prim != prim)
        continue;
      put(&p, k, h.p);
      put(&d, k, rays[i].d);
      ior[k] = rays[i].ior;
      per_prim[prim < 8 ? prim : 7]++;
      if (++k < 4)
        continue;
      k = 0;
      unsigned lanes = i % 3 ? 0xfu : 0x6u;
      for (int pl = 0; pl < 3; pl++)
        for (int dd = 0; dd < 3; dd++) {
          int depth = dd ? plans[pl].max_depth - 2 + dd : 0;
          for (int kind = RT_RAY_PRIMARY; kind <= RT_RAY_SHADOW; kind++) {
            rt_ray4_t out;
            int got[4];
            memset(&out, 0xa5, sizeof out);
            rt_shade_walk_ray4(&s, &plans[pl], prim, &p, &d, ior, depth, kind, lanes, &out, got);
            for (int l = 0; l < 4; l++) {
              if (!(lanes & (1u << l))) {
                assert_int_equal(got[l], 0);
                continue;
              }
              rt_ray_t w;
              int want = rt_shade_walk_ray(&s, &plans[pl], prim, get(&p, l), get(&d, l), ior[l],
                                           depth, kind, &w);
              assert_int_equal(got[l], want);
              seen[want < 0 ? 2 : want]++;
              if (want != 1)
                continue;
              px_vec3_t o = get(&out.o, l), dir = get(&out.d, l);
              assert_memory_equal(&o, &w.o, sizeof o);
              assert_memory_equal(&dir, &w.d, sizeof dir);
              assert_memory_equal(&out.ior[l], &w.ior, sizeof w.ior);
              assert_int_equal(out.skip_prim, w.skip_prim);
              assert_true(w.tmin == 0.0 && w.tmax == INFINITY && w.lambda == 0.0f);
            }
          }
        }
    }
  }
  for (int prim = 0; prim < s.nprim; prim++)
    if (per_prim[prim] < 8)
      fail_msg("primitive %d: %d hits", prim, per_prim[prim]);
  assert_true(seen[0] > 0 && seen[1] > 0 && seen[2] > 0);
  rt_scene_free(&s);
}

/* rt_prim_intersect4() gives each lane rt_prim_intersect()'s answer, distance and point bit for
 * bit: the walks' child rays (starting on the surfaces they leave) and a ray parallel to each
 * plane, against every primitive. */
static void intersections_of_four_are_those_of_each(void **state) {
  (void)state;
  rt_scene_t s;
  walk_scene(&s);
  rt_plan_t plan = rt_plan_make(&s, 1);
  static rt_ray_t rays[2000], kids[4002];
  int nr = walk_rays(rays, 2000), nk = 0;
  for (int i = 0; i < nr; i++) {
    rt_hit_t h;
    if (!rt_intersect(&s, &rays[i], &h))
      continue;
    for (int kind = RT_RAY_REFLECT; kind <= RT_RAY_REFRACT; kind++)
      if (rt_shade_walk_ray(&s, &plan, h.prim, h.p, rays[i].d, rays[i].ior, 0, kind, &kids[nk]) ==
          1)
        nk++;
  }
  kids[nk++] = (rt_ray_t){px_vec3(0.5, 1, -2), px_vec3(1, 0, 0), 0.0, INFINITY, 1.1, -1, 0.0f};
  kids[nk++] = (rt_ray_t){px_vec3(0.5, 1, 2), px_vec3(0, 1, 0), 0.0, INFINITY, 1.1, -1, 0.0f};
  int hits = 0, misses = 0;
  for (int prim = 0; prim < s.nprim; prim++)
    for (int i = 0; i < nk; i += 4) {
      px_vec3x4_t o, d, at;
      double t[4];
      unsigned lanes = 0;
      for (int l = 0; l < 4 && i + l < nk; l++) {
        put(&o, l, kids[i + l].o);
        put(&d, l, kids[i + l].d);
        lanes |= (i / 4) % 5 == 2 && l == 1 ? 0u : 1u << l;
      }
      unsigned hit = rt_prim_intersect4(&s, prim, &o, &d, lanes, t, &at);
      for (int l = 0; l < 4; l++) {
        if (!(lanes & (1u << l))) {
          assert_false(hit & (1u << l));
          continue;
        }
        double want_t;
        int want = rt_prim_intersect(&s, prim, &kids[i + l], INFINITY, &want_t);
        assert_int_equal((hit >> l) & 1u, want);
        if (!want) {
          misses++;
          continue;
        }
        hits++;
        px_vec3_t q = px_v3_axpy(want_t, kids[i + l].d, kids[i + l].o), g = get(&at, l);
        assert_memory_equal(&t[l], &want_t, sizeof want_t);
        assert_memory_equal(&g, &q, sizeof g);
      }
    }
  assert_true(hits > 500 && misses > 500);
  rt_scene_free(&s);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(snell_of_four_is_snell_of_each),
      cmocka_unit_test(walk_of_four_is_walk_of_each),
      cmocka_unit_test(intersections_of_four_are_those_of_each),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
