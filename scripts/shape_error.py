#!/usr/bin/env python3
"""Distance of an aries output state to the rest shape.

usage: shape_error.py OUTPUT_BASE [--step K] [--rigid]

Prints max and RMS vertex distance to the rest positions, divided by L (rest bounding-box diagonal). With --rigid
the state is first aligned to the rest shape by the best rotation and translation (Kabsch), the measure for
free-floating scenes (an inside-out body may recover rotated). Reads OUTPUT_BASE.h5 and the step file of
OUTPUT_BASE.xmf (the last step by default). Needs Debian's python3-h5py (run with /usr/bin/python3).
"""
import argparse

import h5py
import numpy as np

from aries_output import find_step  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("--step", type=int, default=None)
    ap.add_argument("--rigid", action="store_true")
    a = ap.parse_args()
    with h5py.File(a.base + ".h5", "r") as f:
        rest = f["/mesh/rest"][:]
    path = find_step(a.base, a.step, "shape_error")
    with h5py.File(path, "r") as f:
        x = f["/positions"][:]
    err_max, err_rms = shape_error(rest, x, a.rigid)
    print("max_over_L %.6e rms_over_L %.6e step_file %s" % (err_max, err_rms, path))


def shape_error(rest, x, rigid=False):
    """(max, RMS) vertex distance of positions x to rest (n x 3 arrays) over L, the rest bounding-box diagonal; with
    rigid=True x is first aligned to rest by the best rotation and translation (Kabsch). NaN if x is not finite."""
    if not np.all(np.isfinite(x)):
        return float("nan"), float("nan")
    L = np.linalg.norm(rest.max(0) - rest.min(0))
    if rigid:
        x = rigid_align(rest, x)
    dist = np.linalg.norm(x - rest, axis=1)
    return dist.max() / L, np.sqrt((dist**2).mean()) / L


def rigid_align(rest, x):
    """x moved by the rotation and translation that best fit it to rest (least squares over the vertices, Kabsch;
    a proper rotation, never a reflection). n x 3 arrays; x must be finite."""
    cr, cx = rest.mean(0), x.mean(0)
    H = (x - cx).T @ (rest - cr)
    U, _, Vt = np.linalg.svd(H)
    D = np.diag([1, 1, np.sign(np.linalg.det(Vt.T @ U.T))])
    Rm = Vt.T @ D @ U.T
    return (Rm @ (x - cx).T).T + cr


if __name__ == "__main__":
    main()
