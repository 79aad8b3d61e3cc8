"""Physical units <-> DPD units (the C++ mapper of include/mesodpd/units.hpp; formulas in docs/units.md).

    m = mesodpd.units.water(coarse_graining=3)          # water at 300 K, N_m = 3
    m.a_ii, m.length, m.time                            # 85.5 k_BT/r_c, 6.46e-10 m, ... s
    m.to_si(0.86, "viscosity")                          # a DPD viscosity in Pa s
    m.from_si(1e-3, "velocity")                         # 1 mm/s in r_c / tau

    m = mesodpd.units.map(coarse_graining=1, molar_mass=18.015e-3, mass_density=996.5,
                          inverse_compressibility=16, alpha=0.101)

All inputs are SI (kg/mol, m^3, kg/m^3, 1/Pa, Pa s, m^2/s, K). Bad or missing inputs raise ValueError
naming the input.
"""
from . import _core

__all__ = ["map", "water", "WATER_300K", "measured_alpha", "quantities", "Mapping", "INPUTS"]

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
