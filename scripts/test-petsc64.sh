#!/usr/bin/env bash
# Every test against the 64-bit-index PETSc (PetscInt = int64: Debian's libpetsc64-real3.18-dev), in its own build
# directory (build-petsc64, or BUILD_DIR): installs what the README's test command installs plus that package,
# configures with -DARIES_PETSC64=ON, builds and runs ctest. A mesh past 2^31 matrix nonzeros is this build, not a
# port. Not part of the README's test command (it doubles its time); CI-able as it is. Extra arguments go to ctest.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/install-deps.sh"
if ! dpkg-query -W -f='${Status}' libpetsc64-real3.18-dev 2>/dev/null | grep -q "install ok installed"; then
  echo "test-petsc64: installing libpetsc64-real3.18-dev"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends libpetsc64-real3.18-dev >/dev/null
fi
BUILD="${BUILD_DIR:-$ROOT/build-petsc64}"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DARIES_PETSC64=ON -DARIES_REQUIRE_PYTHON=ON >/dev/null
grep -q "^ARIES_PETSC_HAS_64BIT_INDICES:INTERNAL=1" "$BUILD/CMakeCache.txt" ||
  { echo "test-petsc64: the configured PETSc has 32-bit indices" >&2; exit 1; }
cmake --build "$BUILD" -j"$(nproc)"
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_mpi_yield_when_idle=1
cd "$BUILD"
ctest --output-on-failure -j"$(nproc)" "$@"
