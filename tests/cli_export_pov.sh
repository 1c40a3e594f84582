#!/usr/bin/env bash
# The export check of issue 26's peer renderer: `pencil export pov --flat` of the built-in Fig. 8
# scene and of scenes/spheres-10.json rendered by POV-Ray 3.7 at 1 spp, pixel by pixel against the
# exact renderer's id channel (the object met by each pixel's centre ray). The flat file colours
# each object by a code (io/pov.h: object + 1, plus 2^23 on a checkerboard's odd squares), so a
# pixel's POV-Ray object is its PNG bytes; the board's square parity is checked too, against the
# parity of floor(u) + floor(v) of the centre ray's board point (pathT.u, pathT.v where pathT.k is
# 0, the ray met the board first), which catches a left-right flip that Fig. 8's symmetric ids do
# not show.
#
# The limit, 0.01% of the pixels (6 of 65,536) for ids and of the board's pixels for parity: both
# tracers put a pixel centre on the same side of a silhouette, the horizon or a square's edge
# unless the centre lies within rounding distance (about 1e-15 of the scene's size) of it, which
# no pixel of these images does (0 differ, docs/journal/2026-12-03-povray-peer.md), while a
# half-pixel shift, a flip or a field of view off by a part in a thousand moves hundreds of
# silhouette pixels. Also the command's contract: --help, usage errors exit 2 naming the option,
# a refused scene exits 2 naming what is refused, an unwritable path exits 1; and Fig. 9 with
# POV-Ray beside it (`pencil figures --peer povray`), in one run and merged from shards.
# Exit 77 (skipped) when POV-Ray is not installed (scripts/deps installs it).
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# ---- the command's contract (no POV-Ray needed) ----
$pencil export pov --help >"$tmp/help"; rc=$?
check "export pov --help exits 0 with usage" "[ $rc -eq 0 ] && grep -q 'usage: pencil export pov' '$tmp/help'"
$pencil --help >"$tmp/help"; rc=$?
check "pencil --help lists export" "[ $rc -eq 0 ] && grep -q '^  export ' '$tmp/help'"
for bad in "--spp 5" "--size 0x8" "--size 10" "--bogus" "--output"; do
  opt=${bad%% *}
  $pencil export pov -o "$tmp/bad.pov" $bad >/dev/null 2>"$tmp/err"; rc=$?
  check "export pov $bad: exit 2 naming $opt" "[ $rc -eq 2 ] && grep -q -- '$opt' '$tmp/err'"
done
$pencil export pov >/dev/null 2>"$tmp/err"; rc=$?
check "export pov without -o: exit 2 naming -o" "[ $rc -eq 2 ] && grep -q -- '-o OUT.pov' '$tmp/err'"
$pencil export obj -o "$tmp/x.obj" >/dev/null 2>"$tmp/err"; rc=$?
check "export obj: exit 2 naming the format" "[ $rc -eq 2 ] && grep -q \"unknown format 'obj'\" '$tmp/err'"
$pencil export pov "$src/scenes/glass.json" -o "$tmp/glass.pov" >/dev/null 2>"$tmp/err"; rc=$?
check "an area light is refused: exit 2 naming it, nothing written" \
  "[ $rc -eq 2 ] && grep -q 'lights\[0\]: an area light' '$tmp/err' && [ ! -e '$tmp/glass.pov' ]"
$pencil export pov "$src/scenes/fig14.json" -o "$tmp/fig14.pov" >/dev/null 2>"$tmp/err"; rc=$?
check "dispersive glass is refused naming the material" \
  "[ $rc -eq 2 ] && grep -q \"material 'sf11': a dispersive index\" '$tmp/err'"
$pencil export pov -o /nonexistent-dir/x.pov >/dev/null 2>"$tmp/err"; rc=$?
check "unwritable output: exit 2 naming it, before the work" "[ $rc -eq 2 ] && grep -q '/nonexistent-dir/x.pov' '$tmp/err'"
$pencil export pov --size 64x48 --spp 9 -o "$tmp/fig8.pov" >"$tmp/out" 2>"$tmp/err"; rc=$?
check "shaded Fig. 8: exit 0, notes on stderr, header with version, command and render size" \
  "[ $rc -eq 0 ] && grep -q 'note: shadows through' '$tmp/err' && grep -q '^// POV-Ray 3.7 scene written by pencil' '$tmp/fig8.pov' && grep -q '^// command: .*export pov --size 64x48 --spp 9' '$tmp/fig8.pov' && grep -q '+W192 +H144' '$tmp/fig8.pov' && grep -q '^#version 3.7;' '$tmp/fig8.pov'"

# Fig. 9 with --peer povray when POV-Ray is missing from PATH: a note, and its columns nan
nopov=$tmp/nopov
mkdir -p "$nopov"
for t in bash sh python3; do ln -s "$(command -v $t)" "$nopov/$t" 2>/dev/null; done
PATH=$nopov $pencil figures --quick --only fig9 --size 32x32 --peer povray --out "$tmp/fn" >"$tmp/out" 2>&1; rc=$?
check "figures --peer povray without POV-Ray: exit 0, a note, fig9.csv's POV-Ray columns nan" \
  "[ $rc -eq 0 ] && grep -q 'note: --peer povray: povray (POV-Ray 3.7) is not installed' '$tmp/out' && grep -v '^#' '$tmp/fn/fig9.csv' | head -1 | grep -q ',povray_s,povray_rays,pencil_over_povray,exact_over_povray$' && grep -v '^#' '$tmp/fn/fig9.csv' | sed -n 2p | grep -q ',nan,nan,nan,nan$'"
$pencil figures --peer blender --out "$tmp/fb" >/dev/null 2>"$tmp/err"; rc=$?
check "figures --peer blender: exit 2 naming --peer" "[ $rc -eq 2 ] && grep -q -- '--peer' '$tmp/err'"

if ! command -v povray >/dev/null; then
  [ $fail -ne 0 ] && { echo "cli_export_pov: FAILED"; exit 1; }
  echo "SKIP: povray (POV-Ray 3.7) is not installed (scripts/deps installs it); the export check needs it"
  exit 77
fi

# ---- the export check ----
# POV-Ray reads no user configuration: an empty HOME with an empty povray.conf and povray.ini;
# it writes into the current directory, which its I/O restrictions allow.
mkdir -p "$tmp/home/.povray/3.7"
: >"$tmp/home/.povray/3.7/povray.conf"
: >"$tmp/home/povray.ini"
pov() { (cd "$tmp" && env -u DISPLAY HOME="$tmp/home" POVINI="$tmp/home/povray.ini" \
  povray "+I$1" "+O$2" +W256 +H256 -A +FN8 File_Gamma=1.0 +WT1 -D -V >"$tmp/$2.log" 2>&1); }

for case in fig8 spheres-10; do
  scene=""
  [ $case = spheres-10 ] && scene="$src/scenes/spheres-10.json"
  $pencil export pov $scene --flat --size 256x256 --spp 1 -o "$tmp/$case.pov" >/dev/null 2>"$tmp/err"; rc=$?
  check "$case: flat export exits 0" "[ $rc -eq 0 ]"
  pov "$case.pov" "$case-pov.png"; rc=$? # not $case.png: the exact render's preview
  check "$case: POV-Ray renders the flat file" "[ $rc -eq 0 ] && [ -s '$tmp/$case-pov.png' ]"
  [ $rc -eq 0 ] || tail -5 "$tmp/$case-pov.png.log"
  $pencil render $scene --size 256x256 --spp 1 --method exact --threads 1 -o "$tmp/$case.exr" >/dev/null; rc=$?
  check "$case: exact render at 1 spp" "[ $rc -eq 0 ]"
  check "$case: POV-Ray's objects and squares are the exact renderer's (at most 0.01% differ)" \
    "$py - '$tmp/$case-pov.png' '$tmp/$case.exr' $case <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio

def read(path, fmt):
    f = oiio.ImageInput.open(path)
    if f is None:
        sys.exit('cannot open ' + path)
    names = list(f.spec().channelnames)
    a = f.read_image(format=fmt)
    f.close()
    return a, names

png, _ = read(sys.argv[1], 'uint8')
exr, names = read(sys.argv[2], 'float')
b = png[..., :3].astype(np.int64)
code = b[..., 0] + 256 * b[..., 1] + 65536 * b[..., 2]
odd = (code >> 23) & 1
pov_id = (code & ((1 << 23) - 1)) - 1
ch = lambda n: exr[..., names.index(n)]
ids = ch('id').astype(np.int64)
differ = int((pov_id != ids).sum())
# the board (object 0 in both scenes, squares of side 1) met first by the centre ray
board = (ids == 0) & (ch('pathT.k') == 0)
u, v = np.nan_to_num(ch('pathT.u')), np.nan_to_num(ch('pathT.v'))
parity = (np.floor(u).astype(np.int64) + np.floor(v).astype(np.int64)) & 1
flips = int((board & (parity != odd)).sum())
n, nb = ids.size, int(board.sum())
print('%s: %d of %d pixels differ in object, %d of %d board pixels in square parity'
      % (sys.argv[3], differ, n, flips, nb))
assert nb > n // 2, 'the board covers most of the image'
assert differ <= 1e-4 * n, differ
assert flips <= 1e-4 * nb, flips
PY"
done

# Fig. 9 with POV-Ray beside it, in one run and merged from two shards: its columns filled, its
# ray counts (which do not depend on timing) the same both ways
$pencil figures --quick --no-sweep --size 32x32 --peer povray --out "$tmp/f1" >"$tmp/out" 2>&1; rc=$?
check "figures --peer povray: exit 0, the log names POV-Ray's time at each spp" \
  "[ $rc -eq 0 ] && [ \$(grep -c 'Fig. 9: .* POV-Ray [0-9.]* s, pencil / POV-Ray' '$tmp/out') -eq 3 ]"
for k in 1 2; do
  $pencil figures --quick --no-sweep --size 32x32 --peer povray --shard $k/2 --out "$tmp/f2" >/dev/null 2>&1
done
$pencil figures --merge --out "$tmp/f2" >/dev/null 2>&1; rc=$?
check "figures --peer povray: fig9.csv and summary.json hold POV-Ray's figures, merged shards too" \
  "[ $rc -eq 0 ] && $py - '$tmp/f1' '$tmp/f2' <<'PY'
import csv, json, sys
rows = [list(csv.DictReader(l for l in open(d + '/fig9.csv') if not l.startswith('#'))) for d in sys.argv[1:]]
for r in rows[0]:
    assert float(r['povray_s']) >= 0 and int(r['povray_rays']) >= 32 * 32 * int(r['spp']), r
assert [r['povray_rays'] for r in rows[0]] == [r['povray_rays'] for r in rows[1]], rows
s = json.load(open(sys.argv[1] + '/summary.json'))
for t in s['fig9']:
    assert {'povray_s', 'povray_rays', 'pencil_over_povray', 'exact_over_povray'} <= set(t), t
PY"

finish cli_export_pov
