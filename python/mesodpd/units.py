"""Physical units <-> DPD units (the C++ mapper of include/mesodpd/units.hpp; formulas in docs/units.md).

    m = mesodpd.units.water(coarse_graining=3)          # water at 300 K, N_m = 3
    m.a_ii, m.length, m.time                            # 85.5 k_BT/r_c, 6.46e-10 m, ... s
    m.to_si(0.86, "viscosity")                          # a DPD viscosity in Pa s
    m.from_si(1e-3, "velocity")                         # 1 mm/s in r_c / tau

    m = mesodpd.units.map(coarse_graining=1, molar_mass=18.015e-3, mass_density=996.5,
                          inverse_compressibility=16, alpha=0.101)

All inputs are SI (kg/mol, m^3, kg/m^3, 1/Pa, Pa s, m^2/s, K). Bad or missing inputs raise ValueError
naming the input.

A red cell's membrane in the units of a [[membrane]] run (docs/units.md, "Membranes in SI"):

    c = mesodpd.units.membrane(shear_modulus=6.3e-6, bending_rigidity=2.4e-19, diameter=7.82e-6,
                               membrane_viscosity=0.5e-6)   # um, k_BT at 310 K, ms
    c.keys["shear_modulus"], c.from_si(193e-12, "force") # 1471.96 k_BT/um^2, 193 pN in k_BT/um

Smoothed DPD takes its inputs as they are (docs/units.md, "Smoothed DPD in SI"):

    s = mesodpd.units.sdpd(mass_density=996.5, viscosity=8.5e-4, temperature=300, spacing=0.5e-6,
                           flow_speed=1e-3)              # water at 0.5 um, flows of 1 mm/s at Mach 0.1
    s.pair, s.dt, s.to_si(1.0, "time")                   # the [pair] keys, a time step, tau in s
"""
import math

from . import _core

__all__ = ["map", "water", "WATER_300K", "measured_alpha", "quantities", "Mapping", "INPUTS", "sdpd",
           "SdpdUnits", "membrane", "MembraneUnits"]

Mapping = _core.Mapping

# Water at 300 K, the inputs of the worked example (docs/units.md), from the C++ mapper: temperature,
# molar mass, density, isothermal compressibility, shear viscosity, self-diffusion coefficient.
WATER_300K = {k: getattr(_core.water_300k(), k) for k in
              ("temperature", "molar_mass", "mass_density", "isothermal_compressibility", "viscosity",
               "self_diffusion")}

INPUTS = ("coarse_graining", "temperature", "molar_mass", "molecular_volume", "mass_density",
          "inverse_compressibility", "isothermal_compressibility", "viscosity", "self_diffusion", "chi",
          "dpd_density", "alpha", "gamma", "dpd_viscosity", "dpd_diffusion", "time_from")


def map(**inputs):  # noqa: A001 (the natural name)
    """Map a physical liquid to DPD: keyword arguments are the fields of INPUTS (SI units).

    Returns a Mapping: a_ii, delta_a, a_ij (None without chi), alpha, alpha_source,
    inverse_compressibility, length (r_c, m), mass (kg), energy (J), time (tau, s), time_source,
    thermal_time, dpd_viscosity, dpd_diffusion, dpd_transport_source, notes; and to_si(value,
    quantity), from_si(value, quantity), unit(quantity), text().
    """
    system = _core.PhysicalSystem()
    for key, value in inputs.items():
        if key not in INPUTS:
            raise ValueError(f"units.map: unknown input '{key}'; inputs: {', '.join(INPUTS)}")
        if value is not None and key != "time_from":
            value = float(value)
        setattr(system, key, value)
    return _core.map_units(system)


def water(coarse_graining=3, **overrides):
    """The worked example: water at 300 K with N_m molecules per bead (time from the viscosity)."""
    inputs = dict(WATER_300K)
    inputs["coarse_graining"] = coarse_graining
    inputs.update(overrides)
    return map(**inputs)


def measured_alpha(density):
    """alpha(rho) of p = rho kT + alpha a rho^2, as measured with mesodpd (docs/validation.md)."""
    return _core.measured_alpha(float(density))


def quantities():
    """The quantity names to_si/from_si accept, with their SI units."""
    return dict(_core.unit_quantities())


BOLTZMANN = 1.380649e-23  # J/K (exact, SI 2019)


class _ScaledUnits:
    """Reduced units given by three base units (the names in _BASES, their SI values as attributes):
    a quantity's scale is the product of their powers in _DIMENSIONS."""

    _DIMENSIONS = {}
    _BASES = ()

    def __init__(self, **fields):
        self.__dict__.update(fields)

    def _scale(self, quantity):
        if quantity not in self._DIMENSIONS:
            raise ValueError(f"{type(self).__name__}: unknown quantity '{quantity}'; "
                             f"quantities: {', '.join(self._DIMENSIONS)}")
        scale = 1.0
        for base, power in zip(self._BASES, self._DIMENSIONS[quantity]):
            scale *= getattr(self, base) ** power
        return scale

    def to_si(self, value, quantity):
        return value * self._scale(quantity)

    def from_si(self, value, quantity):
        return value / self._scale(quantity)


class SdpdUnits(_ScaledUnits):
    """Smoothed DPD in reduced units from SI inputs (sdpd()). Units: length = the particle spacing
    (number density 1), mass = the particle mass rho dx^3, energy = k_B T (kT = 1), time
    tau = dx sqrt(m / k_B T). Attributes: length, mass, energy, time (SI), pair (the [pair] keys of
    pair.style = "sdpd"), density (1), kT (1), neighbours, cfl_limit, viscous_limit, dt (half the
    smaller limit), mach (of flow_speed), and to_si / from_si for "length", "time", "mass", "velocity",
    "viscosity", "pressure", "force", "energy"."""

    _DIMENSIONS = {  # (length, mass, time) exponents
        "length": (1, 0, 0), "time": (0, 0, 1), "mass": (0, 1, 0), "velocity": (1, 0, -1),
        "viscosity": (-1, 1, -1), "pressure": (-1, 1, -2), "force": (1, 1, -2), "energy": (2, 1, -2),
        "mass_density": (-3, 1, 0),
    }

    _BASES = ("length", "mass", "time")

    def toml(self):
        """The [system], [[species]], [pair] and [integrator] lines of a config (box not included)."""
        pair = "\n".join(f'{k} = "{v}"' if isinstance(v, str) else f"{k} = {v:.10g}" for k, v in self.pair.items())
        return (f"[system]\nkT = 1.0\n\n[[species]]\nname = \"fluid\"\ndensity = 1.0\nmass = 1.0\n\n"
                f"[pair]\nstyle = \"sdpd\"\n{pair}\n\n[integrator]\ndt = {self.dt:.6g}\n")


def sdpd(mass_density, viscosity, temperature, spacing, sound_speed=None, flow_speed=None, mach=0.1,
         bulk_viscosity=0.0, neighbours=100, kernel="lucy", eos_exponent=1.0, thermal_mach=0.1):
    """Map a liquid in SI to pair.style = "sdpd": mass density (kg/m^3), shear and bulk viscosity
    (Pa s), temperature (K) and the particle spacing (m). The sound speed (m/s) is SDPD's numerical
    choice (the real one would make dt tiny): given, or the larger of flow_speed / mach and
    sqrt(k_B T / m) / thermal_mach, so that neither the flow nor the particles' thermal motion
    compresses the fluid much (density fluctuations ~ k_B T / (m c^2)). The kernel cutoff holds
    `neighbours` particles: Lucy's kernel over 100 (the defaults) gave the input viscosity within 4%
    where eta is large against rho_0 c rc (docs/validation.md §12). Raises ValueError naming a bad
    input."""
    named = {"mass_density": mass_density, "viscosity": viscosity, "temperature": temperature,
             "spacing": spacing, "neighbours": neighbours}
    for key, value in named.items():
        if value is None or not (float(value) > 0) or math.isinf(float(value)):
            raise ValueError(f"units.sdpd: {key} = {value!r} must be a positive number")
    if bulk_viscosity < 0:
        raise ValueError(f"units.sdpd: bulk_viscosity = {bulk_viscosity!r} must not be negative")
    if kernel not in ("lucy", "wendland"):
        raise ValueError(f"units.sdpd: kernel = {kernel!r} must be \"lucy\" or \"wendland\"")
    length = float(spacing)
    mass = float(mass_density) * length ** 3
    energy = BOLTZMANN * float(temperature)
    time = length * math.sqrt(mass / energy)
    thermal_speed = length / time  # sqrt(k_B T / m)
    if sound_speed is None:
        if flow_speed is None or not (flow_speed > 0) or not (mach > 0) or not (thermal_mach > 0):
            raise ValueError("units.sdpd: give sound_speed, or flow_speed (> 0) with mach and thermal_mach (> 0)")
        sound_speed = max(flow_speed / mach, thermal_speed / thermal_mach)
    if not (sound_speed > 0):
        raise ValueError(f"units.sdpd: sound_speed = {sound_speed!r} must be positive")
    u = SdpdUnits(length=length, mass=mass, energy=energy, time=time, density=1.0, kT=1.0)
    rc = (3.0 * neighbours / (4.0 * math.pi)) ** (1.0 / 3.0)  # n 4 pi rc^3 / 3 = neighbours at n = 1
    eta = u.from_si(viscosity, "viscosity")
    c = u.from_si(sound_speed, "velocity")
    u.pair = {"kernel": kernel, "rc": rc, "eta": eta, "zeta": u.from_si(bulk_viscosity, "viscosity"), "c": c,
              "rho0": 1.0, "eos_exponent": float(eos_exponent)}
    u.neighbours = float(neighbours)
    # The limits the engine checks (physics/sdpd_pair.hpp): sound 0.25 rc / c, viscous 0.05 rc^2 rho0 / eta.
    u.cfl_limit = 0.25 * rc / c
    u.viscous_limit = 0.05 * rc * rc / eta
    u.dt = 0.5 * min(u.cfl_limit, u.viscous_limit)
    u.mach = None if flow_speed is None else flow_speed / sound_speed
    return u


class MembraneUnits(_ScaledUnits):
    """A membrane in the units of a [[membrane]] run (membrane()): length `length` (m), energy k_B T,
    time `time` (s); the vertex mass is a numerical choice, not mapped (docs/units.md). Attributes:
    length, energy, time, keys (the [[membrane]] keys: diameter, shear_modulus, kappa, ka, kd, kv and
    viscosity when a membrane viscosity is given), area_modulus and young_modulus (SI, N/m: the network's
    K = 2 mu0 + k_a + k_d and Y = 4 K mu0 / (K + mu0), Fedosov et al. 2010), and to_si / from_si for
    "length", "area", "volume", "time", "energy", "force", "modulus" (N/m), "membrane_viscosity" (N s/m),
    "velocity" and "viscosity" (Pa s)."""

    _DIMENSIONS = {  # (length, energy, time) exponents
        "length": (1, 0, 0), "area": (2, 0, 0), "volume": (3, 0, 0), "time": (0, 0, 1), "energy": (0, 1, 0),
        "force": (-1, 1, 0), "modulus": (-2, 1, 0), "membrane_viscosity": (-2, 1, 1), "velocity": (1, 0, -1),
        "viscosity": (-3, 1, 1),
    }

    _BASES = ("length", "energy", "time")

    def toml(self):
        """The physical lines of a [[membrane]] block (species, mesh and placement left to the config)."""
        return "\n".join(f"{k} = {v:.6g}" for k, v in self.keys.items()) + "\n"


def membrane(shear_modulus, bending_rigidity, diameter, temperature=310.0, length=1e-6, time=1e-3,
             membrane_viscosity=None, ka_ratio=49.0, kd_ratio=1.0, kv_ratio=50.0):
    """Map a membrane in SI to [[membrane]] keys: shear modulus mu0 (N/m), bending rigidity kappa (J),
    diameter (m), temperature (K), the length and time units (m, s) and optionally the membrane's 2-D
    shear viscosity (N s/m). The area and volume constraints are given as multiples of mu0 (k_a =
    ka_ratio mu0, k_d = kd_ratio mu0, k_v = kv_ratio mu0 per length unit; the defaults are those of
    examples/rbc_stretch, which hold a red cell's area and volume within 0.5 %). The engine turns
    shear_modulus into the WLC persistence length through the network's analytic modulus at the mesh's
    mean edge length. Raises ValueError naming a bad input."""
    named = {"shear_modulus": shear_modulus, "bending_rigidity": bending_rigidity, "diameter": diameter,
             "temperature": temperature, "length": length, "time": time}
    if membrane_viscosity is not None:
        named["membrane_viscosity"] = membrane_viscosity
    for key, value in {**named, "ka_ratio": ka_ratio, "kd_ratio": kd_ratio, "kv_ratio": kv_ratio}.items():
        try:
            ok = float(value) >= 0 if key.endswith("_ratio") else float(value) > 0
        except (TypeError, ValueError):
            ok = False
        if not ok or math.isinf(float(value)):
            raise ValueError(f"units.membrane: {key} = {value!r} must be a "
                             f"{'non-negative' if key.endswith('_ratio') else 'positive'} finite number")
    u = MembraneUnits(length=float(length), energy=BOLTZMANN * float(temperature), time=float(time))
    mu0 = u.from_si(shear_modulus, "modulus")
    u.keys = {"diameter": u.from_si(diameter, "length"), "shear_modulus": mu0,
              "kappa": u.from_si(bending_rigidity, "energy"), "ka": ka_ratio * mu0, "kd": kd_ratio * mu0,
              "kv": kv_ratio * mu0}
    if membrane_viscosity is not None:
        u.keys["viscosity"] = u.from_si(membrane_viscosity, "membrane_viscosity")
    k_area = 2.0 * mu0 + u.keys["ka"] + u.keys["kd"]
    u.area_modulus = u.to_si(k_area, "modulus")
    u.young_modulus = u.to_si(4.0 * k_area * mu0 / (k_area + mu0), "modulus")
    return u
