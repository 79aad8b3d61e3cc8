#!/usr/bin/env python3
"""Rewrites the key tables of docs/config.md from the keys the code declares (`mesodpd keys`).

Each generated table in docs/config.md follows a line `<!-- keys: PATH -->`; everything else on the
page is prose and is left alone. The test ConfigDocs.KeyTablesMatchTheDeclarations fails while the
page and the declarations differ.

Usage: tools/update_config_docs.py [--mesodpd build/mesodpd] [--docs docs/config.md]
"""
import argparse
import pathlib
import re
import subprocess
import sys

MARK = re.compile(r"^<!-- keys: (\S+) -->$")


def declared(mesodpd):
    text = subprocess.run([mesodpd, "keys"], check=True, capture_output=True, text=True).stdout
    tables, path = {}, None
    for line in text.splitlines():
        m = MARK.match(line)
        if m:
            path = m.group(1)
            tables[path] = []
        elif line.startswith("|") and path:
            tables[path].append(line)
    return tables


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--docs", default="docs/config.md")
    args = ap.parse_args()
    tables = declared(args.mesodpd)
    lines = pathlib.Path(args.docs).read_text(encoding="utf-8").splitlines()
    out, k, seen = [], 0, set()
    while k < len(lines):
        out.append(lines[k])
        m = MARK.match(lines[k])
        k += 1
        if not m:
            continue
        path = m.group(1)
        if path not in tables:
            sys.exit(f"{args.docs}: marker for '{path}', which the code does not declare")
        seen.add(path)
        while k < len(lines) and lines[k].startswith("|"):
            k += 1
        out.extend(tables[path])
    missing = sorted(set(tables) - seen)
    if missing:
        sys.exit(f"{args.docs}: no '<!-- keys: PATH -->' marker for {', '.join(missing)}; add one where the table belongs")
    pathlib.Path(args.docs).write_text("\n".join(out) + "\n", encoding="utf-8")
    print(f"{args.docs}: {len(seen)} key tables written")


if __name__ == "__main__":
    main()
