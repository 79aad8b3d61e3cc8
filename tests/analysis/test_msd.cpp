// Tests of the mean squared displacement and the diffusion coefficient fitted to it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/msd.hpp"

namespace mesodpd {
namespace {

// Particles in storage order `perm` (a permutation of ids), as an engine that re-sorts would give.
struct Snapshot {
  std::vector<std::uint32_t> id;
  std::vector<double> x, y, z;
};

Snapshot permuted(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
                  const std::vector<std::uint32_t>& perm) {
  Snapshot s;
  for (std::uint32_t k : perm) {
    s.id.push_back(k);
    s.x.push_back(x[k]);
    s.y.push_back(y[k]);
    s.z.push_back(z[k]);
  }
  return s;
}

// Gaussian random walks with known D: each component steps by N(0, 2 D dt). Returns D fitted by
// an MSD with the given origins; storage order is reshuffled at every sample.
double random_walk_d(double d_true, std::size_t max_origins, std::size_t origin_every, std::uint64_t seed,
                     MeanSquaredDisplacement* out = nullptr) {
  const std::size_t n = 2000, samples = 100;
  const double dt = 0.1;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> step(0.0, std::sqrt(2.0 * d_true * dt));
  std::uniform_real_distribution<double> u(0.0, 10.0);
  std::vector<double> x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = u(rng);
    y[i] = u(rng);
    z[i] = u(rng);
  }
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0u);
  MeanSquaredDisplacement msd(max_origins, origin_every);
  for (std::size_t s = 0; s < samples; ++s) {
    std::shuffle(perm.begin(), perm.end(), rng);
    const Snapshot snap = permuted(x, y, z, perm);
    msd.sample(1000 + 10 * s, 5.0 + s * dt, snap.id.data(), snap.x.data(), snap.y.data(), snap.z.data(), n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += step(rng);
      y[i] += step(rng);
      z[i] += step(rng);
    }
  }
  if (out) *out = msd;
  return msd.diffusion_coefficient();
}

// Over 200 seeds the fitted D scatters by 3.4% (one origin) and 3.1% (50 origins: the late lags
// that the fit uses have few origins); 12% is 3.5 sd, while a factor 2 or 3 error in the fit
// (MSD = 2 D t, D t) is far outside.
TEST(MeanSquaredDisplacement, RandomWalkRecoversD) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const double d = random_walk_d(0.25, 1, 1, seed);
    EXPECT_NEAR(d, 0.25, 0.12 * 0.25) << "seed " << seed;
  }
}

TEST(MeanSquaredDisplacement, RandomWalkMultipleOrigins) {
  MeanSquaredDisplacement msd;
  const double d = random_walk_d(0.6, 50, 1, 99, &msd);
  EXPECT_NEAR(d, 0.6, 0.12 * 0.6);
  EXPECT_EQ(msd.size(), 100u);
  EXPECT_DOUBLE_EQ(msd.msd()[0], 0.0);
  EXPECT_NEAR(msd.time()[10], 1.0, 1e-12);  // lag time counts from the first sample's time
}

// The multiple-origin average equals a direct average over every (origin, lag) pair that the
// origin schedule allows: origins at samples 0, 2, 4, 6 of 12.
TEST(MeanSquaredDisplacement, OriginAverageMatchesDirectSum) {
  const std::size_t n = 20, samples = 12, every = 2, max_origins = 4;
  std::mt19937_64 rng(77);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<std::vector<double>> x(samples, std::vector<double>(n)), y = x, z = x;
  for (std::size_t s = 0; s < samples; ++s)
    for (std::size_t i = 0; i < n; ++i) {
      x[s][i] = (s ? x[s - 1][i] : 0.0) + gauss(rng);
      y[s][i] = (s ? y[s - 1][i] : 0.0) + gauss(rng);
      z[s][i] = (s ? z[s - 1][i] : 0.0) + gauss(rng);
    }
  std::vector<std::uint32_t> perm(n);
  std::iota(perm.begin(), perm.end(), 100u);  // ids need not start at 0
  MeanSquaredDisplacement msd(max_origins, every);
  for (std::size_t s = 0; s < samples; ++s) {
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<double> px, py, pz;
    for (std::uint32_t k : perm) {
      px.push_back(x[s][k - 100]);
      py.push_back(y[s][k - 100]);
      pz.push_back(z[s][k - 100]);
    }
    msd.sample(7 * s, 0.5 * s, perm.data(), px.data(), py.data(), pz.data(), n);
  }
  const auto m = msd.msd();
  ASSERT_EQ(m.size(), samples);
  for (std::size_t lag = 0; lag < samples; ++lag) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t o = 0; o < max_origins * every; o += every) {
      if (o + lag >= samples) continue;
      double per = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double dx = x[o + lag][i] - x[o][i], dy = y[o + lag][i] - y[o][i], dz = z[o + lag][i] - z[o][i];
        per += dx * dx + dy * dy + dz * dz;
      }
      sum += per / n;
      ++count;
    }
    EXPECT_NEAR(m[lag], sum / count, 1e-12 * (1.0 + sum / count)) << "lag " << lag;
    EXPECT_DOUBLE_EQ(msd.time()[lag], 0.5 * lag);
  }
}

// Ballistic flight r = r0 + v t with |v| fixed gives MSD = v^2 t^2 exactly, even though storage
// order changes: this is what pins the matching by id.
TEST(MeanSquaredDisplacement, BallisticIsQuadratic) {
  const std::size_t n = 300;
  const double speed = 1.7;
  std::mt19937_64 rng(4242);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::vector<double> x0(n), y0(n), z0(n), vx(n), vy(n), vz(n);
  for (std::size_t i = 0; i < n; ++i) {
    x0[i] = u(rng);
    y0[i] = u(rng);
    z0[i] = u(rng);
    const double a = gauss(rng), b = gauss(rng), c = gauss(rng);
    const double norm = std::sqrt(a * a + b * b + c * c);
    vx[i] = speed * a / norm;
    vy[i] = speed * b / norm;
    vz[i] = speed * c / norm;
  }
  for (std::size_t origins : {1u, 5u}) {
    MeanSquaredDisplacement msd(origins, 3);
    std::vector<std::uint32_t> perm(n);
    std::iota(perm.begin(), perm.end(), 0u);
    for (std::size_t s = 0; s < 20; ++s) {
      const double t = 0.25 * s;
      std::vector<double> x(n), y(n), z(n);
      for (std::size_t i = 0; i < n; ++i) {
        x[i] = x0[i] + vx[i] * t;
        y[i] = y0[i] + vy[i] * t;
        z[i] = z0[i] + vz[i] * t;
      }
      std::shuffle(perm.begin(), perm.end(), rng);
      const Snapshot snap = permuted(x, y, z, perm);
      msd.sample(s * 50, t, snap.id.data(), snap.x.data(), snap.y.data(), snap.z.data(), n);
    }
    const auto m = msd.msd();
    ASSERT_EQ(m.size(), 20u);
    for (std::size_t k = 0; k < m.size(); ++k) {
      const double t = msd.time()[k];
      EXPECT_NEAR(m[k], speed * speed * t * t, 1e-10 * (1.0 + t * t))
          << "lag " << k << " origins " << origins;
    }
  }
}

TEST(MeanSquaredDisplacement, RejectsInconsistentSamples) {
  const std::uint32_t id[] = {3, 7};
  const std::uint32_t other[] = {3, 8};
  const std::uint32_t dup[] = {3, 3};
  const double p[] = {0.0, 1.0};
  MeanSquaredDisplacement one;
  one.sample(0, 0.0, id, p, p, p, 2);
  EXPECT_THROW(one.sample(10, 1.0, other, p, p, p, 2), std::invalid_argument);
  EXPECT_THROW(one.sample(10, 1.0, dup, p, p, p, 2), std::invalid_argument);
  EXPECT_THROW(one.sample(10, 1.0, id, p, p, p, 1), std::invalid_argument);
  EXPECT_THROW(one.sample(0, 1.0, id, p, p, p, 2), std::invalid_argument);  // step did not advance
  EXPECT_TRUE(std::isnan(one.diffusion_coefficient()));                     // one point only
  EXPECT_NO_THROW(one.sample(30, 3.0, id, p, p, p, 2));                     // any spacing, one origin

  MeanSquaredDisplacement many(4, 1);
  many.sample(0, 0.0, id, p, p, p, 2);
  many.sample(10, 1.0, id, p, p, p, 2);
  EXPECT_THROW(many.sample(30, 3.0, id, p, p, p, 2), std::invalid_argument);
  EXPECT_THROW(MeanSquaredDisplacement(0, 1), std::invalid_argument);
}

TEST(MeanSquaredDisplacement, WritesCsv) {
  MeanSquaredDisplacement msd;
  random_walk_d(0.5, 1, 1, 5, &msd);
  const std::string path = ::testing::TempDir() + "msd_test.csv";
  msd.write_csv(path);
  std::ifstream is(path);
  std::string line;
  std::getline(is, line);
  EXPECT_EQ(line, "time,msd");
  int rows = 0;
  while (std::getline(is, line)) ++rows;
  EXPECT_EQ(rows, 100);
}

}  // namespace
}  // namespace mesodpd
