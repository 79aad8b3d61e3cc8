// [analysis.stress_profile] (analysis/stress_profile.hpp): a term's virial shared between slabs by the
// straight contour and by halves (known fractions, across the periodic boundary); with amphiphiles
// (pair forces, bonds, angles, with and without exclusions) and no thermostat, the slabs add up to the
// pressure tensor of thermo.csv and the tension integral to L (P_N - P_T); the kinetic part is the
// kinetic energy; bit-identical files on 1 and 2 threads and across a restart; bad keys named.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/observers.hpp"
#include "analysis/stress_profile.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

// H2T3 amphiphiles (harmonic bonds, cosine angles) in water, box 5 x 5 x 8 at density 3.
std::string amphiphile_config(double gamma, const std::string& exclude, const std::string& tail) {
  return fmt::format(R"(
[system]
box = [5.0, 5.0, 8.0]
seed = 7

[[species]]
name = "W"
count = 450

[[species]]
name = "H"

[[species]]
name = "T"

[pair]
a = 25.0
gamma = {0}

[[pair.override]]
species = ["H", "T"]
a = 50.0

[[pair.override]]
species = ["T", "W"]
a = 75.0

[[bond_type]]
name = "spring"
style = "harmonic"
k = 64.0
r0 = 0.5

[[angle_type]]
name = "stiff"
k = 10.0
theta0 = 0.0

[[molecule]]
name = "amphiphile"
sequence = "H2T3"
bond_type = "spring"
angle_type = "stiff"
count = 30
bond_length = 0.5

[bonds]
exclude = "{1}"

[integrator]
dt = 0.02

[output]
progress = false
thermo_every = 10
{2}
)",
                     gamma, exclude, tail);
}

// Two particles and one virial term d (x) f with d = r_0 - r_1 (minimum image along z in an l_z box).
ParticleData two_particles(double z0, double z1) {
  ParticleData p;
  p.resize(2);
  p.n_local = 2;
  p.x = {0.5, 0.5};
  p.y = {0.5, 0.5};
  p.z = {z0, z1};
  p.vx = {0, 0};
  p.vy = {0, 0};
  p.vz = {0, 0};
  p.species = {0, 0};
  p.id = {1, 2};
  return p;
}

}  // namespace

TEST(StressProfile, ContourAndHalfShareATermBetweenSlabsByKnownFractions) {
  const Box box{{1.0, 1.0, 4.0}};
  StressProfileSpec spec;
  spec.enabled = true;
  spec.bins = 4;
  spec.blocks = 2;
  const std::vector<double> mass{1.0};
  // Each case: z of particles 0 and 1, and the expected share of d_z f_z per slab.
  struct Case {
    double z0, z1;
    std::vector<double> contour, half;
  };
  // d_z = -2 (0.5 - 2.5): the line covers half of slab 0, slab 1, half of slab 2. Across the periodic
  // boundary: 0.2 - 3.8 -> +0.4, the line from 3.8 to 4.2 half in slab 3, half in slab 0.
  for (const Case& c : {Case{0.5, 2.5, {0.25, 0.5, 0.25, 0.0}, {0.5, 0.0, 0.5, 0.0}},
                        Case{0.2, 3.8, {0.5, 0.0, 0.0, 0.5}, {0.5, 0.0, 0.0, 0.5}},
                        Case{1.25, 1.75, {0.0, 1.0, 0.0, 0.0}, {0.0, 1.0, 0.0, 0.0}}}) {
    const ParticleData p = two_particles(c.z0, c.z1);
    VirialTerm t;
    t.i = 0;
    t.j = 1;
    t.d[2] = minimum_image(c.z0 - c.z1, 4.0, 2.0);
    t.f[2] = 3.0;
    t.d[0] = 0.1;  // a lateral component, shared in the same way
    t.f[0] = 2.0;
    for (const StressAssignment how : {StressAssignment::Contour, StressAssignment::Half}) {
      spec.assignment = how;
      StressProfile s(spec, box);
      s.sample(p, mass, {}, {t});
      const std::vector<double>& want = how == StressAssignment::Contour ? c.contour : c.half;
      for (std::size_t b = 0; b < 4; ++b) {
        // Bin volume 1: the configurational pressure is the share itself.
        EXPECT_NEAR(s.configurational(b, 2), want[b] * t.d[2] * 3.0, 1e-14) << "z " << c.z0 << " slab " << b;
        EXPECT_NEAR(s.configurational(b, 0), want[b] * 0.2, 1e-14);
        EXPECT_EQ(s.configurational(b, 1), 0.0);
      }
      // Tension: h sum_b (p_N - p_T) = L (P_N - P_T) of the box (volume 4).
      EXPECT_NEAR(s.tension().mean, t.d[2] * 3.0 - 0.5 * 0.2, 1e-14);
    }
  }
}

TEST(StressProfile, SlabsAddUpToThermosPressureTensorWithBondsAnglesAndExclusions) {
  // Without the dissipative and random forces (gamma = 0), thermo.csv's tensor is kinetic plus the
  // conservative, bond and angle virials: the profile's slabs must add up to it at every sampled step,
  // so the means agree to the fixed-point rounding of the force loop's sums.
  for (const std::string exclude : {"none", "1-3"})
    for (const std::string assignment : {"contour", "half"}) {
      const std::string tail = "[run]\nsteps = 100\n[analysis.stress_profile]\nbins = 16\nevery = 10\nblocks = 2\n"
                               "assignment = \"" + assignment + "\"\n";
      RunOptions o;
      o.record = true;
      Simulation sim(parse_config(amphiphile_config(0.0, exclude, tail), "amph.toml"), o);
      sim.run();
      const StressProfile* s = sim.observers().stress_profile();
      ASSERT_NE(s, nullptr);
      double p[3] = {0, 0, 0}, kin = 0, tension = 0;
      std::size_t rows = 0;
      for (const ThermoState& t : sim.observers().history()) {
        if (t.step % 10 != 0) continue;
        for (int c = 0; c < 3; ++c) p[c] += t.p_tensor[static_cast<std::size_t>(c)];
        kin += 2.0 * t.kinetic_energy;
        tension += 8.0 * (t.p_tensor[2] - 0.5 * (t.p_tensor[0] + t.p_tensor[1]));
        ++rows;
      }
      ASSERT_EQ(rows, s->samples()) << "thermo rows and profile samples at the same steps";
      ASSERT_GE(rows, 10u);
      const double n = static_cast<double>(rows), volume = 200.0;
      const auto k = s->box_kinetic(), c = s->box_configurational();
      // Up to 2^-24 lost per pair and component by the force loop's fixed point: a few 1e-6 here.
      const double tol = 5e-6;
      for (int q = 0; q < 3; ++q) {
        const auto u = static_cast<std::size_t>(q);
        EXPECT_NEAR(k[u] + c[u], p[q] / n, tol) << exclude << ' ' << assignment << " component " << q;
      }
      EXPECT_NEAR(k[0] + k[1] + k[2], kin / n / volume, 1e-10) << "kinetic part";
      EXPECT_NEAR(s->tension().mean, tension / n, 8.0 * tol) << exclude << ' ' << assignment;
      // The bonded terms matter at this precision (the test can fail): bonds alone shift P by ~0.1.
      EXPECT_GT(std::abs(c[2]), 1.0);
      double integral = 0;
      for (std::size_t b = 0; b < s->bins(); ++b) integral += (s->normal(b) - s->tangential(b)) * 0.5;
      EXPECT_NEAR(integral, s->tension().mean, 1e-9);
    }
}

TEST(StressProfile, BitIdenticalAcrossThreadsAndARestart) {
  const std::string tail =
      "checkpoint_every = 100\n[run]\nsteps = 200\n"
      "[analysis.stress_profile]\nbins = 20\nevery = 10\nstart = 20\nblocks = 4\n";
  auto run = [&](const std::string& name, int threads, std::uint64_t steps, bool restart) {
    const auto dir = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir);
    omp_set_num_threads(threads);
    const std::string text = amphiphile_config(4.5, "none", tail);
    RunOptions o;
    o.out_dir = dir;
    o.steps = steps;
    Simulation(parse_config(text, "amph.toml"), o).run();
    if (restart) {
      o.steps = 200;
      o.restart = dir / "checkpoint.mdpd";
      Simulation(parse_config(text, "amph.toml"), o).run();
    }
    return test::read_file(dir / "stress_profile.json") + test::read_file(dir / "stress_profile.csv");
  };
  const std::string one = run("mesodpd_stress_one", 1, 200, false);
  EXPECT_GT(one.size(), 1000u);
  EXPECT_EQ(run("mesodpd_stress_two", 2, 200, false), one) << "1 and 2 threads differ";
  EXPECT_EQ(run("mesodpd_stress_restart", 2, 100, true), one) << "the restarted run differs";
  omp_set_num_threads(1);
  for (const char* d : {"mesodpd_stress_one", "mesodpd_stress_two", "mesodpd_stress_restart"})
    std::filesystem::remove_all(std::filesystem::temp_directory_path() / d);
}

TEST(StressProfile, BadKeysAreNamed) {
  auto error = [](const std::string& section) {
    try {
      parse_config(amphiphile_config(4.5, "none", "[run]\nsteps = 10\n" + section), "bad.toml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("[analysis.stress_profile]\nbins = 0\n").find("analysis.stress_profile.bins"), std::string::npos);
  EXPECT_NE(error("[analysis.stress_profile]\naxis = \"w\"\n").find("analysis.stress_profile.axis"), std::string::npos);
  EXPECT_NE(error("[analysis.stress_profile]\nevery = 0\n").find("analysis.stress_profile.every"), std::string::npos);
  EXPECT_NE(error("[analysis.stress_profile]\nblocks = 1\n").find("analysis.stress_profile.blocks"), std::string::npos);
  EXPECT_NE(error("[analysis.stress_profile]\nassignment = \"ik\"\n").find("analysis.stress_profile.assignment"),
            std::string::npos);
  EXPECT_NE(error("[analysis.stress_profile]\nbinz = 4\n").find("binz"), std::string::npos);
}
