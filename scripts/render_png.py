#!/usr/bin/env python3
"""Render an aries output state to PNG (no ParaView needed).

usage: render_png.py OUTPUT_BASE PNG [--step K] [--title T] [--view ELEV,AZIM] [--field NAME]

Draws the boundary surface of the mesh (tetrahedra: faces used by one cell; triangles: all cells) at output step K
(default: the last one written), shaded by a headlight and coloured by --field, with a colour bar and a caption that
give the field's actual range in this state:
  alpha          the singularity measure of the adjacent cell (log scale; 0 = singular, e.g. inside out; the rest
                 value is 64 for tetrahedra and 2 for triangles)          (default)
  stress         von Mises stress (the von_mises field, else computed from cauchy_stress)
  J              det F (< 0: inverted), diverging colours around 1
  displacement   |x - X| per vertex (always available)
  none           plain shading
  any other field written with -output_fields: a per-cell scalar, or the Frobenius norm of a per-cell tensor / vector
(stress and the other fields: the colour scale ends at the 99th percentile, the caption gives the full range)
The fields present depend on the run's -output_fields (docs/options.md). The view is fixed for a given mesh so
before/after images line up. Needs Debian's python3-h5py and python3-matplotlib (run with /usr/bin/python3).
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm, colors  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from aries_output import find_step  # noqa: E402


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


def cell_field(f, name):
    """A per-cell scalar from the step file, or None."""
    if name == "stress":
        if "/cell/von_mises" in f:
            return f["/cell/von_mises"][:], "von Mises stress"
        if "/cell/cauchy_stress" in f:
            s = f["/cell/cauchy_stress"][:].reshape(-1, 3, 3)
            dev = s - np.trace(s, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3.0
            return np.sqrt(1.5 * np.einsum("kij,kij->k", dev, dev)), "von Mises stress (from cauchy_stress)"
        return None, None
    if "/cell/" + name not in f:
        return None, None
    v = f["/cell/" + name][:]
    if v.ndim == 2 and v.shape[1] > 1:
        return np.linalg.norm(v, axis=1), "|%s| (Frobenius norm)" % name
    return v.reshape(-1), name


def main():
    ap = argparse.ArgumentParser(description="Render an aries output state to PNG (see the module docstring).")
    ap.add_argument("base", help="output base (the -output DIR/NAME of the run)")
    ap.add_argument("png")
    ap.add_argument("--step", type=int, default=None, help="output step (default: the last one written)")
    ap.add_argument("--title", default="")
    ap.add_argument("--view", default="15,-60", help="elevation,azimuth in degrees")
    ap.add_argument("--field", default="alpha",
                    help="alpha (default), stress, J, displacement, none, or any per-cell output field")
    a = ap.parse_args()
    with h5py.File(a.base + ".h5", "r") as f:
        cells = f["/mesh/topology"][:].astype(np.int64)
        rest = f["/mesh/rest"][:]
    path = find_step(a.base, a.step, "render_png")
    faces, owner = boundary(cells)
    with h5py.File(path, "r") as f:
        x = f["/positions"][:]
        if a.field in ("displacement", "none"):
            values, name = None, a.field
        else:
            values, name = cell_field(f, a.field)
            if values is None:
                have = sorted(f["/cell"].keys()) if "/cell" in f else []
                sys.exit("render_png: error: field '%s' is not in %s (cell fields there: %s; displacement and none "
                         "always work; add fields with -output_fields)" % (a.field, path, ", ".join(have) or "none"))
    tri = x[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    elev, azim = (float(v) for v in a.view.split(","))
    e, z = np.radians(elev), np.radians(azim)
    eye = np.array([np.cos(e) * np.cos(z), np.cos(e) * np.sin(z), np.sin(e)])
    shade = 0.35 + 0.65 * np.abs(normal @ eye)
    rest_alpha = 64.0 if cells.shape[1] == 4 else 2.0
    norm, cmap, label = None, None, ""
    if a.field == "displacement":
        v = np.linalg.norm(x - rest, axis=1)[faces].mean(1)
        norm, cmap = colors.Normalize(0.0, max(v.max(), 1e-300)), plt.get_cmap("magma")
        label = "displacement magnitude (face mean of vertices): %.3g .. %.3g" % (v.min(), v.max())
    elif values is not None:
        v = values[owner]
        if a.field == "alpha":
            floor = 1e-8
            norm = colors.LogNorm(floor, max(values.max(), rest_alpha))
            cmap = plt.get_cmap("viridis")
            label = ("alpha of the adjacent cell (log scale, < %g drawn at %g): %.3g .. %.3g, rest %g, %d of %d "
                     "cells at alpha = 0" % (floor, floor, values.min(), values.max(), rest_alpha,
                                             int(np.sum(values <= 0.0)), len(values)))
            v = np.maximum(v, floor)
        elif a.field == "J":
            span = max(abs(values.max() - 1.0), abs(values.min() - 1.0), 1e-12)
            norm, cmap = colors.Normalize(1.0 - span, 1.0 + span), plt.get_cmap("coolwarm")
            label = "J = det F: %.3g .. %.3g (%d inverted cells)" % (values.min(), values.max(),
                                                                      int(np.sum(values < 0.0)))
        else:
            # Stress concentrates in a few cells: the colour scale ends at the 99th percentile (the caption gives the
            # full range), so the rest of the body is not drawn in one colour.
            finite = values[np.isfinite(values)]
            lo, hi = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
            top = np.percentile(finite, 99.0) if finite.size else 1.0
            norm, cmap = colors.Normalize(lo, top if top > lo else lo + 1e-300), plt.get_cmap("inferno")
            label = "%s: %.3g .. %.3g (colour scale to the 99th percentile, %.3g)" % (name, lo, hi, top)
    if norm is not None:
        rgb = cmap(norm(v))[:, :3]
    else:
        rgb = np.tile([0.75, 0.72, 0.65], (len(faces), 1))
    facecolors = np.clip(rgb * shade[:, None], 0, 1)
    # Painter's order: far faces first.
    order = np.argsort(tri.mean(1) @ eye)
    fig = plt.figure(figsize=(5.6, 5), dpi=120)
    ax = fig.add_axes([0.0, 0.08, 0.82, 0.86], projection="3d")
    ax.add_collection3d(Poly3DCollection(tri[order], facecolors=facecolors[order], edgecolors="none", linewidths=0))
    allp = np.concatenate([x, rest])
    c, r = allp.mean(0), (allp.max(0) - allp.min(0)).max() / 2
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    ax.set_title(a.title, fontsize=10)
    if norm is not None:
        cax = fig.add_axes([0.84, 0.2, 0.03, 0.6])
        fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=cax).ax.tick_params(labelsize=7)
        fig.text(0.5, 0.02, label, ha="center", fontsize=6.5, wrap=True)
    tmp = a.png + ".tmp.png"
    fig.savefig(tmp)
    os.replace(tmp, a.png)
    print("wrote %s (%s)" % (a.png, label or "no colouring"))


if __name__ == "__main__":
    main()
