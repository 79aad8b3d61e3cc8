// The units mapper (include/mesodpd/units.hpp): physical liquid -> DPD parameters and SI units.
#include "mesodpd/units.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "analysis/kinetic_theory.hpp"

namespace mesodpd::units {

namespace {

// alpha(rho) measured with this engine (docs/validation.md section 2, a = 25, gamma = 4.5, dt = 0.04).
constexpr std::array<std::pair<double, double>, 6> kAlphaTable{{
    {3.0, 0.09176}, {4.0, 0.09575}, {5.0, 0.09797}, {6.0, 0.09937}, {7.0, 0.10032}, {8.0, 0.10100}}};
constexpr double kAlphaHigh = 0.101;  // Groot and Warren's single value (seed 002 Eq. 11), for rho > 8

// Groot and Warren (J. Chem. Phys. 107, 4423, 1997), cited in seed 002: chi = c Delta a at rho = 3, 5.
constexpr std::array<std::pair<double, double>, 2> kChiPerDeltaA{{{3.0, 0.286}, {5.0, 0.689}}};

[[noreturn]] void bad(const std::string& what) { throw std::invalid_argument(what); }

void positive(const std::optional<double>& v, const char* name) {
  if (v && !(*v > 0 && std::isfinite(*v))) bad(fmt::format("{} = {}: must be a positive number", name, *v));
}

}  // namespace

double measured_alpha(double rho) {
  if (!(rho >= kAlphaTable.front().first))
    bad(fmt::format("dpd_density = {}: alpha(rho) is measured only for rho >= 3 (the quadratic equation of state "
                    "holds for rho > 2); give alpha explicitly",
                    rho));
  if (rho >= kAlphaTable.back().first) return rho == kAlphaTable.back().first ? kAlphaTable.back().second : kAlphaHigh;
  for (std::size_t k = 1; k < kAlphaTable.size(); ++k)
    if (rho <= kAlphaTable[k].first) {
      const auto [r0, a0] = kAlphaTable[k - 1];
      const auto [r1, a1] = kAlphaTable[k];
      return a0 + (a1 - a0) * (rho - r0) / (r1 - r0);
    }
  return kAlphaHigh;
}

double measured_alpha_slope(double rho) {
  if (rho < kAlphaTable.front().first || rho >= kAlphaTable.back().first) return 0.0;
  for (std::size_t k = 1; k < kAlphaTable.size(); ++k)
    if (rho < kAlphaTable[k].first)
      return (kAlphaTable[k].second - kAlphaTable[k - 1].second) / (kAlphaTable[k].first - kAlphaTable[k - 1].first);
  return 0.0;
}

PhysicalSystem water_300k() {
  PhysicalSystem s;
  s.temperature = 300.0;
  s.molar_mass = 18.015e-3;
  s.mass_density = 996.5;
  s.isothermal_compressibility = 4.50e-10;
  s.viscosity = 0.851e-3;
  s.self_diffusion = 2.41e-9;
  return s;
}

std::vector<std::pair<std::string, std::string>> quantities() {
  return {{"length", "m"},
          {"time", "s"},
          {"mass", "kg"},
          {"energy", "J"},
          {"velocity", "m/s"},
          {"acceleration", "m/s^2"},
          {"force", "N"},
          {"viscosity", "Pa s"},
          {"kinematic_viscosity", "m^2/s"},
          {"diffusion", "m^2/s"},
          {"stress", "Pa"},
          {"pressure", "Pa"},
          {"thermal_pressure", "Pa"},
          {"number_density", "1/m^3"},
          {"mass_density", "kg/m^3"},
          {"shear_rate", "1/s"},
          // eDPD and tDPD (pair.style = "edpd", "tdpd"; docs/units.md, "Heat and solutes"): a temperature
          // of 1 is the mapping's T, C_v is in units of k_B per particle, and the diffusivities of heat and
          // solutes are lengths squared per time.
          {"temperature", "K"},
          {"heat_capacity", "J/K"},
          {"specific_heat", "J/(kg K)"},
          {"thermal_conductivity", "W/(m K)"},
          {"thermal_diffusivity", "m^2/s"},
          {"heat_flux", "W/m^2"},
          {"power", "W"}};
}

double Mapping::unit(const std::string& q) const {
  const double L = length, T = time, M = mass;
  if (q == "length") return L;
  if (q == "time") return T;
  if (q == "mass") return M;
  if (q == "energy") return energy;
  if (q == "velocity") return L / T;
  if (q == "acceleration") return L / (T * T);
  if (q == "force") return M * L / (T * T);
  if (q == "viscosity") return M / (L * T);
  if (q == "kinematic_viscosity" || q == "diffusion") return L * L / T;
  if (q == "stress" || q == "pressure") return M / (L * T * T);
  if (q == "thermal_pressure") return energy / (L * L * L);
  if (q == "number_density") return 1.0 / (L * L * L);
  if (q == "mass_density") return M / (L * L * L);
  if (q == "shear_rate") return 1.0 / T;
  if (q == "temperature") return energy / kBoltzmann;
  if (q == "heat_capacity") return kBoltzmann;
  if (q == "specific_heat") return kBoltzmann / M;
  if (q == "thermal_conductivity") return kBoltzmann / (L * T);
  if (q == "thermal_diffusivity") return L * L / T;
  if (q == "heat_flux") return energy / (L * L * T);
  if (q == "power") return energy / T;
  std::string names;
  for (const auto& [name, symbol] : quantities()) names += (names.empty() ? "" : ", ") + name;
  bad(fmt::format("quantity '{}' is not known; one of: {}", q, names));
}

double Mapping::to_si(double value, const std::string& quantity) const { return value * unit(quantity); }
double Mapping::from_si(double value, const std::string& quantity) const { return value / unit(quantity); }

Mapping map_units(const PhysicalSystem& s) {
  positive(s.molar_mass, "molar_mass");
  positive(s.molecular_volume, "molecular_volume");
  positive(s.mass_density, "mass_density");
  positive(s.inverse_compressibility, "inverse_compressibility");
  positive(s.isothermal_compressibility, "isothermal_compressibility");
  positive(s.viscosity, "viscosity");
  positive(s.self_diffusion, "self_diffusion");
  positive(s.dpd_viscosity, "dpd_viscosity");
  positive(s.dpd_diffusion, "dpd_diffusion");
  positive(s.alpha, "alpha");
  if (!(s.coarse_graining >= 1)) bad(fmt::format("coarse_graining = {}: N_m must be >= 1", s.coarse_graining));
  if (!(s.temperature > 0)) bad(fmt::format("temperature = {}: must be > 0 K", s.temperature));
  if (!(s.dpd_density > 0)) bad(fmt::format("dpd_density = {}: must be > 0", s.dpd_density));
  if (!(s.gamma > 0)) bad(fmt::format("gamma = {}: must be > 0", s.gamma));

  Mapping m;
  const double kT = kBoltzmann * s.temperature;
  const double Nm = s.coarse_graining, rho = s.dpd_density;

  // Mass and volume of one molecule, from two of molar mass, molecular volume and mass density.
  const int given = (s.molar_mass ? 1 : 0) + (s.molecular_volume ? 1 : 0) + (s.mass_density ? 1 : 0);
  if (given < 2) bad("give two of molar_mass, molecular_volume and mass_density");
  const double m_mol = s.molar_mass ? *s.molar_mass / kAvogadro : *s.mass_density * *s.molecular_volume;
  const double v_mol = s.molecular_volume ? *s.molecular_volume : m_mol / *s.mass_density;
  if (given == 3 && std::abs(m_mol / v_mol / *s.mass_density - 1) > 0.01)
    bad(fmt::format("molar_mass, molecular_volume and mass_density disagree (mass / volume = {:.4g} kg/m^3 vs "
                    "mass_density = {:.4g}); give two of them",
                    m_mol / v_mol, *s.mass_density));
  const double rho_mass = m_mol / v_mol;

  // Compressibility: kappa^-1 = 1 / (n k_B T kappa_T) with n = 1 / v_mol molecules per volume.
  if (s.inverse_compressibility && s.isothermal_compressibility)
    bad("give inverse_compressibility or isothermal_compressibility, not both");
  if (s.inverse_compressibility)
    m.inverse_compressibility = *s.inverse_compressibility;
  else if (s.isothermal_compressibility)
    m.inverse_compressibility = v_mol / (kT * *s.isothermal_compressibility);
  else
    bad("give inverse_compressibility (dimensionless) or isothermal_compressibility (1/Pa)");

  // alpha of the density actually used (alpha(rho) is not constant: docs/validation.md).
  if (s.alpha) {
    m.alpha = *s.alpha;
    m.alpha_source = "given";
  } else {
    m.alpha = measured_alpha(rho);
    m.alpha_source = fmt::format("measured with mesodpd at rho = {} (docs/validation.md; Groot-Warren's 0.101 holds "
                                 "for rho >= 6 only)",
                                 rho);
    m.notes.push_back("alpha was measured at a = 25; it depends weakly on a, so for a far from 25 measure the "
                      "equation of state (mesodpd-validate eos) at the new a and pass alpha");
  }
  // seed 002 Eq. 13: a = (kappa^-1 N_m - 1) / (2 alpha rho), in k_B T / r_c.
  m.a_ii = (m.inverse_compressibility * Nm - 1.0) / (2.0 * m.alpha * rho);
  if (m.a_ii <= 0) bad(fmt::format("kappa^-1 N_m = {} <= 1 gives no repulsion", m.inverse_compressibility * Nm));

  if (s.chi) {
    const auto* row = [&]() -> const std::pair<double, double>* {
      for (const auto& r : kChiPerDeltaA)
        if (r.first == rho) return &r;
      return nullptr;
    }();
    if (!row)
      bad(fmt::format("chi: the chi-Delta a relation is known at dpd_density = 3 (chi = 0.286 Delta a) and 5 "
                      "(0.689 Delta a) only, not at {}",
                      rho));
    m.delta_a = *s.chi / row->second;
    m.a_ij = m.a_ii + *m.delta_a;
  }

  // seed 003, steps 1 and 2: bead mass N_m m_molecule; r_c from equal mass densities,
  // m rho / r_c^3 = rho_mass, i.e. r_c^3 = rho N_m v_molecule.
  m.mass = Nm * m_mol;
  m.length = std::cbrt(rho * Nm * v_mol);
  m.energy = kT;
  m.thermal_time = m.length * std::sqrt(m.mass / kT);

  // Transport of the DPD fluid (reduced units): measured values if given, else kinetic theory.
  const bool kinetic = !s.dpd_viscosity || !s.dpd_diffusion;
  m.dpd_viscosity = s.dpd_viscosity ? *s.dpd_viscosity : kinetic_viscosity(rho, s.gamma, 1.0, 1.0, 2.0);
  m.dpd_diffusion = s.dpd_diffusion ? *s.dpd_diffusion : kinetic_diffusivity(rho, s.gamma, 1.0, 1.0, 2.0);
  m.dpd_transport_source =
      kinetic ? fmt::format("{}kinetic theory for gamma = {}, s = 2 (seed 000 Eq. 16, Table 1), which ignores a: "
                            "at a = 25 the measured viscosity is 10% lower and D about half (docs/validation.md); "
                            "pass dpd_viscosity / dpd_diffusion measured at a = {:.4g} for an accurate time unit",
                            s.dpd_viscosity || s.dpd_diffusion ? "partly given, otherwise " : "", s.gamma, m.a_ii)
              : "given";

  std::string from = s.time_from;
  if (from == "auto") from = s.viscosity ? "viscosity" : (s.self_diffusion ? "diffusion" : "thermal");
  if (from == "viscosity") {
    if (!s.viscosity) bad("time_from = viscosity needs viscosity (Pa s)");
    // seed 003 step 3: equal kinematic viscosities, nu_phys = nu_dpd r_c^2 / tau.
    const double nu_phys = *s.viscosity / rho_mass;
    const double nu_dpd = m.dpd_viscosity / rho;  // unit bead mass: mass density = rho
    m.time = nu_dpd * m.length * m.length / nu_phys;
    m.time_source = "kinematic viscosity matched (seed 003 step 3)";
  } else if (from == "diffusion") {
    if (!s.self_diffusion) bad("time_from = diffusion needs self_diffusion (m^2/s)");
    // Seed 002 (refs 15, 17): match the self-diffusion. A bead of N_m molecules diffuses as their centre
    // of mass, D_molecule / N_m (Groot and Rabone): D_dpd r_c^2 / tau = D_molecule / N_m.
    m.time = Nm * m.dpd_diffusion * m.length * m.length / *s.self_diffusion;
    m.time_source = "self-diffusion matched, bead = N_m molecules (seed 002, Groot and Rabone)";
  } else if (from == "thermal") {
    m.time = m.thermal_time;
    m.time_source = "thermal: r_c sqrt(m / k_B T)";
  } else {
    bad(fmt::format("time_from = '{}': one of auto, viscosity, diffusion, thermal", s.time_from));
  }
  if (from != "thermal")
    m.notes.push_back(fmt::format(
        "the time unit is {:.3g} x r_c sqrt(m / k_B T): stresses in mechanical units m / (r_c tau^2) then differ from "
        "k_B T / r_c^3 by the square of that factor (use 'thermal_pressure' for equation-of-state pressures)",
        m.time / m.thermal_time));
  if (s.viscosity && s.self_diffusion) {
    const double sc_phys = *s.viscosity / rho_mass / *s.self_diffusion;
    const double sc_dpd = m.dpd_viscosity / rho / m.dpd_diffusion;
    m.notes.push_back(fmt::format("Schmidt number: physical {:.3g}, DPD fluid {:.3g} (seed 002: DPD's is gas-like); "
                                  "the time unit cannot match both viscosity and diffusion",
                                  sc_phys, sc_dpd));
  }
  return m;
}

std::string format_mapping(const Mapping& m) {
  std::string out;
  out += fmt::format("kappa^-1 = {:.4g} (dimensionless), alpha = {:.4g} ({})\n", m.inverse_compressibility, m.alpha,
                     m.alpha_source);
  out += fmt::format("a_ii = {:.4f} k_BT/r_c (seed 002 Eq. 13)\n", m.a_ii);
  if (m.delta_a)
    out += fmt::format("Delta a = {:.4f}, a_ij = {:.4f} k_BT/r_c (chi = 0.286 Delta a at rho = 3, Groot-Warren)\n",
                       *m.delta_a, *m.a_ij);
  out += fmt::format("DPD fluid: viscosity {:.4g}, self-diffusion {:.4g} ({})\n", m.dpd_viscosity, m.dpd_diffusion,
                     m.dpd_transport_source);
  out += "one DPD unit in SI:\n";
  out += fmt::format("  length r_c          {:.6g} m\n", m.length);
  out += fmt::format("  mass m              {:.6g} kg\n", m.mass);
  out += fmt::format("  energy k_BT         {:.6g} J\n", m.energy);
  out += fmt::format("  time tau            {:.6g} s ({}; thermal r_c sqrt(m/k_BT) = {:.6g} s)\n", m.time,
                     m.time_source, m.thermal_time);
  for (const auto& [q, symbol] : quantities()) {
    if (q == "length" || q == "mass" || q == "energy" || q == "time") continue;
    out += fmt::format("  {:<19} {:.6g} {}\n", q, m.unit(q), symbol);
  }
  for (const std::string& n : m.notes) out += "note: " + n + "\n";
  return out;
}

}  // namespace mesodpd::units
