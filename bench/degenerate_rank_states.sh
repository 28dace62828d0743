#!/bin/bash
# Step 1 of one dynamic scramble on 1 and on 2 ranks: the two states' largest vertex distance over L (the bounding
# box's diagonal), the vertices more than 1e-3 L apart, and the relative difference of step 1's energy (issue 49: is
# the result rank-independent beyond round-off?).
# usage: bench/degenerate_rank_states.sh MESH HELD_BOX NU SEED [aries options...]
#   e.g. bench/degenerate_rank_states.sh camel -10,10,-10,10,-10,-0.410884 0.45 3 -energy fiber -gamma 5e3 -fiber 1,0.5,0.2
#   (MESH: meshes/cache/MESH_default.msh, from meshes/generate.sh MESH default; HELD_BOX: -bc_box, as
#   bench/degenerate_starts.py holds the lowest tenth)
set -euo pipefail
[ $# -ge 4 ] || { echo "usage: $0 MESH HELD_BOX NU SEED [aries options...]" >&2; exit 2; }
ROOT=$(cd "$(dirname "$0")/.." && pwd)
MESH=$1; HELD=$2; NU=$3; SEED=$4; shift 4
WORK=$ROOT/out/bench/rank_states; mkdir -p "$WORK"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
for np in 1 2; do
  rm -rf "$WORK/np$np.steps"
  mpiexec -n $np --bind-to none "$ROOT/build/aries" -dm_plex_filename "$ROOT/meshes/cache/${MESH}_default.msh" -E 1e4 \
    -nu "$NU" -integrator beuler -dt 1e-2 -steps 1 -density 1000 -gravity 0,0,-9.81 -initial scramble \
    -scramble_seed "$SEED" -bc_box "$HELD" "$@" -output "$WORK/np$np" -stats "$WORK/np$np.csv" > "$WORK/np$np.log" 2>&1
done
WORK=$WORK /usr/bin/python3 - <<'PY'
import csv, os
import h5py, numpy as np
w = os.environ["WORK"]
x = [h5py.File(f"{w}/np{n}.steps/np{n}_000001.h5", "r")["positions"][()].reshape(-1, 3) for n in (1, 2)]
rows = [next(csv.DictReader(l for l in open(f"{w}/np{n}.csv") if not l.startswith("#"))) for n in (1, 2)]
e = [float(r["energy"]) for r in rows]
L = np.linalg.norm(x[0].max(0) - x[0].min(0))
d = np.linalg.norm(x[0] - x[1], axis=1)
print(f"step-1 updates {rows[0]['newton_its']} (1 rank) / {rows[1]['newton_its']} (2 ranks), energy relative "
      f"difference {abs(e[0] - e[1]) / abs(e[1]):.2e}, largest vertex distance {d.max() / L:.2e} L, "
      f"{(d > 1e-3 * L).sum()} of {len(d)} vertices more than 1e-3 L apart")
PY
