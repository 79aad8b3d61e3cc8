#!/usr/bin/python3
"""Permeability of the pillar-array runs against Spielman-Goren (seed 004 Eqs 12-13; README.md).

usage: analyze.py CONFIG_DIR RUNS_DIR [--mu MU] [--mu-err ERR] [--start STEP]
                  [--plot-dir DIR] [--json FILE]

CONFIG_DIR holds the configs and runs.txt written by make_configs.py; RUNS_DIR/<name> is the --out
folder of `mesodpd run CONFIG_DIR/<name>.toml`. Runs that are missing are skipped (with a note).

Per run, from drag.csv (the mass-weighted mean fluid velocity every walls.drag_every steps) after
the first sampled step (walls.drag_start, or --start), and from the time-averaged fields (flow.csv):
  v_i   mean interstitial velocity: the mean x velocity of the fluid particles. Its error is the
        larger of (a) the autocorrelation estimate (integrated autocorrelation time tau_int, Sokal's
        window) and (b) that of a mean flow that relaxes in tau_flow = v_i / g (the Darcy friction:
        dv/dt = g - v / tau_flow) with the variance of the series or kT / N_f, whichever is larger:
        sigma^2 = var x 2 tau_flow / T. The open arrays relax slowly (tau_flow = 40 time units at
        phi = 0.05) and a run samples only a few tau_flow, too few for (a) to see the slow tail.
        The halves of the sampled run are compared (drift, in standard errors);
  n_b   fluid bulk density: mean density of the field bins more than 1 r_c from every pillar surface;
  u_D   Darcy (superficial) velocity: total fluid momentum / (n_b x the cell volume, solid included)
        = N_f v_i / (n_b V) with N_f the number of fluid particles (m = 1);
  K     permeability K = u_D mu / (n_b g) (seed 004 Eq. 13; n_b g is the body force per unit fluid
        volume) and K/d^2; Re = n_b u_D d / mu;
  phi'  the solid fraction that Spielman-Goren predicts from the measured K, for the form printed in
        seed 004 Eq. 12 (with the diameter d) and for the radius form (with a = d/2):
            1/(4 phi') = 1/2 + (sqrt(K)/R) K1(R/sqrt(K)) / K0(R/sqrt(K)),  R = d or d/2;
  F     mean x force on the pillars against the body force on the fluid, N_f g (momentum balance).
Per lattice and phi, the Darcy velocities of all g values are fitted by u_D = c g through the origin
(weights from their errors): c, chi^2 per degree of freedom, and K = c mu / n_b, the K of the
table and of the figure.

--mu is the fluid viscosity (seed 004 quotes 2.40; the default). --plot-dir writes
pillar_array_permeability.png (K/d^2 against phi with both Spielman-Goren curves) and
pillar_array_darcy.png (u_D against g, as seed 004 Figs 11-12). Prints markdown tables.
"""
import argparse
import json
import math
import os
import sys
import tomllib

import numpy as np
from scipy.optimize import brentq
from scipy.special import k0e, k1e

DIAMETER = 6.0


# --- Spielman-Goren --------------------------------------------------------------------------------
def bessel_ratio(x):
    """K1(x) / K0(x), from the exponentially scaled functions (no underflow at large x)."""
    return k1e(x) / k0e(x)


def sg_rhs(k_over_r2):
    """1/2 + (sqrt(K)/R) K1(R/sqrt K) / K0(R/sqrt K) as a function of K / R^2."""
    x = 1.0 / math.sqrt(k_over_r2)
    return 0.5 + bessel_ratio(x) / x


def sg_phi(k, r):
    """phi' = 1 / (4 (1/2 + ...)) predicted for the permeability k with fibres of 'radius' r."""
    return 1.0 / (4.0 * sg_rhs(k / r**2))


def sg_permeability(phi, r):
    """K solving 1/(4 phi) = 1/2 + (sqrt K / r) K1(r / sqrt K) / K0(r / sqrt K); none for phi >= 1/2."""
    if not 0 < phi < 0.5:
        return math.nan
    target = 1.0 / (4.0 * phi)
    # The right-hand side falls from +inf (x -> 0) to 1/2 (x -> inf) monotonically in x = r / sqrt(K).
    x = brentq(lambda x: 0.5 + bessel_ratio(x) / x - target, 1e-9, 1e7, xtol=1e-14)
    return (r / x) ** 2


# --- one run ---------------------------------------------------------------------------------------
def pillar_centres(lattice, spacing, point, lx, lz):
    """Pillar centres (x, z) in the cell (axis y): the lattice through `point`, wrapped into the box."""
    px, pz = point[0], point[2]
    if lattice == "square":
        pts = [(px, pz)]
    else:
        pts = [(px, pz), (px + spacing / 2, pz + math.sqrt(3) * spacing / 2)]
    return [(x % lx, z % lz) for x, z in pts]


def acf_error(values, window=5.0):
    """Mean, its standard error and the integrated autocorrelation time (in samples) of a correlated
    series: tau_int = 1/2 + sum of the normalised autocorrelation up to the lag M, the first M with
    M >= window x tau_int (Sokal's automatic window); var(mean) = var x 2 tau_int / n."""
    x = np.asarray(values, float)
    n = len(x)
    d = x - x.mean()
    f = np.fft.rfft(d, 2 * n)
    acf = np.fft.irfft(f * np.conj(f))[:n] / np.arange(n, 0, -1)
    acf /= acf[0]
    tau = 0.5
    for m in range(1, n):
        tau += acf[m]
        if m >= window * tau:
            break
    return float(x.mean()), float(math.sqrt(d.var() * 2 * tau / n)), tau


def velocity_error(values, tau_flow, floor_variance):
    """Mean of the fluid velocity series and its error: the larger of the autocorrelation estimate
    and that of a mean flow relaxing in tau_flow samples (an exponential autocorrelation) with the
    variance max(sample variance, floor_variance): var(mean) = var x 2 tau_flow / n."""
    mean, err, tau = acf_error(values)
    x = np.asarray(values, float)
    model = math.sqrt(max(x.var(), floor_variance) * 2 * tau_flow / len(x))
    return mean, max(err, model), tau


def read_csv(path):
    data = np.genfromtxt(path, delimiter=",", names=True, dtype=float)
    return np.atleast_1d(data)


def analyze_run(config_path, out_dir, mu, start=None):
    with open(config_path, "rb") as f:
        cfg = tomllib.load(f)
    lx, ly, lz = cfg["system"]["box"]
    fluid = cfg["species"][0]
    g = fluid["body_force"][0]
    solid = cfg["solid"][0]
    if solid["shape"] != "pillars" or solid.get("axis") != "y":
        sys.exit(f"analyze.py: {config_path}: expected one [[solid]] of shape 'pillars' along y")
    lattice, spacing, radius = solid["lattice"], solid["spacing"], solid["radius"]
    per_cell = 1 if lattice == "square" else 2
    volume = lx * ly * lz
    phi = per_cell * math.pi * radius**2 / (lx * lz)
    first = cfg["walls"].get("drag_start", 0) if start is None else start

    drag = read_csv(os.path.join(out_dir, "drag.csv"))
    keep = drag["step"] > first
    if keep.sum() < 100:
        sys.exit(f"analyze.py: {out_dir}/drag.csv: only {int(keep.sum())} samples after step {first}")
    vx = drag["fluid_vx"][keep]
    fx = drag["pillars_fx"][keep]
    every = int(drag["step"][1] - drag["step"][0])
    sample_time = every * cfg["integrator"]["dt"]
    # The mean flow relaxes as dv/dt = g - v / tau_flow (the Darcy friction), so tau_flow = v / g
    # (square phi = 0.05: 43.5 time units; a fit of its start-up gives 45-48, README.md). The
    # equilibrium variance of the mean velocity of N_f particles of mass 1 is kT / N_f.
    v_rough = float(np.mean(vx))
    tau_flow = max(v_rough / g, 0.0) / sample_time
    kt = cfg["system"].get("kT", 1.0)
    fields = read_csv(os.path.join(out_dir, "flow.csv"))
    with open(os.path.join(out_dir, "flow.json")) as f:
        bin_volume = json.load(f)["bin_volume"]
    n_fluid = float(fields["density_fluid"].sum() * bin_volume)
    floor = kt / n_fluid
    v_i, v_err, tau = velocity_error(vx, tau_flow, floor)
    half = len(vx) // 2
    v1, e1, _ = velocity_error(vx[:half], tau_flow, floor)
    v2, e2, _ = velocity_error(vx[half:], tau_flow, floor)
    f_mean, f_err, _ = acf_error(fx)

    centres = pillar_centres(lattice, spacing, solid.get("point", [0, 0, 0]), lx, lz)
    gap = np.full(fields.size, np.inf)
    for cx, cz in centres:
        dx = (fields["x"] - cx + lx / 2) % lx - lx / 2
        dz = (fields["z"] - cz + lz / 2) % lz - lz / 2
        gap = np.minimum(gap, np.hypot(dx, dz) - radius)
    bulk = gap > 1.0
    n_bulk = float(fields["density_fluid"][bulk].mean())
    near = (gap > 0) & (gap < 0.5)
    n_near = float(fields["density_fluid"][near].mean())

    u_d = n_fluid * v_i / (n_bulk * volume)
    u_d_err = n_fluid * v_err / (n_bulk * volume)
    k = u_d * mu / (n_bulk * g)
    k_err = abs(k) * v_err / abs(v_i)
    penetrations = None
    summary = os.path.join(out_dir, "drag_summary.csv")
    if os.path.exists(summary):
        penetrations = int(read_csv(summary)["penetrations"][0])
    return {
        "name": os.path.basename(os.path.normpath(out_dir)), "lattice": lattice, "phi": phi, "g": g,
        "L": spacing, "box": [lx, ly, lz], "samples": int(keep.sum()),
        "tau_int": tau * sample_time, "tau_flow": tau_flow * sample_time, "first_step": int(first),
        "last_step": int(drag["step"][-1]), "n_fluid": n_fluid, "n_bulk": n_bulk, "n_near": n_near,
        "v_i": v_i, "v_i_err": v_err, "half1": v1, "half1_err": e1, "half2": v2, "half2_err": e2,
        "drift_sigma": (v2 - v1) / math.hypot(e1, e2), "u_d": u_d, "u_d_err": u_d_err,
        "K": k, "K_err": k_err, "K_d2": k / DIAMETER**2, "K_d2_err": k_err / DIAMETER**2,
        "Re": n_bulk * u_d * DIAMETER / mu, "drag": f_mean, "drag_err": f_err, "body_force": n_fluid * g,
        "penetrations": penetrations,
    }


# --- groups: u_D = c g per lattice and phi ---------------------------------------------------------
def fit_through_origin(g, u, err):
    g, u, err = map(np.asarray, (g, u, err))
    w = 1.0 / err**2
    c = float((w * g * u).sum() / (w * g * g).sum())
    c_err = float(1.0 / math.sqrt((w * g * g).sum()))
    chi2 = float((w * (u - c * g) ** 2).sum())
    dof = len(g) - 1
    return c, c_err, chi2 / dof if dof > 0 else math.nan


def group_runs(runs, mu, mu_err):
    groups = {}
    for r in runs:
        groups.setdefault((r["lattice"], round(r["phi"], 4)), []).append(r)
    out = []
    for (lattice, phi), rs in sorted(groups.items()):
        rs.sort(key=lambda r: r["g"])
        c, c_err, chi2 = fit_through_origin([r["g"] for r in rs], [r["u_d"] for r in rs], [r["u_d_err"] for r in rs])
        n_b = float(np.mean([r["n_bulk"] for r in rs]))
        k = c * mu / n_b
        k_err_stat = c_err * mu / n_b
        k_err = math.hypot(k_err_stat, k * mu_err / mu)
        out.append({
            "lattice": lattice, "phi": phi, "g": [r["g"] for r in rs], "c": c, "c_err": c_err, "chi2_dof": chi2,
            "K": k, "K_err_stat": k_err_stat, "K_err": k_err, "K_d2": k / DIAMETER**2, "K_d2_err": k_err / DIAMETER**2,
            "phi_printed": sg_phi(k, DIAMETER), "phi_radius": sg_phi(k, DIAMETER / 2),
            # the phi' interval from K +- its statistical error
            "phi_radius_range": sorted([sg_phi(k + k_err_stat, DIAMETER / 2),
                                        sg_phi(max(k - k_err_stat, 1e-12), DIAMETER / 2)]),
            "K_d2_sg_printed": sg_permeability(phi, DIAMETER) / DIAMETER**2,
            "K_d2_sg_radius": sg_permeability(phi, DIAMETER / 2) / DIAMETER**2,
        })
    return out


# --- output ----------------------------------------------------------------------------------------
def print_tables(runs, groups, mu, mu_err):
    print(f"mu = {mu} +- {mu_err}\n")
    print("| run | steps sampled | N_f | n_b | n near surface / n_b | v_i (interstitial) | u_D (Darcy) | "
          "tau_int, v_i/g | halves: 2nd - 1st (sigma) | Re | K/d^2 | pillar drag / N_f g | penetrations |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in runs:
        print(f"| {r['name']} | {r['first_step']}-{r['last_step']} | {r['n_fluid']:.0f} | {r['n_bulk']:.3f} | "
              f"{r['n_near'] / r['n_bulk']:.3f} | {r['v_i']:.4f} +- {r['v_i_err']:.4f} | "
              f"{r['u_d']:.4f} +- {r['u_d_err']:.4f} | {r['tau_int']:.1f}, {r['tau_flow']:.1f} | "
              f"{r['drift_sigma']:+.1f} | {r['Re']:.2f} | {r['K_d2']:.4f} +- {r['K_d2_err']:.4f} | "
              f"{r['drag'] / r['body_force']:.3f} +- {r['drag_err'] / r['body_force']:.3f} | {r['penetrations']} |")
    print("\n| lattice | phi | g values | c = u_D / g | chi^2/dof | K/d^2 measured | K/d^2 SG radius form | "
          "K/d^2 SG printed (d) form | phi' radius form | phi' printed form |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for q in groups:
        chi = "-" if math.isnan(q["chi2_dof"]) else f"{q['chi2_dof']:.2f}"
        lo, hi = q["phi_radius_range"]
        print(f"| {q['lattice']} | {q['phi']:g} | {', '.join(f'{g:g}' for g in q['g'])} | "
              f"{q['c']:.3f} +- {q['c_err']:.3f} | {chi} | {q['K_d2']:.4f} +- {q['K_d2_err']:.4f} | "
              f"{q['K_d2_sg_radius']:.4f} | {q['K_d2_sg_printed']:.4f} | {q['phi_radius']:.3f} ({lo:.3f}-{hi:.3f}) | "
              f"{q['phi_printed']:.3f} |")


def plot(runs, groups, plot_dir):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(plot_dir, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    phis = np.linspace(0.02, 0.495, 300)
    ax.plot(phis, [sg_permeability(p, DIAMETER / 2) / DIAMETER**2 for p in phis], "k-",
            label="Spielman-Goren, radius form (R = d/2)")
    ax.plot(phis, [sg_permeability(p, DIAMETER) / DIAMETER**2 for p in phis], "k--",
            label="Spielman-Goren as printed (seed 004 Eq. 12, d)")
    for lattice, marker, shift in (("square", "o", 0.0), ("hexagonal", "s", 0.004)):
        qs = [q for q in groups if q["lattice"] == lattice]
        if qs:
            ax.errorbar([q["phi"] + shift for q in qs], [q["K_d2"] for q in qs], yerr=[q["K_d2_err"] for q in qs],
                        fmt=marker, mfc="none", capsize=3, label=f"DPD, {lattice} array")
    ax.set_yscale("log")
    ax.set_xlim(0, 0.5)
    ax.set_xlabel("solid fraction phi")
    ax.set_ylabel("K / d^2")
    ax.set_title("Permeability of pillar arrays (d = 6)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(plot_dir, "pillar_array_permeability.png"), dpi=130)
    plt.close(fig)

    multi = [q for q in groups if len(q["g"]) > 1]
    if not multi:
        return
    lattices = sorted({q["lattice"] for q in multi}, reverse=True)
    fig, axes = plt.subplots(1, len(lattices), figsize=(5.2 * len(lattices), 4.2), squeeze=False)
    for ax, lattice in zip(axes[0], lattices):
        for q in (q for q in multi if q["lattice"] == lattice):
            rs = sorted((r for r in runs if r["lattice"] == lattice and round(r["phi"], 4) == q["phi"]),
                        key=lambda r: r["g"])
            g = np.array([r["g"] for r in rs])
            line = ax.errorbar(g, [r["u_d"] for r in rs], yerr=[r["u_d_err"] for r in rs], fmt="o", capsize=3,
                               label=f"phi = {q['phi']:g} (phi' = {q['phi_radius']:.3f}, radius form)")
            gg = np.array([g.min() / 1.3, g.max() * 1.3])
            ax.plot(gg, q["c"] * gg, "-", color=line[0].get_color())
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("body force g")
        ax.set_ylabel("Darcy velocity u_D")
        ax.set_title(f"{lattice} array: fits u_D = c g (slope 1)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(plot_dir, "pillar_array_darcy.png"), dpi=130)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("config_dir")
    ap.add_argument("runs_dir")
    ap.add_argument("--mu", type=float, default=2.40, help="fluid viscosity (seed 004: 2.40)")
    ap.add_argument("--mu-err", type=float, default=0.0)
    ap.add_argument("--start", type=int, help="first sampled step (default: walls.drag_start of each config)")
    ap.add_argument("--plot-dir")
    ap.add_argument("--json")
    args = ap.parse_args()
    with open(os.path.join(args.config_dir, "runs.txt")) as f:
        names = [line.strip() for line in f if line.strip()]
    runs = []
    for name in names:
        out = os.path.join(args.runs_dir, name)
        if not os.path.exists(os.path.join(out, "flow.csv")):
            print(f"note: {out}: no finished run, skipped", file=sys.stderr)
            continue
        runs.append(analyze_run(os.path.join(args.config_dir, name + ".toml"), out, args.mu, args.start))
    if not runs:
        sys.exit("analyze.py: no finished runs")
    groups = group_runs(runs, args.mu, args.mu_err)
    print_tables(runs, groups, args.mu, args.mu_err)
    if args.plot_dir:
        plot(runs, groups, args.plot_dir)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"mu": args.mu, "mu_err": args.mu_err, "runs": runs, "groups": groups}, f, indent=1)


if __name__ == "__main__":
    main()
