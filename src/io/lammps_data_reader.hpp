// Import of initial configurations from LAMMPS data files (atom styles atomic, bond, angle, molecular
// and full without charges; orthorhombic box), so systems built with LAMMPS, Moltemplate, Packmol+VMD
// or OVITO can be started in mesodpd.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace mesodpd {

struct LammpsAtom {
  std::uint32_t id = 0;        // LAMMPS atom id (>= 1)
  int type = 0;                // LAMMPS atom type as in the file, 1..n_types (species index = type - 1)
  double x = 0, y = 0, z = 0;  // as written; not wrapped into the box
  std::int32_t ix = 0, iy = 0, iz = 0;  // image flags, 0 when the file has none
  std::int32_t mol = 0;        // molecule id (styles bond, angle, molecular, full), 0 otherwise
  double temp = 0, cv = 0;     // atom style edpd: internal temperature and heat capacity
  std::array<double, 4> conc{};  // atom style tdpd: the concentrations cc1 .. ccN
  std::size_t line = 0;        // 1-based line of the file, for messages about the atom
};

// One line of the Bonds (atoms a, b) or Angles (a, b, c; b the centre) section.
struct LammpsBonded {
  int type = 0;                      // 1..n types as in the file
  std::uint32_t atoms[4] = {0, 0, 0, 0};
};

struct LammpsData {
  std::string style;              // the Atoms section's style: atomic, molecular, full, edpd or tdpd
  int concentrations = 0;         // atom style tdpd: N, the cc columns per atom
  std::array<double, 3> lo{}, hi{};
  int n_types = 0;
  std::vector<double> masses;     // masses[t - 1] for type t; empty without a Masses section
  std::vector<LammpsAtom> atoms;  // in file order
  bool has_velocities = false;
  std::vector<std::array<double, 3>> velocities;  // velocities[k] belongs to atoms[k]; empty if none
  int n_bond_types = 0, n_angle_types = 0, n_dihedral_types = 0;
  std::vector<LammpsBonded> bonds, angles, dihedrals;  // in file order
};

// Reads the header ("N atoms", "M atom types", "xlo xhi", "ylo yhi", "zlo zhi", "N bonds", "N bond
// types", "N angles", "N angle types", "N dihedrals", "N dihedral types"; zero counts of impropers, ...
// are accepted), the Masses, Atoms, Velocities ("id vx vy vz"), Bonds ("id type a b"), Angles ("id type
// a b c") and Dihedrals ("id type a b c d") sections, and skips "... Coeffs" sections (interactions come from the config). Atoms lines are
// "id type x y z" (atomic), "id mol type x y z" (bond, angle, molecular) or "id mol type q x y z"
// (full; every charge must be zero: DPD has no electrostatics), "id type T cv x y z" (edpd: the
// internal temperature and heat capacity of energy-conserving DPD) or "id type x y z cc1 .. ccN" (tdpd,
// N = `tdpd_concentrations`, the solutes the run carries; 0 refuses the style), each optionally followed
// by image flags; the style is the comment after "Atoms" or, without one, follows from the column count
// (edpd and tdpd must be named). A temperature or heat capacity must be positive, a concentration not
// negative, and every number finite (NaN and inf are refused naming the line).
// Everything else is an error. Errors are ConfigError naming the file and, for a bad line, its
// line number: malformed line, tilted box ("orthorhombic only"), an atom style not read, a nonzero
// charge, impropers, duplicate id, type out of range, count mismatch, missing Atoms
// section, velocity for an unknown id, a bond, angle or dihedral naming an atom that does not exist.
LammpsData read_lammps_data(const std::filesystem::path& path, int tdpd_concentrations = 0);

}  // namespace mesodpd
