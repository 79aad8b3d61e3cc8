"""Checks a run of membrane_in_solvent.toml: python3 check_bounce.py OUT [--leaky].

Default: every cells.csv row has wrong_side = 0, the total momentum stays below 1e-8 and the mean
temperature over steps >= 1000 is within 3 % of 1. --leaky (a run with bounce = false): the last row has
more than 10 particles on the wrong side, so the count can see a leak.
"""
import csv
import sys

out = sys.argv[1]
cells = list(csv.DictReader(open(f"{out}/cells.csv")))
thermo = list(csv.DictReader(open(f"{out}/thermo.csv")))
wrong = [int(r["wrong_side"]) for r in cells]
if "--leaky" in sys.argv:
    print("wrong side at the end without bounce-back:", wrong[-1])
    sys.exit(0 if wrong[-1] > 10 else 1)
momentum = max(abs(float(r[k])) for r in thermo for k in ("momentum_x", "momentum_y", "momentum_z"))
temps = [float(r["temperature"]) for r in thermo if int(r["step"]) >= 1000]
mean_t = sum(temps) / len(temps)
print(f"rows {len(cells)}, largest wrong_side {max(wrong)}, |momentum| <= {momentum:.3g}, mean T {mean_t:.4f}")
ok = max(wrong) == 0 and momentum < 1e-8 and abs(mean_t - 1) < 0.03 and len(cells) >= 20
sys.exit(0 if ok else 1)
