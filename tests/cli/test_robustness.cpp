// End-to-end tests of the program against faults and hostile inputs (issue 24): output that cannot be
// written, two runs into one output folder, bonds and atoms out of range in a data file, restarts with a
// changed config, empty systems, runaway temperatures and fixed-point sums out of range.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct CliResult {
  int code = -1;
  std::string out, err;
};

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

fs::path work_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_robustness" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string command(const fs::path& dir, const std::string& args, const std::string& tag) {
  return "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 timeout 120 '" + mesodpd::test::mesodpd_bin() + "' " + args +
         " > " + tag + "_stdout.txt 2> " + tag + "_stderr.txt";
}

CliResult run_mesodpd(const fs::path& dir, const std::string& args, const std::string& tag = "cli") {
  const int status = std::system(command(dir, args, tag).c_str());
  CliResult r;
  if (status != -1 && WIFEXITED(status)) r.code = WEXITSTATUS(status);
  r.out = mesodpd::test::read_file(dir / (tag + "_stdout.txt"));
  r.err = mesodpd::test::read_file(dir / (tag + "_stderr.txt"));
  return r;
}

bool contains(const std::string& text, const std::string& word) { return text.find(word) != std::string::npos; }

std::string small_config(const std::string& extra = "", const std::string& run = "steps = 20",
                         const std::string& output = "thermo_every = 5") {
  return "[system]\nbox = [5.0, 5.0, 5.0]\nseed = 7\n\n[[species]]\nname = \"A\"\ndensity = 3.0\n\n[run]\n" + run +
         "\n\n[output]\nprogress = false\n" + output + "\n\n" + extra;
}

}  // namespace

// Full disk from the start (every write to thermo.csv fails, as on /dev/full): exit 2 naming thermo.csv,
// the first file that failed, and no "over N thermo rows" for rows that were never written.
TEST(Robustness, UnwritableThermoFileStopsTheRunNamingIt) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path dir = work_dir();
  write_text(dir / "c.toml", small_config("", "steps = 20", "thermo_every = 5\ncheckpoint_every = 10"));
  fs::create_directories(dir / "out");
  fs::create_symlink("/dev/full", dir / "out" / "thermo.csv");
  const CliResult r = run_mesodpd(dir, "run c.toml --out out");
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_TRUE(contains(r.err, "thermo.csv")) << r.err;
  EXPECT_TRUE(contains(r.err, "No space left")) << r.err;
  EXPECT_FALSE(contains(r.out, "thermo rows")) << r.out;
}

// A trajectory that cannot be written is reported the same way.
TEST(Robustness, UnwritableDumpStopsTheRunNamingIt) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const fs::path dir = work_dir();
  write_text(dir / "c.toml", small_config("[output.dump]\nformat = \"lammps\"\nevery = 10\n"));
  fs::create_directories(dir / "out");
  fs::create_symlink("/dev/full", dir / "out" / "trajectory.lammpstrj");
  const CliResult r = run_mesodpd(dir, "run c.toml --out out");
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_TRUE(contains(r.err, "trajectory.lammpstrj")) << r.err;
}

// Two runs into one output folder: while the first is alive, the second is refused (exit 2, naming the
// folder and the holder) and the first ends normally with its own rows.
TEST(Robustness, SecondLiveRunIntoTheSameFolderIsRefused) {
  const fs::path dir = work_dir();
  write_text(dir / "long.toml", small_config("", "steps = 100000"));
  write_text(dir / "other.toml", small_config("", "steps = 20"));
  // The first run in the background; its exit code lands in first.rc.
  const std::string first = "(" + command(dir, "run long.toml --out S", "first") + "; echo $? > '" +
                            (dir / "first.rc").string() + "') &";
  ASSERT_EQ(std::system(first.c_str()), 0);
  for (int k = 0; k < 600 && !fs::exists(dir / "S" / "thermo.csv"); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(fs::exists(dir / "S" / "mesodpd.lock"));
  const CliResult second = run_mesodpd(dir, "run other.toml --out S", "second");
  EXPECT_EQ(second.code, 2) << second.out << second.err;
  EXPECT_TRUE(contains(second.err, "'S' is in use by pid")) << second.err;
  EXPECT_TRUE(contains(second.err, "mesodpd.lock")) << second.err;
  // Stop the first run (it would take minutes) the way a user would, and wait for it.
  const std::string holder = mesodpd::test::read_file(dir / "S" / "mesodpd.lock");
  const auto pid = std::stol(holder.substr(holder.find("pid ") + 4));
  ASSERT_GT(pid, 1);
  ::kill(static_cast<pid_t>(pid), SIGKILL);
  for (int k = 0; k < 600 && !fs::exists(dir / "first.rc"); ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  // The killed run's lock is stale: the next run takes the folder over.
  const CliResult third = run_mesodpd(dir, "run other.toml --out S", "third");
  EXPECT_EQ(third.code, 0) << third.err;
  EXPECT_FALSE(fs::exists(dir / "S" / "mesodpd.lock"));  // a run that ends removes its lock file
}

// A killed run's lock file and the temporaries of its atomic writes: taken over and removed.
TEST(Robustness, StaleLockAndTemporariesOfKilledRunsAreCleanedUp) {
  const fs::path dir = work_dir();
  write_text(dir / "c.toml", small_config());
  fs::create_directories(dir / "S");
  write_text(dir / "S" / "mesodpd.lock", "pid 999999 on host gone\n");
  write_text(dir / "S" / "checkpoint.mdpd.tmp.999999", std::string(1000, 'x'));
  write_text(dir / "S" / "notes.tmp.txt", "kept: not a temporary of ours\n");
  const CliResult r = run_mesodpd(dir, "run c.toml --out S");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir / "S" / "checkpoint.mdpd.tmp.999999"));
  EXPECT_TRUE(fs::exists(dir / "S" / "notes.tmp.txt"));
  EXPECT_TRUE(fs::exists(dir / "S" / "checkpoint.mdpd"));
}

namespace {

// Two bonded beads and two loose ones in a box of 6 (a data file), with one FENE bond type.
std::string bonded_data(double bond_length) {
  return "two beads and a FENE bond\n\n4 atoms\n1 atom types\n1 bonds\n1 bond types\n"
         "0 6 xlo xhi\n0 6 ylo yhi\n0 6 zlo zhi\n\nMasses\n\n1 1.0\n\nAtoms # molecular\n\n"
         "1 1 1 1.0 3.0 3.0\n2 1 1 " + std::to_string(1.0 + bond_length) + " 3.0 3.0\n3 2 1 4.5 1.0 1.0\n"
         "4 3 1 4.5 5.0 5.0\n\nBonds\n\n1 1 1 2\n";
}

std::string bonded_config(const std::string& data) {
  return "[system]\nbox = [6.0, 6.0, 6.0]\n\n[[species]]\nname = \"A\"\n\n[init]\nlammps_data = \"" + data +
         "\"\nvelocities = \"zero\"\n\n[[bond_type]]\nname = \"f\"\nstyle = \"fene\"\nk = 30.0\nrmax = 1.5\n\n"
         "[run]\nsteps = 5\n\n[output]\nprogress = false\nthermo_every = 1\n";
}

}  // namespace

// A FENE bond given longer than rmax in a data file: `run` stops with the blow-up code 3 naming the
// bond, its ids and its length, before any step; `check` refuses the file the same way.
TEST(Robustness, BondPastItsMaximumInTheDataFileIsRefusedByRunAndCheck) {
  const fs::path dir = work_dir();
  write_text(dir / "long.data", bonded_data(1.6));
  write_text(dir / "long.toml", bonded_config("long.data"));
  for (const std::string cmd : {"run long.toml --out out", "check long.toml"}) {
    SCOPED_TRACE(cmd);
    const CliResult r = run_mesodpd(dir, cmd);
    EXPECT_EQ(r.code, 3) << r.out << r.err;
    for (const std::string word : {"long.data", "bond 1 ", "particle ids 1 and 2", "1.6", "bond_type[0].rmax = 1.5", "FENE"})
      EXPECT_TRUE(contains(r.err, word)) << "'" << word << "' not in: " << r.err;
    EXPECT_FALSE(contains(r.err, "integrator.dt")) << r.err;
  }
  // A bond within its limit runs.
  write_text(dir / "ok.data", bonded_data(1.2));
  write_text(dir / "ok.toml", bonded_config("ok.data"));
  EXPECT_EQ(run_mesodpd(dir, "check ok.toml").code, 0);
  EXPECT_EQ(run_mesodpd(dir, "run ok.toml --out ok").code, 0);
}

// An atom far outside the box of a data file is refused naming the file, its line and the atom, not
// wrapped in silence; one on the upper bound is inside.
TEST(Robustness, AtomOutsideTheBoxOfADataFileIsRefusedNamingTheLine) {
  const fs::path dir = work_dir();
  const std::string head = "atoms\n\n2 atoms\n1 atom types\n0 6 xlo xhi\n0 6 ylo yhi\n0 6 zlo zhi\n\nAtoms # atomic\n\n";
  write_text(dir / "far.data", head + "1 1 1.0 1.0 1.0\n2 1 50.0 3.0 3.0\n");
  write_text(dir / "edge.data", head + "1 1 1.0 1.0 1.0\n2 1 6.0 3.0 0.0\n");
  auto config = [](const std::string& data) {
    return "[system]\nbox = [6.0, 6.0, 6.0]\n\n[[species]]\nname = \"A\"\n\n[init]\nlammps_data = \"" + data +
           "\"\nvelocities = \"zero\"\n\n[run]\nsteps = 2\n\n[output]\nprogress = false\n";
  };
  write_text(dir / "far.toml", config("far.data"));
  write_text(dir / "edge.toml", config("edge.data"));
  for (const std::string cmd : {"check far.toml", "run far.toml --out out"}) {
    const CliResult r = run_mesodpd(dir, cmd);
    EXPECT_EQ(r.code, 2) << cmd << ": " << r.err;
    for (const std::string word : {"far.data", "line 12", "atom 2", "x = 50", "[0, 6]"})
      EXPECT_TRUE(contains(r.err, word)) << "'" << word << "' not in: " << r.err;
  }
  EXPECT_EQ(run_mesodpd(dir, "check edge.toml").code, 0);
}

// A restart whose config describes another system than the checkpoint holds is refused naming the
// key and both values; the unchanged config continues.
TEST(Robustness, RestartWithAChangedBoxOrSpeciesIsRefusedNamingTheKey) {
  const fs::path dir = work_dir();
  auto config = [](const std::string& box, const std::string& species) {
    return "[system]\nbox = " + box + "\nseed = 7\n\n[[species]]\n" + species +
           "\n\n[run]\nsteps = 20\n\n[output]\nprogress = false\nthermo_every = 5\n";
  };
  const std::string box = "[5.0, 5.0, 5.0]", species = "name = \"A\"\ndensity = 3.0";
  write_text(dir / "base.toml", config(box, species));
  ASSERT_EQ(run_mesodpd(dir, "run base.toml --out first --steps 10").code, 0);
  struct Case {
    std::string name, toml, key, theirs;
  };
  const std::vector<Case> cases = {
      {"box", config("[5.0, 5.0, 6.0]", species), "system.box", "[5, 5, 5]"},
      {"name", config(box, "name = \"B\"\ndensity = 3.0"), "species[0].name", "\"A\""},
      {"mass", config(box, species + "\nmass = 2.0"), "species[0].mass", "1"},
      {"count", config(box, "name = \"A\"\ncount = 370"), "species[0].count", "375"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_text(dir / "changed.toml", c.toml);
    const CliResult r = run_mesodpd(dir, "run changed.toml --out again --restart first/checkpoint.mdpd");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("error: " + c.key + ": ", 0), 0u) << r.err;
    EXPECT_TRUE(contains(r.err, "checkpoint's " + c.theirs)) << r.err;
    EXPECT_TRUE(contains(r.err, "first/checkpoint.mdpd")) << r.err;
  }
  EXPECT_EQ(run_mesodpd(dir, "run base.toml --out first --restart first/checkpoint.mdpd").code, 0);
}

// A system without particles is refused naming the key, by check and run alike.
TEST(Robustness, EmptySystemIsRefusedNamingTheKey) {
  const fs::path dir = work_dir();
  const std::string head = "[system]\nbox = [5.0, 5.0, 5.0]\n\n";
  write_text(dir / "one.toml", head + "[[species]]\nname = \"A\"\ncount = 0\n");
  write_text(dir / "two.toml", head + "[[species]]\nname = \"A\"\ncount = 0\n\n[[species]]\nname = \"B\"\ncount = 0\n");
  write_text(dir / "thin.toml", head + "[[species]]\nname = \"A\"\ndensity = 0.001\n");
  for (const std::string cmd : {"check one.toml", "run one.toml --out o", "check two.toml", "run thin.toml --out o"}) {
    SCOPED_TRACE(cmd);
    const CliResult r = run_mesodpd(dir, cmd);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "empty")) << r.err;
    EXPECT_TRUE(contains(r.err, cmd.find("thin") != std::string::npos ? "species[0].density" : "species[0].count"))
        << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "o" / "thermo.csv"));
}

// A run that ends far above kT (here dt = 0.15 heats the fluid to about 12 kT) exits with the blow-up
// code after writing its outputs, unless run.max_temperature_ratio switches the guard off.
TEST(Robustness, RunawayTemperatureExitsWithCodeThreeUnlessAllowed) {
  const fs::path dir = work_dir();
  const std::string hot = "[system]\nbox = [5.0, 5.0, 5.0]\nseed = 7\n\n[[species]]\nname = \"A\"\ndensity = 3.0\n\n"
                          "[integrator]\ndt = 0.15\n\n[output]\nprogress = false\nthermo_every = 10\n\n[run]\nsteps = 200\n";
  write_text(dir / "hot.toml", hot);
  const CliResult r = run_mesodpd(dir, "run hot.toml --out hot");
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_TRUE(contains(r.err, "error: the run ran away")) << r.err;
  EXPECT_TRUE(contains(r.err, "run.max_temperature_ratio = 2")) << r.err;
  EXPECT_TRUE(fs::exists(dir / "hot" / "checkpoint.mdpd"));
  write_text(dir / "allowed.toml", hot + "max_temperature_ratio = 0.0\n");
  const CliResult allowed = run_mesodpd(dir, "run allowed.toml --out allowed");
  EXPECT_EQ(allowed.code, 0) << allowed.err;
  write_text(dir / "wider.toml", hot + "max_temperature_ratio = 20.0\n");
  EXPECT_EQ(run_mesodpd(dir, "run wider.toml --out wider").code, 0);
  // A run shorter than 2 time units (here 1.5) is not judged: it may still carry a random start's heat.
  const CliResult short_run = run_mesodpd(dir, "run hot.toml --out short --steps 10");
  EXPECT_EQ(short_run.code, 0) << short_run.err;
}

// Forces beyond what the fixed-point sums hold (a = 1e11 with heavy particles, so no velocity guard
// trips; or dt = 1e-300, whose random force is ~1e150) stop the run at step 0 with exit 3, naming the
// pair and the quantity, the same on one and two threads; the standard fluid is untouched.
TEST(Robustness, FixedPointOverflowStopsTheRunNamingThePair) {
  const fs::path dir = work_dir();
  auto config = [](const std::string& a, const std::string& mass, const std::string& dt) {
    return "[system]\nbox = [6.0, 6.0, 6.0]\nseed = 7\n\n[[species]]\nname = \"A\"\ndensity = 3.0\nmass = " + mass +
           "\n\n[pair]\na = " + a + "\n\n[integrator]\ndt = " + dt +
           "\n\n[run]\nsteps = 20\nmax_velocity = 1e300\n\n[output]\nprogress = false\nthermo_every = 10\n";
  };
  write_text(dir / "strong.toml", config("1e11", "1e9", "0.04"));
  write_text(dir / "tiny_dt.toml", config("25.0", "1.0", "1e-300"));
  write_text(dir / "normal.toml", config("25.0", "1.0", "0.04"));
  for (const std::string name : {"strong", "tiny_dt"}) {
    SCOPED_TRACE(name);
    std::string first_error;
    for (const std::string threads : {"1", "2"}) {
      const CliResult r = run_mesodpd(dir, "run " + name + ".toml --out " + name + threads + " --threads " + threads);
      EXPECT_EQ(r.code, 3) << r.err;
      for (const std::string word : {"fixed-point overflow at step 0", "force component of the pair of particle ids",
                                     "per pair that the fixed-point sums represent"})
        EXPECT_TRUE(contains(r.err, word)) << "'" << word << "' not in: " << r.err;
      EXPECT_FALSE(contains(r.out, "thermo rows")) << r.out;
      const std::string line = r.err.substr(r.err.find("error: "));
      if (first_error.empty()) first_error = line;
      EXPECT_EQ(line, first_error);
    }
  }
  const CliResult ok = run_mesodpd(dir, "run normal.toml --out normal");
  EXPECT_EQ(ok.code, 0) << ok.err;
}
