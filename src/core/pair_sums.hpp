// Sums over pairs that one force evaluation hands to the thermodynamic output (virial, energy).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

namespace mesodpd {

struct PairSums {
  // Virial tensor sum over pairs of r_ij (x) F_ij: xx, yy, zz, xy, xz, yz (seed 000 Eq. 11). The
  // off-diagonal ab (a < b) is the flux of a-momentum through b-planes, sum d_b F_a, which for central
  // forces equals sum d_a F_b (engine/pair_contribution.hpp, add_pair_sums).
  std::array<double, 6> virial{};
  double virial_conservative = 0.0;  // trace of the conservative-only virial
  double potential_energy = 0.0;
  std::uint64_t pairs_in_range = 0;
};

// One term of the configurational virial between particles i and j (storage indices): d = r_i - r_j
// (minimum image) and f the force the term puts on i; its virial is d (x) f. A pair force or a bond is
// one term (-f acts on j); an angle a-b-c is two, (a, b, r_a - r_b, F_a) and (c, b, r_c - r_b, F_c),
// whose virials add up to the angle's -b1 (x) F_a + b2 (x) F_c. The sum of d (x) f over all terms is
// the virial of the pressure tensor. Used to localise the stress ([analysis.stress_profile]).
struct VirialTerm {
  std::uint32_t i = 0, j = 0;
  double d[3] = {0, 0, 0};
  double f[3] = {0, 0, 0};
};
using VirialTerms = std::vector<VirialTerm>;

}  // namespace mesodpd
