#!/usr/bin/python3
"""Checks the eDPD run between walls at two temperatures (examples/edpd_walls/README.md).

usage: check_walls.py OUT_DIR [--config FILE]

Reads OUT_DIR/trajectory.lammpstrj (the frames of the second half of the run), bins the fluid's internal
temperature along z (bins of 1), fits a straight line to the bins more than 1 from the walls, and
checks that the profile is linear (no bin more than 0.01 off the line) and that its slope is between
0.6 and 1.1 times the walls' difference over their distance (the walls' own layer of pairs gives a
temperature jump at each wall, so the fluid's slope is a little smaller). Writes walls_profile.csv,
walls_check.json and walls_profile.png into OUT_DIR; exit code 1 when a criterion fails.
"""
import json
import os
import sys
import tomllib

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "common"))
from lammps_dump import frames  # noqa: E402


def main():
    args = sys.argv[1:]
    if not args:
        sys.exit(__doc__)
    out = args[0]
    config = args[args.index("--config") + 1] if "--config" in args else os.path.join(os.path.dirname(__file__), "walls.toml")
    with open(config, "rb") as f:
        cfg = tomllib.load(f)
    lz = cfg["system"]["box"][2]
    solids = {s["name"]: s for s in cfg["solid"]}
    z_lo, z_hi = solids["bottom"]["point"][2], solids["top"]["point"][2]
    temps = {s["name"]: s.get("temperature") for s in cfg["species"]}
    t_lo, t_hi = temps["hot"], temps["cold"]
    steps = cfg["run"]["steps"]
    edges = np.arange(z_lo, z_hi + 1e-9, 1.0)
    centres = 0.5 * (edges[1:] + edges[:-1])
    sums = np.zeros(len(centres))
    counts = np.zeros(len(centres))
    used = 0
    for step, c in frames(os.path.join(out, "trajectory.lammpstrj")):
        if step < steps // 2:
            continue
        fluid = c["type"] == 1
        k = np.digitize(c["z"][fluid], edges) - 1
        ok = (k >= 0) & (k < len(centres))
        np.add.at(sums, k[ok], c["temp"][fluid][ok])
        np.add.at(counts, k[ok], 1)
        used += 1
    profile = sums / np.maximum(counts, 1)
    inner = (centres > z_lo + 1) & (centres < z_hi - 1)
    slope, icpt = np.polyfit(centres[inner], profile[inner], 1)
    deviation = float(np.max(np.abs(profile[inner] - (icpt + slope * centres[inner]))))
    expected = (t_hi - t_lo) / (z_hi - z_lo)
    ratio = slope / expected
    checks = {"frames": used, "slope": slope, "walls_slope": expected, "slope_ratio": ratio,
              "largest_deviation": deviation, "profile_at_bottom": float(profile[0]),
              "profile_at_top": float(profile[-1])}
    ok = used > 0 and deviation < 0.01 and 0.6 < ratio < 1.1
    checks["pass"] = bool(ok)
    with open(os.path.join(out, "walls_profile.csv"), "w") as f:
        f.write("z,temperature\n")
        for z, t in zip(centres, profile):
            f.write(f"{z},{t}\n")
    with open(os.path.join(out, "walls_check.json"), "w") as f:
        json.dump(checks, f, indent=2)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(centres, profile, "o", label="fluid's internal temperature (mean over frames)")
    ax.plot(centres, icpt + slope * centres, "-", label=f"line fitted inside, slope {slope:.4f}")
    ax.plot([z_lo, z_hi], [t_lo, t_hi], "k--", label=f"walls' {t_lo} to {t_hi}, slope {expected:.4f}")
    ax.set_xlabel("z")
    ax.set_ylabel("T")
    ax.set_title("eDPD: heat conduction between walls held at two temperatures")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "walls_profile.png"), dpi=120)
    print(json.dumps(checks, indent=2))
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
