// A field added to the particle field list (tests/parallel/extra_fields.hpp) follows the sort,
// migration, ghost exchange (only where flagged), gather by id and a checkpoint round trip, with no
// other change to the engine; forward_field refreshes a quantity on ghosts. Run on 1 rank and under
// mpirun on 2 and 4 ranks (CTest label mpi), where particles really cross domains.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "engine/domain_exchange.hpp"
#include "io/frame.hpp"
#include "mesodpd/spec.hpp"
#include "io/lammps_dump_writer.hpp"
#include "io/state_checkpoint.hpp"
#include "neighbor/cell_grid.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/comm.hpp"
#include "parallel/decomposition.hpp"
#include "parallel/halo.hpp"

using namespace mesodpd;

namespace {

double rho_of(std::uint32_t id) { return 0.5 + 0.001 * id; }
std::uint32_t molecule_of(std::uint32_t id) { return 1 + id / 3; }

// A deterministic pseudo-random number in [0, 1) from (id, round, axis), the same on every rank.
double uniform(std::uint32_t id, int round, int axis) {
  std::uint64_t z = (std::uint64_t{id} << 20) ^ (static_cast<std::uint64_t>(round) << 4) ^ static_cast<std::uint64_t>(axis);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

struct World {
  Box box;
  Halo halo;
  CellGrid global;
  NeighborList nlist{NeighborSettings{1.0, 0.0, true}};
  ParticleData p;
  std::uint64_t total = 0;
};

// An 8 x 8 x 8 box with 1536 particles, each rank keeping its own; then the production neighbour
// rebuild (migration, cell sort, ghosts).
void make_world(World& w) {
  w.box.len = {8, 8, 8};
  const Comm comm = Comm::world();
  w.halo = Halo(comm, Decomposition::make(comm.size(), comm.rank(), CellGrid::dims_for(w.box, 1.0), {8, 8, 8},
                                          {0, 0, 0}, 1.0));
  w.global = CellGrid(w.box, 1.0);
  w.total = 1536;
  ParticleData& p = w.p;
  p.resize(w.total);
  p.n_local = w.total;
  for (std::uint32_t k = 0; k < w.total; ++k) {
    const std::uint32_t id = k + 1;
    p.id[k] = id;
    p.x[k] = 8 * uniform(id, 0, 0);
    p.y[k] = 8 * uniform(id, 0, 1);
    p.z[k] = 8 * uniform(id, 0, 2);
    p.vx[k] = id;  // any per-particle value that must arrive with the particle
    p.rho[k] = rho_of(id);
    p.molecule[k] = molecule_of(id);
  }
  w.halo.keep_owned(p, w.global);
  rebuild_neighbors(w.nlist, p, w.box, w.halo);
}

// Every local carries its own values; ghosts carry rho (kGhost) but not the molecule id.
void expect_fields_follow(const World& w) {
  const ParticleData& p = w.p;
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(p.rho[i], rho_of(p.id[i])) << "id " << p.id[i] << (i < p.n_local ? " (local)" : " (ghost)");
    ASSERT_EQ(p.vx[i], static_cast<double>(p.id[i]));
    ASSERT_EQ(p.molecule[i], i < p.n_local ? molecule_of(p.id[i]) : 0u) << "id " << p.id[i];
  }
  std::uint64_t counts[2] = {p.n_local, p.n_ghost};
  w.halo.comm().sum(std::span<std::uint64_t>(counts));
  EXPECT_EQ(counts[0], w.total);
  if (w.halo.active()) {
    EXPECT_GT(counts[1], 0u);
  }
}

}  // namespace

TEST(FieldList, ANewFieldFollowsSortMigrationAndGhosts) {
  World w;
  make_world(w);
  expect_fields_follow(w);
  std::uint64_t moved = 0;
  for (int round = 1; round <= 6; ++round) {
    // Move every local up to 1.5 along each axis (wrapped), so many change rank, and rebuild.
    ParticleData& p = w.p;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      double* r[3] = {&p.x[i], &p.y[i], &p.z[i]};
      for (int d = 0; d < 3; ++d) {
        std::int32_t image = 0;
        *r[d] += 3 * uniform(p.id[i], round, d) - 1.5;
        wrap_coordinate(*r[d], image, 8.0);
      }
    }
    const std::size_t before = p.n_local;
    rebuild_neighbors(w.nlist, p, w.box, w.halo);
    moved += before > p.n_local ? before - p.n_local : p.n_local - before;
    expect_fields_follow(w);
  }
  std::uint64_t m = moved;
  w.halo.comm().sum(std::span<std::uint64_t>(&m, 1));
  if (w.halo.active()) {
    EXPECT_GT(m, 0u) << "no particle changed rank";
  }
}

TEST(FieldList, ForwardFieldSendsOwnersValuesToGhosts) {
  World w;
  make_world(w);
  const ParticleData& p = w.p;
  std::vector<double> density(p.size(), -1.0);
  for (std::size_t i = 0; i < p.n_local; ++i) density[i] = std::sqrt(static_cast<double>(p.id[i]));
  w.halo.forward_field(w.p, density);
  for (std::size_t i = 0; i < p.size(); ++i)
    ASSERT_EQ(density[i], std::sqrt(static_cast<double>(p.id[i]))) << "id " << p.id[i] << " at " << i;
}

TEST(FieldList, ANewFieldIsGatheredAndSurvivesACheckpoint) {
  World w;
  make_world(w);
  const ParticleData all = gather_by_id(w.p, w.halo.comm(), w.total);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / ("mesodpd_field_list_" + std::to_string(w.halo.comm().size()) + ".mdpd");
  w.halo.comm().on_root([&] {
    ASSERT_EQ(all.n_local, w.total);
    for (std::size_t i = 0; i < all.n_local; ++i) {
      ASSERT_EQ(all.id[i], i + 1);
      ASSERT_EQ(all.rho[i], rho_of(all.id[i]));
      ASSERT_EQ(all.molecule[i], molecule_of(all.id[i]));
    }
    StateHeader h;
    h.n_species = 1;
    write_state_checkpoint(file, h, all, {});
    const StateCheckpoint c = read_state_checkpoint(file);
    ASSERT_EQ(c.particles.n_local, w.total);
    for (std::size_t i = 0; i < w.total; ++i) {
      ASSERT_EQ(c.particles.rho[i], rho_of(c.particles.id[i]));
      ASSERT_EQ(c.particles.molecule[i], molecule_of(c.particles.id[i]));
    }
  });
}

TEST(FieldList, ANewFrameFieldIsOfferedToTrajectories) {
  // rho is flagged kFrame: it becomes a selectable trajectory field and a dump column; molecule is
  // not flagged and stays unknown to trajectories.
  const auto& names = trajectory_field_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "rho"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "molecule"), names.end());
  EXPECT_THROW(parse_trajectory_fields({"id", "molecule"}, "t.lammpstrj"), ConfigError);
  World w;
  make_world(w);
  const ParticleData all = gather_by_id(w.p, w.halo.comm(), w.total);
  w.halo.comm().on_root([&] {
    const std::filesystem::path file = std::filesystem::temp_directory_path() / "mesodpd_field_list_frame.lammpstrj";
    {
      LammpsDumpWriter writer(file, {"rho", "id"});
      FrameView f;
      f.box_len = {8, 8, 8};
      set_frame_arrays(f, all);
      writer.write_frame(f);
    }
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line) && line.rfind("ITEM: ATOMS", 0) != 0) {
    }
    ASSERT_EQ(line, "ITEM: ATOMS id rho");
    std::size_t rows = 0;
    for (std::uint32_t id; in >> id;) {
      double rho = 0;
      in >> rho;
      ASSERT_EQ(rho, rho_of(id)) << "id " << id;
      ++rows;
    }
    EXPECT_EQ(rows, w.total);
  });
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
