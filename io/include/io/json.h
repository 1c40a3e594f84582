/* json.h -- JSON output through jansson: every JSON file the project writes is a jansson tree
 * written here, so that any string (a path with quotes, backslashes or non-ASCII letters)
 * round-trips, and every file carries the provenance of output.h. */
#ifndef IO_JSON_H
#define IO_JSON_H

#include <jansson.h>
#include <stddef.h>

/** {"version", "commit", "command_line", "date"} of io_provenance() (a new reference). */
json_t *io_json_provenance(void);

/** Write root to path atomically (output.h), indented, keys in insertion order, reals with 17
 *  significant digits (they read back exactly), after setting root["provenance"] =
 * io_json_provenance() when root is an object without one. 0, or -1 with the reason in err[cap].
 * Does not steal root. */
int io_json_write(const char *path, json_t *root, char *err, size_t cap);

/** json_real(x) for a finite x, json_null() for NaN and infinities (JSON has no such
 *  numbers). */
json_t *io_json_number(double x);

#endif
