#!/usr/bin/env bash
# `pencil verify bounds --quick`: exit 0 (the corrected A-1 holds, the Ceres envelope agrees),
# the JSON summary's documented keys, every CSV table, the errata visible in the printed variant,
# the same results on one thread as on all.
# Leaves the CSV tables in $2 for the notebook test (ctest fixture bounds_csv).
set -u
pencil=$1
dir=$2
rm -rf "$dir" && mkdir -p "$dir"
$pencil verify bounds --quick --json "$dir/summary.json" --csv "$dir" >"$dir/out.txt" ||
  { cat "$dir/out.txt"; echo "FAIL: verify bounds --quick must pass"; exit 1; }
/usr/bin/python3 - "$dir" <<'PY' || exit 1
import csv, json, math, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["pass"] is True and s["corrected_failures"] == 0, s
assert s["systems"] >= 150, s["systems"]
for c in "ABCDEF":
    assert s["corrected"][c]["failures"] == 0
    assert s["corrected"][c]["min"] >= 1 - 1e-9, (c, s["corrected"][c])
# errata of A-1 that the quick sweep must show: f (n/n' factor), d (R^3), a of mirrors (sign)
for c in "ADF":
    assert s["printed"][c]["failures"] > 0, (c, s["printed"][c])
assert s["printed"]["B"]["min"] <= 1 + 1e-9  # b is right for single elements: ratio 1
assert s["tensor_crosscheck"]["above_tolerance"] == 0
assert s["onset"]["second_order_vanishes"] >= 2  # pinhole -> sphere through its centre
assert s["fit"]["outside_tolerance"] == 0 and s["fit"]["unusable"] == 0
assert s["fit"]["worst_attained_deviation"] <= 0.02
for name in ["systems", "summary", "families", "onset", "fit"]:
    rows = list(csv.DictReader(l for l in open(f"{d}/bounds_{name}.csv") if not l.startswith("#")))
    assert rows, name
onset = list(csv.DictReader(l for l in open(f"{d}/bounds_onset.csv") if not l.startswith("#")))
centre = [r for r in onset if "aim 0.00" in r["label"]]
assert centre and all(r["second_order_vanishes"] == "1" for r in centre)
# the spread limit stays finite there: Eq. (6) alone is capped, the third-order term limits it
assert all(r["regime_eq6"] == "cap" and r["regime_k3"] == "third_order" and
           math.isfinite(float(r["spread_k3"])) and float(r["spread_k3"]) < 0.5 for r in centre)
print("cli_verify_bounds: passed,", s["systems"], "systems")
PY
if $pencil verify bounds --quick --no-fit --csv /nonexistent/dir >/dev/null 2>"$dir/err"; then
  echo "FAIL: unwritable CSV directory must fail"; exit 1
fi
grep -q "/nonexistent/dir" "$dir/err" || { echo "FAIL: error must name the file"; exit 1; }
# the systems are verified in parallel: one thread gives the same tables, summary and report
t1="$dir/one-thread" && mkdir -p "$t1"
$pencil verify bounds --quick --threads 1 --json "$t1/summary.json" --csv "$t1" >"$t1/out.txt" ||
  { echo "FAIL: verify bounds --quick --threads 1 must pass"; exit 1; }
# the provenance (command line, date) differs by design; everything else must not
for d in "$dir" "$t1"; do
  /usr/bin/python3 -c "import json,sys; s=json.load(open(sys.argv[1])); p=s.pop('provenance'); \
assert p['version'] and p['commit'] and 'verify bounds' in p['command_line'], p; \
json.dump(s, open(sys.argv[2], 'w'), sort_keys=True)" "$d/summary.json" "$d/summary.stripped.json" ||
    { echo "FAIL: summary.json must carry the provenance"; exit 1; }
done
for f in summary.stripped.json out.txt bounds_systems.csv bounds_summary.csv bounds_families.csv \
         bounds_onset.csv bounds_fit.csv; do # a CSV's provenance lines ('# ...') differ likewise
  cmp -s <(grep -v '^#' "$dir/$f") <(grep -v '^#' "$t1/$f") ||
    { echo "FAIL: $f differs between all threads and --threads 1"; exit 1; }
done
grep -q '^# command_line: .*verify bounds --quick --threads 1 ' "$t1/bounds_systems.csv" ||
  { echo "FAIL: the CSV must start with the provenance"; exit 1; }
$pencil verify bounds --quick --threads 0 >/dev/null 2>"$dir/err"; rc=$?
[ $rc -eq 2 ] && grep -q -- "--threads" "$dir/err" ||
  { echo "FAIL: --threads 0 must exit 2 naming the option"; exit 1; }
$pencil verify bounds --bogus >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || { echo "FAIL: unknown option must exit 2"; exit 1; }
exit 0
