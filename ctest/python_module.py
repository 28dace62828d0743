#!/usr/bin/python3
"""Checks of the Python module aries_kernels (python/aries_kernels.cpp), run by ctest (ctest/library.cmake).

usage: python_module.py MATPOINT MODE        (PYTHONPATH must hold the module: build/python)

modes
  matpoint   every registered energy on every element shape it is defined for, at two F (the second inverted on
             tetrahedra and planar triangles): energy, pk1, hessian, hessian_psd, f, alpha, I4, I6 agree with `aries-matpoint -json` at
             the same F and options to round-off (1e-13 of the entry scale), and the keys are exactly
             aries-matpoint's; per-point parameters (E and fiber varying) agree with one aries-matpoint run per
             point, and equal per-point values are read once.
  fd         central differences of the energy give pk1 and central differences of pk1 give the hessian (every
             energy and shape, F near rest where no singularity fix is active); hessian_psd is symmetric PSD and,
             with projection='none', equals the hessian; hessian=False gives the same energy, pk1 and hessian_psd.
  errors     wrong F shapes, NaN in F, unknown energy or parameter, bad values, per-point arrays of the wrong
             length, bad projection: a ValueError/TypeError naming the culprit, and where aries-matpoint rejects
             the same input, exactly its one-line message.
Exit status 0 when every check passed; otherwise the failures are listed and the status is 1.
"""
import json
import subprocess
import sys

import numpy as np

import aries_kernels as ak

MATPOINT = sys.argv[1]
MODE = sys.argv[2]
failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
    return cond


# Material options per energy and element dimension (3: tets, 2: planar and cloth), as keywords.
PARAMS = {
    "alx": {3: {"fiber": [1, 2, 2]}, 2: {"fiber": [1, 1]}},
    "aniso": {3: {"aniso_dirs": [1, 0, 0, 1, 1, 0], "aniso_mu": [3000, 1500]},
              2: {"aniso_dirs": [1, 0, 1, 1], "aniso_mu": [3000, 1500]}},
    "arap_svd": {3: {"E": 2e4, "nu": 0.2}, 2: {"E": 2e4, "nu": 0.2}},
    "bw": {2: {"fiber": [1, 0], "fiber2": [0, 1], "mu1": 30, "mu2": 5}},
    "bw46": {2: {"mu1": 30}},
    "bw461": {2: {"fiber": [1, 0], "fiber2": [0, 1]}},
    "bw46s": {2: {"fiber": [1, 0], "fiber2": [1, 1]}},
    "caricature": {3: {"beta": 0.5, "curvature": 1.3, "fiber": [0, 0, 1]}},
    "fiber": {3: {"gamma": 50, "fiber": [1, 1, 0]}, 2: {"gamma": 50, "fiber": [1, 2]}},
    "iarap": {3: {"E": 2e4, "nu": 0.25}, 2: {"mu": 3000, "lambda": 1000}},
    "iarap_lin": {3: {}, 2: {}},
    "kim_aa": {3: {"fiber": [0, 1, 1]}, 2: {"fiber": [1, 1]}},
    "ortho": {3: {"ortho_mu": [1000, 2000, 3000], "fiber": [1, 1, 0], "fiber2": [0, 0, 1]},
              2: {"ortho_mu": [1000, 2000], "fiber": [1, 1]}},
    "shape_target": {3: {"target": [1.2, 0.1, 0, 0.1, 0.9, 0, 0, 0, 1]}, 2: {"target": [1.2, 0.1, 0.1, 0.9]}},
}
SHAPES = {"tet": (3, 3), "planar": (2, 2), "cloth": (3, 2)}


def sample_F(shape, seed, inverted=False):
    R, C = SHAPES[shape]
    rng = np.random.default_rng(seed)
    F = np.eye(R, C) + 0.15 * rng.standard_normal((R, C))
    if inverted and R == C:
        F[:, 0] *= -1
    return F


def text(value):
    if isinstance(value, str):
        return value
    return ",".join("%.17g" % x for x in np.atleast_1d(np.asarray(value, dtype=float)).ravel())


def matpoint(energy, F, params):
    args = [MATPOINT, "-energy", energy, "-F", text(F), "-json"]
    for k, v in params.items():
        args += ["-" + k, text(v)]
    proc = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
    return proc.returncode, proc.stdout, proc.stderr.strip()


def cases():
    table = ak.energies()
    check(sorted(table) == sorted(PARAMS), f"energies() {sorted(table)} vs the test's table {sorted(PARAMS)}")
    for energy, info in sorted(table.items()):
        for shape in info["shapes"]:
            dim = 3 if shape == "tet" else 2
            if energy in PARAMS and dim in PARAMS[energy]:
                yield energy, shape, PARAMS[energy][dim]
            else:
                check(False, f"no test parameters for {energy} on {shape}")


def agree(got, want, what):
    got = np.asarray(got, dtype=float).ravel()
    want = np.asarray([np.nan if w is None else w for w in np.atleast_1d(want)], dtype=float)
    scale = max(1.0, float(np.nanmax(np.abs(want))) if want.size and not np.all(np.isnan(want)) else 1.0)
    ok = got.shape == want.shape and np.allclose(got, want, rtol=0, atol=1e-13 * scale, equal_nan=True)
    return check(ok, f"{what}: module {got[:4]}... vs aries-matpoint {want[:4]}... (n {got.size} vs {want.size})")


def mode_matpoint():
    count = 0
    for energy, shape, params in cases():
        Fs = np.array([sample_F(shape, s, inverted=(s == 1)) for s in range(2)])
        out = ak.evaluate(energy, Fs, **params)
        for i, F in enumerate(Fs):
            rc, stdout, stderr = matpoint(energy, F, params)
            if not check(rc == 0, f"{energy} {shape}: aries-matpoint failed: {stderr}"):
                continue
            ref = json.loads(stdout)
            what = f"{energy} {shape} F#{i}"
            keys = set(ref) - {"model", "singularity"}
            check(keys == set(out) - {"materials"}, f"{what}: keys {sorted(set(out))} vs {sorted(keys)}")
            for key in sorted(keys & set(out)):
                agree(out[key][i], ref[key], f"{what} {key}")
            count += 1
    check(count >= 40, f"only {count} energy/shape/F cases compared")

    # Per-point parameters: E and the fiber vary; equal rows share one material read.
    F = np.array([sample_F("tet", 10 + i) for i in range(5)])
    E = np.array([1e4, 2e4, 1e4, 3e4, 1e4])
    fibers = np.array([[1, 0, 0], [0, 1, 1], [1, 0, 0], [1, 2, 3], [1, 0, 0]], dtype=float)
    out = ak.evaluate("fiber", F, gamma=50, E=E, fiber=fibers, nu=0.3)
    check(out["materials"] == 3, f"per-point: {out['materials']} materials read for 3 distinct rows")
    for i in range(5):
        rc, stdout, stderr = matpoint("fiber", F[i], {"gamma": 50, "E": E[i], "fiber": fibers[i], "nu": 0.3})
        if check(rc == 0, f"per-point #{i}: {stderr}"):
            ref = json.loads(stdout)
            for key in ("energy", "pk1", "hessian_psd", "I4"):
                agree(out[key][i], ref[key], f"per-point #{i} {key}")
    print(f"matpoint: {count} energy/shape/F cases and 5 per-point rows agree with aries-matpoint -json")


def fd_check(energy, shape, params):
    R, C = SHAPES[shape]
    N = R * C
    F0 = np.eye(R, C) + 0.05 * np.random.default_rng(7).standard_normal((R, C))
    h = 1e-6
    batch = [F0]
    for k in range(N):
        for sign in (1, -1):
            Fk = F0.copy().ravel()
            Fk[k] += sign * h
            batch.append(Fk.reshape(R, C))
    out = ak.evaluate(energy, np.array(batch), **params)
    e, P, H = out["energy"], out["pk1"].reshape(-1, N), out["hessian"]
    fd_P = np.array([(e[1 + 2 * k] - e[2 + 2 * k]) / (2 * h) for k in range(N)])
    fd_H = np.array([(P[1 + 2 * k] - P[2 + 2 * k]) / (2 * h) for k in range(N)])  # row k: d P / d F_k
    what = f"{energy} {shape}"
    scale_P = max(1.0, np.abs(P[0]).max())
    scale_H = max(1.0, np.abs(H[0]).max())
    check(np.abs(fd_P - P[0]).max() <= 1e-6 * scale_P,
          f"{what}: pk1 vs central differences of the energy: {np.abs(fd_P - P[0]).max():.3e} (scale {scale_P:.3e})")
    check(np.abs(fd_H - H[0]).max() <= 1e-6 * scale_H,
          f"{what}: hessian vs central differences of pk1: {np.abs(fd_H - H[0]).max():.3e} (scale {scale_H:.3e})")
    psd = out["hessian_psd"][0]
    check(np.allclose(psd, psd.T, atol=1e-10 * scale_H), f"{what}: hessian_psd is not symmetric")
    check(np.linalg.eigvalsh(0.5 * (psd + psd.T)).min() >= -1e-9 * scale_H, f"{what}: hessian_psd is not PSD")
    none = ak.evaluate(energy, F0[None], projection="none", **params)
    check(np.array_equal(none["hessian_psd"], none["hessian"]), f"{what}: projection='none' differs from the hessian")
    lean = ak.evaluate(energy, F0[None], hessian=False, **params)
    check("hessian" not in lean, f"{what}: hessian=False still returns the hessian")
    for key in ("energy", "pk1", "hessian_psd"):
        check(np.allclose(lean[key][0], out[key][0], rtol=0, atol=1e-12 * scale_H),
              f"{what}: hessian=False changes {key}")


def mode_fd():
    count = 0
    for energy, shape, params in cases():
        fd_check(energy, shape, params)
        count += 1
    print(f"fd: {count} energy/shape pairs: pk1 and hessian match central differences")


def expect_error(kind, contains, call, matpoint_args=None):
    try:
        call()
    except kind as err:
        message = str(err)
        check(contains in message, f"{kind.__name__} '{message}' does not name '{contains}'")
        if matpoint_args is not None:
            proc = subprocess.run([MATPOINT] + matpoint_args, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                  text=True, timeout=60)
            line = proc.stderr.strip()
            prefix = "aries-matpoint: error: "
            check(proc.returncode != 0 and line.startswith(prefix) and line[len(prefix):] == message,
                  f"message '{message}' differs from aries-matpoint's '{line}'")
        return
    except Exception as err:  # noqa: BLE001 - any other exception is a failure of this check
        check(False, f"expected {kind.__name__} naming '{contains}', got {type(err).__name__}: {err}")
        return
    check(False, f"expected {kind.__name__} naming '{contains}', got no exception")


def mode_errors():
    F = np.array([np.eye(3), np.diag([1.1, 0.9, 1.0])])
    tet = ["-F", "1,0,0,0,1,0,0,0,1"]
    expect_error(ValueError, "F[None]", lambda: ak.evaluate("iarap", np.eye(3)))
    expect_error(ValueError, "(2, 4, 4)", lambda: ak.evaluate("iarap", np.zeros((2, 4, 4))))
    expect_error(ValueError, "(2, 9)", lambda: ak.evaluate("iarap", np.zeros((2, 9))))
    expect_error(TypeError, "F:", lambda: ak.evaluate("iarap", "not an array"))
    bad = F.copy()
    bad[1, 2, 0] = np.nan
    expect_error(ValueError, "F[1] has a non-finite entry", lambda: ak.evaluate("iarap", bad))
    expect_error(ValueError, "unknown energy 'foo'", lambda: ak.evaluate("foo", F),
                 ["-energy", "foo"] + tet)
    expect_error(ValueError, "-gama", lambda: ak.evaluate("fiber", F, gamma=1, gama=2),
                 ["-energy", "fiber", "-gamma", "1", "-gama", "2"] + tet)
    expect_error(ValueError, "-nu", lambda: ak.evaluate("iarap", F, nu=0.7), ["-energy", "iarap", "-nu", "0.7"] + tet)
    expect_error(ValueError, "-E", lambda: ak.evaluate("iarap", F, E=float("nan")),
                 ["-energy", "iarap", "-E", "nan"] + tet)
    expect_error(ValueError, "-gamma", lambda: ak.evaluate("fiber", F), ["-energy", "fiber"] + tet)
    expect_error(ValueError, "-fiber", lambda: ak.evaluate("fiber", F, gamma=1, fiber=[0, 0, 0]),
                 ["-energy", "fiber", "-gamma", "1", "-fiber", "0,0,0"] + tet)
    expect_error(ValueError, "-singularity", lambda: ak.evaluate("iarap_lin", F, singularity="barrier"),
                 ["-energy", "iarap_lin", "-singularity", "barrier"] + tet)
    expect_error(ValueError, "iarap", lambda: ak.evaluate("iarap", np.zeros((2, 3, 2)) + np.eye(3, 2)),
                 ["-energy", "iarap", "-F", "1,0,0,1,0,0"])
    expect_error(ValueError, "parameter E: 3 per-point", lambda: ak.evaluate("iarap", F, E=np.array([1e4, 1e4, 1e4])))
    expect_error(ValueError, "fiber", lambda: ak.evaluate("fiber", F, gamma=1, fiber=np.ones((3, 3))))
    expect_error(ValueError, "E", lambda: ak.evaluate("iarap", F, E=np.ones((2, 2))))
    expect_error(TypeError, "gamma", lambda: ak.evaluate("fiber", F, gamma={"a": 1}))
    expect_error(ValueError, "projection", lambda: ak.evaluate("iarap", F, projection="adaptive"))
    expect_error(ValueError, "eigensystem", lambda: ak.evaluate("iarap", F, eigensystem="closed"))
    expect_error(TypeError, "energy", lambda: ak.evaluate("iarap", F, energy="fiber"))
    # After errors the module still evaluates (no state left behind by a failed read).
    out = ak.evaluate("iarap", F)
    check(abs(out["energy"][0]) < 1e-12 and out["energy"][1] > 0, "evaluation after errors is wrong")
    print("errors: every bad input raised a Python exception naming it")


{"matpoint": mode_matpoint, "fd": mode_fd, "errors": mode_errors}[MODE]()
if failures:
    print("\n".join("FAIL: " + f for f in failures))
    sys.exit(1)
