"""End-to-end cases: nested iteration (-coarse_mesh) on the static scramble, a patch test, the inside-out bunny and
per-cell files."""
import math
import os

import numpy as np

from harness import csv_rows, fail
from .common import (ARGS, CONVERGED, mesh, out_base, read_state, run, shape_error, sized_mesh, static_scramble_args,
                     stats)


def case_nested_static_scramble():
    """Nested iteration (-coarse_mesh) on the static scramble (box pin, as static_scramble): the camel's 1.8k-tet test
    mesh with its 941-tet coarse mesh as the coarse level (generated from the same surface, not nested). Step 1 is
    solved on the coarse mesh first (its own detached start included) and its displacement, interpolated, starts the
    fine solve: the start is taken (stats coarse_start 1), the fine solve then needs at most a few updates where it
    needs tens without the coarse level (0 and 50 when written; on the 16.6k-tet mesh 0 and 47, docs/nested.md), and
    it ends at rest like the plain solve. The coarse level's work is counted apart (coarse_newton_its,
    -newton_history rows of level 1, before the fine rows)."""
    fine, coarse = mesh("camel"), sized_mesh("camel", "coarse")
    results = {}
    for name, extra in (("plain", []), ("nested", ["-coarse_mesh", coarse])):
        tag = "nested_scramble_%s_np%d" % (name, ARGS.ranks)
        run(static_scramble_args(fine, 2, 1) + extra + ["-output", out_base(tag), "-output_every", "1", "-stats",
            out_base(tag) + ".csv", "-newton_history", out_base(tag) + "_newton.csv"], tag=tag)
        results[name] = (stats(out_base(tag) + ".csv")[0], shape_error(out_base(tag), rigid=False)[0],
                         csv_rows(out_base(tag) + "_newton.csv"))
    (plain, err_plain, _), (nested, err_nested, history) = results["plain"], results["nested"]
    levels = [h["level"] for h in history]
    print("fine updates %s without, %s with the coarse level (+%s coarse updates, start %s); distance to rest %.2e / "
          "%.2e L" % (plain["newton_its"], nested["newton_its"], nested["coarse_newton_its"], nested["coarse_start"],
                      err_plain, err_nested))
    for row in (plain, nested):
        if row["reason"] not in CONVERGED:
            fail("step 1 did not converge: %s" % row["reason"])
    if plain["coarse_start"] != "-1" or plain["coarse_newton_its"] != "0":
        fail("without -coarse_mesh the stats name a coarse level: %s" % plain)
    if nested["coarse_start"] != "1" or not int(nested["coarse_newton_its"]) > 0:
        fail("the coarse level's start was not taken or did no work: %s" % nested)
    if not int(nested["newton_its"]) <= 5 or not int(plain["newton_its"]) >= 20:
        fail("fine updates %s with the coarse level, %s without: expected at most 5 and at least 20" %
             (nested["newton_its"], plain["newton_its"]))
    if not (err_nested <= 1e-3 and err_plain <= 1e-3):
        fail("not at rest: %.3e L plain, %.3e L nested" % (err_plain, err_nested))
    if levels.count("0") != int(nested["linear_solves"]) or "1" not in levels or levels != sorted(levels, reverse=True):
        fail("-newton_history levels: %d fine rows for %s linear solves, coarse rows first expected" %
             (levels.count("0"), nested["linear_solves"]))


def case_nested_patch():
    """The nested iteration's interpolation reproduces a linear field exactly, on meshes that are not nested: a patch
    test x = A X on the whole boundary of the cylinder's 17.8k-tet mesh with its 1.8k-tet test mesh as the coarse
    level (fine surface vertices lie outside the coarse mesh's facets: the field is extrapolated from the nearest
    cell). Two load steps, both started from the coarse level (-coarse_steps -1: step 1 from rest, step 2 from the
    interpolated correction): the coarse solution is exactly homogeneous, so the fine solve starts at its solution and
    converges with 0 updates (converged_initial), to 1e-10 L."""
    fine, coarse = sized_mesh("cylinder", "default"), mesh("cylinder")
    A = np.array([[1.2, 0.15, 0.0], [0.05, 1.1, 0.1], [0.0, 0.1, 1.15]])
    values = ",".join("%.17g" % v for v in A.ravel())
    tag = "nested_patch_np%d" % ARGS.ranks
    args = ["-dm_plex_filename", fine, "-energy", "iarap", "-E", "1e3", "-nu", "0.3", "-steps", "2", "-newton_tol",
            "1e-12", "-bc_clamp", "bottom,top,side", "-coarse_mesh", coarse, "-coarse_steps", "-1"]
    for g in ("bottom", "top", "side"):
        args += ["-bc_clamp_%s_affine" % g, values]
    run(args + ["-output", out_base(tag), "-output_every", "2", "-stats", out_base(tag) + ".csv"], tag=tag)
    rows = stats(out_base(tag) + ".csv")
    rest, _, x, _ = read_state(out_base(tag))
    L = np.linalg.norm(rest.max(0) - rest.min(0))
    err = np.abs(x - rest @ A.T).max() / L
    print("steps: %s; max |x - A X| = %.2e L" % ([(r["newton_its"], r["coarse_newton_its"], r["coarse_start"],
                                                    r["reason"]) for r in rows], err))
    if any(r["coarse_start"] != "1" or r["newton_its"] != "0" or r["reason"] != "converged_initial" for r in rows):
        fail("a step did not start at its solution from the coarse level")
    if not err <= 1e-10:
        fail("max |x - A X| = %.2e L (limit 1e-10 L)" % err)


def case_nested_inside_out():
    """Nested iteration in backward Euler, every step (-coarse_steps -1): the inside-out bunny (options/
    bunny_inside_out.yml) on the 3.5k-tet test mesh with the 607-tet coarse bunny, 3 steps. Step 1 starts the coarse
    level from the fine inverted start interpolated to its vertices (exact: the reflection is linear), later steps from
    the fine state and velocities; every step converges on the fine mesh, every step solved the coarse level first
    (coarse_start 0 or 1, coarse_newton_its > 0), after step 1 no cell is singular (min alpha > 0), and the body is
    as far on its way back as without the coarse level: the largest distance to rest (after the best rigid motion)
    within 5% of the plain run's (0.414 L against 0.422 L on one rank, 0.419 L on two, when written; the two paths out
    of the inverted start differ by 0.07 L, the distance they leave does not)."""
    tag = "nested_inside_out_np%d" % ARGS.ranks
    run(["-options_file", os.path.join(ARGS.root, "options", "bunny_inside_out.yml"), "-dm_plex_filename",
         mesh("bunny"), "-steps", "3", "-coarse_mesh", sized_mesh("bunny", "coarse"), "-coarse_steps", "-1",
         "-output", out_base(tag), "-output_every", "3", "-stats", out_base(tag) + ".csv"], tag=tag)
    rows = stats(out_base(tag) + ".csv")
    print("steps (fine, coarse updates, start, reason, min alpha): %s" % [
        (r["newton_its"], r["coarse_newton_its"], r["coarse_start"], r["reason"], r["min_alpha"]) for r in rows])
    if len(rows) != 3 or any(r["reason"] not in CONVERGED for r in rows):
        fail("a step did not converge: %s" % [r["reason"] for r in rows])
    if any(r["coarse_start"] not in ("0", "1") or not int(r["coarse_newton_its"]) > 0 for r in rows):
        fail("a step did not solve the coarse level first: %s" % [(r["coarse_start"], r["coarse_newton_its"])
                                                                   for r in rows])
    if not float(rows[-1]["min_alpha"]) > 0:
        fail("singular cells after 3 steps: min alpha %s" % rows[-1]["min_alpha"])
    plain = "nested_inside_out_plain_np%d" % ARGS.ranks
    run(["-options_file", os.path.join(ARGS.root, "options", "bunny_inside_out.yml"), "-dm_plex_filename",
         mesh("bunny"), "-steps", "3", "-output", out_base(plain), "-output_every", "3"], tag=plain)
    nested_err, _ = shape_error(out_base(tag), True)
    plain_err, _ = shape_error(out_base(plain), True)
    print("distance to rest after 3 steps: nested %.4f L, plain %.4f L" % (nested_err, plain_err))
    if not abs(nested_err - plain_err) <= 0.05 * plain_err:
        fail("the nested iteration leaves the body %.4f L from rest, the plain solve %.4f L (limit 5%% apart)"
             % (nested_err, plain_err))


def case_nested_cell_files():
    """Per-cell files reach the coarse level of the nested iteration: each coarse cell reads -fiber_file at the fine
    cell that contains its centroid. The static cylinder compression (as nested_ranks_agree) with energy fiber
    (gamma 50) on the 17.8k-tet cylinder, 1.8k-tet coarse level, -newton_tol 1e-8. (1) A fiber field that turns with
    the angle about the axis: the nested solve starts every load step from the coarse level (coarse_start 1) and ends
    at the plain solve's equilibrium (1e-6 L: two solves stopped by the step test at 1e-8 L, 6.8e-8 L apart when
    written). (2) One fiber in every row of the file: the same positions as the
    uniform -fiber (1e-12 L), so the coarse level read the file, not a default."""
    fine, coarse = sized_mesh("cylinder", "default"), mesh("cylinder")
    base = ["-options_file", os.path.join(ARGS.root, "options", "cylinder_compress.yml"), "-dm_plex_filename", fine,
            "-integrator", "static", "-steps", "2", "-newton_tol", "1e-8", "-energy", "fiber", "-gamma", "50"]
    probe = "nested_files_probe_np%d" % ARGS.ranks
    run(["-dm_plex_filename", fine, "-output", out_base(probe)], tag=probe)
    rest, cells, _, _ = read_state(out_base(probe))
    centroid = rest[cells].mean(axis=1)
    angle = np.arctan2(centroid[:, 1], centroid[:, 0])
    turning = ["%.17g %.17g 0.5" % (-math.sin(t), math.cos(t)) for t in angle]

    def write_file(name, rows):
        path = os.path.join(ARGS.work, name)
        with open(path, "w") as fh:
            fh.write("# fibers\n%d\n%s\n" % (len(rows), "\n".join(rows)))
        return path

    results = {}
    cases = (("plain", ["-fiber_file", write_file("turning.fibers", turning)]),
             ("nested", ["-fiber_file", os.path.join(ARGS.work, "turning.fibers"), "-coarse_mesh", coarse]),
             ("file_uniform", ["-fiber_file", write_file("uniform.fibers", ["1 1 0"] * len(cells)), "-coarse_mesh",
                               coarse]),
             ("option_uniform", ["-fiber", "1,1,0", "-coarse_mesh", coarse]))
    for name, extra in cases:
        tag = "nested_files_%s_np%d" % (name, ARGS.ranks)
        run(base + extra + ["-output", out_base(tag), "-output_every", "2", "-stats", out_base(tag) + ".csv"], tag=tag)
        results[name] = (stats(out_base(tag) + ".csv"), read_state(out_base(tag))[2])
    L = np.linalg.norm(rest.max(0) - rest.min(0))
    d_turning = np.abs(results["plain"][1] - results["nested"][1]).max() / L
    d_uniform = np.abs(results["file_uniform"][1] - results["option_uniform"][1]).max() / L
    print("updates (fine, coarse, start): %s; nested vs plain %.2e L, uniform file vs -fiber %.2e L" % (
        {k: [(r["newton_its"], r["coarse_newton_its"], r["coarse_start"]) for r in v[0]] for k, v in results.items()},
        d_turning, d_uniform))
    for name, (rows, _) in results.items():
        if any(r["reason"] not in CONVERGED for r in rows):
            fail("%s: a load step did not converge" % name)
        if name != "plain" and any(r["coarse_start"] != "1" for r in rows):
            fail("%s: a load step did not start from the coarse level" % name)
    if not d_turning <= 1e-6:
        fail("nested and plain end %.3e L apart (limit 1e-6 L)" % d_turning)
    if not d_uniform <= 1e-12:
        fail("a uniform -fiber_file and -fiber end %.3e L apart (limit 1e-12 L)" % d_uniform)


CASES = {
    "nested_static_scramble": case_nested_static_scramble,
    "nested_patch": case_nested_patch,
    "nested_inside_out": case_nested_inside_out,
    "nested_cell_files": case_nested_cell_files,
}
