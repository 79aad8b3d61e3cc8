#!/usr/bin/python3
"""Rayleigh-Benard onset (examples/convection/README.md, docs/validation.md 8c).

usage: rayleigh_benard.py [--mesodpd build/mesodpd] [--out out/rb] [--ratios 0 0.6 ...] [--steps N]
                          [--jobs 2] [--nu 0.276] [--png FILE] [--check] [--min-nu NU] [--analyse-only]

Runs examples/convection/rayleigh_benard.toml at g beta = ratio x the value of Ra = 1708 for the walls'
dT = 0.2 (ratio 0 is pure conduction), each into OUT/ratio_<r>, and from each run's flux.json:

- J, the heat through the layer per unit area: the mean of what the hot wall gives and the cold wall
  takes ((hot - cold) / 2), which leaves out the heat the fluid makes itself (viscous heating and the
  time step's drift add to the cold wall's share and take from the hot wall's);
- Nu = J / J_0, J_0 that of the conduction run;
- Ra = g beta dT_f d^3 / (nu D): d = 10, dT_f the fluid's own temperature difference (the conduction
  run's profile, flux_profile.csv, fitted by a line over 2 < z < 10 and taken at the wall surfaces
  z = 1 and 11), D the thermal diffusivity that run measures at the middle plane (k / (n C_v)), nu the
  fluid's kinematic viscosity (--nu; examples/convection/README.md measures 0.276 +- 0.003);
- the onset Ra_c: Nu - 1 = A (Ra - Ra_c) fitted to the runs with Nu - 1 above 0.1 and Ra below 1.75 x
  1708 (weighted by their errors), against 1708 for rigid walls (Chandrasekhar). Close above onset Nu - 1
  grows linearly in Ra; further above it bends down (the run at 2 x 1708 already lies below the line),
  and below the onset the fluid's thermal noise drives fluctuating convection that carries a few per cent
  (Nu - 1 = 0.03 at 0.6 x 1708, 0.06 at 0.9), which would pull a line through those points low.

Writes OUT/rayleigh_benard.json and, with --png, Nu against Ra with the fit and the rolls of the
strongest run (its binned fluid temperature and mean flow). --check exits 1 unless the onset lies within
20% of 1708 and the runs below 0.8 x 1708 show Nu - 1 < 0.05. --min-nu NU (the short version CI runs:
--ratios 0 2.5 --steps 20000 --min-nu 1.2) exits 1 unless the run of the largest ratio reaches Nu >= NU
and the runs below 0.8 x 1708 show Nu - 1 < 0.05, without fitting an onset.
"""
import argparse
import concurrent.futures
import csv
import json
import os
import re
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "rayleigh_benard.toml")
RA_C = 1708.0
DEPTH = 10.0
WALL_DT = 0.2


def g_beta_for(ratio, nu, d_t):
    """g beta for Ra = ratio x 1708 with the walls' dT and the given nu and D."""
    return ratio * RA_C * nu * d_t / (WALL_DT * DEPTH ** 3)


def run(binary, out, ratio, g_beta, steps):
    os.makedirs(out, exist_ok=True)
    text = open(CONFIG).read()
    text = re.sub(r"gravity = \[0\.0, 0\.0, -[0-9.]+\]", f"gravity = [0.0, 0.0, {-g_beta:.6f}]", text)
    if steps:
        text = re.sub(r"^steps = \d+", f"steps = {steps}", text, flags=re.M)
        start = steps // 3
        text = re.sub(r"^start = 20000", f"start = {start}", text, flags=re.M)
    cfg = os.path.join(out, "config.toml")
    with open(cfg, "w") as f:
        f.write(text)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    with open(os.path.join(out, "run.log"), "w") as log:
        subprocess.run([binary, "run", cfg, "--out", out], check=True, stdout=log, stderr=subprocess.STDOUT, env=env)
    return ratio


def flux_of(out):
    j = json.load(open(os.path.join(out, "flux.json")))
    walls = {w["species"]: w for w in j["walls"]}
    hot, cold = walls["hot"], walls["cold"]
    flux = 0.5 * (hot["per_area"] - cold["per_area"])
    err = 0.5 * np.hypot(hot["per_area_err"], cold["per_area_err"])
    middle = j["planes"][len(j["planes"]) // 2]
    return flux, err, middle, hot, cold


def fluid_dt(out):
    """The conduction run's fluid temperature difference between the wall surfaces z = 1 and 11."""
    z, t = [], []
    with open(os.path.join(out, "flux_profile.csv")) as f:
        for row in csv.DictReader(f):
            zz = float(row["position"])
            if 2.0 < zz < 10.0:
                z.append(zz)
                t.append(float(row["mean_temp"]))
    slope, icpt = np.polyfit(z, t, 1)
    return (slope * 1.0 + icpt) - (slope * 11.0 + icpt), slope


def onset(ra, nu_minus_1, err):
    """Ra_c and its error from a weighted straight line Nu - 1 = A (Ra - Ra_c)."""
    w = 1.0 / np.maximum(err, 1e-4) ** 2
    a = np.vstack([ra, np.ones_like(ra)]).T
    cov = np.linalg.inv(a.T @ (a * w[:, None]))
    slope, icpt = cov @ (a.T @ (w * nu_minus_1))
    ra_c = -icpt / slope
    # error of -b/a by propagation
    g = np.array([icpt / slope ** 2, -1.0 / slope])
    return ra_c, float(np.sqrt(g @ cov @ g)), slope, icpt


def rolls_picture(out, ax):
    rows = list(csv.DictReader(open(os.path.join(out, "rolls.csv"))))
    xs = sorted({float(r["x"]) for r in rows})
    zs = sorted({float(r["z"]) for r in rows})
    t = np.full((len(zs), len(xs)), np.nan)
    u = np.zeros_like(t)
    w = np.zeros_like(t)
    for r in rows:
        i, k = zs.index(float(r["z"])), xs.index(float(r["x"]))
        if float(r.get("density", r.get("number_density", 0)) or 0) > 0:
            t[i, k] = float(r["mean_temp"])
            u[i, k] = float(r["vx"])
            w[i, k] = float(r["vz"])
    im = ax.contourf(xs, zs, t, levels=11, cmap="coolwarm")
    ax.streamplot(np.array(xs), np.array(zs), u, w, color="k", density=0.8, linewidth=0.6)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("z")
    return im


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/rb")
    ap.add_argument("--ratios", type=float, nargs="+", default=[0, 0.6, 0.9, 1.05, 1.2, 1.35, 1.5, 2.0, 3.0])
    ap.add_argument("--steps", type=int, default=0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--nu", type=float, default=0.276)
    ap.add_argument("--d", type=float, default=0.396, help="D used to set g beta (the measured D replaces it for Ra)")
    ap.add_argument("--png")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--min-nu", type=float)
    ap.add_argument("--analyse-only", action="store_true")
    a = ap.parse_args()
    if 0 not in a.ratios:
        sys.exit("rayleigh_benard.py: the ratios must include 0 (the conduction run Nu is measured against)")
    dirs = {r: os.path.join(a.out, f"ratio_{r:g}") for r in a.ratios}
    if not a.analyse_only:
        with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
            futures = [pool.submit(run, a.mesodpd, dirs[r], r, g_beta_for(r, a.nu, a.d), a.steps) for r in a.ratios]
            for f in concurrent.futures.as_completed(futures):
                print(f"ratio {f.result():g} done", flush=True)
    j0, j0_err, mid0, _, _ = flux_of(dirs[0])
    dt_f, grad = fluid_dt(dirs[0])
    d_meas, d_err = mid0["diffusivity"], mid0["diffusivity_err"]
    print(f"conduction: J_0 = {j0:.4f} +- {j0_err:.4f}, fluid dT_f = {dt_f:.4f} (walls 0.2), D = {d_meas:.4f} +- {d_err:.4f}, "
          f"Pr = nu / D = {a.nu / d_meas:.3f}")
    results = []
    for r in sorted(a.ratios):
        flux, err, mid, hot, cold = flux_of(dirs[r])
        g_beta = g_beta_for(r, a.nu, a.d)
        ra = g_beta * dt_f * DEPTH ** 3 / (a.nu * d_meas)
        nu = flux / j0
        nu_err = nu * np.hypot(err / flux, j0_err / j0)
        results.append({"ratio": r, "g_beta": g_beta, "ra": ra, "nu": nu, "nu_err": nu_err,
                         "hot": hot["per_area"], "cold": cold["per_area"], "middle_plane_flux": mid["flux"],
                         "middle_plane_convection": mid["convection"]})
        print(f"ratio {r:4g}: g beta {g_beta:.4f}, Ra = {ra:7.1f}, Nu = {nu:.4f} +- {nu_err:.4f} (hot wall {hot['per_area']:.3f}, "
              f"cold {cold['per_area']:.3f}, middle plane {mid['flux']:.3f} of which convection {mid['convection']:.3f})")
    ra = np.array([x["ra"] for x in results])
    nm1 = np.array([x["nu"] - 1 for x in results])
    err = np.array([x["nu_err"] for x in results])
    above = (nm1 > 0.1) & (ra < 1.75 * RA_C)
    if above.sum() < 2:
        above = nm1 > 0.1
    ok = True
    summary = {"fluid_dT": dt_f, "D": d_meas, "D_err": d_err, "nu": a.nu, "Pr": a.nu / d_meas, "J0": j0, "runs": results}
    if above.sum() >= 2:
        ra_c, ra_c_err, slope, icpt = onset(ra[above], nm1[above], err[above])
        print(f"onset: Nu - 1 = {slope:.3e} (Ra - Ra_c) over {int(above.sum())} runs: Ra_c = {ra_c:.0f} +- {ra_c_err:.0f} "
              f"({100 * (ra_c / RA_C - 1):+.1f}% from 1708)")
        summary.update({"ra_c": ra_c, "ra_c_err": ra_c_err, "slope": slope})
        ok = abs(ra_c / RA_C - 1) < 0.2
    else:
        print("onset: fewer than two runs above it")
        ok = False
    below = ra < 0.8 * RA_C
    if np.any(nm1[below] >= 0.05):
        ok = False
        print("a run below 0.8 x 1708 conducts more than 5% above pure conduction")
    json.dump(summary, open(os.path.join(a.out, "rayleigh_benard.json"), "w"), indent=2)
    if a.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4), gridspec_kw={"width_ratios": [1, 1.4]})
        ax1.errorbar(ra, nm1 + 1, yerr=err, fmt="o", label="eDPD (walls' heat)")
        if "ra_c" in summary:
            xx = np.linspace(summary["ra_c"], ra.max(), 50)
            ax1.plot(xx, 1 + summary["slope"] * (xx - summary["ra_c"]), "-", label=f"fit: Ra_c = {summary['ra_c']:.0f}")
        ax1.axvline(RA_C, color="gray", ls="--", label="1708 (rigid walls)")
        ax1.set_xlabel("Ra")
        ax1.set_ylabel("Nu")
        ax1.legend()
        strongest = max(a.ratios)
        im = rolls_picture(dirs[strongest], ax2)
        ax2.set_title(f"Ra = {results[-1]['ra']:.0f}: fluid T and mean flow")
        fig.colorbar(im, ax=ax2, shrink=0.8)
        fig.tight_layout()
        fig.savefig(a.png, dpi=110)
        print(f"wrote {a.png}")
    if a.min_nu is not None:
        strongest = results[-1]
        short_ok = strongest["nu"] >= a.min_nu and not np.any(nm1[ra < 0.8 * RA_C] >= 0.05)
        print(f"short check: Nu = {strongest['nu']:.4f} at Ra = {strongest['ra']:.0f} (needs >= {a.min_nu}): "
              f"{'pass' if short_ok else 'FAIL'}")
        if not short_ok:
            sys.exit(1)
    if a.check and not ok:
        sys.exit(1)


if __name__ == "__main__":
    main()
