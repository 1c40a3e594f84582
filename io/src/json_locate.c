/* json_locate.c -- the line of a value inside JSON text, found by its path (object keys and
 * array indices). jansson reports positions only for syntax errors; for a value that parses but
 * is wrong (a negative radius) the scene loader re-reads the text to name the line. The text is
 * known to be valid JSON (jansson accepted it), so the scanner only skips and counts lines. */
#include <string.h>

#include "json_locate.h"

typedef struct {
  const char *p, *end;
  int line;
} scan_t;

static void ws(scan_t *s) {
  while (s->p < s->end && (*s->p == ' ' || *s->p == '\t' || *s->p == '\n' || *s->p == '\r')) {
    if (*s->p == '\n')
      s->line++;
    s->p++;
  }
}

/* Skip a string starting at '"'; its raw contents are [*a, *b). */
static void skip_string(scan_t *s, const char **a, const char **b) {
  s->p++;
  *a = s->p;
  while (s->p < s->end && *s->p != '"')
    s->p += (*s->p == '\\' && s->p + 1 < s->end) ? 2 : 1;
  *b = s->p;
  if (s->p < s->end)
    s->p++;
}

static void skip_value(scan_t *s, int depth);

/* Skip the members of an object or array opened at s->p. */
static void skip_container(scan_t *s, int depth) {
  char close = *s->p == '{' ? '}' : ']';
  s->p++;
  for (;;) {
    ws(s);
    if (s->p >= s->end || *s->p == close) {
      s->p += s->p < s->end;
      return;
    }
    if (*s->p == ',' || *s->p == ':') {
      s->p++;
      continue;
    }
    const char *before = s->p;
    skip_value(s, depth + 1);
    s->p += s->p == before; /* a byte that starts no value (a NUL): step over it, never stall */
  }
}

static void skip_value(scan_t *s, int depth) {
  const char *a, *b;
  ws(s);
  if (s->p >= s->end)
    return;
  if (*s->p == '"')
    skip_string(s, &a, &b);
  else if ((*s->p == '{' || *s->p == '[') && depth < 4096)
    skip_container(s, depth);
  else
    while (s->p < s->end && (*s->p == '\0' || !strchr(",]} \t\r\n", *s->p)))
      s->p++; /* strchr() would find a NUL byte as the set's terminator */
}

/* Position s at the value of member `key` of the object at s->p; 0 when absent. */
static int find_key(scan_t *s, const char *key) {
  size_t n = strlen(key);
  s->p++; /* '{' */
  for (;;) {
    ws(s);
    if (s->p >= s->end || *s->p != '"')
      return 0;
    const char *a, *b;
    skip_string(s, &a, &b);
    ws(s);
    s->p += s->p < s->end && *s->p == ':';
    ws(s);
    if ((size_t)(b - a) == n && memcmp(a, key, n) == 0)
      return 1;
    skip_value(s, 0);
    ws(s);
    if (s->p >= s->end || *s->p != ',')
      return 0;
    s->p++;
  }
}

/* Position s at element `index` of the array at s->p; 0 when absent. */
static int find_index(scan_t *s, int index) {
  s->p++; /* '[' */
  for (int i = 0;; i++) {
    ws(s);
    if (s->p >= s->end || *s->p == ']')
      return 0;
    if (i == index)
      return 1;
    skip_value(s, 0);
    ws(s);
    if (s->p >= s->end || *s->p != ',')
      return 0;
    s->p++;
  }
}

int io_json_locate(const char *text, size_t len, const io_json_step_t *path, int n) {
  scan_t s = {text, text + len, 1};
  ws(&s);
  int line = s.line;
  for (int k = 0; k < n; k++) {
    scan_t save = s;
    int ok = 0;
    if (path[k].key && s.p < s.end && *s.p == '{')
      ok = find_key(&s, path[k].key);
    else if (!path[k].key && s.p < s.end && *s.p == '[')
      ok = find_index(&s, path[k].index);
    if (!ok)
      return save.line; /* the deepest container that exists */
    line = s.line;
  }
  return line;
}
