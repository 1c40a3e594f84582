#!/usr/bin/env bash
# One parsing rule for every command (docs/journal/2026-12-06-cli-mends.md): numbers are written
# one way (an optional '-', digits, a point, an exponent: no spaces, no '+'), lists are
# comma-separated with no empty item (no leading, trailing or double comma), an option given twice
# is refused naming it (but --receiver, repeated by design), and an option that has no effect
# with the others given is refused naming both. Every case fails before any work: exit 2.
source "$(dirname "${BASH_SOURCE[0]}")/cli_lib.sh"
pencil=$(realpath "$1")
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
o="$tmp/o.exr"
fig8=$src/scenes/fig8.json
$pencil render --size 8x8 --spp 1 -o "$tmp/in.exr" >/dev/null 2>&1 # an input for post star

# refused: exit 2, stderr names the option ($1), nothing written
refused() { # LABEL OPTION ARGS...
  local label=$1 opt=$2
  shift 2
  "$pencil" "$@" >/dev/null 2>"$tmp/err"
  local rc=$?
  check "$label" "[ $rc -eq 2 ] && grep -q -- '$opt' '$tmp/err' && [ ! -e '$o' ]"
  rm -f "$o" "${o%.exr}.png" # each case on its own
}

# --- numbers: " 4" and "+4" are refused by every option, as " 5" always was by --theta-deg
for v in " 4" "+4" "4 " "0x4"; do
  refused "render --spp '$v'" --spp render --spp "$v" -o "$o"
  refused "render --threads '$v'" --threads render --threads "$v" -o "$o"
  refused "render --size '${v}x4'" --size render --size "${v}x4" -o "$o"
  refused "render --method pencil --rho '$v'" --rho render --method pencil --rho "$v" -o "$o"
  refused "matrix refract --theta-deg '$v'" --theta-deg matrix refract --theta-deg "$v" --n1 1 --n2 1.5
  refused "verify stability --samples '$v'" --samples verify stability --samples "$v"
  refused "bench star --runs '$v'" --runs bench star --runs "$v"
  refused "bench render --spp '$v'" --spp bench render --spp "$v"
  refused "export pov --spp '$v'" --spp export pov --spp "$v" -o "$tmp/o.pov"
  refused "post star --angle '$v'" --angle post star "$tmp/in.exr" -o "$o" --angle "$v"
  refused "sweep --rho '$v'" --rho sweep --rho "$v" --out "$tmp/s"
  refused "figures --shard '${v}/8'" --shard figures --shard "${v}/8" --out "$tmp/f"
  refused "render --max-memory '${v}G'" --max-memory render --max-memory "${v}G" -o "$o"
done
refused "illuminance --extent with a '+'" --extent illuminance "$fig8" --receiver checkerboard -o "$o" --extent 0,+1,0,1
refused "post star --sigma with a space" --sigma post star "$tmp/in.exr" -o "$o" --sigma "0.1, 0.2"
$pencil matrix refract --theta-deg 30 --n1 1 --n2 1.5 >/dev/null 2>&1; rc=$?
check "numbers as written stay accepted (30, -2e-3, .5)" \
  "[ $rc -eq 0 ] && $pencil matrix transfer --distance -2e-3 >/dev/null && $pencil matrix transfer --distance .5 >/dev/null"

# --- lists: no empty item, in every list option
for l in "0.5," ",0.5" "0.5,,1"; do
  refused "sweep --rho '$l'" "--rho: expected a comma-separated list" sweep --rho "$l" --out "$tmp/s"
done
refused "bench pencil --spp '1,'" "--spp: expected a comma-separated list" bench pencil --spp 1, --json "$tmp/p.json"
refused "figures --fig9-spp '1,4,'" "--fig9-spp: expected a comma-separated list" figures --fig9-spp 1,4, --out "$tmp/f"
refused "figures --only 'fig9,'" "--only: expected a comma-separated list" figures --only fig9, --out "$tmp/f"
refused "bench star --sizes '512,' (once accepted)" "--sizes: expected a comma-separated list" bench star --sizes 512,
refused "bench caustics --case 'fig8,' (once accepted)" "--case: expected a comma-separated list" bench caustics --case fig8, --out "$tmp/c"
refused "bench beam --case 'prism,' (once accepted)" "--case: expected a comma-separated list" bench beam --case prism, --out "$tmp/b"
refused "illuminance --extent '0,1,0,1,'" "--extent" illuminance "$fig8" --receiver checkerboard -o "$o" --extent 0,1,0,1,
refused "post star --sigma '0.1,0.2,'" "--sigma" post star "$tmp/in.exr" -o "$o" --sigma 0.1,0.2,
check "no sweep, figures or bench output directory was made" "[ ! -e '$tmp/s' ] && [ ! -e '$tmp/f' ] && [ ! -e '$tmp/c' ] && [ ! -e '$tmp/b' ]"

# --- an option given twice: refused naming it, whatever the spelling (the last won silently)
refused "render --spp twice" "--spp is given twice" render --spp 4 --spp=9 -o "$o"
refused "render -o and --output" "--output (-o) is given twice" render -o "$o" --output "$tmp/p.exr"
refused "render: a method option twice" "--rho is given twice" render --method pencil --rho 1 --rho 2 -o "$o"
refused "render --method twice" "--method is given twice" render --method pencil --method exact -o "$o"
refused "verify matrices --quick twice" "--quick is given twice" verify matrices --quick --quick
refused "sweep --rho twice" "--rho is given twice" sweep --rho 0.5 --rho 1 --out "$tmp/s"
refused "post star --angle twice" "--angle is given twice" post star "$tmp/in.exr" -o "$o" --angle 1 --angle 2
$pencil illuminance "$fig8" --receiver checkerboard --receiver "glass ball" -o "$o" >/dev/null 2>"$tmp/err"
check "illuminance --receiver may repeat (objects joined): not refused as given twice" "! grep -q 'given twice' '$tmp/err'"

# --- an option with no effect beside the others: refused naming both
refused "render --spectral-tol without --wavelengths pencil" \
  "spectral-tol has no effect with --wavelengths fan (only with --wavelengths pencil)" render --spectral-tol 0.2 -o "$o"
refused "render --wavelength-axis with --wavelengths off" \
  "wavelength-axis has no effect with --wavelengths off" render --method pencil --wavelengths off --wavelength-axis lambda -o "$o"
refused "render --no-spectral-lattice with --no-interp" \
  "no-spectral-lattice has no effect with --no-interp" render --method pencil --no-interp --no-spectral-lattice -o "$o"
refused "render --bins with --wavelengths pencil" "bins has no effect with --wavelengths pencil" \
  render --wavelengths pencil --bins 9 -o "$o"
refused "render --weight-floor without --tolerance image" "weight-floor has no effect with --tolerance geometric" \
  render --method pencil --weight-floor 0.1 -o "$o"
refused "render --brightness-tol with --no-interp" "brightness-tol has no effect with --no-interp" \
  render --method pencil --no-interp --brightness-tol 0.1 -o "$o"
refused "render --caustic-rays with --caustic-method polygons" \
  "caustic-rays has no effect with --caustic-method polygons" render --caustic-method polygons --caustic-rays 9 -o "$o"
refused "verify stability --quick with --samples" "--quick has no effect with --samples" verify stability --quick --samples 100
refused "illuminance --linear-tol with --method photons" "linear-tol has no effect with --method photons" \
  illuminance "$fig8" --receiver checkerboard -o "$o" --method photons --linear-tol 0.1
refused "bench illuminance --fig11 with --quick" "fig11 has no effect with --quick" \
  bench illuminance --quick --fig11 "$src/scenes/fig11.json" --json "$tmp/i.json"
refused "figures --no-sweep with --only" "no-sweep has no effect with --only" figures --only fig9 --no-sweep --out "$tmp/f"
refused "figures --fig9-spp with --only sweep" "fig9-spp has no effect with --only" figures --only sweep --fig9-spp 1,4 --out "$tmp/f"
refused "figures --peer with --only fig8" "peer has no effect with --only" figures --only fig8 --peer povray --out "$tmp/f"
$pencil render --wavelengths pencil --spectral-tol 0.2 --size 8x8 --spp 1 -o "$tmp/ok.exr" >/dev/null 2>&1; rc=$?
check "... and accepted where it acts (--wavelengths pencil --spectral-tol)" "[ $rc -eq 0 ] && [ -s '$tmp/ok.exr' ]"

finish cli_parsing
