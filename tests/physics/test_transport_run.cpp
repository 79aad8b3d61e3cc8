// [analysis.transport] in runs of the standard fluid: the Green-Kubo viscosity against the
// reverse-Poiseuille value of docs/validation.md section 4, D by Green-Kubo against D by Einstein, a
// restart that continues the correlations bit for bit, and the refusals of bad input naming the key.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "analysis/transport.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

// rho = 3, a = 25, gamma = 4.5, kT = 1, dt = 0.04, lambda = 0.5: the fluid of docs/validation.md
// section 4, in a box of side `box`, with `transport` as the [analysis.transport] table.
std::string fluid(double box, std::uint64_t steps, const std::string& transport, const std::string& extra = "") {
  const std::string b = std::to_string(box);
  return "[system]\nbox = [" + b + ", " + b + ", " + b +
         "]\nkT = 1.0\nseed = 31\n[[species]]\nname = \"A\"\ndensity = 3.0\n[pair]\na = 25.0\ngamma = 4.5\n"
         "[integrator]\ndt = 0.04\nlambda = 0.5\n[run]\nsteps = " +
         std::to_string(steps) + "\n[output]\nprogress = false\nthermo_every = 1000\n" + extra +
         "[analysis.transport]\n" + transport;
}

const TransportResult& measure(Simulation& sim, TransportResult& out) {
  sim.run();
  const TransportStage* stage = sim.component<TransportStage>();
  EXPECT_NE(stage, nullptr);
  out = stage->result()->result(sim.box().volume());
  return out;
}

// 648 particles (6^3 box), 1,000 steps to forget the lattice start, then 10 blocks of 4,000 steps (160 time
// units each), every step a sample; D from a window of 4 time units (100 lags, an origin every 5th
// sample), eta from 2 time units (50 lags). About 20 s on one core.
// - eta: the reverse-Poiseuille flow of the same fluid gives 0.8593 +- 0.0047 (docs/validation.md
//   section 4, 8 x 8 x 20 box). The Green-Kubo value of the shear stresses must agree within 3 combined
//   standard errors, its own error be below 5% (measured 0.868 +- 0.027), so that the test resolves a
//   stress without its dissipative and random parts (eta_D = 0.16, seed 000 Eq. 16, 6 errors) or a
//   wrong V / kT; a stress without its kinetic part gave 0.453 (tried: 40 errors off). The normal
//   stresses measure the same eta (isotropy: factor 1/4, docs/physics.md): within 3 combined errors
//   too (measured 0.863 +- 0.054); a factor 1/3 instead gave 1.150 (tried: 4 errors off).
// - D: the MSD slope (Einstein) and the MSD that the VACF implies, fitted over the same lags, measure the
//   same thing from the same samples: their per-block difference must be within 3.5 of its standard
//   errors (measured 0.2; a wrong sample spacing, a factor in either formula or a VACF of wrongly
//   matched particles is far outside). D (VACF), integrated to the window's end, may exceed them by the
//   VACF's tail (0.7% measured): within 2%. D itself must lie in the band the MSD of docs/validation.md
//   section 4 and the finite size allow (0.29 in an 8^3 box; here 0.297).
TEST(TransportRun, GreenKuboViscosityAndTwoDiffusionRoutesAgree) {
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_test_transport_gk";
  std::filesystem::remove_all(dir);
  Simulation sim(parse_config(fluid(6.0, 41000,
                                    "start = 1000\nevery = 1\nlags = 100\norigin_every = 5\nstress_lags = 50\n"
                                    "block = 4000\nnormal_stress = true\n"),
                              "t.toml"),
                 RunOptions{dir, {}, {}, false, false});
  TransportResult r;
  measure(sim, r);
  ASSERT_EQ(r.blocks, 10u);
  const double eta_poiseuille = 0.8593, eta_poiseuille_err = 0.0047;
  EXPECT_LT(r.eta_shear.error, 0.05 * r.eta_shear.value);
  EXPECT_NEAR(r.eta_shear.value, eta_poiseuille, 3 * std::hypot(r.eta_shear.error, eta_poiseuille_err))
      << r.eta_shear.value << " +- " << r.eta_shear.error;
  EXPECT_NEAR(r.eta_normal.value, eta_poiseuille, 3 * std::hypot(r.eta_normal.error, eta_poiseuille_err))
      << r.eta_normal.value << " +- " << r.eta_normal.error;
  double mean = 0, ss = 0;
  for (const TransportBlockValues& b : r.per_block) mean += b.d_msd - b.d_vacf_window;
  mean /= static_cast<double>(r.blocks);
  for (const TransportBlockValues& b : r.per_block)
    ss += (b.d_msd - b.d_vacf_window - mean) * (b.d_msd - b.d_vacf_window - mean);
  const double se = std::sqrt(ss / static_cast<double>(r.blocks - 1) / static_cast<double>(r.blocks));
  EXPECT_LT(std::fabs(mean), 3.5 * se) << "D_MSD - D_VACF on the same window = " << mean << " +- " << se;
  EXPECT_NEAR(r.d_msd.value / r.d_vacf.value, 1.0, 0.02) << r.d_msd.value << " " << r.d_vacf.value;
  EXPECT_GT(r.d_msd.value, 0.22);
  EXPECT_LT(r.d_msd.value, 0.32);
  // Sc = eta / (rho D) with its jackknife error, eta combining the five components; the files exist.
  EXPECT_NEAR(r.eta.value, (3 * r.eta_shear.value + 2 * r.eta_normal.value) / 5, 1e-12);
  EXPECT_NEAR(r.schmidt.value, r.eta.value / (3.0 * r.d_msd.value), 1e-9 * r.schmidt.value);
  EXPECT_GT(r.schmidt.error, 0.0);
  const std::string csv = test::read_file(dir / "transport.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "time,vacf,d_vacf,msd,g_shear,eta_shear,g_normal,eta_normal");
  EXPECT_NE(test::read_file(dir / "transport.json").find("\"schmidt_err\""), std::string::npos);
  std::filesystem::remove_all(dir);
}

// Interrupted in the middle of a block and of a sampling interval, and restarted from the checkpoint (on
// two threads): the files are byte for byte those of the uninterrupted run on one thread.
TEST(TransportRun, RestartContinuesTheCorrelationsByteForByte) {
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_test_transport_restart";
  std::filesystem::remove_all(dir);
  const std::string cfg =
      fluid(5.0, 600, "start = 50\nevery = 2\nlags = 20\norigin_every = 3\nstress_lags = 12\nblock = 100\n"
                      "normal_stress = true\n");
  {
    Simulation a(parse_config(cfg, "t.toml"), RunOptions{dir / "whole", {}, {}, false, false});
    a.run();
  }
  {
    Simulation b(parse_config(cfg, "t.toml"), RunOptions{dir / "split", 333, {}, false, false});
    b.run();
  }
  omp_set_num_threads(2);
  Simulation c(parse_config(cfg, "t.toml"), RunOptions{dir / "split", {}, dir / "split" / "checkpoint.mdpd", false, false});
  c.run();
  omp_set_num_threads(1);
  for (const char* file : {"transport.csv", "transport.json"}) {
    const std::string whole = test::read_file(dir / "whole" / file);
    EXPECT_FALSE(whole.empty()) << file;
    EXPECT_EQ(test::read_file(dir / "split" / file), whole) << file;
  }
  std::filesystem::remove_all(dir);
}

void expect_refused(const std::string& cfg, const std::string& key) {
  try {
    parse_config(cfg, "t.toml");
    FAIL() << "accepted: " << key;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(TransportRun, RefusesBadInputNamingTheKey) {
  expect_refused(fluid(5.0, 100, "every = 3\nlags = 10\nblock = 100\n"), "analysis.transport.block");
  expect_refused(fluid(5.0, 100, "every = 1\nlags = 100\nblock = 150\n"), "analysis.transport.block");
  expect_refused(fluid(5.0, 100, "lags = 5\n"), "analysis.transport.lags");
  expect_refused(fluid(5.0, 100, "lags = 10\nstress_lags = 100\nblock = 150\n"), "analysis.transport.block");
  expect_refused(fluid(5.0, 100, "lags = 10\nstress_lags = 1\nblock = 150\n"), "analysis.transport.stress_lags");
  expect_refused(fluid(5.0, 100, "window = 5\n"), "window");
  expect_refused(fluid(5.0, 100, "lags = 10\nblock = 100\n", "[poiseuille]\nforce = 0.02\n"), "analysis.transport");
}

}  // namespace
}  // namespace mesodpd
