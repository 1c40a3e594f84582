/* replay.c -- the harness of scene_fuzz.c without libFuzzer: runs LLVMFuzzerTestOneInput once
 * on each file named on the command line, so that a crash the fuzzer found can be replayed and
 * debugged in any build (gcc, the ASan build, a debugger), and so that the seed corpus is
 * checked by ctest in every build (docs/DEVELOPING.md, "Fuzzing").
 * usage: scene_fuzz_replay FILE...   (exit 0; a broken rule aborts) */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "io/output.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: scene_fuzz_replay FILE...\n");
    return 2;
  }
  for (int i = 1; i < argc; i++) {
    size_t len;
    uint8_t *data = (uint8_t *)io_read_file(argv[i], &len);
    if (!data) {
      fprintf(stderr, "scene_fuzz_replay: cannot read %s\n", argv[i]);
      return 2;
    }
    LLVMFuzzerTestOneInput(data, len);
    free(data);
  }
  printf("scene_fuzz_replay: %d files, no rule broken\n", argc - 1);
  return 0;
}
