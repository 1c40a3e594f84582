/* parse.h -- private: the scene loader's cursor (where in the file it is) and typed getters
 * that report "file:line: path: what is wrong, what was expected". */
#ifndef IO_PARSE_H
#define IO_PARSE_H

#include <jansson.h>
#include <stddef.h>

#include "core/scene.h"
#include "json_locate.h"

#define IO_PATH_MAX 16

typedef struct {
  const char *file; /**< path as given, for messages */
  const char *text; /**< the file's bytes when loaded from memory (len bytes), else NULL: errors
                         then read the file again to find their line */
  size_t len;
  char *err; /**< message buffer (caller-owned) */
  size_t cap;
  int failed; /**< 1 after the first error; later errors are not reported */
  int oom;    /**< that error was running out of memory (io_enomem()) */
  io_json_step_t step[IO_PATH_MAX];
  int depth;
  rt_scene_t *scene;
} io_parse_t;

void io_push_key(io_parse_t *P, const char *key);
void io_push_index(io_parse_t *P, int index);
void io_pop(io_parse_t *P);

/** Report an error at the current path (first error only); returns 0 for `return io_fail()`. */
int io_fail(io_parse_t *P, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/** io_fail() with "out of memory", marking the error as that (io_parse_t.oom); returns 0. */
int io_enomem(io_parse_t *P);

/** 1 when every key of object `o` is in the NULL-terminated list `allowed` ("comment" is always
 *  allowed); otherwise reports the first unknown key. */
int io_check_keys(io_parse_t *P, json_t *o, const char *const *allowed);

/** Member `key` of `o` must be an object / array (or absent when !required: *out = NULL). */
int io_get_object(io_parse_t *P, json_t *o, const char *key, int required, json_t **out);
int io_get_array(io_parse_t *P, json_t *o, const char *key, int required, json_t **out);

/** Number member in [lo, hi] (strict bounds when the flags say so); `def` when absent and not
 *  required. */
int io_get_number(io_parse_t *P, json_t *o, const char *key, int required, double def, double lo,
                  double hi, int lo_strict, double *out);
int io_get_int(io_parse_t *P, json_t *o, const char *key, int required, int def, int lo, int hi,
               int *out);
int io_get_bool(io_parse_t *P, json_t *o, const char *key, int def, int *out);
int io_get_string(io_parse_t *P, json_t *o, const char *key, int required, const char **out);
/** Largest coordinate magnitude of a point or vector in a scene (scene units): far beyond any
 *  scene, and far enough below the double range that differences, cross products and squared
 *  lengths of such vectors stay finite. */
#define IO_MAX_COORD 1e12
/** Smallest checker square (scene units): the reciprocal, by which square indices are found,
 *  stays finite, and the squares stay above the resolution of the coordinates in a scene. */
#define IO_MIN_CHECK 1e-12
/** Largest colour component, light intensity, ambient or background: sums over many lights and
 *  reflections stay far inside float32 (3.4e38), so that an image never holds an infinity. */
#define IO_MAX_RADIANCE 1e6
/** Most primitives (spheres, planes, polygons, faces) a scene may have: 2^24, a BVH of them in a
 *  few GB. A larger scene is refused at the object that would pass the limit, before it is
 *  built, rather than exhausting memory part-way. */
#ifndef IO_MAX_PRIMITIVES /* tests/test_scene_limits.c builds the loader with a small one */
#define IO_MAX_PRIMITIVES (1 << 24)
#endif

/** [x, y, z], each component from -IO_MAX_COORD to IO_MAX_COORD. */
int io_get_vec3(io_parse_t *P, json_t *o, const char *key, int required, px_vec3_t def,
                px_vec3_t *out);
/** A colour: [r, g, b] or one number for grey, every component from 0 to IO_MAX_RADIANCE. */
int io_get_rgb(io_parse_t *P, json_t *o, const char *key, rt_rgb_t def, rt_rgb_t *out);
/** The value `v` itself (already at the current path) as a vec3. */
int io_as_vec3(io_parse_t *P, json_t *v, px_vec3_t *out);

/** Material named by member `key`: its index, or an error listing the defined names. */
int io_get_material(io_parse_t *P, json_t *o, const char *key, int required, int *out);

/** Objects (scene_objects.c): the "objects" array. */
int io_parse_objects(io_parse_t *P, json_t *arr);

#endif
