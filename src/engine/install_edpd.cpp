// The installer of energy-conserving DPD (physics/edpd_pair.hpp, pair.style = "edpd"): the particles'
// internal temperatures, their integration and their thermo columns.
//
// The temperature follows the velocity's modified velocity-Verlet step (as LAMMPS's fix mvv/edpd): at
// the start of a step T_i += dt/2 dT_i/dt with the rate of the last force evaluation, then the forces and
// rates of the new positions are evaluated with these temperatures, and after the velocities' second
// half T_i += dt/2 dT_i/dt with the new rate. The rate lives in p.temp_rate (kForce, checkpointed like
// the forces), so a restart continues bit-identically.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/blow_up_error.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/config_error.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

__extension__ using Int128 = __int128;
constexpr double kEnergyScale = 1099511627776.0;  // 2^40: the fixed point of the internal-energy sum

// The per-species values the integration reads (from the law's [[species]] keys, validated).
struct EdpdSpecies {
  std::vector<double> cv;      // heat capacity per particle
  std::vector<double> start;   // starting temperature
  std::vector<double> source;  // constant heat source per particle over C_v: its dT/dt
  std::vector<std::uint8_t> frozen;
};

EdpdSpecies species_values(const SimulationSpec& spec) {
  EdpdSpecies s;
  for (const SpeciesSpec& sp : spec.species) {
    s.cv.push_back(sp.own.at("cv"));
    const double t = sp.own.at("temperature");
    s.start.push_back(t > 0 ? t : spec.kT);  // a frozen species keeps it (half_step skips frozen particles)
    s.frozen.push_back(sp.frozen ? 1 : 0);
    s.source.push_back(sp.own.at("heat_source") / sp.own.at("cv"));
  }
  return s;
}

// T_i += dt/2 dT_i/dt for the mobile local particles; then the particle with the smallest id whose
// temperature is no longer a positive number, over all ranks (the run cannot go on: 1/T_i), stops it.
void half_step(StepContext& ctx, const EdpdSpecies& s) {
  ParticleData& p = ctx.particles;
  const double h = 0.5 * ctx.dt;
  std::uint32_t bad = std::numeric_limits<std::uint32_t>::max();
  double bad_t = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const auto k = static_cast<std::size_t>(p.species[i]);
    if (s.frozen[k]) continue;
    p.temp[i] += h * (p.temp_rate[i] + s.source[k]);
    if (!(p.temp[i] > 0) || !std::isfinite(p.temp[i])) {
      if (p.id[i] < bad) {
        bad = p.id[i];
        bad_t = p.temp[i];
      }
    }
  }
  const std::uint64_t first = ctx.comm.distributed() ? ctx.comm.min(std::uint64_t{bad}) : bad;
  if (first != std::numeric_limits<std::uint32_t>::max()) {
    throw BlowUpError(ctx.step, static_cast<std::uint32_t>(first),
                      fmt::format("step {}: the internal temperature of particle {} is {} (eDPD needs T_i > 0; a time "
                                  "step too large for the heat flux, or kappa too large: docs/physics.md, \"eDPD\")",
                                  ctx.step, first, first == bad ? fmt::format("{}", bad_t) : std::string("not positive")));
  }
}

}  // namespace

std::string edpd_numbers(const SimulationSpec& spec) {
  if (pair_law(spec.pair_style).style != EdpdLaw::kStyle || spec.species.empty()) return "";
  const PairSpec& p = spec.pair(0, 0);
  const double rct = p.value("rct") > 0 ? p.value("rct") : p.rc;
  const double cv = spec.species.front().own.at("cv");
  // Linearised, dT_i/dt = -C_v kappa sum_j w_CT (T_i - T_j): the exchange coefficient is C_v kappa.
  return "eDPD (species " + spec.species.front().name + "):\n" +
         scalar_numbers_line(spec, fmt::format("heat (C_v kappa = {}, r_cT = {})", cv * p.value("kappa"), rct),
                             field_exchange_diffusivity(spec, "temp"), "Prandtl number");
}

void install_edpd(Installation& in) {
  const SimulationSpec& spec = in.spec;
  if (pair_law(spec.pair_style).style != EdpdLaw::kStyle) return;
  // Not yet with eDPD (each a clear refusal rather than wrong physics): bonded exclusions (they subtract
  // forces only, not heat) and the Euler integrator (the temperature step is the velocity-Verlet one).
  if (spec.bond_exclusion != BondExclusion::None)
    throw ConfigError("bonds.exclude: bonded exclusions are not yet supported with pair.style = \"edpd\" (they would "
                      "remove the pair's force but not its heat flux)",
                      "bonds.exclude");
  if (spec.integrator != IntegratorKind::GrootWarren)
    throw ConfigError("integrator.type: pair.style = \"edpd\" integrates the temperatures with the velocity-Verlet "
                      "step; use integrator.type = \"groot-warren\"",
                      "integrator.type");
  ParticleData& p = in.sim.particles();
  const auto s = std::make_shared<EdpdSpecies>(species_values(spec));
  if (in.restarted) {
    if (!p.enabled("temp") || !p.enabled("temp_rate"))
      throw ConfigError(fmt::format("pair.style: \"{}\" continues only from a checkpoint of an eDPD run (this one holds "
                                    "no particle temperatures)",
                                    pair_law(spec.pair_style).style),
                        "pair.style");
  } else if (p.enabled("temp")) {
    // Temperatures from a data file (atom style edpd; engine/initial_state.cpp checked them).
    p.enable("temp_rate");
  } else {
    p.enable("temp");
    p.enable("temp_rate");
    for (std::size_t i = 0; i < p.n_local; ++i) p.temp[i] = s->start[static_cast<std::size_t>(p.species[i])];
  }
  in.stages.add(StagePoint::AfterFirstHalf, make_stage([s](StepContext& ctx) { half_step(ctx, *s); }));
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([s](StepContext& ctx) { half_step(ctx, *s); }));
  // The mean internal temperature and the internal energy sum C_v,i T_i of the mobile particles, in
  // 128-bit fixed point (the same on any rank count and storage order).
  auto sums = std::make_shared<std::array<double, 2>>();
  in.thermo_columns.push_back({"temp_internal", [s, sums](const StepContext& ctx) {
                                 const ParticleData& q = ctx.particles;
                                 Int128 acc[3] = {0, 0, 0};
                                 for (std::size_t i = 0; i < q.n_local; ++i) {
                                   const auto k = static_cast<std::size_t>(q.species[i]);
                                   if (s->frozen[k]) continue;
                                   acc[0] += static_cast<Int128>(q.temp[i] * kEnergyScale);
                                   acc[1] += static_cast<Int128>(s->cv[k] * q.temp[i] * kEnergyScale);
                                   acc[2] += 1;
                                 }
                                 ctx.comm.sum(std::span<Int128>(acc, 3));
                                 const double n = static_cast<double>(acc[2]);
                                 (*sums)[0] = n > 0 ? static_cast<double>(acc[0]) / kEnergyScale / n : 0.0;
                                 (*sums)[1] = static_cast<double>(acc[1]) / kEnergyScale;
                                 return (*sums)[0];
                               }});
  in.thermo_columns.push_back({"energy_internal", [sums](const StepContext&) { return (*sums)[1]; }});
}

}  // namespace mesodpd
