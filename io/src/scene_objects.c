/* scene_objects.c -- the "objects" of a scene file (docs/scene-format.md): spheres, checkered
 * planes (course notes 1.7.1.5), polygons, closed polyhedra and generated faceted spheres (the
 * paper's Fig. 11 polyhedron of 100 polygons). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/builtin.h"
#include "io/scene_json.h"
#include "parse.h"

static int parse_sphere(io_parse_t *P, json_t *o, int mat, int *obj) {
  static const char *const keys[] = {"type", "name", "material", "center", "radius", NULL};
  px_vec3_t c;
  double r;
  if (!io_check_keys(P, o, keys) || !io_get_vec3(P, o, "center", 1, px_vec3(0, 0, 0), &c) ||
      !io_get_number(P, o, "radius", 1, 0, 0, 1e12, 1, &r))
    return 0;
  rt_status_t st = rt_scene_add_sphere(P->scene, c, r, mat, obj);
  return st == RT_OK || (st == RT_ENOMEM ? io_enomem(P) : io_fail(P, "invalid sphere"));
}

static int parse_plane(io_parse_t *P, json_t *o, int mat, int *obj) {
  static const char *const keys[] = {"type",   "name",    "material", "point",
                                     "normal", "checker", NULL};
  static const char *const ckeys[] = {"size", "material", "u", NULL};
  px_vec3_t p, n, u = px_vec3(1, 0, 0);
  json_t *chk;
  int mat2 = -1;
  double size = 1.0;
  if (!io_check_keys(P, o, keys) || !io_get_vec3(P, o, "point", 1, u, &p) ||
      !io_get_vec3(P, o, "normal", 1, u, &n) || !io_get_object(P, o, "checker", 0, &chk))
    return 0;
  if (px_vec3_norm(n) == 0.0) {
    io_push_key(P, "normal");
    io_fail(P, "expected a non-zero normal vector");
    io_pop(P);
    return 0;
  }
  if (chk) {
    io_push_key(P, "checker");
    int ok = io_check_keys(P, chk, ckeys) &&
             io_get_number(P, chk, "size", 1, 1.0, IO_MIN_CHECK, 1e12, 0, &size) &&
             io_get_material(P, chk, "material", 1, &mat2) && io_get_vec3(P, chk, "u", 0, u, &u);
    /* a u given along the normal has no direction in the plane: the frame would take another
     * axis for it (px_frame_from_z's test, 1e-6 rad), and the squares would turn silently */
    px_vec3_t along = px_vec3_scale(n, px_vec3_dot(u, n) / px_vec3_dot(n, n));
    if (ok && json_object_get(chk, "u") &&
        !(px_vec3_norm(px_vec3_sub(u, along)) > 1e-6 * px_vec3_norm(u))) {
      io_push_key(P, "u");
      ok = io_fail(P, "expected a direction of the squares' u axis that is not %s the normal",
                   px_vec3_norm(u) == 0.0 ? "zero nor parallel to" : "parallel to");
      io_pop(P);
    }
    io_pop(P);
    if (!ok)
      return 0;
  }
  rt_status_t st = rt_scene_add_plane(P->scene, p, n, u, mat, mat2, size, obj);
  return st == RT_OK || (st == RT_ENOMEM ? io_enomem(P) : io_fail(P, "invalid plane"));
}

/* Member `key`: an array of at least `min` points [x, y, z]; *v is malloc'ed (caller frees). */
static int get_points(io_parse_t *P, json_t *o, const char *key, int min, px_vec3_t **v, int *n) {
  json_t *arr;
  *v = NULL;
  if (!io_get_array(P, o, key, 1, &arr))
    return 0;
  io_push_key(P, key);
  *n = (int)json_array_size(arr);
  int ok = *n >= min || io_fail(P, "expected at least %d points [x, y, z], got %d", min, *n);
  if (ok && !(*v = malloc((size_t)*n * sizeof **v)))
    ok = io_enomem(P);
  for (int i = 0; ok && i < *n; i++) {
    io_push_index(P, i);
    ok = io_as_vec3(P, json_array_get(arr, (size_t)i), &(*v)[i]);
    io_pop(P);
  }
  io_pop(P);
  return ok;
}

static int parse_polygon(io_parse_t *P, json_t *o, int mat, int *obj) {
  static const char *const keys[] = {"type", "name", "material", "vertices", NULL};
  px_vec3_t *v = NULL;
  int n = 0, ok = io_check_keys(P, o, keys) && get_points(P, o, "vertices", 3, &v, &n);
  rt_status_t st = ok ? rt_scene_add_polygon(P->scene, v, n, mat, obj) : RT_OK;
  if (st == RT_ENOMEM)
    ok = io_enomem(P);
  else if (st != RT_OK) {
    io_push_key(P, "vertices");
    ok = io_fail(P, "degenerate polygon: the vertices must lie in one plane (within 1e-9 of its "
                    "size) and enclose a non-zero area");
    io_pop(P);
  }
  free(v);
  return ok;
}

/* faces: [[i, j, k, ...], ...] -> flat indices and lengths (malloc'ed). */
static int get_faces(io_parse_t *P, json_t *o, int nv, int **idx, int **len, int *nface) {
  json_t *arr;
  *idx = *len = NULL;
  if (!io_get_array(P, o, "faces", 1, &arr))
    return 0;
  io_push_key(P, "faces");
  *nface = (int)json_array_size(arr);
  size_t total = 0;
  for (int f = 0; f < *nface; f++)
    total += json_array_size(json_array_get(arr, (size_t)f));
  *idx = malloc((total ? total : 1) * sizeof **idx);
  *len = malloc((*nface ? (size_t)*nface : 1) * sizeof **len);
  int ok = (*idx && *len) || io_enomem(P);
  for (int f = 0, off = 0; ok && f < *nface; f++) {
    json_t *face = json_array_get(arr, (size_t)f);
    io_push_index(P, f);
    if (!json_is_array(face) || json_array_size(face) < 3)
      ok = io_fail(P, "expected a face: an array of at least 3 vertex indices");
    for (size_t k = 0; ok && k < json_array_size(face); k++) {
      json_t *x = json_array_get(face, k);
      io_push_index(P, (int)k);
      if (!json_is_integer(x) || json_integer_value(x) < 0 || json_integer_value(x) >= nv)
        ok = io_fail(P, "expected a vertex index from 0 to %d", nv - 1);
      else
        (*idx)[off++] = (int)json_integer_value(x);
      io_pop(P);
    }
    (*len)[f] = ok ? (int)json_array_size(face) : 0;
    io_pop(P);
  }
  io_pop(P);
  return ok;
}

static int parse_polyhedron(io_parse_t *P, json_t *o, int mat, int *obj) {
  static const char *const keys[] = {"type", "name", "material", "vertices", "faces", NULL};
  px_vec3_t *v = NULL;
  int *idx = NULL, *len = NULL, nv = 0, nf = 0;
  int ok = io_check_keys(P, o, keys) && get_points(P, o, "vertices", 4, &v, &nv) &&
           get_faces(P, o, nv, &idx, &len, &nf);
  if (ok && nf > IO_MAX_PRIMITIVES - P->scene->nprim) {
    io_push_key(P, "faces");
    ok = io_fail(P, "%d faces would give the scene more than %d primitives", nf, IO_MAX_PRIMITIVES);
    io_pop(P);
  }
  char why[200];
  rt_status_t st =
      ok ? rt_scene_add_polyhedron(P->scene, v, nv, idx, len, nf, mat, obj, why, sizeof why)
         : RT_OK;
  if (st == RT_ENOMEM)
    ok = io_enomem(P);
  else if (st != RT_OK) {
    io_push_key(P, "faces");
    ok = io_fail(P, "not a closed polyhedron: %s", why);
    io_pop(P);
  }
  free(v);
  free(idx);
  free(len);
  return ok;
}

static int parse_faceted(io_parse_t *P, json_t *o, int mat, int *obj) {
  static const char *const keys[] = {"type",   "name",   "material", "center",
                                     "radius", "stacks", "slices",   NULL};
  px_vec3_t c;
  double r;
  int st, sl;
  if (!io_check_keys(P, o, keys) || !io_get_vec3(P, o, "center", 1, px_vec3(0, 0, 0), &c) ||
      !io_get_number(P, o, "radius", 1, 0, 0, 1e12, 1, &r) ||
      !io_get_int(P, o, "stacks", 1, 0, 2, 512, &st) ||
      !io_get_int(P, o, "slices", 1, 0, 3, 512, &sl))
    return 0;
  if (st * sl > IO_MAX_PRIMITIVES - P->scene->nprim)
    return io_fail(P, "%d x %d facets would give the scene more than %d primitives", st, sl,
                   IO_MAX_PRIMITIVES);
  rt_status_t rs = rt_scene_add_faceted_sphere(P->scene, c, r, st, sl, mat, obj);
  return rs == RT_OK ||
         (rs == RT_ENOMEM ? io_enomem(P) : io_fail(P, "cannot build the faceted sphere"));
}

/* An object's "name": 1 to RT_NAME_MAX - 1 bytes (it is kept whole, never cut), and no other
 * object's, since --receiver and messages find an object by its name. Objects are added one per
 * entry of "objects", so object i is objects[i]. */
static int check_name(io_parse_t *P, const char *name) {
  size_t len = strlen(name);
  io_push_key(P, "name");
  int ok = (len > 0 && len < RT_NAME_MAX) ||
           io_fail(P, "object names must have 1 to %d bytes, got %zu", RT_NAME_MAX - 1, len);
  for (int i = 0; ok && i < P->scene->nobject; i++)
    if (strcmp(P->scene->object[i].name, name) == 0)
      ok = io_fail(P, "duplicate object name '%s': objects[%d] has it already", name, i);
  io_pop(P);
  return ok;
}

typedef int (*object_parser_t)(io_parse_t *, json_t *, int, int *);

static const struct {
  const char *type;
  object_parser_t parse;
} parsers[] = {{"sphere", parse_sphere},
               {"plane", parse_plane},
               {"polygon", parse_polygon},
               {"polyhedron", parse_polyhedron},
               {"faceted_sphere", parse_faceted}};

static int parse_object(io_parse_t *P, json_t *o) {
  const char *type, *name;
  int mat, obj = -1;
  if (!json_is_object(o))
    return io_fail(P, "expected an object {\"type\": \"sphere\", ...}");
  if (P->scene->nprim >= IO_MAX_PRIMITIVES)
    return io_fail(P, "the scene has %d primitives already, the most it may have",
                   IO_MAX_PRIMITIVES);
  if (!io_get_string(P, o, "type", 1, &type) || !io_get_string(P, o, "name", 0, &name) ||
      !io_get_material(P, o, "material", 1, &mat) || (name && !check_name(P, name)))
    return 0;
  for (size_t k = 0; k < sizeof parsers / sizeof parsers[0]; k++)
    if (strcmp(type, parsers[k].type) == 0) {
      if (!parsers[k].parse(P, o, mat, &obj))
        return 0;
      if (name)
        rt_scene_name_object(P->scene, obj, name);
      return 1;
    }
  io_push_key(P, "type");
  io_fail(P,
          "unknown object type '%s'; expected sphere, plane, polygon, polyhedron or "
          "faceted_sphere",
          type);
  io_pop(P);
  return 0;
}

int io_parse_objects(io_parse_t *P, json_t *arr) {
  io_push_key(P, "objects");
  int ok = 1;
  for (size_t i = 0; i < json_array_size(arr) && ok; i++) {
    io_push_index(P, (int)i);
    ok = parse_object(P, json_array_get(arr, i));
    io_pop(P);
  }
  io_pop(P);
  return ok;
}
