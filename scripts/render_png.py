#!/usr/bin/env python3
"""Render an aries output state to PNG (no ParaView needed).

usage: render_png.py OUTPUT_BASE PNG [--step K] [--title T] [--view ELEV,AZIM] [--color alpha|displacement|none]

Draws the boundary surface of the mesh (tetrahedra: faces used by one cell; triangles: all cells) at output step K
(default: the last one written), shaded by a headlight and coloured by the singularity measure alpha of the adjacent
cell (log scale; alpha = 0 is the singular, e.g. inside-out, state), by displacement, or plain. The view is fixed
for a given mesh so before/after images line up. Needs Debian's python3-h5py and python3-matplotlib
(run with /usr/bin/python3).
"""
import argparse
import glob
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def boundary(cells):
    """Boundary faces of a tet mesh (with the owning cell), or all triangles of a surface mesh."""
    if cells.shape[1] == 3:
        return cells, np.arange(len(cells))
    faces = np.concatenate([cells[:, [0, 1, 2]], cells[:, [0, 1, 3]], cells[:, [0, 2, 3]], cells[:, [1, 2, 3]]])
    owner = np.tile(np.arange(len(cells)), 4)
    key = np.sort(faces, axis=1)
    _, inv, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    once = counts[inv] == 1
    return faces[once], owner[once]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("png")
    ap.add_argument("--step", type=int, default=None)
    ap.add_argument("--title", default="")
    ap.add_argument("--view", default="15,-60")
    ap.add_argument("--color", default="alpha", choices=["alpha", "displacement", "none"])
    a = ap.parse_args()
    with h5py.File(a.base + ".h5", "r") as f:
        cells = f["/mesh/topology"][:].astype(np.int64)
        rest = f["/mesh/rest"][:]
    d, n = os.path.dirname(a.base) or ".", os.path.basename(a.base)
    steps = sorted(glob.glob(os.path.join(d, n + ".steps", n + "_*.h5")))
    if not steps:
        sys.exit("render_png: no output steps for " + a.base)
    path = steps[-1] if a.step is None else os.path.join(d, n + ".steps", "%s_%06d.h5" % (n, a.step))
    with h5py.File(path, "r") as f:
        x = f["/positions"][:]
        alpha = f["/cell/alpha"][:] if "/cell/alpha" in f else None
    faces, owner = boundary(cells)
    tri = x[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    elev, azim = (float(v) for v in a.view.split(","))
    e, z = np.radians(elev), np.radians(azim)
    eye = np.array([np.cos(e) * np.cos(z), np.cos(e) * np.sin(z), np.sin(e)])
    shade = 0.35 + 0.65 * np.abs(normal @ eye)
    if a.color == "alpha" and alpha is not None:
        val = np.log10(np.maximum(alpha[owner], 1e-8))
        rgb = plt.get_cmap("viridis")((val + 8.0) / (np.log10(64.0) + 8.0))[:, :3]
        label = "log10 alpha (adjacent cell): dark = 0 (singular), yellow = 64 (rest)"
    elif a.color == "displacement":
        dist = np.linalg.norm(x - rest, axis=1)[faces].mean(1)
        rgb = plt.get_cmap("magma")(dist / max(dist.max(), 1e-300))[:, :3]
        label = "displacement magnitude"
    else:
        rgb = np.tile([0.75, 0.72, 0.65], (len(faces), 1))
        label = ""
    colors = np.clip(rgb * shade[:, None], 0, 1)
    # Painter's order: far faces first.
    order = np.argsort(tri.mean(1) @ eye)
    fig = plt.figure(figsize=(5, 5), dpi=120)
    ax = fig.add_subplot(111, projection="3d")
    ax.add_collection3d(Poly3DCollection(tri[order], facecolors=colors[order], edgecolors="none", linewidths=0))
    allp = np.concatenate([x, rest])
    c, r = allp.mean(0), (allp.max(0) - allp.min(0)).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    ax.set_title(a.title, fontsize=10)
    if label:
        fig.text(0.5, 0.03, label, ha="center", fontsize=7)
    tmp = a.png + ".tmp.png"
    fig.savefig(tmp, bbox_inches="tight")
    os.replace(tmp, a.png)
    print("wrote " + a.png)


if __name__ == "__main__":
    main()
