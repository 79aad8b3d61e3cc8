#!/usr/bin/python3
"""A parameter scan in a loop: shear viscosity of the DPD fluid against gamma, measured by reverse-
Poiseuille flow and compared with kinetic theory (seed 000 Eq. 16), plotted.

Run:  PYTHONPATH=build/python /usr/bin/python3 examples/python/viscosity_vs_gamma.py [--steps N] [--out DIR]
Default: 5 gammas x 4,000 steps of 1,296 particles, about a minute on two cores. Short runs give
error bars of a few per cent; docs/validation.md section 4 has the long-run value at gamma = 4.5
(0.859 +- 0.005).
"""
import argparse
import math
import pathlib

import numpy as np

import mesodpd
import mesodpd.plot  # noqa: F401 (sets a non-interactive backend when there is no display)
import matplotlib.pyplot as plt

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--steps", type=int, default=4000)
parser.add_argument("--out", default="out/gamma-scan")
parser.add_argument("--gammas", type=float, nargs="+", default=[1.5, 3.0, 4.5, 6.0, 9.0])
args = parser.parse_args()
out = pathlib.Path(args.out)
out.mkdir(parents=True, exist_ok=True)

base = mesodpd.Spec(
    system={"box": [6.0, 6.0, 12.0], "kT": 1.0, "seed": 11},
    species=[{"name": "A", "density": 3.0}],
    pair={"a": 25.0},
    integrator={"dt": 0.04},
    run={"steps": args.steps},
    output={"thermo_every": 100, "progress": False},
    poiseuille={"force": 0.05, "flow_axis": "x", "gradient_axis": "z", "bins": 24, "start": 500, "blocks": 4},
)


def kinetic_eta(rho, gamma):
    """Seed 000 Eq. 16 / Table 1 for s = 2, r_c = 1, kT = 1."""
    d = 45 / (2 * math.pi * gamma * rho)
    eta_d = 2 * math.pi * gamma * rho ** 2 / 15 * (1 / 3 - 1 + 6 / 5 - 2 / 3 + 1 / 7)
    return rho * d / 2 + eta_d


rows = []
for gamma in args.gammas:
    spec = base.copy()
    spec["pair"]["gamma"] = gamma
    numbers = spec.numbers()
    sim = mesodpd.Simulation(spec)  # results in memory (record=True), no files
    sim.run()
    p = sim.profile()
    rows.append((gamma, p["eta"], p["eta_err"], kinetic_eta(3.0, gamma), numbers["reynolds"], numbers["mach"]))
    print(f"gamma = {gamma:4.1f}: eta = {p['eta']:.4f} +- {p['eta_err']:.4f}  kinetic theory {rows[-1][3]:.4f}  "
          f"(Re ~ {numbers['reynolds']:.1f}, Ma ~ {numbers['mach']:.2f})")

data = np.array(rows)
np.savetxt(out / "viscosity_vs_gamma.csv", data, delimiter=",", header="gamma,eta,eta_err,eta_kinetic,Re,Ma",
           comments="")
fig, ax = plt.subplots(figsize=(6.4, 4.4))
ax.errorbar(data[:, 0], data[:, 1], yerr=data[:, 2], fmt="o", label="measured (reverse Poiseuille)")
g = np.linspace(min(args.gammas), max(args.gammas), 100)
ax.plot(g, [kinetic_eta(3.0, x) for x in g], "--", label="kinetic theory (seed 000 Eq. 16)")
ax.set_xlabel("gamma")
ax.set_ylabel("shear viscosity eta")
ax.set_title("DPD fluid, rho = 3, a = 25")
ax.legend()
fig.savefig(out / "viscosity_vs_gamma.png", bbox_inches="tight")
print(f"wrote {out}/viscosity_vs_gamma.png and .csv")
