/* test_light.c -- illuminance maps (light/): grid-pencil tracing, photon counting and
 * illuminance polygons against the inverse square law on a bare floor, a parallel light's
 * I cos(alpha), a plane mirror's virtual source, the conservation of flux through a glass ball
 * and a glass box, and the refusals of bad arguments. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cmocka_main.h"
#include "io/scene_json.h"
#include "light/illuminance.h"

static void load(const char *json, rt_scene_t *s) {
  char err[512];
  rt_scene_init(s);
  if (io_scene_load_buffer("test.json", json, strlen(json), s, err, sizeof err) != 0)
    fail_msg("%s", err);
}

static const char bare[] =
    "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
    " \"materials\": {\"white\": {\"kd\": 0.8}},"
    " \"lights\": [{\"type\": \"point\", \"position\": [0.3, 2, -0.2], \"intensity\": 1}],"
    " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
    " \"normal\": [0, 1, 0], \"material\": \"white\"}]}";

/* The inverse square law's cell average, I h / r^3 over cell (i, j) by 16 x 16 midpoints; the
 * plane's u is x and v = n x u = -z. */
static double point_cell(const lt_map_t *m, int i, int j, double lx, double ly, double lz) {
  double du = (m->u1 - m->u0) / m->width, dv = (m->v1 - m->v0) / m->height, sum = 0.0;
  for (int a = 0; a < 16; a++)
    for (int b = 0; b < 16; b++) {
      double u = m->u0 + (i + (a + 0.5) / 16) * du, v = m->v0 + (j + (b + 0.5) / 16) * dv;
      double dx = u - lx, dz = -v - lz, r2 = dx * dx + ly * ly + dz * dz;
      sum += ly / (r2 * sqrt(r2));
    }
  return sum / 256.0;
}

/* A bare floor under a parallel light of intensity 2 at 30 degrees from the normal. */
static void load_parallel_floor(rt_scene_t *s) {
  char json[1024];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
           " \"materials\": {\"white\": {\"kd\": 0.8}},"
           " \"lights\": [{\"type\": \"parallel\", \"direction\": [0.5, %.17g, 0], "
           "\"intensity\": 2}],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           " \"normal\": [0, 1, 0], \"material\": \"white\"}]}",
           -sqrt(0.75));
  load(json, s);
}

/* The receiver of object 0 (the floor in every scene here). */
static lt_receiver_t receiver0(const rt_scene_t *s) {
  lt_receiver_t r;
  char why[200];
  const int obj = 0;
  if (lt_receiver_make(s, &obj, 1, &r, why, sizeof why) != RT_OK)
    fail_msg("%s", why);
  return r;
}

static double cell_e(const lt_map_t *m, int i, int j) {
  const double *c = m->e + 3 * ((size_t)j * m->width + i);
  return (c[0] + c[1] + c[2]) / 3.0;
}

/* Grid-pencil tracing follows the inverse square law within 0.5% in every cell (its pencils are
 * flat triangles, so the error is second order in their size); photons with 40 times the rays
 * are far noisier. Both put the same flux on the map. */
static void bare_floor_inverse_square(void **state) {
  (void)state;
  rt_scene_t s;
  load(bare, &s);
  lt_receiver_t floor_rc = receiver0(&s);
  lt_map_t g, p;
  assert_int_equal(lt_map_alloc(&g, 32, 32, -2, 2, -2, 2), RT_OK);
  assert_int_equal(lt_map_alloc(&p, 32, 32, -2, 2, -2, 2), RT_OK);
  lt_options_t o = LT_OPTIONS_DEFAULT;
  lt_stats_t sg, sp;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &g, &sg), RT_OK);
  o.method = LT_METHOD_PHOTONS;
  o.side = 800;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &p, &sp), RT_OK);
  double worst_g = 0.0, worst_p = 0.0;
  for (int j = 0; j < 32; j++)
    for (int i = 0; i < 32; i++) {
      double x = point_cell(&g, i, j, 0.3, 2.0, -0.2);
      worst_g = fmax(worst_g, fabs(cell_e(&g, i, j) - x) / x);
      worst_p = fmax(worst_p, fabs(cell_e(&p, i, j) - x) / x);
    }
  print_message("bare floor: grid-pencil worst %.3e (%llu rays), photons worst %.3e (%llu rays); "
                "flux %.6f, %.6f\n",
                worst_g, (unsigned long long)sg.rays, worst_p, (unsigned long long)sp.rays,
                sg.flux_map, sp.flux_map);
  assert_true(worst_g < 5e-3);
  assert_true(worst_p > worst_g);
  assert_close(sg.flux_map, sp.flux_map, 2e-3, 0.0);
  lt_map_free(&g);
  lt_map_free(&p);
  rt_scene_free(&s);
}

/* A parallel light at 30 degrees from the normal gives I cos(30) everywhere. */
static void parallel_light_cosine(void **state) {
  (void)state;
  rt_scene_t s;
  load_parallel_floor(&s);
  lt_receiver_t floor_rc = receiver0(&s);
  lt_map_t m;
  assert_int_equal(lt_map_alloc(&m, 16, 16, -1, 1, -1, 1), RT_OK);
  lt_options_t o = LT_OPTIONS_DEFAULT;
  o.side = 33;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &m, NULL), RT_OK);
  for (int j = 0; j < 16; j++)
    for (int i = 0; i < 16; i++)
      assert_close(cell_e(&m, i, j), 2.0 * sqrt(0.75), 1e-9, 0.0);
  lt_map_free(&m);
  rt_scene_free(&s);
}

/* A glass ball (kt 1, no reflection) in a vertical beam: every ray reaches the floor but those
 * the ball turns horizontal or upwards near its rim (0.06% of the flux), so the flux on the
 * floor, on the map or beside it, is what the floor absorbs, and with what escapes it is the
 * flux the grid covers. The ball focuses the beam (its focal length nR / 2(n - 1) from its
 * centre puts the focus on the floor). */
static void ball_conserves_flux(void **state) {
  (void)state;
  rt_scene_t s;
  load("{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
       " \"settings\": {\"max_depth\": 6},"
       " \"materials\": {\"white\": {\"kd\": 0.8},"
       "  \"glass\": {\"kd\": 0, \"ka\": 0, \"kr\": 0, \"kt\": 1, \"ior\": 1.5}},"
       " \"lights\": [{\"type\": \"parallel\", \"direction\": [0, -1, 0], \"intensity\": 1}],"
       " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
       " \"normal\": [0, 1, 0], \"material\": \"white\"},"
       " {\"type\": \"sphere\", \"center\": [0, 1.5, 0], \"radius\": 1, \"material\": \"glass\"}]}",
       &s);
  lt_receiver_t floor_rc = receiver0(&s);
  for (int method = 0; method < 2; method++) {
    lt_map_t m;
    assert_int_equal(lt_map_alloc(&m, 64, 64, -2, 2, -2, 2), RT_OK);
    lt_options_t o = LT_OPTIONS_DEFAULT;
    o.method = (lt_method_t)method;
    o.side = method ? 400 : 65;
    lt_stats_t st;
    assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &m, &st), RT_OK);
    double peak = 0.0;
    for (int j = 0; j < 64; j++)
      for (int i = 0; i < 64; i++)
        peak = fmax(peak, cell_e(&m, i, j));
    print_message("%s: flux on the map %.12f + beside %.3e + escaped %.3e of %.12f; absorbed "
                  "%.12f; peak E %.1f\n",
                  lt_method_name(o.method), st.flux_map, st.flux_outside, st.flux_escaped,
                  st.flux_emitted, st.flux_absorbed, peak);
    /* the ledger: every unit of flux escapes or is absorbed (the floor keeps all it gets), to the
     * rounding of sums of one term a ray or more, in an order that depends on the threads'
     * schedule: n u for n terms */
    double tol = 2.0 * (double)st.rays * DBL_EPSILON;
    assert_close(st.flux_escaped + st.flux_absorbed, st.flux_emitted, tol, 0.0);
    assert_close(st.flux_map + st.flux_outside, st.flux_absorbed, tol, 0.0);
    assert_true(st.flux_escaped > 0 && st.flux_escaped < 1e-3 * st.flux_emitted);
    assert_true(peak > 50.0); /* the focus */
    assert_int_equal(st.lost, 0);
    lt_map_free(&m);
  }
  rt_scene_free(&s);
}

/* Illuminance polygons on the bare floor (an unbounded plane face): the beams before any face
 * are exact central projections and E is Eq. (8) Gouraud-interpolated within a quarter of
 * --uniform-tol, so every cell is within 1% (the target; about 0.5% measured) of the
 * inverse square law, and within 0.3% at half the tolerance; on a parallel light's floor E is
 * I cos(alpha) to rounding. */
static void polygons_inverse_square_and_cosine(void **state) {
  (void)state;
  rt_scene_t s;
  load(bare, &s);
  lt_receiver_t floor_rc = receiver0(&s);
  lt_map_t g;
  assert_int_equal(lt_map_alloc(&g, 32, 32, -2, 2, -2, 2), RT_OK);
  lt_options_t o = LT_OPTIONS_DEFAULT;
  o.method = LT_METHOD_POLYGONS;
  lt_stats_t st;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &g, &st), RT_OK);
  double worst = 0.0;
  for (int j = 0; j < 32; j++)
    for (int i = 0; i < 32; i++) {
      double x = point_cell(&g, i, j, 0.3, 2.0, -0.2);
      worst = fmax(worst, fabs(cell_e(&g, i, j) - x) / x);
    }
  print_message("bare floor by polygons: worst %.3e, %llu pencils, %llu divisions\n", worst,
                (unsigned long long)st.pencils, (unsigned long long)st.divided);
  assert_true(worst < 1e-2);
  assert_true(st.pencils > 0);
  o.uniform_tol = 0.01;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &g, &st), RT_OK);
  double worst_half = 0.0;
  for (int j = 0; j < 32; j++)
    for (int i = 0; i < 32; i++) {
      double x = point_cell(&g, i, j, 0.3, 2.0, -0.2);
      worst_half = fmax(worst_half, fabs(cell_e(&g, i, j) - x) / x);
    }
  print_message("... at --uniform-tol 0.01: worst %.3e\n", worst_half);
  assert_true(worst_half < 3e-3);
  o.uniform_tol = 0.02;
  lt_map_free(&g);
  rt_scene_free(&s);
  load_parallel_floor(&s);
  floor_rc = receiver0(&s);
  assert_int_equal(lt_map_alloc(&g, 16, 16, -1, 1, -1, 1), RT_OK);
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &g, NULL), RT_OK);
  for (int j = 0; j < 16; j++)
    for (int i = 0; i < 16; i++)
      assert_close(cell_e(&g, i, j), 2.0 * sqrt(0.75), 1e-9, 0.0);
  lt_map_free(&g);
  rt_scene_free(&s);
}

/* A plane mirror (a polygon in x = 1) beside the light: the floor at x < 1 gets the light
 * directly and from the light's mirror image at x = 1.7, each by the inverse square law. Both
 * pencil methods within 1% of that in every cell: illuminance polygons through one reflection
 * (a path of one face), and grid-pencil tracing. */
static void mirror_virtual_source(void **state) {
  (void)state;
  rt_scene_t s;
  load("{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
       " \"materials\": {\"white\": {\"kd\": 0.8},"
       "  \"mirror\": {\"kd\": 0, \"ka\": 0, \"kr\": 1}},"
       " \"lights\": [{\"type\": \"point\", \"position\": [0.3, 2, -0.2], \"intensity\": 1}],"
       " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
       " \"normal\": [0, 1, 0], \"material\": \"white\"},"
       " {\"type\": \"polygon\", \"name\": \"mirror\", \"material\": \"mirror\","
       " \"vertices\": [[1, 0, -3], [1, 3, -3], [1, 3, 3], [1, 0, 3]]}]}",
       &s);
  lt_receiver_t floor_rc = receiver0(&s);
  for (int method = 0; method < 3; method += 2) {
    lt_map_t g;
    assert_int_equal(lt_map_alloc(&g, 24, 32, -2, 1, -2, 2), RT_OK);
    lt_options_t o = LT_OPTIONS_DEFAULT;
    o.method = (lt_method_t)method;
    lt_stats_t st;
    assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &g, &st), RT_OK);
    double worst = 0.0;
    for (int j = 0; j < 32; j++)
      for (int i = 0; i < 24; i++) {
        double x = point_cell(&g, i, j, 0.3, 2.0, -0.2) + point_cell(&g, i, j, 1.7, 2.0, -0.2);
        worst = fmax(worst, fabs(cell_e(&g, i, j) - x) / x);
      }
    print_message("mirror by %s: worst %.3e, %llu rays\n", lt_method_name(o.method), worst,
                  (unsigned long long)st.rays);
    assert_true(worst < 1e-2);
    lt_map_free(&g);
  }
  rt_scene_free(&s);
}

/* A glass box (a polyhedron: kr 0.1, kt 0.85) over the floor: illuminance polygons keep the
 * flux ledger (what escapes and what surfaces keep is what the light's grid covers) and put the
 * same flux on the map as grid-pencil tracing. */
static void polygons_glass_box_ledger(void **state) {
  (void)state;
  rt_scene_t s;
  load("{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
       " \"settings\": {\"max_depth\": 4},"
       " \"materials\": {\"white\": {\"kd\": 0.8},"
       "  \"glass\": {\"kd\": 0, \"ka\": 0, \"kr\": 0.1, \"kt\": 0.85, \"ior\": 1.5}},"
       " \"lights\": [{\"type\": \"point\", \"position\": [0.3, 6, -0.2], \"intensity\": 1}],"
       " \"objects\": [{\"type\": \"polygon\", \"name\": \"floor\", \"material\": \"white\","
       " \"vertices\": [[-3, 0, -3], [3, 0, -3], [3, 0, 3], [-3, 0, 3]]},"
       " {\"type\": \"polyhedron\", \"material\": \"glass\","
       " \"vertices\": [[-0.5, 1, -0.5], [0.5, 1, -0.5], [0.5, 1, 0.5], [-0.5, 1, 0.5],"
       "  [-0.5, 2, -0.5], [0.5, 2, -0.5], [0.5, 2, 0.5], [-0.5, 2, 0.5]],"
       " \"faces\": [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6],"
       "  [3, 0, 4, 7]]}]}",
       &s);
  lt_receiver_t floor_rc = receiver0(&s);
  lt_map_t p, g;
  assert_int_equal(lt_map_alloc(&p, 64, 64, 0, 6, 0, 6), RT_OK);
  assert_int_equal(lt_map_alloc(&g, 64, 64, 0, 6, 0, 6), RT_OK);
  lt_options_t o = LT_OPTIONS_DEFAULT;
  lt_stats_t sp, sg;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &g, &sg), RT_OK);
  o.method = LT_METHOD_POLYGONS;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &p, &sp), RT_OK);
  print_message("glass box: polygons flux on the map %.9f (%llu pencils, %llu photons), "
                "grid-pencil %.9f; ledger %.3e\n",
                sp.flux_map, (unsigned long long)sp.pencils, (unsigned long long)sp.photons,
                sg.flux_map, sp.flux_escaped + sp.flux_absorbed - sp.flux_emitted);
  assert_close(sp.flux_escaped + sp.flux_absorbed, sp.flux_emitted, 1e-8 * sp.flux_emitted, 0.0);
  assert_close(sp.flux_map, sg.flux_map, 5e-3 * sg.flux_map, 0.0);
  assert_true(sp.pencils > 0 && sp.lost == 0);
  for (int k = 0; k < 3 * 64 * 64; k++)
    assert_true(isfinite(p.e[k]) && p.e[k] >= 0.0);
  lt_map_free(&p);
  lt_map_free(&g);
  rt_scene_free(&s);
}

/* E under a Lambertian rectangle of radiance L parallel to the floor at height h, by the
 * configuration factor of a parallel rectangle with a corner above the point: for the corner at
 * (a, b) from the point, G = (1/2)[a/sqrt(a^2+h^2) atan(b/sqrt(a^2+h^2)) + b/sqrt(b^2+h^2)
 * atan(a/sqrt(b^2+h^2))], odd in a and b, so that the rectangle [x1, x2] x [z1, z2] gives
 * L (G(x2, z2) - G(x1, z2) - G(x2, z1) + G(x1, z1)). */
static double rect_g(double a, double b, double h) {
  double ra = sqrt(a * a + h * h), rb = sqrt(b * b + h * h);
  return 0.5 * (a / ra * atan(b / ra) + b / rb * atan(a / rb));
}

/* The area light of area_light(): centre (0.2, 2, -0.1), edges 1.2 along x and 0.8 along z,
 * facing down, I0 = 3. */
#define AREA_CX 0.2
#define AREA_CZ (-0.1)
#define AREA_H 2.0
#define AREA_W 1.2
#define AREA_D 0.8
#define AREA_I0 3.0

/* A bare floor under the area light above. */
static void load_area_floor(rt_scene_t *s) {
  char json[1024];
  snprintf(json, sizeof json,
           "{\"camera\": {\"eye\": [0, 3, -6], \"look_at\": [0, 0, 0]},"
           " \"materials\": {\"white\": {\"kd\": 0.8}},"
           " \"lights\": [{\"type\": \"area\", \"center\": [%g, %g, %g], \"edge_u\": [%g, 0, 0],"
           " \"edge_v\": [0, 0, %g], \"intensity\": %g}],"
           " \"objects\": [{\"type\": \"plane\", \"name\": \"floor\", \"point\": [0, 0, 0],"
           " \"normal\": [0, 1, 0], \"material\": \"white\"}]}",
           AREA_CX, AREA_H, AREA_CZ, AREA_W, AREA_D, AREA_I0);
  load(json, s);
}

static double rect_e(double x, double z) {
  double L = AREA_I0 / (AREA_W * AREA_D);
  double x1 = AREA_CX - AREA_W / 2 - x, x2 = AREA_CX + AREA_W / 2 - x;
  double z1 = AREA_CZ - AREA_D / 2 - z, z2 = AREA_CZ + AREA_D / 2 - z;
  return L * (rect_g(x2, z2, AREA_H) - rect_g(x1, z2, AREA_H) - rect_g(x2, z1, AREA_H) +
              rect_g(x1, z1, AREA_H));
}

/* The same light as mesh x mesh Lambertian point sources at the mesh cells' centres. */
static double mesh_e(double x, double z, int mesh) {
  double sum = 0.0;
  for (int j = 0; j < mesh; j++)
    for (int i = 0; i < mesh; i++) {
      double px = AREA_CX + ((i + 0.5) / mesh - 0.5) * AREA_W - x;
      double pz = AREA_CZ + ((j + 0.5) / mesh - 0.5) * AREA_D - z;
      double r2 = px * px + pz * pz + AREA_H * AREA_H, c = AREA_H / sqrt(r2);
      sum += AREA_I0 / ((double)mesh * mesh) * c * c / r2; /* cos at the source and the floor */
    }
  return sum;
}

/* The cell average of f over cell (i, j) of m by 4 x 4 midpoints (u = x, v = -z). */
static double cell_avg(const lt_map_t *m, int i, int j, double (*f)(double, double, int),
                       int mesh) {
  double du = (m->u1 - m->u0) / m->width, dv = (m->v1 - m->v0) / m->height, sum = 0.0;
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 4; b++)
      sum += f(m->u0 + (i + (a + 0.5) / 4) * du, -(m->v0 + (j + (b + 0.5) / 4) * dv), mesh);
  return sum / 16.0;
}

static double rect_e3(double x, double z, int mesh) {
  (void)mesh;
  return rect_e(x, z);
}

/* An area light (1989 section 2.3) over a bare floor: traced as mesh x mesh Lambertian point
 * sources, the grid-pencil map agrees with the midpoint rule's sum of their inverse-square and
 * cosine laws in every cell to 0.5% (the tracing's own error), and that sum approaches the
 * rectangle's exact configuration-factor illuminance as the mesh grows (the mesh's error, second
 * order: a quarter at twice the mesh). */
static void area_light_lambertian_rectangle(void **state) {
  (void)state;
  rt_scene_t s;
  load_area_floor(&s);
  assert_int_equal(s.light[0].kind, RT_LIGHT_AREA);
  assert_int_equal(s.light[0].falloff, RT_FALLOFF_INVERSE_SQUARE);
  lt_receiver_t rc = receiver0(&s);
  double mesh_err[4];
  for (int k = 0; k < 4; k++) {
    int mesh = 1 << k; /* 1, 2, 4, 8 */
    lt_map_t m;
    assert_int_equal(lt_map_alloc(&m, 24, 24, -2, 2, -2, 2), RT_OK);
    lt_options_t o = LT_OPTIONS_DEFAULT;
    o.side = 33;
    o.area_mesh = mesh;
    lt_stats_t st;
    assert_int_equal(lt_illuminance(&s, &rc, &o, &m, &st), RT_OK);
    double trace = 0.0, err = 0.0;
    for (int j = 0; j < m.height; j++)
      for (int i = 0; i < m.width; i++) {
        double want = cell_avg(&m, i, j, mesh_e, mesh), exact = cell_avg(&m, i, j, rect_e3, 0);
        trace = fmax(trace, fabs(cell_e(&m, i, j) / want - 1.0));
        err = fmax(err, fabs(want / exact - 1.0));
      }
    mesh_err[k] = err;
    print_message("area light as %d x %d point sources: map vs their sum %.2e, their sum vs the "
                  "rectangle %.2e (%llu rays)\n",
                  mesh, mesh, trace, err, (unsigned long long)st.rays);
    assert_true(trace <= 5e-3);
    lt_map_free(&m);
  }
  for (int k = 1; k < 4; k++) /* second order: about a quarter at each doubling */
    assert_true(mesh_err[k] < 0.35 * mesh_err[k - 1]);
  assert_true(mesh_err[3] < 5e-3);
  /* the polygons method takes point and parallel lights only: refused with the reason */
  char why[256];
  assert_int_equal(lt_method_check(&s, LT_METHOD_POLYGONS, why, sizeof why), RT_EINVAL);
  assert_non_null(strstr(why, "area light"));
  rt_scene_free(&s);
}

/* The 1989 paper's space-variant filter (Eqs. 9-12) on a bare floor, where it is exact: a mesh
 * point's pattern moves rigidly with it, so spreading each pencil over its mesh cell's shifts
 * gives the cell's light. With 1 x 1 and 2 x 2 meshes of the light of
 * area_light_lambertian_rectangle(), the filtered map is within 0.5% of the rectangle's exact
 * illuminance wherever the spread cannot reach past the map's border (the faces cover the map,
 * so light spread in from beyond it is missing), while the plain mesh sums are off by 8.5% and
 * 1.9% there; so with the displacement quadratic over the mesh cell and linear (the printed
 * Eq. 10: on a bare floor the landing is linear in the source's position, and they agree). */
static void area_filter_exact_on_a_bare_floor(void **state) {
  (void)state;
  rt_scene_t s;
  load_area_floor(&s);
  lt_receiver_t rc = receiver0(&s);
  for (int mesh = 1; mesh <= 2; mesh++) {
    double worst[3] = {0, 0, 0};
    static const int forms[3] = {LT_AREA_FILTER_NONE, LT_AREA_FILTER_QUADRATIC,
                                 LT_AREA_FILTER_LINEAR};
    for (int filter = 0; filter < 3; filter++) {
      lt_map_t m;
      assert_int_equal(lt_map_alloc(&m, 24, 24, -2, 2, -2, 2), RT_OK);
      lt_options_t o = LT_OPTIONS_DEFAULT;
      o.side = 33;
      o.area_mesh = mesh;
      o.area_filter = forms[filter];
      lt_stats_t st;
      assert_int_equal(lt_illuminance(&s, &rc, &o, &m, &st), RT_OK);
      assert_true(filter ? st.filtered > 0 && st.unshifted == 0 && st.resampled == 0
                         : st.filtered == 0);
      double reach_u = AREA_W / mesh / 2 + 0.2, reach_v = AREA_D / mesh / 2 + 0.2;
      for (int j = 0; j < m.height; j++)
        for (int i = 0; i < m.width; i++) {
          double u0 = m.u0 + i * (m.u1 - m.u0) / m.width, v0 = m.v0 + j * (m.v1 - m.v0) / m.height;
          double u1 = u0 + (m.u1 - m.u0) / m.width, v1 = v0 + (m.v1 - m.v0) / m.height;
          if (u0 < m.u0 + reach_u || u1 > m.u1 - reach_u || v0 < m.v0 + reach_v ||
              v1 > m.v1 - reach_v)
            continue; /* the spread from beyond the border would reach it */
          worst[filter] =
              fmax(worst[filter], fabs(cell_e(&m, i, j) / cell_avg(&m, i, j, rect_e3, 0) - 1.0));
        }
      lt_map_free(&m);
    }
    print_message("%d x %d mesh: worst interior cell off the rectangle %.2e plain, %.2e filtered "
                  "(quadratic), %.2e (linear)\n",
                  mesh, mesh, worst[0], worst[1], worst[2]);
    for (int filter = 1; filter < 3; filter++) {
      assert_true(worst[filter] <= 5e-3);
      assert_true(worst[filter] < 0.25 * worst[0]);
    }
  }
  rt_scene_free(&s);
}

static void bad_arguments_refused(void **state) {
  (void)state;
  rt_scene_t s;
  load(bare, &s);
  lt_receiver_t floor_rc = receiver0(&s);
  lt_map_t m;
  lt_options_t o = LT_OPTIONS_DEFAULT;
  assert_int_equal(lt_map_alloc(&m, 0, 4, 0, 1, 0, 1), RT_EINVAL);
  assert_int_equal(lt_map_alloc(&m, 4, 4, 0, 0, 0, 1), RT_EINVAL);
  assert_int_equal(lt_map_alloc(&m, LT_MAX_GRID + 1, 4, 0, 1, 0, 1), RT_EINVAL);
  assert_int_equal(lt_map_alloc(&m, 4, 4, 0, 1, 0, 1), RT_OK);
  rt_scene_t empty; /* not prepared (the loader prepares what it loads) */
  rt_scene_init(&empty);
  assert_int_equal(lt_illuminance(&empty, &floor_rc, &o, &m, NULL), RT_ENOTREADY);
  rt_scene_free(&empty);
  char why[200];
  const int sphere_obj[2] = {0, 1};
  lt_receiver_t none;
  assert_int_equal(lt_receiver_make(&s, sphere_obj + 1, 1, &none, why, sizeof why), RT_EINVAL);
  assert_int_equal(lt_receiver_make(&s, sphere_obj, 0, &none, why, sizeof why), RT_EINVAL);
  o.light = 1;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &m, NULL), RT_EINVAL);
  o = (lt_options_t)LT_OPTIONS_DEFAULT;
  o.side = 1;
  assert_int_equal(lt_illuminance(&s, &floor_rc, &o, &m, NULL), RT_EINVAL);
  assert_int_equal(lt_method_parse("polygons"), LT_METHOD_POLYGONS);
  assert_int_equal(lt_method_parse("beams"), -1);
  assert_int_equal(lt_method_parse("photons"), LT_METHOD_PHOTONS);
  lt_map_free(&m);
  rt_scene_free(&s);
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(bare_floor_inverse_square),
      cmocka_unit_test(parallel_light_cosine),
      cmocka_unit_test(ball_conserves_flux),
      cmocka_unit_test(polygons_inverse_square_and_cosine),
      cmocka_unit_test(mirror_virtual_source),
      cmocka_unit_test(polygons_glass_box_ledger),
      cmocka_unit_test(area_light_lambertian_rectangle),
      cmocka_unit_test(area_filter_exact_on_a_bare_floor),
      cmocka_unit_test(bad_arguments_refused),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
