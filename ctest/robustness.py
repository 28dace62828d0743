#!/usr/bin/env python3
"""Robustness cases of aries: kill and restart, failure policies, determinism (registered by ctest/robustness.cmake).

usage: robustness.py CASE --aries BIN --root REPO --work DIR

kill_restart   a run killed with SIGKILL mid-step and restarted from its last checkpoint ends in the same state as
               an uninterrupted run: bitwise (<= 1e-12 relative) on the same number of ranks, to 1e-8 L (solver
               tolerance) when restarted on 2 ranks; the killed run's last output step is readable.
failure_policy -on_failure stop | halve_dt | continue on a step that cannot converge within -snes_max_it: stop exits
               with code 3, halve_dt recovers by half steps and logs why, continue goes on and logs the failure;
               every run leaves readable stats and output, none hangs.
determinism    the same run twice on the same ranks gives bitwise identical stats (except wall time) and output;
               the run on 1 rank matches the 2-rank run to 1e-6 L (1% of the Newton tolerance).
"""
import argparse
import os
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np

from harness import aries_cmd, csv_rows, fail, mpi_env, step_files, step_positions, test_mesh

ARGS = None


def run(args, ranks=1, expect=0):
    c = aries_cmd(ARGS.aries, ranks, args)
    print("$ " + " ".join(c), flush=True)
    p = subprocess.run(c, capture_output=True, text=True, env=mpi_env(), cwd=ARGS.work, timeout=600)
    print("\n".join((p.stdout + p.stderr).splitlines()[-3:]))
    if expect is not None and p.returncode != expect:
        fail("exit code %d, expected %d:\n%s" % (p.returncode, expect, (p.stdout + p.stderr)[-2000:]))
    return p


def mesh(name):
    return test_mesh(ARGS.root, name)


def diagonal(base):
    """L: the diagonal of the rest shape's bounding box, from the rest coordinates an output (BASE.h5) holds."""
    with h5py.File(base + ".h5", "r") as f:
        rest = f["/mesh/rest"][:]
    return float(np.linalg.norm(rest.max(0) - rest.min(0)))


def scramble_args():
    return ["-dm_plex_filename", mesh("armadillo"), "-energy", "iarap", "-E", "1e5", "-nu", "0", "-bc_clamp",
            "hands_feet", "-initial", "scramble", "-integrator", "beuler", "-dt", "1e-2"]


def case_kill_restart():
    steps, every = 24, 4
    w = ARGS.work
    run(scramble_args() + ["-steps", str(steps), "-output", os.path.join(w, "full", "a"), "-output_every", str(steps),
                           "-stats", os.path.join(w, "full.csv")])
    reference = step_positions(os.path.join(w, "full", "a"), steps)
    L = diagonal(os.path.join(w, "full", "a"))
    ck = os.path.join(w, "killed", "a.checkpoint.h5")
    c = aries_cmd(ARGS.aries, 1, scramble_args() + ["-steps", str(steps), "-output", os.path.join(w, "killed", "a"), "-output_every", "2",
                               "-stats", os.path.join(w, "killed.csv"), "-checkpoint_every", str(every)])
    print("$ " + " ".join(c) + "   (killed with SIGKILL once a checkpoint past step 8 exists)", flush=True)
    proc = subprocess.Popen(c, env=mpi_env(), cwd=w, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    killed_at = None
    deadline = time.time() + 300
    while time.time() < deadline and proc.poll() is None:
        try:
            with h5py.File(ck, "r") as f:
                step = int(f.attrs["step"])
            if step >= 8:
                time.sleep(0.3)  # inside a later step
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
                killed_at = step
                break
        except (OSError, KeyError):
            pass
        time.sleep(0.05)
    if killed_at is None:
        proc.kill()
        fail("the run ended before it could be killed (it must still be running after its step-8 checkpoint)")
    with h5py.File(ck, "r") as f:
        ck_step = int(f.attrs["step"])
    if ck_step >= steps:
        fail("the killed run reached the last step; the kill came too late")
    # The killed run's output stays readable: every step file in its index opens.
    files = step_files(os.path.join(w, "killed", "a"))
    for fn in files:
        with h5py.File(fn, "r") as f:
            f["/positions"][:]
    print("killed after checkpoint at step %d; %d output step files readable" % (ck_step, len(files)))
    saved = os.path.join(w, "ck.h5")
    shutil.copy(ck, saved)
    run(scramble_args() + ["-steps", str(steps), "-output", os.path.join(w, "killed", "a"), "-output_every", "2",
                           "-stats", os.path.join(w, "killed.csv"), "-restart", saved])
    same = step_positions(os.path.join(w, "killed", "a"), steps)
    rel = np.abs(same - reference).max() / np.abs(reference).max()
    run(scramble_args() + ["-steps", str(steps), "-output", os.path.join(w, "two", "a"), "-output_every", str(steps),
                           "-restart", saved], ranks=2)
    two = step_positions(os.path.join(w, "two", "a"), steps)
    diff2 = np.abs(two - reference).max() / L
    st = csv_rows(os.path.join(w, "killed.csv"))
    print("restart on 1 rank: max relative difference %.3e (limit 1e-12); on 2 ranks: %.3e L (limit 1e-8; L = %.4f, "
          "the rest bounding-box diagonal); stats rows %d" % (rel, diff2, L, len(st)))
    if not rel <= 1e-12:
        fail("restarted state differs from the uninterrupted run by %.3e" % rel)
    if not diff2 <= 1e-8:
        fail("restart on 2 ranks differs by %.3e L" % diff2)
    if [int(r["step"]) for r in st] != list(range(1, steps + 1)):
        fail("the restarted stats do not list steps 1..%d once each" % steps)
    ref_rows = csv_rows(os.path.join(w, "full.csv"))
    for a, b in zip(ref_rows, st):
        for k in ("newton_its", "ksp_its", "energy", "min_alpha", "max_disp", "reason"):
            if a[k] != b[k]:
                fail("stats differ at step %s column %s: %s vs %s" % (a["step"], k, a[k], b[k]))


def case_failure_policy():
    base = ["-dm_plex_filename", mesh("cube"), "-energy", "iarap", "-E", "1e4", "-nu", "0", "-initial", "invert",
            "-integrator", "beuler", "-dt", "0.2", "-steps", "3", "-snes_max_it", "15"]
    w = ARGS.work
    results = {}
    for policy, code in (("stop", 3), ("halve_dt", 0), ("continue", 0)):
        out = os.path.join(w, policy)
        p = run(base + ["-on_failure", policy, "-output", os.path.join(out, "a"), "-stats", out + ".csv"], expect=code)
        st = csv_rows(out + ".csv")
        with h5py.File(os.path.join(out, "a.h5"), "r") as f:
            f["/mesh/topology"][:]
        last = step_files(os.path.join(out, "a"))[-1]
        with h5py.File(last, "r") as f:
            if not np.all(np.isfinite(f["/positions"][:])):
                fail("%s: the written state is not finite" % policy)
        results[policy] = [r["reason"] for r in st]
        print("%s: exit %d, reasons %s" % (policy, p.returncode, results[policy]))
    if not (len(results["stop"]) == 1 and results["stop"][0].startswith("diverged")):
        fail("stop must end after the failed first step with a diverged_* reason")
    if not (len(results["halve_dt"]) == 3 and "|halved:diverged" in results["halve_dt"][0]
            and not any(r.startswith("diverged") for r in results["halve_dt"])):
        fail("halve_dt must recover the first step by halving and log why")
    if not (len(results["continue"]) == 3 and results["continue"][0].startswith("diverged")):
        fail("continue must log the failed step and go on")


def case_determinism():
    w = ARGS.work
    outs = []
    for k in range(2):
        out = os.path.join(w, "run%d" % k)
        run(scramble_args() + ["-steps", "4", "-output", os.path.join(out, "a"), "-output_every", "4",
                               "-stats", out + ".csv"], ranks=2)
        outs.append(out)
    a, b = csv_rows(outs[0] + ".csv"), csv_rows(outs[1] + ".csv")
    for ra, rb in zip(a, b):
        for k in ra:
            if k != "wall_s" and ra[k] != rb[k]:
                fail("stats differ at step %s column %s: %s vs %s" % (ra["step"], k, ra[k], rb[k]))
    pa, pb = step_positions(os.path.join(outs[0], "a"), 4), step_positions(os.path.join(outs[1], "a"), 4)
    print("identical stats (%d rows, all columns but wall_s); max position difference %.3e" %
          (len(a), np.abs(pa - pb).max()))
    if not np.array_equal(pa, pb):
        fail("the two runs differ bitwise")
    # The same run on one rank: a different partition changes the summation order, so agreement is to solver
    # tolerance, not bitwise: the scramble's chaotic second step amplifies round-off to ~2e-7 L (the Newton
    # tolerance is 1e-4 L); 1e-6 L is 1% of it.
    one = os.path.join(w, "one")
    run(scramble_args() + ["-steps", "4", "-output", os.path.join(one, "a"), "-output_every", "4"])
    p1 = step_positions(os.path.join(one, "a"), 4)
    L = diagonal(os.path.join(one, "a"))
    d12 = np.abs(p1 - pa).max() / L
    print("1 vs 2 ranks: max position difference %.3e L (limit 1e-6; L = %.4f, the rest bounding-box diagonal)"
          % (d12, L))
    if not d12 <= 1e-6:
        fail("1 and 2 ranks differ by %.3e L" % d12)


def main():
    global ARGS
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--aries", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--work", required=True)
    ARGS = ap.parse_args()
    shutil.rmtree(ARGS.work, ignore_errors=True)
    os.makedirs(ARGS.work)
    {"kill_restart": case_kill_restart, "failure_policy": case_failure_policy,
     "determinism": case_determinism}[ARGS.case]()
    print("PASS")


if __name__ == "__main__":
    main()
