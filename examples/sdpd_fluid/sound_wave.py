#!/usr/bin/python3
"""The sound speed of a smoothed-DPD fluid as it propagates (docs/validation.md §12): the longitudinal
current j_k(t) = sum_i v_z,i exp(i k z_i) of the equilibrium fluid decays as cos(c k t) e^(-Gamma t);
the frequency fitted to its autocorrelation gives c at k = 2 pi / L_z and 4 pi / L_z.

    PYTHONPATH=build/python examples/sdpd_fluid/sound_wave.py --kernel lucy --rc 1.5 --kT 0.1 --p_b 0

Box 6 x 6 x 24 at number density 3 (mass 1, rho_0 = 3), eta = 0.5, input c = 8, dt = 0.005; 1000
steps to equilibrate, then --steps samples (about 20 s for 8000 at 42 neighbours on one core).
"""
import argparse

import numpy as np

import mesodpd


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kernel", default="lucy")
    ap.add_argument("--rc", type=float, default=1.5)
    ap.add_argument("--kT", type=float, default=0.1)
    ap.add_argument("--p_b", type=float, default=0.0)
    ap.add_argument("--steps", type=int, default=8000)
    ap.add_argument("--out", default="out/sdpd_sound_wave")
    args = ap.parse_args()
    lz, dt, c_in = 24.0, 0.005, 8.0
    text = f"""[system]
box = [6.0, 6.0, {lz}]
kT = {args.kT}
seed = 41
[[species]]
name = "F"
density = 3.0
[pair]
style = "sdpd"
kernel = "{args.kernel}"
rc = {args.rc}
eta = 0.5
c = {c_in}
rho0 = 3.0
p_b = {args.p_b}
[integrator]
dt = {dt}
[output]
thermo_every = 1000
progress = false
"""
    sim = mesodpd.Simulation.from_string(text, out=args.out, steps=args.steps + 1000)
    sim.step(1000)
    ks = [2 * np.pi / lz * m for m in (1, 2)]
    currents = []
    for _ in range(args.steps):
        sim.step(1)
        z = sim.particles.position[:, 2]
        vz = sim.particles.velocity[:, 2]
        currents.append([np.sum(vz * np.exp(1j * k * z)) for k in ks])
    currents = np.array(currents)
    lags = 400
    t = dt * np.arange(lags)
    for m, k in enumerate(ks):
        j = currents[:, m]
        corr = np.array([np.mean((j[l:] * np.conj(j[: len(j) - l])).real) for l in range(lags)])
        corr /= corr[0]
        best = None
        for w in np.linspace(0.5 * c_in * k, 1.5 * c_in * k, 801):
            for g in np.linspace(0.0, 1.0, 51):
                f = np.exp(-g * t) * np.cos(w * t)
                a = (f @ corr) / (f @ f)
                r = ((a * f - corr) ** 2).sum()
                if best is None or r < best[0]:
                    best = (r, w, g)
        print(f"{args.kernel} rc {args.rc} kT {args.kT} p_b {args.p_b}: k = {k:.4f}, c = {best[1] / k:.3f} "
              f"(input {c_in}), damping {best[2]:.3f}")


if __name__ == "__main__":
    main()
