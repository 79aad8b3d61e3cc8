// Time integrators, split at the force evaluation: pre_force() advances positions and predicts the
// velocity the forces will see; post_force() completes the velocity update. Schemes that act pair by
// pair after the conservative step (Lowe-Andersen, Shardlow, Peters) are a model with a stage after
// post_force instead ([thermostat], integrate/pair_thermostat.hpp); eDPD integrates its temperatures in
// stages around the force stage (engine/install_edpd.cpp). Simulation::step() names none of them.
#pragma once
#include <variant>
#include <vector>

#include "core/particle_data.hpp"

namespace mesodpd {

// Groot-Warren modified velocity-Verlet (seed 000 Eq. 10, seed 002 Eqs. 26-29):
//   r(t+dt) = r + dt v + dt^2/2 f/m;  v~ = v + lambda dt f/m;  f(t+dt) = f(r(t+dt), v~);
//   v(t+dt) = v + dt/2 (f(t) + f(t+dt))/m.   lambda = 1/2 is plain velocity-Verlet.
struct GrootWarrenIntegrator {
  double lambda = 0.5;

  void pre_force(ParticleData& p, const std::vector<double>& inv_mass, double dt) const;
  void post_force(ParticleData& p, const std::vector<double>& inv_mass, double dt) const;
};

// Euler scheme (seed 000 Eq. 9, seed 002 Eqs. 18-20), kept for comparison.
struct EulerIntegrator {
  void pre_force(ParticleData& p, const std::vector<double>& inv_mass, double dt) const;
  void post_force(ParticleData&, const std::vector<double>&, double) const {}
};

using IntegratorVariant = std::variant<GrootWarrenIntegrator, EulerIntegrator>;

}  // namespace mesodpd
