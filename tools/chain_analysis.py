#!/usr/bin/python3
"""Chain measurements from a mesodpd GSD trajectory: radius of gyration, end-to-end vector and their
time autocorrelations (relaxation time), bond length and bond angle distributions, and the
centre-of-mass diffusion of molecules, per molecule kind. Writes CSV files and a PNG plot.

The trajectory must hold positions, images and molecule ids: in the config
    [output.dump]
    format = "gsd"
    fields = ["id", "species", "position", "image", "mol"]
Bonds and angles come from the file's bonds/ and angles/ chunks (mesodpd writes them in the first
frame). A molecule kind is the sequence of bead species of a molecule (e.g. "A10", "H1T4"); molecules
of one [[molecule]] block share it.

    /usr/bin/python3 tools/chain_analysis.py OUT/trajectory.gsd --dt 0.04 --out OUT/chains [--skip N]

Definitions: R_g^2 = mean over beads of |r - r_cm|^2 (unwrapped positions); R_e = r(last bead) -
r(first bead) in id order (for a branched molecule: first to last id); C_e(t) = <R_e(t0) . R_e(t0 + t)>
/ <R_e^2> over molecules and time origins, tau_e the time where C_e first drops below 1/e (linear
interpolation); C_g(t) the same for the fluctuation of R_g^2; bond angle theta between consecutive
bond vectors (0 = straight, as the cosine angle potential uses it); D from the slope of the
centre-of-mass mean squared displacement over the second half of the lags, MSD = 6 D t.
"""
import argparse
import csv
import os
import sys

import numpy as np


def molecule_kinds(mol, typeid, types):
    """Groups molecules (mol > 0) by their bead sequence; returns {kind name: [arrays of particle rows]}."""
    order = np.argsort(mol, kind="stable")
    ids = mol[order]
    kinds = {}
    starts = np.flatnonzero(np.r_[True, ids[1:] != ids[:-1]])
    ends = np.r_[starts[1:], len(ids)]
    for s, e in zip(starts, ends):
        if ids[s] <= 0:
            continue
        rows = np.sort(order[s:e])
        seq = typeid[rows]
        # Run-length name in the notation of seed 002: A10, H1T4, ...
        name, k = "", 0
        while k < len(seq):
            j = k
            while j < len(seq) and seq[j] == seq[k]:
                j += 1
            name += f"{types[seq[k]]}{j - k}"
            k = j
        kinds.setdefault(name, []).append(rows)
    return kinds


def acf(series):
    """Normalised autocorrelation over time origins of series[t, m, ...] (dot product over trailing axes)."""
    n = series.shape[0]
    out = np.zeros(n)
    for lag in range(n):
        a, b = series[: n - lag], series[lag:]
        out[lag] = np.mean(np.sum(a * b, axis=tuple(range(2, series.ndim))) if series.ndim > 2 else a * b)
    return out / out[0] if out[0] != 0 else out


def relaxation_time(times, c):
    below = np.flatnonzero(c < np.exp(-1.0))
    if len(below) == 0:
        return float("nan")
    k = below[0]
    if k == 0:
        return 0.0
    return float(times[k - 1] + (np.exp(-1.0) - c[k - 1]) * (times[k] - times[k - 1]) / (c[k] - c[k - 1]))


def mean_error(x, blocks=10):
    """Mean and standard error from block averages of a time series."""
    x = np.asarray(x, dtype=float)
    nb = min(blocks, len(x))
    if nb < 2:
        return float(np.mean(x)), float("nan")
    means = np.array([b.mean() for b in np.array_split(x, nb)])
    return float(means.mean()), float(means.std(ddof=1) / np.sqrt(nb))


def open_gsd(module, path, mode):
    """gsd 2.x takes modes 'rb'/'wb', gsd 3.x 'r'/'w'."""
    try:
        return module.open(name=path, mode=mode + "b")
    except ValueError:
        return module.open(name=path, mode=mode)


def analyse(path, dt, skip=0):
    import gsd.fl
    import gsd.hoomd

    with open_gsd(gsd.hoomd, path, "r") as traj:
        first = traj[0]
        n = first.particles.N
        box = np.array(first.configuration.box[:3], dtype=float)
        data0 = open_gsd(gsd.fl, path, "r")
        if not data0.chunk_exists(0, "log/particles/mol"):
            sys.exit(f"{path}: no log/particles/mol chunk: add \"mol\" to output.dump.fields")
        mol = data0.read_chunk(0, "log/particles/mol").astype(np.int64)
        types = list(first.particles.types)
        typeid = np.asarray(first.particles.typeid)
        kinds = molecule_kinds(mol, typeid, types)
        if not kinds:
            sys.exit(f"{path}: no molecules (every mol id is 0)")
        bonds = np.asarray(first.bonds.group, dtype=np.int64).reshape(-1, 2) if first.bonds.N else np.zeros((0, 2), int)
        angles = np.asarray(first.angles.group, dtype=np.int64).reshape(-1, 3) if first.angles.N else np.zeros((0, 3), int)
        kind_of_row = np.full(n, "", dtype=object)
        for name, mols in kinds.items():
            for rows in mols:
                kind_of_row[rows] = name
        steps, pos_frames = [], []
        for k, frame in enumerate(traj):
            if k < skip:
                continue
            r = np.asarray(frame.particles.position, dtype=float) + np.asarray(frame.particles.image) * box
            steps.append(int(frame.configuration.step))
            pos_frames.append(r)
        data0.close()
    times = (np.array(steps) - steps[0]) * dt
    pos = np.array(pos_frames)  # [t, N, 3], unwrapped (relative to the box centre)
    results = {}
    for name, mols in kinds.items():
        rows = np.array(mols)  # [M, beads] (every molecule of a kind has the same size)
        r = pos[:, rows, :]  # [t, M, b, 3]
        com = r.mean(axis=2)
        rg2 = ((r - com[:, :, None, :]) ** 2).sum(axis=3).mean(axis=2)  # [t, M]
        re = r[:, :, -1, :] - r[:, :, 0, :]
        re2 = (re**2).sum(axis=2)
        c_e = acf(re)
        # tau_e of each quarter of the run, for its error (each quarter's own autocorrelation)
        quarters = np.array_split(np.arange(len(times)), 4) if len(times) >= 40 else []
        tau_blocks = [relaxation_time(times[q] - times[q[0]], acf(re[q])) for q in quarters]
        dg = rg2 - rg2.mean()
        c_g = acf(dg)
        lags = np.arange(1, len(times))
        msd = np.array([np.mean(((com[l:] - com[:-l]) ** 2).sum(axis=2)) for l in lags]) if len(lags) else np.array([])
        d = float("nan")
        if len(lags) >= 4:
            half = lags[len(lags) // 2 :]
            d = float(np.polyfit(times[half], msd[len(lags) // 2 :], 1)[0] / 6.0)
        sel_b = np.array([kind_of_row[a] == name for a, _ in bonds], dtype=bool) if len(bonds) else np.zeros(0, bool)
        b = bonds[sel_b]
        blen = np.linalg.norm(pos[:, b[:, 1], :] - pos[:, b[:, 0], :], axis=2).ravel() if len(b) else np.zeros(0)
        sel_a = np.array([kind_of_row[a] == name for a, _, _ in angles], dtype=bool) if len(angles) else np.zeros(0, bool)
        a = angles[sel_a]
        theta = np.zeros(0)
        if len(a):
            b1 = pos[:, a[:, 1], :] - pos[:, a[:, 0], :]
            b2 = pos[:, a[:, 2], :] - pos[:, a[:, 1], :]
            c = (b1 * b2).sum(axis=2) / np.sqrt((b1**2).sum(axis=2) * (b2**2).sum(axis=2))
            theta = np.degrees(np.arccos(np.clip(c, -1, 1))).ravel()
        results[name] = dict(
            molecules=len(mols), beads=rows.shape[1], times=times, rg2_t=rg2.mean(axis=1), re2_t=re2.mean(axis=1),
            rg2=mean_error(rg2.mean(axis=1)), re2=mean_error(re2.mean(axis=1)), c_e=c_e, c_g=c_g,
            tau_e=relaxation_time(times, c_e), tau_e_blocks=tau_blocks, tau_g=relaxation_time(times, c_g), msd=msd, lags=times[1:], d=d,
            bond_lengths=blen, angles=theta)
    return results


def write(results, out):
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "chains_summary.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["kind", "molecules", "beads", "rg2", "rg2_err", "re2", "re2_err", "tau_e", "tau_g", "d_com",
                    "bond_length_mean", "angle_mean_deg"])
        for k, r in results.items():
            w.writerow([k, r["molecules"], r["beads"], *r["rg2"], *r["re2"], r["tau_e"], r["tau_g"], r["d"],
                        np.mean(r["bond_lengths"]) if len(r["bond_lengths"]) else "",
                        np.mean(r["angles"]) if len(r["angles"]) else ""])
    with open(os.path.join(out, "chains_timeseries.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["kind", "time", "rg2", "re2", "acf_re", "acf_rg2", "msd_com"])
        for k, r in results.items():
            for i, t in enumerate(r["times"]):
                w.writerow([k, t, r["rg2_t"][i], r["re2_t"][i], r["c_e"][i], r["c_g"][i],
                            0.0 if i == 0 else r["msd"][i - 1]])
    for key, fname, rng in (("bond_lengths", "bond_length_distribution.csv", None),
                            ("angles", "angle_distribution.csv", (0.0, 180.0))):
        with open(os.path.join(out, fname), "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["kind", "bin_centre", "probability_density"])
            for k, r in results.items():
                x = r[key]
                if len(x) == 0:
                    continue
                h, edges = np.histogram(x, bins=50, range=rng, density=True)
                for c, v in zip(0.5 * (edges[1:] + edges[:-1]), h):
                    w.writerow([k, c, v])


def plot(results, out):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(2, 2, figsize=(10, 8))
    for k, r in results.items():
        ax[0, 0].plot(r["times"], r["rg2_t"], label=f"{k}: $R_g^2$")
        ax[0, 0].plot(r["times"], r["re2_t"], "--", label=f"{k}: $R_e^2$")
        ax[0, 1].plot(r["times"], r["c_e"], label=f"{k}: $C_e$, $\\tau$ = {r['tau_e']:.3g}")
        ax[0, 1].plot(r["times"], r["c_g"], "--", label=f"{k}: $C_g$")
        if len(r["bond_lengths"]):
            ax[1, 0].hist(r["bond_lengths"], bins=50, density=True, histtype="step", label=k)
        if len(r["angles"]):
            ax[1, 1].hist(r["angles"], bins=36, range=(0, 180), density=True, histtype="step", label=k)
    ax[0, 0].set(xlabel="t", ylabel="mean square size", title="size")
    ax[0, 1].set(xlabel="lag t", ylabel="autocorrelation", title="relaxation")
    ax[0, 1].axhline(np.exp(-1), color="gray", lw=0.5)
    ax[1, 0].set(xlabel="bond length", ylabel="probability density", title="bond lengths")
    ax[1, 1].set(xlabel="bond angle (degrees, 0 = straight)", ylabel="probability density", title="bond angles")
    for a in ax.ravel():
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "chains.png"), dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("trajectory")
    ap.add_argument("--dt", type=float, required=True, help="time step of the run (integrator.dt)")
    ap.add_argument("--out", default="chains")
    ap.add_argument("--skip", type=int, default=0, help="frames to drop at the start (equilibration)")
    ap.add_argument("--no-plot", action="store_true")
    a = ap.parse_args()
    res = analyse(a.trajectory, a.dt, a.skip)
    write(res, a.out)
    if not a.no_plot:
        plot(res, a.out)
    for k, r in res.items():
        print(f"{k}: {r['molecules']} molecules of {r['beads']} beads, <Rg^2> = {r['rg2'][0]:.4g} +- {r['rg2'][1]:.2g}, "
              f"<Re^2> = {r['re2'][0]:.4g} +- {r['re2'][1]:.2g}, tau_e = {r['tau_e']:.4g}, D_com = {r['d']:.4g}")


if __name__ == "__main__":
    main()
