// Tests of read_lammps_data: a complete file read exactly, and every kind of malformed file rejected
// with an error naming the file and the offending line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "io/lammps_data_reader.hpp"
#include "mesodpd/spec.hpp"

namespace fs = std::filesystem;
using namespace mesodpd;

namespace {

class LammpsDataTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info->name();
    for (char& c : name) {
      if (c == '/') c = '_';  // parameterised test names contain '/'
    }
    dir_ = fs::temp_directory_path() / ("mesodpd_lmpdata_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& content) {
    const auto p = dir_ / "system.data";
    std::ofstream(p) << content;
    return p;
  }

  fs::path dir_;
};

const char* const kFull = R"(LAMMPS data file via write_data, title line: 5 atoms # not a header

5 atoms          # count
2 atom types
0 bonds
0 bond types

-2.5 7.5 xlo xhi
0 10 ylo yhi
  1e-1   2.0e1 zlo zhi
0.0 0.0 0.0 xy xz yz

Masses

1 1.0
2 2.5   # heavy

Pair Coeffs # dpd

1 25 4.5 1.0
2 25 4.5 1.0

Atoms # atomic

3 2 0.1 0.2 0.30000000000000004 0 -1 2
1 1 -2.5 0 0.1 0 0 0
# a comment line in the middle

2 1 7.4999999999999991 9.9999 19.99 1 0 0
5 2 1e-17 3.333333333333333 5 0 0 0
4 1 +1.5 -0 2 0 0 0

Velocities

5 0.5 -0.5 1e-3
1 1 2 3
2 -1 -2 -3
3 0 0 0
4 1.0000000000000002 0 0
)";

TEST_F(LammpsDataTest, ReadsCompleteFileExactly) {
  const LammpsData d = read_lammps_data(write(kFull));
  EXPECT_EQ(d.lo, (std::array<double, 3>{-2.5, 0.0, 0.1}));
  EXPECT_EQ(d.hi, (std::array<double, 3>{7.5, 10.0, 20.0}));
  EXPECT_EQ(d.n_types, 2);
  EXPECT_EQ(d.masses, (std::vector<double>{1.0, 2.5}));
  ASSERT_EQ(d.atoms.size(), 5u);
  // File order is kept.
  EXPECT_EQ(d.atoms[0].id, 3u);
  EXPECT_EQ(d.atoms[0].type, 2);
  EXPECT_EQ(d.atoms[0].z, 0.1 + 0.2);  // parsed to the same double, not merely close
  EXPECT_EQ(d.atoms[0].ix, 0);
  EXPECT_EQ(d.atoms[0].iy, -1);
  EXPECT_EQ(d.atoms[0].iz, 2);
  EXPECT_EQ(d.atoms[2].id, 2u);
  EXPECT_EQ(d.atoms[2].x, 7.4999999999999991);
  EXPECT_EQ(d.atoms[2].ix, 1);
  EXPECT_EQ(d.atoms[3].x, 1e-17);
  EXPECT_EQ(d.atoms[3].y, 3.333333333333333);
  EXPECT_EQ(d.atoms[4].x, 1.5);
  ASSERT_TRUE(d.has_velocities);
  ASSERT_EQ(d.velocities.size(), 5u);
  // Velocities follow the atoms' order, not the Velocities section's.
  EXPECT_EQ(d.velocities[0], (std::array<double, 3>{0, 0, 0}));          // id 3
  EXPECT_EQ(d.velocities[1], (std::array<double, 3>{1, 2, 3}));          // id 1
  EXPECT_EQ(d.velocities[2], (std::array<double, 3>{-1, -2, -3}));       // id 2
  EXPECT_EQ(d.velocities[3], (std::array<double, 3>{0.5, -0.5, 1e-3}));  // id 5
  EXPECT_EQ(d.velocities[4][0], 1.0000000000000002);                     // id 4
}

TEST_F(LammpsDataTest, ReadsMinimalFileWithoutOptionalParts) {
  const LammpsData d =
      read_lammps_data(write("title\n2 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n"
                             "Atoms\n1 1 0.5 0.5 0.5\n2 1 0.25 0.75 0\n"));
  EXPECT_TRUE(d.masses.empty());
  EXPECT_FALSE(d.has_velocities);
  EXPECT_TRUE(d.velocities.empty());
  ASSERT_EQ(d.atoms.size(), 2u);
  EXPECT_EQ(d.atoms[1].y, 0.75);
  EXPECT_EQ(d.atoms[1].iz, 0);
}

// Atom styles edpd ("id type edpd_temp edpd_cv x y z") and tdpd ("id type x y z cc1 .. ccN", N from the
// run), with and without image flags; non-finite, non-positive temperatures and negative concentrations
// are refused naming the line, and so is tdpd where the run carries no solutes.
TEST_F(LammpsDataTest, ReadsEdpdAndTdpdColumns) {
  const std::string box = "title\n2 atoms\n1 atom types\n0 4 xlo xhi\n0 4 ylo yhi\n0 4 zlo zhi\n\n";
  const LammpsData e = read_lammps_data(write(box + "Atoms # edpd\n\n1 1 1.25 100 0.5 0.5 0.5\n2 1 0.75 100 1 2 3 0 1 0\n"));
  EXPECT_EQ(e.style, "edpd");
  ASSERT_EQ(e.atoms.size(), 2u);
  EXPECT_EQ(e.atoms[0].temp, 1.25);
  EXPECT_EQ(e.atoms[0].cv, 100.0);
  EXPECT_EQ(e.atoms[1].z, 3.0);
  EXPECT_EQ(e.atoms[1].iy, 1);
  const LammpsData t =
      read_lammps_data(write(box + "Atoms # tdpd\n\n1 1 0.5 0.5 0.5 0.25 2\n2 1 1 2 3 0 1.5 0 0 -1\n"), 2);
  EXPECT_EQ(t.style, "tdpd");
  EXPECT_EQ(t.concentrations, 2);
  EXPECT_EQ(t.atoms[0].conc[0], 0.25);
  EXPECT_EQ(t.atoms[0].conc[1], 2.0);
  EXPECT_EQ(t.atoms[1].conc[1], 1.5);
  EXPECT_EQ(t.atoms[1].iz, -1);
  const auto refused = [&](const std::string& atoms, int n, int line, const std::string& needle) {
    try {
      (void)read_lammps_data(write(box + atoms), n);
      ADD_FAILURE() << "accepted: " << atoms;
    } catch (const ConfigError& err) {
      const std::string msg = err.what();
      EXPECT_NE(msg.find("line " + std::to_string(line) + ":"), std::string::npos) << msg;
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    }
  };
  refused("Atoms # edpd\n\n1 1 1 100 0 0 0\n2 1 nan 100 1 1 1\n", 0, 11, "cannot read edpd_temp");
  refused("Atoms # edpd\n\n1 1 -1 100 0 0 0\n2 1 1 100 1 1 1\n", 0, 10, "edpd_temp -1 of atom 1 must be positive");
  refused("Atoms # edpd\n\n1 1 1 0 0 0 0\n2 1 1 100 1 1 1\n", 0, 10, "edpd_cv 0 of atom 1 must be positive");
  refused("Atoms # tdpd\n\n1 1 0 0 0 1 inf\n2 1 1 1 1 1 1\n", 2, 10, "cannot read concentration");
  refused("Atoms # tdpd\n\n1 1 0 0 0 1 1\n2 1 1 1 1 1 -0.5\n", 2, 11, "cc2 = -0.5 of atom 2 is negative");
  refused("Atoms # tdpd\n\n1 1 0 0 0 1\n2 1 1 1 1 1\n", 0, 8, "pair.style = \"tdpd\"");
  refused("Atoms # tdpd\n\n1 1 0 0 0 1\n2 1 1 1 1 1\n", 2, 10, "cc1 .. cc2");
}

// Styles molecular and full (zero charges): molecule ids, Bonds, Angles and Dihedrals read exactly.
TEST_F(LammpsDataTest, ReadsMolecularTopology) {
  const std::string molecular = R"(chains
4 atoms
2 atom types
3 bonds
2 bond types
2 angles
1 angle types
1 extra bond per atom
1 dihedrals
1 dihedral types
0 impropers
0 10 xlo xhi
0 10 ylo yhi
0 10 zlo zhi

Atoms # molecular

1 7 1 1.0 1.0 1.0
2 7 1 1.5 1.0 1.0 0 0 0
3 7 2 2.0 1.0 1.0
4 7 2 2.5 1.0 1.0

Bond Coeffs

1 harmonic 4.0 0.0

Bonds

1 1 1 2
2 1 2 3
3 2 3 4

Angles

1 1 1 2 3
2 1 2 3 4

Dihedrals

1 1 1 2 3 4
)";
  for (const bool full : {false, true}) {
    std::string text = molecular;
    if (full) {
      text.replace(text.find("Atoms # molecular"), 17, "Atoms");
      for (const char* line : {"1 7 1 1.0", "2 7 1 1.5", "3 7 2 2.0", "4 7 2 2.5"}) {
        const std::string l = line;
        text.replace(text.find(l), l.size(), l.substr(0, 6) + "0.0 " + l.substr(6));
      }
    }
    const LammpsData d = read_lammps_data(write(text));
    ASSERT_EQ(d.atoms.size(), 4u);
    EXPECT_EQ(d.atoms[1].mol, 7);
    EXPECT_EQ(d.atoms[2].type, 2);
    EXPECT_EQ(d.atoms[3].x, 2.5);
    EXPECT_EQ(d.n_bond_types, 2);
    EXPECT_EQ(d.n_angle_types, 1);
    ASSERT_EQ(d.bonds.size(), 3u);
    EXPECT_EQ(d.bonds[2].type, 2);
    EXPECT_EQ(d.bonds[2].atoms[0], 3u);
    EXPECT_EQ(d.bonds[2].atoms[1], 4u);
    ASSERT_EQ(d.angles.size(), 2u);
    EXPECT_EQ(d.angles[1].atoms[1], 3u);
    EXPECT_EQ(d.angles[1].atoms[2], 4u);
    EXPECT_EQ(d.n_dihedral_types, 1);
    ASSERT_EQ(d.dihedrals.size(), 1u);
    EXPECT_EQ(d.dihedrals[0].atoms[0], 1u);
    EXPECT_EQ(d.dihedrals[0].atoms[3], 4u);
  }
}

TEST_F(LammpsDataTest, MissingFileIsNamed) {
  const auto p = dir_ / "absent.data";
  try {
    (void)read_lammps_data(p);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
}

struct BadCase {
  const char* name;
  std::string content;
  std::optional<int> line;  // expected line number in the message, if the error is about one line
  const char* needle;       // expected text in the message
};

std::string header(int atoms = 2, int types = 2) {
  return "title\n" + std::to_string(atoms) + " atoms\n" + std::to_string(types) +
         " atom types\n0 10 xlo xhi\n0 10 ylo yhi\n0 10 zlo zhi\n\n";  // 7 lines; the next line is 8
}

class BadLammpsData : public LammpsDataTest, public ::testing::WithParamInterface<BadCase> {};

TEST_P(BadLammpsData, IsRejectedNamingFileAndLine) {
  const BadCase& c = GetParam();
  const auto p = write(c.content);
  try {
    (void)read_lammps_data(p);
    FAIL() << "expected ConfigError for case " << c.name;
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(c.needle), std::string::npos) << msg;
    if (c.line) {
      EXPECT_NE(msg.find("line " + std::to_string(*c.line) + ":"), std::string::npos) << msg;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, BadLammpsData,
    ::testing::Values(
        BadCase{"too_few_columns", header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0\n", 11, "id type x y z"},
        BadCase{"mixed_columns", header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0 0\n", 11, "found 6 columns"},
        BadCase{"unknown_column_count", header() + "Atoms\n\n1 1 0 0\n2 1 0 0 0 0\n", 10, "cannot tell the atom style"},
        BadCase{"not_a_number", header() + "Atoms\n\n1 1 0 0 0\n2 1 0 1.0abc 0\n", 11, "cannot read y"},
        BadCase{"nan_coordinate", header() + "Atoms\n\n1 1 0 0 nan\n2 1 0 0 0\n", 10, "finite"},
        BadCase{"fractional_id", header() + "Atoms\n\n1.5 1 0 0 0\n2 1 0 0 0\n", 10, "atom id"},
        BadCase{"duplicate_id", header() + "Atoms\n\n7 1 0 0 0\n7 2 1 1 1\n", 11, "duplicate atom id 7"},
        BadCase{"type_too_large", header() + "Atoms\n\n1 3 0 0 0\n2 1 0 0 0\n", 10,
                "atom type 3 is out of range"},
        BadCase{"type_zero", header() + "Atoms\n\n1 1 0 0 0\n2 0 0 0 0\n", 11, "atom type 0 is out of range"},
        BadCase{"too_few_atoms", header(3) + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n", 8, "declares 3 atoms"},
        BadCase{"too_many_atoms", header(1) + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n", 8, "declares 1 atoms"},
        BadCase{"missing_atoms", header() + "Masses\n\n1 1\n2 1\n", std::nullopt, "no Atoms section"},
        BadCase{"velocity_unknown_id",
                header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n\nVelocities\n\n1 0 0 0\n9 0 0 0\n", 16,
                "atom id 9, which is not in the Atoms section"},
        BadCase{"velocity_twice",
                header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n\nVelocities\n\n1 0 0 0\n1 1 1 1\n", 16,
                "given twice"},
        BadCase{"velocity_columns",
                header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n\nVelocities\n\n1 0 0\n2 0 0 0\n", 15,
                "id vx vy vz"},
        BadCase{"charged_full_style", header() + "Atoms # full\n\n1 1 1 0.0 0 0 0\n2 1 1 0.5 0 0 0\n", 11,
                "charge 0.5 of atom 2 is not zero"},
        BadCase{"sphere_style", header() + "Atoms # sphere\n\n1 1 1 1 0 0 0\n2 1 1 1 0 0 0\n", 8,
                "atom style 'sphere' is not supported"},
        BadCase{"tilt",
                "title\n1 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n0.5 0 0 xy xz yz\n", 7,
                "orthorhombic only"},
        BadCase{"bad_bounds", "title\n1 atoms\n1 atom types\n0 1 xlo xhi\n2 1 ylo yhi\n0 1 zlo zhi\n", 5,
                "yhi must be greater than ylo"},
        BadCase{"missing_bounds",
                "title\n1 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\nAtoms\n\n1 1 0 0 0\n", std::nullopt,
                "zlo zhi"},
        BadCase{"missing_type_count", "title\n1 atoms\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n", std::nullopt,
                "atom types"},
        BadCase{"unknown_header",
                "title\n1 atoms\n1 atom types\n0 1 xlo xhi\n0 1 ylo yhi\n0 1 zlo zhi\n3 widgets\n", 7,
                "unknown header line '3 widgets'"},
        BadCase{"impropers", "title\n1 atoms\n1 atom types\n4 impropers\n", 4, "'impropers' is not supported"},
        BadCase{"dihedrals_missing", "title\n4 atoms\n1 atom types\n1 dihedrals\n1 dihedral types\n0 9 xlo xhi\n"
                "0 9 ylo yhi\n0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n3 1 1 0 1 1\n4 1 1 1 1 1\n",
                std::nullopt, "no Dihedrals section"},
        BadCase{"dihedral_columns", "title\n4 atoms\n1 atom types\n1 dihedrals\n1 dihedral types\n0 9 xlo xhi\n"
                "0 9 ylo yhi\n0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n3 1 1 0 1 1\n4 1 1 1 1 1\n\n"
                "Dihedrals\n\n1 1 1 2 3\n",
                19, "id type atom1 atom2 atom3 atom4"},
        BadCase{"dihedral_unknown_atom", "title\n4 atoms\n1 atom types\n1 dihedrals\n1 dihedral types\n0 9 xlo xhi\n"
                "0 9 ylo yhi\n0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n3 1 1 0 1 1\n4 1 1 1 1 1\n\n"
                "Dihedrals\n\n1 1 1 2 3 7\n",
                19, "names atom 7, which is not in the Atoms section"},
        BadCase{"bonds_not_declared", header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n\nBonds\n\n1 1 1 2\n", 13,
                "declares 0"},
        BadCase{"bonds_missing", "title\n2 atoms\n1 atom types\n1 bonds\n1 bond types\n0 9 xlo xhi\n0 9 ylo yhi\n"
                "0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n",
                std::nullopt, "no Bonds section"},
        BadCase{"bond_unknown_atom", "title\n2 atoms\n1 atom types\n1 bonds\n1 bond types\n0 9 xlo xhi\n0 9 ylo yhi\n"
                "0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n\nBonds\n\n1 1 1 3\n",
                17, "names atom 3, which is not in the Atoms section"},
        BadCase{"bond_type_range", "title\n2 atoms\n1 atom types\n1 bonds\n1 bond types\n0 9 xlo xhi\n0 9 ylo yhi\n"
                "0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n\nBonds\n\n1 2 1 2\n",
                17, "Bonds type 2 is out of range"},
        BadCase{"angle_columns", "title\n3 atoms\n1 atom types\n1 angles\n1 angle types\n0 9 xlo xhi\n0 9 ylo yhi\n"
                "0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n3 1 1 0 1 1\n\nAngles\n\n1 1 1 2\n",
                18, "id type atom1 atom2 atom3"},
        BadCase{"angle_repeated_atom", "title\n3 atoms\n1 atom types\n1 angles\n1 angle types\n0 9 xlo xhi\n"
                "0 9 ylo yhi\n0 9 zlo zhi\n\nAtoms\n\n1 1 1 0 0 0\n2 1 1 0 0 1\n3 1 1 0 1 1\n\nAngles\n\n1 1 1 2 1\n",
                18, "names atom 1 twice"},
        BadCase{"mass_missing_type", header() + "Masses\n\n1 1.0\n\nAtoms\n\n1 1 0 0 0\n2 1 0 0 0\n", 8,
                "no mass for atom type 2"},
        BadCase{"mass_nonpositive", header() + "Masses\n\n1 1.0\n2 -1\n", 11, "must be positive"},
        BadCase{"second_atoms_section",
                header() + "Atoms\n\n1 1 0 0 0\n2 1 0 0 0\n\nAtoms\n\n1 1 0 0 0\n2 1 0 0 0\n", 13,
                "second 'Atoms' section (first at line 8)"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return std::string(info.param.name); });

}  // namespace
