#!/usr/bin/python3
"""Liu's droplet phases with the spline potential U = 18.75 [2 W(r, 0.8) - B W(r, 1.0)] (seed 000
Figs. 14-19): for each B, run liu.toml with pair.attraction = B, find the clusters of the last frames,
and report the number of drops, the liquid and gas densities and their ratio, with a snapshot per B.

    /usr/bin/python3 examples/spline_droplet/run.py [--mesodpd build/mesodpd] [--out out/spline_droplet]
                                                    [--steps 20000] [--b 0 0.9 1.0 1.05 1.1] [--threads 1]

Liquid particles have at least 15 others within r < 1 (local density > 3.6; the uniform start has 1.5);
a drop is a connected set (link 1.0) of at least 30 liquid particles; every other particle is gas.
Liquid density: mean local density of the densest half of the drop particles (the interior); gas
density: gas particles over the volume outside the drops (drop particles / liquid density). Written: results.json, snapshot_B<B>.png; a table on stdout.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def last_frames(path, count):
    """The last `count` frames of a LAMMPS dump with columns id x y z: (box lengths, positions)."""
    with open(path) as f:
        text = f.read()
    frames = []
    for block in text.split("ITEM: TIMESTEP")[1:]:
        lines = block.strip().split("\n")
        n = int(lines[2])
        lens = np.array([float(lines[4 + d].split()[1]) - float(lines[4 + d].split()[0]) for d in range(3)])
        data = np.array([[float(v) for v in line.split()] for line in lines[8:8 + n]])
        frames.append((lens, data[:, 1:4]))
    return frames[-count:]


def neighbours(pos, lens, cut):
    """Pairs (i, j), i < j, closer than `cut` (periodic minimum image), by a cell list."""
    ncell = np.maximum((lens // cut).astype(int), 1)
    cell = (np.floor(pos / lens * ncell).astype(int)) % ncell
    key = (cell[:, 0] * ncell[1] + cell[:, 1]) * ncell[2] + cell[:, 2]
    order = np.argsort(key)
    pairs_i, pairs_j = [], []
    buckets = {}
    for idx in order:
        buckets.setdefault(int(key[idx]), []).append(idx)
    for k, members in buckets.items():
        c = np.array([k // (ncell[1] * ncell[2]), (k // ncell[2]) % ncell[1], k % ncell[2]])
        others = set()
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    cc = (c + (dx, dy, dz)) % ncell
                    others.update(buckets.get(int((cc[0] * ncell[1] + cc[1]) * ncell[2] + cc[2]), ()))
        a = np.array(members)
        b = np.array(sorted(others))
        d = pos[a][:, None, :] - pos[b][None, :, :]
        d -= lens * np.round(d / lens)
        close = (d * d).sum(-1) < cut * cut
        ii, jj = np.nonzero(close)
        keep = a[ii] < b[jj]
        pairs_i.append(a[ii][keep])
        pairs_j.append(b[jj][keep])
    return np.concatenate(pairs_i), np.concatenate(pairs_j)


def analyse(frames):
    """Liquid particles: at least 15 others within r < 1 (local density > 3.6, against 1.5 of the
    uniform start); drops: connected liquid particles (link 1.0) with at least 30 members."""
    out = {"drops": [], "rho_liquid": [], "rho_gas": [], "liquid_fraction": []}
    for lens, pos in frames:
        n = len(pos)
        i, j = neighbours(pos, lens, 1.0)
        count = np.bincount(i, minlength=n) + np.bincount(j, minlength=n)
        liquid = count >= 15
        parent = np.arange(n)

        def find(k):
            while parent[k] != k:
                parent[k] = parent[parent[k]]
                k = parent[k]
            return k

        for a, b in zip(i, j):
            if liquid[a] and liquid[b]:
                ra, rb = find(a), find(b)
                if ra != rb:
                    parent[ra] = rb
        labels = np.array([find(k) if liquid[k] else -1 for k in range(n)])
        roots, inverse, sizes = np.unique(labels, return_inverse=True, return_counts=True)
        drops = [k for k in range(len(roots)) if roots[k] >= 0 and sizes[k] >= 30]
        local = count / (4.0 / 3.0 * math.pi)
        in_drop = np.isin(inverse, drops)
        # The liquid density: the densest half of the drop particles (the interior, not the surface).
        dens = np.sort(local[in_drop])
        rho_l = float(dens[len(dens) // 2:].mean()) if len(dens) >= 2 else float("nan")
        volume = float(np.prod(lens))
        liquid_volume = in_drop.sum() / rho_l if rho_l == rho_l else 0.0
        gas = int((~in_drop).sum())
        out["drops"].append(len(drops))
        out["rho_liquid"].append(rho_l)
        out["rho_gas"].append(gas / max(volume - liquid_volume, 1e-9))
        out["liquid_fraction"].append(float(in_drop.mean()))
    sizes_of = np.where(np.isin(inverse, drops), 1000, 1)  # for the snapshot: drop particles vs gas
    return out, labels, np.where(np.isin(inverse, drops), inverse, -1), sizes_of


def snapshot(path, lens, pos, inverse, sizes, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(4.8, 4.8))
    ax = fig.add_subplot(projection="3d")
    drop = inverse >= 0
    ax.scatter(*pos[~drop].T, s=2, c="#999999", alpha=0.5, depthshade=False)
    ax.scatter(*pos[drop].T, s=4, c=inverse[drop] % 10, cmap="tab10", vmin=0, vmax=9, depthshade=True)
    for d, name in enumerate("xyz"):
        getattr(ax, f"set_{name}lim")(0, lens[d])
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "spline_droplet"))
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("--b", type=float, nargs="+", default=[0.0, 0.9, 1.0, 1.05, 1.1])
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--frames", type=int, default=3, help="last dump frames analysed")
    ap.add_argument("--analyse-only", action="store_true")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(HERE, "liu.toml")) as f:
        template = f.read()
    results = {}
    for b in args.b:
        name = f"B{b:g}"
        cfg = os.path.join(args.out, name + ".toml")
        with open(cfg, "w") as f:
            f.write(re.sub(r"(?m)^attraction = [0-9.]+", f"attraction = {b}", template))
        if not args.analyse_only:
            cmd = [args.mesodpd, "run", cfg, "--out", os.path.join(args.out, name), "--threads", str(args.threads)]
            if args.steps:
                cmd += ["--steps", str(args.steps)]
            print("running:", " ".join(cmd), flush=True)
            r = subprocess.run(cmd, capture_output=True, text=True)
            sys.stdout.write(r.stdout[-600:])
            if r.returncode != 0:
                sys.stderr.write(r.stderr)
                return 1
        frames = last_frames(os.path.join(args.out, name, "trajectory.lammpstrj"), args.frames)
        res, labels, inverse, sizes = analyse(frames)
        thermo = np.genfromtxt(os.path.join(args.out, name, "thermo.csv"), delimiter=",", names=True)
        rho_l, rho_g = np.nanmean(res["rho_liquid"]), float(np.mean(res["rho_gas"]))
        results[name] = {
            "B": b, "drops": res["drops"], "rho_liquid": None if math.isnan(rho_l) else float(rho_l),
            "rho_gas": rho_g, "ratio": None if math.isnan(rho_l) or rho_g == 0 else float(rho_l / rho_g),
            "liquid_fraction": float(np.mean(res["liquid_fraction"])), "steps": int(thermo["step"][-1]),
            "temperature_late": float(thermo["temperature"][len(thermo) // 2:].mean()),
        }
        snapshot(os.path.join(args.out, f"snapshot_{name}.png"), frames[-1][0], frames[-1][1], inverse, sizes,
                 f"B = {b:g}, step {results[name]['steps']}: {res['drops'][-1]} drop(s)")
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=2)
    print(f"\n{'B':>5} {'drops (last frames)':>20} {'rho_liquid':>10} {'rho_gas':>9} {'ratio':>8} {'T':>6}")
    for r in results.values():
        rl = f"{r['rho_liquid']:.3f}" if r["rho_liquid"] is not None else "-"
        ratio = f"{r['ratio']:.0f}" if r["ratio"] is not None else ("inf" if r["rho_liquid"] else "-")
        print(f"{r['B']:5g} {str(r['drops']):>20} {rl:>10} {r['rho_gas']:9.4f} {ratio:>8} {r['temperature_late']:6.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
