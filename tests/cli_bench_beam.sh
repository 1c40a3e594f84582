#!/usr/bin/env bash
# `pencil bench beam` contracts (issue 24): --quick renders three cases (fig11, prism, sphere100)
# with every variant, writes CASE-VARIANT.exr and .png into --out and a JSON summary whose keys
# scripts read (cases[]: case, faces, variants[]: variant, renderer, spp, seconds, mean, p99,
# max; equal_error: exact_seconds, bracket, exact_over_beam); the beams' image errs less than
# exact tracing at 1 spp and the exact ladder's errors fall with samples; bad options exit 2
# naming the option before any rendering; out of memory exits 1 with its reason. DIR (argument
# 2) keeps the outputs for the notebook.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
out=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -n "$out" ] || out=$tmp/out

$pencil bench beam --quick --runs 1 --threads 2 --out "$out" --json "$out/beam.json" \
  >"$tmp/log" 2>"$tmp/err"; rc=$?
check "bench beam --quick exits 0" "[ $rc -eq 0 ]"
check "the table names every case" \
  "grep -q '^fig11 ' '$tmp/log' && grep -q '^prism ' '$tmp/log' && grep -q '^sphere100 ' '$tmp/log'"
for c in fig11 prism sphere100; do
  for v in reference beam beam-probe exact-1 exact-64 pencil-16; do
    check "$c-$v.exr and .png written" "[ -s '$out/$c-$v.exr' ] && [ -s '$out/$c-$v.png' ]"
  done
done
check "the beams' difference maps written" "[ -s '$out/fig11-beam-diff.exr' ] && [ -s '$out/sphere100-beam-diff.exr' ]"
check "JSON: three cases, every variant with its numbers" "$py - '$out/beam.json' <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d['benchmark'] == 'beam' and 'provenance' in d and d['quick'] is True
assert [c['case'] for c in d['cases']] == ['fig11', 'prism', 'sphere100']
assert [c['faces'] for c in d['cases']] == [100, 5, 100]
for c in d['cases']:
    v = {r['variant']: r for r in c['variants']}
    assert set(v) == {'reference', 'beam', 'beam-probe', 'exact-1', 'exact-4', 'exact-16',
                      'exact-64', 'pencil-16'}, set(v)
    assert v['reference']['mean'] is None and v['reference']['spp'] == 144
    for k, r in v.items():
        if k != 'reference':
            assert r['seconds'] > 0 and 0 <= r['mean'] <= r['p99'] <= r['max'], r
    e = c['equal_error']
    assert e['bracket'] in ('inside', 'below', 'above'), e
    assert e['exact_seconds'] > 0 and e['exact_over_beam'] > 0, e
f = d['cases'][0]['fig10']
assert 'fig10' not in d['cases'][1]
assert f['default']['samples'] == 32 * 32 and 0.9 <= f['default']['within'] <= 1, f
assert f['certified']['within'] == 1 and f['certified']['mismatches'] == 0, f
PY"
check "beams err less than exact at 1 spp; the exact ladder's errors fall" "$py - '$out/beam.json' <<'PY'
import json, sys
for c in json.load(open(sys.argv[1]))['cases']:
    v = {r['variant']: r for r in c['variants']}
    assert v['beam']['mean'] < 0.5 * v['exact-1']['mean'], c['case']
    assert v['exact-1']['mean'] > v['exact-4']['mean'] > v['exact-16']['mean'], c['case']
PY"

$pencil bench beam --runs 0 >/dev/null 2>"$tmp/err"; rc=$?
check "--runs 0: exit 2 naming --runs" "[ $rc -eq 2 ] && grep -q -- '--runs' '$tmp/err'"
$pencil bench beam --rho 0 >/dev/null 2>"$tmp/err"; rc=$?
check "--rho 0: exit 2 naming --rho" "[ $rc -eq 2 ] && grep -q -- '--rho' '$tmp/err'"
$pencil bench beam --size 4 >/dev/null 2>"$tmp/err"; rc=$?
check "--size 4: exit 2 naming --size" "[ $rc -eq 2 ] && grep -q -- '--size' '$tmp/err'"
$pencil bench beam --json "$tmp" >/dev/null 2>"$tmp/err"; rc=$?
check "--json naming a directory: exit 2 before rendering" "[ $rc -eq 2 ] && grep -q -- '--json' '$tmp/err'"
$pencil bench beam --case fig11,nope --quick >/dev/null 2>"$tmp/err"; rc=$?
check "--case with an unknown name: exit 2 naming it" "[ $rc -eq 2 ] && grep -q -- \"--case: no case 'nope'\" '$tmp/err'"
$pencil bench beam --case prism --quick --runs 1 --json "$tmp/one.json" >/dev/null 2>"$tmp/err"; rc=$?
check "--case prism runs that case alone" "[ $rc -eq 0 ] && $py -c \"import json,sys; assert [c['case'] for c in json.load(open(sys.argv[1]))['cases']] == ['prism']\" '$tmp/one.json'"
$pencil bench beam --scenes "$tmp/nowhere" --quick >"$tmp/o" 2>"$tmp/e"; rc=$?
check "--scenes without the scene: exit 2 naming the file, no line -1" "[ $rc -eq 2 ] && grep -q 'nowhere/fig1[14].json: ' '$tmp/e' && ! grep -q ':-1:' '$tmp/e'"
# Out of memory is a failure of the work (1), not of the input (2), and says so: an address space
# of 400 MB holds the scene but not a 4096 x 4096 image (before, exit 2 and no message).
(ulimit -v 400000; $pencil bench beam --quick --size 4096 --threads 1 --runs 1) >"$tmp/o" 2>"$tmp/e"; rc=$?
check "out of memory: exit 1 with the reason" "[ $rc -eq 1 ] && grep -q 'cannot allocate a 4096x4096 image' '$tmp/e'"
mkdir "$tmp/ro" && chmod 555 "$tmp/ro"
if [ -w "$tmp/ro" ]; then
  echo "SKIP: an unwritable --out directory (this user writes in any directory)"
else
  $pencil bench beam --quick --out "$tmp/ro" >"$tmp/o" 2>"$tmp/e"; rc=$?
  check "--out an existing directory it cannot write in: exit 2 before any rendering" \
    "[ $rc -eq 2 ] && grep -q 'cannot write in directory' '$tmp/e' && [ ! -s '$tmp/o' ]"
fi
chmod 755 "$tmp/ro"
$pencil bench beam --help >"$tmp/help"; rc=$?
check "--help exits 0" "[ $rc -eq 0 ] && grep -q usage '$tmp/help'"
finish cli_bench_beam
