// Transport DPD (physics/tdpd_pair.hpp, engine/install_tdpd.cpp): the Fick flux against the kinetic-theory
// diffusivity at two cutoffs and for two solutes, the decay of a concentration wave in the moving fluid,
// conservation of every solute, solute and impermeable walls, negative concentrations reported and not
// clipped, reproducibility, bad input.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/blow_up_error.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "schema/declared_tables.hpp"
#include "transport_configs.hpp"
#include "test_support.hpp"

using namespace mesodpd;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A periodic tDPD fluid with two solutes (transport_configs.hpp) in an l^3 box.
std::string tdpd_config(double l, double dt, double kappa1, double kappa2, const std::string& extra_pair = "",
                        const std::string& extra = "") {
  return test::periodic_fluid_config(
      fmt::format("style = \"tdpd\"\nkappa1 = {}\nkappa2 = {}\n{}", kappa1, kappa2, extra_pair), "conc1 = 1.0\nconc2 = 2.0",
      "\n[tdpd]\nsolutes = 2\n" + extra, l, dt, 777);
}

std::vector<double>& conc_of(ParticleData& p, int k) { return *p.doubles(fmt::format("conc{}", k)); }

double amount(ParticleData& p, int k) {
  double s = 0;
  for (double c : conc_of(p, k)) s += c;
  return s;
}

// The concentrations of solute k by id.
std::vector<double> by_id(ParticleData& p, int k) {
  std::vector<double> c(p.n_local);
  for (std::size_t i = 0; i < p.n_local; ++i) c[p.id[i] - 1] = conc_of(p, k)[i];
  return c;
}

// Unwrapped positions x, y, z of every particle by id (box lx x ly x lz; a cube of side lx by default).
std::vector<double> unwrapped(const ParticleData& q, double lx, double ly = 0, double lz = 0) {
  if (ly == 0) ly = lz = lx;
  std::vector<double> r(3 * q.n_local);
  for (std::size_t i = 0; i < q.n_local; ++i) {
    const std::size_t k = 3 * (q.id[i] - 1);
    r[k] = q.x[i] + q.ix[i] * lx;
    r[k + 1] = q.y[i] + q.iy[i] * ly;
    r[k + 2] = q.z[i] + q.iz[i] * lz;
  }
  return r;
}

// The self-diffusion coefficient from the mean squared displacement over time t, MSD / 6t.
double self_diffusion(const std::vector<double>& r0, const std::vector<double>& r1, double t) {
  double msd = 0;
  for (std::size_t k = 0; k < r0.size(); ++k) msd += (r1[k] - r0[k]) * (r1[k] - r0[k]);
  return msd / static_cast<double>(r0.size() / 3) / (6 * t);
}

// D = 2 pi n kappa r_cc^5 / 315 (s_C = 2; docs/physics.md, "tDPD").
double kinetic_d(double n, double kappa, double rcc) { return 2 * kPi * n * kappa * std::pow(rcc, 5) / 315.0; }

}  // namespace

// The Fick flux alone, on one configuration of uniformly placed particles (g(r) = 1): for C = 1 + eps sin(k z)
// the pair sum gives dC_i/dt = -D k^2 (C_i - 1) on average with the kinetic theory's D, up to the
// finite-wavelength term O((k r_cc)^2 / 14). Two solutes with different kappa, at r_cc = 1 and 1.5.
TEST(Tdpd, FickFluxOfAUniformConfigurationHasTheKineticTheoryDiffusivity) {
  const double l = 16.0, eps = 0.05;
  for (double rcc : {1.0, 1.5}) {
    std::string text = tdpd_config(l, 0.01, 0.5, 1.25, fmt::format("rcc = {}", rcc));
    const SimulationSpec spec = parse_config(text, "c.toml");
    Simulation sim(spec, RunOptions{});
    ParticleData p = sim.particles();
    const double k = 2 * kPi / l, n = static_cast<double>(p.n_local) / (l * l * l);
    for (int c = 1; c <= 2; ++c)
      for (std::size_t i = 0; i < p.n_local; ++i) conc_of(p, c)[i] = 1.0 + eps * std::sin(k * p.z[i]);
    const PairLawTables laws = make_pair_laws(spec);
    std::vector<std::array<double, 3>> f;
    PairSums sums;
    std::vector<double> rate;
    reference_forces(p, sim.box(), laws, NoiseSettings{1, NoiseKind::Uniform}, 1, 0.01, f, sums, nullptr, &rate);
    ASSERT_EQ(rate.size(), 2 * p.n_local);
    for (int c = 0; c < 2; ++c) {
      double num = 0, den = 0;
      for (std::size_t i = 0; i < p.n_local; ++i) {
        const double s = std::sin(k * p.z[i]);
        num += rate[static_cast<std::size_t>(c) * p.n_local + i] * s;
        den += (conc_of(p, c + 1)[i] - 1.0) * s;
      }
      const double measured = -num / den / (k * k);
      const double d = kinetic_d(n, c == 0 ? 0.5 : 1.25, rcc);
      std::printf("Fick flux, r_cc = %.1f, solute %d: D = %.4f, kinetic theory %.4f (ratio %.4f)\n", rcc, c + 1,
                  measured, d, measured / d);
      EXPECT_NEAR(measured / d, 1.0, 0.04);
    }
  }
}

// A concentration wave in the moving fluid decays at the rate of the particles' own diffusion (the solute
// rides on them) plus the Fick exchange between them. As for eDPD's temperature (docs/validation.md,
// "eDPD"), the kinetic theory's D is the mean field, an upper bound for the pair network of a disordered
// configuration: the exchange part of the measured rate, D - D_self, lies between 0.4 D and D (measured
// 0.56 and 0.62). Two solutes, kappa 5 and 15 (D = 0.30 and 0.90 against D_self = 0.38).
TEST(Tdpd, AConcentrationWaveDecaysWithTheKineticTheoryDiffusivity) {
  const double l = 10.0, rho = 3.0, dt = 0.01;
  Simulation sim(parse_config(tdpd_config(l, dt, 5.0, 15.0), "wave.toml"), RunOptions{});
  ParticleData& p = sim.particles();
  const double k = 2 * kPi / l;
  for (int c = 1; c <= 2; ++c)
    for (std::size_t i = 0; i < p.n_local; ++i) conc_of(p, c)[i] = 1.0 + 0.3 * std::sin(k * p.z[i]);
  sim.thermo();
  auto amplitude = [&](int c) {
    ParticleData& q = sim.particles();
    const double mean = amount(q, c) / static_cast<double>(q.n_local);
    double a = 0, norm = 0;
    for (std::size_t i = 0; i < q.n_local; ++i) {
      const double s = std::sin(k * q.z[i]);
      a += (conc_of(q, c)[i] - mean) * s;
      norm += s * s;
    }
    return a / norm;
  };
  const std::vector<double> r0 = unwrapped(sim.particles(), l);
  const double a0[2] = {amplitude(1), amplitude(2)};
  double sx = 0, sxx = 0, sy[2] = {0, 0}, sxy[2] = {0, 0};
  int m = 0;
  for (int block = 1; block <= 12; ++block) {
    for (int s = 0; s < 10; ++s) sim.step();
    const double t = block * 10 * dt;
    sx += t, sxx += t * t, ++m;
    for (int c = 0; c < 2; ++c) {
      const double y = std::log(amplitude(c + 1) / a0[c]);
      sy[c] += y, sxy[c] += t * y;
    }
  }
  const double d_self = self_diffusion(r0, unwrapped(sim.particles(), l), 1.2);
  for (int c = 0; c < 2; ++c) {
    const double rate = -(m * sxy[c] - sx * sy[c]) / (m * sxx - sx * sx);
    const double measured = rate / (k * k), d = kinetic_d(rho, c == 0 ? 5.0 : 15.0, 1.0);
    std::printf("wave, solute %d: measured D = %.4f, self-diffusion %.4f, exchange part %.4f = %.3f of the kinetic "
                "theory's %.4f\n",
                c + 1, measured, d_self, measured - d_self, (measured - d_self) / d, d);
    EXPECT_GT(measured - d_self, 0.4 * d);
    EXPECT_LT(measured - d_self, 1.05 * d);
  }
}

// The pair fluxes are antisymmetric, so in a periodic box every solute's amount stays what it was: to
// rounding (the rates are exact opposites in fixed point; C += dt/2 rate rounds once per particle), also
// with the random flux on.
TEST(Tdpd, EverySoluteIsConservedWithTheRandomFlux) {
  Simulation sim(parse_config(tdpd_config(6.0, 0.01, 1.0, 0.5, "epsilon1 = 0.2\nepsilon2 = 0.1"), "c.toml"),
                 RunOptions{});
  ParticleData& p = sim.particles();
  const double before[2] = {amount(p, 1), amount(p, 2)};
  const std::vector<double> c0 = by_id(p, 1);
  for (int k = 0; k < 300; ++k) sim.step();
  const std::vector<double> c1 = by_id(sim.particles(), 1);
  double spread = 0;
  for (std::size_t i = 0; i < c0.size(); ++i) spread += (c1[i] - c0[i]) * (c1[i] - c0[i]);
  spread = std::sqrt(spread / static_cast<double>(c0.size()));
  for (int c = 0; c < 2; ++c) {
    const double after = amount(sim.particles(), c + 1);
    std::printf("solute %d: amount %.15g -> %.15g (relative change %.2e)\n", c + 1, before[c], after,
                (after - before[c]) / before[c]);
    EXPECT_NEAR(after / before[c], 1.0, 1e-12);
  }
  // The random flux did move solute between particles (the test measures something).
  std::printf("rms change of one particle's C1: %.4f\n", spread);
  EXPECT_GT(spread, 0.01);
}

// The same run on 1 and 2 threads and across a restart: bit-identical concentrations of both solutes.
TEST(Tdpd, ConcentrationsAreBitIdenticalAcrossThreadsAndRestarts) {
  const std::string text = tdpd_config(6.0, 0.01, 1.0, 0.5, "epsilon1 = 0.1\nepsilon2 = 0.05");
  const std::vector<std::string> fields{"conc1", "conc2"};
  const fs::path dir = fs::temp_directory_path() / "mesodpd_tdpd_restart";
  fs::create_directories(dir);
  const fs::path file = dir / "state.mdpd";
  const std::vector<double> one = test::run_fields(text, 1, 60, fields), two = test::run_fields(text, 2, 60, fields);
  EXPECT_TRUE(one == two);
  test::run_fields(text, 1, 30, fields, {}, file);
  EXPECT_TRUE(test::run_fields(text, 1, 30, fields, file) == one);
  RunOptions again;
  again.restart = file;
  // A checkpoint of a 2-solute run does not continue a 1-solute one.
  std::string fewer = text;
  fewer.replace(fewer.find("solutes = 2"), 11, "solutes = 1");
  fewer.replace(fewer.find("conc2 = 2.0"), 11, "");
  fewer.replace(fewer.find("kappa2 = 0.5"), 12, "");
  fewer.replace(fewer.find("epsilon2 = 0.05"), 15, "");
  try {
    Simulation s(parse_config(fewer, "r.toml"), again);
    ADD_FAILURE() << "a 1-solute run continued a 2-solute checkpoint";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tdpd.solutes"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

namespace {

// The channel of tests/physics/transport_configs.hpp with one solute (kappa = 20); `bottom` and `top` are the
// walls' [[species]] lines.
std::string wall_config(const std::string& bottom, const std::string& top) {
  return test::plate_channel_config("conc1 = 0.5", bottom, top, "style = \"tdpd\"\nkappa1 = 20.0");
}

}  // namespace

// Solute walls held at C = 1 (bottom) and 0 (top) give the fluid a linear steady profile between them.
TEST(Tdpd, SoluteWallsHoldALinearProfile) {
  Simulation sim(parse_config(wall_config("conc1 = 1.0\nsolute_wall = 1", "conc1 = 0.0\nsolute_wall = 1"), "w.toml"),
                 RunOptions{});
  for (int k = 0; k < 2000; ++k) sim.step();  // relaxation L^2 / (pi^2 D) ~ 3 time units (D ~ 1.2 + D_self)
  const int bins = 10, samples = 40;
  std::vector<double> mean(bins, 0.0);
  for (int s = 0; s < samples; ++s) {
    for (int k = 0; k < 20; ++k) sim.step();
    const std::vector<double> prof = test::fluid_slabs(sim.particles(), sim.particles().conc1, bins);
    for (int b = 0; b < bins; ++b) mean[static_cast<std::size_t>(b)] += prof[static_cast<std::size_t>(b)] / samples;
  }
  const test::ProfileLine line = test::inner_line(mean, "solute walls (walls' slope -0.1)");
  const double slope = line.slope, worst = line.worst;
  EXPECT_LT(slope, -0.06);
  EXPECT_GT(slope, -0.11);
  EXPECT_LT(worst, 0.02);
}

// Impermeable walls (the default) pass no solute: the fluid's amount stays what it was while a wall
// held at C = 0 drains it.
TEST(Tdpd, ImpermeableWallsKeepTheSoluteAndHeldWallsExchangeIt) {
  Simulation sealed(parse_config(wall_config("conc1 = 3.0", "conc1 = 0.0"), "w.toml"), RunOptions{});
  Simulation open(parse_config(wall_config("conc1 = 0.0\nsolute_wall = 1", "conc1 = 0.0\nsolute_wall = 1"), "w.toml"),
                  RunOptions{});
  auto fluid_amount = [](Simulation& sim) {
    ParticleData& p = sim.particles();
    double s = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.species[i] == 0) s += conc_of(p, 1)[i];
    return s;
  };
  const double s0 = fluid_amount(sealed), o0 = fluid_amount(open);
  for (int k = 0; k < 500; ++k) {
    sealed.step();
    open.step();
  }
  const double s1 = fluid_amount(sealed), o1 = fluid_amount(open);
  std::printf("fluid's solute: impermeable walls %.12g -> %.12g, walls at C = 0 %.6g -> %.6g\n", s0, s1, o0, o1);
  EXPECT_NEAR(s1 / s0, 1.0, 1e-12);
  EXPECT_LT(o1, 0.9 * o0);
}

// A concentration is never clipped: a random flux far too strong for the concentrations drives one
// negative, which stops the run naming the step, the particle and the solute; negative = "count" goes on
// and counts them instead.
TEST(Tdpd, ANegativeConcentrationIsReportedNotClipped) {
  const std::string text = tdpd_config(6.0, 0.01, 0.1, 0.1, "epsilon1 = 5.0");
  Simulation sim(parse_config(text, "n.toml"), RunOptions{});
  try {
    for (int k = 0; k < 200; ++k) sim.step();
    ADD_FAILURE() << "no negative concentration in 200 steps";
  } catch (const BlowUpError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("solute 1"), std::string::npos) << m;
    EXPECT_NE(m.find("particle"), std::string::npos) << m;
    EXPECT_NE(m.find("negative"), std::string::npos) << m;
  }
  std::string counting = text;
  counting.replace(counting.find("solutes = 2"), 11, "solutes = 2\nnegative = \"count\"");
  Simulation go_on(parse_config(counting, "n.toml"), RunOptions{});
  for (int k = 0; k < 5; ++k) go_on.step();  // (much longer and the multiplicative noise diverges)
  bool any_negative = false;
  for (double c : conc_of(go_on.particles(), 1)) any_negative = any_negative || c < 0;
  EXPECT_TRUE(any_negative);  // kept as it is, not set to 0
  // The count continues across a restart: 3 + 2 steps through a checkpoint report what 5 steps did.
  const std::string straight = go_on.finish();
  EXPECT_NE(straight.find("particle-steps had a negative concentration"), std::string::npos) << straight;
  const auto file = std::filesystem::temp_directory_path() / "mesodpd_test_tdpd_negatives.mdpd";
  {
    Simulation first(parse_config(counting, "n.toml"), RunOptions{});
    for (int k = 0; k < 3; ++k) first.step();
    first.write_checkpoint(file);
  }
  RunOptions o;
  o.restart = file;
  Simulation second(parse_config(counting, "n.toml"), o);
  for (int k = 0; k < 2; ++k) second.step();
  EXPECT_EQ(second.finish(), straight);
}

// Bad input: one error naming the key.
TEST(Tdpd, BadInputNamesTheKey) {
  const auto error_of = test::config_error_of;
  const std::string good = tdpd_config(6.0, 0.01, 1.0, 0.5);
  EXPECT_EQ(error_of(good), "no error");
  // A solute the run does not carry.
  std::string third = good;
  third.replace(third.find("kappa2 = 0.5"), 12, "kappa2 = 0.5\nkappa3 = 1.0");
  EXPECT_NE(error_of(third).find("pair.kappa3"), std::string::npos) << error_of(third);
  std::string conc3 = good;
  conc3.replace(conc3.find("conc2 = 2.0"), 11, "conc2 = 2.0\nconc3 = 1.0");
  EXPECT_NE(error_of(conc3).find("species[0].conc3"), std::string::npos) << error_of(conc3);
  // Negative kappa, concentration; too many solutes.
  std::string negk = good;
  negk.replace(negk.find("kappa1 = 1"), 10, "kappa1 = -1");
  EXPECT_NE(error_of(negk).find("pair.kappa1"), std::string::npos) << error_of(negk);
  std::string negc = good;
  negc.replace(negc.find("conc1 = 1.0"), 11, "conc1 = -1.0");
  EXPECT_NE(error_of(negc).find("species[0].conc1"), std::string::npos) << error_of(negc);
  std::string many = good;
  many.replace(many.find("solutes = 2"), 11, "solutes = 5");
  EXPECT_NE(error_of(many).find("tdpd.solutes"), std::string::npos) << error_of(many);
  // tDPD keys with another style, and [tdpd] without tdpd.
  std::string dpd = good;
  dpd.replace(dpd.find("style = \"tdpd\""), 14, "style = \"dpd\"");
  EXPECT_NE(error_of(dpd).find("species[0].conc1"), std::string::npos) << error_of(dpd);
  dpd.replace(dpd.find("kappa1 = 1"), 10, "");
  dpd.replace(dpd.find("kappa2 = 0.5"), 12, "");
  dpd.replace(dpd.find("conc1 = 1.0"), 11, "");
  dpd.replace(dpd.find("conc2 = 2.0"), 11, "");
  EXPECT_NE(error_of(dpd).find("tdpd.solutes"), std::string::npos) << error_of(dpd);
  // The Euler integrator.
  std::string euler = good;
  euler.replace(euler.find("[integrator]"), 12, "[integrator]\ntype = \"euler\"");
  EXPECT_NE(error_of(euler).find("integrator.type"), std::string::npos) << error_of(euler);
}

namespace {

// The profile that opposite uniform sources (+q for x < L/2, -q above) build from a uniform start, by the
// heat equation with diffusivity d: the square wave's Fourier series (4q/pi) sum_{odd n} sin(k_n x)/n,
// each mode growing as (1 - exp(-d k_n^2 t)) / (d k_n^2).
double fourier_profile(double x, double t, double q, double d, double l) {
  double c = 0;
  for (int n = 1; n < 200; n += 2) {
    const double k = 2 * kPi * n / l;
    c += 4 * q / (kPi * n) * (1 - std::exp(-d * k * k * t)) / (d * k * k) * std::sin(k * x);
  }
  return c;
}

}  // namespace

// Transient diffusion from two opposite uniform sources in the two halves of a periodic box ([[source]]
// blocks of +q and -q): the binned profiles of two solutes with different kappa follow the heat
// equation's Fourier solution; the diffusivity that fits best, less the particles' self-diffusion, is
// compared with the kinetic theory's D as for the wave (between 0.3 D and D: measured 0.41 and 0.59).
TEST(Tdpd, OppositeSourcesBuildTheHeatEquationsProfile) {
  const double lx = 12.0, q = 0.5, dt = 0.01;
  const std::string extra = R"(
[[source]]
field = "conc1"
rate = 0.5
hi = [6.0, 6.0, 6.0]

[[source]]
field = "conc1"
rate = -0.5
lo = [6.0, 0.0, 0.0]

[[source]]
field = "conc2"
rate = 0.5
hi = [6.0, 6.0, 6.0]

[[source]]
field = "conc2"
rate = -0.5
lo = [6.0, 0.0, 0.0]
)";
  std::string text = tdpd_config(6.0, dt, 5.0, 15.0, "", extra);
  text.replace(text.find("box = [6, 6, 6]"), 15, "box = [12, 6, 6]");
  text.replace(text.find("conc1 = 1.0"), 11, "conc1 = 5.0");
  text.replace(text.find("conc2 = 2.0"), 11, "conc2 = 5.0");
  Simulation sim(parse_config(text, "s.toml"), RunOptions{});
  const int bins = 12, steps = 300;  // t = 3
  const std::vector<double> r0 = unwrapped(sim.particles(), lx, 6.0, 6.0);
  for (int k = 0; k < steps; ++k) sim.step();
  const double t = steps * dt;
  const std::vector<double> r1 = unwrapped(sim.particles(), lx, 6.0, 6.0);
  const double d_self = self_diffusion(r0, r1, t);
  for (int c = 1; c <= 2; ++c) {
    std::vector<double> sum(bins, 0.0), cnt(bins, 0.0);
    ParticleData& p = sim.particles();
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const int b = std::min(bins - 1, static_cast<int>(p.x[i] / lx * bins));
      sum[static_cast<std::size_t>(b)] += conc_of(p, c)[i] - 5.0;
      cnt[static_cast<std::size_t>(b)] += 1;
    }
    // The diffusivity whose profile fits the bins best (a scan; the profile depends on d smoothly).
    double best_d = 0, best_err = 1e300;
    for (double d = 0.02; d < 3.0; d *= 1.01) {
      double err = 0;
      for (int b = 0; b < bins; ++b) {
        const double x = (b + 0.5) * lx / bins, m = sum[static_cast<std::size_t>(b)] / cnt[static_cast<std::size_t>(b)];
        err += std::pow(m - fourier_profile(x, t, q, d, lx), 2);
      }
      if (err < best_err) best_err = err, best_d = d;
    }
    const double d_kin = kinetic_d(3.0, c == 1 ? 5.0 : 15.0, 1.0);
    std::printf("opposite sources, solute %d: best-fit D = %.4f (rms misfit %.4f), self-diffusion %.4f, exchange part "
                "%.3f of the kinetic theory's %.4f\n",
                c, best_d, std::sqrt(best_err / bins), d_self, (best_d - d_self) / d_kin, d_kin);
    EXPECT_GT(best_d - d_self, 0.3 * d_kin);
    EXPECT_LT(best_d - d_self, 1.05 * d_kin);
  }
}

// `mesodpd check` prints each solute's mean-field diffusivity (the value the static test reproduces).
TEST(Tdpd, CheckPrintsEachSolutesKineticTheoryDiffusivity) {
  const std::string text = tdpd_config(6.0, 0.01, 5.0, 15.0, "rcc = 1.5");
  const std::string lines = model_numbers_summary(parse_config(text, "n.toml"));
  std::printf("%s", lines.c_str());
  const double n = 648.0 / 216.0;
  EXPECT_NE(lines.find(fmt::format("solute 1 (kappa = 5, r_cc = 1.5): mean-field exchange diffusivity {:.4g}",
                                   kinetic_d(n, 5.0, 1.5))),
            std::string::npos);
  EXPECT_NE(lines.find(fmt::format("solute 2 (kappa = 15, r_cc = 1.5): mean-field exchange diffusivity {:.4g}",
                                   kinetic_d(n, 15.0, 1.5))),
            std::string::npos);
}
