#!/usr/bin/env python3
"""Flow-rate sweep of tube.toml: the same cell and tube at mean speeds of 0.25, 0.5, 1 and 2 mm/s (U = 0.04
to 0.32 in model units), each run long enough for the cell to reach its lasting shape (the cell moves at
about 2 U: 75,000 steps at 0.25 mm/s, 60 length units of travel; 114,000, 57,000 and 28,000 at the others,
180 units), averaged over its second half; then check_flow.py's table, its assertion that the cell bends
across the flow more the faster the flow, and the picture of the four shapes. About 45 minutes on two
cores.

usage: run.py --mesodpd build/mesodpd --out out/rbc_flow [--threads 2] [--picture docs/rbc_flow.png]
(/usr/bin/python3: check_flow.py needs Debian's python3-gsd)
"""
import argparse
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# The empty tube's mean speed U = n g R^2 / (8 eta) with n = 3, R = 5.125, eta = 30: g = 3.046 U.
SPEEDS = [0.04, 0.08, 0.16, 0.32]
STEPS = {0.04: 75000, 0.08: 114000, 0.16: 57000, 0.32: 28000}
MM_PER_S = 6.28  # one model velocity unit (0.9775 um / 0.1557 ms)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--mesodpd", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--picture")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    base = open(os.path.join(HERE, "tube.toml")).read()
    outs, labels = [], []
    for u in SPEEDS:
        g = 3.046 * u
        steps = STEPS[u]
        cfg = re.sub(r"body_force = \[0\.487,", f"body_force = [{g:.4f},", base)
        cfg = re.sub(r"^steps = \d+", f"steps = {steps}", cfg, flags=re.M)
        # The OFF-free config has no relative paths, so it may live in the output folder.
        path = os.path.join(a.out, f"tube_u{u}.toml")
        with open(path, "w") as f:
            f.write(cfg)
        out = os.path.join(a.out, f"u{u}")
        print(f"U = {u} ({u * MM_PER_S:.2f} mm/s): g = {g:.4f}, {steps} steps", flush=True)
        subprocess.run([a.mesodpd, "run", path, "--out", out, "--threads", str(a.threads), "--no-progress"], check=True)
        outs.append(out)
        labels.append(f"U = {u * MM_PER_S:.2f} mm/s")
    cmd = [sys.executable, os.path.join(HERE, "check_flow.py"), *outs, "--start-fraction", "0.5", "--rising", "bend", "0.03",
           "--labels", *labels]
    if a.picture:
        cmd += ["--picture", a.picture]
    sys.exit(subprocess.run(cmd).returncode)


if __name__ == "__main__":
    main()
