#!/usr/bin/python3
"""Newton's work on the scenes whose supports move: before and after, and the Hessian filters.

usage: bench/newton_work.py run [--before BIN] [--after BIN] [--groups lifting,filters,reference,always,predictor]
                                [--only LABEL,...]
       bench/newton_work.py report [--out bench/results/newton_work.md]

`run` solves each scene below with two aries builds, "before" (--before: a build of an earlier commit; without it the
same build with -lift_increments never, which moves the supports alone as aries did before) and "after" (--after,
default build/aries), 2 MPI ranks, and keeps every run's stats, Newton history, log and final state in
out/newton_work/ (a run whose directory holds the same command line and a finished result is read back, not run
again). The filter group runs the after build with each element Hessian filter (-psd_projection clamp, abs, adaptive,
none) and with the default filter but -newton_exact_hessian false; the reference group solves each static scene with
the after build at -newton_tol 1e-8 (quadratic convergence gets there in a few updates), the solution both builds'
states are measured against; the always group runs the dynamic scenes with -lift_increments always; the predictor
group runs the backward Euler scenes (the dynamic and interaction ones) with the after build's start from x_n + dt v_n
alone (-predictor_acceleration false, as before it existed) and with the acceleration's extrapolation as well
(-predictor_acceleration true, the default). `report` writes the tables of the groups that have runs in
out/newton_work/: steps converged, Newton updates, linear solves and PCG iterations per step, seconds per step
(averages over every step of a run, as the paper's tables), the load sub-steps, and how far the after state is from
the before state at the end (the largest vertex distance over the Newton tolerance of the run: below 1, the two builds
agree within what the tolerance certifies).

Scenes (options files and meshes of the repository, meshes/generate.sh):
  - the static compressed cylinder (options/cylinder_compress.yml as a static run: 30% in 1 and in 3 load steps, on
    the 17.8k-tet cylinder and the ~300k-tet one, meshes/generate.sh cylinder s300k);
  - Table 1's dynamic Fig. 3 / Fig. 6 rows (cube_ortho_compress/pull, cylinder_compress/pull at nu 0, 0.3, 0.49: every
    step of each);
  - the Fig. 13 interaction (bunny_interact: handles pushed 0.06 into the cheeks over 100 steps, 200 steps) on the tet
    bunny (35k) and on voxel hexahedra (the 24.9k-hex bunny, meshes/generate.sh bunny hexmid; the paper-size 199k-hex
    run is bench/scenes.py's bunny_interact_hex row, hours on 2 cores);
  - in the predictor group only, the first steps of the other backward Euler scenes: armadillo_scramble and
    armadillo_crush_barrier (30 steps, meshes/generate.sh armadillo default), bunny_inside_out (30), octopus_fiber on
    the test octopus (100) and cloth_drop_ours (200).
"""
import argparse
import csv
import datetime
import json
import os
import re
import subprocess
import sys
import time

import h5py
import numpy as np

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(ROOT, "ctest"))
import scenes  # noqa: E402  (mesh generation, machine line, commit line, Table 1's paper rows)
from harness import mpi_env  # noqa: E402

WORK = os.path.join(ROOT, "out", "newton_work")
OUT = os.path.join(ROOT, "bench", "results", "newton_work.md")
RANKS = 2
CONVERGED = ("newton_step", "converged_initial", "step_bound", "energy_roundoff")
STATIC = ["-integrator", "static"]

# label -> (options file, mesh (name, size), extra options, group)
SCENES = {
    "cylinder static, 1 load step": ("cylinder_compress", ("cylinder", "default"), STATIC + ["-steps", "1"], "static"),
    "cylinder static, 3 load steps": ("cylinder_compress", ("cylinder", "default"), STATIC + ["-steps", "3"], "static"),
    "cylinder 300k static, 1 load step": ("cylinder_compress", ("cylinder", "s300k"), STATIC + ["-steps", "1"],
                                          "static"),
    "cylinder 300k static, 3 load steps": ("cylinder_compress", ("cylinder", "s300k"), STATIC + ["-steps", "3"],
                                           "static"),
    "cube_ortho_compress (Fig. 3)": ("cube_ortho_compress", ("cube", "default"), [], "dynamic"),
    "cube_ortho_pull (Fig. 3)": ("cube_ortho_pull", ("cube", "default"), [], "dynamic"),
    "cylinder_compress nu 0 (Fig. 6)": ("cylinder_compress", ("cylinder", "default"), ["-nu", "0"], "dynamic"),
    "cylinder_compress nu 0.3 (Fig. 6)": ("cylinder_compress", ("cylinder", "default"), ["-nu", "0.3"], "dynamic"),
    "cylinder_compress nu 0.49 (Fig. 6)": ("cylinder_compress", ("cylinder", "default"), ["-nu", "0.49"], "dynamic"),
    "cylinder_pull nu 0 (Fig. 6)": ("cylinder_pull", ("cylinder", "default"), ["-nu", "0"], "dynamic"),
    "cylinder_pull nu 0.3 (Fig. 6)": ("cylinder_pull", ("cylinder", "default"), ["-nu", "0.3"], "dynamic"),
    "cylinder_pull nu 0.49 (Fig. 6)": ("cylinder_pull", ("cylinder", "default"), ["-nu", "0.49"], "dynamic"),
    "interaction, tets (Fig. 13)": ("bunny_interact", ("bunny", "default"), [], "interaction"),
    "interaction, hexahedra (Fig. 13)": ("bunny_interact", ("bunny", "hexmid"), [], "interaction"),
    # the predictor group's other backward Euler scenes (their first steps; not in the lifting or filter groups)
    "armadillo_scramble (Fig. 4), 30 steps": ("armadillo_scramble", ("armadillo", "default"), ["-steps", "30"],
                                              "predictor"),
    "armadillo_crush_barrier, 30 steps": ("armadillo_crush_barrier", ("armadillo", "default"), ["-steps", "30"],
                                          "predictor"),
    "bunny_inside_out (Fig. 5), 30 steps": ("bunny_inside_out", ("bunny", "default"), ["-steps", "30"], "predictor"),
    "octopus_fiber (Fig. 9), test mesh, 100 steps": ("octopus_fiber", ("octopus", "test"), ["-steps", "100"],
                                                     "predictor"),
    "cloth_drop_ours (Table 2), 200 steps": ("cloth_drop_ours", ("cloth", "default"), ["-steps", "200"],
                                             "predictor"),
}
# the filter study's variants of the after build: each filter (with -newton_exact_hessian, the default), and the
# default filter without the exact Hessian near the solution
FILTERS = {"clamp": ["-psd_projection", "clamp"], "abs": ["-psd_projection", "abs"],
           "adaptive": ["-psd_projection", "adaptive"], "none": ["-psd_projection", "none"],
           "default, -newton_exact_hessian false": ["-newton_exact_hessian", "false"]}
# the filter study: the scenes whose defaults it decides (static: abs, backward Euler: clamp)
FILTER_SCENES = ["cylinder static, 1 load step", "cylinder static, 3 load steps", "cylinder_compress nu 0.3 (Fig. 6)",
                 "cube_ortho_compress (Fig. 3)", "interaction, tets (Fig. 13)", "interaction, hexahedra (Fig. 13)"]


# the predictor group: backward Euler's start without and with the extrapolated acceleration (variant, option value)
PREDICTOR_STARTS = [("predictor_velocity", "false"), ("predictor_acceleration", "true")]
PREDICTOR_NAMES = {"predictor_velocity": "x_n + dt v_n", "predictor_acceleration": "+ dt^2 a_n (default)"}


# the static scenes' reference solution: the after build at this -newton_tol (its Newton converges quadratically there)
REFERENCE_TOL = 1e-8


def slug(text):
    return re.sub(r"[^a-z0-9]+", "_", text.lower()).strip("_")


def scene_args(label):
    opts, (name, size), extra, _ = SCENES[label]
    msh = scenes.generate(name, size)
    args = ["-options_file", os.path.join(ROOT, "options", opts + ".yml"), "-dm_plex_filename", msh] + extra
    text = open(os.path.join(ROOT, "options", opts + ".yml")).read()
    if "target_file" in text:
        args += ["-target_file", msh[:-4] + ".targets"]
    if "fiber_file" in text:
        args += ["-fiber_file", msh[:-4] + ".fibers"]
    return args


def run_one(binary, label, variant, extra, timeout):
    d = os.path.join(WORK, slug(label), variant)
    os.makedirs(d, exist_ok=True)
    base = os.path.join(d, "run")
    cmd = (["mpiexec", "-n", str(RANKS), "--bind-to", "none", binary] + scene_args(label) + extra +
           ["-output", base, "-output_every", "1000000", "-stats", base + ".csv", "-newton_history",
            base + "_newton.csv"])
    meta_path = os.path.join(d, "meta.json")
    if os.path.exists(meta_path):
        with open(meta_path) as fh:
            meta = json.load(fh)
        if meta.get("cmd") == cmd:
            return meta
    print("$ " + " ".join(cmd), flush=True)
    t0 = time.time()
    with open(os.path.join(d, "log.txt"), "w") as fh:
        try:
            code = subprocess.run(cmd, cwd=ROOT, env=mpi_env(), stdout=fh, stderr=subprocess.STDOUT,
                                  timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            code = "timeout"
    meta = {"cmd": cmd, "exit": code, "wall": time.time() - t0, "label": label, "variant": variant,
            "finished": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC")}
    with open(meta_path, "w") as fh:
        json.dump(meta, fh, indent=1)
    return meta


def cmd_run(a):
    after = os.path.abspath(a.after)
    before = os.path.abspath(a.before) if a.before else after
    before_extra = [] if a.before else ["-lift_increments", "never"]
    labels = [l for l in SCENES if not a.only or slug(l) in a.only.split(",") or l in a.only.split(",")]
    groups = a.groups.split(",")
    for label in labels:
        if "lifting" in groups and SCENES[label][3] != "predictor":
            for variant, binary, extra in (("before", before, before_extra), ("after", after, [])):
                m = run_one(binary, label, variant, extra, a.timeout)
                print("%s, %s: exit %s, %.0f s" % (label, variant, m["exit"], m["wall"]), flush=True)
        if "reference" in groups and SCENES[label][3] == "static":
            m = run_one(after, label, "reference", ["-newton_tol", str(REFERENCE_TOL)], a.timeout)
            print("%s, reference: exit %s, %.0f s" % (label, m["exit"], m["wall"]), flush=True)
        if "always" in groups and SCENES[label][3] == "dynamic":
            m = run_one(after, label, "always", ["-lift_increments", "always"], a.timeout)
            print("%s, -lift_increments always: exit %s, %.0f s" % (label, m["exit"], m["wall"]), flush=True)
        if "predictor" in groups and SCENES[label][3] in ("dynamic", "interaction", "predictor"):
            for variant, value in PREDICTOR_STARTS:
                m = run_one(after, label, variant, ["-predictor_acceleration", value], a.timeout)
                print("%s, -predictor_acceleration %s: exit %s, %.0f s" % (label, value, m["exit"], m["wall"]),
                      flush=True)
        if "filters" in groups and label in FILTER_SCENES:
            for f, extra in FILTERS.items():
                m = run_one(after, label, "filter_" + slug(f), extra, a.timeout)
                print("%s, filter %s: exit %s, %.0f s" % (label, f, m["exit"], m["wall"]), flush=True)


def read_run(label, variant):
    d = os.path.join(WORK, slug(label), variant)
    meta_path = os.path.join(d, "meta.json")
    if not os.path.exists(meta_path):
        return None
    with open(meta_path) as fh:
        meta = json.load(fh)
    stats = os.path.join(d, "run.csv")
    if not os.path.exists(stats):
        return dict(meta, rows=[])
    with open(stats) as fh:
        lines = fh.read().splitlines()
    meta["build"] = next((l[1:].strip() for l in lines if l.startswith("# aries")), "?")
    meta["rows"] = list(csv.DictReader(l for l in lines if not l.startswith("#")))
    with open(os.path.join(d, "log.txt")) as fh:
        log = fh.read()
    sub = re.search(r"load sub-steps (\d+)", log)
    meta["substeps"] = int(sub.group(1)) if sub else None
    tol = re.search(r"L = ([0-9.eE+-]+)", log)
    meta["L"] = float(tol.group(1)) if tol else None
    meta["dir"] = d
    return meta


def final_positions(run):
    steps = sorted(os.listdir(os.path.join(run["dir"], "run.steps")))
    with h5py.File(os.path.join(run["dir"], "run.steps", steps[-1]), "r") as f:
        return f["/positions"][:]


def averages(run):
    rows = run["rows"]
    n = max(len(rows), 1)
    conv = sum(1 for r in rows if r["reason"].split("|")[0] in CONVERGED)
    return dict(steps=len(rows), converged=conv, newton=sum(int(r["newton_its"]) for r in rows) / n,
                solves=sum(int(r["linear_solves"]) for r in rows) / n, pcg=sum(int(r["ksp_its"]) for r in rows) / n,
                seconds=sum(float(r["wall_s"]) for r in rows) / n)


def tolerance(run, label):
    """The run's Newton step tolerance: -newton_tol (1e-4 static, 1e-2 backward Euler) x L (x dt)."""
    static = "-integrator" in SCENES[label][2] and "static" in SCENES[label][2]
    text = open(os.path.join(ROOT, "options", SCENES[label][0] + ".yml")).read()
    dt = float(re.search(r"^dt:\s*(\S+)", text, re.M).group(1)) if re.search(r"^dt:", text, re.M) else 1e-2
    return (1e-4 if static else 1e-2 * dt) * run["L"]


def time_ratio(first, second):
    """Seconds per step of `first` over those of `second` ("-" unless both have stats rows)."""
    if not (first and second and first["rows"] and second["rows"]):
        return "-"
    return "%.2fx" % (averages(first)["seconds"] / averages(second)["seconds"])


def distance_over_tol(first, second, label, tol_run):
    """The largest vertex distance between two runs' final states over tol_run's Newton tolerance ("-" if unreadable)."""
    try:
        d = np.linalg.norm(final_positions(first) - final_positions(second), axis=1).max()
        return "%.2g" % (d / tolerance(tol_run, label))
    except (OSError, KeyError, IndexError, ValueError, TypeError):
        return "-"


def lifted_counts(run):
    """Lifted linear solves of the run and how many of them the safeguard or the merit test shortened (lambda < 1)."""
    path = os.path.join(run["dir"], "run_newton.csv") if run and "dir" in run else None
    if not path or not os.path.exists(path):
        return "-"
    with open(path) as fh:
        rows = [r for r in csv.DictReader(fh) if r.get("lifted") == "1"]
    if not rows and not run["rows"]:
        return "-"
    return "%d (%d)" % (len(rows), sum(1 for r in rows if float(r["lambda"]) < 1.0))


def row_cells(run):
    if run is None or run.get("exit") != 0 and not run.get("rows"):
        return ["-"] * 6
    a = averages(run)
    return ["%d / %d" % (a["converged"], a["steps"]), "%.2f" % a["newton"], "%.2f" % a["solves"], "%.1f" % a["pcg"],
            "%.3f" % a["seconds"], "-" if run.get("substeps") is None else str(run["substeps"])]


def cmd_report(a):
    lines = ["# Newton's work where supports move: before and after, and the Hessian filters", "",
             "Generated by `bench/newton_work.py report` on %s from the runs of `bench/newton_work.py run` in "
             "out/newton_work/; **do not edit by hand**. %s. Every number is an average over every step of the run "
             "(as the paper's Table 1); Newton = updates of the state, solves = linear solves (the one that "
             "certifies convergence included), s = the steps' wall time (stats wall_s); sub-steps = load sub-steps "
             "of the whole run; lifted solves = linear solves that carried an increment of the supports (in brackets: "
             "how many of their updates the safeguard or the merit test shortened; `before` builds have none). "
             "Distance = the largest vertex distance between the before and after states at the "
             "end, over the run's Newton tolerance (-newton_tol L, x dt for backward Euler): below 1 the two agree "
             "within what the tolerance certifies. To reference = the same distance of each to the static scenes' "
             "reference solution (the after build at -newton_tol %g): which of the two is nearer the solution." % (
                 datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
                 scenes.machine_line(RANKS), REFERENCE_TOL), ""]
    builds = set()
    rows = []
    head = ["## Before and after", "",
            "| scene | build | steps converged | Newton/step | solves/step | PCG/step | s/step | sub-steps | "
            "lifted solves (shortened) | time ratio | distance / tol | to reference / tol |",
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for label in SCENES:
        before, after = read_run(label, "before"), read_run(label, "after")
        if not before and not after:
            continue
        ratio, dist = time_ratio(before, after), "-"
        reference = read_run(label, "reference")
        to_reference = {}
        if ratio != "-":
            dist = distance_over_tol(before, after, label, after)
            if reference and reference.get("exit") == 0:
                for name, run in (("before", before), ("after", after)):
                    to_reference[name] = distance_over_tol(run, reference, label, after)
        for name, run in (("before", before), ("after", after)):
            if run and "build" in run:
                builds.add("%s: %s" % (name, run["build"]))
            rows.append("| %s | %s | %s | %s | %s | %s | %s |" % (label, name, " | ".join(row_cells(run)),
                                                                   lifted_counts(run) if run and run.get("rows") else "-",
                                                                   ratio if name == "after" else "",
                                                                   dist if name == "after" else "",
                                                                   to_reference.get(name, "-")))
    if rows:
        lines += head + rows + ["", "Builds: " + "; ".join(sorted(builds)) + ".", ""]
    rows = []
    head = ["## Lifting every backward Euler step", "",
            "The dynamic rows with -lift_increments always (every step's increment lifted; the default auto lifts a "
            "backward Euler step only where its supports moved alone would fail the alpha safeguard).", "",
            "| scene | lifting | steps converged | Newton/step | solves/step | PCG/step | s/step | sub-steps |",
            "|---|---|---:|---:|---:|---:|---:|---:|"]
    for label in SCENES:
        run, default = read_run(label, "always"), read_run(label, "after")
        if run:
            rows.append("| %s | auto (default) | %s |" % (label, " | ".join(row_cells(default))))
            rows.append("| %s | always | %s |" % (label, " | ".join(row_cells(run))))
    if rows:
        lines += head + rows + [""]
    rows = []
    head = ["## The start of a backward Euler step", "",
            "Each backward Euler scene started from the prediction x_n + dt v_n alone (-predictor_acceleration "
            "false) and also from the extrapolation of the last step's acceleration, x_n + dt v_n + dt^2 a_n "
            "(-predictor_acceleration true, the default), each taken where its total potential is lower and the "
            "safeguard accepts it. Time ratio = s/step without / with; distance = the largest vertex distance "
            "between the two runs' final states over the Newton tolerance (1e-2 L dt).", "",
            "| scene | start | steps converged | Newton/step | solves/step | PCG/step | s/step | sub-steps | "
            "time ratio | distance / tol |",
            "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    predictor_builds = set()
    for label in SCENES:
        runs = [read_run(label, v) for v, _ in PREDICTOR_STARTS]
        if not any(runs):
            continue
        ratio = time_ratio(runs[0], runs[1])
        dist = distance_over_tol(runs[0], runs[1], label, runs[1]) if ratio != "-" else "-"
        for (variant, _), run in zip(PREDICTOR_STARTS, runs):
            if run and "build" in run:
                predictor_builds.add(run["build"])
            last = variant == PREDICTOR_STARTS[-1][0]
            rows.append("| %s | %s | %s | %s | %s |" % (label, PREDICTOR_NAMES[variant], " | ".join(row_cells(run)),
                                                         ratio if last else "", dist if last else ""))
    if rows:
        lines += head + rows + ["", "Builds: " + "; ".join(sorted(predictor_builds)) + ".", ""]
    rows = []
    head = ["## Hessian filters (after build)", "",
            "Each scene with each element Hessian filter (-psd_projection, each with the unfiltered Hessian after "
            "full-length updates, -newton_exact_hessian, on by default), and the default filter without it; the "
            "default filters are abs for static solves and clamp for backward Euler.", "",
            "| scene | filter | steps converged | Newton/step | solves/step | PCG/step | s/step | sub-steps |",
            "|---|---|---:|---:|---:|---:|---:|---:|"]
    for label in FILTER_SCENES:
        for f in FILTERS:
            run = read_run(label, "filter_" + slug(f))
            if run:
                rows.append("| %s | %s | %s |" % (label, f, " | ".join(row_cells(run))))
    if rows:
        lines += head + rows + [""]
    scenes.write(a.out, lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], usage=__doc__.split("\n\n")[1])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--before", default=None)
    r.add_argument("--after", default=os.path.join(ROOT, "build", "aries"))
    r.add_argument("--groups", default="lifting,filters,reference,always")
    r.add_argument("--only", default=None)
    r.add_argument("--timeout", type=int, default=4 * 3600)
    p = sub.add_parser("report")
    p.add_argument("--out", default=OUT)
    a = ap.parse_args()
    cmd_run(a) if a.cmd == "run" else cmd_report(a)


if __name__ == "__main__":
    main()
