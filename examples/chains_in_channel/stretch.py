#!/usr/bin/python3
"""Chains in a body-force-driven channel stretch with the shear rate (issue 12, "chains in flow";
seed 000 Sect. 4.3, Fig. 22, where 60 chains of 30 beads pass through a channel).

Bead-spring chains (FENE, k = 30, rmax = 1.5 -- the Kremer-Grest-like spring often used for DPD
chains, e.g. Fan et al., cited by seed 000 as Ref. 75) in the standard DPD solvent (rho = 3, a = 25,
gamma = 4.5, dt = 0.02) between two frozen plates (channel height h = 10, bounce-back reflection),
driven along x by a body force g on every mobile particle. One run per g; g = 0 gives the chains' own
relaxation time tau_e (end-to-end autocorrelation, tools/chain_analysis.py). For each g the script
reports the mean extension along the flow <X> (the x-span of a chain, unwrapped) and <R_e^2>,
against the Weissenberg number Wi = tau_e * mean shear rate, the mean |dv/dz| of the Poiseuille
profile rho g h / (4 eta) with eta = 0.867 (docs/validation.md, section 4; the chains change it
little at this dilution).

    /usr/bin/python3 examples/chains_in_channel/stretch.py --mesodpd build/mesodpd --out out/chains_in_channel \
        [--g 0 0.002 0.005 0.01 0.02] [--steps 20000] [--chains 20] [--beads 20]
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
box = [{lx}, 8.0, 12.0]
periodic = [true, true, false]
kT = 1.0
seed = {seed}

[[species]]
name = "S"
density = 3.0
body_force = [{g}, 0.0, 0.0]

[[species]]
name = "P"
body_force = [{g}, 0.0, 0.0]

[[species]]
name = "wall"
frozen = true

[pair]
a = 25.0
gamma = 4.5

[[solid]]
name = "bottom"
species = "wall"
shape = "plane"
point = [0, 0, 1]
normal = [0, 0, 1]

[[solid]]
name = "top"
species = "wall"
shape = "plane"
point = [0, 0, 11]
normal = [0, 0, -1]

[walls]
reflection = "bounce_back"

[[bond_type]]
name = "fene"
style = "fene"
k = 30.0
rmax = 1.5

[[molecule]]
name = "chain"
sequence = "P{beads}"
bond_type = "fene"
count = {chains}
bond_length = 0.8

[bonds]
reach = 1.5

[integrator]
dt = 0.02

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

ETA = 0.867  # shear viscosity of the solvent (reverse Poiseuille, docs/validation.md section 4)
H = 10.0  # channel height


def x_span(path, skip):
    """Mean x-extent of the chains (unwrapped) over the frames after `skip`."""
    import gsd.fl
    import gsd.hoomd

    low = chain_analysis.open_gsd(gsd.fl, path, "r")
    mol = low.read_chunk(0, "log/particles/mol").astype(np.int64)
    low.close()
    spans = []
    with chain_analysis.open_gsd(gsd.hoomd, path, "r") as traj:
        box = np.array(traj[0].configuration.box[:3], float)
        ids = np.unique(mol[mol > 0])
        rows = [np.flatnonzero(mol == m) for m in ids]
        for k, frame in enumerate(traj):
            if k < skip:
                continue
            x = np.asarray(frame.particles.position[:, 0], float) + np.asarray(frame.particles.image[:, 0]) * box[0]
            spans.append([x[r].max() - x[r].min() for r in rows])
    spans = np.array(spans)
    per_frame = spans.mean(axis=1)
    blocks = np.array_split(per_frame, 5)
    means = np.array([b.mean() for b in blocks])
    return float(means.mean()), float(means.std(ddof=1) / np.sqrt(len(means)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesodpd", default=os.path.join(HERE, "..", "..", "build", "mesodpd"))
    ap.add_argument("--out", default="out/chains_in_channel")
    ap.add_argument("--g", type=float, nargs="+", default=[0.0, 0.002, 0.005, 0.01, 0.02])
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--chains", type=int, default=20)
    ap.add_argument("--beads", type=int, default=20)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--tau", type=float, help="relaxation time and mean bond length of the chains at rest, "
                    "as 'tau bond' from an earlier g = 0 run (then --g need not start with 0)", nargs=2)
    a = ap.parse_args()
    if a.g[0] != 0.0 and not a.tau:
        raise SystemExit("--g: the first value must be 0 (the relaxation time comes from it), or give --tau")
    every = max(1, a.steps // 200)
    skip = 40  # of 200 frames: the flow develops in rho (h/pi)^2 / eta ~ 35 time units
    rows = []
    tau, bond = a.tau if a.tau else (None, None)
    for g in a.g:
        d = os.path.join(a.out, f"g{g:g}")
        os.makedirs(d, exist_ok=True)
        cfg = os.path.join(d, "config.toml")
        with open(cfg, "w") as f:
            f.write(CONFIG.format(lx=30.0, seed=21, g=g, beads=a.beads, chains=a.chains, steps=a.steps, every=every))
        subprocess.run([a.mesodpd, "run", cfg, "--out", d, "--threads", str(a.threads)], check=True)
        traj = os.path.join(d, "trajectory.gsd")
        res = chain_analysis.analyse(traj, 0.02, skip=skip)[f"P{a.beads}"]  # dt: time per step
        if tau is None:
            tau = res["tau_e"]
            bond = float(np.mean(res["bond_lengths"]))
        span, span_err = x_span(traj, skip)
        shear = 3.0 * g * H / (4.0 * ETA)
        rows.append((g, shear, tau * shear, span, span_err, res["re2"][0], res["re2"][1]))
        print(f"g = {g:g}: mean shear rate {shear:.4f}, Wi = {tau * shear:.2f}, <X> = {span:.3f} +- {span_err:.3f}, "
              f"<R_e^2> = {res['re2'][0]:.2f} +- {res['re2'][1]:.2f} (tau_e at g = 0: {tau:.3g})", flush=True)
    with open(os.path.join(a.out, "extension.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["g", "mean_shear_rate", "Wi", "x_span", "x_span_err", "re2", "re2_err"])
        w.writerows(rows)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    r = np.array(rows)
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.errorbar(r[:, 2], r[:, 3], yerr=r[:, 4], fmt="o-")
    ax.axhline(bond * (a.beads - 1), ls="--", c="gray", label=f"contour length ({a.beads - 1} x {bond:.2f})")
    ax.set(xlabel="Wi = tau_e x mean shear rate", ylabel="<X> (chain span along the flow)",
           title=f"{a.chains} chains of {a.beads} beads in a channel")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "extension.png"), dpi=110)


if __name__ == "__main__":
    main()
