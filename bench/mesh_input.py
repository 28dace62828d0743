#!/usr/bin/python3
"""Mesh input: the setup of a large run from a gmsh mesh and from the same mesh converted to HDF5, with its faces and
edges made before or after the cells are distributed.

usage: bench/mesh_input.py [--sizes default,s1m] [--ranks 2] [--repeat 3] [--out FILE.md]

The problem is bench/peer.py's (a box 1 x 1 x 2, meshes/generate.sh box SIZE, bottom held, top moved by 0.2 in one
static step, iarap E 1e4 nu 0.3, aries' defaults). Four ways to read the mesh, the same build and options otherwise:
  msh distributed  the .msh read on rank 0 as cells and vertices, partitioned (METIS), distributed, and every rank
                   makes the faces and edges of its part (-mesh_faces distributed, the default)
  msh serial       PETSc's gmsh reader: every face and edge made on rank 0 before distribution (-mesh_faces serial)
  h5 distributed   the .h5 (meshes/generate.sh h5 box SIZE, converted once, not timed) read by every rank in parallel
                   as cells and vertices, repartitioned (RCB), and every rank makes the faces and edges of its part
                   (the default)
  h5 serial        the .h5 with its faces and edges made by every rank on its block of the file, before the cells
                   are repartitioned (-mesh_faces serial; aries' only HDF5 path before 2026-11-30)
Measured per run: aries' `wall time setup` (mesh input to the first step, the matrix and solver set-up included), the
step, the output, the whole process; the held vertices and the top face's reaction, which must agree between the four
(the partitions differ, so the reaction agrees to the Newton tolerance, not bit for bit). Timings are medians over
--repeat runs, made in rounds (each way once per round), so the four are timed side by side. Runs live in
out/mesh_input/; nothing is cached between invocations. Use /usr/bin/python3.
"""
import argparse
import datetime
import json
import os
import re
import statistics
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(ROOT, "ctest"))
import scenes  # noqa: E402  (mesh generation, machine line, commit line)
from harness import mpi_env  # noqa: E402

WORK = os.path.join(ROOT, "out", "mesh_input")
OUT = os.path.join(ROOT, "bench", "results", "mesh_input.md")
WAYS = [("msh", "distributed"), ("msh", "serial"), ("h5", "distributed"), ("h5", "serial")]
PROBLEM = ["-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-integrator", "static", "-steps", "1", "-bc_clamp",
           "bottom,top", "-bc_clamp_top_translate", "0,0,-0.2", "-ksp_rtol", "1e-8", "-output_fields", "J"]


def run_once(aries, mesh, faces, ranks, tag):
    d = os.path.join(WORK, tag)
    os.makedirs(d, exist_ok=True)
    base = os.path.join(d, "box")
    cmd = ["mpiexec", "-n", str(ranks), "--bind-to", "none", aries, "-dm_plex_filename", mesh] + PROBLEM + [
        "-mesh_faces", faces, "-output", base, "-reactions", base + "_reactions.csv"]
    t0 = time.time()
    p = subprocess.run(cmd, cwd=ROOT, env=mpi_env(), capture_output=True, text=True)
    total = time.time() - t0
    if p.returncode != 0:
        sys.exit("mesh_input.py: %s failed (exit %d):\n%s"
                 % (" ".join(cmd), p.returncode, p.stdout[-3000:] + p.stderr[-3000:]))
    times = re.search(r"wall time setup ([0-9.]+) s, steps ([0-9.]+) s .*output ([0-9.]+) s", p.stdout)
    held = re.search(r"\((\d+) Dirichlet\)", p.stdout)
    with open(base + "_reactions.csv") as fh:
        top = [l for l in fh.read().splitlines() if ",top," in l][-1].split(",")
    return {"setup": float(times.group(1)), "step": float(times.group(2)), "output": float(times.group(3)),
            "total": total, "held": int(held.group(1)), "fz": float(top[5])}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], usage=__doc__.split("\n\n")[1])
    ap.add_argument("--sizes", default="default,s1m")
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--aries", default=os.path.join(ROOT, "build", "aries"))
    ap.add_argument("--out", default=OUT)
    a = ap.parse_args()
    started = datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC")
    rows = []
    for size in a.sizes.split(","):
        meshes = {"msh": scenes.generate("box", size), "h5": scenes.generate("box", size, h5=True)}
        samples = {w: [] for w in WAYS}
        for r in range(a.repeat):
            for w in WAYS:
                s = run_once(a.aries, meshes[w[0]], w[1], a.ranks, "%s_%s_%s_n%d" % (size, w[0], w[1], a.ranks))
                samples[w].append(s)
                print("%s %s %s round %d: setup %.2f s, total %.2f s"
                      % (size, w[0], w[1], r + 1, s["setup"], s["total"]), flush=True)
        with open(meshes["msh"][:-4] + ".json") as fh:
            tets = json.load(fh)["tets"]
        ref = samples[WAYS[0]][0]
        for w in WAYS:
            med = {k: statistics.median(x[k] for x in samples[w]) for k in ("setup", "step", "output", "total")}
            held = {x["held"] for x in samples[w]}
            dfz = max(abs(x["fz"] - ref["fz"]) / abs(ref["fz"]) for x in samples[w])
            rows.append((tets, w, med, held, dfz, samples[w]))
    lines = ["# Mesh input: gmsh or HDF5, faces made before or after distribution", "",
             "Generated by `bench/mesh_input.py --sizes %s --ranks %d --repeat %d` (started %s); **do not edit by "
             "hand**. %s; %s." % (a.sizes, a.ranks, a.repeat, started, scenes.machine_line(a.ranks),
                                 scenes.commit_line()), "",
             "The problem: bench/peer.py's box (1 x 1 x 2, bottom held, top moved by 0.2 in one static step, iarap, "
             "aries' defaults), read four ways (bench/mesh_input.py's docstring). setup = aries' `wall time setup` "
             "(mesh input to the first step), total = the whole process; medians of %d runs made in rounds. held = "
             "the Dirichlet vertices, reaction = the top face's force z against the first way's first run (the "
             "partitions differ)."
             % a.repeat, "",
             "| tets | mesh | faces made | setup s | step s | output s | total s | setup / msh distributed | held | "
             "reaction difference |",
             "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    base_setup = {}
    for tets, w, med, held, dfz, _ in rows:
        if w == WAYS[0]:
            base_setup[tets] = med["setup"]
        lines.append("| {:,} | .{} | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {} | {:.1e} |".format(
            tets, w[0], "by every rank after distribution" if w[1] == "distributed" else
            ("on rank 0 (PETSc's reader)" if w[0] == "msh" else "by every rank on its block, before repartitioning"),
            med["setup"], med["step"], med["output"], med["total"], med["setup"] / base_setup[tets],
            "/".join(str(h) for h in sorted(held)), dfz))
    lines += ["", "Every run, in the order made (setup / total s):", ""]
    for tets, w, _, _, _, s in rows:
        lines.append("- {:,} tets, .{} {}: {}".format(tets, w[0], w[1], ", ".join(
            "%.2f / %.2f" % (x["setup"], x["total"]) for x in s)))
    scenes.write(a.out, lines)


if __name__ == "__main__":
    main()
