"""Reads the LAMMPS text dumps that mesodpd writes ([output.dump] format = "lammps"), for the examples'
check scripts."""
import numpy as np


def frames(path):
    """Yields (step, columns dict) for every frame of a LAMMPS text dump."""
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            if not line.startswith("ITEM: TIMESTEP"):
                continue
            step = int(next(lines))
            next(lines)
            n = int(next(lines))
            for _ in range(4):
                next(lines)
            names = next(lines).split()[2:]
            rows = np.array([next(lines).split() for _ in range(n)], dtype=float)
            yield step, {name: rows[:, k] for k, name in enumerate(names)}
