#!/usr/bin/python3
"""Checks a channel run between frozen walls (examples/channel/README.md).

usage: check_channel.py poiseuille|couette OUT_DIR [--config FILE]

Bins the fluid particles of OUT_DIR/trajectory.gsd (frames after walls.drag_start) along z into density
and velocity profiles, with error bars from 10 blocks of frames, and
  poiseuille: fits a parabola to the interior (more than 1 r_c from the walls) and gives the viscosity
              eta = rho g / (-u''), compared with the reverse-Poiseuille value of the same fluid
              (examples/poiseuille: 0.867 +- 0.003) within 3%, and the slip length at each wall
              (distance beyond the wall at which the parabola reaches zero), which must be below 0.1;
  couette:    fits a line to the interior, compares its values at the walls with the wall velocities,
              and gives the viscosity from the shear stress on the moving wall (drag_summary.csv).
Writes profiles.csv, channel_check.json and channel_profiles.png into OUT_DIR; exit code 1 when a
criterion fails.
"""
import json
import os
import sys
import tomllib

import numpy as np

ETA_REVERSE_POISEUILLE = 0.867  # examples/poiseuille, docs/validation.md section 4
ETA_REVERSE_POISEUILLE_ERR = 0.003
BIN = 0.2
BLOCKS = 10


def profiles(out, cfg):
    import gsd.hoomd

    lx, ly, lz = cfg["system"]["box"]
    start = cfg.get("walls", {}).get("drag_start", 0)
    nb = int(round(lz / BIN))
    counts, sums = [], []
    with gsd.hoomd.open(os.path.join(out, "trajectory.gsd"), "rb") as traj:
        for frame in traj:
            if frame.configuration.step <= start:
                continue
            fluid = frame.particles.typeid == 0
            z = frame.particles.position[fluid, 2].astype(float) + lz / 2  # GSD centres the box
            vx = frame.particles.velocity[fluid, 0].astype(float)
            k = np.clip((z / BIN).astype(int), 0, nb - 1)
            counts.append(np.bincount(k, minlength=nb))
            sums.append(np.bincount(k, weights=vx, minlength=nb))
    counts, sums = np.array(counts, float), np.array(sums, float)
    if len(counts) < BLOCKS:
        sys.exit(f"only {len(counts)} frames after step {start}: run longer or dump more often")
    z = (np.arange(nb) + 0.5) * BIN
    volume = lx * ly * BIN
    block_counts = np.array([c.sum(0) for c in np.array_split(counts, BLOCKS)])
    block_sums = np.array([s.sum(0) for s in np.array_split(sums, BLOCKS)])
    block_frames = np.array([len(c) for c in np.array_split(counts, BLOCKS)])
    with np.errstate(invalid="ignore", divide="ignore"):
        u_blocks = block_sums / block_counts
        rho_blocks = block_counts / (block_frames[:, None] * volume)
        u = sums.sum(0) / counts.sum(0)
    rho = counts.sum(0) / (len(counts) * volume)
    return z, rho, u, rho_blocks, u_blocks


def walls(cfg):
    """Lower and upper wall positions and velocities of the two plane solids (normal along z)."""
    lo = hi = None
    for s in cfg["solid"]:
        zc = s["point"][2]
        v = s.get("velocity", [0, 0, 0])[0]
        if s["normal"][2] > 0:
            lo = (zc, v)
        else:
            hi = (zc, v)
    return lo, hi


def fit(z, u, deg, mask):
    return np.polyfit(z[mask], u[mask], deg)


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ("poiseuille", "couette"):
        sys.exit(__doc__)
    mode, out = sys.argv[1], sys.argv[2]
    config = os.path.join(os.path.dirname(os.path.abspath(__file__)), mode + ".toml")
    if "--config" in sys.argv:
        config = sys.argv[sys.argv.index("--config") + 1]
    with open(config, "rb") as f:
        cfg = tomllib.load(f)
    (zlo, vlo), (zhi, vhi) = walls(cfg)
    z, rho, u, rho_b, u_b = profiles(out, cfg)
    inside = (z > zlo) & (z < zhi)
    interior = (z > zlo + 1.0) & (z < zhi - 1.0)
    rho_bulk = rho[interior].mean()
    near = (z > zlo) & (z < zlo + 1.0) | (z < zhi) & (z > zhi - 1.0)
    result = {
        "mode": mode,
        "frames": None,
        "bulk_density": rho_bulk,
        "near_wall_density_min_over_bulk": float(rho[near].min() / rho_bulk),
        "near_wall_density_max_over_bulk": float(rho[near].max() / rho_bulk),
    }
    ok = True
    if mode == "poiseuille":
        g = cfg["species"][0]["body_force"][0]
        mass = cfg["species"][0].get("mass", 1.0)

        def eta_slip(uu, rr):
            c = fit(z, uu, 2, interior)
            r = rr[interior].mean() * mass
            eta = -r * g / (2 * c[0])
            roots = np.sort(np.roots(c).real)
            return eta, zlo - roots[0], roots[1] - zhi

        eta, b_lo, b_hi = eta_slip(u, rho)
        per_block = np.array([eta_slip(u_b[k], rho_b[k]) for k in range(BLOCKS)])
        err = per_block.std(0, ddof=1) / np.sqrt(BLOCKS)
        dev = eta / ETA_REVERSE_POISEUILLE - 1
        result.update(eta=eta, eta_err=err[0], eta_reverse_poiseuille=ETA_REVERSE_POISEUILLE,
                      relative_difference=dev, slip_bottom=b_lo, slip_bottom_err=err[1], slip_top=b_hi,
                      slip_top_err=err[2], peak_velocity=float(u[inside].max()))
        print(f"viscosity from the channel parabola: {eta:.4f} +- {err[0]:.4f}; reverse Poiseuille "
              f"{ETA_REVERSE_POISEUILLE} +- {ETA_REVERSE_POISEUILLE_ERR}: {100 * dev:+.2f}% (criterion 3%)")
        print(f"slip length: bottom {b_lo:+.3f} +- {err[1]:.3f}, top {b_hi:+.3f} +- {err[2]:.3f} "
              f"(criterion |b| < 0.1)")
        ok = abs(dev) < 0.03 and abs(b_lo) < 0.1 and abs(b_hi) < 0.1
    else:
        def line(uu):
            c = fit(z, uu, 1, interior)
            return np.polyval(c, zlo), np.polyval(c, zhi), c[0]

        u_lo, u_hi, slope = line(u)
        per_block = np.array([line(u_b[k]) for k in range(BLOCKS)])
        err = per_block.std(0, ddof=1) / np.sqrt(BLOCKS)
        lx, ly, _ = cfg["system"]["box"]
        eta = None
        summary = os.path.join(out, "drag_summary.csv")
        if os.path.exists(summary):
            rows = [l.strip().split(",") for l in open(summary)]
            head, rows = rows[0], rows[1:]
            top = [r for r in rows if r[0] == "top"][0]
            fx, fx_err = float(top[head.index("fx")]), float(top[head.index("fx_err")])
            eta = -fx / (lx * ly * slope)
            result.update(top_wall_force=fx, top_wall_force_err=fx_err, eta_from_wall_stress=eta,
                          eta_from_wall_stress_err=abs(eta) * np.hypot(fx_err / fx, err[2] / slope))
        result.update(u_at_bottom=u_lo, u_at_bottom_err=err[0], u_at_top=u_hi, u_at_top_err=err[1],
                      wall_velocity_top=vhi, wall_velocity_bottom=vlo, shear_rate=slope, shear_rate_err=err[2])
        print(f"linear fit: u(bottom wall) = {u_lo:+.4f} +- {err[0]:.4f} (wall {vlo}), u(top wall) = "
              f"{u_hi:.4f} +- {err[1]:.4f} (wall {vhi}), shear rate {slope:.5f} +- {err[2]:.5f}")
        if eta is not None:
            print(f"viscosity from the shear stress on the moving wall: {eta:.4f} +- "
                  f"{result['eta_from_wall_stress_err']:.4f} (reverse Poiseuille {ETA_REVERSE_POISEUILLE})")
        # The wall velocity is reached at the wall within 3 error bars (plus 1% of the wall speed).
        tol = 0.01 * abs(vhi - vlo)
        ok = abs(u_lo - vlo) < 3 * err[0] + tol and abs(u_hi - vhi) < 3 * err[1] + tol
    print(f"near-wall density (within 1 r_c): {result['near_wall_density_min_over_bulk']:.3f} .. "
          f"{result['near_wall_density_max_over_bulk']:.3f} of the bulk {rho_bulk:.4f}")
    with open(os.path.join(out, "profiles.csv"), "w") as f:
        f.write("z,density,density_err,u,u_err\n")
        rho_err = rho_b.std(0, ddof=1) / np.sqrt(BLOCKS)
        u_err = np.nanstd(u_b, 0, ddof=1) / np.sqrt(BLOCKS)
        for k in range(len(z)):
            f.write(f"{z[k]:.3f},{rho[k]:.6g},{rho_err[k]:.3g},{u[k]:.6g},{u_err[k]:.3g}\n")
    result = {k: (float(v) if isinstance(v, (np.floating, float)) else v) for k, v in result.items()}
    result["passed"] = bool(ok)
    with open(os.path.join(out, "channel_check.json"), "w") as f:
        json.dump(result, f, indent=2)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        ax[0].plot(z[inside], u[inside], ".", label="measured")
        zz = np.linspace(zlo, zhi, 200)
        ax[0].plot(zz, np.polyval(fit(z, u, 2 if mode == "poiseuille" else 1, interior), zz), "-",
                   label="fit (interior)")
        ax[0].axvline(zlo, color="k", lw=0.5)
        ax[0].axvline(zhi, color="k", lw=0.5)
        ax[0].set_xlabel("z")
        ax[0].set_ylabel("u_x")
        ax[0].legend()
        ax[0].set_title(f"{mode} flow between frozen walls")
        ax[1].plot(z, rho, "-")
        ax[1].axvline(zlo, color="k", lw=0.5)
        ax[1].axvline(zhi, color="k", lw=0.5)
        ax[1].set_xlabel("z")
        ax[1].set_ylabel("fluid number density")
        ax[1].set_title("fluid density profile")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "channel_profiles.png"), dpi=110)
    except ImportError:
        pass
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
