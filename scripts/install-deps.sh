#!/usr/bin/env bash
# Installs exactly the Debian 12 packages aries uses. Idempotent: apt-get runs only when something is missing.
set -euo pipefail
packages=(
  build-essential cmake pkg-config ninja-build  # toolchain (Ninja: scripts/test.sh)
  clang libclang-rt-14-dev                    # the compiler CMakeLists.txt prefers (docs/build.md), its sanitizers
  petsc-dev libopenmpi-dev openmpi-bin        # PETSc 3.18 (DMPlex, SNES, HDF5 viewer) + Open MPI
  libhdf5-openmpi-dev libmetis-dev libeigen3-dev
  libgtest-dev libbenchmark-dev               # tests and kernel benchmarks
  gmsh tetgen                                 # mesh generation for the scenes
  python3-h5py python3-numpy python3-matplotlib  # XDMF generation, PNG snapshots, charts
  pybind11-dev python3-dev python3-scipy      # the Python module of the kernels (python/) and its example
  python3-meshio                              # the output test reads the XDMF as a third-party client
  paraview python3-paraview xvfb xauth        # ParaView's pvpython reads the XDMF in a test (headless, under xvfb)
  libcgal-demo                                # closed/disk surfaces (armadillo, bunny-like, UV disks)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
