// Checked output: OutputFile reports every failed write naming the file, and a run whose output
// cannot be written stops there, keeping what it wrote and its last good checkpoint.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <filesystem>
#include <string>

#include "analysis/observers.hpp"
#include "engine/simulation.hpp"
#include "io/atomic_file.hpp"
#include "io/output_file.hpp"
#include "io/output_lock.hpp"
#include "io/state_checkpoint.hpp"
#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace mesodpd;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_output_file" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Removes the injected fault when a test ends, whatever happens.
struct FaultGuard {
  ~FaultGuard() { set_output_fault_hook({}); }
};

std::size_t count_lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

TEST(OutputFile, WritesTextAndIntegersAndAppends) {
  const fs::path dir = fresh_dir("append");
  {
    OutputFile f(dir / "a.csv", OutputFile::Mode::Truncate);
    f << "step," << 'x' << '\n' << std::uint64_t{42} << ',' << -7 << '\n';
    f.close();
  }
  {
    OutputFile f(dir / "a.csv", OutputFile::Mode::Append);
    f.write("9,9\n");
    f.close();
  }
  EXPECT_EQ(test::read_file(dir / "a.csv"), "step,x\n42,-7\n9,9\n");
}

TEST(OutputFile, FullDeviceFailsTheFlushNamingTheFile) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  OutputFile f("/dev/full", OutputFile::Mode::Append);
  f << "step\n";
  try {
    f.flush();
    FAIL() << "a write to /dev/full succeeded";
  } catch (const OutputError& e) {
    EXPECT_EQ(e.path(), fs::path("/dev/full"));
    EXPECT_NE(std::string(e.what()).find("'/dev/full'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No space left"), std::string::npos) << e.what();
  }
  // Once failed, the file stays failed: no later row is written after a gap.
  EXPECT_THROW(f.write("1\n"), OutputError);
}

TEST(OutputFile, OpenFailureNamesTheFile) {
  const fs::path dir = fresh_dir("open");
  try {
    OutputFile f(dir / "no_such_dir" / "thermo.csv", OutputFile::Mode::Truncate);
    FAIL() << "opened a file in a missing directory";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_dir/thermo.csv"), std::string::npos) << e.what();
  }
}

TEST(OutputFile, InjectedFaultReachesAtomicFilesToo) {
  const fs::path dir = fresh_dir("atomic");
  FaultGuard guard;
  set_output_fault_hook([](const fs::path& p) { return p.filename() == "summary.json" ? ENOSPC : 0; });
  EXPECT_THROW(write_file_atomically(dir / "summary.json", [](std::ostream& os) { os << "{}\n"; }), ConfigError);
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
  OutputFile other(dir / "other.csv", OutputFile::Mode::Truncate);
  EXPECT_NO_THROW(other.write("fine\n"));
}

// The full-disk spell: thermo rows stop arriving in the middle of a run. The run stops at the
// first row that could not be written, naming thermo.csv; the file holds exactly the rows the run
// counted, and the last checkpoint before the failure is intact.
TEST(OutputFile, RunStopsAtTheFirstThermoRowThatCannotBeWritten) {
  const fs::path dir = fresh_dir("run");
  FaultGuard guard;
  SimulationSpec spec = test::fluid_spec(5, 5, 5, 3.0);
  spec.steps = 60;
  spec.thermo_every = 5;
  spec.checkpoint_every = 10;
  RunOptions opt;
  opt.out_dir = dir;
  int thermo_writes = 0;
  // Header and rows of steps 0..20 arrive (6 writes); from step 25 on the disk is full.
  set_output_fault_hook([&](const fs::path& p) {
    if (p.filename() != "thermo.csv") return 0;
    return ++thermo_writes > 6 ? ENOSPC : 0;
  });
  Simulation sim(spec, opt);
  try {
    sim.run();
    FAIL() << "the run ended although thermo.csv could not be written";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("thermo.csv"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.current_step(), 25u);
  const std::string thermo = test::read_file(dir / "thermo.csv");
  EXPECT_EQ(count_lines(thermo), 1u + 5u) << thermo;  // header and steps 0..20
  EXPECT_EQ(sim.observers().history().size(), 5u);   // the rows it wrote, no more
  set_output_fault_hook({});
  const StateCheckpoint c = read_state_checkpoint(dir / "checkpoint.mdpd");
  EXPECT_EQ(c.header.step, 20u);
}

// Two simulations of one process with the same output folder: the second is refused while the first
// lives, and allowed once it is gone.
TEST(OutputLock, SecondSimulationWithTheSameFolderIsRefused) {
  const fs::path dir = fresh_dir("lock");
  SimulationSpec spec = test::fluid_spec(5, 5, 5, 3.0);
  spec.steps = 2;
  RunOptions opt;
  opt.out_dir = dir / "S";
  {
    Simulation first(spec, opt);
    EXPECT_TRUE(fs::exists(dir / "S" / "mesodpd.lock"));
    try {
      Simulation second(spec, opt);
      FAIL() << "a second simulation took the same output folder";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("in use by another simulation of this process"), std::string::npos)
          << e.what();
    }
    // The refusal left the first one's lock in place.
    EXPECT_TRUE(fs::exists(dir / "S" / "mesodpd.lock"));
    first.run();
  }
  EXPECT_FALSE(fs::exists(dir / "S" / "mesodpd.lock"));
  Simulation again(spec, opt);
  EXPECT_NO_THROW(again.run());
}

TEST(OutputLock, AnotherOpenFileDescriptionCannotTakeAHeldLock) {
  const fs::path dir = fresh_dir("flock");
  OutputLock lock(dir);
  ASSERT_TRUE(lock.held());
  // What another process would try: its own open file and flock (the in-process list aside).
  const int fd = ::open((dir / kOutputLockName).c_str(), O_RDWR);
  ASSERT_GE(fd, 0);
  EXPECT_NE(::flock(fd, LOCK_EX | LOCK_NB), 0);
  ::close(fd);
  const std::string text = test::read_file(dir / kOutputLockName);
  EXPECT_EQ(text.rfind("pid " + std::to_string(::getpid()) + " on host ", 0), 0u) << text;
}

// The GSD writer's writes are checked through the same hook: a frame that cannot be written is an
// error naming the file.
TEST(OutputFile, InjectedFaultStopsAGsdTrajectoryNamingIt) {
  const fs::path dir = fresh_dir("gsd");
  FaultGuard guard;
  SimulationSpec spec = test::fluid_spec(5, 5, 5, 3.0);
  spec.steps = 20;
  spec.dump.enabled = true;
  spec.dump.format = DumpFormat::Gsd;
  spec.dump.every = 10;
  RunOptions opt;
  opt.out_dir = dir;
  Simulation sim(spec, opt);
  set_output_fault_hook([](const fs::path& p) { return p.extension() == ".gsd" ? EIO : 0; });
  try {
    sim.run();
    FAIL() << "the run ended although its trajectory could not be written";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.gsd"), std::string::npos) << e.what();
  }
  EXPECT_EQ(sim.current_step(), 10u);
}
