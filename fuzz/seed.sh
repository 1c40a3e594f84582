#!/usr/bin/env bash
# The fuzzer's seed corpus: copies the scene files of scenes/, the broken scenes of
# tests/scenes_bad/ and the fuzzer's own regression inputs fuzz/regress/ (findings that load) into
# DIR (created if needed), prefixed by their folder so that names do not collide. Nothing else is
# committed: the seeds are the files already in the tree.
# Usage: fuzz/seed.sh DIR
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: fuzz/seed.sh DIR" >&2
  exit 2
fi
src=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$1"
for f in "$src"/scenes/*.json; do cp "$f" "$1/scenes_$(basename "$f")"; done
for f in "$src"/tests/scenes_bad/*.json; do cp "$f" "$1/bad_$(basename "$f")"; done
for f in "$src"/fuzz/regress/*.json; do cp "$f" "$1/regress_$(basename "$f")"; done
