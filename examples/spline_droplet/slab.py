#!/usr/bin/env python3
"""Liquid and gas densities of Liu's spline fluid over a flat interface (slab.toml).

Runs slab.toml (unless --analyse-only) and reads its two centred density profiles (steps 5,000-40,000
and 22,500-40,000). Liquid: bins within 2 of the slab's centre; gas: bins farther than 6 from it (the
interfaces lie near 4). The error of each density is half the difference between the two halves of the
window (the first half from the whole window and the second). Writes slab.json in the output folder.

Usage: /usr/bin/python3 examples/spline_droplet/slab.py [--out DIR] [--mesodpd BIN] [--analyse-only]
"""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def profile(out, name):
    path = os.path.join(out, f"{name}.csv")
    if not os.path.exists(path):
        sys.exit(f"{path}: missing (run without --analyse-only first)")
    d = np.genfromtxt(path, delimiter=",", names=True)
    with open(os.path.join(out, f"{name}.json")) as f:
        samples = json.load(f)["samples"]
    return d["z"], d["density"], samples


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesodpd", default=os.path.join(ROOT, "build", "mesodpd"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "spline_slab"))
    ap.add_argument("--analyse-only", action="store_true")
    args = ap.parse_args()
    if not args.analyse_only:
        subprocess.run([args.mesodpd, "run", os.path.join(HERE, "slab.toml"), "--out", args.out, "--threads", "1"],
                       check=True)
    z, whole, n_whole = profile(args.out, "profile")
    _, late, n_late = profile(args.out, "late")
    early = (whole * n_whole - late * n_late) / (n_whole - n_late)
    centre = 0.5 * (z[0] + z[-1])  # the profiles put the slab's centre of mass in the middle of the box
    liquid_bins = np.abs(z - centre) < 2.0
    gas_bins = np.abs(z - centre) > 6.0
    result = {}
    for name, sel in (("liquid", liquid_bins), ("gas", gas_bins)):
        halves = [early[sel].mean(), late[sel].mean()]
        result[name] = {"density": float(whole[sel].mean()), "error": float(abs(halves[1] - halves[0]) / 2),
                        "halves": [float(h) for h in halves]}
    lo_side = whole[gas_bins & (z < centre)].mean()
    hi_side = whole[gas_bins & (z > centre)].mean()
    result["gas"]["sides"] = [float(lo_side), float(hi_side)]
    rl, rg = result["liquid"]["density"], result["gas"]["density"]
    ratio = rl / rg
    ratio_err = ratio * np.hypot(result["liquid"]["error"] / rl, result["gas"]["error"] / rg)
    result["ratio"] = {"value": float(ratio), "error": float(ratio_err)}
    with open(os.path.join(args.out, "slab.json"), "w") as f:
        json.dump(result, f, indent=2)
    print(f"liquid {rl:.4f} +- {result['liquid']['error']:.4f} (halves {result['liquid']['halves'][0]:.4f}, "
          f"{result['liquid']['halves'][1]:.4f})")
    print(f"gas    {rg:.5f} +- {result['gas']['error']:.5f} (halves {result['gas']['halves'][0]:.5f}, "
          f"{result['gas']['halves'][1]:.5f}; sides {lo_side:.5f}, {hi_side:.5f})")
    print(f"liquid/gas ratio {ratio:.0f} +- {ratio_err:.0f}")


if __name__ == "__main__":
    main()
