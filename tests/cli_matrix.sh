#!/usr/bin/env bash
# The `pencil matrix` contract: JSON {"T": 4x4} on stdout; no matrix -> exit 1, reason on
# stderr, nothing on stdout; bad parameters -> exit 2; --help everywhere.
set -u
pencil=$1
fail=0
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; else echo "ok: $1"; fi; }
py=/usr/bin/python3

out=$($pencil matrix refract --theta-deg 30 --n1 1 --n2 1.5 --radius 2)
check "refract prints a 4x4 JSON matrix" \
  "echo '$out' | $py -c 'import json,sys; t=json.load(sys.stdin)[\"T\"]; assert len(t)==4 and all(len(r)==4 for r in t)'"
check "refract C11 = -h/(R cos t cos t')" \
  "echo '$out' | $py -c 'import json,sys,math; t=json.load(sys.stdin)[\"T\"]; th=math.radians(30); tp=math.asin(math.sin(th)/1.5); h=math.cos(tp)-math.cos(th)/1.5; assert abs(t[2][0]+h/(2*math.cos(th)*math.cos(tp)))<1e-15'"
out=$($pencil matrix transfer --distance 2.5)
check "transfer is [[1,z],[0,1]]" "[ '$out' = '{\"T\": [[1, 0, 2.5, 0], [0, 1, 0, 2.5], [0, 0, 1, 0], [0, 0, 0, 1]]}' ]"
out=$($pencil matrix reflect --theta-deg 0 --radius -3)
check "concave mirror: xi1' = 2x/|R| in the flipped frame" \
  "echo '$out' | $py -c 'import json,sys; t=json.load(sys.stdin)[\"T\"]; assert abs(t[2][0]-2/3)<1e-15 and t[0][0]==-1'"

out=$($pencil matrix refract --theta-deg 45 --n1 1.5 --n2 1 2>/tmp/pencil_err.$$); rc=$?
check "TIR exits 1" "[ $rc -eq 1 ]"
check "TIR prints nothing on stdout" "[ -z '$out' ]"
check "TIR reason on stderr" "grep -q 'total internal reflection' /tmp/pencil_err.$$"
out=$($pencil matrix refract --theta-deg 90 --n1 1 --n2 1.5 2>/dev/null); rc=$?
check "grazing exits 1 with empty stdout" "[ $rc -eq 1 ] && [ -z '$out' ]"
$pencil matrix refract --theta-deg 10 --n1 1 --n2 1.5 --radius 0 >/dev/null 2>&1; rc=$?
check "radius 0 is a usage error" "[ $rc -eq 2 ]"
$pencil matrix refract --theta-deg abc --n1 1 --n2 1.5 >/dev/null 2>/tmp/pencil_err.$$; rc=$?
check "bad number names the option" "[ $rc -eq 2 ] && grep -q -- '--theta-deg' /tmp/pencil_err.$$"
for bad in 0x10 " 5" inf; do
  $pencil matrix refract --theta-deg "$bad" --n1 1 --n2 1.5 >/dev/null 2>/tmp/pencil_err.$$; rc=$?
  check "'$bad' is not a decimal number" "[ $rc -eq 2 ] && grep -q 'expected a decimal number' /tmp/pencil_err.$$"
done
out=$($pencil matrix refract --theta-deg 1e-320 --n1 1 --n2 1.5 2>/tmp/pencil_err.$$); rc=$?
check "a subnormal angle is a number (normal incidence)" "[ $rc -eq 0 ] && echo '$out' | grep -q '\"T\"'"
$pencil matrix refract --theta-deg 1e400 --n1 1 --n2 1.5 >/dev/null 2>/tmp/pencil_err.$$; rc=$?
check "1e400 is beyond a double, said so" "[ $rc -eq 2 ] && grep -q 'beyond the range' /tmp/pencil_err.$$"
$pencil matrix refract --theta-deg 10 --n1 -1 --n2 1.5 >/dev/null 2>&1; rc=$?
check "negative index is a usage error" "[ $rc -eq 2 ]"
$pencil matrix refract --theta-deg 10 --n1 1 >/dev/null 2>&1; rc=$?
check "missing --n2 is a usage error" "[ $rc -eq 2 ]"
$pencil matrix transfer --theta-deg 10 >/dev/null 2>&1; rc=$?
check "misplaced option is a usage error" "[ $rc -eq 2 ]"
out=$($pencil matrix refract --theta-deg 30 --n1 1 --n2 1.5 --radius 2 --variant printed)
check "printed variant has B = identity" \
  "echo '$out' | $py -c 'import json,sys; t=json.load(sys.stdin)[\"T\"]; assert t[0][2]==1 and t[1][3]==1'"
for c in "" "matrix" "verify"; do
  $pencil $c --help >/tmp/pencil_help.$$ 2>&1; rc=$?
  check "pencil $c --help exits 0 and prints usage" "[ $rc -eq 0 ] && grep -q usage /tmp/pencil_help.$$"
done
rm -f /tmp/pencil_err.$$ /tmp/pencil_help.$$
echo "cli_matrix: $([ $fail -eq 0 ] && echo passed || echo FAILED)"
exit $fail
