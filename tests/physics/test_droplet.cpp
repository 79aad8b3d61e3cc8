// [analysis.droplet] (analysis/droplet.hpp): the per-particle virial adds up to the pair loop's virial,
// the centre and equimolar radius of a drop built with known values, the local pressure of a
// homogeneous fluid equals its virial pressure (standard and many-body DPD), bit-identical results
// across threads and a restart, and a short Laplace check on Warren's liquid (examples/mdpd_droplet has
// the long runs).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <array>
#include <random>
#include <string>
#include <vector>

#include "analysis/droplet.hpp"
#include "analysis/observers.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

// Warren's liquid (A = -40, B = 25, r_d = 0.75, Warren's kernel) at density rho in an l^3 box.
SimulationSpec warren_spec(double l, double rho) {
  SimulationSpec spec = test::fluid_spec(l, l, l, rho, -40.0, 4.5, 0.01);
  spec.pair_style = PairStyle::Mdpd;
  spec.pair_section.kernel = DensityKernelChoice::Warren;
  spec.pairs[0].own["b"] = 25.0;
  spec.pairs[0].rd = 0.75;
  return spec;
}

// A run directory with a drop of Warren's liquid: the `n` sites of a simple cubic lattice of density 6
// nearest the centre of an l^3 box (a ball, as examples/mdpd_droplet/run.py builds it), and the config
// `toml_tail` after the common sections.
std::filesystem::path drop_case(const std::string& name, double l, int n, const std::string& toml_tail) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const double a = std::cbrt(1.0 / 6.0);
  const int m = static_cast<int>(std::ceil(std::cbrt(3.0 * n / (4.0 * std::numbers::pi * 6.0)) / a)) + 2;
  std::vector<std::array<double, 4>> sites;  // r^2, x, y, z
  for (int i = -m; i <= m; ++i)
    for (int j = -m; j <= m; ++j)
      for (int k = -m; k <= m; ++k) {
        const double x = (i + 0.5) * a, y = (j + 0.5) * a, z = (k + 0.5) * a;
        sites.push_back({x * x + y * y + z * z, x, y, z});
      }
  std::stable_sort(sites.begin(), sites.end(), [](const auto& u, const auto& v) { return u[0] < v[0]; });
  std::ofstream f(dir / "drop.data");
  f << "drop\n\n" << n << " atoms\n1 atom types\n\n0 " << l << " xlo xhi\n0 " << l << " ylo yhi\n0 " << l
    << " zlo zhi\n\nAtoms\n\n";
  for (int k = 0; k < n; ++k)
    f << k + 1 << " 1 " << 0.5 * l + sites[static_cast<std::size_t>(k)][1] << ' ' << 0.5 * l + sites[static_cast<std::size_t>(k)][2]
      << ' ' << 0.5 * l + sites[static_cast<std::size_t>(k)][3] << '\n';
  std::ofstream(dir / "drop.toml")
      << "[system]\nbox = [" << l << ", " << l << ", " << l << "]\nseed = 11\n[[species]]\nname = \"L\"\n"
      << "[init]\nlammps_data = \"drop.data\"\nvelocities = \"maxwell\"\n"
      << "[pair]\nstyle = \"mdpd\"\nkernel = \"warren\"\na = -40.0\nb = 25.0\nrd = 0.75\ngamma = 4.5\n"
      << "[integrator]\ndt = 0.01\n" << toml_tail;
  return dir;
}

double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\": ");
  EXPECT_NE(at, std::string::npos) << key << " in " << json;
  return std::stod(json.substr(at + key.size() + 4));
}

}  // namespace

TEST(Droplet, PerParticleVirialAddsUpToThePairLoopsVirial) {
  // Half of each pair's r . F^C to each particle: the per-particle values must sum to the conservative
  // virial of the reference pair loop, for a law with a density pass (many-body) and one without.
  for (const bool many_body : {true, false}) {
    const SimulationSpec spec = many_body ? warren_spec(4.0, 6.0) : test::fluid_spec(4.0, 4.0, 4.0, 3.0);
    const Box box{{4.0, 4.0, 4.0}};
    const ParticleData p = test::random_particles(box, 300, 5);
    const PairLawTables laws = make_pair_laws(spec);
    std::vector<double> rho;
    if (many_body) reference_density(p, box, *make_density_settings(spec), rho);
    std::vector<std::array<double, 3>> f;
    PairSums sums;
    reference_forces(p, box, laws, NoiseSettings{}, 1, 0.01, f, sums, many_body ? rho.data() : nullptr);
    std::vector<double> w;
    reference_conservative_virial(p, box, laws, w, many_body ? rho.data() : nullptr);
    double total = 0;
    for (double v : w) total += v;
    EXPECT_GT(std::abs(sums.virial_conservative), 100.0);
    // The pair loop sums in fixed point (2^-24 per pair and component at most lost to truncation).
    EXPECT_NEAR(total, sums.virial_conservative, static_cast<double>(sums.pairs_in_range) * 0x1p-24)
        << "many-body " << many_body;
  }
}

TEST(Droplet, CentreRadiusAndPressureOfADropBuiltWithKnownValues) {
  // 1,608 particles uniform in a sphere of radius 4 (density 6) centred across two periodic faces of a
  // 12^3 box, a vapour of density 0.05 outside, every particle with m v^2 = 3 and a virial share of 2:
  // the pressures are then (3 + 2) / 3 times the region's number density, exactly.
  const Box box{{12.0, 12.0, 12.0}};
  const std::array<double, 3> c0{0.7, 11.2, 6.0};
  const double r0 = 4.0;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::array<double, 3>> pos;
  const auto n_drop = static_cast<std::size_t>(std::llround(6.0 * 4.0 / 3.0 * std::numbers::pi * r0 * r0 * r0));
  while (pos.size() < n_drop) {
    const std::array<double, 3> d{(2 * u(rng) - 1) * r0, (2 * u(rng) - 1) * r0, (2 * u(rng) - 1) * r0};
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < r0 * r0) pos.push_back({c0[0] + d[0], c0[1] + d[1], c0[2] + d[2]});
  }
  const double v_vap = box.volume() - 4.0 / 3.0 * std::numbers::pi * r0 * r0 * r0;
  for (std::size_t placed = 0; placed < static_cast<std::size_t>(0.05 * v_vap);) {
    const std::array<double, 3> x{12 * u(rng), 12 * u(rng), 12 * u(rng)};
    double r2 = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double d = minimum_image(x[k] - c0[k], 12.0, 6.0);
      r2 += d * d;
    }
    if (r2 < r0 * r0) continue;
    pos.push_back(x);
    ++placed;
  }
  ParticleData p;
  p.resize(pos.size());
  p.n_local = pos.size();
  for (std::size_t i = 0; i < pos.size(); ++i) {
    p.id[i] = static_cast<std::uint32_t>(i + 1);
    p.x[i] = pos[i][0] - 12.0 * std::floor(pos[i][0] / 12.0);
    p.y[i] = pos[i][1] - 12.0 * std::floor(pos[i][1] / 12.0);
    p.z[i] = pos[i][2] - 12.0 * std::floor(pos[i][2] / 12.0);
    p.vx[i] = p.vy[i] = p.vz[i] = 1.0;
  }
  const std::vector<double> mass{1.0};
  const auto c = droplet_centre(p, mass, box, 5.5);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_LT(std::abs(minimum_image(c[k] - c0[k], 12.0, 6.0)), 0.1) << "axis " << k;

  DropletSpec spec;
  spec.enabled = true;
  spec.inner_radius = 3.0;
  spec.outer_radius = 5.5;
  DropletAnalysis drop(spec, box, 1.75);
  std::size_t largest_subset = 0;
  const LocalVirial virial = [&](const ParticleData& subset, const Box&, std::vector<double>& w) {
    largest_subset = std::max(largest_subset, subset.n_local);
    w.assign(subset.n_local, 2.0);
  };
  drop.sample(p, mass, box, virial);
  const DropletResult d = drop.result();
  EXPECT_NEAR(d.rho_in.mean, 6.0, 0.6);  // ~680 particles: 4 % noise
  EXPECT_NEAR(d.rho_out.mean, 0.05, 0.01);
  EXPECT_NEAR(d.p_in.mean, 5.0 / 3.0 * d.rho_in.mean, 1e-12);
  EXPECT_NEAR(d.p_out.mean, 5.0 / 3.0 * d.rho_out.mean, 1e-12);
  EXPECT_NEAR(d.radius.mean, r0, 0.15);
  EXPECT_NEAR(d.half_density_radius, r0, 0.2);
  // The subsets: the core plus the interaction range (r < 4.75: ~2,700 drop particles), not the box.
  EXPECT_LT(largest_subset, 2800u);
  // The radial profile integrates to the particles within half the box.
  const std::vector<double> rho = drop.profile_density(), r = drop.profile_r();
  double n_profile = 0;
  for (std::size_t b = 0; b < rho.size(); ++b) n_profile += rho[b] * 4.0 * std::numbers::pi * r[b] * r[b] * 0.1;
  EXPECT_NEAR(n_profile, static_cast<double>(n_drop) + 0.05 * (4.0 / 3.0 * std::numbers::pi * 216.0 - 4.0 / 3.0 * std::numbers::pi * 64.0), 40.0);
}

namespace {
// The droplet's local pressures in a homogeneous fluid, around the box centre (a centre found from the
// particles would sit on a density excess and bias rho_in up), against the conservative virial pressure
// of the whole box (the same Eq. 24; thermo()), sampled at the same steps.
void expect_local_pressure_is_the_virial_pressure(const SimulationSpec& spec, double inner, double outer,
                                                  std::uint64_t steps) {
  Simulation sim(spec, RunOptions{});
  const Box box{{spec.box[0], spec.box[1], spec.box[2]}};
  DropletSpec ds;
  ds.enabled = true;
  ds.inner_radius = inner;
  ds.outer_radius = outer;
  ds.blocks = 8;
  const auto density = make_density_settings(spec);
  const PairLawTables laws = make_pair_laws(spec);
  DropletAnalysis drop(ds, box, max_cutoff(laws) + (density ? density->table.max_cutoff : 0.0));
  const LocalVirial virial = make_local_virial(laws, density);
  const std::vector<double> mass{1.0};
  std::vector<double> p;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    sim.step();
    if (k < 200 || k % 10 != 0) continue;
    p.push_back(sim.thermo().pressure_conservative);
    drop.sample_at({0.5 * box.len.x, 0.5 * box.len.y, 0.5 * box.len.z}, sim.particles(), mass, box, virial);
  }
  const BlockMean global = block_mean(p, 8);
  const DropletResult d = drop.result();
  const double rho = static_cast<double>(sim.particles().n_local) / box.volume();
  std::printf("homogeneous rho = %.2f: P (thermo) = %.4f +- %.4f, P_in = %.4f +- %.4f, P_out = %.4f +- %.4f, "
              "rho_in = %.4f, rho_out = %.4f\n",
              rho, global.mean, global.err, d.p_in.mean, d.p_in.err, d.p_out.mean, d.p_out.err, d.rho_in.mean,
              d.rho_out.mean);
  EXPECT_NEAR(d.p_in.mean, global.mean, 4 * std::hypot(d.p_in.err, global.err));
  EXPECT_NEAR(d.p_out.mean, global.mean, 4 * std::hypot(d.p_out.err, global.err));
  // The test resolves a tenth of the virial part (a factor 2 or a lost density term is far outside).
  EXPECT_LT(4 * std::hypot(d.p_in.err, global.err), 0.1 * std::abs(global.mean - rho * spec.kT));
  EXPECT_NEAR(d.rho_in.mean, rho, 0.05 * rho);
}
}  // namespace

TEST(Droplet, LocalPressureOfAHomogeneousStandardFluidIsItsVirialPressure) {
  expect_local_pressure_is_the_virial_pressure(test::fluid_spec(8.0, 8.0, 8.0, 3.0, 25.0, 4.5, 0.04), 2.5, 3.0, 1000);
}

TEST(Droplet, LocalPressureOfAHomogeneousManyBodyFluidIsItsVirialPressure) {
  // Warren's liquid at density 7, above its coexistence density: a compressed homogeneous liquid whose
  // pressure comes mostly from the density-dependent repulsion, so the subset's density pass matters.
  expect_local_pressure_is_the_virial_pressure(warren_spec(6.0, 7.0), 2.0, 2.5, 1000);
}

TEST(Droplet, BitIdenticalAcrossThreadsAndARestart) {
  const std::string tail =
      "[run]\nsteps = 200\n[output]\nprogress = false\nthermo_every = 20\ncheckpoint_every = 100\n"
      "[analysis.droplet]\nstart = 20\nevery = 20\ninner_radius = 1.5\nouter_radius = 4.5\nblocks = 4\n";
  auto run = [&](const std::string& name, int threads, std::uint64_t steps, bool restart) {
    const auto dir = drop_case(name, 10.0, 800, tail);
    omp_set_num_threads(threads);
    RunOptions o;
    o.out_dir = dir / "out";
    o.steps = steps;
    Simulation(load_config((dir / "drop.toml").string()), o).run();
    if (restart) {
      o.steps = 200;
      o.restart = dir / "out" / "checkpoint.mdpd";
      Simulation(load_config((dir / "drop.toml").string()), o).run();
    }
    return test::read_file(dir / "out" / "droplet.json") + test::read_file(dir / "out" / "droplet_profile.csv");
  };
  const std::string one = run("mesodpd_droplet_one", 1, 200, false);
  EXPECT_GT(one.size(), 200u);
  EXPECT_EQ(run("mesodpd_droplet_two", 2, 200, false), one) << "1 and 2 threads differ";
  EXPECT_EQ(run("mesodpd_droplet_restart", 2, 100, true), one) << "the restarted run differs";
  omp_set_num_threads(1);
  for (const char* d : {"mesodpd_droplet_one", "mesodpd_droplet_two", "mesodpd_droplet_restart"})
    std::filesystem::remove_all(std::filesystem::temp_directory_path() / d);
}

TEST(Droplet, ShortWarrenDropObeysLaplace) {
  // A short version of examples/mdpd_droplet: a drop of 1,600 particles of Warren's liquid (R about 4)
  // in a 15^3 box, 5,000 steps. Delta P R / 2 must be positive beyond four error bars and within 30 % of
  // the slab's sigma = 7.86 (docs/validation.md); the long runs fit Delta P against 1/R.
  const std::string tail =
      "[run]\nsteps = 5000\n[output]\nprogress = false\nthermo_every = 100\n"
      "[analysis.droplet]\nstart = 1000\nevery = 20\ninner_radius = 1.79\nouter_radius = 6.99\n";
  const auto dir = drop_case("mesodpd_droplet_laplace", 15.0, 1600, tail);
  RunOptions o;
  o.out_dir = dir / "out";
  Simulation(load_config((dir / "drop.toml").string()), o).run();
  const std::string json = test::read_file(dir / "out" / "droplet.json");
  const double radius = json_number(json, "radius"), dp = json_number(json, "delta_p"),
               dp_err = json_number(json, "delta_p_err"), sigma = json_number(json, "sigma_laplace");
  std::printf("short drop: R = %.3f, rho_in = %.3f, rho_out = %.5f, Delta P = %.3f +- %.3f, Delta P R / 2 = %.3f\n",
              radius, json_number(json, "rho_in"), json_number(json, "rho_out"), dp, dp_err, sigma);
  EXPECT_NEAR(radius, 3.95, 0.15);  // the lattice ball's 3.99 at density 6, a little denser as a liquid
  EXPECT_GT(json_number(json, "rho_in"), 5.8);
  EXPECT_LT(json_number(json, "rho_out"), 0.01);
  EXPECT_GT(dp, 4 * dp_err) << json;
  EXPECT_NEAR(sigma, 7.86, 0.3 * 7.86) << json;
  std::filesystem::remove_all(dir);
}
