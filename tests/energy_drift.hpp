// The largest deviation of the total energy (kinetic + pair potential) from its start over `time` time
// units at time step dt, relative to the start: for a conservative law integrated by velocity Verlet
// (Groot-Warren at lambda = 1/2) it is O(dt^2) without drift, so halving dt divides it by about four.
#pragma once
#include <algorithm>
#include <cmath>

#include "engine/simulation.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd::test {

inline double worst_energy_deviation(SimulationSpec spec, double dt, double time = 2.0) {
  spec.dt = dt;
  Simulation sim(spec, RunOptions{});
  const ThermoState t0 = sim.thermo();
  const double e0 = t0.kinetic_energy + t0.potential_energy;
  double worst = 0;
  const int steps = static_cast<int>(std::lround(time / dt));
  for (int s = 0; s < steps; ++s) {
    sim.step();
    const ThermoState t = sim.thermo();
    worst = std::max(worst, std::abs(t.kinetic_energy + t.potential_energy - e0));
  }
  return worst / std::abs(e0);
}

}  // namespace mesodpd::test
