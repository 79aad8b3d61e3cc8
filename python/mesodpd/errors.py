"""Exceptions raised by mesodpd (the compiled core raises these same classes)."""


class SpecError(ValueError):
    """A configuration problem: a bad key, type, value or file.

    ``key`` is the full key as the TOML schema spells it (``"integrator.dt"``,
    ``"pair.override[1].rd"``), or None when the problem is not about one key (a missing file,
    a TOML syntax error). The message is the one ``mesodpd check`` prints.
    """

    def __init__(self, message, key=None):
        super().__init__(message)
        self.key = key


class BlowUpError(RuntimeError):
    """The run went unstable (NaN, or a particle faster than run.max_velocity).

    ``step`` is the failed step, ``particle_id`` the smallest offending particle id.
    """

    def __init__(self, message, step=0, particle_id=0):
        super().__init__(message)
        self.step = step
        self.particle_id = particle_id


class StopRun(Exception):
    """Raise it in a callback to stop Simulation.run() after the current step."""
