"""Run a config from Python under mpirun (test_mpi.py): python3 mpi_run.py CONFIG OUT."""
import sys

from mpi4py import MPI  # initialises MPI before mesodpd builds its communicator

import mesodpd

config, out = sys.argv[1], sys.argv[2]
sim = mesodpd.Simulation.from_toml(config, out=out, threads=1)
assert sim.ranks == MPI.COMM_WORLD.Get_size() and sim.rank == MPI.COMM_WORLD.Get_rank()
temps = []
sim.add_callback(lambda s: temps.append(s.thermo()["temperature"]) and None, every=10)
sim.run()
snap = sim.snapshot()
assert (snap is None) == (sim.rank != 0)
g = sim.rdf()  # the same on every rank
allg = MPI.COMM_WORLD.allgather((g["samples"], g["g"].tobytes(), tuple(temps)))
assert all(x == allg[0] for x in allg)
if sim.rank == 0:
    print("ok", sim.ranks, len(sim.particles), "of", sim.n_particles)
