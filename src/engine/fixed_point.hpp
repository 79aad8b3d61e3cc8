// Fixed-point accumulation: forces and virials are summed as 64-bit integers, so the total does not
// depend on the order of the additions (threads, ranks, neighbour order) and f_i = -sum f_j exactly.
#pragma once
#include <cstdint>

#include "core/hd.hpp"

namespace mesodpd {

// 2^32 units per force unit: resolution 2.3e-10, range +-2.1e9 per particle. A blow-up is caught by the
// velocity check long before forces reach that range; the clamp below keeps a NaN from being UB.
inline constexpr double kForceScale = 4294967296.0;
inline constexpr double kForceUnscale = 1.0 / kForceScale;
// Virial and energy sums grow with N, so they get 2^24 units (resolution 6e-8 per pair).
inline constexpr double kVirialScale = 16777216.0;
inline constexpr double kVirialUnscale = 1.0 / kVirialScale;

// Largest magnitude to_fixed() converts; beyond it values are clamped (below 2^63, so the conversion
// is defined). Vector versions of to_fixed (engine/force_compute.cpp) use the same bound.
inline constexpr double kFixedLimit = 9.0e18;

MESODPD_HD std::int64_t to_fixed(double v, double scale) {
  constexpr double kLimit = kFixedLimit;
  double s = v * scale;
  s = s > kLimit ? kLimit : s;
  s = s < -kLimit ? -kLimit : s;
  s = (s == s) ? s : kLimit;  // NaN becomes a huge force, which the blow-up check then reports
  return static_cast<std::int64_t>(s);  // truncation is odd-symmetric: to_fixed(-v) == -to_fixed(v)
}

}  // namespace mesodpd
