#!/usr/bin/env python3
"""Draws the cells of a [[membrane]] run from its cells.gsd (the vertices of every cell at each output
step, the edges as bonds): one panel per chosen frame, each cell its own colour, the triangles filled.

The GSD "hoomd" schema has no faces, so the triangles are found again as the 3-cycles of the edge graph;
a closed cell of V vertices has 2 V - 4 of them, which is checked (a mesh with a triangle of edges that is
not a face would fail it, and is then drawn as edges only, with a warning).

usage: render_cells.py OUT/cells.gsd [--frames 0 -1] [--out cells.png] [--view ELEV AZIM] [--title TEXT]
(/usr/bin/python3: Debian's python3-gsd and python3-matplotlib)
"""
import argparse
import sys
from collections import defaultdict

import gsd.hoomd
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection, Line3DCollection  # noqa: E402


def open_gsd(path):
    """gsd 2.x takes mode 'rb', gsd 3.x 'r'."""
    try:
        return gsd.hoomd.open(path, "r")
    except (ValueError, RuntimeError):
        return gsd.hoomd.open(path, "rb")


def cells_and_faces(n, bonds):
    """Connected components of the edge graph (the cells, by row) and each one's triangles (3-cycles)."""
    nb = defaultdict(set)
    for a, b in bonds:
        nb[a].add(b)
        nb[b].add(a)
    label = -np.ones(n, dtype=int)
    cells = []
    for start in range(n):
        if label[start] >= 0 or start not in nb:
            continue
        stack, members = [start], []
        label[start] = len(cells)
        while stack:
            u = stack.pop()
            members.append(u)
            for w in nb[u]:
                if label[w] < 0:
                    label[w] = len(cells)
                    stack.append(w)
        cells.append(sorted(members))
    faces = [[] for _ in cells]
    for u, v in bonds:
        a, b = min(u, v), max(u, v)
        for w in nb[a] & nb[b]:
            if w > b:
                faces[label[a]].append((a, b, w))
    return cells, faces


def main():
    p = argparse.ArgumentParser()
    p.add_argument("gsd")
    p.add_argument("--frames", type=int, nargs="+", default=[-1])
    p.add_argument("--out", default="cells.png")
    p.add_argument("--view", type=float, nargs=2, default=[25.0, -60.0])
    p.add_argument("--title", default="")
    a = p.parse_args()
    traj = open_gsd(a.gsd)
    if len(traj) == 0:
        sys.exit(f"{a.gsd}: no frames")
    first = traj[0]
    bonds = np.asarray(first.bonds.group, dtype=int)
    if len(bonds) == 0:
        sys.exit(f"{a.gsd}: no edges (bonds) in the first frame: not a cells.gsd")
    cells, faces = cells_and_faces(first.particles.N, bonds)
    closed = all(len(f) == 2 * len(c) - 4 for c, f in zip(cells, faces))
    if not closed:
        print("warning: some cell's 3-cycles are not its 2 V - 4 faces; drawing the edges only", file=sys.stderr)
    colours = plt.get_cmap("tab10")
    fig = plt.figure(figsize=(5.0 * len(a.frames), 5.0))
    frames, positions = [traj[i] for i in a.frames], []
    for frame in frames:
        box = np.asarray(frame.configuration.box[:3], dtype=float)
        pos = np.asarray(frame.particles.position, dtype=float) + box / 2  # HOOMD's box is centred on 0
        if frame.particles.image is not None and len(frame.particles.image) == len(pos):
            pos = pos + np.asarray(frame.particles.image, dtype=float) * box
        positions.append(pos)
    # One scale for every panel, so that the sizes compare.
    half = max((pos.max(axis=0) - pos.min(axis=0)).max() for pos in positions) / 2
    for k, (frame, pos) in enumerate(zip(frames, positions)):
        ax = fig.add_subplot(1, len(a.frames), k + 1, projection="3d")
        lo, hi = pos.min(axis=0), pos.max(axis=0)
        for c, (members, tris) in enumerate(zip(cells, faces)):
            colour = colours(c % 10)
            if closed:
                poly = Poly3DCollection([pos[list(t)] for t in tris], facecolor=colour, edgecolor="k",
                                        linewidths=0.1, alpha=0.85)
                ax.add_collection3d(poly)
            else:
                segs = [pos[[u, v]] for u, v in bonds if u in set(members)]
                ax.add_collection3d(Line3DCollection(segs, colors=[colour], linewidths=0.3))
        centre = (lo + hi) / 2
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
        ax.set_zlim(centre[2] - half, centre[2] + half)
        ax.set_box_aspect((1, 1, 1))
        ax.view_init(*a.view)
        ax.set_xlabel("x")
        ax.set_ylabel("y")
        ax.set_zlabel("z")
        ax.set_title(f"step {frame.configuration.step}")
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"{a.out}: {len(cells)} cells, frames {a.frames} of {len(traj)}")


if __name__ == "__main__":
    main()
