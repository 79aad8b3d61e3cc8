// Temperatures and concentrations from LAMMPS data files (atom styles edpd and tdpd; io/lammps_data_reader,
// engine/initial_state.cpp): a run starts from the file's values, a wall held at a value must start at
// it, and a file of the wrong style, a heat capacity other than the species' or a bad number is refused
// naming the key or the line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"

using namespace mesodpd;
namespace fs = std::filesystem;

namespace {

// 27 atoms on a 3 x 3 x 3 lattice in a periodic 3^3 box, type 1, with `columns(k, x, y, z)` giving the line
// of atom k.
template <class Columns>
fs::path data_file(const std::string& name, const std::string& style, Columns columns) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_scalar_data";
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream out(path);
  out << "lattice\n\n27 atoms\n1 atom types\n0 3 xlo xhi\n0 3 ylo yhi\n0 3 zlo zhi\n\nAtoms # " << style << "\n\n";
  int k = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int l = 0; l < 3; ++l) {
        ++k;
        out << columns(k, i + 0.5, j + 0.5, l + 0.5) << "\n";
      }
  return path;
}

std::string config(const std::string& pair, const std::string& species, const fs::path& data,
                   const std::string& extra = "") {
  return fmt::format(
      "[system]\nbox = [3.0, 3.0, 3.0]\nkT = 1.0\nseed = 5\n[[species]]\nname = \"A\"\n{}\n[pair]\na = 25.0\ngamma = "
      "4.5\n{}\n[init]\nlammps_data = \"{}\"\nvelocities = \"maxwell\"\n[integrator]\ndt = 0.01\n[run]\nsteps = 5\n[output]\nprogress = false\n{}",
      species, pair, data.string(), extra);
}

std::string refusal(const std::string& text) {
  try {
    Simulation sim(parse_config(text, "d.toml"), RunOptions{});
    return "";
  } catch (const ConfigError& e) {
    return e.what();
  }
}

}  // namespace

TEST(ScalarDataFiles, EdpdTemperaturesStartFromTheFile) {
  const fs::path f = data_file("edpd.data", "edpd", [](int k, double x, double y, double z) {
    return fmt::format("{} 1 {} 50 {} {} {}", k, 0.8 + 0.01 * k, x, y, z);
  });
  Simulation sim(parse_config(config("style = \"edpd\"\nkappa = 0.01", "cv = 50.0", f), "d.toml"), RunOptions{});
  const ParticleData& p = sim.particles();
  ASSERT_EQ(p.n_local, 27u);
  for (std::size_t i = 0; i < p.n_local; ++i) EXPECT_EQ(p.temp[i], 0.8 + 0.01 * p.id[i]) << "particle " << p.id[i];
  // The heat capacity is the species': a file with another is refused naming species[0].cv.
  const std::string cv = refusal(config("style = \"edpd\"\nkappa = 0.01", "cv = 40.0", f));
  EXPECT_NE(cv.find("species[0].cv"), std::string::npos) << cv;
  EXPECT_NE(cv.find("line 11"), std::string::npos) << cv;
  // An edpd file needs pair.style = "edpd".
  const std::string style = refusal(config("style = \"dpd\"", "", f));
  EXPECT_NE(style.find("init.lammps_data"), std::string::npos) << style;
  EXPECT_NE(style.find("edpd"), std::string::npos) << style;
  // A NaN temperature names the file and the line.
  const fs::path bad = data_file("nan.data", "edpd", [](int k, double x, double y, double z) {
    return fmt::format("{} 1 {} 50 {} {} {}", k, k == 4 ? "nan" : "1.0", x, y, z);
  });
  const std::string nan = refusal(config("style = \"edpd\"\nkappa = 0.01", "cv = 50.0", bad));
  EXPECT_NE(nan.find("line 14"), std::string::npos) << nan;
  EXPECT_NE(nan.find("edpd_temp"), std::string::npos) << nan;
}

TEST(ScalarDataFiles, TdpdConcentrationsStartFromTheFileAndAWallMustHoldItsValue) {
  const fs::path f = data_file("tdpd.data", "tdpd", [](int k, double x, double y, double z) {
    return fmt::format("{} 1 {} {} {} {} {} 0 0 0", k, x, y, z, 0.1 * k, 2.0);
  });
  const std::string pair = "style = \"tdpd\"\nkappa1 = 1.0\nkappa2 = 1.0";
  Simulation sim(parse_config(config(pair, "conc1 = 7.0", f, "[tdpd]\nsolutes = 2\n"), "d.toml"), RunOptions{});
  const ParticleData& p = sim.particles();
  for (std::size_t i = 0; i < p.n_local; ++i) {
    EXPECT_EQ(p.conc1[i], 0.1 * p.id[i]);
    EXPECT_EQ(p.conc2[i], 2.0);
  }
  // With one solute the file's three extra columns do not match 'x y z cc1 [ix iy iz]'.
  const std::string one = refusal(config("style = \"tdpd\"\nkappa1 = 1.0", "", f));
  EXPECT_NE(one.find("cc1 .. cc1"), std::string::npos) << one;
  // A frozen solute wall held at 0.5 cannot start at the file's other values.
  const std::string wall =
      refusal(config(pair, "frozen = true\nconc1 = 0.5\nsolute_wall = 1\n[[species]]\nname = \"B\"", f, "[tdpd]\nsolutes = 2\n"));
  EXPECT_NE(wall.find("species[0].conc1"), std::string::npos) << "[" << wall << "]";
  fs::remove_all(fs::temp_directory_path() / "mesodpd_test_scalar_data");
}
