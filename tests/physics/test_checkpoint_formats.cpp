// Checkpoints of the older state formats still continue their runs: a format 6 checkpoint, whose
// analyses' state is the observers' one blob, restarts under the per-analysis sections of format 7 and
// continues bit-identically to an uninterrupted run.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "io/state_checkpoint.hpp"
#include "mesodpd/config.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

// The lines of `text` from the first whose leading number exceeds `after` (rows of thermo.csv, drag.csv,
// adaptive.csv), or the LAMMPS dump from the first frame after `after`.
std::string rows_after(const std::string& text, std::uint64_t after) {
  std::istringstream in(text);
  std::string line, out;
  bool keep = false;
  for (bool header = true; std::getline(in, line); header = false) {
    if (!header && !keep && !line.empty() && std::isdigit(static_cast<unsigned char>(line[0])))
      keep = std::stoull(line) > after;
    if (keep) out += line + "\n";
  }
  return out;
}
std::string frames_after(const std::string& text, std::uint64_t after) {
  const std::string tag = "ITEM: TIMESTEP\n";
  for (std::size_t at = text.find(tag); at != std::string::npos; at = text.find(tag, at + 1))
    if (std::stoull(text.substr(at + tag.size())) > after) return text.substr(at);
  return {};
}
// The summary without its warnings (judged on the second half of each process's own run).
std::string without_warnings(const std::string& summary) {
  std::istringstream in(summary);
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind("warning: ", 0) != 0) out += line + "\n";
  return out;
}

TEST(Checkpoints, AFormat6CheckpointRestartsBitIdentically) {
  // tests/physics/data/format6: a channel with walls (adaptive force), thermo columns, RDF, MSD, two
  // binned-fields grids, surface tension, stress profile and a LAMMPS dump; its checkpoint at step 60
  // was written by mesodpd a4f5c06 (format 6, the observers' blob with the walls' section inside).
  const fs::path data = fs::path(test::source_dir()) / "tests/physics/data/format6";
  const fs::path base = fs::temp_directory_path() / "mesodpd_format6_restart";
  fs::remove_all(base);
  const StateCheckpoint old = read_state_checkpoint(data / "checkpoint_format6.mdpd");
  ASSERT_EQ(old.header.step, 60u);
  std::vector<std::string> names;
  for (const CheckpointSection& s : old.sections) names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"thermo", "rdf", "msd", "fields/slab", "fields/map", "surface_tension",
                                             "walls", "stress_profile"}));
  const SimulationSpec spec = load_config(data / "channel.toml");
  RunOptions whole;
  whole.out_dir = base / "whole";
  const std::string full = Simulation(spec, whole).run();
  RunOptions restarted;
  restarted.out_dir = base / "restarted";
  fs::create_directories(restarted.out_dir);
  fs::copy_file(data / "checkpoint_format6.mdpd", base / "format6.mdpd");
  restarted.restart = base / "format6.mdpd";
  std::string continued;
  {
    Simulation sim(spec, restarted);
    EXPECT_EQ(sim.current_step(), 60u);
    continued = sim.run();
  }
  EXPECT_EQ(without_warnings(continued), without_warnings(full));
  // The running averages came through: every analysis file is the uninterrupted run's, byte for byte,
  // and so is the final checkpoint (format 7 on both sides).
  for (const char* f : {"rdf.csv", "msd.csv", "slab.csv", "slab.json", "map.csv", "map.json", "map.vti",
                        "stress_profile.csv", "stress_profile.json", "surface_tension.json", "drag_summary.csv",
                        "checkpoint.mdpd"}) {
    ASSERT_TRUE(fs::exists(whole.out_dir / f)) << f;
    EXPECT_EQ(test::read_file(restarted.out_dir / f), test::read_file(whole.out_dir / f)) << f;
  }
  // The rows and frames of steps after 60 too (the restarted folder holds only those).
  for (const char* f : {"thermo.csv", "drag.csv", "adaptive.csv"}) {
    const std::string rows = rows_after(test::read_file(whole.out_dir / f), 60);
    EXPECT_FALSE(rows.empty()) << f;
    EXPECT_EQ(rows_after(test::read_file(restarted.out_dir / f), 60), rows) << f;
  }
  const std::string frames = frames_after(test::read_file(whole.out_dir / "trajectory.lammpstrj"), 60);
  EXPECT_FALSE(frames.empty());
  EXPECT_EQ(test::read_file(restarted.out_dir / "trajectory.lammpstrj"), frames);
  fs::remove_all(base);
}

}  // namespace
}  // namespace mesodpd
