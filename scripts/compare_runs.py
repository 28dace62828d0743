#!/usr/bin/env python3
"""Compares the outputs of two runs of the suite (or of any two output trees) for a behaviour-preserving change:
every stats / history / reactions CSV (all columns but wall-clock times; '#' comment lines, which carry the version,
are skipped) and every numeric dataset of every HDF5 file that exists under both roots at the same relative path.

  /usr/bin/python3 scripts/compare_runs.py BEFORE/build AFTER/build [--under e2e robustness]

Prints one line per differing file and a summary; exit 1 if anything common differs."""
import argparse
import csv
import os
import sys

import h5py
import numpy as np

TIME_COLUMNS = {"wall_s", "elapsed_s", "time_s"}


def files(root, unders):
    out = {}
    for u in unders:
        base = os.path.join(root, u)
        for d, _, names in os.walk(base):
            for n in names:
                if n.endswith((".csv", ".h5")) and ".tmp" not in n:
                    p = os.path.join(d, n)
                    out[os.path.relpath(p, root)] = p
    return out


def read_csv(path):
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if not line.startswith("#"))]
    if not rows:
        return [], []
    head = rows[0]
    keep = [i for i, h in enumerate(head) if h not in TIME_COLUMNS]
    return [head[i] for i in keep], [[r[i] if i < len(r) else "" for i in keep] for r in rows[1:]]


def csv_diff(a, b):
    ha, ra = read_csv(a)
    hb, rb = read_csv(b)
    if ha != hb:
        return "columns differ: %s vs %s" % (ha, hb)
    if len(ra) != len(rb):
        return "%d vs %d rows" % (len(ra), len(rb))
    for k, (x, y) in enumerate(zip(ra, rb)):
        if x != y:
            cols = [ha[i] for i in range(len(x)) if x[i] != y[i]]
            return "row %d differs in %s: %s vs %s" % (k + 1, ",".join(cols), x, y)
    return ""


def datasets(f):
    out = {}
    f.visititems(lambda name, obj: out.__setitem__(name, obj) if isinstance(obj, h5py.Dataset) else None)
    return out


def h5_diff(a, b):
    try:
        fa, fb = h5py.File(a, "r"), h5py.File(b, "r")
    except OSError:  # not HDF5 (a bad-input test's garbage file): compare the bytes
        with open(a, "rb") as x, open(b, "rb") as y:
            return "" if x.read() == y.read() else "non-HDF5 files differ"
    with fa, fb:
        da, db = datasets(fa), datasets(fb)
        if set(da) != set(db):
            return "datasets differ: only before %s, only after %s" % (sorted(set(da) - set(db)), sorted(set(db) - set(da)))
        for name in sorted(da):
            x, y = da[name][()], db[name][()]
            if not (np.issubdtype(np.asarray(x).dtype, np.number) or np.asarray(x).dtype == bool):
                continue
            if np.shape(x) != np.shape(y):
                return "%s: shape %s vs %s" % (name, np.shape(x), np.shape(y))
            if not np.array_equal(x, y, equal_nan=np.issubdtype(np.asarray(x).dtype, np.floating)):
                d = np.nanmax(np.abs(np.asarray(x, float) - np.asarray(y, float)))
                return "%s: max |difference| %.3g" % (name, d)
    return ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("before")
    ap.add_argument("after")
    ap.add_argument("--under", nargs="+", default=["e2e", "robustness"])
    ap.add_argument("--skip", nargs="*", default=[], help="path prefixes (relative) of tests whose runs changed")
    a = ap.parse_args()
    fa, fb = files(a.before, a.under), files(a.after, a.under)
    for f in (fa, fb):
        for rel in [r for r in f if any(r.startswith(p) for p in a.skip)]:
            del f[rel]
    common = sorted(set(fa) & set(fb))
    bad, counts = 0, {"csv": 0, "h5": 0}
    for rel in common:
        kind = "csv" if rel.endswith(".csv") else "h5"
        counts[kind] += 1
        why = csv_diff(fa[rel], fb[rel]) if kind == "csv" else h5_diff(fa[rel], fb[rel])
        if why:
            bad += 1
            print("DIFFERS %s: %s" % (rel, why))
    print("compared %d CSV and %d HDF5 files present in both: %d identical, %d differ; %d only before, %d only after"
          % (counts["csv"], counts["h5"], len(common) - bad, bad, len(set(fa) - set(fb)), len(set(fb) - set(fa))))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
