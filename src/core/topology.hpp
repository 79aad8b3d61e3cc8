// Molecular topology by global particle id: bonds and angles with their type indices. Static for a
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

struct Topology {
  std::vector<Bond> bonds;
  std::vector<Angle> angles;
  bool empty() const { return bonds.empty() && angles.empty(); }
};

}  // namespace mesodpd
