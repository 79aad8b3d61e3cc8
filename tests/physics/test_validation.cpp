// Physical validation, short versions of mesodpd-validate (validation/validate.cpp, docs/validation.md):
// temperature control, equation of state by two routes, ideal-gas g(r), reverse-Poiseuille viscosity.
// Every run is seeded, so each test is deterministic; the tolerances below are chosen from the standard
// errors the same runs report, and each says how it could still fail.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "physics_checks.hpp"

using namespace mesodpd;
using namespace mesodpd::validation;

namespace {

// MESODPD_VALIDATION_SEED=k adds k to every seed: other noise realisations, to check that the tolerances
// hold beyond the committed seeds (unset in CI, so the suite stays deterministic).
std::uint64_t seed_offset() {
  const char* env = std::getenv("MESODPD_VALIDATION_SEED");
  return env ? std::strtoull(env, nullptr, 10) : 0;
}

FluidCase standard_fluid(double box, double dt, double lambda, std::uint64_t seed) {
  FluidCase c;  // rho = 3, a = 25, gamma = 4.5 (sigma = 3), kT = 1, s = 2
  c.lx = c.ly = c.lz = box;
  c.dt = dt;
  c.lambda = lambda;
  c.seed = seed + 1000 * seed_offset();
  return c;
}

RunLength steps_for(double dt, double equil_time, double prod_time, double sample_time, int blocks) {
  RunLength r;
  r.equil = static_cast<std::uint64_t>(std::llround(equil_time / dt));
  r.prod = static_cast<std::uint64_t>(std::llround(prod_time / dt));
  r.every = static_cast<std::uint64_t>(std::llround(sample_time / dt));
  r.blocks = blocks;
  return r;
}

}  // namespace

// Seed 000 Sect. 2.5.2: rho = 3, a = 25, gamma = 4.5, dt = 0.01 must hold kT within 1% of the target.
// N = 3000, 80 time units sampled every 0.1 in 20 blocks: the block standard error is ~0.0013 (0.13%). The
// integrator's own bias at dt = 0.01, lambda = 0.5 is +0.46 +- 0.07% (docs/validation.md), so a failure needs
// a fluctuation of more than ~4 standard errors on top of it, or a real loss of temperature control.
TEST(Validation, TemperatureWithinOnePercentAtDt001) {
  const TemperatureResult r =
      measure_temperature(standard_fluid(10.0, 0.01, 0.5, 101), steps_for(0.01, 10, 80, 0.1, 20));
  std::printf("kT = %.5f +- %.5f (N = %llu, dt = 0.01, lambda = 0.5)\n", r.kT.mean, r.kT.err,
              static_cast<unsigned long long>(r.n));
  ASSERT_TRUE(std::isfinite(r.kT.err));
  EXPECT_LT(r.kT.err, 0.0025) << "run too short for a 1% test";
  EXPECT_NEAR(r.kT.mean, 1.0, 0.01);
}

// Groot and Warren's finding (seed 000 Sect. 2.5.2) that proves lambda reaches the integrator: at lambda =
// 0.5 the temperature rises with dt (measured +4.5% at dt = 0.06, docs/validation.md), and lambda = 0.65
// keeps it much closer (+0.8%). Tolerances: kT(0.06, 0.5) > 1.02 and |kT(0.06, 0.65) - 1| < 0.6 |kT(0.06,
// 0.5) - 1|; each run's standard error is ~0.002 (seed-to-seed spread ~0.004), so both margins are several
// standard errors.
TEST(Validation, TemperatureLambdaSixtyFiveControlsLargeTimeStep) {
  const RunLength rl = steps_for(0.06, 10, 40, 0.12, 20);
  const TemperatureResult half = measure_temperature(standard_fluid(10.0, 0.06, 0.5, 102), rl);
  const TemperatureResult opt = measure_temperature(standard_fluid(10.0, 0.06, 0.65, 102), rl);
  std::printf("dt = 0.06: kT(lambda 0.5) = %.5f +- %.5f, kT(lambda 0.65) = %.5f +- %.5f\n", half.kT.mean,
              half.kT.err, opt.kT.mean, opt.kT.err);
  EXPECT_GT(half.kT.mean, 1.02);
  EXPECT_LT(std::abs(opt.kT.mean - 1.0), 0.6 * std::abs(half.kT.mean - 1.0));
}

// Equation of state, seed 000 Eq. 13: alpha = (p - rho kT) / (a rho^2) at a = 25 for rho = 3..8, with p the
// conservative pressure (kinetic + conservative virial) and kT the measured temperature (sample by sample:
// alpha = W_C / (3 V a rho^2)). Measured (docs/validation.md) alpha rises from 0.0918 at rho = 3 to 0.1010
// at rho = 8 in steps of 0.0007..0.004, while the block standard error of alpha here is ~1e-5..5e-5.
//  - "rises": each step must exceed 3 combined standard errors (fails only if the steps shrink to noise).
//  - range 0.085..0.105 (the band around Groot-Warren's 0.101 +- 0.001).
// And the seed 003 route: p_rdf = rho kT + (2 pi/3) rho^2 Int r F^C g r^2 dr from g(r) of the same snapshots,
// times (N-1)/N because g is normalised by N(N-1)/V^2. Two asserts:
//  - within statistical error: |p_rdf - p_C| <= 3 sqrt(SE(p_rdf)^2 + SE(p_C)^2) + |disc|, disc the change of
//    p_rdf when the bins are doubled (the midpoint-rule error at dr is ~|disc|/3, so |disc| bounds it);
//  - paired (same snapshots, so the noise cancels): |delta| <= |disc| + 4 SE(delta), delta = p_rdf - p_C per
//  block.
//    This can fail only if the virial sum and the g(r) histogram disagree by more than the binning.
TEST(Validation, EquationOfStateAlphaAndRdfRoute) {
  const std::vector<double> rhos{3, 4, 5, 6, 7, 8};
  std::vector<EosResult> res;
  for (double rho : rhos) {
    FluidCase c = standard_fluid(6.0, 0.04, 0.5, 200 + static_cast<std::uint64_t>(rho));
    c.rho = rho;
    res.push_back(measure_eos(c, steps_for(0.04, 10, 40, 0.2, 20), 200));
    const EosResult& r = res.back();
    std::printf(
        "rho = %g: kT = %.4f, p_C = %.4f +- %.4f, alpha = %.5f +- %.5f, p_rdf = %.4f +- %.4f, "
        "delta = %+.5f +- %.5f, disc = %+.5f\n",
        rho, r.kT.mean, r.p_conservative.mean, r.p_conservative.err, r.alpha.mean, r.alpha.err, r.p_rdf.mean,
        r.p_rdf.err, r.delta.mean, r.delta.err, r.rdf_disc);
  }
  for (std::size_t k = 0; k < res.size(); ++k) {
    const EosResult& r = res[k];
    ASSERT_TRUE(std::isfinite(r.alpha.err) && std::isfinite(r.delta.err) && std::isfinite(r.rdf_disc));
    EXPECT_GE(r.alpha.mean, 0.085) << "rho = " << rhos[k];
    EXPECT_LE(r.alpha.mean, 0.105) << "rho = " << rhos[k];
    const double stat = std::hypot(r.p_rdf.err, r.p_conservative.err);
    EXPECT_LE(std::abs(r.p_rdf.mean - r.p_conservative.mean), 3.0 * stat + std::abs(r.rdf_disc))
        << "rho = " << rhos[k];
    EXPECT_LE(std::abs(r.delta.mean), std::abs(r.rdf_disc) + 4.0 * r.delta.err) << "rho = " << rhos[k];
    if (k > 0) {
      const double step = r.alpha.mean - res[k - 1].alpha.mean;
      EXPECT_GT(step, 3.0 * std::hypot(r.alpha.err, res[k - 1].alpha.err))
          << "rho " << rhos[k - 1] << " -> " << rhos[k];
    }
  }
}

// Ideal gas (a = 0): positions are uniform, so g(r) = 1. Over S snapshots the unordered pair count of bin b
// is Poisson with mean mu_b (independent uniform particles: the pair indicators are pairwise independent), so
// z_b = (g_b - 1) sqrt(mu_b) is standard normal; snapshots 2 time units apart are treated as independent
// (rms displacement ~2.5 r_c between them). Asserts, for B = 80 bins on [0, 4):
//  - chi^2 per bin < 1 + 4 sqrt(2/B) = 1.63 (fails by chance with probability ~1e-4);
//  - max_b |z_b| < 4.5 (by chance ~80 x 7e-6 = 5e-4);
//  - the count-weighted mean of g - 1 over r < 1 within 4 Poisson errors.
// Run at dt = 0.01, where the test's resolution of the r < 1 mean (Poisson error 0.10%) is at the size of the
// integrator's finite-step artifact: a dip in g(r < 1) of -0.42 +- 0.03% at dt = 0.04 and -0.12 +- 0.03% at
// dt = 0.01 in the long runs (docs/validation.md), i.e. roughly linear in dt. At dt = 0.04 this test would
// fail on that dip with these statistics (~4 sigma); it checks flatness to the test's noise, not the absence
// of the artifact. Chance failure of the third assert ~6e-5, or ~2e-3 counting the 0.1% dip as a 1-sigma
// offset.
TEST(Validation, IdealGasRdfFlat) {
  FluidCase c = standard_fluid(10.0, 0.01, 0.5, 303);
  c.a = 0.0;
  const IdealGasResult r = measure_ideal_gas(c, steps_for(0.01, 5, 100, 2.0, 2), 80, 4.0);
  std::printf(
      "ideal gas: %llu snapshots, max|g-1| = %.4f, max z = %.2f at r = %.2f, chi2/bin = %.3f "
      "(r<1: %.3f, r>=1: %.3f), mean(g-1, r<1) = %+.5f +- %.5f\n",
      static_cast<unsigned long long>(r.samples), r.max_abs_dev, r.max_z, r.r_max_z, r.chi2_per_bin,
      r.chi2_inside, r.chi2_outside, r.mean_dev_inside, r.mean_dev_inside_err);
  EXPECT_EQ(r.samples, 50u);
  EXPECT_LT(r.chi2_per_bin, 1.0 + 4.0 * std::sqrt(2.0 / 80.0));
  EXPECT_LT(r.max_z, 4.5);
  EXPECT_LT(std::abs(r.mean_dev_inside), 4.0 * r.mean_dev_inside_err);
}

// Reverse Poiseuille viscosity (seed 002) for s = 2, 1, 1/2 at rho = 3, a = 25, gamma = 4.5, against kinetic
// theory (seed 000 Eq. 16 / Table 1: 0.957, 0.884, 1.427). Measured (docs/validation.md):
// 0.859, 1.109, 1.616, i.e. eta(1/2) > eta(1) > eta(2), while kinetic theory orders eta(1/2) > eta(2) >
// eta(1). The measured order is the physical one: kinetic theory's rho D / 2 uses the g(r) = 1, a = 0
// diffusivity, which overestimates D for the a = 25 fluid, and that term alone puts s = 2 above s = 1; the
// dissipative part grows as s falls (seed 000: "reducing s can lead to considerably increasing viscosity").
// Box 8 x 8 x 12, g = 0.04 (max shear rate ~0.4, peak flow ~0.6: linear response, docs/validation.md), 300
// time units in 10 blocks of 30, i.e. 2.4 (s = 2) to 4.4 (s = 1/2) relaxation times of the slowest flow mode;
// the block errors are ~1% (s = 2), ~1.5% (s = 1) and ~2% (s = 1/2), and the spread over four seeds
// (MESODPD_VALIDATION_SEED = 0..3) is 0.4%, 1.2% and 2.5%.
//  - ordering: each gap must exceed 3 combined standard errors (gaps ~25% and ~45%; the errors would have to
//    be underestimated tenfold for a chance failure);
//  - eta(s = 2) has a finite error bar below 3%;
//  - |eta / eta_kinetic - 1| < 0.35 for all s: kinetic theory is an estimate (no conservative stress, g = 1);
//    the measured ratios are 0.90, 1.25, 1.13. A 35% band catches a wrong weight exponent, a missing factor
//    of two or a broken dissipative force, which move eta by far more, but not a few-% error.
TEST(Validation, ViscositySOrderingAndKineticTheory) {
  const std::vector<double> ss{2.0, 1.0, 0.5};
  std::vector<ViscosityResult> res;
  for (double s : ss) {
    FluidCase c = standard_fluid(8.0, 0.04, 0.5, 404);
    c.lz = 12.0;
    c.s = s;
    res.push_back(measure_viscosity(c, 0.04, steps_for(0.04, 60, 300, 0.4, 10)));
    const ViscosityResult& r = res.back();
    std::printf(
        "s = %g: eta = %.4f +- %.4f (%d blocks), kinetic theory %.4f, ratio %.3f, peak flow %.3f, "
        "max shear rate %.3f, kT_yz %.4f\n",
        s, r.eta, r.eta_err, r.blocks, r.eta_kinetic, r.eta / r.eta_kinetic, r.v_max, r.shear_rate_max,
        r.kT_transverse.mean);
    ASSERT_TRUE(std::isfinite(r.eta_err));
    EXPECT_LT(std::abs(r.eta / r.eta_kinetic - 1.0), 0.35) << "s = " << s;
  }
  ::testing::Test::RecordProperty("eta_s2", std::to_string(res[0].eta));
  ::testing::Test::RecordProperty("eta_s2_err", std::to_string(res[0].eta_err));
  EXPECT_LT(res[0].eta_err / res[0].eta, 0.03);
  EXPECT_GT(res[2].eta - res[1].eta, 3.0 * std::hypot(res[2].eta_err, res[1].eta_err));
  EXPECT_GT(res[1].eta - res[0].eta, 3.0 * std::hypot(res[1].eta_err, res[0].eta_err));
}
