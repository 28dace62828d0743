#!/usr/bin/env python3
"""Size limits of the library's sources: no file over --max-file lines, no function body over --max-function lines.

Usage: check_code_size.py [--max-file 600] [--max-function 120] [--list N] DIR...

Scans *.cpp / *.hpp under each DIR. A function is a brace block opened at namespace or class scope whose head ends
like a parameter list (`) {`, `) const {`, `) override {`, a constructor's initializer list); its length counts the
lines from its signature's last line (the opening brace) to its closing brace. Lambdas and blocks inside a function
count toward that function. Prints every violation (file:line name length) and exits 1 if there is one; --list N
also prints the N longest functions.
"""
import argparse
import pathlib
import re
import sys

FUNCTION_HEAD = re.compile(
    r"\)\s*(?:const\b|override\b|final\b|noexcept\b|mutable\b|->\s*[\w:<>,*&\s]+|\s)*$"
    r"|\)\s*:\s*[\w:]+\s*[({].*[)}]\s*$",
    re.S)
SCOPE_HEAD = re.compile(r"\b(namespace|class|struct|union|enum)\b[^()]*$", re.S)


def strip(text):
    """Blanks comments, string and character literals, keeping newlines (line numbers stay right)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + re.sub(r"[^\n]", " ", text[i + 1:j]) + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    """(name, first line, length) of every function body in a file."""
    text = strip(path.read_text())
    found, stack, head_start, line = [], [], 0, 1
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c in ";{}":
            if c == "{":
                head = text[head_start:i]
                inside_function = any(kind == "function" for kind, *_ in stack)
                if inside_function:
                    stack.append(("block", line, ""))
                elif SCOPE_HEAD.search(head.split("(")[0]) and "(" not in head.split("{")[0][-1:]:
                    stack.append(("scope", line, ""))
                elif FUNCTION_HEAD.search(head.strip()):
                    name = re.findall(r"([~\w]+(?:<[\w\s,]*>)?(?:::[~\w]+)*)\s*\(", head)
                    stack.append(("function", line, name[0] if name else "?"))
                else:
                    stack.append(("block", line, ""))
            elif c == "}" and stack:
                kind, start, name = stack.pop()
                if kind == "function":
                    found.append((name, start, line - start + 1))
            head_start = i + 1
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--max-file", type=int, default=600)
    ap.add_argument("--max-function", type=int, default=120)
    ap.add_argument("--list", type=int, default=0)
    a = ap.parse_args()
    bad, everything = [], []
    for d in a.dirs:
        for p in sorted(pathlib.Path(d).rglob("*")):
            if p.suffix not in (".cpp", ".hpp"):
                continue
            n = len(p.read_text().splitlines())
            if n > a.max_file:
                bad.append(f"{p}: {n} lines (file limit {a.max_file})")
            for name, start, length in functions(p):
                everything.append((length, f"{p}:{start} {name}"))
                if length > a.max_function:
                    bad.append(f"{p}:{start} {name}: {length} lines (function limit {a.max_function})")
    for length, where in sorted(everything, reverse=True)[:a.list]:
        print(f"{length:5d}  {where}")
    for b in bad:
        print(b)
    print(f"check_code_size: {len(everything)} functions, {len(bad)} over the limits")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
