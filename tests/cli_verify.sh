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
rows = list(csv.DictReader(l for l in open(f"{d}/v.csv") if not l.startswith("#")))
assert len(rows) == s["systems"] > 100
assert all(r["pass"] == "1" for r in rows)
print("cli_verify: passed,", s["systems"], "systems")
PY
if $pencil verify matrices --json /nonexistent/dir/v.json --quick >/dev/null 2>"$dir/err"; then
  echo "FAIL: unwritable JSON path must fail"; exit 1
fi
grep -q "/nonexistent/dir/v.json" "$dir/err" || { echo "FAIL: error must name the file"; exit 1; }

# `pencil verify stability --quick`: counts in a table and in JSON (with provenance), no failure,
# the counts independent of the thread count, every regime drawn and each refusal reason met.
$pencil verify stability --quick --threads 2 --json "$dir/s.json" >"$dir/s.txt" || { cat "$dir/s.txt"; exit 1; }
$pencil verify stability --quick --threads 1 --json "$dir/s1.json" >/dev/null || exit 1
grep -q "silent NaN/Inf 0" "$dir/s.txt" || { echo "FAIL: stability table"; cat "$dir/s.txt"; exit 1; }
/usr/bin/python3 - "$dir" <<'PY' || exit 1
import json, sys
d = sys.argv[1]
s, s1 = json.load(open(f"{d}/s.json")), json.load(open(f"{d}/s1.json"))
a = s["all"]
assert s["failures"] == 0 and "provenance" in s, s
assert a["total"] == s["samples"] == 20000 and a["silent_nonfinite"] == 0, a
assert a["checked"] + sum(a["refused"].values()) == a["total"], a
assert all(a["refused"][k] > 0 for k in ("tir", "grazing", "illcond", "overflow")), a
assert a["largest_bound"] <= s["accuracy"] and a["sampled"] > 0, a
assert len(s["regimes"]) == 10 and all(r["total"] == 2000 for r in s["regimes"].values())
assert s["all"] == s1["all"], "counts depend on the thread count"
print("cli_verify: stability passed,", a["checked"], "checked,", a["refused"], "refused")
PY
# `pencil verify illuminance --quick`: the summary and the rows, no failure, provenance; the
# pool's energy check in the JSON.
$pencil verify illuminance --quick --json "$dir/i.json" --csv "$dir/i.csv" >"$dir/i.txt" || { cat "$dir/i.txt"; exit 1; }
/usr/bin/python3 - "$dir" <<'PY' || exit 1
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/i.json"))
assert s["failures"] == 0 and "provenance" in s, s
assert s["worst_relative_error_away"] <= s["tolerance"] == 1e-9, s
rows = list(csv.DictReader(l for l in open(f"{d}/i.csv") if not l.startswith("#")))
assert len(rows) == s["cases"] > 200 and all(r["pass"] == "1" for r in rows)
assert {r["source"] for r in rows} == {"point", "parallel"}
assert any(r["status"] == "PX_ECAUSTIC" for r in rows), "no receiver came near enough a caustic"
assert abs(s["pool"]["flux_ratio_eq8"] - 1) < 1e-10 and abs(s["pool"]["flux_ratio_printed_eq1"] - 0.75) < 1e-3
print("cli_verify: illuminance passed,", s["cases"], "cases")
PY
$pencil verify stability --samples 0 >/dev/null 2>&1; rc=$?
[ $rc -eq 2 ] || { echo "FAIL: --samples 0 must be a usage error"; exit 1; }
# `pencil verify dispersion` (the full sweep: 0.3 s): every column within 1e-9 of exact tracing
# differentiated in wavelength, the printed Eq. (14) failing (erratum E7), the linearity sweep in
# lambda and in the paper's Lambda.
$pencil verify dispersion --json "$dir/d.json" --csv "$dir/d.csv" >"$dir/d.txt" || { cat "$dir/d.txt"; exit 1; }
/usr/bin/python3 - "$dir" <<'PY' || exit 1
import csv, json, sys
d = sys.argv[1]
s = json.load(open(f"{d}/d.json"))
assert s["failures"] == 0 and "provenance" in s and s["tolerance"] == 1e-9, s
assert s["compared"] >= 1000 and s["worst_relative_error"] <= 1e-9, s
assert s["printed"]["failures"] > 1000, s["printed"]
assert set(s["families"]) >= {"plane", "sphere", "cylinder", "ellipsoid", "cascade"}
lin = {round(r["delta_lambda_nm"]): r for r in s["linearity"]}
assert lin[10]["optics_median"] < lin[10]["median"] < lin[190]["median"], lin
# the paper's Lambda scale removes the index's curvature: at the range's ends its linear model
# errs a tenth of lambda's or less
for k in (-200, 190):
    assert lin[k]["lambda_scale_median"] < 0.1 * lin[k]["median"], lin[k]
assert "lambda_scale_+190" in csv.DictReader(l for l in open(f"{d}/d.csv") if not l.startswith("#")).fieldnames
# Eq. (15) and 3.2.4 (erratum E8): the derived image-solid vertex errs by the linear model's
# error, the printed one (absolute wavelength) by factors; the selective estimate printed is twice
sol = {round(r["delta_lambda_nm"]): r for r in s["image_solids"]}
assert sol[10]["cases"] >= 100, sol[10]
assert sol[10]["derived_median"] < 0.1 and sol[10]["printed_median"] > 10, sol[10]
assert sol[190]["lambda_scale_median"] < 0.2 * sol[190]["derived_median"], sol[190]
sel = s["selective"]
assert 0.5 < sel["median"] < 1.2 and sel["printed_median"] > 1.4 * sel["median"], sel
rows = list(csv.DictReader(l for l in open(f"{d}/d.csv") if not l.startswith("#")))
assert len(rows) == s["cases"] and {r["glass"] for r in rows} == {"low", "high"}
assert any("41.8" in r["label"] and r["status"].startswith("ok") for r in rows), "no case near the critical angle"
# a nan in a row says why in its status (once 156 rows of --quick had "ok" and nan): "ok" rows
# hold numbers only; the linear model's columns are nan where the exact column is zero, or where
# exact tracing has no ray at an offset (total internal reflection)
model = [k for k in rows[0] if k.startswith(("lin_", "optics_", "lambda_scale_"))]
known = {"ok", "ok_zero_column", "ok_tir_at_offset", "ok_no_ray_at_offset",
         "ok_not_finite_at_offset", "ok_no_lambda_scale"}
for r in rows:
    nan = [k for k in ["rel_err", "printed_rel_err", "column_scale"] + model if r[k] == "nan"]
    assert not (r["status"] == "ok" and nan), (r["id"], r["label"], nan)
    assert r["status"] in known or not r["status"].startswith("ok"), r["status"]
    if r["status"] == "ok_zero_column":
        assert float(r["column_scale"]) <= 1e-12 and all(r[k] == "nan" for k in model), r
    if r["status"] == "ok_tir_at_offset":
        assert float(r["column_scale"]) > 1e-12 and any(r[k] == "nan" for k in model), r
assert {"ok_zero_column", "ok_tir_at_offset"} <= {r["status"] for r in rows}
print("cli_verify: dispersion passed,", s["compared"], "cases")
PY
# outputs checked before the work (verify stability runs about 70 s by default): exit 2 naming
# the option, nothing on stdout
$pencil verify stability --samples 200000 --threads 1 --json /nonexistent/dir/s.json \
  >"$dir/out" 2>"$dir/err"; rc=$?
if [ $rc -ne 2 ] || [ -s "$dir/out" ] || ! grep -q -- '--json: /nonexistent/dir/s.json' "$dir/err"; then
  echo "FAIL: verify stability with an unwritable --json must stop before the run (rc $rc)"
  cat "$dir/err"; exit 1
fi
touch "$dir/afile"
$pencil verify bounds --quick --no-fit --csv "$dir/afile" >"$dir/out" 2>"$dir/err"; rc=$?
if [ $rc -ne 2 ] || [ -s "$dir/out" ] || ! grep -q 'afile is not a writable directory' "$dir/err"; then
  echo "FAIL: verify bounds --csv FILE must stop before the run naming it (rc $rc)"; exit 1
fi
echo "cli_verify: outputs checked first"
