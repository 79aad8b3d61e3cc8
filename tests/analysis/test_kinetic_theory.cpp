// Kinetic-theory transport estimates against the closed forms of seed 000 Table 1.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "analysis/kinetic_theory.hpp"

namespace mesodpd {
namespace {

constexpr double kPi = std::numbers::pi;

// Parameter sets away from 1 so a misplaced power of rho, gamma, kT or rd shows up.
struct Params {
  double rho, gamma, kT, rd;
};
constexpr Params kCases[] = {{3.0, 4.5, 1.0, 1.0}, {4.0, 4.5, 1.0, 1.88}, {2.5, 7.0, 0.7, 1.3}};

TEST(KineticTheory, DiffusivityMatchesTable1) {
  for (const Params& p : kCases) {
    const double base = p.kT / (kPi * p.gamma * p.rho * std::pow(p.rd, 3));
    EXPECT_NEAR(kinetic_diffusivity(p.rho, p.gamma, p.kT, p.rd, 2.0), 45.0 / 2.0 * base, 1e-12 * base);
    EXPECT_NEAR(kinetic_diffusivity(p.rho, p.gamma, p.kT, p.rd, 1.0), 9.0 * base, 1e-12 * base);
    EXPECT_NEAR(kinetic_diffusivity(p.rho, p.gamma, p.kT, p.rd, 0.5), 315.0 / 64.0 * base, 1e-12 * base);
  }
}

TEST(KineticTheory, DissipativeViscosityMatchesTable1) {
  for (const Params& p : kCases) {
    const double base = kPi * p.gamma * p.rho * p.rho * std::pow(p.rd, 5);
    EXPECT_NEAR(kinetic_dissipative_viscosity(p.rho, p.gamma, p.rd, 2.0), 2.0 * base / 1575.0, 1e-12 * base);
    EXPECT_NEAR(kinetic_dissipative_viscosity(p.rho, p.gamma, p.rd, 1.0), base / 225.0, 1e-12 * base);
    EXPECT_NEAR(kinetic_dissipative_viscosity(p.rho, p.gamma, p.rd, 0.5), 512.0 * base / 51975.0,
                1e-12 * base);
  }
}

TEST(KineticTheory, ViscosityMatchesTable1) {
  for (const Params& p : kCases) {
    const double dbase = p.kT / (kPi * p.gamma * p.rho * std::pow(p.rd, 3));
    const double vbase = kPi * p.gamma * p.rho * p.rho * std::pow(p.rd, 5);
    const double s2 = p.rho * 45.0 / 2.0 * dbase / 2.0 + 2.0 * vbase / 1575.0;
    const double s1 = p.rho * 9.0 * dbase / 2.0 + vbase / 225.0;
    const double sh = p.rho * 315.0 / 64.0 * dbase / 2.0 + 512.0 * vbase / 51975.0;
    EXPECT_NEAR(kinetic_viscosity(p.rho, p.gamma, p.kT, p.rd, 2.0), s2, 1e-12 * s2);
    EXPECT_NEAR(kinetic_viscosity(p.rho, p.gamma, p.kT, p.rd, 1.0), s1, 1e-12 * s1);
    EXPECT_NEAR(kinetic_viscosity(p.rho, p.gamma, p.kT, p.rd, 0.5), sh, 1e-12 * sh);
  }
}

// The standard fluid (rho = 3, gamma = 4.5, kT = 1, rd = 1, s = 2), worked by hand:
// D = 45 / (2 pi 13.5) = 0.5305, eta = 3 D / 2 + 2 pi 40.5 / 1575 = 0.7958 + 0.1616.
TEST(KineticTheory, StandardFluidNumbers) {
  EXPECT_NEAR(kinetic_diffusivity(3.0, 4.5, 1.0, 1.0, 2.0), 0.5305, 1e-4);
  EXPECT_NEAR(kinetic_dissipative_viscosity(3.0, 4.5, 1.0, 2.0), 0.1616, 1e-4);
  EXPECT_NEAR(kinetic_viscosity(3.0, 4.5, 1.0, 1.0, 2.0), 0.7958 + 0.1616, 1e-4);
}

// Eq. 16's bracket is the Beta integral B(5, s+1) = 24 / ((s+1)...(s+5)); check at a generic s
// so the formula is right between the tabulated exponents too.
TEST(KineticTheory, DissipativeViscosityIsBetaIntegral) {
  for (double s : {0.25, 0.75, 1.5, 3.0}) {
    const double beta = 24.0 / ((s + 1) * (s + 2) * (s + 3) * (s + 4) * (s + 5));
    const double expected = 2.0 * kPi * 4.5 * 9.0 / 15.0 * beta;
    EXPECT_NEAR(kinetic_dissipative_viscosity(3.0, 4.5, 1.0, s), expected, 1e-12 * expected) << "s = " << s;
  }
}

// Two species A, B with every pair at the [pair] values of seed 000 Sect. 2.
SimulationSpec two_species() {
  SimulationSpec spec;
  spec.kT = 1.0;
  spec.species.resize(2);
  spec.species[0].name.push_back('A');  // (assigning a literal trips GCC 12's false -Wrestrict here)
  spec.species[1].name.push_back('B');
  spec.pairs.resize(3);  // (0,0), (0,1), (1,1)
  for (PairSpec& p : spec.pairs) {
    p.gamma = 4.5;
    p.rd = 1.0;
    p.s = 2.0;
  }
  return spec;
}

TEST(KineticTheory, MixtureThatDiffersOnlyInAGetsTheOneFluidValue) {
  SimulationSpec spec = two_species();
  spec.pairs[1].a = 40.0;  // A-B repulsion: conservative only, which kinetic theory does not see
  const KineticViscosity k = kinetic_viscosity_of(spec, 3.0);
  ASSERT_TRUE(k.applies) << k.why_not;
  EXPECT_EQ(k.eta, kinetic_viscosity(3.0, 4.5, 1.0, 1.0, 2.0));
  EXPECT_EQ(k.gamma, 4.5);
  EXPECT_EQ(k.s, 2.0);
}

TEST(KineticTheory, MixturePairsWithOtherGammaRdOrSGetNoValue) {
  // The (0,0) pair alone used to stand for the whole fluid; any pair may differ, also the last.
  for (int pair = 0; pair < 3; ++pair)
    for (int key = 0; key < 3; ++key) {
      SimulationSpec spec = two_species();
      PairSpec& p = spec.pairs[static_cast<std::size_t>(pair)];
      (key == 0 ? p.gamma : key == 1 ? p.rd : p.s) *= 1.5;
      const KineticViscosity k = kinetic_viscosity_of(spec, 3.0);
      EXPECT_FALSE(k.applies) << "pair " << pair << " key " << key;
      EXPECT_NE(std::string(k.why_not).find("gamma, r_d or s"), std::string::npos) << k.why_not;
    }
}

TEST(KineticTheory, MassOtherThanOneGetsNoValue) {
  SimulationSpec spec = two_species();
  spec.species[1].mass = 2.0;
  const KineticViscosity k = kinetic_viscosity_of(spec, 3.0);
  EXPECT_FALSE(k.applies);
  EXPECT_NE(std::string(k.why_not).find("mass"), std::string::npos) << k.why_not;
}

}  // namespace
}  // namespace mesodpd
