/* json_locate.h -- private: line numbers of values in JSON text by path. */
#ifndef IO_JSON_LOCATE_H
#define IO_JSON_LOCATE_H

#include <stddef.h>

/** One step of a path: an object member (key != NULL) or an array element (index). */
typedef struct {
  const char *key;
  int index;
} io_json_step_t;

/** 1-based line of the value at `path` (n steps) in valid JSON text; when a step does not exist
 *  (a missing member), the line of the deepest enclosing value that does. */
int io_json_locate(const char *text, size_t len, const io_json_step_t *path, int n);

#endif
