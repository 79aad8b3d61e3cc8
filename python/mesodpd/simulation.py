"""The Simulation class: build a run from a Spec, advance it, steer it with callbacks, read its state."""
import os

import numpy as np

from . import _core
from .errors import StopRun
from .spec import Spec

__all__ = ["Simulation", "LocalParticles"]

# The largest step number: run.steps is a TOML integer (signed 64-bit), as is `mesodpd run --steps`.
_MAX_STEP = 2**63 - 1

_FIELDS = ("id", "species", "x", "y", "z", "vx", "vy", "vz", "fx", "fy", "fz", "ix", "iy", "iz")


class LocalParticles:
    """The particles this MPI rank owns, in storage order, as read-only numpy arrays.

    Each attribute (``id``, ``species``, ``x``, ``y``, ``z``, ``vx``, ``vy``, ``vz``, ``fx``,
    ``fy``, ``fz``, ``ix``, ``iy``, ``iz``) is a read-only array that owns a copy of the engine's
    array at the current step. The copy is made at the first read after a step and shared by the
    reads that follow until the next step, so reading ``sim.particles.x[i]`` in a loop copies once.
    An array kept across a step stays valid and still holds the state of the step it was read at.

    A model's scalars are attributes too: ``temp`` (eDPD), ``conc1`` .. ``conc4`` (tDPD) and their
    rates ``temp_rate``, ``conc_rate1``, ...; ``set(name, values)`` writes the scalars (not the rates).

    ``view(name)`` gives a zero-copy view of the engine's memory instead; the simulation refuses to
    step (RuntimeError) while such a view is referenced, because a step may move or free that memory.
    ``position``, ``velocity``, ``force`` and ``image`` are (N, 3) copies. Storage order is not id
    order: use ``id`` or Simulation.snapshot().
    """

    def __init__(self, sim):
        self._sim = sim
        self._cache = {}
        self._version = None

    def __len__(self):
        return self._sim._core.local_count()

    def __getattr__(self, name):
        if name in _FIELDS:
            return self._copy(name)
        if not name.startswith("_"):
            try:  # a model's scalar: eDPD's temp, tDPD's conc1 .. conc4, spdpd's omega_x .. and their rates
                return self._copy(name)
            except KeyError:
                pass
        raise AttributeError(f"LocalParticles has no attribute {name!r}; fields: {', '.join(_FIELDS)} and the "
                             "run's scalars (temp with pair.style = 'edpd', conc1 .. with 'tdpd', omega_x .. with 'spdpd')")

    def set(self, name, values):
        """Sets a model's scalar of the owned particles: ``temp`` (eDPD's internal temperature),
        ``conc1`` .. ``conc4`` (tDPD's concentrations) or ``omega_x`` .. ``omega_z`` (single-particle DPD's
        angular velocities), one value per owned particle in storage order
        (the order of ``id``). ValueError for a field the run does not hold, a rate, or a wrong length.
        """
        self._sim._core.set_local(name, np.asarray(values, dtype=float))
        self._cache = {}

    def _copy(self, name):
        version = self._sim._core.state_version()
        if version != self._version:
            self._cache = {}
            self._version = version
        a = self._cache.get(name)
        if a is None:
            a = self._cache[name] = self._sim._core.local_copy(name)
        return a

    def view(self, name):
        """A zero-copy, read-only view of the engine's own array ``name`` (no data is copied).

        It is valid only until the next step, and the simulation enforces that: step() and run() raise
        RuntimeError while any view is still referenced. Delete it (``del v``) or copy what you need
        (``numpy.array(v)``) before advancing.
        """
        if name not in _FIELDS:
            raise KeyError(f"no particle array {name!r}; fields: {', '.join(_FIELDS)}")
        return self._sim._core.local_view(name)

    def _stack(self, a, b, c):
        return np.stack([self._copy(a), self._copy(b), self._copy(c)], axis=1)

    @property
    def position(self):
        return self._stack("x", "y", "z")

    @property
    def angular_velocity(self):
        """(N, 3) copy of the angular velocities (pair.style = 'spdpd'; KeyError in a run without spins)."""
        return self._stack("omega_x", "omega_y", "omega_z")

    @property
    def velocity(self):
        return self._stack("vx", "vy", "vz")

    @property
    def force(self):
        return self._stack("fx", "fy", "fz")

    @property
    def image(self):
        return self._stack("ix", "iy", "iz")


class _Callback:
    def __init__(self, fn, every):
        self.fn = fn
        self.every = every


class Simulation:
    """A DPD run (the C++ engine through mesodpd::api::Simulation).

    ``Simulation(spec, out=None, restart=None, steps=None, threads=None, progress=False, record=True)``

    - ``spec``: a Spec or a dict; validated by the C++ code (SpecError naming the key).
    - ``out``: output directory; the same files as ``mesodpd run --out`` (thermo.csv, trajectory,
      analyses, checkpoint.mdpd), byte for byte. None: no files.
    - ``restart``: a checkpoint file to continue from (bit-identical continuation).
    - ``steps``: the final step number, instead of the spec's run.steps (like ``--steps``).
    - ``threads``: OpenMP threads for this process (results do not depend on it).
    - ``record``: measure thermo rows and the configured analyses (profile, RDF, MSD) in memory
      even without ``out``, for thermo_history(), profile(), rdf(), msd().

    Under MPI (``mpirun -np N python3 script.py`` with ``from mpi4py import MPI`` first) every rank
    builds the same Simulation and calls the same methods; results do not depend on the rank count.
    """

    def __init__(self, spec, out=None, *, restart=None, steps=None, threads=None, progress=False, record=True):
        self._spec = spec.copy() if isinstance(spec, Spec) else Spec(spec)
        if threads is not None:
            from . import set_threads
            set_threads(threads)
        validated = self._spec._validated()
        if steps is not None and not 0 <= int(steps) <= _MAX_STEP:
            from .errors import SpecError
            raise SpecError(f"steps = {steps}: must be an integer from 0 to {_MAX_STEP}", "run.steps")
        self.out = os.fspath(out) if out is not None else None
        self._core = _core.Simulation(validated, self.out or "", os.fspath(restart) if restart else "",
                                      None if steps is None else int(steps), bool(progress), bool(record))
        self._callbacks = []
        self.stopped = False
        self.particles = LocalParticles(self)

    def close(self):
        """Ends the simulation: closes its files and releases its output folder, so that another
        Simulation may write there (a live run holds its folder; a second one with the same ``out``
        is refused). The simulation cannot be used afterwards. Also ``with Simulation(...) as sim:``."""
        self._core = None
        self._callbacks = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    @classmethod
    def from_toml(cls, path, out=None, **kwargs):
        """Build from a TOML file (the same file ``mesodpd run`` takes)."""
        return cls(Spec.from_toml(path), out, **kwargs)

    @classmethod
    def from_string(cls, text, out=None, **kwargs):
        """Build from TOML text."""
        return cls(Spec.from_string(text), out, **kwargs)

    # ---- what the run is ----
    @property
    def spec(self):
        """A copy of the Spec this run was built from (editing it does not change the run)."""
        return self._spec.copy()

    @property
    def current_step(self):
        """The current step number."""
        return self._core.current_step()

    @property
    def final_step(self):
        """Where run() without arguments stops: run.steps or the ``steps`` argument."""
        return self._core.final_step()

    @property
    def time(self):
        """step x dt."""
        return self._core.time()

    @property
    def box(self):
        return tuple(self._core.box())

    @property
    def n_particles(self):
        """Particles in the whole system (all ranks)."""
        return self._core.total_particles()

    @property
    def rank(self):
        return self._core.rank()

    @property
    def ranks(self):
        return self._core.ranks()

    # ---- advancing ----
    def add_callback(self, fn, every=1):
        """Call ``fn(sim)`` after every step that is a multiple of ``every``, during run() and step().

        The callback may read anything (thermo(), particles, snapshot(), ...). It stops the run by
        returning a true value (True, numpy.True_, ...) or raising StopRun; None or False continue. Under MPI it runs on every rank and must decide the same
        everywhere (thermo() and the analyses are the same on every rank). Returns a handle for
        remove_callback().
        """
        if int(every) < 1:
            raise ValueError(f"every = {every}: must be >= 1")
        cb = _Callback(fn, int(every))
        self._callbacks.append(cb)
        return cb

    def remove_callback(self, handle):
        self._callbacks.remove(handle)

    def step(self, steps=1):
        """Advance ``steps`` time steps (callbacks fire) without finishing. Returns False if a callback
        stopped it."""
        if not 0 <= int(steps) <= _MAX_STEP - self.current_step:
            raise ValueError(f"steps = {steps}: must be >= 0 and end at step {_MAX_STEP} at most")
        return self._advance_to(self.current_step + int(steps))

    def _advance_to(self, target):
        self.stopped = False
        while self._core.current_step() < target:
            cur = self._core.current_step()
            nxt = target
            for cb in self._callbacks:
                nxt = min(nxt, (cur // cb.every + 1) * cb.every)
            self._core.step(nxt - cur)
            for cb in list(self._callbacks):
                if nxt % cb.every:
                    continue
                try:
                    result = cb.fn(self)
                    stop = result is not None and bool(result)
                except StopRun:
                    stop = True
                if stop:
                    self.stopped = True
                    return False
        return True

    def run(self, steps=None):
        """Advance ``steps`` steps, or to final_step when None, firing callbacks.

        When the run reaches final_step it does what ``mesodpd run`` does at the end: writes the final
        checkpoint and the analysis files (with ``out``) and returns the summary text (rank 0; '' on the
        others). Returns None when a callback stopped the run or final_step was not reached (call
        finish() to write the summaries at any step).
        """
        if steps is not None and not 0 <= int(steps) <= _MAX_STEP - self.current_step:
            raise ValueError(f"steps = {steps}: must be >= 0 and end at step {_MAX_STEP} at most")
        target = self.final_step if steps is None else self.current_step + int(steps)
        if not self._advance_to(target):
            return None
        if self.current_step >= self.final_step:
            return self.finish()
        return None

    def finish(self):
        """Write the final checkpoint and analysis files (with ``out``) at the current step and return the
        summary text (mean temperature, viscosity, D, warnings). May be called more than once."""
        return self._core.finish()

    # ---- state ----
    def thermo(self):
        """The instantaneous state of the whole system: a dict with step, time, temperature,
        temperature_transverse, pressure, pressure_tensor (xx yy zz xy xz yz), pressure_conservative,
        momentum (3), potential_energy, kinetic_energy. Collective under MPI."""
        return self._core.thermo()

    def thermo_history(self):
        """Thermo rows measured so far (every output.thermo_every steps) as numpy arrays, keyed like
        thermo() (pressure_tensor is (n, 6), momentum (n, 3)); the columns of thermo.csv."""
        return self._core.thermo_history()

    def snapshot(self):
        """The whole system in increasing id order (copies): a dict of arrays id, species, x, y, z, vx,
        vy, vz, fx, fy, fz, ix, iy, iz on rank 0, None on the other ranks. Collective under MPI."""
        return self._core.gather()

    def profile(self):
        """The reverse-Poiseuille profile and viscosity so far ([poiseuille]): dict with z, v_mean, v_err,
        v_fit (arrays), eta, eta_err, blocks_used, samples, flow_axis, gradient_axis; None if not
        configured. Same on every rank."""
        return self._core.profile()

    def rdf(self):
        """g(r) so far ([analysis.rdf]): dict with r, g (arrays), samples; None if not configured."""
        return self._core.rdf()

    def msd(self):
        """Mean squared displacement so far ([analysis.msd]): dict with time, msd (arrays), diffusion
        (D from the slope; NaN with too few points); None if not configured."""
        return self._core.msd()

    def bodies(self):
        """The [[body]] rigid bodies now, in block order: a list of dicts with solid (the [[solid]] name),
        mass, particles (its frozen particles), and arrays position (centre of mass, unwrapped),
        orientation (unit quaternion w, x, y, z), velocity, angular_velocity, force and torque (of the
        last step: pair forces, bounce-backs, external force, contacts) and stresslet (xx, yy, zz, xy,
        xz, yz: the symmetric first moment of the last step's forces on it about its centre). Empty
        without bodies; the same on every rank."""
        return self._core.bodies()

    def fields(self):
        """The [analysis.fields] grids averaged so far: a dict name -> dict with bins (nx, ny, nz), samples,
        and arrays of shape (nx, ny, nz): x, y, z (cell centres), density (selected species, per volume),
        vx, vy, vz (mass-weighted velocity), temperature (mean of the three components). The arrays are
        empty before the first sample. Same on every rank."""
        out = {}
        for f in self._core.fields():
            nx, ny, nz = f["bins"]
            for k in ("x", "y", "z", "density", "vx", "vy", "vz", "temperature"):
                if len(f[k]):
                    f[k] = f[k].reshape(nz, ny, nx).transpose(2, 1, 0)
            f["bins"] = (nx, ny, nz)
            out[f["name"]] = f
        return out

    def numbers(self):
        """Dimensionless numbers of this run's spec (see Spec.numbers())."""
        return self._core.spec().flow_numbers()

    def write_checkpoint(self, path):
        """Write the full state; Simulation(spec, restart=path) or ``mesodpd run --restart`` continues it
        bit-identically."""
        self._core.write_checkpoint(os.fspath(path))
