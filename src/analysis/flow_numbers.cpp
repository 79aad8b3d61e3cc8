// Dimensionless numbers of a run from its spec (include/mesodpd/flow_numbers.hpp).
#include "mesodpd/flow_numbers.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "analysis/kinetic_theory.hpp"
#include "mesodpd/units.hpp"

namespace mesodpd {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Above this Mach number a flow is no longer nearly incompressible (density changes ~ Ma^2 / 2 > 4.5%).
constexpr double kMaxMach = 0.3;
// The thermostat's time-step bound, as a friction rate times dt. The standard fluid (gamma = 4.5,
// rho = 3, s = 2: friction rate 5.65) runs 2.3% warm at dt = 0.04 and 4.5% at dt = 0.06
// (docs/validation.md section 1), just inside the 5% at which a finished run warns; the temperature
// error grows with gamma dt, so we allow the product that dt = 0.06 gives there.
constexpr double kStandardFriction = 4.5 * 3.0 * 4.0 * std::numbers::pi * 2.0 / 60.0;
constexpr double kMaxFrictionDt = kStandardFriction * 0.06;
}  // namespace

FlowNumbers flow_numbers(const SimulationSpec& s) {
  FlowNumbers f;
  const double volume = s.box[0] * s.box[1] * s.box[2];
  double n = 0, mass = 0;
  for (const SpeciesSpec& sp : s.species) {
    n += static_cast<double>(sp.count);
    mass += static_cast<double>(sp.count) * sp.mass;
  }
  f.density = n / volume;
  const double rho_m = mass / volume;
  const double m_mean = n > 0 ? mass / n : 1.0;
  // Mean repulsion weighted by pair fractions x_i x_j.
  double a_mean = 0;
  double gamma_mean = 0, rd_mean = 0, s_mean = 0;
  const int ns = static_cast<int>(s.species.size());
  for (int i = 0; i < ns; ++i)
    for (int j = 0; j < ns; ++j) {
      const double w = n > 0 ? static_cast<double>(s.species[static_cast<std::size_t>(i)].count) *
                                   static_cast<double>(s.species[static_cast<std::size_t>(j)].count) / (n * n)
                             : 0.0;
      const PairSpec& p = s.pair(i, j);
      a_mean += w * p.a;
      gamma_mean += w * p.gamma;
      rd_mean += w * p.rd;
      s_mean += w * p.s;
    }
  f.viscosity = f.diffusion = f.schmidt = f.flow_speed = f.length = f.reynolds = f.mach = kNaN;
  f.sound_speed = f.alpha = f.friction_rate = f.thermostat_dt_limit = kNaN;
  if (s.pair_style != PairStyle::Dpd || n == 0) {
    f.viscosity_source = "only for pair.style = \"dpd\"";
    return f;
  }

  // Speed of sound: c^2 = dp/d rho_m with p = rho kT + alpha(rho) a rho^2 (seed 002 Eq. 11, alpha measured).
  double alpha_slope = 0;
  if (f.density >= 3) {
    f.alpha = units::measured_alpha(f.density);
    alpha_slope = units::measured_alpha_slope(f.density);
  } else {
    f.alpha = units::measured_alpha(3.0);
    f.warnings.push_back(fmt::format("density {:.3g} is below 3, where alpha(rho) was measured: the speed of sound "
                                     "uses alpha(3) = {:.4f}",
                                     f.density, f.alpha));
  }
  const double dp_drho = s.kT + 2 * f.alpha * a_mean * f.density + alpha_slope * a_mean * f.density * f.density;
  f.sound_speed = std::sqrt(dp_drho / m_mean);

  // Transport from kinetic theory (one fluid: the shared gamma, r_d, s and unit masses).
  const KineticViscosity kv = kinetic_viscosity_of(s, f.density);
  if (kv.applies) {
    f.viscosity = kv.eta;
    f.diffusion = kinetic_diffusivity(f.density, kv.gamma, s.kT, kv.rd, kv.s);
    f.schmidt = f.viscosity / (rho_m * f.diffusion);
    f.viscosity_source = "kinetic theory, seed 000 Eq. 16 / Table 1 (at a = 25 the measured value is 10% lower)";
  } else {
    f.viscosity_source = std::string("no kinetic-theory value for ") + kv.why_not;
  }

  // Driven flow: reverse Poiseuille, v(z) = c z (L/2 - z) in each half with c = rho_m g / (2 eta), so the
  // peak is rho_m g L^2 / (32 eta) at z = L/4; the length is the layer width L/2.
  if (s.poiseuille.enabled && kv.applies) {
    const double L = s.box[static_cast<std::size_t>(s.poiseuille.gradient_axis)];
    f.flow_speed = rho_m * std::abs(s.poiseuille.force) * L * L / (32 * f.viscosity);
    f.length = L / 2;
    f.reynolds = rho_m * f.flow_speed * f.length / f.viscosity;
    f.mach = f.flow_speed / f.sound_speed;
    if (f.mach > kMaxMach)
      f.warnings.push_back(fmt::format("Mach number {:.3g} > {}: the flow is compressible; lower poiseuille.force",
                                       f.mach, kMaxMach));
  }

  // Thermostat: friction rate gamma rho Int w_D d^3r / m, Int w_D = 4 pi r_d^3 2 / ((s+1)(s+2)(s+3)).
  // A pair law without friction (a [thermostat] sweep supplies it, or a Hamiltonian run) has no bound
  // here: n/a rather than a limit of infinity.
  if (gamma_mean == 0.0) return f;
  const double w_integral =
      4 * std::numbers::pi * rd_mean * rd_mean * rd_mean * 2 / ((s_mean + 1) * (s_mean + 2) * (s_mean + 3));
  f.friction_rate = gamma_mean * f.density * w_integral / m_mean;
  f.thermostat_dt_limit = kMaxFrictionDt / f.friction_rate;
  if (s.dt > f.thermostat_dt_limit)
    f.warnings.push_back(fmt::format(
        "integrator.dt = {} is too large for the thermostat: friction rate {:.3g} x dt = {:.3g} > {:.3g} (the standard "
        "fluid at dt = 0.06, 4.5% too warm); use dt <= {:.3g}",
        s.dt, f.friction_rate, f.friction_rate * s.dt, kMaxFrictionDt, f.thermostat_dt_limit));
  return f;
}

std::string format_flow_numbers(const FlowNumbers& f) {
  std::string out;
  auto num = [](double v) { return std::isnan(v) ? std::string("n/a") : fmt::format("{:.4g}", v); };
  out += fmt::format("  density {} per r_c^3, speed of sound {} (alpha = {}, measured EOS)\n", num(f.density),
                     num(f.sound_speed), num(f.alpha));
  out += fmt::format("  viscosity {}, self-diffusion {}, Schmidt number {} ({})\n", num(f.viscosity),
                     num(f.diffusion), num(f.schmidt), f.viscosity_source);
  if (!std::isnan(f.flow_speed))
    out += fmt::format("  driven flow: peak speed {}, length {}, Reynolds {}, Mach {}\n", num(f.flow_speed),
                       num(f.length), num(f.reynolds), num(f.mach));
  else if (std::isnan(f.viscosity))
    out += "  no Reynolds or Mach number here (no viscosity estimate; a model's own numbers follow)\n";
  else
    out += "  no driven flow (Reynolds and Mach numbers need [poiseuille])\n";
  out += fmt::format("  thermostat: friction rate {}, time step limit {}\n", num(f.friction_rate),
                     num(f.thermostat_dt_limit));
  for (const std::string& w : f.warnings) out += "warning: " + w + "\n";
  return out;
}

}  // namespace mesodpd
