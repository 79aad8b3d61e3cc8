#!/usr/bin/python3
"""Judges examples/wetting/run.py's results.json (exit code 1 when a check fails):
- at least four A_SL with a static contact angle (a drop outline whose circle meets the wall, and no
  precursor film on the wall away from the drop);
- the angle falls as the solid-liquid attraction grows (A_SL more negative), each step by more than
  2 combined error bars;
- the set spans wetting (theta < 90) and non-wetting (theta > 90) walls.

    /usr/bin/python3 examples/wetting/check.py out/wetting/results.json
"""
import json
import math
import sys


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "out/wetting/results.json"
    results = sorted(json.load(open(path)), key=lambda r: r["a_sl"])  # most attractive first
    ok = True

    def report(good, text):
        nonlocal ok
        ok = ok and good
        print(("ok    " if good else "FAIL  ") + text)

    measured = [r for r in results if r["theta"] == r["theta"] and r["theta_err"] == r["theta_err"]
                and not r.get("complete_wetting")]
    for r in results:
        print(f"      A_SL = {r['a_sl']:g}: theta = {r['theta']:.1f} +- {r['theta_err']:.1f} deg"
              + (" (precursor film: complete wetting, not a static angle)" if r.get("complete_wetting") else ""))
    report(len(measured) >= 4, f"{len(measured)} A_SL values with a contact angle (at least 4 wanted)")
    for a, b in zip(measured, measured[1:]):
        gap = b["theta"] - a["theta"]
        err = math.hypot(a["theta_err"], b["theta_err"])
        report(gap > 2 * err, f"theta grows from A_SL = {a['a_sl']:g} to {b['a_sl']:g} by {gap:.1f} "
                              f"(> 2 x {err:.1f})")
    report(any(r["theta"] < 90 for r in measured) and any(r["theta"] > 90 for r in measured),
           "wetting (theta < 90) and non-wetting (theta > 90) walls both present")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
