// Dimensionless numbers a user should know before a run (printed by `mesodpd check`, returned by
// mesodpd.Spec.numbers() in Python): Reynolds and Mach numbers of a driven flow, the Schmidt number,
// the speed of sound from the measured equation of state, and warnings for a compressible flow or a time
// step too large for the thermostat. Estimates from the spec alone (kinetic theory, measured alpha).
#pragma once
#include <string>
#include <vector>

#include "mesodpd/spec.hpp"

namespace mesodpd {

struct FlowNumbers {
  double density = 0;          // beads per r_c^3 (all species)
  double alpha = 0;            // EOS coefficient at this density (measured, docs/validation.md)
  double sound_speed = 0;      // sqrt(dp / d rho_m), p = rho kT + alpha(rho) a rho^2 (seed 002 Eq. 11)
  double viscosity = 0;        // kinetic-theory estimate, seed 000 Eq. 16 / Table 1 (NaN if it does not apply)
  std::string viscosity_source;
  double diffusion = 0;        // kinetic-theory self-diffusion (seed 000 Table 1)
  double schmidt = 0;          // nu / D (seed 000 Table 1: 1/2 + ...)
  double flow_speed = 0;       // peak speed of the driven flow (NaN without one)
  double length = 0;           // its length scale: the half-box width of each reverse-Poiseuille layer
  double reynolds = 0;         // rho_m U L / eta (NaN without a driven flow)
  double mach = 0;             // U / c_s
  double friction_rate = 0;    // gamma rho Int w_D d^3r / m: how fast the thermostat damps a velocity
  double thermostat_dt_limit = 0;  // largest dt judged safe for this friction rate (see flow_numbers.cpp)
  std::vector<std::string> warnings;
};

// For a validated spec (DPD pair style; other styles get NaNs and no thermostat check).
FlowNumbers flow_numbers(const SimulationSpec& spec);
// Lines for `mesodpd check`: the numbers, then "warning: ..." lines.
std::string format_flow_numbers(const FlowNumbers& f);

}  // namespace mesodpd
