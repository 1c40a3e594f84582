#!/usr/bin/env bash
# scripts/curves contracts (issue 26): --quick writes DIR/curves.csv with its provenance lines
# ('# version:', '# commit:', '# date:', '# command_line:', as pencil's), its header and a row per point and mode (default, certified) of each curve (spp, size, spheres, rho), every time and
# ratio positive and the ratio the times' quotient; with valgrind the rho curve's default rows carry
# instruction counts (the counts' quotient), else those columns stay empty; curves.json records the
# version, the command line and each bench command; a bad option exits 2 naming it, a pencil that
# is not an executable file exits 2. DIR (argument 3) keeps the outputs.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
curves=$1
pencil=$2
out=${3:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
[ -n "$out" ] || out=$tmp/out

$py "$curves" --quick --pencil "$pencil" --out "$out" >"$tmp/log" 2>"$tmp/err"; rc=$?
check "curves --quick exits 0" "[ $rc -eq 0 ] && [ -s '$out/curves.csv' ] && [ -s '$out/curves.json' ]"
valgrind=0
command -v valgrind >/dev/null && valgrind=1
check "CSV: every curve's points, both modes, times and ratios consistent" "$py - '$out' $valgrind <<'PY'
import csv, json, sys
lines = open(sys.argv[1] + '/curves.csv').read().splitlines()
assert lines[0].startswith('# version: 0.') and lines[1].startswith('# commit: '), lines[:4]
assert lines[2].startswith('# date: 20') and lines[3].startswith('# command_line: '), lines[:4]
assert '--quick' in lines[3], lines[:4]
rows = list(csv.DictReader(l for l in lines if not l.startswith('#')))
assert list(rows[0]) == ['curve', 'x', 'scene', 'size', 'spp', 'rho', 'mode', 'exact_s',
                         'pencil_s', 'ratio', 'exact_instructions', 'pencil_instructions',
                         'instruction_ratio'], list(rows[0])
assert len(rows) == 16, len(rows)
for c in ('spp', 'size', 'spheres', 'rho'):
    r = [x for x in rows if x['curve'] == c]
    assert len(r) == 4 and {x['mode'] for x in r} == {'default', 'certified'}, (c, r)
for r in rows:
    e, p, q = float(r['exact_s']), float(r['pencil_s']), float(r['ratio'])
    assert e > 0 and p > 0 and abs(q - p / e) < 1e-9 * q, r
    counted = r['curve'] == 'rho' and r['mode'] == 'default' and sys.argv[2] == '1'
    if counted:
        a, b = int(r['exact_instructions']), int(r['pencil_instructions'])
        assert a > 0 and b > 0 and abs(float(r['instruction_ratio']) - b / a) < 1e-9, r
    else:
        assert r['exact_instructions'] == r['instruction_ratio'] == '', r
assert {r['scene'] for r in rows if r['curve'] == 'spheres'} == {'scenes/spheres-1.json',
                                                                  'scenes/spheres-10.json'}
j = json.load(open(sys.argv[1] + '/curves.json'))
assert j['version'].startswith('pencil ') and '--quick' in j['command_line'], j
assert len(j['rows']) == 16 and any('bench pencil' in c for c in j['commands'])
PY"
$py "$curves" --quick --curves spp,bogus --pencil "$pencil" --out "$tmp/x" >/dev/null 2>"$tmp/err"; rc=$?
check "an unknown curve exits 2 naming --curves" "[ $rc -eq 2 ] && grep -q -- '--curves' '$tmp/err' && [ ! -e '$tmp/x/curves.csv' ]"
$py "$curves" --quick --runs 2 --pencil "$pencil" --out "$tmp/x" >/dev/null 2>"$tmp/err"; rc=$?
check "--runs 2 exits 2 naming --runs" "[ $rc -eq 2 ] && grep -q -- '--runs' '$tmp/err'"
$py "$curves" --quick --pencil "$tmp" --out "$tmp/x" >/dev/null 2>"$tmp/err"; rc=$?
check "a --pencil that is no executable file exits 2 naming it" "[ $rc -eq 2 ] && grep -q -- '--pencil' '$tmp/err'"
$py "$curves" --help >"$tmp/help" 2>&1; rc=$?
check "--help exits 0 and names the curves" "[ $rc -eq 0 ] && grep -q 'spheres' '$tmp/help'"
finish cli_curves
