#!/usr/bin/env python3
"""Checks a cells.gsd: its frames are at exactly the given steps and, when asked, every frame's first
has the given numbers of vertices (particles) and edges (bonds).

usage: check_cells_gsd.py FILE --steps S1 S2 ... [--vertices N] [--edges M]   (/usr/bin/python3, python3-gsd)
"""
import argparse
import sys

import gsd.hoomd


def main():
    p = argparse.ArgumentParser()
    p.add_argument("file")
    p.add_argument("--steps", type=int, nargs="+", required=True)
    p.add_argument("--vertices", type=int)
    p.add_argument("--edges", type=int)
    a = p.parse_args()
    try:
        t = gsd.hoomd.open(a.file, "r")
    except (ValueError, RuntimeError):  # gsd 2.x takes 'rb'
        t = gsd.hoomd.open(a.file, "rb")
    steps = [int(f.configuration.step) for f in t]
    print(f"{a.file}: steps {steps}, {t[0].particles.N} vertices, {t[0].bonds.N} edges")
    if steps != a.steps:
        sys.exit(f"expected frames at steps {a.steps}")
    if a.vertices is not None and t[0].particles.N != a.vertices:
        sys.exit(f"expected {a.vertices} vertices")
    if a.edges is not None and t[0].bonds.N != a.edges:
        sys.exit(f"expected {a.edges} edges")


if __name__ == "__main__":
    main()
