// Many-body DPD (seed 000 Eq. 17) and Liu's spline potentials (seed 000 Eqs. 18-23): forces against
// finite differences of their energies where a potential exists, Liu's published zero crossing, runs
// that stay bit-identical across thread counts and a restart, and the density blow-up report.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "physics/mdpd_pair.hpp"
#include "physics/spline_pair.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"
#include "threads_and_restart.hpp"

using namespace mesodpd;

namespace {

// Warren's liquid (A = -40, B = 25, r_d = 0.75) as a one-species spec at density rho, without
// dissipation when `gamma` is 0.
SimulationSpec warren_spec(double l, double rho, double gamma, DensityKernelChoice kernel) {
  SimulationSpec spec = test::fluid_spec(l, l, l, rho, -40.0, gamma, 0.01);
  spec.pair_style = PairStyle::Mdpd;
  spec.pair_section.kernel = kernel;
  spec.pairs[0].own["b"] = 25.0;
  spec.pairs[0].rd = 0.75;
  return spec;
}

// The many-body potential energy of seed 000 Eq. 17 in plain double: local densities by a brute-force
// sum of the kernel, then the law's pair energies, which with Warren's kernel add up to
// sum_i (pi r_d^4 / 30) B rho_i^2 + sum_pairs A r_c / 2 (1 - r/r_c)^2.
double mdpd_energy(const ParticleData& p, const Box& box, const MdpdPairParamsT<double>& q, DensityKernelKind kernel) {
  const std::size_t n = p.n_local;
  auto for_pairs = [&](auto&& visit) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) {
        const double dx = minimum_image(p.x[i] - p.x[j], box.len.x, 0.5 * box.len.x);
        const double dy = minimum_image(p.y[i] - p.y[j], box.len.y, 0.5 * box.len.y);
        const double dz = minimum_image(p.z[i] - p.z[j], box.len.z, 0.5 * box.len.z);
        visit(i, j, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
  };
  std::vector<double> rho(n, 0.0);
  const DensityParamsT<double> dp{q.rd, q.rd * q.rd};
  for_pairs([&](std::size_t i, std::size_t j, double r) {
    const double w = kernel == DensityKernelKind::Warren ? WarrenDensityKernel{}(dp, r) : LucyDensityKernel{}(dp, r);
    rho[i] += w;
    rho[j] += w;
  });
  double e = 0;
  for_pairs([&](std::size_t i, std::size_t j, double r) {
    PairInput<double> in;
    in.r = r;
    in.rho_i = rho[i];
    in.rho_j = rho[j];
    e += MdpdLaw::Eval<WeightKind::Two>{}(q, in).energy;
  });
  return e;
}

// Largest |F - (-dE/dx)| over a few particles and components, relative to the force scale, with the
// force from the reference pair loop fed by the reference density pass.
double gradient_mismatch(DensityKernelChoice choice) {
  const SimulationSpec spec = warren_spec(4.0, 3.0, 0.0, choice);
  const Box box{{4.0, 4.0, 4.0}};
  ParticleData p = test::random_particles(box, 192, 31);
  const PairLawTables laws = make_pair_laws(spec);
  const DensitySettings ds = *make_density_settings(spec);
  const auto& q = std::get<LawTable<MdpdLaw>>(laws).table(0, 0);
  std::vector<double> rho;
  reference_density(p, box, ds, rho);
  std::vector<std::array<double, 3>> f;
  PairSums sums;
  reference_forces(p, box, laws, NoiseSettings{}, 1, 0.01, f, sums, rho.data());
  double worst = 0, scale = 0;
  const double h = 1e-5;
  for (std::size_t i : {0u, 17u, 55u, 101u, 150u}) {
    for (int c = 0; c < 3; ++c) {
      double* x = c == 0 ? &p.x[i] : c == 1 ? &p.y[i] : &p.z[i];
      const double x0 = *x;
      *x = x0 + h;
      const double up = mdpd_energy(p, box, q, ds.kernel);
      *x = x0 - h;
      const double down = mdpd_energy(p, box, q, ds.kernel);
      *x = x0;
      const double fd = -(up - down) / (2 * h);
      worst = std::max(worst, std::abs(f[i][static_cast<std::size_t>(c)] - fd));
      scale = std::max(scale, std::abs(fd));
    }
  }
  EXPECT_GT(scale, 5.0);  // the particles feel real forces
  return worst / scale;
}

}  // namespace

TEST(ManyBody, WarrenKernelForceIsMinusTheGradientOfItsEnergy) {
  // With Warren's kernel and one B and r_d, F = -grad U exactly (Warren 2003; docs/physics.md).
  EXPECT_LT(gradient_mismatch(DensityKernelChoice::Warren), 1e-6);
}

TEST(ManyBody, LucyKernelForceHasNoPotential) {
  // Lucy's kernel is not the one whose gradient is proportional to w_d = 1 - r/r_d: the same energy
  // expression is then no potential of the force, and the finite-difference check must see it (so the
  // check above can fail).
  EXPECT_GT(gradient_mismatch(DensityKernelChoice::Lucy), 1e-2);
}

TEST(Spline, ForceIsMinusTheDerivativeAndTheShapeIsLius) {
  // seed 000 Fig. 10: A = 2, r_c1 = 0.8, B = 1, r_c2 = 1, a = 1 is repulsive at the origin, changes sign
  // at r = 0.4529 and vanishes smoothly at r = 1.
  SplinePairParamsT<double> q;
  q.a = 1.0;
  q.ka = 2.0;
  q.rc1 = 0.8;
  q.kb = 1.0;
  q.rc2 = 1.0;
  q.rcut2 = 1.0;
  auto eval = [&](double r) {
    PairInput<double> in;
    in.r = r;
    return SplineLaw::Eval<WeightKind::Two>{}(q, in);
  };
  EXPECT_DOUBLE_EQ(eval(0.0).energy, 1.0);  // a (A - B)
  EXPECT_EQ(eval(0.0).fc, 0.0);
  EXPECT_GT(eval(0.4520).energy, 0.0);
  EXPECT_LT(eval(0.4540).energy, 0.0);
  EXPECT_EQ(eval(1.0).energy, 0.0);
  EXPECT_EQ(eval(1.0).fc, 0.0);
  EXPECT_EQ(eval(1.3).fc, 0.0);
  const double h = 1e-6;
  for (double r = 0.005; r < 1.1; r += 0.01) {
    const double fd = -(eval(r + h).energy - eval(r - h).energy) / (2 * h);
    EXPECT_NEAR(eval(r).fc, fd, 1e-7) << "r = " << r;
  }
  // The spline of Eq. 18 itself: W(0) = 1, W(r_c/2) = 1/4, continuous slope there.
  double w, dw, w2, dw2;
  cubic_spline(0.4 - 1e-12, 0.8, w, dw);
  cubic_spline(0.4 + 1e-12, 0.8, w2, dw2);
  EXPECT_NEAR(w, 0.25, 1e-9);
  EXPECT_NEAR(dw, dw2, 1e-9);
}

TEST(ManyBody, BitIdenticalForOneAndTwoThreadsAndAcrossARestart) {
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_many_body_restart";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const SimulationSpec spec = warren_spec(5.0, 5.0, 4.5, DensityKernelChoice::Lucy);
  const auto one = test::run_on_threads(spec, 1, 120, dir);
  EXPECT_TRUE(test::run_on_threads(spec, 2, 120, dir) == one) << "1 and 2 threads differ";
  test::run_on_threads(spec, 1, 50, dir);
  EXPECT_TRUE(test::run_on_threads(spec, 2, 120, dir, dir / "c50.mdpd") == one) << "the restarted run diverged";
  omp_set_num_threads(1);
  std::filesystem::remove_all(dir);
}

TEST(ManyBody, MomentumIsConservedInARun) {
  const SimulationSpec spec = warren_spec(5.0, 5.0, 4.5, DensityKernelChoice::Warren);
  Simulation sim(spec, RunOptions{});
  const ThermoState t0 = sim.thermo();
  for (int k = 0; k < 100; ++k) {
    sim.step();
    const ThermoState t = sim.thermo();
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.momentum[c], t0.momentum[c], 1e-9) << "step " << k + 1;
  }
}

TEST(ManyBody, CollapseStopsTheRunNamingTheLocalDensity) {
  // A strong attraction with a feeble many-body repulsion: the fluid collapses; the run must stop with
  // the step, the particle and its local density, before anything becomes NaN.
  SimulationSpec spec = warren_spec(5.0, 4.0, 4.5, DensityKernelChoice::Warren);
  spec.max_density = 30.0;
  {
    // Warren's liquid from the same start stays far below the threshold.
    Simulation liquid(spec, RunOptions{});
    for (int k = 0; k < 300; ++k) liquid.step();
  }
  spec.pairs[0].a = -80.0;
  spec.pairs[0].own["b"] = 0.2;
  Simulation sim(spec, RunOptions{});
  try {
    for (int k = 0; k < 3000; ++k) sim.step();
    FAIL() << "expected the collapse to be reported";
  } catch (const BlowUpError& e) {
    const std::string what = e.what();
    EXPECT_GE(e.step(), 2u);
    EXPECT_NE(what.find("local density"), std::string::npos) << what;
    EXPECT_NE(what.find("run.max_density = 30"), std::string::npos) << what;
    EXPECT_NE(what.find("particle id " + std::to_string(e.particle_id())), std::string::npos) << what;
    EXPECT_NE(what.find("step " + std::to_string(e.step())), std::string::npos) << what;
  }
}

TEST(ManyBody, ShortSlabHoldsALiquidWithPositiveSurfaceTension) {
  // A short version of examples/mdpd_slab (Warren's liquid, A = -40, B = 25, r_d = 0.75): a slab of
  // density 6 in a 6 x 6 x 18 box stays a slab with a dense liquid, an empty vapour and a surface
  // tension well above zero (the example's long run gives the numbers in docs/validation.md).
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_short_slab";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const int n = 1296;  // density 6 in |z - 9| < 3
    std::ofstream f(dir / "slab.data");
    f << "short slab\n\n" << n << " atoms\n1 atom types\n\n0 6 xlo xhi\n0 6 ylo yhi\n0 18 zlo zhi\n\nAtoms\n\n";
    for (int k = 0; k < n; ++k) f << k + 1 << " 1 " << 6 * u(rng) << ' ' << 6 * u(rng) << ' ' << 6 + 6 * u(rng) << '\n';
  }
  const std::string toml =
      "[system]\nbox = [6.0, 6.0, 18.0]\nseed = 9\n[[species]]\nname = \"L\"\n"
      "[init]\nlammps_data = \"slab.data\"\nvelocities = \"maxwell\"\n"
      "[pair]\nstyle = \"mdpd\"\na = -40.0\nb = 25.0\nrd = 0.75\ngamma = 4.5\n"
      "[integrator]\ndt = 0.01\n[run]\nsteps = 4000\n[output]\nthermo_every = 10\nprogress = false\n"
      "[analysis.surface_tension]\naxis = \"z\"\nstart = 1000\nblocks = 6\n";
  std::ofstream(dir / "slab.toml") << toml;
  SimulationSpec spec = load_config((dir / "slab.toml").string());
  RunOptions o;
  o.out_dir = dir / "out";
  Simulation sim(spec, o);
  sim.run();
  // The slab's centre (circular mean of z) and the densities inside and far outside it.
  const ParticleData& p = sim.particles();
  double c = 0, s = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    c += std::cos(2 * M_PI * p.z[i] / 18.0);
    s += std::sin(2 * M_PI * p.z[i] / 18.0);
  }
  const double zc = 18.0 * std::atan2(s, c) / (2 * M_PI);
  int inside = 0, outside = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const double d = std::abs(minimum_image(p.z[i] - zc, 18.0, 9.0));
    inside += d < 1.5 ? 1 : 0;
    outside += d > 6.0 ? 1 : 0;
  }
  const double rho_l = inside / (36.0 * 3.0), rho_v = outside / (36.0 * 6.0);
  EXPECT_GT(rho_l, 5.3);
  EXPECT_LT(rho_l, 6.9);
  EXPECT_LT(rho_v, 0.07);
  const std::string json = test::read_file(dir / "out" / "surface_tension.json");
  auto number = [&](const std::string& key) { return std::stod(json.substr(json.find("\"" + key + "\": ") + key.size() + 4)); };
  const double sigma = number("sigma"), err = number("sigma_err");
  EXPECT_GT(sigma, 3 * err) << json;
  EXPECT_GT(sigma, 4.0) << json;
  EXPECT_LT(sigma, 11.0) << json;
  std::printf("short slab: rho_l = %.3f, rho_v = %.4f, sigma = %.3f +- %.3f\n", rho_l, rho_v, sigma, err);
  std::filesystem::remove_all(dir);
}
