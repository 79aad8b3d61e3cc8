// Test program for test_mpi: a fluid in a box with bounded axes, built in code (the config reader refuses
// bounded axes until walls exist), run a few steps under mpirun. The root writes the gathered state in id
// order (step-0 forces, then positions, velocities and forces at the end) so runs on different rank
// counts can be compared byte for byte.
// Usage: bounded_run OUT_FILE PERIODIC(e.g. ttf) LX LY LZ GX GY GZ STEPS
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "parallel/comm.hpp"
#include "parallel/halo.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

void append(std::vector<double>& out, const ParticleData& all, std::initializer_list<const std::vector<double>*> fields) {
  for (const auto* f : fields) out.insert(out.end(), f->begin(), f->begin() + static_cast<std::ptrdiff_t>(all.n_local));
}

}  // namespace

int main(int argc, char** argv) {
  MpiSession mpi(argc, argv);
  if (argc != 10) {
    std::fprintf(stderr, "usage: bounded_run OUT_FILE PERIODIC LX LY LZ GX GY GZ STEPS\n");
    return 2;
  }
  const std::string out_file = argv[1], pattern = argv[2];
  SimulationSpec spec = test::fluid_spec(std::atof(argv[3]), std::atof(argv[4]), std::atof(argv[5]), 3.0, 25.0, 4.5, 0.01);
  // Lattice sites sit half a spacing (about 0.35) inside every face, further than any particle moves
  // in a few steps of 0.01, so nothing leaves through a bounded face, which has no wall yet.
  spec.species[0].placement = Placement::Lattice;
  for (std::size_t d = 0; d < 3; ++d) {
    spec.periodic[d] = pattern.at(d) == 't';
    spec.parallel_grid[d] = std::atoi(argv[6 + d]);
  }
  const auto steps = static_cast<std::uint64_t>(std::atoll(argv[9]));
  try {
    Simulation sim(spec, RunOptions{});
    const Comm& comm = sim.halo().comm();
    std::vector<double> out;
    {
      const ParticleData all = gather_by_id(sim.particles(), comm, sim.total_particles());
      append(out, all, {&all.fx, &all.fy, &all.fz});
    }
    // Ghost copies over all ranks: zero on one rank, and across a bounded face there are none.
    std::uint64_t ghosts[1] = {sim.particles().n_ghost};
    comm.sum(std::span<std::uint64_t>(ghosts, 1));
    for (std::uint64_t k = 0; k < steps; ++k) sim.step();
    const ParticleData all = gather_by_id(sim.particles(), comm, sim.total_particles());
    append(out, all, {&all.x, &all.y, &all.z, &all.vx, &all.vy, &all.vz, &all.fx, &all.fy, &all.fz});
    if (comm.root()) {
      std::ofstream(out_file, std::ios::binary)
          .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(out.size() * sizeof(double)));
      const auto& g = sim.halo().decomposition().grid;
      fmt::print("grid {} {} {} particles {} ghosts {}\n", g[0], g[1], g[2], all.n_local, ghosts[0]);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  }
  return 0;
}
