"""mesodpd: dissipative particle dynamics from Python.

    import mesodpd
    sim = mesodpd.Simulation.from_toml("examples/poiseuille/poiseuille.toml", out="out/py")
    sim.run()

The spec is TOML (docs/config.md) held as nested dicts and validated by the same C++ code as the
``mesodpd`` command; the engine is the C++ library. Units are DPD reduced units (lengths in r_c,
masses in the bead mass, energies in k_BT); ``mesodpd.units`` converts to and from SI.
See docs/python.md.
"""
import os as _os

# Idle OpenMP threads spin briefly, then sleep (as the mesodpd command does; docs/performance.md
# "Busy machines"). libgomp reads this when it is loaded, i.e. when _core is imported below.
if "OMP_WAIT_POLICY" not in _os.environ and "GOMP_SPINCOUNT" not in _os.environ:
    _os.environ["GOMP_SPINCOUNT"] = "1000"

from . import _core  # noqa: E402
from .errors import BlowUpError, SpecError, StopRun  # noqa: E402
from .spec import Spec  # noqa: E402
from .simulation import Simulation, LocalParticles  # noqa: E402
from . import units  # noqa: E402

__version__ = _core.version

__all__ = ["Spec", "Simulation", "LocalParticles", "SpecError", "BlowUpError", "StopRun", "units", "plot",
           "set_threads", "max_threads", "__version__"]


def set_threads(n):
    """Set the OpenMP thread count of this process (results do not depend on it)."""
    if int(n) < 1:
        raise ValueError(f"threads = {n}: must be >= 1")
    _core.set_threads(int(n))


def max_threads():
    """The OpenMP thread count runs will use."""
    return _core.max_threads()


def __getattr__(name):
    # matplotlib is imported only when the plot helpers are used.
    if name == "plot":
        import importlib
        return importlib.import_module(".plot", __name__)
    raise AttributeError(f"module 'mesodpd' has no attribute {name!r}")
