"""Shared fixtures of the Python tests (run by ctest: python/CMakeLists.txt sets PYTHONPATH and
MESODPD_BIN)."""
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

# A small fluid with everything the observers can do: reverse-Poiseuille profile, RDF, MSD, GSD
# frames, periodic checkpoints. 6 x 6 x 8 at rho = 3: 864 particles, a few ms per step.
SMALL = """
[system]
box = [6.0, 6.0, 8.0]
kT = 1.0
seed = 7

[[species]]
name = "A"
density = 3.0

[pair]
a = 25.0
gamma = 4.5

[integrator]
dt = 0.04

[run]
steps = 60

[output]
thermo_every = 10
checkpoint_every = 30

[output.dump]
format = "gsd"
every = 20
fields = ["id", "species", "position", "velocity"]

[poiseuille]
force = 0.05
flow_axis = "x"
gradient_axis = "z"
bins = 8
start = 10
blocks = 2

[analysis.rdf]
bins = 30
rmax = 2.5
every = 10

[analysis.msd]
every = 10

[analysis.fields]
name = "layers"
bins = [1, 1, 8]
every = 10
"""


@pytest.fixture
def small_toml(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    return path


@pytest.fixture(scope="session")
def mesodpd_bin():
    b = os.environ.get("MESODPD_BIN", str(REPO / "build" / "mesodpd"))
    if not os.path.exists(b):
        pytest.skip(f"no mesodpd command at {b}")
    return b
