#!/usr/bin/env bash
# The `pencil matrix` contract: JSON {"T": 4x4} on stdout; no matrix -> exit 1, reason on
# stderr, nothing on stdout; bad parameters -> exit 2; --help everywhere.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$1

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
# indices: normal doubles from RT_IOR_MIN to RT_IOR_MAX (a scene's ior), else a usage error naming
# the option (1e-323 is subnormal: once taken as eta 2/3 with an error bound of 1e-14)
for bad in "--n1 1e-323 --n2 1.3e-323" "--n1 1 --n2 1e-4" "--n1 1e300 --n2 1.5" "--n1 1 --n2 101"; do
  opt=$(echo "$bad" | $py -c 'import sys; a=sys.stdin.read().split(); print(a[0] if not 1e-3 <= float(a[1]) <= 100 else a[2])')
  out=$($pencil matrix refract --theta-deg 10 $bad 2>/tmp/pencil_err.$$); rc=$?
  check "index out of range ($bad): exit 2 naming $opt, nothing on stdout" \
    "[ $rc -eq 2 ] && [ -z '$out' ] && grep -q -- '$opt: expected a refractive index from 0.001 to 100' /tmp/pencil_err.$$"
done
$pencil bounds reflect --theta-deg 10 --n1 0 >/dev/null 2>/tmp/pencil_err.$$; rc=$?
check "bounds: the same range (--n1 0)" "[ $rc -eq 2 ] && grep -q -- 'pencil bounds reflect: --n1: expected a refractive index' /tmp/pencil_err.$$"
out=$($pencil matrix refract --theta-deg 10 --n1 0.001 --n2 100 2>/dev/null); rc=$?
check "the range's ends are indices" "[ $rc -eq 0 ] && echo '$out' | grep -q '\"T\"'"
$pencil matrix refract --theta-deg 10 --n1 1 >/dev/null 2>&1; rc=$?
check "missing --n2 is a usage error" "[ $rc -eq 2 ]"
$pencil matrix transfer --theta-deg 10 >/dev/null 2>&1; rc=$?
check "misplaced option is a usage error" "[ $rc -eq 2 ]"
out=$($pencil matrix refract --theta-deg 30 --n1 1 --n2 1.5 --radius 2 --variant printed)
check "printed variant has B = identity" \
  "echo '$out' | $py -c 'import json,sys; t=json.load(sys.stdin)[\"T\"]; assert t[0][2]==1 and t[1][3]==1'"
# Numerics that refuse instead of lying (docs/verification.md, "Stability"): a matrix printed is
# within 1e-8 of the exact one (mpmath, 60 digits, from the decimal angle), else exit 1.
exact_check() { # theta_deg n1 n2 R: exit 1, or every scaled entry within 1e-8 of mpmath's
  local out rc
  out=$($pencil matrix refract --theta-deg "$1" --n1 "$2" --n2 "$3" --radius "$4" 2>/dev/null); rc=$?
  [ $rc -eq 1 ] && [ -z "$out" ] && return 0
  [ $rc -eq 0 ] || return 1
  echo "$out" | $py -c "
import json, sys, mpmath as m
m.mp.dps = 60
t = json.load(sys.stdin)['T']; th = m.radians(m.mpf(float('$1'))); n1, n2, R = m.mpf('$2'), m.mpf('$3'), m.mpf('$4')
c = m.cos(th); eta = n1 / n2; cp = m.sqrt(1 - eta**2 * m.sin(th)**2); h = cp - eta * c
ex = [[cp / c, 0, 0, 0], [0, 1, 0, 0], [-h / (R * c * cp), 0, eta * c / cp, 0], [0, -h / R, 0, eta]]
sc = lambda i, j: abs(R) if (i >= 2 and j < 2) else (1 / abs(R) if (i < 2 and j >= 2) else 1)
big = max(abs(ex[i][j] * sc(i, j)) for i in range(4) for j in range(4))
err = max(abs((m.mpf(t[i][j]) - ex[i][j]) * sc(i, j)) for i in range(4) for j in range(4)) / big
sys.exit(0 if err <= m.mpf('1e-8') else print('error', m.nstr(err, 3)) or 1)"
}
for d in 0.01 0.0001 0.000001; do
  th=$($py -c "print(repr(90 - $d))")
  check "n1 = n2, $d deg from grazing: exact (identity) or refused" "exact_check $th 1.4 1.4 -6000"
done
check "theta 89.999999, n1 = n2 = 1.4, R -6000: T00 = 1, not 0.854" \
  "exact_check 89.999999 1.4 1.4 -6000"
for d in 1e-4 1e-8 1e-12; do
  th=$($py -c "import math; print(repr(math.degrees(math.asin(1/1.5)) - $d))")
  check "$d deg below the critical angle: within 1e-8 or refused" "exact_check $th 1.5 1 -2"
done
# --error-bound: the bound is printed, <= 1e-8, and the true error (mpmath) is within it
for args in "30 1 1.5 2" "$($py -c "import math; print(repr(math.degrees(math.asin(1/1.5)) - 1e-5))") 1.5 1 -2" \
            "89.9999 1 1.0001 3"; do
  set -- $args
  out=$($pencil matrix refract --theta-deg $1 --n1 $2 --n2 $3 --radius $4 --error-bound)
  check "--error-bound at $1 deg, n $2 -> $3: true error <= bound <= 1e-8" "echo '$out' | $py -c \"
import json, sys, mpmath as m
m.mp.dps = 60
d = json.load(sys.stdin); t, b = d['T'], d['error_bound']; th = m.radians(m.mpf(float('$1'))); n1, n2, R = m.mpf('$2'), m.mpf('$3'), m.mpf('$4')
c = m.cos(th); eta = n1 / n2; cp = m.sqrt(1 - eta**2 * m.sin(th)**2); h = cp - eta * c
ex = [[cp / c, 0, 0, 0], [0, 1, 0, 0], [-h / (R * c * cp), 0, eta * c / cp, 0], [0, -h / R, 0, eta]]
sc = lambda i, j: abs(R) if (i >= 2 and j < 2) else (1 / abs(R) if (i < 2 and j >= 2) else 1)
big = max(abs(ex[i][j] * sc(i, j)) for i in range(4) for j in range(4))
err = max(abs((m.mpf(t[i][j]) - ex[i][j]) * sc(i, j)) for i in range(4) for j in range(4)) / big
assert 0 < b <= 1e-8 and err <= b, (err, b)\""
done
th=$($py -c "import math; print(repr(math.degrees(math.asin(1/1.5)) - 1e-12))")
$pencil matrix refract --theta-deg $th --n1 1.5 --n2 1 >/dev/null 2>/tmp/pencil_err.$$; rc=$?
check "1e-12 deg below the critical angle is refused as ill-conditioned" \
  "[ $rc -eq 1 ] && grep -q 'ill-conditioned' /tmp/pencil_err.$$"
out=$($pencil matrix refract --theta-deg 30 --n1 1 --n2 1.5 --radius 1e-300 2>/tmp/pencil_err.$$); rc=$?
check "radius 1e-300 is refused as overflow (as by pencil bounds)" \
  "[ $rc -eq 1 ] && [ -z '$out' ] && grep -q 'overflow' /tmp/pencil_err.$$"
# --dispersion (issue 22): the 5 x 5 of the 1989 Eq. (13); its 4 x 4 block is the plain matrix,
# its column (0, 0, (-dn2 sin theta') / (n2 cos theta'), 0, 1) for air into glass (docs/spectral.md:
# 1.289e-5 at 40 degrees, n2 = 1.5168, D = -4.18e-5); a reflection's and a transfer's is zero
out5=$($pencil matrix refract --theta-deg 40 --n1 1 --n2 1.5168 --dispersion -4.18e-5)
out4=$($pencil matrix refract --theta-deg 40 --n1 1 --n2 1.5168)
check "refract --dispersion: 5 x 5, block = the 4 x 4, the derived column" \
  "$py -c 'import json,sys,math; t=json.loads(sys.argv[1])[\"T\"]; m=json.loads(sys.argv[2])[\"T\"]; assert len(t)==5 and all(len(r)==5 for r in t); assert all(t[i][j]==m[i][j] for i in range(4) for j in range(4)); tp=math.asin(math.sin(math.radians(40))/1.5168); want=4.18e-5*math.sin(tp)/(1.5168*math.cos(tp)); assert abs(t[2][4]-want)<1e-15 and abs(want-1.289e-5)<1e-8 and t[0][4]==t[1][4]==t[3][4]==0 and t[4]==[0,0,0,0,1]' '$out5' '$out4'"
out=$($pencil matrix reflect --theta-deg 30 --dispersion 1e-4)
check "reflect --dispersion: a zero column" \
  "$py -c 'import json,sys; t=json.loads(sys.argv[1])[\"T\"]; assert [r[4] for r in t]==[0,0,0,0,1]' '$out'"
out=$($pencil matrix transfer --distance 2 --dispersion 1e-4)
check "transfer --dispersion: a zero column" "[ '$out' = '{\"T\": [[1, 0, 2, 0, 0], [0, 1, 0, 2, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1]]}' ]"
$pencil matrix refract --theta-deg 40 --n1 1 --n2 1.5 --dispersion x >/dev/null 2>/tmp/pencil_err.$$; rc=$?
check "--dispersion x: exit 2 naming it" "[ $rc -eq 2 ] && grep -q -- '--dispersion' /tmp/pencil_err.$$"
$pencil matrix refract --theta-deg 60 --n1 1.5 --n2 1 --dispersion 1e-5 >/dev/null 2>&1; rc=$?
check "--dispersion at total internal reflection: exit 1" "[ $rc -eq 1 ]"


for c in "" "matrix" "verify"; do
  $pencil $c --help >/tmp/pencil_help.$$ 2>&1; rc=$?
  check "pencil $c --help exits 0 and prints usage" "[ $rc -eq 0 ] && grep -q usage /tmp/pencil_help.$$"
done
rm -f /tmp/pencil_err.$$ /tmp/pencil_help.$$
finish cli_matrix
