// Pressure-density relation of Liu's spline fluid (seed 000 Sect. 3.3.2, Fig. 13; Eqs. 19, 24): a short
// version of examples/spline_droplet/eos.py. With the attraction (a = 18.75, A = 2, r_c1 = 0.8,
// B = 0.95, r_c2 = 1) at k_BT = 0.54 the virial pressure falls between rho = 1 and rho = 4 (the van der
// Waals loop: a homogeneous start separates into liquid and vapour and the box's pressure turns
// negative), while the purely repulsive spline (B = 0, Liu's gas of Fig. 15) at the same temperature
// has a pressure that rises with density. With a = 8 instead of 18.75 (the configurations depend on a / kT
// only) the fluid shows Liu's pattern: the loop at k_BT = 0.54 and none at k_BT = 1. The long runs are in
// docs/validation.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/surface_tension.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

struct Pressure {
  double mean = 0, err = 0, kT = 0;
};

// Mean virial pressure of thermo rows every 10 steps over `prod` steps after `equil` steps, with a 5-block
// error, of a one-species spline fluid of strength a (seed 000 Eq. 21) started uniformly at random at
// density rho in a 6^3 box.
Pressure spline_pressure(double rho, double attraction, double kT, std::uint64_t seed, double a = 18.75,
                         std::uint64_t equil = 1000, std::uint64_t prod = 2000) {
  const std::string toml = "[system]\nbox = [6.0, 6.0, 6.0]\nkT = " + std::to_string(kT) + "\nseed = " +
                           std::to_string(seed) + "\n[[species]]\nname = \"F\"\ndensity = " + std::to_string(rho) +
                           "\nplacement = \"random\"\n[pair]\nstyle = \"spline\"\na = " + std::to_string(a) +
                           "\nrepulsion = 2.0\n"
                           "rc1 = 0.8\nattraction = " + std::to_string(attraction) +
                           "\nrc2 = 1.0\ngamma = 4.5\nrc = 1.0\n[integrator]\ndt = 0.01\n[output]\nprogress = false\n";
  Simulation sim(parse_config(toml, "spline_eos.toml"), RunOptions{});
  for (std::uint64_t k = 0; k < equil; ++k) sim.step();
  std::vector<double> p;
  double t = 0;
  for (std::uint64_t k = 0; k < prod / 10; ++k) {
    for (int i = 0; i < 10; ++i) sim.step();
    const ThermoState s = sim.thermo();
    p.push_back(s.pressure);
    t += s.temperature;
  }
  const BlockMean b = block_mean(p, 5);
  return {b.mean, b.err, t / static_cast<double>(p.size())};
}

}  // namespace

TEST(SplineEos, PressureFallsWithDensityOnlyWithTheAttraction) {
  // Measured here: P(1) = -0.05 +- 0.03 and P(4) = -1.23 +- 0.07 with the attraction (the 10^3 boxes of
  // docs/validation.md: -0.009 and -1.22); for B = 0, 1.08 and 31.6. Each assert demands 3 combined
  // errors, so it fails only if the attraction stops making a loop (or, for B = 0, if the repulsion stops
  // raising P).
  const Pressure low = spline_pressure(1.0, 0.95, 0.54, 41), high = spline_pressure(4.0, 0.95, 0.54, 42);
  const Pressure low0 = spline_pressure(1.0, 0.0, 0.54, 43), high0 = spline_pressure(4.0, 0.0, 0.54, 44);
  std::printf("kT = 0.54, B = 0.95: P(1) = %.4f +- %.4f (T %.4f), P(4) = %.4f +- %.4f (T %.4f)\n", low.mean, low.err,
              low.kT, high.mean, high.err, high.kT);
  std::printf("kT = 0.54, B = 0:    P(1) = %.4f +- %.4f (T %.4f), P(4) = %.4f +- %.4f (T %.4f)\n", low0.mean,
              low0.err, low0.kT, high0.mean, high0.err, high0.kT);
  EXPECT_LT(high.mean, low.mean - 3 * std::hypot(low.err, high.err)) << "no loop with the attraction";
  EXPECT_LT(high.mean, -3 * high.err) << "the separated box at rho = 4 should pull (P < 0)";
  EXPECT_GT(high0.mean, low0.mean + 3 * std::hypot(low0.err, high0.err)) << "B = 0 should have a rising P";
  // The thermostat holds the lower temperature within 3 % with the attraction (measured 0.2 %). Not
  // asserted for B = 0: the dilute repulsive gas at rho = 1 runs about 5 % warm at dt = 0.01 (binary
  // collisions with the steep core, U(0) = 37.5 = 69 kT, and few neighbours to thermostat them).
  for (const Pressure& r : {low, high}) EXPECT_NEAR(r.kT, 0.54, 0.03 * 0.54);
}

TEST(SplineEos, LoopAtTheLowerTemperatureOnlyWithASofterStrength) {
  // Liu's Fig. 13 pattern (seed 000): with a = 8 (docs/validation.md: the critical a / kT_c, measured
  // between 9.4 and 12.5, puts the pattern at a = 6.8 .. 9.4) the pressure falls from rho = 1 to 4 at
  // kT = 0.54 and rises at kT = 1. The 10^3 boxes
  // give P(1), P(4) = 0.174, -0.113 (kT = 0.54, separated) and 0.802, 2.05 (kT = 1, homogeneous). Fails
  // if the attraction is too weak for a loop at 0.54 or strong enough for one at kT = 1. Measured here
  // (6^3): 0.207 +- 0.014, -0.229 +- 0.043 (kT = 0.54) and 0.798 +- 0.010, 2.002 +- 0.037 (kT = 1; the
  // homogeneous kT = 1 boxes need no time to separate and run 1,500 steps instead of 3,000). 16 s of CPU.
  const double a = 8.0;
  const Pressure cold1 = spline_pressure(1.0, 0.95, 0.54, 51, a), cold4 = spline_pressure(4.0, 0.95, 0.54, 52, a);
  const Pressure hot1 = spline_pressure(1.0, 0.95, 1.0, 53, a, 500, 1000);
  const Pressure hot4 = spline_pressure(4.0, 0.95, 1.0, 54, a, 500, 1000);
  std::printf("a = 8, kT = 0.54: P(1) = %.4f +- %.4f (T %.4f), P(4) = %.4f +- %.4f (T %.4f)\n", cold1.mean, cold1.err,
              cold1.kT, cold4.mean, cold4.err, cold4.kT);
  std::printf("a = 8, kT = 1:    P(1) = %.4f +- %.4f (T %.4f), P(4) = %.4f +- %.4f (T %.4f)\n", hot1.mean, hot1.err,
              hot1.kT, hot4.mean, hot4.err, hot4.kT);
  EXPECT_LT(cold4.mean, cold1.mean - 3 * std::hypot(cold1.err, cold4.err)) << "no loop at kT = 0.54 with a = 8";
  EXPECT_GT(hot4.mean, hot1.mean + 3 * std::hypot(hot1.err, hot4.err)) << "a loop at kT = 1 with a = 8";
  EXPECT_NEAR(cold4.kT, 0.54, 0.03 * 0.54);
  EXPECT_NEAR(hot4.kT, 1.0, 0.03);
}
