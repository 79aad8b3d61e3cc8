#!/usr/bin/python3
"""Mean Nusselt number of the heated cavity (examples/convection/README.md).

usage: check_cavity.py CONFIG OUT_DIR [CONFIG OUT_DIR ...] [--D 0.396] [--nu 0.276] [--png FILE]

Reads the run's binned fields OUT_DIR/cavity.csv ([analysis.fields] "cavity": fluid density, mass-
weighted velocity and mean internal temperature on a grid in x and z, averaged over y and time) and,
when present, the snapshots OUT_DIR/snap_<step>.csv/.json of the same file written during the run
(write_every; copied by the command in README.md), which give block averages for the error bars.

- Fluid temperatures at the walls: the z-average of the fluid's T(x) near each wall (the 3 columns of
  bins within 1.5 of the surface) extrapolated linearly to the surface. dT_f = T_f(hot) - T_f(cold)
  is the fluid's own difference, smaller than the walls' (1.1 - 0.9) by the two Kapitza jumps.
- Nu = 1 + L <(rho/rho_0) u_x (T - <T>_col)> / (D dT_f), the cavity average of the convective flux
  of the binned mean flow over the conduction flux D dT_f / L of pure conduction with the same fluid
  temperature difference (the conduction part of the cavity-averaged flux is exactly D dT_f / L with
  these end points). Also: Nu_core, the heat flux through the columns of bins in the central half of
  the cavity (convective part plus -D dT/dx of the z-averaged profile there), over D dT_f / L: it uses
  D only where the fluid is bulk (next to a wall the fluid is layered and its D differs); in pure
  conduction (cavity_conduction.toml) it is the bulk slope over dT_f / L. The binned product u_x T misses the correlation of the particles' velocity and
  temperature fluctuations inside a bin: that is the heat the particles carry by self-diffusion, which
  is part of the measured D (calibrate.toml), so it is counted once, in the conduction term.
- Ra = g beta dT_f L^3 / (nu D), Pr = nu / D; Mach = max |u| / c with the isothermal sound speed c = 4.0 (c^2 = kT + 2 alpha a rho,
  seed 000 Eqs 13, 15; as in docs/validation.md section 6). max |u| is that of the binned mean
  velocity, which still carries the bins' thermal noise (about 0.03), so it is an upper bound.
- The reference: de Vahl Davis (1983), Pr = 0.71: Nu = 1.118 at Ra = 10^3, 2.243 at 10^4, 4.519 at
  10^5; between them Nu is interpolated as a power law in Ra (log-log).
Writes OUT_DIR/cavity_check.json for every run and, with --png, one picture with a panel per run: the
fluid temperature with 9 isotherms (tenths of dT_f) and streamlines of the binned mean velocity
(smoothed over 3 x 3 bins). Also printed: the peak u_x on the vertical mid-line and the peak u_z on
the horizontal one (velocity smoothed over 3 x 3 bins), in units of D / L, against de Vahl Davis's.
"""
import csv
import glob
import json
import os
import sys
import tomllib

import numpy as np

DE_VAHL_DAVIS = [(1e3, 1.118), (1e4, 2.243), (1e5, 4.519)]  # Ra, mean Nu (Pr = 0.71)
# de Vahl Davis's peak velocities in units of D / L: u_x on the vertical mid-line, u_z on the horizontal one
DE_VAHL_DAVIS_SPEEDS = {1e3: (3.649, 3.697), 1e4: (16.178, 19.617), 1e5: (34.73, 68.59)}
SOUND_SPEED = 4.0


def reference_nu(ra):
    """de Vahl Davis's mean Nu interpolated (log-log) at ra; None outside 10^3..10^5."""
    for (r0, n0), (r1, n1) in zip(DE_VAHL_DAVIS, DE_VAHL_DAVIS[1:]):
        if r0 <= ra <= r1:
            p = np.log(n1 / n0) / np.log(r1 / r0)
            return n0 * (ra / r0) ** p
    if ra < DE_VAHL_DAVIS[0][0]:  # below 10^3: Nu - 1 ~ Ra^2 (weak convection), through (1e3, 1.118)
        return 1 + (DE_VAHL_DAVIS[0][1] - 1) * (ra / DE_VAHL_DAVIS[0][0]) ** 2
    return None


def read_grid(path):
    rows = list(csv.DictReader(open(path)))
    ix = np.array([int(r["ix"]) for r in rows])
    iz = np.array([int(r["iz"]) for r in rows])
    nx, nz = ix.max() + 1, iz.max() + 1

    def grid(key):
        g = np.full((nx, nz), np.nan)
        g[ix, iz] = [float(r[key]) for r in rows]
        return g
    return {k: grid(k) for k in ("x", "z", "density", "vx", "vz", "mean_temp")}


def block(later, earlier, n_later, n_earlier):
    """Averages over the samples between two cumulative files (weights density x samples)."""
    w2, w1 = later["density"] * n_later, earlier["density"] * n_earlier
    w = w2 - w1
    out = {"x": later["x"], "z": later["z"], "density": w / (n_later - n_earlier)}
    for k in ("vx", "vz", "mean_temp"):
        with np.errstate(invalid="ignore", divide="ignore"):  # empty bins (inside the walls) stay NaN
            out[k] = (np.nan_to_num(later[k]) * w2 - np.nan_to_num(earlier[k]) * w1) / w
    return out


def analyse(g, x0, x1, z0, z1, d, rho0):
    x, z = g["x"][:, 0], g["z"][0, :]
    cx, cz = (x > x0) & (x < x1), (z > z0) & (z < z1)
    t = g["mean_temp"][np.ix_(cx, cz)]
    ux = g["vx"][np.ix_(cx, cz)]
    uz = g["vz"][np.ix_(cx, cz)]
    rho = g["density"][np.ix_(cx, cz)]
    xs = x[cx]
    prof = t.mean(axis=1)  # T(x) averaged over z
    near_hot = xs < x0 + 1.5
    near_cold = xs > x1 - 1.5
    t_hot = np.polyval(np.polyfit(xs[near_hot], prof[near_hot], 1), x0)
    t_cold = np.polyval(np.polyfit(xs[near_cold], prof[near_cold], 1), x1)
    dt = t_hot - t_cold
    length = x1 - x0
    conv = (rho / rho0) * ux * (t - t.mean(axis=1, keepdims=True))
    # Nu through each vertical column of bins, with the column's own conduction -D dT/dx (of the
    # z-averaged profile): constant in a steady state; its ends are the walls' Nusselt numbers.
    nu_cols = (conv.mean(axis=1) / d - np.gradient(prof, xs)) * length / dt
    mid_x = np.argsort(np.abs(xs - 0.5 * (x0 + x1)))[:2]  # the two columns nearest the vertical mid-line
    zs = z[cz]
    mid_z = np.argsort(np.abs(zs - 0.5 * (z0 + z1)))[:2]
    # peaks of the velocity smoothed over 3 x 3 bins (the bins' noise would bias a raw maximum upwards)
    u_mid = float(np.max(smooth(ux)[mid_x, :].mean(axis=0))) * length / d
    w_mid = float(np.max(smooth(uz)[:, mid_z].mean(axis=1))) * length / d
    core = np.abs(xs - 0.5 * (x0 + x1)) < 0.25 * length  # the columns of the central half, away from the walls
    return {"Nu": float(1 + length * conv.mean() / (d * dt)), "Nu_columns": nu_cols,
            "Nu_core": float(nu_cols[core].mean()), "u_mid_max": u_mid, "w_mid_max": w_mid,
            "t_hot_fluid": t_hot, "t_cold_fluid": t_cold, "dT_fluid": dt,
            "u_max": float(np.nanmax(np.hypot(ux, uz))), "x": xs, "z": z[cz], "T": t, "ux": ux, "uz": uz}


def main():
    args = sys.argv[1:]
    options = {}
    for name in ("--D", "--nu", "--png"):
        if name in args:
            k = args.index(name)
            options[name] = args[k + 1]
            del args[k:k + 2]
    if len(args) < 2 or len(args) % 2:
        sys.exit(__doc__)
    d = float(options.get("--D", 0.396))
    nu = float(options.get("--nu", 0.276))
    panels = [check_run(config, out, d, nu) for config, out in zip(args[0::2], args[1::2])]
    if "--png" in options:
        plot(panels, options["--png"])


def check_run(config, out, d, nu):
    with open(config, "rb") as f:
        cfg = tomllib.load(f)
    solids = {s["name"]: s for s in cfg["solid"]}
    x0, x1 = solids["hot"]["point"][0], solids["cold"]["point"][0]
    z0, z1 = solids["bottom"]["point"][2], solids["top"]["point"][2]
    rho0 = next(s["density"] for s in cfg["species"] if not s.get("frozen", False))
    b = cfg["buoyancy"]
    g_beta = b["beta"] * float(np.linalg.norm(b["gravity"]))
    length = x1 - x0

    whole = analyse(read_grid(os.path.join(out, "cavity.csv")), x0, x1, z0, z1, d, rho0)
    # Block averages from the snapshots of the cumulative averages.
    snaps = []
    for p in glob.glob(os.path.join(out, "snap_*.json")):
        meta = json.load(open(p))
        snaps.append((meta["last_step"], meta["samples"], p[:-5] + ".csv"))
    snaps.sort()
    blocks = []
    for (s1, n1, p1), (s2, n2, p2) in zip(snaps, snaps[1:]):
        r = analyse(block(read_grid(p2), read_grid(p1), n2, n1), x0, x1, z0, z1, d, rho0)
        blocks.append({"steps": [s1, s2], "Nu": r["Nu"], "Nu_core": r["Nu_core"], "dT_fluid": r["dT_fluid"]})
    if snaps:  # the first block: from the start of sampling to the first snapshot
        r = analyse(read_grid(snaps[0][2]), x0, x1, z0, z1, d, rho0)
        blocks.insert(0, {"steps": [None, snaps[0][0]], "Nu": r["Nu"], "Nu_core": r["Nu_core"], "dT_fluid": r["dT_fluid"]})
    nus = np.array([bl["Nu"] for bl in blocks])
    nu_err = float(nus.std(ddof=1) / np.sqrt(len(nus))) if len(nus) > 1 else None
    cores = np.array([bl["Nu_core"] for bl in blocks])
    core_err = float(cores.std(ddof=1) / np.sqrt(len(cores))) if len(cores) > 1 else None

    ra = g_beta * whole["dT_fluid"] * length ** 3 / (nu * d)
    ref = reference_nu(ra)
    result = {"L": length, "D": d, "nu": nu, "Pr": nu / d, "g_beta": g_beta,
              "T_hot_fluid": whole["t_hot_fluid"], "T_cold_fluid": whole["t_cold_fluid"],
              "dT_fluid": whole["dT_fluid"], "Ra": ra, "Nu": whole["Nu"], "Nu_block_error": nu_err,
              "Nu_core": whole["Nu_core"], "Nu_core_block_error": core_err,
              "Nu_blocks": blocks, "Nu_columns_min_max": [float(whole["Nu_columns"].min()), float(whole["Nu_columns"].max())],
              "Nu_columns": [float(v) for v in whole["Nu_columns"]],
              "Nu_mid_plane": float(np.mean(whole["Nu_columns"][np.argsort(np.abs(whole["x"] - 0.5 * (x0 + x1)))[:2]])),
              "Nu_de_Vahl_Davis_at_Ra": ref, "u_max": whole["u_max"], "Mach": whole["u_max"] / SOUND_SPEED,
              "u_mid_max_L_over_D": whole["u_mid_max"], "w_mid_max_L_over_D": whole["w_mid_max"]}
    with open(os.path.join(out, "cavity_check.json"), "w") as f:
        json.dump(result, f, indent=1)
    walls = {sp["name"]: sp.get("temperature") for sp in cfg["species"]}
    print("fluid at the walls %.4f, %.4f: dT_f = %.4f (walls %g - %g)" % (
        whole["t_hot_fluid"], whole["t_cold_fluid"], whole["dT_fluid"], walls["hot"], walls["cold"]))
    print("Pr = %.3f, Ra = %.0f, max |u| = %.3f, Mach = %.3f" % (nu / d, ra, whole["u_max"], result["Mach"]))
    print("Nu = %.3f%s (through the columns of bins %.3f..%.3f, mid-plane %.3f); blocks: %s" % (
        whole["Nu"], "" if nu_err is None else " +- %.3f" % nu_err, *result["Nu_columns_min_max"], result["Nu_mid_plane"],
        ", ".join("%.3f" % v for v in nus)))
    print("Nu through the central half of the columns (bulk D): %.3f%s" % (
        whole["Nu_core"], "" if core_err is None else " +- %.3f" % core_err))
    print("peak u_x on the vertical mid-line %.2f D/L, peak u_z on the horizontal one %.2f D/L%s" % (
        whole["u_mid_max"], whole["w_mid_max"], "".join(
            "; de Vahl Davis at Ra = %.0e: %.2f, %.2f" % (k, *v) for k, v in DE_VAHL_DAVIS_SPEEDS.items() if 0.5 < ra / k < 2)))
    if ref is not None:
        print("de Vahl Davis at this Ra: Nu = %.3f (%+.1f %%)" % (ref, 100 * (whole["Nu"] / ref - 1)))
    return whole, (x0, x1, z0, z1), ra


def smooth(a):
    """3 x 3 box average (edges: the bins that exist), for the streamlines only."""
    p = np.pad(a, 1, mode="edge")
    return sum(p[i:i + a.shape[0], j:j + a.shape[1]] for i in range(3) for j in range(3)) / 9


def plot(panels, png):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 4.4), squeeze=False)
    for ax, (r, (x0, x1, z0, z1), ra) in zip(axes[0], panels):
        xx, zz = np.meshgrid(r["x"], r["z"], indexing="ij")
        levels = np.linspace(r["t_cold_fluid"], r["t_hot_fluid"], 11)
        cs = ax.contourf(xx, zz, r["T"], levels=40, cmap="coolwarm")
        ax.contour(xx, zz, r["T"], levels=levels[1:-1], colors="k", linewidths=0.7)
        ax.streamplot(r["x"], r["z"], smooth(r["ux"]).T, smooth(r["uz"]).T, color="0.3", density=0.8,
                      linewidth=0.6, arrowsize=0.6)
        fig.colorbar(cs, ax=ax, label="fluid temperature", shrink=0.85)
        ax.set_xlim(x0, x1)
        ax.set_ylim(z0, z1)
        ax.set_aspect("equal")
        ax.set_xlabel("x (hot wall on the left)")
        ax.set_ylabel("z (gravity along -z)")
        ax.set_title("Ra = %.0f, Nu = %.3f" % (ra, r["Nu"]))
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
