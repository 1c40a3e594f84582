#!/usr/bin/env bash
# A Slurm job array that runs `pencil figures` or `pencil sweep` as one shard per array task;
# Slurm schedules, the project only splits (--shard) and merges (--merge). Submit the array,
# then the merge to run after every task succeeded:
#
#   jid=$(sbatch --parsable --array=1-16 scripts/slurm-shards.sh figures out/figures --fig9-spp 1,4,9,49)
#   sbatch --dependency=afterok:$jid --wrap "build/cli/pencil figures --merge --out out/figures"
#
# The output directory must be on a file system every node sees. Each task runs single-threaded
# renders as the paper's figures do (--threads 1 by default), so ask for one CPU per task;
# PENCIL names the binary (default build/cli/pencil in the submission directory).
#SBATCH --job-name=pencil-shards
#SBATCH --cpus-per-task=1
#SBATCH --output=pencil-shard-%A_%a.log
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,13p' "$0" >&2; exit 2; }
: "${SLURM_ARRAY_TASK_ID:?run this script with sbatch --array=1-N}"
: "${SLURM_ARRAY_TASK_COUNT:?run this script with sbatch --array=1-N}"
pencil=${PENCIL:-${SLURM_SUBMIT_DIR:-.}/build/cli/pencil}
cmd=$1 out=$2
shift 2
k=$((SLURM_ARRAY_TASK_ID - ${SLURM_ARRAY_TASK_MIN:-1} + 1))
exec "$pencil" "$cmd" "$@" --out "$out" --shard "$k/$SLURM_ARRAY_TASK_COUNT"
