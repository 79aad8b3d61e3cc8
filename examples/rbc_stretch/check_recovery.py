#!/usr/bin/env python3
"""Shape recovery of a red cell released from optical-tweezers stretching (recovery.toml, then
release.toml restarted from its checkpoint). Issue 28: the recovery time against seed 002 Fig. 3 (the
cell "recovers its equilibrium biconcave shape 0.2 seconds after the body force is turned off") and
Hochmuth & Hampel, J. Rheol. 23, 669 (1979) (released cells recover their disc shape in about 0.3 s).

The deformation is measured as Evans and Hochmuth do, through lambda^2 = D_A / D_T (the rest shape is
a disc, D_A = D_T): y = (lambda^2 - 1) / (lambda^2 + 1). For a Kelvin-Voigt membrane (elastic shear
modulus mu, 2-D viscosity eta) y decays as exp(-t / t_c) with t_c = eta / mu. Fedosov, Caswell &
Karniadakis (Biophys. J. 98, 2215 (2010)) fit a stretched exponential y / y0 = exp(-(t / t_c)^beta);
this script fits beta and t_c by least squares of ln(-ln(y / y0)) against ln t over y / y0 from 0.9
to 0.1 (the part above the thermal noise) and prints both.

The assertions use the 1/e time t_e, at which y has fallen to y0 / e (read off the samples, no model):
the fitted beta moves t_c between runs more than the data do.

usage: check_recovery.py --release STEP --dt DT [--unit ms] [--same TOL] [--ratio R TOL] [--band LO HI]
                         OUT [OUT ...]
  --same TOL     every run's t_e within the relative tolerance TOL of the first's
  --ratio R TOL  the second run's t_e / the first's is R within the relative tolerance TOL
  --band LO HI   the first run's t_e lies in [LO, HI] (in the time unit of DT)
"""
import argparse
import csv
import math
import sys


def recovery(out, release, dt):
    with open(f"{out}/cells.csv") as f:
        rows = [r for r in csv.DictReader(f) if int(r["step"]) >= release]
    if len(rows) < 5:
        sys.exit(f"{out}/cells.csv: {len(rows)} rows at or after step {release}, too few")
    t = [(int(r["step"]) - release) * dt for r in rows]
    lam2 = [float(r["axial"]) / float(r["transverse"]) for r in rows]
    y = [(l - 1.0) / (l + 1.0) for l in lam2]
    y0 = y[0]
    xs, ys = [], []
    for ti, yi in zip(t[1:], y[1:]):
        q = yi / y0
        if 0.1 <= q <= 0.9:
            xs.append(math.log(ti))
            ys.append(math.log(-math.log(q)))
    if len(xs) < 3:
        sys.exit(f"{out}: fewer than 3 samples between 90 % and 10 % of the initial deformation: "
                 "run the release longer")
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    beta = sum((x - mx) * (yy - my) for x, yy in zip(xs, ys)) / sxx
    tc = math.exp(mx - my / beta)
    # the time to fall to 1/e of the initial deformation, read off the samples (linear in ln y)
    te = None
    for i in range(1, len(y)):
        if y[i] / y0 <= math.exp(-1.0) < y[i - 1] / y0:
            a, b = math.log(y[i - 1] / y0), math.log(y[i] / y0)
            te = t[i - 1] + (t[i] - t[i - 1]) * (-1.0 - a) / (b - a)
            break
    return dict(tc=tc, beta=beta, t_e=te, y0=y0, lam2_0=lam2[0], lam2_end=lam2[-1], t_end=t[-1], n=n)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--release", type=int, required=True)
    p.add_argument("--dt", type=float, required=True)
    p.add_argument("--unit", default="ms")
    p.add_argument("--same", type=float)
    p.add_argument("--ratio", type=float, nargs=2)
    p.add_argument("--band", type=float, nargs=2)
    p.add_argument("out", nargs="+")
    a = p.parse_args()
    res = [recovery(o, a.release, a.dt) for o in a.out]
    for o, r in zip(a.out, res):
        te = f"{r['t_e']:.1f}" if r["t_e"] is not None else "n/a"
        print(f"{o}: D_A/D_T {r['lam2_0']:.3f} at release -> {r['lam2_end']:.3f} after {r['t_end']:.0f} {a.unit}; "
              f"t_c = {r['tc']:.1f} {a.unit}, beta = {r['beta']:.3f} ({r['n']} samples); "
              f"1/e time {te} {a.unit}")
    ok = True
    if any(r["t_e"] is None for r in res):
        sys.exit("a run never fell to 1/e of its initial deformation: run the release longer")
    if a.same is not None:
        for o, r in zip(a.out[1:], res[1:]):
            rel = abs(r["t_e"] / res[0]["t_e"] - 1.0)
            print(f"|t_e({o}) / t_e({a.out[0]}) - 1| = {rel:.3f} (tolerance {a.same})")
            ok &= rel <= a.same
    if a.ratio is not None:
        if len(res) < 2:
            sys.exit("--ratio needs two runs")
        q = res[1]["t_e"] / res[0]["t_e"]
        print(f"t_e ratio {q:.3f} (expected {a.ratio[0]} within {a.ratio[1]:.0%})")
        ok &= abs(q / a.ratio[0] - 1.0) <= a.ratio[1]
    if a.band is not None:
        inside = a.band[0] <= res[0]["t_e"] <= a.band[1]
        print(f"{a.out[0]}: t_e {res[0]['t_e']:.1f} {a.unit} in [{a.band[0]}, {a.band[1]}]: {inside}")
        ok &= inside
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
