#!/usr/bin/env python3
"""Table-1-style rows for the volumetric scenes at the paper's sizes, beside the paper's numbers.

usage: bench/scenes.py [--steps K] [--ranks N] [--build DIR] [--out FILE.md] [SCENE ...]

Runs each scene's options file (options/*.yml, meshes generated on demand) with its paper-size mesh and writes a
markdown table: elements, E, nu, dt, steps, Newton/step, PCG/step, s/step for aries and for the paper (Table 1;
20-core 3.8 GHz i9, Eigen PCG + Jacobi). --steps K runs only the first K steps of each scene (the averages are then
over those steps, stated in the table); without it every scene runs its full length (hours on 2 cores for the
largest). Default output: bench/results/table1.md. Use /usr/bin/python3 (Debian's).
"""
import argparse
import csv
import datetime
import json
import os
import platform
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# scene name -> (options file, extra options, mesh (name, size), paper row: elems, E, nu, dt, steps, newton, pcg, s)
SCENES = {
    "cube_ortho_compress": ("cube_ortho_compress", [], ("cube", "default"), (54985, 1e3, 0.3, 1e-2, 50, 1.9, 906.3, 0.41)),
    "cube_ortho_pull": ("cube_ortho_pull", [], ("cube", "default"), (34992, 1e3, 0.3, 1e-2, 50, 1.5, 874.7, 0.38)),
    "armadillo_scramble": ("armadillo_scramble", [], ("armadillo", "default"), (34992, 1e5, 0.0, 1e-2, 2000, 2.8, 411.3, 0.71)),
    "bunny_inside_out": ("bunny_inside_out", [], ("bunny", "paper"), (637584, 1e4, 0.0, 1e-2, 200, 26.0, 15663.6, 128.76)),
    "cylinder_compress_nu0": ("cylinder_compress", ["-nu", "0"], ("cylinder", "default"), (17840, 1e4, 0.0, 1e-2, 100, 1.3, 490.6, 0.16)),
    "cylinder_compress_nu0.3": ("cylinder_compress", ["-nu", "0.3"], ("cylinder", "default"), (17840, 1e4, 0.3, 1e-2, 100, 1.4, 644.8, 0.18)),
    "cylinder_compress_nu0.49": ("cylinder_compress", ["-nu", "0.49"], ("cylinder", "default"), (17840, 1e4, 0.49, 1e-2, 100, 1.8, 2509.4, 0.31)),
    "cylinder_pull_nu0": ("cylinder_pull", ["-nu", "0"], ("cylinder", "default"), (17840, 1e4, 0.0, 1e-2, 200, 1.6, 544.7, 0.18)),
    "cylinder_pull_nu0.3": ("cylinder_pull", ["-nu", "0.3"], ("cylinder", "default"), (17840, 1e4, 0.3, 1e-2, 200, 1.8, 775.8, 0.22)),
    "cylinder_pull_nu0.49": ("cylinder_pull", ["-nu", "0.49"], ("cylinder", "default"), (17840, 1e4, 0.49, 1e-2, 200, 3.1, 3685.7, 0.44)),
    "octopus_iso": ("octopus_iso", [], ("octopus", "default"), (308200, 1e3, 0.0, 1e-2, 400, 3.5, 1738.9, 8.54)),
    "octopus_fiber": ("octopus_fiber", [], ("octopus", "default"), (308200, 1e3, 0.0, 1e-2, 400, 3.8, 24010.2, 53.02)),
    "octopus_stiff": ("octopus_stiff", [], ("octopus", "default"), (308200, 1e5, 0.0, 1e-2, 400, 1.0, 4980.3, 12.61)),
}


def generate(name, size):
    out = subprocess.run([os.path.join(ROOT, "meshes", "generate.sh"), name, size], capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("mesh generation failed: " + out.stderr[-2000:])
    return out.stdout.strip().splitlines()[-1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "table1.md"))
    ap.add_argument("--work", default=os.path.join(ROOT, "out", "bench"))
    a = ap.parse_args()
    names = a.scenes or list(SCENES)
    for n in names:
        if n not in SCENES:
            sys.exit("unknown scene %s (known: %s)" % (n, ", ".join(SCENES)))
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")
    if os.geteuid() == 0:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    rows = []
    for n in names:
        opts, extra, (mname, msize), paper = SCENES[n]
        msh = generate(mname, msize)
        with open(msh[:-4] + ".json") as fh:
            elems = json.load(fh)["tets"]
        work = os.path.join(a.work, n)
        os.makedirs(work, exist_ok=True)
        stats = os.path.join(work, "stats.csv")
        args = ["-options_file", os.path.join(ROOT, "options", opts + ".yml"), "-dm_plex_filename", msh] + extra
        if "fiber" in opts:
            args += ["-fiber_file", msh[:-4] + ".fibers"]
        args += ["-stats", stats, "-output", os.path.join(work, n), "-output_every", "1000000"]
        if a.steps:
            args += ["-steps", str(min(a.steps, paper[4])), "-bc_ramp_steps", str(paper[4])]
        cmd = ["mpiexec", "-n", str(a.ranks), "--bind-to", "none", os.path.join(a.build, "aries")] + args
        print("$ " + " ".join(cmd), flush=True)
        p = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True)
        with open(os.path.join(work, "log.txt"), "w") as fh:
            fh.write(p.stdout + p.stderr)
        summary = [l for l in (p.stdout + p.stderr).splitlines() if l.startswith("aries:")]
        print("\n".join(summary[-3:]), flush=True)
        with open(stats) as fh:
            st = list(csv.DictReader(fh))
        k = max(len(st), 1)
        newton = sum(int(r["newton_its"]) for r in st) / k
        pcg = sum(int(r["ksp_its"]) for r in st) / k
        secs = sum(float(r["wall_s"]) for r in st) / k
        E = re.search(r"^E:\s*(\S+)", open(os.path.join(ROOT, "options", opts + ".yml")).read(), re.M).group(1)
        nu = extra[1] if extra else re.search(r"^nu:\s*(\S+)", open(os.path.join(ROOT, "options", opts + ".yml")).read(), re.M).group(1)
        failed = sum(1 for r in st if r["reason"].startswith(("diverged", "safeguard")))
        rows.append((n, elems, E, nu, paper, len(st), newton, pcg, secs, failed))
    cpu = "?"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    out = ["# Table 1: volumetric scenes, aries vs the paper\n",
           "Generated by `bench/scenes.py%s` on %s, %d MPI ranks on %s (%d cores); %s. Paper: 20-core 3.8 GHz i9, "
           "Eigen PCG + diagonal preconditioner, same Newton tolerance (1e-2 L dt) and PCG tolerance (1e-6).\n"
           % (" --steps %d" % a.steps if a.steps else "", datetime.date.today().isoformat(), a.ranks, cpu,
              os.cpu_count(), platform.platform()),
           "| scene | elements | E | nu | dt | steps run / total | Newton/step | PCG/step | s/step | failed steps | paper: elements | Newton/step | PCG/step | s/step |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for n, elems, E, nu, paper, steps, newton, pcg, secs, failed in rows:
        out.append("| %s | %s | %s | %s | %g | %d / %d | %.2f | %.1f | %.3f | %d | %d | %.1f | %.1f | %.2f |"
                   % (n, elems, E, nu, paper[3], steps, paper[4], newton, pcg, secs, failed, paper[0], paper[5],
                      paper[6], paper[7]))
    out.append("")
    if a.steps:
        out.append("Averages are over the first %d steps of each scene (the prescribed motion keeps its full-length "
                   "ramp), not over the whole run.\n" % a.steps)
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out + ".tmp", "w") as fh:
        fh.write("\n".join(out))
    os.replace(a.out + ".tmp", a.out)
    print("wrote " + a.out)


if __name__ == "__main__":
    main()
