#!/usr/bin/python3
"""The compiler's cost and gain: GCC against clang on the same sources, the same machine, in one run.

usage: bench/compilers.py [--jobs N] [--repeat N] [--no-build] [--out docs/build.md]

Builds the whole project (every target of the README's test command: Release, the Python module) from an empty folder
with each compiler (out/compilers/gcc, out/compilers/clang; CC/CXX set, so CMakeLists.txt's choice is overridden), and
records the build's wall time and CPU time (every process of the build: cmake, make and the compilers); then runs a
few scenes with each build's aries, in turns (GCC, clang, GCC, ...), --repeat times each, and compares their wall
times pair by pair (the median of the clang/GCC ratios) and their Newton and PCG counts. Writes docs/build.md. Takes about 20 minutes on 2 cores.
--no-build times the scenes again with the builds of the last run (their times, jobs, compiler versions and commit:
out/compilers/builds.json).
"""
import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(ROOT, "ctest"))
import scenes  # noqa: E402  (mesh generation, machine line, commit line)
from harness import aries_cmd, mpi_env  # noqa: E402

WORK = os.path.join(ROOT, "out", "compilers")
COMPILERS = {"gcc": ("gcc", "g++"), "clang": ("clang", "clang++")}

# label -> (ranks, mesh (name, size) or None, options); every scene runs to its end with its own stats line.
SCENES = [
    ("armadillo_scramble, 3 steps", 2, ("armadillo", "default"), ["-options_file", "options/armadillo_scramble.yml",
                                                                   "-steps", "3"]),
    ("bunny_inside_out (35k tets), 10 steps", 2, ("bunny", "default"),
     ["-options_file", "options/bunny_inside_out.yml", "-steps", "10"]),
    ("box 125k tets compressed 10% (bench/peer.py), GAMG", 2, ("box", "default"),
     ["-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-integrator", "static", "-steps", "1", "-bc_clamp", "bottom,top",
      "-bc_clamp_top_translate", "0,0,-0.2", "-ksp_rtol", "1e-8", "-multigrid_min_dofs", "0"]),
    ("cloth_drop_ours, 20 steps", 1, ("cloth", "default"), ["-options_file", "options/cloth_drop_ours.yml", "-steps", "20"]),
]


def versions(cc):
    return subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()[0]


def build(name):
    """A clean build with compiler `name`: (wall s, CPU s of all child processes)."""
    cc, cxx = COMPILERS[name]
    folder = os.path.join(WORK, name)
    shutil.rmtree(folder, ignore_errors=True)
    env = dict(os.environ, CC=cc, CXX=cxx)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.monotonic()
    for cmd in (["cmake", "-S", ROOT, "-B", folder, "-DCMAKE_BUILD_TYPE=Release", "-DARIES_REQUIRE_PYTHON=ON"],
                ["cmake", "--build", folder, "-j", str(ARGS.jobs)]):
        out = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit("compilers.py: %s failed:\n%s" % (" ".join(cmd), (out.stdout + out.stderr)[-3000:]))
    wall = time.monotonic() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    print("%s: build %.1f s wall, %.1f s CPU" % (name, wall, cpu), flush=True)
    return wall, cpu


def run(name, ranks, opts):
    """One run of a scene with build `name`: (wall s, 'Newton x/step, PCG y/step')."""
    binary = os.path.join(WORK, name, "aries")
    outdir = os.path.join(WORK, "runs", name)
    os.makedirs(outdir, exist_ok=True)
    cmd = aries_cmd(binary, ranks, opts + ["-output", os.path.join(outdir, "scene")])
    start = time.monotonic()
    out = subprocess.run(cmd, cwd=ROOT, env=mpi_env(), capture_output=True, text=True)
    wall = time.monotonic() - start
    if out.returncode != 0:
        sys.exit("compilers.py: %s exited %d:\n%s" % (" ".join(cmd), out.returncode, (out.stdout + out.stderr)[-3000:]))
    m = re.search(r"Newton ([\d.]+)/step, PCG ([\d.]+)/step", out.stdout)
    return wall, ("Newton %s, PCG %s per step" % m.groups()) if m else "?"


def main():
    global ARGS
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--jobs", type=int, default=2, help="parallel build jobs (default 2)")
    ap.add_argument("--repeat", type=int, default=5, help="runs of each scene with each build (default 5)")
    ap.add_argument("--no-build", action="store_true", help="reuse the builds of the last run (out/compilers)")
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "build.md"))
    ARGS = ap.parse_args()
    for _, cxx in COMPILERS.values():
        if not shutil.which(cxx):
            sys.exit("compilers.py: %s is not installed (bash scripts/install-deps.sh installs both)" % cxx)
    started = time.monotonic()
    record_file = os.path.join(WORK, "builds.json")
    if ARGS.no_build:
        if not os.path.exists(record_file):
            sys.exit("compilers.py: --no-build: no builds of an earlier run (%s); run without --no-build" % record_file)
        record = json.load(open(record_file))
    else:
        record = {"builds": {name: build(name) for name in COMPILERS}, "jobs": ARGS.jobs,
                  "versions": [versions("g++"), versions("clang++")], "commit": scenes.commit_line(),
                  "when": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
        with open(record_file, "w") as fh:
            json.dump(record, fh)
    builds = record["builds"]
    rows = []
    for label, ranks, mesh, opts in SCENES:
        opts = list(opts)
        if mesh:
            opts += ["-dm_plex_filename", scenes.generate(*mesh)]
        for name in COMPILERS:  # warm-up: file caches, meshes
            run(name, ranks, opts)
        walls = {"gcc": [], "clang": []}
        counts = {}
        for _ in range(ARGS.repeat):
            for name in ("gcc", "clang"):
                wall, counts[name] = run(name, ranks, opts)
                walls[name].append(wall)
        ratios = [c / g for g, c in zip(walls["gcc"], walls["clang"])]
        rows.append((label, ranks, statistics.median(walls["gcc"]), statistics.median(walls["clang"]),
                     statistics.median(ratios), min(ratios), max(ratios), counts["gcc"], counts["clang"]))
        print("%s: GCC %.2f s, clang %.2f s, ratio %.3f" % (rows[-1][0:1] + rows[-1][2:5]), flush=True)
    (gw, gc), (cw, cc) = builds["gcc"], builds["clang"]
    lines = [
        "# Build: which compiler",
        "",
        "Generated by `/usr/bin/python3 bench/compilers.py%s` (%s; %s; %.0f min%s). CMakeLists.txt compiles with clang when it "
        "is installed with its sanitizer runtime and no compiler was chosen (`CC`/`CXX`, `-DCMAKE_CXX_COMPILER` or a "
        "toolchain file choose another; a build folder keeps the compiler it was configured with); "
        "scripts/install-deps.sh installs both. These figures are why."
        % (" --no-build" if ARGS.no_build else "", scenes.machine_line(ARGS.jobs).split(" on ", 1)[1],
           scenes.commit_line(), (time.monotonic() - started) / 60,
           ", the scenes; the builds: %s, %s" % (record["when"], record["commit"]) if ARGS.no_build else ""),
        "",
        "Compilers: %s; %s." % tuple(record["versions"]),
        "",
        "## The whole build from an empty folder (every target of `bash scripts/test.sh`, -j%d)" % record["jobs"],
        "",
        "| compiler | wall s | CPU s (cmake, make, compilers) |",
        "| --- | ---: | ---: |",
        "| GCC | %.0f | %.0f |" % (gw, gc),
        "| clang | %.0f | %.0f |" % (cw, cc),
        "| clang / GCC | %.2f | %.2f |" % (cw / gw, cc / gc),
        "",
        "## The solver, the same scene with each build (medians of %d runs each, in turns)" % ARGS.repeat,
        "",
        "Whole-process wall time. The ratio is the median of the runs' clang/GCC ratios, pair by pair (min-max in "
        "brackets). The counts say whether both builds took the same path (they may differ in the last digits: the "
        "compilers order floating-point operations differently).",
        "",
        "| scene | ranks | GCC s | clang s | clang / GCC | GCC counts | clang counts |",
        "| --- | ---: | ---: | ---: | ---: | --- | --- |",
    ]
    for label, ranks, g, c, r, lo, hi, ng, nc in rows:
        lines.append("| %s | %d | %.2f | %.2f | %.3f (%.3f-%.3f) | %s | %s |" % (label, ranks, g, c, r, lo, hi, ng, nc))
    lines.append("")
    scenes.write(ARGS.out, lines)


if __name__ == "__main__":
    main()
