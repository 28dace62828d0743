"""Shared pieces of the CTest driver scripts (e2e.py, robustness.py, bad_input.py): how aries is launched on 1 or N
ranks, how a test mesh is obtained, how output and stats are read, how a case fails."""
import atexit
import csv
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
from aries_output import step_file, step_files  # noqa: E402,F401  (the output layout; re-exported to the drivers)


def fail(msg):
    """Ends the case; CTest matches the 'FAIL:' prefix (FAIL_REGULAR_EXPRESSION) as well as the exit code."""
    print("FAIL: " + msg)
    sys.exit(1)


_SESSION_BASE = []  # this process's Open MPI session directory base, made on first use


def _session_base():
    """A directory of this process's own for Open MPI's session files. Runs of tests side by side (ctest -j) otherwise
    share /tmp/ompi.HOST.UID, which one run removes as it ends while another is making its job directory in it: the
    latter then fails in orte_init ("mkdir ... jf.0: No such file or directory"; seen once in a CI run). Kept short
    (sockets live under it) and removed when the process ends."""
    if not _SESSION_BASE:
        _SESSION_BASE.append(tempfile.mkdtemp(prefix="ompi-"))
        atexit.register(shutil.rmtree, _SESSION_BASE[0], True)
    return _SESSION_BASE[0]


def mpi_env():
    """Open MPI as root, oversubscribed on small CI machines, without busy-waiting ranks, with session files of its
    own; a one-rank run (no mpiexec) is an isolated singleton, which spawns no daemon; the one-machine transport
    named (ob1 over shared memory), so that MPI_Init does not probe the network layers first (CMakeLists.txt)."""
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1",
                OMPI_MCA_ess_singleton_isolated="1", OMPI_MCA_pml="ob1", OMPI_MCA_btl="self,vader",
                OMPI_MCA_orte_tmpdir_base=_session_base())


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
