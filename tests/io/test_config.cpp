// Tests of the TOML config reader: the full schema, defaults, mixing, and one test per kind of bad input.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <string_view>

#include "mesodpd/config.hpp"
#include "mesodpd/validate.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

// A minimal valid config; tests that need more write their own text.
constexpr std::string_view kMinimal = R"(
[system]
box = [10, 10, 10]

[[species]]
name = "A"
density = 3
)";

// The ConfigError message for `text`, or a test failure when it parses.
std::string error_of(std::string_view text) {
  try {
    parse_config(text, "test.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ConfigError for:\n" << text;
  return {};
}

// Checks that `text` is rejected with a message containing every one of `needles`.
void expect_error(std::string_view text, std::initializer_list<std::string_view> needles) {
  const std::string message = error_of(text);
  for (const std::string_view needle : needles) {
    EXPECT_NE(message.find(needle), std::string::npos) << "message: " << message << "\nlacks: " << needle;
  }
}

// `kMinimal` followed by `extra` (which may add tables but not reopen [system] or species[0]).
std::string minimal_plus(std::string_view extra) { return std::string(kMinimal) + std::string(extra); }

// A fresh directory under the system temp dir, removed at scope exit.
class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() /
            ("mesodpd_test_config_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }
  fs::path write(const std::string& name, std::string_view text) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p) << text;
    return p;
  }

 private:
  fs::path path_;
};

TEST(Config, FullConfigParses) {
  const SimulationSpec spec = parse_config(R"(
[system]
box = [12.0, 14, 16.5]
kT = 1.5
seed = 42

[[species]]
name = "W"
mass = 2
body_force = [0.1, 0, -0.2]
count = 500
placement = "lattice"

[[species]]
name = "Oil_2"
density = 1.0

[pair]
a = 30
gamma = 3.0
sigma = 3.0   # 3^2 = 2 * 3 * 1.5
rc = 1.0
rd = 1.2
s = 0.5

[[pair.override]]
species = ["Oil_2", "W"]
a = 60
gamma = 6.0
sigma = 4.242640687119285  # sqrt(2 * 6 * 1.5)
rc = 1.3

[integrator]
type = "groot-warren"
dt = 0.02
lambda = 0.65

[run]
steps = 5000
noise = "gaussian"
max_velocity = 50
threads = 2

[neighbor]
method = "verlet"
skin = 0.5

[init]
velocities = "zero"

[output]
thermo_every = 10
checkpoint_every = 1000
progress = false

[output.dump]
format = "gsd"
every = 50
fields = ["id", "position", "velocity", "image"]

[poiseuille]
force = -0.1
flow_axis = "y"
gradient_axis = "x"
bins = 24
start = 100
every = 5
blocks = 4

[analysis.rdf]
bins = 50
rmax = 5.5
start = 10
every = 20

[analysis.msd]
start = 7
every = 3
)",
                                           "full.toml");
  EXPECT_EQ(spec.source, "full.toml");
  EXPECT_EQ(spec.box, (std::array<double, 3>{12.0, 14.0, 16.5}));
  EXPECT_DOUBLE_EQ(spec.kT, 1.5);
  EXPECT_EQ(spec.seed, 42u);

  ASSERT_EQ(spec.species.size(), 2u);
  EXPECT_EQ(spec.species[0].name, "W");
  EXPECT_DOUBLE_EQ(spec.species[0].mass, 2.0);
  EXPECT_FALSE(spec.species[0].a.has_value());
  EXPECT_EQ(spec.species[0].body_force, (std::array<double, 3>{0.1, 0.0, -0.2}));
  EXPECT_EQ(spec.species[0].count, 500u);
  EXPECT_EQ(spec.species[0].placement, Placement::Lattice);
  EXPECT_EQ(spec.species[1].name, "Oil_2");
  EXPECT_EQ(spec.species[1].count, 2772u);  // round(1.0 * 12 * 14 * 16.5)
  EXPECT_EQ(spec.species[1].placement, Placement::Random);

  ASSERT_EQ(spec.pairs.size(), 3u);
  const PairSpec& ww = spec.pair(0, 0);
  EXPECT_EQ(ww.i, 0);
  EXPECT_EQ(ww.j, 0);
  EXPECT_DOUBLE_EQ(ww.a, 30.0);
  EXPECT_DOUBLE_EQ(ww.gamma, 3.0);
  EXPECT_DOUBLE_EQ(ww.rc, 1.0);
  EXPECT_DOUBLE_EQ(ww.rd, 1.2);
  EXPECT_DOUBLE_EQ(ww.s, 0.5);
  const PairSpec& wo = spec.pair(1, 0);
  EXPECT_EQ(&wo, &spec.pairs[1]);
  EXPECT_EQ(wo.i, 0);
  EXPECT_EQ(wo.j, 1);
  EXPECT_DOUBLE_EQ(wo.a, 60.0);
  EXPECT_DOUBLE_EQ(wo.gamma, 6.0);
  EXPECT_DOUBLE_EQ(wo.rc, 1.3);
  EXPECT_DOUBLE_EQ(wo.rd, 1.2);  // [pair] rd set explicitly, so the override's rc does not move it
  EXPECT_DOUBLE_EQ(wo.s, 0.5);
  EXPECT_EQ(spec.pair(1, 1).i, 1);
  EXPECT_DOUBLE_EQ(spec.pair(1, 1).a, 30.0);

  EXPECT_EQ(spec.integrator, IntegratorKind::GrootWarren);
  EXPECT_DOUBLE_EQ(spec.dt, 0.02);
  EXPECT_DOUBLE_EQ(spec.lambda, 0.65);
  EXPECT_EQ(spec.steps, 5000u);
  EXPECT_EQ(spec.noise, NoiseDistribution::Gaussian);
  EXPECT_DOUBLE_EQ(spec.max_velocity, 50.0);
  EXPECT_EQ(spec.threads, 2);
  EXPECT_EQ(spec.neighbor, NeighborMethod::Verlet);
  EXPECT_DOUBLE_EQ(spec.skin, 0.5);
  EXPECT_TRUE(spec.data_file.empty());
  EXPECT_EQ(spec.velocities, VelocityInit::Zero);
  EXPECT_FALSE(spec.init_velocities);

  EXPECT_EQ(spec.thermo_every, 10u);
  EXPECT_EQ(spec.checkpoint_every, 1000u);
  EXPECT_FALSE(spec.progress);
  EXPECT_TRUE(spec.dump.enabled);
  EXPECT_EQ(spec.dump.format, DumpFormat::Gsd);
  EXPECT_EQ(spec.dump.every, 50u);
  EXPECT_EQ(spec.dump.fields, (std::vector<std::string>{"id", "position", "velocity", "image"}));
  EXPECT_EQ(spec.dump.file, "trajectory.gsd");

  EXPECT_TRUE(spec.poiseuille.enabled);
  EXPECT_DOUBLE_EQ(spec.poiseuille.force, -0.1);
  EXPECT_EQ(spec.poiseuille.flow_axis, 1);
  EXPECT_EQ(spec.poiseuille.gradient_axis, 0);
  EXPECT_EQ(spec.poiseuille.bins, 24);
  EXPECT_EQ(spec.poiseuille.start, 100u);
  EXPECT_EQ(spec.poiseuille.every, 5u);
  EXPECT_EQ(spec.poiseuille.blocks, 4);

  EXPECT_TRUE(spec.rdf.enabled);
  EXPECT_EQ(spec.rdf.bins, 50);
  EXPECT_DOUBLE_EQ(spec.rdf.rmax, 5.5);
  EXPECT_EQ(spec.rdf.start, 10u);
  EXPECT_EQ(spec.rdf.every, 20u);
  EXPECT_TRUE(spec.msd.enabled);
  EXPECT_EQ(spec.msd.start, 7u);
  EXPECT_EQ(spec.msd.every, 3u);
}

TEST(Config, Defaults) {
  const SimulationSpec spec = parse_config(kMinimal, "min.toml");
  EXPECT_DOUBLE_EQ(spec.kT, 1.0);
  EXPECT_EQ(spec.seed, 1u);
  ASSERT_EQ(spec.species.size(), 1u);
  EXPECT_DOUBLE_EQ(spec.species[0].mass, 1.0);
  EXPECT_EQ(spec.species[0].count, 3000u);
  EXPECT_EQ(spec.species[0].placement, Placement::Random);
  EXPECT_EQ(spec.species[0].body_force, (std::array<double, 3>{0, 0, 0}));
  ASSERT_EQ(spec.pairs.size(), 1u);
  EXPECT_DOUBLE_EQ(spec.pairs[0].a, 25.0);
  EXPECT_DOUBLE_EQ(spec.pairs[0].gamma, 4.5);
  EXPECT_DOUBLE_EQ(spec.pairs[0].rc, 1.0);
  EXPECT_DOUBLE_EQ(spec.pairs[0].rd, 1.0);
  EXPECT_DOUBLE_EQ(spec.pairs[0].s, 2.0);
  EXPECT_EQ(spec.integrator, IntegratorKind::GrootWarren);
  EXPECT_DOUBLE_EQ(spec.dt, 0.04);
  EXPECT_DOUBLE_EQ(spec.lambda, 0.5);
  EXPECT_EQ(spec.steps, 1000u);
  EXPECT_EQ(spec.noise, NoiseDistribution::Uniform);
  EXPECT_DOUBLE_EQ(spec.max_velocity, 1000.0);
  EXPECT_EQ(spec.threads, 0);
  EXPECT_EQ(spec.neighbor, NeighborMethod::Cells);
  EXPECT_DOUBLE_EQ(spec.skin, 0.3);
  EXPECT_TRUE(spec.data_file.empty());
  EXPECT_EQ(spec.velocities, VelocityInit::Maxwell);
  EXPECT_TRUE(spec.init_velocities);
  EXPECT_EQ(spec.thermo_every, 100u);
  EXPECT_EQ(spec.checkpoint_every, 0u);
  EXPECT_TRUE(spec.progress);
  EXPECT_FALSE(spec.dump.enabled);
  EXPECT_FALSE(spec.poiseuille.enabled);
  EXPECT_FALSE(spec.rdf.enabled);
  EXPECT_FALSE(spec.msd.enabled);
  EXPECT_EQ(spec.periodic, (std::array<bool, 3>{true, true, true}));
}

// Bounded axes parse but are refused until walls exist to close them; the message says so.
TEST(Config, PeriodicAxes) {
  const auto with = [](std::string_view periodic) {
    return "[system]\nbox = [10, 10, 10]\nperiodic = " + std::string(periodic) +
           "\n[[species]]\nname = \"A\"\ndensity = 3\n";
  };
  EXPECT_EQ(parse_config(with("[true, true, true]"), "p.toml").periodic, (std::array<bool, 3>{true, true, true}));
  expect_error(with("[true, true, false]"),
               {"system.periodic = [true, true, false]", "bounded axis", "[[solid]] walls"});
  expect_error(with("[false, true, true]"), {"system.periodic", "walls"});
  expect_error(with("[true, true]"), {"system.periodic", "expected 3 booleans, got 2"});
  expect_error(with("[true, 1, true]"), {"system.periodic[1]", "boolean"});
  expect_error(with("true"), {"system.periodic", "an array of 3 booleans"});
  expect_error(with("[true, true, true]\nperiodc = 1"), {"system.periodc", "system.periodic"});
}

TEST(Config, PresentTablesUseTheirDefaults) {
  const SimulationSpec spec = parse_config(minimal_plus(R"(
[output.dump]
[poiseuille]
force = 0.05
[analysis.rdf]
[analysis.msd]
)"),
                                           "t.toml");
  EXPECT_TRUE(spec.dump.enabled);
  EXPECT_EQ(spec.dump.format, DumpFormat::Lammps);
  EXPECT_EQ(spec.dump.every, 1000u);
  EXPECT_EQ(spec.dump.fields, (std::vector<std::string>{"id", "species", "position"}));
  EXPECT_EQ(spec.dump.file, "trajectory.lammpstrj");
  EXPECT_TRUE(spec.poiseuille.enabled);
  EXPECT_EQ(spec.poiseuille.flow_axis, 0);
  EXPECT_EQ(spec.poiseuille.gradient_axis, 2);
  EXPECT_EQ(spec.poiseuille.bins, 40);
  EXPECT_EQ(spec.poiseuille.start, 0u);
  EXPECT_EQ(spec.poiseuille.every, 1u);
  EXPECT_EQ(spec.poiseuille.blocks, 10);
  EXPECT_TRUE(spec.rdf.enabled);
  EXPECT_EQ(spec.rdf.bins, 100);
  EXPECT_DOUBLE_EQ(spec.rdf.rmax, 3.0);
  EXPECT_EQ(spec.rdf.every, 100u);
  EXPECT_TRUE(spec.msd.enabled);
  EXPECT_EQ(spec.msd.every, 100u);
}

TEST(Config, GeometricMixingAndOverrideOrder) {
  const SimulationSpec spec = parse_config(R"(
[system]
box = [5, 5, 5]
[[species]]
name = "A"
a = 25
count = 10
[[species]]
name = "B"
a = 36
count = 10
[[species]]
name = "C"
a = 16
count = 10
[pair]
mixing = "geometric"
[[pair.override]]
species = ["C", "A"]
a = 99
)",
                                           "mix.toml");
  ASSERT_EQ(spec.pairs.size(), 6u);
  // Row-major upper triangle: (0,0) (0,1) (0,2) (1,1) (1,2) (2,2).
  const int expected_i[] = {0, 0, 0, 1, 1, 2}, expected_j[] = {0, 1, 2, 1, 2, 2};
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(spec.pairs[k].i, expected_i[k]);
    EXPECT_EQ(spec.pairs[k].j, expected_j[k]);
    EXPECT_EQ(&spec.pair(expected_j[k], expected_i[k]), &spec.pairs[k]);
  }
  EXPECT_DOUBLE_EQ(spec.pair(0, 0).a, 25.0);
  EXPECT_DOUBLE_EQ(spec.pair(0, 1).a, 30.0);  // sqrt(25 * 36), seed 002 Eq. 4
  EXPECT_DOUBLE_EQ(spec.pair(0, 2).a, 99.0);  // override wins over mixing
  EXPECT_DOUBLE_EQ(spec.pair(1, 2).a, 24.0);  // sqrt(36 * 16)
  EXPECT_DOUBLE_EQ(spec.pair(2, 2).a, 16.0);
}

TEST(Config, RdFollowsRcUnlessSet) {
  const SimulationSpec spec = parse_config(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
count = 1
[[species]]
name = "B"
count = 1
[pair]
rc = 1.2
[[pair.override]]
species = ["B", "B"]
rc = 1.5
)",
                                           "rd.toml");
  EXPECT_DOUBLE_EQ(spec.pair(0, 0).rd, 1.2);
  EXPECT_DOUBLE_EQ(spec.pair(0, 1).rd, 1.2);
  EXPECT_DOUBLE_EQ(spec.pair(1, 1).rc, 1.5);
  EXPECT_DOUBLE_EQ(spec.pair(1, 1).rd, 1.5);
}

TEST(Config, ConsistentSigmaAccepted) {
  const SimulationSpec spec = parse_config(minimal_plus("[pair]\nsigma = 3.0\n"), "t.toml");
  EXPECT_DOUBLE_EQ(spec.pairs[0].gamma, 4.5);
}

TEST(Config, RejectsUnknownKeys) {
  expect_error(minimal_plus("[run]\nstpes = 10\n"), {"unknown key 'run.stpes'", "did you mean 'run.steps'"});
  expect_error(minimal_plus("[sytem_x]\n"), {"unknown key 'sytem_x'"});
  expect_error(minimal_plus("[integrator]\ndt = 0.01\nfoo_bar_baz = 1\n"),
               {"integrator.foo_bar_baz", "valid keys in [integrator]: type, dt, lambda"});
  expect_error(minimal_plus("[output.dump]\nevry = 5\n"), {"output.dump.evry", "output.dump.every"});
  expect_error(minimal_plus("[analysis.vacf]\n"), {"unknown key 'analysis.vacf'"});
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
count = 3
[[species]]
name = "B"
count = 3
mas = 2
)",
               {"unknown key 'species[1].mas'", "species[1].mass"});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\nsigmaa = 3\n"),
               {"pair.override[0].sigmaa"});
  // The location of the offending key is given as file:line:col.
  expect_error(minimal_plus("[run]\nstpes = 10\n"), {"test.toml:9:1"});
}

TEST(Config, RejectsWrongTypes) {
  expect_error(minimal_plus("[run]\nsteps = \"1000\"\n"), {"run.steps", "expected an integer, got a string"});
  expect_error(minimal_plus("[run]\nsteps = 10.5\n"), {"run.steps", "expected an integer"});
  expect_error(minimal_plus("[integrator]\ndt = \"fast\"\n"), {"integrator.dt", "expected a number"});
  expect_error(minimal_plus("[output]\nprogress = 1\n"), {"output.progress", "boolean"});
  expect_error(minimal_plus("[pair]\nmixing = 3\n"), {"pair.mixing", "expected a string"});
  expect_error("integrator = 3\n" + std::string(kMinimal), {"integrator = 3", "expected a table"});
  expect_error("[system]\nbox = [10, 10, 10]\n[species]\nname = \"A\"\ncount = 1\n",
               {"species", "array of tables"});
  expect_error("[system]\nbox = [10, \"10\", 10]\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.box[1]", "expected a number"});
  expect_error("[system]\nbox = [10, 10]\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.box", "expected 3 numbers"});
  expect_error(minimal_plus("[output.dump]\nfields = [\"id\", 3]\n"), {"output.dump.fields[1]", "string"});
}

TEST(Config, RejectsBadChoices) {
  expect_error(minimal_plus("[run]\nnoise = \"gausian\"\n"),
               {"run.noise = \"gausian\"", "\"uniform\", \"gaussian\"", "did you mean \"gaussian\""});
  expect_error(minimal_plus("[integrator]\ntype = \"verlet\"\n"), {"integrator.type", "\"groot-warren\""});
  expect_error(minimal_plus("[neighbor]\nmethod = \"list\"\n"), {"neighbor.method"});
  expect_error(minimal_plus("[output.dump]\nformat = \"xyz\"\n"), {"output.dump.format"});
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
count = 3
placement = "grid"
)",
               {"species[0].placement"});
}

TEST(Config, RejectsOutOfRangeValues) {
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
density = 0
)",
               {"species[0].density = 0", "must be > 0"});
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
density = -3
)",
               {"species[0].density"});
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
count = 1
[[species]]
name = "B"
count = 1
mass = 0
)",
               {"species[1].mass = 0", "must be > 0"});
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
count = -1
)",
               {"species[0].count", ">= 0"});
  expect_error(minimal_plus("[integrator]\ndt = 0\n"), {"integrator.dt = 0", "(0, 0.5]"});
  expect_error(minimal_plus("[integrator]\ndt = -0.01\n"), {"integrator.dt"});
  expect_error(minimal_plus("[integrator]\ndt = 2.0\n"), {"integrator.dt = 2", "(0, 0.5]"});
  expect_error(minimal_plus("[integrator]\ndt = nan\n"), {"integrator.dt = nan"});
  expect_error(minimal_plus("[integrator]\nlambda = 1.5\n"), {"integrator.lambda", "[0, 1]"});
  expect_error(minimal_plus("[pair]\nrc = 0\n"), {"pair.rc = 0", "(0, 10]"});
  expect_error(minimal_plus("[pair]\nrc = -1\n"), {"pair.rc = -1"});
  expect_error(minimal_plus("[pair]\nrd = 10.5\n"), {"pair.rd = 10.5", "(0, 10]"});
  expect_error(minimal_plus("[pair]\nrd = 0\n"), {"pair.rd"});
  expect_error(minimal_plus("[pair]\ns = 0\n"), {"pair.s = 0", "(0, 10]"});
  expect_error(minimal_plus("[pair]\ns = -2\n"), {"pair.s"});
  expect_error(minimal_plus("[pair]\na = -1\n"), {"pair.a = -1", ">= 0"});
  expect_error(minimal_plus("[pair]\ngamma = -4.5\n"), {"pair.gamma"});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\ns = 0\n"),
               {"pair.override[0].s = 0"});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\nrc = 20\n"),
               {"pair.override[0].rc"});
  expect_error("[system]\nbox = [10, 10, 10]\nkT = 0\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.kT = 0", "must be > 0"});
  expect_error("[system]\nbox = [10, 10, 10]\nkT = -1\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.kT"});
  expect_error("[system]\nbox = [10, 0, 10]\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.box[1] = 0", "must be > 0"});
  expect_error("[system]\nbox = [10, 10, 10]\nseed = -1\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.seed"});
  expect_error(minimal_plus("[run]\nsteps = -5\n"), {"run.steps = -5", ">= 0"});
  expect_error(minimal_plus("[run]\nthreads = -1\n"), {"run.threads"});
  expect_error(minimal_plus("[run]\nmax_velocity = 0\n"), {"run.max_velocity"});
  expect_error(minimal_plus("[neighbor]\nskin = 3\n"), {"neighbor.skin = 3", "[0, 2]"});
  expect_error(minimal_plus("[output]\nthermo_every = 0\n"), {"output.thermo_every", ">= 1"});
  expect_error(minimal_plus("[output.dump]\nevery = 0\n"), {"output.dump.every"});
  expect_error(minimal_plus("[analysis.rdf]\nbins = 0\n"), {"analysis.rdf.bins"});
  expect_error(minimal_plus("[analysis.msd]\nevery = 0\n"), {"analysis.msd.every"});
}

TEST(Config, RejectsBoxSmallerThanTwiceTheCutoff) {
  expect_error("[system]\nbox = [10, 1.5, 10]\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"system.box", ">= 2"});
  // The longest cutoff may come from an override's rd.
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\nrd = 6\n"),
               {"system.box", ">= 12"});
}

// Errors found by validate() carry the position of the key they name, also inside arrays of tables
// and arrays; a value the file leaves at its default is marked so, at its table's position.
TEST(Config, ValidationErrorsPointAtTheirKey) {
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\na = 30\n"
                            "[[pair.override]]\nspecies = [\"A\", \"A\"]\n  rd = 11\n"),
               {"test.toml:12:11: pair.override[1].species", "already set by pair.override[0]"});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\n  rd = 11\n"),
               {"test.toml:10:8: pair.override[0].rd = 11: must be in (0, 10]"});
  expect_error("[system]\nbox = [10, 10,   -4]\n[[species]]\nname = \"A\"\ncount = 1\n",
               {"test.toml:2:18: system.box[2] = -4: must be > 0"});
  expect_error("[system]\nbox = [5, 10, 10]\n[[species]]\nname = \"A\"\ncount = 1\n\n[analysis.rdf]\nbins = 10\n",
               {"test.toml:7:1: analysis.rdf.rmax = 3 (default): must be < half the smallest box length (2.5)"});
}

TEST(Config, RejectsRdfRangeBeyondHalfTheBox) {
  expect_error(minimal_plus("[analysis.rdf]\nrmax = 5\n"),
               {"analysis.rdf.rmax = 5", "half the smallest box"});
  // The default rmax (3) does not fit a 5-wide box either.
  expect_error("[system]\nbox = [5, 10, 10]\n[[species]]\nname = \"A\"\ncount = 1\n[analysis.rdf]\n",
               {"analysis.rdf.rmax"});
}

TEST(Config, RejectsInconsistentSigma) {
  expect_error(minimal_plus("[pair]\nsigma = 4.0\n"),
               {"pair.sigma = 4", "pair.gamma = 4.5", "sigma = 3", "seed 000 Eq. 7"});
  expect_error(minimal_plus("[pair]\ngamma = 8\nsigma = 3.0\n"), {"pair.sigma"});
  // An override that changes gamma must not leave the [pair] sigma behind.
  expect_error(minimal_plus("[pair]\nsigma = 3.0\n[[pair.override]]\nspecies = [\"A\", \"A\"]\ngamma = 8\n"),
               {"pair.sigma", "pair.override[0].gamma"});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\ngamma = 2\nsigma = 3\n"),
               {"pair.override[0].sigma"});
}

TEST(Config, RejectsBadOverrides) {
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"B\"]\na = 40\n"),
               {"pair.override[0].species", "unknown species \"B\""});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\"]\n"), {"pair.override[0].species", "two"});
  expect_error(minimal_plus("[[pair.override]]\na = 40\n"),
               {"missing required key 'pair.override[0].species'"});
  expect_error(minimal_plus("[[pair.override]]\nspecies = [\"A\", \"A\"]\na = 1\n"
                            "[[pair.override]]\nspecies = [\"A\", \"A\"]\na = 2\n"),
               {"pair.override[1].species", "already set by pair.override[0]"});
}

TEST(Config, RejectsBadSpecies) {
  expect_error("[system]\nbox = [10, 10, 10]\n", {"species", "at least one"});
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
count = 1
[[species]]
name = "A"
count = 2
)",
               {"species[1].name = \"A\"", "duplicate", "species[0].name"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\ncount = 1\n", {"species[0].name"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"\"\ncount = 1\n", {"species[0].name"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A B\"\ncount = 1\n",
               {"species[0].name", "letters, digits"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\n",
               {"species[0].density", "species[0].count"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\ndensity = 3\ncount = 1\n",
               {"species[0].density", "species[0].count", "only one"});
  expect_error(
      "[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\ncount = 1\nbody_force = [0, inf, 0]\n",
      {"species[0].body_force[1]"});
}

TEST(Config, MixingRulesNeedTheRightSpeciesKeys) {
  expect_error(R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
a = 25
count = 1
[[species]]
name = "B"
count = 1
[pair]
mixing = "geometric"
)",
               {"species[1].a", "geometric"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\na = 25\ncount = 1\n",
               {"species[0].a", "geometric"});
  expect_error(
      "[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\na = 25\ncount = 1\n"
      "[pair]\nmixing = \"geometric\"\na = 30\n",
      {"pair.a", "geometric"});
}

TEST(Config, RejectsMissingRequiredKeys) {
  expect_error("[[species]]\nname = \"A\"\ncount = 1\n", {"missing required key 'system.box'"});
  expect_error(minimal_plus("[poiseuille]\nbins = 20\n"), {"missing required key 'poiseuille.force'"});
}

TEST(Config, RejectsBadIntegratorCombination) {
  expect_error(minimal_plus("[integrator]\ntype = \"euler\"\nlambda = 0.5\n"),
               {"integrator.lambda", "euler"});
  const SimulationSpec spec =
      parse_config(minimal_plus("[integrator]\ntype = \"euler\"\ndt = 0.01\n"), "t.toml");
  EXPECT_EQ(spec.integrator, IntegratorKind::Euler);
}

TEST(Config, RejectsBadPoiseuille) {
  expect_error(minimal_plus("[poiseuille]\nforce = 0\n"), {"poiseuille.force = 0", "non-zero"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\nbins = 21\n"), {"poiseuille.bins = 21", "even"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\nbins = 2\n"), {"poiseuille.bins = 2", ">= 4"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\nflow_axis = \"z\"\n"),
               {"poiseuille.gradient_axis", "poiseuille.flow_axis"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\ngradient_axis = \"x\"\n"),
               {"poiseuille.gradient_axis"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\nflow_axis = \"w\"\n"), {"poiseuille.flow_axis"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\nblocks = 1\n"), {"poiseuille.blocks"});
  expect_error(minimal_plus("[poiseuille]\nforce = 0.1\nevery = 0\n"), {"poiseuille.every"});
}

TEST(Config, RejectsBadDumpFields) {
  expect_error(minimal_plus("[output.dump]\nfields = []\n"), {"output.dump.fields", "at least one"});
  expect_error(minimal_plus("[output.dump]\nfields = [\"id\", \"charge\"]\n"),
               {"output.dump.fields", "unknown field \"charge\""});
  expect_error(minimal_plus("[output.dump]\nfields = [\"id\", \"position\", \"id\"]\n"),
               {"output.dump.fields", "\"id\" is listed twice"});
  expect_error(minimal_plus("[output.dump]\nfile = \"\"\n"), {"output.dump.file"});
}

TEST(Config, RejectsMalformedToml) {
  const std::string message = error_of("[system]\nbox = [10, 10, 10]\nkT = = 1\n");
  EXPECT_NE(message.find("test.toml:3:"), std::string::npos) << message;
  EXPECT_NE(message.find("TOML syntax error"), std::string::npos) << message;
  expect_error("[system]\nbox = [10, 10, 10]\n[system]\nkT = 1\n", {"test.toml:3:", "TOML syntax error"});
}

TEST(Config, LoadConfigReportsMissingFile) {
  const TempDir dir;
  const fs::path missing = dir.path() / "nope.toml";
  try {
    load_config(missing);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_config(dir.path()), ConfigError);  // a directory is not a config file
}

TEST(Config, LoadConfigReportsSyntaxErrorWithFileName) {
  const TempDir dir;
  const fs::path file = dir.write("bad.toml", "[system\n");
  try {
    load_config(file);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string() + ":1:"), std::string::npos) << e.what();
  }
}

TEST(Config, LammpsDataPathIsResolvedAgainstTheConfigDirectory) {
  const TempDir dir;
  dir.write("data/start.data", "LAMMPS data file\n");
  const fs::path config = dir.write("job/run.toml", R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
[init]
lammps_data = "../data/start.data"
)");
  const SimulationSpec spec = load_config(config);
  EXPECT_EQ(fs::path(spec.data_file), fs::absolute(dir.path() / "data" / "start.data").lexically_normal());
  EXPECT_TRUE(fs::path(spec.data_file).is_absolute());
  EXPECT_EQ(spec.velocities, VelocityInit::File);
  EXPECT_FALSE(spec.init_velocities);
  EXPECT_EQ(spec.species[0].count, 0u);
  EXPECT_EQ(spec.source, config.string());
}

TEST(Config, RejectsBadInit) {
  const TempDir dir;
  const fs::path data = dir.write("a.data", "LAMMPS data file\n");
  const std::string init = "[init]\nlammps_data = \"" + data.string() + "\"\n";
  expect_error(minimal_plus("[init]\nlammps_data = \"surely/not/here.data\"\n"),
               {"init.lammps_data", "no such file", "here.data"});
  expect_error(minimal_plus("[init]\nvelocities = \"file\"\n"), {"init.velocities", "init.lammps_data"});
  expect_error(minimal_plus("[init]\nvelocities = \"hot\"\n"), {"init.velocities", "\"maxwell\""});
  // With a data file the particles are not generated, so counts and placement are refused.
  expect_error(minimal_plus(init), {"species[0].density", "init.lammps_data"});
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\nplacement = \"lattice\"\n" + init,
               {"species[0].placement", "init.lammps_data"});
  const SimulationSpec spec = parse_config(
      "[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\n" + init + "velocities = \"maxwell\"\n",
      "t.toml");
  EXPECT_EQ(spec.velocities, VelocityInit::Maxwell);
  EXPECT_TRUE(spec.init_velocities);
}

TEST(Config, SpeciesRegionIsAShapeCheckedLikeASolid) {
  // [[species]] region restricts where a generated species is placed (examples/wetting).
  const std::string head = "[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\ndensity = 3\n";
  const SimulationSpec spec =
      parse_config(head + "region = {shape = \"sphere\", center = [5, 5, 5], radius = 3}\n", "t.toml");
  ASSERT_TRUE(spec.species[0].region.has_value());
  EXPECT_EQ(spec.species[0].region->kind, ShapeKind::Sphere);
  EXPECT_EQ(spec.species[0].region->radius, 3.0);
  expect_error(head + "region = {shape = \"sphere\", center = [5, 5, 5]}\n", {"species[0].region.radius", "missing"});
  expect_error(head + "region = {shape = \"sphere\", center = [5, 5, 5], radius = -1}\n", {"species[0].region.radius"});
  expect_error(head + "region = {shape = \"sphere\", centre = [5, 5, 5], radius = 1}\n", {"species[0].region.centre"});
  expect_error(head + "region = \"sphere\"\n", {"species[0].region", "table"});
  // A half space along a periodic axis is refused as for a solid (use a box).
  expect_error(head + "region = {shape = \"plane\", point = [0, 0, 5], normal = [0, 0, 1]}\n",
               {"species[0].region.normal", "periodic"});
  expect_error(head + "[[species]]\nname = \"W\"\nfrozen = true\nregion = {shape = \"sphere\", center = [5, 5, 5], radius = 3}\n",
               {"species[1].region", "frozen"});
  const TempDir dir;
  const fs::path data = dir.write("a.data", "LAMMPS data file\n");
  expect_error("[system]\nbox = [10, 10, 10]\n[[species]]\nname = \"A\"\n"
               "region = {shape = \"sphere\", center = [5, 5, 5], radius = 3}\n[init]\nlammps_data = \"" +
                   data.string() + "\"\n",
               {"species[0].region", "init.lammps_data"});
}

// The source tree: $MESODPD_SOURCE (set by ctest), else derived from this file's path.
fs::path source_root() {
  if (const char* root = std::getenv("MESODPD_SOURCE")) return root;
  return fs::path(__FILE__).parent_path().parent_path().parent_path();
}

// The shipped examples must stay valid.
TEST(Config, ExamplesParse) {
  const fs::path root = source_root();
  const SimulationSpec fluid = load_config(root / "examples/fluid/fluid.toml");
  ASSERT_EQ(fluid.species.size(), 1u);
  EXPECT_EQ(fluid.species[0].count, 98304u);
  EXPECT_DOUBLE_EQ(fluid.dt, 0.04);
  const SimulationSpec flow = load_config(root / "examples/poiseuille/poiseuille.toml");
  EXPECT_TRUE(flow.poiseuille.enabled);
  EXPECT_EQ(flow.poiseuille.bins, 40);
  EXPECT_EQ(flow.species[0].count, 6000u);
}

// The annotated example in docs/config.md (its first toml code block) must stay valid.
TEST(Config, DocumentationExampleParses) {
  const fs::path root = source_root();
  std::ifstream in(root / "docs/config.md");
  ASSERT_TRUE(in) << "cannot open docs/config.md";
  const std::string doc((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string fence = "```toml\n";
  const std::size_t begin = doc.find(fence);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```", begin + fence.size());
  ASSERT_NE(end, std::string::npos);
  const SimulationSpec spec =
      parse_config(doc.substr(begin + fence.size(), end - begin - fence.size()), "config.md");
  ASSERT_EQ(spec.species.size(), 2u);
  EXPECT_DOUBLE_EQ(spec.pair(0, 1).a, 40.0);
  EXPECT_TRUE(spec.poiseuille.enabled);
}

TEST(Config, PairStyleChoosesTheForceLaw) {
  EXPECT_EQ(parse_config(minimal_plus(""), "test.toml").pair_style, PairStyle::Dpd);
  const SimulationSpec soft = parse_config(minimal_plus("[pair]\nstyle = \"soft\"\na = 10.0\nrc = 0.9\n"), "test.toml");
  EXPECT_EQ(soft.pair_style, PairStyle::Soft);
  EXPECT_EQ(soft.pairs.at(0).a, 10.0);
  EXPECT_EQ(soft.pairs.at(0).rc, 0.9);
  expect_error(minimal_plus("[pair]\nstyle = \"sofft\"\n"), {"pair.style", "soft"});
  // Thermostat keys would be silently ignored by the soft law: refused, naming the key.
  expect_error(minimal_plus("[pair]\nstyle = \"soft\"\ngamma = 4.5\n"), {"pair.gamma", "soft"});
  expect_error(minimal_plus("[pair]\nstyle = \"soft\"\n\n[[pair.override]]\nspecies = [\"A\", \"A\"]\nrd = 0.8\n"),
               {"pair.override[0].rd", "soft"});
}

TEST(Config, FieldsTableAndArrayOfTables) {
  const SimulationSpec one = parse_config(minimal_plus(R"(
[[species]]
name = "W"
count = 10

[analysis.fields]
bins = [20, 1, 10]
lo = [0, 0, 2.5]
start = 100
every = 5
exclude = ["W"]
centre = "z"
)"), "test.toml");
  ASSERT_EQ(one.fields.size(), 1u);
  const FieldsSpec& f = one.fields[0];
  EXPECT_EQ(f.name, "fields");
  EXPECT_EQ(f.bins, (std::array<int, 3>{20, 1, 10}));
  EXPECT_EQ(f.region_lo, (std::array<double, 3>{0, 0, 2.5}));
  EXPECT_EQ(f.region_hi, (std::array<double, 3>{10, 10, 10}));
  EXPECT_EQ(f.start, 100u);
  EXPECT_EQ(f.every, 5u);
  EXPECT_EQ(f.selected, std::vector<int>{0});
  EXPECT_EQ(f.centre_axis, 2);
  EXPECT_EQ(f.fit, FieldsFit::None);
  const SimulationSpec two = parse_config(minimal_plus(R"(
[[analysis.fields]]
name = "map"
bins = [4, 4, 1]

[[analysis.fields]]
name = "profile"
bins = [1, 1, 40]
fit = "slab"
species = ["A"]
)"), "test.toml");
  ASSERT_EQ(two.fields.size(), 2u);
  EXPECT_EQ(two.fields[1].name, "profile");
  EXPECT_EQ(two.fields[1].fit, FieldsFit::Slab);
  EXPECT_EQ(two.fields[0].every, 10u);  // default
  EXPECT_EQ(two.fields[0].write_every, 0u);
  EXPECT_EQ(parse_config(minimal_plus("[analysis.fields]\nwrite_every = 500\n"), "test.toml").fields[0].write_every, 500u);
}

TEST(Config, RejectsBadFields) {
  const std::string two_species = "[[species]]\nname = \"W\"\ncount = 10\n\n";
  expect_error(minimal_plus("[analysis.fields]\nbins = [0, 1, 1]\n"), {"analysis.fields.bins[0] = 0", ">= 1"});
  expect_error(minimal_plus("[analysis.fields]\nbins = [2.5, 1, 1]\n"), {"analysis.fields.bins", "whole number"});
  expect_error(minimal_plus("[analysis.fields]\nbins = [2000, 2000, 2]\n"), {"analysis.fields.bins", "more than"});
  expect_error(minimal_plus("[analysis.fields]\nhi = [5, 11, 5]\n"), {"analysis.fields.hi[1] = 11", "system.box[1]"});
  expect_error(minimal_plus("[analysis.fields]\nlo = [5, 0, 0]\nhi = [4, 10, 10]\n"), {"analysis.fields.hi[0] = 4", "> lo[0]"});
  expect_error(minimal_plus("[analysis.fields]\nlo = [-1, 0, 0]\n"), {"analysis.fields.lo[0] = -1"});
  expect_error(minimal_plus("[analysis.fields]\nevery = 0\n"), {"analysis.fields.every"});
  expect_error(minimal_plus("[analysis.fields]\nblocks = 1\n"), {"analysis.fields.blocks = 1", ">= 2"});
  expect_error(minimal_plus("[analysis.fields]\nspecies = [\"B\"]\n"), {"analysis.fields.species", "unknown species \"B\""});
  expect_error(minimal_plus("[analysis.fields]\nexclude = [\"A\"]\n"), {"analysis.fields.exclude", "leaves no species"});
  expect_error(minimal_plus(two_species + "[analysis.fields]\nspecies = [\"A\"]\nexclude = [\"W\"]\n"),
               {"analysis.fields.exclude", "not allowed together"});
  expect_error(minimal_plus("[analysis.fields]\nspecies = [\"A\", \"A\"]\n"), {"listed twice"});
  expect_error(minimal_plus("[analysis.fields]\ncentre = \"q\"\n"), {"analysis.fields.centre", "\"x\""});
  expect_error(minimal_plus("[analysis.fields]\nfit = \"slab\"\nbins = [4, 1, 20]\n"),
               {"analysis.fields.fit", "exactly one axis"});
  expect_error(minimal_plus("[analysis.fields]\nfit = \"slab\"\nbins = [1, 1, 4]\n"), {"analysis.fields.bins[2] = 4", ">= 8"});
  expect_error(minimal_plus("[analysis.fields]\nname = \"a/b\"\n"), {"analysis.fields.name", "letters"});
  expect_error(minimal_plus("[[analysis.fields]]\nbins = [2, 1, 1]\n\n[[analysis.fields]]\nbins = [1, 2, 1]\n"),
               {"analysis.fields[1].name = \"fields\"", "also the name of analysis.fields[0]"});
  expect_error(minimal_plus("[analysis.fields]\nbinz = [2, 1, 1]\n"), {"analysis.fields.binz", "analysis.fields.bins"});
  expect_error(minimal_plus("[analysis]\nfields = 3\n"), {"analysis.fields", "array of tables"});
}

}  // namespace

TEST(Config, ManyBodyAndSplineStyles) {
  const std::string mdpd = "[pair]\nstyle = \"mdpd\"\na = -40\nb = 25\nrd = 0.75\nkernel = \"lucy\"\n";
  const SimulationSpec spec = parse_config(minimal_plus(mdpd), "test.toml");
  EXPECT_EQ(spec.pair_style, PairStyle::Mdpd);
  EXPECT_EQ(spec.pair(0, 0).a, -40.0);
  EXPECT_EQ(spec.pair(0, 0).value("b"), 25.0);
  EXPECT_EQ(spec.pair(0, 0).rd, 0.75);
  EXPECT_EQ(spec.pair_section.kernel, DensityKernelChoice::Lucy);
  // Bad input: a kernel that does not exist, r_d beyond r_c, a collapsing sign combination, missing keys.
  expect_error(minimal_plus("[pair]\nstyle = \"mdpd\"\na = -40\nb = 25\nrd = 0.75\nkernel = \"lucky\"\n"),
               {"pair.kernel", "\"warren\", \"lucy\"", "did you mean \"lucy\""});
  expect_error(minimal_plus("[pair]\nstyle = \"mdpd\"\na = -40\nb = 25\nrd = 1.2\n"),
               {"pair.rd = 1.2", "must not exceed rc = 1"});
  expect_error(minimal_plus("[pair]\nstyle = \"mdpd\"\na = -40\nb = 0\nrd = 0.75\n"), {"pair.b = 0", "collapses"});
  expect_error(minimal_plus("[pair]\nstyle = \"mdpd\"\na = -40\nb = -5\nrd = 0.75\n"), {"pair.b = -5", ">= 0"});
  expect_error(minimal_plus("[pair]\nstyle = \"mdpd\"\na = -40\nrd = 0.75\n"), {"pair.b", "missing", "B_ij"});
  expect_error(minimal_plus("[pair]\nstyle = \"mdpd\"\nb = 25\nrd = 0.75\n"), {"pair.a", "missing"});
  expect_error(minimal_plus("[pair]\na = 25\nb = 25\n"), {"pair.b = 25", "not used with pair.style = \"dpd\""});
  expect_error(minimal_plus("[pair]\nkernel = \"warren\"\n"), {"pair.kernel", "only used with pair.style = \"mdpd\""});
  expect_error(minimal_plus("[pair]\na = -1\n"), {"pair.a = -1", ">= 0"});
  expect_error(minimal_plus("[run]\nmax_density = 0\n"), {"run.max_density = 0", "> 0"});

  const std::string spline = "[pair]\nstyle = \"spline\"\na = 18.75\nrepulsion = 2.0\nrc1 = 0.8\nattraction = 1.0\nrc2 = 1.0\n";
  const SimulationSpec sp = parse_config(minimal_plus(spline + "[[pair.override]]\nspecies = [\"A\", \"A\"]\nattraction = 1.1\n"),
                                         "test.toml");
  EXPECT_EQ(sp.pair_style, PairStyle::Spline);
  EXPECT_EQ(sp.pair(0, 0).value("attraction"), 1.1);  // per pair
  EXPECT_EQ(sp.pair(0, 0).value("rc1"), 0.8);
  expect_error(minimal_plus("[pair]\nstyle = \"spline\"\na = 18.75\nrepulsion = 2.0\nrc1 = 0.8\nattraction = 1.0\n"),
               {"pair.rc2", "missing"});
  expect_error(minimal_plus("[pair]\nstyle = \"spline\"\na = 1\nrepulsion = 1.0\nrc1 = 0.8\nattraction = 1.0\nrc2 = 1\n"),
               {"pair.attraction = 1", "must be smaller than repulsion", "collapse"});
  expect_error(minimal_plus(spline + "b = 3\n"), {"pair.b = 3", "not used with pair.style = \"spline\""});
}

TEST(Config, ManyBodyMixtureWithDifferentBIsWarnedAbout) {
  const std::string two = R"(
[system]
box = [10, 10, 10]
[[species]]
name = "A"
density = 3
[[species]]
name = "B"
density = 3
[pair]
style = "mdpd"
a = -40
b = 25
rd = 0.75
)";
  EXPECT_TRUE(spec_warnings(parse_config(two, "test.toml")).empty());
  const auto w = spec_warnings(parse_config(two + "[[pair.override]]\nspecies = [\"A\", \"B\"]\nb = 20\n", "test.toml"));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("no potential"), std::string::npos) << w[0];
}


TEST(Config, DropletAnalysisErrorsNameTheirKey) {
  expect_error(minimal_plus("[analysis.droplet]\nouter_radius = 4\n"),
               {"analysis.droplet.inner_radius", "is required"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = 2\n"),
               {"analysis.droplet.outer_radius", "is required"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = 3\nouter_radius = 2\n"),
               {"analysis.droplet.outer_radius = 2", "must be > analysis.droplet.inner_radius (3)"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = 2\nouter_radius = 5\n"),
               {"analysis.droplet.outer_radius = 5", "half the smallest box length (5)"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = -1\nouter_radius = 4\n"),
               {"analysis.droplet.inner_radius = -1", "must be > 0"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = 1\nouter_radius = 4\nevery = 0\n"),
               {"analysis.droplet.every = 0"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = 1\nouter_radius = 4\nblocks = 1\n"),
               {"analysis.droplet.blocks = 1"});
  expect_error(minimal_plus("[analysis.droplet]\ninner_radius = 1\nouter_radius = 4\nradius = 3\n"),
               {"unknown key 'analysis.droplet.radius'"});
  expect_error("[system]\nbox = [10, 10, 12]\nperiodic = [true, true, false]\n[[species]]\nname = \"A\"\ndensity = 3\n"
               "[[species]]\nname = \"wall\"\nfrozen = true\n"
               "[[solid]]\nname = \"bottom\"\nspecies = \"wall\"\nshape = \"plane\"\npoint = [0, 0, 1]\nnormal = [0, 0, 1]\n"
               "[[solid]]\nname = \"top\"\nspecies = \"wall\"\nshape = \"plane\"\npoint = [0, 0, 11]\nnormal = [0, 0, -1]\n"
               "[analysis.droplet]\ninner_radius = 1\nouter_radius = 4\n",
               {"analysis.droplet", "periodic along every axis"});
  const SimulationSpec ok = parse_config(minimal_plus("[analysis.droplet]\ninner_radius = 1\nouter_radius = 4\n"), "t.toml");
  EXPECT_TRUE(ok.droplet.enabled);
  EXPECT_EQ(ok.droplet.every, 100u);
  EXPECT_EQ(ok.droplet.blocks, 10);
  EXPECT_DOUBLE_EQ(ok.droplet.bin_width, 0.1);
}


TEST(Config, CatastrophicSplineAttractionIsWarned) {
  // Liu's spline (a = 18.75, A = 2, r_c1 = 0.8, r_c2 = 1): B above A (r_c1/r_c2)^3 = 1.024 makes the
  // integral of U negative; B = 1.0 (Liu's single drop) is fine.
  auto spline = [](double b) {
    return minimal_plus("[pair]\nstyle = \"spline\"\na = 18.75\nrepulsion = 2.0\nrc1 = 0.8\nattraction = " +
                        std::to_string(b) + "\nrc2 = 1.0\n");
  };
  EXPECT_TRUE(spec_warnings(parse_config(spline(1.0), "test.toml")).empty());
  EXPECT_TRUE(spec_warnings(parse_config(spline(1.02), "test.toml")).empty());
  const auto w = spec_warnings(parse_config(spline(1.05), "test.toml"));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("catastrophic"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("1.024"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("(A, A)"), std::string::npos) << w[0];
}

}  // namespace mesodpd
