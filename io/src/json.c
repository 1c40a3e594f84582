/* json.c -- JSON output through jansson (json.h). */
#include "io/json.h"

#include <math.h>
#include <stdio.h>

#include "io/output.h"

json_t *io_json_provenance(void) {
  const io_provenance_t *p = io_provenance();
  return json_pack("{s:s, s:s, s:s, s:s}", "version", p->version, "commit", p->commit,
                   "command_line", p->command_line, "date", p->date);
}

json_t *io_json_number(double x) {
  return isfinite(x) ? json_real(x) : json_null();
}

int io_json_write(const char *path, json_t *root, char *err, size_t cap) {
  if (json_is_object(root) && !json_object_get(root, "provenance"))
    json_object_set_new(root, "provenance", io_json_provenance());
  io_atomic_t a;
  if (io_atomic_open(&a, path, err, cap) != 0)
    return -1;
  if (json_dumpf(root, a.f, JSON_INDENT(2)) != 0 || fputc('\n', a.f) == EOF) {
    snprintf(err, cap, "%s: error writing JSON", path);
    io_atomic_abort(&a);
    return -1;
  }
  return io_atomic_commit(&a, err, cap);
}
