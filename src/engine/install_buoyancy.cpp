// [buoyancy]: the Boussinesq body force that couples a transported scalar to the flow, for natural
// convection. Each mobile particle feels F_i = -m_i beta (X_i - X_0) g, with X the internal temperature
// (eDPD) or a solute concentration (tDPD): where the fluid is hotter than X_0 and beta > 0 it rises
// against g. A Forces stage, added to the pair forces one particle at a time, so the result does not
// depend on thread or rank count.
#include <array>
#include <algorithm>
#include <cmath>
#include <limits>
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

// The Rayleigh number g beta dX L^3 / (nu D) for `mesodpd check`: dX the spread of the values the walls
// hold (thermal walls: a frozen species with `temperature`; solute walls: `solute_wall = 1`), L the
// distance between the two plane [[solid]] surfaces normal to g (else the box length along g's largest
// component), nu and D the kinetic-theory estimates (seed 000 Eq. 16; D = D_self + the mean-field
// exchange), so an estimate: a run measures D ([analysis.flux]) and nu ([poiseuille]).
std::string buoyancy_numbers(const SimulationSpec& spec) {
  const BuoyancySpec* b = spec.model<BuoyancySpec>("buoyancy");
  if (!b || spec.species.empty()) return "";
  const bool heat = b->field == "temp";
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const SpeciesSpec& sp : spec.species) {
    if (!sp.frozen) continue;
    if (heat && sp.own.count("temperature") && sp.own.at("temperature") > 0) {
      lo = std::min(lo, sp.own.at("temperature"));
      hi = std::max(hi, sp.own.at("temperature"));
    }
    if (!heat && sp.own.count("solute_wall") && sp.own.at("solute_wall") > 0.5 && sp.own.count(b->field)) {
      lo = std::min(lo, sp.own.at(b->field));
      hi = std::max(hi, sp.own.at(b->field));
    }
  }
  const double g = std::sqrt(b->gravity[0] * b->gravity[0] + b->gravity[1] * b->gravity[1] + b->gravity[2] * b->gravity[2]);
  if (!(hi > lo) || !(g > 0))
    return "buoyancy: no Rayleigh number (it needs walls held at two values of " + b->field + " and a gravity)\n";
  const std::array<double, 3> e{b->gravity[0] / g, b->gravity[1] / g, b->gravity[2] / g};
  std::vector<double> planes;
  for (const SolidSpec& s : spec.solids) {
    if (s.shape.kind != ShapeKind::Plane) continue;
    const auto& n = s.shape.normal;
    const double dot = n[0] * e[0] + n[1] * e[1] + n[2] * e[2];
    if (std::abs(std::abs(dot) - 1.0) < 1e-9) planes.push_back(s.shape.point[0] * e[0] + s.shape.point[1] * e[1] + s.shape.point[2] * e[2]);
  }
  int axis = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(e[static_cast<std::size_t>(d)]) > std::abs(e[static_cast<std::size_t>(axis)])) axis = d;
  const double depth = planes.size() >= 2 ? *std::max_element(planes.begin(), planes.end()) -
                                                *std::min_element(planes.begin(), planes.end())
                                          : spec.box[static_cast<std::size_t>(axis)];
  const auto [nu, d_self] = kinetic_fluid(spec);
  const double d_exchange = field_exchange_diffusivity(spec, b->field);
  const double ra = g * std::abs(b->beta) * (hi - lo) * depth * depth * depth / (nu * (d_self + d_exchange));
  return fmt::format(
      "buoyancy: Rayleigh number g beta dX L^3 / (nu D) = {:.4g} (dX = {:.4g} between the walls, L = {:.4g}{}; nu = "
      "{:.4g} and D = {:.4g} by kinetic theory, an estimate: at a = 25 both come out higher than measured, so a run's "
      "Ra is larger (examples/convection measures D with [analysis.flux] and nu with [poiseuille]); a layer "
      "heated from below between rigid walls turns to convection at Ra = 1708\n",
      ra, hi - lo, depth, planes.size() >= 2 ? " between the plane walls" : " (the box along g)", nu, d_self + d_exchange);
}

void install_buoyancy(Installation& in) {
  const BuoyancySpec* b = in.spec.model<BuoyancySpec>("buoyancy");
  if (!b) return;
  check_buoyancy(*b, in.spec);
  require_held(in.sim.particles(), b->field, "buoyancy.field", "\"" + b->field + "\"");
  in.stages.add(StagePoint::Forces, std::make_unique<BuoyancyForce>(b->field, b->beta, b->reference, b->gravity));
}

}  // namespace mesodpd
