#!/usr/bin/python3
"""Why the Fig. 13 interaction takes more Newton updates per step on finer meshes: the cells at the handles' edges.

usage: bench/interaction_handles.py [--steps K] [--meshes tets,tets_fine,hexmid,hex[:K]] [--variants V,...]
                                   [--out FILE.md]

Runs options/bunny_interact.yml (two box handles pushed 0.06 into the cheeks over 100 steps, backward Euler, 200
steps) on bunny meshes of several element types and sizes, 2 MPI ranks, each with a step's first Newton system
filtered and unfiltered (-newton_exact_start false / true), and reports for each: its cell size h (the mean rest
edge), the Newton updates and linear solves per step in three phases (the handles move and the targets change: steps
1-55 and 56-100; the handles hold: 101-200), and, at the output steps, the cells the handles crush: cells whose J (det
F, averaged over the cell's quadrature points) is below 0.25, how many of them lie within 2 h of a support box's
boundary (the handles or the pinned base), and the worst cell (smallest J) with its energy density against the median.
--steps K runs only the first K steps of each mesh, MESH:K those of one (the phases then cover fewer steps, and the
table says how many). --variants picks the runs of each mesh (default: filtered start,exact start; also abs filter,
adaptive filter: -psd_projection abs / adaptive in place of backward Euler's clamp; element filter: -psd_scope
element, each element's whole Hessian clamped instead of each quadrature point's; no exact Hessian:
-newton_exact_hessian false, every system filtered; density 100, density 1000: the scene's density 10 raised;
handles 0.03: the two handles pushed 0.03 into the cheeks in place of the scene's 0.06; surface handles: the two
handles hold the body's boundary vertices in their boxes only, -bc_box_<k>_surface; local solve: -newton_local_solve
20, up to 20 Newton iterations on the vertices a concentrated update moved, reported in their own column).
Each run lives in out/interaction_handles/<mesh>_<variant>/ with its stats, Newton history and output; a run whose
directory holds the same command line and a stats row for every step asked for is read back, not run again. Use
/usr/bin/python3.
"""
import argparse
import datetime
import os
import re
import subprocess
import sys

import h5py
import numpy as np

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(ROOT, "ctest"))
import scenes  # noqa: E402  (mesh generation, machine line, commit line)
from harness import mpi_env  # noqa: E402

WORK = os.path.join(ROOT, "out", "interaction_handles")
OUT = os.path.join(ROOT, "bench", "results", "interaction_handles.md")
SCENE = "bunny_interact"
OPTIONS = os.path.join(ROOT, "options", SCENE + ".yml")
RANKS = 2
OUTPUT_EVERY = 10
CRUSHED_J = 0.25
SLOW_UPDATES = 4  # a step of this many Newton updates or more is a slow one (the report's third table)
NEAR_BOX_H = 2.0
# label -> (mesh name, size, description)
MESHES = {
    "tets": ("bunny", "default", "tetrahedra (the scene's mesh)"),
    "tets_fine": ("bunny", "fig15", "tetrahedra, fine"),
    "hexmid": ("bunny", "hexmid", "voxel hexahedra, edge 0.02"),
    "hex": ("bunny", "hex", "voxel hexahedra, edge 0.01 (the paper's size)"),
}
PHASES = [(1, 55), (56, 100), (101, 200)]
# variant -> options: a step's first Newton system filtered (as before issue 45's measurement) or unfiltered (the
# default), the Hessian filters (each with the default exact start; clamp per quadrature point, backward Euler's
# default, is "exact start"; element: clamp of each element's whole Hessian), and projected Newton without the
# unfiltered Hessian near the solution; the scene at 10 and 100 times its density (10; the paper does not give its
# density), the mass term 10 and 100 times as large against the stiffness
VARIANTS = {"filtered start": ["-newton_exact_start", "false"], "exact start": ["-newton_exact_start", "true"],
            "abs filter": ["-psd_projection", "abs"], "adaptive filter": ["-psd_projection", "adaptive"],
            "element filter": ["-psd_scope", "element"], "no exact Hessian": ["-newton_exact_hessian", "false"],
            "density 100": ["-density", "100"], "density 1000": ["-density", "1000"],
            # the handles pushed half as deep (0.03 into each cheek in place of 0.06): less crushing at their edges
            "handles 0.03": ["-bc_box_2_translate", "0,0.03,0", "-bc_box_3_translate", "0,-0.03,0"],
            # the handles hold the body's surface in their boxes only (-bc_box_<k>_surface): they push the skin of
            # the cheeks and leave the interior free, instead of moving the box's whole volume through the body
            "surface handles": ["-bc_box_2_surface", "true", "-bc_box_3_surface", "true"],
            # after an update concentrated on a few vertices, up to 20 Newton iterations on them alone
            # (-newton_local_solve, solver/local_solve.cpp)
            "local solve": ["-newton_local_solve", "20"]}
DEFAULT_VARIANTS = "filtered start,exact start"


def scene_value(key, extra=()):
    """A value of the scene's options file, or of the variant's options where they set it (scenes.yml_value)."""
    value = scenes.yml_value(SCENE, key, list(extra))
    if value == "-":
        raise SystemExit("interaction_handles: no %s in %s" % (key, OPTIONS))
    return value


def mass_to_stiffness(variant, h):
    """A vertex's mass term against its cells' stiffness, rho h^3 / dt^2 over E h: rho h^2 / (E dt^2)."""
    rho, E, dt = (float(scene_value(key, VARIANTS[variant])) for key in ("density", "E", "dt"))
    return rho * h * h / (E * dt ** 2)


def read_boxes():
    v = [float(x) for x in scene_value("bc_box").split(",")]
    return [v[i:i + 6] for i in range(0, len(v), 6)]


def run(label, variant, steps, build):
    name, size, _ = MESHES[label]
    msh = scenes.generate(name, size)
    work = os.path.join(WORK, label + "_" + variant.replace(" ", "_"))
    os.makedirs(work, exist_ok=True)
    stats = os.path.join(work, "stats.csv")
    cmd = ["mpiexec", "-n", str(RANKS), os.path.join(build, "aries"), "-options_file", OPTIONS,
           "-dm_plex_filename", msh, "-target_file", msh[:-4] + ".targets", "-steps", str(steps),
           "-output", os.path.join(work, "bi"), "-output_every", str(OUTPUT_EVERY), "-stats", stats,
           "-newton_history", os.path.join(work, "history.csv")] + VARIANTS[variant]
    key = " ".join(cmd)
    keyfile = os.path.join(work, "command.txt")
    if (os.path.exists(keyfile) and open(keyfile).read() == key and os.path.exists(stats)
            and len(scenes.read_stats(stats)[0]) == steps):
        return work
    print("interaction_handles: running", label, variant, flush=True)
    with open(os.path.join(work, "log.txt"), "w") as log:
        rc = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT, env=mpi_env(), cwd=ROOT)
    if rc != 0:
        raise SystemExit("interaction_handles: %s (%s) failed (exit %d), see %s/log.txt" % (label, variant, rc, work))
    open(keyfile, "w").write(key)
    return work


def held_vertices(work):
    """The vertices the run's supports hold (the pinned base and the handles), from aries' mesh line in its log."""
    m = re.search(r"vertices \((\d+) Dirichlet\)", open(os.path.join(work, "log.txt")).read())
    return m.group(1) if m else "-"


def box_distance(c, box):
    """Distance from points c (n x 3) to the boundary of an axis-aligned box (inside or out)."""
    lo, hi = np.array(box[0::2]), np.array(box[1::2])
    inside = np.all((c >= lo) & (c <= hi), axis=1)
    out = np.linalg.norm(np.maximum(0.0, np.maximum(lo - c, c - hi)), axis=1)
    depth = np.min(np.minimum(c - lo, hi - c), axis=1)
    return np.where(inside, depth, out)


def crushed_cells(work, boxes):
    mesh = h5py.File(os.path.join(work, "bi.h5"), "r")["mesh"]
    rest, topo = mesh["rest"][:], mesh["topology"][:]
    centroids = rest[topo].mean(axis=1)
    # the mean rest edge: tets' six edges, hexahedra's twelve (VTK order)
    edges = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] if topo.shape[1] == 4 else \
        [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    h = float(np.mean([np.linalg.norm(rest[topo[:, i]] - rest[topo[:, j]], axis=1).mean() for i, j in edges]))
    near = np.min([box_distance(centroids, b) for b in boxes], axis=0) <= NEAR_BOX_H * h
    rows = []
    steps_dir = os.path.join(work, "bi.steps")
    for fname in sorted(os.listdir(steps_dir)):
        step = int(fname.split("_")[-1].split(".")[0])
        if step == 0:
            continue
        cell = h5py.File(os.path.join(steps_dir, fname), "r")["cell"]
        J = cell["J"][:].reshape(-1)
        e = cell["energy_density"][:].reshape(-1)
        bad = J < CRUSHED_J
        worst = int(np.argmin(J))
        rows.append(dict(step=step, crushed=int(bad.sum()), near=int((bad & near).sum()), minJ=float(J[worst]),
                         worst_at=centroids[worst], worst_e=float(e[worst]) / float(np.median(e))))
    return h, len(topo), rows


def slow_steps(work, stats):
    """The steps of SLOW_UPDATES or more updates, from the Newton history: how many, how many began with an unfiltered
    system that failed (CG met negative curvature or the direction did not descend; its row is not applied), their
    line-search cuts and extrapolations, and how fast their full-length filtered steps shrink (the final correction
    included; the median and the quartiles of the ratio of one's |step|_inf to the previous one's, within a step);
    and the alpha safeguard's halvings in the whole run (the run's summary line)."""
    slow = {int(r["step"]) for r in stats if int(r["newton_its"]) >= SLOW_UPDATES}
    by_step = {}
    for r in scenes.read_stats(os.path.join(work, "history.csv"))[0]:
        if int(r["step"]) in slow and r["level"] == "0":
            by_step.setdefault(int(r["step"]), []).append(r)
    failed_first = cuts = extrapolated = 0
    ratios = []
    for rows in by_step.values():
        failed_first += rows[0]["filter"] == "none" and float(rows[0]["lambda"]) == 0.0 and len(rows) > 1 \
            and rows[1]["iteration"] == "0"
        cuts += sum(1 for r in rows if 0.0 < float(r["lambda"]) < 1.0)
        extrapolated += sum(1 for r in rows if float(r["extrapolated"]) > 0.0)
        full = [float(r["step_inf"]) for r in rows if r["filter"] != "none" and float(r["lambda"]) == 1.0]
        ratios += [b / a for a, b in zip(full, full[1:]) if a > 0.0]
    q = np.percentile(ratios, [25, 50, 75]) if ratios else None
    m = re.search(r"safeguard halvings (\d+)", open(os.path.join(work, "log.txt")).read())
    if not m:
        raise SystemExit("interaction_handles: no 'safeguard halvings' in %s/log.txt (the run's summary line)" % work)
    return dict(count=len(slow), failed_first=failed_first, cuts=cuts, extrapolated=extrapolated, ratio=q,
                halvings=int(m.group(1)))


def phase_averages(stats):
    """(steps, Newton/step, solves/step) over each phase's steps that were run (scenes.averages), None for none."""
    out = []
    for a, b in PHASES:
        rows = [r for r in stats if a <= int(r["step"]) <= b]
        out.append((len(rows),) + scenes.averages(rows)[:2] if rows else None)
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--steps", type=int, default=200)
    p.add_argument("--meshes", default=",".join(MESHES))
    p.add_argument("--build", default=os.path.join(ROOT, "build"))
    p.add_argument("--variants", default=DEFAULT_VARIANTS)
    p.add_argument("--out", default=OUT)
    a = p.parse_args()
    variants = a.variants.split(",")
    for v in variants:
        if v not in VARIANTS:
            raise SystemExit("interaction_handles: unknown variant '%s' (known: %s)" % (v, ",".join(VARIANTS)))
    boxes = read_boxes()
    labels, steps = [], {}
    for item in a.meshes.split(","):
        label, _, k = item.partition(":")
        if label not in MESHES:
            raise SystemExit("interaction_handles: unknown mesh '%s' (known: %s)" % (label, ",".join(MESHES)))
        if k and not (k.isdigit() and 1 <= int(k) <= 200):
            raise SystemExit("interaction_handles: '%s': the steps after ':' must be 1..200" % item)
        labels.append(label)
        steps[label] = int(k) if k else a.steps
    results = {(label, v): run(label, v, steps[label], a.build) for label in labels for v in variants}

    lines = ["# The Fig. 13 interaction: Newton's work against the cells the handles crush", "",
             "Generated by `bench/interaction_handles.py%s` on %s at %s, %s; **do not edit by hand**. "
             "options/bunny_interact.yml (handles: boxes 2 and 3 of its bc_box, pushed 0.06 into the cheeks over steps "
             "1-100, then held; the shape targets move until t = 1, step 100), 200 steps unless a row says fewer. "
             "Newton = updates of the state per step, solves = linear solves per step, averaged over the steps of "
             "each phase. Crushed = cells whose J (det F averaged over the cell's points) is below %g; near a "
             "support = the cell's rest centroid within %g h of a support box's boundary (the handles and the "
             "pinned base); h = the mean rest edge of the mesh's cells."
             % ((" --steps %d" % a.steps if a.steps != 200 else "") + " --meshes " + a.meshes
                + (" --variants '%s'" % a.variants if a.variants != DEFAULT_VARIANTS else ""),
                datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), scenes.commit_line(),
                scenes.machine_line(RANKS), CRUSHED_J, NEAR_BOX_H), "",
             "## Newton per step by phase", "",
             "| mesh | cells | h | variant | steps 1-55: Newton / solves | 56-100 | 101-200 | all steps | "
             "local iterations / step | s/step | held vertices | crushed cells: most / smallest J | rho h^2 / (E dt^2) |",
             "|---|---:|---:|---|---|---|---|---|---:|---:|---:|---|---:|"]
    cells, slow = {}, {}
    for label in labels:
        for v in variants:
            stats = scenes.read_stats(os.path.join(results[label, v], "stats.csv"))[0]
            slow[label, v] = slow_steps(results[label, v], stats)
            h, n, rows = crushed_cells(results[label, v], boxes)
            cells[label, v] = rows
            ph = ["%.2f / %.2f (%d)" % (x[1], x[2], x[0]) if x else "-" for x in phase_averages(stats)]
            newton, solves, _, seconds, _ = scenes.averages(stats)
            allp = "%.2f / %.2f (%d)" % (newton, solves, len(stats))
            local = sum(int(r.get("local_its") or 0) for r in stats) / max(len(stats), 1)
            lines.append("| %s | %d | %.4f | %s | %s | %s | %s | %s | %.2f | %.2f | %s | %d / %.3f | %.2f |" % (
                MESHES[label][2], n, h, v, ph[0], ph[1], ph[2], allp, local, seconds,
                held_vertices(results[label, v]),
                max(r["crushed"] for r in rows),
                min(r["minJ"] for r in rows), mass_to_stiffness(v, h)))
    lines += ["", "(in brackets: the steps averaged; held vertices: those the supports hold, the pinned base's and the "
              "handles'; crushed cells: the most at one output step (every %d steps) and "
              "the smallest J over them; rho h^2 / (E dt^2): a vertex's mass term rho h^3 / dt^2 against its cells' "
              "stiffness E h; filtered / exact start: a step's first Newton system filtered, "
              "or unfiltered where the previous step's unfiltered systems were all positive definite, "
              "`-newton_exact_start`, the default; abs / adaptive filter: `-psd_projection abs` / `adaptive` in "
              "place of backward Euler's clamp, with the exact start; element filter: `-psd_scope element`, each "
              "element's whole Hessian clamped in place of each quadrature point's; no exact Hessian: "
              "`-newton_exact_hessian false`, every Newton system filtered by clamp; density 100 / 1000: `-density`, "
              "the scene's 10 raised; handles 0.03: the handles pushed 0.03 into the cheeks in place of 0.06, "
              "`-bc_box_2_translate 0,0.03,0 -bc_box_3_translate 0,-0.03,0`; surface handles: the handles hold "
              "the body's boundary vertices in their boxes only, `-bc_box_2_surface true -bc_box_3_surface true`, "
              "the vertices beneath them free; local solve: `-newton_local_solve 20`, after an update that moved a few "
              "vertices far more than the rest, up to 20 Newton iterations on them and their neighbours alone, the "
              "local iterations/step column (not in the Newton counts; 0 in runs made before the stats had it))" % OUTPUT_EVERY]
    lines += ["", "## Slow steps (%d or more Newton updates)" % SLOW_UPDATES, "",
              "From each run's `-newton_history`: the slow steps, of them those whose first Newton system was "
              "unfiltered and failed (CG met negative curvature, or its direction did not descend; the step then "
              "continued with the filter), their line-search cuts (updates shorter than full length) and extrapolated "
              "updates (`-newton_extrapolate`), and the ratio of each full-length filtered step's |step|_inf (the "
              "final correction included) to the previous one's in the same step (quartiles): near 0 is fast "
              "convergence, near 1 a crawl. Safeguard halvings: the alpha safeguard's in the whole run, every step.",
              "", "| mesh | variant | slow steps | first system unfiltered and failed | line-search cuts | "
              "extrapolated | step ratio: 25% / median / 75% | safeguard halvings |",
              "|---|---|---:|---:|---:|---:|---|---:|"]
    for label in labels:
        for v in variants:
            w = slow[label, v]
            ratio = "%.2f / %.2f / %.2f" % tuple(w["ratio"]) if w["ratio"] is not None else "-"
            lines.append("| %s | %s | %d | %d | %d | %d | %s | %d |" % (
                MESHES[label][2], v, w["count"], w["failed_first"], w["cuts"], w["extrapolated"], ratio,
                w["halvings"]))
    shown = "exact start" if "exact start" in variants else variants[0]
    lines += ["", "## Crushed cells at the output steps (%s)" % shown, "",
              "| mesh | step | crushed cells | of them near a support | smallest J | its rest centroid | its energy "
              "density / median |", "|---|---:|---:|---:|---:|---|---:|"]
    for label in labels:
        for r in cells[label, shown]:
            lines.append("| %s | %d | %d | %d | %.3f | (%.3f, %.3f, %.3f) | %.0f |" % (
                MESHES[label][2], r["step"], r["crushed"], r["near"], r["minJ"], *r["worst_at"], r["worst_e"]))
    open(a.out, "w").write("\n".join(lines) + "\n")
    print("interaction_handles: wrote", a.out)


if __name__ == "__main__":
    main()
