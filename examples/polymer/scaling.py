#!/usr/bin/python3
"""Radius of gyration against chain length for dilute chains in a good solvent (issue 12, seed 002
"Polymer Solutions and Melts"): R_g ~ N^nu with nu near the Flory value 0.588 (Spenley, Europhys.
Lett. 49, 534 (2000), cited by seed 002). One run per N: a few chains of N beads (harmonic springs
k = 4, r0 = 0) in a DPD solvent at rho = 3, a = 25 for every pair (the chain beads are like the
solvent: an athermal good solvent). Writes rg_vs_n.csv and rg_vs_n.png in --out.

    /usr/bin/python3 examples/polymer/scaling.py --mesodpd build/mesodpd --out out/polymer [--short]

--short: N = 5, 10, 20 with short runs (minutes on 2 cores): a smoke test of the pipeline whose
exponent carries a large error. The full run (N = 5 to 40, 10^5 steps each) takes about 30 minutes (one thread per run).
"""
import argparse
import csv
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
import chain_analysis  # noqa: E402

CONFIG = """
[system]
box = [{box}, {box}, {box}]
kT = 1.0
seed = {seed}

[[species]]
name = "P"

[[species]]
name = "S"
count = {solvent}

[pair]
a = {a}
gamma = 4.5

[[pair.override]]
species = ["P", "S"]
a = {a_ps}

[[bond_type]]
name = "spring"
style = "harmonic"
k = 4.0

[[molecule]]
name = "chain"
sequence = "P{n}"
bond_type = "spring"
count = {chains}
bond_length = 0.8

[integrator]
dt = 0.04

[run]
steps = {steps}

[output]
thermo_every = 1000
progress = false

[output.dump]
format = "gsd"
every = {every}
fields = ["id", "species", "position", "image", "mol"]
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesodpd", default=os.path.join(HERE, "..", "..", "build", "mesodpd"))
    ap.add_argument("--out", default="out/polymer")
    ap.add_argument("--short", action="store_true")
    ap.add_argument("--a-ps", type=float, default=25.0, help="chain-solvent repulsion (larger: poorer solvent)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--steps", type=int, help="steps per run (default 6,000 with --short, else 100,000)")
    ap.add_argument("--n", type=int, nargs="+", help="chain lengths (default 5 10 20, or 5 10 20 40)")
    ap.add_argument("--melt", action="store_true",
                    help="a melt instead: chains only, rho = 3 in a box of --box (R_g ~ N^(1/2) expected)")
    ap.add_argument("--box", type=float, default=10.0, help="box edge of the melt runs (default 10)")
    a = ap.parse_args()
    ns = a.n or ([5, 10, 20] if a.short else [5, 10, 20, 40])
    steps = a.steps or (6000 if a.short else 100000)
    every = 50 if a.short else 200
    rows = []
    for n in ns:
        if a.melt:
            box = a.box
            chains = int(round(3.0 * box**3 / n))
            solvent = 0
        else:
            box = max(8.0, 2.0 * 0.8 * n ** 0.6 + 4.0)  # several R_g across, so a chain does not meet its image
            chains = 4 if a.short else 8
            solvent = int(round(3.0 * box**3)) - chains * n
        d = os.path.join(a.out, f"n{n}")
        os.makedirs(d, exist_ok=True)
        cfg = os.path.join(d, "config.toml")
        with open(cfg, "w") as f:
            f.write(CONFIG.format(box=box, seed=100 + n, solvent=solvent, a=25.0, a_ps=a.a_ps, n=n, chains=chains,
                                  steps=steps, every=every))
        subprocess.run([a.mesodpd, "run", cfg, "--out", d, "--threads", str(a.threads)], check=True)
        res = chain_analysis.analyse(os.path.join(d, "trajectory.gsd"), 0.04, skip=len(range(0, steps + 1, every)) // 5)
        r = res[f"P{n}"]
        chain_analysis.write(res, os.path.join(d, "chains"))
        tb = np.array(r["tau_e_blocks"], float)
        tau_err = float(tb.std(ddof=1) / np.sqrt(len(tb))) if len(tb) > 1 and np.all(np.isfinite(tb)) else float("nan")
        rows.append((n, r["rg2"][0], r["rg2"][1], r["re2"][0], r["re2"][1], r["tau_e"], tau_err))
        print(f"N = {n}: <Rg^2> = {r['rg2'][0]:.4f} +- {r['rg2'][1]:.4f}, tau_e = {r['tau_e']:.3g} +- {tau_err:.2g}"
              f" (quarters: {', '.join(f'{t:.3g}' for t in tb)})", flush=True)
    n = np.array([r[0] for r in rows], float)
    rg = np.sqrt([r[1] for r in rows])
    rg_err = np.array([r[2] for r in rows]) / (2 * rg)
    nu, c = np.polyfit(np.log(n), np.log(rg), 1, w=rg / np.maximum(rg_err, 1e-12))
    cov = np.polyfit(np.log(n), np.log(rg), 1, w=rg / np.maximum(rg_err, 1e-12), cov="unscaled")[1] if len(n) > 2 else None
    nu_err = float(np.sqrt(cov[0, 0])) if cov is not None else float("nan")
    with open(os.path.join(a.out, "rg_vs_n.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["N", "rg2", "rg2_err", "re2", "re2_err", "tau_e", "tau_e_err"])
        w.writerows(rows)
    print(f"nu = {nu:.3f} +- {nu_err:.3f} ({'melt: 0.5 expected' if a.melt else 'Flory 0.588; ideal chain 0.5'})")
    for k in range(len(n) - 1):
        print(f"local nu {n[k]:.0f} -> {n[k + 1]:.0f}: {np.log(rg[k + 1] / rg[k]) / np.log(n[k + 1] / n[k]):.3f}")
    # tau_e ~ N^x over N >= 10 (Rouse: 1 + 2 nu; Zimm: 3 nu), weighted by the quarter-block errors
    tau = np.array([r[5] for r in rows])
    tau_err = np.array([r[6] for r in rows])
    sel = (n >= 10) & np.isfinite(tau) & np.isfinite(tau_err) & (tau_err > 0)
    if sel.sum() >= 3:
        wt = tau[sel] / tau_err[sel]
        p, cv = np.polyfit(np.log(n[sel]), np.log(tau[sel]), 1, w=wt, cov=True)  # error scaled by the scatter
        print(f"tau_e ~ N^x over N = {', '.join(f'{v:.0f}' for v in n[sel])}: x = {p[0]:.2f} +- {np.sqrt(cv[0, 0]):.2f}"
              f" (error scaled by the scatter; Rouse 1 + 2 nu = {1 + 2 * nu:.2f}, Zimm 3 nu = {3 * nu:.2f})")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 4))
    ax.errorbar(n, rg, yerr=rg_err, fmt="o", label="mesodpd")
    xx = np.linspace(n.min(), n.max(), 50)
    ax.plot(xx, np.exp(c) * xx**nu, label=f"fit: $\\nu$ = {nu:.3f} $\\pm$ {nu_err:.3f}")
    ref, ref_name = (0.5, "ideal 1/2") if a.melt else (0.588, "Flory 0.588")
    ax.plot(xx, rg[0] * (xx / n[0]) ** ref, "--", label=ref_name)
    ax.set(xscale="log", yscale="log", xlabel="N (beads)", ylabel="$R_g$")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "rg_vs_n.png"), dpi=110)


if __name__ == "__main__":
    main()
