#!/usr/bin/python3
"""Darcy's law in a short pillar-array run (examples/pillar_array, docs/validation.md section 6).

usage: test_pillar_array.py MESODPD_BINARY SOURCE_DIR

Square array at phi = 0.3 (L = 9.71, about 1,080 fluid particles) driven by g1 = 0.05 and g2 = 2 g1,
12,000 steps each, sampled after step 2,000 (about 25 s on one core). Checks, with the errors of
examples/pillar_array/analyze.py (integrated autocorrelation time of the mean fluid velocity):
  1. Darcy's law (seed 004 Eq. 13): the Darcy velocities are in the ratio of the forces,
     |u2/u1 - 2| < 3 sigma + 2%;
  2. the permeability, as c = u_D / g at g2 (independent of the viscosity), equals the mean of four
     runs with other seeds, C_REF, within 3 times their scatter (docs/validation.md: each seed has
     its own random frozen pillar surface and fluid count, which moves c by about 3%, more than the
     statistical error of one run).
Exit code 1 when a check fails; the run folders stay in $TMPDIR then.
"""
import math
import os
import shutil
import subprocess
import sys
import tempfile

PHI = 0.3
G1, G2 = 0.05, 0.1
STEPS, START = 12000, 2000
SEED = 11  # not the long runs' seed 4: an independent sample
# u_D / g of the square array at phi = 0.3 and g = 0.1 for seeds 4 (the long run, 17,000 sampled
# steps), 5, 6 and 7 (10,000 sampled steps each): 1.125, 1.169, 1.197, 1.183 (docs/validation.md
# section 6, "Pillar arrays"): their mean and standard deviation.
C_REF, C_SCATTER = 1.1685, 0.031


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    binary, source = sys.argv[1:]
    sys.dont_write_bytecode = True  # no __pycache__ in the source tree
    sys.path.insert(0, os.path.join(source, "examples", "pillar_array"))
    import analyze
    import make_configs

    work = tempfile.mkdtemp(prefix="pillar_array_")
    configs = os.path.join(work, "configs")
    subprocess.run([sys.executable, os.path.join(source, "examples", "pillar_array", "make_configs.py"), configs,
                    "--lattice", "square", "--phi", str(PHI), "--g", str(G1), str(G2), "--steps", str(STEPS),
                    "--start", str(START), "--seed", str(SEED)], check=True)
    runs = []
    for g in (G1, G2):
        name = make_configs.name("square", PHI, g)
        out = os.path.join(work, name)
        subprocess.run([binary, "run", os.path.join(configs, name + ".toml"), "--out", out, "--threads", "1"],
                       check=True, stdout=subprocess.DEVNULL)
        runs.append(analyze.analyze_run(os.path.join(configs, name + ".toml"), out, mu=2.40))
    failed = []
    for r in runs:
        print(f"g = {r['g']:g}: u_D = {r['u_d']:.5f} +- {r['u_d_err']:.5f}, K/d^2 = {r['K_d2']:.4f} +- "
              f"{r['K_d2_err']:.4f} (mu = 2.40), penetrations {r['penetrations']}")
    r1, r2 = runs
    ratio = r2["u_d"] / r1["u_d"]
    ratio_err = ratio * math.hypot(r1["u_d_err"] / r1["u_d"], r2["u_d_err"] / r2["u_d"])
    print(f"u_D ratio {ratio:.3f} +- {ratio_err:.3f}, force ratio {G2 / G1:g}")
    if not abs(ratio - G2 / G1) < 3 * ratio_err + 0.02 * G2 / G1:
        failed.append(f"Darcy velocities in the ratio {ratio:.3f} +- {ratio_err:.3f}, forces {G2 / G1:g}")
    c2, c2_err = r2["u_d"] / G2, r2["u_d_err"] / G2
    tolerance = 3 * C_SCATTER * math.sqrt(1 + 1 / 4)  # a new seed against the mean of four
    print(f"c = u_D / g = {c2:.4f} +- {c2_err:.4f} at g = {G2:g}, other seeds {C_REF} (tolerance {tolerance:.3f})")
    if not abs(c2 - C_REF) < tolerance:
        failed.append(f"u_D / g = {c2:.4f} +- {c2_err:.4f}, other seeds {C_REF} +- {tolerance:.3f}")
    if failed:
        print("FAILED: " + "; ".join(failed) + f" (runs kept in {work})")
        sys.exit(1)
    shutil.rmtree(work)
    print("passed")


if __name__ == "__main__":
    main()
