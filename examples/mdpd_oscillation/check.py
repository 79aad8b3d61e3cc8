#!/usr/bin/python3
"""Judge examples/mdpd_oscillation/run.py's results.json against Rayleigh's l = 2 frequency.

    /usr/bin/python3 examples/mdpd_oscillation/check.py [out/mdpd_oscillation/results.json] [--tolerance 0.15]

For every drop: the stretched drop must oscillate (the mean shape signal changes sign and its fit is
underdamped, beta < omega_d), and the undamped frequency of the fitted damped oscillator,
omega_0 = sqrt(omega_d^2 + beta^2), must be within the tolerance (default 15 %, issue 11) of Rayleigh's
omega_0 = sqrt(8 sigma / (rho R^3)) with the slab's sigma = 7.86. The same comparison is printed for the
autocorrelation of the thermal shape fluctuations, where run.py measured it, and for the Laplace sigma
(informative). Exit code 1 if any drop fails.
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="?", default=os.path.join(ROOT, "out", "mdpd_oscillation", "results.json"))
    ap.add_argument("--tolerance", type=float, default=0.15)
    args = ap.parse_args()
    with open(args.results) as f:
        r = json.load(f)
    failures = []
    for d in r["drops"]:
        n, mf, wr = d["particles"], d["mean_fit"], d["omega_rayleigh_slab"]
        ratio = mf["omega_0"] / wr
        print(f"N = {n}, R = {d['radius']:.3f}: stretched drop omega_0 = {mf['omega_0']:.4f} "
              f"(omega_d = {mf['omega_d']:.4f}, beta = {mf['beta']:.4f}); Rayleigh {wr:.4f} (slab sigma), "
              f"ratio {ratio:.3f}; with the Laplace sigma {mf['omega_0'] / d['omega_rayleigh_laplace']:.3f}")
        if d["fluctuations"]:
            af = d["fluctuations"]["fit"]
            print(f"          fluctuations omega_0 = {af['omega_0']:.4f} +- {d['fluctuations']['omega_0_sem']:.4f}, "
                  f"ratio {af['omega_0'] / wr:.3f}")
        if d["sign_changes"] < 1:
            failures.append(f"N = {n}: the mean shape signal does not change sign")
        if not mf["beta"] < mf["omega_d"]:
            failures.append(f"N = {n}: overdamped fit (beta {mf['beta']:.4f} >= omega_d {mf['omega_d']:.4f})")
        if abs(ratio - 1) > args.tolerance:
            failures.append(f"N = {n}: omega_0 / omega_Rayleigh = {ratio:.3f}, off by more than {args.tolerance:.0%}")
    for f in failures:
        print("FAIL:", f)
    if not failures:
        print("PASS")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
