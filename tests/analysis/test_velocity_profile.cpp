// Tests of the reverse-Poiseuille profile and its viscosity fit on synthetic flows of known eta.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/velocity_profile.hpp"

namespace mesodpd {
namespace {

constexpr double kLen = 20.0;
constexpr double kG = 0.05;
constexpr double kRho = 3.0;

// The exact reverse Poiseuille solution (seed 002, Backer et al.) for viscosity eta.
double exact_v(double z, double eta, double v0) {
  const double c = kRho * kG / (2.0 * eta);
  const double h = kLen / 2.0;
  return z < h ? c * z * (h - z) + v0 : -c * (z - h) * (kLen - z) + v0;
}

// Particles uniform across the channel, velocity = exact profile + thermal-like Gaussian noise.
PoiseuilleProfile synthetic_run(double eta, std::size_t samples, std::size_t blocks, std::uint64_t seed,
                                std::size_t n = 1000, double noise = 1.0) {
  PoiseuilleProfile prof(40, 0, 2, kLen, blocks, kG, kRho);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, kLen);
  std::normal_distribution<double> gauss(0.0, noise);
  std::vector<double> z(n), v(n);
  for (std::size_t s = 0; s < samples; ++s) {
    for (std::size_t i = 0; i < n; ++i) {
      z[i] = u(rng);
      v[i] = exact_v(z[i], eta, 0.3) + gauss(rng);
      if (i % 7 == 0) z[i] += kLen;  // unwrapped coordinates must be wrapped by the profile
    }
    prof.sample(z.data(), v.data(), n);
  }
  return prof;
}

// Without noise the fit is exact because the basis is the bin average of the parabola: evenly
// spaced particles (1000 per bin) sample that average to O((dz/1000)^2). A basis taken at bin
// centres would be off by dz^2/12 with opposite signs in the two halves and fail this.
TEST(PoiseuilleProfile, NoiselessProfileGivesExactEta) {
  const double eta = 0.85;
  PoiseuilleProfile prof(40, 0, 2, kLen, 4, kG, kRho);
  const std::size_t n = 40 * 1000;  // 1000 evenly spaced particles per bin
  std::vector<double> z(n), v(n);
  for (std::size_t i = 0; i < n; ++i) {
    z[i] = (static_cast<double>(i) + 0.5) * kLen / n;
    v[i] = exact_v(z[i], eta, -0.2);
  }
  for (int s = 0; s < 8; ++s) prof.sample(z.data(), v.data(), n);
  const ViscosityFit f = prof.fit();
  EXPECT_NEAR(f.eta, eta, 1e-6 * eta);
  EXPECT_NEAR(f.v_amplitude, kRho * kG / (2.0 * eta) * kLen * kLen / 16.0, 1e-6);
  EXPECT_EQ(f.blocks_used, 4);
  EXPECT_NEAR(f.eta_err, 0.0, 1e-6 * eta);  // identical blocks
  const auto vf = prof.v_fit();
  const auto vm = prof.v_mean();
  for (std::size_t b = 0; b < vf.size(); ++b) EXPECT_NEAR(vf[b], vm[b], 1e-8);
}

TEST(PoiseuilleProfile, NoisyProfileWithinThreeSigma) {
  const double eta = 0.96;
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    const PoiseuilleProfile prof = synthetic_run(eta, 200, 16, seed);
    const ViscosityFit f = prof.fit();
    ASSERT_GE(f.blocks_used, 16);
    ASSERT_LT(f.blocks_used, 32);
    ASSERT_GT(f.eta_err, 0.0);
    EXPECT_LT(std::fabs(f.eta - eta), 3.0 * f.eta_err)
        << "seed " << seed << " eta " << f.eta << " ± " << f.eta_err;
    EXPECT_LT(f.eta_err, 0.05 * eta);
  }
}

// The error bar must be honest, not just small: over independent runs the normalised errors
// (eta - eta_true) / eta_err should have mean square ~ 1: 15/13 for a t-distribution with 15
// degrees of freedom, with sd ~ 0.18 over 100 runs. Reporting the block sd instead of the standard
// error (mean square ~ 1/16) or being off by a factor 2 (~ 4.6 or ~ 0.29) fails.
TEST(PoiseuilleProfile, ErrorBarIsCalibrated) {
  const double eta = 1.2;
  const int runs = 100;
  double sum_z2 = 0.0;
  for (int r = 0; r < runs; ++r) {
    const ViscosityFit f = synthetic_run(eta, 64, 16, 1000 + r, 400).fit();
    ASSERT_EQ(f.blocks_used, 16);
    const double zscore = (f.eta - eta) / f.eta_err;
    sum_z2 += zscore * zscore;
  }
  const double mean_z2 = sum_z2 / runs;
  EXPECT_GT(mean_z2, 0.6);
  EXPECT_LT(mean_z2, 1.8);
}

TEST(PoiseuilleProfile, ErrorShrinksWithMoreData) {
  const double eta = 0.96;
  const ViscosityFit small = synthetic_run(eta, 100, 16, 21).fit();
  const ViscosityFit large = synthetic_run(eta, 400, 16, 22).fit();
  // Four times the data: expect half the error; allow for the noise of a 16-31 block estimate.
  EXPECT_LT(large.eta_err, 0.75 * small.eta_err);
  EXPECT_GT(large.eta_err, 0.3 * small.eta_err);
}

TEST(PoiseuilleProfile, BlocksStayEqualAndBounded) {
  PoiseuilleProfile prof(10, 0, 1, 5.0, 3, 0.1, 1.0);
  const double z = 1.0, v = 0.5;
  for (std::size_t s = 1; s <= 100; ++s) {
    prof.sample(&z, &v, 1);
    const ViscosityFit f = prof.fit();  // with one occupied bin there is no fit, only the count
    const std::size_t full = s / prof.samples_per_block();
    if (s >= 3) {
      EXPECT_EQ(static_cast<std::size_t>(f.blocks_used), full) << "after " << s;
      EXPECT_GE(f.blocks_used, 3);
      EXPECT_LE(f.blocks_used, 5);
    }
    EXPECT_TRUE(std::isnan(f.eta));
  }
  EXPECT_EQ(prof.samples(), 100u);
}

TEST(PoiseuilleProfile, RejectsBadParameters) {
  EXPECT_THROW(PoiseuilleProfile(1, 0, 2, 10.0, 4, 0.1, 3.0), std::invalid_argument);
  EXPECT_THROW(PoiseuilleProfile(10, 2, 2, 10.0, 4, 0.1, 3.0), std::invalid_argument);
  EXPECT_THROW(PoiseuilleProfile(10, 0, 3, 10.0, 4, 0.1, 3.0), std::invalid_argument);
  EXPECT_THROW(PoiseuilleProfile(10, 0, 2, 0.0, 4, 0.1, 3.0), std::invalid_argument);
  EXPECT_THROW(PoiseuilleProfile(10, 0, 2, 10.0, 1, 0.1, 3.0), std::invalid_argument);
  EXPECT_THROW(PoiseuilleProfile(10, 0, 2, 10.0, 4, 0.0, 3.0), std::invalid_argument);
  EXPECT_THROW(PoiseuilleProfile(10, 0, 2, 10.0, 4, 0.1, -1.0), std::invalid_argument);
}

TEST(PoiseuilleProfile, WritesCsvAndSummary) {
  const PoiseuilleProfile prof = synthetic_run(1.0, 40, 4, 3);
  const std::string path = ::testing::TempDir() + "profile_test.csv";
  prof.write_csv(path);
  std::ifstream is(path);
  std::string line;
  std::getline(is, line);
  EXPECT_EQ(line, "z,v_mean,v_err,v_fit");
  int rows = 0;
  while (std::getline(is, line)) {
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 3);
  }
  EXPECT_EQ(rows, 40);

  const std::string spath = ::testing::TempDir() + "viscosity_test.csv";
  write_viscosity_summary_csv(spath, prof.fit(), 0.96);
  std::ifstream ss(spath);
  std::getline(ss, line);
  EXPECT_EQ(line, "eta,eta_err,v_amplitude,blocks_used,eta_kinetic");
  std::getline(ss, line);
  EXPECT_NE(line.find(",0.96"), std::string::npos);
}

}  // namespace
}  // namespace mesodpd
