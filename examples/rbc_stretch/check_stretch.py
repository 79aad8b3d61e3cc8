#!/usr/bin/env python3
"""Checks a red-cell stretching run (stretch.toml) against Mills et al., Mech. Chem. Biosystems 1, 169
(2004), as issue 28 quotes them: at 109 pN D_A = 13.6 um, D_T = 4.5 um; at 193 pN D_A = 15.3 um (the
cells' spread 12.95-17.65 um), D_T = 4.3 um. Passes when the mean diameters over the second half of
cells.csv lie within +-2.35 um (D_A) and +-0.6 um (D_T) of the measured ones.

usage: check_stretch.py OUT_DIR FORCE_PN
"""
import csv
import sys

MILLS = {109: (13.6, 4.5), 193: (15.3, 4.3)}


def main():
    out, force = sys.argv[1], int(sys.argv[2])
    with open(f"{out}/cells.csv") as f:
        rows = list(csv.DictReader(f))
    if len(rows) < 4:
        sys.exit(f"{out}/cells.csv: {len(rows)} rows, too few")
    half = rows[len(rows) // 2:]
    da = sum(float(r["axial"]) for r in half) / len(half)
    dt = sum(float(r["transverse"]) for r in half) / len(half)
    area = [float(r["area"]) for r in rows]
    volume = [float(r["volume"]) for r in rows]
    print(f"F = {force} pN: D_A = {da:.3f} um, D_T = {dt:.3f} um (mean of the last {len(half)} rows); "
          f"area {min(area):.2f}-{max(area):.2f} um^2, volume {min(volume):.2f}-{max(volume):.2f} um^3")
    if force not in MILLS:
        print("no measured value at this force to compare with")
        return
    ma, mt = MILLS[force]
    print(f"Mills et al. 2004: D_A = {ma} um, D_T = {mt} um")
    ok = abs(da - ma) <= 2.35 and abs(dt - mt) <= 0.6
    print("PASS" if ok else "FAIL")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
