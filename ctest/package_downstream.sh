#!/usr/bin/env bash
# ctest package.downstream: install aries into a fresh prefix, build examples/downstream against it (nothing of the
# source or build tree on its include path), run it, and compare its numbers with aries-matpoint -json at the same
# material and F. Then a project asking for an incompatible version (9.0) must fail to configure.
# usage: package_downstream.sh BUILD_DIR SOURCE_DIR MATPOINT
set -euo pipefail
BUILD="$1" SRC="$2" MATPOINT="$3"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
cmake --install "$BUILD" --prefix "$WORK/prefix" >/dev/null
for f in include/aries/kernels/alpha.hpp include/aries/energies/energy.hpp include/aries/energies/catalog.hpp \
         lib/cmake/aries/ariesConfig.cmake lib/cmake/aries/ariesConfigVersion.cmake; do
  [ -f "$WORK/prefix/$f" ] || { echo "FAIL: the install lacks $f"; exit 1; }
done
if grep -rl "petsc" "$WORK/prefix/include/aries" >/dev/null; then
  echo "FAIL: an installed header mentions PETSc: $(grep -rl petsc "$WORK/prefix/include/aries" | head -3)"; exit 1
fi
# The downstream project is compiled by the compiler aries was built with (its static library's toolchain): the
# system's default c++ (GCC) took 67 s for this one file against clang's 23 s on the 2-core box.
CXX_OF_BUILD="$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$BUILD/CMakeCache.txt")"
cmake -S "$SRC/examples/downstream" -B "$WORK/downstream" -DCMAKE_PREFIX_PATH="$WORK/prefix" \
      ${CXX_OF_BUILD:+-DCMAKE_CXX_COMPILER="$CXX_OF_BUILD"} \
      -DCMAKE_BUILD_TYPE=Release >"$WORK/configure.log" 2>&1 || { cat "$WORK/configure.log"; exit 1; }
if grep -q -- "$SRC/lib" "$WORK/downstream/CMakeFiles/fiber_point.dir/flags.make"; then
  echo "FAIL: the downstream build sees the source tree's lib/"; exit 1
fi
cmake --build "$WORK/downstream" >"$WORK/build.log" 2>&1 || { cat "$WORK/build.log"; exit 1; }
"$WORK/downstream/fiber_point" >"$WORK/downstream.json"
"$MATPOINT" -energy fiber -E 1e4 -nu 0.3 -gamma 50 -fiber 1,1,0 -F 1.1,0.2,0,-0.1,0.9,0.05,0,0.3,1.2 -json \
  >"$WORK/matpoint.json"
/usr/bin/python3 - "$WORK/downstream.json" "$WORK/matpoint.json" <<'PY'
import json, sys
got, want = (json.load(open(p)) for p in sys.argv[1:3])
for key in ("energy", "pk1", "hessian_psd"):
    g, w = got[key], want[key]
    g, w = (g, w) if isinstance(g, list) else ([g], [w])
    scale = max(1.0, max(abs(x) for x in w))
    worst = max(abs(a - b) for a, b in zip(g, w))
    if len(g) != len(w) or worst > 1e-13 * scale:
        sys.exit(f"FAIL: downstream {key} differs from aries-matpoint by {worst:.3e} (scale {scale:.3e})")
print("downstream: energy, pk1 and hessian_psd equal aries-matpoint's")
PY
mkdir -p "$WORK/too_new"
printf 'cmake_minimum_required(VERSION 3.18)\nproject(too_new LANGUAGES CXX)\nfind_package(aries 9.0 CONFIG REQUIRED)\n' \
  >"$WORK/too_new/CMakeLists.txt"
if cmake -S "$WORK/too_new" -B "$WORK/too_new/build" -DCMAKE_PREFIX_PATH="$WORK/prefix" >"$WORK/too_new.log" 2>&1; then
  echo "FAIL: find_package(aries 9.0) accepted version $(grep -o 'PACKAGE_VERSION "[^"]*"' \
    "$WORK/prefix/lib/cmake/aries/ariesConfigVersion.cmake" | head -1)"; exit 1
fi
grep -q "ariesConfig.cmake, version: 0.1" "$WORK/too_new.log" || { cat "$WORK/too_new.log"; exit 1; }
echo "package: installed, downstream built and agreeing; version 9.0 refused"
