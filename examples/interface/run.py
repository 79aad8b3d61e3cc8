#!/usr/bin/python3
"""Interfacial tension of two immiscible standard-DPD liquids against Delta a = a_AB - a_AA.

    /usr/bin/python3 examples/interface/run.py [--mesodpd build/mesodpd] [--out out/interface]
                                               [--da 2 5 10 15 20 30] [--steps 30000] [--jobs 1]
                                               [--analyse-only]

For every Delta a: interface.toml with a_AB = 25 + Delta a (and the data file's absolute path) is run
in --out/da<Delta a>/ on one thread. From each run: sigma +- its block error ([analysis.surface_tension]),
and the composition of both bulk phases from the binned A and B densities along z (profile.csv,
centred on A's centre of mass): phi = the minority fraction, averaged over the bins farther than 2.5
from both interfaces in each phase. For a symmetric mixture of monomers the Flory-Huggins free energy
gives the coexisting phi through chi = ln((1 - phi)/phi) / (1 - 2 phi) (the binodal of a symmetric
blend, N = 1); that chi is listed beside Groot and Warren's mapping chi = 0.286 Delta a at rho = 3.
Writes results.json and sigma.png (sigma and chi against Delta a) in --out. check.py judges results.json.
"""
import argparse
import json
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools"))
from sweep import add_run_args, run_all, run_config  # noqa: E402
A_SELF = 25.0
CHI_PER_DA = 0.286  # Groot and Warren's mapping at rho = 3 (J. Chem. Phys. 107, 4423 (1997), seed 002 ref. 6)


def make_config(da, steps, start):
    text = open(os.path.join(HERE, "interface.toml")).read()
    text = text.replace("a = 45.0                      # 25 + Delta a", f"a = {A_SELF + da}  # 25 + Delta a")
    text = text.replace('lammps_data = "slab.data"', f'lammps_data = "{os.path.join(HERE, "slab.data")}"')
    if steps is not None:
        text = text.replace("steps = 30000", f"steps = {steps}")
    if start is not None:
        text = text.replace("start = 5000", f"start = {start}")
    return text


def run_one(args, da):
    run_config(args.mesodpd, make_config(da, args.steps, args.start), os.path.join(args.out, f"da{da:g}"),
               "interface.toml")


def flory_huggins_chi(phi):
    """chi on the binodal of a symmetric monomer blend: d f / d phi = 0 with
    f = phi ln phi + (1 - phi) ln(1 - phi) + chi phi (1 - phi) gives chi = ln((1 - phi)/phi)/(1 - 2 phi)."""
    if not 0 < phi < 0.5:
        return float("nan")
    return math.log((1 - phi) / phi) / (1 - 2 * phi)


def analyse(d, da):
    st = json.load(open(os.path.join(d, "surface_tension.json")))
    prof = json.load(open(os.path.join(d, "profile.json")))
    rows = np.genfromtxt(os.path.join(d, "profile.csv"), delimiter=",", names=True)
    z, ra, rb = rows["z"], rows["density_A"], rows["density_B"]
    lz = float(prof["hi"][2]) - float(prof["lo"][2])
    # A's slab is centred at lz / 2 with half-width ~lz / 4: interfaces near lz/4 and 3 lz/4.
    fit = prof.get("slab_fit") or {}
    h = fit.get("half_width") if fit.get("converged") else None
    h = h if h is not None and 0.5 < h < lz / 2 - 0.5 else lz / 4
    dist = np.abs(z - lz / 2)
    a_rich = dist < h - 2.5
    b_rich = dist > h + 2.5
    out = {"delta_a": da, "a_ab": A_SELF + da, "chi_mapping": CHI_PER_DA * da,
           "sigma": st["sigma"], "sigma_err": st["sigma_err"], "samples": st["samples"],
           "half_width": h}
    if a_rich.sum() >= 2 and b_rich.sum() >= 2:
        phi_a = float(np.mean(rb[a_rich] / (ra[a_rich] + rb[a_rich])))  # B dissolved in the A-rich phase
        phi_b = float(np.mean(ra[b_rich] / (ra[b_rich] + rb[b_rich])))  # A dissolved in the B-rich phase
        phi = 0.5 * (phi_a + phi_b)
        # Minority fractions near 1/2 mean one mixed phase (below the critical chi = 2): no coexistence.
        out.update({"phi_in_A": phi_a, "phi_in_B": phi_b, "phi": phi, "mixed": phi > 0.4,
                    "chi_coexistence": None if phi > 0.4 else flory_huggins_chi(phi),
                    # The two phases are two estimates: half their difference is the standard error of the mean.
                    "chi_coexistence_err": None if phi > 0.4 else
                    0.5 * abs(flory_huggins_chi(phi_a) - flory_huggins_chi(phi_b)),
                    "rho_total_A_phase": float(np.mean(ra[a_rich] + rb[a_rich])),
                    "rho_total_B_phase": float(np.mean(ra[b_rich] + rb[b_rich]))})
    if fit.get("converged"):
        out.update({"width": fit.get("width"), "width_err": fit.get("width_err")})
    return out


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    da = np.array([r["delta_a"] for r in results])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4))
    ax1.errorbar(da, [r["sigma"] for r in results], yerr=[r["sigma_err"] for r in results], fmt="o-", capsize=3)
    ax1.axhline(0, color="grey", lw=0.5)
    ax1.axvline(2 / CHI_PER_DA, color="grey", ls=":", label=r"$\chi = 2$ (critical, by the mapping)")
    ax1.set_xlabel(r"$\Delta a = a_{AB} - a_{AA}$")
    ax1.set_ylabel(r"interfacial tension $\sigma$ ($k_BT / r_c^2$)")
    ax1.legend()
    chi = [(r["delta_a"], r["chi_coexistence"]) for r in results if r.get("chi_coexistence") is not None]
    x = np.linspace(0, max(da) * 1.05, 50)
    ax2.plot(x, CHI_PER_DA * x, "-", label=r"Groot-Warren $\chi = 0.286\,\Delta a$")
    if chi:
        ax2.errorbar([c[0] for c in chi], [c[1] for c in chi], fmt="o", capsize=3,
                     yerr=[r["chi_coexistence_err"] for r in results if r.get("chi_coexistence") is not None],
                     label="from coexisting compositions")
    ax2.set_xlabel(r"$\Delta a$")
    ax2.set_ylabel(r"$\chi$")
    ax2.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_run_args(ap, ROOT, "interface")
    ap.add_argument("--da", type=float, nargs="+", default=[2, 5, 10, 15, 20, 30])
    ap.add_argument("--steps", type=int, default=None, help="override run.steps (default 30000)")
    ap.add_argument("--start", type=int, default=None, help="override the analyses' start (default 5000)")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if not args.analyse_only:
        run_all(lambda da: run_one(args, da), args.da, args.jobs)
    results = [analyse(os.path.join(args.out, f"da{da:g}"), da) for da in args.da]
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(results, f, indent=1)
    print(f"{'Delta a':>8} {'chi=0.286Da':>11} {'sigma':>16} {'phi':>8} {'chi(phi)':>16}")
    for r in results:
        print(f"{r['delta_a']:8g} {r['chi_mapping']:11.2f} {r['sigma']:8.3f} +- {r['sigma_err']:5.3f} "
              f"{r.get('phi', float('nan')):8.4f} " +
              ("           mixed" if r.get("chi_coexistence") is None
               else f"{r['chi_coexistence']:7.2f} +- {r['chi_coexistence_err']:5.2f}"))
    plot(results, os.path.join(args.out, "sigma.png"))
    print(f"wrote {args.out}/results.json and sigma.png")


if __name__ == "__main__":
    sys.exit(main())
