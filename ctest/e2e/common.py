"""Shared pieces of the end-to-end cases (ctest/e2e.py): the parsed command line (ARGS), running aries, reading its
output and stats, test meshes, and the helpers used by more than one topic module."""
import argparse
import os
import re
import subprocess
import sys

import h5py
import numpy as np

from harness import aries_cmd, csv_rows, fail, mpi_env, step_file, step_files, test_mesh

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))),
                                "scripts"))
from shape_error import shape_error as distance_to_rest  # noqa: E402

# The command line, filled in place by ctest/e2e.py's main (parse_args(namespace=ARGS)) before any case
# runs; never rebound, so `from .common import ARGS` sees the parsed values.
ARGS = argparse.Namespace()


# The reasons of a converged step (solver/newton.hpp).
CONVERGED = ("newton_step", "converged_initial", "step_bound", "energy_roundoff")


def mesh(name):
    return test_mesh(ARGS.root, name)


def run(args, ranks=None, expect_code=0, tag="run"):
    """Runs aries; returns (stdout+stderr, exit code). Fails unless the exit code is `expect_code`."""
    n = ranks or ARGS.ranks
    cmd = aries_cmd(ARGS.aries, n, args)
    print("$ " + " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, env=mpi_env(), cwd=ARGS.work, timeout=900)
    log = p.stdout + p.stderr
    with open(os.path.join(ARGS.work, tag + ".log"), "w") as fh:
        fh.write(log)
    print("\n".join(log.splitlines()[-4:]))
    if expect_code is not None and p.returncode != expect_code:
        fail("exit code %d, expected %d; log tail:\n%s" % (p.returncode, expect_code, log[-3000:]))
    return log, p.returncode


def out_base(tag):
    return os.path.join(ARGS.work, "out", tag)


def read_state(base, step=None):
    with h5py.File(base + ".h5", "r") as f:
        rest = f["/mesh/rest"][:]
        cells = f["/mesh/topology"][:]
    files = step_files(base)
    if not files:
        fail("no output steps for " + base)
    path = files[-1] if step is None else step_file(base, step)
    with h5py.File(path, "r") as f:
        x = f["/positions"][:]
        alpha = f["/cell/alpha"][:]
    return rest, cells, x, alpha


def read_cell_field(base, name):
    """A cell field of the last written step (written with -output_fields NAME), one row per cell."""
    files = step_files(base)
    if not files:
        fail("no output steps for " + base)
    with h5py.File(files[-1], "r") as f:
        if "/cell/" + name not in f:
            fail("%s: no cell field %s (not in -output_fields?)" % (files[-1], name))
        values = f["/cell/" + name][:]
    return values.reshape(len(values), -1)


def shape_error(base, rigid):
    """Max distance of the final state to rest over L (rigid: after the best rotation + translation, for
    free-floating bodies), via scripts/shape_error.py; and L."""
    rest, _, x, _ = read_state(base)
    if not np.all(np.isfinite(x)):
        fail("NaN/Inf in the final positions of " + base)
    err, _ = distance_to_rest(rest, x, rigid)
    return err, np.linalg.norm(rest.max(0) - rest.min(0))


def stats(path):
    rows = csv_rows(path)
    if not rows:
        fail("empty stats " + path)
    return rows


def summary_value(log, key):
    m = re.search(key + r" (\d+)", log)
    if not m:
        fail("no '%s' in the run summary" % key)
    return int(m.group(1))


def sized_mesh(name, size):
    """A catalog mesh of another size than the fixture's (meshes/generate.sh caches it)."""
    out = subprocess.run(["bash", os.path.join(ARGS.root, "meshes", "generate.sh"), name, size], capture_output=True,
                         text=True)
    if out.returncode != 0:
        fail("meshes/generate.sh %s %s failed: %s" % (name, size, out.stderr[-500:]))
    return out.stdout.strip().splitlines()[-1]


def static_scramble_args(msh, seed, steps):
    """A static scramble with a box pin: the vertices in the bottom 10% of the rest bounding box are fixed."""
    rest_box = meta_box(msh)
    lo, hi = rest_box
    box = "%g,%g,%g,%g,%g,%g" % (lo[0] - 1, hi[0] + 1, lo[1] - 1, hi[1] + 1, lo[2] - 1, lo[2] + 0.1 * (hi[2] - lo[2]))
    return ["-dm_plex_filename", msh, "-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-integrator", "static",
            "-steps", str(steps), "-initial", "scramble", "-scramble_seed", str(seed), "-bc_box", box]


def dynamic_scramble_args(msh, seed):
    """A dynamic scramble with a volume term and a box pin (iarap, nu 0.3; the bottom 10% of the rest bounding box held;
    backward Euler, 2 steps of 1e-2, density 1000, gravity)."""
    lo, hi = meta_box(msh)
    box = "%g,%g,%g,%g,%g,%g" % (lo[0] - 1, hi[0] + 1, lo[1] - 1, hi[1] + 1, lo[2] - 1, lo[2] + 0.1 * (hi[2] - lo[2]))
    return ["-dm_plex_filename", msh, "-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-integrator", "beuler",
            "-dt", "1e-2", "-steps", "2", "-density", "1000", "-gravity", "0,0,-9.81", "-initial", "scramble",
            "-scramble_seed", str(seed), "-bc_box", box]


def meta_box(msh):
    import json
    with open(msh[:-4] + ".json") as fh:
        meta = json.load(fh)
    return meta["bbox_min"], meta["bbox_max"]


def solve_blocks(history_csv, step="1"):
    """The -newton_history rows of one step, split into its Newton solves (column solve)."""
    blocks, solve = [], None
    for h in csv_rows(history_csv):
        if h["step"] != step:
            continue
        if h["solve"] != solve:
            blocks.append([])
            solve = h["solve"]
        blocks[-1].append(h)
    return blocks


def cloth_args(msh):
    return ["-dm_plex_filename", msh, "-dm_plex_gmsh_spacedim", "3"]


def caricature_run(tag, beta, ranks=None, extra=()):
    run(["-dm_plex_filename", mesh("bunny"), "-energy", "caricature", "-beta", str(beta), "-E", "1e2", "-nu", "0",
         "-steps", "1", "-output", out_base(tag), "-stats", out_base(tag) + ".csv"] + list(extra), ranks=ranks, tag=tag)
    cmd = [sys.executable, os.path.join(ARGS.root, "scripts", "curvature_report.py"), out_base(tag), "--json"]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        fail("curvature_report failed: " + out.stderr[-1000:])
    import json
    return json.loads(out.stdout.strip().splitlines()[-1])
