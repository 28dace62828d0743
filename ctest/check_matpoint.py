#!/usr/bin/python3
"""Checks for the aries-matpoint CLI, run by ctest (ctest/matpoint.cmake, label "cli").

usage: check_matpoint.py MATPOINT MODE [mode options] [-- matpoint arguments]

modes
  json --entries N [--with KEY ...] [--without KEY ...] -- ARGS
        run `MATPOINT ARGS -json`: exit code 0, empty stderr, one JSON object with the keys energy, pk1 (N entries),
        hessian and hessian_psd (N*N), f, alpha (finite numbers) and exactly the optional keys I4 / I6 given by
        --with / --without; the Hessian is symmetric, hessian_psd is symmetric PSD and equals the Hessian when that
        is already PSD.
  closed-form CASE
        compare one evaluation with a result derived by hand (see CLOSED_FORMS below): energy, pk1, hessian, f,
        alpha, I4, I6 as far as the case defines them.
  path --shape tet|planar
        `-path uniaxial -max 1e-4 -n 4` with E = 1e4, nu = 0.3: every row converged, the effective modulus P11/strain
        is E (tet) or E/(1-nu^2) (planar, plane strain) within 1%, the lateral contraction (F22-1)/strain is -nu or
        -nu/(1-nu) within 1%.
  help --docs docs/options.md
        `MATPOINT -help`: exit code 0 and every option of docs/options.md's aries-matpoint, material and singularity
        tables listed with its default (the tables and the help come from the same declarations), every energy too.
  error [--contains TEXT] -- ARGS
        `MATPOINT ARGS` must exit with code 1, print nothing on stdout and exactly one line on stderr, starting with
        "aries-matpoint: error:" (and containing TEXT if given).
Exit status 0 when every check passed; otherwise the failed checks are listed and the status is 1.
"""
import json
import math
import subprocess
import sys

E, NU = 1e4, 0.3
MU = E / (2 * (1 + NU))
LAMBDA = E * NU / ((1 + NU) * (1 - 2 * NU))

failures = []


def check(cond, msg):
    if not cond:
        failures.append(msg)
    return cond


def close(got, want, rtol, what, atol=0.0):
    ok = isinstance(got, (int, float)) and math.isfinite(got) and abs(got - want) <= rtol * abs(want) + atol
    check(ok, f"{what}: got {got!r}, expected {want!r} (rtol {rtol}, atol {atol})")
    return ok


def run(matpoint, args):
    proc = subprocess.run([matpoint] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=60)
    return proc.returncode, proc.stdout, proc.stderr


def finite_number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def sym_eigmin(mat, n):
    """Smallest eigenvalue of a symmetric n x n matrix given row-major (numpy when available, else Jacobi)."""
    try:
        import numpy as np

        return float(np.linalg.eigvalsh(np.array(mat, dtype=float).reshape(n, n)).min())
    except ImportError:
        a = [[mat[i * n + j] for j in range(n)] for i in range(n)]
        for _ in range(100):
            off = max((abs(a[i][j]), i, j) for i in range(n) for j in range(n) if i != j) if n > 1 else (0, 0, 0)
            if off[0] < 1e-14 * max(1.0, max(abs(a[i][i]) for i in range(n))):
                break
            _, p, q = off
            theta = 0.5 * math.atan2(2 * a[p][q], a[q][q] - a[p][p])
            c, s = math.cos(theta), math.sin(theta)
            for k in range(n):
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(n):
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
        return min(a[i][i] for i in range(n))


def parse_json(matpoint, args):
    code, out, err = run(matpoint, args + ["-json"])
    check(code == 0, f"exit code {code} (stderr: {err.strip()!r})")
    check(err == "", f"unexpected stderr: {err.strip()!r}")
    lines = [l for l in out.splitlines() if l.strip()]
    if not check(len(lines) == 1, f"expected one JSON line on stdout, got {len(lines)}: {out[:200]!r}"):
        return None
    try:
        return json.loads(lines[0])
    except json.JSONDecodeError as e:
        check(False, f"stdout is not JSON ({e}): {lines[0][:200]!r}")
        return None


# ---------------------------------------------------------------------------------------------------------------------
def mode_json(matpoint, opts, args):
    n = int(opts["entries"])
    d = parse_json(matpoint, args)
    if d is None:
        return
    for key in ("energy", "f", "alpha"):
        check(key in d and finite_number(d[key]), f"key {key!r} missing or not a finite number: {d.get(key)!r}")
    for key, length in (("pk1", n), ("hessian", n * n), ("hessian_psd", n * n)):
        v = d.get(key)
        if check(isinstance(v, list) and len(v) == length, f"key {key!r}: expected a list of {length} numbers"):
            check(all(finite_number(x) for x in v), f"key {key!r} has non-finite entries")
    for key in opts["with"]:
        check(key in d and finite_number(d[key]), f"key {key!r} expected for this energy/shape")
    for key in opts["without"]:
        check(key not in d, f"key {key!r} must not be printed for this energy/shape")
    check(d.get("alpha", -1) >= 0, "alpha must be >= 0")
    if failures:
        return
    h, p = d["hessian"], d["hessian_psd"]
    scale = max(1e-300, math.sqrt(sum(x * x for x in h)))
    asym = max(abs(h[i * n + j] - h[j * n + i]) for i in range(n) for j in range(n))
    check(asym <= 1e-9 * scale, f"hessian not symmetric (max |H - H^T| = {asym:g}, |H| = {scale:g})")
    pasym = max(abs(p[i * n + j] - p[j * n + i]) for i in range(n) for j in range(n))
    check(pasym <= 1e-9 * scale, f"hessian_psd not symmetric ({pasym:g})")
    check(sym_eigmin(p, n) >= -1e-9 * scale, f"hessian_psd not PSD (min eigenvalue {sym_eigmin(p, n):g})")
    if sym_eigmin(h, n) >= 0:
        diff = max(abs(a - b) for a, b in zip(h, p))
        check(diff <= 1e-12 * scale, f"hessian_psd differs from a PSD hessian by {diff:g}")


# ---------------------------------------------------------------------------------------------------------------------
def levi(i, j, k):
    return (i - j) * (j - k) * (k - i) / 2


def iarap_diag_reference(s):
    """iarap = mu |F - R|^2 + lambda/2 (J - 1)^2 at F = diag(s) (s > 0, so R = I), with E = 1e4, nu = 0.3.

    PK1 = 2 mu (F - I) + lambda (J - 1) cof F. Hessian = 2 mu (Id - dR/dF) + lambda (cof (x) cof + (J - 1) d2J/dF2),
    where at F = diag(s) dR_ij/dF_ij = 1/(s_i + s_j), dR_ij/dF_ji = -1/(s_i + s_j) (i != j), dR_ii/dF = 0, and
    d2J/dF_ij dF_kl = eps_ikm eps_jln F_mn (3x3) or the constant 2x2 pattern."""
    d = len(s)
    n = d * d
    J = math.prod(s)
    cof = [[0.0] * d for _ in range(d)]
    for i in range(d):
        cof[i][i] = J / s[i]
    energy = MU * sum((x - 1) ** 2 for x in s) + 0.5 * LAMBDA * (J - 1) ** 2
    pk1 = [0.0] * n
    for i in range(d):
        for j in range(d):
            pk1[i * d + j] = 2 * MU * ((s[i] if i == j else 0) - (1 if i == j else 0)) + LAMBDA * (J - 1) * cof[i][j]
    hess = [0.0] * (n * n)
    for i in range(d):
        for j in range(d):
            for k in range(d):
                for l in range(d):
                    a, b = i * d + j, k * d + l
                    dR = 0.0
                    if i != j and (k, l) == (i, j):
                        dR = 1 / (s[i] + s[j])
                    elif i != j and (k, l) == (j, i):
                        dR = -1 / (s[i] + s[j])
                    if d == 3:
                        d2J = sum(levi(i, k, m) * levi(j, l, m) * s[m] for m in range(3))
                    else:
                        d2J = {(0, 0, 1, 1): 1, (1, 1, 0, 0): 1, (0, 1, 1, 0): -1, (1, 0, 0, 1): -1}.get((i, j, k, l), 0)
                    hess[a * n + b] = 2 * MU * ((1 if a == b else 0) - dR) + LAMBDA * (cof[i][j] * cof[k][l]
                                                                                        + (J - 1) * d2J)
    f = sum(s)
    alpha = 8 * (s[0] + s[1]) * (s[0] + s[2]) * (s[1] + s[2]) if d == 3 else f
    return {"energy": energy, "pk1": pk1, "hessian": hess, "f": f, "alpha": alpha}


def flat(m):
    return ",".join(repr(float(x)) for row in m for x in row)


CLOSED_FORMS = {
    # iarap at F = diag(1.1, 1, 1): energy = mu 0.01 + lambda/2 0.01 = 67.3077, PK1 = diag(2 mu 0.1 + lambda 0.1,
    # 1.1 lambda 0.1, 1.1 lambda 0.1), f = 3.1, alpha = 8 (2.1)(2.1)(2) = 70.56.
    "iarap_tet_uniaxial": (["-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-F", flat([[1.1, 0, 0], [0, 1, 0], [0, 0, 1]])],
                           iarap_diag_reference([1.1, 1.0, 1.0])),
    "iarap_tet_triaxial": (["-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-F", flat([[1.2, 0, 0], [0, 0.9, 0], [0, 0, 1.05]])],
                           iarap_diag_reference([1.2, 0.9, 1.05])),
    "arap_svd_tet": (["-energy", "arap_svd", "-E", "1e4", "-nu", "0.3", "-F", flat([[1.2, 0, 0], [0, 0.9, 0], [0, 0, 1.05]])],
                     iarap_diag_reference([1.2, 0.9, 1.05])),
    "iarap_planar": (["-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-F", flat([[1.1, 0], [0, 0.95]])],
                     iarap_diag_reference([1.1, 0.95])),
    # alx with a = (1,1,0)/sqrt2 at F = diag(1.1,1,1): I4 = (1.1+1)/2 = 1.05, I5 = (1.21+1)/2 = 1.105,
    # Psi = mu/2 (I5 - 2 I4 + 1) = mu/2 * 0.005.
    "alx_tet": (["-energy", "alx", "-E", "1e4", "-nu", "0.3", "-fiber", "1,1,0", "-F", flat([[1.1, 0, 0], [0, 1, 0], [0, 0, 1]])],
                {"energy": MU / 2 * 0.005, "f": 3.1, "alpha": 70.56, "I4": 1.05}),
    # bw461 on a cloth triangle F = [[1.1, .05], [.05, .9], [0, 0]] (symmetric PD block, so S = that block, R = [I; 0]),
    # a = e1, b = e2: I4(a) = 1.1, I4(b) = 0.9, I6 = 0.05; Psi = mu1/2 (0.1^2 + 0.1^2) + mu2 0.05^2 with mu1 = 2,
    # mu2 = 3 -> 0.0275; f = tr S = 2, alpha = f sqrt(III_C) = 2 det S = 1.975.
    "bw461_cloth": (["-energy", "bw461", "-mu1", "2", "-mu2", "3", "-fiber", "1,0", "-fiber2", "0,1",
                     "-F", flat([[1.1, 0.05], [0.05, 0.9], [0, 0]])],
                    {"energy": 0.0275, "f": 2.0, "alpha": 1.975, "I4": 1.1, "I6": 0.05}),
    # bw46 = mu1/2 |F - R|^2 on the same triangle: |S - I|^2 = 0.01 + 0.01 + 2 * 0.0025 = 0.025 -> 0.025.
    "bw46_cloth": (["-energy", "bw46", "-mu1", "2", "-F", flat([[1.1, 0.05], [0.05, 0.9], [0, 0]])],
                   {"energy": 0.025, "f": 2.0, "alpha": 1.975}),
}


def mode_closed_form(matpoint, case):
    if not check(case in CLOSED_FORMS, f"unknown closed-form case {case!r} (known: {', '.join(CLOSED_FORMS)})"):
        return
    args, ref = CLOSED_FORMS[case]
    d = parse_json(matpoint, args)
    if d is None:
        return
    for key, want in ref.items():
        got = d.get(key)
        if isinstance(want, list):
            if not check(isinstance(got, list) and len(got) == len(want), f"{key}: length {len(got or [])} != {len(want)}"):
                continue
            scale = max(abs(x) for x in want)
            err = max(abs(a - b) for a, b in zip(got, want))
            check(err <= 1e-10 * scale, f"{key}: max deviation {err:g} from the closed form (scale {scale:g})")
        else:
            close(got, want, 1e-10, key, atol=1e-13)


# ---------------------------------------------------------------------------------------------------------------------
def mode_path(matpoint, shape):
    eff_e = E if shape == "tet" else E / (1 - NU * NU)
    eff_nu = NU if shape == "tet" else NU / (1 - NU)
    code, out, err = run(matpoint, ["-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-path", "uniaxial", "-max", "1e-4",
                                    "-n", "4", "-shape", shape])
    check(code == 0 and err == "", f"exit code {code}, stderr {err.strip()!r}")
    rows = [l.split(",") for l in out.splitlines() if l.strip()]
    if not check(len(rows) == 6, f"expected a header and 5 rows, got {len(rows)}"):
        return
    header = rows[0]
    for col in ("strain", "F11", "F22", "P11", "P22", "lateral_converged"):
        check(col in header, f"CSV column {col!r} missing: {header}")
    if failures:
        return
    idx = {c: i for i, c in enumerate(header)}
    nonzero = 0
    for r in rows[1:]:
        v = {c: float(r[i]) for c, i in idx.items()}
        check(v["lateral_converged"] == 1, f"lateral relaxation did not converge at strain {v['strain']}")
        check(abs(v["P22"]) <= 1e-6 * E * max(abs(v["strain"]), 1e-6), f"lateral stress {v['P22']} not relaxed")
        if v["strain"] > 0:
            nonzero += 1
            close(v["P11"] / v["strain"], eff_e, 0.01, f"effective modulus at strain {v['strain']}")
            close((v["F22"] - 1) / v["strain"], -eff_nu, 0.01, f"lateral contraction at strain {v['strain']}")
    check(nonzero == 4, f"expected 4 rows with positive strain, got {nonzero}")


# ---------------------------------------------------------------------------------------------------------------------
def mode_help(matpoint, docs):
    import re
    code, out, _ = run(matpoint, ["-help"])
    check(code == 0, f"-help exit code {code}")
    with open(docs) as fh:
        md = fh.read()
    rows = []
    for key in ("matpoint", "material", "singularity"):
        body = re.search(r"<!-- options:%s -->\n(.*?)<!-- /options -->" % key, md, re.S)
        if not check(body is not None, f"docs block {key} missing"):
            continue
        for usage, default in re.findall(r"^\| `([^`]+)` \| ([^|]*(?:\\\|[^|]*)*) \|", body.group(1), re.M):
            rows.append((usage.replace("\\|", "|"), default.replace("`", "").replace("\\|", "|").strip()))
    check(len(rows) >= 20, f"only {len(rows)} option rows in the docs' matpoint/material/singularity tables")
    for usage, default in rows:
        check(f"  {usage} [{default}]" in out, f"-help does not list '{usage} [{default}]'")
    energies = re.search(r"<!-- options:energies -->\n(.*?)<!-- /options -->", md, re.S).group(1)
    for name in re.findall(r"^\| `([a-z0-9_]+)` \|", energies, re.M):
        check(re.search(r"^  %s " % re.escape(name), out, re.M) is not None, f"-help does not list energy {name}")


def mode_error(matpoint, opts, args):
    code, out, err = run(matpoint, args)
    check(code == 1, f"exit code {code}, expected 1")
    check(out == "", f"stdout must be empty on errors, got {out[:200]!r}")
    lines = err.splitlines()
    check(len(lines) == 1, f"stderr must be exactly one line, got {len(lines)}: {err[:400]!r}")
    if lines:
        check(lines[0].startswith("aries-matpoint: error:"), f"stderr does not start with 'aries-matpoint: error:': "
                                                             f"{lines[0]!r}")
        if opts.get("contains"):
            check(opts["contains"] in lines[0], f"message {lines[0]!r} does not mention {opts['contains']!r}")


# ---------------------------------------------------------------------------------------------------------------------
def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    matpoint, mode, rest = argv[1], argv[2], argv[3:]
    args = []
    if "--" in rest:
        k = rest.index("--")
        rest, args = rest[:k], rest[k + 1:]
    opts = {"with": [], "without": []}
    i = 0
    positional = []
    while i < len(rest):
        if rest[i] in ("--with", "--without"):
            opts[rest[i][2:]].append(rest[i + 1])
            i += 2
        elif rest[i].startswith("--"):
            opts[rest[i][2:]] = rest[i + 1]
            i += 2
        else:
            positional.append(rest[i])
            i += 1
    if mode == "json":
        mode_json(matpoint, opts, args)
    elif mode == "closed-form":
        mode_closed_form(matpoint, positional[0] if positional else "")
    elif mode == "path":
        mode_path(matpoint, opts.get("shape", "tet"))
    elif mode == "error":
        mode_error(matpoint, opts, args)
    elif mode == "help":
        mode_help(matpoint, opts["docs"])
    else:
        print(f"check_matpoint.py: unknown mode {mode!r}", file=sys.stderr)
        return 2
    if failures:
        print(f"FAILED ({mode} {' '.join(positional)} {' '.join(args)}):")
        for f in failures:
            print("  - " + f)
        return 1
    print(f"OK ({mode} {' '.join(positional)} {' '.join(args)})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
