#!/usr/bin/python3
"""The default job (examples/poiseuille) from Python: reverse-Poiseuille flow of the standard DPD
fluid, its viscosity and velocity profile. Same spec, same numbers, same files as

    build/mesodpd run examples/poiseuille/poiseuille.toml --out out/poiseuille

Run:  PYTHONPATH=build/python /usr/bin/python3 examples/python/poiseuille.py [--steps N] [--out DIR]
(the full 37,500 steps take about half a minute on two cores; --steps 5000 for a quick look).
"""
import argparse
import pathlib

import mesodpd
import mesodpd.plot

HERE = pathlib.Path(__file__).resolve().parent
CONFIG = HERE.parent / "poiseuille" / "poiseuille.toml"

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--steps", type=int, help="final step (default: run.steps of the config, 37500)")
parser.add_argument("--out", default="out/poiseuille-py", help="output directory")
args = parser.parse_args()

spec = mesodpd.Spec.from_toml(CONFIG)
print(spec.check())                      # Reynolds, Schmidt, Mach numbers before the run
sim = mesodpd.Simulation(spec, out=args.out, steps=args.steps)
print(f"{sim.n_particles} particles, steps {sim.current_step} -> {sim.final_step}, output in {args.out}")
sim.add_callback(lambda s: print(f"step {s.current_step:6d}  T across the flow = {s.thermo()['temperature_transverse']:.4f}"), every=5000)
print(sim.run(), end="")

prof = sim.profile()
print(f"viscosity eta = {prof['eta']:.4f} +- {prof['eta_err']:.4f} from {prof['samples']} profile samples")
fig = mesodpd.plot.velocity_profile(prof, path=pathlib.Path(args.out) / "velocity_profile.png")
print(f"wrote {args.out}/velocity_profile.png (the command line draws velocity_profile.svg)")
