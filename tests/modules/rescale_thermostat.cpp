// A test-only thermostat, written as the recipe of docs/architecture.md says a new thermostat is: this
// one file (its keys, its section, its stage and its installer), one list entry (here the
// register_model() call of the test) and its test (test_model_recipes.cpp).
//
// [test_rescale]: Berendsen's weak-coupling rescale. After each step's velocities are complete, every
// mobile velocity is scaled by lambda = sqrt(1 + (dt / tau) (kT_target / T - 1)), so the kinetic
// temperature T relaxes to kT_target with time constant tau (Berendsen et al., J. Chem. Phys. 81, 3684
// (1984)). It is not a DPD thermostat (it does not conserve momentum pair by pair); its only purpose is
// to prove the seam.
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>

#include "engine/installer.hpp"
#include "mesodpd/model_section.hpp"
#include "parallel/comm.hpp"

namespace mesodpd::test_models {

struct RescaleSpec {
  double kT = 1.0;
  double tau = 1.0;
};

const keys::KeyTable<RescaleSpec>& rescale_keys() {
  static const keys::KeyTable<RescaleSpec> table = [] {
    keys::KeyTable<RescaleSpec> t("test_rescale");
    t.number("kT", &RescaleSpec::kT, keys::kPositive, "Target temperature of the rescale.");
    t.number("tau", &RescaleSpec::tau, keys::kPositive, "Coupling time; at least integrator.dt.");
    return t;
  }();
  return table;
}

namespace {

void check_rescale(const RescaleSpec& r, const SimulationSpec& spec) {
  if (r.tau < spec.dt)
    throw SpecError("test_rescale.tau", std::to_string(r.tau), "must be at least integrator.dt");
}

void install_rescale(Installation& in) {
  const RescaleSpec* r = in.spec.model<RescaleSpec>("test_rescale");
  if (!r) return;
  const RescaleSpec cfg = *r;
  in.stages.add(StagePoint::AfterSecondHalf, make_stage([cfg](StepContext& ctx) {
    ParticleData& p = ctx.particles;
    // Sum of m v^2 in 2^32 fixed point and the particle count: integer sums, the same on any rank count.
    std::int64_t sums[2] = {0, static_cast<std::int64_t>(p.n_local)};
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
      sums[0] += std::llround(m * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]) * 4294967296.0);
    }
    ctx.comm.sum(std::span<std::int64_t>(sums, 2));
    const double t = static_cast<double>(sums[0]) / 4294967296.0 / (3.0 * static_cast<double>(sums[1]) - 3.0);
    const double lambda = std::sqrt(1.0 + ctx.dt / cfg.tau * (cfg.kT / t - 1.0));
    for (std::size_t i = 0; i < p.n_local; ++i) {
      p.vx[i] *= lambda;
      p.vy[i] *= lambda;
      p.vz[i] *= lambda;
    }
  }));
}

}  // namespace

Model rescale_model() {
  return {"test_rescale", install_rescale, [] { return model_section(rescale_keys(), check_rescale); }};
}

}  // namespace mesodpd::test_models
