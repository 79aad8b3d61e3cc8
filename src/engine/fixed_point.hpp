// Fixed-point accumulation: forces and virials are summed as 64-bit integers, so the total does not
// depend on the order of the additions (threads, ranks, neighbour order) and f_i = -sum f_j exactly.
#pragma once
#include <cstdint>

#include "core/hd.hpp"

namespace mesodpd {

// 2^32 units per force unit: resolution 2.3e-10, range +-2.1e9 per particle. The pair loop stops the
// run when one pair's contribution leaves the range below (kPairFixedLimit), so the clamp in to_fixed
// only keeps a NaN or huge value from being undefined behaviour before that report.
inline constexpr double kForceScale = 4294967296.0;
inline constexpr double kForceUnscale = 1.0 / kForceScale;
// Virial and energy sums grow with N, so they get 2^24 units (resolution 6e-8 per pair).
inline constexpr double kVirialScale = 16777216.0;
inline constexpr double kVirialUnscale = 1.0 / kVirialScale;

// Largest magnitude to_fixed() converts; beyond it values are clamped (below 2^63, so the conversion
// is defined). Vector versions of to_fixed (engine/force_compute.cpp) use the same bound.
inline constexpr double kFixedLimit = 9.0e18;

// Range checks of the pair sums. One pair's contribution to a per-particle sum is taken without a
// check while |value x scale| < kPairFixedLimit: below 2^51 the vector conversion is exact and cheap,
// and 4096 such contributions (more pairs than any particle has within the cutoff at DPD densities)
// cannot leave the int64 range. The loop lowers the limit for particles with more candidate pairs
// (ForceCompute), and a contribution at or past it stops the run (Simulation::check_health). Per-pair
// virial and energy terms (2^24 units) must stay below kPairSumLimit, and their totals are added with
// overflow checks.
inline constexpr double kPairFixedLimit = 2251799813685248.0;  // 2^51
inline constexpr std::int64_t kPairSumLimit = std::int64_t{1} << 62;

MESODPD_HD std::int64_t to_fixed(double v, double scale) {
  constexpr double kLimit = kFixedLimit;
  double s = v * scale;
  s = s > kLimit ? kLimit : s;
  s = s < -kLimit ? -kLimit : s;
  s = (s == s) ? s : kLimit;  // NaN becomes a huge force, which the blow-up check then reports
  return static_cast<std::int64_t>(s);  // truncation is odd-symmetric: to_fixed(-v) == -to_fixed(v)
}

}  // namespace mesodpd
