#!/usr/bin/env python3
"""Nested iteration (-coarse_mesh) against the plain solve: Newton updates and wall time from degenerate starts.

  /usr/bin/python3 bench/nested.py scramble [--aries BIN] [--surfaces camel,hand,triceratops] [--seeds 1,2,3]
                                            [--ranks 2]
      The static scramble of the test suite (iarap, E 1e4, nu 0.3, every vertex in the bottom 10% of the rest box
      pinned, -initial scramble), one step, on each surface at two resolutions: the `test` mesh (1.8k-4.6k tets) with
      the `coarse` mesh as its coarse level, and the `default` mesh (17k-34k tets) with the `test` mesh. Each seed
      plain and nested: step 1's fine updates, the coarse levels' updates, the step's wall time (everything: coarse
      solves, interpolation, detached start) and the distance to rest (max |x - X| / L; the pins hold the rest shape,
      so rest is the solution).
  /usr/bin/python3 bench/nested.py inside_out [--aries BIN] [--sizes default] [--steps 20] [--ranks 2]
                                              [--coarse-steps 1] [--variants plain,nested]
      options/bunny_inside_out.yml (paper Fig. 5 settings) on the bunny of each size, plain and with the next smaller
      bunny as the coarse level (paper: default; default: test): updates and wall time per step.
  /usr/bin/python3 bench/nested.py scaling [--aries BIN] [--sizes test,default] [--ranks 2]
      Why the inside-out counts grow with the mesh: steps 1-3 of options/bunny_inside_out.yml on each size, with the
      density set so that the cell-scale ratio of stiffness to inertia, kappa = E dt^2 / (rho h^2) (h: the mesh's
      target edge length), takes each value the test, default and paper bunnies have at the scene's density.
  /usr/bin/python3 bench/nested.py load [--aries BIN] [--load-steps 1,2,4] [--ranks 2]
      A smooth static problem from rest: options/cylinder_compress.yml made static (the top moved down by 0.6, 30% of
      the height) in 1, 2 or 4 load steps on the 17.8k-tet cylinder, plain and with the 1.8k-tet one as the coarse
      level of every step (the static default, -coarse_steps -1): updates and wall time over all load steps.
  /usr/bin/python3 bench/nested.py report
      docs/nested.md from the stats files the runs above left in out/nested/ (every number is read from them; the
      page names the machine and the aries build of each run).

Every run's command line, log and stats go to out/nested/."""
import argparse
import csv
import glob
import os
import platform
import re
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "out", "nested")
SMALLER = {"paper": "default", "fig15": "default", "default": "test", "test": "coarse"}
PER_STEP_ROWS = 20  # steps listed one by one; a longer run adds a row for the rest
CONVERGED = ("newton_step", "converged_initial", "step_bound", "energy_roundoff")
INSIDE_OUT_SCENE = os.path.join(ROOT, "options", "bunny_inside_out.yml")


def env():
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1")


def machine():
    try:
        with open("/proc/cpuinfo") as fh:
            model = next(l.split(":", 1)[1].strip() for l in fh if l.startswith("model name"))
    except (OSError, StopIteration):
        model = platform.processor() or "unknown cpu"
    return "%s, %d cores, %s" % (model, os.cpu_count() or 0, platform.node())


def mesh(name, size):
    p = subprocess.run([os.path.join(ROOT, "meshes", "generate.sh"), name, size], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("meshes/generate.sh %s %s failed: %s" % (name, size, p.stderr[-2000:]))
    return p.stdout.strip().splitlines()[-1]


def run(tag, args):
    """Runs aries with -stats out/nested/TAG.csv; returns the stats rows."""
    os.makedirs(OUT, exist_ok=True)
    base = os.path.join(OUT, tag)
    cmd = ["mpiexec", "--quiet", "-n", str(ARGS.ranks), "--bind-to", "none", ARGS.aries] + args + [
        "-stats", base + ".csv", "-output", base, "-output_every", "1000000"]
    print("$ " + " ".join(cmd), flush=True)
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env())
    with open(base + ".log", "w") as fh:
        fh.write("$ %s\n# machine: %s\n# wall %.2f s\n%s%s" % (" ".join(cmd), machine(), time.time() - t0,
                                                             p.stdout, p.stderr))
    if p.returncode not in (0, 3):
        sys.exit("run %s failed (exit %d): %s" % (tag, p.returncode, (p.stdout + p.stderr)[-2000:]))
    return rows(base + ".csv")


def rows(path):
    with open(path) as fh:
        return list(csv.DictReader(l for l in fh if not l.startswith("#")))


def box_args(msh):
    import json
    with open(msh[:-4] + ".json") as fh:
        meta = json.load(fh)
    lo, hi = meta["bbox_min"], meta["bbox_max"]
    box = "%g,%g,%g,%g,%g,%g" % (lo[0] - 1, hi[0] + 1, lo[1] - 1, hi[1] + 1, lo[2] - 1, lo[2] + 0.1 * (hi[2] - lo[2]))
    return ["-bc_box", box]


def distance_to_rest(base):
    import h5py
    with h5py.File(base + ".h5", "r") as f:
        rest = f["/mesh/rest"][:]
    last = sorted(glob.glob(base + ".steps/*.h5"))[-1]
    with h5py.File(last, "r") as f:
        x = f["/positions"][:]
    return float(np.abs(x - rest).max() / np.linalg.norm(rest.max(0) - rest.min(0)))


def cmd_scramble():
    for surface in ARGS.surfaces.split(","):
        for size in ("test", "default"):
            fine, coarse = mesh(surface, size), mesh(surface, SMALLER[size])
            for seed in ARGS.seeds.split(","):
                args = ["-dm_plex_filename", fine, "-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-integrator",
                        "static", "-steps", "1", "-initial", "scramble", "-scramble_seed", seed] + box_args(fine)
                for variant, extra in (("plain", []), ("nested", ["-coarse_mesh", coarse])):
                    tag = "scramble_%s_%s_s%s_%s" % (surface, size, seed, variant)
                    r = run(tag, args + extra)[0]
                    d = distance_to_rest(os.path.join(OUT, tag))
                    with open(os.path.join(OUT, tag + ".rest"), "w") as fh:
                        fh.write("%.6e\n" % d)
                    print("%s: fine %s, coarse %s, %.2f s, %s, %.2e L" % (tag, r["newton_its"], r["coarse_newton_its"],
                                                                         float(r["wall_s"]), r["reason"], d))


def cmd_inside_out():
    scene = INSIDE_OUT_SCENE
    for size in (ARGS.sizes or "default").split(","):
        fine, coarse = mesh("bunny", size), mesh("bunny", SMALLER[size])
        args = ["-options_file", scene, "-dm_plex_filename", fine, "-steps", str(ARGS.steps)]
        for variant, extra in (("plain", []), ("nested", ["-coarse_mesh", coarse, "-coarse_steps",
                                                          str(ARGS.coarse_steps)])):
            if variant not in ARGS.variants.split(","):
                continue
            tag = "inside_out_%s_%s" % (size, variant if variant == "plain" else "nested%d" % ARGS.coarse_steps)
            rs = run(tag, args + extra)
            print("%s: fine %s" % (tag, [int(r["newton_its"]) for r in rs]))


SCALING_SIZES = ("test", "default", "paper")
SCALING_STEPS = 3


def scene_value(key):
    """A number of options/bunny_inside_out.yml (E, dt, density)."""
    text = open(INSIDE_OUT_SCENE).read()
    return float(re.search(r"^%s:\s*(\S+)" % key, text, re.M).group(1))


def kappa(h, density):
    """The cell-scale ratio of stiffness to inertia in a backward Euler step, E dt^2 / (rho h^2)."""
    return scene_value("E") * scene_value("dt") ** 2 / (density * h * h)


def mesh_h(size):
    """The bunny mesh's target edge length (meshes/cache/bunny_SIZE.json); None where that mesh was not generated."""
    import json
    path = os.path.join(ROOT, "meshes", "cache", "bunny_%s.json" % size)
    if not os.path.exists(path):
        return None
    with open(path) as fh:
        return float(json.load(fh)["provenance"]["h"])


def cmd_scaling():
    scene = INSIDE_OUT_SCENE
    rho = scene_value("density")
    for other in SCALING_SIZES:  # every size's h is needed (the paper mesh: generated once, ~30 s)
        mesh("bunny", other)
    for size in (ARGS.sizes or "test,default").split(","):
        fine = mesh("bunny", size)
        for other in SCALING_SIZES:  # kappa of each bunny at the scene's density, reached on this one
            density = rho * mesh_h(other) ** 2 / mesh_h(size) ** 2
            tag = "scaling_%s_kappa_%s" % (size, other)
            rs = run(tag, ["-options_file", scene, "-dm_plex_filename", fine, "-steps", str(SCALING_STEPS),
                           "-density", "%.6g" % density])
            print("%s: density %.4g, kappa %.3g, updates %s" % (tag, density, kappa(mesh_h(size), density),
                                                              [int(r["newton_its"]) for r in rs]))


def cmd_load():
    fine, coarse = mesh("cylinder", "default"), mesh("cylinder", "test")
    for n in ARGS.load_steps.split(","):
        args = ["-options_file", os.path.join(ROOT, "options", "cylinder_compress.yml"), "-dm_plex_filename", fine,
                "-integrator", "static", "-steps", n]
        for variant, extra in (("plain", []), ("nested", ["-coarse_mesh", coarse])):
            rs = run("load_cylinder_%s_%s" % (n, variant), args + extra)
            print("%s steps %s: fine %s" % (n, variant, [int(r["newton_its"]) for r in rs]))


def log_header(tag):
    with open(os.path.join(OUT, tag + ".log")) as fh:
        text = fh.read()
    m = re.search(r"# machine: (.*)", text)
    v = re.search(r"aries \S+ \(git (\S+)\)", text)
    return (m.group(1) if m else "?"), (v.group(1) if v else "?")


def scaling_section(machines, builds):
    """The table of `scaling`: steps 1-3 per mesh and kappa; a mesh's own kappa at the scene's density may come from
    its 20-step plain run of `inside_out` instead (the paper-size mesh, whose runs are long)."""
    cells, ranks = {}, set()
    found = {}  # (size, kappa of) -> the first steps' stats rows (a run that wrote no row is left out)
    for size in SCALING_SIZES:
        for other in SCALING_SIZES:
            tag = "scaling_%s_kappa_%s" % (size, other)
            if not os.path.exists(os.path.join(OUT, tag + ".csv")) and other == size:
                tag = "inside_out_%s_plain" % size
            stats = rows(os.path.join(OUT, tag + ".csv")) if os.path.exists(os.path.join(OUT, tag + ".csv")) else []
            if not stats:
                continue
            found[(size, other)] = stats[:SCALING_STEPS]
            log = open(os.path.join(OUT, tag + ".log")).read()
            m = re.search(r"(\d+) cells", log)
            cells[size] = m.group(1) if m else "?"
            m = re.search(r"(\d+) ranks", log)
            ranks.add(m.group(1) if m else "?")
            m, b = log_header(tag)
            machines.add(m)
            builds.add(b)
    if not any(k[0] != k[1] for k in found):
        return []
    rho = scene_value("density")
    kappa_of = lambda size: "%.2f" % kappa(mesh_h(size), rho) if mesh_h(size) else "?"
    h_of = lambda size: "%g" % mesh_h(size) if mesh_h(size) else "?"
    lines = ["## Why the inside-out counts grow with the mesh", "",
             "options/bunny_inside_out.yml, steps 1-%d, plain, %s ranks (`bench/nested.py scaling`). A backward Euler "
             "step weighs each cell's stiffness against its inertia by kappa = E dt^2 / (rho h^2) (h: the mesh's target "
             "edge length): refining at a fixed dt raises it. Each mesh runs at the kappa of each bunny at the scene's "
             "density %g (the density changed, the tolerance not). Updates of steps 1, 2, 3; a mesh at its own kappa "
             "is the scene as shipped (without a `scaling` run there: steps 1-%d of its `inside_out` plain run); a step that did not converge counts in its column as run." % (
                 SCALING_STEPS, "/".join(sorted(ranks)), rho, SCALING_STEPS), "",
             "| mesh | cells | h | " + " | ".join("kappa %s (%s)" % (kappa_of(o), o) for o in SCALING_SIZES) + " |",
             "|---|---|---|" + "---|" * len(SCALING_SIZES)]
    bad = []
    for size in SCALING_SIZES:
        if size not in cells:
            continue
        row = []
        for other in SCALING_SIZES:
            rs = found.get((size, other))
            row.append(" / ".join(r["newton_its"] for r in rs) if rs else "-")
            bad += ["%s at kappa of %s, step %s" % (size, other, r["step"]) for r in rs or []
                    if r["reason"] not in CONVERGED]
        lines.append("| %s | %s | %s | %s |" % (size, cells[size], h_of(size), " | ".join(row)))
    step1 = lambda size, other: int(found[(size, other)][0]["newton_its"])
    by_kappa = ["kappa %s: %s" % (kappa_of(o), ", ".join(
        "%d (%s)" % (step1(sz, o), sz) for sz in SCALING_SIZES if (sz, o) in found)) for o in SCALING_SIZES
        if sum((sz, o) in found for sz in SCALING_SIZES) > 1]
    by_mesh = ["%s %d-%d" % (sz, min(step1(sz, o) for o in SCALING_SIZES if (sz, o) in found),
                             max(step1(sz, o) for o in SCALING_SIZES if (sz, o) in found)) for sz in SCALING_SIZES
               if sum((sz, o) in found for o in SCALING_SIZES) > 1]
    lines += ["", "Step 1 at one kappa, coarse to fine mesh: %s. Step 1 on one mesh over the kappas: %s." % (
        "; ".join(by_kappa), ", ".join(by_mesh)), "",
        "Every step converged." if not bad else "Not converged: %s." % "; ".join(bad), ""]
    return lines


def cmd_report():
    lines = ["# Nested iteration: measured", "",
             "Generated by `bench/nested.py report` from the runs of `bench/nested.py scramble`, `load`, `inside_out` "
             "and `scaling` (logs and stats in out/nested/). Step wall times include everything the step did: the coarse "
             "levels' solves, the interpolations, the detached start. What the nested iteration is: docs/options.md "
             "(Nested iteration).", ""]
    machines, builds = set(), set()
    scramble = sorted(glob.glob(os.path.join(OUT, "scramble_*_plain.csv")))
    if scramble:
        lines += ["## Static scramble, step 1", "",
                  "iarap, E 1e4, nu 0.3, the bottom 10% of the rest box pinned, `-initial scramble`, 2 ranks. Fine "
                  "updates / coarse updates / wall time of step 1, and the distance to rest at its end.", "",
                  "| surface | fine mesh (tets) | coarse mesh (tets) | seed | plain: updates | plain: s | nested: fine "
                  "+ coarse updates | nested: s | time ratio | distance to rest plain / nested (L) |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for plain in scramble:
            tag = os.path.basename(plain)[:-len("_plain.csv")]
            nested = os.path.join(OUT, tag + "_nested.csv")
            if not os.path.exists(nested):
                continue
            _, surface, size, seed = tag.split("_", 3)
            p, n = rows(plain)[0], rows(nested)[0]
            dp = open(os.path.join(OUT, tag + "_plain.rest")).read().strip()
            dn = open(os.path.join(OUT, tag + "_nested.rest")).read().strip()
            for t in (tag + "_plain", tag + "_nested"):
                m, b = log_header(t)
                machines.add(m)
                builds.add(b)
            cells = lambda s: re.search(r"(\d+) cells", open(os.path.join(OUT, tag + s + ".log")).read()).group(1)
            coarse_cells = re.search(r"level 1: \S+, (\d+) cells", open(os.path.join(OUT, tag + "_nested.log")).read())
            note = lambda r: "" if r["reason"] in CONVERGED else " (%s)" % r["reason"]
            lines.append("| %s | %s %s | %s %s | %s | %s%s | %.2f | %s + %s%s | %.2f | %.1fx | %.1e / %.1e |" % (
                surface, size, cells("_plain"), SMALLER[size], coarse_cells.group(1) if coarse_cells else "?",
                seed[1:], p["newton_its"], note(p), float(p["wall_s"]), n["newton_its"], n["coarse_newton_its"],
                note(n), float(n["wall_s"]), float(p["wall_s"]) / float(n["wall_s"]), float(dp), float(dn)))
        lines.append("")
    load = sorted(glob.glob(os.path.join(OUT, "load_cylinder_*_plain.csv")),
                  key=lambda p: int(os.path.basename(p).split("_")[2]))
    if load:
        lines += ["## Static load steps from rest", "",
                  "options/cylinder_compress.yml made static: iarap, E 1e4, nu 0.3, bottom clamped, top moved down by "
                  "0.6 (30% of the height), on the 17.8k-tet cylinder; nested: the 1.8k-tet cylinder as the coarse "
                  "level of every load step (`-coarse_steps -1`, the static default). 2 ranks; sums over all load "
                  "steps.", "",
                  "| load steps | plain: updates | plain: s | nested: fine + coarse updates | nested: s | time ratio | "
                  "nested starts taken |", "|---|---|---|---|---|---|---|"]
        for plain in load:
            n = os.path.basename(plain).split("_")[2]
            nested = plain.replace("_plain.csv", "_nested.csv")
            if not os.path.exists(nested):
                continue
            p, q = rows(plain), rows(nested)
            for t in (plain, nested):
                m, b = log_header(os.path.basename(t)[:-4])
                machines.add(m)
                builds.add(b)
            tp, tq = sum(float(r["wall_s"]) for r in p), sum(float(r["wall_s"]) for r in q)
            bad = [r["step"] for r in p + q if r["reason"] not in CONVERGED]
            lines.append("| %s | %d | %.2f | %d + %d | %.2f | %.1fx | %d of %d%s |" % (
                n, sum(int(r["newton_its"]) for r in p), tp, sum(int(r["newton_its"]) for r in q),
                sum(int(r["coarse_newton_its"]) for r in q), tq, tp / tq, sum(r["coarse_start"] == "1" for r in q),
                len(q), "; not converged: %s" % bad if bad else ""))
        lines.append("")
    inside = sorted(glob.glob(os.path.join(OUT, "inside_out_*_plain.csv")))
    for plain in inside:
        size = os.path.basename(plain)[len("inside_out_"):-len("_plain.csv")]
        for nested in sorted(glob.glob(os.path.join(OUT, "inside_out_%s_nested*.csv" % size))):
            p, n = rows(plain), rows(nested)
            k = min(len(p), len(n))
            label = os.path.basename(nested)[:-4]
            for t in (os.path.basename(plain)[:-4], label):
                m, b = log_header(t)
                machines.add(m)
                builds.add(b)
            cs = re.search(r"-coarse_steps (-?\d+)", open(os.path.join(OUT, label + ".log")).read()).group(1)
            lines += ["## Inside-out bunny (%s mesh), plain vs `-coarse_mesh` (bunny %s), `-coarse_steps %s`" % (
                size, SMALLER[size], cs), "",
                "options/bunny_inside_out.yml (iarap, E 1e4, nu 0, dt 1e-2, mollifier, every element at F = -I), 2 "
                "ranks, the first %d steps." % k, "",
                "min alpha = the smallest element alpha at the step's end (rest 64, 0 inverted; stats `min_alpha`).", "",
                "| step | plain: updates | plain: s | plain: min alpha | nested: fine updates | nested: coarse updates "
                "| nested: s | nested: min alpha |",
                "|---|---|---|---|---|---|---|---|"]
            for i in range(min(k, PER_STEP_ROWS)):
                lines.append("| %s | %s | %.2f | %.2f | %s | %s | %.2f | %.2f |" % (
                    p[i]["step"], p[i]["newton_its"], float(p[i]["wall_s"]), float(p[i]["min_alpha"]),
                    n[i]["newton_its"], n[i]["coarse_newton_its"], float(n[i]["wall_s"]), float(n[i]["min_alpha"])))

            def total(label, a, b):  # sums over the steps a..b-1 (0-based); min alpha: the smallest of the steps'
                return "| %s | %d | %.1f | %.2f | %d | %d | %.1f | %.2f |" % (
                    label, sum(int(r["newton_its"]) for r in p[a:b]), sum(float(r["wall_s"]) for r in p[a:b]),
                    min(float(r["min_alpha"]) for r in p[a:b]), sum(int(r["newton_its"]) for r in n[a:b]),
                    sum(int(r["coarse_newton_its"]) for r in n[a:b]), sum(float(r["wall_s"]) for r in n[a:b]),
                    min(float(r["min_alpha"]) for r in n[a:b]))
            if k > PER_STEP_ROWS:  # a long run: totals of the listed steps and of the rest, before all steps
                lines += [total("steps 1-%d" % PER_STEP_ROWS, 0, PER_STEP_ROWS),
                          total("steps %d-%d" % (PER_STEP_ROWS + 1, k), PER_STEP_ROWS, k)]
            lines += [total("all %d" % k, 0, k), ""]
            bad = [r["step"] for r in p[:k] + n[:k] if r["reason"] not in CONVERGED]
            lines += ["Every step converged." if not bad else "Not converged: steps %s." % bad, ""]
    lines += scaling_section(machines, builds)
    lines += ["Machine: %s. aries builds: %s." % ("; ".join(sorted(machines)), ", ".join(sorted(builds))), ""]
    path = os.path.join(ROOT, "docs", "nested.md")
    with open(path, "w") as fh:
        fh.write("\n".join(lines))
    print("wrote " + path)


def main():
    global ARGS
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("command", choices=["scramble", "load", "inside_out", "scaling", "report"])
    ap.add_argument("--aries", default=os.path.join(ROOT, "build", "aries"))
    ap.add_argument("--surfaces", default="camel,hand,triceratops")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--sizes", default=None, help="inside_out: default; scaling: test,default")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--coarse-steps", type=int, default=1)
    ap.add_argument("--load-steps", default="1,2,4")
    ap.add_argument("--variants", default="plain,nested")
    ap.add_argument("--ranks", type=int, default=2)
    ARGS = ap.parse_args()
    {"scramble": cmd_scramble, "load": cmd_load, "inside_out": cmd_inside_out, "scaling": cmd_scaling,
     "report": cmd_report}[ARGS.command]()


if __name__ == "__main__":
    main()
