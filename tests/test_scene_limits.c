/* test_scene_limits.c -- the scene loader's limit on primitives (io/src/parse.h,
 * IO_MAX_PRIMITIVES), with the loader built here with a limit of 64 so that the scenes that
 * pass it stay small (the real limit, 2^24, would take gigabytes to reach). A scene that would
 * pass the limit is refused at the object that passes it, naming it, before that object is
 * built; one at the limit loads. */
#include <stdio.h>
#include <string.h>

#include "cmocka_main.h"
#include "io/scene_json.h"

#define HEAD                                                                                       \
  "{\"camera\": {\"eye\": [0, 0, -5], \"look_at\": [0, 0, 0]},"                                    \
  " \"materials\": {\"m\": {\"kd\": 0.5}}, \"objects\": ["

/* Loads "HEAD objects ]}" from memory: 0 and the error in err, or 1 with the primitive count. */
static int load(const char *objects, char *err, size_t cap, int *nprim) {
  char buf[65536];
  snprintf(buf, sizeof buf, "%s%s]}", HEAD, objects);
  rt_scene_t s;
  rt_scene_init(&s);
  int rc = io_scene_load_buffer("limits.json", buf, strlen(buf), &s, err, cap);
  *nprim = s.nprim;
  rt_scene_free(&s);
  return rc == 0;
}

/* n objects of the given JSON, comma-separated, into out. */
static void repeat(const char *obj, int n, char *out, size_t cap) {
  out[0] = 0;
  for (int i = 0; i < n; i++) {
    strncat(out, i ? ", " : "", cap - strlen(out) - 1);
    strncat(out, obj, cap - strlen(out) - 1);
  }
}

static void spheres_up_to_the_limit(void **state) {
  (void)state;
  assert_int_equal(IO_MAX_PRIMITIVES, 64);
  char objs[16384], err[512];
  int n;
  const char *ball = "{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
                     "\"material\": \"m\"}";
  repeat(ball, 64, objs, sizeof objs);
  assert_true(load(objs, err, sizeof err, &n));
  assert_int_equal(n, 64);
  repeat(ball, 65, objs, sizeof objs);
  assert_false(load(objs, err, sizeof err, &n));
  print_message("%s\n", err);
  assert_non_null(strstr(err, "objects[64]: the scene has 64 primitives already"));
}

static void faceted_sphere_refused_before_it_is_built(void **state) {
  (void)state;
  char err[512];
  int n;
  assert_false(load("{\"type\": \"faceted_sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
                    "\"stacks\": 8, \"slices\": 9, "
                    "\"material\": \"m\"}",
                    err, sizeof err, &n));
  print_message("%s\n", err);
  assert_non_null(strstr(err, "objects[0]: 8 x 9 facets would give the scene more than 64"));
}

static void polyhedron_faces_counted(void **state) {
  (void)state;
  /* a tetrahedron's 4 faces, 60 spheres before it: 64 loads, one more sphere does not */
  char objs[16384], err[512];
  int n;
  const char *ball = "{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
                     "\"material\": \"m\"}";
  const char *tet = ", {\"type\": \"polyhedron\", \"material\": \"m\", \"vertices\": [[0, 0, 0], "
                    "[1, 0, 0], [0, 1, 0], [0, 0, 1]], \"faces\": [[0, 2, 1], [0, 1, 3], "
                    "[0, 3, 2], [1, 2, 3]]}";
  repeat(ball, 60, objs, sizeof objs);
  strncat(objs, tet, sizeof objs - strlen(objs) - 1);
  int ok = load(objs, err, sizeof err, &n);
  if (!ok)
    print_message("%s\n", err);
  assert_true(ok);
  assert_int_equal(n, 64);
  repeat(ball, 61, objs, sizeof objs);
  strncat(objs, tet, sizeof objs - strlen(objs) - 1);
  assert_false(load(objs, err, sizeof err, &n));
  print_message("%s\n", err);
  assert_non_null(strstr(err, "objects[61].faces: 4 faces would give the scene more than 64"));
}

int main(int argc, char **argv) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(spheres_up_to_the_limit),
      cmocka_unit_test(faceted_sphere_refused_before_it_is_built),
      cmocka_unit_test(polyhedron_faces_counted),
  };
  if (argc > 1)
    cmocka_set_test_filter(argv[1]);
  return cmocka_run_group_tests(tests, NULL, NULL);
}
