// The units mapper: from a physical description of a liquid (coarse-graining level, molecular size,
// temperature, compressibility, viscosity or self-diffusion, Flory-Huggins chi) to DPD parameters and
// the SI value of the DPD units, and back. Used by `mesodpd units` and by mesodpd.units in Python.
// Formulas and sources: docs/units.md (seed 002 Eqs. 11-13, seed 003 "Mapping DPD units to physical
// units", Groot and Warren's chi-Delta a relation, our measured alpha(rho) in docs/validation.md).
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace mesodpd::units {

inline constexpr double kBoltzmann = 1.380649e-23;  // J/K (exact, SI 2019)
inline constexpr double kAvogadro = 6.02214076e23;  // 1/mol (exact)

// The physical system, in SI units. Of molar_mass, molecular_volume and mass_density give two; of
// inverse_compressibility and isothermal_compressibility one; viscosity or self_diffusion (or both,
// with time_from saying which sets the time unit).
struct PhysicalSystem {
  double coarse_graining = 1.0;                       // N_m: molecules per DPD bead (>= 1)
  double temperature = 300.0;                         // K
  std::optional<double> molar_mass;                   // kg/mol of one molecule (water: 18.015e-3)
  std::optional<double> molecular_volume;             // m^3 per molecule (water at 300 K: 2.99e-29)
  std::optional<double> mass_density;                 // kg/m^3 (water at 300 K: 996.5)
  std::optional<double> inverse_compressibility;      // dimensionless kappa^-1 = 1 / (n k_B T kappa_T)
  std::optional<double> isothermal_compressibility;   // kappa_T in 1/Pa (water at 300 K: 4.5e-10)
  std::optional<double> viscosity;                    // dynamic shear viscosity, Pa s
  std::optional<double> self_diffusion;               // self-diffusion coefficient of one molecule, m^2/s
  std::optional<double> chi;                          // Flory-Huggins chi between two components, per bead
  // DPD side.
  double dpd_density = 3.0;                           // rho, beads per r_c^3
  std::optional<double> alpha;                        // EOS coefficient; default measured_alpha(rho)
  double gamma = 4.5;                                 // dissipative strength (for the transport estimates)
  std::optional<double> dpd_viscosity;                // measured viscosity of the DPD fluid (reduced units)
  std::optional<double> dpd_diffusion;                // measured self-diffusion of the DPD fluid (reduced)
  // Which property sets the time unit: "viscosity", "diffusion", "thermal" (tau = r_c sqrt(m / k_B T))
  // or "auto" (viscosity if given, else diffusion, else thermal).
  std::string time_from = "auto";
};

// Water at 300 K, the worked example of docs/units.md (time unit from the viscosity): molar mass
// 18.015 g/mol, density 996.5 kg/m^3, isothermal compressibility 4.50e-10 1/Pa, viscosity 0.851 mPa s,
// self-diffusion 2.41e-9 m^2/s; N_m and the DPD side are left at their defaults.
PhysicalSystem water_300k();

// The result: DPD parameters and the SI value of one DPD unit of each quantity.
struct Mapping {
  double inverse_compressibility = 0;  // kappa^-1 used (dimensionless)
  double alpha = 0;                    // EOS coefficient used
  std::string alpha_source;            // "measured ..." or "given"
  double a_ii = 0;                     // like-like repulsion, k_B T / r_c (seed 002 Eq. 13)
  std::optional<double> delta_a;       // from chi (Groot and Warren: chi = 0.286 Delta a at rho = 3)
  std::optional<double> a_ij;          // a_ii + delta_a
  double length = 0;                   // r_c in m (seed 003 step 2)
  double mass = 0;                     // bead mass N_m m_molecule in kg (seed 003 step 1)
  double energy = 0;                   // k_B T in J
  double time = 0;                     // the DPD time unit in s
  std::string time_source;             // how it was chosen
  double thermal_time = 0;             // r_c sqrt(m / k_B T) in s, for comparison
  double dpd_viscosity = 0;            // the DPD fluid's viscosity used for the time (reduced)
  double dpd_diffusion = 0;            // and its self-diffusion
  std::string dpd_transport_source;    // "given" or "kinetic theory ..."
  std::vector<std::string> notes;      // caveats worth printing

  // The SI value of `value` DPD units of `quantity` (one of quantities()), and the inverse.
  double to_si(double value, const std::string& quantity) const;
  double from_si(double value, const std::string& quantity) const;
  // SI value of one DPD unit of `quantity`, and its SI unit symbol in unit_symbol().
  double unit(const std::string& quantity) const;
};

// Names accepted by Mapping::to_si/from_si/unit, with their SI symbols: length (m), time (s), mass (kg),
// energy (J), velocity (m/s), acceleration (m/s^2), force (N), viscosity (Pa s), kinematic_viscosity
// (m^2/s), diffusion (m^2/s), stress and pressure (Pa, mechanical: m / (r_c tau^2)), thermal_pressure
// (Pa, k_B T / r_c^3), number_density (1/m^3), mass_density (kg/m^3), shear_rate (1/s).
std::vector<std::pair<std::string, std::string>> quantities();

// alpha(rho) of p = rho k_B T + alpha a rho^2 (seed 002 Eq. 11) as measured with this engine at a = 25,
// k_B T = 1 (docs/validation.md section 2: 0.0918 at rho = 3 rising to 0.1010 at rho = 8), linearly
// interpolated; 0.101 (Groot and Warren) above rho = 8. Throws std::invalid_argument below rho = 3
// (no measurement; the quadratic EOS holds only for rho > 2).
double measured_alpha(double rho);
// d alpha / d rho of the same table (piecewise constant; 0 above rho = 8).
double measured_alpha_slope(double rho);

// Throws std::invalid_argument naming the input that is missing or out of range.
Mapping map_units(const PhysicalSystem& system);

// A readable report of a mapping (the `mesodpd units` output).
std::string format_mapping(const Mapping& m);

}  // namespace mesodpd::units
