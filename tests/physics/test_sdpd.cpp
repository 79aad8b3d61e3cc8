// Smoothed DPD (physics/sdpd_pair.hpp; seed 003 §4): the kernel moments the viscous terms rest on, the
// random force's covariance against the fluctuation-dissipation theorem, the law's antisymmetry, and
// runs whose temperature, sound speed and shear viscosity are the inputs, with momentum conserved and
// the trajectory bit-identical across threads and a restart. The long versions of the runs are in
// examples/sdpd_fluid (docs/validation.md §12).
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <variant>

#include "engine/pair_laws.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "mesodpd/validate.hpp"
#include "physics/sdpd_pair.hpp"
#include "test_support.hpp"
#include "threads_and_restart.hpp"

using namespace mesodpd;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The law's parameters for one pair of equal particles.
SdpdPairParamsT<double> params(DensityKernelKind kernel, double h, double eta, double zeta, double c, double rho0,
                               double n = 1, double kT = 1) {
  PairValues v;
  v.rc = h;
  v.kernel = kernel;
  v.kT = kT;
  v.own[0] = eta;
  v.own[1] = zeta;
  v.own[2] = c;
  v.own[3] = rho0;
  v.own[4] = n;
  v.own[5] = 0;
  v.own[6] = 1;  // interact
  return SdpdLaw::make(v);
}

template <int K, int N>
PairForceT<double> eval(const SdpdPairParamsT<double>& p, const PairInput<double>& in) {
  return SdpdLaw::Eval<K, N>{}(p, in);
}

// The fluid of the run tests: number density 3 (m = 1, rho_0 = 3), a kernel over h = 1.5 (about 42
// neighbours), sound speed 8, dt = 0.01 (CFL dt c / h = 0.05), with the given kT and background pressure.
struct Fluid {
  double box_x = 6.0, box_y = 6.0, box_z = 6.0, eta = 1.0, density = 3.0, mass = 1.0, kT = 1.0, p_b = 0.0;
  std::string kernel = "lucy", extra;
};
std::string fluid_toml(const Fluid& f) {
  return "[system]\nbox = [" + std::to_string(f.box_x) + ", " + std::to_string(f.box_y) + ", " +
         std::to_string(f.box_z) + "]\nkT = " + std::to_string(f.kT) +
         "\nseed = 41\n[[species]]\nname = \"F\"\nmass = " + std::to_string(f.mass) + "\ndensity = " +
         std::to_string(f.density) + "\n[pair]\nstyle = \"sdpd\"\nkernel = \"" + f.kernel +
         "\"\nrc = 1.5\neta = " + std::to_string(f.eta) + "\nc = 8.0\nrho0 = " + std::to_string(3.0 * f.mass) +
         "\np_b = " + std::to_string(f.p_b) + "\n[integrator]\ndt = 0.01\n[output]\nthermo_every = 10\nprogress = false\n" +
         f.extra;
}

}  // namespace

TEST(Sdpd, KernelMomentsAreTheOnesTheViscousTermsAssume) {
  // integral of W over space = 1 and integral of F(r) r^2 = 3 (so that sum_j F_ij r_ij r_ij / d_j -> 1,
  // which fixes alpha and beta), and F = -W'(r) / r against a finite difference of the density kernel.
  for (DensityKernelKind kind : {DensityKernelKind::Lucy, DensityKernelKind::Wendland}) {
    const double h = 1.3;
    const SdpdPairParamsT<double> p = params(kind, h, 1, 0, 1, 1);
    const DensityParamsT<double> dp{h, h * h};
    const auto w = [&](double r) {
      return with_density_kernel(kind, [&](auto k) { return k(dp, r); });
    };
    const auto f = [&](double r) {
      const double om = r < h ? 1 - r / h : 0;
      return kind == DensityKernelKind::Wendland ? p.fnorm * om * om * om : p.fnorm * om * om;
    };
    double iw = 0, if2 = 0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
      const double r = (k + 0.5) * h / n, shell = 4 * kPi * r * r * h / n;
      iw += w(r) * shell;
      if2 += f(r) * r * r * shell;
    }
    EXPECT_NEAR(iw, 1.0, 1e-6);
    EXPECT_NEAR(if2, 3.0, 1e-6);
    EXPECT_NEAR(p.w0, w(0.0), 1e-12);
    for (double r = 0.05; r < h; r += 0.1) {
      const double d = 1e-6, dw = (w(r + d) - w(r - d)) / (2 * d);
      EXPECT_NEAR(f(r), -dw / r, 1e-6 * (1 + f(r))) << "r = " << r;
    }
  }
}

TEST(Sdpd, RandomForceCovarianceIsTwoKTTimesTheFriction) {
  // For a fixed pair geometry the random force's covariance times dt must be 2 kT (alpha 1 + beta e e)
  // F / (d_i d_j): the FDT that makes the input kT the temperature. Sampled with Gaussian words; a
  // wrong amplitude of the traceless or the trace part shows in the transverse or the longitudinal
  // variance.
  const double eta = 1.7, zeta = 0.4, kT = 1.3, dt = 0.01;
  const SdpdPairParamsT<double> p = params(DensityKernelKind::Lucy, 1.5, eta, zeta, 5, 3, 1, kT);
  PairInput<double> in;
  in.d[0] = 0.3, in.d[1] = -0.5, in.d[2] = 0.4;
  in.r = std::sqrt(0.09 + 0.25 + 0.16);
  in.rho_i = 2.6, in.rho_j = 3.3;
  in.inv_sqrt_dt = 1 / std::sqrt(dt);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  double sum[3] = {0, 0, 0}, sum2[3][3] = {};
  const int n = 400000;
  for (int s = 0; s < n; ++s) {
    for (double& x : in.xm) x = g(rng);
    const PairForceT<double> f = eval<0, 1>(p, in);
    double v[3];
    for (int a = 0; a < 3; ++a) v[a] = f.fr * in.d[a] / in.r + f.fn[a];
    for (int a = 0; a < 3; ++a) {
      sum[a] += v[a];
      for (int b = 0; b < 3; ++b) sum2[a][b] += v[a] * v[b];
    }
  }
  const double di = in.rho_i + p.w0, dj = in.rho_j + p.w0, om = 1 - in.r / 1.5;
  const double gij = p.fnorm * om * om / (di * dj);
  const double alpha = 5 * eta / 3 - zeta, beta = 5 * (zeta + eta / 3);
  for (int a = 0; a < 3; ++a) {
    const double ea = in.d[a] / in.r;
    for (int b = 0; b < 3; ++b) {
      const double eb = in.d[b] / in.r;
      const double want = 2 * kT * (alpha * (a == b ? 1 : 0) + beta * ea * eb) * gij;
      const double got = (sum2[a][b] / n - sum[a] / n * sum[b] / n) * dt;
      EXPECT_NEAR(got, want, 0.012 * 2 * kT * (alpha + beta) * gij) << "component " << a << b;
    }
  }
}

TEST(Sdpd, PairForceIsOppositeWhenTheParticlesSwap) {
  // Entry (a, b) with i of species a and entry (b, a) with the roles swapped: the same force, reversed
  // (masses that differ enter the pressures), and the dissipative parts oppose the relative motion.
  PairValues v;
  v.rc = 1.2;
  v.kernel = DensityKernelKind::Wendland;
  v.own = {0.8, 0.3, 4.0, 2.5, 7.0, 0.5, 1.0};
  v.mass_i = 1.0, v.mass_j = 1.7;
  const SdpdPairParamsT<double> ab = SdpdLaw::make(v);
  std::swap(v.mass_i, v.mass_j);
  const SdpdPairParamsT<double> ba = SdpdLaw::make(v);
  PairInput<double> in;
  in.d[0] = 0.2, in.d[1] = 0.6, in.d[2] = -0.3;
  in.r = std::sqrt(0.04 + 0.36 + 0.09);
  in.dv[0] = 0.7, in.dv[1] = -0.2, in.dv[2] = 0.9;
  in.rv = (0.2 * 0.7 - 0.6 * 0.2 - 0.3 * 0.9) / in.r;
  in.rho_i = 1.9, in.rho_j = 2.4;
  in.inv_sqrt_dt = 10;
  for (int k = 0; k < 6; ++k) in.xm[k] = 0.3 * k - 0.7;
  PairInput<double> out = in;
  for (int a = 0; a < 3; ++a) out.d[a] = -in.d[a], out.dv[a] = -in.dv[a];
  std::swap(out.rho_i, out.rho_j);
  const PairForceT<double> f = eval<1, 7>(ab, in), r = eval<1, 7>(ba, out);
  for (int a = 0; a < 3; ++a) {
    const double fa = (f.fc + f.fd + f.fr) * in.d[a] / in.r + f.fn[a];
    const double ra = (r.fc + r.fd + r.fr) * out.d[a] / out.r + r.fn[a];
    EXPECT_NEAR(fa, -ra, 1e-12 * (1 + std::abs(fa)));
  }
  // Without noise the friction takes energy from the relative motion: F^D . v_ij < 0.
  PairInput<double> quiet = in;
  for (double& x : quiet.xm) x = 0;
  const PairForceT<double> q = eval<1, 7>(ab, quiet);
  double power = 0;
  for (int a = 0; a < 3; ++a) power += (q.fd * in.d[a] / in.r + q.fn[a]) * in.dv[a];
  EXPECT_LT(power, 0);
}

TEST(Sdpd, RunConservesMomentumAndHoldsTheInputTemperature) {
  // The noise is set by the FDT for the particle mass, not by hand: the kinetic temperature is kT and
  // the velocity variance kT/m, for m = 1 and m = 2 (the same mass density rho_0 = 3 m).
  for (const double mass : {1.0, 2.0}) {
    Fluid f;
    f.mass = mass;
    const SimulationSpec spec = parse_config(fluid_toml(f), "sdpd_temperature.toml");
    Simulation sim(spec, RunOptions{});
    const ThermoState t0 = sim.thermo();
    double t_sum = 0, v2 = 0;
    int samples = 0;
    for (int k = 1; k <= 2500; ++k) {
      sim.step();
      if (k % 10 != 0) continue;
      const ThermoState t = sim.thermo();
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(t.momentum[c], t0.momentum[c], 1e-9) << "step " << k;
      if (k <= 500) continue;
      t_sum += t.temperature;
      const ParticleData& p = sim.particles();
      for (std::size_t i = 0; i < p.n_local; ++i) v2 += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
      ++samples;
    }
    const double temperature = t_sum / samples;
    const double var = v2 / (3.0 * samples * static_cast<double>(sim.particles().n_local));
    std::printf("sdpd m = %.0f: <T> = %.4f, <v_a^2> m = %.4f (kT = 1)\n", mass, temperature, var * mass);
    EXPECT_NEAR(temperature, 1.0, 0.01) << "m = " << mass;
    EXPECT_NEAR(var * mass, 1.0, 0.01) << "m = " << mass;
  }
}

TEST(Sdpd, SoundSpeedFromThePressureAgainstDensityIsTheInput) {
  // Two boxes at 4% below and above rho_0: c_T^2 = dP/drho of the virial pressure less its ideal-gas
  // part n kT (the particles' kinetic pressure, which the continuum equation of state does not hold)
  // must be c^2 = 64 within 5% in c. With a background pressure p_b = c^2 rho_0 / 3, which keeps the
  // particles ordered; at p_b = 0 the disordered fluid's sound speed is 13-20% below the input at this
  // resolution (printed here, measured in docs/validation.md §12).
  for (const double p_b : {64.0, 0.0}) {
    double pressure[2], rho[2];
    for (int s = 0; s < 2; ++s) {
      Fluid f;
      f.density = 3.0 * (s == 0 ? 0.96 : 1.04);
      f.p_b = p_b;
      const SimulationSpec spec = parse_config(fluid_toml(f), "sdpd_sound.toml");
      Simulation sim(spec, RunOptions{});
      double p_sum = 0;
      int samples = 0;
      for (int k = 1; k <= 1500; ++k) {
        sim.step();
        if (k > 300 && k % 10 == 0) {
          const ThermoState t = sim.thermo();
          p_sum += t.pressure - f.density * t.temperature;
          ++samples;
        }
      }
      pressure[s] = p_sum / samples;
      rho[s] = f.density;  // m = 1
    }
    const double c = std::sqrt((pressure[1] - pressure[0]) / (rho[1] - rho[0]));
    std::printf("sdpd sound speed, p_b = %.0f: P(%.2f) = %.3f, P(%.2f) = %.3f, c = %.3f (input 8)\n", p_b, rho[0],
                pressure[0], rho[1], pressure[1], c);
    if (p_b > 0) EXPECT_NEAR(c, 8.0, 0.4);
  }
}

TEST(Sdpd, ReversePoiseuilleViscosityIsTheInput) {
  // seed 002's reverse Poiseuille flow: the fitted shear viscosity must be the input eta = 2 within 5%,
  // for Wendland's kernel over 42 neighbours at kT = 0.1 (Sc ~ 100; Lucy's kernel there gives +7%, over
  // 100 neighbours +1%). At eta = 2 = 0.056 rho_0 c h the numerical viscosity of the pressure forces
  // (~0.19 at c = 8) and the friction's discretisation deficit (~10%) nearly cancel; a smaller eta
  // comes out too viscous (docs/validation.md §12), which this test does not cover.
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_sdpd_poiseuille";
  std::filesystem::remove_all(dir);
  const std::string extra =
      "[run]\nsteps = 9000\n[poiseuille]\nforce = 0.1\nflow_axis = \"x\"\ngradient_axis = \"z\"\nbins = 24\n"
      "start = 3000\nblocks = 6\n";
  Fluid f;
  f.box_z = 12.0;
  f.eta = 2.0;
  f.kT = 0.1;
  f.kernel = "wendland";
  f.extra = extra;
  const SimulationSpec spec = parse_config(fluid_toml(f), "sdpd_poiseuille.toml");
  RunOptions o;
  o.out_dir = dir;
  Simulation sim(spec, o);
  sim.run();
  const std::string json = test::read_file(dir / "viscosity.json");
  const auto number = [&](const std::string& key) {
    return std::stod(json.substr(json.find("\"" + key + "\": ") + key.size() + 4));
  };
  const double eta = number("eta");
  std::printf("sdpd reverse Poiseuille: eta = %.4f (input 2)\n%s\n", eta, json.c_str());
  EXPECT_NEAR(eta, 2.0, 0.1);
  std::filesystem::remove_all(dir);
}

TEST(Sdpd, LeesEdwardsStressGivesTheReversePoiseuilleViscosity) {
  // The same fluid sheared by Lees-Edwards images: the stress must carry the non-central friction, whose
  // x force follows v_x,ij ~ y_ij (the flux of x-momentum through y-planes, sum y_ij F_x,ij; the
  // transposed component sum x_ij F_y,ij misses most of it and gave eta = 0.6). Against the reverse-
  // Poiseuille value of the test above (2.02) within 10%.
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_sdpd_shear";
  std::filesystem::remove_all(dir);
  Fluid f;
  f.eta = 2.0;
  f.kT = 0.1;
  f.kernel = "wendland";
  f.extra =
      "[lees_edwards]\nflow = \"x\"\ngradient = \"y\"\nshear_rate = 0.3\nstress_every = 5\nequilibrate = 1000\n"
      "blocks = 10\n[run]\nsteps = 7000\n";
  f.box_x = 8.0;
  f.box_y = 8.0;
  RunOptions o;
  o.out_dir = dir;
  Simulation sim(parse_config(fluid_toml(f), "sdpd_shear.toml"), o);
  sim.run();
  const std::string csv = test::read_file(dir / "shear_summary.csv");
  const auto at = csv.find("\neta,");
  ASSERT_NE(at, std::string::npos) << csv;
  const double eta = std::stod(csv.substr(at + 5));
  const double err = std::stod(csv.substr(csv.find(',', at + 5) + 1));
  std::printf("sdpd Lees-Edwards: eta = %.4f +- %.4f (reverse Poiseuille 2.019, input 2)\n", eta, err);
  EXPECT_NEAR(eta, 2.019, 0.2);
  std::filesystem::remove_all(dir);
}

TEST(Sdpd, BitIdenticalForOneAndTwoThreadsAndAcrossARestart) {
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_sdpd_restart";
  Fluid f;
  f.box_z = 5.0;
  f.p_b = 10.0;
  const SimulationSpec spec = parse_config(fluid_toml(f), "sdpd_restart.toml");
  test::expect_bit_identical_on_threads_and_restart(spec, dir);
}

TEST(Sdpd, PairThatDoesNotInteractIsInvisible) {
  // interact = 0: the law's force is zero at every distance inside the kernel, whatever the velocities
  // and noise, and the pair's density range is empty, so its kernel adds nothing.
  PairValues v;
  v.rc = 1.5;
  v.kernel = DensityKernelKind::Wendland;
  v.own = {2.0, 0.5, 8.0, 3.0, 1.0, 0.0, 0.0};
  const SdpdPairParamsT<double> p = SdpdLaw::make(v);
  ASSERT_LT(SdpdLaw::density_range(v), 0.0);
  const DensityParamsT<double> dp{SdpdLaw::density_range(v), 0.0};
  for (const double r : {0.1, 0.7, 1.3}) {
    PairInput<double> in;
    in.r = r;
    in.d[0] = r;
    in.dv[0] = 0.3;
    in.dv[1] = -0.2;
    in.dv[2] = 0.1;
    in.rv = 0.3 * r;
    in.rho_i = 3.0;
    in.rho_j = 2.0;
    in.inv_sqrt_dt = 10.0;
    for (int w = 0; w < 6; ++w) in.xm[w] = 0.4 * w - 1.0;
    const PairForceT<double> f = eval<1, 1>(p, in);
    EXPECT_EQ(f.fc, 0.0);
    EXPECT_EQ(f.fd, 0.0);
    EXPECT_EQ(f.fr, 0.0);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(f.fn[c], 0.0) << "r = " << r;
    EXPECT_EQ(WendlandDensityKernel{}(dp, r), 0.0) << "r = " << r;
  }
  // A run: two fluids A and B filling the same box (number density 3 each) that do not see each other
  // have the excess pressure (virial minus n kT) of two separate fluids, twice one fluid's; interacting,
  // they are one fluid at twice rho_0, whose equation of state pushes far harder.
  const auto excess_pressure = [](int fluids, bool interact) {
    std::string toml = "[system]\nbox = [6.0, 6.0, 6.0]\nkT = 0.1\nseed = 5\n[[species]]\nname = \"A\"\ndensity = 3.0\n";
    if (fluids == 2) toml += "[[species]]\nname = \"B\"\ndensity = 3.0\n";
    toml += "[pair]\nstyle = \"sdpd\"\nkernel = \"wendland\"\nrc = 1.5\neta = 2.0\nc = 8.0\nrho0 = 3.0\n";
    if (fluids == 2 && !interact) toml += "[[pair.override]]\nspecies = [\"A\", \"B\"]\ninteract = 0\n";
    toml += "[integrator]\ndt = 0.01\n[output]\nthermo_every = 10\nprogress = false\n";
    Simulation sim(parse_config(toml, "sdpd_interact.toml"), RunOptions{});
    double sum = 0;
    int samples = 0;
    for (int k = 1; k <= 600; ++k) {
      sim.step();
      if (k > 200 && k % 10 == 0) {
        const ThermoState t = sim.thermo();
        sum += t.pressure - 3.0 * fluids * t.temperature;
        ++samples;
      }
    }
    return sum / samples;
  };
  const double one = excess_pressure(1, true), apart = excess_pressure(2, false), mixed = excess_pressure(2, true);
  std::printf("sdpd interact: excess pressure of one fluid %.3f, two that do not interact %.3f (ratio %.3f), two "
              "that do %.3f\n", one, apart, apart / one, mixed);
  EXPECT_NEAR(apart / one, 2.0, 0.2);
  EXPECT_GT(mixed, 5.0 * apart);
}

TEST(Sdpd, BadInputNamesTheKey) {
  const auto refused = [](const std::string& toml, const std::string& key) {
    try {
      parse_config(toml, "bad.toml");
      ADD_FAILURE() << "accepted; expected an error naming " << key;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  const std::string base = fluid_toml(Fluid{});
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string t = base;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  refused(with("eta = 1.000000\n", "eta = 1.0\nzeta = 2.0\n"), "pair.zeta");
  refused(with("eta = 1.000000\n", "eta = -1.0\n"), "pair.eta");
  refused(with("eta = 1.000000\n", ""), "pair.eta");
  refused(with("c = 8.0\n", "c = -2.0\n"), "pair.c");
  refused(with("c = 8.0\n", "c = 0.0\n"), "pair.c");
  refused(with("kernel = \"lucy\"", "kernel = \"warren\""), "pair.kernel");
  refused(with("rc = 1.5\n", "rc = 1.5\ngamma = 4.5\n"), "pair.gamma");
  refused(with("p_b = ", "interact = 0.5\np_b = "), "pair.interact");  // 0 or 1 only
  // The Wendland kernel and Tait's law are accepted.
  refused(with("rc = 1.5\n", "rc = 0.5\n"), "pair.rc");              // below the spacing 3^(-1/3)
  refused(with("dt = 0.01\n", "dt = 0.05\n"), "pair.c");             // the sound limit 0.25 h / c
  refused(with("eta = 1.000000\n", "eta = 200.0\n"), "pair.eta");     // the viscous limit 0.05 h^2 rho0 / eta
  // The Wendland kernel and Tait's law are accepted; few neighbours are a warning, not an error.
  EXPECT_NO_THROW(parse_config(with("kernel = \"lucy\"", "kernel = \"wendland\"\neos_exponent = 7"), "ok.toml"));
  const SimulationSpec few = parse_config(with("rc = 1.5\n", "rc = 1.0\n"), "few.toml");
  const std::vector<std::string> warnings = spec_warnings(few);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("neighbours"), std::string::npos) << warnings[0];
  // eta = 1 against rho0 c rc = 36: the numerical viscosity of the pressure forces would show.
  const std::vector<std::string> small_eta = spec_warnings(parse_config(base, "small_eta.toml"));
  ASSERT_EQ(small_eta.size(), 1u);
  EXPECT_NE(small_eta[0].find("pair.eta"), std::string::npos) << small_eta[0];
  EXPECT_TRUE(spec_warnings(parse_config(with("eta = 1.000000\n", "eta = 2.0\n"), "ok_eta.toml")).empty());
}
