#!/usr/bin/env python3
"""Energy conservation of a frictionless membrane run (membrane_nve.toml): E = kinetic_energy +
potential_energy + membrane_energy from thermo.csv. Asserts that E wanders by less than 0.2 % of the
mean kinetic energy (measured 0.09 %: velocity Verlet's O(dt^2) wobble) and does not drift: the means of
the two halves of the run agree within 0.01 % of it (measured 6e-6 %). A force that is not the gradient of
the energy (a wrong term or sign) breaks both by orders of magnitude.

usage: check_energy.py OUT_DIR
"""
import csv
import sys


def main():
    rows = list(csv.DictReader(open(f"{sys.argv[1]}/thermo.csv")))
    e = [float(r["kinetic_energy"]) + float(r["potential_energy"]) + float(r["membrane_energy"]) for r in rows]
    ke = sum(float(r["kinetic_energy"]) for r in rows) / len(rows)
    half = len(e) // 2
    wobble = (max(e) - min(e)) / ke
    drift = abs(sum(e[half:]) / (len(e) - half) - sum(e[:half]) / half) / ke
    print(f"{len(rows)} rows: E from {min(e):.6f} to {max(e):.6f}, mean kinetic energy {ke:.3f}; "
          f"wobble {wobble:.2e}, drift {drift:.2e} of it")
    ok = wobble < 2e-3 and drift < 1e-4
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
