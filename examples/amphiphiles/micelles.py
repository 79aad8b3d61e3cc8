#!/usr/bin/python3
"""Self-assembly of amphiphiles and their micelle-size distribution (issue 12; seed 002 "Amphiphilic Systems").

Head-tail molecules H_m T_n (notation of seed 002) in water W. Default repulsions and bonded
interactions: the set quoted for Shillcock and Lipowsky (J. Chem. Phys. 117, 5048 (2002), cited by
seed 002 as Ref. 110; not confirmed against the paper here, see README.md): a_WW = a_TT = 25,
a_HH = 30, a_HW = 35, a_HT = 50, a_TW = 75, gamma = 4.5, rho = 3; harmonic bonds k = 128, r0 = 0.5; the
cosine angle potential of seed 002 Eq. 32 with k = 20, theta0 = 0 along every chain. --a-tw, --a-hw
and --a-hh change the tail-water, head-water and head-head repulsions (README.md: set B, whose
molecules exchange between micelles and solution).

Aggregates are found from the tail beads: two molecules belong to one aggregate when a tail bead of
one lies within r_c = 1 of a tail bead of the other (minimum image); a molecule alone is free. Over an
averaging window (default: the last third of the frames; --window-start) the script writes the
molecule-weighted size distribution with block errors (aggregation_number.csv), the free-molecule
fraction and concentration, the number of micelles (aggregates of at least --micelle molecules) and
their number- and molecule-weighted mean aggregation numbers, and the exchange events between
consecutive frames (a molecule leaving a micelle for the solution, or entering one), in
equilibrium.json; the time series in aggregates_time.csv; plots in aggregates.png.

    /usr/bin/python3 examples/amphiphiles/micelles.py --mesodpd build/mesodpd --out out/amphiphiles \
        [--sequence H3T4] [--fraction 0.1] [--box 12] [--steps 20000] [--every 200] [--dt 0.02] \
        [--a-tw 75] [--a-hw 35] [--a-hh 30] [--precoarsen STEPS] [--window-start STEP] [--analyse-only]
    /usr/bin/python3 examples/amphiphiles/micelles.py --out out/compare --compare RUN1 RUN2

--precoarsen N first runs N steps with the default (Shillcock-Lipowsky) repulsions into
<out>/precoarsen, then continues from its checkpoint with the given repulsions for --steps more into
<out> (a start from aggregates grown without exchange, for comparison with a random start).
--analyse-only reads the trajectory already in --out (for instance after continuing the run from its
checkpoint with `mesodpd run <out>/config.toml --out <out> --restart <out>/checkpoint.mdpd --steps N`,
which gives the bits of an uninterrupted run). --compare overlays the distributions of analysed runs.
"""
import argparse
import csv
import os
import subprocess

import numpy as np

# The pair and bonded interactions, shared with bilayer.py. The defaults are the Shillcock-Lipowsky
# values; --a-tw and --a-hw change the tail-water and head-water repulsions only.
INTERACTIONS_TEMPLATE = """\
[pair]
a = 25.0
gamma = 4.5

[[pair.override]]
species = ["H", "H"]
a = {a_hh}

[[pair.override]]
species = ["H", "W"]
a = {a_hw}

[[pair.override]]
species = ["H", "T"]
a = {a_ht}
{tt}
[[pair.override]]
species = ["T", "W"]
a = {a_tw}

[[bond_type]]
name = "spring"
style = "harmonic"
k = 128.0
r0 = 0.5

[[angle_type]]
name = "stiff"
k = {angle_k}
theta0 = 0.0
"""


def interactions(a_tw=75.0, a_hw=35.0, a_hh=30.0, a_ht=50.0, a_tt=25.0, angle_k=20.0):
    """The [pair], overrides, bond and angle types (a_WW = 25 is the default repulsion; a T-T
    override is written only when a_tt differs from it)."""
    tt = "" if a_tt == 25.0 else f'\n[[pair.override]]\nspecies = ["T", "T"]\na = {float(a_tt)}\n'
    return INTERACTIONS_TEMPLATE.format(a_tw=float(a_tw), a_hw=float(a_hw), a_hh=float(a_hh),
                                        a_ht=float(a_ht), tt=tt, angle_k=float(angle_k))


INTERACTIONS = interactions()

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

{interactions}
[[molecule]]
name = "amphiphile"
sequence = "{sequence}"
bond_type = "spring"
angle_type = "stiff"
count = {molecules}
bond_length = 0.5

[integrator]
dt = {dt}

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


def molecule_sizes(path, box):
    """Per frame of the GSD trajectory: its step and the size of the aggregate of every molecule
    (frames x molecules, molecules in id order); also the last frame's positions and type ids."""
    import gsd.fl
    import gsd.hoomd

    from chain_analysis import open_gsd

    low = open_gsd(gsd.fl, path, "r")
    mol = low.read_chunk(0, "log/particles/mol").astype(np.int64)
    low.close()
    steps, sizes = [], []
    with open_gsd(gsd.hoomd, path, "r") as traj:
        types = list(traj[0].particles.types)
        for frame in traj:
            tid = np.asarray(frame.particles.typeid)
            pos = np.asarray(frame.particles.position, float)
            s, label, mols = aggregates(pos, mol, tid == types.index("T"), box)
            steps.append(int(frame.configuration.step))
            sizes.append(s[label])
    return np.array(steps), np.array(sizes), mol, mols, label, pos, tid, types


def exchange_events(z, micelle):
    """Exits (a molecule in an aggregate of at least `micelle` molecules in one frame and free in the
    next) and entries (the reverse) in a frames x molecules array of aggregate sizes."""
    exits = int(np.sum((z[:-1] >= micelle) & (z[1:] == 1)))
    entries = int(np.sum((z[:-1] == 1) & (z[1:] >= micelle)))
    return exits, entries


SIZE_CLASSES = [(1, 1), (2, 4), (5, 9), (10, 14), (15, 19), (20, 24), (25, 29), (30, None)]


def equilibrium(steps, z, volume, micelle, blocks):
    """Statistics of the frames in z (frames x molecules): free-molecule fraction and concentration,
    mean aggregation numbers of the micelles (aggregates of at least `micelle` molecules), the
    molecule-weighted size distribution, each with block errors (tools/chain_analysis.mean_error)."""
    from chain_analysis import mean_error

    frames, m = z.shape
    free = (z == 1).mean(axis=1)
    # Number-average aggregation number of the micelles in each frame: molecules in micelles over
    # the number of micelles (a micelle of size s holds s molecules, each listed once in z).
    in_mic = np.where(z >= micelle, 1.0, 0.0)
    n_mic = (in_mic / np.maximum(z, 1)).sum(axis=1)
    number_avg = np.where(n_mic > 0, in_mic.sum(axis=1) / np.maximum(n_mic, 1e-300), np.nan)
    weight_avg = np.array([row[row >= micelle].mean() if np.any(row >= micelle) else np.nan for row in z])
    nmax = int(z.max())
    per_frame = np.stack([np.bincount(row, minlength=nmax + 1) / m for row in z])  # P(s) per frame
    out = {
        "frames": int(frames), "first_step": int(steps[0]), "last_step": int(steps[-1]),
        "molecules": int(m), "blocks": blocks, "micelle_min": micelle,
        "free_fraction": mean_error(free, blocks),
        "free_concentration": [v * m / volume for v in mean_error(free, blocks)],
        "micelles_per_frame": mean_error(n_mic, blocks),
        "number_average_aggregation": mean_error(number_avg[~np.isnan(number_avg)], blocks),
        "weight_average_aggregation": mean_error(weight_avg[~np.isnan(weight_avg)], blocks),
        # Molecule-weighted mean over all aggregates, free molecules included (the number this
        # script printed before it counted micelles separately).
        "weight_average_all": mean_error(z.mean(axis=1), blocks),
    }
    out["exits"], out["entries"] = exchange_events(z, micelle)
    out["molecules_ever_free"] = int(np.sum((z == 1).any(axis=0)))
    dist = [(s, *mean_error(per_frame[:, s], blocks)) for s in range(1, nmax + 1) if per_frame[:, s].any()]
    # The same in classes of sizes (fraction of molecules in aggregates of lo..hi molecules), with
    # block errors of the class sums.
    out["classes"] = []
    for lo, hi in SIZE_CLASSES:
        top = nmax if hi is None else min(hi, nmax)
        frac = per_frame[:, lo:top + 1].sum(axis=1) if lo <= nmax else np.zeros(frames)
        out["classes"].append((f"{lo}" if lo == hi else f"{lo}-{'' if hi is None else hi}", *mean_error(frac, blocks)))
    return out, dist


def run_mesodpd(a, cfg_text, out, restart=None, final_step=None):
    os.makedirs(out, exist_ok=True)
    cfg = os.path.join(out, "config.toml")
    with open(cfg, "w") as f:
        f.write(cfg_text)
    cmd = [a.mesodpd, "run", cfg, "--out", out, "--threads", str(a.threads)]
    if restart:
        cmd += ["--restart", restart, "--steps", str(final_step)]
    subprocess.run(cmd, check=True)


def compare(dirs, out):
    """Overlay the distributions of runs already analysed (their equilibrium.json files)."""
    import json

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(out, exist_ok=True)
    fig, (ax, at) = plt.subplots(1, 2, figsize=(13, 4.5))
    for k, d in enumerate(dirs):
        with open(os.path.join(d, "equilibrium.json")) as f:
            r = json.load(f)
        name = os.path.basename(os.path.normpath(d))
        labels, p, e = zip(*r["classes"])
        width = 0.8 / len(dirs)
        x = np.arange(len(labels)) + width * (k - (len(dirs) - 1) / 2)
        short = "random start" if r["start"].startswith("random") else "precoarsened start"
        bars = ax.bar(x, p, width, yerr=e, capsize=2,
                      label=f"{name}: {short}, steps {r['first_step']}-{r['last_step']}")
        with open(os.path.join(d, "aggregates_time.csv")) as f:
            rows = [(int(x["step"]), int(x["largest"]), float(x["free_fraction"])) for x in csv.DictReader(f)]
        st, big, free = (np.array(c) for c in zip(*rows))
        colour = bars.patches[0].get_facecolor()
        at.plot(st - st[0], big, color=colour, lw=0.8, label=f"{name}: largest aggregate")
        at.plot(st - st[0], 100 * free, color=colour, lw=0.8, ls=":", label=f"{name}: free molecules (%)")
        at.axvline(r["first_step"] - st[0], color=colour, ls="--", lw=0.6)
        print(f"{d}: free fraction {r['free_fraction'][0]:.4f} +- {r['free_fraction'][1]:.4f}, "
              f"free concentration {r['free_concentration'][0]:.5f} +- {r['free_concentration'][1]:.5f}, "
              f"<N>_n {r['number_average_aggregation'][0]:.2f} +- {r['number_average_aggregation'][1]:.2f}, "
              f"<N>_w {r['weight_average_aggregation'][0]:.2f} +- {r['weight_average_aggregation'][1]:.2f}, "
              f"micelles {r['micelles_per_frame'][0]:.2f} +- {r['micelles_per_frame'][1]:.2f}, "
              f"exits {r['exits']}, entries {r['entries']} (steps {r['first_step']}-{r['last_step']})")
        print("  classes: " + ", ".join(f"{c} {v:.3f} +- {e:.3f}" for c, v, e in r["classes"]))
    ax.set_xticks(np.arange(len(labels)), labels)
    ax.set(xlabel="aggregation number s (classes)", ylabel="fraction of molecules in aggregates of size s",
           title="size distribution over the averaging windows (block errors)")
    ax.legend(fontsize=7)
    at.set(xlabel="steps since the run's first frame (dashed: averaging window starts)", ylim=(0, None),
           title="largest aggregate and free molecules per frame")
    at.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "compare.png"), dpi=100)


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
    ap.add_argument("--a-tw", type=float, default=75.0, help="tail-water repulsion (Shillcock-Lipowsky: 75)")
    ap.add_argument("--a-hw", type=float, default=35.0, help="head-water repulsion (Shillcock-Lipowsky: 35)")
    ap.add_argument("--a-hh", type=float, default=30.0, help="head-head repulsion (Shillcock-Lipowsky: 30)")
    ap.add_argument("--dt", type=float, default=0.02)
    ap.add_argument("--precoarsen", type=int, default=0,
                    help="first run this many steps with the Shillcock-Lipowsky repulsions (out/precoarsen), "
                         "then continue from its checkpoint with the given ones for --steps more")
    ap.add_argument("--window-start", type=int, default=-1,
                    help="first step of the averaging window (default: the last third of the frames)")
    ap.add_argument("--micelle", type=int, default=5, help="smallest aggregate counted as a micelle")
    ap.add_argument("--blocks", type=int, default=5)
    ap.add_argument("--analyse-only", action="store_true", help="analyse the trajectory already in --out")
    ap.add_argument("--compare", nargs="+", help="overlay the distributions of these analysed runs in --out")
    a = ap.parse_args()
    import json
    import re
    import sys

    sys.path.insert(0, os.path.join(here, "..", "..", "tools"))
    if a.compare:
        compare(a.compare, a.out)
        return
    beads = sum(int(c) for c in re.findall(r"(\d+)", a.sequence.replace("(", "").replace(")", "")))
    if "(" in a.sequence:
        raise SystemExit("--sequence: give a linear H_m T_n here")
    total = int(round(3.0 * a.box**3))
    molecules = int(round(a.fraction * total / beads))
    water = total - molecules * beads
    os.makedirs(a.out, exist_ok=True)
    every = a.every if a.every > 0 else max(1, a.steps // 100)

    def config(steps, inter):
        return CONFIG.format(box=a.box, seed=a.seed, water=water, sequence=a.sequence, molecules=molecules,
                             steps=steps, every=every, dt=a.dt, interactions=inter)

    inter = interactions(a.a_tw, a.a_hw, a.a_hh)
    if a.precoarsen > 0:
        start = (f"{a.precoarsen} steps with a_TW = 75, a_HW = 35, a_HH = 30 (Shillcock-Lipowsky), then "
                 f"a_TW = {a.a_tw:g}, a_HW = {a.a_hw:g}, a_HH = {a.a_hh:g}; seed {a.seed}")
    else:
        start = f"random start, seed {a.seed}"
    if not a.analyse_only:
        if a.precoarsen > 0:
            pre = os.path.join(a.out, "precoarsen")
            run_mesodpd(a, config(a.precoarsen, interactions()), pre)
            # A restart into a new directory starts new files; the config may change the repulsions
            # (docs/config.md, "Restarts"), not the seed, species or time step.
            run_mesodpd(a, config(a.precoarsen + a.steps, inter), a.out,
                        restart=os.path.join(pre, "checkpoint.mdpd"), final_step=a.precoarsen + a.steps)
        else:
            run_mesodpd(a, config(a.steps, inter), a.out)

    steps, z, mol, mols, label, last_pos, last_tid, types = molecule_sizes(os.path.join(a.out, "trajectory.gsd"),
                                                                         a.box)
    n_frames = len(steps)
    first = a.window_start if a.window_start >= 0 else int(steps[2 * n_frames // 3])
    win = steps >= first
    stats, dist = equilibrium(steps[win], z[win], a.box**3, a.micelle, a.blocks)
    stats["start"] = start
    stats["distribution"] = dist
    stats["exits_whole_run"], stats["entries_whole_run"] = exchange_events(z, a.micelle)
    with open(os.path.join(a.out, "equilibrium.json"), "w") as f:
        json.dump(stats, f, indent=1)
    # Number of aggregates, largest and mean size per frame.
    rows = []
    for st, row in zip(steps, z):
        sizes = np.bincount(row)[1:] / np.arange(1, row.max() + 1)  # aggregates of each size
        count = int(round(sizes.sum()))
        rows.append((int(st), count, int(row.max()), len(row) / count, float(np.mean(row == 1))))
    with open(os.path.join(a.out, "aggregates_time.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["step", "aggregates", "largest", "mean_size", "free_fraction"])
        w.writerows(rows)
    with open(os.path.join(a.out, "aggregation_number.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["size", "molecule_fraction", "error", "aggregates_per_frame"])
        for s, p, e in dist:
            w.writerow([s, f"{p:.5f}", f"{e:.5f}", f"{p * len(z[0]) / s:.4f}"])
    # Shapes of the aggregates of the last frame (10 molecules or more): principal radii of gyration
    # of all their beads; a sphere has three equal radii, a rod one large, a disc one small.
    sizes = np.bincount(label)
    in_agg = {m: label[k] for k, m in enumerate(mols)}
    for g in np.flatnonzero(sizes >= 10):
        members = np.array([in_agg.get(m, -1) == g for m in mol])
        r = shape(np.mod(last_pos[members], a.box), a.box)
        print(f"last frame: aggregate of {sizes[g]} molecules, principal radii of gyration "
              f"{r[0]:.2f}, {r[1]:.2f}, {r[2]:.2f}")
    ff, nw, nn = stats["free_fraction"], stats["weight_average_aggregation"], stats["number_average_aggregation"]
    print(f"{molecules} x {a.sequence} in {water} W (bead fraction {molecules * beads / total:.3f}); {start}; "
          f"window steps {stats['first_step']}-{stats['last_step']} ({stats['frames']} frames, {a.blocks} blocks): "
          f"free molecules {ff[0]:.4f} +- {ff[1]:.4f} (concentration {stats['free_concentration'][0]:.5f} "
          f"+- {stats['free_concentration'][1]:.5f} per r_c^3), micelles (>= {a.micelle}) per frame "
          f"{stats['micelles_per_frame'][0]:.2f} +- {stats['micelles_per_frame'][1]:.2f}, aggregation number "
          f"number-average {nn[0]:.2f} +- {nn[1]:.2f}, molecule-weighted {nw[0]:.2f} +- {nw[1]:.2f} "
          f"(all aggregates and free molecules: {stats['weight_average_all'][0]:.2f}); "
          f"exits {stats['exits']}, entries {stats['entries']}, molecules free at least once "
          f"{stats['molecules_ever_free']} of {molecules}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    st = np.array([r[0] for r in rows])
    ax[0].plot(st, [r[1] for r in rows], label="aggregates")
    ax[0].plot(st, [r[2] for r in rows], label="largest (molecules)")
    ax[0].axvline(first, color="grey", ls=":", label="averaging from")
    ax[0].set(xlabel="step", title=start if len(start) < 40 else "from a precoarsened start")
    ax[0].legend()
    s_, p_, e_ = (np.array(c, float) for c in zip(*dist))
    ax[1].bar(s_, p_, yerr=e_, capsize=2)
    ax[1].set(xlabel="aggregation number", ylabel="fraction of molecules", title="averaging window")
    p = np.mod(last_pos, a.box)
    for name, colour in (("T", "tab:orange"), ("H", "tab:blue")):
        m = last_tid == types.index(name)
        ax[2].scatter(p[m, 0], p[m, 1], s=3, c=colour, label=name)
    ax[2].set(aspect="equal", xlabel="x", ylabel="y", title="last frame (heads and tails, water hidden)")
    ax[2].legend(loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "aggregates.png"), dpi=100)


if __name__ == "__main__":
    main()
