#!/usr/bin/env bash
# Index models in scene files (issue 22): "ior" as {"glass": NAME} or {"model": ...} loads; the
# exact renderer draws it through the spectral fan (the effects plan says how many bins), the
# pencil renderer by spectral pencils, or with --wavelengths off at its index at the d-line (so its
# image equals the same scene with that number, and the plan says why); "spectral_bins" sets the
# bins.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
scene() { # $1: the ior JSON
  cat <<JSON
{"camera": {"eye": [0, 0.5, -5], "look_at": [0, 0, 0], "fov": 40, "width": 24, "height": 24},
 "settings": {"caustics": "off"},
 "materials": {"glass": {"kt": 0.9, "kd": 0, "ior": $1}, "board": {"kd": 0.8}},
 "lights": [{"type": "point", "position": [2, 3, -4]}],
 "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"},
             {"type": "plane", "point": [0, -1, 0], "normal": [0, 1, 0], "material": "board",
              "checker": {"size": 0.5, "material": "glass"}}]}
JSON
}
scene '{"model": "abbe", "nd": 1.5, "vd": 50}' >"$tmp/model.json"
scene '1.5' >"$tmp/number.json"
scene '{"glass": "SF11"}' >"$tmp/sf11.json"
$pencil render "$tmp/model.json" --explain >"$tmp/plan" 2>&1; rc=$?
check "a model loads; the exact renderer's plan fans it out into 40 bins" "[ $rc -eq 0 ] && grep -q \"dispersion     on: material 'glass' disperses (dn/dlambda .* /nm at the d-line): white rays refracting at it fan out into 40 wavelength bins over 380-780 nm\" '$tmp/plan'"
$pencil render "$tmp/model.json" --method pencil --explain >"$tmp/plan1" 2>&1
check "the pencil renderer's plan: spectral pencils" "grep -q \"dispersion     on: material 'glass' disperses (dn/dlambda .* /nm at the d-line): white rays refracting at it become spectral pencils over 380-780 nm\" '$tmp/plan1'"
$pencil render "$tmp/model.json" --method pencil --wavelengths off --explain >"$tmp/plan1" 2>&1
check "the pencil renderer's plan with --wavelengths off: at n_d" "grep -q \"dispersion     off: material 'glass' disperses, but the pencil renderer was asked for --wavelengths off: it is rendered at n_d = 1.5\" '$tmp/plan1'"
$pencil render "$tmp/number.json" --explain >"$tmp/plan2" 2>&1
check "a number: no dispersion" "grep -q \"dispersion     off: no transparent material's index varies with wavelength\" '$tmp/plan2'"
$pencil render "$tmp/sf11.json" --method beam --wavelengths off --explain >"$tmp/plan3" 2>&1
check "a catalogue glass: SF11 at n_d 1.7847 for beams asked for --wavelengths off" "grep -q 'n_d = 1.7847' '$tmp/plan3'"
$pencil render "$tmp/sf11.json" --method beam --explain >"$tmp/plan3" 2>&1
check "beams draw a catalogue glass by dispersion image solids" "grep -q 'dispersion     on: white rays refracting into dispersive glass become dispersion image solids' '$tmp/plan3'"
sed 's/"caustics": "off"/"caustics": "off", "spectral_bins": 4/' "$tmp/model.json" >"$tmp/bins4.json"
$pencil render "$tmp/bins4.json" --explain >"$tmp/plan4" 2>&1
check "spectral_bins sets the bins" "grep -q 'fan out into 4 wavelength bins' '$tmp/plan4'"
for m in exact pencil; do
  off=; [ $m = pencil ] && off="--wavelengths off"
  $pencil render "$tmp/model.json" --method $m $off --no-aux -o "$tmp/a-$m.exr" >/dev/null 2>&1 &&
    $pencil render "$tmp/number.json" --method $m --no-aux -o "$tmp/b-$m.exr" >/dev/null 2>&1 ||
    echo "FAIL: render $m"
done
check "the pencil renderer with --wavelengths off draws a model as its index at the d-line" "$py - '$tmp/a-pencil.exr' '$tmp/b-pencil.exr' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
a, b = (oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[:, :, :3] for p in sys.argv[1:3])
assert np.abs(a - b).max() < 1e-5, np.abs(a - b).max()
PY"
check "the exact renderer draws its dispersion: colours change through the glass only" "$py - '$tmp/a-exact.exr' '$tmp/b-exact.exr' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
a, b = (oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[:, :, :3] for p in sys.argv[1:3])
assert np.isfinite(a).all()
d = np.abs(a - b).max(axis=2)
assert d.max() > 1e-3, d.max()           # the board seen through the ball shifts by wavelength
assert (d < 1e-6).mean() > 0.3, (d < 1e-6).mean()  # the board beside the ball is untouched
PY"
# the `spectral` channel: only where the render draws dispersion, 1 where the centre ray's tree
# refracts at dispersive glass (the ball, and the board's glass squares), the same in both renderers
for m in exact pencil; do
  $pencil render "$tmp/model.json" --method $m -o "$tmp/s-$m.exr" >/dev/null 2>&1 || echo "FAIL: render $m with aux"
done
# ... and where the pencil renderer traces a node per sample: mirror balls that show the glass
src=$(cd "$(dirname "$0")/.." && pwd)
sed 's/"ior": 1.5/"ior": {"glass": "SF11"}/' "$src/scenes/spheres-10.json" >"$tmp/sp10.json"
for m in exact pencil; do
  $pencil render "$tmp/sp10.json" --method $m --size 128x128 -o "$tmp/sp-$m.exr" >/dev/null 2>&1 || echo "FAIL: render spheres $m"
done
$pencil render "$tmp/model.json" --method pencil --wavelengths off -o "$tmp/s-off.exr" >/dev/null 2>&1 &&
  $pencil render "$tmp/number.json" -o "$tmp/s-number.exr" >/dev/null 2>&1 || echo "FAIL: render without dispersion"
check "the spectral channel: 1 on the ball, 0 on the board's diffuse squares, alike in both renderers (also through mirror balls); none without dispersion" "$py - '$tmp' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
def read(name):
    b = oiio.ImageBuf(sys.argv[1] + '/' + name)
    n = list(b.spec().channelnames)
    return b.get_pixels(oiio.FLOAT), n
ch = {}
for m in ('exact', 'pencil'):
    a, n = read('s-%s.exr' % m)
    s, ids, u, v = (a[:, :, n.index(c)] for c in ('spectral', 'id', 'pathT.u', 'pathT.v'))
    assert set(np.unique(s)) == {0.0, 1.0}, np.unique(s)
    assert (s[ids == 0] == 1).all(), m             # every ray meeting the ball refracts there
    direct = (ids == 1) & (a[:, :, n.index('pathT.k')] == 0)
    assert (s[direct] == 0).any() and (s[direct] == 1).any(), m  # diffuse squares, glass squares
    ch[m] = s
assert (ch['exact'] == ch['pencil']).all(), (ch['exact'] != ch['pencil']).sum()
e, p = (read('sp-%s.exr' % m) for m in ('exact', 'pencil'))
e, p = (a[:, :, n.index('spectral')] for a, n in (e, p))
assert 0.05 < e.mean() < 0.5 and (e == p).all(), (e.mean(), (e != p).sum())
for f in ('s-off.exr', 's-number.exr'):
    assert 'spectral' not in read(f)[1], f
PY"
# two dispersive glasses (the prism's halves: SF11, and a model of SF11's n_d with V_d 40, so that
# the slit is seen through both): the solids need one glass's Lambda scale, so beams draw them at
# n_d and say so; --wavelengths pencils draws both
$py - "$(dirname "$0")/../scenes/prism.json" "$tmp/two.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["camera"]["width"] = s["camera"]["height"] = 32
s["settings"]["spp"] = 1
s["materials"]["v40"] = dict(s["materials"]["sf11"], ior={"model": "abbe", "nd": 1.7847, "vd": 40})
prism = [o for o in s["objects"] if o.get("name") == "prism"][0]
v = prism["vertices"]  # each vertex at x = -2 or 2: the halves are the same prism, cut
s["objects"].append(dict(prism, name="twin", material="v40",
                         vertices=[[max(x, 0.02), y, z] for x, y, z in v]))
prism["vertices"] = [[min(x, -0.02), y, z] for x, y, z in v]
json.dump(s, open(sys.argv[2], "w"))
PY
$pencil render "$tmp/two.json" --method beam --explain --no-aux -o "$tmp/two-solids.exr" >"$tmp/two1" 2>&1; rc=$?
check "beams with two glasses: solids refused by name, drawn at n_d" "[ $rc -eq 0 ] && grep -q 'dispersion image solids need one glass (its Lambda scale): the scene.s dispersive materials differ' '$tmp/two1' && ! grep -q 'dispersion image solids:' '$tmp/two1'"
$pencil render "$tmp/two.json" --method beam --wavelengths pencils --explain --no-aux -o "$tmp/two-pencils.exr" >"$tmp/two2" 2>&1; rc=$?
check "beams with two glasses: --wavelengths pencils traces both" "[ $rc -eq 0 ] && grep -q 'traced from each cell share.s point by spectral pencils' '$tmp/two2' && grep -Eq 'dispersion image solids: [1-9][0-9]* white refractions .* [1-9][0-9]* traced exactly by spectral pencils' '$tmp/two2'"
check "beams with two glasses: the pencils' image differs from n_d's in both halves" "$py - '$tmp/two-solids.exr' '$tmp/two-pencils.exr' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
a, b = (oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[:, :, :3] for p in sys.argv[1:3])
assert np.isfinite(b).all()
w = a.shape[1]
for half in (slice(0, w // 2 - 1), slice(w // 2 + 1, w)):  # each glass's half of the view
    assert np.abs(a[:, half] - b[:, half]).max() > 1e-2, np.abs(a[:, half] - b[:, half]).max()
PY"
# the beam renderer's image solids grow with the image: their estimate (BT_SOLID_SAMPLE_BYTES a
# sample) is in the memory a render needs, so that --max-memory refuses before it starts
$pencil render "$src/scenes/prism.json" --method beam --size 512x512 --max-memory 200M \
  -o "$tmp/big.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "image solids past --max-memory: refused before the render, saying so and what helps" \
  "[ $rc -eq 2 ] && grep -q 'the dispersion image solids, estimated), more than the 200.0 MB --max-memory allows' '$tmp/err' && grep -q -- '--wavelengths pencils' '$tmp/err' && [ ! -e '$tmp/big.exr' ]"
$pencil render "$src/scenes/prism.json" --method beam --wavelengths off --size 512x512 \
  --max-memory 200M -o "$tmp/nd.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "... and not counted where the glass is drawn at n_d" "[ $rc -eq 0 ] && [ -s '$tmp/nd.exr' ]"
finish cli_dispersion
