// x^y for the pair laws' weights, (1 - r/r_c)^s with a run-time exponent s (eDPD's s(T), a general s of
// standard DPD, tDPD's and sp-DPD's exponents), written with plain arithmetic and bit operations only so
// that the compiler vectorises the pair loop around it. std::pow is a library call per pair, which keeps
// the whole law scalar (docs/performance.md, sessions 18 and 28).
//
// Method: t = y ln x with the logarithm of core/portable_math.hpp; then x^y = e^t = 2^n e^r with
// n = round(t / ln 2) and |r| <= ln(2)/2 (ln 2 split in two parts, Cody and Waite, so that n ln2_hi is
// exact), e^r by its Taylor series to r^13/13! (the first term left out is below 5e-18). Plain IEEE
// arithmetic and bit operations as in that header, so every SIMD target, the scalar reference loop and a
// future GPU backend get the same bits.
//
// Domain: x = 0 or a normal positive number, y finite. Results past the double range underflow
// (through the subnormals) to 0 and overflow to +inf; 0^y is 0 for every y. Accuracy against
// std::pow: a relative error below 1e-15 (|y ln x| + 1) (tests/physics/test_pair_force.cpp, Power.MatchesStdPowToAFewUlp).
#pragma once
#include <cstdint>

#include "core/hd.hpp"
#include "core/portable_math.hpp"

namespace mesodpd {

// x^y for x >= 0 (see the header comment for the domain and the accuracy).
MESODPD_HD_FORCE double pow_pos(double x, double y) {
  using portable_math::bits_of;
  using portable_math::double_of;
  using portable_math::kLn2Hi;
  using portable_math::kLn2Lo;
  constexpr double kTwo52d = 4503599627370496.0;             // 2^52
  constexpr double kRound = 6755399441055744.0;              // 1.5 * 2^52: adding it rounds to an integer
  constexpr double kInvLn2 = 1.44269504088896338700e+00;
  double t = y * ln_pos(x);  // ln 0 is read from a zero exponent field: finite garbage, replaced below

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
