#!/usr/bin/env bash
# The scene fuzzer (docs/DEVELOPING.md, "Fuzzing"): configures and builds build-fuzz/ with clang
# (PENCIL_FUZZ=ON: libFuzzer, AddressSanitizer, UndefinedBehaviorSanitizer), seeds a corpus from
# scenes/ and tests/scenes_bad/ (fuzz/seed.sh) and runs fuzz/scene_fuzz on it, one process.
#
#   fuzz/run.sh --smoke         the test suite's run (ctest fuzz.smoke): a fresh corpus in a
#                               temporary directory, the seeds then 25 s of fuzzing
#   fuzz/run.sh [SECONDS]       the long run (default 3600 s) on the corpus kept in
#                               build-fuzz/corpus/, which grows from run to run
#
# Crashes, leaks, timeouts and sanitizer reports stop the run and leave their input in
# build-fuzz/crashes/ (printed); the exit status is then non-zero. Exit 77 (ctest's skip) with a
# reason when clang or its libFuzzer runtime is missing. Environment: PENCIL_FUZZ_CC (default
# clang), PENCIL_FUZZ_BUILD (default build-fuzz).
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
cd "$src"
cc=${PENCIL_FUZZ_CC:-clang}
build=${PENCIL_FUZZ_BUILD:-build-fuzz}
smoke=0
seconds=3600
case "${1:-}" in
  --smoke) smoke=1; seconds=25 ;;
  "") ;;
  *[!0-9]*) echo "usage: fuzz/run.sh [--smoke | SECONDS]" >&2; exit 2 ;;
  *) seconds=$1 ;;
esac

if ! command -v "$cc" >/dev/null; then
  echo "fuzz/run.sh: SKIPPED: no $cc on PATH (the fuzzer needs clang's libFuzzer)"
  exit 77
fi
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
printf 'int LLVMFuzzerTestOneInput(const char *d, long n) { return (int)(d[0] + n) * 0; }\n' \
  >"$probe/p.c"
if ! "$cc" -fsanitize=fuzzer,address,undefined "$probe/p.c" -o "$probe/p" 2>"$probe/err"; then
  echo "fuzz/run.sh: SKIPPED: $cc cannot link -fsanitize=fuzzer,address,undefined:"
  sed 's/^/  /' "$probe/err" | head -5
  exit 77
fi

# -O1: the sanitizers' usual level (a fuzzer wants speed, a report wants usable stacks).
cmake -S . -B "$build" -DCMAKE_C_COMPILER="$cc" -DPENCIL_FUZZ=ON -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_C_FLAGS_DEBUG=-O1 >"$probe/cmake.log" 2>&1 || { cat "$probe/cmake.log"; exit 1; }
cmake --build "$build" -j "$(nproc)" --target scene_fuzz >"$probe/build.log" 2>&1 ||
  { cat "$probe/build.log"; exit 1; }

if [ $smoke -eq 1 ]; then
  corpus=$probe/corpus
else
  corpus=$build/corpus
fi
fuzz/seed.sh "$corpus"
mkdir -p "$build/crashes"
# Scenes are a few KB (the largest seed beyond 16 KB is a deliberately oversized bad face);
# -max_len keeps mutations in that range. -timeout: seconds for one input (the harness bounds
# the image, the samples and the ray-tree depth, so a slow input is a finding): 30. The seeds
# include scenes/fig8-caustics.json, whose caustic maps take about 4 s under the sanitizers and
# coverage on an idle machine, and scenes/fig11-caustics.json, 10 to 12 s (its torus's facets
# divide nearly every grid pencil to the limit: 81 light rays become 39,594). At 10 s the smoke
# run failed once beside other tests, and the long run stopped on a copy of fig11-caustics.json
# with one digit changed (docs/journal/2026-12-05-spectral-channel.md).
timeout=30
echo "fuzz/run.sh: $seconds s on $corpus (crashes go to $build/crashes/)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1 \
  "$build/fuzz/scene_fuzz" -max_total_time="$seconds" -timeout=$timeout -rss_limit_mb=2048 \
  -max_len=20000 -dict=fuzz/scene.dict -print_final_stats=1 \
  -artifact_prefix="$build/crashes/" "$corpus"
