// The end-of-run temperature warning: its tolerance, its allowance for noise and its advice.
#include <gtest/gtest.h>

#include "analysis/observers.hpp"

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
  spec.integrator = IntegratorKind::Euler;
  const auto euler = temperature_warning(1.2, spec, 3e5, 100);
  ASSERT_TRUE(euler);
  EXPECT_NE(euler->find("groot-warren"), std::string::npos) << *euler;
}
