/* scene_json.h -- reading scene files: JSON (docs/scene-format.md) through jansson.
 *
 * Bad files never crash the loader: every error is reported once as
 *     FILE:LINE: PATH: what is wrong; what was expected
 * (FILE:LINE:COLUMN for JSON syntax errors), e.g.
 *     scenes/x.json:12: objects[1].radius: expected a number > 0, got -1
 */
#ifndef IO_SCENE_JSON_H
#define IO_SCENE_JSON_H

#include <stddef.h>

#include "core/scene.h"

/** Load the scene in `path` into s (any previous content is freed) and prepare it. Returns 0;
 *  -1 for a file that is not a valid scene, or -2 when memory ran out, with the message in
 *  err[cap] and s left empty. Duplicate keys are errors. */
int io_scene_load(const char *path, rt_scene_t *s, char *err, size_t cap);

/** io_scene_load() of a scene held in memory: the len bytes at data (not NUL-terminated; a NUL
 *  byte is an error, as in a file), named `name` in messages ("NAME:LINE: ..."). The caller
 *  keeps data; nothing refers to it after the call. For scenes that are not files, and for the
 *  fuzzer (fuzz/scene_fuzz.c). */
int io_scene_load_buffer(const char *name, const char *data, size_t len, rt_scene_t *s, char *err,
                         size_t cap);

#endif
