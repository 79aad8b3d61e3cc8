#!/usr/bin/python3
"""Brownian motion of a free rigid sphere of frozen particles ([[body]]): its translational and
rotational diffusion against Stokes-Einstein with the hydrodynamic radii of the towed and turned sphere
(towed.py's long runs, docs/validation.md section 15: a_t = 2.00, a_r = 1.91 in the same fluid and box).

One neutrally buoyant sphere of radius 2 in the 16^3 box of towed.toml (no towing, no body force),
run with --seeds seeds side by side. From bodies.csv (the unwrapped centre and the angular velocity
every `every` steps):
    D_t from the mean-square displacement, slope / 6 fitted between --fit (time units), against
        D_t = kT / (6 pi eta a) (1 - 2.837 a / L)    (Hasimoto's finite-box correction; the box's total
                                                      momentum is zero, as that correction assumes)
    D_r = (1/3) int_0^t_max <Omega(0) . Omega(t)> dt, against kT / (8 pi eta a^3).
and the radii a_t, a_r that they give. The error bars are the scatter over the seeds (and over halves of
each run).

    /usr/bin/python3 examples/colloids/brownian_body.py --mesodpd build/mesodpd --out out/brownian_body
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def series(path):
    t, x, w = [], [], []
    with open(path) as f:
        for r in csv.DictReader(f):
            t.append(int(r["step"]))
            x.append((float(r["x"]), float(r["y"]), float(r["z"])))
            w.append((float(r["wx"]), float(r["wy"]), float(r["wz"])))
    return t, x, w


def msd_slope(x, dt_row, lo, hi):
    """Least-squares slope of the MSD between lags lo and hi (time units), over all origins."""
    lags = range(max(1, int(round(lo / dt_row))), int(round(hi / dt_row)) + 1, max(1, int(round(1.0 / dt_row))))
    pts = []
    n = len(x)
    for lag in lags:
        s = 0.0
        for i in range(0, n - lag):
            d = [x[i + lag][a] - x[i][a] for a in range(3)]
            s += d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        pts.append((lag * dt_row, s / (n - lag)))
    mt = sum(p[0] for p in pts) / len(pts)
    mm = sum(p[1] for p in pts) / len(pts)
    return sum((p[0] - mt) * (p[1] - mm) for p in pts) / sum((p[0] - mt) ** 2 for p in pts)


def spin_integral(w, dt_row, tmax):
    """(1/3) int_0^tmax <Omega(0) . Omega(t)> dt by the trapezoid rule over all origins."""
    n = len(w)
    kmax = int(round(tmax / dt_row))
    c = []
    for lag in range(kmax + 1):
        s = 0.0
        for i in range(0, n - lag):
            s += sum(w[i][a] * w[i + lag][a] for a in range(3))
        c.append(s / (n - lag) / 3.0)
    return dt_row * (sum(c) - 0.5 * (c[0] + c[-1]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesodpd", default="build/mesodpd")
    ap.add_argument("--out", default="out/brownian_body")
    ap.add_argument("--steps", type=int, default=100000)
    ap.add_argument("--every", type=int, default=5, help="steps between rows of bodies.csv")
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--fit", default="10,40", help="MSD fit range in time units")
    ap.add_argument("--tmax", type=float, default=10.0, help="upper limit of the spin autocorrelation integral")
    ap.add_argument("--eta", type=float, default=0.8674)
    ap.add_argument("--a-t", type=float, default=2.00, help="the towed sphere's radius (towed.py, long runs)")
    ap.add_argument("--a-r", type=float, default=1.91, help="the turned sphere's radius (towed.py, long runs)")
    ap.add_argument("--analyse", action="store_true")
    args = ap.parse_args()
    base = open(os.path.join(HERE, "towed.toml")).read()
    text = (base.replace('motion = "towed"\n', "").replace("velocity = [0.15, 0, 0]\n", "")
            .replace("body_force = [-7.0e-4, 0, 0]", "body_force = [0, 0, 0]")
            .replace("output_every = 10", f"output_every = {args.every}").replace("steps = 40000", f"steps = {args.steps}")
            .replace("thermo_every = 10", "thermo_every = 1000"))
    folders = []
    procs = []
    for s in range(args.seeds):
        folder = os.path.join(args.out, f"seed{s}")
        folders.append(folder)
        if args.analyse:
            continue
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "config.toml"), "w") as f:
            f.write(text.replace("seed = 26", f"seed = {300 + s}"))
        procs.append(subprocess.Popen([args.mesodpd, "run", os.path.join(folder, "config.toml"), "--out", folder, "--no-progress",
                                       "--threads", "1"], stdout=open(os.path.join(folder, "log.txt"), "w"),
                                      stderr=subprocess.STDOUT))
    for p in procs:
        if p.wait() != 0:
            sys.exit("a run failed: see the log.txt files under " + args.out)
    lo, hi = (float(v) for v in args.fit.split(","))
    dt_row = 0.04 * args.every
    dts, drs = [], []
    for folder in folders:
        t, x, w = series(os.path.join(folder, "bodies.csv"))
        start = len(t) // 20  # the first 5% as start-up
        half = (len(t) - start) // 2
        for part in (slice(start, start + half), slice(start + half, len(t))):
            dts.append(msd_slope(x[part], dt_row, lo, hi) / 6.0)
            drs.append(spin_integral(w[part], dt_row, args.tmax))
    mean = lambda v: sum(v) / len(v)
    err = lambda v: math.sqrt(sum((a - mean(v)) ** 2 for a in v) / (len(v) * (len(v) - 1)))
    dt_m, dt_e, dr_m, dr_e = mean(dts), err(dts), mean(drs), err(drs)
    box = 16.0
    # a_t from D_t = kT / (6 pi eta a) (1 - 2.837 a / L): 1/a - 2.837/L = 6 pi eta D_t.
    a_t = 1.0 / (6 * math.pi * args.eta * dt_m + 2.837 / box)
    a_t_e = a_t * a_t * 6 * math.pi * args.eta * dt_e
    a_r = (1.0 / (8 * math.pi * args.eta * dr_m)) ** (1.0 / 3.0)
    a_r_e = a_r * dr_e / (3 * dr_m)
    expect_t = 1.0 / (6 * math.pi * args.eta * args.a_t) * (1 - 2.837 * args.a_t / box)
    expect_r = 1.0 / (8 * math.pi * args.eta * args.a_r ** 3)
    result = {"D_t": dt_m, "D_t_err": dt_e, "D_t_expected": expect_t, "D_r": dr_m, "D_r_err": dr_e, "D_r_expected": expect_r,
              "a_t": a_t, "a_t_err": a_t_e, "a_r": a_r, "a_r_err": a_r_e, "pieces": len(dts)}
    with open(os.path.join(args.out, "brownian_body.json"), "w") as f:
        json.dump(result, f, indent=2)
    print(f"D_t = {dt_m:.5f} +- {dt_e:.5f} (Stokes-Einstein with the towed a = {args.a_t}, Hasimoto: {expect_t:.5f}); "
          f"a_t = {a_t:.3f} +- {a_t_e:.3f}")
    print(f"D_r = {dr_m:.5f} +- {dr_e:.5f} (kT / (8 pi eta a^3) with the turned a = {args.a_r}: {expect_r:.5f}); "
          f"a_r = {a_r:.3f} +- {a_r_e:.3f}")


if __name__ == "__main__":
    main()
