// Energy-conserving DPD (physics/edpd_pair.hpp, engine/install_edpd.cpp): energy conservation, the heat
// a decaying flow leaves behind, the common temperature kinetic and internal degrees of freedom reach,
// Fourier conduction against the kinetic-theory diffusivity, reproducibility, bad input.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "transport_configs.hpp"
#include "test_support.hpp"

using namespace mesodpd;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A periodic eDPD fluid: rho = 3, a = 25, gamma = 4.5 in an l^3 box; `pair` and `species` add keys.
std::string edpd_config(double l, double dt, double cv, double kappa, const std::string& extra_pair = "",
                        const std::string& extra_species = "", double temperature = 0.0) {
  return test::periodic_fluid_config(fmt::format("style = \"edpd\"\nkappa = {}\n{}", kappa, extra_pair),
                                     fmt::format("cv = {}\ntemperature = {}\n{}", cv, temperature, extra_species), "",
                                     l, dt, 4242);
}

double internal_energy(const Simulation& sim, double cv) {
  const ParticleData& p = sim.particles();
  double u = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) u += cv * p.temp[i];
  return u;
}

double mean_temp(const ParticleData& p) {
  double t = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) t += p.temp[i];
  return t / static_cast<double>(p.n_local);
}

}  // namespace

// Total energy (kinetic + potential + internal) per particle at every thermo row of a run of `steps` steps
// of dt, from t = 0 (the random start's excess potential energy turns into heat on the way).
std::vector<double> energy_per_particle(double dt, int steps, int every, double cv) {
  Simulation sim(parse_config(edpd_config(7.0, dt, cv, 0.02), "e.toml"), RunOptions{});
  const double n = static_cast<double>(sim.particles().n_local);
  std::vector<double> e;
  for (int k = 0; k <= steps; ++k) {
    if (k % every == 0) {
      const ThermoState t = sim.thermo();
      e.push_back((t.kinetic_energy + t.potential_energy + internal_energy(sim, cv)) / n);
    }
    if (k < steps) sim.step();
  }
  return e;
}

// Least-squares slope of e against time (rows `every` steps of dt apart), from row `from` on.
double slope(const std::vector<double>& e, double row_time, std::size_t from) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0;
  for (std::size_t k = from; k < e.size(); ++k) {
    const double t = static_cast<double>(k) * row_time;
    sx += t, sy += e[k], sxx += t * t, sxy += t * e[k], m += 1;
  }
  return (m * sxy - sx * sy) / (m * sxx - sx * sx);
}

// In an isolated periodic box the total energy is conserved up to the time step's error, which vanishes
// as dt -> 0: the modified velocity-Verlet step gives the pair's dissipative and random forces one
// kick of their linear work each, not the second-order part (dt^2 |F^D|^2 / 2m per particle per step),
// so the energy drifts upwards at a rate proportional to dt. Measured (docs/validation.md, "eDPD"):
// 0.048 kT per particle per time unit at dt = 0.01, so 4.8 kT per particle per 10^4 steps, against an
// internal energy of C_v kT per particle (0.05% of it for C_v = 10^4, 5e-5 for LAMMPS's C_v = 10^5).
// The bound asserted: below 0.08 kT per particle per time unit at dt = 0.01 (8 kT per 10^4 steps), and
// the drift rate halving (0.3 to 0.7) when dt halves.
TEST(Edpd, TotalEnergyDriftIsBoundedAndVanishesWithTheTimeStep) {
  const double cv = 100.0;
  const std::vector<double> coarse = energy_per_particle(0.01, 2000, 100, cv);
  const std::vector<double> fine = energy_per_particle(0.005, 4000, 200, cv);
  const double rate_coarse = slope(coarse, 1.0, 5), rate_fine = slope(fine, 1.0, 5);  // from t = 5 on
  std::printf("eDPD energy drift per particle and time unit: %.4f kT at dt = 0.01, %.4f kT at dt = 0.005 "
              "(%.2f kT per particle per 10^4 steps at dt = 0.01)\n",
              rate_coarse, rate_fine, 100 * rate_coarse);
  EXPECT_LT(std::abs(rate_coarse), 0.08);
  EXPECT_GT(rate_fine / rate_coarse, 0.3);
  EXPECT_LT(rate_fine / rate_coarse, 0.7);
}

// A decaying shear wave: the flow's kinetic energy (and the random start's excess potential energy)
// turns into internal energy. The ratio gained / lost tends to 1 as dt -> 0 (extrapolated linearly from
// dt = 0.01 and 0.005); under the seed's printed factor 1/(2 C_v) it would tend to 1/C_v = 0.1.
TEST(Edpd, ADecayingFlowHeatsTheFluidByTheMechanicalEnergyItLoses) {
  const double cv = 10.0, l = 8.0, u0 = 3.0, duration = 10.0;
  auto ratio = [&](double dt) {
    Simulation sim(parse_config(edpd_config(l, dt, cv, 0.0), "wave.toml"), RunOptions{});
    ParticleData& p = sim.particles();
    for (std::size_t i = 0; i < p.n_local; ++i) p.vx[i] += u0 * std::sin(2 * kPi * p.z[i] / l);
    const ThermoState t0 = sim.thermo();  // recomputes the forces and rates of the new velocities
    const double u_start = internal_energy(sim, cv);
    const int steps = static_cast<int>(std::lround(duration / dt));
    for (int k = 0; k < steps; ++k) sim.step();
    const ThermoState t1 = sim.thermo();
    const double gained = internal_energy(sim, cv) - u_start;
    const double lost = (t0.kinetic_energy + t0.potential_energy) - (t1.kinetic_energy + t1.potential_energy);
    const double n = static_cast<double>(p.n_local);
    std::printf("shear wave, dt = %g: mechanical energy lost %.4g kT per particle, internal gained %.4g\n", dt,
                lost / n, gained / n);
    EXPECT_GT(lost / n, 3.0);  // the wave (2.25 kT per particle) and the random start's overlaps
    return gained / lost;
  };
  const double coarse = ratio(0.01), fine = ratio(0.005);
  const double limit = 2 * fine - coarse;
  std::printf("gained / lost: %.4f (dt = 0.01), %.4f (dt = 0.005), %.4f (dt -> 0)\n", coarse, fine, limit);
  EXPECT_NEAR(limit, 1.0, 0.03);
}

// Kinetic and internal temperatures started apart (internal 1.5, kinetic 1.0) meet: the random force
// of a pair follows the particles' internal temperatures. With C_v = 1000 energy conservation puts the
// common temperature at 1.5 - 0.5 (3/2) / (C_v + 3/2) = 1.4993; the internal mean may sit up to ~T/C_v
// above the kinetic temperature (docs/physics.md, "eDPD", equilibrium), here 0.0015.
TEST(Edpd, KineticAndInternalTemperaturesMeet) {
  const double cv = 1000.0;
  Simulation sim(parse_config(edpd_config(7.0, 0.005, cv, 0.0005, "", "", 1.5), "relax.toml"), RunOptions{});
  for (int k = 0; k < 1000; ++k) sim.step();
  double t_kin = 0, t_int = 0;
  const int samples = 20;
  for (int s = 0; s < samples; ++s) {
    for (int k = 0; k < 50; ++k) sim.step();
    t_kin += sim.thermo().temperature / samples;
    t_int += mean_temp(sim.particles()) / samples;
  }
  std::printf("relaxation: T_kin = %.4f, T_int = %.4f\n", t_kin, t_int);
  EXPECT_NEAR(t_kin, 1.4993, 0.02);
  EXPECT_NEAR(t_int, 1.5, 0.004);
}

// Heat conduction: a sinusoidal temperature profile decays as exp(-D k^2 t) with the kinetic-theory
// diffusivity D_T = 2 pi n C_v kappa r_cT^5 / 315 (s_T = 2; docs/physics.md, "eDPD") plus the particles'
// own self-diffusion, which carries their heat (measured in the same run).
TEST(Edpd, ATemperatureWaveDecaysWithTheKineticTheoryDiffusivity) {
  const double cv = 100.0, kappa = 0.3, l = 10.0, rho = 3.0, dt = 0.01;
  const double d_t = 2 * kPi * rho * cv * kappa / 315.0;  // 1.795
  Simulation sim(parse_config(edpd_config(l, dt, cv, kappa), "wave.toml"), RunOptions{});
  ParticleData& p = sim.particles();
  const double k = 2 * kPi / l;
  for (std::size_t i = 0; i < p.n_local; ++i) p.temp[i] = 1.0 + 0.2 * std::sin(k * p.z[i]);
  sim.thermo();
  // The least-squares amplitude of the mode: sum (T_i - <T>) sin(k z_i) / sum sin^2(k z_i). Taking the mean
  // out matters: sum sin(k z_i) alone is the density's own Fourier mode, which sound waves move.
  auto amplitude = [&] {
    const ParticleData& q = sim.particles();
    const double t_mean = mean_temp(q);
    double a = 0, norm = 0;
    for (std::size_t i = 0; i < q.n_local; ++i) {
      const double s = std::sin(k * q.z[i]);
      a += (q.temp[i] - t_mean) * s;
      norm += s * s;
    }
    return a / norm;
  };
  // Unwrapped z of every particle by id, for the self-diffusion.
  auto unwrapped = [&] {
    const ParticleData& q = sim.particles();
    std::vector<double> z(q.n_local);
    for (std::size_t i = 0; i < q.n_local; ++i) z[q.id[i] - 1] = q.z[i] + q.iz[i] * l;
    return z;
  };
  const std::vector<double> z0 = unwrapped();
  const double a0 = amplitude();
  // Fit log A(t) over t in [0, 1.5] (the amplitude falls to ~e^-1.1).
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int m = 0;
  for (int block = 1; block <= 15; ++block) {
    for (int s = 0; s < 10; ++s) sim.step();
    const double t = block * 10 * dt, y = std::log(amplitude() / a0);
    sx += t, sy += y, sxx += t * t, sxy += t * y, ++m;
  }
  const double rate = -(m * sxy - sx * sy) / (m * sxx - sx * sx);
  const std::vector<double> z1 = unwrapped();
  double msd = 0;
  for (std::size_t i = 0; i < z0.size(); ++i) msd += (z1[i] - z0[i]) * (z1[i] - z0[i]);
  const double d_self = msd / static_cast<double>(z0.size()) / (2 * 1.5);
  const double measured = rate / (k * k);
  std::printf("conduction: measured D = %.4f, D_T = %.4f, self-diffusion %.4f, D_T + D_self = %.4f\n", measured, d_t,
              d_self, d_t + d_self);
  // D_T is the mean-field value: the rate of a smooth field on the particles at one instant, an upper
  // bound for the network of pair conductances, whose slowest mode adapts to the particles' disorder
  // (a frozen random configuration decays at 0.5 D_T; docs/validation.md, "eDPD"). The fluid's motion
  // averages the disorder and carries heat, so the decay lies between 0.8 D_T and D_T + D_self
  // (measured 0.89 D_T here).
  EXPECT_GT(measured, 0.8 * d_t);
  EXPECT_LT(measured, d_t + d_self);
}

// The same run on 1 and 2 threads and across a restart: bit-identical temperatures.
TEST(Edpd, TemperaturesAreBitIdenticalAcrossThreadsAndRestarts) {
  const std::string text = edpd_config(6.0, 0.01, 50.0, 0.05);
  const std::vector<std::string> fields{"temp"};
  const std::vector<double> one = test::run_fields(text, 1, 60, fields), two = test::run_fields(text, 2, 60, fields);
  EXPECT_TRUE(one == two);
  {
    // Sampling (thermo() recomputes the forces and rates at the end-of-step velocities) leaves the
    // trajectory alone: every field the force stage writes is put back.
    Simulation sim(parse_config(text, "r.toml"), RunOptions{});
    for (int k = 0; k < 60; ++k) {
      sim.step();
      sim.thermo();
    }
    EXPECT_TRUE(test::fields_by_id(sim.particles(), fields) == one);
  }
  const fs::path dir = fs::temp_directory_path() / "mesodpd_edpd_restart";
  fs::create_directories(dir);
  const fs::path file = dir / "state.mdpd";
  test::run_fields(text, 1, 30, fields, {}, file);
  EXPECT_TRUE(test::run_fields(text, 1, 30, fields, file) == one);
  fs::remove_all(dir);
}

// Bad input: one error naming the key.
TEST(Edpd, BadInputNamesTheKey) {
  const auto error_of = test::config_error_of;
  // cv is required with eDPD.
  std::string text = edpd_config(6.0, 0.01, 50.0, 0.05);
  text.replace(text.find("cv = 50"), 7, "");
  EXPECT_NE(error_of(text).find("species[0].cv"), std::string::npos) << error_of(text);
  // A species key of eDPD with another style.
  std::string dpd = edpd_config(6.0, 0.01, 50.0, 0.05);
  dpd.replace(dpd.find("style = \"edpd\""), 14, "style = \"dpd\"");
  dpd.replace(dpd.find("kappa = 0.05"), 12, "");
  EXPECT_NE(error_of(dpd).find("species[0].cv"), std::string::npos) << error_of(dpd);
  // A negative heat capacity, a negative kappa.
  std::string neg = edpd_config(6.0, 0.01, -1.0, 0.05);
  EXPECT_NE(error_of(neg).find("species[0].cv"), std::string::npos) << error_of(neg);
  std::string negk = edpd_config(6.0, 0.01, 50.0, -0.05);
  EXPECT_NE(error_of(negk).find("pair.kappa"), std::string::npos) << error_of(negk);
  // The Euler integrator.
  std::string euler = edpd_config(6.0, 0.01, 50.0, 0.05);
  euler.replace(euler.find("[integrator]"), 12, "[integrator]\ntype = \"euler\"");
  EXPECT_NE(error_of(euler).find("integrator.type"), std::string::npos) << error_of(euler);
  // A binned mean of something that is not a floating-point particle field.
  const std::string means = edpd_config(6.0, 0.01, 50.0, 0.05) + "\n[analysis.fields]\nmeans = [\"species\"]\n";
  EXPECT_NE(error_of(means).find("analysis.fields.means"), std::string::npos) << error_of(means);
}

// The conduction term alone, on one configuration: for a temperature field T = 1 + eps sin(k z) on
// uniformly placed particles (g(r) = 1), the pair sum gives dT_i/dt = -D_T k^2 (T_i - 1) on average with
// D_T = 2 pi n C_v kappa / 315 (s_T = 2, r_cT = 1): the kinetic theory, exact here up to the
// finite-wavelength term O((k r_c)^2 / 14). The random heat flux is made negligible with a huge dt
// (it scales as dt^-1/2), the velocities are zero (no viscous heating).
TEST(Edpd, ConductionOfAUniformConfigurationHasTheKineticTheoryDiffusivity) {
  const double cv = 100.0, kappa = 0.1, l = 16.0, eps = 0.02;
  std::string text = edpd_config(l, 0.01, cv, kappa);
  text.replace(text.find("gamma = 4.5"), 11, "gamma = 0.0");  // no dissipative heat (nor its Ito term)
  const SimulationSpec spec = parse_config(text, "c.toml");
  Simulation sim(spec, RunOptions{});
  ParticleData p = sim.particles();
  const double k = 2 * kPi / l, n = static_cast<double>(p.n_local) / (l * l * l);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    p.vx[i] = p.vy[i] = p.vz[i] = 0;
    p.temp[i] = 1.0 + eps * std::sin(k * p.z[i]);
  }
  const PairLawTables laws = make_pair_laws(spec);
  std::vector<std::array<double, 3>> f;
  PairSums sums;
  std::vector<double> rate;
  reference_forces(p, sim.box(), laws, NoiseSettings{1, NoiseKind::Uniform}, 1, 1e16, f, sums, nullptr, &rate);
  double num = 0, den = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const double s = std::sin(k * p.z[i]);
    num += rate[i] * s;
    den += (p.temp[i] - 1.0) * s;
  }
  const double measured = -num / den / (k * k);
  const double d_t = 2 * kPi * n * cv * kappa / 315.0;
  std::printf("static conduction: D = %.4f, kinetic theory %.4f\n", measured, d_t);
  EXPECT_NEAR(measured / d_t, 1.0, 0.04);
}

// The parameter table's entry (a, b) holds species a's heat capacity as particle i's, so the pair loop
// gives the same rates whichever particle of a pair it takes first (found by the MPI test: a mixture of
// two heat capacities ran differently on two ranks until the entry (b, a) had them in its own order).
TEST(Edpd, EachTableEntryHoldsItsOwnSpeciesOrder) {
  std::string text = edpd_config(6.0, 0.01, 50.0, 0.05);
  text.replace(text.find("density = 3.0"), 13, "density = 1.5");
  text += "\n[[species]]\nname = \"B\"\ndensity = 1.5\ncv = 80.0\nmass = 2.0\n";
  const SimulationSpec spec = parse_config(text, "two.toml");
  const PairLawTables laws = make_pair_laws(spec);
  const auto& table = std::get<LawTable<EdpdLaw>>(laws).table;
  EXPECT_EQ(table(0, 1).cv_i, 50.0);
  EXPECT_EQ(table(0, 1).cv_j, 80.0);
  EXPECT_EQ(table(1, 0).cv_i, 80.0);
  EXPECT_EQ(table(1, 0).cv_j, 50.0);
  EXPECT_EQ(table(1, 1).cv_i, 80.0);
}

namespace {
// The channel of tests/physics/transport_configs.hpp with eDPD (C_v = 100, kappa = 0.3); `bottom` and `top`
// are the walls' extra [[species]] lines (a temperature or nothing).
std::string wall_config(const std::string& bottom, const std::string& top, double fluid_temperature) {
  return test::plate_channel_config(fmt::format("cv = 100.0\ntemperature = {}", fluid_temperature),
                                    "cv = 100.0\n" + bottom, "cv = 100.0\n" + top, "style = \"edpd\"\nkappa = 0.3");
}
}  // namespace

// Walls held at 1.2 (bottom) and 0.8 (top): heat flows through the fluid and the steady profile is
// linear, falling from near 1.2 to near 0.8 (the walls' own layer of pairs gives a jump at each wall,
// a Kapitza resistance, so the fluid's end values lie inside [0.8, 1.2]).
TEST(Edpd, ThermalWallsHoldALinearTemperatureProfile) {
  Simulation sim(parse_config(wall_config("temperature = 1.2", "temperature = 0.8", 1.0), "walls.toml"), RunOptions{});
  for (int k = 0; k < 2500; ++k) sim.step();  // relaxation time L^2 / (pi^2 D) ~ 6 time units
  const int bins = 10;
  std::vector<double> mean(bins, 0.0);
  const int samples = 50;
  for (int s = 0; s < samples; ++s) {
    for (int k = 0; k < 20; ++k) sim.step();
    const std::vector<double> prof = test::fluid_slabs(sim.particles(), sim.particles().temp, bins);
    for (int b = 0; b < bins; ++b) mean[static_cast<std::size_t>(b)] += prof[static_cast<std::size_t>(b)] / samples;
  }
  // The walls' difference over their distance: -0.4 / 10 = -0.04.
  const test::ProfileLine line = test::inner_line(mean, "thermal walls (walls' slope -0.04)");
  const double slope = line.slope, worst = line.worst;
  EXPECT_LT(slope, -0.025);
  EXPECT_GT(slope, -0.045);
  EXPECT_LT(worst, 0.01);
  EXPECT_GT(mean.front(), 1.1);
  EXPECT_LT(mean.back(), 0.9);
}

// Adiabatic walls (wall species without a temperature) pass no heat: a fluid started with internal
// temperature 1.3 keeps its energy (kinetic + potential + internal) up to the time step's drift, while
// walls held at 1.0 cool it. (The adiabatic wall's particles still carry system.kT in the pair's random
// force, so the near-wall kinetic temperature is pulled towards it; the heat that this moves stays in
// the fluid.)
TEST(Edpd, AdiabaticWallsKeepTheFluidsEnergyAndThermalWallsTakeIt) {
  auto run = [](const std::string& wall, double& t_int, double& drift) {
    Simulation sim(parse_config(wall_config(wall, wall, 1.3), "w.toml"), RunOptions{});
    auto energy = [&] {
      const ThermoState t = sim.thermo();
      double u = 0;
      const ParticleData& p = sim.particles();
      for (std::size_t i = 0; i < p.n_local; ++i)
        if (p.species[i] == 0) u += 100.0 * p.temp[i];
      return t.kinetic_energy + t.potential_energy + u;
    };
    for (int k = 0; k < 300; ++k) sim.step();  // past the random start's first relaxation
    const ParticleData& p = sim.particles();
    double n = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) n += p.species[i] == 0 ? 1 : 0;
    const double e0 = energy();
    for (int k = 0; k < 1500; ++k) sim.step();
    drift = (energy() - e0) / n;
    t_int = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.species[i] == 0) t_int += p.temp[i] / n;
  };
  double t_adiabatic, drift_adiabatic, t_thermal, drift_thermal;
  run("", t_adiabatic, drift_adiabatic);
  run("temperature = 1.0", t_thermal, drift_thermal);
  std::printf("adiabatic walls: energy change %.4f kT per fluid particle over 15 time units, T_int %.4f; walls at 1.0: "
              "%.4f, T_int %.4f\n",
              drift_adiabatic, t_adiabatic, drift_thermal, t_thermal);
  // The periodic box drifts 0.032 kT per particle and time unit at this dt (0.5 over 15); the walls'
  // reflections and forces add to it (measured 1.05): bounded at 1.5.
  EXPECT_LT(std::abs(drift_adiabatic), 1.5);
  EXPECT_GT(t_adiabatic, 1.3);
  EXPECT_LT(drift_thermal, -15.0);  // the walls took most of the 0.3 C_v = 30 per particle of excess
  EXPECT_LT(t_thermal, 1.15);
}

// A species' constant heat source (heat_source, energy per particle and time) raises the total energy
// at N q: here q = 0.5 for 10 time units on top of the time step's drift (0.032 per particle and time).
TEST(Edpd, AHeatSourceAddsItsEnergy) {
  std::string text = edpd_config(7.0, 0.01, 100.0, 0.02);
  text.replace(text.find("cv = 100"), 9, "cv = 100.0\nheat_source = 0.5\n");
  Simulation sim(parse_config(text, "q.toml"), RunOptions{});
  for (int k = 0; k < 300; ++k) sim.step();
  const double n = static_cast<double>(sim.particles().n_local);
  auto energy = [&] {
    const ThermoState t = sim.thermo();
    return (t.kinetic_energy + t.potential_energy + internal_energy(sim, 100.0)) / n;
  };
  const double e0 = energy();
  for (int k = 0; k < 1000; ++k) sim.step();
  const double gained = energy() - e0;
  std::printf("heat source 0.5 per particle for 10 time units: energy gained %.4f per particle\n", gained);
  EXPECT_NEAR(gained, 5.0, 0.6);  // 5.0 from the source, ~0.3 from the drift
}
