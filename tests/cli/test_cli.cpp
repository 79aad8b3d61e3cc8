// End-to-end tests of the mesodpd program: exit codes and error lines for bad input, blow-up
// handling, trajectory and thermo output, LAMMPS data import, restarts and thread independence.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/kinetic_theory.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct CliResult {
  int code = -1;  // exit status of the program (timeout's 124 on a hang, 128 + n on signal n)
  std::string out, err;
};

std::string slurp(const fs::path& path) { return mesodpd::test::read_file(path); }

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  ASSERT_TRUE(out.good()) << path;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// A fresh working directory per test, removed at the start (not the end, so a failure can be inspected).
fs::path work_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_cli" / info->name();
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Runs `mesodpd ARGS` in `dir` under `timeout 60`, with stdout and stderr captured to files.
CliResult mesodpd(const fs::path& dir, const std::string& args) {
  const std::string cmd = "cd '" + dir.string() + "' && OMP_NUM_THREADS=1 timeout 60 '" + mesodpd::test::mesodpd_bin() +
                          "' " + args + " > cli_stdout.txt 2> cli_stderr.txt";
  const int status = std::system(cmd.c_str());
  CliResult r;
  if (status != -1 && WIFEXITED(status)) r.code = WEXITSTATUS(status);
  r.out = slurp(dir / "cli_stdout.txt");
  r.err = slurp(dir / "cli_stderr.txt");
  return r;
}

// A 5 x 5 x 5 box at density 3 (375 particles): each run below takes a few milliseconds per step.
std::string small_config(const std::string& extra = "", const std::string& run = "steps = 20",
                         const std::string& output = "thermo_every = 5") {
  return "[system]\nbox = [5.0, 5.0, 5.0]\nseed = 7\n\n[[species]]\nname = \"A\"\ndensity = 3.0\n\n[run]\n" + run +
         "\n\n[output]\nprogress = false\n" + output + "\n\n" + extra;
}

const std::string kAllFields = R"(fields = ["id", "species", "position", "velocity", "force", "image"])";

std::string dump_section(int every, const std::string& format = "lammps", const std::string& fields = kAllFields) {
  return "[output.dump]\nformat = \"" + format + "\"\nevery = " + std::to_string(every) + "\n" + fields + "\n";
}

// One frame of a LAMMPS text dump: column names and one row of numbers per particle.
struct DumpFrame {
  std::uint64_t step = 0;
  std::size_t n = 0;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  std::size_t col(const std::string& name) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    EXPECT_NE(it, columns.end()) << "no column " << name;
    return static_cast<std::size_t>(it - columns.begin());
  }
};

std::vector<DumpFrame> read_dump(const fs::path& path) {
  std::vector<DumpFrame> frames;
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::string line;
  while (std::getline(in, line)) {
    EXPECT_EQ(line, "ITEM: TIMESTEP");
    if (line != "ITEM: TIMESTEP") break;
    DumpFrame f;
    in >> f.step;
    std::getline(in, line);
    std::getline(in, line);
    EXPECT_EQ(line, "ITEM: NUMBER OF ATOMS");
    in >> f.n;
    std::getline(in, line);
    std::getline(in, line);
    EXPECT_EQ(line, "ITEM: BOX BOUNDS pp pp pp");
    for (int d = 0; d < 3; ++d) in >> f.lo[d] >> f.hi[d];
    std::getline(in, line);
    std::getline(in, line);
    std::istringstream header(line);
    std::string word;
    header >> word >> word;  // "ITEM: ATOMS"
    while (header >> word) f.columns.push_back(word);
    for (std::size_t i = 0; i < f.n; ++i) {
      std::getline(in, line);
      std::istringstream row(line);
      std::vector<double> values;
      for (double v; row >> v;) values.push_back(v);
      EXPECT_EQ(values.size(), f.columns.size()) << "step " << f.step << " row " << i;
      f.rows.push_back(values);
    }
    frames.push_back(std::move(f));
  }
  return frames;
}

std::vector<std::uint64_t> thermo_steps(const fs::path& path) {
  std::vector<std::uint64_t> steps;
  const auto lines = lines_of(slurp(path));
  for (std::size_t k = 1; k < lines.size(); ++k) steps.push_back(std::stoull(lines[k]));
  return steps;
}

bool have_python_gsd() { return std::system("/usr/bin/python3 -c 'import gsd.hoomd, numpy' > /dev/null 2>&1") == 0; }

// ---------------------------------------------------------------------------------------------

TEST(Cli, VersionPrintsTheVersion) {
  const fs::path dir = work_dir();
  const CliResult r = mesodpd(dir, "--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_EQ(r.out, std::string("mesodpd ") + MESODPD_VERSION + "\n");
}

TEST(Cli, CheckAcceptsEveryExample) {
  const fs::path dir = work_dir();
  int checked = 0;
  for (const auto& entry : fs::recursive_directory_iterator(fs::path(mesodpd::test::source_dir()) / "examples")) {
    if (entry.path().extension() != ".toml") continue;
    const CliResult r = mesodpd(dir, "check '" + entry.path().string() + "'");
    EXPECT_EQ(r.code, 0) << entry.path() << ": " << r.err;
    EXPECT_NE(r.out.find("valid"), std::string::npos) << r.out;
    // The settings the file changes, from the declarations: every example sets the box.
    EXPECT_NE(r.out.find("\nsettings (other than the defaults):\n  system: box = ["), std::string::npos) << r.out;
    EXPECT_EQ(r.err, "");
    ++checked;
  }
  EXPECT_GE(checked, 2);
}

// Every class of bad input: exit code 2 and exactly one line on stderr, "error: ...", naming the
// key, option or file (all of `expect` must appear in it).
struct BadInput {
  std::string name;
  std::string config;  // written to bad.toml unless empty
  std::string args;    // command-line arguments after "mesodpd"
  std::vector<std::string> expect;
};

void expect_config_error(const fs::path& dir, const BadInput& c) {
  SCOPED_TRACE(c.name);
  if (!c.config.empty()) write_text(dir / "bad.toml", c.config);
  const CliResult r = mesodpd(dir, c.args);
  EXPECT_EQ(r.code, 2) << "stderr: " << r.err;
  const auto lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << "stderr: " << r.err;
  EXPECT_EQ(lines[0].rfind("error: ", 0), 0u) << lines[0];
  for (const auto& word : c.expect) EXPECT_NE(lines[0].find(word), std::string::npos) << "'" << word << "' not in: " << lines[0];
}

TEST(Cli, BadConfigsExitWithCodeTwoAndOneLine) {
  const fs::path dir = work_dir();
  const std::string sys = "[system]\nbox = [5.0, 5.0, 5.0]\n";
  const std::string a = "[[species]]\nname = \"A\"\ndensity = 3.0\n";
  const std::vector<BadInput> cases = {
      {"unknown key", small_config("", "stpes = 20"), "check bad.toml", {"bad.toml", "run.stpes", "run.steps"}},
      {"wrong type", sys + "[[species]]\nname = \"A\"\ndensity = \"three\"\n", "check bad.toml",
       {"bad.toml", "species[0].density"}},
      {"float for integer", small_config("", "steps = 10.5"), "check bad.toml", {"run.steps"}},
      {"integer beyond 64 bits", small_config("", "steps = 99999999999999999999"), "run bad.toml",
       {"bad.toml", "99999999999999999999"}},
      {"density", sys + "[[species]]\nname = \"A\"\ndensity = -3.0\n", "check bad.toml", {"species[0].density"}},
      {"dt", sys + a + "[integrator]\ndt = 0.0\n", "check bad.toml", {"integrator.dt"}},
      {"dt too large", sys + a + "[integrator]\ndt = 0.6\n", "run bad.toml", {"integrator.dt"}},
      {"cutoff", sys + a + "[pair]\nrc = 0.0\n", "check bad.toml", {"pair.rc"}},
      {"s", sys + a + "[pair]\ns = 11.0\n", "check bad.toml", {"pair.s"}},
      {"kT", "[system]\nbox = [5.0, 5.0, 5.0]\nkT = -1.0\n" + a, "check bad.toml", {"system.kT"}},
      {"mass", sys + a + "mass = 0.0\n", "check bad.toml", {"species[0].mass"}},
      {"nan", sys + a + "[pair]\ngamma = nan\n", "check bad.toml", {"pair.gamma"}},
      {"box below twice the cutoff", "[system]\nbox = [1.5, 5.0, 5.0]\n" + a, "run bad.toml", {"system.box"}},
      {"bounded axis (run)", "[system]\nbox = [5.0, 5.0, 5.0]\nperiodic = [true, false, true]\n" + a, "run bad.toml",
       {"system.periodic", "walls"}},
      {"bounded axis (check)", "[system]\nbox = [5.0, 5.0, 5.0]\nperiodic = [true, true, false]\n" + a,
       "check bad.toml", {"system.periodic", "walls"}},
      {"run.threads", small_config("", "steps = 2\nthreads = 100000"), "run bad.toml", {"run.threads"}},
      {"malformed TOML", "[system]\nbox = [5.0, 5.0\n", "check bad.toml", {"bad.toml", "TOML syntax error"}},
      {"missing config file (check)", "", "check no_such.toml", {"no_such.toml"}},
      {"missing config file (run)", "", "run no_such.toml", {"no_such.toml"}},
  };
  for (const auto& c : cases) expect_config_error(dir, c);
}

TEST(Cli, BadCommandLinesExitWithCodeTwoAndOneLine) {
  const fs::path dir = work_dir();
  write_text(dir / "ok.toml", small_config());
  const std::vector<BadInput> cases = {
      {"threads not a number", "", "run ok.toml --threads abc", {"--threads"}},
      {"threads negative", "", "run ok.toml --threads -1", {"--threads"}},
      {"threads absurd", "", "run ok.toml --threads 100000", {"--threads"}},
      {"steps negative", "", "run ok.toml --steps -5", {"--steps"}},
      {"steps not a number", "", "run ok.toml --steps many", {"--steps"}},
      {"steps with a suffix", "", "run ok.toml --steps 12x", {"--steps", "12x"}},
      // Beyond 2^64 - 1 and beyond run.steps' 2^63 - 1: refused, not clamped to the largest integer.
      {"steps beyond 64 bits", "", "run ok.toml --steps 99999999999999999999", {"--steps", "99999999999999999999"}},
      {"steps beyond run.steps", "", "run ok.toml --steps 9223372036854775808", {"--steps", "too large"}},
      {"unknown option", "", "run ok.toml --bogus", {"--bogus"}},
      {"no config", "", "run", {"config"}},
      {"no subcommand", "", "", {"subcommand"}},
      {"restart file missing", "", "run ok.toml --restart nowhere.mdpd", {"--restart", "nowhere.mdpd"}},
  };
  for (const auto& c : cases) expect_config_error(dir, c);
  EXPECT_FALSE(fs::exists(dir / "out")) << "a rejected command line must not start a run";
}

constexpr const char* kDataHeader =
    "data file written by test_cli\n\n4 atoms\n2 atom types\n-2.5 2.5 xlo xhi\n-2.5 2.5 ylo yhi\n-2.5 2.5 zlo zhi\n\n"
    "Masses\n\n1 1.0\n2 1.0\n\n";

std::string two_species_data_config(const std::string& data_file, const std::string& extra = "") {
  return "[system]\nbox = [5.0, 5.0, 5.0]\n\n[[species]]\nname = \"A\"\n\n[[species]]\nname = \"B\"\n\n[init]\n"
         "lammps_data = \"" + data_file + "\"\n" + extra + "\n[output]\nprogress = false\nthermo_every = 1\n";
}

TEST(Cli, BadDataFilesExitWithCodeTwoAndNameFileAndLine) {
  const fs::path dir = work_dir();
  write_text(dir / "bad.data", std::string(kDataHeader) +
                                   "Atoms # atomic\n\n10 1 0.0 0.0 0.0\n3 2 1.0 0.0 zz\n7 1 0.0 1.5 0.0\n21 2 -1.2 -1.2 2.0\n");
  write_text(dir / "style.data", std::string(kDataHeader) + "Atoms # full\n\n10 1 1 0.0 0.0 0.0 0.0\n");
  const std::vector<BadInput> cases = {
      {"missing data file", two_species_data_config("missing.data"), "run bad.toml", {"init.lammps_data", "missing.data"}},
      {"malformed data file (run)", two_species_data_config("bad.data"), "run bad.toml", {"bad.data", "line 17"}},
      {"malformed data file (check)", two_species_data_config("bad.data"), "check bad.toml", {"bad.data", "line 17"}},
      {"wrong atom style", two_species_data_config("style.data"), "check bad.toml", {"style.data"}},
  };
  for (const auto& c : cases) expect_config_error(dir, c);
}

TEST(Cli, DamagedCheckpointsAreRejected) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config());
  ASSERT_EQ(mesodpd(dir, "run run.toml --out out --steps 2").code, 0);
  const std::string good = slurp(dir / "out" / "checkpoint.mdpd");
  ASSERT_GT(good.size(), 100u);

  std::string flipped = good;
  flipped[good.size() / 2] = static_cast<char>(flipped[good.size() / 2] ^ 0x10);
  write_text(dir / "flipped.mdpd", flipped);
  write_text(dir / "short.mdpd", good.substr(0, good.size() - 9));
  write_text(dir / "notours.mdpd", "hello, world\n");
  write_text(dir / "other_seed.toml", small_config() + "\n");
  {
    std::string text = slurp(dir / "run.toml");
    text.replace(text.find("seed = 7"), 8, "seed = 8");
    write_text(dir / "other_seed.toml", text);
  }
  const std::vector<BadInput> cases = {
      {"flipped byte", "", "run run.toml --out o2 --restart flipped.mdpd", {"flipped.mdpd", "checksum"}},
      {"truncated", "", "run run.toml --out o2 --restart short.mdpd", {"short.mdpd", "truncated"}},
      {"not a checkpoint", "", "run run.toml --out o2 --restart notours.mdpd", {"notours.mdpd"}},
      {"other seed", "", "run other_seed.toml --out o2 --restart out/checkpoint.mdpd", {"system.seed"}},
      {"already past the end", "", "run run.toml --out o2 --steps 1 --restart out/checkpoint.mdpd", {"--steps", "step 2"}},
  };
  for (const auto& c : cases) expect_config_error(dir, c);
}

// A checkpoint of the state format before the particle field list (tag "MESODPD3", written by the
// program as it was then: tests/cli/data/format3_tiny.mdpd from format3_tiny.toml) is refused with
// the file and both format numbers named, not misread.
TEST(Cli, CheckpointOfAnOlderFormatIsRefused) {
  const fs::path dir = work_dir();
  const fs::path data = fs::path(mesodpd::test::source_dir()) / "tests" / "cli" / "data";
  fs::copy_file(data / "format3_tiny.mdpd", dir / "old.mdpd", fs::copy_options::overwrite_existing);
  fs::copy_file(data / "format3_tiny.toml", dir / "tiny.toml", fs::copy_options::overwrite_existing);
  expect_config_error(dir, {"format 3 checkpoint", "", "run tiny.toml --out o --steps 4 --restart old.mdpd",
                            {"old.mdpd", "format 3", "format 5"}});
  EXPECT_FALSE(fs::exists(dir / "o" / "thermo.csv"));
}

// A restart with another integrator.dt than the checkpoint's is refused: the stored forces and the
// noise amplitude belong to the checkpoint's dt. The same dt continues.
TEST(Cli, RestartWithAnotherTimeStepIsRefused) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config("[integrator]\ndt = 0.04\n"));
  write_text(dir / "other_dt.toml", small_config("[integrator]\ndt = 0.03\n"));
  ASSERT_EQ(mesodpd(dir, "run run.toml --out out --steps 4").code, 0);
  expect_config_error(dir, {"other dt", "", "run other_dt.toml --out o2 --steps 8 --restart out/checkpoint.mdpd",
                            {"integrator.dt", "0.03", "0.04", "checkpoint.mdpd"}});
  EXPECT_EQ(mesodpd(dir, "run run.toml --out out --steps 8 --restart out/checkpoint.mdpd").code, 0);
}

// With max_velocity = 6.5 this system blows up at step 13 (random start, large initial forces).
TEST(Cli, BlowUpExitsThreeAndKeepsTheLastCheckpoint) {
  const fs::path dir = work_dir();
  const std::string output = "thermo_every = 1\ncheckpoint_every = 5";
  write_text(dir / "blow.toml", small_config(dump_section(1), "steps = 40\nmax_velocity = 6.5", output));
  write_text(dir / "calm.toml", small_config(dump_section(1), "steps = 40\nmax_velocity = 1000.0", output));

  const CliResult r = mesodpd(dir, "run blow.toml --out out");
  ASSERT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("step 13"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("particle id 367"), std::string::npos) << r.err;
  // Output stops at the last good step; the checkpoint is the one of step 10.
  EXPECT_EQ(thermo_steps(dir / "out" / "thermo.csv").back(), 12u);
  EXPECT_EQ(read_dump(dir / "out" / "trajectory.lammpstrj").back().step, 12u);

  // The checkpoint loads, and the same run from it blows up at the same step and particle again.
  const CliResult again = mesodpd(dir, "run blow.toml --out out --restart out/checkpoint.mdpd");
  ASSERT_EQ(again.code, 3) << again.err;
  EXPECT_NE(again.err.find("step 13"), std::string::npos) << again.err;
  EXPECT_NE(again.err.find("particle id 367"), std::string::npos) << again.err;

  // With a larger max_velocity it goes on to the end, and the output directory then holds exactly
  // what an uninterrupted calm run writes: rows and frames 11, 12 of the failed runs are not repeated.
  const CliResult cont = mesodpd(dir, "run calm.toml --out out --restart out/checkpoint.mdpd");
  ASSERT_EQ(cont.code, 0) << cont.err;
  EXPECT_NE(cont.out.find("steps 10 -> 40"), std::string::npos) << cont.out;
  ASSERT_EQ(mesodpd(dir, "run calm.toml --out calm").code, 0);
  const auto steps = thermo_steps(dir / "out" / "thermo.csv");
  ASSERT_EQ(steps.size(), 41u);
  for (std::uint64_t k = 0; k < steps.size(); ++k) EXPECT_EQ(steps[k], k);
  EXPECT_EQ(slurp(dir / "out" / "thermo.csv"), slurp(dir / "calm" / "thermo.csv"));
  EXPECT_EQ(slurp(dir / "out" / "trajectory.lammpstrj"), slurp(dir / "calm" / "trajectory.lammpstrj"));
}

TEST(Cli, ZeroStepsWritesFrameZeroWithForces) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config(dump_section(10)));
  const CliResult r = mesodpd(dir, "run run.toml --out out --steps 0");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto frames = read_dump(dir / "out" / "trajectory.lammpstrj");
  ASSERT_EQ(frames.size(), 1u);
  const DumpFrame& f = frames[0];
  EXPECT_EQ(f.step, 0u);
  ASSERT_EQ(f.n, 375u);
  double sum[3] = {0, 0, 0}, largest = 0;
  for (const auto& row : f.rows)
    for (int d = 0; d < 3; ++d) {
      const double fd = row[f.col(std::string("f") + "xyz"[d])];
      sum[d] += fd;
      largest = std::max(largest, std::abs(fd));
    }
  EXPECT_GT(largest, 1.0) << "forces at step 0 are all zero";
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(sum[d], 0.0, 1e-9 * largest * 375) << "axis " << d;
  EXPECT_TRUE(fs::exists(dir / "out" / "checkpoint.mdpd"));
  EXPECT_EQ(thermo_steps(dir / "out" / "thermo.csv"), std::vector<std::uint64_t>{0});
}

TEST(Cli, LammpsDumpFramesAreInIdOrder) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config(dump_section(5)));
  ASSERT_EQ(mesodpd(dir, "run run.toml --out out --steps 23").code, 0);
  const auto frames = read_dump(dir / "out" / "trajectory.lammpstrj");
  ASSERT_EQ(frames.size(), 5u);  // steps 0, 5, 10, 15, 20
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const DumpFrame& f = frames[k];
    EXPECT_EQ(f.step, 5 * k);
    ASSERT_EQ(f.rows.size(), 375u);
    const std::size_t id = f.col("id"), x = f.col("x"), type = f.col("type");
    for (std::size_t i = 0; i < f.rows.size(); ++i) {
      EXPECT_EQ(f.rows[i][id], static_cast<double>(i + 1));
      EXPECT_EQ(f.rows[i][type], 1.0);
      EXPECT_GE(f.rows[i][x], f.lo[0]);
      EXPECT_LT(f.rows[i][x], f.hi[0]);
    }
  }
}

// The same run written as a LAMMPS dump and as GSD: the gsd package reads the GSD file, frame count
// and steps are right, particles are in id order, and the values are the float32 of the dump's.
TEST(Cli, GsdTrajectoryMatchesTheLammpsDump) {
  if (!have_python_gsd()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd not available";
  const fs::path dir = work_dir();
  write_text(dir / "lammps.toml", small_config(dump_section(5)));
  write_text(dir / "gsd.toml", small_config(dump_section(5, "gsd")));
  ASSERT_EQ(mesodpd(dir, "run lammps.toml --out out --steps 20").code, 0);
  ASSERT_EQ(mesodpd(dir, "run gsd.toml --out out --steps 20").code, 0);
  write_text(dir / "compare.py", R"(
import sys
import numpy as np
import gsd.hoomd

def read_dump(path):
    frames, lines, k = [], open(path).read().split("\n"), 0
    while k < len(lines) and lines[k] == "ITEM: TIMESTEP":
        step, n = int(lines[k + 1]), int(lines[k + 3])
        lo = np.array([float(lines[k + 5 + d].split()[0]) for d in range(3)])
        hi = np.array([float(lines[k + 5 + d].split()[1]) for d in range(3)])
        cols = lines[k + 8].split()[2:]
        rows = np.array([[float(v) for v in lines[k + 9 + i].split()] for i in range(n)])
        frames.append((step, lo, hi, {c: rows[:, j] for j, c in enumerate(cols)}))
        k += 9 + n
    return frames

dump = read_dump("out/trajectory.lammpstrj")
with gsd.hoomd.open("out/trajectory.gsd", "rb") as traj:
    assert len(traj) == len(dump) == 5, (len(traj), len(dump))
    for snap, (step, lo, hi, c) in zip(traj, dump):
        assert int(snap.configuration.step) == step, (snap.configuration.step, step)
        n = len(c["id"])
        assert snap.particles.N == n
        ids = snap.log["particles/id"]
        assert np.array_equal(ids, c["id"].astype(np.uint32)), "ids"
        assert np.all(np.diff(ids.astype(np.int64)) > 0), "ids not increasing"
        assert np.array_equal(snap.particles.typeid, (c["type"] - 1).astype(np.uint32)), "typeid"
        v = np.stack([c["vx"], c["vy"], c["vz"]], axis=1).astype(np.float32)
        assert np.array_equal(snap.particles.velocity, v), "velocity"
        f = np.stack([c["fx"], c["fy"], c["fz"]], axis=1).astype(np.float32)
        assert np.array_equal(snap.log["particles/force"], f), "force"
        img = np.stack([c["ix"], c["iy"], c["iz"]], axis=1).astype(np.int32)
        assert np.array_equal(snap.particles.image, img), "image"
        x = np.stack([c["x"], c["y"], c["z"]], axis=1) - (lo + 0.5 * (hi - lo))
        assert np.max(np.abs(snap.particles.position - x)) < 1e-5, "position"
print("ok")
)");
  const std::string cmd = "cd '" + dir.string() + "' && /usr/bin/python3 compare.py > py.txt 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "py.txt");
}

// 60 particles on a grid with ids 5, 10, ..., 300 and two types, in a box from -2.5 to 2.5.
std::string grid_data(bool with_velocities) {
  std::ostringstream s;
  s << "grid written by test_cli\n\n60 atoms\n2 atom types\n-2.5 2.5 xlo xhi\n-2.5 2.5 ylo yhi\n-2.5 2.5 zlo zhi\n\n"
    << "Atoms # atomic\n\n";
  for (int k = 0; k < 60; ++k)
    s << 5 * (60 - k) << ' ' << 1 + k % 2 << ' ' << -2.25 + 1.25 * (k % 4) << ' ' << -2.0 + 1.0 * ((k / 4) % 5) << ' '
      << -2.5 + 1.75 * (k / 20) << '\n';
  if (with_velocities) {
    s << "\nVelocities\n\n";
    for (int k = 0; k < 60; ++k) s << 5 * (60 - k) << ' ' << 0.125 * (k % 7) - 0.25 << ' ' << -0.5 + 0.0625 * k << " 1.5\n";
  }
  return s.str();
}

TEST(Cli, LammpsDataImport) {
  const fs::path dir = work_dir();
  write_text(dir / "plain.data", grid_data(false));
  write_text(dir / "vel.data", grid_data(true));
  const std::string dump = dump_section(10);
  write_text(dir / "plain.toml", two_species_data_config("plain.data", "velocities = \"maxwell\"") + dump);
  write_text(dir / "vel.toml", two_species_data_config("vel.data", "velocities = \"file\"") + dump);

  for (const std::string name : {"plain", "vel"}) {
    SCOPED_TRACE(name);
    const CliResult check = mesodpd(dir, "check " + name + ".toml");
    EXPECT_EQ(check.code, 0) << check.err;
    EXPECT_NE(check.out.find("60 particles"), std::string::npos) << check.out;
    const CliResult r = mesodpd(dir, "run " + name + ".toml --out " + name + " --steps 10");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto frames = read_dump(dir / name / "trajectory.lammpstrj");
    ASSERT_EQ(frames.size(), 2u);
    for (const DumpFrame& f : frames) {
      ASSERT_EQ(f.rows.size(), 60u);
      for (std::size_t i = 0; i < 60; ++i) {
        EXPECT_EQ(f.rows[i][f.col("id")], 5.0 * static_cast<double>(i + 1));
        EXPECT_EQ(f.rows[i][f.col("type")], 1.0 + static_cast<double>((60 - (i + 1)) % 2));
      }
    }
    // Step 0 holds the file's positions (relative to the box corner, since the dump's box may be shifted).
    const DumpFrame& f0 = frames[0];
    for (std::size_t i = 0; i < 60; ++i) {
      const int k = 60 - static_cast<int>(i + 1);
      EXPECT_EQ(f0.rows[i][f0.col("x")] - f0.lo[0], -2.25 + 1.25 * (k % 4) + 2.5);
      EXPECT_EQ(f0.rows[i][f0.col("y")] - f0.lo[1], -2.0 + 1.0 * ((k / 4) % 5) + 2.5);
      EXPECT_EQ(f0.rows[i][f0.col("z")] - f0.lo[2], -2.5 + 1.75 * (k / 20) + 2.5);
      if (name == "vel") {
        EXPECT_EQ(f0.rows[i][f0.col("vx")], 0.125 * (k % 7) - 0.25);
        EXPECT_EQ(f0.rows[i][f0.col("vy")], -0.5 + 0.0625 * k);
        EXPECT_EQ(f0.rows[i][f0.col("vz")], 1.5);
      }
    }
  }
}

// init.velocities = "file" (the default with init.lammps_data) needs a Velocities section in the data file.
TEST(Cli, DataFileWithoutVelocitiesNeedsAnotherVelocityInit) {
  const fs::path dir = work_dir();
  write_text(dir / "plain.data", grid_data(false));
  const std::vector<BadInput> cases = {
      {"default velocities (run)", two_species_data_config("plain.data"), "run bad.toml --out out",
       {"init.velocities", "plain.data", "Velocities"}},
      {"default velocities (check)", two_species_data_config("plain.data"), "check bad.toml",
       {"init.velocities", "plain.data", "Velocities"}},
      {"explicit file", two_species_data_config("plain.data", "velocities = \"file\""), "run bad.toml --out out",
       {"init.velocities", "plain.data", "Velocities"}},
  };
  for (const auto& c : cases) expect_config_error(dir, c);
  // The other choices accept the same file.
  for (const std::string v : {"maxwell", "zero"}) {
    SCOPED_TRACE(v);
    write_text(dir / "ok.toml", two_species_data_config("plain.data", "velocities = \"" + v + "\""));
    const CliResult r = mesodpd(dir, "run ok.toml --out ok_" + v + " --steps 2");
    EXPECT_EQ(r.code, 0) << r.err;
  }
}

// `check` refuses what `run` refuses before its first step, with the same message, for every refusal
// that does not depend on the MPI rank count (issue: check called 10^12 particles valid).
TEST(Cli, CheckRefusesWhatRunRefuses) {
  const fs::path dir = work_dir();
  write_text(dir / "heavy.data", std::string(kDataHeader).replace(std::string(kDataHeader).find("1 1.0"), 5, "1 2.0") +
                                     "Atoms # atomic\n\n1 1 0.0 0.0 0.0\n2 2 1.0 0.0 0.0\n3 1 0.0 1.0 0.0\n4 2 0.0 0.0 1.0\n");
  write_text(dir / "plain.data", grid_data(false));
  const std::string a = "[[species]]\nname = \"A\"\ndensity = 3.0\n";
  struct Case {
    std::string name, config;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {"10^12 particles", "[system]\nbox = [10000.0, 10000.0, 10000.0]\n[[species]]\nname = \"A\"\ndensity = 1.0\n",
       {"species[0].density", "32-bit"}},
      {"ids overflow over two species",
       "[system]\nbox = [5.0, 5.0, 5.0]\n[[species]]\nname = \"A\"\ncount = 3000000000\n"
       "[[species]]\nname = \"B\"\ncount = 2000000000\n",
       {"species[1].count", "5000000000"}},
      {"cutoff of an override beyond half the box",
       "[system]\nbox = [5.0, 5.0, 5.0]\n" + a + "[[pair.override]]\nspecies = [\"A\", \"A\"]\nrd = 3.0\n",
       {"system.box", ">= 6"}},
      {"run.threads", small_config("", "steps = 2\nthreads = 100000"), {"run.threads", "1024"}},
      {"grid finer than the cells", "[system]\nbox = [3.5, 5.0, 5.0]\n" + a + "[parallel]\ngrid = [4, 1, 1]\n",
       {"parallel.grid[0]", "fewer than 3 cells"}},
      {"split run with a box axis under 3 cells", "[system]\nbox = [2.5, 10.0, 10.0]\n" + a + "[parallel]\ngrid = [1, 2, 0]\n",
       {"system.box[0]", "3 cells"}},
      {"cells beyond what any rank count can index",
       "[system]\nbox = [100000.0, 100000.0, 100000.0]\n[[species]]\nname = \"A\"\ncount = 10\n",
       {"system.box", "neighbour cells"}},
      {"default rdf range beyond half the box", small_config("[analysis.rdf]\n"), {"analysis.rdf.rmax", "(default)"}},
      {"data file mass differs", two_species_data_config("heavy.data"), {"species[0].mass", "heavy.data"}},
      {"data file without velocities", two_species_data_config("plain.data"), {"init.velocities", "plain.data"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    write_text(dir / "bad.toml", c.config);
    const CliResult checked = mesodpd(dir, "check bad.toml");
    const CliResult ran = mesodpd(dir, "run bad.toml --out out --no-progress");
    EXPECT_EQ(checked.code, 2) << checked.out << checked.err;
    EXPECT_EQ(ran.code, 2) << ran.out << ran.err;
    EXPECT_EQ(checked.err, ran.err);
    ASSERT_EQ(lines_of(checked.err).size(), 1u) << checked.err;
    for (const auto& word : c.expect) EXPECT_NE(checked.err.find(word), std::string::npos) << word << " not in " << checked.err;
  }
  // A grid that only the rank count can refuse is left to `run`: on one rank, `check` accepts it.
  write_text(dir / "grid.toml", "[system]\nbox = [5.0, 5.0, 5.0]\n" + a + "[parallel]\ngrid = [4, 1, 1]\n");
  EXPECT_EQ(mesodpd(dir, "check grid.toml").code, 0);
}

// Uninterrupted run to step 30 against 10 steps then a restart to 30, for both neighbour methods.
TEST(Cli, RestartContinuesBitIdentically) {
  const fs::path dir = work_dir();
  for (const std::string method : {"cells", "verlet"}) {
    SCOPED_TRACE(method);
    const std::string extra = dump_section(5) + "\n[neighbor]\nmethod = \"" + method + "\"\n";
    write_text(dir / "run.toml", small_config(extra, "steps = 30", "thermo_every = 2"));
    const fs::path full = dir / ("full_" + method), part = dir / ("part_" + method);
    ASSERT_EQ(mesodpd(dir, "run run.toml --out " + full.string()).code, 0);
    ASSERT_EQ(mesodpd(dir, "run run.toml --out " + part.string() + " --steps 10").code, 0);
    const CliResult r = mesodpd(dir, "run run.toml --out " + part.string() + " --restart " +
                                         (part / "checkpoint.mdpd").string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("steps 10 -> 30"), std::string::npos) << r.out;
    // The restart appends: no step twice, and the same frames and rows as the uninterrupted run.
    EXPECT_EQ(slurp(part / "trajectory.lammpstrj"), slurp(full / "trajectory.lammpstrj"));
    EXPECT_EQ(thermo_steps(part / "thermo.csv"), thermo_steps(full / "thermo.csv"));
    // With cells the lists are rebuilt every step and the storage order after a restart is the
    // uninterrupted run's, so everything matches. A Verlet list is rebuilt (and the particles
    // re-sorted) on the first step after a restart: positions and velocities still match exactly,
    // but the order-dependent thermo sums (momentum ~1e-14) and the build count may not.
    if (method == "cells") {
      EXPECT_EQ(slurp(part / "thermo.csv"), slurp(full / "thermo.csv"));
      EXPECT_EQ(slurp(part / "checkpoint.mdpd"), slurp(full / "checkpoint.mdpd"));
    }
  }
}

// A restart into a new output directory starts new files after the checkpoint's step.
TEST(Cli, RestartIntoAnotherDirectory) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config(dump_section(5), "steps = 20", "thermo_every = 5"));
  ASSERT_EQ(mesodpd(dir, "run run.toml --out a --steps 10").code, 0);
  ASSERT_EQ(mesodpd(dir, "run run.toml --out b --restart a/checkpoint.mdpd").code, 0);
  EXPECT_EQ(thermo_steps(dir / "b" / "thermo.csv"), (std::vector<std::uint64_t>{15, 20}));
  const auto frames = read_dump(dir / "b" / "trajectory.lammpstrj");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].step, 15u);
}

// A GSD trajectory of a run that went past its last checkpoint must not repeat frames after a restart:
// the frames after the checkpoint's step (11 and 12) are dropped, like the LAMMPS dump's and thermo.csv's.
TEST(Cli, GsdRestartDoesNotRepeatFrames) {
  if (!have_python_gsd()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd not available";
  const fs::path dir = work_dir();
  const std::string output = "thermo_every = 1\ncheckpoint_every = 5";
  write_text(dir / "blow.toml", small_config(dump_section(1, "gsd"), "steps = 20\nmax_velocity = 6.5", output));
  write_text(dir / "calm.toml", small_config(dump_section(1, "gsd"), "steps = 20", output));
  ASSERT_EQ(mesodpd(dir, "run blow.toml --out out").code, 3);
  ASSERT_EQ(mesodpd(dir, "run calm.toml --out out --restart out/checkpoint.mdpd").code, 0);
  const std::string cmd = "cd '" + dir.string() +
                          "' && /usr/bin/python3 -c 'import gsd.hoomd; t = gsd.hoomd.open(\"out/trajectory.gsd\", \"rb\"); "
                          "print(\" \".join(str(f.configuration.step) for f in t))' > py.txt 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "py.txt");
  std::string expected;
  for (int k = 0; k <= 20; ++k) expected += std::to_string(k) + (k < 20 ? " " : "\n");
  EXPECT_EQ(slurp(dir / "py.txt"), expected);
}

TEST(Cli, ThreadCountDoesNotChangeResults) {
  const fs::path dir = work_dir();
  for (const std::string method : {"cells", "verlet"}) {
    SCOPED_TRACE(method);
    write_text(dir / "run.toml", small_config(dump_section(5) + "\n[neighbor]\nmethod = \"" + method + "\"\n",
                                              "steps = 20", "thermo_every = 1"));
    ASSERT_EQ(mesodpd(dir, "run run.toml --out t1 --threads 1").code, 0);
    const CliResult r = mesodpd(dir, "run run.toml --out t2 --threads 2");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("2 thread(s)"), std::string::npos) << r.out;
    EXPECT_EQ(slurp(dir / "t1" / "trajectory.lammpstrj"), slurp(dir / "t2" / "trajectory.lammpstrj"));
    EXPECT_EQ(slurp(dir / "t1" / "thermo.csv"), slurp(dir / "t2" / "thermo.csv"));
    EXPECT_EQ(slurp(dir / "t1" / "checkpoint.mdpd"), slurp(dir / "t2" / "checkpoint.mdpd"));
  }
}

TEST(Cli, ThermoCsvHeaderAndRows) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config());
  ASSERT_EQ(mesodpd(dir, "run run.toml --out out").code, 0);
  const auto lines = lines_of(slurp(dir / "out" / "thermo.csv"));
  ASSERT_EQ(lines.size(), 6u);  // header and steps 0, 5, ..., 20
  const std::string prefix =
      "step,time,temperature,pressure,pxx,pyy,pzz,pxy,pxz,pyz,momentum_x,momentum_y,momentum_z,potential_energy";
  EXPECT_EQ(lines[0].rfind(prefix, 0), 0u) << lines[0];
  const auto ncols = std::count(lines[0].begin(), lines[0].end(), ',');
  for (std::size_t k = 1; k < lines.size(); ++k) EXPECT_EQ(std::count(lines[k].begin(), lines[k].end(), ','), ncols);
  EXPECT_EQ(lines[1].rfind("0,0,1,", 0), 0u) << "Maxwell start at exactly kT: " << lines[1];
}

TEST(Cli, PoiseuilleWritesProfileViscosityAndPlot) {
  const fs::path dir = work_dir();
  const std::string flow = "[poiseuille]\nforce = 0.5\nbins = 4\nstart = 0\nevery = 1\nblocks = 2\n";
  write_text(dir / "run.toml", small_config(flow, "steps = 20"));
  const CliResult r = mesodpd(dir, "run run.toml --out out");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("viscosity eta ="), std::string::npos) << r.out;
  const std::string profile = slurp(dir / "out" / "poiseuille_profile.csv");
  EXPECT_GE(lines_of(profile).size(), 5u) << profile;  // header and 4 bins
  const std::string json = slurp(dir / "out" / "viscosity.json");
  EXPECT_NE(json.find("\"eta\":"), std::string::npos) << json;
  EXPECT_NE(json.find("\"samples\": 20"), std::string::npos) << json;
  const auto parsed = nlohmann::json::parse(json);  // throws on invalid JSON
  EXPECT_TRUE(parsed.at("eta").is_number()) << json;
  EXPECT_EQ(parsed.at("samples").get<int>(), 20);
  EXPECT_EQ(parsed.at("force").get<double>(), 0.5);
  EXPECT_NE(slurp(dir / "out" / "velocity_profile.svg").find("<svg"), std::string::npos);
}

// Two species at density 1.5 each with reverse Poiseuille flow; `ab` sets the A-B pair.
std::string poiseuille_mixture(const std::string& ab) {
  return "[system]\nbox = [5.0, 5.0, 5.0]\nseed = 7\n\n[[species]]\nname = \"A\"\ndensity = 1.5\n\n"
         "[[species]]\nname = \"B\"\ndensity = 1.5\n\n[[pair.override]]\nspecies = [\"A\", \"B\"]\n" +
         ab + "\n\n[run]\nsteps = 20\n\n[output]\nprogress = false\nthermo_every = 5\n\n"
              "[poiseuille]\nforce = 0.5\nbins = 4\nstart = 0\nevery = 1\nblocks = 2\n";
}

TEST(Cli, PoiseuilleMixtureWithOtherGammaHasNoKineticTheoryValue) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", poiseuille_mixture("gamma = 9.0"));
  const CliResult r = mesodpd(dir, "run run.toml --out out");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("no kinetic-theory value for species pairs with different gamma"), std::string::npos) << r.out;
  const auto json = nlohmann::json::parse(slurp(dir / "out" / "viscosity.json"));
  EXPECT_TRUE(json.at("eta").is_number());
  EXPECT_TRUE(json.at("eta_kinetic_theory").is_null());
  EXPECT_TRUE(json.at("gamma").is_null());
  // Only `a` differing: kinetic theory does not see the conservative force, so the one-fluid value applies.
  write_text(dir / "run.toml", poiseuille_mixture("a = 40.0"));
  const CliResult q = mesodpd(dir, "run run.toml --out out2");
  ASSERT_EQ(q.code, 0) << q.err;
  EXPECT_NE(q.out.find("kinetic theory, seed 000 Eq. 16 / Table 1: "), std::string::npos) << q.out;
  const auto json2 = nlohmann::json::parse(slurp(dir / "out2" / "viscosity.json"));
  const double rho = json2.at("density").get<double>();
  EXPECT_NEAR(rho, 3.0, 0.01);
  EXPECT_NEAR(json2.at("eta_kinetic_theory").get<double>(), mesodpd::kinetic_viscosity(rho, 4.5, 1.0, 1.0, 2.0), 1e-7);
}

TEST(Cli, OverheatedRunWarnsAndSaysWhatToChange) {
  const fs::path dir = work_dir();
  // 300 steps: the heat of the random initial placement is gone in the second half, which is judged.
  // dt = 0.1 is 2.5 times the standard step: the Groot-Warren scheme then runs about 30% hot.
  write_text(dir / "hot.toml", small_config("[integrator]\ndt = 0.1\n", "steps = 300"));
  const CliResult hot = mesodpd(dir, "run hot.toml --out hot");
  EXPECT_EQ(hot.code, 0) << hot.err;  // a warning, not an error: the run finished
  EXPECT_NE(hot.err.find("warning: over the second half of the run the mean temperature"), std::string::npos)
      << hot.err;
  EXPECT_NE(hot.err.find("above the target kT = 1"), std::string::npos) << hot.err;
  EXPECT_NE(hot.err.find("reduce integrator.dt (now 0.1)"), std::string::npos) << hot.err;
  EXPECT_NE(hot.err.find("integrator.lambda"), std::string::npos) << hot.err;
  EXPECT_NE(hot.out.find("warning: over the second half"), std::string::npos) << hot.out;  // also in the summary
  // The standard dt on the same system stays within the tolerance: no warning.
  write_text(dir / "ok.toml", small_config("", "steps = 300"));
  const CliResult ok = mesodpd(dir, "run ok.toml --out ok");
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(ok.err.find("warning"), std::string::npos) << ok.err;
  EXPECT_EQ(ok.out.find("warning"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("mean temperature"), std::string::npos) << ok.out;
}

// The banner line of `mesodpd run` started with `env` (e.g. "-u OMP_WAIT_POLICY GOMP_SPINCOUNT=7").
std::string banner_with_env(const fs::path& dir, const std::string& env) {
  const std::string cmd = "cd '" + dir.string() + "' && env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT " + env +
                          " OMP_NUM_THREADS=2 timeout 60 '" + mesodpd::test::mesodpd_bin() +
                          "' run run.toml --out out > cli_stdout.txt 2> cli_stderr.txt";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << slurp(dir / "cli_stderr.txt");
  const auto lines = lines_of(slurp(dir / "cli_stdout.txt"));
  return lines.empty() ? "" : lines.front();
}

TEST(Cli, WaitingThreadsSpinBrieflyUnlessTheUserChose) {
  const fs::path dir = work_dir();
  write_text(dir / "run.toml", small_config("", "steps = 2"));
  // Nothing set: the program re-executes itself with a short spin before OpenMP starts.
  EXPECT_NE(banner_with_env(dir, "").find("2 thread(s) per rank (GOMP_SPINCOUNT=1000)"), std::string::npos);
  // A user's choice stands.
  EXPECT_NE(banner_with_env(dir, "GOMP_SPINCOUNT=50000").find("(GOMP_SPINCOUNT=50000)"), std::string::npos);
  EXPECT_NE(banner_with_env(dir, "OMP_WAIT_POLICY=active").find("(OMP_WAIT_POLICY=active)"), std::string::npos);
}

TEST(Cli, RdfAndMsdAreWritten) {
  const fs::path dir = work_dir();
  const std::string analysis = "[analysis.rdf]\nbins = 20\nrmax = 2.0\nevery = 5\n\n[analysis.msd]\nevery = 2\n";
  write_text(dir / "run.toml", small_config(analysis, "steps = 20"));
  const CliResult r = mesodpd(dir, "run run.toml --out out");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GE(lines_of(slurp(dir / "out" / "rdf.csv")).size(), 20u);
  EXPECT_GE(lines_of(slurp(dir / "out" / "msd.csv")).size(), 10u);
  EXPECT_NE(r.out.find("self-diffusion coefficient"), std::string::npos) << r.out;
}

}  // namespace
