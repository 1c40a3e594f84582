# cli_lib.sh -- sourced by the tests/cli_*.sh scripts: unset variables are errors; `check NAME
# CONDITION` evaluates CONDITION, prints "ok: NAME" or "FAIL: NAME" and remembers a failure;
# `finish SCRIPT` prints the verdict and exits 0 or 1; $py is Debian's Python, which has numpy and
# OpenImageIO (the python3 on PATH may be another interpreter).
set -u
fail=0
py=/usr/bin/python3
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; else echo "ok: $1"; fi; }
finish() {
  echo "$1: $([ $fail -eq 0 ] && echo passed || echo FAILED)"
  exit $fail
}
