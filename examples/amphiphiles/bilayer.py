#!/usr/bin/python3
"""A pre-assembled amphiphile bilayer: tension against area per molecule, the area at zero tension and
the lateral stress profile (issue 12, "Amphiphiles"; seed 002 "Amphiphilic Systems": Shillcock and
Lipowsky measured the lateral stress profile of DPD bilayers and its dependence on the amphiphile's
architecture, and "lipid bilayers around cells are often close to a tension-free state").

The molecules are H3(T4)2 (seed 002 notation): three head beads in a line and two tails of four tail
beads, both bonded to the last head bead (the convention of the [[molecule]] builder). Interaction
parameters as in micelles.py (the form used by Shillcock and Lipowsky, J. Chem. Phys. 117, 5048 (2002),
seed 002 Ref. 110; values as commonly quoted from that paper, not re-checked against it here):
a_WW = a_TT = 25, a_HH = 30, a_HW = 35, a_HT = 50, a_TW = 75, gamma = 4.5, rho = 3, dt = 0.02; harmonic
bonds k = 128, r0 = 0.5; the cosine angle potential of seed 002 Eq. 32, k = 20, theta0 = 0, on every
triple along the chain from the first head bead into each tail (H1-H2-H3, H2-H3-T1, H3-T1-T2, ... for
both tails); there is no angle between the two tails (the builder would add one, T1-H3-T1', whose
theta0 = 0 pushes the tails apart, so this script writes its own data file).

For each projected area per molecule a (per leaflet: a = Lx Ly / (M / 2)) the script writes a LAMMPS
data file with M molecules in two flat leaflets on square lattices around z = Lz / 2 and water in the
rest of the box, Lx = Ly = sqrt(a M / 2) and Lz = N / (3 Lx Ly), so that the particle count N and the
density rho = 3 stay fixed; it runs mesodpd with [analysis.stress_profile] and reads the tension
gamma = int (p_N - p_T) dz = Lz (P_zz - (P_xx + P_yy) / 2) (the membrane's tension). A straight line
through the two points on each side of gamma = 0 gives the tensionless area a0 (error by propagating the fit's
covariance). Written: bilayer_scan.csv (a, box, tension from the profile and from thermo.csv's full
tensor, errors), bilayer.png (gamma(a) with the fit, and the stress profile of the run nearest a0).

    nice -n 19 /usr/bin/python3 examples/amphiphiles/bilayer.py --mesodpd build/mesodpd --out out/bilayer
"""
import argparse
import csv
import json
import math
import os
import subprocess

import numpy as np

from micelles import interactions  # the same pair, bond and angle parameters


# The run's config: CONFIG (shared with bilayer_assembly.py), then PROFILE (the stress profile along z)
# and, with --dump-every, DUMP.
CONFIG = """
[system]
box = [{lx:.10f}, {ly:.10f}, {lz:.10f}]
kT = 1.0
seed = {seed}

[[species]]
name = "W"

[[species]]
name = "H"

[[species]]
name = "T"

[init]
lammps_data = "bilayer.data"
velocities = "maxwell"

{interactions}
[integrator]
dt = {dt}

[run]
steps = {steps}

[output]
thermo_every = 50
progress = false
"""

PROFILE = """
[analysis.stress_profile]
axis = "z"
bins = {bins}
start = {start}
every = {every}
blocks = 10
"""

DUMP = """
[output.dump]
format = "gsd"
every = {every}
fields = ["id", "species", "position", "image", "mol"]
"""


class Molecule:
    """A branched amphiphile as a tree of beads: species[i] and parent[i] (-1 for the first bead; a
    bead's parent always comes before it). Bonds join every bead to its parent; angles are the triples
    (grandparent, parent, bead) along each chain from the first bead, kept when their species pattern
    is in `angle_patterns` (read in either direction; None keeps them all). lane[i] is the bead's
    sideways offset (in units of 0.25) in the pre-assembled bilayer, where each bead sits at a height
    given by its distance along the bonds from the first bead."""

    def __init__(self, name, species, parent, lane, angle_patterns=None):
        self.name, self.species, self.parent, self.lane = name, species, parent, lane
        self.depth = []
        for p in parent:
            self.depth.append(0 if p < 0 else self.depth[p] + 1)
        local_bonds = [(p, i) for i, p in enumerate(parent) if p >= 0]
        self.local_angles = []
        for i, p in enumerate(parent):
            if p >= 0 and parent[p] >= 0:
                pattern = species[parent[p]] + species[p] + species[i]
                if angle_patterns is None or pattern in angle_patterns or pattern[::-1] in angle_patterns:
                    self.local_angles.append((parent[p], p, i))
        self.local_bonds = local_bonds

    def __len__(self):
        return len(self.species)

    def topology(self, first):
        """Bonds and angles (atom ids) of the molecule whose first bead has id `first`."""
        return ([(first + a, first + b) for a, b in self.local_bonds],
                [(first + a, first + b, first + c) for a, b, c in self.local_angles])


# H3(T4)2: three heads in a line, two tails of four both bonded to the last head; an angle on every
# triple along each chain, none between the two tails (T1-H3-T1').
H3T4_2 = Molecule("H3(T4)2", list("HHH" + "TTTT" + "TTTT"), [-1, 0, 1, 2, 3, 4, 5, 2, 7, 8, 9],
                  [0, 0, 0, -1, -1, -1, -1, 1, 1, 1, 1])
# Osprey-DPD examples/dmpci.bilayer: Polymer Lipid " (H H (* (T T T T T T)) H T T T T T T) ": a side
# branch of six T on the second head, then the third head and six T (Osprey's parser bonds a branch
# to the bead before it and goes on from that bead); BondPair H T T and T T T only.
OSPREY_LIPID = Molecule("H(T6)H(T6) (Osprey-DPD dmpci.bilayer)", list("HH" + "T" * 6 + "H" + "T" * 6),
                        [-1, 0, 1, 2, 3, 4, 5, 6, 1, 8, 9, 10, 11, 12, 13],
                        [0, 0, -1, -1, -1, -1, -1, -1, 0, 1, 1, 1, 1, 1, 1], angle_patterns={"HTT", "TTT"})

# Parameter sets (README.md, "Parameters"): the molecule, its [pair]/[bond]/[angle] text and dt.
PARAMETER_SETS = {
    "A": dict(molecule=H3T4_2, interactions=interactions(), dt=0.02),
    # Repulsions, bonds and BondPair (angle) constants as read in Osprey-DPD examples/dmpci.bilayer
    # (repulsions attributed there to Grafmueller et al., Biophys. J. 96, 2658 (2009)); that file runs
    # at dt = 0.005 then 0.01, here 0.02 as for set A.
    "osprey": dict(molecule=OSPREY_LIPID, dt=0.02,
                   interactions=interactions(a_tw=75, a_hw=30, a_hh=30, a_ht=35, a_tt=10, angle_k=15)),
}


def lipid(mol, x, y, zm, up, bond=0.5):
    """Beads (species, x, y, z) of one molecule standing along z, heads away from the mid-plane zm."""
    s = 1.0 if up else -1.0
    top = max(mol.depth)
    return [(sp, x + ln * 0.25, y, zm + s * (0.25 + (top - d) * bond))
            for sp, ln, d in zip(mol.species, mol.lane, mol.depth)]


def write_lammps_data(path, title, box, atoms, bonds, angles):
    """A LAMMPS data file (atom style molecular, types W = 1, H = 2, T = 3, one bond and one angle
    type) of atoms (mol, species, x, y, z) in the box (Lx, Ly, Lz) with its corner at the origin."""
    type_of = {"W": 1, "H": 2, "T": 3}
    lx, ly, lz = box
    with open(path, "w") as f:
        f.write(f"{title}\n\n{len(atoms)} atoms\n3 atom types\n"
                f"{len(bonds)} bonds\n1 bond types\n{len(angles)} angles\n1 angle types\n\n"
                f"0 {lx:.10f} xlo xhi\n0 {ly:.10f} ylo yhi\n0 {lz:.10f} zlo zhi\n\nAtoms # molecular\n\n")
        for k, (mo, sp, x, y, z) in enumerate(atoms):
            f.write(f"{k + 1} {mo} {type_of[sp]} {x:.8f} {y:.8f} {z:.8f}\n")
        f.write("\nBonds\n\n")
        for k, (a, b) in enumerate(bonds):
            f.write(f"{k + 1} 1 {a} {b}\n")
        f.write("\nAngles\n\n")
        for k, (a, b, c) in enumerate(angles):
            f.write(f"{k + 1} 1 {a} {b} {c}\n")


def write_data(path, n_side, area, total, seed, mol=H3T4_2):
    """The data file of 2 n_side^2 molecules at area per molecule `area`; returns (Lx, Lz)."""
    m = 2 * n_side * n_side
    lx = math.sqrt(area * m / 2)
    lz = total / (3.0 * lx * lx)
    zm = lz / 2
    atoms, bonds, angles = [], [], []
    step = lx / n_side
    mo = 0
    for leaflet, shift in ((True, 0.25), (False, 0.75)):
        for i in range(n_side):
            for j in range(n_side):
                mo += 1
                first = len(atoms) + 1
                for sp, x, y, z in lipid(mol, (i + shift) * step, (j + shift) * step, zm, leaflet):
                    atoms.append((mo, sp, x % lx, y % lx, z))
                b, a = mol.topology(first)
                bonds += b
                angles += a
    half = (max(mol.depth) + 1) * 0.5 + 0.25  # the bilayer's half thickness as placed
    water = total - len(atoms)
    rng = np.random.default_rng(seed)
    span = lz - 2 * half
    if span < 1.0:
        raise SystemExit(f"area {area}: box too thin for the bilayer (Lz = {lz:.2f}); raise --total")
    for _ in range(water):
        x, y = rng.uniform(0, lx, 2)
        z = (zm + half + rng.uniform(0, span)) % lz
        atoms.append((0, "W", x, y, z))
    write_lammps_data(path, f"{mol.name} bilayer, area per molecule {area}", (lx, lx, lz), atoms, bonds, angles)
    return lx, lz


def thermo_tension(path, start, lz, axis="z"):
    """L_n (P_nn - (P_aa + P_bb) / 2) along the normal `axis` (L_n = lz, its box length) from
    thermo.csv's full tensor (with the dissipative and random forces) from step `start`, mean and a
    10-block error bar."""
    a, b = [c for c in "xyz" if c != axis]
    with open(path) as f:
        rows = [r for r in csv.DictReader(f) if int(r["step"]) >= start]
    g = np.array([lz * (float(r[f"p{axis}{axis}"]) - 0.5 * (float(r[f"p{a}{a}"]) + float(r[f"p{b}{b}"])))
                  for r in rows])
    nb = 10
    per = len(g) // nb
    blocks = g[len(g) - per * nb:].reshape(nb, per).mean(axis=1)
    return float(g.mean()), float(blocks.std(ddof=1) / math.sqrt(nb))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesodpd", default=os.path.join(here, "..", "..", "build", "mesodpd"))
    ap.add_argument("--out", default="out/bilayer")
    ap.add_argument("--n-side", type=int, default=8, help="molecules per leaflet = n_side^2")
    ap.add_argument("--total", type=int, default=3000, help="particles (molecule beads + water)")
    ap.add_argument("--areas", default="1.0,1.1,1.2,1.3,1.4", help="areas per molecule to run")
    ap.add_argument("--steps", type=int, default=15000)
    ap.add_argument("--start", type=int, default=3000, help="first step of the averages")
    ap.add_argument("--every", type=int, default=50)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--set", default="A", choices=sorted(PARAMETER_SETS), help="parameter set (README.md)")
    ap.add_argument("--dt", type=float, default=0.0, help="time step (default: the set's, 0.02)")
    ap.add_argument("--dump-every", type=int, default=0, help="also write a GSD trajectory (0: none)")
    ap.add_argument("--plot-only", action="store_true", help="collect the existing runs in --out")
    a = ap.parse_args()
    pset = PARAMETER_SETS[a.set]
    areas = [float(v) for v in a.areas.split(",")]
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for area in areas:
        d = os.path.join(a.out, f"a{area:.3f}")
        os.makedirs(d, exist_ok=True)
        lx, lz = write_data(os.path.join(d, "bilayer.data"), a.n_side, area, a.total, a.seed, pset["molecule"])
        if not a.plot_only:
            with open(os.path.join(d, "config.toml"), "w") as f:
                f.write(CONFIG.format(lx=lx, ly=lx, lz=lz, seed=a.seed, steps=a.steps,
                                      interactions=pset["interactions"], dt=a.dt or pset["dt"])
                        + PROFILE.format(bins=int(round(lz / 0.2)), start=a.start, every=a.every)
                        + (DUMP.format(every=a.dump_every) if a.dump_every else ""))
            subprocess.run([a.mesodpd, "run", os.path.join(d, "config.toml"), "--out", d, "--threads",
                            str(a.threads)], check=True)
        with open(os.path.join(d, "stress_profile.json")) as f:
            sp = json.load(f)
        gt, gt_err = thermo_tension(os.path.join(d, "thermo.csv"), a.start, lz)
        rows.append(dict(area=area, lx=lx, lz=lz, tension=sp["tension"], tension_err=sp["tension_err"],
                         tension_thermo=gt, tension_thermo_err=gt_err, samples=sp["samples"]))
        print(f"a = {area:.3f}: Lx = Ly = {lx:.4f}, Lz = {lz:.4f}, tension {sp['tension']:.3f} +- "
              f"{sp['tension_err']:.3f} (profile), {gt:.3f} +- {gt_err:.3f} (thermo.csv, all forces)")
    with open(os.path.join(a.out, "bilayer_scan.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    # Zero tension: a weighted straight line through the points around the sign change.
    x = np.array([r["area"] for r in rows])
    y = np.array([r["tension"] for r in rows])
    e = np.array([r["tension_err"] for r in rows])
    fit = None
    order = np.argsort(x)
    x, y, e = x[order], y[order], e[order]
    rows = [rows[k] for k in order]
    change = [k for k in range(len(x) - 1) if y[k] < 0 <= y[k + 1]]
    if change:
        # gamma(a) is not straight over a wide range: the line goes through the two points on each
        # side of the first sign change.
        k = change[0]
        pick = slice(max(0, k - 1), min(len(x), k + 3))
        (slope, icpt), cov = np.polyfit(x[pick], y[pick], 1, w=1 / e[pick], cov="unscaled")
        a0 = -icpt / slope
        # Var(a0) from the covariance of (slope, intercept): a0 = -c/b.
        g = np.array([icpt / slope**2, -1 / slope])
        a0_err = float(np.sqrt(g @ cov @ g))
        fit = (slope, icpt, a0, a0_err, x[pick])
        print(f"zero tension at a0 = {a0:.4f} +- {a0_err:.4f} per molecule (slope dgamma/da = {slope:.2f}, "
              f"area stretching modulus K_A ~ a0 dgamma/da = {a0 * slope:.1f})")
        with open(os.path.join(a.out, "bilayer_zero_tension.json"), "w") as f:
            json.dump(dict(a0=a0, a0_err=a0_err, slope=slope, intercept=icpt, areas=list(x[pick])), f, indent=2)
    else:
        print("the tension does not change sign over these areas: widen --areas")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    ax[0].errorbar(x, y, yerr=e, fmt="o", label="stress profile (conservative forces)")
    yt = np.array([r["tension_thermo"] for r in rows])
    et = np.array([r["tension_thermo_err"] for r in rows])
    ax[0].errorbar(x + 0.005, yt, yerr=et, fmt="s", mfc="none", label="thermo.csv (all forces)")
    if fit:
        xs = np.linspace(fit[4].min(), fit[4].max(), 50)
        ax[0].plot(xs, fit[0] * xs + fit[1], "k--", lw=1, label=f"fit: a0 = {fit[2]:.3f} +- {fit[3]:.3f}")
    ax[0].axhline(0, color="grey", lw=0.5)
    ax[0].set(xlabel="projected area per molecule a", ylabel="tension int (p_N - p_T) dz",
              title=f"{pset['molecule'].name} bilayer, {2 * a.n_side**2} molecules")
    ax[0].legend(fontsize=8)
    near = rows[int(np.argmin(np.abs(y)))]
    d = os.path.join(a.out, f"a{near['area']:.3f}")
    with open(os.path.join(d, "stress_profile.csv")) as f:
        prof = list(csv.DictReader(f))
    z = np.array([float(r["z"]) for r in prof])
    pn = np.array([float(r["p_n"]) for r in prof])
    pt = np.array([float(r["p_t"]) for r in prof])
    an = np.array([float(r["p_n_minus_p_t"]) for r in prof])
    ae = np.array([float(r["p_n_minus_p_t_err"]) for r in prof])
    ax[1].plot(z, pn, label="p_N")
    ax[1].plot(z, pt, label="p_T")
    ax[1].errorbar(z, an, yerr=ae, fmt=".-", label="p_N - p_T")
    ax[1].axhline(0, color="grey", lw=0.5)
    ax[1].set(xlabel="z", ylabel="pressure", title=f"stress profile at a = {near['area']:.3f} "
              f"(tension {near['tension']:.2f} +- {near['tension_err']:.2f})")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "bilayer.png"), dpi=100)


if __name__ == "__main__":
    main()
