// The single-particle DPD model (physics/spdpd_pair.hpp, pair.style = "spdpd"): the particles' angular
// velocities, their integration and their thermo columns. The law returns the angular accelerations
// T_i / I as the rates of its three scalars, so the pair loop, the ghosts and the halo sums carry them
// as they carry eDPD's temperature.
//
// The spin follows the velocity's step with lambda = 1/2 (as the temperature does in install_edpd.cpp):
// Omega_i += dt/2 dOmega_i/dt with the rate of the last force evaluation at the start of a step, then the
// forces and rates of the new positions are evaluated with these spins, and after the velocities' second
// half Omega_i += dt/2 dOmega_i/dt with the new rate. The rate lives in p.omega_rate_* (kForce,
// checkpointed like the forces), so a restart continues bit-identically.
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "core/philox.hpp"
#include "analysis/kinetic_theory.hpp"
#include "engine/blow_up_error.hpp"
#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config_error.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

__extension__ using Int128 = __int128;
constexpr double kSumScale = 1099511627776.0;  // 2^40: the fixed point of the thermo sums

bool is_spdpd(const SimulationSpec& spec) { return pair_law(spec.pair_style).style == SpdpdLaw::kStyle; }

// Per species: the moment of inertia (0 for a frozen species, which never turns).
std::vector<double> species_inertia(const SimulationSpec& spec) {
  std::vector<double> inertia;
  for (const SpeciesSpec& sp : spec.species) {
    std::array<double, PairValues::kMaxSpeciesOwn> own{};
    own[0] = sp.own.at("radius");
    own[1] = sp.own.at("inertia");
    inertia.push_back(sp.frozen ? 0.0 : SpdpdLaw::inertia(sp.mass, own));
  }
  return inertia;
}

struct Spin {
  double* w[3];
  double* rate[3];
};
Spin spin(ParticleData& p) {
  Spin s{};
  for (int a = 0; a < 3; ++a) {
    s.w[a] = p.doubles(SpdpdLaw::kScalarFields[static_cast<std::size_t>(a)])->data();
    s.rate[a] = p.doubles(SpdpdLaw::kScalarRates[static_cast<std::size_t>(a)])->data();
  }
  return s;
}

// Omega_i += dt/2 dOmega_i/dt for the mobile local particles; a spin that is no longer finite stops the
// run, naming the particle with the smallest id over all ranks.
void half_step(StepContext& ctx, const std::vector<double>& inertia) {
  ParticleData& p = ctx.particles;
  const Spin s = spin(p);
  const double h = 0.5 * ctx.dt;
  std::uint32_t bad = std::numeric_limits<std::uint32_t>::max();
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (inertia[static_cast<std::size_t>(p.species[i])] == 0 || p.body[i] != 0) continue;
    bool finite = true;
    for (int a = 0; a < 3; ++a) {
      s.w[a][i] += h * s.rate[a][i];
      finite = finite && std::isfinite(s.w[a][i]);
    }
    if (!finite && p.id[i] < bad) bad = p.id[i];
  }
  const std::uint64_t first = ctx.comm.distributed() ? ctx.comm.min(std::uint64_t{bad}) : bad;
  if (first != std::numeric_limits<std::uint32_t>::max())
    throw BlowUpError(ctx.step, static_cast<std::uint32_t>(first),
                      fmt::format("step {}: the angular velocity of particle {} is not finite (single-particle DPD: a "
                                  "time step too large for its moment of inertia; docs/physics.md, \"Single-particle "
                                  "DPD\")",
                                  ctx.step, first));
}

// Maxwell-Boltzmann spins at kT: each component N(0, kT / I), a pure function of the seed and the id
// (draws 2 and 3 of the initial-velocity stream, whose draws 0 and 1 are the velocity's).
void maxwell_spins(const SimulationSpec& spec, const std::vector<double>& inertia, ParticleData& p) {
  const Spin s = spin(p);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const double in = inertia[static_cast<std::size_t>(p.species[i])];
    if (in == 0 || p.body[i] != 0) continue;
    const auto bits = [&](std::uint32_t draw) {
      const Philox4x32 ctr{{p.id[i], draw, 0u, static_cast<std::uint32_t>(RngStream::InitVelocity) << 24}};
      return philox4x32_10(ctr, static_cast<std::uint32_t>(spec.seed), static_cast<std::uint32_t>(spec.seed >> 32));
    };
    const Philox4x32 b = bits(2), d = bits(3);
    const double sd = std::sqrt(spec.kT / in);
    s.w[0][i] = sd * gaussian_unit(b.v[0], b.v[1]);
    s.w[1][i] = sd * gaussian_unit(b.v[2], b.v[3]);
    s.w[2][i] = sd * gaussian_unit(d.v[0], d.v[1]);
  }
}

}  // namespace

// `mesodpd check`: per species its radius, moment of inertia and spin relaxation rate, per species pair
// lambda_ij. The rate: a particle spinning at Omega among particles at rest feels from a neighbour j at
// distance r the friction -gamma_perp w_perp(r) r x (lambda_ij Omega) across e and so the torque
// lambda_ij^2 gamma_perp w_perp (r (r.Omega) - r^2 Omega), -(2/3) lambda_ij^2 gamma_perp w_perp r^2 Omega
// on average over directions. Neighbours at the uniform density n_j give
//   k_i = sum_j (8 pi / 3) lambda_ij^2 gamma_perp n_j r_d^5 Int_0^1 x^4 (1 - x)^s_perp dx / I_i
// (weight_moment4; g(r) = 1, as the kinetic theory of the viscosity): the rate at which the spins forget,
// printed with k_i dt.
std::string spdpd_numbers(const SimulationSpec& spec) {
  if (!is_spdpd(spec) || spec.species.empty()) return "";
  const double volume = spec.box[0] * spec.box[1] * spec.box[2];
  const std::vector<double> inertia = species_inertia(spec);
  std::string out = "single-particle DPD:\n";
  const std::size_t n = spec.species.size();
  for (std::size_t i = 0; i < n; ++i) {
    const SpeciesSpec& si = spec.species[i];
    const double ri = si.own.at("radius");
    if (si.frozen) {
      out += fmt::format("  {}: radius {:.4g}, frozen (never turns)\n", si.name, ri);
      continue;
    }
    double rate = 0;
    std::string lambdas;
    for (std::size_t j = 0; j < n; ++j) {
      const SpeciesSpec& sj = spec.species[j];
      const double lambda = ri / (ri + sj.own.at("radius"));
      const PairSpec& pair = spec.pair(static_cast<int>(i), static_cast<int>(j));
      const double gperp = pair.value("gamma_perp");
      const double sp = pair.value("s_perp") > 0 ? pair.value("s_perp") : pair.s;
      rate += 8.0 * std::numbers::pi / 3.0 * lambda * lambda * gperp * static_cast<double>(sj.count) / volume *
              std::pow(pair.rd, 5) * weight_moment4(sp);
      lambdas += fmt::format("{}{} {:.4g}", lambdas.empty() ? "" : ", ", sj.name, lambda);
    }
    rate /= inertia[i];
    out += fmt::format("  {}: radius {:.4g}, inertia {:.4g}, spin relaxation rate {:.4g} (x dt = {:.3g}); lambda with {}\n",
                       si.name, ri, inertia[i], rate, rate * spec.dt, lambdas);
  }
  return out;
}

void install_spdpd(Installation& in) {
  const SimulationSpec& spec = in.spec;
  if (!is_spdpd(spec)) return;
  const std::string style(SpdpdLaw::kStyle);
  // Not yet with single-particle DPD (each a clear refusal rather than wrong physics).
  if (spec.bond_exclusion != BondExclusion::None)
    throw ConfigError("bonds.exclude: bonded exclusions are not yet supported with pair.style = \"" + style +
                          "\" (they would remove the pair's force but not its torques)",
                      "bonds.exclude");
  if (spec.integrator != IntegratorKind::GrootWarren)
    throw ConfigError("integrator.type: pair.style = \"" + style +
                          "\" integrates the spins with the velocity-Verlet step; use integrator.type = \"groot-warren\"",
                      "integrator.type");
  if (spec.models.count("thermostat") != 0)
    throw ConfigError("[thermostat]: not supported with pair.style = \"" + style +
                          "\" (a sweep over the velocities would leave the spins' friction out of its balance; the "
                          "law's own gamma and gamma_perp thermostat both)",
                      "thermostat");
  ParticleData& p = in.sim.particles();
  const auto inertia = std::make_shared<std::vector<double>>(species_inertia(spec));
  const bool held = [&] {
    for (int a = 0; a < 3; ++a)
      if (!p.enabled(SpdpdLaw::kScalarFields[static_cast<std::size_t>(a)]) ||
          !p.enabled(SpdpdLaw::kScalarRates[static_cast<std::size_t>(a)]))
        return false;
    return true;
  }();
  if (in.restarted) {
    if (!held)
      throw ConfigError("pair.style: \"" + style +
                            "\" continues only from a checkpoint of a single-particle DPD run (this one holds no "
                            "angular velocities)",
                        "pair.style");
  } else {
    for (int a = 0; a < 3; ++a) {
      p.enable(SpdpdLaw::kScalarFields[static_cast<std::size_t>(a)]);
      p.enable(SpdpdLaw::kScalarRates[static_cast<std::size_t>(a)]);
    }
    if (spec.velocities == VelocityInit::Maxwell) maxwell_spins(spec, *inertia, p);
  }
  in.stages.add(StagePoint::AfterFirstHalf, make_stage([inertia](StepContext& ctx) { half_step(ctx, *inertia); }));
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([inertia](StepContext& ctx) { half_step(ctx, *inertia); }));
  // The rotational temperature sum I Omega^2 / (3 N) of the mobile particles and the total angular
  // momentum about the origin, sum m r x v + I Omega with unwrapped positions (conserved in a box without
  // periodic axes; a periodic image carries momentum across the boundary), in 128-bit fixed point (the
  // same on any rank count and storage order).
  auto sums = std::make_shared<std::array<double, 4>>();
  in.thermo_columns.push_back(
      {"temp_rotational", [inertia, sums](const StepContext& ctx) {
         ParticleData& q = ctx.particles;
         const Spin s = spin(q);
         const double lx = ctx.box.length(0), ly = ctx.box.length(1), lz = ctx.box.length(2);
         Int128 acc[5] = {0, 0, 0, 0, 0};
         for (std::size_t i = 0; i < q.n_local; ++i) {
           const auto k = static_cast<std::size_t>(q.species[i]);
           const double in = (*inertia)[k];
           if (in == 0 || q.body[i] != 0) continue;
           const double m = ctx.species_mass[k];
           const double x = q.x[i] + q.ix[i] * lx, y = q.y[i] + q.iy[i] * ly, z = q.z[i] + q.iz[i] * lz;
           const double w2 = s.w[0][i] * s.w[0][i] + s.w[1][i] * s.w[1][i] + s.w[2][i] * s.w[2][i];
           acc[0] += static_cast<Int128>(in * w2 * kSumScale);
           acc[1] += static_cast<Int128>((m * (y * q.vz[i] - z * q.vy[i]) + in * s.w[0][i]) * kSumScale);
           acc[2] += static_cast<Int128>((m * (z * q.vx[i] - x * q.vz[i]) + in * s.w[1][i]) * kSumScale);
           acc[3] += static_cast<Int128>((m * (x * q.vy[i] - y * q.vx[i]) + in * s.w[2][i]) * kSumScale);
           acc[4] += 1;
         }
         ctx.comm.sum(std::span<Int128>(acc, 5));
         const double n = static_cast<double>(acc[4]);
         (*sums)[0] = n > 0 ? static_cast<double>(acc[0]) / kSumScale / (3.0 * n) : 0.0;
         for (int a = 0; a < 3; ++a) (*sums)[static_cast<std::size_t>(a + 1)] = static_cast<double>(acc[a + 1]) / kSumScale;
         return (*sums)[0];
       }});
  for (int a = 0; a < 3; ++a)
    in.thermo_columns.push_back({std::string("angular_momentum_") + "xyz"[a],
                                 [sums, a](const StepContext&) { return (*sums)[static_cast<std::size_t>(a + 1)]; }});
}

}  // namespace mesodpd
