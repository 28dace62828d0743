#!/usr/bin/env python3
"""Scale-out measurements (issue: parallel input, collective output, the linear solver at size).

  /usr/bin/python3 bench/scale_out.py io [--aries BIN] [--size s2m] [--ranks 1,2] [--formats msh,h5]
      The cube of meshes/generate.sh cube SIZE (s2m: 2,058,000 tets; its HDF5 copy from generate.sh h5), clamped at
      the bottom, one static step that starts converged (CG + Jacobi, so the memory is the mesh's and the output's,
      not a multigrid hierarchy's), -output_fields all: per rank count and input format the
      run's resource line (setup, output of the two written steps, peak RSS of every rank) and the size of the files.
  /usr/bin/python3 bench/scale_out.py solvers [--aries BIN] [--sizes mid,default,fine,s1m] [--ranks 2]
                                              [--solvers jacobi,gamg,hypre] [--scene static|dynamic]
      Compression of the unit cube (iarap, E 1e4, nu 0.3, clamped bottom and top, the top moved down by 0.1): static
      in 2 load steps, or dynamic (backward Euler, dt 1e-2, density 1000, the motion ramped over 50 steps, the first 3
      steps). Newton, PCG per Newton, the steps' wall time, the share of it in the model's evaluations (the rest is
      the linear solves) and s per Newton, per preconditioner and size.

  /usr/bin/python3 bench/scale_out.py agree [--size s1m] [--ranks 1,2]
      The static compression above with the default solver (the rule's) and -output on each rank count: the largest
      distance between the final positions over L, against the first rank count.
  /usr/bin/python3 bench/scale_out.py report
      docs/scale_out.md and its chart docs/images/results/scale_out.png from the logs the runs above left in
      out/scale_out/ (every number in the page is read from a log; the page names the machine and the commit).

Every run's command line and log go to out/scale_out/; the tables go to stdout (markdown). The machine is named in the
header line: quote it with the numbers."""
import argparse
import os
import platform
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "out", "scale_out")
RESOURCES = re.compile(r"aries: wall time setup ([\d.]+) s, steps ([\d.]+) s \(model evaluations ([\d.]+) s\), "
                       r"output ([\d.]+) s; peak memory per rank (.*) MB")
SUMMARY = re.compile(r"aries: (\d+) steps, (\d+) DoFs: Newton ([\d.]+)/step, PCG ([\d.]+)/step")

SOLVERS = {  # the paper's configuration; GAMG by the rule (ex56's smoothed aggregation) and by hand (lagged 2: the
    # rule's -multigrid_reuse_growth is aries' own, for GAMG by the rule only); BoomerAMG
    "jacobi": ["-pc_type", "jacobi"],
    "gamg": ["-multigrid_min_dofs", "0"],
    # the rule's GAMG by hand, for dynamic scenes (where the rule keeps Jacobi)
    "gamg_rule": ["-pc_type", "gamg", "-dm_mat_type", "aij", "-pc_gamg_type", "agg", "-pc_gamg_agg_nsmooths", "1",
                  "-pc_gamg_threshold", "0", "-pc_gamg_reuse_interpolation", "true", "-mg_levels_ksp_max_it", "1",
                  "-snes_lag_preconditioner", "2"],
    # PETSc's snes ex56 set-up (threshold 0.05, two Chebyshev steps per level): the rule's first set-up
    "gamg_ex56": ["-pc_type", "gamg", "-dm_mat_type", "aij", "-pc_gamg_type", "agg", "-pc_gamg_agg_nsmooths", "1",
                  "-pc_gamg_threshold", "0.05", "-pc_gamg_reuse_interpolation", "true", "-snes_lag_preconditioner",
                  "2"],
    # BoomerAMG with nodal coarsening (block size 3). The rigid modes as interpolation vectors
    # (-pc_hypre_boomeramg_vec_interp_variant 3) crash in PETSc 3.18.5 + Debian's hypre (SEGV in the setup); variants 1
    # and 2 run but cost 7x the setup on the 10k-tet cube, so none is used here.
    "hypre": ["-pc_type", "hypre", "-pc_hypre_type", "boomeramg", "-dm_mat_type", "aij",
              "-pc_hypre_boomeramg_nodal_coarsen", "6", "-pc_hypre_boomeramg_strong_threshold", "0.5"],
}


def env():
    e = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
             OMPI_MCA_rmaps_base_oversubscribe="1")
    return e


def mesh(name, size, h5=False):
    cmd = [os.path.join(ROOT, "meshes", "generate.sh")] + (["h5"] if h5 else []) + [name, size]
    p = subprocess.run(cmd, capture_output=True, text=True, env=dict(env(), ARIES_BIN=ARGS.aries))
    if p.returncode != 0:
        sys.exit("mesh %s %s failed: %s" % (name, size, p.stderr[-2000:]))
    return p.stdout.strip().splitlines()[-1]


def run(tag, ranks, args):
    os.makedirs(OUT, exist_ok=True)
    cmd = ["mpiexec", "--quiet", "-n", str(ranks), "--bind-to", "none", ARGS.aries] + args
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env())
    wall = time.time() - t0
    log = p.stdout + p.stderr
    with open(os.path.join(OUT, tag + ".log"), "w") as fh:
        fh.write("$ " + " ".join(cmd) + "\n# machine: %s\n" % machine() + log)
    if p.returncode != 0:
        sys.exit("%s failed (exit %d):\n%s" % (tag, p.returncode, log[-3000:]))
    m = RESOURCES.search(log)
    s = SUMMARY.search(log)
    return {"setup": float(m.group(1)), "steps": float(m.group(2)), "evaluations": float(m.group(3)),
            "output": float(m.group(4)), "rss": m.group(5), "wall": wall,
            "newton": float(s.group(3)) if s else None, "pcg": float(s.group(4)) if s else None,
            "dofs": int(s.group(2)) if s else None, "log": log}


def du(path):
    total = 0
    for d, _, names in os.walk(path):
        total += sum(os.path.getsize(os.path.join(d, n)) for n in names)
    return total


def machine():
    return "%s, %d cores" % (platform.node(), os.cpu_count())


def header():
    return "machine: %s; aries %s" % (machine(), ARGS.aries)


def case_io():
    print(header())
    print()
    print("| input | ranks | setup s | output s (2 steps) | peak RSS per rank MB | step file MB |")
    print("|---|---|---|---|---|---|")
    for fmt in ARGS.formats.split(","):
        m = mesh("cube", ARGS.size, h5=(fmt == "h5"))
        for n in (int(r) for r in ARGS.ranks.split(",")):
            tag = "io_%s_%s_np%d" % (ARGS.size, fmt, n)
            base = os.path.join(OUT, tag, "run")
            r = run(tag, n, ["-dm_plex_filename", m, "-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-bc_clamp",
                             "bottom", "-integrator", "static", "-steps", "1", "-pc_type", "jacobi", "-output", base,
                             "-output_fields", "all"])
            step = os.path.join(OUT, tag, "run.steps", "run_000001.h5")
            print("| %s | %d | %.1f | %.1f | %s | %.0f |" % (fmt, n, r["setup"], r["output"], r["rss"],
                                                            os.path.getsize(step) / 2 ** 20), flush=True)


def case_solvers():
    print(header())
    print()
    print("scene: %s" % ARGS.scene)
    print()
    print("| cube | tets | DoFs | ranks | preconditioner | Newton/step | PCG/Newton | steps wall s | of it solves s | "
          "s/Newton |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    scene = {"static": ["-integrator", "static", "-steps", "2"],
             "dynamic": ["-integrator", "beuler", "-dt", "1e-2", "-density", "1000", "-steps", "3", "-bc_ramp_steps",
                         "50"]}[ARGS.scene]
    for size in ARGS.sizes.split(","):
        m = mesh("cube", size)
        for n in (int(r) for r in ARGS.ranks.split(",")):
            for solver in ARGS.solvers.split(","):
                tag = "solver_%s_%s_%s_np%d" % (ARGS.scene, size, solver, n)
                r = run(tag, n, ["-dm_plex_filename", m, "-energy", "iarap", "-E", "1e4", "-nu", "0.3",
                                 "-bc_clamp", "bottom,top", "-bc_clamp_top_translate", "0,0,-0.1",
                                 "-ksp_converged_reason"] + scene + SOLVERS[solver])
                tets = re.search(r"(\d+) cells", r["log"]).group(1)
                steps = int(scene[scene.index("-steps") + 1])
                newton = r["newton"] * steps
                unconverged = len(re.findall(r"Linear solve did not converge", r["log"]))
                print("| %s | %s | %d | %d | %s%s | %.1f | %.0f | %.1f | %.1f | %.2f |" % (
                    size, tets, r["dofs"], n, solver, " (%d unconverged solves)" % unconverged if unconverged else "",
                    r["newton"], r["pcg"] / max(r["newton"], 1e-9), r["steps"], r["steps"] - r["evaluations"],
                    r["steps"] / max(newton, 1e-9)), flush=True)


def case_agree():
    import h5py
    import numpy as np
    m = mesh("cube", ARGS.size)
    states = []
    for n in (int(r) for r in ARGS.ranks.split(",")):
        tag = "agree_%s_np%d" % (ARGS.size, n)
        base = os.path.join(OUT, tag, "run")
        run(tag, n, ["-dm_plex_filename", m, "-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-bc_clamp", "bottom,top",
                     "-bc_clamp_top_translate", "0,0,-0.1", "-integrator", "static", "-steps", "2", "-output", base,
                     "-output_every", "2"])
        with h5py.File(base + ".steps/run_000002.h5", "r") as f:
            states.append((n, f["/positions"][()]))
        with h5py.File(base + ".h5", "r") as f:
            rest = f["/mesh/rest"][()]
    L = np.linalg.norm(rest.max(0) - rest.min(0))
    for n, x in states[1:]:
        print("cube %s static, %d vs %d ranks: max |x - x'| / L = %.2e" % (ARGS.size, states[0][0], n,
                                                                          np.abs(x - states[0][1]).max() / L))


def parse_log(path):
    """What one run's log says: its command line, the mesh header, the summary and resource lines."""
    text = open(path).read()
    cmd = text.splitlines()[0][2:] if text.startswith("$ ") else ""
    m, s = RESOURCES.search(text), SUMMARY.search(text)
    head = re.search(r"aries: \S+, (\d+) cells, (\d+) vertices .*?, (\d+) ranks", text)
    version = re.search(r"^aries \S+ \(git (\S+)\)", text, re.M)
    where = re.search(r"^# machine: (.*)$", text, re.M)
    if not (m and s and head):
        return None
    return {"cmd": cmd, "cells": int(head.group(1)), "ranks": int(head.group(3)), "setup": float(m.group(1)),
            "steps": float(m.group(2)), "evaluations": float(m.group(3)), "output": float(m.group(4)),
            "rss": m.group(5), "newton": float(s.group(3)), "pcg": float(s.group(4)), "dofs": int(s.group(2)),
            "nsteps": int(s.group(1)), "commit": version.group(1) if version else "?",
            "machine": where.group(1) if where else "%s, %d cores" % (platform.node(), os.cpu_count()),
            "unconverged": len(re.findall(r"Linear solve did not converge", text)),
            "gamg_by_rule": "aries: linear solver CG + GAMG" in text}


def case_report():
    import glob
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = {}
    for path in sorted(glob.glob(os.path.join(OUT, "*.log"))):
        r = parse_log(path)
        if r:
            runs[os.path.basename(path)[:-4]] = r
    commits = sorted({r["commit"] for r in runs.values()})
    lines = ["# Scale-out measurements", "",
             "Generated by `bench/scale_out.py report` from the logs of `bench/scale_out.py io` and `solvers` (see the "
             "script's docstring for the scenes); aries %s. One run each; the input/output table names each run's "
             "machine, the solver tables ran on %s." % (", ".join(commits), machine()), ""]
    io = [(k, r) for k, r in runs.items() if k.startswith("io_")]
    if io:
        lines += ["## Input and output at 2M tets", "",
                  "The cube `s2m` (2,058,000 tets, 357,911 vertices), one static step that starts converged, "
                  "`-output_fields all` (two step files written, the initial one and step 1): setup (options, mesh, "
                  "layout, files), output time and every rank's peak resident memory (with many ranks: min, median, "
                  "max and rank 0's). The machine column names where each run ran; rows of a lent 16-core machine ran "
                  "the same aries binary there, with this machine's Debian runtime carried along.", "",
                  "| machine | aries | input | ranks | setup s | output s | peak RSS per rank MB |",
                  "|---|---|---|---|---|---|---|"]
        for k, r in sorted(io, key=lambda kv: (kv[1]["machine"], kv[0].split("_")[2], kv[1]["ranks"])):
            lines.append("| %s | %s | %s | %d | %.1f | %.1f | %s |" % (r["machine"], r["commit"][:7], k.split("_")[2],
                                                                       r["ranks"], r["setup"], r["output"], r["rss"]))
        lines.append("")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, scene in zip(axes, ("static", "dynamic")):
        rows = [(k, r) for k, r in runs.items() if k.startswith("solver_%s_" % scene)]
        if not rows:
            continue
        lines += ["## Linear solvers, %s compression of the cube (2 ranks)" % scene, "",
                  "| tets | DoFs | preconditioner | aries | Newton/step | PCG/Newton | steps s | of it linear solves s | "
                  "s/Newton |", "|---|---|---|---|---|---|---|---|---|"]
        series = {}
        for k, r in sorted(rows, key=lambda kv: (kv[1]["dofs"], kv[0])):
            solver = {"gamg_rule": "gamg"}.get("_".join(k.split("_")[3:-1]), "_".join(k.split("_")[3:-1]))
            newton_total = max(r["newton"] * r["nsteps"], 1e-9)
            label = solver + (" (rule)" if r["gamg_by_rule"] else "")
            lines.append("| %d | %d | %s%s | %s | %.1f | %.0f | %.1f | %.1f | %.2f |" % (
                r["cells"], r["dofs"], label, " (%d unconverged)" % r["unconverged"] if r["unconverged"] else "",
                r["commit"][:7],
                r["newton"], r["pcg"] / max(r["newton"], 1e-9), r["steps"], r["steps"] - r["evaluations"],
                r["steps"] / newton_total))
            series.setdefault(solver, []).append((r["dofs"], r["steps"] / newton_total))
        lines.append("")
        for solver, pts in sorted(series.items()):
            pts.sort()
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=solver)
        ax.set_xlabel("free DoFs")
        ax.set_ylabel("wall s per Newton iteration (2 ranks)")
        ax.set_title("%s compression" % scene)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    os.makedirs(os.path.join(ROOT, "docs", "images", "results"), exist_ok=True)
    fig.tight_layout()
    fig.savefig(os.path.join(ROOT, "docs", "images", "results", "scale_out.png"), dpi=110)
    lines += ["![seconds per Newton iteration against the number of free DoFs](images/results/scale_out.png)", ""]
    with open(os.path.join(ROOT, "docs", "scale_out.md"), "w") as fh:
        fh.write("\n".join(lines))
    print("wrote docs/scale_out.md and docs/images/results/scale_out.png from %d runs" % len(runs))


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["io", "solvers", "agree", "report"])
    ap.add_argument("--aries", default=os.path.join(ROOT, "build", "aries"))
    ap.add_argument("--size", default=None)
    ap.add_argument("--sizes", default="mid,default,fine,s1m")
    ap.add_argument("--scene", default="static", choices=["static", "dynamic"])
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--formats", default="msh,h5")
    ap.add_argument("--solvers", default="jacobi,gamg,hypre")
    ARGS = ap.parse_args()
    ARGS.aries = os.path.abspath(ARGS.aries)
    if ARGS.size is None:
        ARGS.size = "s1m" if ARGS.what == "agree" else "s2m"
    {"io": case_io, "solvers": case_solvers, "agree": case_agree, "report": case_report}[ARGS.what]()
