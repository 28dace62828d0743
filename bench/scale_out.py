#!/usr/bin/env python3
"""Scale-out measurements (issue: parallel input, collective output, the linear solver at size).

  /usr/bin/python3 bench/scale_out.py io [--aries BIN] [--size s2m] [--ranks 1,2] [--formats msh,h5]
      The cube of meshes/generate.sh cube SIZE (s2m: 2,058,000 tets; its HDF5 copy from generate.sh h5), clamped at
      the bottom, one static step that starts converged, -output_fields all: per rank count and input format the
      run's resource line (setup, output of the two written steps, peak RSS of every rank) and the size of the files.
  /usr/bin/python3 bench/scale_out.py solvers [--aries BIN] [--sizes default,fine,s1m] [--ranks 2]
                                              [--solvers jacobi,gamg,hypre]
      Static compression of the cube by 10 % in 2 load steps (iarap, E 1e4, nu 0.3): Newton, PCG per Newton and the
      steps' wall time per preconditioner and size.

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

SOLVERS = {  # the paper's configuration, and the multigrids as PETSc's snes ex56 sets GAMG up
    "jacobi": ["-pc_type", "jacobi"],
    "gamg": ["-pc_type", "gamg", "-dm_mat_type", "aij", "-pc_gamg_type", "agg", "-pc_gamg_agg_nsmooths", "1",
             "-pc_gamg_threshold", "0.05", "-pc_gamg_reuse_interpolation", "true", "-mg_levels_ksp_type",
             "chebyshev", "-mg_levels_pc_type", "jacobi", "-mg_levels_ksp_max_it", "2"],
    "hypre": ["-pc_type", "hypre", "-pc_hypre_type", "boomeramg", "-dm_mat_type", "aij",
              "-pc_hypre_boomeramg_nodal_coarsen", "6", "-pc_hypre_boomeramg_vec_interp_variant", "3",
              "-pc_hypre_boomeramg_strong_threshold", "0.5"],
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
        fh.write("$ " + " ".join(cmd) + "\n" + log)
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


def header():
    return "machine: %s, %d cores; aries %s" % (platform.node(), os.cpu_count(), ARGS.aries)


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
                             "bottom", "-integrator", "static", "-steps", "1", "-output", base, "-output_fields",
                             "all"])
            step = os.path.join(OUT, tag, "run.steps", "run_000001.h5")
            print("| %s | %d | %.1f | %.1f | %s | %.0f |" % (fmt, n, r["setup"], r["output"], r["rss"],
                                                            os.path.getsize(step) / 2 ** 20), flush=True)


def case_solvers():
    print(header())
    print()
    print("| cube | tets | DoFs | ranks | preconditioner | Newton/step | PCG/Newton | steps wall s | s/Newton |")
    print("|---|---|---|---|---|---|---|---|---|")
    for size in ARGS.sizes.split(","):
        m = mesh("cube", size)
        for n in (int(r) for r in ARGS.ranks.split(",")):
            for solver in ARGS.solvers.split(","):
                tag = "solver_%s_%s_np%d" % (size, solver, n)
                r = run(tag, n, ["-dm_plex_filename", m, "-energy", "iarap", "-E", "1e4", "-nu", "0.3",
                                 "-bc_clamp", "bottom,top", "-bc_clamp_top_translate", "0,0,-0.1", "-integrator",
                                 "static", "-steps", "2"] + SOLVERS[solver])
                tets = re.search(r"(\d+) cells", r["log"]).group(1)
                newton = r["newton"] * 2
                print("| %s | %s | %d | %d | %s | %.1f | %.0f | %.1f | %.2f |" % (
                    size, tets, r["dofs"], n, solver, r["newton"], r["pcg"] / max(r["newton"], 1e-9), r["steps"],
                    r["steps"] / max(newton, 1e-9)), flush=True)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["io", "solvers"])
    ap.add_argument("--aries", default=os.path.join(ROOT, "build", "aries"))
    ap.add_argument("--size", default="s2m")
    ap.add_argument("--sizes", default="default,fine,s1m")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--formats", default="msh,h5")
    ap.add_argument("--solvers", default="jacobi,gamg,hypre")
    ARGS = ap.parse_args()
    ARGS.aries = os.path.abspath(ARGS.aries)
    case_io() if ARGS.what == "io" else case_solvers()
