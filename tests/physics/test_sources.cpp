// Sources, first-order reactions and buoyancy of the transported scalars (engine/install_sources.cpp,
// engine/install_buoyancy.cpp): exact first-order decay, conservation of reactant plus product, a heat
// source in a region adding its energy, the Boussinesq force's momentum, bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "test_support.hpp"
#include "transport_configs.hpp"

using namespace mesodpd;

namespace {

// A periodic l^3 fluid of pair style `style` (transport_configs.hpp).
std::string fluid(const std::string& style, const std::string& pair, const std::string& species,
                  const std::string& extra, double l = 6.0) {
  return test::periodic_fluid_config("style = \"" + style + "\"\n" + pair, species, extra, l);
}

double total(ParticleData& p, const std::string& field) {
  double s = 0;
  const std::vector<double>& v = *p.doubles(field);
  for (std::size_t i = 0; i < p.n_local; ++i) s += v[i];
  return s;
}

std::string error_of(const std::string& text) { return test::config_error_of(text); }

const std::string kTdpd = "kappa1 = 1.0\nkappa2 = 1.0\nepsilon1 = 0.05";
const std::string kTwo = "conc1 = 2.0\nconc2 = 0.5";

}  // namespace

// A -> B at rate k over the whole box: the pair fluxes conserve each solute, so the amount of A decays
// exactly as exp(-k t) (each half step removes C_A (1 - exp(-k dt/2))), and A + B is conserved.
TEST(Sources, AFirstOrderReactionDecaysExactlyAndConservesReactantPlusProduct) {
  const std::string extra = "[tdpd]\nsolutes = 2\n\n[[reaction]]\nsolute = 1\nproduct = 2\nrate = 0.7\n";
  Simulation sim(parse_config(fluid("tdpd", kTdpd, kTwo, extra), "r.toml"), RunOptions{});
  const double a0 = total(sim.particles(), "conc1"), b0 = total(sim.particles(), "conc2");
  for (int k = 0; k < 200; ++k) sim.step();
  const double a1 = total(sim.particles(), "conc1"), b1 = total(sim.particles(), "conc2");
  std::printf("reaction: A %.10g -> %.10g (exp(-1.4) x A0 = %.10g), A + B %.12g -> %.12g\n", a0, a1,
              a0 * std::exp(-1.4), a0 + b0, a1 + b1);
  EXPECT_NEAR(a1 / (a0 * std::exp(-0.7 * 2.0)), 1.0, 1e-10);
  EXPECT_NEAR((a1 + b1) / (a0 + b0), 1.0, 1e-12);
}

// A reaction in a region acts only there: the half of the box outside keeps its solute A until the
// Fick flux brings it over, so after a short time A is depleted far more inside than outside.
TEST(Sources, AReactionInARegionActsOnlyThere) {
  const std::string extra =
      "[tdpd]\nsolutes = 2\n\n[[reaction]]\nsolute = 1\nrate = 5.0\nhi = [12.0, 6.0, 6.0]\n";
  std::string text = fluid("tdpd", "kappa1 = 0.2\nkappa2 = 0.2", kTwo, extra, 6.0);
  text.replace(text.find("box = [6, 6, 6]"), 15, "box = [24, 6, 6]");
  Simulation sim(parse_config(text, "r.toml"), RunOptions{});
  for (int k = 0; k < 50; ++k) sim.step();  // t = 0.5: exp(-2.5) = 0.08 inside, no reaction outside
  ParticleData& p = sim.particles();
  double in = 0, out = 0, n_in = 0, n_out = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.x[i] > 2 && p.x[i] < 10) in += p.conc1[i], n_in += 1;     // well inside
    if (p.x[i] > 14 && p.x[i] < 22) out += p.conc1[i], n_out += 1;  // well outside
  }
  std::printf("reaction in x < 12: mean C_A inside %.4f, outside %.4f (start 2.0)\n", in / n_in, out / n_out);
  EXPECT_LT(in / n_in, 0.4);
  EXPECT_GT(out / n_out, 1.9);
}

// A heat source in a region (eDPD): the internal energy grows by q per particle in the region and time
// (plus the time step's small drift, which the same run without the source measures).
TEST(Sources, AHeatSourceInARegionAddsItsEnergy) {
  const std::string src = "\n[[source]]\nfield = \"temp\"\nrate = 2.0\nlo = [0.0, 0.0, 0.0]\nhi = [3.0, 6.0, 6.0]\n";
  auto run = [&](const std::string& extra, double& in_region) {
    Simulation sim(parse_config(fluid("edpd", "kappa = 0.05", "cv = 100.0", extra), "h.toml"), RunOptions{});
    ParticleData& p = sim.particles();
    const double u0 = 100.0 * total(p, "temp");
    in_region = 0;
    for (int k = 0; k < 200; ++k) {
      sim.step();
      ParticleData& q = sim.particles();
      for (std::size_t i = 0; i < q.n_local; ++i) in_region += q.x[i] < 3.0 ? 0.01 : 0.0;  // particle-time
    }
    return 100.0 * total(sim.particles(), "temp") - u0;
  };
  double region = 0, unused = 0;
  const double with = run(src, region), without = run("", unused);
  std::printf("heat source: internal energy +%.3f with, +%.3f without; q x particle-time in the region = %.3f\n",
              with, without, 2.0 * region);
  EXPECT_NEAR((with - without) / (2.0 * region), 1.0, 0.03);
}

// The Boussinesq force on a fluid uniformly warmer than X_0: every particle feels -m beta (T - T0) g, so
// the centre-of-mass velocity grows at that acceleration (the pair forces cancel).
TEST(Sources, BuoyancyAcceleratesAWarmFluidAgainstGravity) {
  const std::string extra =
      "\n[buoyancy]\nfield = \"temp\"\nbeta = 0.5\nreference = 1.0\ngravity = [0.0, 0.0, -0.2]\n";
  Simulation sim(parse_config(fluid("edpd", "kappa = 0.05", "cv = 1000.0\ntemperature = 1.2", extra), "b.toml"),
                 RunOptions{});
  auto vz = [&] {
    ParticleData& p = sim.particles();
    double s = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) s += p.vz[i];
    return s / static_cast<double>(p.n_local);
  };
  const double v0 = vz();
  for (int k = 0; k < 100; ++k) sim.step();
  const double mean_t = total(sim.particles(), "temp") / static_cast<double>(sim.particles().n_local);
  // a = -beta (T - T0) g = 0.5 x 0.2 x 0.2 = 0.02 upwards (T drifts a little towards the kinetic kT).
  const double expected = 0.5 * (0.5 * (1.2 + mean_t) - 1.0) * 0.2 * 1.0;
  std::printf("buoyancy: <v_z> %.5f -> %.5f after t = 1, expected +%.5f\n", v0, vz(), expected);
  EXPECT_NEAR((vz() - v0) / expected, 1.0, 0.02);
}

TEST(Sources, BadInputNamesTheKey) {
  const std::string two = "[tdpd]\nsolutes = 2\n";
  // A region outside the box, a field of another style, a solute not carried, a product equal to the
  // reactant, buoyancy of a field the style has not.
  const std::string outside = fluid("tdpd", kTdpd, kTwo, two + "\n[[source]]\nfield = \"conc1\"\nrate = 1.0\nhi = [7.0, 6.0, 6.0]\n");
  EXPECT_NE(error_of(outside).find("source[0].hi[0]"), std::string::npos) << error_of(outside);
  const std::string style = fluid("tdpd", kTdpd, kTwo, two + "\n[[source]]\nfield = \"temp\"\nrate = 1.0\n");
  EXPECT_NE(error_of(style).find("source[0].field"), std::string::npos) << error_of(style);
  const std::string carried = fluid("tdpd", kTdpd, kTwo, two + "\n[[source]]\nfield = \"conc3\"\nrate = 1.0\n");
  EXPECT_NE(error_of(carried).find("source[0].field"), std::string::npos) << error_of(carried);
  const std::string same = fluid("tdpd", kTdpd, kTwo, two + "\n[[reaction]]\nsolute = 2\nproduct = 2\nrate = 1.0\n");
  EXPECT_NE(error_of(same).find("reaction[0].product"), std::string::npos) << error_of(same);
  const std::string rate = fluid("tdpd", kTdpd, kTwo, two + "\n[[reaction]]\nsolute = 1\nrate = -1.0\n");
  EXPECT_NE(error_of(rate).find("reaction[0].rate"), std::string::npos) << error_of(rate);
  const std::string buoy = fluid("tdpd", kTdpd, kTwo, two + "\n[buoyancy]\nbeta = 1.0\nreference = 1.0\ngravity = [0, 0, -1]\n");
  EXPECT_NE(error_of(buoy).find("buoyancy.field"), std::string::npos) << error_of(buoy);
  const std::string missing = fluid("tdpd", kTdpd, kTwo, two + "\n[[source]]\nfield = \"conc1\"\n");
  EXPECT_NE(error_of(missing).find("source[0].rate"), std::string::npos) << error_of(missing);
}
