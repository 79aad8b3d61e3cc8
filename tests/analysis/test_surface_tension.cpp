// The surface-tension estimator sigma = (L/2) <P_nn - (P_tt + P_t't')/2> and its block error bar on
// cases with a known answer: synthetic correlated series, and a homogeneous fluid (sigma = 0).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "analysis/surface_tension.hpp"
#include "engine/simulation.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {
// An AR(1) series x_k = m + phi (x_{k-1} - m) + e_k with Var(e) = s^2: the variance of its mean over n
// samples tends to s^2 / (1 - phi)^2 / n.
std::vector<double> ar1(std::size_t n, double m, double phi, double s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, s);
  std::vector<double> x(n);
  double prev = m;
  for (std::size_t k = 0; k < n; ++k) prev = x[k] = m + phi * (prev - m) + g(rng);
  return x;
}
}  // namespace

TEST(SurfaceTension, BlockErrorMatchesTheKnownErrorOfACorrelatedSeries) {
  // 40 independent series: the block error must match the true standard error of the mean (which a
  // naive sample error would underestimate fourfold here), and the means scatter by that amount.
  const double m = 2.5, phi = 0.9, s = 1.0;
  const std::size_t n = 20000;
  const double true_err = s / (1 - phi) / std::sqrt(static_cast<double>(n));
  double err_sum = 0, chi2 = 0;
  const int runs = 40;
  for (int r = 0; r < runs; ++r) {
    const BlockMean b = block_mean(ar1(n, m, phi, s, 100 + r), 20);
    EXPECT_EQ(b.blocks, 20u);
    EXPECT_EQ(b.samples, n);
    err_sum += b.err;
    chi2 += (b.mean - m) * (b.mean - m) / (true_err * true_err);
  }
  EXPECT_NEAR(err_sum / runs / true_err, 1.0, 0.15);
  EXPECT_NEAR(chi2 / runs, 1.0, 0.5);  // chi^2 / dof of 40 draws: 1 +- 0.22
  // Too few samples for blocks: no error bar.
  EXPECT_TRUE(std::isnan(block_mean({1.0, 2.0}, 10).err));
}

TEST(SurfaceTension, SyntheticSlabTensorGivesHalfTheBoxTimesTheAnisotropy) {
  // P_zz - (P_xx + P_yy)/2 = 0.5 on average in a box 30 long along z: sigma = 15 * 0.5 = 7.5.
  SurfaceTension st(2, 30.0, 10);
  SurfaceTension along_x(0, 30.0, 10);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.3);
  for (int k = 0; k < 5000; ++k) {
    const double pxx = 1.0 + noise(rng), pyy = 1.0 + noise(rng), pzz = 1.5 + noise(rng);
    st.add({pxx, pyy, pzz, noise(rng), 0.0, 0.0});
    along_x.add({pzz, pxx, pyy, 0.0, 0.0, 0.0});  // the same system with its normal along x
  }
  const BlockMean b = st.result();
  EXPECT_NEAR(b.mean, 7.5, 3 * b.err);
  // Per sample sd = 15 sqrt(0.3^2 + 0.3^2/2) = 5.51, so the error of the mean is 0.078; ten blocks
  // estimate it to about 25 %.
  EXPECT_NEAR(b.err, 0.078, 0.035);
  EXPECT_EQ(along_x.result().mean, b.mean);
  EXPECT_EQ(normal_minus_tangential({1, 2, 3, 9, 9, 9}, 1), 2 - 0.5 * (3 + 1));
}

TEST(SurfaceTension, HomogeneousFluidHasNoSurfaceTension) {
  // A standard DPD fluid (no interface) through [analysis.surface_tension]: sigma = 0 within three
  // block errors, and the error bar is small enough for that to mean something.
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_surface_tension_fluid";
  std::filesystem::remove_all(dir);
  SimulationSpec spec = test::fluid_spec(6.0, 6.0, 9.0, 3.0);
  spec.thermo_every = 5;
  spec.surface_tension.enabled = true;
  spec.surface_tension.start = 200;
  spec.surface_tension.blocks = 10;
  RunOptions o;
  o.out_dir = dir;
  o.steps = 2000;
  Simulation sim(spec, o);
  const std::string summary = sim.run();
  const std::string json = test::read_file(dir / "surface_tension.json");
  ASSERT_FALSE(json.empty()) << summary;
  auto number = [&](const std::string& key) {
    const auto at = json.find("\"" + key + "\": ");
    return std::stod(json.substr(at + key.size() + 4));
  };
  const double sigma = number("sigma"), err = number("sigma_err");
  EXPECT_NEAR(sigma, 0.0, 3 * err) << json;
  EXPECT_LT(err, 0.5) << json;  // vs 7.5 for Warren's liquid
  EXPECT_EQ(number("samples"), 360);  // rows 200..2000 every 5: 361, trimmed to 10 blocks of 36
  EXPECT_NE(summary.find("surface tension sigma"), std::string::npos) << summary;
  std::filesystem::remove_all(dir);
}
