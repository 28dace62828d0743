#!/usr/bin/python3
"""A researcher's prototype on aries_kernels: a strip of planar triangles stretched by 30%, solved by projected Newton
with scipy's sparse solver, for three fiber orientations of the fiber energy (iarap + gamma/2 (I4(a) - 1)^2).

The left edge is held, the right edge is moved along x and left free to slide along y. A fiber along the pull makes
the strip stiffer; a fiber across it does not stiffen the pull; a fiber at 45 degrees couples the pull to shear, so
the free right edge slides sideways (by symmetry the other two do not slide). Each element's energy, PK1 and
projected Hessian come from one batched call, ak.evaluate("fiber", F, ...), per Newton iteration.

usage: PYTHONPATH=build/python /usr/bin/python3 examples/python/stretch_strip.py [--out DIR] [--check]
  --out DIR   writes DIR/stretch_strip.png (the three deformed strips) and prints the table
  --check     exits 1 unless every Newton solve converged and the three physical statements above hold
"""
import argparse
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import aries_kernels as ak

MATERIAL = dict(E=1e4, nu=0.3, gamma=5e4)


def strip(nx=30, ny=10, length=3.0, height=1.0):
    xs, ys = np.meshgrid(np.linspace(0, length, nx + 1), np.linspace(0, height, ny + 1), indexing="ij")
    X = np.column_stack([xs.ravel(), ys.ravel()])
    vid = lambda i, j: i * (ny + 1) + j  # noqa: E731
    tris = []
    for i in range(nx):
        for j in range(ny):
            a, b, c, d = vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)
            # alternating diagonals: the mesh is symmetric about the strip's midline (ny even)
            tris += [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
    return X, np.array(tris)


class Strip:
    """Linear triangles: F = Ds Dm^-1; vec(F) (row-major, aries' order) = B x_e with x_e = (x0, y0, x1, y1, x2, y2)."""

    def __init__(self, X, tris):
        self.X, self.tris = X, tris
        Dm = np.stack([X[tris[:, 1]] - X[tris[:, 0]], X[tris[:, 2]] - X[tris[:, 0]]], axis=2)  # columns: edges
        self.area = 0.5 * np.abs(np.linalg.det(Dm))
        Dinv = np.linalg.inv(Dm)
        self.B = np.zeros((len(tris), 4, 6))
        for i in range(2):
            for j in range(2):
                for k in range(2):  # F_ij = sum_k (x_{k+1,i} - x_{0,i}) Dinv_kj
                    self.B[:, 2 * i + j, 2 * (k + 1) + i] += Dinv[:, k, j]
                    self.B[:, 2 * i + j, i] -= Dinv[:, k, j]
        self.dofs = np.stack([2 * tris[:, v] + c for v in range(3) for c in range(2)], axis=1)

    def evaluate(self, x, fiber, hessian=True):
        xe = x[self.dofs]
        F = np.einsum("eab,eb->ea", self.B, xe).reshape(-1, 2, 2)
        out = ak.evaluate("fiber", F, projection="abs", hessian=False, fiber=fiber, **MATERIAL)
        energy = float(self.area @ out["energy"])
        grad_e = self.area[:, None] * np.einsum("eab,ea->eb", self.B, out["pk1"].reshape(-1, 4))
        grad = np.zeros_like(x)
        np.add.at(grad, self.dofs, grad_e)
        if not hessian:
            return energy, grad, None
        K_e = self.area[:, None, None] * np.einsum("eai,eab,ebj->eij", self.B, out["hessian_psd"], self.B)
        rows = np.repeat(self.dofs, 6, axis=1).ravel()
        cols = np.tile(self.dofs, (1, 6)).ravel()
        K = sp.csr_matrix((K_e.ravel(), (rows, cols)), shape=(x.size, x.size))
        return energy, grad, K


def solve(body, fiber, stretch=0.3, steps=3, tol=1e-9, max_newton=40):
    X = body.X
    length = X[:, 0].max()
    left, right = np.isclose(X[:, 0], 0.0), np.isclose(X[:, 0], length)
    fixed = np.zeros(X.size, bool)
    fixed[2 * np.flatnonzero(left)] = fixed[2 * np.flatnonzero(left) + 1] = True
    fixed[2 * np.flatnonzero(right)] = True  # x prescribed; y free to slide
    free = ~fixed
    x = X.ravel().copy()
    iterations = []
    for step in range(1, steps + 1):
        x[2 * np.flatnonzero(right)] = length * (1 + stretch * step / steps)
        for it in range(max_newton):
            energy, grad, K = body.evaluate(x, fiber)
            g = grad[free]
            scale = MATERIAL["E"] * body.area.sum()
            if np.abs(g).max() <= tol * scale:
                break
            du = spla.spsolve(K[free][:, free].tocsc(), -g)
            t = 1.0
            while t > 1e-8:  # backtracking on the energy (Armijo)
                trial = x.copy()
                trial[free] += t * du
                if body.evaluate(trial, fiber, hessian=False)[0] <= energy + 1e-4 * t * g @ du:
                    break
                t *= 0.5
            x = trial
        else:
            return None, iterations
        iterations.append(it)
    energy, grad, _ = body.evaluate(x, fiber, hessian=False)
    reaction = grad[2 * np.flatnonzero(right)].sum()  # the force holding the right edge, along x
    slide = (x[2 * np.flatnonzero(right) + 1] - X[right, 1]).mean()
    return dict(x=x.reshape(-1, 2), reaction=reaction, slide=slide), iterations


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="out/examples")
    parser.add_argument("--check", action="store_true")
    args = parser.parse_args()
    body = Strip(*strip())
    cases = {"along the pull [1, 0]": [1, 0], "across the pull [0, 1]": [0, 1], "at 45 degrees [1, 1]": [1, 1]}
    results, problems = {}, []
    print(f"{'fiber':26s} {'Newton per step':>16s} {'reaction x':>12s} {'edge slide y':>13s}")
    for name, fiber in cases.items():
        result, iterations = solve(body, fiber)
        if result is None:
            problems.append(f"{name}: Newton did not converge (iterations per step {iterations})")
            continue
        results[name] = result
        print(f"{name:26s} {str(iterations):>16s} {result['reaction']:12.2f} {result['slide']:13.5f}")
    if len(results) == 3:
        along, across, oblique = (results[n] for n in cases)
        if not along["reaction"] > 1.5 * across["reaction"] > 0:
            problems.append("a fiber along the pull should make the strip much stiffer than one across it")
        if not (abs(along["slide"]) < 1e-8 and abs(across["slide"]) < 1e-8):
            problems.append("fibers along or across the pull must not slide the free edge (symmetry)")
        if not abs(oblique["slide"]) > 1e-2:
            problems.append("a fiber at 45 degrees should slide the free edge (shear coupling)")
    if args.out and results:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        os.makedirs(args.out, exist_ok=True)
        fig, axes = plt.subplots(len(results), 1, figsize=(7, 2.2 * len(results)), sharex=True)
        for ax, (name, r) in zip(np.atleast_1d(axes), results.items()):
            ax.triplot(body.X[:, 0], body.X[:, 1], body.tris, color="0.85", lw=0.5)
            ax.triplot(r["x"][:, 0], r["x"][:, 1], body.tris, color="tab:blue", lw=0.6)
            ax.set_title(f"fiber {name}: reaction {r['reaction']:.0f}, edge slide {r['slide']:+.3f}", fontsize=9)
            ax.set_aspect("equal")
        fig.tight_layout()
        path = os.path.join(args.out, "stretch_strip.png")
        fig.savefig(path, dpi=120)
        print(f"wrote {path}")
    for p in problems:
        print("FAIL: " + p)
    return 1 if (args.check and problems) else 0


if __name__ == "__main__":
    sys.exit(main())
