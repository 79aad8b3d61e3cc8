// What one evaluated pair adds to the totals: its force vector from the law's magnitudes, and its
// virial, energy and count in fixed point. Written once for every backend (fast loop, reference loop,
// CUDA), so that they add the same integers for a pair.
#pragma once
#include <cstdint>

#include "core/hd.hpp"
#include "engine/fixed_point.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

// The force on i due to j, in double before the fixed-point conversion (j gets the opposite).
struct PairForceVector {
  double x = 0, y = 0, z = 0;
};

// F_ij = (fc + fd + fr) / r * d for the displacement d = r_i - r_j of length r (inv_r = 1/r, 0 at r = 0),
// plus the non-central part fn of a law with kNonCentral. The scale and its products with d are taken
// in the pair arithmetic type Real and only then widened, as the single-precision build has always
// done; in double this is plain double arithmetic.
template <bool kNonCentral = false, class Real>
MESODPD_HD PairForceVector pair_force_vector(const PairForceT<Real>& f, Real inv_r, Real dx, Real dy, Real dz) {
  const Real scale = (f.fc + f.fd + f.fr) * inv_r;
  if constexpr (kNonCentral) return {scale * dx + f.fn[0], scale * dy + f.fn[1], scale * dz + f.fn[2]};
  return {scale * dx, scale * dy, scale * dz};
}

// The force vector in the fixed point of the per-particle sums (2^32 units). The fast loop converts
// whole batches with a vector version of to_fixed that gives the same bits.
struct PairForceFixed {
  std::int64_t x = 0, y = 0, z = 0;
};
MESODPD_HD PairForceFixed to_fixed(const PairForceVector& f) {
  return {to_fixed(f.x, kForceScale), to_fixed(f.y, kForceScale), to_fixed(f.z, kForceScale)};
}

// Adds one pair's share of the thermodynamic sums to `sums` ([0..5] virial d (x) F: xx, yy, zz, xy,
// xz, yz; [6] the conservative virial fc r; [7] the pair energy; [8] 1 when r^2 < rcut2), each term
// converted to fixed point on its own, so the totals do not depend on the order of the pairs
// (engine/fixed_point.hpp, core/pair_sums.hpp). The off-diagonal ab (a < b) is the flux of
// a-momentum through planes normal to b, d_b F_a: the shear stress of flow along a with its gradient
// along b (Lees-Edwards, whose flow axis is the lower). A central force has d_a F_b = d_b F_a and keeps
// the product d_a F_b it has always been summed as; a non-central law's tensor is not symmetric and
// takes d_b F_a.
template <bool kNonCentral = false, class Real>
MESODPD_HD void add_pair_sums(std::int64_t* sums, const PairForceT<Real>& f, const PairForceVector& fv, Real r,
                              Real dx, Real dy, Real dz, Real rcut2) {
  sums[0] += to_fixed(dx * fv.x, kVirialScale);
  sums[1] += to_fixed(dy * fv.y, kVirialScale);
  sums[2] += to_fixed(dz * fv.z, kVirialScale);
  if constexpr (kNonCentral) {
    sums[3] += to_fixed(dy * fv.x, kVirialScale);
    sums[4] += to_fixed(dz * fv.x, kVirialScale);
    sums[5] += to_fixed(dz * fv.y, kVirialScale);
  } else {
    sums[3] += to_fixed(dx * fv.y, kVirialScale);
    sums[4] += to_fixed(dx * fv.z, kVirialScale);
    sums[5] += to_fixed(dy * fv.z, kVirialScale);
  }
  sums[6] += to_fixed(f.fc * r, kVirialScale);
  sums[7] += to_fixed(f.energy, kVirialScale);
  sums[8] += r * r < rcut2 ? 1 : 0;
}

}  // namespace mesodpd
