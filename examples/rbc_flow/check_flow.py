#!/usr/bin/env python3
"""Shape of a red cell flowing through a tube (tube.toml; issue 28, seed 000 Sect. 4.4), from the cell's
vertices in cells.gsd, averaged over the frames from --start on.

Measures, with x the flow (and tube) axis, c the cell's centroid, s = x - c_x the axial position of a
vertex relative to it and rho its distance from the line through c along x:
  offset   the centroid's distance from the tube axis over the tube radius;
  depth    the mean s of the central vertices (rho < 0.35 rho_max) minus the mean s of the rim
           (rho > 0.85 rho_max), over the cell diameter D: 0 for a disc facing the flow (its two dimples
           are symmetric), > 0 when the centre leads and the rim trails (a parachute, concave at the rear);
  length   the cell's extent along x over D;
  tilt     the angle (degrees) between the flow axis and the direction of least extent (the disc's
           normal; the gyration tensor's smallest axis): 0 for a disc facing the flow, 90 for one whose
           plane holds the flow axis;
  bend     in the cross-section across the flow, how far the two ends of the cell's long direction sit
           from its middle, over D: 0 for a flat disc seen edge-on, about 0.1 for a croissant;
  wrong    the largest wrong_side count of cells.csv (fluid particles that crossed the membrane).
The shape is named by these numbers (thresholds ours, stated here and in README.md; the numbers are
printed): "parachute" where depth > 0.12, offset < 0.15 and tilt < 30 (an axisymmetric cup on the axis,
facing the flow); "croissant" where tilt >= 60, bend > 0.08 and offset < 0.15 (a disc along the flow,
bent across it, on the axis); "slipper" where the cell is off the axis (offset >= 0.15) and deformed
(depth or bend > 0.06); "tilted cup" where 30 <= tilt < 60 and depth > 0.06 (a parachute turning over);
"disc" where depth and bend are below 0.06; else "cup".

usage: check_flow.py OUT [OUT ...] [--start STEP | --start-fraction F] [--diameter D] [--radius R] [--axis Y Z]
                     [--rising METRIC RISE] [--min-depth X] [--picture FILE] [--labels L1 L2 ...]
  --start-fraction F  average from F times each run's last frame's step instead
  --rising METRIC RISE  the runs are in order of increasing flow: assert METRIC (depth, bend, length)
                  rises from the first run to the last by more than RISE, and no fluid particle crossed a
                  membrane in any run
  --min-depth X   assert the last run's depth exceeds X
  --picture FILE  side views (along y) and end views (along x) of each run's last frame
(/usr/bin/python3: Debian's python3-gsd, numpy and matplotlib)
"""
import argparse
import csv
import math
import sys

import gsd.hoomd
import numpy as np


def open_gsd(path):
    try:
        return gsd.hoomd.open(path, "r")
    except (ValueError, RuntimeError):  # gsd 2.x takes 'rb'
        return gsd.hoomd.open(path, "rb")


def whole(pos, box):
    """The vertices made whole across periodic faces, relative to the first vertex."""
    ref = pos[0]
    d = pos - ref
    for k in range(3):
        if box[k] > 0:
            d[:, k] -= box[k] * np.round(d[:, k] / box[k])
    return ref + d


def shape(pos, diameter, radius, axis_yz):
    c = pos.mean(axis=0)
    rel = pos - c
    s = rel[:, 0]
    rho = np.hypot(rel[:, 1], rel[:, 2])
    rmax = rho.max()
    centre, rim = s[rho < 0.35 * rmax], s[rho > 0.85 * rmax]
    depth = (centre.mean() - rim.mean()) / diameter if len(centre) and len(rim) else float("nan")
    gyr = rel.T @ rel / len(rel)
    w, v = np.linalg.eigh(gyr)
    normal = v[:, 0]
    tilt = math.degrees(math.acos(min(1.0, abs(normal[0]))))
    offset = math.hypot(c[1] - axis_yz[0], c[2] - axis_yz[1]) / radius
    # The bend across the flow: in the cross-section (y, z), the cell's long direction u and the one across
    # it, w; how far the two ends (|u| > 0.7 of the largest) sit from the middle (|u| < 0.3) along w.
    yz = rel[:, 1:]
    wy, vy = np.linalg.eigh(yz.T @ yz / len(yz))
    u, w = yz @ vy[:, 1], yz @ vy[:, 0]
    umax = np.abs(u).max()
    ends, middle = w[np.abs(u) > 0.7 * umax], w[np.abs(u) < 0.3 * umax]
    bend = abs(ends.mean() - middle.mean()) / diameter if len(ends) and len(middle) else float("nan")
    return {"offset": offset, "depth": depth, "length": (s.max() - s.min()) / diameter, "tilt": tilt, "bend": bend}


def name_of(m):
    if m["depth"] > 0.12 and m["offset"] < 0.15 and m["tilt"] < 30:
        return "parachute"
    if m["tilt"] >= 60 and m["bend"] > 0.08 and m["offset"] < 0.15:
        return "croissant"
    if m["offset"] >= 0.15 and max(m["depth"], m["bend"]) > 0.06:
        return "slipper"
    if 30 <= m["tilt"] < 60 and m["depth"] > 0.06:
        return "tilted cup"
    if m["depth"] < 0.06 and m["bend"] < 0.06:
        return "disc"
    return "cup"


def analyse(out, start, fraction, diameter, radius, axis_yz):
    t = open_gsd(f"{out}/cells.gsd")
    if fraction is not None:
        start = fraction * int(t[len(t) - 1].configuration.step)
    rows, last = [], None
    for f in t:
        if int(f.configuration.step) < start:
            continue
        box = np.array(f.configuration.box[:3], dtype=float)
        # GSD positions are relative to the box centre; the config's coordinates start at the lower corner.
        pos = whole(np.array(f.particles.position, dtype=float), box) + box / 2
        rows.append(shape(pos, diameter, radius, axis_yz))
        last = (pos, f.bonds.group.copy(), int(f.configuration.step))
    if not rows:
        sys.exit(f"{out}/cells.gsd: no frame at or after step {start}")
    with open(f"{out}/cells.csv") as fh:
        wrong = max(int(r["wrong_side"]) for r in csv.DictReader(fh))
    m = {k: float(np.mean([r[k] for r in rows])) for k in ("offset", "depth", "length", "tilt", "bend")}
    m["depth_err"] = float(np.std([r["depth"] for r in rows]) / math.sqrt(len(rows)))
    m["frames"] = len(rows)
    m["wrong"] = wrong
    m["name"] = name_of(m)
    return m, last


def faces_of(n, bonds):
    nb = [set() for _ in range(n)]
    for a, b in bonds:
        nb[a].add(b)
        nb[b].add(a)
    return [(a, b, w) for a, b in ((min(u, v), max(u, v)) for u, v in bonds) for w in nb[a] & nb[b] if w > b]


def picture(path, runs, labels, radius, axis_yz):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(3.2 * len(runs), 6.4))
    for k, ((m, (pos, bonds, step)), label) in enumerate(zip(runs, labels)):
        faces = faces_of(len(pos), bonds)
        c = pos.mean(axis=0)
        for row, (elev, azim, title) in enumerate(((0, -90, "side (flow ->)"), (0, 0, "from downstream"))):
            ax = fig.add_subplot(2, len(runs), row * len(runs) + k + 1, projection="3d")
            tri = [[pos[a] - [c[0], 0, 0], pos[b] - [c[0], 0, 0], pos[w] - [c[0], 0, 0]] for a, b, w in faces]
            ax.add_collection3d(Poly3DCollection(tri, facecolor="#c0392b", edgecolor="#5a1a12", linewidths=0.2,
                                                 alpha=0.9))
            if row == 0:  # the tube wall: its two lines in the side view, its circle seen from downstream
                for side in (-1, 1):
                    ax.plot([-6, 6], [axis_yz[0]] * 2, [axis_yz[1] + side * radius] * 2, color="0.4", lw=1.0)
            else:
                th = np.linspace(0, 2 * np.pi, 100)
                ax.plot(np.zeros_like(th), axis_yz[0] + radius * np.cos(th), axis_yz[1] + radius * np.sin(th),
                        color="0.4", lw=1.0)
            ax.set_xlim(-6, 6)
            ax.set_ylim(axis_yz[0] - 6, axis_yz[0] + 6)
            ax.set_zlim(axis_yz[1] - 6, axis_yz[1] + 6)
            ax.set_box_aspect((1, 1, 1))
            ax.view_init(elev=elev, azim=azim)
            ax.set_axis_off()
            if row == 0:
                ax.set_title(f"{label}: {m['name']}\ndepth {m['depth']:.2f}, bend {m['bend']:.2f}, tilt {m['tilt']:.0f} deg",
                             fontsize=9)
            else:
                ax.set_title(title, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"wrote {path}")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out", nargs="+")
    p.add_argument("--start", type=int, default=10000)
    p.add_argument("--start-fraction", type=float)
    p.add_argument("--diameter", type=float, default=8.0)
    p.add_argument("--radius", type=float, default=5.125)
    p.add_argument("--axis", type=float, nargs=2, default=[6.625, 6.625])
    p.add_argument("--rising", nargs=2, metavar=("METRIC", "RISE"))
    p.add_argument("--min-depth", type=float)
    p.add_argument("--picture")
    p.add_argument("--labels", nargs="+")
    a = p.parse_args()
    runs = [analyse(o, a.start, a.start_fraction, a.diameter, a.radius, a.axis) for o in a.out]
    print("run | frames | offset / R | depth / D | bend / D | length / D | tilt (deg) | wrong side | shape")
    for o, (m, _) in zip(a.out, runs):
        print(f"{o} | {m['frames']} | {m['offset']:.3f} | {m['depth']:.3f} +- {m['depth_err']:.3f} | {m['bend']:.3f} | "
              f"{m['length']:.3f} | {m['tilt']:.1f} | {m['wrong']} | {m['name']}")
    if a.picture:
        picture(a.picture, runs, a.labels or a.out, a.radius, a.axis)
    failed = []
    if a.rising:
        metric, rise = a.rising[0], float(a.rising[1])
        d0, d1 = runs[0][0][metric], runs[-1][0][metric]
        if not d1 > d0 + rise:
            failed.append(f"{metric} does not rise with the flow: {d0:.3f} -> {d1:.3f} (want a rise > {rise})")
        for o, (m, _) in zip(a.out, runs):
            if m["wrong"] != 0:
                failed.append(f"{o}: {m['wrong']} fluid particles on the wrong side of the membrane")
    if a.min_depth is not None and not runs[-1][0]["depth"] > a.min_depth:
        failed.append(f"{a.out[-1]}: depth {runs[-1][0]['depth']:.3f} not above {a.min_depth}")
    for f in failed:
        print("FAIL:", f)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
