#!/usr/bin/python3
"""Contact angle of a cylindrical many-body DPD drop against the solid-liquid attraction A_SL.

    /usr/bin/python3 examples/wetting/run.py [--mesodpd build/mesodpd] [--out out/wetting]
                                             [--asl -40 -35 -30 -25 -20 -15] [--jobs 1] [--analyse-only]

For every A_SL: wetting.toml with the [[pair.override]] a of the liquid-wall pair set to A_SL runs in
--out/asl<A_SL>/ on one thread. Its four density maps (started at the beginnings of four equal
blocks of the production run) give the map of each block by differences of running means; the contact
angle (contact_angle.py: circle fitted to the half-density contour above the wall's first liquid
layer, angle where it meets the wall plane z = 2) is measured on the whole average and on each block,
whose spread gives the error bar. Writes results.json, theta.png (theta against A_SL) and
profiles.png (the maps with their contours and circles) in --out. check.py judges results.json.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(ROOT, "tools"))
from contact_angle import contact_angle, read_map  # noqa: E402
from sweep import add_run_args, run_all, run_config  # noqa: E402

GRIDS = ["map", "from_15000", "from_20000", "from_25000"]  # nested: each starts one block later
WALL = 2.0
SKIP = 1.0


def run_one(args, asl):
    text = open(os.path.join(HERE, "wetting.toml")).read()
    old = "a = -20.0                     # A_SL: the solid-liquid attraction"
    assert old in text
    text = text.replace(old, f"a = {asl:g}  # A_SL: the solid-liquid attraction")
    run_config(args.mesodpd, text, os.path.join(args.out, f"asl{asl:g}"), "wetting.toml")


def block_maps(d):
    """The maps of the four blocks: block k = (n_k mean_k - n_{k+1} mean_{k+1}) / (n_k - n_{k+1})."""
    maps, counts = [], []
    for g in GRIDS:
        x, z, rho = read_map(os.path.join(d, f"{g}.csv"))
        maps.append(rho)
        counts.append(json.load(open(os.path.join(d, f"{g}.json")))["samples"])
    blocks = []
    for k in range(len(GRIDS)):
        if k + 1 < len(GRIDS):
            blocks.append((counts[k] * maps[k] - counts[k + 1] * maps[k + 1]) / (counts[k] - counts[k + 1]))
        else:
            blocks.append(maps[k])
    return x, z, maps[0], blocks


def analyse(d, asl):
    x, z, rho, blocks = block_maps(d)
    whole, pts, used = contact_angle(x, z, rho, WALL, SKIP)
    thetas = [contact_angle(x, z, b, WALL, SKIP)[0]["theta"] for b in blocks]
    good = [t for t in thetas if t == t]
    err = float(np.std(good, ddof=1) / math.sqrt(len(good))) if len(good) >= 2 else float("nan")
    # A liquid layer on the wall far from the drop (the map is centred on it: the box edges along x) is a
    # precursor film: the liquid wets the wall completely and the "angle" is that of a drop still
    # spreading, not a static contact angle.
    near = (z > WALL) & (z < WALL + 0.75)
    edges = (x < x[0] + 2.0) | (x > x[-1] - 2.0)
    film = float(rho[np.ix_(near, edges)].mean()) / whole["rho_l"]
    res = {"a_sl": asl, "theta": whole["theta"], "theta_err": err, "theta_blocks": thetas,
           "film": film, "complete_wetting": film > 0.1}
    res.update({k: v for k, v in whole.items() if k != "theta"})
    return res, (x, z, rho, pts, used)


def plot(results, maps, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 4))
    static = [r for r in results if not r["complete_wetting"]]
    ax.errorbar([r["a_sl"] for r in static], [r["theta"] for r in static], yerr=[r["theta_err"] for r in static],
                fmt="o-", capsize=3, label="static contact angle")
    film = [r for r in results if r["complete_wetting"]]
    if film:
        ax.plot([r["a_sl"] for r in film], [0 for r in film], "v", color="C3",
                label="complete wetting (precursor film)")
    ax.legend(fontsize=8)
    ax.axhline(90, color="grey", lw=0.5)
    ax.set_xlabel(r"solid-liquid attraction $A_{SL}$ ($A_{LL} = -40$, $B = 25$)")
    ax.set_ylabel(r"contact angle $\theta$ (degrees)")
    ax.set_ylim(0, 180)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "theta.png"), dpi=120)
    n = len(maps)
    fig, axes = plt.subplots(n, 1, figsize=(8, 2.2 * n), squeeze=False)
    for ax, r, (x, z, rho, pts, used) in zip(axes[:, 0], results, maps):
        ax.pcolormesh(x, z, rho, shading="nearest", cmap="viridis", vmin=0, vmax=8)
        if len(pts):
            ax.plot(pts[:, 0], pts[:, 1], "w-", lw=0.8)
        if r["theta"] == r["theta"]:
            t = np.linspace(0, 2 * np.pi, 200)
            ax.plot(r["xc"] + r["radius"] * np.cos(t), r["zc"] + r["radius"] * np.sin(t), "r--", lw=0.8)
        ax.axhline(WALL, color="w", lw=1)
        ax.set_xlim(x[0] - 0.125, x[-1] + 0.125)
        ax.set_ylim(0, z[-1] + 0.125)
        ax.set_aspect("equal")
        ax.set_title(f"A_SL = {r['a_sl']:g}: theta = {r['theta']:.1f} +- {r['theta_err']:.1f} deg", fontsize=9)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "profiles.png"), dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_run_args(ap, ROOT, "wetting")
    ap.add_argument("--asl", type=float, nargs="+", default=[-40, -35, -30, -25, -20, -15])
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if not args.analyse_only:
        run_all(lambda a: run_one(args, a), args.asl, args.jobs)
    results, maps = [], []
    for a in args.asl:
        r, m = analyse(os.path.join(args.out, f"asl{a:g}"), a)
        results.append(r)
        maps.append(m)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    print(f"{'A_SL':>6} {'theta (deg)':>16} {'R':>6} {'base':>6} {'height':>6} {'rho_l':>6} {'film':>6}  blocks")
    for r in results:
        print(f"{r['a_sl']:6g} {r['theta']:7.1f} +- {r['theta_err']:5.1f} {r.get('radius', float('nan')):6.2f} "
              f"{r.get('base_width', float('nan')):6.2f} {r.get('height', float('nan')):6.2f} {r['rho_l']:6.3f} "
              f"{r['film']:6.3f}  {' '.join(f'{t:.1f}' for t in r['theta_blocks'])}"
              + ("  (precursor film: complete wetting, still spreading)" if r["complete_wetting"] else ""))
    plot(results, maps, args.out)
    print(f"wrote {args.out}/results.json, theta.png, profiles.png")


if __name__ == "__main__":
    sys.exit(main())
