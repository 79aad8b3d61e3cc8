"""Keeps particle arrays across steps while a rank's local count grows (test_valgrind.py runs it under
valgrind on two ranks): python3 kept_arrays.py. Prints 'ok RANK' when the kept arrays still hold the
values of the step they were read at."""
import sys

try:
    from mpi4py import MPI  # noqa: F401  (initialises MPI before mesodpd builds its communicator)
except ImportError:
    pass
import numpy as np

import mesodpd

# All particles start in x < 5 of an 8-wide box split in two along x at x = 4, pushed along +x: the
# rank of x >= 4 goes from ~200 to ~500 particles, so its arrays are reallocated (a kept zero-copy
# view of the old ones would read freed memory).
spec = mesodpd.Spec(system={"box": [8.0, 8.0, 8.0], "seed": 3},
                    species=[{"name": "A", "density": 3.0, "body_force": [1.0, 0.0, 0.0],
                              "region": {"shape": "box", "lo": [0.0, 0.0, 0.0], "hi": [5.0, 8.0, 8.0]}}],
                    pair={"a": 25.0, "gamma": 4.5}, integrator={"dt": 0.04}, run={"steps": 100},
                    parallel={"grid": [2, 1, 1]})
sim = mesodpd.Simulation(spec, threads=1)
kept = {name: getattr(sim.particles, name) for name in ("id", "x", "vx", "fx", "ix")}
expected = {name: np.array(a, copy=True) for name, a in kept.items()}
n0 = len(sim.particles)
sim.step(20)
# Read every kept array after the steps (valgrind reports a read of freed memory here), then check it.
same = {name: bool(np.array_equal(kept[name], expected[name])) for name in kept}
inside = bool(np.all((kept["x"] >= 0) & (kept["x"] < 8.0)))
n1 = len(sim.particles)
print(f"rank {sim.rank}: {n0} -> {n1} particles, kept arrays unchanged: {same}, x inside the box: {inside}")
sys.stdout.flush()
if all(same.values()) and inside:
    print(f"ok {sim.rank}")
