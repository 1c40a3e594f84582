#!/usr/bin/env bash
# Execute a notebook headless with Debian's Python (never the python3 on PATH):
#   run_notebook.sh NOTEBOOK [VAR=value ...]   -- the assignments are exported first.
# With OUTDIR=dir among them the executed notebook is kept there, else in a temporary folder.
set -euo pipefail
nb=$1; shift
export PYDEVD_DISABLE_FILE_VALIDATION=1
for kv in "$@"; do export "${kv?}"; done
if [ -n "${OUTDIR:-}" ]; then
  work=$OUTDIR
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
PATH=/usr/bin:$PATH /usr/bin/python3 -m nbconvert --to notebook --execute \
  --ExecutePreprocessor.kernel_name=python3 --ExecutePreprocessor.timeout=300 \
  --output-dir "$work" --output "$(basename "$nb")" "$nb"
echo "notebook $(basename "$nb"): executed"
