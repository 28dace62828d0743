#!/usr/bin/env python3
"""The verification study: aries against exact solutions and published small-strain values, with the observed
convergence order on three or more meshes. Writes docs/verification.md (generated; do not edit by hand).

  /usr/bin/python3 bench/verification.py [--build build] [--ranks 2] [--out out/verification] [--only P1,P2,...]

Problems (each a function below, its reference in its docstring and in the report):
  end_traction   unit cube, bottom clamped, dead traction on the top: uniform stretch (exact), iarap / fiber / ortho
  simple_shear   unit cube, simple shear g = 0.5 on its boundary: the homogeneous state and its stress, iarap / fiber
  hanging_bar    unit cube hanging from its top under its own weight: uniaxial, exact, iarap / fiber / ortho
  lame_sphere    thick sphere (a = 0.5, b = 1) under internal follower pressure, small strain: Lame's u_r(r)
  lame_elements  the same on P1, P2 and hexahedra (a cubed sphere)
  thick_cylinder Lame's thick cylinder in plane strain, dead pressure on the open inner wall: P1, P2, hexahedra
  inflation      the sphere inflated by 40-60% (iarap, radially fibered fiber) against the radial equilibrium ODE
  cantilever     a plane-stress cantilever under an end load against Timoshenko beam theory
  cook_membrane  Cook's membrane, plane stress, small strain: the vertical displacement at the right edge's midpoint
                 against 23.96, on planar triangles and as a thin 3D slab (symmetry plane held in z)
  compress_elements  the compressed cylinder at nu = 0.3 and 0.49, P1 against P2, against P2 on the finest mesh:
                 the solve time each element needs to reach 1e-3 L
"""
import argparse
import datetime
import glob
import json
import math
import os
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "meshes", "tools"))
import build  # noqa: E402  (the Cook panel's nodes and triangles, for the independent CST code)
ARGS = None
SERIES = []  # per convergence study: its problem, label, mesh sizes h, errors and solve times (bench/evidence.py charts)


def record(problem, label, hs, errs, times, error_kind):
    SERIES.append({"problem": problem, "label": label, "h": list(hs), "error": list(errs), "time": list(times),
                   "error_kind": error_kind})


def mesh(name, size):
    out = subprocess.run(["bash", os.path.join(ROOT, "meshes", "generate.sh"), name, size], capture_output=True,
                         text=True, check=True)
    return out.stdout.strip().splitlines()[-1]


def run(tag, args):
    """Runs aries; returns (rest, final positions, stats rows, wall seconds of the solve)."""
    base = os.path.join(ARGS.out, tag)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    cmd = ["mpiexec", "--quiet", "-n", str(ARGS.ranks), "--bind-to", "none", os.path.join(ARGS.build, "aries")]
    cmd += args + ["-output", base, "-output_every", "1000000", "-stats", base + ".csv", "-strict"]
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        sys.exit("verification: %s failed:\n%s" % (" ".join(cmd), (p.stdout + p.stderr)[-3000:]))
    with h5py.File(base + ".h5") as f:
        rest = f["/mesh/rest"][:]
    with h5py.File(sorted(glob.glob(base + ".steps/*.h5"))[-1]) as f:
        x = f["/positions"][:]
    import csv
    with open(base + ".csv") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    return rest, x, rows, sum(float(r["wall_s"]) for r in rows)


def orders(hs, errs):
    return [""] + ["%.2f" % (math.log(errs[k - 1] / errs[k]) / math.log(hs[k - 1] / hs[k]))
                   if errs[k] > 0 and errs[k - 1] > 0 else "" for k in range(1, len(errs))]


def table(head, rows):
    out = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n"
    for r in rows:
        out += "| " + " | ".join(str(c) for c in r) + " |\n"
    return out


HEX_SIZES = [("test", 6), ("mid", 12), ("default", 18), ("fine", 24)]
WARPED_HEX_SIZES = [("wtest", 6), ("wmid", 12), ("wdefault", 18), ("wfine", 24)]


def cube_sizes():
    return [("test", 6), ("mid", 12), ("default", 18), ("fine", 24)]


# Materials whose uniaxial state along z is exact with the lateral stretch 1 (no Poisson effect), each with its
# nominal stress P_zz(lambda) along z: iarap at nu = 0 (mu = E / 2, lambda = 0): E (l - 1); fiber = that + gamma/2
# (I4(a) - 1)^2 with a = z and the paper's I4 = a^T S a = l (S = R^T F, the stretch): + gamma (l - 1); ortho
# (lambda = 0) with mu_z on the basis direction z: 2 mu_z (l - 1).
UNIAXIAL = [
    ("iarap", ["-energy", "iarap", "-E", "1e4", "-nu", "0"], lambda l: 1e4 * (l - 1)),
    ("fiber", ["-energy", "fiber", "-E", "1e4", "-nu", "0", "-gamma", "2000", "-fiber", "0,0,1"],
     lambda l: 1e4 * (l - 1) + 2000 * (l - 1)),
    ("ortho", ["-energy", "ortho", "-mu", "1", "-lambda", "0", "-ortho_mu", "2000,3000,5000", "-fiber", "1,0,0",
               "-fiber2", "0,1,0"], lambda l: 2 * 5000 * (l - 1)),
]


def stretch_for(P, stress):
    """The stretch l >= 1 with stress(l) = P (bisection; stress increasing)."""
    lo, hi = 1.0, 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stress(mid) < P else (lo, mid)
    return 0.5 * (lo + hi)


def end_traction():
    """Unit cube [0,1]^3, the bottom (z = 0) clamped, a dead traction t = 2000 along z on the top (-load_traction_top),
    3 load steps, for each material of UNIAXIAL (iarap at nu = 0; fiber with its fiber along z; ortho with mu_z = 5000
    along z, lambda = 0). Exact: F = diag(1, 1, l) with P_zz(l) = t (the sides traction-free and the clamp compatible:
    no lateral strain): u_z = (l - 1) z, u_x = u_y = 0. A linear field: P1 reproduces it on every mesh (a patch
    test), so the error is the solver's (-newton_tol 1e-8: 1e-10 asks for steps below what the energy's round-off can
    certify on the larger meshes, and the line search then fails)."""
    rows = []
    for energy, material, stress in UNIAXIAL:
        l = stretch_for(2000.0, stress)
        for size, n in cube_sizes():
            rest, x, st, wall = run("traction_%s_%s" % (energy, size), [
                "-dm_plex_filename", mesh("cube", size)] + material + ["-bc_clamp", "bottom", "-load_traction_top",
                                                                       "0,0,2000", "-steps", "3", "-newton_tol", "1e-8"])
            exact = rest.copy()
            exact[:, 2] *= l
            err = np.abs(x - exact).max() / np.linalg.norm(rest.max(0) - rest.min(0))
            rows.append([energy, "%.6f" % l, size, 6 * n ** 3, "1/%d" % n, "%.2e" % err,
                         "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)), "%.2f" % wall])
    return ("End traction: uniform stretch (exact)", end_traction.__doc__,
            table(["energy", "stretch", "mesh", "tets", "h", "max error / L", "Newton / step", "solve s"], rows))


def polar_rotation(F):
    U, _, Vt = np.linalg.svd(F)
    return U @ Vt


def simple_shear():
    """Simple shear at large strain, F = I + g e_x e_z^T with g = 0.5 (a 26.6 deg shear angle), imposed on every face of
    the unit cube (-bc_clamp_<face>_affine, 5 load steps, -newton_tol 1e-12). The homogeneous state is an equilibrium
    of every homogeneous material (div P = 0) and P1 reproduces it, so the interior vertices must sit at F X and every
    cell's first Piola-Kirchhoff stress (-output_fields pk1_stress) must be P(F): for iarap (E = 1e4, nu = 0.3; J = 1,
    so P = 2 mu (F - R), R the polar rotation, from numpy's SVD here, independent of aries' closed-form kernels), with
    the shear stress P_xz and the normal stress P_zz = 2 mu (1 - cos t), tan t = g / 2, that linear elasticity misses
    (the Poynting effect); for fiber (a fiber along x, gamma = 2000) against aries-matpoint's P at the same F (the
    same kernels: this checks the assembly and the solve, not the material law)."""
    g = 0.5
    A = np.eye(3)
    A[0, 2] = g
    groups = ["left", "right", "front", "back", "bottom", "top"]
    affine = ",".join("%.17g" % v for v in A.ravel())
    rows = []
    for energy, material in (("iarap", ["-energy", "iarap", "-E", "1e4", "-nu", "0.3"]),
                             ("fiber", ["-energy", "fiber", "-E", "1e4", "-nu", "0.3", "-gamma", "2000",
                                        "-fiber", "1,0,0"])):
        if energy == "iarap":
            mu = 1e4 / (2 * 1.3)
            P = 2 * mu * (A - polar_rotation(A))
        else:
            out = subprocess.run([os.path.join(ARGS.build, "aries-matpoint")] + material + ["-F", affine, "-json"],
                                 capture_output=True, text=True, check=True).stdout
            P = np.array(json.loads(out)["pk1"]).reshape(3, 3)
        for size, n in cube_sizes()[:3]:
            args = ["-dm_plex_filename", mesh("cube", size)] + material + ["-bc_clamp", ",".join(groups)]
            for grp in groups:
                args += ["-bc_clamp_%s_affine" % grp, affine]
            rest, x, st, wall = run("shear_%s_%s" % (energy, size), args + [
                "-steps", "5", "-newton_tol", "1e-12", "-output_fields", "pk1_stress"])
            with h5py.File(sorted(glob.glob(os.path.join(ARGS.out, "shear_%s_%s.steps" % (energy, size), "*.h5")))[-1]) as f:
                cellP = f["/cell/pk1_stress"][:].reshape(-1, 3, 3)
            L = np.linalg.norm(rest.max(0) - rest.min(0))
            xerr = np.abs(x - rest @ A.T).max() / L
            perr = np.abs(cellP - P).max() / np.abs(P).max()
            reasons = sorted(set(r["reason"] for r in st))
            rows.append([energy, size, 6 * n ** 3, "%.2e" % xerr, "%.4f" % P[0, 2], "%.4f" % P[2, 2], "%.2e" % perr,
                         ", ".join(reasons), "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)),
                         "%.2f" % wall])
    return ("Simple shear (exact, large strain)", simple_shear.__doc__,
            table(["energy", "mesh", "tets", "max |x - F X| / L", "exact P_xz", "exact P_zz",
                   "max cell |P - P(F)| / max |P(F)|", "reasons", "Newton / step", "solve s"], rows))


def hanging_bar():
    """Unit cube [0,1]^3 hanging from its top face (z = 1, clamped) under its own weight, density 1000, g = 5 along -z
    (rho g = 5000), for each material of UNIAXIAL (iarap: the stretch grows linearly from 1 at the bottom to 1.5 at the
    top). Exact (uniaxial, no lateral strain, so the clamp is compatible): P_zz(l(z)) = rho g z, F = diag(1, 1, l(z)),
    u_z(z) = -int_z^1 (l(s) - 1) ds (closed form for iarap: -rho g (1 - z^2) / (2 E); by quadrature otherwise). P1 with
    lumped gravity: order 2 expected. Trilinear hexahedra (meshes/generate.sh hexcube) on the uniform grid: the
    discrete problem is the 1D bar's, whose linear elements are exact at the nodes (a uniform mesh, and the lumped
    weight equals the consistent one), so the error is the solver's; on the warped grids (hexcube w*: interior nodes
    moved by up to 0.2 of a cell) the nodal error converges at the observed order. Quadratic tetrahedra (-element p2,
    the same cube meshes): the exact displacement is quadratic in z and gravity acts on P2's consistent load, so the
    discrete solution is the exact one at every node; what is left is the solver's tolerance (-newton_tol 1e-8) and
    round-off, on every mesh."""
    rows = []
    grid = np.linspace(0.0, 1.0, 4001)
    for energy, material, stress in UNIAXIAL:
        lam = np.array([stretch_for(5000.0 * z, stress) for z in grid])
        # u_z at the grid points: minus the integral from z to 1 of (l - 1), trapezoidal on the fine grid.
        seg = 0.5 * (lam[1:] + lam[:-1] - 2.0) * np.diff(grid)
        uz = -np.concatenate([np.cumsum(seg[::-1])[::-1], [0.0]])
        families = [(energy, "cube", cube_sizes(), lambda n: "%d tets" % (6 * n ** 3)),
                    (energy + ", P2", "cube", cube_sizes()[:3], lambda n: "%d P2 tets" % (6 * n ** 3)),
                    (energy + ", hexahedra", "hexcube", HEX_SIZES, lambda n: "%d hexahedra" % n ** 3),
                    (energy + ", warped hexahedra", "hexcube", WARPED_HEX_SIZES, lambda n: "%d hexahedra" % n ** 3)]
        for label, mesh_name, sizes, cells in families:
            hs, errs, ts, block = [], [], [], []
            for size, n in sizes:
                quadratic = label.endswith("P2")
                rest, x, st, wall = run("hanging_%s_%s_%s%s" % (energy, mesh_name, size, "_p2" * quadratic), [
                    "-dm_plex_filename", mesh(mesh_name, size)] + ["-element", "p2"] * quadratic + material + [
                    "-bc_clamp", "top", "-density", "1000", "-gravity", "0,0,-5", "-steps", "1", "-newton_tol", "1e-8"])
                exact = rest.copy()
                exact[:, 2] += np.interp(rest[:, 2], grid, uz)
                err = np.abs(x - exact).max() / np.linalg.norm(rest.max(0) - rest.min(0))
                hs.append(1.0 / n)
                errs.append(err)
                ts.append(wall)
                block.append([label, "%.4f" % lam[-1], mesh_name + " " + size, cells(n), "1/%d" % n, "%.3e" % err,
                              "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)), "%.2f" % wall])
            record("hanging bar", label, hs, errs, ts, "max nodal error / L")
            for r, o in zip(block, orders(hs, errs)):
                r.insert(6, o)
            rows += block
    return ("Hanging bar under its own weight (exact, large stretch)", hanging_bar.__doc__,
            table(["energy", "top stretch", "mesh", "cells", "h", "max nodal error / L", "order", "Newton / step",
                   "solve s"], rows))


def lame_sphere():
    """Thick sphere, inner radius a = 0.5, outer b = 1 (meshes/generate.sh shell), iarap with E = 1e4, nu = 0.3, a
    follower pressure p = 10 (1e-3 E: small strain) on the cavity (-load_pressure_inner), the body free. Reference:
    Lame's solution of linear elasticity, u_r(r) = p a^3 / (E (b^3 - a^3)) ((1 - 2 nu) r + (1 + nu) b^3 / (2 r^2))
    (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., 1970, Sec. 137); iarap's small-strain limit is linear
    elasticity with these Lame parameters. Error: the mean radial displacement of the cavity's wall vertices (after
    removing the mean translation) against u_r(a), and the largest vertex error over max u_r."""
    hs, errs, ts, rows = [], [], [], []
    E, nu, p, a, b = 1e4, 0.3, 10.0, 0.5, 1.0
    ur_exact = lambda r: p * a ** 3 / (E * (b ** 3 - a ** 3)) * ((1 - 2 * nu) * r + (1 + nu) * b ** 3 / (2 * r ** 2))
    for size, h in (("test", 0.2), ("default", 0.1), ("fine3", 0.07), ("fine4", 0.05), ("fine5", 0.035)):
        rest, x, st, wall = run("lame_%s" % size, [
            "-dm_plex_filename", mesh("shell", size), "-energy", "iarap", "-E", str(E), "-nu", str(nu),
            "-load_pressure_inner", str(p), "-steps", "1", "-newton_tol", "1e-10"])
        u = x - rest
        u -= u.mean(0)
        r = np.linalg.norm(rest, axis=1)
        ur = np.einsum("ij,ij->i", u, rest) / r
        inner = r < a + 1e-6
        err = abs(ur[inner].mean() - ur_exact(a)) / ur_exact(a)
        vmax = np.abs(ur - ur_exact(r)).max() / ur_exact(r).max()
        hs.append(h)
        errs.append(err)
        ts.append(wall)
        rows.append([size, "%d" % tets_of(size), "%g" % h, "%.4e" % ur[inner].mean(), "%.4e" % ur_exact(a),
                     "%.2f%%" % (100 * err), "%.2f%%" % (100 * vmax),
                     "%.2f" % (sum(int(q["newton_its"]) for q in st) / len(st)), "%.2f" % wall])
    record("Lame sphere", "iarap, u_r(a)", hs, errs, ts, "relative error of u_r(a)")
    for row, o in zip(rows, orders(hs, errs)):
        row.insert(6, o)
    return ("Lame's thick sphere under internal pressure (small strain)", lame_sphere.__doc__,
            table(["mesh", "tets", "h", "u_r(a) mean", "Lame u_r(a)", "error", "order", "max vertex error",
                   "Newton / step", "solve s"], rows))


def cells_of(name, size):
    with open(mesh(name, size)[:-4] + ".json") as fh:
        d = json.load(fh)
    return d.get("tets", d.get("hexes"))


# Each volume element on the thick sphere: (label, mesh name, sizes (size, h), extra options). h: the mesh's cell size
# (tets: gmsh's target edge; the cubed sphere: its radial layer 0.5 / (n / 2)).
SPHERE_ELEMENTS = [
    ("P1", "shell", [("test", 0.2), ("default", 0.1), ("fine3", 0.07)], []),
    ("P2", "shell", [("test", 0.2), ("default", 0.1), ("fine3", 0.07)], ["-element", "p2"]),
    ("P2 curved", "shell_curved", [("test", 0.2), ("default", 0.1), ("fine3", 0.07)], ["-element", "p2"]),
    ("Q1 hex", "shell_hex", [("test", 0.25), ("default", 0.125), ("s12", 0.25 / 3), ("s16", 0.0625), ("s20", 0.05)],
     []),
]


def radial_errors(rest, x, ur_ref, a):
    """(cavity's mean radial displacement error, largest vertex error) relative to the reference's u_r(a), after
    removing the mean translation (the body is free)."""
    u = x - rest
    u -= u.mean(0)
    r = np.linalg.norm(rest, axis=1)
    ur = np.einsum("ij,ij->i", u, rest) / r
    inner = r < a + 1e-6
    return (abs(ur[inner].mean() - ur_ref(a)) / ur_ref(a), np.abs(ur - ur_ref(r)).max() / ur_ref(a),
            ur[inner].mean())


def radial_series(problem, label, rows, series, column):
    """Records one element's series (h, the u_r(a) errors, the largest node errors, solve times) for the charts and
    fills the order columns of its last rows of the table: `column` the u_r(a) error's order, `column` + 2 the largest
    node error's."""
    hs, errs, vmaxs, ts = series
    record(problem, label, hs, vmaxs, ts, "largest vertex error of u_r / u_r(a)")
    first = len(rows) - len(hs)
    for k, (o, ov) in enumerate(zip(orders(hs, errs), orders(hs, vmaxs))):
        rows[first + k][column] = o
        rows[first + k][column + 2] = ov


def lame_elements():
    """Lame's thick sphere (a = 0.5, b = 1, iarap E = 1e4, nu = 0.3, follower pressure p = 0.1 (1e-5 E: the nonlinear
    solution is within ~1e-5 of the linear one) on the cavity, the body free, -newton_tol 1e-12) on every volume
    element: P1 and P2 tetrahedra on the gmsh shells (meshes/generate.sh shell; P2's edge nodes
    at the straight edges' middles, so its cavity is the same polyhedron as P1's), P2 on gmsh's second-order meshes
    with the same corners ("P2 curved", meshes/generate.sh shell_curved: 10-node tets whose edge nodes on the spheres
    lie on them; isoparametric) and trilinear hexahedra on a cubed
    sphere (meshes/generate.sh shell_hex: n x n cells per cube face, n/2 radial layers). Reference: Lame's u_r(r)
    (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., 1970, Sec. 137). Errors relative to u_r(a): the cavity
    wall's mean, and the largest over every node (corners and P2 edge nodes) against u_r at the node's rest radius."""
    E, nu, p, a, b = 1e4, 0.3, 0.1, 0.5, 1.0
    ur_exact = lambda r: p * a ** 3 / (E * (b ** 3 - a ** 3)) * ((1 - 2 * nu) * r + (1 + nu) * b ** 3 / (2 * r ** 2))
    rows = []
    for label, name, sizes, extra in SPHERE_ELEMENTS:
        hs, errs, vmaxs, ts = [], [], [], []
        for size, h in sizes:
            rest, x, st, wall = run("lame_%s_%s" % (name, size) + ("_p2" if extra else ""), [
                "-dm_plex_filename", mesh(name, size), "-energy", "iarap", "-E", str(E), "-nu", str(nu),
                "-load_pressure_inner", str(p), "-steps", "1", "-newton_tol", "1e-12"] + extra)
            err, vmax, _ = radial_errors(rest, x, ur_exact, a)
            hs.append(h)
            errs.append(err)
            vmaxs.append(vmax)
            ts.append(wall)
            rows.append([label, size, "%d" % cells_of(name, size), "%d" % len(rest), "%.3g" % h,
                         "%.3f%%" % (100 * err), "", "%.3f%%" % (100 * vmax), "", "%.2f" % wall])
        radial_series("Lame sphere elements", label, rows, (hs, errs, vmaxs, ts), 6)
    return ("Lame's thick sphere on every volume element (small strain)", lame_elements.__doc__,
            table(["element", "mesh", "cells", "nodes", "h", "u_r(a) error", "order", "max node error", "order",
                   "solve s"], rows))


def thick_cylinder():
    """Lame's thick cylinder in plane strain: a quarter of the tube with inner radius a = 1 and outer b = 2, one cell
    layer in z (meshes/generate.sh tube / tube_hex: n cells across the wall, about square ones around it; every node
    on its circle; "P2 curved": tube_curved, the same tets with every edge node at its edge's middle in polar
    coordinates, so the walls' edges are arcs), rollers on the cut faces (x = 0 held in x, y = 0 in y) and on both ends (z), a dead pressure
    p = 0.1 (1e-5 E: the geometrically nonlinear solution is then within ~1e-5 of the linear one) on the open inner
    wall (-load_pressure_inner_kind dead), iarap E = 1e4, nu = 0.3, -newton_tol 1e-12. Reference:
    u_r(r) = (1 + nu) p a^2 / (E (b^2 - a^2)) ((1 - 2 nu) r + b^2 / r) (Timoshenko & Goodier, Sec. 28). Errors as for
    the sphere, relative to u_r(a)."""
    E, nu, p, a, b = 1e4, 0.3, 0.1, 1.0, 2.0
    ur_exact = lambda r: (1 + nu) * p * a ** 2 / (E * (b ** 2 - a ** 2)) * ((1 - 2 * nu) * r + b ** 2 / r)
    rollers = ["-bc_clamp", "xzero,yzero,bottom,top", "-bc_clamp_xzero_components", "x", "-bc_clamp_yzero_components",
               "y", "-bc_clamp_bottom_components", "z", "-bc_clamp_top_components", "z"]
    rows = []
    for label, name, sizes, extra in (("P1", "tube", ["test", "default", "s8", "s16"], []),
                                      ("P2", "tube", ["test", "default", "s8", "s16"], ["-element", "p2"]),
                                      ("P2 curved", "tube_curved", ["test", "default", "s8", "s16"], ["-element", "p2"]),
                                      ("Q1 hex", "tube_hex", ["default", "s8", "s16", "s32"], [])):
        hs, errs, vmaxs, ts = [], [], [], []
        for size in sizes:
            n = build.CATALOG[name][size]["n"]
            rest, x, st, wall = run("tube_%s_%s" % (name, size) + ("_p2" if extra else ""), [
                "-dm_plex_filename", mesh(name, size), "-energy", "iarap", "-E", str(E), "-nu", str(nu),
                "-load_pressure_inner", str(p), "-load_pressure_inner_kind", "dead", "-steps", "1", "-newton_tol",
                "1e-12"] + rollers + extra)
            r = np.linalg.norm(rest[:, :2], axis=1)
            u = x - rest
            ur = np.einsum("ij,ij->i", u[:, :2], rest[:, :2]) / r
            inner = np.abs(r - a) < 1e-9
            err = abs(ur[inner].mean() - ur_exact(a)) / ur_exact(a)
            vmax = np.abs(ur - ur_exact(r)).max() / ur_exact(a)
            hs.append((b - a) / n)
            errs.append(err)
            vmaxs.append(vmax)
            ts.append(wall)
            rows.append([label, size, "%d" % n, "%d" % cells_of(name, size), "%d" % len(rest),
                         "%.3f%%" % (100 * err), "", "%.3f%%" % (100 * vmax), "", "%.2f" % wall])
        radial_series("Thick cylinder", label, rows, (hs, errs, vmaxs, ts), 6)
    return ("Lame's thick cylinder, plane strain, dead pressure on an open wall", thick_cylinder.__doc__,
            table(["element", "mesh", "cells across", "cells", "nodes", "u_r(a) error", "order", "max node error",
                   "order", "solve s"], rows))


def radial_fiber_file(name, size):
    """A -fiber_file of radial fibers (each cell's rest centroid, normalized) for a shell mesh, in gmsh element
    order."""
    path = mesh(name, size)
    out = os.path.join(ARGS.out, "%s_%s.radial_fibers" % (name, size))
    lines = open(path).read().split("\n")
    nodes, cells = {}, []
    i = lines.index("$Nodes") + 2
    while lines[i] != "$EndNodes":
        w = lines[i].split()
        nodes[int(w[0])] = np.array([float(v) for v in w[1:4]])
        i += 1
    i = lines.index("$Elements") + 2
    while lines[i] != "$EndElements":
        w = [int(v) for v in lines[i].split()]
        if w[1] in (4, 5, 11):  # tetrahedron, hexahedron, 10-node tetrahedron (its corners)
            corners = w[3 + w[2]:][:4 if w[1] == 11 else None]
            cells.append(np.mean([nodes[n] for n in corners], axis=0))
        i += 1
    with open(out, "w") as fh:
        fh.write("# radial fibers of %s\n%d\n" % (os.path.basename(path), len(cells)))
        for c in cells:
            fh.write("%.17g %.17g %.17g\n" % tuple(c / np.linalg.norm(c)))
    return out


def inflation():
    """Large-strain inflation of the thick sphere (a = 0.5, b = 1, the body free) by a follower pressure on its
    cavity, ramped over 10 load steps: iarap E = 1e4, nu = 0.3 at p = 2800 (the cavity's radius grows by 60%), and the
    anisotropic fiber energy with radial fibers (-fiber_file: each cell's centroid direction; transversely isotropic
    about the radius, so the state stays spherically symmetric), gamma = 5e3, at p = 3000 (40%). Reference: the
    spherically symmetric equilibrium of the same energy (the radial ODE, bench/radial_reference.py: shooting with
    DOP853 at rtol 1e-12, the outer traction brought to 1e-10 p; it reproduces Lame's u_r(a) to 5e-8 at small strain).
    Errors relative to the reference's u_r(a), as above; P2 on the shells of h = 0.3, 0.2, 0.1."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from radial_reference import RadialInflation
    E, nu, a, b = 1e4, 0.3, 0.5, 1.0
    rows = []
    for material, p, gamma in (("iarap", 2800.0, 0.0), ("fiber (radial)", 3000.0, 5e3)):
        ref = RadialInflation(a, b, p, E, nu, gamma)
        ur_ref = ref.displacement
        # (P2 curved: in lame_elements; its large-strain rows are not part of this study's run yet)
        for label, name, sizes, extra in [e for e in SPHERE_ELEMENTS if e[0] != "P2 curved"]:
            hs, errs, vmaxs, ts = [], [], [], []
            # P2 from h = 0.3 (its h = 0.07 run would take longer than the rest of the study together)
            for size, h in ([("coarse", 0.3)] + sizes[:2] if label == "P2" else sizes[:3]):
                energy = ["-energy", "iarap"] if gamma == 0 else [
                    "-energy", "fiber", "-gamma", str(gamma), "-fiber_file", radial_fiber_file(name, size)]
                rest, x, st, wall = run("inflate_%s_%s_%s" % (material.split()[0], name, size) + ("_p2" if extra else ""),
                                        ["-dm_plex_filename", mesh(name, size), "-E", str(E), "-nu", str(nu),
                                         "-load_pressure_inner", str(p), "-steps", "10", "-newton_tol", "1e-10"]
                                        + energy + extra)
                err, vmax, mean = radial_errors(rest, x, ur_ref, a)
                hs.append(h)
                errs.append(err)
                vmaxs.append(vmax)
                ts.append(wall)
                rows.append([material, label, size, "%d" % len(rest), "%.3g" % h, "%.4f" % ((a + mean) / a),
                             "%.4f" % ((a + ur_ref(a)) / a), "%.3f%%" % (100 * err), "", "%.3f%%" % (100 * vmax), "",
                             "%.2f" % (sum(int(q["newton_its"]) for q in st) / len(st)), "%.2f" % wall])
            radial_series("Inflation " + material, label, rows, (hs, errs, vmaxs, ts), 8)
    return ("Large-strain inflation against the radial equilibrium ODE", inflation.__doc__,
            table(["material", "element", "mesh", "nodes", "h", "cavity stretch", "reference", "u_r(a) error", "order",
                   "max node error", "order", "Newton / step", "solve s"], rows))


def cook_cst(n, E=1.0, nu=1.0 / 3.0):
    """The same problem by an independent linear-elastic constant-strain-triangle code (numpy/scipy, plane stress; it
    shares only the mesh with aries, from meshes/tools/build.py) on the same n x n mesh: the vertical displacement at
    (48, 52) for F = 1."""
    import scipy.sparse as sparse
    import scipy.sparse.linalg as sparse_linalg
    X, T = build.cook_panel_points(n), build.grid_triangles(n, n)  # the mesh of meshes/generate.sh cook
    D = E / (1 - nu ** 2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
    rows, cols, vals = [], [], []
    for t in T:
        x = X[t]
        area = 0.5 * np.linalg.det(np.c_[np.ones(3), x])
        b = np.array([x[1, 1] - x[2, 1], x[2, 1] - x[0, 1], x[0, 1] - x[1, 1]]) / (2 * area)
        c = np.array([x[2, 0] - x[1, 0], x[0, 0] - x[2, 0], x[1, 0] - x[0, 0]]) / (2 * area)
        B = np.zeros((3, 6))
        B[0, 0::2], B[1, 1::2], B[2, 0::2], B[2, 1::2] = b, c, c, b
        dof = np.ravel([[2 * v, 2 * v + 1] for v in t])
        rows += list(np.repeat(dof, 6))
        cols += list(np.tile(dof, 6))
        vals += list((area * B.T @ D @ B).ravel())
    K = sparse.csr_matrix((vals, (rows, cols)), shape=(2 * len(X), 2 * len(X)))
    f = np.zeros(2 * len(X))
    right = np.where(np.abs(X[:, 0] - 48.0) < 1e-9)[0]
    right = right[np.argsort(X[right, 1])]
    for k in range(len(right) - 1):  # F = 1 uniform over the right edge (16 long): consistent nodal forces
        half = 0.5 * (X[right[k + 1], 1] - X[right[k], 1]) / 16.0
        f[2 * right[k] + 1] += half
        f[2 * right[k + 1] + 1] += half
    fixed = np.ravel([[2 * v, 2 * v + 1] for v in np.where(np.abs(X[:, 0]) < 1e-9)[0]])
    free = np.setdiff1d(np.arange(2 * len(X)), fixed)
    u = np.zeros(2 * len(X))
    u[free] = sparse_linalg.spsolve(K[free][:, free].tocsc(), f[free])
    return u[2 * int(np.argmin(np.abs(X[:, 0] - 48.0) + np.abs(X[:, 1] - 52.0))) + 1]


COOK_POINT = (48.0, 52.0)  # the midpoint of the loaded edge, where the reference value is read


def cook_membrane():
    """Cook's membrane: the tapered panel with corners (0,0), (48,44), (48,60), (0,44) (meshes/generate.sh cook: n x n
    structured cells, 2 n^2 triangles), clamped on its left edge, a total vertical shear F on its right edge
    (-load_force_right 0,F, spread uniformly), plane stress with E = 1, nu = 1/3, thickness 1. Reference: the vertical
    displacement of the midpoint of the loaded edge, (48, 52), 23.96 F / E converged (Cook 1989; Belytschko et al.
    2014; FinEtools' Cook membrane examples track the same point, mid_edge = [48, 52], against 23.97). aries' planar
    iarap is nonlinear with the plane-strain Lame parameters of -E/-nu, so the plane-stress ones are given directly
    (mu = E / (2 (1 + nu)) = 0.375 E, lambda* = 2 mu nu / (1 - nu) = 0.375 E) and the load is small (E = 1e4, F = 0.1:
    strains ~1e-5); the reported value is u E / F. Column "independent CST": a linear constant-strain-triangle code
    (cook_cst: numpy, E = 1, F = 1) on the same mesh. Linear triangles are too stiff in bending, so the values rise
    towards the reference from below. Column "u(48,60) E / F": the top corner, which some descriptions name instead;
    it moves more, and its values rise past 23.96 (an earlier version of this study read it there and saw that
    overshoot).

    The slab rows: the same panel as a 3D body 1 thick, modelled by its upper half z in [0, 1/2] (meshes/generate.sh
    cook_slab: one layer of 6 n^2 tets) with 3D iarap (E = 1e4, nu = 1/3: mu = 0.375 E, lambda = 0.75 E), the left face
    held in x and y only (-bc_clamp_left_components x,y), the symmetry plane z = 0 held in z
    (-bc_clamp_mid_components z), the top face free, and half the shear, F / 2, on the half's right face: thin, so
    close to plane stress (a small through-thickness effect remains); the value is u E t / F with t = 1 at (48, 52, 0).
    The same slab in trilinear hexahedra (meshes/generate.sh cook_hex: n x n x 1 cells, 2x2x2 Gauss points): fully
    integrated Q1 locks in this bending-dominated panel (shear locking: no incompatible modes, no reduced
    integration), so its values approach 23.96 from below. The tet slab in quadratic tetrahedra (-element p2, the same
    meshes): P2 bends without locking, so its error falls fast."""
    hs, errs, ts, rows = [], [], [], []
    E, F, ref = 1e4, 0.1, 23.96
    def point(rest):
        return int(np.argmin(np.abs(rest[:, 0] - COOK_POINT[0]) + np.abs(rest[:, 1] - COOK_POINT[1])
                             + np.abs(rest[:, 2])))
    for size, n in (("test", 8), ("s16", 16), ("default", 32), ("s64", 64), ("s128", 128)):
        rest, x, st, wall = run("cook_%s" % size, [
            "-dm_plex_filename", mesh("cook", size), "-energy", "iarap", "-mu", str(0.375 * E), "-lambda",
            str(0.375 * E), "-bc_clamp", "left", "-load_force_right", "0,%g" % F, "-steps", "1", "-newton_tol", "1e-9"])
        k = point(rest)
        value = (x[k, 1] - rest[k, 1]) * E / F
        corner = int(np.argmin(np.abs(rest[:, 0] - 48.0) + np.abs(rest[:, 1] - 60.0)))
        hs.append(1.0 / n)
        errs.append(abs(value - ref) / ref)
        ts.append(wall)
        rows.append(["planar", size, "%d triangles" % (2 * n * n), "%d x %d" % (n, n), "%.4f" % value,
                     "%.4f" % cook_cst(n), "%.4f" % ((x[corner, 1] - rest[corner, 1]) * E / F),
                     "%.2f%%" % (100 * errs[-1]),
                     "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)), "%.2f" % wall])
    for row, o in zip(rows, orders(hs, errs)):
        row.insert(8, o)
    record("Cook's membrane", "planar triangles", hs, errs, ts, "relative error vs 23.96")
    slab, slab_series = [], {}
    for name, cells, per_cell, label, element in (("cook_slab", "tets", 6, "3D slab (tets)", "p1"),
                                                  ("cook_slab", "P2 tets", 6, "3D slab (P2 tets)", "p2"),
                                                  ("cook_hex", "hexahedra", 1, "3D slab (hexahedra)", "p1")):
        slab_hs, slab_errs, slab_ts, block = [], [], [], []
        sizes = (("test", 8), ("s16", 16), ("default", 32), ("s64", 64), ("s128", 128))
        for size, n in sizes[:4] if element == "p2" else sizes:
            rest, x, st, wall = run("%s_%s_%s" % (name, size, element), [
                "-dm_plex_filename", mesh(name, size), "-element", element, "-energy", "iarap", "-mu", str(0.375 * E), "-lambda",
                str(0.75 * E), "-bc_clamp", "left,mid", "-bc_clamp_left_components", "x,y", "-bc_clamp_mid_components",
                "z", "-load_force_right", "0,%g,0" % (F / 2), "-steps", "1", "-newton_tol", "1e-9"])
            k = point(rest)
            value = (x[k, 1] - rest[k, 1]) * E / F
            slab_hs.append(1.0 / n)
            slab_errs.append(abs(value - ref) / ref)
            slab_ts.append(wall)
            block.append([label, size, "%d %s" % (per_cell * n * n, cells), "%d x %d x 1" % (n, n), "%.4f" % value,
                          "", "", "%.2f%%" % (100 * slab_errs[-1]),
                          "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)), "%.2f" % wall])
        record("Cook's membrane", label, slab_hs, slab_errs, slab_ts, "relative error vs 23.96")
        slab_series[{"p1": "P1", "p2": "P2"}[element] if name == "cook_slab" else "Q1"] = (slab_errs, slab_ts)
        for row, o in zip(block, orders(slab_hs, slab_errs)):
            row.insert(8, o)
        slab += block
    reach = "Slab, solve time to a relative error of " + "; of ".join(
        compare_times({k: slab_series[k] for k in ("P1", "P2")}, t) for t in (1e-2, 1e-3)) + "."
    return ("Cook's membrane (plane stress, small strain)", cook_membrane.__doc__ + " " + reach,
            table(["model", "mesh", "cells", "grid", "u(48,52) E / F", "independent CST", "u(48,60) E / F",
                   "error vs 23.96", "order", "Newton / step", "solve s"], rows + slab))


def cantilever():
    """A cantilever 10 long and 1 deep (meshes/generate.sh beam: nx x nx/10 square cells, 2 triangles each), clamped
    on its left end, a total vertical force P on its right end (-load_force_right 0,P, spread uniformly), plane stress
    (mu = lambda* = 0.375 E: E = 1e4, nu = 1/3) at small strain (P = 0.01). Reference: Timoshenko beam theory's end
    deflection, P L^3 / (3 E I) + P L / (kappa G A) with I = 1/12, A = 1, kappa = 5/6, G = mu: 4032 P / E (e.g.
    Timoshenko & Goodier 1970, Sec. 21, whose plane-stress solution adds the clamp's local compliance, a fraction of a
    percent here). Reported: the right end's mean vertical displacement times E / P, and the order of its distance to
    the extrapolated limit (Richardson from the two finest meshes, assuming order 2: the finest mesh's order is 2 by
    construction, the others are measured)."""
    E, P, ref = 1e4, 0.01, 4032.0
    values, ts, rows = [], [], []
    sizes = (("test", 40), ("default", 80), ("s160", 160), ("s320", 320))
    for size, nx in sizes:
        rest, x, st, wall = run("beam_%s" % size, [
            "-dm_plex_filename", mesh("beam", size), "-energy", "iarap", "-mu", str(0.375 * E), "-lambda",
            str(0.375 * E), "-bc_clamp", "left", "-load_force_right", "0,%g" % P, "-steps", "1", "-newton_tol", "1e-10"])
        end = np.abs(rest[:, 0] - 10.0) < 1e-9
        values.append((x[end, 1] - rest[end, 1]).mean() * E / P)
        ts.append(wall)
        rows.append([size, 2 * nx * nx // 10, "%d x %d" % (nx, nx // 10), "%.2f" % values[-1],
                     "%.2f%%" % (100 * abs(values[-1] - ref) / ref),
                     "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)), "%.2f" % wall])
    limit = values[-1] + (values[-1] - values[-2]) / 3.0
    errs = [abs(v - limit) for v in values]
    record("cantilever", "end deflection vs Timoshenko", [1.0 / n for _, n in sizes],
           [abs(v - ref) / ref for v in values], ts, "relative error vs Timoshenko (0.23% model floor)")
    for row, o in zip(rows, orders([1.0 / n for _, n in sizes], errs)):
        row.insert(5, o)
    return ("Cantilever under an end load (plane stress, small strain)",
            cantilever.__doc__ + " Extrapolated limit: %.1f (%.2f%% from Timoshenko's %.0f)."
            % (limit, 100 * abs(limit - ref) / ref, ref),
            table(["mesh", "triangles", "cells", "end deflection E / P", "vs Timoshenko", "order", "Newton / step",
                   "solve s"], rows))


P2_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]  # a tetra10's edge nodes 4-9 (VTK order)


def displacement_at(rest, cells, x, points):
    """The displacement field of a P1 (4 nodes per cell) or P2 (10: corners, then P2_EDGES) solution at rest points:
    each point is located in the element whose corner tet holds it (largest smallest barycentric) and the element's
    shape functions interpolate the nodal displacements."""
    u = x - rest
    X0 = rest[cells[:, 0]]
    T = np.stack([rest[cells[:, k]] - X0 for k in (1, 2, 3)], axis=2)
    Tinv = np.linalg.inv(T)
    out = np.empty((len(points), 3))
    for i, p in enumerate(points):
        lam = np.einsum("nij,nj->ni", Tinv, p - X0)
        b = np.column_stack([1.0 - lam.sum(1), lam])
        k = int(np.argmax(b.min(1)))
        b = b[k]
        if cells.shape[1] == 4:
            N = b
        else:
            N = np.concatenate([b * (2 * b - 1), [4 * b[a] * b[c] for a, c in P2_EDGES]])
        out[i] = N @ u[cells[k]]
    return out


def compress_points(n=400, seed=7):
    """Sample points inside the cylinder (r <= 0.45 of its radius 0.5: inside every faceted mesh of it)."""
    rng = np.random.default_rng(seed)
    pts = rng.uniform([-0.45, -0.45, 0.02], [0.45, 0.45, 1.98], size=(4 * n, 3))
    return pts[pts[:, 0] ** 2 + pts[:, 1] ** 2 <= 0.45 ** 2][:n]


def time_to_reach(errs, times, target):
    """Solve time at which a series (coarse to fine) reaches the error `target`, log-log in (error, time) between the
    two meshes that bracket it, or from the two finest when none reaches it: (seconds, how), how = "" (interpolated),
    "extrapolated", or "at most" (the coarsest mesh is already below the target: its time bounds it)."""
    if errs[0] <= target:
        return times[0], "at most"
    k = next((k for k in range(1, len(errs)) if errs[k] <= target), len(errs) - 1)
    if not 0 < errs[k] < errs[k - 1]:
        return math.inf, "not reached"  # no decrease to interpolate or extrapolate along
    s = math.log(target / errs[k - 1]) / math.log(errs[k] / errs[k - 1])
    return math.exp(math.log(times[k - 1]) + s * (math.log(times[k]) - math.log(times[k - 1]))), \
        "" if errs[k] <= target else "extrapolated"


def compare_times(series, target):
    """'P1 x s, P2 y s: P2 r times cheaper' for {label: (errs, times)} at `target`, each time marked as time_to_reach
    says; the ratio is a lower bound where P2's time is an upper bound."""
    found = {label: time_to_reach(e, t, target) for label, (e, t) in series.items()}
    parts = ["%s %s%.2f s%s" % (label, "at most " if how == "at most" else "", t,
                                " (extrapolated)" if how == "extrapolated" else "") for label, (t, how) in found.items()]
    (t1, h1), (t2, h2) = found["P1"], found["P2"]
    if not math.isfinite(t1) or not math.isfinite(t2):
        return "%.0e: %s; no ratio" % (target, ", ".join(parts))
    if h1 == "at most":
        return "%.0e: %s; both are below it on the coarsest mesh, no ratio" % (target, ", ".join(parts))
    bound = "at least " if h2 == "at most" else ""
    return "%.0e: %s; P2 %s%.1fx cheaper" % (target, ", ".join(parts), bound, t1 / t2)


def compress_elements():
    """P1 against P2 on the compressed cylinder (the paper's Fig. 6 body, meshes/generate.sh cylinder: radius 0.5,
    height 2, unstructured tets at h = 0.17, 0.12, 0.076, 0.05), static: bottom clamped, top clamped and moved down by
    0.2 (10%) in 2 load steps, iarap with E = 1e4 at nu = 0.3 and at nu = 0.49 (nearly incompressible, where linear
    tets lock), -newton_tol 1e-6, the paper's CG + Jacobi. No closed form exists, so the reference is P2 at h = 0.076
    (77k DoFs); the error is the largest distance between the displacement fields at 400 random points inside the body
    (r <= 0.45), over L. P2 runs on the two coarser meshes, P1 on all four; the reference's own error (about
    (0.076 / 0.12)^3 = 0.25 of P2's at h = 0.12, at P2's order 3) makes that P2 error uncertain by about that fraction.
    Time to an error (1e-3 L, and 2e-4 L, which P1 needs more than the coarsest mesh for at nu = 0.3): the solve time at
    which a series reaches it, log-log between the two meshes that bracket it, extrapolated from the two finest where no
    mesh reaches it, and bounded by the coarsest mesh's time where that one already does."""
    points = compress_points()
    sizes = (("test", 0.17), ("s12", 0.12), ("default", 0.076), ("s05", 0.05))
    reference = "default"
    rows, summary = [], []
    for nu in (0.3, 0.49):
        def solve(element, size):
            rest, x, st, wall = run("compress_nu%s_%s_%s" % (nu, element, size), [
                "-dm_plex_filename", mesh("cylinder", size), "-element", element, "-energy", "iarap", "-E", "1e4",
                "-nu", str(nu), "-bc_clamp", "bottom,top", "-bc_clamp_top_translate", "0,0,-0.2", "-steps", "2",
                "-newton_tol", "1e-6"])
            with h5py.File(os.path.join(ARGS.out, "compress_nu%s_%s_%s.h5" % (nu, element, size))) as f:
                cells = f["/mesh/topology"][:]
            return rest, cells, x, st, wall
        rest, cells, x, _, ref_wall = solve("p2", reference)
        L = np.linalg.norm(rest.max(0) - rest.min(0))
        ref = displacement_at(rest, cells, x, points)
        series = {}
        for element, use in (("p1", sizes), ("p2", sizes[:2])):
            hs, errs, ts, block = [], [], [], []
            for size, h in use:
                rest, cells, x, st, wall = solve(element, size)
                err = np.abs(displacement_at(rest, cells, x, points) - ref).max() / L
                hs.append(h)
                errs.append(err)
                ts.append(wall)
                block.append(["%g" % nu, element.upper(), size, "%d" % len(cells), "%d" % (3 * len(rest)), "%g" % h,
                              "%.3e" % err, "%.2f" % (sum(int(r["newton_its"]) for r in st) / len(st)),
                              "%.0f" % (sum(int(r["ksp_its"]) for r in st) / len(st)), "%.2f" % wall])
            for r, o in zip(block, orders(hs, errs)):
                r.insert(7, o)
            rows += block
            record("cylinder compress, nu = %g" % nu, element.upper(), hs, errs, ts,
                   "max displacement error / L vs P2 at h = 0.076")
            series[element.upper()] = (errs, ts)
        summary.append("nu = %g, time to an error of %s (reference solve %.1f s)."
                       % (nu, "; of ".join(compare_times(series, t) for t in (1e-3, 2e-4)), ref_wall))
    return ("Compressed cylinder: linear against quadratic tetrahedra", compress_elements.__doc__ + " "
            + " ".join(summary),
            table(["nu", "element", "mesh", "elements", "dofs", "h", "max error / L", "order", "Newton / step",
                   "PCG / step", "solve s"], rows))


# The element comparison: per scene, the series of each element (problem, label) -> element name.
ELEMENT_SCENES = [
    ("hanging bar (iarap)", "max nodal error / L", [("hanging bar", "iarap", "P1"), ("hanging bar", "iarap, P2", "P2"),
                                                     ("hanging bar", "iarap, warped hexahedra", "Q1 (warped grids)")]),
    ("Cook's membrane, 3D slab", "relative error vs 23.96",
     [("Cook's membrane", "3D slab (tets)", "P1"), ("Cook's membrane", "3D slab (P2 tets)", "P2"),
      ("Cook's membrane", "3D slab (hexahedra)", "Q1")]),
    ("cylinder compress, nu = 0.3", "max error / L", [("cylinder compress, nu = 0.3", "P1", "P1"),
                                                       ("cylinder compress, nu = 0.3", "P2", "P2")]),
    ("cylinder compress, nu = 0.49", "max error / L", [("cylinder compress, nu = 0.49", "P1", "P1"),
                                                        ("cylinder compress, nu = 0.49", "P2", "P2")]),
]


ELEMENT_TITLE = "Elements: the cheapest per target error"  # the section study() appends after the problems
ELEMENT_CHART = os.path.join(ROOT, "docs", "images", "verification_elements.png")  # bench/evidence.py copies it
ELEMENT_NOTE = ("Per scene, the element that reaches a target error in the least solve time (from the convergence "
                "series: interpolated log-log between the two meshes that bracket the target; 'at most': the coarsest "
                "mesh is already below it; 'extrapolated': from the two finest meshes, at most a decade beyond the "
                "finest error). The hanging bar on uniform hexahedral grids is left out: there Q1 is exact at the "
                "nodes (a 1D property of that grid), so only the warped grids measure it. No Q1 on the cylinder: "
                "there is no hexahedral cylinder mesh.")


def element_comparison():
    """Charts error against solve time per scene and element (docs/images/verification_elements.png) and names the
    cheapest element per target error; returns the report's section."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    found = {(s["problem"], s["label"]): s for s in SERIES}
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    rows = []
    for ax, (scene, kind, members) in zip(axes.ravel(), ELEMENT_SCENES):
        present = [(found[(p, l)], name) for p, l, name in members if (p, l) in found]
        for s, name in present:
            ax.loglog([max(t, 1e-3) for t in s["time"]], s["error"], "-o", label=name)
        ax.set_title(scene, fontsize=9)
        ax.set_xlabel("solve time [s], %d ranks (log)" % ARGS.ranks)
        ax.set_ylabel(kind + " (log)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        for target in (1e-2, 1e-3, 1e-4):
            times = []
            for s, name in present:
                if min(s["error"]) > 10 * target:
                    continue  # no extrapolation over more than a decade
                t, how = time_to_reach(s["error"], s["time"], target)
                if math.isfinite(t):
                    times.append((t, name, how))
            if not times:
                continue
            t, name, how = min(times)
            rows.append([scene, "%.0e" % target, name, "%s%.3g s%s" % ("at most " if how == "at most" else "", t,
                                                                       " (extrapolated)" if how == "extrapolated" else ""),
                         "; ".join("%s %s%.3g s%s" % (n, "<= " if h == "at most" else "", tt,
                                                       " (extrap.)" if h == "extrapolated" else "")
                                   for tt, n, h in sorted(times, key=lambda x: x[1]))])
    fig.suptitle("Error against solve time per element (bench/verification.py)", fontsize=10)
    fig.tight_layout()
    fig.savefig(ELEMENT_CHART, dpi=100)
    plt.close(fig)
    text = ELEMENT_NOTE + " Chart: ![error against time per element](images/verification_elements.png)"
    return (ELEMENT_TITLE, text,
            table(["scene", "target", "cheapest", "its time", "every element"], rows))


def tets_of(size):
    with open(mesh("shell", size)[:-4] + ".json") as fh:
        return json.load(fh)["tets"]


def study(args):
    """Runs every problem with `args` (build, ranks, out); returns the report's sections (title, text, table), and
    fills SERIES."""
    global ARGS
    ARGS = args
    os.makedirs(ARGS.out, exist_ok=True)
    del SERIES[:]
    if getattr(args, "only", None):
        return [PROBLEMS[name]() for name in args.only]
    sections = [end_traction(), simple_shear(), hanging_bar(), lame_sphere(), lame_elements(), thick_cylinder(),
                inflation(), cantilever(), cook_membrane(), compress_elements()]
    return sections + [element_comparison()]


def replace_sections(sections, seconds, made_by, commit):
    """--only: the given sections replace those of the same title in docs/verification.md (new ones go before the
    element comparison), and the header names the command, commit and date of each regenerated section."""
    path = os.path.join(ROOT, "docs", "verification.md")
    text = open(path).read()
    head, *parts = text.split("\n## ")
    old = [(part.split("\n", 1)[0], "## " + part) for part in parts]
    for title, body, tab in sections:
        block = "\n".join(["## " + title, "", " ".join(line.strip() for line in body.strip().splitlines()), "", tab])
        k = next((k for k, (t, _) in enumerate(old) if t == title), None)
        if k is None:
            k = next((k for k, (t, _) in enumerate(old) if t == ELEMENT_TITLE), len(old))
            old.insert(k, (title, block))
        else:
            old[k] = (title, block)
    # One line per regenerated section (a later run of the same section replaces its line).
    titles = [t for t, _, _ in sections]
    kept = [line for line in head.rstrip("\n").split("\n")
            if not any(line.startswith('Regenerated: "%s"' % t) for t in titles)]
    notes = ['Regenerated: "%s" by `%s` at commit %s on %s, %d MPI ranks (the run: %.0f s).'
             % (t, made_by, commit, datetime.date.today().isoformat(), ARGS.ranks, seconds) for t in titles]
    head = "\n".join(kept).rstrip("\n") + "\n\n" + "\n\n".join(notes) + "\n"
    doc = head + "\n" + "\n".join(block.rstrip("\n") + "\n" for _, block in old)
    with open(path, "w") as fh:
        fh.write(doc)
    return doc.splitlines()


def write_report(sections, seconds, made_by):
    """docs/verification.md from the study's sections (`made_by`: the command that ran it)."""
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    if getattr(ARGS, "only", None):
        return replace_sections(sections, seconds, made_by, commit)
    doc = ["# Verification: exact solutions and reference values", "",
           "<!-- generated by bench/verification.py; do not edit by hand -->", "",
           "Made by `%s` at commit %s on %s, %d MPI ranks, in %.0f s (%s). Errors are relative to the rest bounding-box "
           "diagonal L unless stated; orders are log(e_k-1 / e_k) / log(h_k-1 / h_k). Charts of error vs h and vs solver "
           "time: docs/results.md, section 7 (`bench/run`)."
           % (made_by, commit, datetime.date.today().isoformat(), ARGS.ranks, seconds, os.uname().nodename), ""]
    doc += ["Patch tests (homogeneous deformations imposed on the whole boundary with `-bc_clamp_<set>_affine`, for every "
            "energy on every element shape it supports) run in ctest: `e2e.patch_tests_<shape>` (tet, hex, p2, "
            "planar, cloth; ctest/e2e/supports.py, case_patch_tests), on one rank. Supports on some components (`-bc_clamp_<id>_components`: rollers, "
            "symmetry planes) are checked against an exact homogeneous state in `e2e.symmetry_supports`.", ""]
    for title, text, tab in sections:
        doc += ["## " + title, "", " ".join(line.strip() for line in text.strip().splitlines()), "", tab]
    with open(os.path.join(ROOT, "docs", "verification.md"), "w") as fh:
        fh.write("\n".join(doc))
    return doc


PROBLEMS = {"end_traction": end_traction, "simple_shear": simple_shear, "hanging_bar": hanging_bar,
            "lame_sphere": lame_sphere, "lame_elements": lame_elements, "thick_cylinder": thick_cylinder,
            "inflation": inflation, "cantilever": cantilever, "cook_membrane": cook_membrane,
            "compress_elements": compress_elements}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "verification"))
    ap.add_argument("--only", type=lambda t: t.split(","), default=None,
                    help="comma-separated problems (%s): run only these and replace their sections of "
                         "docs/verification.md" % ", ".join(PROBLEMS))
    args = ap.parse_args()
    for name in args.only or []:
        if name not in PROBLEMS:
            ap.error("--only: unknown problem '%s' (problems: %s)" % (name, ", ".join(PROBLEMS)))
    start = time.time()
    sections = study(args)
    made_by = "/usr/bin/python3 bench/verification.py" + (" --only " + ",".join(args.only) if args.only else "")
    print("\n".join(write_report(sections, time.time() - start, made_by)))


if __name__ == "__main__":
    main()
