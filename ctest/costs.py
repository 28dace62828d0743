#!/usr/bin/python3
"""Writes ctest/costs.txt, the run time of each top-level test (seconds, from a build folder's CTest cost data:
BUILD/Testing/Temporary/CTestCostData.txt, the moving average CTest keeps of every test it ran). CMakeLists.txt gives
each test its time as the COST property, so that a first `ctest -j N` in a new build folder, which has no cost data
yet (CI, a fresh clone), starts the longest tests first as later runs do, instead of in the order the tests were
declared with the longest ones left for the end. Run it after a full `ctest` when tests were added or their time
changed much:

    /usr/bin/python3 ctest/costs.py build
"""
import os
import sys

MIN_SECONDS = 1.0  # shorter tests keep cost 0 (they run last, where they fill the gaps)


def main(argv):
    if len(argv) != 1:
        raise SystemExit(__doc__)
    data = os.path.join(argv[0], "Testing", "Temporary", "CTestCostData.txt")
    if not os.path.isfile(data):
        raise SystemExit("costs.py: %s not found (run ctest in that build folder first)" % data)
    costs = {}
    with open(data) as fh:
        for line in fh:
            if line.strip() == "---":  # the failed tests' list follows
                break
            parts = line.split()
            if len(parts) == 3 and "." in parts[0] and float(parts[2]) >= MIN_SECONDS:
                costs[parts[0]] = float(parts[2])  # name, runs, average seconds
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "costs.txt")
    with open(out, "w") as fh:
        fh.write("# test seconds: written by ctest/costs.py from a full ctest's cost data (CTest's COST property)\n")
        for name in sorted(costs):
            fh.write("%s %.1f\n" % (name, costs[name]))
    print("%s: %d tests" % (out, len(costs)))


if __name__ == "__main__":
    main(sys.argv[1:])
