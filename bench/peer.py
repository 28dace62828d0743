#!/usr/bin/python3
"""Peer benchmark: aries against DOLFINx on the same problem, the same PETSc, the same machine.

usage: bench/peer.py run [--sizes s10k,s40k,default,s400k,s1m] [--ranks 1,2] [--pcs default,gamg,jacobi]
                         [--aries build/aries] [--before BIN] [--timeout S]
       bench/peer.py report [--out docs/peer.md]

The problem (the one issue 45 measured): a box 1 x 1 x 2 (meshes/generate.sh box SIZE: one gmsh mesh per size, 10k to
1M P1 tets, read by both codes), bottom face held, top face moved by (0, 0, -0.2) (10% of its height) in one static
load step, every component of both faces prescribed; E = 1e4, nu = 0.3. aries runs its iarap (mu |F - R|^2 +
lambda/2 (J - 1)^2) with its defaults (-integrator static, -lift_increments auto, the preconditioner by its rule), and
the same with -pc_type jacobi and with GAMG at every size (-multigrid_min_dofs 0); the "before" rows run
-lift_increments never (the supports move alone, the increment halved until the alpha safeguard accepts it, as aries did
before) or another build (--before BIN). DOLFINx 0.5.2 (Debian's python3-dolfinx-real on the same PETSc 3.18.5; installed
here with apt-get when missing, not by the README's commands) runs a compressible neo-Hookean solid with the same E and
nu (the same linear elasticity at small strain) under PETSc's SNES newtonls with the increment lifted
(bench/peer_dolfinx.py), CG + GAMG with aries' rule's settings or CG + Jacobi, -ksp_rtol 1e-8 in both codes.

Measured per run: Newton updates, linear solves, Krylov iterations, the nonlinear solve's wall time (aries: the step's
wall_s; DOLFINx: SNESSolve, after the forms' JIT compile, which is cached) and the whole process's wall time; the top
face's reaction force; and the distance between the two codes' solutions (vertices matched by rest position): the
materials differ at finite strain, so the distance says by how much on this problem. `run` keeps every run's files in
out/peer/ (a run with the same command line and a finished result is read back); `report` writes docs/peer.md and its
chart docs/images/results/peer.png from them. Timings are medians over --repeat runs of each configuration, made in
rounds (every configuration of a size and rank count once per round), so that the codes are timed side by side.
"""
import argparse
import csv
import datetime
import json
import os
import re
import statistics
import subprocess
import sys
import time

import h5py
import numpy as np

BENCH = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(BENCH)
sys.path.insert(0, BENCH)
sys.path.insert(0, os.path.join(ROOT, "ctest"))
import scenes  # noqa: E402  (mesh generation, machine line, commit line)
from harness import mpi_env  # noqa: E402

WORK = os.path.join(ROOT, "out", "peer")
DOCS = os.path.join(ROOT, "docs", "peer.md")
CHART = os.path.join(ROOT, "docs", "images", "results", "peer.png")
SIZES = ["s10k", "s40k", "default", "s400k", "s1m"]
DISP, E, NU, KSP_RTOL = 0.2, 1e4, 0.3, 1e-8
# aries variants: label -> extra options (the defaults are aries' own; every run shares the problem's options)
VARIANTS = {
    "default": [],
    "gamg": ["-multigrid_min_dofs", "0"],
    "gamg_rebuild": ["-multigrid_min_dofs", "0", "-multigrid_reuse_growth", "0"],
    "jacobi": ["-pc_type", "jacobi"],
    "before": ["-lift_increments", "never"],
    "before_jacobi": ["-lift_increments", "never", "-pc_type", "jacobi"],
    "default_h5": [],  # the defaults reading the same mesh converted once to HDF5 (read by all ranks in parallel)
}
H5_VARIANTS = {"default_h5"}


CONVERGED = ("newton_step", "converged_initial", "step_bound", "energy_roundoff")


def ensure_dolfinx():
    """DOLFINx from Debian (python3-dolfinx-real, python3-gmsh), installed with apt-get when missing."""
    probe = subprocess.run(["/usr/bin/python3", "-c", "import dolfinx, gmsh"], capture_output=True)
    if probe.returncode == 0:
        return
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    print("peer.py: installing DOLFINx (python3-dolfinx-real python3-gmsh) with apt-get", flush=True)
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(sudo + ["apt-get", "update", "-qq"], check=True, env=env)
    subprocess.run(sudo + ["apt-get", "install", "-y", "-qq", "--no-install-recommends", "python3-dolfinx-real",
                           "python3-gmsh"], check=True, env=env)


def mesh_cells(msh):
    with open(msh[:-4] + ".json") as fh:
        return json.load(fh)["tets"]


def run_dir(code, size, ranks, variant):
    return os.path.join(WORK, "%s_%s_%s_n%d" % (code, variant, size, ranks))


def finished(d, cmd, rounds=1):
    """A run of this command line with at least `rounds` timed samples, or a failed one (read back instead of run
    again)."""
    meta = os.path.join(d, "meta.json")
    if not os.path.exists(meta):
        return None
    with open(meta) as fh:
        m = json.load(fh)
    if m.get("cmd") != cmd:
        return None
    return m if m.get("exit") != 0 or m.get("repeats", 1) >= rounds else None


def earlier_samples(d, cmd, keys):
    """The timed samples of the earlier rounds of this command line (lists per key; empty for a new command)."""
    m = finished(d, cmd)
    samples = (m or {}).get("samples") if m and m.get("exit") == 0 else None
    return samples if samples and all(k in samples for k in keys) else {k: [] for k in keys}


def launch(cmd, d, timeout):
    os.makedirs(d, exist_ok=True)
    print("$ " + " ".join(cmd), flush=True)
    t0 = time.time()
    with open(os.path.join(d, "log.txt"), "w") as fh:
        try:
            p = subprocess.run(cmd, cwd=ROOT, env=mpi_env(), stdout=fh, stderr=subprocess.STDOUT, timeout=timeout)
            code = p.returncode
        except subprocess.TimeoutExpired:
            code = "timeout"
    return code, time.time() - t0


def run_aries(binary, msh, size, ranks, variant, extra, timeout, rounds):
    """One more run of the configuration unless it has `rounds` samples; its meta (medians over the samples)."""
    d = run_dir("aries", size, ranks, variant)
    base = os.path.join(d, "box")
    args = ["-dm_plex_filename", msh, "-energy", "iarap", "-E", str(E), "-nu", str(NU), "-integrator", "static",
            "-steps", "1", "-bc_clamp", "bottom,top", "-bc_clamp_top_translate", "0,0,%g" % -DISP,
            "-ksp_rtol", str(KSP_RTOL), "-output", base, "-output_fields", "J", "-stats", base + ".csv",
            "-newton_history", base + "_newton.csv", "-reactions", base + "_reactions.csv"] + extra
    cmd = ["mpiexec", "-n", str(ranks), "--bind-to", "none", binary] + args
    done = finished(d, cmd, rounds)
    if done:
        return done
    samples = earlier_samples(d, cmd, ("total_s", "solve_s", "setup_s", "model_s"))
    code, wall = launch(cmd, d, timeout)
    if code == 0:
        with open(base + ".csv") as fh:
            step = float(next(csv.DictReader(l for l in fh if not l.startswith("#")))["wall_s"])
        with open(os.path.join(d, "log.txt")) as fh:
            log = fh.read()  # read once: the timings here, the preconditioner and sub-steps below
        setup = re.search(r"wall time setup ([0-9.]+) s", log)
        model = re.search(r"\(model evaluations ([0-9.]+) s\)", log)  # of the steps' time
        for k, x in (("total_s", wall), ("solve_s", step), ("setup_s", float(setup.group(1)) if setup else None),
                     ("model_s", float(model.group(1)) if model else None)):
            samples[k].append(x)
    meta = {"cmd": cmd, "exit": code, "code": "aries", "variant": variant, "size": size, "ranks": ranks,
            "repeats": len(samples["total_s"]), "samples": samples,
            "finished": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC")}
    meta.update({k: statistics.median(v) if v and None not in v else None for k, v in samples.items()})
    if code == 0:
        with open(base + ".csv") as fh:
            lines = fh.read().splitlines()
        row = next(csv.DictReader(l for l in lines if not l.startswith("#")))
        meta["build"] = next((l[1:].strip() for l in lines if l.startswith("# aries")), "?")
        meta.update(newton=int(row["newton_its"]), linear_solves=int(row["linear_solves"]), krylov=int(row["ksp_its"]),
                    reason=row["reason"], residual=float(row["residual"]))
        meta["pc"] = "CG + GAMG" if "linear solver CG + GAMG" in log or "gamg" in extra else "CG + Jacobi"
        sub = re.search(r"load sub-steps (\d+)", log)
        meta["substeps"] = int(sub.group(1)) if sub else 0
        with open(base + "_reactions.csv") as fh:
            rows = [r for r in csv.DictReader(l for l in fh if not l.startswith("#")) if r["set"] == "top"]
        meta["top_force"] = [float(rows[-1][k]) for k in ("fx", "fy", "fz")]
        with open(base + "_newton.csv") as fh:
            meta["history"] = [{k: r[k] for k in ("iteration", "step_inf", "lambda", "ksp_its", "filter", "load",
                                                   "lifted")}
                               for r in csv.DictReader(fh)]
    with open(os.path.join(d, "meta.json"), "w") as fh:
        json.dump(meta, fh, indent=1)
    return meta


def run_dolfinx(msh, size, ranks, pc, timeout, rounds):
    """As run_aries, for DOLFINx."""
    d = run_dir("dolfinx", size, ranks, pc)
    out = os.path.join(d, "result.json")
    cmd = ["mpiexec", "-n", str(ranks), "--bind-to", "none", "/usr/bin/python3", os.path.join(BENCH, "peer_dolfinx.py"),
           msh, out, "--pc", pc, "--disp", str(DISP), "--E", str(E), "--nu", str(NU), "--ksp-rtol", str(KSP_RTOL),
           "--npz", os.path.join(d, "solution.npz")]
    done = finished(d, cmd, rounds)
    if done:
        return done
    samples = earlier_samples(d, cmd, ("total_s", "solve_s", "setup_s"))
    code, wall = launch(cmd, d, timeout)
    meta = {"cmd": cmd, "exit": code, "code": "dolfinx", "variant": pc, "size": size, "ranks": ranks,
            "finished": datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC")}
    if code == 0:
        with open(out) as fh:
            r = json.load(fh)
        for k, x in (("total_s", wall), ("solve_s", r["solve_s"]), ("setup_s", r["setup_s"])):
            samples[k].append(x)
        meta.update(newton=r["newton"], linear_solves=r["linear_solves"], krylov=r["krylov"],
                    reason=r["reason"], build=r["code"], step_inf=r["step_inf"], top_force=r["top_force"],
                    residual=r["residual"], pc="CG + GAMG" if pc == "gamg" else "CG + Jacobi")
        meta.update({k: statistics.median(v) for k, v in samples.items()})
    meta.update(repeats=len(samples["total_s"]), samples=samples)
    with open(os.path.join(d, "meta.json"), "w") as fh:
        json.dump(meta, fh, indent=1)
    return meta


def solution_distance(size, ranks, variant, pc):
    """max and rms over vertices of |u_aries - u_dolfinx| / max |u_dolfinx|, vertices matched by rest position."""
    a = run_dir("aries", size, ranks, variant)
    dfx = os.path.join(run_dir("dolfinx", size, ranks, pc), "solution.npz")
    steps = sorted(f for f in os.listdir(os.path.join(a, "box.steps")) if f.endswith(".h5"))
    with h5py.File(os.path.join(a, "box.h5"), "r") as f:
        rest = f["/mesh/rest"][:]
    with h5py.File(os.path.join(a, "box.steps", steps[-1]), "r") as f:
        ua = f["/displacement"][:]
    d = np.load(dfx)
    key = lambda X: np.round(X * 1e7).astype(np.int64)  # noqa: E731  (the same .msh coordinates in both)
    ka, kd = key(rest), key(d["rest"])
    ia, idx = np.lexsort(ka.T[::-1]), np.lexsort(kd.T[::-1])
    if not np.array_equal(ka[ia], kd[idx]):
        raise SystemExit("peer.py: the two codes' vertices do not match (%d vs %d)" % (len(ka), len(kd)))
    diff = np.linalg.norm(ua[ia] - d["disp"][idx], axis=1)
    scale = np.linalg.norm(d["disp"], axis=1).max()
    return diff.max() / scale, np.sqrt((diff ** 2).mean()) / scale


def warm_up(timeout):
    """DOLFINx compiles its forms on first use (JIT, cached in ~/.cache/fenics, the same forms for every mesh): once on
    the smallest box, untimed, so that no timed run pays for it."""
    d = os.path.join(WORK, "dolfinx_warmup")
    cmd = ["/usr/bin/python3", os.path.join(BENCH, "peer_dolfinx.py"), scenes.generate("box", "test"),
           os.path.join(d, "result.json")]
    code, _ = launch(cmd, d, timeout)
    if code != 0:
        sys.exit("peer.py: DOLFINx does not run (exit %s); its log: %s" % (code, os.path.join(d, "log.txt")))


def run_all(sizes, ranks, variants, dolfinx_pcs, binary, before=None, timeout=3600, repeat=1):
    """Every configuration (finished runs with the same command line are read back); the metas of all of them."""
    ensure_dolfinx()
    warm_up(timeout)
    for s in sizes:
        if s not in SIZES:
            sys.exit("peer.py: unknown size '%s' (sizes: %s)" % (s, ", ".join(SIZES)))
    binary = os.path.abspath(binary)
    if not os.access(binary, os.X_OK):
        sys.exit("peer.py: no aries binary at %s (build it: cmake --build build)" % binary)
    for v in variants:
        if v not in VARIANTS:
            sys.exit("peer.py: unknown aries variant '%s' (variants: %s)" % (v, ", ".join(VARIANTS)))
    metas = []
    for size in sizes:
        msh = scenes.generate("box", size)
        for n in ranks:
            # every configuration once per round (DOLFINx, aries, DOLFINx, aries, ...): a drift in the machine's speed
            # falls on all of them alike, and the medians compare runs made side by side
            for r in range(1, repeat + 1):
                last = r == repeat
                for pc in dolfinx_pcs:
                    m = run_dolfinx(msh, size, n, pc, timeout, r)
                    if last:
                        print("dolfinx %s %s n%d: %s" % (pc, size, n, summary(m)), flush=True)
                        metas.append(m)
                for v in variants:
                    other = before and v.startswith("before")
                    binv = os.path.abspath(before) if other else binary
                    extra = VARIANTS[v][2:] if other else VARIANTS[v]
                    m = run_aries(binv, scenes.generate("box", size, h5=True) if v in H5_VARIANTS else msh, size, n,
                                  v, extra, timeout, r)
                    if last:
                        print("aries %s %s n%d: %s" % (v, size, n, summary(m)), flush=True)
                        metas.append(m)
    return metas


def cmd_run(a):
    run_all(a.sizes.split(","), [int(r) for r in a.ranks.split(",")], a.variants.split(","),
            a.dolfinx_pcs.split(","), a.aries, a.before, a.timeout, a.repeat)


def summary(m):
    if m.get("exit") != 0:
        return "failed (exit %s)" % m.get("exit")
    return "%d Newton, %d solves, %d Krylov, solve %.2f s, total %.2f s, %s" % (
        m["newton"], m["linear_solves"], m["krylov"], m["solve_s"], m["total_s"], m["reason"])


def load_all():
    runs = []
    if os.path.isdir(WORK):
        for d in sorted(os.listdir(WORK)):
            meta = os.path.join(WORK, d, "meta.json")
            if os.path.exists(meta):
                with open(meta) as fh:
                    m = json.load(fh)
                if m.get("exit") == 0 and m.get("setup_s") is None:  # runs made before the setup was recorded
                    m["setup_s"] = recorded_setup(os.path.join(WORK, d), m["code"])
                runs.append(m)
    return runs


def recorded_setup(d, code):
    """The setup time a finished run wrote: aries' log line, DOLFINx's result file; None if neither says."""
    if code == "dolfinx":
        with open(os.path.join(d, "result.json")) as fh:
            return json.load(fh).get("setup_s")
    with open(os.path.join(d, "log.txt")) as fh:
        setup = re.search(r"wall time setup ([0-9.]+) s", fh.read())
    return float(setup.group(1)) if setup else None


PROBLEM = ("The problem: a box 1 x 1 x 2 (meshes/generate.sh box SIZE), bottom held, top moved by 0.2 (10%) in one "
           "static load step, E = 1e4, nu = 0.3; aries iarap, DOLFINx compressible neo-Hookean (the same linear "
           "elasticity at small strain); CG at -ksp_rtol 1e-8 in both. Newton = updates of the state, solves = "
           "linear solves (aries: the one that certifies convergence included; DOLFINx newtonls: one per update, "
           "converged on PETSc's default relative residual 1e-8). Solve = the nonlinear solve's wall time (aries: "
           "the step; DOLFINx: SNESSolve after the JIT compile), setup = from the start to the solve (aries: its "
           "`wall time setup`, mesh input included; DOLFINx: mesh input, function spaces, forms), total = the whole "
           "process (mesh input, setup, output). aries rows: `default` = aries' defaults (the preconditioner by its rule: GAMG from "
           "-multigrid_min_dofs free DoFs), `gamg` = GAMG at every size (-multigrid_min_dofs 0), `gamg_rebuild` = "
           "the same with a new GAMG hierarchy for every Newton system (-multigrid_reuse_growth 0; `gamg` keeps one "
           "while its solves stay fast), `jacobi` = -pc_type jacobi, `default_h5` = the defaults with the same mesh converted once to HDF5 (meshes/generate.sh "
           "h5 box SIZE, not timed: read by every rank in parallel, where a .msh is read by rank 0 and distributed; "
           "DOLFINx reads the .msh through gmsh on rank 0), `before` = -lift_increments never (the supports move alone first, as aries did "
           "before: the increment halved until the alpha safeguard accepts it, each part a Newton solve). Times "
           "are medians of the repeats; ratios are aries / DOLFINx with the same preconditioner family and ranks.")


def index(metas):
    """(code, variant, size, ranks) -> meta of the finished runs; the sizes present, in order; their tet counts."""
    find = {(m["code"], m["variant"], m["size"], m["ranks"]): m for m in metas if m.get("exit") == 0}
    sizes = [s for s in SIZES if any(k[2] == s for k in find)]
    cells = {s: mesh_cells(scenes.generate("box", s)) for s in sizes}
    return find, sizes, cells


def rank_table(find, sizes, cells, n):
    lines = ["| tets | code | variant | linear solver | Newton | solves | Krylov | setup s | solve s | total s | "
             "solves / DOLFINx Newton | solve time / DOLFINx | total / DOLFINx | reason |",
             "|---:|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for s in sizes:
        for code, variants in (("dolfinx", ["gamg", "jacobi"]), ("aries", list(VARIANTS))):
            for v in variants:
                m = find.get((code, v, s, n))
                if not m:
                    continue
                peer = find.get(("dolfinx", "jacobi" if m["pc"] == "CG + Jacobi" else "gamg", s, n))
                ratio_n = ratio_t = ratio_w = "-"
                if peer and code == "aries":
                    ratio_n = "%.2f" % (m["linear_solves"] / peer["newton"])
                    ratio_t = "%.2f" % (m["solve_s"] / peer["solve_s"])
                    ratio_w = "%.2f" % (m["total_s"] / peer["total_s"])
                reason = m["reason"] if code == "aries" else ("converged (%d)" % m["reason"])
                setup = "%.2f" % m["setup_s"] if m.get("setup_s") is not None else "-"
                lines.append("| %s | %s | %s | %s | %d | %d | %d | %s | %.2f | %.2f | %s | %s | %s | %s |" % (
                    "{:,}".format(cells[s]), "DOLFINx" if code == "dolfinx" else "aries", v, m["pc"],
                    m["newton"], m["linear_solves"], m["krylov"], setup, m["solve_s"], m["total_s"], ratio_n,
                    ratio_t, ratio_w, reason))
    return lines


def findings(find, sizes, cells, ranks):
    """The count across sizes and the default against CG + Jacobi end to end, as bullets."""
    lines = []
    for n in ranks:
        have = [s for s in sizes if ("aries", "default", s, n) in find]
        solves = [find[("aries", "default", s, n)]["linear_solves"] for s in have]
        if solves:
            lines.append("- %d rank%s: aries' default takes %s linear solves from %s to %s tets (spread %d)." % (
                n, "s" if n > 1 else "", "/".join(str(x) for x in solves), "{:,}".format(cells[have[0]]),
                "{:,}".format(cells[have[-1]]), max(solves) - min(solves)))
        for s in sizes:
            dflt, jac = find.get(("aries", "default", s, n)), find.get(("aries", "jacobi", s, n))
            if dflt and jac and dflt["pc"] != jac["pc"]:
                lines.append("- %d rank%s, %s tets: the default (%s) is %.2fx faster end to end than CG + Jacobi "
                             "(%.1f s against %.1f s)." % (n, "s" if n > 1 else "", "{:,}".format(cells[s]), dflt["pc"],
                                                           jac["total_s"] / dflt["total_s"], dflt["total_s"],
                                                           jac["total_s"]))
                lines += speedup_bound(find, s, n, dflt, jac)
        for s in sizes:
            kept, rebuilt = find.get(("aries", "gamg", s, n)), find.get(("aries", "gamg_rebuild", s, n))
            if kept and rebuilt:
                lines.append("- %d rank%s, %s tets: GAMG keeping its hierarchy across Newton systems (`gamg`) "
                             "against a new one for every system (`gamg_rebuild`): %.2fx the solve time (%.2f s "
                             "against %.2f s), %d against %d Krylov iterations in %d and %d linear solves." % (
                                 n, "s" if n > 1 else "", "{:,}".format(cells[s]),
                                 kept["solve_s"] / rebuilt["solve_s"], kept["solve_s"], rebuilt["solve_s"],
                                 kept["krylov"], rebuilt["krylov"], kept["linear_solves"], rebuilt["linear_solves"]))
    return lines


def speedup_bound(find, s, n, dflt, jac):
    """How fast the default's linear algebra would have to be for a 2x end to end over CG + Jacobi: the rest of its
    run (setup, model evaluations, output, process start and end) is shared by any linear solver."""
    if dflt.get("model_s") is None:
        return []
    linear = dflt["solve_s"] - dflt["model_s"]  # the step's time outside model evaluations: Krylov, PC set-up
    rest = dflt["total_s"] - linear
    room = jac["total_s"] / 2 - rest
    line = ("  The rest of the default's run, everything but its linear algebra (the step's time outside model "
            "evaluations), takes %.1f s (setup %.1f, model evaluations %.1f, output and process %.1f): %.0f%% of CG + "
            "Jacobi's total. Twice as fast end to end (%.1f s) would leave %s for the linear algebra, which takes "
            "%.1f s (%d linear solves, %d Krylov iterations, preconditioner set-ups included)." % (
                rest, dflt["setup_s"], dflt["model_s"], rest - dflt["setup_s"] - dflt["model_s"],
                100 * rest / jac["total_s"], jac["total_s"] / 2,
                "%.1f s" % room if room > 0 else "no time (%.1f s too little)" % -room, linear,
                dflt["linear_solves"], dflt["krylov"]))
    dg, dj = find.get(("dolfinx", "gamg", s, n)), find.get(("dolfinx", "jacobi", s, n))
    if dg and dj:
        line += " DOLFINx's own GAMG is %.2fx faster end to end than its CG + Jacobi here (%.1f s against %.1f s)." % (
            dj["total_s"] / dg["total_s"], dg["total_s"], dj["total_s"])
    return [line]


def distance_table(find, sizes, cells, ranks):
    lines = ["| tets | ranks | max distance | rms distance | aries force z | DOLFINx force z | force difference |",
             "|---:|---:|---:|---:|---:|---:|---:|"]
    for n in ranks:
        for s in sizes:
            a_, d_ = find.get(("aries", "default", s, n)), find.get(("dolfinx", "gamg", s, n))
            if not (a_ and d_):
                continue
            mx, rms = solution_distance(s, n, "default", "gamg")
            fa, fd = a_["top_force"][2], d_["top_force"][2]
            lines.append("| %s | %d | %.2e | %.2e | %.1f | %.1f | %.2f%% |" % (
                "{:,}".format(cells[s]), n, mx, rms, fa, fd, 100 * (fa - fd) / abs(fd)))
    return lines


DISTANCE = ("Distance between aries' and DOLFINx's displacements at every vertex (matched by rest position), relative "
            "to DOLFINx's largest displacement, and the force on the moved face (z): the two materials agree at small "
            "strain and differ at 10% compression by this much.")


def cmd_report(a):
    runs = load_all()
    if not runs:
        sys.exit("peer.py: no runs in %s (bench/peer.py run first)" % WORK)
    find, sizes, cells = index(runs)
    ranks = sorted({k[3] for k in find})
    lines = ["# aries vs DOLFINx: the compressed box", "",
             "Generated by `bench/peer.py report` on %s from the runs `bench/peer.py run` made (%s); **do not edit by "
             "hand**. Machine: %s. aries builds: %s. Peer: %s." % (
                 datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M UTC"),
                 "%d runs, finished %s to %s" % (len(runs), min(m["finished"] for m in runs),
                                                max(m["finished"] for m in runs)),
                 scenes.machine_line(max(ranks)).split(" MPI ranks on ")[1],
                 "; ".join(sorted({m["build"] for m in runs if m["code"] == "aries" and "build" in m})),
                 "; ".join(sorted({m["build"] for m in runs if m["code"] == "dolfinx" and "build" in m}))), "",
             PROBLEM, ""]
    for n in ranks:
        lines += ["## %d rank%s" % (n, "s" if n > 1 else ""), ""] + rank_table(find, sizes, cells, n) + [""]
    lines += ["## What the rows show", ""] + findings(find, sizes, cells, ranks)
    lines += ["", "## The two solutions", "", DISTANCE, ""] + distance_table(find, sizes, cells, ranks)
    lines += ["", "![peer](images/results/peer.png)", "",
              "Chart: linear solves (left) and solve time (right) against the mesh size, %d rank%s." % (
                  max(ranks), "s" if max(ranks) > 1 else ""), ""]
    chart(find, sizes, cells, max(ranks), CHART)
    scenes.write(a.out, lines)


def chart(find, sizes, cells, n, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    series = [("dolfinx", "gamg", "DOLFINx, CG + GAMG", "k-o"), ("dolfinx", "jacobi", "DOLFINx, CG + Jacobi", "k--s"),
              ("aries", "default", "aries default", "C0-o"), ("aries", "jacobi", "aries, CG + Jacobi", "C0--s"),
              ("aries", "before", "aries before (supports alone)", "C3:^")]
    for code, v, label, style in series:
        pts = [(cells[s], find[(code, v, s, n)]) for s in sizes if (code, v, s, n) in find]
        if not pts:
            continue
        ax[0].plot([p[0] for p in pts], [p[1]["linear_solves"] for p in pts], style, label=label)
        ax[1].plot([p[0] for p in pts], [p[1]["solve_s"] for p in pts], style, label=label)
    for a_, t in zip(ax, ["linear solves", "nonlinear solve, s"]):
        a_.set_xscale("log")
        a_.set_xlabel("tets")
        a_.set_ylabel(t)
        a_.grid(True, alpha=0.3)
    ax[1].set_yscale("log")
    ax[0].legend(fontsize=8)
    fig.tight_layout()
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print("wrote " + path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], usage=__doc__.split("\n\n")[1])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--sizes", default=",".join(SIZES))
    r.add_argument("--ranks", default="1,2")
    r.add_argument("--variants", default="default,jacobi,before")
    r.add_argument("--dolfinx-pcs", default="gamg,jacobi")
    r.add_argument("--aries", default=os.path.join(ROOT, "build", "aries"))
    r.add_argument("--before", default=None, help="another aries build for the 'before' rows (with its defaults)")
    r.add_argument("--repeat", type=int, default=1)
    r.add_argument("--timeout", type=int, default=3600)
    p = sub.add_parser("report")
    p.add_argument("--out", default=DOCS)
    a = ap.parse_args()
    cmd_run(a) if a.cmd == "run" else cmd_report(a)


if __name__ == "__main__":
    main()
