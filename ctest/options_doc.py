#!/usr/bin/env python3
"""Shows that `aries-options-doc --check` fails when docs/options.md disagrees with the option declarations: the docs
as they are pass; a copy with one documented default changed by hand (a solver default, a per-integrator default, an
energy table cell) fails with exit code 1 and names the edited line. Exit 0 when every case behaves so."""
import argparse
import os
import re
import shutil
import subprocess
import sys

EDITS = [  # (what, pattern in a table row, replacement)
    ("-dt's default", r"(\| `-dt X` \| )`1e-2`", r"\1`1e-3`"),
    ("-newton_tol's static default", r"(\| `-newton_tol X` \| )`1e-4` \(static\)", r"\1`1e-5` (static)"),
    ("an energy's shapes", r"(\| `iarap` \| )tet, planar", r"\1tet"),
]


def check(tool, path):
    p = subprocess.run([tool, "--check", path], capture_output=True, text=True)
    return p.returncode, p.stderr


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--tool", required=True)
    ap.add_argument("--docs", required=True)
    ap.add_argument("--work", required=True)
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    code, err = check(a.tool, a.docs)
    if code != 0:
        sys.exit("FAIL: the docs as they are do not pass the check:\n" + err)
    with open(a.docs) as fh:
        text = fh.read()
    for what, pattern, repl in EDITS:
        edited, n = re.subn(pattern, repl, text)
        if n != 1:
            sys.exit("FAIL: the table row for %s was not found exactly once (%d)" % (what, n))
        line = 1 + text[: re.search(pattern, text).start()].count("\n")
        copy = os.path.join(a.work, "options.md")
        shutil.copy(a.docs, copy)
        with open(copy, "w") as fh:
            fh.write(edited)
        code, err = check(a.tool, copy)
        if code != 1 or ("line %d differs" % line) not in err:
            sys.exit("FAIL: changing %s (line %d) was not caught: exit %d, %r" % (what, line, code, err))
        print("changing %s by hand: caught at line %d" % (what, line))
    print("3 passed, 0 failed")


if __name__ == "__main__":
    main()
