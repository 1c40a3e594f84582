#!/usr/bin/env bash
# `pencil post star` and `pencil verify star` contracts (issue 23): a synthetic HDR image with a
# spot 3,200 times its background is filtered into OUT.exr (R, G, B), OUT.png and OUT.json (flux
# kept, kernel, parameters); the star lies along its rays; bad input (not an EXR, a missing
# channel, NaN or negative pixels, a directory, a kernel larger than the image, n <= 1, the
# input as output) exits 2 naming the cause, and nothing is written. `verify star --quick`
# passes and writes its JSON. `pencil render` with the scene's "post": {"star"} (the glints scene)
# or --star filters R, G, B and keeps the unfiltered image; a bad "star" key or a plate too coarse
# for the image is a scene error found before rendering. DIR (argument 3; argument 2 is the source
# tree) keeps the glints render and the verification for the notebook.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
src=$2
keep=${3:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

$py - "$tmp" <<'PY'
import sys, numpy as np, OpenImageIO as oiio
d = sys.argv[1]
def write(name, arr, chans, fmt="float"):
    spec = oiio.ImageSpec(arr.shape[1], arr.shape[0], len(chans), fmt)
    spec.channelnames = tuple(chans)
    out = oiio.ImageOutput.create(f"{d}/{name}")
    out.open(f"{d}/{name}", spec)
    out.write_image(arr.astype(np.float32))
    out.close()
rng = np.random.default_rng(7)
img = (0.1 * rng.random((96, 128, 3))).astype(np.float32)
img[48, 64, :] = 320.0
write("in.exr", img, ("R", "G", "B"))
write("grey.exr", img[:, :, :1], ("Y",))
write("half.exr", img, ("R", "G", "B"), "half")   # the most common EXR: half floats
bad = img.copy(); bad[5, 7, 1] = np.nan; write("nan.exr", bad, ("R", "G", "B"))
neg = img.copy(); neg[9, 3, 2] = -1.0; write("neg.exr", neg, ("R", "G", "B"))
PY
[ -s "$tmp/in.exr" ] || { echo "FAIL: could not write the test image"; exit 1; }

$pencil post star "$tmp/in.exr" -o "$tmp/out.exr" --sigma 0.01,0.04 >"$tmp/log" 2>"$tmp/err"; rc=$?
check "post star exits 0" "[ $rc -eq 0 ]"
check "OUT.exr, OUT.png and OUT.json written" "[ -s '$tmp/out.exr' ] && [ -s '$tmp/out.png' ] && [ -s '$tmp/out.json' ]"
check "JSON: flux kept, kernel and parameters" "$py - '$tmp/out.json' <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d['filter'] == 'star' and d['width'] == 128 and d['height'] == 96 and 'provenance' in d
assert d['parameters']['ratio'] == 0.07 and d['parameters']['sigma2'] == 0.04
assert d['kernel']['side'] == 2 * d['kernel']['radius'] + 1 <= 96
for c in 'RGB':
    f = d['flux'][c]
    assert abs(f['full'] - f['in']) <= 1e-9 * f['in'], f
    assert 0.99 * f['in'] < f['frame'] <= f['in'] * (1 + 1e-9), f
PY"
check "the star: light along its rays, not between them; the image otherwise kept" "$py - '$tmp' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
d = sys.argv[1]
def read(p):
    b = oiio.ImageBuf(p); return b.get_pixels(oiio.FLOAT)[:, :, :3]
a, b = read(f'{d}/in.exr'), read(f'{d}/out.exr')
assert b.shape == a.shape
e = b - a   # the light the filter moved
diag = np.mean([e[48 - t, 64 + t, 0] + e[48 + t, 64 + t, 0] for t in range(4, 12)])
axis = np.mean([e[48, 64 + t, 0] + e[48 - t, 64, 0] for t in range(4, 12)])
assert diag > 0.03 and diag > 10 * abs(axis), (diag, axis)   # an X: rays at 45 degrees
assert abs(b.sum() / a.sum() - 1) < 0.01
assert b[48, 64, 0] < a[48, 64, 0] and b[48, 64, 0] > 0.9 * a[48, 64, 0]
PY"

$pencil post star "$tmp/half.exr" -o "$tmp/half-out.exr" --sigma 0.01,0.04 >/dev/null 2>"$tmp/err"; rc=$?
check "half-float R, G, B read (once a crash in the reader): the float input's star to half precision" "[ $rc -eq 0 ] && $py - '$tmp' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
d = sys.argv[1]
def read(p):
    b = oiio.ImageBuf(p); return b.get_pixels(oiio.FLOAT)[:, :, :3]
a, b = read(f'{d}/out.exr'), read(f'{d}/half-out.exr')
assert np.abs(b - a).max() <= 2e-3 * max(a.max(), 1.0), np.abs(b - a).max()
PY"

nothing() { [ ! -e "$tmp/x.exr" ] && [ ! -e "$tmp/x.png" ] && [ ! -e "$tmp/x.json" ]; }
echo "not an image" >"$tmp/text.exr"
$pencil post star "$tmp/text.exr" -o "$tmp/x.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "not an EXR: exit 2 naming the file, nothing written" "[ $rc -eq 2 ] && grep -q 'text.exr' '$tmp/err' && nothing"
$pencil post star "$tmp/grey.exr" -o "$tmp/x.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a missing channel: exit 2 naming it" "[ $rc -eq 2 ] && grep -q \"no channel 'R'\" '$tmp/err' && nothing"
$pencil post star "$tmp/nan.exr" -o "$tmp/x.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a NaN pixel: exit 2 naming channel and pixel" "[ $rc -eq 2 ] && grep -q 'channel G, pixel (7, 5)' '$tmp/err' && nothing"
$pencil post star "$tmp/neg.exr" -o "$tmp/x.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a negative pixel: exit 2 naming channel and pixel" "[ $rc -eq 2 ] && grep -q 'channel B, pixel (3, 9)' '$tmp/err' && nothing"
$pencil post star "$tmp" -o "$tmp/x.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a directory: exit 2, not a regular file" "[ $rc -eq 2 ] && grep -q 'not a regular file' '$tmp/err' && nothing"
$pencil post star "$tmp/in.exr" -o "$tmp/x.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a kernel larger than the image: exit 2 with its size" "[ $rc -eq 2 ] && grep -q 'larger than the image' '$tmp/err' && nothing"
$pencil post star "$tmp/in.exr" -o "$tmp/x.exr" --ior 1 >/dev/null 2>"$tmp/err"; rc=$?
check "--ior 1: exit 2 naming --ior" "[ $rc -eq 2 ] && grep -q -- '--ior' '$tmp/err' && nothing"
$pencil post star "$tmp/in.exr" -o "$tmp/in.exr" --sigma 0.01,0.04 >/dev/null 2>"$tmp/err"; rc=$?
check "the input as output: exit 2, the input kept" "[ $rc -eq 2 ] && cmp -s '$tmp/in.exr' <(cat '$tmp/in.exr') && [ ! -e '$tmp/in.png' ]"
$pencil post star "$tmp/in.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "no -o: exit 2" "[ $rc -eq 2 ] && grep -q -- '-o OUT.exr is required' '$tmp/err'"
$pencil post star --help >"$tmp/help"; rc=$?
check "--help exits 0" "[ $rc -eq 0 ] && grep -q usage '$tmp/help'"

$pencil verify star --quick --json "$tmp/v.json" --csv "$tmp/v.csv" >"$tmp/vlog"; rc=$?
check "verify star --quick passes" "[ $rc -eq 0 ] && grep -q 'agrees with exact refraction to first order' '$tmp/vlog'"
check "verify star JSON and CSV" "$py - '$tmp/v.json' '$tmp/v.csv' <<'PY'
import json, sys, csv
d = json.load(open(sys.argv[1]))
assert d['pass'] is True and len(d['slopes']) == 6 and len(d['profiles']) == 2
for r in d['slopes']:
    assert r['relative_error_at_1e-4'] < 1e-6 and r['sign'] == '-N'
    assert 0.1 < r['slope_at_1pct'] < r['slope_at_10pct'] < 1
rows = list(csv.DictReader(l for l in open(sys.argv[2]) if not l.startswith('#')))
assert len(rows) == 6 * 25
PY"
[ -n "$keep" ] || keep=$tmp/keep
mkdir -p "$keep"
$pencil render "$src/scenes/glints.json" --size 96x96 --spp 1 -o "$keep/glints.exr" >"$tmp/rlog" 2>"$tmp/err"; rc=$?
check "render glints.json: exit 0, the star filter reported" "[ $rc -eq 0 ] && grep -q '^star filter: kernel' '$tmp/rlog' && [ -s '$keep/glints.png' ]"
check "the render: R, G, B filtered, unfiltered.R/G/B kept, flux kept to what left the frame" "$py - '$keep/glints.exr' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
b = oiio.ImageBuf(sys.argv[1]); n = list(b.spec().channelnames); a = b.get_pixels(oiio.FLOAT)
assert all(('unfiltered.' + c) in n for c in 'RGB'), n
after = a[:, :, [n.index(c) for c in 'RGB']]; before = a[:, :, [n.index('unfiltered.' + c) for c in 'RGB']]
assert before.max() > 100 and after.max() < before.max()   # sun glints, spread into stars
r = after.sum() / before.sum()
assert 0.95 < r <= 1 + 1e-6, r
assert oiio.ImageInput.open(sys.argv[1]).spec().get_string_attribute('pencil:star').startswith('directions 2')
PY"
$pencil render --star --size 32x32 --spp 1 --no-aux -o "$tmp/f8.exr" >"$tmp/rlog" 2>&1; rc=$?
check "--star on a scene without it: the defaults" "[ $rc -eq 0 ] && grep -q '^star filter' '$tmp/rlog'"
$pencil render --size 32x32 --explain >"$tmp/plan" 2>&1
check "--explain without it: off, and why" "grep -q 'star-filter    off: the scene does not ask for it' '$tmp/plan'"
$py - "$src/scenes/fig11.json" "$tmp" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["post"] = {"star": {"ior": 1}}
json.dump(s, open(sys.argv[2] + "/bad_ior.json", "w"))
s["post"] = {"star": {"sigma": [0.02, 5]}}
json.dump(s, open(sys.argv[2] + "/coarse.json", "w"))
PY
$pencil render "$tmp/bad_ior.json" -o "$tmp/y.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a bad star key: exit 2 naming post.star.ior" "[ $rc -eq 2 ] && grep -q 'post.star.ior' '$tmp/err' && [ ! -e '$tmp/y.exr' ]"
$pencil render "$tmp/coarse.json" -o "$tmp/y.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a plate too coarse for the image: exit 2 before rendering" "[ $rc -eq 2 ] && grep -q 'larger than the image' '$tmp/err' && [ ! -e '$tmp/y.exr' ]"
$pencil render --star --size 4096x4096 --max-memory 100M -o "$tmp/y.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "the star filter's memory counted before rendering" "[ $rc -eq 2 ] && grep -q \"the star filter's FFT grid\" '$tmp/err' && [ ! -e '$tmp/y.exr' ]"
$pencil verify star --quick --json "$keep/verify-star.json" --csv "$keep/verify-star.csv" >/dev/null
finish cli_post_star
