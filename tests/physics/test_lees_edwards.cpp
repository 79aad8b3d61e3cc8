// Lees-Edwards shear ([lees_edwards], core/box.hpp ShearImages, engine/install_lees_edwards.cpp):
// the sheared images in the pair loop against the reference loop and an image-by-image search, the
// wrap across the gradient faces, the dissipative viscosity of the ideal DPD gas against Groot and
// Warren's formula, the linear profile and the viscosity of the standard fluid against reverse
// Poiseuille, oscillatory shear, reproducibility across threads and a restart, and bad input.
#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/domain_exchange.hpp"
#include "engine/force_compute.hpp"
#include "engine/pair_laws.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/comm.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"
#include "transport_configs.hpp"

using namespace mesodpd;
namespace fs = std::filesystem;

namespace {

Box sheared_box(int flow, int gradient, double offset, double velocity) {
  Box box{{7.3, 6.1, 8.4}, {true, true, true}};
  box.shear.flow = flow;
  box.shear.gradient = gradient;
  box.shear.offset = offset;
  box.shear.velocity = velocity;
  return box;
}

// The pairs closer than rc found by trying the images of j one by one: image (a, b, c) of j sits at
// r_j + a L e_x + b L e_y + c L e_z + b' offset e_f, with b' the component along the gradient axis.
std::uint64_t pairs_by_image_search(const ParticleData& p, const Box& box, double rc) {
  std::uint64_t count = 0;
  const int f = box.shear.flow, g = box.shear.gradient;
  for (std::size_t i = 0; i < p.n_local; ++i)
    for (std::size_t j = i + 1; j < p.n_local; ++j) {
      double best = 1e300;
      for (int a = -2; a <= 2; ++a)
        for (int b = -2; b <= 2; ++b)
          for (int c = -2; c <= 2; ++c) {
            const int n[3] = {a, b, c};
            double d[3] = {p.x[i] - p.x[j] - a * box.len.x, p.y[i] - p.y[j] - b * box.len.y,
                           p.z[i] - p.z[j] - c * box.len.z};
            d[f] -= n[g] * box.shear.offset;
            best = std::min(best, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          }
      if (best < rc * rc) ++count;
    }
  return count;
}

std::string sheared_fluid(const std::string& lees_edwards, double l, double a = 25.0, double dt = 0.04, int seed = 31,
                          const std::string& extra = "") {
  return fmt::format(R"(
[system]
box = [{1}, {1}, {1}]
kT = 1.0
seed = {4}

[[species]]
name = "A"
density = 3.0

[pair]
a = {2}
gamma = 4.5

[integrator]
dt = {3}

[run]
steps = 1000

[output]
thermo_every = 50
progress = false

[lees_edwards]
{0}
{5}
)",
                     lees_edwards, l, a, dt, seed, extra);
}

// Mean flow velocity in `bins` slabs along the gradient axis, over the mobile particles.
std::vector<double> flow_profile(const ParticleData& p, const Box& box, int bins) {
  const int f = box.shear.flow, g = box.shear.gradient;
  const std::vector<double>& v = f == 0 ? p.vx : (f == 1 ? p.vy : p.vz);
  const std::vector<double>& x = g == 0 ? p.x : (g == 1 ? p.y : p.z);
  std::vector<double> sum(static_cast<std::size_t>(bins)), count(static_cast<std::size_t>(bins));
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const auto b = static_cast<std::size_t>(std::min(bins - 1, static_cast<int>(x[i] / box.length(g) * bins)));
    sum[b] += v[i];
    count[b] += 1;
  }
  for (std::size_t b = 0; b < sum.size(); ++b) sum[b] /= std::max(1.0, count[b]);
  return sum;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mesodpd_test_le_" + name);
  fs::remove_all(dir);
  return dir;
}

// A value of shear_summary.csv.
double summary_value(const fs::path& file, const std::string& name, double* error = nullptr) {
  const std::string text = test::read_file(file);
  const std::size_t at = text.find("\n" + name + ",");
  if (at == std::string::npos) return std::nan("");
  double v = 0, e = 0;
  std::sscanf(text.c_str() + at + name.size() + 2, "%lf,%lf", &v, &e);
  if (error) *error = e;
  return v;
}

}  // namespace

// The shared loop with sheared images equals the reference loop bit for bit (forces, virial, pair count)
// for the three planes, offsets across the whole range, both neighbour methods and 1-2 threads, and the
// reference's pairs are exactly those an image-by-image search finds. The image velocity reaches the
// dissipative force: the same positions with another image velocity give other forces.
TEST(LeesEdwards, PairLoopEqualsTheReferenceLoopAcrossTheShearedFaces) {
  const SimulationSpec spec = test::fluid_spec(7.3, 6.1, 8.4, 3.0);
  const PairLawTables laws = make_pair_laws(spec);
  int compared = 0;
  std::uint64_t seed = 5;
  for (const auto& [f, g] : std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {1, 2}}) {
    for (double frac : {0.0, 0.137, -0.4999, 0.4999}) {
      const Box plain{{7.3, 6.1, 8.4}};
      const double lf = plain.length(f);
      const Box box = sheared_box(f, g, frac * lf, 2.5);
      const ParticleData start = test::random_particles(box, 1100, seed++, 1, 7, 5);
      std::vector<std::array<double, 3>> ref_f;
      PairSums ref;
      reference_forces(start, box, laws, NoiseSettings{99, NoiseKind::Uniform}, 17, 0.04, ref_f, ref);
      const std::uint64_t searched = pairs_by_image_search(start, box, 1.0);
      EXPECT_EQ(ref.pairs_in_range, searched) << "plane " << f << g << " offset " << frac;
      for (double skin : {0.0, 0.3})
        for (int threads : {1, 2}) {
          omp_set_num_threads(threads);
          ParticleData p = start;
          NeighborList list(NeighborSettings{1.0, skin, true});
          list.build(p, box);
          ForceCompute fc(laws, NoiseSettings{99, NoiseKind::Uniform});
          PairSums sums;
          fc.compute(p, box, list, 17, 0.04, true, sums, nullptr, nullptr);
          const std::string what = fmt::format("plane {}{} offset {} skin {} threads {}", f, g, frac, skin, threads);
          // Storage was sorted by the build: compare by id.
          std::vector<std::array<double, 3>> got(start.n_local);
          std::vector<std::size_t> at(2000000, 0);
          for (std::size_t i = 0; i < start.n_local; ++i) at[start.id[i]] = i;
          std::size_t same = 0;
          for (std::size_t i = 0; i < p.n_local; ++i) {
            const std::size_t k = at[p.id[i]];
            same += p.fx[i] == ref_f[k][0] && p.fy[i] == ref_f[k][1] && p.fz[i] == ref_f[k][2];
          }
          EXPECT_EQ(same, p.n_local) << what;
          EXPECT_EQ(sums.pairs_in_range, ref.pairs_in_range) << what;
          for (std::size_t c = 0; c < 6; ++c) EXPECT_EQ(sums.virial[c], ref.virial[c]) << what;
          ++compared;
        }
      // The image velocity enters the relative velocity of the pairs across the gradient faces.
      std::vector<std::array<double, 3>> other_f;
      PairSums other;
      reference_forces(start, sheared_box(f, g, frac * lf, 0.0), laws, NoiseSettings{99, NoiseKind::Uniform}, 17, 0.04,
                       other_f, other);
      EXPECT_NE(other.virial[f == 0 ? (g == 1 ? 3 : 4) : 5], ref.virial[f == 0 ? (g == 1 ? 3 : 4) : 5]);
    }
  }
  omp_set_num_threads(1);
  EXPECT_EQ(compared, 3 * 4 * 2 * 2);
}

// A particle that leaves through the top face of the gradient axis comes back at the bottom, moved by
// -offset along the flow axis with -velocity added to its flow velocity (both the current and the
// half-step velocity); through the bottom face the opposite; a particle that crosses only the flow
// axis is wrapped as usual.
TEST(LeesEdwards, ParticlesCrossingTheGradientFacesAreShiftedAndBoosted) {
  Box box = sheared_box(0, 1, 1.25, 0.8);
  ParticleData p;
  p.resize(3);
  p.n_local = 3;
  p.x = {3.0, 3.0, 7.5};
  p.y = {6.3, -0.2, 3.0};
  p.z = {1.0, 1.0, 1.0};
  p.vx = {0.1, 0.1, 0.1};
  p.hx = {0.2, 0.2, 0.2};
  ASSERT_FALSE(apply_box_boundaries(p, box, Comm::world()).has_value());
  EXPECT_NEAR(p.y[0], 0.2, 1e-12);
  EXPECT_NEAR(p.x[0], 3.0 - 1.25, 1e-12);
  EXPECT_NEAR(p.vx[0], 0.1 - 0.8, 1e-12);
  EXPECT_NEAR(p.hx[0], 0.2 - 0.8, 1e-12);
  EXPECT_EQ(p.iy[0], 1);
  EXPECT_NEAR(p.y[1], 6.1 - 0.2, 1e-12);
  EXPECT_NEAR(p.x[1], 3.0 + 1.25, 1e-12);
  EXPECT_NEAR(p.vx[1], 0.1 + 0.8, 1e-12);
  EXPECT_NEAR(p.x[2], 7.5 - 7.3, 1e-12);
  EXPECT_EQ(p.vx[2], 0.1);
  // The offset follows the time: steady U t wrapped into [-L_f/2, L_f/2], oscillatory gamma_0 L_g sin.
  box.shear.rate = 0.5;
  box.set_time(10.0);  // 0.5 x 6.1 x 10 = 30.5 = 4 x 7.3 + 1.3
  EXPECT_NEAR(box.shear.offset, 1.3, 1e-12);
  EXPECT_NEAR(box.shear.velocity, 0.5 * 6.1, 1e-12);
  box.shear.omega = 2.0;
  box.shear.strain_amplitude = 0.1;
  box.set_time(0.3);
  EXPECT_NEAR(box.shear.offset, 0.1 * 6.1 * std::sin(0.6), 1e-12);
  EXPECT_NEAR(box.shear.velocity, 0.1 * 2.0 * 6.1 * std::cos(0.6), 1e-12);
}

// The ideal DPD gas (a = 0, rho = 3, gamma = 4.5, r_c = 1): with g(r) = 1 the dissipative stress of a
// linear flow is exactly eta_D rate with eta_D = 2 pi gamma rho^2 r_c^5 / 1575 (Groot & Warren, J.
// Chem. Phys. 107, 4423 (1997); seed 000 Table 1 for s = 2), 0.1616. The pair part of the measured
// stress must give it within 3% (about 1.7 of the test's block errors; the rate nonlinearity at rate 1 is
// about +1.5%, docs/validation.md section 11); the run's temperature is the
// one across the flow.
TEST(LeesEdwards, IdealGasHasTheDissipativeViscosityOfGrootWarren) {
  const fs::path dir = fresh_dir("ideal");
  Simulation sim(parse_config(sheared_fluid("shear_rate = 1.0\nstress_every = 4\nequilibrate = 200", 8.0, 0.0, 0.01), "i.toml"),
                 RunOptions{.out_dir = dir, .steps = 40200, .restart = {}});
  const std::string text = sim.run();
  std::printf("%s", text.c_str());
  EXPECT_NE(text.find("(across the flow)"), std::string::npos);
  double err = 0;
  const double eta_d = summary_value(dir / "shear_summary.csv", "eta_pairs", &err);
  const double theory = 2 * std::numbers::pi * 4.5 * 9.0 / 1575.0;
  std::printf("ideal gas: eta_D = %.5f +- %.5f, Groot-Warren %.5f (ratio %.4f)\n", eta_d, err, theory, eta_d / theory);
  EXPECT_NEAR(eta_d / theory, 1.0, 0.03);
  EXPECT_LT(err / theory, 0.02);  // 3% is 1.5 to 2 of the test's errors
}

// The standard fluid (rho = 3, a = 25, gamma = 4.5, dt = 0.04) sheared at rate 0.25 in a 10^3 box: the
// mean flow profile is the imposed straight line (slope within 3%, no slab off it by more than 0.03),
// and eta equals the reverse-Poiseuille viscosity of the same fluid, 0.8593 +- 0.0047
// (docs/validation.md section 4), within 5% (the test's own block error is about 2%).
TEST(LeesEdwards, StandardFluidHasALinearProfileAndTheReversePoiseuilleViscosity) {
  const fs::path dir = fresh_dir("standard");
  Simulation sim(parse_config(sheared_fluid("shear_rate = 0.25\nstress_every = 5\nequilibrate = 250", 10.0), "s.toml"),
                 RunOptions{.out_dir = dir, .steps = 5250, .restart = {}});
  // The profile, averaged over the second half of the run.
  const int bins = 10;
  std::vector<double> mean(bins, 0.0);
  int samples = 0;
  while (sim.current_step() < 5250) {
    sim.step();
    if (sim.current_step() > 2500 && sim.current_step() % 10 == 0) {
      const std::vector<double> v = flow_profile(sim.particles(), sim.box(), bins);
      for (int b = 0; b < bins; ++b) mean[static_cast<std::size_t>(b)] += v[static_cast<std::size_t>(b)];
      ++samples;
    }
  }
  for (double& v : mean) v /= samples;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int b = 0; b < bins; ++b) {
    const double y = (b + 0.5) * 10.0 / bins;
    sx += y, sy += mean[static_cast<std::size_t>(b)], sxx += y * y, sxy += y * mean[static_cast<std::size_t>(b)];
  }
  const double slope = (bins * sxy - sx * sy) / (bins * sxx - sx * sx), icpt = (sy - slope * sx) / bins;
  double worst = 0;
  for (int b = 0; b < bins; ++b)
    worst = std::max(worst, std::abs(mean[static_cast<std::size_t>(b)] - (icpt + slope * (b + 0.5) * 10.0 / bins)));
  std::printf("profile slope %.5f (imposed 0.25), largest deviation %.4f\n", slope, worst);
  EXPECT_NEAR(slope / 0.25, 1.0, 0.03);
  EXPECT_LT(worst, 0.03);
  const std::string text = sim.finish();
  std::printf("%s", text.c_str());
  double err = 0;
  const double eta = summary_value(dir / "shear_summary.csv", "eta", &err);
  std::printf("standard fluid: eta = %.4f +- %.4f against reverse Poiseuille 0.8593 +- 0.0047\n", eta, err);
  EXPECT_NEAR(eta / 0.8593, 1.0, 0.05);
  EXPECT_LT(err, 0.05);
  // The normal stress differences of a simple fluid are second order in the rate (N1 = -0.108 +- 0.006
  // at rate 0.8, docs/validation.md section 11): below 3 errors of this run at 0.25.
  double e1 = 0, e2 = 0;
  const double n1 = summary_value(dir / "shear_summary.csv", "N1", &e1), n2 = summary_value(dir / "shear_summary.csv", "N2", &e2);
  std::printf("N1 = %.4f +- %.4f, N2 = %.4f +- %.4f\n", n1, e1, n2, e2);
  EXPECT_LT(std::abs(n1), 3 * e1);
  EXPECT_LT(std::abs(n2), 3 * e2);
  EXPECT_GT(e1, 0.0);
}

// The ideal gas (a = 0, rho = 3) thermostatted by a [thermostat] sweep (pair.gamma = 0) and sheared by
// [lees_edwards]: the config text.
std::string sheared_ideal_gas(double box, double dt, int seed, const std::string& thermostat, const std::string& le,
                              int steps, int thermo_every) {
  return fmt::format(
      "[system]\nbox = [{0:.1f}, {0:.1f}, {0:.1f}]\nkT = 1.0\nseed = {1}\n\n[[species]]\nname = \"A\"\ndensity = 3.0\n\n"
      "[pair]\na = 0.0\ngamma = 0.0\n\n[integrator]\ndt = {2}\n\n[thermostat]\n{3}\n\n[lees_edwards]\n{4}\n\n"
      "[run]\nsteps = {5}\n\n[output]\nthermo_every = {6}\nprogress = false\n",
      box, seed, dt, thermostat, le, steps, thermo_every);
}

// Lees-Edwards with Lowe-Andersen (the pair sweep takes the whole flow row across the sheared faces and
// the image velocity in the pairs' relative velocity) in the ideal gas (a = 0): the profile stays the
// imposed line, the temperature across the flow stays at kT within 3%, the momentum across the flow is
// conserved, and the stress carried by the sweep's impulses (PairThermostat::last_virial; without it
// the pair stress of this gas would be zero) is the collisional viscosity. A collision at rate Gamma
// acts on average like a dissipative force with gamma w_D = Gamma mu inside r_c, which with affine pair
// velocities gives eta_c = 2 pi Gamma mu rho^2 / 75 = 1.696; measured 0.80 of it here and 0.76 at rate
// 1 (docs/validation.md section 11; we have no derivation of the shortfall). Asserted: the impulses
// carry more than 3 times the kinetic stress, and 0.6-1.1 of eta_c. (Shardlow's sweep gives Groot and
// Warren's eta_D the same way: 0.988 +- 0.030, so the virial itself is right.)
TEST(LeesEdwards, LoweAndersenThermostatKeepsTheShearedFluidAtKT) {
  const fs::path dir = fresh_dir("lowe_andersen");
  const std::string text = sheared_ideal_gas(8.0, 0.04, 77, "type = \"lowe-andersen\"\nrate = 4.5",
                                             "shear_rate = 0.25\nstress_every = 5\nequilibrate = 250", 3250, 50);
  Simulation sim(parse_config(text, "la.toml"), RunOptions{.out_dir = dir, .steps = {}, .restart = {}});
  auto momentum = [&] {
    std::array<double, 3> m{0, 0, 0};
    const ParticleData& p = sim.particles();
    for (std::size_t i = 0; i < p.n_local; ++i) m[0] += p.vx[i], m[1] += p.vy[i], m[2] += p.vz[i];
    return m;
  };
  const auto m0 = momentum();
  std::vector<double> mean(8, 0.0);
  int samples = 0;
  while (sim.current_step() < 3250) {
    sim.step();
    if (sim.current_step() > 1000 && sim.current_step() % 10 == 0) {
      const std::vector<double> v = flow_profile(sim.particles(), sim.box(), 8);
      for (int b = 0; b < 8; ++b) mean[static_cast<std::size_t>(b)] += v[static_cast<std::size_t>(b)];
      ++samples;
    }
  }
  const auto m1 = momentum();
  const std::string summary = sim.finish();
  std::printf("%s", summary.c_str());
  for (double& v : mean) v /= samples;
  // The slope of the mean profile from its two halves (bins 1-3 against 4-6).
  const double slope = ((mean[4] + mean[5] + mean[6]) - (mean[1] + mean[2] + mean[3])) / 3.0 / 3.0;
  std::printf("Lowe-Andersen under shear: profile slope %.4f (imposed 0.25), momentum change %.3g %.3g %.3g\n", slope,
              m1[0] - m0[0], m1[1] - m0[1], m1[2] - m0[2]);
  EXPECT_NEAR(slope / 0.25, 1.0, 0.05);
  // The images exchange flow momentum with the box (each crossing of the gradient faces adds +-dU); the
  // other two components are conserved.
  for (int d = 1; d < 3; ++d) EXPECT_LT(std::abs(m1[static_cast<std::size_t>(d)] - m0[static_cast<std::size_t>(d)]), 1e-8);
  const std::size_t at = summary.find("mean temperature ");
  ASSERT_NE(at, std::string::npos);
  const double kt = std::stod(summary.substr(at + 17));
  EXPECT_NEAR(kt, 1.0, 0.03);
  EXPECT_NE(summary.find("(across the flow)"), std::string::npos);
  double err = 0;
  const double eta = summary_value(dir / "shear_summary.csv", "eta_pairs", &err);
  const double theory = 2 * std::numbers::pi * 4.5 * 0.5 * 9.0 / 75.0;
  std::printf("eta (pairs: the sweep's impulses) = %.4f +- %.4f, collisional theory %.4f (ratio %.4f)\n", eta, err, theory,
              eta / theory);
  EXPECT_GT(eta / theory, 0.6);
  EXPECT_LT(eta / theory, 1.1);
  EXPECT_GT(eta, 3 * summary_value(dir / "shear_summary.csv", "eta_kinetic"));
}

// Peters' thermostat under shear: in the ideal gas (a = 0) its pair update is the DPD friction and noise
// of gamma = 4.5, w_D = (1 - r)^2, so the stress its impulses carry (PairThermostat::last_virial, added to
// the pair sums) is Groot and Warren's dissipative viscosity eta_D = 2 pi gamma rho^2 / 1575 = 0.1616,
// as the Groot-Warren ideal gas above gives. 6^3 box, rate 0.8, dt 0.02, 300 time units: measured
// 0.979 +- 0.035 of it (an 8^3 box at rate 0.6 gave 1.049 +- 0.029); asserted within 8% with a block
// error under 5%, and the temperature across the flow within 2% of kT. Without the sweep's virial in
// the pair sums eta_pairs would be about 0.
TEST(LeesEdwards, PetersThermostatGivesTheDissipativeViscosityOfTheIdealGas) {
  const fs::path dir = fresh_dir("peters");
  const std::string text = sheared_ideal_gas(6.0, 0.02, 78, "type = \"peters\"\ngamma = 4.5",
                                             "shear_rate = 0.8\nstress_every = 4\nequilibrate = 200", 15200, 100);
  Simulation sim(parse_config(text, "p.toml"), RunOptions{.out_dir = dir, .steps = {}, .restart = {}});
  const std::string summary = sim.run();
  std::printf("%s", summary.c_str());
  const std::size_t at = summary.find("mean temperature ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_NEAR(std::stod(summary.substr(at + 17)), 1.0, 0.02);
  double err = 0;
  const double eta = summary_value(dir / "shear_summary.csv", "eta_pairs", &err);
  const double theory = 2 * std::numbers::pi * 4.5 * 9.0 / 1575.0;
  std::printf("Peters under shear: eta_pairs = %.5f +- %.5f, Groot-Warren eta_D %.5f (ratio %.4f)\n", eta, err, theory,
              eta / theory);
  EXPECT_NEAR(eta / theory, 1.0, 0.08);
  EXPECT_LT(err / theory, 0.05);
}

// Oscillatory shear of the ideal gas (with the homogeneous-shear force, so the whole box follows the
// strain) at a low frequency, omega = 2 pi / 20 (omega tau = 0.13 for the kinetic relaxation time
// tau = 0.42): its dissipative stress follows the strain rate, so the pair stress has the loss modulus
// eta_D omega (within 6%, 2.5 of this run's errors) and no storage modulus (within 3 errors). The long
// runs of docs/validation.md section 11 give 1.003 +- 0.012 of eta_D omega here and show the pair
// stress lagging at omega = 1.26 (G'' 3-7% low, G' > 0): not asserted.
TEST(LeesEdwards, OscillatoryShearOfTheIdealGasIsViscousInItsPairStress) {
  const fs::path dir = fresh_dir("oscillatory");
  const double omega = 2 * std::numbers::pi / 20.0;  // period 20 time units; 6 periods
  Simulation sim(parse_config(sheared_fluid(fmt::format("strain_amplitude = 3.6\nomega = {:.17g}\nstress_every = 2", omega),
                                            8.0, 0.0, 0.01),
                              "o.toml"),
                 RunOptions{.out_dir = dir, .steps = 12000, .restart = {}});
  std::printf("%s", sim.run().c_str());
  double e1 = 0, e2 = 0;
  const fs::path csv = dir / "shear_summary.csv";
  const double g_loss = summary_value(csv, "G_loss_pairs", &e2), g_storage = summary_value(csv, "G_storage_pairs", &e1);
  const double theory = 2 * std::numbers::pi * 4.5 * 9.0 / 1575.0 * omega;
  std::printf("ideal gas, omega %.4f: pairs G'' = %.5f +- %.5f (eta_D omega = %.5f), G' = %.5f +- %.5f; kinetic G' = %.4f, "
              "G'' = %.4f\n",
              omega, g_loss, e2, theory, g_storage, e1, summary_value(csv, "G_storage_kinetic"),
              summary_value(csv, "G_loss_kinetic"));
  EXPECT_NEAR(g_loss / theory, 1.0, 0.06);
  EXPECT_LT(std::abs(g_storage), 3 * e1);
  EXPECT_LT(e2 / theory, 0.03);
}

// Reproducibility: the sheared run (Verlet list, so the skin's offset drift is exercised, and cell
// pairs) gives the same bits on 1 and 2 threads, and 100 + 100 steps through a checkpoint equal 200
// steps straight (the offset is a function of the step). A Verlet list that missed a pair would change
// the trajectory: the Verlet run equals the cell-pair run bit for bit (both evaluate exactly the pairs
// within the cutoff, and the fixed-point sums do not depend on their order).
TEST(LeesEdwards, RunsAreBitIdenticalOnOneAndTwoThreadsAndAcrossARestart) {
  const fs::path dir = fresh_dir("restart");
  fs::create_directories(dir);
  std::map<std::string, std::map<std::uint32_t, std::array<double, 6>>> by_method;
  for (const char* neighbor : {"cells", "verlet"}) {
    const std::string text =
        sheared_fluid("shear_rate = 0.3", 8.0, 25.0, 0.04, 7, fmt::format("[neighbor]\nmethod = \"{}\"\n", neighbor));
    auto state = [&](int threads, int steps, const fs::path& restart, const fs::path& save) {
      omp_set_num_threads(threads);
      RunOptions o;
      o.restart = restart;
      Simulation sim(parse_config(text, "r.toml"), o);
      for (int k = 0; k < steps; ++k) sim.step();
      if (!save.empty()) sim.write_checkpoint(save);
      omp_set_num_threads(1);
      return test::state_by_id(sim.particles());
    };
    const auto one = state(1, 200, {}, {});
    EXPECT_TRUE(one == state(2, 200, {}, {})) << neighbor;
    state(1, 100, {}, dir / "half.mdpd");
    EXPECT_TRUE(one == state(2, 100, dir / "half.mdpd", {})) << neighbor;
    // The shear did something: the flow profile is there.
    double sum = 0;
    for (const auto& [id, s] : one) sum += s[3] * (s[1] - 4.0);
    EXPECT_GT(sum / static_cast<double>(one.size()), 0.3 * 16.0 / 3.0 * 0.5) << neighbor;
    by_method[neighbor] = one;
  }
  EXPECT_TRUE(by_method["cells"] == by_method["verlet"]);
}

// Bad input: each a ConfigError naming the key.
TEST(LeesEdwards, BadInputIsRefusedNamingTheKey) {
  auto error = [](const std::string& le, const std::string& extra = "", double l = 8.0) {
    return test::config_error_of(sheared_fluid(le, l, 25.0, 0.04, 31, extra));
  };
  EXPECT_NE(error("shear_rate = 5.0").find("lees_edwards.shear_rate"), std::string::npos);  // images too fast
  EXPECT_NE(error("flow = \"y\"\ngradient = \"x\"\nshear_rate = 0.1").find("lees_edwards.flow"), std::string::npos);
  EXPECT_NE(error("flow = \"x\"\ngradient = \"x\"\nshear_rate = 0.1").find("lees_edwards.gradient"), std::string::npos);
  EXPECT_NE(error("shear_rate = 0.0").find("lees_edwards.shear_rate"), std::string::npos);
  EXPECT_NE(error("omega = 1.0").find("lees_edwards.strain_amplitude"), std::string::npos);
  EXPECT_NE(error("").find("lees_edwards.shear_rate"), std::string::npos);
  EXPECT_NE(error("shear_rate = 0.1\nomega = 1.0\nstrain_amplitude = 0.5").find("lees_edwards.shear_rate"),
            std::string::npos);
  EXPECT_NE(error("shear_rate = 0.1", "", 3.5).find("system.box"), std::string::npos);  // 3 cells along x
  EXPECT_NE(error("shear_rate = 0.1", "[poiseuille]\nforce = 0.02\n").find("poiseuille"), std::string::npos);
  EXPECT_NE(error("shear_rate = 0.1", "[bonds]\nsubcycles = 2\n").find("bonds.subcycles"), std::string::npos);
  // The equilibrium analyses would measure the imposed flow.
  EXPECT_NE(error("shear_rate = 0.1", "[analysis.msd]\nevery = 10\n").find("analysis.msd"), std::string::npos);
  EXPECT_NE(error("shear_rate = 0.1", "[analysis.transport]\n").find("analysis.transport"), std::string::npos);
  // Walls close the gradient axis z of a plate channel.
  const std::string channel =
      test::plate_channel_config("", "", "", "\n[lees_edwards]\ngradient = \"z\"\nshear_rate = 0.1\n");
  EXPECT_NE(test::config_error_of(channel).find("system.periodic"), std::string::npos);
  EXPECT_EQ(error("shear_rate = 0.1"), "no error");
}

// A polymer melt (10-bead harmonic chains, examples/shear/melt.toml) thins under shear and has a first
// normal stress difference: eta at rate 0.4 (Weissenberg number above 1) lies more than 2 combined
// errors below eta at rate 0.1, N1 > 0 by more than 10 errors at rate 0.4, and N2 is small beside N1
// (|N2| < N1 / 10). The long runs are in docs/validation.md section 11.
TEST(LeesEdwards, PolymerMeltShearThinsWithAPositiveFirstNormalStressDifference) {
  const std::string melt = test::read_file(fs::path(MESODPD_SOURCE_DIR) / "examples/shear/melt.toml");
  ASSERT_FALSE(melt.empty());
  struct Point {
    double eta, eta_err, n1, n1_err, n2;
  };
  auto run = [&](double rate, double dt, std::uint64_t steps, const char* name) {
    std::string text = melt;
    auto set = [&](const std::string& key, const std::string& value) {
      const std::size_t at = text.find("\n" + key + " = ");
      ASSERT_NE(at, std::string::npos) << key;
      const std::size_t end = text.find('\n', at + 1);
      text.replace(at + 1, end - at - 1, key + " = " + value);
    };
    set("shear_rate", fmt::format("{}", rate));
    set("dt", fmt::format("{}", dt));
    set("equilibrate", fmt::format("{}", static_cast<int>(20 / dt)));
    const fs::path dir = fresh_dir(name);
    Simulation sim(parse_config(text, "melt.toml"), RunOptions{.out_dir = dir, .steps = steps, .restart = {}});
    std::printf("%s", sim.run().c_str());
    Point p{};
    const fs::path csv = dir / "shear_summary.csv";
    p.eta = summary_value(csv, "eta", &p.eta_err);
    p.n1 = summary_value(csv, "N1", &p.n1_err);
    p.n2 = summary_value(csv, "N2");
    return p;
  };
  const Point slow = run(0.1, 0.04, 5500, "melt_slow"), fast = run(0.4, 0.025, 8800, "melt_fast");
  std::printf("melt: eta(0.1) = %.3f +- %.3f, eta(0.4) = %.3f +- %.3f; N1(0.4) = %.3f +- %.3f, N2(0.4) = %.3f\n", slow.eta,
              slow.eta_err, fast.eta, fast.eta_err, fast.n1, fast.n1_err, fast.n2);
  EXPECT_LT(fast.eta, slow.eta - 2 * std::hypot(slow.eta_err, fast.eta_err));
  EXPECT_GT(fast.n1, 10 * fast.n1_err);
  EXPECT_LT(std::abs(fast.n2), fast.n1 / 10);
}
