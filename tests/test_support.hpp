// Shared helpers for the test suite: standard specs built in code, and small utilities.
#pragma once
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "mesodpd/spec.hpp"

namespace mesodpd::test {

// One-species DPD fluid at density rho in an lx x ly x lz box (seed 000 Sect. 2 parameters by default).
inline SimulationSpec fluid_spec(double lx, double ly, double lz, double rho, double a = 25.0, double gamma = 4.5,
                                 double dt = 0.04, double s = 2.0) {
  SimulationSpec spec;
  spec.source = "test";
  spec.box = {lx, ly, lz};
  spec.kT = 1.0;
  spec.seed = 20261123;
  SpeciesSpec sp;
  sp.name = "A";
  sp.mass = 1.0;
  sp.count = static_cast<std::uint64_t>(std::llround(rho * lx * ly * lz));
  spec.species = {sp};
  PairSpec pp;
  pp.a = a;
  pp.gamma = gamma;
  pp.s = s;
  spec.pairs = {pp};
  spec.dt = dt;
  spec.thermo_every = 10;
  spec.progress = false;
  return spec;
}

// The whole content of a file (empty if it cannot be read).
inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The mesodpd program and the source tree, fixed at configure time (tests/CMakeLists.txt).
inline std::string mesodpd_bin() { return MESODPD_BIN_PATH; }
inline std::string source_dir() { return MESODPD_SOURCE_DIR; }

}  // namespace mesodpd::test
