#!/usr/bin/env python3
"""Generates the C++ table behind `aries -help` from docs/options.md (the one source of the option documentation):
every row of a table whose header is `| option | default | meaning |`, with the section heading above it, and the
output-field table (the energies are printed from the energy registry, lib/energies/registry.hpp). Usage:
options_help.py docs/options.md OUT.cpp. The rows are written as they read in the docs, without markdown."""
import re
import sys


def plain(text):
    text = text.replace("\\|", "|").replace("`", "").replace("**", "")
    return re.sub(r"\s+", " ", text).strip()


def rows(md):
    """(section, usage, default, meaning) for every option row, plus the value tables of -energy (energy | shapes |
    definition) and -output_fields (field | on | components | meaning) as their own sections."""
    section, table = "", None
    for line in md.splitlines():
        if line.startswith("#"):
            section, table = line.lstrip("#").strip(), None
            continue
        if not line.startswith("|"):
            table = None
            continue
        cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]
        if cells and cells[0] in ("option", "energy", "field"):
            table = cells[0]
            continue
        if not cells or cells[0].startswith("---") or set(cells[0]) <= {"-"}:
            continue
        if table == "option" and len(cells) == 3 and cells[0].startswith("`-"):
            yield section, plain(cells[0]), plain(cells[1]), plain(cells[2])
        elif table == "energy" and len(cells) == 3:
            yield "Energies (-energy NAME)", plain(cells[0]), plain(cells[1]), plain(cells[2])
        elif table == "field" and len(cells) == 4:
            yield ("Output fields (-output_fields)", plain(cells[0]), "%s, %s components" % (plain(cells[1]),
                   plain(cells[2])), plain(cells[3]))


def cstr(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def main():
    src, dst = sys.argv[1], sys.argv[2]
    with open(src, encoding="utf-8") as fh:
        table = [r for r in rows(fh.read()) if not r[0].startswith("Energies")]
    if not table:
        sys.exit("options_help.py: no option rows found in %s" % src)
    out = ["// Generated from docs/options.md by cmake/options_help.py: do not edit.",
           '#include "io/options_help.hpp"', "", "namespace aries::io {", "",
           "const OptionHelp kOptionHelp[] = {"]
    for section, usage, default, meaning in table:
        out.append("    {%s, %s, %s, %s}," % (cstr(section), cstr(usage), cstr(default), cstr(meaning)))
    out += ["};", "const int kOptionHelpCount = %d;" % len(table), "", "}  // namespace aries::io", ""]
    text = "\n".join(out)
    try:
        with open(dst, encoding="utf-8") as fh:
            if fh.read() == text:
                return
    except OSError:
        pass
    with open(dst, "w", encoding="utf-8") as fh:
        fh.write(text)


if __name__ == "__main__":
    main()
