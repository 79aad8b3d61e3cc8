// x^y for the pair laws' weights, (1 - r/r_c)^s with a run-time exponent s (eDPD's s(T), a general s of
// standard DPD, tDPD's and sp-DPD's exponents), written with plain arithmetic and bit operations only so
// that the compiler vectorises the pair loop around it. std::pow is a library call per pair, which keeps
// the whole law scalar (docs/performance.md, sessions 18 and 28).
//
// Method: x = 2^e m with m in [sqrt(1/2), sqrt(2)), ln m = 2 atanh(f) = 2 (f + f^3/3 + f^5/5 + ...) with
// f = (m - 1)/(m + 1), |f| <= 0.1716 (ten odd terms: the first left out is below 3e-17 of the sum);
// t = y (e ln 2 + ln m); then x^y = e^t = 2^n e^r with n = round(t / ln 2) and |r| <= ln(2)/2 (ln 2 split
// in two parts, Cody and Waite, so that n ln2_hi is exact), e^r by its Taylor series to r^13/13! (the
// first term left out is below 5e-18). Rounding follows from IEEE operations alone: no fused
// multiply-add (the project compiles with -ffp-contract=off), no table, no library call, so every SIMD
// target, the scalar reference loop and a future GPU backend get the same bits. The selects below
// vectorise where the file is compiled with -fno-trapping-math (engine/force_compute.cpp is); elsewhere
// the same arithmetic runs lane by lane.
//
// Domain: x = 0 or a normal positive number, y finite. Results past the double range underflow
// (through the subnormals) to 0 and overflow to +inf; 0^y is 0 for every y. Accuracy against
// std::pow: a relative error below 1e-15 (|y ln x| + 1) (tests/physics/test_pair_force.cpp, Power.MatchesStdPowToAFewUlp).
#pragma once
#include <bit>
#include <cstdint>

#include "core/hd.hpp"

namespace mesodpd {

namespace power_detail {

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

}  // namespace power_detail

// x^y for x >= 0 (see the header comment for the domain and the accuracy).
MESODPD_HD_FORCE double pow_pos(double x, double y) {
  using power_detail::bits_of;
  using power_detail::double_of;
  constexpr std::uint64_t kMantissa = 0x000FFFFFFFFFFFFFull;
  constexpr std::uint64_t kOne = 0x3FF0000000000000ull;      // the bits of 1.0
  constexpr std::uint64_t kTwo52 = 0x4330000000000000ull;    // the bits of 2^52
  constexpr double kTwo52d = 4503599627370496.0;             // 2^52
  constexpr double kRound = 6755399441055744.0;              // 1.5 * 2^52: adding it rounds to an integer
  constexpr double kSqrt2 = 1.41421356237309504880;
  constexpr double kLn2Hi = 6.93147180369123816490e-01;      // ln 2 to 32 bits: n kLn2Hi is exact
  constexpr double kLn2Lo = 1.90821492927058770002e-10;      // ln 2 - kLn2Hi
  constexpr double kInvLn2 = 1.44269504088896338700e+00;

  // x = 2^e m, m in [1, 2); then m in [sqrt(1/2), sqrt(2)). The biased exponent becomes a double
  // without an integer conversion (which AVX2 lacks for 64-bit lanes): its bits below those of 2^52.
  const std::uint64_t u = bits_of(x);
  const double m1 = double_of((u & kMantissa) | kOne);
  const double e1 = double_of((u >> 52) | kTwo52) - (kTwo52d + 1023.0);
  const bool high = m1 > kSqrt2;
  const double m = m1 * (high ? 0.5 : 1.0);
  const double e = e1 + (high ? 1.0 : 0.0);

  // ln m = 2 (f + f^3/3 + ... + f^21/21).
  const double f = (m - 1.0) / (m + 1.0);
  const double s = f * f;
  const double series =
      s * (1.0 / 3 + s * (1.0 / 5 + s * (1.0 / 7 + s * (1.0 / 9 + s * (1.0 / 11 + s * (1.0 / 13 + s * (1.0 / 15 +
      s * (1.0 / 17 + s * (1.0 / 19 + s * (1.0 / 21))))))))));
  const double ln_m = 2.0 * f + 2.0 * f * series;
  const double ln_x = (e * kLn2Hi + ln_m) + e * kLn2Lo;
  double t = y * ln_x;

  // e^t = 2^n e^r. 2^n is applied as two factors, 2^n1 2^(n - n1) with n1 = round(n/2), each a normal
  // number for |t| < 1416, so that results below the smallest normal number come out as subnormals or
  // 0 and those past the largest as +inf without testing t again. Past |t| = 1400 the result is 0 or
  // +inf anyway, so t is clamped there.
  t = t < -1400.0 ? -1400.0 : (t > 1400.0 ? 1400.0 : t);
  const double n = (t * kInvLn2 + kRound) - kRound;
  const double r = (t - n * kLn2Hi) - n * kLn2Lo;
  const double er =
      1.0 + r * (1.0 + r * (1.0 / 2 + r * (1.0 / 6 + r * (1.0 / 24 + r * (1.0 / 120 + r * (1.0 / 720 +
      r * (1.0 / 5040 + r * (1.0 / 40320 + r * (1.0 / 362880 + r * (1.0 / 3628800 + r * (1.0 / 39916800 +
      r * (1.0 / 479001600 + r * (1.0 / 6227020800.0)))))))))))));
  const double n1 = (0.5 * n + kRound) - kRound;
  const double n2 = n - n1;
  // 2^k from the bits of k + 1023 + 2^52, whose low bits hold k + 1023 (1..2046 here).
  const double scale1 = double_of(bits_of(n1 + (1023.0 + kTwo52d)) << 52);
  const double scale2 = double_of(bits_of(n2 + (1023.0 + kTwo52d)) << 52);
  const double out = (er * scale1) * scale2;
  // 0^y = 0 (ln 0 would be read from a zero exponent field). Not 1 for y = 0 nor +inf for y < 0: a
  // select on y, a loop constant in most calls, would keep the pair loop from vectorising, and no law
  // passes x = 0 with y <= 0 (its exponents are positive where 1 - r/r_c can be 0).
  return x > 0.0 ? out : 0.0;
}

// Single precision: the double path, rounded once (a float has no room for the splitting above).
MESODPD_HD_FORCE float pow_pos(float x, float y) {
  return static_cast<float>(pow_pos(static_cast<double>(x), static_cast<double>(y)));
}

}  // namespace mesodpd
