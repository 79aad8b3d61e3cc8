#!/usr/bin/python3
"""Judge examples/mdpd_droplet/run.py's results.json against the slab's surface tension.

    /usr/bin/python3 examples/mdpd_droplet/check.py [out/mdpd_droplet/results.json] [--tolerance 0.10]

Passes (exit 0) when, for at least three drops, the slope of Delta P against 1/R gives a sigma within
the tolerance (default 10 %) of the slab's sigma = 7.86 (examples/mdpd_slab, docs/validation.md), the
straight line describes the points (chi^2 per degree of freedom below 4), and every drop has Delta P
above five error bars. Prints what failed otherwise (exit 1).
"""
import argparse
import json
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="?", default=os.path.join(ROOT, "out", "mdpd_droplet", "results.json"))
    ap.add_argument("--tolerance", type=float, default=0.10)
    args = ap.parse_args()
    with open(args.results) as f:
        r = json.load(f)
    failures = []
    drops = r["drops"]
    if len(drops) < 3:
        failures.append(f"{len(drops)} drops: at least three radii are needed")
    for d in drops:
        if not d["delta_p"] > 5 * d["delta_p_err"]:
            failures.append(f"N = {d['particles']}: Delta P = {d['delta_p']:.3f} +- {d['delta_p_err']:.3f} is not resolved")
    sigma, slab = r["sigma_fit"], r["sigma_slab"]
    rel = abs(sigma / slab - 1)
    if not rel <= args.tolerance:
        failures.append(f"sigma from the slope {sigma:.3f} +- {r['sigma_fit_err']:.3f} is {100 * rel:.1f} % from the "
                        f"slab's {slab} (tolerance {100 * args.tolerance:.0f} %)")
    if r["dof"] > 0 and not r["chi2"] / r["dof"] < 4:
        failures.append(f"chi^2 / dof = {r['chi2']:.2f} / {r['dof']}: the points are not on a line")
    print(f"sigma (slope / 2) = {sigma:.3f} +- {r['sigma_fit_err']:.3f}, intercept {r['intercept']:.3f} +- "
          f"{r['intercept_err']:.3f}; through the origin {r['sigma_origin']:.3f} +- {r['sigma_origin_err']:.3f}; "
          f"slab {slab} +- {r['sigma_slab_err']}: {100 * rel:.1f} % apart")
    for msg in failures:
        print("FAIL:", msg)
    if not failures:
        print("PASS")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
