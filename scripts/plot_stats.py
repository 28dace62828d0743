#!/usr/bin/env python3
"""Chart a run's per-step solver work from its stats CSV (-stats FILE.csv) into a PNG.

usage: plot_stats.py STATS.csv PNG [--title T] [--compare OTHER.csv ...]

Three panels over the step number: Newton updates per step, CG (PCG) iterations per step and wall seconds per step
(log scale where the values span more than two decades), each with its mean over all steps in the legend; steps that
did not converge (reason not a convergence reason) are marked with a red x. --compare adds further runs (e.g. a
baseline energy or another solver) to the same panels. The CSV columns are documented in docs/options.md (-stats).
Needs Debian's python3-matplotlib (run with /usr/bin/python3).
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CONVERGED = {"newton_step", "converged_initial", "step_bound", "energy_roundoff", "fnorm_abs", "fnorm_rel"}
PANELS = [("newton_its", "Newton updates / step"), ("ksp_its", "CG iterations / step"), ("wall_s", "wall s / step")]


def read_stats(path):
    try:
        with open(path) as fh:
            rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    except OSError as e:
        sys.exit("plot_stats: error: cannot read %s: %s" % (path, e.strerror))
    missing = [c for c, _ in PANELS + [("step", ""), ("reason", "")] if rows and c not in rows[0]]
    if not rows or missing:
        sys.exit("plot_stats: error: %s is not an aries stats CSV (%s)" % (
            path, "no rows" if not rows else "missing columns " + ", ".join(missing)))
    return rows


def main():
    ap = argparse.ArgumentParser(description="Chart Newton / CG / time per step from aries stats CSVs.")
    ap.add_argument("stats")
    ap.add_argument("png")
    ap.add_argument("--title", default="")
    ap.add_argument("--compare", nargs="*", default=[], help="further stats CSVs drawn in the same panels")
    a = ap.parse_args()
    runs = [(p, read_stats(p)) for p in [a.stats] + a.compare]
    fig, axes = plt.subplots(len(PANELS), 1, figsize=(7, 7), sharex=True, dpi=120)
    for ax, (col, label) in zip(axes, PANELS):
        spans = []
        for path, rows in runs:
            steps = [int(r["step"]) for r in rows]
            vals = [float(r[col]) for r in rows]
            mean = sum(vals) / len(vals)
            ax.plot(steps, vals, lw=1, label="%s: mean %.3g over %d steps" % (os.path.basename(path), mean,
                                                                               len(vals)))
            bad = [(s, v) for s, v, r in zip(steps, vals, rows) if r["reason"] not in CONVERGED]
            if bad:
                ax.plot([s for s, _ in bad], [v for _, v in bad], "rx", ms=6, label="not converged (%d)" % len(bad))
            spans += [v for v in vals if v > 0]
        if spans and max(spans) / min(spans) > 100:
            ax.set_yscale("log")
        ax.set_ylabel(label, fontsize=8)
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
    axes[-1].set_xlabel("step", fontsize=8)
    axes[0].set_title(a.title or os.path.basename(a.stats), fontsize=10)
    fig.tight_layout()
    tmp = a.png + ".tmp.png"
    fig.savefig(tmp)
    os.replace(tmp, a.png)
    print("wrote " + a.png)


if __name__ == "__main__":
    main()
