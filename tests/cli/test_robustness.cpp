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

