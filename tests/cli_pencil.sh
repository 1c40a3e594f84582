#!/usr/bin/env bash
# The pencil renderer's command-line contracts (issue 5): `pencil render --method pencil` writes
# an EXR with the reference channels plus pencil.error / pencil.method / pencil.rays and a PNG,
# --measure prints the Fig. 10 statistics; bad options exit 2 naming the option; `pencil sweep`
# writes sweep.csv with one row per rho and variant; --help exits 0 for every new command; `pencil figures --fig9-spp` extends Fig. 9 beyond 49 spp; a scene
# with nothing to measure says so.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

out=$($pencil render --method pencil -o "$tmp/p.exr" --size 24x20 --spp 4 --threads 2 --measure 2>"$tmp/err"); rc=$?
check "pencil render exits 0" "[ $rc -eq 0 ]"
check "EXR and PNG written" "[ -s '$tmp/p.exr' ] && [ -s '$tmp/p.png' ]"
for ch in pencil.error pencil.method pencil.rays pathT.u R; do
  check "EXR has channel $ch" "grep -aq '$ch' '$tmp/p.exr'"
done
check "closing line names the methods" "echo '$out' | grep -q 'matrix, .* interpolated, .* exact'"
check "--measure prints the Fig. 10 line" "echo '$out' | grep -q 'Fig. 10 error: .* within rho = 0.5'"
check "no progress bar when stderr is not a terminal" "[ ! -s '$tmp/err' ]"

# a scene with no surface the error measure compares (glass only): said on stderr, not passed off
# as error-free; the benchmark does not call its accuracy target met
cat >"$tmp/glass.json" <<'JSON'
{"camera": {"eye": [0, 0, -5], "look_at": [0, 0, 0], "fov": 40, "width": 16, "height": 16},
 "materials": {"glass": {"ka": 0, "kd": 0, "ks": 0.6, "phong": 80, "kr": 0.15, "kt": 0.75, "ior": 1.5}},
 "lights": [{"type": "point", "position": [-5, 6, -2.5], "intensity": 1}],
 "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"}]}
JSON
out=$($pencil render "$tmp/glass.json" --method pencil -o "$tmp/g.exr" --spp 4 --measure 2>"$tmp/err"); rc=$?
check "--measure on a glass-only scene: exit 0, 0 samples with measured points, a warning on stderr" \
  "[ $rc -eq 0 ] && echo '$out' | grep -q '(0 with measured points)' && grep -q 'compared nothing' '$tmp/err'"
$pencil bench pencil "$tmp/glass.json" --runs 3 --json "$tmp/g.json" >"$tmp/log" 2>&1; rc=$?
check "bench pencil on a glass-only scene: warns, no target met, samples_with_points 0 and no error figures in JSON" \
  "[ $rc -eq 0 ] && grep -q 'compared nothing' '$tmp/log' && ! grep -q ' yes$' '$tmp/log' && $py -c 'import json; d=json.load(open(\"$tmp/g.json\")); assert all(r[\"samples_with_points\"] == 0 and r[\"fraction_within\"] is None and r[\"target_met\"] is False for r in d[\"results\"])'"

# certified mode on scenes/balls.json: the matte ball seen through the glass ball at depth 3 had
# 3 samples over rho (largest 0.549) while the measure saw only the checkerboard; a bilinear
# interpolation's error can reach 1.38 times its largest measured deviation (docs/pencil.md)
scenes=$(cd "$(dirname "$0")/../scenes" && pwd)
out=$($pencil render "$scenes/balls.json" --method pencil --certified --measure --spp 4 -o "$tmp/b.exr" 2>/dev/null); rc=$?
check "certified balls.json at 4 spp: every sample within rho, matte and mirror balls measured" \
  "[ $rc -eq 0 ] && echo '$out' | grep -q ' 100.0000% within rho = 0.5' && [ \$(echo '$out' | sed -n 's/.*(\([0-9]*\) with measured points).*/\1/p') -gt 214000 ]"

for bad in "--rho 0" "--rho -1" "--bounds exact" "--domain 0" "--domain 33" "--spp 5"; do
  opt=${bad%% *}
  $pencil render --method pencil -o "$tmp/q.exr" --size 8x8 $bad >/dev/null 2>"$tmp/err"; rc=$?
  check "render $bad: exit 2 naming $opt" "[ $rc -eq 2 ] && grep -q -- '$opt' '$tmp/err'"
done
check "no image after usage errors" "[ ! -e '$tmp/q.exr' ]"

for cmd in "render --method pencil" figures sweep; do
  $pencil $cmd --help >"$tmp/help"; rc=$?
  check "$cmd --help exits 0 with usage" "[ $rc -eq 0 ] && grep -q usage '$tmp/help'"
done
$pencil sweep --rho 0.5,0 >/dev/null 2>"$tmp/err"; rc=$?
check "sweep --rho with 0: exit 2 naming --rho" "[ $rc -eq 2 ] && grep -q -- '--rho' '$tmp/err'"
$pencil sweep --spp 5 >/dev/null 2>"$tmp/err"; rc=$?
check "sweep --spp 5: exit 2" "[ $rc -eq 2 ] && grep -q -- '--spp' '$tmp/err'"
for bad in "49,9" "1,9,1089" "9,9" "" "1,,4"; do
  $pencil figures --fig9-spp "$bad" --out "$tmp/bad" >/dev/null 2>"$tmp/err"; rc=$?
  check "figures --fig9-spp '$bad': exit 2 naming --fig9-spp, nothing written" \
    "[ $rc -eq 2 ] && grep -q -- '--fig9-spp' '$tmp/err' && [ ! -e '$tmp/bad' ]"
done
for list in 1,4,64 1,49,64; do # Fig. 9 beyond the paper's 49; the targets stay at 49 when listed
  $pencil figures --quick --no-sweep --size 16x16 --fig9-spp $list --out "$tmp/f$list" >"$tmp/log"; rc=$?
  want=$([ $list = 1,49,64 ] && echo 49 || echo 64)
  check "figures --fig9-spp $list: fig9.csv rows, targets at $want spp, the crossing in JSON and table" \
    "[ $rc -eq 0 ] && [ \$(grep -vc '^#' '$tmp/f$list/fig9.csv') -eq 4 ] && grep -q 'ratio <= 0.10 from this spp on' '$tmp/log' && $py -c 'import json; d=json.load(open(\"$tmp/f$list/summary.json\")); assert [r[\"spp\"] for r in d[\"fig9\"]] == [int(x) for x in \"$list\".split(\",\")] and d[\"targets\"][\"spp\"] == $want and \"fig9_below_0_1_from_spp\" in d'"
done
check "figures: the targets' cost with no accuracy asked, in JSON and the table" \
  "grep -q 'with no accuracy asked (rho 100, brightness 100)' '$tmp/log' && $py -c 'import json; t=json.load(open(\"$tmp/f1,49,64/summary.json\"))[\"targets\"][\"no_accuracy\"]; assert t[\"rho\"] == 100 and t[\"brightness_tol\"] == 100 and t[\"ratio\"] > 0 and t[\"certified_ratio\"] > 0, t'"
# a progress bar on a terminal's stderr, erased before each log line and at the end, none else
$pencil figures --quick --no-sweep --size 16x16 --fig9-spp 1,4 --out "$tmp/fb" >"$tmp/log" 2>"$tmp/err"; rc=$?
check "figures without a terminal: no progress bar" "[ $rc -eq 0 ] && [ ! -s '$tmp/err' ]"
script -qec "$pencil figures --quick --no-sweep --size 16x16 --fig9-spp 1,4 --out '$tmp/ft'" /dev/null \
  >"$tmp/tty" 2>&1; rc=$?
check "figures on a terminal: a bar of work items, erased before the log's lines and at the end" \
  "[ $rc -eq 0 ] && $py - '$tmp/tty' '$tmp/log' <<'PY'
import re, sys
t = open(sys.argv[1], encoding='utf-8', newline='').read().replace('\\r\\n', '\\n')
bars = re.findall(r'pencil figures \\[[# ]{40}\\] (\\d+)/(\\d+) work items(.{0,4})', t, re.S)
assert len(bars) >= 5 and all(b[2].startswith('\\r\\x1b[K') for b in bars), bars
assert [int(b[0]) for b in bars] == list(range(len(bars))) and {b[1] for b in bars} == {str(len(bars))}
seen = re.sub(r'[^\\n]*\\r\\x1b\\[K', '', t)  # what the terminal shows once a bar is erased
log = [l for l in open(sys.argv[2]).read().splitlines() if l.startswith('  Fig. 9:')]
assert [l[:16] for l in log] == [l[:16] for l in seen.splitlines() if l.startswith('  Fig. 9:')], (log, seen)
PY"
# out of memory part way (a 400 MB address space, a 4096 x 4096 image): exit 1 with the reason,
# on a terminal after the bar is erased (before, exit 1 and no message)
script -qec "bash -c 'ulimit -v 400000; $pencil figures --quick --no-sweep --size 4096x4096 --fig9-spp 1,4 --out \"$tmp/fm\"'" \
  /dev/null >"$tmp/tty" 2>&1; rc=$?
check "figures out of memory on a terminal: exit 1, the reason after the bar is erased" \
  "[ $rc -eq 1 ] && grep -aq \"work items\$(printf '\\r\\033')\\[Kpencil figures: a timed render at 1 spp: cannot allocate a 4096x4096 image\" '$tmp/tty'"
$pencil figures --bogus >/dev/null 2>"$tmp/err"; rc=$?
check "figures --bogus: exit 2" "[ $rc -eq 2 ] && grep -q -- '--bogus' '$tmp/err'"
for cmd in figures sweep; do # a scene error is an input error, as for render; nothing written
  $pencil $cmd "$tmp/missing.json" --quick --out "$tmp/f" >/dev/null 2>"$tmp/err"; rc=$?
  check "$cmd on a missing scene file: exit 2 naming it, no output folder" \
    "[ $rc -eq 2 ] && grep -q 'missing.json' '$tmp/err' && [ ! -e '$tmp/f' ]"
done

$pencil sweep --quick --size 24x24 --rho 0.5,1 --spp 4 --out "$tmp/s" >"$tmp/log"; rc=$?
check "sweep exits 0" "[ $rc -eq 0 ]"
check "sweep.csv: header + 2 rho x 3 variants" "[ \$(grep -vc '^#' '$tmp/s/sweep.csv') -eq 7 ]"
check "sweep.csv has the three variants" \
  "grep -q ',corrected,' '$tmp/s/sweep.csv' && grep -q ',printed,' '$tmp/s/sweep.csv' && grep -q ',certified,' '$tmp/s/sweep.csv'"
check "sweep.json written" "[ -s '$tmp/s/sweep.json' ]"

finish cli_pencil
