// [buoyancy]: the Boussinesq body force that couples a transported scalar to the flow, for natural
// convection. Each mobile particle feels F_i = -m_i beta (X_i - X_0) g, with X the internal temperature
// (eDPD) or a solute concentration (tDPD): where the fluid is hotter than X_0 and beta > 0 it rises
// against g. A Forces stage, added to the pair forces one particle at a time, so the result does not
// depend on thread or rank count.
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/installer.hpp"
#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"

namespace mesodpd {

struct BuoyancySpec {
  std::string field = "temp";
  double beta = 0;       // expansion coefficient: rho(X) = rho_0 (1 - beta (X - X_0))
  double reference = 0;  // X_0
  std::array<double, 3> gravity{0, 0, 0};
};

namespace {

const keys::KeyTable<BuoyancySpec>& buoyancy_keys() {
  using T = BuoyancySpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("buoyancy");
    t.string("field", &T::field,
             "The scalar that makes the fluid lighter or heavier: `temp` (pair.style = \"edpd\") or `conc1` .. "
             "`conc4` (pair.style = \"tdpd\", a solute the run carries).")
        .default_text("\"temp\"");
    t.number("beta", &T::beta, keys::kFinite,
             "Expansion coefficient beta of rho(X) = rho_0 (1 - beta (X - X_0)); the force on a mobile particle is "
             "F = -m beta (X - X_0) g.")
        .required("(the thermal or solutal expansion coefficient)");
    t.number("reference", &T::reference, keys::kFinite, "The reference value X_0 (a temperature or a concentration).")
        .required("(X_0, where the fluid has its reference density)");
    t.vec3("gravity", &T::gravity, keys::kFinite, "The acceleration g (a vector; [0, 0, -g] points down along z).")
        .required("(a vector, e.g. [0, 0, -0.01])");
    return t;
  }();
  return table;
}

void check_buoyancy(const BuoyancySpec& b, const SimulationSpec& spec) { check_scalar_field(b.field, spec, "buoyancy.field"); }

class BuoyancyForce final : public Stage {
 public:
  BuoyancyForce(std::string field, double beta, double reference, std::array<double, 3> g)
      : field_(std::move(field)), beta_(beta), reference_(reference), g_(g) {}
  void run(StepContext& ctx) override {
    ParticleData& p = ctx.particles;
    const double* x = p.doubles(field_)->data();
    const std::vector<double>& mass = ctx.species_mass;
    const std::size_t n = p.n_local;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (p.body[i] != 0) continue;
      const double s = -mass[static_cast<std::size_t>(p.species[i])] * beta_ * (x[i] - reference_);
      p.fx[i] += s * g_[0];
      p.fy[i] += s * g_[1];
      p.fz[i] += s * g_[2];
    }
  }

 private:
  std::string field_;
  double beta_, reference_;
  std::array<double, 3> g_;
};

}  // namespace

ModelSection buoyancy_section() { return model_section(buoyancy_keys(), check_buoyancy); }

void install_buoyancy(Installation& in) {
  const BuoyancySpec* b = in.spec.model<BuoyancySpec>("buoyancy");
  if (!b) return;
  check_buoyancy(*b, in.spec);
  require_held(in.sim.particles(), b->field, "buoyancy.field", "\"" + b->field + "\"");
  in.stages.add(StagePoint::Forces, std::make_unique<BuoyancyForce>(b->field, b->beta, b->reference, b->gravity));
}

}  // namespace mesodpd
