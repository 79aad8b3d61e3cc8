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

#include <gtest/gtest.h>

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

// The usual check: 100 steps on 1 and on 2 threads, and 100 steps on 2 threads continued from the
// checkpoint of a 40-step run on 1, give the same final state by id (the run's scratch files in `dir`,
// which is created and removed).
inline void expect_bit_identical_on_threads_and_restart(const SimulationSpec& spec, const std::filesystem::path& dir) {
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto one = run_on_threads(spec, 1, 100, dir);
  EXPECT_TRUE(run_on_threads(spec, 2, 100, dir) == one) << "1 and 2 threads differ";
  run_on_threads(spec, 1, 40, dir);
  EXPECT_TRUE(run_on_threads(spec, 2, 100, dir, dir / "c40.mdpd") == one) << "the restarted run diverged";
  omp_set_num_threads(1);
  std::filesystem::remove_all(dir);
}

}  // namespace mesodpd::test
