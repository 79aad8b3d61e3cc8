#!/usr/bin/python3
"""Pressure-density relation of the spline fluid (seed 000 Fig. 13: A = 2.0, r_c1 = 0.8, B = 0.95,
r_c2 = 1.0, a = 18.75) at k_BT = 1 and 0.54 in a 10^3 box, from the virial pressure of thermo.csv
(seed 000 Eq. 24), with a fit of the van der Waals form p = rho kT / (1 - rho b) - a rho^2 (Eq. 25).

    /usr/bin/python3 examples/spline_droplet/eos.py [--mesodpd build/mesodpd] [--out out/spline_eos]
                     [--steps 3000] [--rho 0.5 1 2 3 4 5 6] [--kT 1 0.54]

Each state point starts from a uniform random gas and runs --steps steps of dt = 0.01; the pressure is
the mean over the second half with a 5-block error. Inside the two-phase region of the lower
temperature a homogeneous start is unstable: there the mean pressure of a short run is that of a
separating system (the loop's negative-slope branch), not of a stable state. Writes eos.csv, eos.png.
"""
import argparse
import math
import os
import re
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def block(x, blocks=5):
    per = len(x) // blocks
    m = np.asarray(x[len(x) - per * blocks:]).reshape(blocks, per).mean(axis=1)
    return float(m.mean()), float(m.std(ddof=1) / math.sqrt(blocks))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "spline_eos"))
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--rho", type=float, nargs="+", default=[0.5, 1, 2, 3, 4, 5, 6])
    ap.add_argument("--kT", type=float, nargs="+", default=[1.0, 0.54])
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(HERE, "liu.toml")) as f:
        template = f.read()
    rows = []
    for kT in args.kT:
        for rho in args.rho:
            name = f"kT{kT:g}_rho{rho:g}"
            text = re.sub(r"(?m)^attraction = [0-9.]+", "attraction = 0.95", template)
            text = re.sub(r"(?m)^box = .*", "box = [10.0, 10.0, 10.0]", text)
            text = re.sub(r"(?m)^kT = .*", f"kT = {kT}", text)
            text = re.sub(r"(?m)^density = .*", f"density = {rho}", text)
            text = re.sub(r"(?m)^thermo_every = .*", "thermo_every = 10", text)
            text = re.sub(r"(?ms)^\[output\.dump\].*", "", text)
            cfg = os.path.join(args.out, name + ".toml")
            with open(cfg, "w") as f:
                f.write(text)
            r = subprocess.run([args.mesodpd, "run", cfg, "--out", os.path.join(args.out, name), "--threads", "1",
                                "--steps", str(args.steps)], capture_output=True, text=True)
            if r.returncode != 0:
                sys.stderr.write(r.stderr)
                return 1
            t = np.genfromtxt(os.path.join(args.out, name, "thermo.csv"), delimiter=",", names=True)
            late = t["step"] >= args.steps // 2
            p, dp = block(t["pressure"][late])
            T, _ = block(t["temperature"][late])
            rows.append((kT, rho, p, dp, T))
            print(f"kT = {kT:5g} rho = {rho:5g}: p = {p:9.4f} +- {dp:.4f}  (measured T = {T:.3f})", flush=True)
    with open(os.path.join(args.out, "eos.csv"), "w") as f:
        f.write("kT,rho,pressure,pressure_err,temperature\n")
        for row in rows:
            f.write(",".join(f"{v:.6g}" for v in row) + "\n")
    # van der Waals fit per temperature: p = rho kT/(1 - rho b) - a rho^2 (Eq. 25), least squares over b
    # on a grid with a linear a for each b.
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for kT in args.kT:
        sel = [r for r in rows if r[0] == kT]
        rho = np.array([r[1] for r in sel])
        p = np.array([r[2] for r in sel])
        err = np.array([r[3] for r in sel])
        best = None
        for b in np.linspace(0.001, 0.9 / rho.max(), 400):
            ideal = rho * kT / (1 - rho * b)
            a = np.sum((ideal - p) * rho ** 2) / np.sum(rho ** 4)
            res = np.sum((ideal - a * rho ** 2 - p) ** 2)
            if best is None or res < best[0]:
                best = (res, a, b)
        _, a, b = best
        loop = bool(np.any(np.diff(p) < -3 * np.sqrt(err[1:] ** 2 + err[:-1] ** 2)))
        print(f"kT = {kT:g}: van der Waals fit a = {a:.3f}, b = {b:.4f}; P(rho) decreasing somewhere "
              f"(beyond 3 errors): {'yes' if loop else 'no'}")
        ax.errorbar(rho, p, yerr=err, fmt="o", label=f"kT = {kT:g} (mesodpd)")
        grid = np.linspace(0.05, rho.max(), 200)
        ax.plot(grid, grid * kT / (1 - grid * b) - a * grid ** 2, "--", label=f"vdW fit a = {a:.2f}, b = {b:.3f}")
    ax.axhline(0, color="gray", lw=0.5)
    ax.set_xlabel("density rho")
    ax.set_ylabel("pressure (virial, seed 000 Eq. 24)")
    ax.set_title("Spline fluid A = 2, rc1 = 0.8, B = 0.95, rc2 = 1, a = 18.75")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "eos.png"), dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
