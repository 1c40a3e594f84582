#!/usr/bin/env bash
# The `pencil render` and `pencil bench` contracts: an EXR with the documented channels and a PNG
# beside it; the closing line with time, rays and rays/s on stdout; --explain prints the effects
# plan; usage and scene errors exit 2 naming the option or file:line; --method pencil hands over
# to the pencil tracer (tests/cli_pencil.sh has its contract); bench writes JSON with 1- and
# 2-thread rows for both scenes.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

out=$($pencil render -o "$tmp/a.exr" --size 24x16 --spp 4 --threads 2 2>"$tmp/err"); rc=$?
check "built-in scene renders (exit 0)" "[ $rc -eq 0 ]"
check "EXR and PNG written" "[ -s '$tmp/a.exr' ] && [ -s '$tmp/a.png' ]"
check "closing line: time, rays, rays/s" "echo '$out' | grep -Eq 'in [0-9.]+ s: [0-9]+ rays .* rays/s'"
check "no progress bar when stderr is not a terminal" "[ ! -s '$tmp/err' ]"
check "PNG preview has the image size" \
  "$py -c 'import struct,sys; d=open(\"$tmp/a.png\",\"rb\").read(24); sys.exit(struct.unpack(\">II\", d[16:24]) != (24, 16))'"

out2=$($pencil render -o "$tmp/n.exr" --size 24x16 --spp 4 --threads 2 --no-aux 2>/dev/null); rc=$?
# the same PNG but for its text chunks, which record each command line
png_same() {
  $py - "$1" "$2" <<'PY'
import struct, sys
def chunks(p):
    d, i, out = open(p, "rb").read(), 8, []
    while i < len(d):
        n, kind = struct.unpack(">I", d[i:i + 4])[0], d[i + 4:i + 8]
        if kind not in (b"tEXt", b"iTXt", b"zTXt"):
            out.append(d[i:i + 12 + n])
        i += 12 + n
    return out
sys.exit(chunks(sys.argv[1]) != chunks(sys.argv[2]))
PY
}
check "--no-aux renders the same image (PNG identical but for its provenance text)" "[ $rc -eq 0 ] && png_same '$tmp/a.png' '$tmp/n.png'"
check "--no-aux traces no centre-ray trees (384 fewer primary rays)" \
  "[ \$(echo '$out' | sed -E 's/.*[(]([0-9]+) primary.*/\\1/') -eq \$((\$(echo '$out2' | sed -E 's/.*[(]([0-9]+) primary.*/\\1/') + 384)) ]"
$pencil render "$src/scenes/balls.json" -o "$tmp/b.exr" --size 8x6 --explain >"$tmp/plan"; rc=$?
check "scene file renders with --explain" "[ $rc -eq 0 ]"
check "--explain names each effect and why" \
  "grep -q 'refraction *on: material .glass.' '$tmp/plan' && grep -q 'caustics *off' '$tmp/plan'"
$pencil render "$src/scenes/fig8.json" --explain >"$tmp/plan"; rc=$?
check "--explain alone prints the plan without rendering" \
  "[ $rc -eq 0 ] && grep -q 'effects plan' '$tmp/plan' && ! grep -q rendered '$tmp/plan'"

# caustics: the plan names the object and the receiver; the closing lines and the EXR header say
# what the maps took; bad caustic options exit 2 naming the option, nothing written
$pencil render "$src/scenes/fig8-caustics.json" --explain >"$tmp/plan"; rc=$?
check "--explain: caustics on through the ball onto the board" \
  "[ $rc -eq 0 ] && grep -q \"caustics *on: .* through 'glass ball' onto 'checkerboard'\" '$tmp/plan'"
# with "shadows": false every light reaches every point directly: a map would add the light
# through the ball a second time (a probe found the focus at 99 against 0.59), so the plan turns
# caustics off and says why, and the image is the one with "caustics": "off"
sed 's/"settings": {/"settings": {"shadows": false, /' "$src/scenes/fig8-caustics.json" >"$tmp/ns.json"
sed 's/"caustics": "auto"/"caustics": "off"/' "$tmp/ns.json" >"$tmp/ns-off.json"
$pencil render "$tmp/ns.json" --explain >"$tmp/plan"; rc=$?
check "--explain: shadows off turns caustics off, saying why" \
  "[ $rc -eq 0 ] && grep -q \"caustics *off: shadows are off .*light through 'glass ball' would be counted twice\" '$tmp/plan'"
for m in exact pencil; do
  $pencil render "$tmp/ns.json" --method $m --size 16x16 --spp 1 -o "$tmp/ns-$m.exr" >/dev/null 2>&1
  $pencil render "$tmp/ns-off.json" --method $m --size 16x16 --spp 1 -o "$tmp/ns-off-$m.exr" >/dev/null 2>&1
  check "--method $m, shadows off: the same image as with caustics off" \
    "$py -c \"import OpenImageIO as o,numpy as n,sys; a,b=(o.ImageBuf(p).get_pixels(o.FLOAT)[...,:3] \
for p in ('$tmp/ns-$m.exr','$tmp/ns-off-$m.exr')); sys.exit(0 if n.array_equal(a,b) else 1)\""
done
for m in exact pencil; do
  $pencil render "$src/scenes/fig8-caustics.json" --method $m --size 16x16 --spp 1 \
    --caustic-rays 65 --caustic-cells 32 -o "$tmp/cz-$m.exr" >"$tmp/out" 2>"$tmp/err"; rc=$?
  check "--method $m with caustics: exit 0, a caustics line" \
    "[ $rc -eq 0 ] && grep -q '^caustics: 1 map(s) of 32 cells' '$tmp/out'"
  check "--method $m with caustics: the EXR header records the maps" \
    "$py -c \"import OpenImageIO as o,sys; i=o.ImageInput.open('$tmp/cz-$m.exr'); \
sys.exit(0 if 'rays a side, 32 cells' in i.spec().get_string_attribute('pencil:caustics') else 1)\""
done
# an area light: drawn by both renderers (its mesh points' soft light and its caustic map); the
# polygons method, which takes point and parallel lights only, is refused naming the light
cat >"$tmp/area.json" <<'JSON'
{"camera": {"eye": [0, 4, -3], "look_at": [0, 0, 0]},
 "settings": {"max_depth": 4},
 "materials": {"white": {"kd": 0.5}, "glass": {"kd": 0, "ka": 0, "kt": 0.8, "ior": 1.5}},
 "lights": [{"type": "area", "center": [0, 4, 0], "edge_u": [0.6, 0, 0], "edge_v": [0, 0, 0.4],
             "intensity": 16, "samples": 3}],
 "objects": [{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
              "material": "white"},
             {"type": "faceted_sphere", "name": "gem", "center": [0, 1, 0], "radius": 0.5,
              "stacks": 4, "slices": 6, "material": "glass"}]}
JSON
for m in exact pencil; do
  $pencil render "$tmp/area.json" --method $m --size 16x16 --spp 1 --caustic-rays 65 \
    --caustic-cells 32 -o "$tmp/area-$m.exr" >"$tmp/out" 2>"$tmp/err"; rc=$?
  check "--method $m with an area light: exit 0, its caustic map made" \
    "[ $rc -eq 0 ] && [ -s '$tmp/area-$m.exr' ] && grep -q '^caustics: 1 map(s) of 32 cells' '$tmp/out'"
done
$pencil render "$tmp/area.json" --size 8x8 --caustic-method polygons -o "$tmp/area-bad.exr" \
  >/dev/null 2>"$tmp/err"; rc=$?
check "--caustic-method polygons with an area light: exit 2 naming the light" \
  "[ $rc -eq 2 ] && grep -q 'area light' '$tmp/err' && [ ! -e '$tmp/area-bad.exr' ]"
grep -q "by photons" <($pencil render "$src/scenes/fig8-caustics.json" --size 8x8 --spp 1 \
  --caustic-rays 33 --caustic-cells 8 -o "$tmp/cz.exr"); rc=$?
check "the exact renderer maps by photons by default" "[ $rc -eq 0 ]"
for bad in "--caustic-method sunlight" "--caustic-rays 1" "--caustic-cells 0" \
  "--caustic-method polygons"; do
  $pencil render "$src/scenes/fig8-caustics.json" --size 8x8 $bad -o "$tmp/bad.exr" \
    >/dev/null 2>"$tmp/err"; rc=$?
  opt=${bad%% *}
  check "$bad: exit 2 naming $opt, nothing written" \
    "[ $rc -eq 2 ] && grep -q -- '$opt' '$tmp/err' && [ ! -e '$tmp/bad.exr' ]"
done
grep -q "sphere" "$tmp/err"; rc=$?
check "--caustic-method polygons on a sphere says why" "[ $rc -eq 0 ]"

$pencil render -o "$tmp/p.exr" --method pencil --size 20x20 --spp 1 >/dev/null 2>"$tmp/err"; rc=$?
check "--method pencil renders (exit 0)" "[ $rc -eq 0 ] && [ -s '$tmp/p.exr' ]"
$pencil render -o "$tmp/c.exr" --spp 5 >/dev/null 2>"$tmp/err"; rc=$?
check "--spp 5 is a usage error naming --spp" "[ $rc -eq 2 ] && grep -q -- '--spp' '$tmp/err'"
$pencil render -o "$tmp/c.exr" --spp 1089 >/dev/null 2>"$tmp/err"; rc=$?
check "--spp 1089 (33 x 33, above the largest grid) is a usage error naming --spp" \
  "[ $rc -eq 2 ] && grep -q -- '--spp' '$tmp/err' && [ ! -e '$tmp/c.exr' ]"
for m in exact pencil; do # beyond the paper's 49: the grids up to 32 x 32
  $pencil render -o "$tmp/g_$m.exr" --method $m --size 6x6 --spp 1024 --threads 2 >"$tmp/out" 2>"$tmp/err"; rc=$?
  check "--method $m --spp 1024 renders (exit 0)" "[ $rc -eq 0 ] && [ -s '$tmp/g_$m.exr' ] && grep -q '1024 spp' '$tmp/out'"
done
$pencil render -o "$tmp/c.exr" --threads 0 >/dev/null 2>"$tmp/err"; rc=$?
check "--threads 0 is a usage error" "[ $rc -eq 2 ] && grep -q -- '--threads' '$tmp/err'"
$pencil render --size 10 -o "$tmp/c.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "--size without x is a usage error" "[ $rc -eq 2 ] && grep -q -- '--size' '$tmp/err'"
$pencil render >/dev/null 2>"$tmp/err"; rc=$?
check "missing -o is a usage error" "[ $rc -eq 2 ] && grep -q -- '-o' '$tmp/err'"
$pencil render "$src/tests/scenes_bad/sphere_negative_radius.json" -o "$tmp/c.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "bad scene: exit 2 with file:line" "[ $rc -eq 2 ] && grep -q 'sphere_negative_radius.json:9: objects\[0\].radius' '$tmp/err'"
check "bad scene: no image written" "[ ! -e '$tmp/c.exr' ]"
$pencil render "$tmp/none.json" -o "$tmp/c.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "missing scene file: exit 2 naming it" "[ $rc -eq 2 ] && grep -q 'none.json' '$tmp/err'"
$pencil render -o /nonexistent-dir/x.exr --size 4x4 >/dev/null 2>"$tmp/err"; rc=$?
check "unwritable output: exit 2 naming it, before rendering" "[ $rc -eq 2 ] && grep -q '/nonexistent-dir/x.exr' '$tmp/err'"

out=$($pencil bench render --runs 1 --size 8x8 --json "$tmp/bench.json"); rc=$?
check "bench render runs" "[ $rc -eq 0 ] && echo '$out' | grep -q mesh1000"
check "bench JSON: fig8 and mesh1000 at 1 and 2 threads" \
  "$py -c 'import json; r=json.load(open(\"$tmp/bench.json\"))[\"results\"]; assert sorted((x[\"scene\"], x[\"threads\"]) for x in r) == [(\"fig8\",1),(\"fig8\",2),(\"mesh1000\",1),(\"mesh1000\",2)] and all(x[\"rays_per_second\"] > 0 for x in r) and r[2][\"primitives\"] > 1000'"
$pencil bench render --runs 0 >/dev/null 2>&1; rc=$?
check "bench --runs 0 is a usage error" "[ $rc -eq 2 ]"
for c in "render" "bench"; do
  $pencil $c --help >"$tmp/help" 2>&1; rc=$?
  check "pencil $c --help exits 0 and prints usage" "[ $rc -eq 0 ] && grep -q usage '$tmp/help'"
done
finish cli_render
