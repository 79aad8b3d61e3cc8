// The end-of-run temperature warning: its tolerance, its allowance for noise and its advice.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "analysis/observers.hpp"
#include "analysis/thermo.hpp"

using namespace mesodpd;

TEST(TemperatureWarning, FlagsADeviationBeyondTheToleranceOnlyWhereNoiseCannotExplainIt) {
  SimulationSpec spec;
  spec.kT = 1.5;
  const double big = 3 * 100000.0, small = 3 * 50.0;  // degrees of freedom
  EXPECT_FALSE(temperature_warning(1.5 * 1.045, spec, big, 1000));  // the scheme's +4.5% at dt = 0.06
  EXPECT_FALSE(temperature_warning(1.5 * 0.96, spec, big, 1000));
  const auto hot = temperature_warning(1.5 * 1.06, spec, big, 1000);
  ASSERT_TRUE(hot);
  EXPECT_NE(hot->find("6.0% above the target kT = 1.5"), std::string::npos) << *hot;
  EXPECT_NE(hot->find("integrator.dt (now 0.04)"), std::string::npos) << *hot;
  EXPECT_NE(hot->find("integrator.lambda (now 0.5"), std::string::npos) << *hot;
  // 150 degrees of freedom sampled twice: 6% is within the noise (3 x sqrt(2/150/2) = 24%); 40% is not.
  EXPECT_FALSE(temperature_warning(1.5 * 1.06, spec, small, 2));
  EXPECT_TRUE(temperature_warning(1.5 * 1.40, spec, small, 2));
}

TEST(TemperatureWarning, AdviceFitsTheIntegrator) {
  SimulationSpec spec;
  const auto cold = temperature_warning(0.9, spec, 3e5, 100);
  ASSERT_TRUE(cold);
  EXPECT_NE(cold->find("below"), std::string::npos) << *cold;
  EXPECT_EQ(cold->find("lambda"), std::string::npos) << *cold;  // a larger lambda would not warm it
  spec.lambda = 0.65;
  const auto hot_065 = temperature_warning(1.2, spec, 3e5, 100);
  ASSERT_TRUE(hot_065);
  EXPECT_EQ(hot_065->find("lambda"), std::string::npos) << *hot_065;
  // No pair friction (a pairwise [thermostat] does the dissipation): lambda is not the remedy.
  spec.lambda = 0.5;
  spec.pairs.assign(1, PairSpec{});
  spec.pairs[0].gamma = 0.0;
  const auto frictionless = temperature_warning(1.2, spec, 3e5, 100);
  ASSERT_TRUE(frictionless);
  EXPECT_EQ(frictionless->find("lambda"), std::string::npos) << *frictionless;
  spec.pairs[0].gamma = 4.5;
  const auto with_friction = temperature_warning(1.2, spec, 3e5, 100);
  ASSERT_TRUE(with_friction);
  EXPECT_NE(with_friction->find("lambda"), std::string::npos) << *with_friction;
  spec.integrator = IntegratorKind::Euler;
  const auto euler = temperature_warning(1.2, spec, 3e5, 100);
  ASSERT_TRUE(euler);
  EXPECT_NE(euler->find("groot-warren"), std::string::npos) << *euler;
}

// Runs with walls judge their temperature by peculiar_temperature: a strong flow (u_x = 2 sin(2 pi z /
// Lz), mean square 2, i.e. +2/3 on the plain temperature) must not count as heat, the thermal part must
// (kT = 1 within 3%: the flow's variation inside a bin one cutoff wide adds about 2%), frozen particles
// are left out, and the value does not depend on the storage order.
TEST(PeculiarTemperature, RemovesAFlowAndKeepsTheHeat) {
  Box box;
  box.len = {10.0, 4.0, 10.0};
  const std::size_t n = 40000;
  ParticleData p;
  p.resize(n);
  p.n_local = n;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  double plain = 0;
  for (std::size_t i = 0; i < n; ++i) {
    p.species[i] = i % 10 == 0 ? 1 : 0;  // every tenth a frozen wall particle with a wild velocity
    p.x[i] = 10.0 * u01(rng);
    p.y[i] = 4.0 * u01(rng);
    p.z[i] = 10.0 * u01(rng);
    const double flow = 2.0 * std::sin(2.0 * M_PI * p.z[i] / 10.0);
    p.vx[i] = (p.species[i] ? 50.0 : flow) + gauss(rng);
    p.vy[i] = gauss(rng);
    p.vz[i] = gauss(rng);
    if (!p.species[i]) plain += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  }
  plain /= 3.0 * 0.9 * static_cast<double>(n);
  const std::vector<double> mass{1.0, 1.0};
  const std::vector<std::uint8_t> frozen{0, 1};
  const double t = peculiar_temperature(p, mass, box, {10, 4, 10}, Comm::serial(), frozen);
  EXPECT_GT(plain, 1.5);  // the flow in the plain temperature
  EXPECT_NEAR(t, 1.0, 0.03) << "plain " << plain;
  // Reversed storage order: the same bits.
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(n - 1 - i);
  p.permute(order);
  EXPECT_EQ(peculiar_temperature(p, mass, box, {10, 4, 10}, Comm::serial(), frozen), t);
}
