"""Shared pieces of the CTest driver scripts (e2e.py, robustness.py, bad_input.py): how aries is launched on 1 or N
ranks, how a test mesh is obtained, how output and stats are read, how a case fails."""
import csv
import os
import subprocess
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from aries_output import step_file, step_files  # noqa: E402,F401  (the output layout; re-exported to the drivers)


def fail(msg):
    """Ends the case; CTest matches the 'FAIL:' prefix (FAIL_REGULAR_EXPRESSION) as well as the exit code."""
    print("FAIL: " + msg)
    sys.exit(1)


def mpi_env():
    """Open MPI as root, oversubscribed on small CI machines, without busy-waiting ranks; a one-rank run (no mpiexec)
    is an isolated singleton, which spawns no daemon."""
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1",
                OMPI_MCA_ess_singleton_isolated="1")


def aries_cmd(aries, ranks, args):
    """The command line: the binary itself on one rank, under mpiexec (--quiet: no Open MPI abort banner, so an
    input error stays one line) on more."""
    if ranks == 1:
        return [aries] + args
    return ["mpiexec", "--quiet", "-n", str(ranks), "--bind-to", "none", aries] + args


def test_mesh(root, name):
    """Path of the small ('test') variant of a scene mesh, generated on first use."""
    p = subprocess.run([os.path.join(root, "meshes", "generate.sh"), name, "test"], capture_output=True, text=True)
    if p.returncode != 0:
        fail("mesh generation failed: " + p.stderr[-2000:])
    return p.stdout.strip().splitlines()[-1]


def step_positions(base, step):
    with h5py.File(step_file(base, step), "r") as f:
        return f["/positions"][:]


def csv_rows(path):
    with open(path) as fh:
        return list(csv.DictReader(l for l in fh if not l.startswith("#")))
