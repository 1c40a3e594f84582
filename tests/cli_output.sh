#!/usr/bin/env bash
# The command line and output contracts shared by every subcommand: one parser (--opt=value,
# -oFILE, "--"), options that belong to a --method only with it, output paths checked before a
# render (a directory, a device or a .png name is refused and nothing is left behind), the
# provenance in EXR headers and JSON, and paths with a quote, a backslash and a non-ASCII letter
# round-tripping through summary.json and the plots.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$(realpath "$1")
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
small="--size 12x8 --spp 1 --threads 1"

$pencil render $small -o"$tmp/a.exr" >/dev/null 2>&1; rc=$?
check "-oFILE is the output" "[ $rc -eq 0 ] && [ -s '$tmp/a.exr' ] && [ -s '$tmp/a.png' ]"
$pencil render $small --output="$tmp/b.exr" --method=pencil --rho=0.25 >/dev/null 2>&1; rc=$?
check "--opt=value for common and method options" "[ $rc -eq 0 ] && [ -s '$tmp/b.exr' ]"
cp "$src/scenes/fig8.json" "$tmp/-dash.json"
(cd "$tmp" && $pencil render $small -o c.exr -- -dash.json >/dev/null 2>&1); rc=$?
check "'--' makes a dash-led scene path positional" "[ $rc -eq 0 ] && [ -s '$tmp/c.exr' ]"

# an argument that is not UTF-8 (JSON outputs record it): refused at once, nothing written
bad=$(printf 'x\xff\xfe')
$pencil render $small -o "$tmp/$bad.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "an argument that is not UTF-8: exit 2 naming it, nothing written" \
  "[ $rc -eq 2 ] && grep -q 'argument 9 (.*) is not valid UTF-8' '$tmp/err' && grep -qF '\\xFF\\xFE' '$tmp/err' && [ ! -e \"\$tmp/\$bad.exr\" ]"
$pencil render $small -o "$tmp/é€😀.exr" >/dev/null 2>&1; rc=$?
check "UTF-8 beyond ASCII (2, 3 and 4 bytes) is accepted" "[ $rc -eq 0 ] && [ -s '$tmp/é€😀.exr' ]"

# an output that is the scene read, by whatever name: refused, the scene kept
cp "$src/scenes/fig8.json" "$tmp/same.exr"
$pencil render $small -o "$tmp/same.exr" "$tmp/same.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "render: a scene called OUT.exr is not replaced by it" \
  "[ $rc -ne 0 ] && grep -q 'is the input' '$tmp/err' && cmp -s '$src/scenes/fig8.json' '$tmp/same.exr'"
mkdir "$tmp/side" && cp "$src/scenes/fig8.json" "$tmp/side/sweep.json"
$pencil sweep "$tmp/side/sweep.json" --quick --rho 0.5 --size 12x8 --out "$tmp/side" >/dev/null 2>"$tmp/err"; rc=$?
check "sweep: its scene as --out's sweep.json is not replaced (once overwritten, exit 0)" \
  "[ $rc -ne 0 ] && grep -q 'is the input' '$tmp/err' && cmp -s '$src/scenes/fig8.json' '$tmp/side/sweep.json'"
check "... found before any work: exit 2, no sweep.csv written (once found at the JSON, after it)" \
  "[ $rc -eq 2 ] && [ ! -e '$tmp/side/sweep.csv' ]"
mkdir "$tmp/side2" && cp "$src/scenes/fig8.json" "$tmp/side2/fig9.png"
$pencil figures "$tmp/side2/fig9.png" --quick --only fig9 --size 12x8 --out "$tmp/side2" >/dev/null 2>"$tmp/err"; rc=$?
check "figures: a scene named like a plot of --out is refused before any work, nothing written" \
  "[ $rc -eq 2 ] && grep -q 'fig9.png: is the input' '$tmp/err' && [ \"\$(ls '$tmp/side2')\" = fig9.png ]"

$pencil render $small -o "$tmp/d.exr" --rho 0.5 >/dev/null 2>"$tmp/err"; rc=$?
check "a pencil option without --method pencil: exit 2 naming it" \
  "[ $rc -eq 2 ] && grep -q -- '--rho is not an option of --method exact' '$tmp/err'"
$pencil render $small -o "$tmp/d.exr" --method pencil --rho 0 >/dev/null 2>"$tmp/err"; rc=$?
check "--rho 0: exit 2 saying what is expected" "[ $rc -eq 2 ] && grep -q -- '--rho: expected a number > 0' '$tmp/err'"
$pencil render $small -o "$tmp/d.exr" --method pencil --bounds nope >/dev/null 2>"$tmp/err"; rc=$?
check "--bounds nope lists the choices" "[ $rc -eq 2 ] && grep -q 'corrected, printed or probe' '$tmp/err'"
$pencil render $small -o "$tmp/d.exr" --method beamz >/dev/null 2>"$tmp/err"; rc=$?
check "unknown --method lists the table" "[ $rc -eq 2 ] && grep -q 'exact, pencil or beam' '$tmp/err'"
$pencil render $small -o "$tmp/d.exr" --method beam >/dev/null 2>"$tmp/err"; rc=$?
check "beams refuse the ball: exit 2 naming it, no file" "[ $rc -eq 2 ] && grep -q \"object 'glass ball' is a sphere\" '$tmp/err' && [ ! -e '$tmp/d.exr' ]"
$pencil render $small -o "$tmp/d.exr" --measure >/dev/null 2>"$tmp/err"; rc=$?
check "--measure on the exact renderer is refused" "[ $rc -eq 2 ] && grep -q 'nothing to measure' '$tmp/err'"
$pencil render $small -o "$tmp/d.exr" --no-aux=1 >/dev/null 2>"$tmp/err"; rc=$?
check "a value given to a flag is refused" "[ $rc -eq 2 ] && grep -q 'takes no value' '$tmp/err'"
$pencil render $small -o "$tmp/d.exr" --thread 2 >/dev/null 2>"$tmp/err"; rc=$?
check "no abbreviations: --thread is unknown" "[ $rc -eq 2 ] && grep -q \"unknown option '--thread'\" '$tmp/err'"
$pencil render --method pencil --help >"$tmp/help"; rc=$?
check "--method pencil --help lists the pencil options" "[ $rc -eq 0 ] && grep -q -- '--brightness-tol' '$tmp/help'"

$pencil render $small -o "$tmp/x.png" >/dev/null 2>"$tmp/err"; rc=$?
check "-o x.png is refused, saying why" "[ $rc -eq 2 ] && grep -q 'must be named NAME.exr' '$tmp/err' && [ ! -e '$tmp/x.png' ]"
mkdir "$tmp/dir.exr"
$pencil render $small -o "$tmp/dir.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "-o naming a directory is refused before rendering" \
  "[ $rc -eq 2 ] && grep -q 'not a regular file' '$tmp/err' && [ -d '$tmp/dir.exr' ]"
mkfifo "$tmp/fifo.exr"
$pencil render $small -o "$tmp/fifo.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "-o naming a FIFO is refused and the FIFO stays" "[ $rc -eq 2 ] && [ -p '$tmp/fifo.exr' ]"
# an output that cannot be written, found before any work, is an input error in every command:
# exit 2 (render, export and bench pencil once said 1, verify, bench star and post star 2)
mkdir "$tmp/adir.exr" "$tmp/adir.json" "$tmp/adir.pov"
echo x >"$tmp/afile"
for c in "render $small -o $tmp/adir.exr" "export pov -o $tmp/adir.pov" \
  "bench pencil --size 8x8 --json $tmp/adir.json" "bench render --json $tmp/adir.json" \
  "verify matrices --quick --json $tmp/adir.json" "bench star --json $tmp/adir.json" \
  "post star $tmp/a.exr -o $tmp/adir.exr" "sweep --quick --out $tmp/afile" \
  "illuminance $src/scenes/fig8.json --receiver checkerboard -o $tmp/adir.exr"; do
  $pencil $c >/dev/null 2>"$tmp/err"; rc=$?
  check "$(echo $c | cut -d' ' -f1-2): an output that cannot be written exits 2, before any work" "[ $rc -eq 2 ] && [ -s '$tmp/err' ]"
done
rmdir "$tmp/adir.exr" "$tmp/adir.json" "$tmp/adir.pov"
rm "$tmp/afile"
check "no temporary files are left behind" "[ -z \"\$(ls -A '$tmp' | grep '^\\.')\" ]"

$pencil render --size 64x64 --threads 1 --max-memory 100K -o "$tmp/mem.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "a render above --max-memory is refused before it starts, saying how much it needs" \
  "[ $rc -eq 2 ] && grep -q 'on 1 thread allocates 207.8 KB' '$tmp/err' && [ ! -e '$tmp/mem.exr' ]"
# the pencil's working buffers count too, per thread, and stay bounded at depth 32 (a 2x2 image
# of a glass ball between mirrors: before the bound they were 2.5 GB a thread)
cat > "$tmp/deep.json" <<'EOF'
{"camera": {"eye": [0, 0, -3.5], "look_at": [0, 0, 0], "fov": 60, "width": 2, "height": 2},
 "settings": {"max_depth": 32},
 "materials": {"mirror": {"kd": 0.2, "kr": 0.7},
               "glass": {"ka": 0, "kd": 0, "kr": 0.15, "kt": 0.75, "ior": 1.5}},
 "lights": [{"type": "point", "position": [0.5, 3, -1]}],
 "objects": [{"type": "plane", "point": [0, -4, 0], "normal": [0, 1, 0], "material": "mirror"},
             {"type": "plane", "point": [0, 4, 0], "normal": [0, -1, 0], "material": "mirror"},
             {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"}]}
EOF
$pencil render "$tmp/deep.json" --method pencil --threads 3 --max-memory 100M -o "$tmp/deep.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "the pencil's buffers are counted per thread and bounded at depth 32" \
  "[ $rc -eq 2 ] && grep -q 'on 3 threads allocates 1[0-9][0-9]\\.[0-9] MB' '$tmp/err'"
$pencil render "$tmp/deep.json" --method pencil --threads 1 --max-memory 100M -o "$tmp/deep.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "... and one thread's fit in 100 MB" "[ $rc -eq 0 ] && [ -s '$tmp/deep.exr' ]"
# the caustic maps count too: grid-pencils hold a band of 129 rows of a grid face's rays with
# their trees' arrivals (about 3.6 KB a ray), at 2049 rays a side 924 MB; refused before any
# tracing, naming the options
$pencil render "$src/scenes/fig8-caustics.json" --method pencil --caustic-rays 2049 --size 8x8 \
  --spp 1 --max-memory 100M -o "$tmp/maps.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "caustic maps above --max-memory: refused, naming --caustic-rays" \
  "[ $rc -eq 2 ] && grep -q 'caustic maps of .*fig8-caustics.json need 9[0-9][0-9]\.[0-9] MB' '$tmp/err' && grep -q -- '--caustic-rays' '$tmp/err' && [ ! -e '$tmp/maps.exr' ]"
$pencil render "$src/scenes/fig8-caustics.json" --method pencil --size 8x8 --spp 1 \
  --max-memory 200M -o "$tmp/maps.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "... the default grid-pencil maps fit in 200 MB" "[ $rc -eq 0 ] && [ -s '$tmp/maps.exr' ]"
$pencil render --size 64x64 --max-memory 8Q -o "$tmp/mem.exr" >/dev/null 2>"$tmp/err"; rc=$?
check "--max-memory 8Q is refused" "[ $rc -eq 2 ] && grep -q 'such as 512M' '$tmp/err'"

# an old output survives a failed write: the preview's name is taken by a directory
echo old >"$tmp/keep.exr"
mkdir "$tmp/keep.png"
$pencil render $small -o "$tmp/keep.exr" >/dev/null 2>&1; rc=$?
check "a preview that cannot be written leaves the old EXR as it was (exit 2: found before rendering)" "[ $rc -eq 2 ] && [ \"\$(cat '$tmp/keep.exr')\" = old ]"

check "EXR header carries version, commit, command line and date" \
  "grep -aq 'pencil:version' '$tmp/a.exr' && grep -aq 'pencil:commit' '$tmp/a.exr' && grep -aq 'pencil:command_line' '$tmp/a.exr' && grep -aq 'pencil:date' '$tmp/a.exr' && grep -aq -- '-o$tmp/a.exr' '$tmp/a.exr'"

check "the PNG preview carries them too, as text chunks (once it had none)" \
  "grep -aq 'pencil:version' '$tmp/a.png' && grep -aq 'pencil:commit' '$tmp/a.png' && grep -aq 'pencil:date' '$tmp/a.png' && grep -aq 'Software' '$tmp/a.png' && grep -aq 'pencil:command_line' '$tmp/a.png' && grep -aq -- '-o$tmp/a.exr' '$tmp/a.png'"

# a quote, a backslash and a non-ASCII letter in the scene path and in --out
odd="$tmp/o'q\"b\\s é"
mkdir -p "$odd"
cp "$src/scenes/fig8.json" "$odd/scène'.json"
$pencil sweep "$odd/scène'.json" --quick --rho 0.5 --size 16x16 --out "$odd/out" >/dev/null 2>"$tmp/err"; rc=$?
check "sweep with an odd scene path and --out" "[ $rc -eq 0 ] && [ -s \"\$odd/out/sweep.json\" ]"
check "sweep.json round-trips the scene path and records the command line" \
  "$py -c 'import json,sys; d=json.load(open(sys.argv[1])); sys.exit(not (d[\"scene\"] == sys.argv[2] and d[\"provenance\"][\"command_line\"].count(\"sweep\") == 1 and len(d[\"sweep\"]) == 3))' \"\$odd/out/sweep.json\" \"\$odd/scène'.json\""
check "the plot was made in the odd directory" "[ -s \"\$odd/out/sweep.png\" ]"
check "the plot carries its data's provenance in text chunks (once it had none)" "$py - \"\$odd/out/sweep.png\" \"\$($pencil --version)\" <<'PY'
import struct, sys, zlib
d, i, t = open(sys.argv[1], 'rb').read(), 8, {}
while i < len(d):
    n, kind = struct.unpack('>I', d[i:i + 4])[0], d[i + 4:i + 8]
    body = d[i + 8:i + 8 + n]
    if kind == b'tEXt':
        k, v = body.split(b'\\0', 1)
        t[k.decode('latin-1')] = v.decode('latin-1')
    elif kind == b'iTXt':
        k, rest = body.split(b'\\0', 1)
        comp, rest = rest[0], rest[2:]
        v = rest.split(b'\\0', 2)[2]
        t[k.decode('latin-1')] = (zlib.decompress(v) if comp else v).decode('utf-8')
    i += 12 + n
assert 'pencil_plots.py' in t['Software'] and t['Source'] == 'sweep.csv', t
assert sys.argv[2] == 'pencil %s (%s)' % (t['pencil:version'], t['pencil:commit']), (sys.argv[2], t)
assert ' sweep ' in t['pencil:command_line'] and 'scène' in t['pencil:command_line'], t
assert t['pencil:date'].startswith('20') and t['pencil:commit'], t
PY"
check "sweep.csv starts with the provenance as '#' lines (once it had none), the header after them" \
  "head -4 \"\$odd/out/sweep.csv\" | grep -q '^# version: ' && head -4 \"\$odd/out/sweep.csv\" | grep -q '^# commit: ' && head -4 \"\$odd/out/sweep.csv\" | grep -q '^# date: 20' && sed -n 4p \"\$odd/out/sweep.csv\" | grep -q '^# command_line: .* sweep .*sc.ne' && sed -n 5p \"\$odd/out/sweep.csv\" | grep -q '^rho,variant,'"
check "no file escaped the output directory" "[ \"\$(ls \"\$odd\" | wc -l)\" -eq 2 ]"

finish cli_output
