#!/usr/bin/env bash
# Index models in scene files (issue 22): "ior" as {"glass": NAME} or {"model": ...} loads, the
# material renders at its index at the d-line (so a scene with a model renders as the same scene
# with that number), and the effects plan names the dispersive material and why dispersion is off.
set -u
pencil=$1
fail=0
py=/usr/bin/python3
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; else echo "ok: $1"; fi; }
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
check "a model loads; the plan names it and its n_d" "[ $rc -eq 0 ] && grep -q \"dispersion     off: material 'glass' disperses (dn/dlambda .* /nm at the d-line), but no renderer draws dispersion yet: it is rendered at n_d = 1.5\" '$tmp/plan'"
$pencil render "$tmp/number.json" --explain >"$tmp/plan2" 2>&1
check "a number: no dispersion" "grep -q \"dispersion     off: no transparent material's index varies with wavelength\" '$tmp/plan2'"
$pencil render "$tmp/sf11.json" --explain >"$tmp/plan3" 2>&1
check "a catalogue glass: SF11 at n_d 1.7847" "grep -q 'n_d = 1.7847' '$tmp/plan3'"
$pencil render "$tmp/model.json" --no-aux -o "$tmp/a.exr" >/dev/null 2>&1 && $pencil render "$tmp/number.json" --no-aux -o "$tmp/b.exr" >/dev/null 2>&1
check "a model renders as its index at the d-line" "$py - '$tmp/a.exr' '$tmp/b.exr' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
a, b = (oiio.ImageBuf(p).get_pixels(oiio.FLOAT)[:, :, :3] for p in sys.argv[1:3])
assert np.abs(a - b).max() < 1e-5, np.abs(a - b).max()
PY"
echo "cli_dispersion: $([ $fail -eq 0 ] && echo passed || echo FAILED)"
exit $fail
