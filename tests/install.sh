#!/usr/bin/env bash
# The installed library's contract: `cmake --install` of the build tree into a temporary prefix
# gives the pencil command, libparaxial (static and shared, needing nothing beyond libm), all of
# its public headers, a CMake package and a pkg-config file, and the docs; examples/ builds
# against that prefix with CMake and with pkg-config, by gcc and by clang, and runs; a C++
# compiler accepts paraxial/paraxial.h; libparaxial configures and builds on its own with clang.
# Usage: tests/install.sh BUILD_DIR. Exit 77 (skipped) when gcc or clang is missing.
set -u
build=$(realpath "$1")
src=$(cd "$(dirname "$0")/.." && pwd)
fail=0
check() { if ! eval "$2"; then echo "FAIL: $1"; fail=1; else echo "ok: $1"; fi; }
for cc in gcc clang; do
  command -v $cc >/dev/null || { echo "SKIP: $cc not installed (scripts/deps)"; exit 77; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
log=$tmp/log
version=$(head -n1 "$src/VERSION")
major=${version%%.*}

# ---- what is installed -------------------------------------------------------------------------
check "cmake --install into a staged prefix" "cmake --install '$build' --prefix '$prefix' >'$log' 2>&1"
pc=$(find "$prefix" -name paraxial.pc | head -n1)
libdir=$(dirname "$(dirname "${pc:-$prefix/lib/pkgconfig/x}")")
check "bin/pencil runs and says its version" "'$prefix/bin/pencil' --version | grep -q 'pencil $version'"
check "libparaxial.a and libparaxial.so.$major installed" \
  "[ -f '$libdir/libparaxial.a' ] && [ -f '$libdir/libparaxial.so.$major' ] && [ -L '$libdir/libparaxial.so' ]"
others=$(find "$prefix" -name 'lib*.a' -o -name 'lib*.so*' | grep -v '/libparaxial\.' || true)
check "no other library installed (the rest are internal)" "[ -z '$others' ]"
want=$( (cd "$src/libparaxial/include" && ls paraxial/*.h; echo paraxial/version.h) | sort)
have=$(cd "$prefix/include" 2>/dev/null && find paraxial -name '*.h' | sort)
check "every public header installed, and only those" "[ '$want' = '$have' ]"
check "version.h says $version" \
  "grep -q '#define PX_VERSION_STRING \"$version\"' '$prefix/include/paraxial/version.h'"
needed=$(readelf -d "$libdir/libparaxial.so.$major" | sed -n 's/.*NEEDED.*\[\(.*\)\]/\1/p' | sort | tr '\n' ' ')
check "libparaxial.so needs only libm and libc (got: $needed)" "[ '$needed' = 'libc.so.6 libm.so.6 ' ]"
check "no quad precision in libparaxial" "! nm -D '$libdir/libparaxial.so.$major' | grep -qi 'quadmath\|float128\|__[a-z]*tf[0-9]'"
check "CMake package files" "[ -f '$libdir/cmake/paraxial/paraxialConfig.cmake' ] && [ -f '$libdir/cmake/paraxial/paraxialConfigVersion.cmake' ]"
doc=$prefix/share/doc/pencil
check "docs in share/doc/pencil" "[ -f '$doc/README.md' ] && [ -f '$doc/LICENSE' ] && [ -f '$doc/docs/DEVELOPING.md' ] && [ -f '$doc/examples/ball_lens.c' ]"
check "CITATION.cff has the version of VERSION" "grep -q '^version: $version\$' '$doc/CITATION.cff'"

# ---- C++ can include the umbrella header ---------------------------------------------------------
printf '#include <paraxial/paraxial.h>\nint main() { return px_v3_norm(px_v3(0, 0, 1)) == 1.0 ? 0 : 1; }\n' >"$tmp/cxx.cpp"
for cxx in g++ clang++; do
  command -v $cxx >/dev/null || { echo "skip: $cxx not installed"; continue; }
  check "$cxx -std=c++11 -pedantic-errors accepts paraxial/paraxial.h" \
    "$cxx -std=c++11 -pedantic-errors -Wall -Wextra -Werror -fsyntax-only -I'$prefix/include' '$tmp/cxx.cpp'"
done

# ---- examples/ against the prefix -------------------------------------------------------------
# run_example NAME EXE: runs, prints the version line, and loads libparaxial from the prefix
run_example() {
  check "$1 runs and its checks pass" "LD_LIBRARY_PATH='$libdir' '$2' >'$tmp/out' 2>&1"
  check "$1 prints library and header versions" "grep -q '^libparaxial $version (headers $version)' '$tmp/out'"
}
for cc in gcc clang; do
  b=$tmp/example-$cc
  check "CMake configures examples/ with $cc, finding paraxial in the prefix" \
    "cmake -S '$src/examples' -B '$b' -DCMAKE_C_COMPILER=$cc -DCMAKE_C_FLAGS='-Wall -Wextra -Werror' -DCMAKE_PREFIX_PATH='$prefix' >'$log' 2>&1 && grep -q 'paraxial $version from $libdir/cmake/paraxial' '$log'"
  check "CMake builds examples/ with $cc" "cmake --build '$b' >'$log' 2>&1"
  run_example "ball_lens (CMake, $cc, shared)" "$b/ball_lens"
  check "ball_lens (CMake, $cc) loads the installed libparaxial.so.$major" \
    "ldd '$b/ball_lens' | grep -q 'libparaxial.so.$major => $libdir/libparaxial.so.$major'"
  run_example "ball_lens_static (CMake, $cc, static)" "$b/ball_lens_static"
  check "ball_lens_static (CMake, $cc) does not need libparaxial.so" "! ldd '$b/ball_lens_static' | grep -q libparaxial"
  exe=$tmp/ball_lens-pc-$cc
  check "pkg-config build with $cc" \
    "PKG_CONFIG_PATH='$libdir/pkgconfig' $cc -std=c11 -Wall -Wextra -Werror '$src/examples/ball_lens.c' -o '$exe' \$(PKG_CONFIG_PATH='$libdir/pkgconfig' pkg-config --cflags --libs paraxial) 2>'$log'"
  run_example "ball_lens (pkg-config, $cc, shared)" "$exe"
  check "ball_lens (pkg-config, $cc) loads the installed libparaxial.so.$major" \
    "LD_LIBRARY_PATH='$libdir' ldd '$exe' | grep -q 'libparaxial.so.$major => $libdir/libparaxial.so.$major'"
done

# ---- libparaxial on its own, with clang ---------------------------------------------------------
px=$tmp/px-clang
check "libparaxial configures standalone with clang (C compiler and libm only)" \
  "cmake -S '$src/libparaxial' -B '$px' -DCMAKE_C_COMPILER=clang -DPARAXIAL_WERROR=ON >'$log' 2>&1"
check "libparaxial builds standalone with clang, warnings as errors" "cmake --build '$px' -j2 >'$log' 2>&1 || { cat '$log'; false; }"
check "standalone build installs" "cmake --install '$px' --prefix '$tmp/px-prefix' >'$log' 2>&1 && [ -f '$tmp/px-prefix/include/paraxial/version.h' ]"

exit $fail
