#!/usr/bin/env bash
# The main job, end to end on a fresh Debian 12 machine: install the Debian packages, build aries, generate the
# bunny mesh, run the inside-out bunny (paper Fig. 5) on 2 MPI ranks, print where the XDMF output is and render two
# PNG snapshots into out/main/ (ignored by git: the job changes no tracked file).
#
#   bash scripts/run-main.sh [--update-readme-images] [--render-only]
#
#   --update-readme-images  also copy the snapshots over the README's pictures,
#                           docs/images/bunny_inside_out_{before,after}.png (tracked files: commit them on purpose)
#   --render-only           no install, build or solve: render the snapshots again from the last run in out/main/
#
# The scene is options/bunny_inside_out.yml: the paper's stiffness, time step and length (E = 1e4, nu = 0,
# dt = 1e-2, 200 steps; the density 1000 is ours, the paper states none) on our default bunny mesh (~35k tets; the paper's bunny has 637,584 tets, ours at that size
# is `meshes/generate.sh bunny paper`, 639,254 tets, hours on 2 cores). The solve takes minutes on 2 cores; every step prints a line with the time spent
# and an estimate of the time left. Environment knobs:
#   ARIES_MAIN_MESH=test|default|paper   bunny mesh size (default: default; test = a few thousand tets, for a quick try)
#   ARIES_MAIN_ARGS="-steps 100"         extra aries options, after the scene's
# Snapshots, each beside the rest shape: out/main/bunny_inside_out_before.png (the start: every element inside out)
# and out/main/bunny_inside_out_after.png (the last step written, moved by the best-fit rotation and translation
# onto the rest shape; the caption gives the remaining distance to rest). Colour = alpha, the element's singularity
# measure: 64 = undeformed, 0 = inside out or crushed onto a line or point (docs/options.md, docs/kernels.md).
set -euo pipefail
usage() { sed -n '2,21p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit "$1"; }
UPDATE_README=0
RENDER_ONLY=0
for arg in "$@"; do
  case "$arg" in
    --update-readme-images) UPDATE_README=1 ;;
    --render-only) RENDER_ONLY=1 ;;
    -h|--help) usage 0 ;;
    *) echo "run-main.sh: unknown argument '$arg'" >&2; usage 2 ;;
  esac
done
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PY=/usr/bin/python3  # Debian's python (h5py, matplotlib)
OUTDIR="$ROOT/out/main"
OUT="$OUTDIR/bunny_inside_out"
if [ "$RENDER_ONLY" -eq 0 ]; then
  bash scripts/install-deps.sh
  BUILD="${BUILD_DIR:-$ROOT/build}"
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$BUILD" -j"$(nproc)" --target aries-app aries-matpoint
  MESH="$(meshes/generate.sh bunny "${ARIES_MAIN_MESH:-default}")"
  if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
  export OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_mpi_yield_when_idle=1
  mkdir -p "$OUTDIR"
  # shellcheck disable=SC2086
  mpiexec -n 2 --bind-to none "$BUILD/aries" -options_file options/bunny_inside_out.yml -dm_plex_filename "$MESH" \
    -output "$OUT" -output_every 10 -stats "$OUTDIR/stats.csv" ${ARIES_MAIN_ARGS:-}
elif [ ! -f "$OUT.h5" ]; then
  echo "run-main.sh: --render-only: no run in $OUTDIR (run bash scripts/run-main.sh first)" >&2
  exit 1
fi
BEFORE="$OUTDIR/bunny_inside_out_before.png"
AFTER="$OUTDIR/bunny_inside_out_after.png"
"$PY" scripts/render_png.py "$OUT" "$BEFORE" --step 0 --beside-rest \
  --title "inside-out bunny, start: every vertex reflected through the centroid"
"$PY" scripts/render_png.py "$OUT" "$AFTER" --rigid --beside-rest \
  --title "inside-out bunny after {step} steps (t = {time:g} s)"
"$PY" scripts/shape_error.py "$OUT" --rigid
if [ "$UPDATE_README" -eq 1 ]; then
  mkdir -p docs/images
  cp "$BEFORE" docs/images/bunny_inside_out_before.png
  cp "$AFTER" docs/images/bunny_inside_out_after.png
  echo "README pictures updated: docs/images/bunny_inside_out_before.png docs/images/bunny_inside_out_after.png"
fi
echo "XDMF (open in ParaView, then Warp By Vector with displacement): $OUT.xmf"
echo "stats: $OUTDIR/stats.csv"
echo "snapshots: $BEFORE $AFTER"
