/* parse.c -- typed access to the scene file's JSON with errors that name the file, the line,
 * the key path, what is wrong and what was expected (docs/scene-format.md). */
#include "parse.h"

#include "io/output.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void io_push_key(io_parse_t *P, const char *key) {
  if (P->depth < IO_PATH_MAX)
    P->step[P->depth] = (io_json_step_t){key, 0};
  P->depth++;
}

void io_push_index(io_parse_t *P, int index) {
  if (P->depth < IO_PATH_MAX)
    P->step[P->depth] = (io_json_step_t){NULL, index};
  P->depth++;
}

void io_pop(io_parse_t *P) {
  P->depth--;
}

/* "objects[2].radius" */
static void format_path(const io_parse_t *P, char *out, size_t cap) {
  size_t n = 0;
  out[0] = '\0';
  int depth = P->depth < IO_PATH_MAX ? P->depth : IO_PATH_MAX;
  for (int k = 0; k < depth && n < cap; k++) {
    if (P->step[k].key)
      n += (size_t)snprintf(out + n, cap - n, "%s%s", k ? "." : "", P->step[k].key);
    else
      n += (size_t)snprintf(out + n, cap - n, "[%d]", P->step[k].index);
  }
}

int io_enomem(io_parse_t *P) {
  if (!P->failed)
    P->oom = 1;
  return io_fail(P, "out of memory");
}

int io_fail(io_parse_t *P, const char *fmt, ...) {
  if (P->failed)
    return 0;
  P->failed = 1;
  size_t len = P->len;
  char *copy = P->text ? NULL : io_read_file(P->file, &len);
  const char *text = P->text ? P->text : copy;
  int depth = P->depth < IO_PATH_MAX ? P->depth : IO_PATH_MAX;
  int line = text ? io_json_locate(text, len, P->step, depth) : 1;
  free(copy);
  char where[256], what[512];
  format_path(P, where, sizeof where);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  snprintf(P->err, P->cap, "%s:%d: %s%s%s", P->file, line, where, where[0] ? ": " : "", what);
  return 0;
}

int io_check_keys(io_parse_t *P, json_t *o, const char *const *allowed) {
  const char *key;
  json_t *v;
  json_object_foreach(o, key, v) {
    int ok = strcmp(key, "comment") == 0;
    for (int i = 0; allowed[i] && !ok; i++)
      ok = strcmp(key, allowed[i]) == 0;
    if (!ok) {
      char list[400];
      size_t n = 0;
      list[0] = '\0';
      for (int i = 0; allowed[i] && n < sizeof list; i++)
        n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "", allowed[i]);
      io_push_key(P, key);
      io_fail(P, "unknown key '%s'; expected one of: %s", key, list);
      io_pop(P);
      return 0;
    }
  }
  return 1;
}

static const char *type_name(json_t *v) {
  switch (json_typeof(v)) {
  case JSON_OBJECT:
    return "an object";
  case JSON_ARRAY:
    return "an array";
  case JSON_STRING:
    return "a string";
  case JSON_INTEGER:
  case JSON_REAL:
    return "a number";
  case JSON_TRUE:
  case JSON_FALSE:
    return "a boolean";
  case JSON_NULL:
    return "null";
  }
  return "something else";
}

/* Member lookup: 1 with *v set, 0 when absent (an error when required). */
static int member(io_parse_t *P, json_t *o, const char *key, int required, json_t **v) {
  *v = json_object_get(o, key);
  if (*v)
    return 1;
  if (required)
    io_fail(P, "missing required key '%s'", key);
  return 0;
}

static int get_typed(io_parse_t *P, json_t *o, const char *key, int required, json_t **out,
                     json_type type, const char *what) {
  json_t *v;
  *out = NULL;
  if (!member(P, o, key, required, &v))
    return !required;
  if (json_typeof(v) != type) {
    io_push_key(P, key);
    io_fail(P, "expected %s, got %s", what, type_name(v));
    io_pop(P);
    return 0;
  }
  *out = v;
  return 1;
}

int io_get_object(io_parse_t *P, json_t *o, const char *key, int required, json_t **out) {
  return get_typed(P, o, key, required, out, JSON_OBJECT, "an object {...}");
}

int io_get_array(io_parse_t *P, json_t *o, const char *key, int required, json_t **out) {
  return get_typed(P, o, key, required, out, JSON_ARRAY, "an array [...]");
}

static int number_in(io_parse_t *P, json_t *v, double lo, double hi, int lo_strict, double *out) {
  if (!json_is_number(v))
    return io_fail(P, "expected a number, got %s", type_name(v));
  double x = json_number_value(v);
  char got[IO_SHORTEST_MAX]; /* as read: %g would print 100.0000001 as 100 beside "<= 100" */
  if (!isfinite(x) || x < lo || (lo_strict && x == lo) || x > hi) {
    if (isinf(hi))
      return io_fail(P, "expected a number %s %g, got %s", lo_strict ? ">" : ">=", lo,
                     io_shortest(x, got));
    if (lo_strict)
      return io_fail(P, "expected a number > %g and <= %g, got %s", lo, hi, io_shortest(x, got));
    return io_fail(P, "expected a number from %g to %g, got %s", lo, hi, io_shortest(x, got));
  }
  *out = x;
  return 1;
}

int io_get_number(io_parse_t *P, json_t *o, const char *key, int required, double def, double lo,
                  double hi, int lo_strict, double *out) {
  json_t *v;
  if (!member(P, o, key, required, &v)) {
    *out = def;
    return !required;
  }
  io_push_key(P, key);
  int ok = number_in(P, v, lo, hi, lo_strict, out);
  io_pop(P);
  return ok;
}

int io_get_int(io_parse_t *P, json_t *o, const char *key, int required, int def, int lo, int hi,
               int *out) {
  json_t *v;
  if (!member(P, o, key, required, &v)) {
    *out = def;
    return !required;
  }
  io_push_key(P, key);
  int ok = 1;
  char got[IO_SHORTEST_MAX];
  if (!json_is_integer(v)) {
    if (json_is_number(v)) {
      /* 5.0 is a real to JSON: say so, rather than echo "5" as if it were refused by value */
      const char *g = io_shortest(json_number_value(v), got);
      ok = io_fail(P, "expected an integer from %d to %d, got %s%s", lo, hi, g,
                   strpbrk(g, ".eEin") ? "" : ".0");
    } else
      ok = io_fail(P, "expected an integer from %d to %d, got %s", lo, hi, type_name(v));
  } else if (json_integer_value(v) < lo || json_integer_value(v) > hi) {
    ok = io_fail(P, "expected an integer from %d to %d, got %lld", lo, hi,
                 (long long)json_integer_value(v));
  } else {
    *out = (int)json_integer_value(v);
  }
  io_pop(P);
  return ok;
}

int io_get_bool(io_parse_t *P, json_t *o, const char *key, int def, int *out) {
  json_t *v;
  *out = def;
  if (!member(P, o, key, 0, &v))
    return 1;
  if (!json_is_boolean(v)) {
    io_push_key(P, key);
    io_fail(P, "expected true or false, got %s", type_name(v));
    io_pop(P);
    return 0;
  }
  *out = json_is_true(v);
  return 1;
}

int io_get_string(io_parse_t *P, json_t *o, const char *key, int required, const char **out) {
  json_t *v;
  *out = NULL;
  if (!get_typed(P, o, key, required, &v, JSON_STRING, "a string \"...\""))
    return 0;
  if (v)
    *out = json_string_value(v);
  return 1;
}

int io_as_vec3(io_parse_t *P, json_t *v, px_vec3_t *out) {
  if (!json_is_array(v) || json_array_size(v) != 3)
    return io_fail(P, "expected [x, y, z] (three numbers), got %s%s", type_name(v),
                   json_is_array(v) ? " of the wrong length" : "");
  double c[3];
  for (int k = 0; k < 3; k++) {
    io_push_index(P, k);
    int ok = number_in(P, json_array_get(v, (size_t)k), -IO_MAX_COORD, IO_MAX_COORD, 0, &c[k]);
    io_pop(P);
    if (!ok)
      return 0;
  }
  *out = px_vec3(c[0], c[1], c[2]);
  return 1;
}

int io_get_vec3(io_parse_t *P, json_t *o, const char *key, int required, px_vec3_t def,
                px_vec3_t *out) {
  json_t *v;
  if (!member(P, o, key, required, &v)) {
    *out = def;
    return !required;
  }
  io_push_key(P, key);
  int ok = io_as_vec3(P, v, out);
  io_pop(P);
  return ok;
}

int io_get_rgb(io_parse_t *P, json_t *o, const char *key, rt_rgb_t def, rt_rgb_t *out) {
  json_t *v;
  if (!member(P, o, key, 0, &v)) {
    *out = def;
    return 1;
  }
  io_push_key(P, key);
  int ok;
  double g = 0.0;
  px_vec3_t c = {0.0, 0.0, 0.0};
  if (json_is_number(v)) {
    ok = number_in(P, v, 0.0, IO_MAX_RADIANCE, 0, &g);
    c = px_vec3(g, g, g);
  } else if (!json_is_array(v)) {
    ok = io_fail(P, "expected a colour [r, g, b] or one number, got %s", type_name(v));
  } else if ((ok = io_as_vec3(P, v, &c)) &&
             (c.x < 0 || c.y < 0 || c.z < 0 || c.x > IO_MAX_RADIANCE || c.y > IO_MAX_RADIANCE ||
              c.z > IO_MAX_RADIANCE)) {
    ok = io_fail(P, "colour components must be from 0 to %g, got [%g, %g, %g]", IO_MAX_RADIANCE,
                 c.x, c.y, c.z);
  }
  io_pop(P);
  if (ok)
    *out = rt_rgb(c.x, c.y, c.z);
  return ok;
}

int io_get_material(io_parse_t *P, json_t *o, const char *key, int required, int *out) {
  const char *name;
  *out = -1;
  if (!io_get_string(P, o, key, required, &name))
    return 0;
  if (!name)
    return 1;
  *out = rt_scene_find_material(P->scene, name);
  if (*out >= 0)
    return 1;
  char list[300];
  size_t n = 0;
  list[0] = '\0';
  for (int i = 0; i < P->scene->nmaterial && n < sizeof list; i++)
    n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", i ? ", " : "",
                          P->scene->material[i].name);
  io_push_key(P, key);
  io_fail(P, "no material called '%s'; expected one of the \"materials\": %s", name,
          n ? list : "(none defined)");
  io_pop(P);
  return 0;
}
