#!/usr/bin/env bash
# Runs that scale out: `pencil sweep` and `pencil figures` split into shards (--shard K/N) and
# merged (--merge) give what one run gives, timings aside (summary.json and sweep.json equal
# without their time fields, the CSV columns that are not times equal, the histogram and the
# Fig. 8 image identical); a merge refuses a missing shard, a shard of another run and extra
# options; the Slurm job-array script and the MPI launcher run the same split (the launcher only
# where mpirun is installed: openmpi-bin, which scripts/deps installs).
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$(realpath "$1")
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
fig=(--quick --size 16x16 --fig9-spp 1,4)
swp=(--quick --size 16x16)

# JSON equal once the time fields and the provenance are removed
same_json() {
  $py - "$1" "$2" <<'PY'
import json, sys
drop = {"provenance", "exact_s", "pencil_s", "exact_wall_s", "pencil_wall_s", "ratio", "speedup",
        "certified_ratio", "fig9_below_0_1_from_spp"}
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if k not in drop}
    return [strip(v) for v in x] if isinstance(x, list) else x
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
sys.exit(0 if a == b else 1)
PY
}
# CSV equal without the time columns (named *_s, *_wall_s, ratio)
same_csv() {
  $py - "$1" "$2" <<'PY'
import csv, sys
def rows(p):
    r = list(csv.reader(l for l in open(p) if not l.startswith("#")))
    keep = [i for i, h in enumerate(r[0]) if not (h.endswith("_s") or h == "ratio")]
    return [[row[i] for i in keep] for row in r]
sys.exit(0 if rows(sys.argv[1]) == rows(sys.argv[2]) else 1)
PY
}

$pencil sweep "${swp[@]}" --out one >/dev/null 2>&1
for k in 1 2; do $pencil sweep "${swp[@]}" --out two --shard $k/2 >/dev/null 2>&1 || echo "shard $k failed"; done
check "the shards leave their results in DIR/shards/" "[ -s two/shards/sweep-1-of-2.json ] && [ -s two/shards/sweep-2-of-2.json ] && [ ! -e two/sweep.csv ]"
$pencil sweep --merge --out two >/dev/null 2>&1; rc=$?
check "sweep: 2 shards merged" "[ $rc -eq 0 ] && [ -s two/sweep.csv ] && [ -s two/sweep.json ]"
check "sweep: merged CSV equals the single run's (times aside)" "same_csv one/sweep.csv two/sweep.csv"
check "sweep: merged JSON equals the single run's (times aside)" "same_json one/sweep.json two/sweep.json"

$pencil figures "${fig[@]}" --out f1 >/dev/null 2>&1
for k in 1 2 3; do $pencil figures "${fig[@]}" --out f3 --shard $k/3 >/dev/null 2>&1 || echo "shard $k failed"; done
$pencil figures --merge --out f3 >/dev/null 2>&1; rc=$?
check "figures: 3 shards merged" "[ $rc -eq 0 ] && [ -s f3/summary.json ]"
check "figures: summary.json equals the single run's (times aside)" "same_json f1/summary.json f3/summary.json"
check "figures: Fig. 10 histogram identical" "cmp -s <(grep -v '^#' f1/fig10_hist.csv) <(grep -v '^#' f3/fig10_hist.csv)"
check "figures: sweep.csv and fig9.csv equal (times aside)" "same_csv f1/sweep.csv f3/sweep.csv && same_csv f1/fig9.csv f3/fig9.csv"
if command -v idiff >/dev/null; then
  check "figures: the Fig. 8 image identical" "idiff -q -fail 0 -failpercent 0 -warn 0 f1/fig8.exr f3/fig8.exr >/dev/null"
else
  echo "skip: Fig. 8 image comparison (idiff missing: apt-get install openimageio-tools)"
fi

mkdir -p miss/shards && cp f3/shards/figures-1-of-3.json f3/shards/figures-3-of-3.json miss/shards/
$pencil figures --merge --out miss >/dev/null 2>"err"; rc=$?
check "a missing shard is named" "[ $rc -eq 1 ] && grep -q 'shard 2 of 3 is missing' err"
$pencil figures --quick --size 24x24 --fig9-spp 1,4 --out mixed --shard 1/2 >/dev/null 2>&1
cp f3/shards/figures-2-of-3.json mixed/shards/ 2>/dev/null
$pencil figures --quick --size 16x16 --fig9-spp 1,4 --out other --shard 2/2 >/dev/null 2>&1
cp other/shards/figures-2-of-2.json mixed/shards/
rm -f mixed/shards/figures-2-of-3.json
$pencil figures --merge --out mixed >/dev/null 2>"err"; rc=$?
check "a shard of another run is refused" "[ $rc -eq 1 ] && grep -q 'configuration differs' err"
$pencil figures --merge --out f3 --quick >/dev/null 2>"err"; rc=$?
check "--merge takes only --out" "[ $rc -eq 2 ] && grep -q 'takes only --out' err"
$pencil sweep --quick --shard 3/2 --out x >/dev/null 2>"err"; rc=$?
check "--shard 3/2 is refused" "[ $rc -eq 2 ] && grep -q 'K/N' err"

# a single figure on its own
$pencil figures "${fig[@]}" --only fig9 --out only9 >/dev/null 2>&1; rc=$?
check "--only fig9 times Fig. 9 alone" \
  "[ $rc -eq 0 ] && [ -s only9/fig9.csv ] && [ ! -e only9/fig8.exr ] && $py -c 'import json,sys; d=json.load(open(\"only9/summary.json\")); sys.exit(not (d[\"only\"] == [\"fig9\"] and \"fig9\" in d and \"fig10\" not in d and \"targets\" not in d))'"
for k in 1 2; do $pencil figures "${fig[@]}" --only fig9 --out only9s --shard $k/2 >/dev/null 2>&1; done
$pencil figures --merge --out only9s >/dev/null 2>"err"; rc=$?
check "--only fig9 in 2 shards merges to the single run's (times aside)" \
  "[ $rc -eq 0 ] && same_json only9/summary.json only9s/summary.json && same_csv only9/fig9.csv only9s/fig9.csv"
# --fig9-spp has no effect on Figs. 8 and 10 alone, and is refused there
$pencil figures --quick --size 16x16 --only fig10 --out only10 >/dev/null 2>&1; rc=$?
check "--only fig10 makes Figs. 8 and 10 alone, equal to the full run's" \
  "[ $rc -eq 0 ] && [ -s only10/fig8.exr ] && [ ! -e only10/fig9.csv ] && cmp -s <(grep -v '^#' f1/fig10_hist.csv) <(grep -v '^#' only10/fig10_hist.csv)"
$pencil figures --only fig11 --out x >/dev/null 2>"err"; rc=$?
check "--only fig11 is refused, listing the figures" "[ $rc -eq 2 ] && grep -q 'fig8, fig9, fig10, targets and sweep' err"

for k in 1 2; do
  SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=2 PENCIL=$pencil \
    bash "$src/scripts/slurm-shards.sh" sweep slurm "${swp[@]}" >/dev/null 2>&1 || echo "slurm task $k failed"
done
$pencil sweep --merge --out slurm >/dev/null 2>&1; rc=$?
check "the Slurm array script runs the shards" "[ $rc -eq 0 ] && same_csv one/sweep.csv slurm/sweep.csv"
if command -v mpirun >/dev/null; then
  PENCIL=$pencil "$src/scripts/mpi-shards" 2 sweep mpi "${swp[@]}" >mpi.log 2>&1; rc=$?
  check "the MPI launcher runs 2 shards and merges" "[ $rc -eq 0 ] && same_csv one/sweep.csv mpi/sweep.csv" ||
    cat mpi.log
else
  echo "skip: the MPI launcher (mpirun missing: apt-get install openmpi-bin)"
fi

finish cli_shards
