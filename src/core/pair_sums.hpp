// Sums over pairs that one force evaluation hands to the thermodynamic output (virial, energy).
#pragma once
#include <array>
#include <cstdint>

namespace mesodpd {

struct PairSums {
  // Virial tensor sum over pairs of r_ij (x) F_ij: xx, yy, zz, xy, xz, yz (seed 000 Eq. 11).
  std::array<double, 6> virial{};
  double virial_conservative = 0.0;  // trace of the conservative-only virial
  double potential_energy = 0.0;
  std::uint64_t pairs_in_range = 0;
};

}  // namespace mesodpd
