#include "engine/transported_scalars.hpp"

#include <cmath>
#include <numbers>
#include <string_view>

#include <fmt/format.h>

#include "analysis/kinetic_theory.hpp"
#include "engine/pair_laws.hpp"
#include "mesodpd/key_table.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

void check_scalar_field(const std::string& field, const SimulationSpec& spec, const std::string& key) {
  const std::string_view style = pair_law(spec.pair_style).style;
  const bool temp = field == "temp";
  const bool conc = field.size() == 5 && field.starts_with("conc") && field[4] >= '1' && field[4] <= '0' + kMaxScalars;
  if (!temp && !conc) keys::fail(key, "\"" + field + "\"", "expected \"temp\" (eDPD) or \"conc1\" .. \"conc4\" (tDPD)");
  const std::string_view need = temp ? "edpd" : "tdpd";
  if (style != need)
    keys::fail(key, "\"" + field + "\"", fmt::format("needs pair.style = \"{}\" (this run's is \"{}\")", need, style));
}

void require_held(const ParticleData& p, const std::string& field, const std::string& key, const std::string& value) {
  if (!p.enabled(field))
    throw SpecError(key, value, fmt::format("the run does not carry {} ([tdpd] solutes is smaller)", field));
}

double mobile_density(const SimulationSpec& spec) {
  double n = 0;
  for (const SpeciesSpec& sp : spec.species)
    if (!sp.frozen) n += static_cast<double>(sp.count);
  return n / (spec.box[0] * spec.box[1] * spec.box[2]);
}

double exchange_diffusivity(double n, double k, double rc, double s) {
  return 16.0 * std::numbers::pi * n * k * std::pow(rc, 5) * std::tgamma(s + 1.0) / std::tgamma(s + 6.0);
}

double field_exchange_diffusivity(const SimulationSpec& spec, const std::string& field) {
  const double n = mobile_density(spec);
  const PairSpec& p = spec.pair(0, 0);
  if (field == "temp") {
    const double rct = p.value("rct") > 0 ? p.value("rct") : p.rc;
    return exchange_diffusivity(n, spec.species.front().own.at("cv") * p.value("kappa"), rct, p.value("st"));
  }
  const std::string k = field.substr(4);  // conc<k>
  const double rcc = p.value("rcc") > 0 ? p.value("rcc") : p.rc;
  return exchange_diffusivity(n, p.value("kappa" + k), rcc, p.value("sc" + k));
}

KineticFluid kinetic_fluid(const SimulationSpec& spec) {
  const double n = mobile_density(spec);
  const PairSpec& p = spec.pair(0, 0);
  return {kinetic_viscosity(n, p.gamma, spec.kT, p.rd, p.s) / n, kinetic_diffusivity(n, p.gamma, spec.kT, p.rd, p.s)};
}

std::string scalar_numbers_line(const SimulationSpec& spec, const std::string& what, double d_kin,
                                const std::string& number) {
  const auto [nu, d_self] = kinetic_fluid(spec);
  // Both estimates are mean-field upper bounds: the conservative repulsion lowers D_self (0.30 measured
  // at a = 25, rho = 3, gamma = 4.5, kinetic theory 0.53), and the exchange of a disordered fluid
  // reaches 0.4-0.8 of d_kin (docs/validation.md 8 and 8b).
  return fmt::format(
      "  {}: mean-field exchange diffusivity {:.4g} (a run shows 0.4-0.8 of it), self-diffusion {:.4g} (kinetic "
      "theory, an upper bound: 0.30 measured at a = 25); {} nu / (D_self + D_exchange) = {:.3g} with nu = {:.4g} "
      "(seed 000 Eq. 16, which ignores the repulsion too), an estimate; calibrate with examples/diffusion (docs/validation.md 8b)\n",
      what, d_kin, d_self, number, nu / (d_self + d_kin), nu);
}

}  // namespace mesodpd
