// Tests of the radial distribution function and the virial pressure from it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/rdf.hpp"

namespace mesodpd {
namespace {

struct Points {
  std::vector<double> x, y, z;
};

Points uniform_points(std::size_t n, std::array<double, 3> box, std::mt19937_64& rng) {
  Points p;
  std::uniform_real_distribution<double> ux(0.0, box[0]), uy(0.0, box[1]), uz(0.0, box[2]);
  for (std::size_t i = 0; i < n; ++i) {
    p.x.push_back(ux(rng));
    p.y.push_back(uy(rng));
    p.z.push_back(uz(rng));
  }
  return p;
}

// The definition: every ordered pair, minimum image by explicit comparison with L/2.
std::vector<std::uint64_t> brute_force_counts(const Points& p, std::array<double, 3> box, std::size_t bins,
                                              double rmax) {
  std::vector<std::uint64_t> counts(bins, 0);
  const double dr = rmax / static_cast<double>(bins);
  const auto image = [](double d, double len) {
    if (d > 0.5 * len) return d - len;
    if (d < -0.5 * len) return d + len;
    return d;
  };
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    for (std::size_t j = 0; j < p.x.size(); ++j) {
      if (i == j) continue;
      const double dx = image(p.x[j] - p.x[i], box[0]);
      const double dy = image(p.y[j] - p.y[i], box[1]);
      const double dz = image(p.z[j] - p.z[i], box[2]);
      const double r2 = dx * dx + dy * dy + dz * dz;
      if (r2 >= rmax * rmax) continue;
      ++counts[std::min(static_cast<std::size_t>(std::sqrt(r2) / dr), bins - 1)];
    }
  }
  return counts;
}

TEST(RadialDistribution, CellBinningEqualsBruteForce) {
  struct Case {
    std::array<double, 3> box;
    double rmax;
    std::size_t n;
  };
  // Shapes chosen to hit 2 cells along an axis (shifts alias), odd counts, and the cell cap.
  const Case cases[] = {{{6.0, 6.0, 6.0}, 2.5, 400},
                        {{10.0, 7.0, 5.5}, 2.0, 600},
                        {{15.0, 4.2, 9.0}, 1.5, 500},
                        {{20.0, 20.0, 20.0}, 1.0, 300},
                        {{3.1, 12.0, 8.0}, 1.5, 350}};
  std::mt19937_64 rng(20240611);
  for (const Case& c : cases) {
    Points p = uniform_points(c.n, c.box, rng);
    // Edge positions: exactly 0 and the largest double below L.
    p.x[0] = 0.0;
    p.y[1] = std::nextafter(c.box[1], 0.0);
    p.z[2] = std::nextafter(c.box[2], 0.0);
    const std::size_t bins = 37;
    RadialDistribution rdf(bins, c.rmax);
    rdf.sample(p.x.data(), p.y.data(), p.z.data(), p.x.size(), c.box);
    const auto expected = brute_force_counts(p, c.box, bins, c.rmax);
    ASSERT_EQ(rdf.counts(), expected) << "box " << c.box[0] << "x" << c.box[1] << "x" << c.box[2];
    std::uint64_t total = 0;
    for (auto k : expected) total += k;
    EXPECT_GT(total, 0u);
  }
}

TEST(RadialDistribution, IdealGasIsFlat) {
  const std::array<double, 3> box{10.0, 10.0, 10.0};
  const std::size_t n = 1000, bins = 30, samples = 20;
  const double rmax = 3.0;
  RadialDistribution rdf(bins, rmax);
  std::mt19937_64 rng(12345);
  for (std::size_t s = 0; s < samples; ++s) {
    const Points p = uniform_points(n, box, rng);
    rdf.sample(p.x.data(), p.y.data(), p.z.data(), n, box);
  }
  // On a torus the displacement of independent uniform points is uniform and independent of either
  // point, so unordered-pair counts per shell are sums of pairwise independent Bernoulli variables:
  // variance = mean (1 - p) ~ mean. Chi-square over bins then has mean ~ bins, sd ~ sqrt(2 bins).
  const double volume = box[0] * box[1] * box[2];
  const double pairs = static_cast<double>(samples) * n * (n - 1) / 2.0;
  const double dr = rmax / bins;
  const auto g = rdf.g();
  double chi2 = 0.0;
  for (std::size_t b = 0; b < bins; ++b) {
    const double lo = b * dr, hi = lo + dr;
    const double expected = pairs * 4.0 / 3.0 * std::numbers::pi * (hi * hi * hi - lo * lo * lo) / volume;
    const double observed = static_cast<double>(rdf.counts()[b]) / 2.0;
    chi2 += (observed - expected) * (observed - expected) / expected;
    EXPECT_NEAR(g[b], 1.0, 5.0 / std::sqrt(expected)) << "bin " << b;
  }
  EXPECT_LT(chi2, bins + 5.0 * std::sqrt(2.0 * bins));
  EXPECT_GT(chi2, 0.0);
}

TEST(RadialDistribution, SimpleCubicLatticeShells) {
  const int m = 8;
  const double a = 1.0;
  const std::array<double, 3> box{m * a, m * a, m * a};
  Points p;
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j)
      for (int k = 0; k < m; ++k) {
        p.x.push_back((i + 0.5) * a);
        p.y.push_back((j + 0.5) * a);
        p.z.push_back((k + 0.5) * a);
      }
  const std::size_t n = p.x.size();
  // dr = 1/10.25 keeps every shell radius (1, sqrt2, sqrt3, 2, sqrt5, sqrt6) away from a bin edge.
  const std::size_t bins = 26;
  const double dr = 1.0 / 10.25;
  RadialDistribution rdf(bins, bins * dr);
  rdf.sample(p.x.data(), p.y.data(), p.z.data(), n, box);

  std::vector<std::uint64_t> expected(bins, 0);
  const std::pair<double, std::uint64_t> shells[] = {{1.0, 6}, {std::sqrt(2.0), 12}, {std::sqrt(3.0), 8},
                                                     {2.0, 6}, {std::sqrt(5.0), 24}, {std::sqrt(6.0), 24}};
  for (const auto& [r, coordination] : shells)
    expected[static_cast<std::size_t>(r * a / dr)] += coordination * n;
  EXPECT_EQ(rdf.counts(), expected);

  // The first non-empty bin is the one holding the lattice spacing, and it is a sharp peak.
  const auto g = rdf.g();
  const auto first = static_cast<std::size_t>(a / dr);
  for (std::size_t b = 0; b < first; ++b) EXPECT_EQ(g[b], 0.0);
  // g = coordination / (rho * shell volume): 6 neighbours in a thin shell, far above the ideal 1.
  const double lo = first * dr, hi = lo + dr;
  const double shell = 4.0 / 3.0 * std::numbers::pi * (hi * hi * hi - lo * lo * lo);
  EXPECT_NEAR(g[first], 6.0 * n / (n - 1.0) / shell, 1e-9);  // rho = 1; N-1 in the ideal count
  EXPECT_GT(g[first], 4.0);
  EXPECT_EQ(g[first - 1], 0.0);
  EXPECT_EQ(g[first + 1], 0.0);
  const auto r = rdf.r();
  EXPECT_NEAR(r[first], a, dr / 2);
}

TEST(RadialDistribution, RejectsRmaxAtHalfBox) {
  RadialDistribution rdf(10, 2.0);
  const double x = 0.5, y = 0.5, z = 0.5;
  EXPECT_THROW(rdf.sample(&x, &y, &z, 1, {4.0, 10.0, 10.0}), std::invalid_argument);
  EXPECT_NO_THROW(rdf.sample(&x, &y, &z, 1, {4.001, 10.0, 10.0}));
  EXPECT_THROW(RadialDistribution(0, 1.0), std::invalid_argument);
  EXPECT_THROW(RadialDistribution(10, 0.0), std::invalid_argument);
}

// Along a bounded axis there is no image. Particles 0 (z = 0.2) and 1, 2 (z = L - 0.2) are 0.4 and
// 0.5 apart through the z faces, 3 (y = 2, z = 0.9) is 1.22 from 0 inside the box and 1.30 from 2
// through the faces; 1 and 2 are 0.3 apart. With rmax = 1.4: 5 pairs in a periodic box, 2 when z is
// bounded. Lengths give 2, 3 and 7 cells along z (the cell stencil must not wrap there either).
TEST(RadialDistribution, BoundedAxesHaveNoImages) {
  for (const double lz : {3.0, 5.0, 11.0}) {
    const std::vector<double> x = {1.0, 1.0, 1.0, 1.0}, y = {1.0, 1.0, 1.3, 2.0};
    const std::vector<double> z = {0.2, lz - 0.2, lz - 0.2, 0.9};
    auto pairs = [&](std::array<bool, 3> periodic) {
      RadialDistribution rdf(10, 1.4);
      rdf.sample(x.data(), y.data(), z.data(), x.size(), {4.0, 4.0, lz}, periodic);
      std::uint64_t total = 0;
      for (std::uint64_t c : rdf.counts()) total += c;
      return total / 2;  // counts are of ordered pairs
    };
    EXPECT_EQ(pairs({true, true, true}), 5u) << "lz " << lz;
    EXPECT_EQ(pairs({true, true, false}), 2u) << "lz " << lz;
    EXPECT_EQ(pairs({false, false, false}), 2u) << "lz " << lz;
  }
}

TEST(RadialDistribution, WritesCsv) {
  RadialDistribution rdf(5, 1.0);
  const std::array<double, 3> box{3.0, 3.0, 3.0};
  std::mt19937_64 rng(7);
  const Points p = uniform_points(50, box, rng);
  rdf.sample(p.x.data(), p.y.data(), p.z.data(), 50, box);
  const std::string path = ::testing::TempDir() + "rdf_test.csv";
  rdf.write_csv(path);
  std::ifstream is(path);
  std::string line;
  std::getline(is, line);
  EXPECT_EQ(line, "r,g");
  int rows = 0;
  while (std::getline(is, line)) ++rows;
  EXPECT_EQ(rows, 5);
}

// With g = 1 the integral is a rc^4 / 20, so p = rho kT + pi a rho^2 rc^4 / 30 (the mean-field
// value of Groot-Warren's alpha, 0.1047).
TEST(VirialPressure, MeanFieldWithFlatRdf) {
  const double rc = 1.0, a = 25.0, rho = 3.0, kT = 1.0;
  const std::size_t bins = 2000;
  const double rmax = 1.5 * rc;  // bins beyond rc must contribute nothing
  const double dr = rmax / bins;
  std::vector<double> r(bins), g(bins, 1.0);
  for (std::size_t b = 0; b < bins; ++b) r[b] = (b + 0.5) * dr;
  const double expected = rho * kT + std::numbers::pi * a * rho * rho * std::pow(rc, 4) / 30.0;
  EXPECT_NEAR(virial_pressure_from_rdf(r, g, dr, rho, kT, a, rc), expected, 1e-5 * expected);

  const double rc2 = 0.8;
  const double expected2 = rho * kT + std::numbers::pi * a * rho * rho * std::pow(rc2, 4) / 30.0;
  EXPECT_NEAR(virial_pressure_from_rdf(r, g, dr, rho, kT, a, rc2), expected2, 1e-5 * expected2);

  std::vector<double> zero(bins, 0.0);
  EXPECT_DOUBLE_EQ(virial_pressure_from_rdf(r, zero, dr, rho, kT, a, rc), rho * kT);
  EXPECT_THROW(virial_pressure_from_rdf(r, std::vector<double>(3, 1.0), dr, rho, kT, a, rc),
               std::invalid_argument);
}

}  // namespace
}  // namespace mesodpd
