#!/usr/bin/env python3
"""End-to-end cases of aries with their expected values (registered with CTest by ctest/e2e.cmake).

usage: e2e.py CASE --aries BIN --root REPO --work DIR [--ranks N]

Each case runs the solver on a small test mesh (meshes/generate.sh NAME test) and asserts a physical outcome:
rest shape recovered, reaction force of linear elasticity, stiffness ratio, ranks agreeing, the alpha safeguard
acting, a baseline failing cleanly. Exit 0 = pass; a failure prints what was expected and what was measured.
The cases live in ctest/e2e/, one module per topic, each with its CASES dict; this script merges them (a case name
registered twice is an error) and runs one. CASE options:NAME runs the shipped options file options/NAME.yml.
Needs Debian's python3-h5py and numpy (run with /usr/bin/python3).
"""
import argparse
import os
import sys

# ctest/ on the path from any working directory: harness.py and the package e2e/ (a package takes precedence over
# this script's own name, e2e.py, in the same folder).
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from harness import fail  # noqa: E402
from e2e import (cloth, common, elements, inside_out, loads, mesh_io, nested, output, ranks, shape,  # noqa: E402
                 solver, starts, supports)

TOPICS = (inside_out, starts, supports, loads, elements, cloth, nested, shape, output, mesh_io, ranks, solver)


def merged_cases():
    """Every topic's CASES in one dict; a name registered by two modules raises."""
    cases, owner = {}, {}
    for module in TOPICS:
        for name, function in module.CASES.items():
            if name in cases:
                raise RuntimeError("e2e case %r is registered by both %s and %s" % (name, owner[name],
                                                                                     module.__name__))
            cases[name], owner[name] = function, module.__name__
    return cases


CASES = merged_cases()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("case")
    ap.add_argument("--aries", required=True)
    ap.add_argument("--root", required=True)
    ap.add_argument("--work", required=True)
    ap.add_argument("--ranks", type=int, default=1)
    ap.parse_args(namespace=common.ARGS)  # filled in place: every module holds this one object
    ARGS = common.ARGS
    os.makedirs(os.path.join(ARGS.work, "out"), exist_ok=True)
    if ARGS.case.startswith("options:"):
        output.case_options_file(ARGS.case.split(":", 1)[1])
    elif ARGS.case in CASES:
        CASES[ARGS.case]()
    else:
        fail("unknown case " + ARGS.case)
    print("PASS")


if __name__ == "__main__":
    main()
