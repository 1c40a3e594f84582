#!/usr/bin/env bash
# `pencil bench dispersion` contracts (issue 22, the 1989 Fig. 14 table): --quick renders
# scenes/fig14.json by every method, writes fig14-METHOD.exr and .png into --out and a JSON
# summary whose keys scripts read (methods[]: method, renderer, wavelengths, bins, seconds,
# over_exact_nd, rays, delta_e2000_mean, delta_e2000_p99, delta_e2000_max; targets: the issue's
# time and colour targets with their verdicts; beams: the beam renderer's dispersion image solids and
# spectral pencils against its time at n_d, and the solids against the pencils at the same
# points; spp and reference_spp); Takagi's wavelength supersampling and the fan of as many bins
# give the same colours; the error falls as the bins grow, and drawing the glass at n_d errs most;
# against a reference of area averages (--reference-spp) the beams err least; bad options exit 2
# before any rendering; out of memory exits 1 with its reason. DIR (argument 2) keeps the outputs.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
out=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -n "$out" ] || out=$tmp/out

$pencil bench dispersion --quick --threads 2 --out "$out" --json "$out/dispersion.json" \
  >"$tmp/log" 2>"$tmp/err"; rc=$?
check "bench dispersion --quick exits 0" "[ $rc -eq 0 ]"
for m in reference pencil pencil-spectral exact-nd exact-takagi9 exact-fan9 exact-fan40 \
  exact-spectral-pencil exact-fan50 beam beam-solids beam-pencils; do
  check "fig14-$m.exr and .png written" "[ -s '$out/fig14-$m.exr' ] && [ -s '$out/fig14-$m.png' ]"
  check "the table has $m" "grep -q '^$m ' '$tmp/log'"
done
check "JSON: every method with its numbers; errors fall with the bins" "$py - '$out/dispersion.json' <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d['benchmark'] == 'dispersion' and 'provenance' in d and d['quick'] is True
assert d['reference_bins'] == 100 and d['size'] == 48 and d['spp'] == 1 and d['reference_spp'] == 1
m = {r['method']: r for r in d['methods']}
assert set(m) == {'reference', 'pencil', 'pencil-spectral', 'exact-nd', 'exact-takagi9',
                  'exact-fan9', 'exact-fan40', 'exact-spectral-pencil', 'exact-fan50', 'beam',
                  'beam-solids', 'beam-pencils'}, set(m)
assert m['reference']['delta_e2000_mean'] is None
for k, r in m.items():
    assert r['seconds'] > 0 and r['over_exact_nd'] > 0, r
    if k != 'reference':
        assert 0 <= r['delta_e2000_mean'] <= r['delta_e2000_p99'] <= r['delta_e2000_max'], r
assert abs(m['exact-takagi9']['delta_e2000_mean'] - m['exact-fan9']['delta_e2000_mean']) < 1e-3
assert m['exact-takagi9']['rays'] > m['exact-fan9']['rays'] > m['exact-nd']['rays']
e = [m[k]['delta_e2000_mean'] for k in ('exact-nd', 'exact-fan9', 'exact-fan40', 'exact-fan50')]
assert e == sorted(e, reverse=True) and e[-1] < 1.0, e
assert m['pencil']['wavelengths'] == 'off' and m['exact-nd']['wavelengths'] == 'off'
assert m['pencil-spectral']['wavelengths'] == 'pencil'
# the pencil renderer's dispersion adds no error of its own beyond its error at n_d
assert (m['pencil-spectral']['delta_e2000_mean'] < m['pencil']['delta_e2000_mean'] -
        (m['exact-nd']['delta_e2000_mean'] - m['exact-spectral-pencil']['delta_e2000_mean']) + 0.1), m
sp = m['exact-spectral-pencil']  # within the 40-bin fan's error, in fewer rays
assert sp['wavelengths'] == 'pencil', sp
assert sp['delta_e2000_mean'] < m['exact-fan40']['delta_e2000_mean'], (sp, m['exact-fan40'])
assert sp['rays'] < m['exact-fan40']['rays'], (sp, m['exact-fan40'])
b = d['beams']  # the beam renderer's dispersion: solids drawn as the spectral pencils draw it
assert m['beam']['wavelengths'] == 'off' and m['beam-solids']['wavelengths'] == 'solids'
assert abs(b['solids_over_beam'] - m['beam-solids']['seconds'] / m['beam']['seconds']) < 1e-9, b
assert abs(b['pencils_over_beam'] - m['beam-pencils']['seconds'] / m['beam']['seconds']) < 1e-9, b
assert 0 <= b['solids_against_pencils_delta_e2000_mean'] < 0.1, b
assert b['solids_against_pencils_delta_e2000_mean'] < m['beam']['delta_e2000_mean'], (b, m['beam'])
t = d['targets']  # the issue's targets, each with its verdict as the numbers give it
ps = m['pencil-spectral']
assert abs(t['time_over_pencil'] - ps['seconds'] / m['pencil']['seconds']) < 1e-9, t
assert t['time_met'] == (t['time_over_pencil'] <= t['time_over_pencil_target'] == 1.3), t
assert t['delta_e2000_mean'] == ps['delta_e2000_mean'] and t['delta_e_met'] is True, t
assert t['faster_than_exact_nd'] == (t['time_over_exact_nd'] < 1.0), t
PY"
check "the report gives the targets' verdicts" "grep -q '^targets (issue 22): pencil-spectral .* times pencil.s time (target <= 1.3' '$tmp/log'"
# against a reference of area averages (--reference-spp 16) the beams, which integrate each
# pixel's area, err less than any method sampling the pixel's centre, and less than against the
# point-sampled reference
$pencil bench dispersion --quick --reference-spp 16 --threads 2 --json "$out/equal-spp1.json" \
  >"$tmp/log16" 2>"$tmp/err"; rc=$?
check "--reference-spp 16: the beams' error falls; every point sampler's is larger" "[ $rc -eq 0 ] && grep -q 'spectral fan with 100 bins at 16 spp' '$tmp/log16' && $py - '$out/dispersion.json' '$out/equal-spp1.json' <<'PY'
import json, sys
one, area = (json.load(open(p)) for p in sys.argv[1:3])
assert area['spp'] == 1 and area['reference_spp'] == 16, area
e1, e16 = ({r['method']: r['delta_e2000_mean'] for r in d['methods']} for d in (one, area))
assert e16['beam-solids'] < 0.8 * e1['beam-solids'], (e1['beam-solids'], e16['beam-solids'])
points = [k for k in e16 if k != 'reference' and not k.startswith('beam')]
assert len(points) == 8 and all(e16[k] > 1.5 * e16['beam-solids'] for k in points), e16
assert area['targets']['delta_e_met'] is None  # the colour target is judged at equal spp only
PY"
src=$(cd "$(dirname "$0")/.." && pwd)
for b in 9 40 100; do # the prism's spectrum for the notebook: steps or smooth
  $pencil render "$src/scenes/prism.json" --size 96x96 --spp 1 --bins $b --no-aux \
    -o "$out/prism-$b.exr" >/dev/null 2>"$tmp/err" || echo "FAIL: prism with $b bins"
done
$pencil render "$src/scenes/prism.json" --size 96x96 --spp 1 --wavelengths pencil --no-aux \
  -o "$out/prism-pencil.exr" >/dev/null 2>"$tmp/err" || echo "FAIL: prism by spectral pencils"
$pencil render "$src/scenes/prism.json" --size 96x96 --spp 1 --method beam --no-aux \
  -o "$out/prism-solids.exr" >/dev/null 2>"$tmp/err" || echo "FAIL: prism by image solids"
# the glass sphere's band for the notebook: pencil renderer at n_d and by spectral pencils, 400-bin fan
band() { # SUFFIX OPTIONS...
  local suffix=$1
  shift
  $pencil render "$src/scenes/sphere-band.json" --size 96x96 --spp 1 --no-aux "$@" \
    -o "$out/sphere-band$suffix.exr" >/dev/null 2>"$tmp/err" || echo "FAIL: sphere-band$suffix"
}
band -nd --method pencil --wavelengths off
band "" --method pencil
band -fan --bins 400
check "the prism's band: violet to red over rows, separate slit images at 9 bins, smooth at 100, by spectral pencils and by image solids" "$py - '$out' <<'PY'
import sys, numpy as np, OpenImageIO as oiio
def col(b):
    p = oiio.ImageBuf(f'{sys.argv[1]}/prism-{b}.exr').get_pixels(oiio.FLOAT)[:, :, :3]
    return p[:, p.shape[1] // 2, :]
rows = {b: col(b) for b in (9, 40, 100, 'pencil', 'solids')}
for b, c in rows.items():
    lit = c.max(axis=1) > 1e-3
    assert lit.sum() >= 5, (b, lit.sum())          # a band, not a line
    top, bottom = np.nonzero(lit)[0][[0, -1]]
    hue = lambda r: np.argmax(c[r])                # the dominant channel at each end
    assert hue(top) != hue(bottom), (b, c[top], c[bottom])
def gaps(c):  # dark pixels inside the band: the slit's separate images with few bins
    lum = c.max(axis=1)
    lit = np.nonzero(lum > 0.05 * lum.max())[0]
    return int((lum[lit[0]:lit[-1] + 1] < 0.05 * lum.max()).sum())
assert gaps(rows[9]) >= 2 and gaps(rows[100]) == 0, (gaps(rows[9]), gaps(rows[100]))
assert gaps(rows['pencil']) == 0, gaps(rows['pencil'])  # spectral pencils: no bins, no steps
assert gaps(rows['solids']) == 0, gaps(rows['solids'])  # the paper's image solids: nor these
PY"
$pencil bench dispersion --reference-bins 4 >"$tmp/o" 2>"$tmp/e"; rc=$?
check "--reference-bins 4: exit 2 naming the option" "[ $rc -eq 2 ] && grep -q -- '--reference-bins' '$tmp/e' && [ ! -s '$tmp/o' ]"
for bad in "--spp 3" "--reference-spp 0" "--spp x"; do
  $pencil bench dispersion $bad >"$tmp/o" 2>"$tmp/e"; rc=$?
  check "$bad: exit 2 naming the option" "[ $rc -eq 2 ] && grep -q -- '${bad% *}: expected a square number' '$tmp/e' && [ ! -s '$tmp/o' ]"
done
$pencil bench dispersion --json "$tmp/no/such/dir/x.json" >"$tmp/o" 2>"$tmp/e"; rc=$?
check "--json in a missing directory: exit 2 before rendering" "[ $rc -eq 2 ] && grep -q -- '--json' '$tmp/e' && [ ! -s '$tmp/o' ]"
$pencil bench dispersion --scenes "$tmp/nowhere" --quick >"$tmp/o" 2>"$tmp/e"; rc=$?
check "--scenes without the scene: exit 2 naming the file, no line -1" "[ $rc -eq 2 ] && grep -q 'nowhere/fig1[14].json: ' '$tmp/e' && ! grep -q ':-1:' '$tmp/e'"
# Out of memory is a failure of the work (1), not of the input (2), and says so: an address space
# of 400 MB holds the scene but not a 4096 x 4096 image (before, exit 2 and no message).
(ulimit -v 400000; $pencil bench dispersion --quick --size 4096 --threads 1 --runs 1) >"$tmp/o" 2>"$tmp/e"; rc=$?
check "out of memory: exit 1 with the reason" "[ $rc -eq 1 ] && grep -q 'cannot allocate a 4096x4096 image' '$tmp/e'"
$pencil bench dispersion --help >"$tmp/h"; rc=$?
check "--help" "[ $rc -eq 0 ] && grep -q 'usage: pencil bench dispersion' '$tmp/h'"
finish cli_bench_dispersion
