#!/usr/bin/env bash
# `pencil bench caustics` contracts (issue 25): --quick renders the four caustic scenes, writes
# CASE-VARIANT.exr and .png for every variant into --out and a JSON summary whose keys scripts
# read (cases[].variants[]: variant, seconds, rms, p99, max; pencil_over_exact); bad options exit
# 2 naming the option before any rendering. DIR (argument 2) keeps the outputs for the notebook.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
out=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -n "$out" ] || out=$tmp/out

$pencil bench caustics --quick --runs 1 --threads 2 --out "$out" --json "$out/caustics.json" \
  >"$tmp/log" 2>"$tmp/err"; rc=$?
check "bench caustics --quick exits 0" "[ $rc -eq 0 ]"
check "the table names every case" \
  "grep -q '^fig8 ' '$tmp/log' && grep -q '^fig11 ' '$tmp/log' && grep -q '^pool ' '$tmp/log' && grep -q '^glass ' '$tmp/log'"
for c in fig8 fig11 pool glass; do
  for v in reference reference-half exact pencil textbook; do
    check "$c-$v.exr and .png written" "[ -s '$out/$c-$v.exr' ] && [ -s '$out/$c-$v.png' ]"
  done
done
check "JSON: four cases, every variant with its numbers" "$py - '$out/caustics.json' <<'PY'
import json, sys, math
d = json.load(open(sys.argv[1]))
assert [c['case'] for c in d['cases']] == ['fig8', 'fig11', 'pool', 'glass']
for c in d['cases']:
    v = {r['variant']: r for r in c['variants']}
    assert set(v) >= {'reference', 'reference-half', 'exact', 'pencil', 'textbook'}
    assert v['reference']['rms'] is None
    for k in ('exact', 'pencil', 'textbook'):
        r = v[k]
        assert r['seconds'] > 0 and 0 <= r['rms'] <= r['max'] and r['p99'] <= r['max'], r
    assert v['textbook']['caustic_method'] == 'none' and v['exact']['caustic_method'] == 'photons'
    assert v['pencil']['caustic_method'] == 'grid-pencil'
    assert c['pencil_over_exact'] > 0 and 'provenance' in d
PY"
check "the textbook image is farther from the reference than the caustic renders" "$py - '$out/caustics.json' <<'PY'
import json, sys
for c in json.load(open(sys.argv[1]))['cases']:
    v = {r['variant']: r for r in c['variants']}
    assert v['textbook']['rms'] > max(v['exact']['rms'], v['pencil']['rms']), c['case']
PY"

$pencil bench caustics --runs 0 >/dev/null 2>"$tmp/err"; rc=$?
check "--runs 0: exit 2 naming --runs" "[ $rc -eq 2 ] && grep -q -- '--runs' '$tmp/err'"
$pencil bench caustics --json "$tmp" >/dev/null 2>"$tmp/err"; rc=$?
check "--json naming a directory: exit 2 before rendering" "[ $rc -eq 2 ] && grep -q -- '--json' '$tmp/err'"
$pencil bench caustics --scenes "$tmp/nowhere" --quick >/dev/null 2>"$tmp/err"; rc=$?
check "--scenes without the scenes: exit 2 naming the file" "[ $rc -eq 2 ] && grep -q 'fig8-caustics.json' '$tmp/err'"
$pencil bench caustics --case fig8,nope --quick >/dev/null 2>"$tmp/err"; rc=$?
check "--case with an unknown name: exit 2 naming it" "[ $rc -eq 2 ] && grep -q -- \"--case: no case 'nope'\" '$tmp/err'"
$pencil bench caustics --case fig8 --quick --runs 1 --json "$tmp/one.json" >/dev/null 2>"$tmp/err"; rc=$?
check "--case fig8 runs that case alone" "[ $rc -eq 0 ] && $py -c \"import json,sys; assert [c['case'] for c in json.load(open(sys.argv[1]))['cases']] == ['fig8']\" '$tmp/one.json'"
$pencil bench caustics --help >"$tmp/help"; rc=$?
check "--help exits 0" "[ $rc -eq 0 ] && grep -q usage '$tmp/help'"
finish cli_bench_caustics
