#!/usr/bin/python3
"""Judges examples/interface/run.py's results.json (exit code 1 when a check fails):
- below the critical point (one mixed phase) the tension is zero within 3 error bars + 0.1;
- with two phases it is positive by more than 5 error bars and grows with Delta a;
- chi from the coexisting compositions (Flory-Huggins binodal of a symmetric blend) is within 10% of
  Groot and Warren's chi = 0.286 Delta a.

    /usr/bin/python3 examples/interface/check.py out/interface/results.json
"""
import json
import sys


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "out/interface/results.json"
    results = sorted(json.load(open(path)), key=lambda r: r["delta_a"])
    ok = True

    def report(good, text):
        nonlocal ok
        ok = ok and good
        print(("ok    " if good else "FAIL  ") + text)

    two_phase = [r for r in results if r.get("chi_coexistence") is not None]
    for r in results:
        da, s, e = r["delta_a"], r["sigma"], r["sigma_err"]
        if r.get("chi_coexistence") is None:
            report(abs(s) < 3 * e + 0.1, f"Delta a = {da:g}: one mixed phase, sigma = {s:.3f} +- {e:.3f} ~ 0")
        else:
            report(s > 5 * e, f"Delta a = {da:g}: sigma = {s:.3f} +- {e:.3f} > 5 error bars")
            chi, ref = r["chi_coexistence"], r["chi_mapping"]
            report(abs(chi / ref - 1) < 0.10, f"Delta a = {da:g}: chi from coexistence {chi:.2f} vs 0.286 Delta a = "
                                              f"{ref:.2f} ({100 * (chi / ref - 1):+.1f}%)")
    for a, b in zip(two_phase, two_phase[1:]):
        report(b["sigma"] > a["sigma"], f"sigma grows from Delta a = {a['delta_a']:g} to {b['delta_a']:g}")
    report(len(two_phase) >= 4, f"{len(two_phase)} two-phase Delta a values (at least 4 wanted)")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
