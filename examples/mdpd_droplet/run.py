#!/usr/bin/python3
"""Laplace's law for Warren's many-body DPD liquid: droplets of several radii, the pressure jump
Delta P = P_in - P_out against 1/R, and the slope 2 sigma compared with the slab's surface tension.

    /usr/bin/python3 examples/mdpd_droplet/run.py [--mesodpd build/mesodpd] [--out out/mdpd_droplet]
                                                  [--steps 20000] [--threads 1] [--sizes 1600 3200 7000]
                                                  [--analyse-only]

Each drop: N particles on a simple cubic lattice of density 6 filling a ball at the centre of a cubic periodic box of edge
2 (R0 + 3.5) (R0 the initial radius), the config droplet.toml with the box, data file and the radii of
[analysis.droplet] filled in (inner_radius = R0 - 2.2: the liquid core whose particles and neighbours
stay in the homogeneous liquid; outer_radius = R0 + 3). Writes, under --out: N<count>/ (the run:
thermo.csv, droplet.json, droplet_profile.csv), laplace.csv, laplace.png, profiles.png, results.json.
check.py judges results.json (exit code 1 outside the tolerance of README.md).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
RHO0 = 6.0


def write_drop(path, n, box, seed):
    """A LAMMPS data file: the n simple-cubic lattice sites of density RHO0 nearest the box centre (a
    ball; lattice spacing RHO0^(-1/3)), each moved by a small random offset. A lattice start releases far
    less energy than uniform random positions, whose overlaps boil the drop for thousands of steps."""
    rng = np.random.default_rng(seed)
    a = RHO0 ** (-1 / 3)
    m = int(math.ceil((3 * n / (4 * math.pi * RHO0)) ** (1 / 3) / a)) + 2
    g = np.arange(-m, m + 1) * a
    sites = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T + a / 2
    sites = sites[np.argsort(np.einsum("ij,ij->i", sites, sites), kind="stable")[:n]]
    pos = box / 2 + sites + rng.uniform(-0.05, 0.05, sites.shape)
    with open(path, "w") as f:
        f.write("Warren droplet for mesodpd (examples/mdpd_droplet/run.py)\n\n")
        f.write(f"{n} atoms\n1 atom types\n\n0 {box} xlo xhi\n0 {box} ylo yhi\n0 {box} zlo zhi\n\n")
        f.write("Masses\n\n1 1.0\n\nAtoms # atomic\n\n")
        for k, (x, y, z) in enumerate(pos):
            f.write(f"{k + 1} 1 {x:.6f} {y:.6f} {z:.6f}\n")


def geometry(n):
    """Initial radius, box edge and the two radii of [analysis.droplet] for a drop of n particles."""
    r0 = (3 * n / (4 * math.pi * RHO0)) ** (1 / 3)
    box = round(2 * (r0 + 3.5), 1)
    return r0, box, round(r0 - 2.2, 2), round(r0 + 3.0, 2)


def make_config(template, n, steps, start):
    r0, box, inner, outer = geometry(n)
    text = open(template).read()
    text = text.replace("box = [15.0, 15.0, 15.0]", f"box = [{box}, {box}, {box}]")
    text = text.replace("inner_radius = 1.79", f"inner_radius = {inner}")
    text = text.replace("outer_radius = 6.99", f"outer_radius = {outer}")
    if steps is not None:
        text = text.replace("steps = 20000", f"steps = {steps}")
    if start is not None:
        text = text.replace("start = 2000", f"start = {start}")
    return text, box


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "mdpd_droplet"))
    ap.add_argument("--steps", type=int, default=None, help="override run.steps (default: droplet.toml's 20000)")
    ap.add_argument("--start", type=int, default=None, help="override analysis.droplet.start (default 2000)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--sizes", type=int, nargs="+", default=[1600, 3200, 7000], help="particles per drop")
    ap.add_argument("--analyse-only", action="store_true", help="only analyse runs already in --out")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    template = os.path.join(HERE, "droplet.toml")
    rows = []
    for n in args.sizes:
        run_dir = os.path.join(args.out, f"N{n}")
        if not args.analyse_only:
            os.makedirs(run_dir, exist_ok=True)
            text, box = make_config(template, n, args.steps, args.start)
            with open(os.path.join(run_dir, "droplet.toml"), "w") as f:
                f.write(text)
            write_drop(os.path.join(run_dir, "drop.data"), n, box, 2003 + n)
            env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
            cmd = [args.mesodpd, "run", "droplet.toml", "--out", "out", "--no-progress"]
            print("running", " ".join(cmd), "in", run_dir, flush=True)
            with open(os.path.join(run_dir, "log.txt"), "w") as log:
                if subprocess.run(cmd, cwd=run_dir, env=env, stdout=log, stderr=subprocess.STDOUT).returncode != 0:
                    print(f"run N{n} failed, see {run_dir}/log.txt")
                    return 1
        with open(os.path.join(run_dir, "out", "droplet.json")) as f:
            d = json.load(f)
        d["particles"] = n
        rows.append(d)
    # Delta P against 1/R (equimolar R): weighted straight line Delta P = a + (2 sigma) / R.
    x = np.array([1 / r["radius"] for r in rows])
    y = np.array([r["delta_p"] for r in rows])
    e = np.array([r["delta_p_err"] for r in rows])
    w = 1 / e**2
    A = np.vstack([np.ones_like(x), x]).T
    cov = np.linalg.inv(A.T @ (A * w[:, None]))
    icept, slope = cov @ (A.T @ (w * y))
    icept_err, slope_err = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    chi2 = float(np.sum(w * (y - icept - slope * x) ** 2))
    # The line through the origin (Laplace without offset): Delta P = 2 sigma / R.
    slope0 = float(np.sum(w * x * y) / np.sum(w * x * x))
    slope0_err = float(1 / math.sqrt(np.sum(w * x * x)))
    results = {
        "drops": rows,
        "sigma_fit": slope / 2, "sigma_fit_err": slope_err / 2,
        "intercept": icept, "intercept_err": icept_err, "chi2": chi2, "dof": len(rows) - 2,
        "sigma_origin": slope0 / 2, "sigma_origin_err": slope0_err / 2,
        "sigma_slab": 7.86, "sigma_slab_err": 0.10,
    }
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=2)
    with open(os.path.join(args.out, "laplace.csv"), "w") as f:
        f.write("particles,radius,radius_err,half_density_radius,rho_in,rho_out,p_in,p_in_err,p_out,p_out_err,"
                "delta_p,delta_p_err,sigma_laplace,sigma_laplace_err\n")
        for r in rows:
            f.write(",".join(str(r[k]) for k in ["particles", "radius", "radius_err", "half_density_radius", "rho_in",
                                                 "rho_out", "p_in", "p_in_err", "p_out", "p_out_err", "delta_p",
                                                 "delta_p_err", "sigma_laplace", "sigma_laplace_err"]) + "\n")
    print(f"{'N':>6} {'R':>8} {'R_half':>7} {'rho_in':>7} {'P_in':>14} {'P_out':>9} {'dP':>14} {'dP R/2':>8}")
    for r in rows:
        print(f"{r['particles']:6d} {r['radius']:8.4f} {r['half_density_radius']:7.3f} {r['rho_in']:7.4f} "
              f"{r['p_in']:7.4f}+-{r['p_in_err']:.4f} {r['p_out']:9.5f} {r['delta_p']:7.4f}+-{r['delta_p_err']:.4f} "
              f"{r['sigma_laplace']:8.3f}")
    print(f"fit dP = a + 2 sigma / R: sigma = {slope / 2:.3f} +- {slope_err / 2:.3f}, a = {icept:.3f} +- {icept_err:.3f}, "
          f"chi2 = {chi2:.2f} ({len(rows) - 2} dof)")
    print(f"through the origin: sigma = {slope0 / 2:.3f} +- {slope0_err / 2:.3f}; slab: 7.86 +- 0.10")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.errorbar(x, y, yerr=e, fmt="o", label="droplets")
        xs = np.linspace(0, x.max() * 1.1, 50)
        ax.plot(xs, icept + slope * xs, "-", label=f"fit: sigma = {slope / 2:.2f} +- {slope_err / 2:.2f}")
        ax.plot(xs, 2 * 7.86 * xs, "--", label="2 sigma_slab / R, sigma_slab = 7.86")
        ax.set_xlabel("1 / R (equimolar)")
        ax.set_ylabel("Delta P = P_in - P_out")
        ax.set_title("Laplace's law, Warren's liquid")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "laplace.png"), dpi=120)
        fig, ax = plt.subplots(figsize=(5, 4))
        for r in rows:
            prof = np.genfromtxt(os.path.join(args.out, f"N{r['particles']}", "out", "droplet_profile.csv"),
                                 delimiter=",", names=True)
            ax.plot(prof["r"], prof["density"], label=f"N = {r['particles']}, R = {r['radius']:.2f}")
        ax.set_xlabel("r (distance from the drop's centre)")
        ax.set_ylabel("number density")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(args.out, "profiles.png"), dpi=120)
    except ImportError:
        print("matplotlib missing: no plots")
    return 0


if __name__ == "__main__":
    sys.exit(main())
