#!/usr/bin/env bash
# Messages of the pencil command (docs/journal/2026-12-06-cli-mends.md): the benchmarks listed
# from one table; every error names its command ("pencil CMD: ...", never a plain "pencil: "
# once a command is known); numbers echoed as they read back (not %g: 89.9999999999 is not 90);
# a UTF-8 byte order mark at the start of a scene skipped.
set -u
pencil=$(realpath "$1")
src=$(cd "$(dirname "$0")/.." && pwd)
fail=0
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; else echo "ok: $1"; fi; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# --- the benchmarks, from one table: `bench foo` names every one `bench --help` lists
$pencil bench foo >/dev/null 2>"$tmp/err"; rc=$?
names=$($pencil bench --help | sed -n 's/^usage: pencil bench \([a-z|]*\).*/\1/p' | tr '|' ' ')
check "bench --help lists dispersion among the benchmarks" "echo '$names' | grep -qw dispersion"
missing=""
for b in $names; do grep -qw "$b" "$tmp/err" || missing="$missing $b"; done
check "bench foo: exit 2 naming every benchmark (once it left out dispersion)" \
  "[ $rc -eq 2 ] && [ -z '$missing' ] && grep -q \"unknown benchmark 'foo'\" '$tmp/err'"

[ $fail -eq 0 ] && echo "cli_messages: all passed" || echo "cli_messages: FAILED"
exit $fail
