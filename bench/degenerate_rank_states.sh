#!/bin/bash
# Step 1 of one dynamic scramble run several ways (by default on 1 and on 2 ranks): each run's step-1 updates and
# energy, and for every pair of runs the two states' largest vertex distance over L (the rest bounding box's
# diagonal), the vertices more than 1e-3 L apart and the relative difference of step 1's energy (issue 49: is the
# result rank-independent beyond round-off?). Runs that differ in round-off only, on one rank count (another partition
# of the same rank count, another mesh file of the same mesh), say how far round-off alone moves the result.
# usage: [RUNS="NP [options];..."] bench/degenerate_rank_states.sh MESH HELD_BOX NU SEED [aries options...]
#   e.g. bench/degenerate_rank_states.sh camel -10,10,-10,10,-10,-0.410884 0.45 3 -energy fiber -gamma 5e3 -fiber 1,0.5,0.2
#   MESH: meshes/cache/MESH_default.msh, from meshes/generate.sh MESH default; HELD_BOX: -bc_box, as
#   bench/degenerate_starts.py holds the lowest tenth. RUNS (default "1;2"): the runs, separated by ';', each a rank
#   count and options of its own, e.g. RUNS="1;2;2 -partitioner rcb;3"; the word MESH_H5 in them stands for the same
#   mesh converted to HDF5 (meshes/generate.sh h5 MESH default), e.g. "1 -dm_plex_filename MESH_H5", and MESH_SHUFFLED
#   for the same mesh with its cells listed in another (fixed random) order and its vertices as they were: the same
#   start and problem, summed in another order (round-off alone, on any rank count).
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: [RUNS=\"NP [options];...\"] $0 MESH HELD_BOX NU SEED [aries options...]" >&2; exit 2; }
ROOT=$(cd "$(dirname "$0")/.." && pwd)
MESH=$1; HELD=$2; NU=$3; SEED=$4; shift 4
WORK=$ROOT/out/bench/rank_states; mkdir -p "$WORK"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
IFS=';' read -r -a runs <<< "${RUNS:-1;2}"
SHUFFLED=$WORK/${MESH}_cells_shuffled.msh
if [[ ${RUNS:-} == *MESH_SHUFFLED* ]]; then
  /usr/bin/python3 - "$ROOT/meshes/cache/${MESH}_default.msh" "$SHUFFLED" <<'PY'
import random, sys
lines = open(sys.argv[1]).read().split("\n")
if lines[1].split()[0] != "2.2":
    sys.exit(f"degenerate_rank_states: error: {sys.argv[1]}: MESH_SHUFFLED reads gmsh 2.2 ASCII meshes only")
a = lines.index("$Elements")
n = int(lines[a + 1])
cells = lines[a + 2:a + 2 + n]
random.Random(1).shuffle(cells)  # the element numbers keep their lines: only the order of the cells changes
open(sys.argv[2], "w").write("\n".join(lines[:a + 2] + cells + lines[a + 2 + n:]))
PY
fi
for i in "${!runs[@]}"; do
  entry=${runs[$i]//MESH_H5/$ROOT/meshes/cache/${MESH}_default.h5}
  read -r -a words <<< "${entry//MESH_SHUFFLED/$SHUFFLED}"
  np=${words[0]}; own=("${words[@]:1}")
  [[ $np =~ ^[1-9][0-9]*$ ]] || { echo "$0: error: RUNS entry '${runs[$i]}' does not start with a rank count" >&2; exit 2; }
  rm -rf "$WORK/run$i.steps"
  # the run's own options come last: a -dm_plex_filename there replaces the .msh
  mpiexec -n "$np" --bind-to none "$ROOT/build/aries" -dm_plex_filename "$ROOT/meshes/cache/${MESH}_default.msh" \
    -E 1e4 -nu "$NU" -integrator beuler -dt 1e-2 -steps 1 -density 1000 -gravity 0,0,-9.81 -initial scramble \
    -scramble_seed "$SEED" -bc_box "$HELD" "$@" "${own[@]}" -output "$WORK/run$i" -stats "$WORK/run$i.csv" \
    > "$WORK/run$i.log" 2>&1 || { echo "$0: error: run '${runs[$i]}' failed, see $WORK/run$i.log" >&2; exit 1; }
done
WORK=$WORK LABELS=$(printf '%s\n' "${runs[@]}") /usr/bin/python3 - <<'PY'
import csv, itertools, os
import h5py, numpy as np
w, labels = os.environ["WORK"], os.environ["LABELS"].split("\n")
x = [h5py.File(f"{w}/run{i}.steps/run{i}_000001.h5", "r")["positions"][()].reshape(-1, 3) for i in range(len(labels))]
rows = [next(csv.DictReader(l for l in open(f"{w}/run{i}.csv") if not l.startswith("#"))) for i in range(len(labels))]
e = [float(r["energy"]) for r in rows]
L = np.linalg.norm(x[0].max(0) - x[0].min(0))
print("| run | ranks and options | step-1 updates | CG | energy |")
print("|---|---|---:|---:|---:|")
for i, (label, r) in enumerate(zip(labels, rows)):
    print(f"| {i} | {label} | {r['newton_its']} | {r['ksp_its']} | {e[i]:.9e} |")
print("\n| runs | energy relative difference | largest vertex distance / L | vertices > 1e-3 L apart |")
print("|---|---:|---:|---:|")
for i, j in itertools.combinations(range(len(labels)), 2):
    d = np.linalg.norm(x[i] - x[j], axis=1)
    print(f"| {i} - {j} | {abs(e[i] - e[j]) / abs(e[j]):.2e} | {d.max() / L:.2e} | {(d > 1e-3 * L).sum()} of {len(d)} |")
PY
