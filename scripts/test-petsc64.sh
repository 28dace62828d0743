#!/usr/bin/env bash
# Every test against the 64-bit-index PETSc (PetscInt = int64: Debian's libpetsc64-real3.18-dev): installs that
# package, then runs the README's test command (scripts/test.sh) in its own build directory (build-petsc64, or
# BUILD_DIR) configured with -DARIES_PETSC64=ON, which refuses a PETSc with 32-bit indices. A mesh past 2^31 matrix
# nonzeros is this build, not a port. Not part of the README's test command (it doubles its time); CI-able as it is.
# Extra arguments go to ctest.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if ! dpkg-query -W -f='${Status}' libpetsc64-real3.18-dev 2>/dev/null | grep -q "install ok installed"; then
  echo "test-petsc64: installing libpetsc64-real3.18-dev"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends libpetsc64-real3.18-dev >/dev/null
fi
BUILD_DIR="${BUILD_DIR:-$ROOT/build-petsc64}" ARIES_CMAKE_ARGS="-DARIES_PETSC64=ON" exec bash "$ROOT/scripts/test.sh" "$@"
