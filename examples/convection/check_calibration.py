#!/usr/bin/env python3
"""Heat diffusivity of the eDPD fluid from calibrate.toml's steady source-sink profile.

Usage: /usr/bin/python3 examples/convection/check_calibration.py CONFIG OUT [CONFIG OUT ...]

Each OUT is a run of CONFIG (calibrate.toml, or a copy with another kappa); q, C_v, kappa and the box
are read from CONFIG. Between the source slab
(0 <= x < w) and the sink slab (L/2 <= x < L/2 + w) the steady flux is q n w / 2 each way, so
D = q w / (2 C_v |dT/dx|). The gradient is fitted on the two linear stretches (away from the slabs by
half a unit); their difference is the error estimate. Prints kappa, C_v kappa, D for each run.
"""
import csv
import pathlib
import re
import sys

import numpy as np


def config_value(text, key):
    m = re.search(r"^\s*%s\s*=\s*([-0-9.eE+]+)" % key, text, re.M)
    return float(m.group(1))


def main():
    args = sys.argv[1:]
    if not args or len(args) % 2:
        sys.exit(__doc__)
    for config, out in zip(args[0::2], map(pathlib.Path, args[1::2])):
        text = pathlib.Path(config).read_text()
        rows = list(csv.DictReader(open(out / "profile.csv")))
        x = np.array([float(r["x"]) for r in rows])
        t = np.array([float(r["mean_temp"]) for r in rows])
        q = config_value(text, "rate")
        cv = config_value(text, "cv")
        kappa = config_value(text, "kappa")
        box = [float(v) for v in re.search(r"box\s*=\s*\[([^\]]*)\]", text).group(1).split(",")]
        length, w = box[0], 2.0
        slopes = []
        for lo, hi in [(w + 0.5, length / 2 - 0.5), (length / 2 + w + 0.5, length - 0.5)]:
            m = (x > lo) & (x < hi)
            slopes.append(abs(np.polyfit(x[m], t[m], 1)[0]))
        d = [q * w / (2 * cv * s) for s in slopes]
        print("%s: kappa = %g, C_v kappa = %.3g, |dT/dx| = %.5f, %.5f, D = %.4f +- %.4f"
              % (out, kappa, cv * kappa, slopes[0], slopes[1], np.mean(d), abs(d[0] - d[1]) / 2))


if __name__ == "__main__":
    main()
