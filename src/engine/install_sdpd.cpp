// The smoothed-DPD model (physics/sdpd_pair.hpp, pair.style = "sdpd"): its law is in the engine's list of
// pair laws and its density pass comes from the law's declarations, so the installer only refuses what
// the law does not support yet; `mesodpd check` prints its stability limits and dimensionless numbers.
#include <cmath>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/config_error.hpp"

namespace mesodpd {

namespace {
bool is_sdpd(const SimulationSpec& spec) { return pair_law(spec.pair_style).style == SdpdLaw::kStyle; }
}  // namespace

// For the first species pair: the kernel, its neighbour count, the time-step limits against the run's
// dt, and the Reynolds, Mach and Schmidt numbers the inputs give (the Schmidt number with the
// Stokes-Einstein diffusivity kT / (6 pi eta R) of a sphere of the particle's volume, R = (3 / (4 pi
// n))^(1/3): an estimate; [analysis.msd] measures D).
std::string sdpd_numbers(const SimulationSpec& spec) {
  if (!is_sdpd(spec) || spec.species.empty()) return "";
  const PairValues v = pair_values(spec.pair(0, 0), spec);
  const double eta = v.own[0], c = v.own[2], rho0 = v.own[3];
  const double n = mobile_density(spec);
  const double nu = eta / rho0;
  const double radius = std::cbrt(3.0 / (4.0 * std::numbers::pi * n));
  const double diffusion = spec.kT / (6.0 * std::numbers::pi * eta * radius);
  const char* kernel = v.kernel == DensityKernelKind::Wendland ? "Wendland C2" : "Lucy";
  std::string out = fmt::format("smoothed DPD (species pair {0}-{0}):\n", spec.species.front().name);
  out += fmt::format("  kernel {} over rc = {}, {:.1f} neighbours (n 4 pi rc^3 / 3), spacing n^(-1/3) = {:.4g}\n", kernel,
                     v.rc, SdpdLaw::neighbours(v), std::cbrt(1.0 / n));
  out += fmt::format("  dt = {} against the sound limit 0.25 rc / c = {:.4g} and the viscous limit 0.05 rc^2 / nu = {:.4g}\n",
                     spec.dt, SdpdLaw::cfl_limit(v), SdpdLaw::viscous_limit(v));
  out += fmt::format("  kinematic viscosity nu = {:.4g}, sound speed c = {}, thermal speed sqrt(kT/m) = {:.4g}\n", nu, c,
                     std::sqrt(spec.kT / spec.species.front().mass));
  out += fmt::format("  Schmidt number ~ {:.3g} (nu / D with the Stokes-Einstein D = {:.4g} of radius {:.4g})\n",
                     nu / diffusion, diffusion, radius);
  if (spec.poiseuille.enabled) {
    // Reverse Poiseuille: peak speed rho g L^2 / (32 eta) over the layer width L/2 (flow_numbers()).
    const double l = spec.box[static_cast<std::size_t>(spec.poiseuille.gradient_axis)];
    const double u = rho0 * std::abs(spec.poiseuille.force) * l * l / (32.0 * eta);
    out += fmt::format("  driven flow: peak speed {:.4g}, Reynolds {:.4g}, Mach {:.3g}\n", u, u * l / 2.0 / nu, u / c);
  }
  return out;
}

void install_sdpd(Installation& in) {
  const SimulationSpec& spec = in.spec;
  if (!is_sdpd(spec)) return;
  if (spec.bond_exclusion != BondExclusion::None)
    throw ConfigError("bonds.exclude: bonded exclusions are not yet supported with pair.style = \"sdpd\" (the density "
                      "pass would still count the excluded neighbours); use bonds.exclude = \"none\"",
                      "bonds.exclude");
}

}  // namespace mesodpd
