#!/usr/bin/env bash
# `pencil bench area` contracts (issue 25): --quick maps a bare floor and a glass ball under area
# lights as meshes of point sources, plain and filtered (1989 Eqs. 9-12, the displacement
# quadratic and linear as printed), against the brute-force sum; writes every map
# (CASE-VARIANT.exr, .png, .json), area-curve.csv, area-size.csv and a JSON summary whose keys
# scripts read. What it measures must hold: on the bare floor, where Eq. (9) is exact, both
# filters remove the mesh's error (and the brute-force sum agrees with the closed form); the plain
# sums converge with the mesh; through the ball the quadratic filter beats the plain sum and the
# printed linear one; flux is kept. Bad options exit 2 naming the option before any work. DIR
# (argument 2) keeps the outputs for the notebook.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
out=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -n "$out" ] || out=$tmp/out

$pencil bench area --quick --threads 2 --out "$out" --json "$out/area.json" >"$tmp/log" \
  2>"$tmp/err"; rc=$?
check "bench area --quick exits 0" "[ $rc -eq 0 ]"
check "the table names both cases" "grep -q '^floor ' '$tmp/log' && grep -q '^ball ' '$tmp/log'"
for c in floor ball; do
  for v in reference m1-none m1-quadratic m1-linear m2-none m2-quadratic m2-linear; do
    check "$c-$v.exr, .png and .json written" \
      "[ -s '$out/$c-$v.exr' ] && [ -s '$out/$c-$v.png' ] && [ -s '$out/$c-$v.json' ]"
  done
done
check "floor-exact.exr written" "[ -s '$out/floor-exact.exr' ]"
check "CSV headers" "grep -v '^#' '$out/area-curve.csv' | head -1 | grep -q '^case,mesh,filter,rays,seconds,rms,p99,max,' &&
  grep -v '^#' '$out/area-size.csv' | head -1 | grep -q '^scale,cell_rad,mesh,filter,rms,max,seconds'"
check "JSON: cases with references and rows; the size sweep" "$py - '$out/area.json' <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert [c['case'] for c in d['cases']] == ['floor', 'ball'] and 'provenance' in d
for c in d['cases']:
    assert c['reference']['mesh'] == d['reference_mesh'] == 16 and c['reference']['own_rms'] >= 0
    want = [(m, f) for m in (1, 2) for f in ('none', 'quadratic', 'linear')]
    assert [(r['mesh'], r['filter']) for r in c['rows']] == want
    for r in c['rows']:
        assert r['seconds'] > 0 and r['rays'] > 0 and 0 <= r['rms'] and r['p99'] >= 0, r
        assert abs(r['flux_relative_error']) < 0.03, r
        assert (r['filtered'] > 0) == (r['filter'] != 'none'), r
assert len(d['size_sweep']) == 2
for s in d['size_sweep']:
    assert s['cell_rad'] > 0 and all(s[k]['rms'] > 0 for k in ('plain', 'quadratic', 'linear'))
PY"
check "floor: the brute-force sum is the closed form's, the filter removes the mesh's error" \
  "$py - '$out/area.json' <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))['cases'][0]
r = {(x['mesh'], x['filter']): x for x in c['rows']}
assert c['reference']['exact_rms'] < 2e-3, c['reference']
for m in (1, 2):
    for f in ('quadratic', 'linear'):
        assert r[(m, f)]['rms'] < 0.1 * r[(m, 'none')]['rms'], (m, f, r[(m, f)], r[(m, 'none')])
        assert r[(m, f)]['rms'] < 2e-3
PY"
check "ball: the quadratic filter beats the plain sum and the printed linear one at M = 2" \
  "$py - '$out/area.json' <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))['cases'][1]
r = {(x['mesh'], x['filter']): x['rms'] for x in c['rows']}
assert r[(2, 'quadratic')] < 0.5 * r[(2, 'none')] and r[(2, 'quadratic')] < 0.5 * r[(2, 'linear')], r
PY"
check "plain sums converge with the mesh (second order: under 0.35 at twice the mesh)" \
  "$py - '$out/area.json' <<'PY'
import json, sys
for c in json.load(open(sys.argv[1]))['cases']:
    r = {(x['mesh'], x['filter']): x for x in c['rows']}
    assert r[(2, 'none')]['rms'] < 0.35 * r[(1, 'none')]['rms'], c['case']
PY"

$pencil bench area --reference-mesh 1 >/dev/null 2>"$tmp/err"; rc=$?
check "--reference-mesh 1: exit 2 naming it" "[ $rc -eq 2 ] && grep -q -- '--reference-mesh' '$tmp/err'"
$pencil bench area --json "$tmp" >/dev/null 2>"$tmp/err"; rc=$?
check "--json naming a directory: exit 2 before work" "[ $rc -eq 2 ] && grep -q -- '--json' '$tmp/err'"
$pencil bench area --help >"$tmp/help"; rc=$?
check "--help exits 0" "[ $rc -eq 0 ] && grep -q usage '$tmp/help'"
finish cli_bench_area
