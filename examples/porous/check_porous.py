#!/usr/bin/python3
"""Darcy's law and the permeability of a porous run (examples/porous/README.md).

usage: check_porous.py --run CONFIG OUT_DIR [--run CONFIG OUT_DIR ...] [--mu MU] [--mu-err E]
                       [--blocks B] [--json FILE] [--plot FILE]

Each run is a config with an image solid (`[[solid]] shape = "image"`, its packing.json beside the
image: disc centres and radius) and the directory of its run: drag.csv (the drag on the solid and the
mean fluid velocity every walls.drag_every steps after walls.drag_start) and the binned fields
(<name>.csv, [analysis.fields], averaged over the same steps). Per run:

  N          fluid particles (the fields' density summed over the bins; constant during a run)
  u          interstitial (particle-averaged) velocity along x, mean of drag.csv with the error of B
             blocks; the two halves of the series are compared (steady state)
  rho_b      bulk fluid density: mean density of the bins more than 1 r_c from every disc
  q          Darcy (superficial) velocity = total fluid momentum / (rho_b x box volume) = N m u / (rho_b V);
             also from the velocity map: bin velocities times the bins' fluid fractions (from the
             image's pixels), over the box volume
  K          permeability = q mu / (rho_b g) (seed 004 Eq. 13, with rho the mass density rho_b m)
  Re         rho_b u d / mu, d the disc diameter
  F          drag on the solid along x (drag.csv, B blocks) against the body force on the fluid N m g

Over all runs: K from the slope of q against g (least squares through the origin), the Spielman-Goren
permeability of fibres perpendicular to the flow at the image's solid fraction phi (fibre radius a):
1/(4 phi) = 1/2 + (sqrt(K)/a) K1(a/sqrt(K)) / K0(a/sqrt(K)) (Spielman and Goren's original form, with
the fibre radius; seed 004 prints it as Eq. 12 with the diameter d in place of a, which gives 4 times
the K and is also reported; scipy.special.k0, k1), the solid fraction phi' and fibre radius a' for
which it gives the measured K (as seed 004 does with phi' in Figs. 11-12), and the Kozeny-Carman form
K = eps^3 a^2 / (4 k phi^2) with k = 5.

For context (not from the seeds) it also gives the permeability of a square array of fibres at the same
phi, Drummond & Tahir's series K/a^2 = (-ln phi - 1.476 + 2 phi - 1.774 phi^2 + 4.076 phi^3) / (8 phi)
(Int. J. Multiphase Flow 10 (1984) 515; for phi up to about 0.3).

mu is the fluid's shear viscosity (default 3.64 +- 0.02, measured for this fluid by reverse Poiseuille
flow; seed 004 quotes 2.40); K is proportional to it. Writes the JSON
summary (default OUT_DIR/porous_check.json of the first run) and, with --plot, a PNG of q against g.
Exit code 1 when a check fails: the halves of u differ by more than 3 combined errors, the drag
differs from N m g by more than 3 errors + 2%, or the q/g ratios of the runs differ by more than
3 combined errors (Darcy's law).
"""
import argparse
import json
import math
import os
import sys
import tomllib

import numpy as np

KOZENY = 5.0


def fail(message):
    print(f"check_porous.py: error: {message}", file=sys.stderr)
    sys.exit(2)


def block_mean(x, blocks):
    """Mean and standard error of the mean from `blocks` equal blocks."""
    parts = np.array_split(np.asarray(x, float), blocks)
    means = np.array([p.mean() for p in parts])
    return float(np.asarray(x, float).mean()), float(means.std(ddof=1) / math.sqrt(blocks))


def read_csv(path):
    if not os.path.isfile(path):
        fail(f"file not found: {path}")
    return np.genfromtxt(path, delimiter=",", names=True, dtype=float)


def packing_of(cfg, config_path):
    solids = [s for s in cfg.get("solid", []) if s.get("shape") == "image"]
    if len(solids) != 1:
        fail(f"{config_path}: expected one [[solid]] with shape = \"image\"")
    image = os.path.join(os.path.dirname(os.path.abspath(config_path)), solids[0]["file"])
    info = image[:-4] + ".json" if image.endswith(".pgm") else image + ".json"
    if not os.path.isfile(info):
        fail(f"{info} not found (make_packing.py writes it beside the image)")
    with open(info) as f:
        return solids[0]["name"], json.load(f)


def image_of(cfg, config_path):
    solid = [s for s in cfg["solid"] if s.get("shape") == "image"][0]
    return os.path.join(os.path.dirname(os.path.abspath(config_path)), solid["file"])


def read_pgm(path):
    """A plain-text (P2) PGM as an array [iy, ix] with iy = 0 at y = 0 (solid where nonzero)."""
    words = []
    with open(path) as f:
        for line in f:
            words += line.split("#", 1)[0].split()
    if words[0] != "P2":
        fail(f"{path}: only plain-text (P2) PGM files are read here")
    nx, ny = int(words[1]), int(words[2])
    pixels = np.array(words[4:4 + nx * ny], dtype=int).reshape(ny, nx)
    return pixels[::-1] != 0


def fluid_fraction(image, bins, fields):
    """Fluid fraction of each bin of an xy-grid of fields from the image's pixels (bins must hold whole
    pixels)."""
    solid = read_pgm(image)
    ny, nx = solid.shape
    bx, by = bins[0], bins[1]
    if nx % bx or ny % by:
        fail(f"{image}: {nx} x {ny} pixels do not split into {bx} x {by} bins")
    frac = 1 - solid.reshape(by, ny // by, bx, nx // bx).mean(axis=(1, 3))  # [jy, jx]
    return frac[fields["iy"].astype(int), fields["ix"].astype(int)]


def analyse(config_path, out, mu, blocks):
    with open(config_path, "rb") as f:
        cfg = tomllib.load(f)
    box = np.array(cfg["system"]["box"], float)
    volume = float(box.prod())
    fluid = cfg["species"][0]
    g = float(fluid["body_force"][0])
    mass = float(fluid.get("mass", 1.0))
    body, packing = packing_of(cfg, config_path)
    if not np.allclose(packing["size"], box[:2]):
        fail(f"{config_path}: box {box[:2].tolist()} does not match the packing {packing['size']}")

    drag = read_csv(os.path.join(out, "drag.csv"))
    if drag.size < 2 * blocks:
        fail(f"{out}/drag.csv: only {drag.size} samples, need at least {2 * blocks}")
    u_series = drag["fluid_vx"]
    f_series = drag[f"{body}_fx"]
    u, u_err = block_mean(u_series, blocks)
    half = len(u_series) // 2
    u1, e1 = block_mean(u_series[:half], blocks // 2)
    u2, e2 = block_mean(u_series[half:], blocks // 2)
    force, force_err = block_mean(f_series, blocks)

    name = cfg["analysis"]["fields"]["name"]
    fields = read_csv(os.path.join(out, f"{name}.csv"))
    with open(os.path.join(out, f"{name}.json")) as f:
        fj = json.load(f)
    bin_volume = float(fj["bin_volume"])
    density = fields["density"]
    n_fluid = float(density.sum() * bin_volume)
    # Bins whose centre lies more than 1 r_c from every disc surface (periodic distances).
    centres = np.array(packing["centres"])
    px, py = fields["x"], fields["y"]
    gap = np.full(px.shape, np.inf)
    for c in centres:
        dx = np.abs(px - c[0])
        dx = np.minimum(dx, box[0] - dx)
        dy = np.abs(py - c[1])
        dy = np.minimum(dy, box[1] - dy)
        gap = np.minimum(gap, np.hypot(dx, dy) - packing["radius"])
    bulk = gap > 1.0
    rho_b = float(density[bulk].mean()) * mass
    # Superficial velocity also from the velocity map: each bin's velocity times its fluid fraction
    # (from the image's pixels), summed over the box volume.
    vx = np.nan_to_num(fields["vx"]) * (density > 0)
    fraction = fluid_fraction(image_of(cfg, config_path), fj["bins"], fields)
    q_map = float((vx * fraction).sum() * bin_volume / volume)

    q = n_fluid * mass * u / (rho_b * volume)
    q_err = q * u_err / abs(u)
    K = q * mu / (rho_b * g)
    K_err = K * u_err / abs(u)
    d = 2 * packing["radius"]
    return {
        "config": config_path, "out": out, "g": g, "fluid_particles": round(n_fluid),
        "samples": int(drag.size), "first_step": int(drag["step"][0]), "last_step": int(drag["step"][-1]),
        "u": u, "u_err": u_err, "u_first_half": [u1, e1], "u_second_half": [u2, e2],
        "halves_agree": abs(u1 - u2) <= 3 * math.hypot(e1, e2),
        "bulk_density": rho_b, "porosity_particles": n_fluid / (rho_b / mass * volume),
        "q": q, "q_err": q_err, "q_from_velocity_map": q_map, "K": K, "K_err": K_err,
        "Re": rho_b * u * d / mu,
        "drag_x": force, "drag_x_err": force_err, "body_force_total": n_fluid * mass * g,
        "drag_balances": abs(force - n_fluid * mass * g) <= 3 * force_err + 0.02 * n_fluid * mass * g,
    }


def spielman_goren(phi, a):
    """K of fibres of radius a perpendicular to the flow at solid fraction phi (None if phi >= 0.5)."""
    from scipy.optimize import brentq
    from scipy.special import k0, k1

    lhs = 1 / (4 * phi) - 0.5
    if lhs <= 0:
        return None
    # (sqrt K / a) K1(x) / K0(x) with x = a / sqrt(K): decreasing in x from infinity to 0.
    x = brentq(lambda x: k1(x) / (x * k0(x)) - lhs, 1e-6, 700)
    return a * a / (x * x)


def phi_for(K, a):
    """Solid fraction phi' at which Spielman-Goren gives K for fibres of radius a."""
    from scipy.special import k0, k1

    x = a / math.sqrt(K)
    return 1 / (4 * (0.5 + k1(x) / (x * k0(x))))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--run", nargs=2, action="append", required=True, metavar=("CONFIG", "OUT_DIR"))
    ap.add_argument("--mu", type=float, default=3.64)
    ap.add_argument("--mu-err", type=float, default=0.02)
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--json")
    ap.add_argument("--plot")
    a = ap.parse_args()
    if a.mu <= 0:
        fail(f"--mu {a.mu} must be positive")
    if a.blocks < 4 or a.blocks % 2:
        fail(f"--blocks {a.blocks} must be even and >= 4")

    runs = [analyse(c, o, a.mu, a.blocks) for c, o in a.run]
    runs.sort(key=lambda r: r["g"])
    with open(a.run[0][0], "rb") as f:
        cfg = tomllib.load(f)
    _, packing = packing_of(cfg, a.run[0][0])
    phi = packing["solid_fraction_pixels"]
    radius = packing["radius"]

    print(f"viscosity mu = {a.mu} +- {a.mu_err}; solid fraction (image) {phi:.4f}, fibre radius {radius}")
    print("g       N      u (interstitial)      halves                        rho_b   q (Darcy)             "
          "q (map)  K                Re     drag_x / N m g")
    for r in runs:
        print(f"{r['g']:<7g} {r['fluid_particles']:<6d} {r['u']:.5f} +- {r['u_err']:.5f}   "
              f"{r['u_first_half'][0]:.5f} / {r['u_second_half'][0]:.5f} {'ok ' if r['halves_agree'] else 'BAD'}   "
              f"{r['bulk_density']:.3f}   {r['q']:.5f} +- {r['q_err']:.5f}   {r['q_from_velocity_map']:.5f}  "
              f"{r['K']:.4f} +- {r['K_err']:.4f}  {r['Re']:.3f}  {r['drag_x']:.1f} +- {r['drag_x_err']:.1f} / "
              f"{r['body_force_total']:.1f} {'ok' if r['drag_balances'] else 'BAD'}")

    # Darcy: q = (K rho_b / mu) g, through the origin, weighted by the errors of q.
    gs = np.array([r["g"] for r in runs])
    qs = np.array([r["q"] for r in runs])
    qe = np.array([r["q_err"] for r in runs])
    rho_b = float(np.mean([r["bulk_density"] for r in runs]))
    w = 1 / qe ** 2
    slope = float((w * gs * qs).sum() / (w * gs * gs).sum())
    slope_err = float(1 / math.sqrt((w * gs * gs).sum()))
    chi2 = float((w * (qs - slope * gs) ** 2).sum())
    K = slope * a.mu / rho_b
    K_err_stat = slope_err * a.mu / rho_b
    K_err_mu = K * a.mu_err / a.mu
    ratios = qs / gs
    ratio_err = qe / gs
    darcy_ok = all(abs(ratios[i] - ratios[j]) <= 3 * math.hypot(ratio_err[i], ratio_err[j])
                   for i in range(len(runs)) for j in range(i + 1, len(runs)))
    K_sg = spielman_goren(phi, radius)
    phi_prime = phi_for(K, radius)
    radius_prime = radius * math.sqrt(phi_prime / phi)
    eps = 1 - phi
    K_kc = eps ** 3 * radius ** 2 / (4 * KOZENY * phi ** 2)
    K_square = radius ** 2 * (-math.log(phi) - 1.476 + 2 * phi - 1.774 * phi ** 2 + 4.076 * phi ** 3) / (8 * phi)
    print(f"Darcy fit q = s g: s = {slope:.4f} +- {slope_err:.4f} (chi^2 = {chi2:.2f} for {len(runs) - 1} "
          f"degrees of freedom); q/g of the runs: " + ", ".join(f"{x:.4f} +- {e:.4f}" for x, e in zip(ratios, ratio_err))
          + (" (consistent)" if darcy_ok else " (INCONSISTENT)"))
    print(f"K = s mu / rho_b = {K:.4f} +- {K_err_stat:.4f} (statistics) +- {K_err_mu:.4f} (mu); "
          f"K / d^2 = {K / (2 * radius) ** 2:.5f}")
    if K_sg is not None:
        print(f"Spielman-Goren at phi = {phi:.4f}, a = {radius}: K = {K_sg:.4f}; measured / theory = {K / K_sg:.3f}")
        print(f"  as printed in seed 004 Eq. 12 (diameter d = {2 * radius:g} in place of a): K = {4 * K_sg:.4f}; "
              f"measured / that = {K / (4 * K_sg):.3f}")
    print(f"Spielman-Goren gives the measured K at phi' = {phi_prime:.4f} (image {phi:.4f}), i.e. fibre radius "
          f"a' = {radius_prime:.3f} at the same number of fibres (a' - a = {radius_prime - radius:+.3f})")
    print(f"Kozeny-Carman (k = {KOZENY}): K = {K_kc:.4f}; measured / KC = {K / K_kc:.3f}")
    print(f"square array at the same phi (Drummond-Tahir, not from the seeds): K = {K_square:.4f}; "
          f"measured / square = {K / K_square:.3f}")

    balances = all(r["drag_balances"] for r in runs)
    halves = all(r["halves_agree"] for r in runs)
    summary = {
        "mu": a.mu, "mu_err": a.mu_err, "solid_fraction_image": phi, "fibre_radius": radius,
        "runs": runs, "darcy_slope": slope, "darcy_slope_err": slope_err, "darcy_chi2": chi2,
        "bulk_density": rho_b, "K": K, "K_err_stat": K_err_stat, "K_err_mu": K_err_mu,
        "K_over_d2": K / (2 * radius) ** 2, "K_spielman_goren": K_sg,
        "ratio_spielman_goren": K / K_sg if K_sg else None,
        "K_seed004_eq12_with_diameter": 4 * K_sg if K_sg else None, "phi_prime": phi_prime, "radius_prime": radius_prime,
        "K_square_array": K_square, "ratio_square_array": K / K_square, "K_kozeny_carman": K_kc, "kozeny_constant": KOZENY, "ratio_kozeny_carman": K / K_kc,
        "checks": {"halves_agree": halves, "drag_balances_body_force": balances, "darcy_linear": darcy_ok},
    }
    path = a.json or os.path.join(a.run[0][1], "porous_check.json")
    with open(path, "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")
    print(f"wrote {path}")

    if a.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 3.8))
        ax.errorbar(gs, qs, yerr=qe, fmt="o", capsize=3, label="DPD, image packing")
        gg = np.linspace(0, gs.max() * 1.1, 50)
        ax.plot(gg, slope * gg, "-", label=f"Darcy fit: K = {K:.3f}")
        if K_sg is not None:
            ax.plot(gg, K_sg * rho_b / a.mu * gg, "--", label=f"Spielman-Goren: K = {K_sg:.3f}")
        ax.set_xlabel("body force g")
        ax.set_ylabel("Darcy velocity q")
        ax.set_title(f"random discs, phi = {phi:.3f}, mu = {a.mu:g}")
        ax.set_xlim(0, None)
        ax.set_ylim(0, None)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(a.plot, dpi=150)
        print(f"wrote {a.plot}")

    if not (balances and halves and darcy_ok):
        sys.exit(1)


if __name__ == "__main__":
    main()
