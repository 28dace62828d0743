#!/usr/bin/env python3
"""Distortion report and PNG of a UV map computed by aries (-uv_map).

usage: uv_report.py OUTPUT_BASE [--step K] [--png FILE] [--json FILE] [--title T]

Reads the 3D surface (OUTPUT_BASE.h5, /mesh/rest) and the UV coordinates of output step K (default: the last; step 0
is the initial Tutte map). Per triangle, J maps the 3D triangle (in its own orthonormal frame, right-handed about the
mesh normal) to the UV triangle, with singular values s1 >= s2 after scaling the map to the surface's total area:
  flipped           triangles with det J <= 0 (orientation reversed relative to the mesh)
  area distortion   |ln(s1 s2)|            (0 = area preserving); area-weighted mean and max
  angle distortion  s1 / s2                (1 = conformal); area-weighted mean and max
  isometric         (s1 - 1)^2 + (s2 - 1)^2 (0 = isometric, the ARAP measure); area-weighted mean
Prints one JSON object (and writes it with --json). --png draws the UV layout coloured by angle distortion next to
the surface textured with a checkerboard in UV. Needs Debian's python3-h5py and python3-matplotlib.
"""
import argparse
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from aries_output import find_step  # noqa: E402


def distortion(rest, uv, tri):
    P = rest[tri]
    e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
    n = np.cross(e1, e2)
    area3 = 0.5 * np.linalg.norm(n, axis=1)
    t1 = e1 / np.linalg.norm(e1, axis=1, keepdims=True)
    t2 = np.cross(n / np.linalg.norm(n, axis=1, keepdims=True), t1)
    Dm = np.stack([np.stack([(e1 * t1).sum(1), (e2 * t1).sum(1)], 1),
                   np.stack([(e1 * t2).sum(1), (e2 * t2).sum(1)], 1)], 1)  # 2x2 per triangle, columns = edges
    U = uv[tri]
    Ds = np.stack([U[:, 1] - U[:, 0], U[:, 2] - U[:, 0]], 2)  # 2x2, columns = edges
    J = Ds @ np.linalg.inv(Dm)
    detJ = np.linalg.det(J)
    areaUV = detJ * area3  # signed UV area
    scale = np.sqrt(area3.sum() / max(np.abs(areaUV).sum(), 1e-300))
    s = np.linalg.svd(J * scale, compute_uv=False)
    s1, s2 = s[:, 0], s[:, 1]
    w = area3 / area3.sum()
    with np.errstate(divide="ignore", invalid="ignore"):
        area_d = np.abs(np.log(s1 * s2))
        angle_d = s1 / s2
    iso = (s1 - 1) ** 2 + (s2 - 1) ** 2
    return {
        "triangles": int(len(tri)),
        "flipped": int((detJ <= 0).sum()),
        "area_distortion_mean": float((w * area_d).sum()),
        "area_distortion_max": float(area_d.max()),
        "angle_distortion_mean": float((w * angle_d).sum()),
        "angle_distortion_max": float(angle_d.max()),
        "isometric_distortion_mean": float((w * iso).sum()),
    }, angle_d, detJ


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("--step", type=int, default=None)
    ap.add_argument("--png")
    ap.add_argument("--json")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    with h5py.File(a.base + ".h5", "r") as f:
        tri = f["/mesh/topology"][:].astype(np.int64)
        rest = f["/mesh/rest"][:]
    if tri.shape[1] != 3:
        sys.exit("uv_report: not a triangle mesh")
    path = find_step(a.base, a.step, "uv_report")
    with h5py.File(path, "r") as f:
        uv = f["/positions"][:, :2]
    stats, angle_d, detJ = distortion(rest, uv, tri)
    stats["step_file"] = path
    print(json.dumps(stats, sort_keys=True))
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(stats, fh, sort_keys=True, indent=1)
    if a.png:
        fig = plt.figure(figsize=(10, 5), dpi=110)
        ax = fig.add_subplot(121)
        col = plt.get_cmap("viridis")(np.clip((angle_d - 1.0) / 1.0, 0, 1))
        col[detJ <= 0] = (1, 0, 0, 1)
        ax.add_collection(PolyCollection(uv[tri], facecolors=col, edgecolors="k", linewidths=0.05))
        ax.autoscale()
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.set_title("UV layout: angle distortion s1/s2 (dark = 1, yellow >= 2, red = flipped)", fontsize=8)
        ax3 = fig.add_subplot(122, projection="3d")
        c = uv[tri].mean(1)
        k = 12.0 / (uv.max(0) - uv.min(0)).max()
        checker = (np.floor(c[:, 0] * k) + np.floor(c[:, 1] * k)) % 2
        P = rest[tri]
        nrm = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
        nrm /= np.maximum(np.linalg.norm(nrm, axis=1, keepdims=True), 1e-300)
        eye = np.array([0.3, -0.5, 0.8])
        eye /= np.linalg.norm(eye)
        shade = 0.4 + 0.6 * np.abs(nrm @ eye)
        base = np.where(checker[:, None] > 0, [[0.95, 0.9, 0.8]], [[0.25, 0.35, 0.6]])
        order = np.argsort(P.mean(1) @ eye)
        ax3.add_collection3d(Poly3DCollection(P[order], facecolors=(base * shade[:, None])[order], edgecolors="none"))
        lo, hi = rest.min(0), rest.max(0)
        mid, r = (lo + hi) / 2, (hi - lo).max() / 2
        ax3.set_xlim(mid[0] - r, mid[0] + r)
        ax3.set_ylim(mid[1] - r, mid[1] + r)
        ax3.set_zlim(mid[2] - r, mid[2] + r)
        ax3.view_init(elev=60, azim=-90)
        ax3.set_axis_off()
        ax3.set_title("surface with a checkerboard in UV", fontsize=8)
        fig.suptitle("%s  (flipped %d, angle distortion mean %.3f, area distortion mean %.3f)"
                     % (a.title, stats["flipped"], stats["angle_distortion_mean"], stats["area_distortion_mean"]),
                     fontsize=9)
        tmp = a.png + ".tmp.png"
        fig.savefig(tmp, bbox_inches="tight")
        os.replace(tmp, a.png)


if __name__ == "__main__":
    main()
