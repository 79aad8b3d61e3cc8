#!/usr/bin/python3
"""A run steered by a callback: the standard fluid starts from random positions (hot: overlapping
particles release their repulsion energy) and runs until its temperature has converged, then writes a
checkpoint that a production run (or `mesodpd run --restart`) continues from.

Converged: the mean of the last 5 thermo rows differs from the mean of the 5 before by less than 0.5%.
(At dt = 0.04 the Groot-Warren integrator settles about 2.5% above kT = 1, docs/validation.md, so we
test for a plateau, not for 1.)

Run:  PYTHONPATH=build/python /usr/bin/python3 examples/python/steered.py [--out DIR]
"""
import argparse
import pathlib

import numpy as np

import mesodpd

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--out", default="out/steered")
args = parser.parse_args()

spec = mesodpd.Spec(
    system={"box": [8.0, 8.0, 8.0], "kT": 1.0, "seed": 3},
    species=[{"name": "A", "density": 3.0}],
    pair={"a": 25.0, "gamma": 4.5},
    integrator={"dt": 0.04},
    run={"steps": 100000},  # an upper bound: the callback ends the run long before
    output={"thermo_every": 20, "progress": False},
)
sim = mesodpd.Simulation(spec, out=args.out)


def converged(s):
    t = s.thermo_history()["temperature"]
    if len(t) < 10:
        return False
    old, new = t[-10:-5].mean(), t[-5:].mean()
    print(f"step {s.current_step:5d}: T = {t[-1]:.4f}, last 5 rows {new:.4f}, 5 before {old:.4f}")
    return abs(new - old) < 0.005 * new


sim.add_callback(converged, every=100)
sim.run()
assert sim.stopped, "did not converge within run.steps"
h = sim.thermo_history()
print(f"converged at step {sim.current_step} (time {sim.time:.1f}): mean T over the last 5 rows {h['temperature'][-5:].mean():.4f}")
sim.write_checkpoint(pathlib.Path(args.out) / "equilibrated.mdpd")
print(f"wrote {args.out}/equilibrated.mdpd; continue with "
      f"mesodpd.Simulation(spec, restart='{args.out}/equilibrated.mdpd', steps=...)")
np.savetxt(pathlib.Path(args.out) / "temperature.csv", np.c_[h["step"], h["temperature"]], delimiter=",",
           header="step,temperature", comments="")
