"""Imports an installed mesodpd and runs a tiny simulation (tests/install/: the cmake --install and the
pip tests). Usage: python3 tiny_run.py EXPECTED_DIR, where the package must have been imported from
(so a copy elsewhere on sys.path, e.g. the build tree, cannot make the test pass)."""
import os
import pathlib
import sys

import mesodpd

expected = pathlib.Path(sys.argv[1]).resolve()
package = pathlib.Path(mesodpd.__file__).resolve().parent
core = pathlib.Path(mesodpd._core.__file__).resolve()
print(f"mesodpd {mesodpd.__version__} from {package}, _core {core.name}")
assert package.is_relative_to(expected), f"mesodpd imported from {package}, not from under {expected}"
assert core.parent == package, f"_core is {core}, outside the package {package}"

# 4 x 4 x 4 at rho = 3: 192 particles, the standard fluid; velocities start at kT = 1.
sim = mesodpd.Simulation.from_string("""
[system]
box = [4.0, 4.0, 4.0]
kT = 1.0
seed = 3
[[species]]
name = "A"
density = 3.0
[pair]
a = 25.0
gamma = 4.5
[integrator]
dt = 0.04
[run]
steps = 200
""", threads=1)
assert sim.n_particles == 192, sim.n_particles
sim.step(40)
temps = []
for _ in range(16):
    sim.step(10)
    temps.append(sim.thermo()["temperature"])
mean = sum(temps) / len(temps)
print(f"mean temperature {mean:.4f} (kT = 1)")
# 192 particles scatter by about sqrt(2 / 573) = 6% per sample, less over 16 samples.
assert abs(mean - 1.0) < 0.1, mean
assert len(sim.particles.x) == 192
print("tiny_run: ok")
