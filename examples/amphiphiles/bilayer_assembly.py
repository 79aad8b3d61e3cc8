#!/usr/bin/python3
"""A bilayer self-assembling from a random start, measured (issue 12, "Amphiphiles"; seed 002
"Amphiphilic Systems").

The molecules and parameters are bilayer.py's (--set A: H3(T4)2 with set A; --set osprey: the lipid and
parameters of Osprey-DPD's examples/dmpci.bilayer). Each molecule is placed as a random walk (every
bead at the bond length r0 = 0.5 from its parent, in a random direction, the first bead at a random
place), the water at random places, all at density 3, written as a LAMMPS data file by bilayer.py's
writer; mesodpd runs it and dumps a GSD trajectory. The box is cubic (--box L: the membrane chooses
its normal) or, with --area a, bilayer.py's box for M molecules at a projected area a per molecule
(Lx = Ly = sqrt(a M / 2), Lz = N / (3 Lx Ly)).

Each frame is measured from the tail beads (README.md, "Bilayer from a random start"):
  slab_x, slab_y, slab_z  for each axis, how much more of the tail beads lie in the best periodic slab
                          of width w normal to it than a uniform spread puts there: (f - w/L) /
                          (1 - w/L), f the fraction inside (0: uniform, 1: all inside); w = 2 (n + 1) r0
                          for tails of n beads (5 for T4, 7 for T6; the pre-assembled H3(T4)2 bilayer
                          has 93% of its tail beads within it); the normal is the axis with the largest;
  coverage                fraction of the cells (about 1 x 1) of the plane normal to it that hold a
                          tail bead of the slab (a membrane spanning the box covers them all, a
                          cylinder a strip, a micelle a disc);
  inplane_cv              the largest, over the two in-plane axes, of the relative standard deviation
                          of the tail density in bins of about 1 (a flat spanning membrane: Poisson
                          noise only);
  water_core              water beads within w / 4 of the slab's centre, over 3 times that volume
                          (0: no water in the tail core, 1: bulk water; pores raise it);
  tail_water              tail beads within 0.5 of the water layer's middle (half a box from the mid-plane),
                          over 3 times that volume (bridges or stalks through the water);
  largest                 molecules in the largest aggregate (micelles.py's tail-contact clusters);
  upper, lower            molecules whose heads lie (on average) above, below the mid-plane;
  lamellar_peaks          how many of the 13 lattice directions (h, k, l in {-1, 0, 1}) have a tail
                          density wave |<exp(i q.r)>| > 0.3 (a lamella: 1; a cylinder along an axis:
                          4; one compact micelle: 13; a random state: 0).
A frame is a bilayer when the slab excess >= 0.7, coverage >= 0.95, largest >= 0.9 M, water_core < 0.05
and tail_water < 0.05 (the pre-assembled bilayer at a = 1.05, 80-400 time units: 0.875, 1, all, 0, 0;
the random starts at step 0: excess 0.1-0.2; tests/analysis/test_bilayer_assembly.py: a cylinder and
a micelle fail on the coverage).

Written: assembly_time.csv (per frame), assembly.json (the first time from which every frame is a
bilayer, the averages over the window, the tension L_n (P_nn - (P_aa + P_bb) / 2) along the normal from
thermo.csv and, with --reference, the same for a pre-assembled run), assembly.png (time series,
density profiles of W, H and T along the normal beside the reference's, a side view of the last frame).

    nice -n 19 /usr/bin/python3 examples/amphiphiles/bilayer_assembly.py --mesodpd build/mesodpd \\
        --out out/bil-a105-s1 --area 1.05 --molecules 128 --steps 100000 --every 500 --seed 1
    /usr/bin/python3 examples/amphiphiles/bilayer_assembly.py --out out/bil-a105-s1 --analyse-only \\
        --window-start 20000 --reference out/bil-ref/a1.050

(--reference: a run of `bilayer.py --dump-every N`; --analyse-only takes the box, seed and time step
from the run's files, --set must be the run's.)

A run is continued with `mesodpd run <out>/config.toml --out <out> --restart <out>/checkpoint.mdpd
--steps N` and then analysed with --analyse-only.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools"))
from bilayer import CONFIG, DUMP, PARAMETER_SETS, thermo_tension, write_lammps_data  # noqa: E402
from micelles import aggregates  # noqa: E402

SLAB_MIN, COVERAGE_MIN, LARGEST_MIN, CLEAN_MAX = 0.7, 0.95, 0.9, 0.05
LAMELLAR_THRESHOLD = 0.3
AXES = "xyz"


def slab_width(mol, bond=0.5):
    """The slab width 2 (n + 1) r0 for the longest run of n bonded tail beads: n + 1 bond lengths on each
    side of the mid-plane (the pre-assembled H3(T4)2 bilayer at a = 1.05 has 93% of its tail beads
    within it)."""
    run = []
    for i, p in enumerate(mol.parent):
        t = mol.species[i] == "T"
        run.append((run[p] + 1 if p >= 0 and mol.species[p] == "T" else 1) if t else 0)
    return 2 * (max(run) + 1) * bond


def box_for(args_box, area, molecules, total):
    """(Lx, Ly, Lz): a cubic box of side args_box, or bilayer.py's box at `area` per molecule."""
    if area:
        lx = math.sqrt(area * molecules / 2)
        return (lx, lx, total / (3.0 * lx * lx))
    return (args_box,) * 3


def random_start(path, box, molecules, total, seed, mol, bond=0.5):
    """Write the random start: `molecules` random walks of `mol` and water up to `total` particles.
    Returns the atoms (mol, species, x, y, z), positions inside [0, L)."""
    rng = np.random.default_rng(seed)
    size = np.asarray(box, float)
    water = total - molecules * len(mol)
    if water < 0:
        raise SystemExit(f"{molecules} molecules of {len(mol)} beads do not fit in {total} particles")
    atoms, bonds, angles = [], [], []
    for m in range(1, molecules + 1):
        p = np.empty((len(mol), 3))
        p[0] = rng.uniform(0.0, 1.0, 3) * size
        for i in range(1, len(mol)):
            u = rng.normal(size=3)
            p[i] = p[mol.parent[i]] + bond * u / np.linalg.norm(u)
        b, a = mol.topology(len(atoms) + 1)
        atoms += [(m, sp, *wrap(q, size)) for sp, q in zip(mol.species, p)]
        bonds += b
        angles += a
    atoms += [(0, "W", *wrap(q, size)) for q in rng.uniform(0.0, 1.0, (water, 3)) * size]
    write_lammps_data(path, f"{mol.name} random start, {molecules} molecules, seed {seed}", box, atoms,
                      bonds, angles)
    return atoms


def wrap(q, size):
    """q in [0, L) on every axis (also after rounding to the 8 decimals the data file keeps)."""
    q = np.mod(q, size)
    q[np.round(q, 8) >= np.round(size, 8)] = 0.0
    return q


def slab(coord, length, width):
    """The periodic slab of `width` holding the most of `coord`: (fraction inside, centre)."""
    nb = max(8, int(round(length / 0.1)))
    h = np.bincount((np.mod(coord, length) * (nb / length)).astype(int) % nb, minlength=nb)
    k = int(round(width / length * nb))
    if k >= nb:
        return 1.0, 0.5 * length
    s = np.concatenate([[0], np.cumsum(np.concatenate([h, h]))])
    win = s[k:k + nb] - s[:nb]  # window of bins i .. i + k - 1
    i = int(np.argmax(win))
    return float(win[i] / max(1, h.sum())), float(((i + 0.5 * k) * length / nb) % length)


def signed(coord, centre, length):
    """Periodic distance of coord from centre, in [-L/2, L/2)."""
    d = coord - centre
    return d - length * np.round(d / length)


LATTICE = [(h, k, l) for h in (-1, 0, 1) for k in (-1, 0, 1) for l in (-1, 0, 1) if (h, k, l) > (0, 0, 0)]


def metrics(pos, species, mol, box, width):
    """The measures of one frame (module docstring). pos (N, 3), species an array of 'W'/'H'/'T',
    mol the molecule ids (0: water)."""
    size = np.asarray(box, float)
    pos = np.mod(pos, size)
    tail = species == "T"
    t = pos[tail]
    out = {}
    slabs = [slab(t[:, k], size[k], width) for k in range(3)]
    # The excess over a uniform spread (fraction w / L inside): 0 uniform, 1 all inside.
    excess = [(f - min(width / size[k], 1.0)) / max(1e-12, 1.0 - width / size[k]) for k, (f, _) in enumerate(slabs)]
    for k in range(3):
        out[f"slab_{AXES[k]}"] = excess[k]
    n = int(np.argmax(excess))
    a, b = [k for k in range(3) if k != n]
    centre = slabs[n][1]
    out["normal"] = AXES[n]
    out["centre"] = centre
    d = signed(t[:, n], centre, size[n])
    inside = t[np.abs(d) <= 0.5 * width]
    na, nbb = max(1, int(round(size[a]))), max(1, int(round(size[b])))
    cells, _, _ = np.histogram2d(inside[:, a], inside[:, b], bins=[na, nbb], range=[[0, size[a]], [0, size[b]]])
    out["coverage"] = float(np.mean(cells > 0))
    cv = []
    for k, nk in ((a, na), (b, nbb)):
        h = np.bincount((t[:, k] * (nk / size[k])).astype(int) % nk, minlength=nk)
        cv.append(float(h.std() / max(h.mean(), 1e-300)))
    out["inplane_cv"] = max(cv)
    # Leaflets: a molecule belongs to the side of the mid-plane where its heads are (on average).
    heads = species == "H"
    side = np.bincount(mol[heads], weights=signed(pos[heads, n], centre, size[n]), minlength=mol.max() + 1)[1:]
    side = side[np.bincount(mol[heads], minlength=mol.max() + 1)[1:] > 0]
    out["upper"] = int(np.sum(side > 0))
    out["lower"] = int(np.sum(side <= 0))
    w = pos[species == "W"]
    core = 0.25 * width
    in_core = np.sum(np.abs(signed(w[:, n], centre, size[n])) < core)
    out["water_core"] = float(in_core / (3.0 * size[a] * size[b] * 2 * core))
    # Tail beads in the middle of the water layer (a slab of width 1 half a box away from the
    # mid-plane): bridges (stalks) that join the membrane to its periodic image across the water.
    far = np.sum(np.abs(d) > 0.5 * size[n] - 0.5)
    out["tail_water"] = float(far / (3.0 * size[a] * size[b]))
    sizes, _, _ = aggregates(pos, mol, tail, size)
    out["largest"] = int(sizes.max())
    out["aggregates"] = int(len(sizes))
    rho = [abs(np.mean(np.exp(2j * np.pi * (t @ (np.array(q) / size))))) for q in LATTICE]
    out["lamellar_peaks"] = int(np.sum(np.array(rho) > LAMELLAR_THRESHOLD))
    out["rho_max"] = float(max(rho))
    m = len(np.unique(mol[mol > 0]))
    out["bilayer"] = int(excess[n] >= SLAB_MIN and out["coverage"] >= COVERAGE_MIN
                         and out["largest"] >= LARGEST_MIN * m and out["water_core"] < CLEAN_MAX
                         and out["tail_water"] < CLEAN_MAX)
    return out


def profiles(pos, species, box, normal, centre, dz=0.25):
    """Number densities of W, H and T against the distance from the mid-plane along `normal`."""
    size = np.asarray(box, float)
    n = AXES.index(normal)
    a, b = [k for k in range(3) if k != n]
    nb = int(size[n] / dz)
    edges = np.linspace(-0.5 * size[n], 0.5 * size[n], nb + 1)
    d = signed(np.mod(pos[:, n], size[n]), centre, size[n])
    vol = (edges[1] - edges[0]) * size[a] * size[b]
    return 0.5 * (edges[1:] + edges[:-1]), {s: np.histogram(d[species == s], bins=edges)[0] / vol for s in "WHT"}


def read_lammps_data(path):
    """Positions, species ('W'/'H'/'T'), molecule ids, box, bonds (atom indices from 0) of a data
    file written by bilayer.write_lammps_data."""
    lines = open(path).read().splitlines()
    box = [float(lines[k].split()[1]) for k in range(len(lines)) if lines[k].endswith(("xhi", "yhi", "zhi"))]
    sec = {name: lines.index(name) for name in lines if name in ("Bonds", "Angles") or name.startswith("Atoms")}
    start = [v for k, v in sec.items() if k.startswith("Atoms")][0] + 2
    atoms = np.array([ln.split() for ln in lines[start:sec["Bonds"] - 1]], dtype=float)
    atoms = atoms[np.argsort(atoms[:, 0])]
    bonds = np.array([ln.split()[2:4] for ln in lines[sec["Bonds"] + 2:sec["Angles"] - 1]], dtype=int) - 1
    return atoms[:, 3:6], np.array(["W", "H", "T"])[atoms[:, 2].astype(int) - 1], atoms[:, 1].astype(np.int64), \
        tuple(box), bonds


def read_frames(path):
    """Steps, positions, species (array of 'W'/'H'/'T'), molecule ids and box of a GSD trajectory."""
    import gsd.fl
    import gsd.hoomd

    from chain_analysis import open_gsd

    low = open_gsd(gsd.fl, path, "r")
    mol = low.read_chunk(0, "log/particles/mol").astype(np.int64)
    low.close()
    with open_gsd(gsd.hoomd, path, "r") as traj:
        types = np.array(list(traj[0].particles.types))
        box = tuple(float(v) for v in traj[0].configuration.box[:3])
        for frame in traj:
            yield (int(frame.configuration.step), np.asarray(frame.particles.position, float),
                   types[np.asarray(frame.particles.typeid)], mol, box)


def analyse_run(d, width, window_start, dt):
    """Per-frame measures of run directory d, the averages from step window_start (default, when
    negative: the last third of the frames), the mean density profiles of the window's frames, the last
    frame and the thermo tension along the window's normal."""
    from chain_analysis import mean_error

    if not os.path.isfile(os.path.join(d, "trajectory.gsd")):
        raise SystemExit(f"{d}: no trajectory.gsd (a bilayer_assembly.py run, or bilayer.py with --dump-every)")
    rows, last = [], None
    for step, pos, species, mol, box in read_frames(os.path.join(d, "trajectory.gsd")):
        r = dict(step=step, time=step * dt, **metrics(pos, species, mol, box, width))
        rows.append(r)
        last = (pos, species, box, r)
    if window_start < 0:
        window_start = rows[2 * len(rows) // 3]["step"]
    win = [r for r in rows if r["step"] >= window_start] or rows[-1:]
    normals = [r["normal"] for r in win]
    normal = max(set(normals), key=normals.count)
    summary = {"frames": len(rows), "window_start": win[0]["step"], "window_frames": len(win), "normal": normal,
               "normal_share": normals.count(normal) / len(win)}
    blocks = min(5, len(win))
    for key in ("slab_x", "slab_y", "slab_z", "coverage", "inplane_cv", "water_core", "tail_water", "largest", "aggregates", "upper",
                "lamellar_peaks", "rho_max", "bilayer"):
        summary[key] = mean_error([r[key] for r in win], blocks)
    summary["slab_normal"] = mean_error([r[f"slab_{normal}"] for r in win], blocks)
    # The first time from which every later frame is a bilayer.
    formed = None
    for r in reversed(rows):
        if not r["bilayer"]:
            break
        formed = r
    summary["bilayer_from_step"] = formed["step"] if formed else None
    summary["bilayer_from_time"] = formed["time"] if formed else None
    # Density profiles: each window frame centred on its own tail slab along the window's normal.
    n = AXES.index(normal)
    prof = {sp: 0.0 for sp in "WHT"}
    for step, pos, species, mol, box in read_frames(os.path.join(d, "trajectory.gsd")):
        if step >= win[0]["step"]:
            _, c = slab(np.mod(pos[species == "T", n], box[n]), box[n], width)
            z, p = profiles(pos, species, box, normal, c)
            prof = {sp: prof[sp] + p[sp] / len(win) for sp in "WHT"}
    box = last[2]
    summary["box"] = list(box)
    summary["tension"] = thermo_tension(os.path.join(d, "thermo.csv"), win[0]["step"], box[n], normal)
    summary["inplane_area"] = float(np.prod([box[k] for k in range(3) if k != n]))
    summary["molecules"] = int(len(np.unique(mol[mol > 0])))
    summary["particles"] = int(len(mol))
    summary["area_per_molecule"] = summary["inplane_area"] / (summary["molecules"] / 2)
    return rows, summary, (z, prof), last


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesodpd", default=os.path.join(HERE, "..", "..", "build", "mesodpd"))
    ap.add_argument("--out", default="out/bilayer-assembly")
    ap.add_argument("--set", default="A", choices=sorted(PARAMETER_SETS), help="parameter set (README.md)")
    ap.add_argument("--dt", type=float, default=0.0, help="time step (default: the set's, 0.02)")
    ap.add_argument("--box", type=float, default=10.0, help="cubic box side")
    ap.add_argument("--area", type=float, default=0.0, help="instead of --box: bilayer.py's box at this area")
    ap.add_argument("--molecules", type=int, default=192)
    ap.add_argument("--total", type=int, default=0, help="particles (default 3 L^3 of the cubic box)")
    ap.add_argument("--steps", type=int, default=60000)
    ap.add_argument("--every", type=int, default=500, help="trajectory frame interval")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--window-start", type=int, default=-1, help="first step of the averages (default: last third)")
    ap.add_argument("--reference", help="a pre-assembled run (bilayer.py --dump-every) to compare with")
    ap.add_argument("--analyse-only", action="store_true", help="analyse the run already in --out")
    a = ap.parse_args()
    pset = PARAMETER_SETS[a.set]
    mol = pset["molecule"]
    total = a.total or (3000 if a.area else int(round(3.0 * a.box**3)))
    box = box_for(a.box, a.area, a.molecules, total)
    width = slab_width(mol)
    if not a.analyse_only:
        os.makedirs(a.out, exist_ok=True)
        random_start(os.path.join(a.out, "bilayer.data"), box, a.molecules, total, a.seed, mol)
        with open(os.path.join(a.out, "config.toml"), "w") as f:
            f.write(CONFIG.format(lx=box[0], ly=box[1], lz=box[2], seed=a.seed, steps=a.steps,
                                  interactions=pset["interactions"], dt=a.dt or pset["dt"]) + DUMP.format(every=a.every))
        subprocess.run([a.mesodpd, "run", os.path.join(a.out, "config.toml"), "--out", a.out, "--threads",
                        str(a.threads)], check=True)
    dt = config_value(a.out, "dt")
    rows, summary, (z, prof), last = analyse_run(a.out, width, a.window_start, dt)
    summary.update(set=a.set, molecule=mol.name, seed=int(config_value(a.out, "seed")), width=width, thresholds=dict(
                       slab=SLAB_MIN, coverage=COVERAGE_MIN, largest=LARGEST_MIN, lamellar=LAMELLAR_THRESHOLD))
    ref = None
    if a.reference:
        # The reference's averages start where its stress profile does (bilayer.py's --start).
        rrows, rsum, (rz, rprof), _ = analyse_run(a.reference, width, int(config_value(a.reference, "start", 0)),
                                                  config_value(a.reference, "dt"))
        summary["reference"] = {k: v for k, v in rsum.items()}
        summary["reference"]["dir"] = a.reference
        ref = (rz, rprof)
    with open(os.path.join(a.out, "assembly_time.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "assembly.json"), "w") as f:
        json.dump(summary, f, indent=2)
    report(summary)
    plot(a.out, rows, summary, z, prof, ref, last, summary["molecules"])


def config_value(d, key, default=None):
    """The first `key = value` of run directory d's config.toml, as a number (default if absent)."""
    if not os.path.isfile(os.path.join(d, "config.toml")):
        raise SystemExit(f"{d}: no config.toml (not a bilayer_assembly.py or bilayer.py run directory)")
    with open(os.path.join(d, "config.toml")) as f:
        for line in f:
            if line.startswith(f"{key} = "):
                return float(line.split("=")[1])
    return default


def report(s):
    def f(key):
        v, e = s[key]
        return f"{v:.3f} +- {e:.3f}"

    print(f"{s['molecule']}, {s['molecules']} molecules, box {' x '.join(f'{v:.3f}' for v in s['box'])}, seed {s['seed']}")
    print(f"window from step {s['window_start']} ({s['window_frames']} frames): normal {s['normal']} "
          f"({100 * s['normal_share']:.0f}% of frames), slab {f('slab_normal')}, coverage {f('coverage')}, "
          f"in-plane cv {f('inplane_cv')}, water in core {f('water_core')}, tails in the water layer "
          f"{f('tail_water')}, largest {f('largest')}, "
          f"lamellar peaks {f('lamellar_peaks')}, molecules with heads above / below the mid-plane "
          f"{s['upper'][0]:.1f} / {s['molecules'] - s['upper'][0]:.1f}, bilayer frames {f('bilayer')}")
    print(f"bilayer in every frame from step {s['bilayer_from_step']} (time {s['bilayer_from_time']}); "
          f"area per molecule {s['area_per_molecule']:.4f}; tension {s['tension'][0]:.3f} +- {s['tension'][1]:.3f}")
    if "reference" in s:
        r = s["reference"]
        print(f"reference {r['dir']}: area per molecule {r['area_per_molecule']:.4f}, slab "
              f"{r['slab_normal'][0]:.3f}, coverage {r['coverage'][0]:.3f}, in-plane cv {r['inplane_cv'][0]:.3f}, "
              f"water in core {r['water_core'][0]:.3f}, tails in the water layer {r['tail_water'][0]:.3f}, tension {r['tension'][0]:.3f} +- {r['tension'][1]:.3f}")


def plot(out, rows, s, z, prof, ref, last, molecules):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    t = np.array([r["time"] for r in rows])
    ax[0].plot(t, [r[f"slab_{r['normal']}"] for r in rows], label="tail slab excess (normal axis)")
    ax[0].plot(t, [r["coverage"] for r in rows], label="in-plane coverage")
    ax[0].plot(t, [r["largest"] / molecules for r in rows], label="largest aggregate / M")
    ax[0].plot(t, [r["water_core"] for r in rows], label="water in tail core / bulk")
    ax[0].plot(t, [r["tail_water"] for r in rows], label="tails mid-water / 3")
    ax[0].set(xlabel="time", ylim=(0, 1.05), title=f"{s['molecules']} {s['molecule'].split(' ')[0]}, seed {s['seed']}")
    ax[0].legend(fontsize=7)
    for sp, c in (("W", "tab:blue"), ("H", "tab:red"), ("T", "tab:green")):
        ax[1].plot(z, prof[sp], color=c, label=f"{sp} (random start)")
        if ref:
            ax[1].plot(ref[0], ref[1][sp], color=c, ls="--", lw=1, label=f"{sp} (pre-assembled)")
    ax[1].set(xlabel=f"distance from mid-plane along {s['normal']}", ylabel="number density",
              title=f"a = {s['area_per_molecule']:.3f} per molecule" + (
                  f" (pre-assembled: {s['reference']['area_per_molecule']:.3f})" if ref else ""))
    ax[1].set_ylim(0, 4.3)
    ax[1].legend(fontsize=6, ncol=2, loc="upper center")
    pos, species, box, r = last
    n = AXES.index(r["normal"])
    k = [j for j in range(3) if j != n][0]
    p = np.mod(pos, np.asarray(box))
    for sp, c in (("H", "tab:red"), ("T", "tab:green")):
        sel = species == sp
        ax[2].plot(p[sel, k], p[sel, n], ".", ms=1.5, color=c, label=sp)
    ax[2].set(xlabel=AXES[k], ylabel=AXES[n], aspect="equal", title=f"last frame (step {r['step']}), side view")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "assembly.png"), dpi=80)


if __name__ == "__main__":
    main()
