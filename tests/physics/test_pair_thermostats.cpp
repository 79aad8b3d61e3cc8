// The pairwise thermostats of [thermostat] (integrate/pair_thermostat.hpp): the temperature they hold,
// the momentum they keep, the distribution of a single pair's update, bit identity across thread counts
// and a restart, and the refusals of bad input.
#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/philox.hpp"
#include "engine/simulation.hpp"
#include "integrate/pair_thermostat.hpp"
#include "mesodpd/config.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"
#include "threads_and_restart.hpp"

namespace mesodpd {
namespace {

// An a = 25, rho = 3 fluid whose pair law has no dissipation, thermostatted by `section`.
std::string fluid(double box, double dt, const std::string& section, const std::string& pair_gamma = "0.0",
                  const std::string& extra = "") {
  const std::string b = std::to_string(box);
  return "[system]\nbox = [" + b + ", " + b + ", " + b +
         "]\nkT = 1.0\nseed = 11\n[[species]]\nname = \"A\"\n"
         "density = 3.0\n" +
         extra + "[pair]\na = 25.0\ngamma = " + pair_gamma + "\n[integrator]\ndt = " + std::to_string(dt) +
         "\n[run]\nsteps = 100\n[output]\nprogress = false\n[thermostat]\n" + section;
}

double kinetic_temperature(const ParticleData& p) {
  double twice_ke = 0;
  for (std::size_t i = 0; i < p.n_local; ++i)
    twice_ke += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  return twice_ke / (3.0 * static_cast<double>(p.n_local) - 3.0);
}

// The mean kinetic temperature over the steps after `from` up to `to`, run from the current step.
double mean_temperature(Simulation& sim, std::uint64_t from, std::uint64_t to) {
  while (sim.current_step() < from) sim.step();
  double sum = 0;
  int n = 0;
  while (sim.current_step() < to) {
    sim.step();
    sum += kinetic_temperature(sim.particles());
    ++n;
  }
  return sum / n;
}

const std::vector<std::string> kSections{"type = \"lowe-andersen\"\nrate = 4.5\n",
                                         "type = \"shardlow\"\ngamma = 4.5\n",
                                         "type = \"peters\"\ngamma = 4.5\n",
                                         "type = \"stoyanov-groot\"\nrate = 0.5\nalpha = 4.5\n"};

// Each thermostat holds kT = 1 at a small step. 7^3 x 3 = 1029 particles, 400 steps of relaxation from
// the random start (which heats the fluid), then the mean over 2000 steps (40 time units of a
// temperature that fluctuates by sqrt(2 / 3N) = 2.5% from step to step and is correlated over a good
// part of a time unit): the statistical error is a few tenths of a per cent (measured: 1.0040, 1.0040,
// 0.9964), against 1% allowed; the time-step error at dt = 0.02 is smaller still (docs/validation.md,
// "Pairwise thermostats: temperature against dt"). A wrong noise variance or a missing pair fails.
TEST(PairThermostats, EachHoldsTheTemperatureAtASmallStep) {
  for (const std::string& section : kSections) {
    Simulation sim(parse_config(fluid(7.0, 0.02, section), "t.toml"), RunOptions{});
    EXPECT_NEAR(mean_temperature(sim, 400, 2400), 1.0, 0.01) << section;
  }
}

// One sweep keeps the total momentum to round-off, with two species of different mass; and it does
// change the velocities (a sweep that did nothing would pass the first check).
TEST(PairThermostats, EachSweepConservesMomentum) {
  Box box;
  box.len = {5.0, 6.0, 5.5};
  ParticleData p = test::random_particles(box, 500, 3, 2);
  const std::vector<double> mass{1.0, 2.5};
  const auto momentum = [&] {
    std::array<double, 3> m{0, 0, 0};
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const double mi = mass[static_cast<std::size_t>(p.species[i])];
      m[0] += mi * p.vx[i];
      m[1] += mi * p.vy[i];
      m[2] += mi * p.vz[i];
    }
    return m;
  };
  for (const PairThermostatKind kind : {PairThermostatKind::LoweAndersen, PairThermostatKind::Shardlow,
                                       PairThermostatKind::Peters, PairThermostatKind::StoyanovGroot}) {
    PairThermostatParams params;
    params.kind = kind;
    params.rate = 10.0;
    params.gamma = 4.5;
    params.alpha = 4.5;
    params.kT = 2.0;  // the random velocities are far from it: Stoyanov-Groot's kick is not zero
    PairThermostat sweep(params);
    const auto before = momentum();
    const std::vector<double> vx0 = p.vx;
    sweep.sweep(p, box, mass, 17, 0.05);
    const auto after = momentum();
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(after[static_cast<std::size_t>(c)], before[static_cast<std::size_t>(c)], 1e-12);
    EXPECT_GT(sweep.last_pairs(), 1000u);
    EXPECT_NE(p.vx, vx0);
  }
}

// Lowe-Andersen at Gamma dt = 1 and one pair: every step the relative velocity along e is drawn afresh
// from N(0, kT / mu); the perpendicular parts and the centre-of-mass velocity stay as they were.
TEST(PairThermostats, LoweAndersenDrawsThePairsMaxwellDistributionAlongTheLineOfCentres) {
  Box box;
  box.len = {4.0, 4.0, 4.0};
  const std::vector<double> mass{1.0, 3.0};
  const double mu = 0.75, kT = 1.3;
  PairThermostatParams params;
  params.kind = PairThermostatKind::LoweAndersen;
  params.rate = 20.0;
  params.kT = kT;
  PairThermostat sweep(params);
  const double e[3] = {0.48, 0.6, 0.64};  // a unit vector
  const double v0[2][3] = {{0.3, -1.1, 0.7}, {-0.2, 0.4, 1.5}};
  const auto dot = [](const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const int n = 40000;
  double sum = 0, sum2 = 0, worst_perp = 0, worst_com = 0;
  for (int k = 0; k < n; ++k) {
    ParticleData p;
    p.resize(2);
    p.n_local = 2;
    p.id = {5, 9};
    p.species = {0, 1};
    p.x = {1.0 + 0.7 * e[0], 1.0};
    p.y = {1.0 + 0.7 * e[1], 1.0};
    p.z = {1.0 + 0.7 * e[2], 1.0};
    p.vx = {v0[0][0], v0[1][0]};
    p.vy = {v0[0][1], v0[1][1]};
    p.vz = {v0[0][2], v0[1][2]};
    sweep.sweep(p, box, mass, static_cast<std::uint64_t>(k), 0.05);
    ASSERT_EQ(sweep.last_pairs(), 1u);
    const double rel[3] = {p.vx[0] - p.vx[1], p.vy[0] - p.vy[1], p.vz[0] - p.vz[1]};
    const double rel0[3] = {v0[0][0] - v0[1][0], v0[0][1] - v0[1][1], v0[0][2] - v0[1][2]};
    const double u = dot(rel, e), u0 = dot(rel0, e);
    sum += u;
    sum2 += u * u;
    const std::vector<double>* v[3] = {&p.vx, &p.vy, &p.vz};
    for (int c = 0; c < 3; ++c) {
      worst_perp = std::max(worst_perp, std::abs((rel[c] - u * e[c]) - (rel0[c] - u0 * e[c])));
      const double com = mass[0] * (*v[c])[0] + mass[1] * (*v[c])[1];
      const double com0 = mass[0] * v0[0][c] + mass[1] * v0[1][c];
      worst_com = std::max(worst_com, std::abs(com - com0));
    }
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  // Standard errors: sqrt(kT/mu / n) = 0.0066 on the mean, sqrt(2/n) = 0.7% on the variance.
  EXPECT_NEAR(mean, 0.0, 0.03);
  EXPECT_NEAR(var / (kT / mu), 1.0, 0.03);
  EXPECT_LT(worst_perp, 1e-14);
  EXPECT_LT(worst_com, 1e-14);
}

// Applied again and again to one pair, the Shardlow and Peters updates relax the relative velocity to
// N(0, kT / mu) whatever the step: the pair's equilibrium is Maxwell's, without time-step error.
TEST(PairThermostats, ShardlowAndPetersKeepThePairsMaxwellDistributionAtAnyStep) {
  const double kT = 1.0, mu = 0.5;
  for (const double a : {0.1, 0.9}) {  // gamma w_D dt / mu
    const double gwdt = a * mu;
    double su = 0, su2 = 0, pu = 0, pu2 = 0, us = 3.0, up = 3.0;
    const int n = 200000, skip = 200;
    for (int k = 0; k < n + skip; ++k) {
      const Philox4x32 b =
          pair_random_bits(99, static_cast<std::uint64_t>(k), 1, 2, RngStream::PairThermostat);
      us = shardlow_update(us, mu, gwdt, kT, b.v);
      up = peters_update(up, mu, gwdt, kT, b.v);
      if (k < skip) continue;
      su += us;
      su2 += us * us;
      pu += up;
      pu2 += up * up;
    }
    // Correlated samples (relaxation over about 1/a updates): a few per cent of statistical error at a = 0.1.
    EXPECT_NEAR((su2 / n - (su / n) * (su / n)) / (kT / mu), 1.0, a < 0.5 ? 0.06 : 0.02)
        << "shardlow a = " << a;
    EXPECT_NEAR((pu2 / n - (pu / n) * (pu / n)) / (kT / mu), 1.0, a < 0.5 ? 0.06 : 0.02)
        << "peters a = " << a;
  }
}

// Stoyanov-Groot's Nose-Hoover part alone (rate 0) on a frozen configuration: repeated sweeps carry the
// kinetic temperature from about 1 to the target, up for kT = 2 and down for kT = 0.5, without overshoot
// (the kick is proportional to kT / T - 1); momentum is kept; and the sweep is Galilean invariant: the
// same velocities plus a uniform V come out as the first result plus V.
TEST(PairThermostats, StoyanovGrootSteersTheKineticTemperatureAndIsGalileanInvariant) {
  Box box;
  box.len = {5.0, 6.0, 5.5};
  const std::vector<double> mass{1.0};
  for (const double target : {2.0, 0.5}) {
    ParticleData p = test::random_particles(box, 500, 5);
    PairThermostatParams params;
    params.kind = PairThermostatKind::StoyanovGroot;
    params.rate = 0.0;
    params.alpha = 4.5;
    params.kT = target;
    PairThermostat sweep(params);
    double t_prev = 0;
    for (int k = 0; k < 400; ++k) {
      sweep.sweep(p, box, mass, static_cast<std::uint64_t>(k), 0.05);
      const double t = sweep.last_temperature();
      if (k == 0) {
        EXPECT_NEAR(t, 1.0, 0.15);  // N(0, 1) velocities
      } else if (target > 1.0) {
        EXPECT_GE(t, t_prev) << "sweep " << k;
        EXPECT_LE(t, target * (1 + 1e-9)) << "sweep " << k;
      } else {
        EXPECT_LE(t, t_prev) << "sweep " << k;
        EXPECT_GE(t, target * (1 - 1e-9)) << "sweep " << k;
      }
      t_prev = t;
    }
    EXPECT_NEAR(t_prev / target, 1.0, 0.01) << "kT " << target;
    // Galilean invariance, and the momentum: one more sweep on a copy moved by V.
    ParticleData q = p;
    const double v[3] = {0.7, -1.3, 2.1};
    for (std::size_t i = 0; i < q.n_local; ++i) {
      q.vx[i] += v[0];
      q.vy[i] += v[1];
      q.vz[i] += v[2];
    }
    // Push the state off the target first, so the kick is not zero.
    for (std::size_t i = 0; i < p.n_local; ++i) {
      p.vx[i] *= 1.2;
      q.vx[i] = p.vx[i] + v[0];
    }
    double before[3] = {0, 0, 0}, after[3] = {0, 0, 0};
    for (std::size_t i = 0; i < p.n_local; ++i) {
      before[0] += p.vx[i];
      before[1] += p.vy[i];
      before[2] += p.vz[i];
    }
    PairThermostat a(params), b(params);
    a.sweep(p, box, mass, 999, 0.05);
    b.sweep(q, box, mass, 999, 0.05);
    EXPECT_NEAR(a.last_temperature(), b.last_temperature(), 1e-10);
    double worst = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      after[0] += p.vx[i];
      after[1] += p.vy[i];
      after[2] += p.vz[i];
      worst = std::max({worst, std::abs(q.vx[i] - v[0] - p.vx[i]), std::abs(q.vy[i] - v[1] - p.vy[i]),
                        std::abs(q.vz[i] - v[2] - p.vz[i])});
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c], before[c], 1e-11);
    EXPECT_LT(worst, 1e-12);
    EXPECT_GT(std::abs(a.last_temperature() - target), 0.01 * target);  // the kick was not zero
  }
}

// Stoyanov-Groot at dt = 0.06, where Groot-Warren at lambda = 0.5 runs 6% warm (docs/validation.md
// section 9) and Lowe-Andersen alone at the same Gamma = 0.5 runs +2.2% (measured, 1029 particles,
// 120 time units): the Nose-Hoover kick steers the measured kinetic temperature back. Its proportional
// feedback leaves a small offset, measured +0.48 to +0.61% over three other seeds and +0.75% for this
// test's (statistical error about 0.1%); the test allows 1%. A wrong sign of the kick heats the fluid without bound.
TEST(PairThermostats, StoyanovGrootHoldsTheTemperatureAtALargeStep) {
  Simulation sim(parse_config(fluid(7.0, 0.06, kSections.back()), "t.toml"), RunOptions{});
  const double t = mean_temperature(sim, 200, 2200);
  std::printf("Stoyanov-Groot at dt = 0.06: mean kT %.5f\n", t);
  EXPECT_NEAR(t, 1.0, 0.01);
}

// Under Lees-Edwards shear the Nose-Hoover kick steers the temperature across the flow (the streaming
// velocity is not heat): the a = 25 fluid sheared at rate 0.2 in an 8^3 box, Stoyanov-Groot at P = 0
// (the kick alone), keeps the two transverse components at kT within 1% (measured 1.002 over 400 time
// units in docs/validation.md). Counting the streaming velocity, whose mean square across the box is
// (0.2 x 8)^2 / 12 = 0.21, as heat would cool the fluid by about 7%.
TEST(PairThermostats, StoyanovGrootUnderShearSteersTheTemperatureAcrossTheFlow) {
  const std::string section = "type = \"stoyanov-groot\"\nrate = 0.0\nalpha = 4.5\n"
                              "[lees_edwards]\nshear_rate = 0.2\n";
  Simulation sim(parse_config(fluid(8.0, 0.02, section), "t.toml"), RunOptions{});
  while (sim.current_step() < 500) sim.step();
  double sum = 0;
  int n = 0;
  while (sim.current_step() < 3000) {
    sim.step();
    const ParticleData& p = sim.particles();
    double my = 0, mz = 0, k = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) my += p.vy[i], mz += p.vz[i];
    my /= static_cast<double>(p.n_local);
    mz /= static_cast<double>(p.n_local);
    for (std::size_t i = 0; i < p.n_local; ++i)
      k += (p.vy[i] - my) * (p.vy[i] - my) + (p.vz[i] - mz) * (p.vz[i] - mz);
    sum += k / (2.0 * static_cast<double>(p.n_local) - 2.0);
    ++n;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.01);
}

// Bit identity: 1 and 2 OpenMP threads give the same trajectory, and a run restarted from a checkpoint
// continues it exactly, for each thermostat.
TEST(PairThermostats, BitIdenticalForOneAndTwoThreadsAndAcrossARestart) {
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_pair_thermostats_restart";
  for (const std::string& section : kSections) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const SimulationSpec spec = parse_config(fluid(5.0, 0.04, section), "t.toml");
    const auto one = test::run_on_threads(spec, 1, 120, dir);
    EXPECT_TRUE(test::run_on_threads(spec, 2, 120, dir) == one) << "1 and 2 threads differ: " << section;
    test::run_on_threads(spec, 1, 50, dir);
    EXPECT_TRUE(test::run_on_threads(spec, 2, 120, dir, dir / "c50.mdpd") == one)
        << "the restarted run diverged: " << section;
  }
  omp_set_num_threads(1);
  std::filesystem::remove_all(dir);
}

// The key a refusal names, or "accepted".
std::string refused_key(const std::string& toml) {
  try {
    parse_config(toml, "bad.toml");
  } catch (const ConfigError& e) {
    return e.key();
  }
  return "accepted";
}

TEST(PairThermostats, BadInputIsRefusedNamingTheKey) {
  const std::string la = "rate = 4.5\n";
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, la)), "accepted");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "rate = 30.0\n")), "thermostat.rate");  // Gamma dt = 1.2 > 1
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "rate = 0.0\n")), "thermostat.rate");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "type = \"lowe-andersen\"\n")), "thermostat.rate");  // missing
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "type = \"shardlow\"\n")), "thermostat.gamma");      // missing
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "type = \"anderson\"\nrate = 4.5\n")), "thermostat.type");
  // A key of another type.
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "type = \"shardlow\"\ngamma = 4.5\nrate = 4.5\n")),
            "thermostat.rate");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "rate = 4.5\ngamma = 4.5\n")), "thermostat.gamma");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "rate = 4.5\ns = 1.0\n")), "thermostat.s");
  // Peters: gamma dt / mu = 20 x 0.04 / 0.5 = 1.6 > 1.
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "type = \"peters\"\ngamma = 20.0\n")), "thermostat.gamma");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "type = \"shardlow\"\ngamma = 20.0\n")), "accepted");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "rate = 4.5\nrc = 3.0\n")), "thermostat.rc");  // box 5 < 2 rc
  // Stoyanov-Groot: rate may be 0 but not missing; alpha required and alpha dt / mu <= 1; no gamma.
  const std::string sg = "type = \"stoyanov-groot\"\n";
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, sg + "rate = 0.0\nalpha = 4.5\n")), "accepted");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, sg + "alpha = 4.5\n")), "thermostat.rate");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, sg + "rate = 1.0\n")), "thermostat.alpha");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, sg + "rate = 1.0\nalpha = 20.0\n")), "thermostat.alpha");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, sg + "rate = 1.0\nalpha = 4.5\ngamma = 4.5\n")), "thermostat.gamma");
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, "rate = 4.5\nalpha = 4.5\n")), "thermostat.alpha");
  // The pair law's own dissipation must be off.
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, la, "4.5")), "pair.gamma");
  // Euler, and frozen (wall) particles.
  std::string euler = fluid(5.0, 0.04, la);
  euler.replace(euler.find("[integrator]\n"), 13, "[integrator]\ntype = \"euler\"\n");
  EXPECT_EQ(refused_key(euler), "integrator.type");
  // (A [[solid]] needs a frozen species, so walls are refused by this one too.)
  EXPECT_EQ(refused_key(fluid(5.0, 0.04, la, "0.0", "[[species]]\nname = \"W\"\nfrozen = true\n")),
            "species[1].frozen");
}

// eDPD keeps its own energy balance: a thermostat beside it is refused when the run is built.
TEST(PairThermostats, RefusedWithALawThatCarriesParticleTemperatures) {
  std::string toml = fluid(5.0, 0.01, "rate = 4.5\n", "0.0", "cv = 100.0\n");
  toml.replace(toml.find("[pair]\n"), 7, "[pair]\nstyle = \"edpd\"\nkappa = 0.1\n");
  try {
    Simulation sim(parse_config(toml, "edpd.toml"), RunOptions{});
    FAIL() << "eDPD with [thermostat] accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "pair.style") << e.what();
  }
}

// On the command line: one line naming the key, and a non-zero exit.
TEST(PairThermostats, TheCommandExitsNonZeroNamingTheKey) {
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_pair_thermostats_cli";
  std::filesystem::create_directories(dir);
  const auto file = dir / "bad.toml";
  {
    std::FILE* f = std::fopen(file.string().c_str(), "w");
    ASSERT_NE(f, nullptr);
    const std::string text = fluid(5.0, 0.04, "rate = 30.0\n");
    std::fputs(text.c_str(), f);
    std::fclose(f);
  }
  const std::string cmd =
      test::mesodpd_bin() + " run " + file.string() + " --out " + (dir / "out").string() + " 2>&1";
  std::FILE* pipe = popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) output += buf;
  const int status = pclose(pipe);
  EXPECT_NE(status, 0) << output;
  EXPECT_NE(output.find("thermostat.rate"), std::string::npos) << output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mesodpd
