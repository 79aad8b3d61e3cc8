// Molecular topology by global particle id: bonds, angles and dihedrals with their type indices. Static for a
// run (built by the config's molecule builder or read from a LAMMPS data file), held whole on every
// rank and stored in checkpoints.
#pragma once
#include <cstdint>
#include <vector>

namespace mesodpd {

struct Bond {
  std::uint32_t a = 0, b = 0;  // global ids
  std::int32_t type = 0;       // index into the bond types (0-based)
};

struct Angle {
  std::uint32_t a = 0, b = 0, c = 0;  // global ids; b is the centre
  std::int32_t type = 0;              // index into the angle types (0-based)
};

// A dihedral (LAMMPS's order i, j, k, l): the hinge of triangles (a, b, c) and (b, c, d) about the
// central bond b-c.
struct Dihedral {
  std::uint32_t a = 0, b = 0, c = 0, d = 0;  // global ids; b-c is the central bond
  std::int32_t type = 0;                     // index into the dihedral types (0-based)
};

struct Topology {
  std::vector<Bond> bonds;
  std::vector<Angle> angles;
  std::vector<Dihedral> dihedrals;
  bool empty() const { return bonds.empty() && angles.empty() && dihedrals.empty(); }
};

}  // namespace mesodpd
