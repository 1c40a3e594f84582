#!/usr/bin/env bash
# Execute a notebook headless with Debian's Python (never the python3 on PATH):
#   run_notebook.sh NOTEBOOK [VAR=value ...]   -- the assignments are exported first.
set -euo pipefail
nb=$1; shift
for kv in "$@"; do export "${kv?}"; done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
PATH=/usr/bin:$PATH /usr/bin/python3 -m nbconvert --to notebook --execute \
  --ExecutePreprocessor.kernel_name=python3 --ExecutePreprocessor.timeout=300 \
  --output-dir "$work" --output executed.ipynb "$nb"
echo "notebook $(basename "$nb"): executed"
