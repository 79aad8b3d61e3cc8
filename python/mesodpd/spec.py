"""The simulation spec in Python: the TOML document (docs/config.md) as nested dicts.

Nothing here knows the schema: a Spec is converted to TOML text and read and validated by the
C++ code (the same reader and validate() as ``mesodpd run``/``check``), so new sections of the
schema work from Python as soon as the C++ reader knows them.
"""
import copy
import os

from . import _core

__all__ = ["Spec"]


def _merge(into, update):
    """Deep-merge dict `update` into dict `into` (dicts merge, everything else replaces)."""
    for key, value in update.items():
        if isinstance(value, dict) and isinstance(into.get(key), dict):
            _merge(into[key], value)
        else:
            into[key] = copy.deepcopy(value)


class Spec:
    """A run description: ``spec.data`` is the TOML document as nested dicts and lists.

    Build it from a TOML file (``Spec.from_toml(path)``), TOML text (``Spec.from_string(text)``),
    a dict (``Spec({"system": {...}, "species": [...]})``) or keyword arguments naming the
    top-level sections (``Spec(system={"box": [10, 10, 10]}, species=[{"name": "A", "density": 3}])``).
    Edit it like a dict: ``spec["integrator"]["dt"] = 0.03``, ``spec.update(run={"steps": 100})``.
    A value of None leaves the key out (its default applies).

    ``validate()`` (and every Simulation built from the spec) runs the C++ reader and validate();
    a bad key raises SpecError whose ``key`` is the full key name.
    """

    def __init__(self, data=None, /, *, source="<python>", **sections):
        if isinstance(data, Spec):
            source = data.source if source == "<python>" else source
            data = data.data
        if data is None:
            data = {}
        if not isinstance(data, dict):
            raise TypeError(f"Spec(data): expected a dict or a Spec, got {type(data).__name__}")
        self.data = copy.deepcopy(data)
        _merge(self.data, sections)
        # Where the spec came from: messages name it, and relative paths inside it
        # (init.lammps_data) are taken relative to its directory.
        self.source = str(source)
        self._text = None       # the original TOML text, used while the data is unchanged
        self._text_data = None

    # ---- construction ----
    @classmethod
    def from_toml(cls, path):
        """Read a TOML file (SpecError if it is missing or not valid TOML; keys are checked by validate())."""
        path = os.fspath(path)
        try:
            with open(path, encoding="utf-8") as f:
                text = f.read()
        except OSError as e:
            raise _core_error(f"{path}: cannot read config file: {e.strerror}") from None
        except UnicodeDecodeError as e:
            # TOML is UTF-8 text; a binary file (a checkpoint, an image) is a config problem, not a crash.
            raise _core_error(f"{path}: not a TOML file: byte 0x{e.object[e.start]:02x} at offset {e.start} "
                              "is not UTF-8 text") from None
        return cls._from_text(text, path)

    @classmethod
    def from_string(cls, text, source="<string>"):
        """Parse TOML text."""
        return cls._from_text(text, source)

    @classmethod
    def _from_text(cls, text, source):
        data = _core.toml_to_dict(text, str(source))
        spec = cls(data, source=source)
        spec._text = text
        spec._text_data = copy.deepcopy(data)
        return spec

    def copy(self):
        return Spec(self, source=self.source)

    # ---- dict-like access ----
    def __getitem__(self, key):
        return self.data[key]

    def __setitem__(self, key, value):
        self.data[key] = value

    def __delitem__(self, key):
        del self.data[key]

    def __contains__(self, key):
        return key in self.data

    def get(self, key, default=None):
        return self.data.get(key, default)

    def setdefault(self, key, default):
        return self.data.setdefault(key, default)

    def update(self, other=None, /, **sections):
        """Deep-merge a dict (or Spec) and/or keyword sections into this spec; returns self."""
        if other is not None:
            _merge(self.data, other.data if isinstance(other, Spec) else other)
        _merge(self.data, sections)
        return self

    def __eq__(self, other):
        return isinstance(other, Spec) and self.to_toml() == other.to_toml()

    def __repr__(self):
        return f"Spec(source={self.source!r}, sections={list(self.data)})"

    # ---- TOML ----
    def to_toml(self):
        """The spec as TOML text (tables and keys in sorted order; None values left out)."""
        return _core.dict_to_toml(self.data)

    def save(self, path):
        """Write the spec as a TOML file."""
        with open(os.fspath(path), "w", encoding="utf-8") as f:
            f.write(self.to_toml())

    def _toml_for_reader(self):
        # The original text while the data is unchanged, so messages give its true line numbers.
        text = self.to_toml()
        if self._text is not None and text == _core.dict_to_toml(self._text_data):
            return self._text
        return text

    # ---- validation (C++) ----
    def _validated(self):
        return _core.parse_spec(self._toml_for_reader(), self.source)

    def validate(self):
        """Run the C++ reader and validate(); raise SpecError naming the key. Returns self."""
        self._validated()
        return self

    def resolved(self):
        """Validated values, with what validate() derives (species counts, the pair table, ...):
        a dict with source, box, periodic, kT, seed, dt, steps, thermo_every, species (name, mass,
        count and the pair law's species keys: eDPD's cv, single-particle DPD's radius and inertia, ...)
        and pairs (species, a, gamma, rc, rd, s)."""
        return self._validated().summary()

    def numbers(self):
        """Dimensionless numbers before a run (the lines ``mesodpd check`` prints): a dict with density,
        sound_speed, alpha, viscosity, diffusion, schmidt, flow_speed, length, reynolds, mach,
        friction_rate, thermostat_dt_limit, warnings (list of str) and text. NaN where not defined."""
        return self._validated().flow_numbers()

    def check(self):
        """What ``mesodpd check`` does: validate, read a data file if any, and report. Returns the text."""
        v = self._validated()
        n = v.check_initial_state()
        summary = v.summary()
        numbers = v.flow_numbers()
        return (f"{self.source}: valid ({len(summary['species'])} species, {n} particles)\n"
                + numbers["text"])


def _core_error(message):
    from .errors import SpecError
    return SpecError(message, None)
