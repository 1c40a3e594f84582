#!/usr/bin/env bash
# The `pencil bounds` contract: JSON {"a".."f"} on stdout with the conventions of `pencil matrix`;
# no coefficients -> exit 1, reason on stderr, nothing on stdout; bad parameters -> exit 2; --help.
# Values are checked against closed forms evaluated independently here (docs/bounds.md).
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1
err=$(mktemp)
trap 'rm -f "$err"' EXIT

out=$($pencil bounds refract --theta-deg 30 --n1 1 --n2 1.5 --radius 2)
check "refract prints the six coefficients as JSON" \
  "echo '$out' | $py -c 'import json,sys; k=json.load(sys.stdin); assert sorted(k)==list(\"abcdef\") and k[\"c\"]==0'"
# b = s (1 - eta^2) / (c^2 c'), f = eta s (1 - eta^2) / (2 c'^3), a = k/c^2 (sin(t-t')/(2c) + s' h / c')
check "corrected a, b, f match their closed forms" \
  "echo '$out' | $py -c '
import json,sys,math
k=json.load(sys.stdin); t=math.radians(30); e=1/1.5; s,c=math.sin(t),math.cos(t); sp=e*s; cp=math.sqrt(1-sp*sp); h=cp-e*c
assert abs(k[\"b\"]-s*(1-e*e)/(c*c*cp))<1e-15
assert abs(k[\"f\"]-e*s*(1-e*e)/(2*cp**3))<1e-15
assert abs(k[\"a\"]-0.5/(c*c)*((s*cp-c*sp)/(2*c)+sp*h/cp))<1e-15'"
outp=$($pencil bounds refract --theta-deg 30 --n1 1 --n2 1.5 --radius 2 --variant printed)
check "printed f carries the extra factor n/n' (erratum)" \
  "$py -c 'import json; a=json.loads(\"\"\"$out\"\"\"); b=json.loads(\"\"\"$outp\"\"\"); assert abs(b[\"f\"]-a[\"f\"]/1.5)<1e-15 and abs(b[\"b\"]-a[\"b\"])<1e-15'"
check "the sign of the radius does not change the coefficients" \
  "[ \"\$($pencil bounds refract --theta-deg 30 --n1 1 --n2 1.5 --radius -2)\" = '$out' ]"
out=$($pencil bounds reflect --theta-deg 30 --radius 2 --variant printed)
check "printed a of a mirror is negative (cos theta' < 0, erratum)" \
  "echo '$out' | $py -c 'import json,sys; assert json.load(sys.stdin)[\"a\"]<0'"
out=$($pencil bounds reflect --theta-deg 30 --radius 2)
check "corrected mirror: a, d, e > 0, b = f = 0" \
  "echo '$out' | $py -c 'import json,sys; k=json.load(sys.stdin); assert k[\"a\"]>0 and k[\"d\"]>0 and k[\"e\"]>0 and k[\"b\"]==0 and k[\"f\"]==0'"
out=$($pencil bounds refract --theta-deg 20 --n1 1 --n2 1.33)
check "a plane has a = d = e = 0" \
  "echo '$out' | $py -c 'import json,sys; k=json.load(sys.stdin); assert k[\"a\"]==0 and k[\"d\"]==0 and k[\"e\"]==0 and k[\"b\"]>0'"
out=$($pencil bounds refract --theta-deg 20 --n1 1 --n2 1.33 --d3m 0.5)
check "--d3m adds sqrt(2) |h| d3m / (c' c^2) to d" \
  "echo '$out' | $py -c '
import json,sys,math
k=json.load(sys.stdin); t=math.radians(20); e=1/1.33; s,c=math.sin(t),math.cos(t); cp=math.sqrt(1-(e*s)**2); h=cp-e*c
assert abs(k[\"d\"]-math.sqrt(2)*abs(h)*0.5/(cp*c*c))<1e-15'"

out=$($pencil bounds refract --theta-deg 45 --n1 1.5 --n2 1 2>"$err"); rc=$?
check "TIR exits 1 with empty stdout" "[ $rc -eq 1 ] && [ -z '$out' ]"
check "TIR reason on stderr" "grep -q 'total internal reflection' '$err'"
out=$($pencil bounds refract --theta-deg 41.8103149 --n1 1.5 --n2 1 2>/dev/null); rc=$?
check "exit at the critical angle (grazing) exits 1 with empty stdout" "[ $rc -eq 1 ] && [ -z '$out' ]"
out=$($pencil bounds refract --theta-deg 90 --n1 1 --n2 1.5 2>"$err"); rc=$?
check "theta 90 (grazing) exits 1 with empty stdout, as pencil matrix" "[ $rc -eq 1 ] && [ -z '$out' ] && grep -q grazing '$err'"
$pencil bounds refract --theta-deg 90.5 --n1 1 --n2 1.5 >/dev/null 2>&1; rc=$?
check "theta above 90 is a usage error" "[ $rc -eq 2 ]"
$pencil bounds refract --theta-deg 10 --n1 1 --n2 1.5 --radius 0 >/dev/null 2>&1; rc=$?
check "radius 0 is a usage error" "[ $rc -eq 2 ]"
$pencil bounds refract --theta-deg x --n1 1 --n2 1.5 >/dev/null 2>"$err"; rc=$?
check "bad number names the option" "[ $rc -eq 2 ] && grep -q -- '--theta-deg' '$err'"
$pencil bounds refract --theta-deg 10 --n1 1 >/dev/null 2>&1; rc=$?
check "missing --n2 is a usage error" "[ $rc -eq 2 ]"
$pencil bounds refract --theta-deg 10 --n1 0 --n2 1.5 >/dev/null 2>&1; rc=$?
check "index 0 is a usage error" "[ $rc -eq 2 ]"
$pencil bounds refract --theta-deg 10 --n1 1 --n2 1.5 --d3m -1 >/dev/null 2>&1; rc=$?
check "negative d3m is a usage error" "[ $rc -eq 2 ]"
$pencil bounds reflect --theta-deg 10 --n2 1.5 >/dev/null 2>&1; rc=$?
check "--n2 with reflect is misplaced" "[ $rc -eq 2 ]"
$pencil bounds refract --theta-deg 10 --n1 1 --n2 1.5 --variant exact >/dev/null 2>&1; rc=$?
check "unknown variant is a usage error" "[ $rc -eq 2 ]"
$pencil bounds transfer --distance 1 >/dev/null 2>&1; rc=$?
check "transfer is not an element with coefficients here" "[ $rc -eq 2 ]"
# `pencil matrix` and `pencil bounds` refuse at the same places, for the same reason
# (px_element_cosines; docs/verification.md, "Stability").
for th in 89.9999989 89.9999999 89.99999999999 89.999999 41.810314895778596; do
  for pair in "1.4 1.4" "1 1.5" "1.5 1" "1 1.0001"; do
    set -- $pair
    for r in 1 -6000 1e-300; do
      $pencil matrix refract --theta-deg $th --n1 $1 --n2 $2 --radius $r >/dev/null 2>"$err.m"; rm_=$?
      $pencil bounds refract --theta-deg $th --n1 $1 --n2 $2 --radius $r >/dev/null 2>"$err.b"; rb=$?
      check "matrix and bounds agree at $th deg, n $1 -> $2, R $r" \
        "[ $rm_ -eq $rb ] && [ \"\$(sed 's/.*: //' $err.m)\" = \"\$(sed 's/.*: //' $err.b)\" ]"
    done
  done
done
rm -f "$err.m" "$err.b"
out=$($pencil bounds refract --theta-deg 89.9999989 --n1 1.4 --n2 1.4 --radius 1)
check "n1 = n2 near grazing: every coefficient is 0 (was a = 3.7e14)" \
  "echo '$out' | $py -c 'import json,sys; k=json.load(sys.stdin); assert all(v == 0 for v in k.values())'"

$pencil bounds --help | grep -q usage; rc=$?
check "pencil bounds --help prints usage" "[ $rc -eq 0 ]"
$pencil bounds refract --help | grep -q usage; rc=$?
check "pencil bounds refract --help prints usage" "[ $rc -eq 0 ]"
finish cli_bounds
