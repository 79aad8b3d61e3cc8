// Unit tests of the DPD force law and the pair noise: symmetry, r = 0, F = -dU/dr, noise moments.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "core/philox.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/power.hpp"
#include "physics/soft_pair.hpp"

using namespace mesodpd;

namespace {
DpdPairParams params(double s, double rc = 1.0, double rd = 1.0) {
  DpdPairParams p;
  p.a = 25.0;
  p.gamma = 4.5;
  p.sigma = std::sqrt(2 * 4.5);
  p.rc = rc;
  p.rd = rd;
  p.s = s;
  const double m = std::max(rc, rd);
  p.rcut2 = m * m;
  return p;
}
}  // namespace

TEST(PairForce, NoNanAtZeroDistance) {
  const DpdPairForce f = dpd_pair_force(params(2.0), 0.0, 0.0, 1.0, 5.0);
  EXPECT_EQ(f.fc, 0.0);
  EXPECT_EQ(f.fd, 0.0);
  EXPECT_EQ(f.fr, 0.0);
  EXPECT_FALSE(std::isnan(f.energy));
}

TEST(PairForce, ConservativeIsMinusGradientOfEnergy) {
  for (double rc : {1.0, 1.3}) {
    const DpdPairParams p = params(2.0, rc, 1.0);
    for (double r = 0.05; r < rc - 0.01; r += 0.05) {
      const double h = 1e-6;
      const double up = dpd_pair_force(p, r + h, 0, 0, 1).energy, um = dpd_pair_force(p, r - h, 0, 0, 1).energy;
      const double fd = -(up - um) / (2 * h);
      EXPECT_NEAR(dpd_pair_force(p, r, 0, 0, 1).fc, fd, 1e-7 * p.a) << "r = " << r;
    }
    EXPECT_EQ(dpd_pair_force(p, rc + 1e-12, 0, 0, 1).fc, 0.0);
  }
}

TEST(PairForce, WeightFunctionsSatisfyFluctuationDissipation) {
  // w_D = w_R^2 for every exponent (seed 000 Eq. 6): compare fd/gamma with (fr/sigma)^2 at unit rv, xi.
  for (double s : {2.0, 1.0, 0.5, 0.25, 1.7}) {
    const DpdPairParams p = params(s, 1.0, 1.3);
    for (double r = 0.1; r < 1.3; r += 0.1) {
      const DpdPairForce f = dpd_pair_force(p, r, -1.0, 1.0, 1.0);
      const double wd = f.fd / p.gamma, wr = f.fr / p.sigma;
      EXPECT_NEAR(wd, wr * wr, 1e-12) << "s = " << s << " r = " << r;
      EXPECT_NEAR(wd, std::pow(1 - r / 1.3, s), 1e-12);
    }
  }
}

TEST(PairNoise, SymmetricInIdsAndDifferentForOtherPairsOrSteps) {
  for (std::uint32_t i = 1; i < 50; ++i)
    for (std::uint32_t j = i + 1; j < 60; j += 7) {
      EXPECT_EQ(pair_noise(7, 11, i, j, NoiseKind::Uniform), pair_noise(7, 11, j, i, NoiseKind::Uniform));
      EXPECT_EQ(pair_noise(7, 11, i, j, NoiseKind::Gaussian), pair_noise(7, 11, j, i, NoiseKind::Gaussian));
    }
  EXPECT_NE(pair_noise(7, 11, 1, 2, NoiseKind::Uniform), pair_noise(7, 12, 1, 2, NoiseKind::Uniform));
  EXPECT_NE(pair_noise(7, 11, 1, 2, NoiseKind::Uniform), pair_noise(8, 11, 1, 2, NoiseKind::Uniform));
  EXPECT_NE(pair_noise(7, 11, 1, 2, NoiseKind::Uniform), pair_noise(7, 11, 1, 3, NoiseKind::Uniform));
}

TEST(PairNoise, PhiloxKnownAnswer) {
  // Known-answer vectors of Philox-4x32-10 (Salmon et al., Random123 distribution).
  const Philox4x32 z = philox4x32_10(Philox4x32{{0, 0, 0, 0}}, 0, 0);
  EXPECT_EQ(z.v[0], 0x6627e8d5u);
  EXPECT_EQ(z.v[1], 0xe169c58du);
  EXPECT_EQ(z.v[2], 0xbc57ac4cu);
  EXPECT_EQ(z.v[3], 0x9b00dbd8u);
  const Philox4x32 pi = philox4x32_10(Philox4x32{{0x243f6a88u, 0x85a308d3u, 0x13198a2eu, 0x03707344u}},
                                      0xa4093822u, 0x299f31d0u);
  EXPECT_EQ(pi.v[0], 0xd16cfe09u);
  EXPECT_EQ(pi.v[1], 0x94fdccebu);
  EXPECT_EQ(pi.v[2], 0x5001e420u);
  EXPECT_EQ(pi.v[3], 0x24126ea1u);
}

TEST(PairNoise, ZeroMeanUnitVarianceAndNoCorrelation) {
  // 400k draws: standard error of the mean 1/sqrt(n) = 0.0016; assert within 5 standard errors.
  for (NoiseKind kind : {NoiseKind::Uniform, NoiseKind::Gaussian}) {
    const int n = 400000;
    double s1 = 0, s2 = 0, s4 = 0, lag = 0, prev = 0;
    for (int k = 0; k < n; ++k) {
      const double x = pair_noise(99, static_cast<std::uint64_t>(k / 1000), static_cast<std::uint32_t>(k % 1000), 5000, kind);
      s1 += x;
      s2 += x * x;
      s4 += x * x * x * x;
      lag += x * prev;
      prev = x;
    }
    const double se = 1.0 / std::sqrt(n);
    EXPECT_NEAR(s1 / n, 0.0, 5 * se);
    EXPECT_NEAR(s2 / n, 1.0, 5 * se * std::sqrt(2.0));
    EXPECT_NEAR(lag / n, 0.0, 5 * se);
    // Fourth moment distinguishes the distributions: 9/5 for the uniform, 3 for the Gaussian.
    EXPECT_NEAR(s4 / n, kind == NoiseKind::Uniform ? 1.8 : 3.0, 0.05);
  }
}

TEST(PairForce, ActionEqualsReactionExactly) {
  // The force on j is evaluated from j's side (displacement and relative velocity negated, same noise
  // because xi_ij = xi_ji): it must be exactly the negative of the force on i, bit for bit.
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double s : {2.0, 1.0, 0.5, 0.25, 1.7}) {
    const DpdPairParams p = params(s, 1.0, 1.2);
    for (int k = 0; k < 2000; ++k) {
      const Vec3 d{u(rng), u(rng), u(rng)}, v{3 * u(rng), 3 * u(rng), 3 * u(rng)};
      const double r = std::sqrt(dot(d, d));
      const std::uint32_t id_i = 7 + static_cast<std::uint32_t>(k), id_j = 9000 + static_cast<std::uint32_t>(k);
      auto force_on = [&](Vec3 dd, Vec3 vv, std::uint32_t a, std::uint32_t b) {
        const double rv = dot(dd, vv) / r;
        const DpdPairForce f = dpd_pair_force(p, r, rv, pair_noise(3, 17, a, b, NoiseKind::Gaussian), 5.0);
        return ((f.fc + f.fd + f.fr) / r) * dd;
      };
      const Vec3 fi = force_on(d, v, id_i, id_j), fj = force_on(-d, -v, id_j, id_i);
      ASSERT_EQ(fi.x, -fj.x);
      ASSERT_EQ(fi.y, -fj.y);
      ASSERT_EQ(fi.z, -fj.z);
    }
  }
}

TEST(SoftPair, ForceIsMinusGradientOfEnergyAndVanishesAtTheEnds) {
  // U = A [1 + cos(pi r / r_c)]: F = -dU/dr by central differences inside, zero at r = 0, zero at and
  // beyond r_c, where U also reaches 0 (the potential is continuous).
  for (const double rc : {0.8, 1.0, 1.3}) {
    const SoftPairParamsT<double> p{12.0, rc, rc * rc};
    const SoftLaw::Eval eval;
    auto at = [&](double r) {
      PairInput<double> in;
      in.r = r;
      return eval(p, in);
    };
    for (double r = 0.05; r < rc - 0.01; r += 0.037) {
      const double h = 1e-6;
      const double fd = -(at(r + h).energy - at(r - h).energy) / (2 * h);
      EXPECT_NEAR(at(r).fc, fd, 1e-6 * p.a) << "r = " << r;
      EXPECT_GT(at(r).fc, 0.0) << "repulsive everywhere inside, r = " << r;
    }
    EXPECT_EQ(at(0.0).fc, 0.0);
    EXPECT_NEAR(at(0.0).energy, 2 * p.a, 1e-12);
    EXPECT_EQ(at(rc).fc, 0.0);
    EXPECT_EQ(at(rc).energy, 0.0);
    EXPECT_EQ(at(rc + 0.1).energy, 0.0);
    EXPECT_NEAR(at(rc - 1e-9).energy, 0.0, 1e-9);
  }
}

// pow_pos (physics/power.hpp), the pair laws' vectorisable power, against std::pow: a relative error
// below 1e-15 (|y ln x| + 1) over the weights' range (x in (0, 1], exponents 0.005-10) and beyond it
// (x up to 1e6, negative y), the edge cases exactly, and underflow to 0 past e^-708.
TEST(Power, MatchesStdPowToAFewUlp) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0;
  for (int k = 0; k < 200000; ++k) {
    double x = unit(gen);
    if (k % 4 == 1) x = std::pow(10.0, -16 * unit(gen));  // down to the smallest weight 1 - r/rc can hold
    if (k % 4 == 2) x = std::pow(10.0, 12 * unit(gen) - 6);
    if (x == 0.0) continue;
    double y = 10 * unit(gen);
    if (k % 3 == 1) y = 0.005 + 0.1 * unit(gen);
    if (k % 5 == 2) y = -3 * unit(gen);
    const double t = y * std::log(x);
    if (t < -700 || t > 700) continue;
    const double want = std::pow(x, y);
    const double err = std::abs(pow_pos(x, y) - want) / want / (std::abs(t) + 1);
    worst = std::max(worst, err);
    ASSERT_LT(err, 1e-15) << "x " << x << " y " << y;
  }
  std::printf("pow_pos: largest relative error / (|y ln x| + 1) = %.3g\n", worst);
  for (const double x : {1.0, 0.5, 0.25, 2.0, 1024.0}) EXPECT_EQ(pow_pos(x, 1.0), x);
  EXPECT_EQ(pow_pos(0.3, 0.0), 1.0);
  EXPECT_EQ(pow_pos(0.0, 2.5), 0.0);
  EXPECT_EQ(pow_pos(0.0, 0.005), 0.0);
  const double tiny = std::numeric_limits<double>::min();  // the smallest normal number
  EXPECT_NEAR(pow_pos(tiny, 0.5) / std::sqrt(tiny), 1.0, 1e-12);
  EXPECT_NEAR(pow_pos(1e-200, 1.6) / std::pow(1e-200, 1.6), 1.0, 1e-9);  // a subnormal result
  EXPECT_EQ(pow_pos(1e-300, 3.0), 0.0);
  EXPECT_TRUE(std::isinf(pow_pos(1e300, 3.0)));
  EXPECT_NEAR(pow_pos(0.5f, 0.205f), std::pow(0.5f, 0.205f), 1e-7f);
}

// The logarithm and cosine of core/portable_math.hpp against the library's, over the arguments the
// Gaussian pair noise gives them (u01_open of every kind of 32-bit word, the extremes included), and the
// Box-Muller variate built from them against gaussian_unit, which uses the library functions.
TEST(PortableMath, LogCosineAndGaussianMatchTheLibrary) {
  std::mt19937_64 gen(31);
  double worst_ln = 0, worst_cos = 0, worst_gauss = 0;
  for (int k = 0; k < 1000000; ++k) {
    std::uint32_t w0 = static_cast<std::uint32_t>(gen()), w1 = static_cast<std::uint32_t>(gen());
    if (k < 4) {  // the extremes of both words
      w0 = (k & 1) != 0 ? 0xFFFFFFFFu : 0u;
      w1 = (k & 2) != 0 ? 0xFFFFFFFFu : 0u;
    }
    if (k % 7 == 3) w0 >>= (k % 32);  // small u: the tail of the Gaussian
    const double u = u01_open(w0), v = u01_open(w1);
    worst_ln = std::max(worst_ln, std::abs(ln_pos(u) - std::log(u)) / std::abs(std::log(u)));
    worst_cos = std::max(worst_cos, std::abs(cos_two_pi(v) - std::cos(6.283185307179586 * v)));
    const double g = gaussian_unit_portable(w0, w1), want = gaussian_unit(w0, w1);
    worst_gauss = std::max(worst_gauss, std::abs(g - want) / (1.0 + std::sqrt(-2.0 * std::log(u))));
  }
  std::printf("ln_pos: largest relative error %.3g; cos_two_pi: largest absolute error %.3g; Gaussian: largest "
              "error / (1 + radius) %.3g\n", worst_ln, worst_cos, worst_gauss);
  // ln: a few units in the last place. The cosine: the library's own argument 2 pi v rounds (up to
  // 4.4e-16 near v = 1), so the two differ by about an ulp of 2 pi. The variate: the radius
  // sqrt(-2 ln u) (up to 6.8) times the cosine's error, plus the radius's own rounding.
  EXPECT_LT(worst_ln, 1e-15);
  EXPECT_LT(worst_cos, 2e-15);
  EXPECT_LT(worst_gauss, 2e-15);
  // Exact values: ln 1 = 0, ln 2^k = k ln 2 to an ulp, cos at the quarter periods.
  EXPECT_EQ(ln_pos(1.0), 0.0);
  EXPECT_NEAR(ln_pos(0.125), -3 * std::log(2.0), 1e-15);
  EXPECT_EQ(cos_two_pi(0.5), -1.0);
  EXPECT_EQ(cos_two_pi(0.0), 1.0);
  EXPECT_EQ(cos_two_pi(0.25), 0.0);
  EXPECT_EQ(sin_half_period(0.0), 0.0);
  EXPECT_EQ(sin_half_period(-0.3), -sin_half_period(0.3));
}
