// Import of initial configurations from LAMMPS data files (atom_style atomic, orthorhombic box), so
// systems built with LAMMPS, Moltemplate, Packmol+VMD or OVITO can be started in mesodpd.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace mesodpd {

struct LammpsAtom {
  std::uint32_t id = 0;        // LAMMPS atom id (>= 1)
  int type = 0;                // LAMMPS atom type as in the file, 1..n_types (species index = type - 1)
  double x = 0, y = 0, z = 0;  // as written; not wrapped into the box
  std::int32_t ix = 0, iy = 0, iz = 0;  // image flags, 0 when the file has none
};

struct LammpsData {
  std::array<double, 3> lo{}, hi{};
  int n_types = 0;
  std::vector<double> masses;     // masses[t - 1] for type t; empty without a Masses section
  std::vector<LammpsAtom> atoms;  // in file order
  bool has_velocities = false;
  std::vector<std::array<double, 3>> velocities;  // velocities[k] belongs to atoms[k]; empty if none
};

// Reads the header ("N atoms", "M atom types", "xlo xhi", "ylo yhi", "zlo zhi"; zero counts of
// bonds, angles, ... are accepted), the Masses, Atoms ("id type x y z [ix iy iz]") and Velocities
// ("id vx vy vz") sections, and skips "... Coeffs" sections (interactions come from the config).
// Everything else is an error. Errors are ConfigError naming the file and, for a bad line, its
// line number: malformed line, tilted box ("orthorhombic only"), atom style other than atomic,
// duplicate id, type out of range, count mismatch, missing Atoms section, velocity for an unknown id.
LammpsData read_lammps_data(const std::filesystem::path& path);

}  // namespace mesodpd
