#!/usr/bin/env bash
# `pencil bench pencil --peer povray` with POV-Ray installed (issue 26's peer): a scene the
# exporter refuses is timed without it, with a note; POV-Ray's columns and JSON are consistent
# with the times; its private directories are removed, even under a TMPDIR with a space. The
# checks without POV-Ray are tests/cli_bench_pencil.sh's. Skipped (77) without povray.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
if ! command -v povray >/dev/null; then
  echo "SKIP: povray (POV-Ray 3.7) is not installed (scripts/deps installs it)"
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
src=$(dirname "$0")/../scenes
ptmp="$tmp/povray tmp" # POV-Ray's private directories go here, where no other run makes any;
# a space in the path, which POV-Ray's +I switch must be given quoted
mkdir -p "$ptmp"
# (the prism: its dispersive glass is refused, and it renders in milliseconds at 8 x 8)
$pencil bench pencil "$src/prism.json" --size 8x8 --spp 1 --runs 3 --no-measure --peer povray >"$tmp/out" 2>"$tmp/err"; rc=$?
check "--peer povray on a scene the exporter refuses: exit 0, a note with its reason" \
  "[ $rc -eq 0 ] && grep -q \"the scene cannot be exported: material 'sf11': a dispersive index\" '$tmp/err'"
# 64 x 64: POV-Ray prints its CPU seconds to the millisecond, and at 1 spp it takes about 7 ms
TMPDIR="$ptmp" $pencil bench pencil --size 64x64 --spp 1,4 --runs 3 --no-measure --peer povray --json "$tmp/pv.json" >"$tmp/out" 2>"$tmp/err"; rc=$?
check "--peer povray: exit 0, POV-Ray's columns filled, its JSON consistent with the times" \
  "[ $rc -eq 0 ] && grep -q 'POV-Ray 3.7' '$tmp/out' && $py - '$tmp/pv.json' <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d['peer']['name'] == 'povray' and d['peer']['timed'] is True and d['peer']['why'] is None, d['peer']
assert d['peer']['version'].startswith('3.7'), d['peer']
r = d['results']
assert [(x['spp'], x['mode']) for x in r] == [(1, 'default'), (1, 'certified'), (4, 'default'), (4, 'certified')]
for x in r:
  p = x['povray']
  assert p['seconds'] > 0 and p['process_seconds'] >= p['seconds'] * 0.5, p
  assert p['rays'] == p['traced_rays'] + p['shadow_tests'], p
  # the camera rays alone: one per pixel of the image s times the size
  assert p['traced_rays'] >= 64 * 64 * x['spp'], (x['spp'], p)
  assert abs(p['pencil_over_povray'] - x['pencil_s'] / p['seconds']) <= 1e-9 * p['pencil_over_povray']
  assert abs(p['exact_over_povray'] - x['exact_s'] / p['seconds']) <= 1e-9 * p['exact_over_povray']
  assert abs(p['rays_per_second'] * p['seconds'] - p['rays']) <= 1e-6 * p['rays']
assert r[0]['povray']['seconds'] == r[1]['povray']['seconds']  # the certified row shares them
PY"
left=$(ls -A "$ptmp" | wc -l)
check "POV-Ray's private directories removed ($left left in TMPDIR)" "[ $left -eq 0 ]"

# interrupted while POV-Ray runs (SIGTERM to pencil alone, as a batch system sends it): POV-Ray
# is stopped and the private directory removed; pencil dies of the signal
itmp="$tmp/interrupted"
mkdir -p "$itmp"
TMPDIR="$itmp" $pencil bench pencil --size 256x256 --spp 49 --runs 3 --no-measure --peer povray \
  >"$tmp/out" 2>"$tmp/err" &
pid=$!
child=""
for _ in $(seq 600); do # up to 60 s for the exact and pencil runs before POV-Ray's
  child=$(pgrep -P $pid -x povray || true)
  [ -n "$child" ] && break
  sleep 0.1
done
check "POV-Ray started under bench pencil (child pid '${child}')" "[ -n '$child' ]"
kill -TERM $pid
wait $pid; rc=$?
gone=0
for _ in $(seq 50); do
  # gone, or a zombie that no one reaps (a container whose PID 1 does not): it runs no more
  if [ -n "$child" ] && { ! kill -0 "$child" 2>/dev/null ||
    ps -o stat= -p "$child" 2>/dev/null | grep -q Z; }; then gone=1; break; fi
  sleep 0.1
done
left=$(ls -A "$itmp" | wc -l)
check "SIGTERM: pencil dies of it (rc $rc), POV-Ray stopped, no private directory left ($left)" \
  "[ $rc -eq 143 ] && [ $gone -eq 1 ] && [ $left -eq 0 ]"

if [ $fail -ne 0 ]; then
  echo "cli_bench_pencil_povray: FAILED"
  exit 1
fi
echo "cli_bench_pencil_povray: all passed"
