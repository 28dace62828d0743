#!/usr/bin/env python3
"""Surface curvature statistics of an aries tet-mesh output state (caricature scenes, paper Fig. 15).

usage: curvature_report.py OUTPUT_BASE [--step K] [--json]

Extracts the boundary surface of the tets (faces used by one tet, oriented outward), computes the mean curvature
per surface vertex with the cotangent Laplacian (Delta x = -2 H n, barycentric areas; the same discretization as the
solver's caricature field) at rest and at the state (the last step by default), and prints for both: the
area-weighted mean curvature H_mean and the dimensionless curvature variance var(H / H_mean) (area-weighted), plus
the volume ratio. Scale-free, so a uniformly scaled shape has the same variance. Needs Debian's python3-h5py and
numpy (run with /usr/bin/python3).
"""
import argparse
import json
import sys

import h5py
import numpy as np

from aries_output import find_step  # noqa: E402


def boundary_faces(tets, X):
    faces = np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 3, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 1]]])
    apex = np.concatenate([tets[:, 0], tets[:, 1], tets[:, 2], tets[:, 3]])
    key = np.sort(faces, axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inv.ravel()] == 1
    F, A = faces[once], apex[once]
    n = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    flip = np.einsum("ij,ij->i", n, X[F[:, 0]] - X[A]) < 0
    F[flip] = F[flip][:, [0, 2, 1]]
    return F


def curvature(F, X):
    """Per-vertex mean curvature H (Delta x = -2 H n) and barycentric area, on the vertices used by F."""
    nv = len(X)
    lap = np.zeros((nv, 3))
    nrm = np.zeros((nv, 3))
    area = np.zeros(nv)
    fn = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
    fa = 0.5 * np.linalg.norm(fn, axis=1)
    for k in range(3):
        o, i, j = F[:, k], F[:, (k + 1) % 3], F[:, (k + 2) % 3]
        ei, ej = X[i] - X[o], X[j] - X[o]
        cot = np.einsum("ij,ij->i", ei, ej) / np.linalg.norm(np.cross(ei, ej), axis=1)
        d = 0.5 * cot[:, None] * (X[j] - X[i])
        np.add.at(lap, i, d)
        np.add.at(lap, j, -d)
        np.add.at(nrm, o, 0.5 * fn)
        np.add.at(area, o, fa / 3.0)
    used = area > 0
    n = nrm[used] / np.linalg.norm(nrm[used], axis=1)[:, None]
    H = -0.5 * np.einsum("ij,ij->i", lap[used] / area[used][:, None], n)
    return H, area[used]


def stats(tets, X):
    F = boundary_faces(tets, X)
    H, A = curvature(F, X)
    Hm = float((H * A).sum() / A.sum())
    h = H / Hm
    var = float((A * (h - (h * A).sum() / A.sum()) ** 2).sum() / A.sum())
    D = np.stack([X[tets[:, k]] - X[tets[:, 0]] for k in (1, 2, 3)], axis=2)
    vol = float(np.linalg.det(D).sum() / 6.0)
    return {"mean_curvature": Hm, "curvature_variance": var, "surface_vertices": int(len(H)), "volume": vol}


def report(base, step=None):
    with h5py.File(base + ".h5", "r") as f:
        rest = f["/mesh/rest"][:]
        tets = f["/mesh/topology"][:].astype(np.int64)
    if tets.shape[1] != 4:
        sys.exit("curvature_report.py: %s is not a tet mesh" % base)
    path = find_step(base, step, "curvature_report.py")
    with h5py.File(path, "r") as f:
        x = f["/positions"][:]
    r, s = stats(tets, rest), stats(tets, x)
    return {"rest": r, "state": s, "step_file": path, "volume_ratio": s["volume"] / r["volume"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("--step", type=int, default=None)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    out = report(a.base, a.step)
    if a.json:
        print(json.dumps(out))
        return
    for k in ("rest", "state"):
        print("%-5s  H_mean %.6g  curvature variance var(H/H_mean) %.6g  (%d surface vertices)"
              % (k, out[k]["mean_curvature"], out[k]["curvature_variance"], out[k]["surface_vertices"]))
    print("volume ratio %.6f" % out["volume_ratio"])


if __name__ == "__main__":
    main()
