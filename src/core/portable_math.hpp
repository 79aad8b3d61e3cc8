// Elementary functions written with plain IEEE arithmetic and bit operations only: no fused
// multiply-add (the project compiles with -ffp-contract=off), no table, no library call. Two reasons:
//  - the compiler vectorises a loop around them (a library call per element keeps it scalar), and
//  - every SIMD target, the scalar reference loop and a future GPU backend get the same bits, which the
//    pair loop's reproducibility rests on (DESIGN.md aim 2).
// The selects vectorise where the file is compiled with -fno-trapping-math (engine/force_compute.cpp
// is); elsewhere the same arithmetic runs lane by lane. Users: physics/power.hpp (x^y for the laws'
// weights) and core/philox.hpp (the Gaussian pair noise). Accuracy: tests/physics/test_pair_force.cpp
// (Power.*, PortableMath.*).
#pragma once
#include <bit>
#include <cstdint>

#include "core/hd.hpp"

namespace mesodpd {

namespace portable_math {

MESODPD_HD_FORCE std::uint64_t bits_of(double x) {
#if defined(__CUDA_ARCH__)
  return static_cast<std::uint64_t>(__double_as_longlong(x));
#else
  return std::bit_cast<std::uint64_t>(x);
#endif
}

MESODPD_HD_FORCE double double_of(std::uint64_t u) {
#if defined(__CUDA_ARCH__)
  return __longlong_as_double(static_cast<long long>(u));
#else
  return std::bit_cast<double>(u);
#endif
}

inline constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln 2 to 32 bits: n kLn2Hi is exact
inline constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln 2 - kLn2Hi

}  // namespace portable_math

// ln x for a normal positive x (0, subnormals, infinities and NaN are outside the domain).
// x = 2^e m with m in [sqrt(1/2), sqrt(2)); ln m = 2 atanh(f) = 2 (f + f^3/3 + ... + f^21/21) with
// f = (m - 1)/(m + 1), |f| <= 0.1716 (the first term left out is below 3e-17 of the sum); ln x =
// e ln2_hi + ln m + e ln2_lo (ln 2 split in two parts, Cody and Waite, so that e ln2_hi is exact).
// The biased exponent becomes a double without an integer conversion (which AVX2 lacks for 64-bit
// lanes): from the bits below those of 2^52.
MESODPD_HD_FORCE double ln_pos(double x) {
  using portable_math::bits_of;
  using portable_math::double_of;
  constexpr std::uint64_t kMantissa = 0x000FFFFFFFFFFFFFull;
  constexpr std::uint64_t kOne = 0x3FF0000000000000ull;    // the bits of 1.0
  constexpr std::uint64_t kTwo52 = 0x4330000000000000ull;  // the bits of 2^52
  constexpr double kTwo52d = 4503599627370496.0;           // 2^52
  constexpr double kSqrt2 = 1.41421356237309504880;
  const std::uint64_t u = bits_of(x);
  const double m1 = double_of((u & kMantissa) | kOne);
  const double e1 = double_of((u >> 52) | kTwo52) - (kTwo52d + 1023.0);
  const bool high = m1 > kSqrt2;
  const double m = m1 * (high ? 0.5 : 1.0);
  const double e = e1 + (high ? 1.0 : 0.0);
  const double f = (m - 1.0) / (m + 1.0);
  const double s = f * f;
  const double series =
      s * (1.0 / 3 + s * (1.0 / 5 + s * (1.0 / 7 + s * (1.0 / 9 + s * (1.0 / 11 + s * (1.0 / 13 + s * (1.0 / 15 +
      s * (1.0 / 17 + s * (1.0 / 19 + s * (1.0 / 21))))))))));
  const double ln_m = 2.0 * f + 2.0 * f * series;
  return (e * portable_math::kLn2Hi + ln_m) + e * portable_math::kLn2Lo;
}

// sin y for |y| <= pi/2, by its Taylor series to y^21/21! (the first term left out, y^23/23!, is below
// 1.3e-18 at pi/2); odd, so sin(-y) = -sin(y) exactly. Past pi/2 the error grows quickly: reduce first.
MESODPD_HD_FORCE double sin_half_period(double y) {
  const double s = y * y;
  return y + y * (s * (-1.0 / 6 + s * (1.0 / 120 + s * (-1.0 / 5040 + s * (1.0 / 362880 + s * (-1.0 / 39916800 +
      s * (1.0 / 6227020800.0 + s * (-1.0 / 1307674368000.0 + s * (1.0 / 355687428096000.0 +
      s * (-1.0 / 121645100408832000.0 + s * (1.0 / 51090942171709440000.0)))))))))));
}

// cos(2 pi u) for u in [0, 1] from the sine above: with t = u - 1/2, cos(2 pi u) = -cos(2 pi t) =
// -sin(2 pi (1/4 - |t|)), the argument in [-pi/2, pi/2]. For the u of u01_open (a multiple of 2^-33)
// t and 1/4 - |t| are exact; only the product with 2 pi and the series round.
MESODPD_HD_FORCE double cos_two_pi(double u) {
  const double t = u - 0.5;
  const double v = 0.25 - (t < 0.0 ? -t : t);
  return -sin_half_period(6.283185307179586 * v);
}

}  // namespace mesodpd
