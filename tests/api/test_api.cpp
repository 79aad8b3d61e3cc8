// Tests of the public C++ API: validate(spec) on specs built in code, the Simulation facade (state,
// conservation, restart) and the examples/api program against the same run through the CLI.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "mesodpd/config.hpp"
#include "mesodpd/simulation.hpp"
#include "mesodpd/validate.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

// A small one-species fluid through the API: 5^3 box at density 3 (375 particles).
SimulationSpec small_fluid() {
  SimulationSpec spec;
  spec.box = {5.0, 5.0, 5.0};
  spec.seed = 99;
  SpeciesSpec a;
  a.name = "A";
  a.density = 3.0;
  spec.species = {a};
  spec.steps = 40;
  spec.progress = false;
  return spec;
}

// The SpecError validate() raises for `spec`, or a test failure.
SpecError error_of(SimulationSpec spec) {
  try {
    validate(spec);
  } catch (const SpecError& e) {
    return e;
  }
  ADD_FAILURE() << "validate() accepted the spec";
  return SpecError("", "", "");
}

// An override of the pair (first, second) with the members `set` fills.
template <class Set>
PairOverride override_of(const std::string& first, const std::string& second, Set set) {
  PairOverride o;
  o.species = {first, second};
  set(o.params);
  return o;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_api" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Api, ValidateFillsDerivedDefaultsAndIsIdempotent) {
  SimulationSpec spec = small_fluid();
  spec.species.push_back(spec.species[0]);
  spec.species[1].name = "B";
  spec.species[1].density.reset();
  spec.species[1].count = 10;
  spec.pair_section.params.rc = 1.2;
  spec.pair_section.overrides.push_back(override_of("B", "A", [](PairParams& p) {
    p.a = 40.0;
    p.rc = 0.9;
  }));
  spec.dump.enabled = true;
  spec.dump.format = DumpFormat::Gsd;
  validate(spec);
  EXPECT_EQ(spec.species[0].count, 375u);  // round(3 x 125)
  EXPECT_EQ(spec.species[1].count, 10u);
  ASSERT_EQ(spec.pairs.size(), 3u);
  EXPECT_DOUBLE_EQ(spec.pair(0, 0).rd, 1.2);  // rd follows [pair] rc
  EXPECT_DOUBLE_EQ(spec.pair(1, 0).a, 40.0);
  EXPECT_DOUBLE_EQ(spec.pair(1, 0).rd, 0.9);  // ... and the override's rc
  EXPECT_DOUBLE_EQ(spec.pair(1, 1).a, 25.0);
  EXPECT_EQ(spec.dump.file, "trajectory.gsd");
  EXPECT_TRUE(spec.init_velocities);

  SimulationSpec changed = spec;  // a validated spec, edited and validated again, follows the edit
  changed.box = {6.0, 5.0, 5.0};
  changed.pair_section.params.rc.reset();
  validate(changed);
  EXPECT_EQ(changed.species[0].count, 450u);
  EXPECT_DOUBLE_EQ(changed.pair(0, 0).rd, 1.0);

  const SimulationSpec once = spec;
  validate(spec);
  EXPECT_EQ(spec.species[0].count, once.species[0].count);
  ASSERT_EQ(spec.pairs.size(), once.pairs.size());
  for (std::size_t k = 0; k < spec.pairs.size(); ++k) {
    EXPECT_EQ(spec.pairs[k].a, once.pairs[k].a);
    EXPECT_EQ(spec.pairs[k].rd, once.pairs[k].rd);
  }
}

TEST(Api, ValidateNamesTheKeyAsTheTomlSchemaDoes) {
  SimulationSpec spec = small_fluid();
  spec.dt = 0.7;
  const SpecError dt = error_of(spec);
  EXPECT_EQ(dt.key(), "integrator.dt");
  EXPECT_EQ(std::string(dt.what()), "integrator.dt = 0.7: must be in (0, 0.5]");
  // The TOML reader raises the same message, prefixed with the key's position in the file.
  try {
    parse_config("[system]\nbox = [5, 5, 5]\n[[species]]\nname = \"A\"\ndensity = 3\n[integrator]\ndt = 0.7\n", "t.toml");
    ADD_FAILURE() << "parse_config accepted dt = 0.7";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()), "t.toml:7:6: " + std::string(dt.what()));
  }

  spec = small_fluid();
  spec.box[2] = -1.0;
  EXPECT_EQ(error_of(spec).key(), "system.box[2]");
  spec = small_fluid();
  spec.pair_section.overrides.push_back(override_of("A", "A", [](PairParams& p) { p.rd = 0.5; }));
  spec.pair_section.overrides.push_back(override_of("A", "A", [](PairParams& p) { p.rd = 11.0; }));
  EXPECT_EQ(error_of(spec).key(), "pair.override[1].species");  // the pair is set twice
  spec.pair_section.overrides.erase(spec.pair_section.overrides.begin());
  EXPECT_EQ(error_of(spec).key(), "pair.override[0].rd");
  spec = small_fluid();
  spec.species[0].density = 1.0e12 / 125.0;
  EXPECT_EQ(error_of(spec).key(), "species[0].density");  // beyond 32-bit ids
  spec = small_fluid();
  spec.parallel_grid = {2, 2, 1};
  spec.box = {5.0, 2.5, 5.0};
  EXPECT_EQ(error_of(spec).key(), "parallel.grid[1]");  // 2 cells cannot be split in 2 (3 at least)
}

TEST(Api, StateIsReadableAndMomentumIsConserved) {
  api::Simulation sim(small_fluid());
  EXPECT_EQ(sim.total_particles(), 375u);
  EXPECT_EQ(sim.spec().species[0].count, 375u);  // the constructor validated the spec
  const api::Thermo start = sim.thermo();
  sim.step(25);
  EXPECT_EQ(sim.current_step(), 25u);
  EXPECT_DOUBLE_EQ(sim.time(), 1.0);
  const api::Thermo t = sim.thermo();
  EXPECT_EQ(t.step, 25u);
  // Pair forces are exactly antisymmetric (fixed-point sums), so the total momentum keeps its start
  // value (zero up to rounding of the Maxwell draw) to rounding of the velocity updates.
  for (int d = 0; d < 3; ++d) {
    EXPECT_LT(std::abs(start.momentum[d]), 1e-11);
    EXPECT_LT(std::abs(t.momentum[d] - start.momentum[d]), 1e-10) << "axis " << d;
  }
  EXPECT_NEAR(t.temperature, 2.0 * t.kinetic_energy / (3.0 * 375 - 3.0), 1e-12);  // 3N - 3 degrees of freedom
  EXPECT_NEAR(start.temperature, 1.0, 1e-12);  // the Maxwell start is rescaled to kT exactly
  EXPECT_NE(t.potential_energy, start.potential_energy);

  const api::Particles p = sim.particles();
  ASSERT_EQ(p.id.size(), 375u);
  std::vector<std::uint32_t> ids(p.id.begin(), p.id.end());
  std::sort(ids.begin(), ids.end());
  std::vector<std::uint32_t> expected(375);
  std::iota(expected.begin(), expected.end(), 1u);
  EXPECT_EQ(ids, expected);
  double momentum_x = 0;
  for (std::size_t i = 0; i < p.id.size(); ++i) {
    EXPECT_EQ(p.species[i], 0);
    for (const double c : {p.x[i], p.y[i], p.z[i]}) {
      EXPECT_GE(c, 0.0);
      EXPECT_LT(c, 5.0);
    }
    momentum_x += p.vx[i];  // unit masses
  }
  EXPECT_NEAR(momentum_x, t.momentum[0], 1e-10);
}

// Sorted-by-id copies of x and vz, to compare two runs whatever their storage order.
std::vector<double> by_id(const api::Particles& p) {
  std::vector<double> out(2 * p.id.size());
  for (std::size_t i = 0; i < p.id.size(); ++i) {
    out[2 * (p.id[i] - 1)] = p.x[i];
    out[2 * (p.id[i] - 1) + 1] = p.vz[i];
  }
  return out;
}

// thermo() between steps recomputes the pair sums (the steps computed none); the trajectory must not
// notice (it did before: the recomputed dissipative forces replaced the step's).
TEST(Api, ReadingThermoDoesNotChangeTheTrajectory) {
  api::Simulation quiet(small_fluid()), watched(small_fluid());
  quiet.step(20);
  for (int k = 0; k < 20; ++k) {
    watched.step();
    (void)watched.thermo();
  }
  EXPECT_EQ(by_id(quiet.particles()), by_id(watched.particles()));
}

TEST(Api, RestartFromACheckpointContinuesBitIdentically) {
  const fs::path dir = fresh_dir("restart");
  api::Simulation straight(small_fluid());
  straight.step(30);
  api::Simulation first(small_fluid());
  first.step(12);
  first.write_checkpoint(dir / "at12.mdpd");
  api::Options from_checkpoint;
  from_checkpoint.restart = dir / "at12.mdpd";
  api::Simulation second(small_fluid(), from_checkpoint);
  EXPECT_EQ(second.current_step(), 12u);
  second.step(18);
  const api::Particles a = straight.particles(), b = second.particles();
  ASSERT_EQ(a.id.size(), b.id.size());
  // Compare by id: storage order is the engine's business.
  std::vector<std::size_t> ia(a.id.size()), ib(b.id.size());
  std::iota(ia.begin(), ia.end(), 0);
  std::iota(ib.begin(), ib.end(), 0);
  std::sort(ia.begin(), ia.end(), [&](auto l, auto r) { return a.id[l] < a.id[r]; });
  std::sort(ib.begin(), ib.end(), [&](auto l, auto r) { return b.id[l] < b.id[r]; });
  std::size_t differ = 0;
  for (std::size_t k = 0; k < ia.size(); ++k)
    differ += a.x[ia[k]] != b.x[ib[k]] || a.vz[ia[k]] != b.vz[ib[k]] || a.fy[ia[k]] != b.fy[ib[k]];
  EXPECT_EQ(differ, 0u);
}

TEST(Api, BlowUpIsReportedWithStepAndParticle) {
  SimulationSpec spec = small_fluid();
  spec.max_velocity = 0.5;  // below thermal speeds: the first step trips the guard
  api::Simulation sim(spec);
  try {
    sim.step(5);
    FAIL() << "expected a BlowUpError";
  } catch (const api::BlowUpError& e) {
    EXPECT_EQ(e.step(), 1u);
    EXPECT_GE(e.particle_id(), 1u);
    EXPECT_NE(std::string(e.what()).find("run.max_velocity"), std::string::npos) << e.what();
  }
}

// examples/api builds its spec in C++; examples/api/fluid_api.toml is the same system as a file. Both
// routes must give the same run, bit for bit.
TEST(Api, ExampleProgramMatchesTheSameRunThroughTheCli) {
  const fs::path dir = fresh_dir("example");
  const std::string example = std::string("cd '") + dir.string() + "' && OMP_NUM_THREADS=1 '" + MESODPD_FLUID_API_PATH +
                              "' api_out > example.txt 2>&1";
  ASSERT_EQ(std::system(example.c_str()), 0) << test::read_file(dir / "example.txt");
  const std::string cli = std::string("cd '") + dir.string() + "' && OMP_NUM_THREADS=1 '" + test::mesodpd_bin() +
                          "' run '" + test::source_dir() + "/examples/api/fluid_api.toml' --out cli_out --no-progress > cli.txt 2>&1";
  ASSERT_EQ(std::system(cli.c_str()), 0) << test::read_file(dir / "cli.txt");
  const std::string printed = test::read_file(dir / "example.txt");
  EXPECT_NE(printed.find("1536 particles"), std::string::npos) << printed;
  const std::string thermo = test::read_file(dir / "api_out" / "thermo.csv");
  EXPECT_GT(std::count(thermo.begin(), thermo.end(), '\n'), 10);  // header + steps 0, 20, ..., 200
  EXPECT_EQ(thermo, test::read_file(dir / "cli_out" / "thermo.csv"));
  EXPECT_EQ(test::read_file(dir / "api_out" / "checkpoint.mdpd"), test::read_file(dir / "cli_out" / "checkpoint.mdpd"));
}

}  // namespace
}  // namespace mesodpd
