// The global id -> storage index map over a running simulation: after every step (sorts, migrations,
// ghost builds) every local and ghost id maps to a particle with that id, owned copies first, and ids
// this rank does not hold are reported missing. Run on 1 rank and under mpirun on 2 and 4 ranks.
#include <gtest/gtest.h>

#include <vector>

#include "core/id_map.hpp"
#include "engine/simulation.hpp"
#include "parallel/comm.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

void check_map_over_run(NeighborMethod method) {
  SimulationSpec spec = test::fluid_spec(8, 8, 8, 3.0);
  spec.neighbor = method;
  spec.steps = 200;
  Simulation sim(spec, RunOptions{});
  const Comm& comm = sim.halo().comm();
  const std::uint64_t n_total = sim.total_particles();
  IdMap map;
  std::vector<std::uint8_t> held(n_total + 2);
  std::uint64_t checked_ghosts = 0;
  for (int s = 0; s < 200; ++s) {
    sim.step();
    const ParticleData& p = sim.particles();
    map.refresh(p);
    std::fill(held.begin(), held.end(), 0);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::uint32_t at = map.find(p.id[i]);
      ASSERT_NE(at, IdMap::kNotHere) << "step " << s << " id " << p.id[i];
      ASSERT_EQ(p.id[at], p.id[i]);
      // The owned copy wins; among ghosts the first in storage.
      if (i < p.n_local) {
        ASSERT_EQ(at, i);
      } else {
        ASSERT_LE(at, i);
      }
      held[p.id[i]] = 1;
    }
    checked_ghosts += p.n_ghost;
    for (std::uint32_t id = 0; id < n_total + 2; ++id)
      if (!held[id]) {
        ASSERT_EQ(map.find(id), IdMap::kNotHere) << "id " << id;
      }
    // Every particle is owned exactly once over the ranks.
    std::uint64_t owned = p.n_local;
    comm.sum(std::span<std::uint64_t>(&owned, 1));
    ASSERT_EQ(owned, n_total);
  }
  comm.sum(std::span<std::uint64_t>(&checked_ghosts, 1));
  if (comm.distributed()) {
    EXPECT_GT(checked_ghosts, 0u);
  }
}

}  // namespace

TEST(IdMapOverRun, CellsMethod) { check_map_over_run(NeighborMethod::Cells); }
TEST(IdMapOverRun, VerletMethod) { check_map_over_run(NeighborMethod::Verlet); }

TEST(IdMapOverRun, NothingIsRebuiltWhileTheParticlesStay) {
  // With a Verlet list most steps only refresh ghosts: the map is not rebuilt on those steps.
  SimulationSpec spec = test::fluid_spec(8, 8, 8, 3.0);
  spec.neighbor = NeighborMethod::Verlet;
  spec.skin = 0.6;
  Simulation sim(spec, RunOptions{});
  IdMap map;
  map.refresh(sim.particles());
  std::uint64_t steps_without_build = 0;
  for (int s = 0; s < 50; ++s) {
    const auto builds = sim.neighbor_list().builds();
    const auto rebuilds = map.rebuilds();
    sim.step();
    map.refresh(sim.particles());
    if (sim.neighbor_list().builds() == builds) {
      ++steps_without_build;
      EXPECT_EQ(map.rebuilds(), rebuilds) << "step " << s;
    }
  }
  EXPECT_GT(steps_without_build, 0u);
}

int main(int argc, char** argv) {
  MpiSession mpi(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  const Comm comm = Comm::world();
  if (!comm.root()) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const int rc = RUN_ALL_TESTS();
  return static_cast<int>(comm.max(static_cast<std::uint64_t>(rc)));
}
