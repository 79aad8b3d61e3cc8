// One run of a spec for the bit-identity tests: on a given number of OpenMP threads, either from the
// start (writing DIR/c<steps>.mdpd at its end, the checkpoint a later run restarts from) or continued
// from a checkpoint. The final states by id of two such runs are equal exactly when the trajectories are
// bit-identical.
#pragma once
#include <omp.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "engine/simulation.hpp"
#include "random_particles.hpp"

namespace mesodpd::test {

inline std::map<std::uint32_t, std::array<double, 6>> run_on_threads(
    const SimulationSpec& spec, int threads, std::uint64_t steps, const std::filesystem::path& dir,
    const std::filesystem::path& restart = {}) {
  omp_set_num_threads(threads);
  RunOptions o;
  o.steps = steps;
  o.restart = restart;
  Simulation sim(spec, o);
  sim.run();
  if (restart.empty()) sim.write_checkpoint(dir / ("c" + std::to_string(steps) + ".mdpd"));
  return state_by_id(sim.particles());
}

}  // namespace mesodpd::test
