#!/usr/bin/python3
"""Degenerate starts with a volume term (issue 49): dynamic scrambles at nu 0, 0.3, 0.45 for iarap, fiber (along x
and oblique) and ortho on meshes the scenes do not use, seeds 1-3, 1 and 2 ranks; the static scramble and the
inside-out start at nu 0.3 and 0.45; and, for comparison, the dynamic scramble without the shape stage
(-beuler_shape_first 0, the behaviour before it) on one seed. With --variant "OPTIONS", every dynamic run is made a
second time with those solver options added, and the report compares the two per energy and nu (how a candidate
default is judged).

Each dynamic run: backward Euler dt 1e-2, density 1000, gravity -9.81 z, E 1e4, 2 steps, the lowest tenth of the
body's height held (-bc_box), every free vertex scrambled (-initial scramble). Reported per run from -stats: step 1's
Newton updates, CG iterations, linear solves stopped at -ksp_max_it and wall seconds; whether every step converged;
and step 2's updates. The summary gives, per energy and nu, the medians over meshes, seeds and ranks and their ratio
to nu 0's.

usage: /usr/bin/python3 bench/degenerate_starts.py [--build build] [--energies A,B] [--meshes M,N] [--seeds 1,2,3]
                                                  [--ranks 1,2] [--nus 0,0.3,0.45] [--timeout S] [--no-static]
                                                  [--no-before] [--extra "OPTIONS"] [--variant "OPTIONS"] [--out NAME]
                                                  [--start scramble|invert] [--no-dynamic] [--no-invert]
                                                  [--static-extra "OPTIONS"]
  defaults: the energies iarap, fiber x, fiber oblique and ortho (also known: ortho equal, ortho mild: the ortho
  basis with equal moduli and with 1.2 : 1 : 0.8), every mesh, seed 1-3, 1 and 2 ranks, nu 0, 0.3 and 0.45, 1800 s
  per run, the static starts and the runs without the shape stage too (--no-static, --no-before skip them), no
  variant; --extra adds options to every dynamic run (e.g. "-snes_max_it 60 -on_failure continue": a stalling run then
  ends with the statistics of where it stalled instead of at --timeout; with the default -on_failure stop, a failed
  step's row is the last accepted state's); --out NAME writes bench/results/NAME.md (default degenerate_starts);
  --start invert makes the dynamic runs start inside out (x = -X about the centroid) instead of scrambled;
  --no-dynamic runs the static starts only; --static-extra "OPTIONS" adds options to every static run; --no-invert leaves the static inside-out start out (it has no seed: a
  run over further seeds need not repeat it); --runs FILE,... reports the runs recorded in earlier outputs of this
  script (its per-run JSON lines) instead of running (several benches, e.g. one per rank count, in one report);
  --against FILE,... pairs the static runs with earlier records of the same starts (e.g. without --static-extra);
  --work DIR: the runs' scratch folder (one per bench run at the same time). A
  run past --timeout is reported as not converged. Each run's step-1 least band coordinate is reported against the
  band of the singularity mollifier (Eq. 33: the coordinate in [eps, 3 eps], eps = -mollifier_eps; the coordinate is
  alpha, or its scale-free form where the run's console names that band, -mollifier_measure): a run that stalls with
  its least coordinate there is held by the band (see "Where the runs end" in the report), and the signed principal
  stretches of the cell with that coordinate, read from step 1's written state (-output_fields
  alpha,principal_stretches), with their relative gap (s2 + s3) / s2: how close the cell is to the singular set
  s2 = -s3 of I4 (Sec. 4). The static starts (the scramble for every --seeds value and inside out, nu 0.3 and 0.45,
  every --ranks value) run every energy of --energies.
"""
import argparse
import csv
import datetime
import itertools
import json
import math
import os
import shlex
import statistics
import shutil
import subprocess
import sys
import time

import re

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# a static start ends at rest when its elastic energy is at most this (E 1e4, bodies ~20 across: E V ~ 1e7; the rest
# shape's energy is round-off, |E| ~ 1e-13)
REST_ENERGY = 1e-6
MESHES = ["camel", "triceratops", "hand"]  # meshes/generate.sh NAME default: 16.6k, 30.2k, 34.1k tets
ENERGIES = {
    "iarap": ["-energy", "iarap"],
    "fiber x": ["-energy", "fiber", "-gamma", "5e3", "-fiber", "1,0,0"],
    "fiber oblique": ["-energy", "fiber", "-gamma", "5e3", "-fiber", "1,0.5,0.2"],
    "ortho": ["-energy", "ortho", "-ortho_mu", "3846,7692,1923", "-fiber", "1,0.5,0.2", "-fiber2", "0,1,0"],
    # controls for ortho: the same basis with equal moduli (iarap's energy through the direction terms) and a mild
    # anisotropy (1.2 : 1 : 0.8); not in the default set
    "ortho equal": ["-energy", "ortho", "-ortho_mu", "3846,3846,3846", "-fiber", "1,0.5,0.2", "-fiber2", "0,1,0"],
    "ortho mild": ["-energy", "ortho", "-ortho_mu", "3846,4615,3077", "-fiber", "1,0.5,0.2", "-fiber2", "0,1,0"],
}
DEFAULT_ENERGIES = ["iarap", "fiber x", "fiber oblique", "ortho"]
MOLLIFIER_EPS = 1e-3  # aries' -mollifier_eps default on alpha: the band of Eq. (33) is alpha in [eps, 3 eps]
# aries' console line for a band on the scale-free coordinate (the default of these dynamic starts with anisotropic
# I4/I6 terms, or -mollifier_measure scale_free)
SCALE_FREE_LINE = re.compile(r"the singularity mollifier's band is on the scale-free coordinate, eps (\S+) ")
NUS = ["0", "0.3", "0.45"]
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1")


def mesh_path(name):
    out = subprocess.run([os.path.join(ROOT, "meshes", "generate.sh"), name, "default"], stdout=subprocess.PIPE,
                         check=True, text=True).stdout.strip()
    info = json.load(open(out[:-4] + ".json"))
    lo, hi = info["bbox_min"], info["bbox_max"]
    held = f"-10,10,-10,10,-10,{lo[2] + 0.1 * (hi[2] - lo[2]):.6g}"
    return out, info["tets"], held


def run(build, ranks, args, stats, timeout=1800):
    cmd = (["mpiexec", "-n", str(ranks)] if ranks > 1 else []) + [os.path.join(build, "aries")] + args
    cmd += ["-stats", stats]
    if os.path.exists(stats):
        os.remove(stats)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                              timeout=timeout, start_new_session=True)
    except subprocess.TimeoutExpired:
        subprocess.run(["pkill", "-f", os.path.join(build, "aries")])
        return 124, [], time.perf_counter() - t0, [f"timeout after {timeout:.0f} s"], ""
    wall = time.perf_counter() - t0
    rows = list(csv.DictReader(line for line in open(stats) if not line.startswith("#"))) if os.path.exists(stats) \
        else []
    return proc.returncode, rows, wall, proc.stderr.strip().splitlines()[-1:] if proc.returncode else [], proc.stdout


# aries' reasons of a converged step (solver::reasonName; a step recovered by -on_failure halve_dt appends
# "|halved:<failure>" to its final reason). Anything else is a failure: diverged_*, safeguard_load, ...
CONVERGED_REASONS = {"converged_initial", "newton_step", "step_bound", "energy_roundoff", "fnorm_abs", "fnorm_rel",
                     "snorm_rel", "its"}


def step_converged(reason):
    """A step's stats reason is a convergence (-on_failure continue goes on after a failed step: its reason says)."""
    return reason.split("|")[0] in CONVERGED_REASONS


def mollifier_eps(options):
    """The band parameter eps of Eq. (33) that a run's options give (the last -mollifier_eps, else aries' default)."""
    eps = MOLLIFIER_EPS
    for k, o in enumerate(options[:-1]):
        if o == "-mollifier_eps":
            eps = float(options[k + 1])
    return eps


def band_of(console, options):
    """The run's band: ("scale_free", eps) where its console names it, else ("alpha", the options' eps)."""
    m = SCALE_FREE_LINE.search(console or "")
    return ("scale_free", float(m.group(1))) if m else ("alpha", mollifier_eps(options))


def least_band_cell(path, measure):
    """(least band coordinate, that cell's signed principal stretches (s1 >= s2 >= |s3|; s3 < 0: inverted)) in a
    written state, or (nan, None) where the step wrote none (a run stopped before it). The coordinate is alpha, or on
    the scale-free band alpha (I_C / 3)^(-3/2) (kernels/alpha.hpp, scaleFreeAlpha), from the stretches: both are
    functions of them (alpha = 8 (s1+s2)(s1+s3)(s2+s3), Eq. 28), one point per P1 tet."""
    if not os.path.exists(path):
        return float("nan"), None
    with h5py.File(path, "r") as f:
        alpha = f["cell/alpha"][()].ravel()
        stretches = f["cell/principal_stretches"][()].reshape(-1, 3)
    if measure == "scale_free":
        ic = (stretches ** 2).sum(axis=1)
        alpha = alpha * (ic / 3.0) ** -1.5
    k = int(np.argmin(alpha))
    return float(alpha[k]), [float(v) for v in stretches[k]]


def relative_gap(s):
    """(s2 + s3) / s2 of signed principal stretches: 0 on the singular set of I4 (alpha = 8 (s1+s2)(s1+s3)(s2+s3))."""
    return (s[1] + s[2]) / s[1] if s else float("nan")


def stretches_text(s):
    return ", ".join("%.3g" % v for v in s) if s else "-"


def band_ratio(r):
    """A run's step-1 least band coordinate over the top of the mollifier's band, 3 eps (Eq. 33: [eps, 3 eps]); on
    alpha it is the statistics' min alpha (every quadrature point), on the scale-free band the written state's."""
    return (r["min_alpha"] if r["band"] == "alpha" else r["min_band"]) / (3.0 * r["eps"])


def at_band(r):
    """The least coordinate in the band or at its top edge (within 10% above 3 eps), where the I4/I6 terms' forces
    peak."""
    return 1.0 / 3.0 <= band_ratio(r) <= 1.1


def to_nu0(med, base, key):
    """A median over nu 0's for the same energy, as table text; blank where nu 0 is not run or did not converge."""
    return f"{med[key] / base[key]:.2f}" if base else ""


def medians(runs, energy, nu, keys=("updates", "cg", "seconds")):
    """The converged runs of one energy and nu: their count and the median of each key (None if there are none)."""
    rs = [r for r in runs if r["energy"] == energy and r["nu"] == nu and r["ok"]]
    return len(rs), ({k: statistics.median(r[k] for r in rs) for k in keys} if rs else None)


def read_records(paths):
    """The per-run JSON lines this script printed, from comma-separated files (a saved console may hold other JSON,
    such as a mesh build's report: only lines that start as a record are read)."""
    return [json.loads(line) for path in filter(None, paths.split(",")) for line in open(path)
            if line.startswith('{"mesh"')]


def static_converged(r):
    """A static record's run exited 0 with a converged step."""
    return r["rc"] == 0 and step_converged(r["reason"])


def seed_of(r):
    """A static record's scramble seed: records without one ran the default -scramble_seed 1 (inside out: none)."""
    return r.get("seed") or (1 if r["start"] == "scramble" else None)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--energies", default=",".join(DEFAULT_ENERGIES))
    parser.add_argument("--meshes", default=",".join(MESHES))
    parser.add_argument("--seeds", default="1,2,3")
    parser.add_argument("--ranks", default="1,2")
    parser.add_argument("--nus", default=",".join(NUS))
    parser.add_argument("--timeout", type=float, default=1800)
    parser.add_argument("--extra", default="", help="options added to every dynamic run")
    parser.add_argument("--no-static", action="store_true")
    parser.add_argument("--no-invert", action="store_true", help="the static starts without inside out")
    parser.add_argument("--static-extra", default="", help="options added to every static run")
    parser.add_argument("--no-dynamic", action="store_true", help="only the static starts")
    parser.add_argument("--no-before", action="store_true", help="skip the runs without the shape stage")
    parser.add_argument("--variant", default="", help="solver options every dynamic run is repeated with")
    parser.add_argument("--start", default="scramble", choices=("scramble", "invert"),
                        help="the dynamic runs' -initial (invert: deterministic, so one seed)")
    parser.add_argument("--out", default="degenerate_starts")
    parser.add_argument("--runs", default="",
                        help="report the runs recorded in these files (comma-separated; the JSON lines this script "
                             "prints per run, e.g. its saved output) instead of running")
    parser.add_argument("--against", default="",
                        help="static records to compare with (comma-separated files as for --runs, e.g. the same "
                             "starts without --static-extra): each static run of this report is paired with the record "
                             "of the same mesh, energy, start, seed, ranks and nu, and the report gives per energy the "
                             "pairs' converged and at-rest counts on both sides and their median ratios")
    parser.add_argument("--work", default=os.path.join(ROOT, "out", "bench", "degenerate_starts"),
                        help="scratch folder of the runs' states and stats (one per concurrent bench)")
    args = parser.parse_args()
    meshes = args.meshes.split(",")
    seeds = [int(x) for x in args.seeds.split(",")]
    if args.start == "invert" and len(seeds) > 1:
        sys.exit("degenerate_starts: error: --start invert is deterministic: give one --seeds value")
    ranks_list = [int(x) for x in args.ranks.split(",")]
    energies = args.energies.split(",")
    for e in energies:
        if e not in ENERGIES:
            sys.exit(f"degenerate_starts: error: unknown energy '{e}' (known: {', '.join(ENERGIES)})")
    nus = args.nus.split(",")
    for nu in nus:
        if nu not in NUS:
            sys.exit(f"degenerate_starts: error: --nus: unknown nu '{nu}' (known: {', '.join(NUS)})")
    extra_all = args.extra.split()
    work = args.work
    os.makedirs(work, exist_ok=True)
    results, lines = [], []
    started = time.perf_counter()

    def dynamic(mesh, tets, held, energy, nu, seed, ranks, extra=()):
        a = ["-dm_plex_filename", mesh, "-E", "1e4", "-nu", nu, "-integrator", "beuler", "-dt", "1e-2",
             "-steps", "2", "-density", "1000", "-gravity", "0,0,-9.81", "-initial", args.start] + \
            (["-scramble_seed", str(seed)] if args.start == "scramble" else []) + \
            ["-bc_box", held] + ENERGIES[energy] + extra_all + list(extra)
        state = os.path.join(work, "state")
        shutil.rmtree(state + ".steps", ignore_errors=True)
        a += ["-output", state, "-output_fields", "alpha,principal_stretches"]
        rc, rows, wall, err, console = run(args.build, ranks, a, os.path.join(work, "stats.csv"), args.timeout)
        ok = rc == 0 and len(rows) == 2 and all(step_converged(r["reason"]) for r in rows)
        s1 = rows[0] if rows else {}
        band, eps = band_of(console, extra_all + list(extra))
        min_band, stretches = least_band_cell(state + ".steps/state_000001.h5", band)
        return dict(mesh=os.path.basename(mesh), tets=tets, energy=energy, nu=nu, seed=seed, ranks=ranks, ok=ok,
                    rc=rc, updates=int(s1.get("newton_its", -1)), cg=int(s1.get("ksp_its", -1)),
                    at_limit=int(s1.get("ksp_at_limit", -1)), seconds=float(s1.get("wall_s", "nan")),
                    step2=int(rows[1]["newton_its"]) if len(rows) > 1 else -1, reason=s1.get("reason", str(err)),
                    energy_value=float(s1.get("energy", "nan")), min_alpha=float(s1.get("min_alpha", "nan")),
                    band=band, eps=eps, min_band=min_band, extra=" ".join(extra), stretches=stretches)

    recorded = read_records(args.runs)
    results += [r for r in recorded if "start" not in r]  # the static runs' records name their start
    for name in [] if args.no_dynamic or args.runs else meshes:
        mesh, tets, held = mesh_path(name)
        for energy in energies:
            for nu in nus:
                for seed in seeds:
                    for ranks in ranks_list:
                        r = dynamic(mesh, tets, held, energy, nu, seed, ranks)
                        results.append(r)
                        print(json.dumps(r), flush=True)
                        if args.variant:
                            r = dynamic(mesh, tets, held, energy, nu, seed, ranks, args.variant.split())
                            r["variant"] = True
                            results.append(r)
                            print(json.dumps(r), flush=True)
        for energy in [] if args.no_before else energies:  # before: no shape stage (nu 0.3, seed 1, 2 ranks)
            r = dynamic(mesh, tets, held, energy, "0.3", 1, 2, ["-beuler_shape_first", "0"])
            results.append(r)
            print(json.dumps(r), flush=True)

    static = [r for r in recorded if "start" in r]
    against = [r for r in read_records(args.against) if "start" in r]
    for name in [] if args.no_static or args.runs else meshes:
        mesh, tets, held = mesh_path(name)
        starts = [("scramble", seed) for seed in seeds] + \
            ([] if args.no_invert else [("invert", None)])  # inside out is deterministic: no seed
        for energy, (start, seed), nu, ranks in itertools.product(energies, starts, ("0.3", "0.45"), ranks_list):
            a = ["-dm_plex_filename", mesh, "-E", "1e4", "-nu", nu, "-integrator", "static", "-steps", "1",
                 "-initial", start, "-bc_box", held] + ENERGIES[energy] + \
                (["-scramble_seed", str(seed)] if seed is not None else []) + args.static_extra.split()
            rc, rows, wall, err, _ = run(args.build, ranks, a, os.path.join(work, "stats.csv"), args.timeout)
            s1 = rows[0] if rows else {}
            static.append(dict(mesh=name, tets=tets, energy=energy, start=start, seed=seed, ranks=ranks, nu=nu, rc=rc,
                               updates=int(s1.get("newton_its", -1)), cg=int(s1.get("ksp_its", -1)),
                               at_limit=int(s1.get("ksp_at_limit", -1)), seconds=float(s1.get("wall_s", "nan")),
                               reason=s1.get("reason", str(err)), energy_value=float(s1.get("energy", "nan")),
                               **({"options": args.static_extra} if args.static_extra else {})))
            print(json.dumps(static[-1]), flush=True)

    source = (f"from the {len(recorded)} runs recorded in {args.runs} (one JSON line per run, written as it "
              "finished)" if args.runs else f"{time.perf_counter() - started:.0f} s")
    main_runs = [r for r in results if not r["extra"]]
    variant_runs = [r for r in results if r.get("variant")]
    lines += [f"# Degenerate starts with a volume term", "",
              f"Generated by `bench/degenerate_starts.py {shlex.join(sys.argv[1:])}` on {os.cpu_count()} cores, "
              f"{datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, {source}. Dynamic "
              f"{'scramble' if args.start == 'scramble' else 'inside-out start (-initial invert)'}: backward Euler dt 1e-2, density 1000, gravity, E 1e4, 2 steps, the lowest tenth held; "
              "meshes " + ", ".join(f"{m} default" for m in meshes) + f"; seeds {seeds}; ranks {ranks_list}. "
              "Step 1 unless said.", "",
              f"Every dynamic run converged in both steps: **{all(r['ok'] for r in main_runs)}** "
              f"({sum(r['ok'] for r in main_runs)} of {len(main_runs)}); step-1 linear solves at -ksp_max_it in these "
              f"runs (the variant's not counted): **{sum(r['at_limit'] for r in main_runs)}**.", "",
              "## Medians per energy and nu (over meshes, seeds and ranks)", "",
              "| energy | nu | runs | step-1 updates | CG iterations | seconds | updates / nu 0 | CG / nu 0 | "
              "seconds / nu 0 | step-2 updates |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for energy in energies:
        base = None
        for nu in nus:
            count, med = medians(main_runs, energy, nu, ("updates", "cg", "seconds", "step2"))
            if not med:
                lines.append(f"| {energy} | {nu} | 0 | (no run converged) | | | | | | |")
                continue
            if nu == "0":
                base = med
            lines.append(f"| {energy} | {nu} | {count} | {med['updates']:.0f} | {med['cg']:.0f} | "
                         f"{med['seconds']:.2f} | {to_nu0(med, base, 'updates')} | {to_nu0(med, base, 'cg')} | "
                         f"{to_nu0(med, base, 'seconds')} | {med['step2']:.0f} |")
    if variant_runs:
        lines += ["", f"## With `{args.variant}` (the same runs; medians, ratio to the runs above)", "",
                  f"Every run converged in both steps: **{all(r['ok'] for r in variant_runs)}** "
                  f"({sum(r['ok'] for r in variant_runs)} of {len(variant_runs)}).", "",
                  "| energy | nu | runs | step-1 updates | CG iterations | seconds | seconds / nu 0 | updates / above | "
                  "CG / above | seconds / above |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for energy in energies:
            base = None
            for nu in nus:
                count, med = medians(variant_runs, energy, nu)
                ref = medians(main_runs, energy, nu)[1]
                if not med or not ref:
                    lines.append(f"| {energy} | {nu} | {count} | (no comparison: a side did not converge) "
                                 "| | | | | | |")
                    continue
                if nu == "0":
                    base = med
                lines.append(f"| {energy} | {nu} | {count} | {med['updates']:.0f} | {med['cg']:.0f} | "
                             f"{med['seconds']:.2f} | {to_nu0(med, base, 'seconds')} | "
                             f"{med['updates'] / ref['updates']:.2f} | {med['cg'] / ref['cg']:.2f} | "
                             f"{med['seconds'] / ref['seconds']:.2f} |")
    lines += ["", "## Worst run per energy and nu", "",
              "| energy | nu | mesh | seed | ranks | step-1 updates | CG | at limit | seconds |",
              "|---|---:|---|---:|---:|---:|---:|---:|---:|"]
    for energy in energies:
        for nu in nus:
            rs = [r for r in main_runs if r["energy"] == energy and r["nu"] == nu]
            if not rs:
                continue
            r = max(rs, key=lambda r: (not r["ok"], r["updates"], r["cg"], r["seconds"]))
            lines.append(f"| {energy} | {nu} | {r['mesh']} | {r['seed']} | {r['ranks']} | {r['updates']} | {r['cg']} | "
                         f"{r['at_limit']} | {r['seconds']:.2f} |")
    lines += ["", "## Rank independence (step-1 energy, 1 vs 2 ranks)", ""]
    worst = 0.0
    for r1 in (r for r in main_runs if r["ranks"] == 1):
        for r2 in main_runs:
            if r2["ranks"] == 2 and all(r2[k] == r1[k] for k in ("mesh", "energy", "nu", "seed")):
                worst = max(worst, abs(r1["energy_value"] - r2["energy_value"]) / abs(r2["energy_value"]))
    lines.append(f"Largest relative difference of step 1's elastic energy between 1 and 2 ranks: {worst:.2e}" if
                 any(r["ranks"] == 1 for r in main_runs) else "(one rank count only)")
    before = [r for r in results if r["extra"] and not r.get("variant")]
    if before:
        lines += ["", "## Without the shape stage (-beuler_shape_first 0: before), nu 0.3, seed 1, 2 ranks", "",
                  "| mesh | energy | converged | step-1 updates | CG | at limit | seconds | with the stage: converged | "
                  "updates | CG | at limit | seconds |", "|---|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|"]
    for r in before:
        w = next((x for x in main_runs if x["mesh"] == r["mesh"] and x["energy"] == r["energy"] and x["nu"] == r["nu"]
                  and x["seed"] == 1 and x["ranks"] == 2), None)
        if w:
            lines.append(f"| {r['mesh']} | {r['energy']} | {r['ok']} | {r['updates']} | {r['cg']} | {r['at_limit']} | "
                         f"{r['seconds']:.2f} | {w['ok']} | {w['updates']} | {w['cg']} | {w['at_limit']} | "
                         f"{w['seconds']:.2f} |")
    static_from = len(lines)
    if static:
        converged = [r for r in static if static_converged(r)]
        lines += ["", "## Static starts (the detached start)", "",
                  f"Every static run converged: **{len(converged) == len(static)}** ({len(converged)} of "
                  f"{len(static)}); linear solves at -ksp_max_it: **{sum(max(r['at_limit'], 0) for r in static)}**; "
                  "ranks " + ", ".join(str(k) for k in sorted({r.get("ranks", 2) for r in static})) + ", the "
                  "scrambles' seeds " + ", ".join(str(k) for k in sorted({seed_of(r) for r in static
                                                                          if r["start"] == "scramble"})) +
                  " (records without a seed or rank count: seed 1, 2 ranks).", ""]
        pairs = [(a, b) for a in converged for b in converged if a.get("ranks", 2) == 1 and b.get("ranks", 2) == 2 and
                 all(a.get(k) == b.get(k) for k in ("mesh", "energy", "start", "nu")) and seed_of(a) == seed_of(b)]
        # A static start's solution is the rest shape (no load; the held box fixes the rigid motions): its elastic
        # energy is 0 up to round-off (|E| ~ 1e-13 here), so a relative difference between ranks says nothing; a run
        # that ends elsewhere (a tangled equilibrium the safeguard cannot leave) is named instead.
        valued = [r for r in converged if "energy_value" in r]
        away = [r for r in valued if abs(r["energy_value"]) > REST_ENERGY]
        if valued:
            lines += [f"Converged runs that end at the rest shape (|elastic energy| <= {REST_ENERGY:g}): "
                      f"**{len(valued) - len(away)} of {len(valued)}**" +
                      ("; elsewhere: " + "; ".join(
                          f"{r['mesh']} {r['energy']} {r['start']} seed {seed_of(r)} {r.get('ranks', 2)} rank(s) "
                          f"nu {r['nu']}: energy {r['energy_value']:.3g}" for r in away) if away else "") + ".", ""]
        if pairs:
            lines += [f"1 against 2 ranks, the same start ({len(pairs)} pairs, both converged): updates "
                      f"{statistics.median(a['updates'] / b['updates'] for a, b in pairs):.2f}x (median).", ""]
        if against:
            def key(r):
                return r["mesh"], r["energy"], r["start"], seed_of(r), r.get("ranks", 2), r["nu"]

            def at_rest(side):  # "N of M": of the M runs whose energy was recorded (older records have none)
                valued = [r for r in side if "energy_value" in r]
                rest = [r for r in valued if static_converged(r) and abs(r["energy_value"]) <= REST_ENERGY]
                return f"{len(rest)} of {len(valued)}"

            reference = {key(r): r for r in against}
            matched = [(r, reference[key(r)]) for r in static if key(r) in reference]
            lines += [f"Against the records of `{args.against}`: {len(matched)} of these {len(static)} runs paired "
                      "(the same mesh, energy, start, seed, ranks and nu); ratios are this report's / theirs, medians "
                      "over the pairs where both converged.", "",
                      "| energy | pairs | converged: here / there | at rest (of those with an energy): here / there | updates ratio | "
                      "seconds ratio | at limit: here / there | seconds summed: here / there |",
                      "|---|---:|---|---|---:|---:|---|---|"]
            for energy in energies + ["all"]:
                ps = [(a, b) for a, b in matched if energy in ("all", a["energy"])]
                both = [(a, b) for a, b in ps if static_converged(a) and static_converged(b)]
                if not ps:
                    continue
                ratio = (lambda k: f"{statistics.median(a[k] / b[k] for a, b in both):.2f}x") if both else \
                    (lambda k: "-")
                lines.append(f"| {energy} | {len(ps)} | {sum(static_converged(a) for a, _ in ps)} / "
                             f"{sum(static_converged(b) for _, b in ps)} | {at_rest([a for a, _ in ps])} / "
                             f"{at_rest([b for _, b in ps])} | {ratio('updates')} | {ratio('seconds')} | "
                             f"{sum(max(a['at_limit'], 0) for a, _ in ps)} / {sum(max(b['at_limit'], 0) for _, b in ps)} | "
                             f"{sum(a['seconds'] for a, _ in ps):.0f} / {sum(b['seconds'] for _, b in ps):.0f} |")
            lines.append("")
        lines += ["| energy | start | nu | runs | converged | updates: median / max | CG: median | at limit | "
                  "seconds: median / max |", "|---|---|---:|---:|---:|---|---:|---:|---|"]
        for energy, start, nu in itertools.product(energies, ("scramble", "invert"), ("0.3", "0.45")):
            rs = [r for r in static if (r["energy"], r["start"], r["nu"]) == (energy, start, nu)]
            ok = [r for r in rs if r in converged]
            if rs and ok:
                lines.append(f"| {energy} | {start} | {nu} | {len(rs)} | {len(ok)} | "
                             f"{statistics.median(r['updates'] for r in ok):.0f} / {max(r['updates'] for r in ok)} | "
                             f"{statistics.median(r['cg'] for r in ok):.0f} | {sum(max(r['at_limit'], 0) for r in rs)} | "
                             f"{statistics.median(r['seconds'] for r in ok):.2f} / {max(r['seconds'] for r in ok):.2f} |")
            elif rs:
                lines.append(f"| {energy} | {start} | {nu} | {len(rs)} | 0 | | | | |")
        lines += ["", "| mesh | energy | start | seed | ranks | nu | exit | updates | CG | at limit | seconds | reason | "
                  "elastic energy |", "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"]
    for r in static:
        lines.append(f"| {r['mesh']} | {r['energy']} | {r['start']} | {seed_of(r) or '-'} | {r.get('ranks', 2)} | "
                     f"{r['nu']} | {r['rc']} | {r['updates']} | {r['cg']} | {r['at_limit']} | {r['seconds']:.2f} | "
                     f"{r['reason']} | " + (f"{r['energy_value']:.3g}" if "energy_value" in r else "-") + " |")
    static_to = len(lines)
    failed = [r for r in results if not r["ok"]]
    lines += ["", "## Where the runs end (step 1's least band coordinate against the mollifier's band)", "",
              "The singularity mollifier (Eq. 33) blends the I4/I6 terms out where the band's coordinate is in "
              "[eps, 3 eps] (eps = -mollifier_eps; the coordinate is alpha, or on the scale-free band alpha (I_C / 3)"
              "^(-3/2), column 'band'); 'coord. / 3 eps' is step 1's least coordinate over the band's top, at the "
              "last iterate (converged or not). Runs that converged: %d, coord. / 3 eps %s. Runs that did not: %d; "
              "of them %d with the least coordinate in the band or at its top edge (coord. / 3 eps in [1/3, 1.1]), "
              "%d below the band, %d without statistics (stopped by --timeout). (aries' console line for a failed "
              "step counts the cells in [eps, 2 x 3 eps].)" % (
                  len(results) - len(failed),
                  "from %.3g to %.3g" % (min(band_ratio(r) for r in results if r["ok"]),
                                         max(band_ratio(r) for r in results if r["ok"]))
                  if len(failed) < len(results) else "(none)",
                  len(failed), sum(at_band(r) for r in failed), sum(band_ratio(r) < 1.0 / 3.0 for r in failed),
                  sum(math.isnan(r["min_alpha"]) for r in failed))]
    held = [r for r in failed if at_band(r) and r["stretches"]]
    if held:
        lines += ["", "The least-coordinate cell of each of those %d failed runs held at the band: inverted in %d (s3 < 0), "
                  "stretches s1 from %.3g to %.3g and s2 from %.3g to %.3g, relative gap (s2 + s3) / s2 from %.3g to "
                  "%.3g. Near s2 = -s3, alpha = 8 (s1+s2)(s1+s3)(s2+s3) is linear in the gap with the factor 8 (s1+s2)"
                  "(s1+s3): the larger the stretches, the smaller the gap at the band's top (alpha = 3 eps), and the "
                  "I4 terms' derivatives grow with its inverse powers." % (
                      len(held), sum(r["stretches"][2] < 0 for r in held),
                      min(r["stretches"][0] for r in held), max(r["stretches"][0] for r in held),
                      min(r["stretches"][1] for r in held), max(r["stretches"][1] for r in held),
                      min(relative_gap(r["stretches"]) for r in held), max(relative_gap(r["stretches"]) for r in held))]
    lines += ["", "## Every dynamic run", "", "| mesh | energy | nu | seed | ranks | converged | step-1 updates | CG | "
              "at limit | seconds | step-1 min alpha | band, eps | coord. / 3 eps | its cell's stretches | "
              "(s2 + s3) / s2 | step-2 updates | reason | options |",
              "|---|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---|---:|---|---:|---:|---|---|"]
    for r in results:
        lines.append(f"| {r['mesh']} | {r['energy']} | {r['nu']} | {r['seed']} | {r['ranks']} | {r['ok']} | "
                     f"{r['updates']} | {r['cg']} | {r['at_limit']} | {r['seconds']:.2f} | {r['min_alpha']:.3g} | "
                     f"{r['band']}, {r['eps']:g} | {band_ratio(r):.3g} | {stretches_text(r['stretches'])} | {relative_gap(r['stretches']):.3g} | "
                     f"{r['step2']} | {r['reason']} | "
                     f"{' '.join(extra_all + r['extra'].split())} |")
    if not results:  # no dynamic run (--no-dynamic, or static records only): the header (its first two lines, the
        # run's command) and the static table
        lines = lines[:2] + [f"Generated by `bench/degenerate_starts.py {shlex.join(sys.argv[1:])}` on "
                             f"{os.cpu_count()} cores, {datetime.datetime.utcnow():%Y-%m-%d %H:%M} UTC, "
                             f"{source}: the static starts only (no dynamic runs)."] + \
            lines[static_from:static_to]
    text = "\n".join(lines) + "\n"
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    with open(os.path.join(ROOT, "bench", "results", args.out + ".md"), "w") as f:
        f.write(text)
    print(text)
    return 0 if all(r["ok"] for r in main_runs) else 1


if __name__ == "__main__":
    sys.exit(main())
