#!/usr/bin/env bash
# `pencil illuminance`: the contract scripts read (options, the EXR's one channel E and its row
# order, MAP.json's keys, MAP.png), and the refusals of bad input: each exits 2, names the option
# or the name at fault, and writes nothing.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$(realpath "$1")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat >"$dir/both.json" <<'JSON'
{"camera": {"eye": [0, 3, -6], "look_at": [0, 0, 0]},
 "materials": {"white": {"kd": 0.8}},
 "lights": [{"type": "point", "position": [0, 5, 0]}],
 "objects": [{"type": "polygon", "name": "rectangle red", "material": "white",
              "vertices": [[0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]]},
             {"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"}]}
JSON
cat >"$dir/ball.json" <<'JSON'
{"camera": {"eye": [0, 3, -6], "look_at": [0, 0, 0]},
 "settings": {"max_depth": 6},
 "materials": {"white": {"kd": 0.8}, "glass": {"kd": 0, "ka": 0, "kr": 0, "kt": 1, "ior": 1.5}},
 "lights": [{"type": "parallel", "direction": [0, -1, 0], "intensity": 1}],
 "objects": [{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
              "material": "white"},
             {"type": "sphere", "name": "ball", "center": [0, 1.5, 0], "radius": 1,
              "material": "glass"}]}
JSON
$pencil illuminance "$dir/ball.json" --receiver floor -o "$dir/m.exr" --grid 40x30 \
  --extent -2,2,-1,2 --rays 1700 >"$dir/out" 2>"$dir/err"; rc=$?
check "a map is written: exit 0, EXR, PNG and JSON" \
  "[ $rc -eq 0 ] && [ -s '$dir/m.exr' ] && [ -s '$dir/m.png' ] && [ -s '$dir/m.json' ]"
check "the EXR has one float channel E, 40 x 30, and says its row order" \
  "oiiotool --info -v '$dir/m.exr' 2>/dev/null | grep -q '40 x   30, 1 channel, float' && oiiotool --info -v '$dir/m.exr' | grep -q 'channel list: E\$' && oiiotool --info -v '$dir/m.exr' | grep -q 'pencil:rows'"
/usr/bin/python3 - "$dir" <<'PY' || fail=1
import json, sys
d = sys.argv[1]
j = json.load(open(f"{d}/m.json"))
for k in ("extent", "grid", "method", "lights", "rays_per_side", "counts", "flux", "seconds", "cpu_seconds",
          "provenance", "receiver"):
    assert k in j, k
assert j["extent"] == [-2, 2, -1, 2] and j["grid"] == [40, 30] and j["method"] == "grid-pencil"
assert j["lights"] == [0] and j["rays_per_side"] == 41 and j["counts"]["rays"] >= 41 * 41
assert 0 < j["flux"]["on_map"] <= j["flux"]["emitted_by_grid"]
print("ok: MAP.json has the documented keys")
PY
# the row order: the ball's focus is at (u, v) = (0, 0), in cell row j = 7 of 30 for v in [-1, 2]
/usr/bin/python3 - "$dir" <<'PY' || fail=1
import sys, OpenImageIO as oiio
d = sys.argv[1]
i = oiio.ImageInput.open(f"{d}/m.exr"); a = i.read_image(format="float")[:, :, 0]; i.close()
row, col = divmod(int(a.argmax()), a.shape[1])
assert (row, col) in ((9, 19), (9, 20), (10, 19), (10, 20)), (row, col)
print("ok: EXR row y holds v cells j = y (the focus at v = 0 is in row 10 of 30)")
PY
$pencil illuminance "$dir/ball.json" --receiver floor -o "$dir/p.exr" --grid 8x8 --extent -2,2,-2,2 \
  --method photons --rays 10000 >/dev/null 2>&1
check "photons write a map too" "grep -q '\"method\": \"photons\"' '$dir/p.json'"

refused() { # name, expected message, args...
  local name=$1 msg=$2; shift 2
  rm -f "$dir/bad.exr" "$dir/bad.png" "$dir/bad.json"
  $pencil illuminance "$@" -o "$dir/bad.exr" >/dev/null 2>"$dir/err"; local rc=$?
  check "$name: exit 2, says '$msg', writes nothing" \
    "[ $rc -eq 2 ] && grep -q -- \"$msg\" '$dir/err' && [ ! -e '$dir/bad.exr' ] && [ ! -e '$dir/bad.json' ] && [ ! -e '$dir/bad.png' ]"
}
# polygons in one plane join one receiver: the three rectangles of Fig. 11, coordinates from the
# first one's first vertex and edge, default extent their bounds
$pencil illuminance "$(dirname "$0")/../scenes/fig11.json" --receiver "rectangle red" \
  --receiver "rectangle green" --receiver "rectangle blue" -o "$dir/f.exr" --grid 24x20 \
  --rays 900 >/dev/null 2>"$dir/err"; rc=$?
check "polygon receivers in one plane join (Fig. 11's rectangle)" \
  "[ $rc -eq 0 ] && grep -q '\"receiver\": \"rectangle red,rectangle green,rectangle blue\"' '$dir/f.json' && grep -q '\"on_map\"' '$dir/f.json'"
refused "receivers not in one plane" "'rectangle red' and 'floor' are not in one plane" "$dir/both.json" --receiver "rectangle red" --receiver floor
refused "unknown receiver" "no object named 'wall'" "$dir/ball.json" --receiver wall
refused "a receiver that is not a plane" "'ball' is not a plane" "$dir/ball.json" --receiver ball
refused "zero-area extent" "--extent: the rectangle has zero area" "$dir/ball.json" --receiver floor --extent 0,0,0,1
refused "malformed extent" "--extent: expected U0,U1,V0,V1" "$dir/ball.json" --receiver floor --extent 0,1,2
refused "grid of 0 cells" "--grid: expected WxH" "$dir/ball.json" --receiver floor --grid 0x10
refused "grid of 10^6 x 10^6 cells" "--grid: expected WxH" "$dir/ball.json" --receiver floor --grid 1000000x1000000
refused "light out of range" "--light: .* has 1 light, no light 3" "$dir/ball.json" --receiver floor --light 3
refused "unknown method" "--method: expected grid-pencil, photons or polygons" "$dir/ball.json" --receiver floor --method rays
refused "polygons need planar faces" "--method polygons: .*object 'ball' is a sphere" "$dir/ball.json" --receiver floor --method polygons
refused "polygons take no --rays" "--rays: the polygons method traces the rays its beams need" "$dir/ball.json" --receiver floor --method polygons --rays 100
# illuminance polygons on Fig. 11: a map whose flux agrees with grid-pencil tracing's (the bench
# measures both against a converged reference), its ledger closed
$pencil illuminance "$(dirname "$0")/../scenes/fig11.json" --receiver "rectangle red" \
  --receiver "rectangle green" --receiver "rectangle blue" -o "$dir/fp.exr" --grid 24x20 \
  --method polygons --max-split 1 >/dev/null 2>"$dir/err"; rc=$?
/usr/bin/python3 - "$dir" "$rc" <<'PY' || fail=1
import json, sys
d, rc = sys.argv[1], int(sys.argv[2])
p, g = json.load(open(f"{d}/fp.json")), json.load(open(f"{d}/f.json"))
assert rc == 0 and p["method"] == "polygons" and p["counts"]["pencils"] > 0, p
assert p["rays_per_side"] is None and isinstance(g["rays_per_side"], int), p
assert abs(p["flux"]["on_map"] / g["flux"]["on_map"] - 1) < 0.01, (p["flux"], g["flux"])
f = p["flux"]
assert abs(f["escaped"] + f["absorbed"] - f["emitted_by_grid"]) < 1e-6 * f["emitted_by_grid"], f
print("ok: polygons on Fig. 11: flux within 1% of grid-pencil's, ledger closed")
PY
# MAP.json beside MAP.exr must not replace the scene it was computed from
cp "$dir/ball.json" "$dir/same.json"
$pencil illuminance "$dir/same.json" --receiver floor -o "$dir/same.exr" >/dev/null 2>"$dir/err"; rc=$?
check "an output that is the scene: exit 2, scene kept, nothing written" \
  "[ $rc -eq 2 ] && grep -q 'is the input' '$dir/err' && cmp -s '$dir/ball.json' '$dir/same.json' && [ ! -e '$dir/same.exr' ] && [ ! -e '$dir/same.png' ]"
refused "missing receiver" "missing --receiver NAME" "$dir/ball.json"
# a receiver no light can reach: the floor under an opaque slab
cat >"$dir/dark.json" <<'JSON'
{"camera": {"eye": [0, 3, -6], "look_at": [0, 0, 0]},
 "materials": {"white": {"kd": 0.8}},
 "lights": [{"type": "point", "position": [0, 5, 0]}],
 "objects": [{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0], "material": "white"},
             {"type": "plane", "name": "slab", "point": [0, 1, 0], "normal": [0, 1, 0], "material": "white"}]}
JSON
refused "a receiver no light reaches" "no light reaches the receiver 'floor'" "$dir/dark.json" --receiver floor --extent -1,1,-1,1
$pencil illuminance --help | grep -q "usage: pencil illuminance" || { echo "FAIL: --help"; fail=1; }
# the benchmark of issue 21's targets, small: grid-pencil within 1% of the exact map on smooth
# cells and its flux within 0.5%, photons far off with as many rays
$pencil bench illuminance --quick --json "$dir/b.json" >"$dir/b.txt"; rc=$?
/usr/bin/python3 - "$dir" "$rc" <<'PY' || fail=1
import json, sys
d, rc = sys.argv[1], int(sys.argv[2])
b = json.load(open(f"{d}/b.json"))
assert rc == 0 and b["targets_met"] and "provenance" in b, (rc, b)
gp = [c for c in b["cases"] if c["method"] == "grid-pencil"]
ph = [c for c in b["cases"] if c["method"] == "photons"]
assert len(gp) == 2 and len(ph) == 2
for g, p in zip(gp, ph):
    assert g["worst_relative_error_smooth"] <= 0.01 and g["flux_relative_error"] <= 0.005, g
    assert p["rms_error"] > 5 * g["rms_error"], (g, p)
print("ok: bench illuminance --quick meets the targets")
PY
$pencil bench illuminance --fig11 "$dir/none.json" >/dev/null 2>"$dir/err"; rc=$?
check "bench illuminance: a missing Fig. 11 scene is refused at once, named" \
  "[ $rc -eq 2 ] && grep -q 'cannot read the Fig. 11 scene: $dir/none.json' '$dir/err'"
printf '{"camera": {"eye": [0, 0, -5], "look_at": [0, 0, 0], "fov": 40},\n "objects": [1]}\n' \
  >"$dir/bad11.json"
$pencil bench illuminance --fig11 "$dir/bad11.json" >/dev/null 2>"$dir/err"; rc=$?
check "bench illuminance: a malformed Fig. 11 scene is refused at once, at its line" \
  "[ $rc -eq 2 ] && grep -q 'cannot read the Fig. 11 scene: $dir/bad11.json:2: objects\[0\]' '$dir/err'"
# an area light (1989 section 2.3): mapped as a mesh of Lambertian point sources, the mesh in the
# JSON; the renderers and the polygons method refuse it, naming it, writing nothing
cat >"$dir/area.json" <<'JSON'
{"camera": {"eye": [0, 3, -6], "look_at": [0, 0, 0]},
 "materials": {"white": {"kd": 0.8}, "glass": {"kd": 0, "ka": 0, "kr": 0, "kt": 1, "ior": 1.5}},
 "lights": [{"type": "area", "center": [0, 4, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 0.5],
             "intensity": 10}],
 "objects": [{"type": "plane", "name": "floor", "point": [0, 0, 0], "normal": [0, 1, 0],
              "material": "white"},
             {"type": "sphere", "name": "ball", "center": [0, 1.5, 0], "radius": 1,
              "material": "glass"}]}
JSON
$pencil illuminance "$dir/area.json" --receiver floor -o "$dir/amap.exr" --grid 16x16 \
  --rays 289 --area-mesh 3 >/dev/null 2>"$dir/err"; rc=$?
check "an area light is mapped; MAP.json records the mesh" \
  "[ $rc -eq 0 ] && /usr/bin/python3 -c \"import json, sys; d = json.load(open('$dir/amap.json')); sys.exit(0 if d['area_mesh'] == 3 and d['flux']['on_map'] > 0 else 1)\""
$pencil illuminance "$dir/area.json" --receiver floor -o "$dir/afil.exr" --grid 16x16 \
  --rays 289 --area-mesh 2 --area-filter quadratic --indirect >/dev/null 2>"$dir/err"; rc=$?
check "--area-filter quadratic --indirect: the filter ran, MAP.json says so" \
  "[ $rc -eq 0 ] && /usr/bin/python3 -c \"import json, sys; d = json.load(open('$dir/afil.json')); sys.exit(0 if d['area_filter'] == 'quadratic' and d['indirect'] and d['counts']['filtered'] > 0 else 1)\""
$pencil illuminance "$dir/area.json" --receiver floor -o "$dir/afil3.exr" --grid 16x16 \
  --area-filter cubic >/dev/null 2>"$dir/err"; rc=$?
check "--area-filter cubic: exit 2 naming the option and the forms, nothing written" \
  "[ $rc -eq 2 ] && grep -q -- \"--area-filter: 'cubic'\" '$dir/err' && grep -q linear '$dir/err' && [ ! -e '$dir/afil3.exr' ]"
$pencil illuminance "$dir/area.json" --receiver floor -o "$dir/afil2.exr" --method photons \
  --area-filter linear >/dev/null 2>"$dir/err"; rc=$?
check "--area-filter with photons: exit 2 naming it, nothing written" \
  "[ $rc -eq 2 ] && grep -q -- '--area-filter' '$dir/err' && [ ! -e '$dir/afil2.exr' ]"
$pencil illuminance "$dir/area.json" --receiver floor -o "$dir/area2.exr" --area-mesh 0 \
  >/dev/null 2>"$dir/err"; rc=$?
check "--area-mesh 0: exit 2 naming it, nothing written" \
  "[ $rc -eq 2 ] && grep -q -- '--area-mesh' '$dir/err' && [ ! -e '$dir/area2.exr' ]"
$pencil illuminance "$dir/area.json" --receiver floor -o "$dir/area3.exr" --method polygons \
  >/dev/null 2>"$dir/err"; rc=$?
check "polygons with an area light: exit 2 naming it" \
  "[ $rc -eq 2 ] && grep -q 'area light' '$dir/err' && [ ! -e '$dir/area3.exr' ]"
$pencil render "$dir/area.json" --size 16x16 --spp 1 -o "$dir/area-render.exr" >/dev/null \
  2>"$dir/err"; rc=$?
check "pencil render draws the area light (its mesh points' soft light)" \
  "[ $rc -eq 0 ] && [ -s '$dir/area-render.exr' ]"

finish cli_illuminance
