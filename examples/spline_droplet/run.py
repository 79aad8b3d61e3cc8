#!/usr/bin/python3
"""Liu's droplet phases with the spline potential U = 18.75 [2 W(r, 0.8) - B W(r, 1.0)] (seed 000
Figs. 14-19): for each B, run liu.toml with pair.attraction = B, find the drops in every dump frame,
and report the number of drops, the liquid and gas densities and their ratio, with a snapshot per B.

    /usr/bin/python3 examples/spline_droplet/run.py [--mesodpd build/mesodpd] [--out out/spline_droplet]
                     [--steps 20000] [--b 0 0.9 1.0 1.05 1.1] [--average-from 10000] [--analyse-only]

Per frame (dumps every 500 steps): liquid-like particles have at least 15 others within r < 1 (local
density > 3.6; the uniform start has 1.5); a drop is a connected set (link 1.0) of at least 30 of them.
Liquid density: particles within half the equimolar radius of the largest drop's centre, over that
sphere's volume. Gas density: particles farther than --shell (2.0) from every drop particle, over the
volume of the box farther than --shell from every drop particle (measured on a 64^3 grid of points);
with no drop, all particles over the box. Means and errors are over the frames from --average-from
on, in 5 blocks of consecutive frames (error = standard deviation of the block means / sqrt(5)).
Written per B: series.csv (step, drops, largest drop, liquid and gas densities); and results.json,
gas_density.png, snapshot_B<B>.png (drops coloured, gas grey) and snapshots.png (all B in one); a table
on stdout.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def frames(path):
    """Every frame of a LAMMPS text dump with columns id x y z: (step, box lengths, positions by id)."""
    with open(path) as f:
        text = f.read()
    out = []
    for chunk in text.split("ITEM: TIMESTEP")[1:]:
        lines = chunk.strip().split("\n")
        n = int(lines[2])
        lens = np.array([float(lines[4 + d].split()[1]) - float(lines[4 + d].split()[0]) for d in range(3)])
        data = np.array([[float(v) for v in line.split()] for line in lines[8:8 + n]])
        data = data[np.argsort(data[:, 0])]
        out.append((int(lines[0]), lens, np.mod(data[:, 1:4], lens)))
    return out


def periodic_centre(pos, lens):
    """Centre of a compact group in a periodic box (mean angle per axis)."""
    ang = pos / lens * 2 * math.pi
    return np.mod(np.arctan2(np.sin(ang).mean(0), np.cos(ang).mean(0)) / (2 * math.pi) * lens, lens)


def analyse_frame(lens, pos, shell, grid_points=64):
    """Drops (labels per particle, -1 for none), liquid and gas densities of one frame."""
    n = len(pos)
    tree = cKDTree(pos, boxsize=lens)
    pairs = tree.query_pairs(1.0, output_type="ndarray")
    count = np.bincount(pairs[:, 0], minlength=n) + np.bincount(pairs[:, 1], minlength=n)
    liquid = count >= 15
    link = pairs[liquid[pairs[:, 0]] & liquid[pairs[:, 1]]]
    graph = coo_matrix((np.ones(len(link)), (link[:, 0], link[:, 1])), shape=(n, n))
    roots = np.where(liquid, connected_components(graph, directed=False)[1], -1)
    ids, inverse, sizes = np.unique(roots, return_inverse=True, return_counts=True)
    drop_ids = [k for k in range(len(ids)) if ids[k] >= 0 and sizes[k] >= 30]
    labels = np.full(n, -1)
    for rank, k in enumerate(sorted(drop_ids, key=lambda k: -sizes[k])):
        labels[inverse == k] = rank
    volume = float(np.prod(lens))
    if not drop_ids:
        return labels, float("nan"), n / volume, n
    # Liquid density: inside half the equimolar radius of the largest drop (two passes for R).
    members = pos[labels == 0]
    centre = periodic_centre(members, lens)
    d = pos - centre
    d -= lens * np.round(d / lens)
    r = np.sqrt((d * d).sum(1))
    rho_l = len(members) / (4 / 3 * math.pi * np.percentile(r[labels == 0], 90) ** 3)
    for _ in range(2):
        radius = (3 * len(members) / (4 * math.pi * rho_l)) ** (1 / 3)
        r_in = 0.5 * radius
        rho_l = float((r < r_in).sum() / (4 / 3 * math.pi * r_in ** 3))
    # Gas: farther than `shell` from every drop particle, particles and volume alike.
    drop_tree = cKDTree(pos[labels >= 0], boxsize=lens)
    far_particles = drop_tree.query(pos, distance_upper_bound=shell)[0] == np.inf
    g = (np.arange(grid_points) + 0.5) / grid_points
    pts = np.stack(np.meshgrid(g * lens[0], g * lens[1], g * lens[2], indexing="ij"), -1).reshape(-1, 3)
    far_volume = float((drop_tree.query(pts, distance_upper_bound=shell)[0] == np.inf).mean()) * volume
    rho_g = float(far_particles.sum()) / far_volume if far_volume > 0 else float("nan")
    return labels, rho_l, rho_g, int(far_particles.sum())


def block(x, blocks=5):
    x = np.asarray(x, dtype=float)
    per = len(x) // blocks
    if per == 0:
        return float(np.mean(x)), float("nan")
    m = x[len(x) - per * blocks:].reshape(blocks, per).mean(axis=1)
    return float(m.mean()), float(m.std(ddof=1) / math.sqrt(blocks))


def draw_snapshot(ax, lens, pos, labels, title):
    if (labels == 0).any():  # the largest drop in the middle of the picture, not cut by the boundary
        pos = np.mod(pos + lens / 2 - periodic_centre(pos[labels == 0], lens), lens)
    gas = labels < 0
    ax.scatter(*pos[gas].T, s=2, c="#999999", alpha=0.5, depthshade=False)
    ax.scatter(*pos[~gas].T, s=3, c=labels[~gas] % 10, cmap="tab10", vmin=0, vmax=9, depthshade=True)
    for d, name in enumerate("xyz"):
        getattr(ax, f"set_{name}lim")(0, lens[d])
        getattr(ax, f"set_{name}ticks")([0, lens[d] / 2, lens[d]])
    ax.set_title(title, fontsize=8)


def laplace(args):
    """Continue B1/ (the B = 1.0 run) from its checkpoint for --laplace steps with [analysis.droplet]: the
    drop's inside and outside densities and pressures, Delta P and sigma = Delta P R / 2. Kelvin's
    equation for an incompressible liquid and an ideal vapour, kT ln(rho_g(R) / rho_g(inf)) = Delta P /
    rho_l, then gives the gas density over a flat interface, rho_g(inf) = rho_g(R) exp(-Delta P / (rho_l kT)).
    """
    src = os.path.join(args.out, "B1")
    with open(src + ".toml") as f:
        text = f.read()
    done = int(np.genfromtxt(os.path.join(src, "thermo.csv"), delimiter=",", names=True)["step"][-1])
    text = re.sub(r"(?m)^steps = .*", f"steps = {done + args.laplace}", text)
    text = re.sub(r"(?ms)^\[output\.dump\].*", "", text)
    text += (f"\n[analysis.droplet]\nstart = {done}\nevery = 50\ninner_radius = 1.5\nouter_radius = 5.5\n"
             "bin_width = 0.25\nblocks = 10\n")
    cfg = os.path.join(args.out, "B1_laplace.toml")
    with open(cfg, "w") as f:
        f.write(text)
    out = os.path.join(args.out, "B1_laplace")
    cmd = [args.mesodpd, "run", cfg, "--restart", os.path.join(src, "checkpoint.mdpd"), "--out", out,
           "--threads", str(args.threads)]
    print("running:", " ".join(cmd), flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stderr)
        return 1
    with open(os.path.join(out, "droplet.json")) as f:
        d = json.load(f)
    kT = float(re.search(r"(?m)^kT = ([0-9.]+)", text).group(1))
    flat = d["rho_out"] * math.exp(-d["delta_p"] / (d["rho_in"] * kT))
    print(f"steps {done}..{done + args.laplace}: R = {d['radius']:.3f}, rho_in = {d['rho_in']:.3f} +- {d['rho_in_err']:.3f}, "
          f"rho_out = {d['rho_out']:.5f} +- {d['rho_out_err']:.5f} (ratio {d['rho_in'] / d['rho_out']:.0f}), "
          f"p_in = {d['p_in']:.3f} +- {d['p_in_err']:.3f}, p_out = {d['p_out']:.5f} +- {d['p_out_err']:.5f}, "
          f"Delta P = {d['delta_p']:.3f} +- {d['delta_p_err']:.3f}, sigma = Delta P R / 2 = {d['sigma_laplace']:.3f}")
    print(f"Kelvin: flat-interface gas density rho_g(inf) = rho_out exp(-Delta P / (rho_in kT)) = {flat:.5f}, "
          f"ratio rho_in / rho_g(inf) = {d['rho_in'] / flat:.0f}")
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "spline_droplet"))
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--dt", type=float, default=None, help="integrator.dt (liu.toml: 0.01)")
    ap.add_argument("--b", type=float, nargs="+", default=[0.0, 0.9, 1.0, 1.05, 1.1])
    ap.add_argument("--average-from", type=int, default=10000, help="first step of the averages")
    ap.add_argument("--shell", type=float, default=2.0, help="gas: farther than this from every drop particle")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--analyse-only", action="store_true")
    ap.add_argument("--laplace", type=int, default=0, metavar="STEPS",
                    help="continue the B = 1 run STEPS steps with [analysis.droplet] (Kelvin estimate), then stop")
    args = ap.parse_args()
    if args.laplace:
        return laplace(args)
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(HERE, "liu.toml")) as f:
        template = f.read()
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    results, last = {}, {}
    for b in args.b:
        name = f"B{b:g}"
        run_dir = os.path.join(args.out, name)
        text = re.sub(r"(?m)^attraction = [0-9.]+", f"attraction = {b}", template)
        text = re.sub(r"(?m)^steps = .*", f"steps = {args.steps}", text)
        text = re.sub(r"(?m)^every = 2000", "every = 500", text)
        if args.dt:
            text = re.sub(r"(?m)^dt = .*", f"dt = {args.dt}", text)
        cfg = os.path.join(args.out, name + ".toml")
        if not args.analyse_only:
            with open(cfg, "w") as f:
                f.write(text)
            cmd = [args.mesodpd, "run", cfg, "--out", run_dir, "--threads", str(args.threads)]
            print("running:", " ".join(cmd), flush=True)
            r = subprocess.run(cmd, capture_output=True, text=True)
            sys.stdout.write(r.stdout[-300:])
            if r.returncode != 0:
                sys.stderr.write(r.stderr)
                return 1
        series = []
        for step, lens, pos in frames(os.path.join(run_dir, "trajectory.lammpstrj")):
            labels, rho_l, rho_g, n_gas = analyse_frame(lens, pos, args.shell)
            drops = int(labels.max()) + 1
            largest = int((labels == 0).sum())
            series.append((step, drops, largest, rho_l, rho_g, n_gas))
            last[name] = (lens, pos, labels, step, drops)
        s = np.array(series, dtype=float)
        np.savetxt(os.path.join(run_dir, "series.csv"), s, delimiter=",", fmt="%.6g",
                   header="step,drops,largest_drop,rho_liquid,rho_gas,gas_particles", comments="")
        late = s[s[:, 0] >= args.average_from]
        rho_l, rho_l_err = block(late[:, 3]) if np.isfinite(late[:, 3]).all() else (float("nan"), float("nan"))
        rho_g, rho_g_err = block(late[:, 4])
        # Is the gas still depleting? The mean of the first and the last third of the window.
        third = max(len(late) // 3, 1)
        g_first, g_last = float(late[:third, 4].mean()), float(late[-third:, 4].mean())
        thermo = np.genfromtxt(os.path.join(run_dir, "thermo.csv"), delimiter=",", names=True)
        t_late = thermo["temperature"][thermo["step"] >= args.average_from]
        ratio = rho_l / rho_g if rho_g > 0 and math.isfinite(rho_l) else float("nan")
        ratio_err = ratio * math.hypot(rho_l_err / rho_l, rho_g_err / rho_g) if math.isfinite(ratio) else float("nan")
        results[name] = {
            "B": b, "steps": int(s[-1, 0]), "frames_averaged": int(len(late)),
            "drops_late": sorted(set(int(v) for v in late[:, 1])), "drops_last": int(s[-1, 1]),
            "largest_drop_last": int(s[-1, 2]), "rho_liquid": rho_l, "rho_liquid_err": rho_l_err,
            "drops_mean": float(late[:, 1].mean()),
            "rho_gas": rho_g, "rho_gas_err": rho_g_err, "gas_particles_mean": float(late[:, 5].mean()),
            # Counting error if the frames were independent: rho_g / sqrt(gas particles counted in all).
            "rho_gas_count_err": rho_g / math.sqrt(late[:, 5].sum()) if late[:, 5].sum() > 0 else float("nan"),
            "rho_gas_first_third": g_first, "rho_gas_last_third": g_last,
            "ratio": ratio, "ratio_err": ratio_err, "temperature": float(t_late.mean()),
        }
        lens, pos, labels, step, drops = last[name]
        fig = plt.figure(figsize=(4.2, 4.2))
        draw_snapshot(fig.add_subplot(projection="3d"), lens, pos, labels, f"B = {b:g}, step {step}: {drops} drop(s)")
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, f"snapshot_{name}.png"), dpi=80)
        plt.close(fig)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=2)
    # All snapshots in one picture, and the gas density against time.
    fig = plt.figure(figsize=(2.4 * len(last), 2.6))
    for k, (name, (lens, pos, labels, step, drops)) in enumerate(last.items()):
        draw_snapshot(fig.add_subplot(1, len(last), k + 1, projection="3d"), lens, pos, labels,
                      f"B = {name[1:]}: {drops} drop(s)")
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "snapshots.png"), dpi=80)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(5.5, 3.5))
    for name in last:
        s = np.loadtxt(os.path.join(args.out, name, "series.csv"), delimiter=",", skiprows=1, ndmin=2)
        ax.semilogy(s[:, 0], s[:, 4], ".-", ms=3, lw=0.8, label=name.replace("B", "B = "))
    ax.axvline(args.average_from, color="grey", lw=0.5)
    ax.set_xlabel("step (dt = liu.toml's)")
    ax.set_ylabel(f"gas density (> {args.shell:g} from drops)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "gas_density.png"), dpi=90)
    plt.close(fig)
    print(f"\n{'B':>5} {'drops (mean)':>16} {'rho_liquid':>14} {'rho_gas +- block (count) error':>32} "
          f"{'gas: 1st/last third':>20} {'ratio':>12} {'T':>6}")
    for r in results.values():
        print(f"{r['B']:5g} {str(r['drops_late']):>10} ({r['drops_mean']:3.1f}) {r['rho_liquid']:7.2f} +- "
              f"{r['rho_liquid_err']:4.2f} {r['rho_gas']:8.5f} +- {r['rho_gas_err']:7.5f} ({r['rho_gas_count_err']:7.5f}) "
              f"{r['rho_gas_first_third']:9.5f}/{r['rho_gas_last_third']:8.5f} "
              f"{r['ratio']:6.0f} +- {r['ratio_err']:4.0f} {r['temperature']:6.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
