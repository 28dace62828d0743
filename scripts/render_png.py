#!/usr/bin/env python3
"""Render an aries output state to PNG (no ParaView needed).

usage: render_png.py OUTPUT_BASE PNG [--step K] [--title T] [--view ELEV,AZIM] [--field NAME] [--rigid]
                     [--beside-rest]

Draws the boundary surface of the mesh (tetrahedra: faces used by one cell; triangles: all cells) at output step K
(default: the last one written), shaded by a headlight and coloured by --field, with a colour bar and a caption that
says what the colours mean and gives the field's actual range in this state:
  alpha          alpha of the adjacent cell, the element's singularity measure (log scale): its rest value (64 for
                 tetrahedra, 2 for triangles) means undeformed or only rotated, it grows under stretching and falls
                 under compression or inversion, and 0 means singular: the element is a mirror image of its rest
                 shape (inside out) or crushed onto a line or a point, where its rotation is undefined   (default)
  stress         von Mises stress (the von_mises field, else computed from cauchy_stress)
  J              det F (< 0: inverted), diverging colours around 1
  displacement   |x - X| per vertex (always available)
  none           plain shading
  any other field written with -output_fields: a per-cell scalar, or the Frobenius norm of a per-cell tensor / vector
(stress and the other fields: the colour scale ends at the 99th percentile, the caption gives the full range)
--rigid moves the state by the rotation and translation that best fit it to the rest shape (least squares, Kabsch;
scripts/shape_error.py) before drawing it, so a free-floating body that recovered turned or drifted is seen in the
rest pose; the caption then gives the remaining distance to rest. --beside-rest draws the rest shape (uncoloured)
in a second panel to the left, with the same view and scale. --title may contain {step} (the output step) and
{time} (the simulated time of that step, a number: {time:g}).
The fields present depend on the run's -output_fields (docs/options.md). The view is fixed for a given mesh so
before/after images line up. Needs Debian's python3-h5py and python3-matplotlib (run with /usr/bin/python3).
"""
import argparse
import os
import re
import sys
import textwrap

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib import cm, colors  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from aries_output import find_step  # noqa: E402
from shape_error import rigid_align, shape_error  # noqa: E402


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


def draw(fig, rect, x, faces, facecolors, elev, azim, lim, title):
    """One 3D panel: the faces of positions x, painter's order (far faces first), headlight shading."""
    tri = x[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    e, z = np.radians(elev), np.radians(azim)
    eye = np.array([np.cos(e) * np.cos(z), np.cos(e) * np.sin(z), np.sin(e)])
    shade = 0.35 + 0.65 * np.abs(normal @ eye)
    fc = np.clip(facecolors * shade[:, None], 0, 1)
    order = np.argsort(tri.mean(1) @ eye)
    ax = fig.add_axes(rect, projection="3d")
    ax.add_collection3d(Poly3DCollection(tri[order], facecolors=fc[order], edgecolors="none", linewidths=0))
    c, r = lim
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)
    return ax


def main():
    ap = argparse.ArgumentParser(description="Render an aries output state to PNG (see the module docstring).")
    ap.add_argument("base", help="output base (the -output DIR/NAME of the run)")
    ap.add_argument("png")
    ap.add_argument("--step", type=int, default=None, help="output step (default: the last one written)")
    ap.add_argument("--title", default="", help="figure title; {step} and {time} are replaced by the step's")
    ap.add_argument("--view", default="15,-60", help="elevation,azimuth in degrees")
    ap.add_argument("--field", default="alpha",
                    help="alpha (default), stress, J, displacement, none, or any per-cell output field")
    ap.add_argument("--rigid", action="store_true",
                    help="draw the state moved by the best-fit rotation + translation onto the rest shape (Kabsch)")
    ap.add_argument("--beside-rest", action="store_true", help="draw the rest shape in a panel to the left")
    a = ap.parse_args()
    with h5py.File(a.base + ".h5", "r") as f:
        cells = f["/mesh/topology"][:].astype(np.int64)
        rest = f["/mesh/rest"][:]
    path = find_step(a.base, a.step, "render_png")
    faces, owner = boundary(cells)
    with h5py.File(path, "r") as f:
        x = f["/positions"][:]
        sim_time = float(f.attrs["time"]) if "time" in f.attrs else float("nan")
        if a.field in ("displacement", "none"):
            values, name = None, a.field
        else:
            values, name = cell_field(f, a.field)
            if values is None:
                have = sorted(f["/cell"].keys()) if "/cell" in f else []
                sys.exit("render_png: error: field '%s' is not in %s (cell fields there: %s; displacement and none "
                         "always work; add fields with -output_fields)" % (a.field, path, ", ".join(have) or "none"))
    m = re.search(r"_(\d+)\.h5$", path)
    step = int(m.group(1)) if m else -1
    try:
        title = a.title.format(step=step, time=sim_time)
    except (KeyError, IndexError, ValueError):  # other braces in the title: keep it as given
        title = a.title
    rigid_note = ""
    if a.rigid:
        if not np.all(np.isfinite(x)):
            sys.exit("render_png: error: --rigid: the state in %s is not finite" % path)
        x = rigid_align(rest, x)
        emax, erms = shape_error(rest, x)
        rigid_note = ("The state is drawn moved by the rotation and translation that best fit it to the rest shape; "
                      "its largest vertex distance to rest is then %.2g%% of the rest bounding-box diagonal (RMS "
                      "%.2g%%)." % (100 * emax, 100 * erms))
    elev, azim = (float(v) for v in a.view.split(","))
    rest_alpha = 64.0 if cells.shape[1] == 4 else 2.0
    # summary: the one line printed (logs, tests); caption: the words under the picture
    norm, cmap, summary, caption = None, None, "", ""
    if a.field == "displacement":
        v = np.linalg.norm(x - rest, axis=1)[faces].mean(1)
        norm, cmap = colors.Normalize(0.0, max(v.max(), 1e-300)), plt.get_cmap("magma")
        summary = "displacement magnitude (face mean of vertices): %.3g .. %.3g" % (v.min(), v.max())
        caption = "Colour: distance of the surface from its rest position (%s): %.3g .. %.3g." % (
            "after the rigid fit" if a.rigid else "mean of the face's vertices", v.min(), v.max())
    elif values is not None:
        v = values[owner]
        if a.field == "alpha":
            floor = 1e-8
            norm = colors.LogNorm(floor, max(values.max(), rest_alpha))
            cmap = plt.get_cmap("viridis")
            at0 = int(np.sum(values < floor))  # F = -I gives alpha = 0 up to round-off (~1e-27), not exactly 0
            summary = ("alpha of the adjacent cell (log scale, < %g drawn at %g): %.3g .. %.3g, rest %g, %d of %d "
                       "cells at alpha = 0 (below %g)" % (floor, floor, values.min(), values.max(), rest_alpha, at0,
                                                          len(values), floor))
            caption = ("Colour: alpha, each element's singularity measure (log scale). %g = undeformed or only "
                       "rotated (yellow); lower = compressed or inverted, higher = stretched; 0 = singular (dark "
                       "purple): the element is inside out (a mirror image of its rest shape) or crushed onto a line "
                       "or a point. This state: alpha %.3g .. %.3g; {:,} of {:,} elements at 0 (below %g).".format(
                           at0, len(values)) % (rest_alpha, values.min(), values.max(), floor))
            v = np.maximum(v, floor)
        elif a.field == "J":
            span = max(abs(values.max() - 1.0), abs(values.min() - 1.0), 1e-12)
            norm, cmap = colors.Normalize(1.0 - span, 1.0 + span), plt.get_cmap("coolwarm")
            inv = int(np.sum(values < 0.0))
            summary = "J = det F: %.3g .. %.3g (%d inverted cells)" % (values.min(), values.max(), inv)
            caption = ("Colour: J = det F, the element's volume over its rest volume (1 = volume kept, white; "
                       "< 1 compressed, blue; > 1 expanded, red; < 0 inverted). This state: %.3g .. %.3g, %d inverted "
                       "elements." % (values.min(), values.max(), inv))
        else:
            # Stress concentrates in a few cells: the colour scale ends at the 99th percentile (the caption gives the
            # full range), so the rest of the body is not drawn in one colour.
            finite = values[np.isfinite(values)]
            lo, hi = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
            top = np.percentile(finite, 99.0) if finite.size else 1.0
            norm, cmap = colors.Normalize(lo, top if top > lo else lo + 1e-300), plt.get_cmap("inferno")
            summary = "%s: %.3g .. %.3g (colour scale to the 99th percentile, %.3g)" % (name, lo, hi, top)
            caption = "Colour: %s of the adjacent cell, %.3g .. %.3g (the colour scale ends at the 99th percentile, " \
                      "%.3g)." % (name, lo, hi, top)
    if norm is not None:
        rgb = cmap(norm(v))[:, :3]
    else:
        rgb = np.tile([0.75, 0.72, 0.65], (len(faces), 1))
    caption = " ".join(t for t in (caption, rigid_note) if t)
    allp = np.concatenate([x, rest])
    lim = (allp.mean(0), (allp.max(0) - allp.min(0)).max() / 2)
    grey = np.tile([0.75, 0.72, 0.65], (len(faces), 1))
    if a.beside_rest:
        width, bottom = 9.6, 0.1
        fig = plt.figure(figsize=(width, 4.4), dpi=120)
        draw(fig, [0.0, bottom, 0.44, 0.8], rest, faces, grey, elev, azim, lim, "rest shape")
        draw(fig, [0.41, bottom, 0.46, 0.8], x, faces, rgb, elev, azim, lim,
             "step %d (t = %g s)%s" % (step, sim_time, ", rigidly aligned to the rest shape" if a.rigid else ""))
        cbar = [0.87, 0.25, 0.02, 0.6]
        fig.suptitle(title, fontsize=10, y=0.985)
    else:
        width, bottom = 5.6, 0.12
        fig = plt.figure(figsize=(width, 5.4), dpi=120)
        draw(fig, [0.0, bottom, 0.82, 0.82], x, faces, rgb, elev, azim, lim, title)
        cbar = [0.84, 0.24, 0.03, 0.56]
    if norm is not None:
        cb = fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), cax=fig.add_axes(cbar))
        if a.field == "alpha":  # name the two values that matter: singular (0, drawn at the floor) and rest
            ticks = [t for t in (floor, 1e-6, 1e-4, 1e-2, 1.0) if t < rest_alpha / 2] + [rest_alpha]
            cb.ax.minorticks_off()
            cb.set_ticks(ticks, labels=["0"] + ["%g" % t for t in ticks[1:-1]] + ["%g rest" % rest_alpha])
            cb.set_label("alpha (log scale)", fontsize=8)
        cb.ax.tick_params(labelsize=7)
    if caption:
        fig.text(0.5, 0.01, textwrap.fill(caption, int(width * 19)), ha="center", va="bottom", fontsize=7)
    tmp = a.png + ".tmp.png"
    fig.savefig(tmp)
    os.replace(tmp, a.png)
    print("wrote %s (%s)" % (a.png, summary or "no colouring"))


if __name__ == "__main__":
    main()
