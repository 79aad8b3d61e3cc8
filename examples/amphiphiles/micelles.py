#!/usr/bin/python3
"""Self-assembly of amphiphiles from a random start (issue 12; seed 002 "Amphiphilic Systems").

Head-tail molecules H_m T_n (notation of seed 002) in water W, with the repulsion parameters and
bonded interactions of the form used by Shillcock and Lipowsky (J. Chem. Phys. 117, 5048 (2002),
cited by seed 002 as Ref. 110): a_WW = a_TT = 25, a_HH = 30, a_HW = 35, a_HT = 50, a_TW = 75,
gamma = 4.5, rho = 3; harmonic bonds k = 128, r0 = 0.5; the cosine angle potential of seed 002
Eq. 32 with k = 20, theta0 = 0 along every chain (tails straight). The parameter values are quoted
as commonly reproduced from that paper; they were not re-checked against the original here.

Aggregates are found from the tail beads: two molecules belong to one aggregate when a tail bead of
one lies within r_c = 1 of a tail bead of the other (minimum image). The script writes the
aggregation-number distribution (molecules per aggregate, weighted by molecule) averaged over the
last third of the frames with the number of aggregates of each size per frame, its time series
(number of aggregates and the largest), and a snapshot plot.

    /usr/bin/python3 examples/amphiphiles/micelles.py --mesodpd build/mesodpd --out out/amphiphiles \
        [--sequence H3T4] [--fraction 0.1] [--box 12] [--steps 20000] [--every 200] [--analyse-only]

--analyse-only reads the trajectory already in --out (for instance after continuing the run from its
checkpoint with `mesodpd run <out>/config.toml --out <out> --restart <out>/checkpoint.mdpd --steps N`,
which gives the bits of an uninterrupted run).
"""
import argparse
import csv
import os
import subprocess

import numpy as np

# The pair and bonded interactions, shared with bilayer.py.
INTERACTIONS = """\
[pair]
a = 25.0
gamma = 4.5

[[pair.override]]
species = ["H", "H"]
a = 30.0

[[pair.override]]
species = ["H", "W"]
a = 35.0

[[pair.override]]
species = ["H", "T"]
a = 50.0

[[pair.override]]
species = ["T", "W"]
a = 75.0

[[bond_type]]
name = "spring"
style = "harmonic"
k = 128.0
r0 = 0.5

[[angle_type]]
name = "stiff"
k = 20.0
theta0 = 0.0
"""

CONFIG = """
[system]
box = [{box}, {box}, {box}]
kT = 1.0
seed = {seed}

[[species]]
name = "W"
count = {water}

[[species]]
name = "H"

[[species]]
name = "T"

""" + INTERACTIONS + """
[[molecule]]
name = "amphiphile"
sequence = "{sequence}"
bond_type = "spring"
angle_type = "stiff"
count = {molecules}
bond_length = 0.5

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


def aggregates(pos, mol, is_tail, box):
    """Aggregation number of every molecule's aggregate: tail beads within 1.0 connect molecules."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    tails = np.flatnonzero(is_tail)
    p = np.mod(pos[tails], box)
    pairs = cKDTree(p, boxsize=box).query_pairs(1.0, output_type="ndarray")
    mols = np.unique(mol[mol > 0])
    index = {m: k for k, m in enumerate(mols)}
    a = np.array([index[m] for m in mol[tails[pairs[:, 0]]]], dtype=int) if len(pairs) else np.zeros(0, int)
    b = np.array([index[m] for m in mol[tails[pairs[:, 1]]]], dtype=int) if len(pairs) else np.zeros(0, int)
    g = coo_matrix((np.ones(len(a)), (a, b)), shape=(len(mols), len(mols)))
    _, label = connected_components(g, directed=False)
    sizes = np.bincount(label)
    return sizes, label, mols  # molecules per aggregate; aggregate of each molecule id in mols


def shape(pos, box):
    """Principal radii of gyration (ascending) of a cluster of beads in a periodic cubic box: each
    axis centred on its circular mean, then minimum image."""
    theta = 2 * np.pi * pos / box
    centre = box * (np.arctan2(-np.sin(theta).mean(0), -np.cos(theta).mean(0)) + np.pi) / (2 * np.pi)
    d = pos - centre
    d -= box * np.round(d / box)
    return np.sqrt(np.linalg.eigvalsh(d.T @ d / len(d)))


def main():
    ap = argparse.ArgumentParser()
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--mesodpd", default=os.path.join(here, "..", "..", "build", "mesodpd"))
    ap.add_argument("--out", default="out/amphiphiles")
    ap.add_argument("--sequence", default="H3T4")
    ap.add_argument("--fraction", type=float, default=0.1, help="amphiphile bead fraction")
    ap.add_argument("--box", type=float, default=12.0)
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--every", type=int, default=0, help="trajectory frame interval (default: steps / 100)")
    ap.add_argument("--analyse-only", action="store_true", help="analyse the trajectory already in --out")
    a = ap.parse_args()
    import re

    beads = sum(int(c) for c in re.findall(r"(\d+)", a.sequence.replace("(", "").replace(")", "")))
    if "(" in a.sequence:
        raise SystemExit("--sequence: give a linear H_m T_n here")
    total = int(round(3.0 * a.box**3))
    molecules = int(round(a.fraction * total / beads))
    water = total - molecules * beads
    os.makedirs(a.out, exist_ok=True)
    cfg = os.path.join(a.out, "config.toml")
    every = a.every if a.every > 0 else max(1, a.steps // 100)
    if not a.analyse_only:
        with open(cfg, "w") as f:
            f.write(CONFIG.format(box=a.box, seed=a.seed, water=water, sequence=a.sequence, molecules=molecules,
                                  steps=a.steps, every=every))
        subprocess.run([a.mesodpd, "run", cfg, "--out", a.out, "--threads", str(a.threads)], check=True)

    import sys

    import gsd.fl
    import gsd.hoomd

    sys.path.insert(0, os.path.join(here, "..", "..", "tools"))
    from chain_analysis import open_gsd

    path = os.path.join(a.out, "trajectory.gsd")
    low = open_gsd(gsd.fl, path, "r")
    mol = low.read_chunk(0, "log/particles/mol").astype(np.int64)
    low.close()
    with open_gsd(gsd.hoomd, path, "r") as traj:
        types = list(traj[0].particles.types)
        rows = []
        hist = []
        n_frames = len(traj)
        for k, frame in enumerate(traj):
            is_tail = np.asarray(frame.particles.typeid) == types.index("T")
            sizes, label, mols = aggregates(np.asarray(frame.particles.position, float), mol, is_tail, a.box)
            rows.append((int(frame.configuration.step), len(sizes), int(sizes.max()), float(np.mean(sizes))))
            if k >= 2 * n_frames // 3:
                hist.append(sizes)
            last_pos = np.asarray(frame.particles.position, float)
            last_tid = np.asarray(frame.particles.typeid)
    allsizes = np.concatenate(hist)
    nmax = int(allsizes.max())
    # Probability that a molecule sits in an aggregate of size s (molecule-weighted distribution).
    weight = np.bincount(allsizes, weights=allsizes, minlength=nmax + 1)
    weight /= weight.sum()
    mean_weighted = float((np.arange(nmax + 1) * weight).sum())
    with open(os.path.join(a.out, "aggregates_time.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["step", "aggregates", "largest", "mean_size"])
        w.writerows(rows)
    # Aggregates of each size per frame (number distribution).
    per_frame = np.bincount(allsizes, minlength=nmax + 1) / len(hist)
    with open(os.path.join(a.out, "aggregation_number.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["size", "molecule_fraction", "aggregates_per_frame"])
        for s in range(1, nmax + 1):
            if weight[s] > 0:
                w.writerow([s, f"{weight[s]:.5f}", f"{per_frame[s]:.4f}"])
    free = weight[1] if nmax >= 1 else 0.0
    # Shapes of the aggregates of the last frame (10 molecules or more): principal radii of gyration
    # of all their beads; a sphere has three equal radii, a rod one large, a disc one small.
    in_agg = {m: label[k] for k, m in enumerate(mols)}
    for g in np.flatnonzero(sizes >= 10):
        members = np.array([in_agg.get(m, -1) == g for m in mol])
        r = shape(np.mod(last_pos[members], a.box), a.box)
        print(f"last frame: aggregate of {sizes[g]} molecules, principal radii of gyration "
              f"{r[0]:.2f}, {r[1]:.2f}, {r[2]:.2f}")
    print(f"{molecules} x {a.sequence} in {water} W (bead fraction {molecules * beads / total:.3f}); last third: "
          f"{np.mean([r[1] for r in rows[2 * n_frames // 3:]]):.1f} aggregates on average, molecule-weighted mean "
          f"aggregation number {mean_weighted:.1f}, free molecules {100 * free:.1f}%, largest {nmax}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    st = np.array([r[0] for r in rows])
    ax[0].plot(st, [r[1] for r in rows], label="aggregates")
    ax[0].plot(st, [r[2] for r in rows], label="largest (molecules)")
    ax[0].set(xlabel="step", title="from a random start")
    ax[0].legend()
    s = np.arange(nmax + 1)
    ax[1].bar(s[1:], weight[1:])
    ax[1].set(xlabel="aggregation number", ylabel="fraction of molecules", title="last third of the run")
    p = np.mod(last_pos, a.box)
    tid = last_tid
    for name, colour in (("T", "tab:orange"), ("H", "tab:blue")):
        m = tid == types.index(name)
        ax[2].scatter(p[m, 0], p[m, 1], s=3, c=colour, label=name)
    ax[2].set(aspect="equal", xlabel="x", ylabel="y", title="last frame (heads and tails, water hidden)")
    ax[2].legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "aggregates.png"), dpi=100)


if __name__ == "__main__":
    main()
