// Binned fields in whole runs (analysis/binned_fields.hpp through the observers): equipartition in an
// equilibrated fluid, a restart that continues the averages byte for byte, and files that do not depend
// on the thread count. Rank-count identity is in tests/parallel/test_mpi.cpp.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/simulation.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_fields_run" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

FieldsSpec whole_box_grid(const SimulationSpec& spec, std::array<int, 3> bins, const std::string& name) {
  FieldsSpec f;
  f.name = name;
  f.bins = bins;
  f.region_hi = spec.box;
  for (std::size_t s = 0; s < spec.species.size(); ++s) f.selected.push_back(static_cast<int>(s));
  return f;
}

// Column `name` of a CSV file with a header row.
std::vector<double> csv_column(const fs::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::size_t col = header.size();
  for (std::size_t k = 0; k < header.size(); ++k)
    if (header[k] == name) col = k;
  EXPECT_LT(col, header.size()) << name << " not in " << file;
  std::vector<double> out;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cell;
    for (std::size_t k = 0; k <= col && std::getline(ss, cell, ','); ++k) {
    }
    out.push_back(std::stod(cell));
  }
  return out;
}

TEST(FieldsRun, BinTemperaturesAreKTInAnEquilibratedFluid) {
  // Standard fluid (rho = 3, a = 25, gamma = 4.5) at dt = 0.04 with lambda = 0.65, which keeps the kinetic
  // temperature within 1% of kT (docs/validation.md). 27 bins of ~24 particles, 400 samples each.
  SimulationSpec spec = test::fluid_spec(6.0, 6.0, 6.0, 3.0);
  spec.lambda = 0.65;
  spec.thermo_every = 100;
  spec.fields.push_back(whole_box_grid(spec, {3, 3, 3}, "fields"));
  spec.fields[0].start = 500;
  spec.fields[0].every = 5;
  RunOptions opt;
  opt.out_dir = fresh_dir("equipartition");
  opt.steps = 2500;
  Simulation(spec, opt).run();
  const fs::path csv = opt.out_dir / "fields.csv";
  const std::vector<double> t = csv_column(csv, "temperature");
  const std::vector<double> rho = csv_column(csv, "density");
  ASSERT_EQ(t.size(), 27u);
  double mean = 0, mean_rho = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    mean += t[k] / 27;
    mean_rho += rho[k] / 27;
    // One bin: ~9,600 correlated particle-samples; 8% is several standard deviations.
    EXPECT_NEAR(t[k], 1.0, 0.08) << "bin " << k;
  }
  std::printf("mean bin temperature %.4f, mean density %.6f\n", mean, mean_rho);
  EXPECT_NEAR(mean, 1.0, 0.02);
  EXPECT_NEAR(mean_rho, 3.0, 1e-9);  // particles are neither lost nor counted twice
  for (const char* axis : {"temperature_x", "temperature_y", "temperature_z"}) {
    double m = 0;
    for (double x : csv_column(csv, axis)) m += x / 27;
    EXPECT_NEAR(m, 1.0, 0.03) << axis;
  }
}

std::string slurp(const fs::path& f) { return test::read_file(f); }

TEST(FieldsRun, RestartContinuesTheFieldAveragesByteForByte) {
  // A 2-D map and a centred 1-D profile with a slab fit (of a uniform fluid: the numbers are
  // meaningless, the bytes must still agree): interrupted at step 90 and restarted, the files equal
  // those of the uninterrupted run.
  SimulationSpec spec = test::fluid_spec(5.0, 5.0, 8.0, 3.0);
  spec.poiseuille.enabled = true;
  spec.poiseuille.force = 0.1;
  spec.poiseuille.bins = 8;
  spec.poiseuille.blocks = 2;
  spec.fields.push_back(whole_box_grid(spec, {5, 1, 8}, "map"));
  spec.fields.push_back(whole_box_grid(spec, {1, 1, 16}, "profile"));
  spec.fields[1].centre_axis = 2;
  spec.fields[1].fit = FieldsFit::Slab;
  spec.fields[1].every = 7;
  RunOptions whole;
  whole.out_dir = fresh_dir("restart") / "whole";
  whole.steps = 200;
  Simulation(spec, whole).run();
  RunOptions first = whole;
  first.out_dir = whole.out_dir.parent_path() / "split";
  first.steps = 90;
  Simulation(spec, first).run();
  RunOptions second = first;
  second.steps = 200;
  second.restart = first.out_dir / "checkpoint.mdpd";
  Simulation(spec, second).run();
  for (const char* f : {"map.vti", "map.csv", "map.json", "profile.vti", "profile.csv", "profile.json",
                        "profile_profile.svg"}) {
    ASSERT_TRUE(fs::exists(whole.out_dir / f)) << f;
    EXPECT_EQ(slurp(whole.out_dir / f), slurp(first.out_dir / f)) << f << " differs after a restart";
  }
  // The first sample is step 0, the last step 200 (every 10): 21 samples.
  EXPECT_NE(slurp(whole.out_dir / "map.json").find("\"samples\": 21"), std::string::npos);
  // A restart with another grid under the same name is refused, naming it.
  spec.fields[0].bins = {5, 1, 4};
  RunOptions third = second;
  third.steps = 210;
  third.restart = whole.out_dir / "checkpoint.mdpd";
  try {
    Simulation(spec, third).run();
    ADD_FAILURE() << "restart with another grid accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("analysis.fields \"map\""), std::string::npos) << e.what();
  }
}

TEST(FieldsRun, WriteEveryLeavesTheFilesSoFarDuringTheRun) {
  // Stepped by hand (no end-of-run write): with write_every = 50 the files exist after step 50 and hold
  // the 6 samples of steps 0, 10, ..., 50; at step 100 they hold 11.
  SimulationSpec spec = test::fluid_spec(5.0, 5.0, 5.0, 3.0);
  spec.fields.push_back(whole_box_grid(spec, {2, 2, 2}, "fields"));
  spec.fields[0].write_every = 50;
  RunOptions opt;
  opt.out_dir = fresh_dir("write_every");
  opt.steps = 1000;
  Simulation sim(spec, opt);
  for (int k = 0; k < 49; ++k) sim.step();
  EXPECT_FALSE(fs::exists(opt.out_dir / "fields.json"));
  sim.step();
  EXPECT_NE(slurp(opt.out_dir / "fields.json").find("\"samples\": 6,"), std::string::npos) << slurp(opt.out_dir / "fields.json");
  for (int k = 0; k < 50; ++k) sim.step();
  EXPECT_NE(slurp(opt.out_dir / "fields.json").find("\"samples\": 11,"), std::string::npos);
  EXPECT_TRUE(fs::exists(opt.out_dir / "fields.vti"));
}

TEST(FieldsRun, FilesDoNotDependOnTheThreadCount) {
  SimulationSpec spec = test::fluid_spec(6.0, 5.0, 7.0, 3.0);
  spec.fields.push_back(whole_box_grid(spec, {6, 5, 7}, "fields"));
  spec.fields[0].every = 3;
  std::string ref[3];
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    RunOptions opt;
    opt.out_dir = fresh_dir("threads" + std::to_string(threads));
    opt.steps = 150;
    Simulation(spec, opt).run();
    const std::string got[3] = {slurp(opt.out_dir / "fields.vti"), slurp(opt.out_dir / "fields.csv"),
                                slurp(opt.out_dir / "fields.json")};
    for (int k = 0; k < 3; ++k) {
      if (threads == 1) ref[k] = got[k];
      else EXPECT_EQ(got[k], ref[k]) << "file " << k << " differs with 2 threads";
    }
  }
  omp_set_num_threads(1);
}

}  // namespace
}  // namespace mesodpd
