/* scene_bad.c -- one file of the broken-scene corpus (tests/scenes_bad/): loading it must fail
 * without crashing, with a message "FILE:LINE:..." containing the text that DIR/expect.txt
 * lists for FILE (a line "FILE | LINE | TEXT"). A file without an entry fails the test, so the
 * corpus and its expectations stay in step. Loading the same bytes from memory
 * (io_scene_load_buffer, what the fuzzer calls) must fail with the same message.
 * usage: scene_bad DIR FILE   (one ctest entry per .json file, tests/CMakeLists.txt) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/output.h"
#include "io/scene_json.h"

/* Find FILE's expectation: *line and text[cap]; 0 when there is none. */
static int expectation(const char *dir, const char *file, int *line, char *text, size_t cap) {
  char path[2048], buf[1024], name[512];
  snprintf(path, sizeof path, "%s/expect.txt", dir);
  FILE *f = fopen(path, "r");
  if (!f)
    return 0;
  int found = 0;
  while (!found && fgets(buf, sizeof buf, f)) {
    int pos = 0;
    if (buf[0] == '#' || sscanf(buf, "%511s | %d | %n", name, line, &pos) != 2 || pos == 0 ||
        strcmp(name, file) != 0)
      continue;
    buf[strcspn(buf, "\n")] = '\0';
    snprintf(text, cap, "%s", buf + pos);
    found = 1;
  }
  fclose(f);
  return found;
}

/* Loading path's bytes from memory under the same name gives the message `want`. */
static int same_from_memory(const char *path, const char *want) {
  size_t len;
  char *data = io_read_file(path, &len), err[2048];
  if (!data) {
    fprintf(stderr, "FAIL: cannot read %s\n", path);
    return 0;
  }
  rt_scene_t s;
  rt_scene_init(&s);
  int rc = io_scene_load_buffer(path, data, len, &s, err, sizeof err);
  free(data);
  rt_scene_free(&s);
  if (rc == 0 || strcmp(err, want) != 0) {
    fprintf(stderr, "FAIL: from memory: %s\n", rc == 0 ? "loaded without an error" : err);
    return 0;
  }
  return 1;
}

int main(int argc, char **argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: scene_bad DIR FILE\n");
    return 2;
  }
  char path[2048], err[2048], prefix[2100], text[1024];
  int line;
  if (!expectation(argv[1], argv[2], &line, text, sizeof text)) {
    fprintf(stderr, "FAIL: no entry for %s in %s/expect.txt\n", argv[2], argv[1]);
    return 1;
  }
  snprintf(path, sizeof path, "%s/%s", argv[1], argv[2]);
  snprintf(prefix, sizeof prefix, "%s:%d:", path, line);
  rt_scene_t s;
  rt_scene_init(&s);
  if (io_scene_load(path, &s, err, sizeof err) == 0) {
    fprintf(stderr, "FAIL: %s loaded without an error\n", path);
    rt_scene_free(&s);
    return 1;
  }
  printf("%s\n", err);
  int ok = strncmp(err, prefix, strlen(prefix)) == 0 && strstr(err, text) != NULL;
  if (!ok)
    fprintf(stderr, "FAIL: expected a message starting '%s' containing '%s'\n", prefix, text);
  if (s.nobject != 0 || s.nmaterial != 0 || s.bvh != NULL) {
    fprintf(stderr, "FAIL: the scene was not left empty\n");
    ok = 0;
  }
  ok = same_from_memory(path, err) && ok;
  return ok ? 0 : 1;
}
