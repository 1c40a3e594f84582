/* scene_bad.c -- one file of the broken-scene corpus (tests/scenes_bad/): loading it must fail
 * without crashing, with a message "FILE:LINE:..." containing the text that DIR/expect.txt
 * lists for FILE (a line "FILE | LINE | TEXT"). A file without an entry fails the test, so the
 * corpus and its expectations stay in step.
 * usage: scene_bad DIR FILE   (one ctest entry per .json file, tests/CMakeLists.txt) */
#include <stdio.h>
#include <string.h>

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
  return ok ? 0 : 1;
}
