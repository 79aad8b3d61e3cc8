#!/usr/bin/python3
"""A short version of examples/mdpd_oscillation (docs/validation.md section 5, "Droplet oscillation").

usage: test_oscillation.py SOURCE_DIR      (PYTHONPATH must hold the built module, build/python)

A 1,600-particle drop of Warren's liquid (R about 4) is equilibrated, and three states 500 steps apart
are stretched by e = 0.2 (x -> 1.2 x, y, z -> y, z / sqrt(1.2)), relaxed for 50 steps, stripped of
their straining flow (released from rest) and run for 1.3 Rayleigh periods: about 13 million
particle-steps, ~10 s of CPU. Checks on the mean shape signal Q(t) = G_xx - (G_yy + G_zz) / 2:
  1. the drop is deformed well beyond its thermal shape fluctuations: Q(0) > 4 rms(Q) of the unstretched drop;
  2. it passes through the sphere and overshoots: the signal changes sign, its minimum is negative, and
     the damped-cosine fit is underdamped (beta < omega_d);
  3. the undamped frequency of the fit, sqrt(omega_d^2 + beta^2), is within 25 % of Rayleigh's
     omega_0 = sqrt(8 sigma / (rho R^3)) with the slab's sigma = 7.86 (measured: +8 %);
  4. the first zero of Q comes within 15 % of the time at which the least-damped mode of a viscous drop
     (slab sigma, the measured viscosity nu = 0.893), released from rest, first reaches zero (measured: -2.5 %).
Exit code 1 when a check fails (the run folder stays in $TMPDIR then), 77 (skipped) without the module.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    source = sys.argv[1]
    try:
        import mesodpd  # noqa: F401
        import scipy  # noqa: F401
    except ImportError as e:
        print(f"skipped: {e}")
        return 77
    out = tempfile.mkdtemp(prefix="mesodpd_oscillation_")
    cmd = [sys.executable, "-B", os.path.join(source, "examples", "mdpd_oscillation", "run.py"), "--sizes", "1600",
           "--seeds", "3", "--equilibrate", "1000", "--gap", "500", "--relax", "50", "--stretch", "0.2",
           "--periods", "1.3", "--out", out]
    print(" ".join(cmd), flush=True)
    if subprocess.run(cmd).returncode != 0:
        print(f"run.py failed; output in {out}")
        return 1
    with open(os.path.join(out, "results.json")) as f:
        d = json.load(f)["drops"][0]
    mf, theory = d["mean_fit"], d["viscous_theory_slab"]
    ratio = mf["omega_0"] / d["omega_rayleigh_slab"]
    zero_ratio = d["t_zero"] / theory["t_zero_from_rest"]
    checks = [
        (d["q_mean_start"] > 4 * d["q_equilibrium_rms"],
         f"Q(0) = {d['q_mean_start']:.3f} against 4 x the thermal rms {d['q_equilibrium_rms']:.3f}"),
        (d["sign_changes"] >= 1 and d["q_mean_min"] < 0,
         f"sign changes {d['sign_changes']}, minimum of Q {d['q_mean_min']:.3f} at t = {d['t_min']:.1f}"),
        (mf["beta"] < mf["omega_d"], f"fit beta = {mf['beta']:.4f}, omega_d = {mf['omega_d']:.4f}"),
        (abs(ratio - 1) < 0.25, f"fit omega_0 = {mf['omega_0']:.4f}, Rayleigh {d['omega_rayleigh_slab']:.4f}: "
                                f"ratio {ratio:.3f} (tolerance 25 %)"),
        (abs(zero_ratio - 1) < 0.15, f"first zero at t = {d['t_zero']:.2f}, viscous theory from rest "
                                     f"{theory['t_zero_from_rest']:.2f}: ratio {zero_ratio:.3f} (tolerance 15 %)"),
    ]
    for ok, text in checks:
        print("ok  " if ok else "FAIL", text)
    if all(ok for ok, _ in checks):
        shutil.rmtree(out)
        return 0
    print(f"output in {out}")
    return 1


if __name__ == "__main__":
    sys.exit(main())
