#!/usr/bin/python3
"""Checks the tDPD run of two solutes diffusing from opposite sources (examples/diffusion/README.md), or
the eDPD run of heat conducted from opposite heat sources (examples/heat/transient.toml).

usage: check_diffusion.py OUT_DIR [--config FILE]

Reads OUT_DIR/trajectory.lammpstrj, bins each solute's concentration along x in every frame after the
first and fits, frame by frame, the diffusivity D whose Fourier solution of the heat equation (opposite
uniform sources +q / -q in the two halves of a periodic box, from a uniform start) matches the bins best.
D is the mean over frames, its error the standard error of the frames' values. The self-diffusion
D_self comes from OUT_DIR/msd.csv (the slope of the second half over 6). The solute rides on the
particles and is exchanged between them, so D is about D_self plus an exchange part, which the kinetic
theory D_kin = 2 pi n kappa r_cc^5 / 315 (s_C = 2) bounds from above (the mean field; the pair network of
a disordered configuration conducts less). The check passes when each solute's exchange part D - D_self
lies between 0.3 and 1.05 D_kin. Writes diffusion_check.json and diffusion_profile.png into OUT_DIR;
exit code 1 when a criterion fails.

For eDPD (pair.style = "edpd") the field is the internal temperature T: a heat source q per particle
raises T at q / C_v, the kinetic theory is D_T = 2 pi n C_v kappa r_cT^5 / 315, and the profile's mean
is taken out before the fit (the time step's drift and viscous heating warm the whole box uniformly).
"""
import json
import math
import os
import sys
import tomllib

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from lammps_dump import frames  # noqa: E402


def fourier(x, t, q, d, lx, modes=199):
    """The profile C - C0 that sources +q (x < lx/2) and -q build by time t with diffusivity d."""
    c = np.zeros_like(x)
    for n in range(1, modes + 1, 2):
        k = 2 * math.pi * n / lx
        c += 4 * q / (math.pi * n) * (1 - math.exp(-d * k * k * t)) / (d * k * k) * np.sin(k * x)
    return c


def best_d(x, profile, t, q, lx):
    """The diffusivity whose Fourier profile fits `profile` best (golden-section search in log d)."""
    def err(logd):
        return float(np.sum((profile - fourier(x, t, q, math.exp(logd), lx)) ** 2))
    a, b = math.log(1e-3), math.log(20.0)
    g = (math.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    for _ in range(80):
        if err(c) < err(d):
            b = d
        else:
            a = c
        c, d = b - g * (b - a), a + g * (b - a)
    return math.exp(0.5 * (a + b))


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    out = args[0]
    config = args[args.index("--config") + 1] if "--config" in args else os.path.join(os.path.dirname(__file__), "diffusion.toml")
    with open(config, "rb") as f:
        cfg = tomllib.load(f)
    lx, ly, lz = cfg["system"]["box"]
    dt = cfg["integrator"]["dt"]
    rho = cfg["species"][0]["density"]
    pair = cfg["pair"]
    heat = pair.get("style") == "edpd"
    cv = cfg["species"][0].get("cv", 1.0) if heat else 1.0
    rcc = pair.get("rct" if heat else "rcc", pair.get("rc", 1.0)) or pair.get("rc", 1.0)
    q = {}
    for s in cfg["source"]:
        if s["rate"] > 0:
            q[s["field"]] = s["rate"] / cv
    if heat:
        c0 = {"temp": cfg["species"][0].get("temperature", cfg["system"]["kT"])}
    else:
        c0 = {f"conc{k}": cfg["species"][0].get(f"conc{k}", 0.0) for k in range(1, cfg["tdpd"]["solutes"] + 1)}
    bins = int(round(lx))
    edges = np.linspace(0, lx, bins + 1)
    x = 0.5 * (edges[1:] + edges[:-1])
    fits = {f: [] for f in c0}
    last = {}
    for step, c in frames(os.path.join(out, "trajectory.lammpstrj")):
        if step == 0:
            continue
        t = step * dt
        k = np.minimum((c["x"] / lx * bins).astype(int), bins - 1)
        counts = np.bincount(k, minlength=bins)
        for f in c0:
            prof = np.bincount(k, weights=c[f] - c0[f], minlength=bins) / np.maximum(counts, 1)
            if heat:
                prof -= prof.mean()
            fits[f].append(best_d(x, prof, t, q[f], lx))
            last[f] = (t, prof)
    msd = np.loadtxt(os.path.join(out, "msd.csv"), delimiter=",", skiprows=1)
    half = msd[len(msd) // 2:]
    d_self = float(np.polyfit(half[:, 0], half[:, 1], 1)[0] / 6)
    checks = {"d_self": d_self, "rcc": rcc, "field": "heat" if heat else "solutes", "solutes": {}}
    ok = True
    for n, f in enumerate(c0, start=1):
        kappa = pair["kappa"] if heat else pair[f"kappa{n}"]
        d_kin = 2 * math.pi * rho * cv * kappa * rcc ** 5 / 315
        vals = np.array(fits[f])
        mean, err = float(vals.mean()), float(vals.std(ddof=1) / math.sqrt(len(vals))) if len(vals) > 1 else float("nan")
        exchange = (mean - d_self) / d_kin
        passed = 0.3 < exchange < 1.05
        ok = ok and passed
        checks["solutes"][f] = {"kappa": kappa, "d_fit": mean, "d_fit_error": err, "d_kinetic": d_kin,
                                "exchange_over_kinetic": exchange, "frames": len(vals), "pass": bool(passed)}
    checks["pass"] = bool(ok)
    with open(os.path.join(out, "diffusion_check.json"), "w") as f:
        json.dump(checks, f, indent=2)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.5, 4))
    xs = np.linspace(0, lx, 400)
    for f, colour in zip(c0, ["C0", "C1"]):
        t, prof = last[f]
        s = checks["solutes"][f]
        ax.plot(x, prof, "o", color=colour, label=f"{f}: kappa = {s['kappa']}, binned at t = {t:g}")
        ax.plot(xs, fourier(xs, t, q[f], s["d_fit"], lx), "-", color=colour, label=f"  Fourier, fitted D = {s['d_fit']:.3f}")
        ax.plot(xs, fourier(xs, t, q[f], s["d_kinetic"], lx), ":", color=colour, label=f"  Fourier, kinetic D = {s['d_kinetic']:.3f}")
    ax.set_xlabel("x")
    ax.set_ylabel("T - <T>" if heat else "C - C0")
    ax.set_title(f"eDPD: conduction from opposite heat sources (r_cT = {rcc})" if heat else
                 f"tDPD: diffusion from opposite sources (r_cc = {rcc})")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "diffusion_profile.png"), dpi=120)
    print(json.dumps(checks, indent=2))
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
