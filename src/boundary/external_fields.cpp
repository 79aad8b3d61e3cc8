// External force fields: per-species body force and the reverse-Poiseuille field, added to the pair
// forces one particle at a time (so the result does not depend on thread or rank count).
#include "boundary/external_fields.hpp"

#include <algorithm>
#include <memory>

namespace mesodpd {

void SpeciesBodyForce::run(StepContext& ctx) {
  ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const auto& bf = force_[static_cast<std::size_t>(p.species[i])];
    p.fx[i] += bf[0];
    p.fy[i] += bf[1];
    p.fz[i] += bf[2];
  }
}

void ReversePoiseuilleField::run(StepContext& ctx) {
  ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local;
  const Box& box = ctx.box;
  const int ga = gradient_axis_, fa = flow_axis_;
  const double half = 0.5 * (ga == 0 ? box.len.x : ga == 1 ? box.len.y : box.len.z);
  const auto& coord = ga == 0 ? p.x : ga == 1 ? p.y : p.z;
  auto& f = fa == 0 ? p.fx : fa == 1 ? p.fy : p.fz;
  const auto& mass = ctx.species_mass;
  const double g = g_;
  // The force is the mass times the acceleration g (seed 002), so every species feels the same g.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) f[i] += mass[static_cast<std::size_t>(p.species[i])] * (coord[i] < half ? g : -g);
}

void add_external_fields(const SimulationSpec& spec, StageList& stages) {
  const auto& sp = spec.species;
  const bool any_body = std::any_of(sp.begin(), sp.end(), [](const SpeciesSpec& s) {
    return s.body_force[0] != 0 || s.body_force[1] != 0 || s.body_force[2] != 0;
  });
  if (any_body) {
    std::vector<std::array<double, 3>> force;
    for (const auto& s : sp) force.push_back(s.body_force);
    stages.add(StagePoint::Forces, std::make_unique<SpeciesBodyForce>(std::move(force)));
  }
  if (spec.poiseuille.enabled)
    stages.add(StagePoint::Forces, std::make_unique<ReversePoiseuilleField>(
                                       spec.poiseuille.force, spec.poiseuille.flow_axis, spec.poiseuille.gradient_axis));
}

}  // namespace mesodpd
