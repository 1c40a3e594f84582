#!/usr/bin/env bash
# Messages of the pencil command (docs/journal/2026-12-06-cli-mends.md): the benchmarks listed
# from one table; every error names its command ("pencil CMD: ...", never a plain "pencil: "
# once a command is known); numbers echoed as they read back (not %g: 89.9999999999 is not 90);
# a UTF-8 byte order mark at the start of a scene skipped; out of memory while loading a scene
# exits 1 and says so.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$(realpath "$1")
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# --- the benchmarks, from one table: `bench foo` names every one `bench --help` lists
$pencil bench foo >/dev/null 2>"$tmp/err"; rc=$?
names=$($pencil bench --help | sed -n 's/^usage: pencil bench \([a-z|]*\).*/\1/p' | tr '|' ' ')
check "bench --help lists dispersion among the benchmarks" "echo '$names' | grep -qw dispersion"
missing=""
for b in $names; do grep -qw "$b" "$tmp/err" || missing="$missing $b"; done
check "bench foo: exit 2 naming every benchmark (once it left out dispersion)" \
  "[ $rc -eq 2 ] && [ -z '$missing' ] && grep -q \"unknown benchmark 'foo'\" '$tmp/err'"

# --- every error names its command
echo x >"$tmp/afile"
$pencil render --size 8x8 --spp 1 -o "$tmp/a.exr" >/dev/null 2>&1 # an input for post star
while IFS='|' read -r want args; do
  # shellcheck disable=SC2086
  $pencil $args >/dev/null 2>"$tmp/err"; rc=$?
  check "'$args': exit 2, the message starts '$want: '" \
    "[ $rc -eq 2 ] && head -1 '$tmp/err' | grep -q '^$want: ' && ! grep -q '^pencil: ' '$tmp/err'"
done <<EOF2
pencil render|render --size 8x8 --threads x -o $tmp/b.exr
pencil verify stability|verify stability --samples x
pencil verify matrices|verify matrices --quick --json $tmp
pencil bench star|bench star --runs x
pencil bench render|bench render --runs 0
pencil post star|post star $tmp/a.exr -o $tmp/c.exr --angle x
pencil matrix refract|matrix refract --theta-deg x --n1 1 --n2 1.5
pencil bounds reflect|bounds reflect --theta-deg 10 --d3m -1
pencil sweep|sweep --quick --out $tmp/afile
pencil figures|figures --quick --out $tmp/afile
pencil illuminance|illuminance $src/scenes/fig8.json --receiver checkerboard -o $tmp/m.exr --rays x
EOF2

# --- numbers echoed as they read back, not rounded by %g
$pencil matrix refract --theta-deg 90.0000000001 --n1 1 --n2 1.5 >/dev/null 2>"$tmp/err"; rc=$?
check "theta 90.0000000001 is echoed whole (once 'got 90')" \
  "[ $rc -eq 2 ] && grep -q 'got 90.0000000001$' '$tmp/err'"
$pencil matrix refract --theta-deg 89.9999999999 --n1 1 --n2 1.5 >/dev/null 2>"$tmp/err"; rc=$?
check "theta 89.9999999999 (grazing): 'theta = 89.9999999999 deg' (once 'theta = 90 deg')" \
  "[ $rc -eq 1 ] && grep -q 'theta = 89.9999999999 deg, n1 = 1, n2 = 1.5' '$tmp/err'"
$pencil bounds refract --theta-deg 89.9999999999 --n1 1.000000000001 --n2 1.5 >/dev/null 2>"$tmp/err"
check "bounds echoes theta and n1 whole" \
  "grep -q 'theta = 89.9999999999 deg, n1 = 1.000000000001, n2 = 1.5' '$tmp/err'"
sed 's/"fov": [0-9.]*/"fov": 179.0000000001/' "$src/scenes/fig8.json" >"$tmp/fov.json"
$pencil render "$tmp/fov.json" -o "$tmp/f.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a scene's number out of range is echoed whole: 'got 179.0000000001' (once 'got 179')" \
  "[ $rc -eq 2 ] && grep -q 'camera.fov: expected a number > 0 and <= 179, got 179.0000000001' '$tmp/err'"
$pencil sweep --quick --size 12x8 --rho 0.1234567 --out "$tmp/s" >/dev/null 2>&1; rc=$?
check "sweep.csv holds rho as given (once 0.123457)" \
  "[ $rc -eq 0 ] && grep -v '^#' '$tmp/s/sweep.csv' | grep -q '^0.1234567,corrected,'"
$pencil post star "$tmp/a.exr" -o "$tmp/st.exr" --angle 20.123456789 >/dev/null 2>&1; rc=$?
check "post star: the EXR's pencil:star holds the angle as given (once 20.1235)" \
  "[ $rc -eq 0 ] && grep -aq 'angle 20.123456789 deg' '$tmp/st.exr'"

# --- a UTF-8 byte order mark is skipped; a scene error after it keeps its line
printf '\xef\xbb\xbf' >"$tmp/bom.json"
cat "$src/scenes/fig8.json" >>"$tmp/bom.json"
$pencil render "$tmp/bom.json" --size 8x8 --spp 1 -o "$tmp/bom.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a scene starting with a UTF-8 BOM renders (once 'invalid JSON')" "[ $rc -eq 0 ] && [ -s '$tmp/bom.exr' ]"
printf '\xef\xbb\xbf{\n "camera": 3}\n' >"$tmp/bom2.json"
$pencil render "$tmp/bom2.json" -o "$tmp/bom.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "... and its errors keep the file's lines" "[ $rc -eq 2 ] && grep -q 'bom2.json:2: camera: expected an object' '$tmp/err'"

# --- out of memory while loading a scene is a failure of the work (1), not of the input (2), and
# says so (once: exit 2 and "cannot build the faceted sphere"): three faceted spheres of 512 x 512
# facets need some 300 MB, the address space is limited to 200 MB
big='{"camera": {"eye": [0, 2, -10], "look_at": [0, 1, 0], "fov": 40, "width": 8, "height": 8},
 "materials": {"m": {"kd": 0.8}}, "objects": ['
for i in 0 1 2; do
  big="$big$([ $i -gt 0 ] && echo ,){\"type\": \"faceted_sphere\", \"center\": [$((3 * i)), 1, 0], \"radius\": 1, \"stacks\": 512, \"slices\": 512, \"material\": \"m\"}"
done
printf '%s]}\n' "$big" >"$tmp/big.json"
mkdir -p "$tmp/bigdir" && cp "$tmp/big.json" "$tmp/bigdir/fig14.json"
(ulimit -v 200000; $pencil render "$tmp/big.json" -o "$tmp/big.exr" --threads 1) >/dev/null 2>"$tmp/err"; rc=$?
check "render: out of memory loading a scene exits 1 naming the file and 'out of memory'" \
  "[ $rc -eq 1 ] && grep -q 'big.json:[0-9]*: objects\[[0-9]\]: out of memory' '$tmp/err' && [ ! -e '$tmp/big.exr' ]"
$pencil render "$tmp/big.json" -o "$tmp/big.exr" --threads 1 --method exact >/dev/null 2>&1; rc=$?
check "... and the same scene renders with the memory it needs" "[ $rc -eq 0 ] && [ -s '$tmp/big.exr' ]"
(ulimit -v 200000; $pencil bench dispersion --quick --threads 1 --runs 1 --scenes "$tmp/bigdir") \
  >/dev/null 2>"$tmp/err"; rc=$?
check "bench dispersion: out of memory loading its scene exits 1 (once 2)" \
  "[ $rc -eq 1 ] && grep -q 'out of memory' '$tmp/err'"

# --- the eye inside a closed object: refused when the object transmits light (its surface would
# not refract rays leaving it from inside; tests/scenes_bad/camera_eye_inside_glass.json), accepted
# inside an opaque one, whose inside is what is seen (a room)
sed 's/"material": "glass"}/"material": "white"}/' "$src/tests/scenes_bad/camera_eye_inside_glass.json" >"$tmp/room.json"
$pencil render "$tmp/room.json" --size 8x8 --spp 1 -o "$tmp/room.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "the eye inside an opaque closed object renders" "[ $rc -eq 0 ] && [ -s '$tmp/room.exr' ]"
$pencil render "$src/tests/scenes_bad/camera_eye_inside_glass.json" -o "$tmp/g.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "the eye inside glass: exit 2 naming camera.eye and the object" \
  "[ $rc -eq 2 ] && grep -q \"camera.eye: the eye is inside 'globe'\" '$tmp/err' && [ ! -e '$tmp/g.exr' ]"

finish cli_messages
