#!/usr/bin/python3
"""Pressure-density relation of the spline fluid (seed 000 Fig. 13: A = 2.0, r_c1 = 0.8, B = 0.95,
r_c2 = 1.0; by default with the a = 18.75 of liu.toml, --a sets the strength a of Eq. 21: the seed does
not state Fig. 13's a) at k_BT = 1 and 0.54 in a 10^3 box, from the virial pressure of thermo.csv
(seed 000 Eq. 24), with a fit of the van der Waals form of Eq. 25, p = rho kT / (1 - rho b) - a rho^2
(this a-bar, b-bar are the fit's, not the pair strength a).

    /usr/bin/python3 examples/spline_droplet/eos.py [--mesodpd build/mesodpd] [--out out/spline_eos] [--a 18.75]
                     [--steps 2400] [--gas-steps 20000] [--dt 0.01] [--rho 0.1 0.25 0.5 1 2 3 4 6 8 9 10 11 12]
                     [--kT 1 0.54] [--plot-only]

Each state point starts from a uniform random gas and runs --steps steps of --dt (--gas-steps at
rho <= 2, where condensation and the thermostat are slow); the pressure is the mean of the thermo rows
after the first third with a 5-block error. The final frame's particles are
counted in the 8 octants of the box: when their densities differ by more than 15 % of rho and their
variance is more than 5 times the Poisson variance of an ideal gas, the box has separated into liquid
and vapour (a drop, a slab or a bubble), and its pressure is that finite
two-phase state's, not a homogeneous fluid's. The fit of Eq. 25 is an unweighted least-squares fit in
p over the homogeneous boxes, per temperature and jointly over both temperatures with one (a, b) as
in Fig. 13 (exact: a is linear for a given b, b is scanned on a fine grid below 1 / max rho). Writes
eos.csv, eos_fit.json (with the pair strength a it was run with) and eos.png; --plot-only takes a
from --a, or else from an existing eos_fit.json.
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
BOX = 10.0


def block(x, blocks=5):
    per = len(x) // blocks
    m = np.asarray(x[len(x) - per * blocks:]).reshape(blocks, per).mean(axis=1)
    return float(m.mean()), float(m.std(ddof=1) / math.sqrt(blocks))


def final_positions(path):
    """Positions of the last frame of a LAMMPS text dump (columns named on its ITEM: ATOMS line)."""
    with open(path) as f:
        lines = f.read().splitlines()
    k = [i for i, line in enumerate(lines) if line.startswith("ITEM: ATOMS")][-1]
    cols = lines[k].split()[2:]
    n = int(lines[k - 5])
    data = np.array([[float(v) for v in line.split()] for line in lines[k + 1:k + 1 + n]])
    return data[:, [cols.index("x"), cols.index("y"), cols.index("z")]]


def vdw(rho, kT, a, b):
    """Seed 000 Eq. 25."""
    return rho * kT / (1 - rho * b) - a * rho ** 2


def fit_vdw(rho, p, kT):
    """Least squares in p over (a, b): a is linear for each b; b on a grid of 20,000 below 1/max(rho)."""
    best = None
    kT = np.broadcast_to(kT, rho.shape)
    for b in np.linspace(0.0, 0.999 / rho.max(), 20000):
        ideal = rho * kT / (1 - rho * b)
        a = float(np.sum((ideal - p) * rho ** 2) / np.sum(rho ** 4))
        res = float(np.sum((ideal - a * rho ** 2 - p) ** 2))
        if best is None or res < best[0]:
            best = (res, a, float(b))
    res, a, b = best
    return a, b, math.sqrt(res / max(len(rho) - 2, 1))


def run_point(args, template, kT, rho, seed):
    name = f"kT{kT:g}_rho{rho:g}"
    steps = args.gas_steps if rho <= 2 else args.steps
    text = re.sub(r"(?m)^attraction = [0-9.]+", "attraction = 0.95", template)
    text = re.sub(r"(?m)^a = [0-9.]+", f"a = {args.a!r}", text)
    text = re.sub(r"(?m)^box = .*", f"box = [{BOX}, {BOX}, {BOX}]", text)
    text = re.sub(r"(?m)^kT = .*", f"kT = {kT}", text)
    text = re.sub(r"(?m)^seed = .*", f"seed = {seed}", text)
    text = re.sub(r"(?m)^density = .*", f"density = {rho}", text)
    text = re.sub(r"(?m)^dt = .*", f"dt = {args.dt}", text)
    text = re.sub(r"(?m)^steps = .*", f"steps = {steps}", text)
    text = re.sub(r"(?m)^thermo_every = .*", "thermo_every = 10", text)
    text = re.sub(r"(?m)^every = 2000", f"every = {steps}", text)  # the dump: final frame only
    cfg = os.path.join(args.out, name + ".toml")
    with open(cfg, "w") as f:
        f.write(text)
    out = os.path.join(args.out, name)
    r = subprocess.run([args.mesodpd, "run", cfg, "--out", out, "--threads", "1"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.stderr.write(r.stderr)
        raise SystemExit(f"{name}: mesodpd failed")
    t = np.genfromtxt(os.path.join(out, "thermo.csv"), delimiter=",", names=True)
    late = t["step"] > steps / 3
    p, dp = block(t["pressure"][late])
    temp = float(np.mean(t["temperature"][late]))
    x = final_positions(os.path.join(out, "trajectory.lammpstrj"))
    octant = (np.floor(x / (BOX / 2)).astype(int) % 2) @ np.array([1, 2, 4])
    counts = np.bincount(octant, minlength=8)
    dens = counts / (BOX / 2) ** 3
    poisson = float(counts.var(ddof=1) / counts.mean())  # 1 for an ideal gas
    return (kT, rho, p, dp, temp, float(dens.min()), float(dens.max()), poisson)


def separated(rows):
    """Octant densities apart by more than 15 % of rho and a variance over 5 times Poisson's."""
    return (rows[:, 6] - rows[:, 5] > 0.15 * rows[:, 1]) & (rows[:, 7] > 5)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "spline_eos"))
    ap.add_argument("--steps", type=int, default=2400)
    ap.add_argument("--gas-steps", type=int, default=20000, help="steps at rho <= 2 (slow condensation)")
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--a", type=float, default=None,
                    help="pair strength a of U = a [A W(r, rc1) - B W(r, rc2)] (default: liu.toml's, 18.75)")
    ap.add_argument("--rho", type=float, nargs="+", default=[0.1, 0.25, 0.5, 1, 2, 3, 4, 6, 8, 9, 10, 11, 12])
    ap.add_argument("--kT", type=float, nargs="+", default=[1.0, 0.54])
    ap.add_argument("--plot-only", action="store_true", help="fit and redraw from --out/eos.csv")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    csv = os.path.join(args.out, "eos.csv")
    with open(os.path.join(HERE, "liu.toml")) as f:
        template = f.read()
    if args.a is None and args.plot_only and os.path.exists(os.path.join(args.out, "eos_fit.json")):
        with open(os.path.join(args.out, "eos_fit.json")) as f:
            args.a = json.load(f).get("pair_a")
    if args.a is None:
        args.a = float(re.search(r"(?m)^a = ([0-9.]+)", template).group(1))
    if not args.a > 0:
        raise SystemExit(f"--a must be positive (got {args.a})")
    if args.plot_only:
        rows = [tuple(v) for v in np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)]
    else:
        rows = []
        for kT in args.kT:
            for rho in args.rho:
                row = run_point(args, template, kT, rho, 300 + round(100 * rho))  # a seed per density
                rows.append(row)
                print(f"kT = {kT:5g} rho = {rho:5g}: p = {row[2]:9.4f} +- {row[3]:.4f}  T = {row[4]:.4f}  "
                      f"octant densities {row[5]:.2f}..{row[6]:.2f} (variance/Poisson {row[7]:.1f})", flush=True)
                with open(csv, "w") as f:  # rewritten after each point, so a stopped run keeps its rows
                    f.write("kT,rho,pressure,pressure_err,temperature,octant_density_min,octant_density_max,octant_var_over_poisson\n")
                    for r in rows:
                        f.write(",".join(f"{v:.6g}" for v in r) + "\n")
    table = np.array(rows)
    fits = {"pair_a": args.a}
    print(f"\n{'kT':>5} {'rho':>5} {'P':>18} {'T':>7} {'octants':>12} {'var/Poisson':>11} {'state':>12}")
    for r, sep in zip(table, separated(table)):
        print(f"{r[0]:5g} {r[1]:5g} {r[2]:9.3f} +- {r[3]:5.3f} {r[4]:7.4f} {r[5]:5.2f}-{r[6]:5.2f} {r[7]:11.1f} "
              f"{'separated' if sep else 'homogeneous':>12}")
    for kT in sorted(set(table[:, 0]), reverse=True):
        sel = table[table[:, 0] == kT]
        sel = sel[np.argsort(sel[:, 1])]
        homog = ~separated(sel)
        a, b, rms = fit_vdw(sel[homog, 1], sel[homog, 2], kT)
        a_all, b_all, rms_all = fit_vdw(sel[:, 1], sel[:, 2], kT)
        # A fall of P with rho beyond 3 combined errors between neighbouring densities.
        falls = [(float(sel[i, 1]), float(sel[i + 1, 1])) for i in range(len(sel) - 1)
                 if sel[i + 1, 2] - sel[i, 2] < -3 * math.hypot(sel[i, 3], sel[i + 1, 3])]
        crit = {"kTc": 8 * a / (27 * b), "rho_c": 1 / (3 * b)} if b > 0 else {}
        fits[f"{kT:g}"] = {"a_bar": a, "b_bar": b, "rms": rms, "points": int(homog.sum()),
                           "a_bar_all_points": a_all, "b_bar_all_points": b_all, "rms_all_points": rms_all,
                           "falls": falls, **crit}
        print(f"kT = {kT:g}: Eq. 25 fit over the {int(homog.sum())} homogeneous boxes a = {a:.4f}, b = {b:.5f} "
              f"(rms {rms:.3f}; its critical point kTc = 8a/27b = {crit.get('kTc', float('nan')):.3f}); "
              f"over all points a = {a_all:.4f}, b = {b_all:.5f} (rms {rms_all:.3f}); "
              f"P falls (> 3 errors) between rho = {falls if falls else 'none'}")
    homog = ~separated(table)
    a, b, rms = fit_vdw(table[homog, 1], table[homog, 2], table[homog, 0])
    fits["joint"] = {"a_bar": a, "b_bar": b, "rms": rms, "points": int(homog.sum()),
                     "kTc": 8 * a / (27 * b) if b > 0 else float("nan"), "rho_c": 1 / (3 * b) if b > 0 else float("nan")}
    print(f"both temperatures, one (a, b): a = {a:.4f}, b = {b:.5f} (rms {rms:.3f}; kTc = 8a/27b = "
          f"{fits['joint']['kTc']:.3f})")
    with open(os.path.join(args.out, "eos_fit.json"), "w") as f:
        json.dump(fits, f, indent=2)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, zoom in zip(axes, [False, True]):
        for kT, colour in zip(sorted(set(table[:, 0]), reverse=True), ["C0", "C3", "C2", "C1"]):
            sel = table[table[:, 0] == kT]
            sel = sel[np.argsort(sel[:, 1])]
            homog = ~separated(sel)
            ax.errorbar(sel[homog, 1], sel[homog, 2], yerr=sel[homog, 3], fmt="o", color=colour,
                        label=f"kT = {kT:g}, homogeneous box")
            ax.errorbar(sel[~homog, 1], sel[~homog, 2], yerr=sel[~homog, 3], fmt="s", mfc="none", color=colour,
                        label=f"kT = {kT:g}, separated box")
            ax.plot(sel[:, 1], sel[:, 2], ":", color=colour, lw=0.8)
            fit = fits[f"{kT:g}"]
            grid = np.linspace(0.01, sel[:, 1].max() * 1.02, 300)
            ax.plot(grid, vdw(grid, kT, fit["a_bar"], fit["b_bar"]), "-", color=colour, lw=1,
                    label=f"Eq. 25 fit: a = {fit['a_bar']:.3f}, b = {fit['b_bar']:.4f}")
            joint = fits["joint"]
            ax.plot(grid, vdw(grid, kT, joint["a_bar"], joint["b_bar"]), "--", color=colour, lw=0.8,
                    label=f"joint fit a = {joint['a_bar']:.3f}, b = {joint['b_bar']:.4f}" if colour == "C0" else None)
        ax.axhline(0, color="grey", lw=0.5)
        ax.set_xlabel("density rho")
        ax.set_ylabel("virial pressure P (seed 000 Eq. 24)")
        if zoom:
            ax.set_ylim(-3, 3)
            ax.set_title("zoom on the loop")
        else:
            ax.set_title(f"spline fluid a = {args.a:g}, A = 2, rc1 = 0.8, B = 0.95, rc2 = 1", fontsize=9)
            ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "eos.png"), dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
