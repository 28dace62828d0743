"""End-to-end cases: the inside-out bunny recovered (mollifier, barrier, CG + GAMG, density 1)."""
import os
import re
import subprocess

from harness import csv_rows, fail
from .common import ARGS, mesh, out_base, run, shape_error, stats, summary_value


def case_inside_out(mode):
    """Inside-out bunny (every element at alpha = 0) recovers its shape with the given fix: <= 1e-3 L up to a
    rigid motion (the body floats free), no NaN."""
    tag = "inside_out_%s_np%d" % (mode, ARGS.ranks)
    run(["-dm_plex_filename", mesh("bunny"), "-energy", "iarap", "-E", "1e4", "-nu", "0", "-singularity", mode,
         "-initial", "invert", "-integrator", "beuler", "-dt", "0.2", "-steps", "60", "-output", out_base(tag),
         "-output_every", "60", "-stats", out_base(tag) + ".csv"], tag=tag)
    err, _ = shape_error(out_base(tag), rigid=True)
    first = stats(out_base(tag) + ".csv")[0]
    print("step 1 min_alpha %s; final max distance to rest (rigidly aligned) / L = %.3e (limit 1e-3)"
          % (first["min_alpha"], err))
    if not err <= 1e-3:
        fail("inside-out not recovered: %.3e L" % err)


def case_inside_out_gamg():
    """The inside-out recovery with CG + GAMG (rigid-body near-nullspace): every linear solve converges and the
    shape is recovered (<= 1e-3 L). With PETSc's GAMG defaults the smoothers keep eigenvalue bounds from the first
    Hessian, the preconditioner turns indefinite once the elements enter the mollifier's blend band, and step 1
    fails (0.44 L); aries turns -pc_gamg_use_sa_esteig off. The solves counted are those of filtered (PSD) systems:
    an unfiltered one (-newton_exact_hessian) that meets negative curvature fails by design and is solved again
    filtered; -newton_history logs it as a row with filter none that was not applied (lambda 0)."""
    tag = "inside_out_gamg_np%d" % ARGS.ranks
    log, _ = run(["-dm_plex_filename", mesh("bunny"), "-energy", "iarap", "-E", "1e4", "-nu", "0", "-initial",
                  "invert", "-integrator", "beuler", "-dt", "0.2", "-steps", "60", "-ksp_type", "cg", "-pc_type",
                  "gamg", "-dm_mat_type", "aij", "-ksp_converged_reason", "-output", out_base(tag), "-output_every",
                  "60", "-stats", out_base(tag) + ".csv", "-newton_history", out_base(tag) + "_newton.csv"], tag=tag)
    failed_solves = len(re.findall(r"Linear solve did not converge", log))
    hist = csv_rows(out_base(tag) + "_newton.csv")
    exact_attempts = sum(1 for h in hist if h["filter"] == "none" and float(h["lambda"]) == 0.0)
    err, _ = shape_error(out_base(tag), rigid=True)
    print("failed linear solves %d (unfiltered attempts solved again filtered: %d); final distance to rest (rigidly "
          "aligned) %.3e L (limit 1e-3)" % (failed_solves, exact_attempts, err))
    if failed_solves > exact_attempts:
        fail("%d linear solves of filtered systems did not converge with GAMG" % (failed_solves - exact_attempts))
    if not err <= 1e-3:
        fail("inside-out not recovered with GAMG: %.3e L" % err)


def case_inside_out_density1():
    """The inside-out bunny (35k tets) at density 1, a stiffness-dominated regime: it recovers, every step
    converges, the safeguard does not block the steps. With -alpha_min guarding every cell just above 1e-6 (26,294
    cells below it and 7,949 in the mollifier's flat region after one iteration), step 1 used to halve every
    direction ~53 times and end with diverged_line_search."""
    tag = "inside_out_rho1_np%d" % ARGS.ranks
    p = subprocess.run([os.path.join(ARGS.root, "meshes", "generate.sh"), "bunny", "default"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        fail("mesh generation failed: " + p.stderr[-2000:])
    msh = p.stdout.strip().splitlines()[-1]
    log, _ = run(["-options_file", os.path.join(ARGS.root, "options", "bunny_inside_out.yml"), "-dm_plex_filename",
                  msh, "-density", "1", "-steps", "3", "-output", out_base(tag), "-output_every", "3",
                  "-stats", out_base(tag) + ".csv"], tag=tag)
    rows = stats(out_base(tag) + ".csv")
    halvings = summary_value(log, "safeguard halvings")
    print("Newton updates per step %s, reasons %s, safeguard halvings %d, min alpha after step 1 %s"
          % ([r["newton_its"] for r in rows], [r["reason"] for r in rows], halvings, rows[0]["min_alpha"]))
    if any(r["reason"] != "newton_step" for r in rows):
        fail("a step did not converge")
    if not float(rows[-1]["min_alpha"]) > 1.0:
        fail("not un-inverted after 3 steps: min alpha %s" % rows[-1]["min_alpha"])
    if halvings > 10:
        fail("the safeguard halved %d times in 3 steps" % halvings)


CASES = {
    "inside_out_mollifier": lambda: case_inside_out("mollifier"),
    "inside_out_barrier": lambda: case_inside_out("barrier"),
    "inside_out_gamg": case_inside_out_gamg,
    "inside_out_density1": case_inside_out_density1,
}
