"""End-to-end cases: cloth (hanging, dropped on a sphere, bw461 against bw46) and the UV parameterization of a disk."""
import os
import re
import subprocess
import sys

import h5py
import numpy as np

from harness import fail, step_files
from .common import ARGS, cloth_args, mesh, out_base, read_state, run, stats


def last_residual(log):
    vals = re.findall(r"\|r\| (\S+)", log)
    if not vals:
        fail("no residual on the step lines")
    return float(vals[-1])


def case_cloth_hang():
    """A cloth hanging from two corners reaches static equilibrium: zero net force on the free vertices (the Newton
    residual is at round-off level relative to the weight) and the corner reactions carry exactly the weight of the
    free vertices."""
    tag = "cloth_hang_np%d" % ARGS.ranks
    rho, g = 0.1, 9.8
    log, _ = run(cloth_args(mesh("cloth")) + ["-energy", "bw46", "-mu1", "20", "-bending", "1e-3", "-bc_clamp",
                 "top_corners", "-density", str(rho), "-gravity", "0,0,-%g" % g, "-steps", "1", "-newton_tol",
                 "1e-6", "-output", out_base(tag), "-reactions", out_base(tag) + "_reactions.csv"], tag=tag)
    rest, cells, x, _ = read_state(out_base(tag))
    tri = rest[cells]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    mass = np.zeros(len(rest))
    np.add.at(mass, cells.ravel(), np.repeat(rho * area / 3, 3))
    corners = [i for i, p in enumerate(rest) if abs(p[1] - 1) < 1e-12 and (abs(p[0]) < 1e-12 or abs(p[0] - 1) < 1e-12)]
    free_weight = (mass.sum() - mass[corners].sum()) * g
    fz = float(stats(out_base(tag) + "_reactions.csv")[-1]["fz"])
    res = last_residual(log)
    print("corner reaction %.12g, weight of the free vertices %.12g; residual %.3e (weight %.3e); sag %.3f"
          % (fz, free_weight, res, free_weight, -x[:, 2].min()))
    if not abs(fz - free_weight) <= 1e-6 * free_weight:
        fail("reaction %.12g does not balance the weight %.12g" % (fz, free_weight))
    if not res <= 1e-6 * free_weight:
        fail("net force on the free vertices %.3e is not ~0 (weight %.3e)" % (res, free_weight))
    if not -x[:, 2].min() > 0.05:
        fail("the cloth did not sag")


def case_cloth_sphere():
    """A cloth dropped on a sphere never penetrates it (nor the ground): every vertex keeps a positive distance at
    every output step. The Hessian (cells, bending hinges, contact) is fully preallocated: no assembly mallocs, in
    the matrix nor in the stash of off-rank entries (PETSc -info reports both at every assembly)."""
    tag = "cloth_sphere_np%d" % ARGS.ranks
    center, radius = np.array([0.5, 0.5, -0.3]), 0.25
    log, _ = run(cloth_args(mesh("cloth")) + ["-options_file", os.path.join(ARGS.root, "options", "cloth_drop_ours.yml"),
                 "-dm_plex_filename", mesh("cloth"), "-steps", "150", "-output", out_base(tag), "-output_every", "5",
                 "-stats", out_base(tag) + ".csv", "-info", ":mat"], tag=tag)
    mallocs = [int(m) for m in re.findall(r"Number of mallocs during MatSetValues is (\d+)", log)]
    print("matrix assemblies: %d, mallocs during MatSetValues: %d" % (len(mallocs), sum(mallocs)))
    if not mallocs:
        fail("-info :mat reported no matrix assembly: the malloc check did not run")
    if sum(mallocs):
        fail("%d mallocs during Hessian assembly: a coupling is not preallocated" % sum(mallocs))
    # Entries for rows of another rank: PETSc's stash (scalar and block) must not grow during assembly either.
    stash = [int(m) for m in re.findall(r"Stash has \d+ entries, ?uses (\d+) mallocs", log)]
    print("off-rank stash reports: %d, stash mallocs: %d" % (len(stash), sum(stash)))
    if ARGS.ranks > 1 and not stash:
        fail("-info :mat reported no stash use on %d ranks: the stash check did not run" % ARGS.ranks)
    if sum(stash):
        fail("%d stash mallocs during Hessian assembly: the off-rank buffer is not sized" % sum(stash))
    worst, touched = np.inf, False
    for f in step_files(out_base(tag)):
        with h5py.File(f, "r") as h:
            x = h["/positions"][:]
        dist = min((np.linalg.norm(x - center, axis=1) - radius).min(), (x[:, 2] + 0.6).min())
        worst = min(worst, dist)
        touched = touched or dist < 5e-3
    print("smallest distance to an obstacle over all output steps: %.3e (contact reached: %s)" % (worst, touched))
    if not worst > 0:
        fail("the cloth penetrated an obstacle (distance %.3e)" % worst)
    if not touched:
        fail("the cloth never reached the barrier distance: the test does not exercise contact")


def case_cloth_appendix_d():
    """Appendix D: bw461 with orthogonal unit fibers and mu2 = mu1 is the isotropic bw46; both hanging cloths end in
    the same state to solver tolerance (-newton_tol 1e-6 L)."""
    states = []
    for energy in (["-energy", "bw46", "-mu1", "20"],
                   ["-energy", "bw461", "-mu1", "20", "-mu2", "20", "-fiber", "1,0", "-fiber2", "0,1"]):
        tag = "cloth_%s_np%d" % (energy[1], ARGS.ranks)
        run(cloth_args(mesh("cloth")) + energy + ["-bending", "1e-3", "-bc_clamp", "top_corners", "-density", "0.1",
            "-gravity", "0,0,-9.8", "-steps", "1", "-newton_tol", "1e-6", "-output", out_base(tag)], tag=tag)
        rest, _, x, _ = read_state(out_base(tag))
        states.append(x)
    L = np.linalg.norm(rest.max(0) - rest.min(0))
    diff = np.abs(states[0] - states[1]).max() / L
    print("max |x(bw46) - x(bw461)| / L = %.3e (limit 1e-5 = 10 x the Newton tolerance)" % diff)
    if not diff <= 1e-5:
        fail("bw46 and bw461 (mu2 = mu1) differ by %.3e L" % diff)


def uv_report(base, step=None):
    cmd = [sys.executable, os.path.join(ARGS.root, "scripts", "uv_report.py"), base]
    if step is not None:
        cmd += ["--step", str(step)]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        fail("uv_report failed: " + out.stderr[-1000:])
    import json
    return json.loads(out.stdout.strip().splitlines()[-1])


def case_uv_disk():
    """UV parameterization of the test disk (Tutte start, 2D iarap): no flipped triangle and lower distortion than
    the Tutte map."""
    tag = "uv_disk_np%d" % ARGS.ranks
    run(cloth_args(mesh("disk")) + ["-uv_map", "-energy", "iarap", "-mu", "1", "-initial", "tutte", "-steps", "1",
        "-output", out_base(tag)], tag=tag)
    tutte, final = uv_report(out_base(tag), 0), uv_report(out_base(tag))
    print("Tutte: area %.4f angle %.4f isometric %.4f | iarap: area %.4f angle %.4f isometric %.4f, flipped %d"
          % (tutte["area_distortion_mean"], tutte["angle_distortion_mean"], tutte["isometric_distortion_mean"],
             final["area_distortion_mean"], final["angle_distortion_mean"], final["isometric_distortion_mean"],
             final["flipped"]))
    if final["flipped"] != 0:
        fail("%d flipped triangles" % final["flipped"])
    for k in ("area_distortion_mean", "angle_distortion_mean", "isometric_distortion_mean"):
        if not final[k] < tutte[k]:
            fail("%s not lower than Tutte's (%.4f vs %.4f)" % (k, final[k], tutte[k]))


CASES = {
    "cloth_hang": case_cloth_hang,
    "cloth_sphere": case_cloth_sphere,
    "cloth_appendix_d": case_cloth_appendix_d,
    "uv_disk": case_uv_disk,
}
