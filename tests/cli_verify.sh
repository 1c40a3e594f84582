#!/usr/bin/env bash
# `pencil verify matrices --quick` writes a JSON summary with the documented keys and a CSV.
set -u
pencil=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
$pencil verify matrices --quick --json "$dir/v.json" --csv "$dir/v.csv" >"$dir/out.txt" || { cat "$dir/out.txt"; exit 1; }
/usr/bin/python3 - "$dir" <<'PY' || exit 1
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/v.json"))
assert s["failures"] == 0 and s["worst_relative_error"] <= 1e-9, s
rows = list(csv.DictReader(open(f"{d}/v.csv")))
assert len(rows) == s["systems"] > 100
assert all(r["pass"] == "1" for r in rows)
print("cli_verify: passed,", s["systems"], "systems")
PY
if $pencil verify matrices --json /nonexistent/dir/v.json --quick >/dev/null 2>"$dir/err"; then
  echo "FAIL: unwritable JSON path must fail"; exit 1
fi
grep -q "/nonexistent/dir/v.json" "$dir/err" || { echo "FAIL: error must name the file"; exit 1; }
