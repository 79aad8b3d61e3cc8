// Bonded forces: each law against its energy, Newton's third law and momentum, thread and restart
// bit-identity, and the statistics of ideal chains (Gaussian bond and end-to-end statistics) and of an
// angle-only trimer (Boltzmann angle distribution).
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "engine/bonded_forces.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/validate.hpp"
#include "physics/bond_laws.hpp"
#include "test_support.hpp"
#include "octahedra_data.hpp"
#include "threads_and_restart.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

// --- the laws -------------------------------------------------------------------------------------

TEST(BondLaws, ForceIsMinusTheEnergyDerivative) {
  const BondParams laws[] = {{BondStyle::Harmonic, 4.0, 0.0, 0.0},
                             {BondStyle::Harmonic, 30.0, 0.7, 0.0},
                             {BondStyle::Fene, 7.0, 0.0, 1.5},
                             {BondStyle::Wlc, 0.8, 0.0, 1.2}};
  for (const BondParams& p : laws) {
    for (double r = 0.05; r < 1.19; r += 0.0731) {
      const double h = 1e-6;
      const BondForce f = bond_force(p, r);
      ASSERT_FALSE(f.broken);
      const double fd = -(bond_force(p, r + h).energy - bond_force(p, r - h).energy) / (2 * h);
      EXPECT_NEAR(f.f_over_r * r, fd, 1e-6 * (1 + std::abs(fd))) << "style " << static_cast<int>(p.style) << " r " << r;
    }
    EXPECT_EQ(bond_force(p, 0.0).energy, p.style == BondStyle::Harmonic ? 0.5 * p.k * p.r0 * p.r0 : 0.0);
  }
  // Seed 000 Eq. 27 and Eq. 26 as written (magnitude along r-hat).
  const BondForce fene = bond_force(laws[2], 1.0);
  EXPECT_NEAR(fene.f_over_r, -7.0 / (1 - 1.0 / 2.25), 1e-12);
  const BondForce wlc = bond_force(laws[3], 0.6);
  EXPECT_NEAR(wlc.f_over_r * 0.6, -0.8 * (1.0 / 0.25 + 4 * 0.5 - 1), 1e-12);
}

TEST(BondLaws, FeneAndWlcBreakAtTheirMaximum) {
  EXPECT_TRUE(bond_force({BondStyle::Fene, 7.0, 0.0, 1.5}, 1.5).broken);
  EXPECT_TRUE(bond_force({BondStyle::Fene, 7.0, 0.0, 1.5}, 2.0).broken);
  EXPECT_FALSE(bond_force({BondStyle::Fene, 7.0, 0.0, 1.5}, 1.4999).broken);
  EXPECT_TRUE(bond_force({BondStyle::Wlc, 1.0, 0.0, 1.2}, 1.2).broken);
  EXPECT_TRUE(std::isfinite(bond_force({BondStyle::Wlc, 1.0, 0.0, 1.2}, 1.1999).f_over_r));
}

TEST(BondLaws, AngleForceIsMinusTheEnergyGradient) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double theta0_deg : {0.0, 60.0, 120.0, 180.0}) {
    const AngleParams p = make_angle_params(3.0, theta0_deg * M_PI / 180.0);
    for (int trial = 0; trial < 20; ++trial) {
      double r[3][3];
      for (auto& a : r)
        for (double& c : a) c = u(rng);
      auto energy = [&](const double (&q)[3][3]) {
        const double b1[3] = {q[1][0] - q[0][0], q[1][1] - q[0][1], q[1][2] - q[0][2]};
        const double b2[3] = {q[2][0] - q[1][0], q[2][1] - q[1][1], q[2][2] - q[1][2]};
        return angle_force(p, b1, b2);
      };
      const AngleForce f = energy(r);
      // A configuration at the cusp (theta = 0 or pi with theta0 strictly between) has no gradient.
      if (std::abs(f.cos_theta) > 0.999) continue;
      const double f2[3] = {-(f.f1[0] + f.f3[0]), -(f.f1[1] + f.f3[1]), -(f.f1[2] + f.f3[2])};
      const double* forces[3] = {f.f1, f2, f.f3};
      for (int atom = 0; atom < 3; ++atom)
        for (int d = 0; d < 3; ++d) {
          const double h = 1e-6;
          double up[3][3], dn[3][3];
          std::copy(&r[0][0], &r[0][0] + 9, &up[0][0]);
          std::copy(&r[0][0], &r[0][0] + 9, &dn[0][0]);
          up[atom][d] += h;
          dn[atom][d] -= h;
          const double fd = -(energy(up).energy - energy(dn).energy) / (2 * h);
          EXPECT_NEAR(forces[atom][d], fd, 2e-6 * (1 + std::abs(fd))) << "theta0 " << theta0_deg << " atom " << atom;
        }
    }
  }
  // Seed 002 Eq. 32: U = k [1 - cos(theta - theta0)], theta between the bond vectors.
  const double b1[3] = {1, 0, 0}, b2[3] = {0.5, std::sqrt(3.0) / 2, 0};  // theta = 60 degrees
  EXPECT_NEAR(angle_force(make_angle_params(3.0, 0.0), b1, b2).energy, 3.0 * 0.5, 1e-12);
  EXPECT_NEAR(angle_force(make_angle_params(3.0, M_PI / 3), b1, b2).energy, 0.0, 1e-12);
}

// The dihedral law U = k [1 - cos(theta - theta0)] over the hinge angle: forces are minus the gradient
// (finite differences over all four atoms), they sum to zero and have no torque, and the angle is the
// one between the triangles' normals (0 flat, 90 degrees for a right-angled hinge).
TEST(BondLaws, DihedralForceIsMinusTheEnergyGradient) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double theta0_deg : {0.0, 35.0, -120.0}) {
    const DihedralParams p{2.5, theta0_deg * M_PI / 180.0};
    for (int trial = 0; trial < 20; ++trial) {
      double r[4][3];
      for (auto& a : r)
        for (double& c : a) c = u(rng);
      auto eval = [&](const double (&q)[4][3]) {
        double ra[3], rc[3], rd[3];
        for (int c = 0; c < 3; ++c) {
          ra[c] = q[0][c] - q[1][c];
          rc[c] = q[2][c] - q[1][c];
          rd[c] = q[3][c] - q[1][c];
        }
        return dihedral_force(p, ra, rc, rd);
      };
      const DihedralForce f = eval(r);
      const double* forces[4] = {f.fa, f.fb, f.fc, f.fd};
      double total[3] = {0, 0, 0}, torque[3] = {0, 0, 0};
      for (int atom = 0; atom < 4; ++atom) {
        const double* q = r[atom];
        const double* F = forces[atom];
        for (int d = 0; d < 3; ++d) total[d] += F[d];
        torque[0] += q[1] * F[2] - q[2] * F[1];
        torque[1] += q[2] * F[0] - q[0] * F[2];
        torque[2] += q[0] * F[1] - q[1] * F[0];
        for (int d = 0; d < 3; ++d) {
          const double h = 1e-6;
          double up[4][3], dn[4][3];
          std::copy(&r[0][0], &r[0][0] + 12, &up[0][0]);
          std::copy(&r[0][0], &r[0][0] + 12, &dn[0][0]);
          up[atom][d] += h;
          dn[atom][d] -= h;
          const double fd = -(eval(up).energy - eval(dn).energy) / (2 * h);
          EXPECT_NEAR(F[d], fd, 2e-5 * (1 + std::abs(fd))) << "theta0 " << theta0_deg << " atom " << atom;
        }
      }
      for (int d = 0; d < 3; ++d) {
        EXPECT_NEAR(total[d], 0.0, 1e-9);
        EXPECT_NEAR(torque[d], 0.0, 1e-9);
      }
    }
  }
  // b = origin, c along x: a flat hinge (a and d on opposite sides of b-c) has theta = 0; lifting d out
  // of the plane to a right angle gives |theta| = 90 degrees.
  const double a[3] = {0.5, -1.0, 0.0}, c[3] = {1.0, 0.0, 0.0}, flat[3] = {0.5, 1.0, 0.0}, up[3] = {0.5, 0.0, 1.0};
  EXPECT_NEAR(dihedral_force(DihedralParams{3.0, 0.0}, a, c, flat).theta, 0.0, 1e-12);
  EXPECT_NEAR(dihedral_force(DihedralParams{3.0, 0.0}, a, c, flat).energy, 0.0, 1e-12);
  EXPECT_NEAR(std::abs(dihedral_force(DihedralParams{3.0, 0.0}, a, c, up).theta), M_PI / 2, 1e-12);
  EXPECT_NEAR(dihedral_force(DihedralParams{3.0, 0.0}, a, c, up).energy, 3.0, 1e-12);
  // A triangle of zero area has no normal: no force.
  const double on_line[3] = {2.0, 0.0, 0.0};
  EXPECT_EQ(dihedral_force(DihedralParams{3.0, 0.0}, on_line, c, up).energy, 0.0);
}

// --- the engine ------------------------------------------------------------------------------------

// Chains (and solvent) in a box: a config in TOML, parsed and validated like a file.
std::string chains_config(const std::string& extra, double a = 25.0, double box = 6.0) {
  return fmt::format(R"(
[system]
box = [{0}, {0}, {0}]
kT = 1.0
seed = 99

[[species]]
name = "A"

[[species]]
name = "W"
density = 1.0

[pair]
a = {1}
gamma = 4.5

[[bond_type]]
name = "spring"
style = "harmonic"
k = 20.0
r0 = 0.6

[[bond_type]]
name = "fene"
style = "fene"
k = 10.0
rmax = 1.5

[[angle_type]]
name = "bend"
k = 2.0
theta0 = 30.0

[[molecule]]
name = "chain"
sequence = "A8"
bond_type = "spring"
angle_type = "bend"
count = 20
bond_length = 0.6

[[molecule]]
name = "lipid"
sequence = "W2(A3)2"
bond_type = "fene"
angle_type = "bend"
count = 10
bond_length = 0.6

[integrator]
dt = 0.02

[run]
steps = 100

[output]
thermo_every = 10
progress = false
{2}
)",
                     box, a, extra);
}

SimulationSpec chains_spec(const std::string& extra = "", double a = 25.0, double box = 6.0) {
  return parse_config(chains_config(extra, a, box), "chains.toml");
}

TEST(Bonded, BuilderMakesTheMoleculesOfTheSequence) {
  const SimulationSpec spec = chains_spec();
  ASSERT_EQ(spec.molecules.size(), 2u);
  EXPECT_EQ(spec.molecules[0].beads.size(), 8u);
  EXPECT_EQ(spec.molecules[0].bonds.size(), 7u);
  EXPECT_EQ(spec.molecules[0].angles.size(), 6u);
  // W2(A3)2: W-W, then two A3 tails on the second W: 8 beads, 7 bonds, angles: W1-W2-A, W1-W2-A',
  // A-W2-A' at the branch point plus 2 in each tail.
  const MoleculeSpec& lipid = spec.molecules[1];
  EXPECT_EQ(lipid.beads, (std::vector<int>{1, 1, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(lipid.bonds.size(), 7u);
  EXPECT_EQ(lipid.angles.size(), 7u);
  Simulation sim(spec, RunOptions{});
  EXPECT_EQ(sim.total_particles(), 20u * 8 + 10 * 8 + 216);
  EXPECT_EQ(sim.topology().bonds.size(), 20u * 7 + 10 * 7);
  EXPECT_EQ(sim.topology().angles.size(), 20u * 6 + 10 * 7);
  // Molecule ids and the random walk: every bond starts at the placement length.
  const ParticleData& p = sim.particles();
  std::vector<std::size_t> at(p.n_local + 1);
  for (std::size_t i = 0; i < p.n_local; ++i) at[p.id[i]] = i;
  for (const Bond& b : sim.topology().bonds) {
    const std::size_t i = at[b.a], j = at[b.b];
    EXPECT_EQ(p.mol[i], p.mol[j]);
    EXPECT_GT(p.mol[i], 0);
    const double dx = (p.x[i] + p.ix[i] * 6.0) - (p.x[j] + p.ix[j] * 6.0);
    const double dy = (p.y[i] + p.iy[i] * 6.0) - (p.y[j] + p.iy[j] * 6.0);
    const double dz = (p.z[i] + p.iz[i] * 6.0) - (p.z[j] + p.iz[j] * 6.0);
    EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + dz * dz), 0.6, 1e-9);
  }
  EXPECT_EQ(p.mol[at[p.n_local]], 0);  // the last particle is solvent
}

TEST(Bonded, ConfigErrorsNameTheKey) {
  auto error_of = [](const std::string& text) {
    try {
      parse_config(text, "bad.toml");
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string good = chains_config("");
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    s.replace(s.find(from), from.size(), to);
    return s;
  };
  EXPECT_NE(error_of(replaced("sequence = \"A8\"", "sequence = \"B8\"")).find("names species 'B'"), std::string::npos);
  EXPECT_NE(error_of(replaced("sequence = \"A8\"", "sequence = \"A\"")).find("molecule[0].sequence"), std::string::npos);
  EXPECT_NE(error_of(replaced("sequence = \"A8\"", "sequence = \"A2(A2)2A1\"")).find("nothing may follow"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("bond_type = \"spring\"\nangle", "bond_type = \"sprung\"\nangle"))
                .find("molecule[0].bond_type"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("angle_type = \"bend\"\ncount = 20", "angle_type = \"bent\"\ncount = 20"))
                .find("angle type without parameters"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("rmax = 1.5", "rmax = 1.5\nr0 = 0.3")).find("bond_type[1].r0"), std::string::npos);
  EXPECT_NE(error_of(replaced("style = \"fene\"", "style = \"morse\"")).find("bond_type[1].style"), std::string::npos);
  EXPECT_NE(error_of(replaced("count = 20\nbond_length = 0.6", "count = 20\nbond_length = 1.6"))
                .find("molecule[0].bond_length"),
            std::string::npos);
  EXPECT_NE(error_of(replaced("k = 10.0\nrmax = 1.5", "k = 10.0")).find("rmax"), std::string::npos);
}

// Sum of the forces on all particles after the bonded stage alone, in the integers it accumulated.
TEST(Bonded, NewtonsThirdLawIsExactAndMomentumIsConserved) {
  Simulation sim(chains_spec(), RunOptions{});
  // Momentum: every force adds to zero over the system, so the total stays at its start value.
  auto momentum = [&] {
    const ParticleData& p = sim.particles();
    double m[3] = {0, 0, 0};
    for (std::size_t i = 0; i < p.n_local; ++i) {
      m[0] += p.vx[i];
      m[1] += p.vy[i];
      m[2] += p.vz[i];
    }
    return std::array<double, 3>{m[0], m[1], m[2]};
  };
  const auto m0 = momentum();
  for (int s = 0; s < 100; ++s) sim.step();
  const auto m1 = momentum();
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(m1[d], m0[d], 1e-9);
  // The bonded forces alone on the current configuration: each bond and angle adds integers that
  // cancel, so the total force is exactly zero.
  ParticleData p = sim.particles();
  std::fill(p.fx.begin(), p.fx.end(), 0.0);
  std::fill(p.fy.begin(), p.fy.end(), 0.0);
  std::fill(p.fz.begin(), p.fz.end(), 0.0);
  BondedForces bonded = sim.bonded();
  Halo halo;
  PairSums sums;
  ASSERT_FALSE(bonded.compute(p, sim.box(), halo, true, sums).has_value());
  double f[3] = {0, 0, 0}, fmax = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    f[0] += p.fx[i];
    f[1] += p.fy[i];
    f[2] += p.fz[i];
    fmax = std::max(fmax, std::abs(p.fx[i]));
  }
  EXPECT_GT(fmax, 1.0);
  EXPECT_EQ(f[0], 0.0);
  EXPECT_EQ(f[1], 0.0);
  EXPECT_EQ(f[2], 0.0);
  EXPECT_GT(sums.potential_energy, 0.0);
}

// The storage-index lists follow a sort through its permutation instead of looking every partner up
// by id; the forces must be those of a lookup by id, bit for bit, and a change that is not a sort
// alone must send them back to the ids.
TEST(Bonded, ListsFollowASortAndGiveTheForcesOfALookupById) {
  Simulation sim(chains_spec(), RunOptions{});
  for (int s = 0; s < 10; ++s) sim.step();
  // A cell-mode run sorts every step: its lists were built from ids once and followed every sort since.
  EXPECT_EQ(sim.bonded().list_rebuilds(), 1u);

  ParticleData p = sim.particles();
  auto forces = [](BondedForces& bonded, ParticleData& q, const Box& box, PairSums& sums) {
    std::fill(q.fx.begin(), q.fx.end(), 0.0);
    std::fill(q.fy.begin(), q.fy.end(), 0.0);
    std::fill(q.fz.begin(), q.fz.end(), 0.0);
    Halo halo;
    ASSERT_FALSE(bonded.compute(q, box, halo, true, sums).has_value());
  };
  auto by_id = [](const ParticleData& q) {
    std::vector<double> out(3 * (std::size_t{*std::max_element(q.id.begin(), q.id.begin() + static_cast<std::ptrdiff_t>(q.n_local))} + 1));
    for (std::size_t i = 0; i < q.n_local; ++i) {
      out.at(3 * q.id[i]) = q.fx[i];
      out.at(3 * q.id[i] + 1) = q.fy[i];
      out.at(3 * q.id[i] + 2) = q.fz[i];
    }
    return out;
  };
  BondedForces followed = sim.bonded();
  PairSums s0;
  forces(followed, p, sim.box(), s0);
  const std::vector<double> before = by_id(p);
  const std::uint64_t built = followed.list_rebuilds();

  // A random permutation (far from the near-identity of a step's sort), then the same forces.
  std::vector<std::uint32_t> order(p.n_local);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), std::mt19937(7));
  p.permute(order);
  PairSums s1;
  forces(followed, p, sim.box(), s1);
  EXPECT_EQ(followed.list_rebuilds(), built);  // followed, not rebuilt
  EXPECT_EQ(by_id(p), before);
  EXPECT_EQ(s1.potential_energy, s0.potential_energy);
  EXPECT_EQ(s1.virial, s0.virial);

  // A fresh object, which looks every partner up by id, gives the same bits in the new order.
  ParticleData q = p;
  BondedForces fresh = sim.bonded();
  PairSums s2;
  forces(fresh, q, sim.box(), s2);
  EXPECT_EQ(fresh.list_rebuilds(), sim.bonded().list_rebuilds() + 1);
  EXPECT_EQ(q.fx, p.fx);
  EXPECT_EQ(q.fy, p.fy);
  EXPECT_EQ(q.fz, p.fz);

  // A change after the sort (here a resize to the same size) is not followed: the ids are looked up.
  p.resize(p.n_local);
  PairSums s3;
  forces(followed, p, sim.box(), s3);
  EXPECT_EQ(followed.list_rebuilds(), built + 1);
  EXPECT_EQ(by_id(p), before);
}

std::vector<double> positions_after(const SimulationSpec& spec, int threads, int steps) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  Simulation sim(spec, RunOptions{});
  for (int s = 0; s < steps; ++s) sim.step();
  omp_set_num_threads(before);
  const ParticleData all = sim.particles();
  std::vector<double> out(3 * (sim.total_particles() + 1));
  for (std::size_t i = 0; i < all.n_local; ++i) {
    out[3 * all.id[i]] = all.x[i];
    out[3 * all.id[i] + 1] = all.vy[i];
    out[3 * all.id[i] + 2] = all.fz[i];
  }
  return out;
}

TEST(Bonded, OneAndTwoThreadsGiveTheSameBits) {
  const SimulationSpec spec = chains_spec();
  EXPECT_EQ(positions_after(spec, 1, 60), positions_after(spec, 2, 60));
}

TEST(Bonded, FeneBondPastItsMaximumStopsTheRunNamingBondAndIds) {
  // Squeeze the FENE maximum below the placement length: the first evaluation finds a broken bond.
  SimulationSpec spec = chains_spec();
  spec.bond_types[1].rmax = 0.61;
  spec.molecules[1].bond_length = 0.6;
  spec.dt = 0.2;
  try {
    Simulation sim(spec, RunOptions{});
    for (int s = 0; s < 50; ++s) sim.step();
    FAIL() << "no error";
  } catch (const BlowUpError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bond "), std::string::npos) << m;
    EXPECT_NE(m.find("particle ids"), std::string::npos) << m;
    EXPECT_NE(m.find("rmax = 0.61"), std::string::npos) << m;
    EXPECT_NE(m.find("at step"), std::string::npos) << m;
  }
}

TEST(Bonded, RestartIsBitIdentical) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_bonds_restart";
  fs::remove_all(dir);
  const SimulationSpec spec = chains_spec();
  {
    RunOptions o;
    o.out_dir = dir / "whole";
    o.steps = 80;
    Simulation sim(spec, o);
    sim.run();
  }
  {
    RunOptions o;
    o.out_dir = dir / "part";
    o.steps = 40;
    Simulation sim(spec, o);
    sim.run();
  }
  {
    RunOptions o;
    o.out_dir = dir / "part";
    o.steps = 80;
    o.restart = dir / "part" / "checkpoint40.mdpd";
    fs::copy_file(dir / "part" / "checkpoint.mdpd", o.restart);
    Simulation sim(spec, o);
    EXPECT_EQ(sim.topology().bonds.size(), 210u);
    EXPECT_EQ(sim.topology().angles.size(), 190u);
    sim.run();
  }
  EXPECT_EQ(test::read_file(dir / "whole" / "checkpoint.mdpd"), test::read_file(dir / "part" / "checkpoint.mdpd"));
  fs::remove_all(dir);
}

// Excluded pairs lose exactly their pair force: a lone trimer with zero-strength bonds feels only the
// pair forces of the pairs that are not excluded (all three are within the cutoff). Standard DPD and
// many-body DPD (whose excluded pairs are re-evaluated with the step's local densities).
class ExcludedPairs : public ::testing::TestWithParam<std::string> {};

TEST_P(ExcludedPairs, LoseExactlyTheirPairForce) {
  const std::string pair_section = GetParam();
  auto forces_of = [&](const std::string& exclude) {
    const std::string text = fmt::format(R"(
[system]
box = [5.0, 5.0, 5.0]
seed = 3

[[species]]
name = "A"

{}

[[bond_type]]
name = "none"
style = "harmonic"
k = 0.0

[[molecule]]
name = "trimer"
sequence = "A3"
bond_type = "none"
count = 1
bond_length = 0.3

[bonds]
exclude = "{}"

[output]
progress = false
)",
                                         pair_section, exclude);
    Simulation sim(parse_config(text, "x.toml"), RunOptions{});
    sim.step();
    const ParticleData& p = sim.particles();
    std::vector<double> f(9);
    for (std::size_t i = 0; i < 3; ++i) {
      f[3 * (p.id[i] - 1)] = p.fx[i];
      f[3 * (p.id[i] - 1) + 1] = p.fy[i];
      f[3 * (p.id[i] - 1) + 2] = p.fz[i];
    }
    return std::make_pair(f, sim.thermo());
  };
  const auto [none, t_none] = forces_of("none");
  const auto [one_two, t12] = forces_of("1-2");
  const auto [one_three, t13] = forces_of("1-3");
  for (double v : none) EXPECT_NE(v, 0.0);
  // 1-3: nothing is left, exactly.
  for (double v : one_three) EXPECT_EQ(v, 0.0);
  if (pair_section.find("mdpd") != std::string::npos) {
    // Many-body DPD: only the forces are asserted (its energy is not a pair sum).
    for (int d = 0; d < 3; ++d) {
      EXPECT_EQ(one_two[3 + d], 0.0);
      EXPECT_EQ(one_two[d], -one_two[6 + d]);
      EXPECT_NE(one_two[d], 0.0);
    }
    return;
  }
  EXPECT_EQ(t13.potential_energy, 0.0);
  // 1-2: only the pair (1, 3) acts: equal and opposite on 1 and 3, nothing on the middle bead.
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(one_two[3 + d], 0.0);
    EXPECT_EQ(one_two[d], -one_two[6 + d]);
    EXPECT_NE(one_two[d], 0.0);
  }
  EXPECT_GT(t12.potential_energy, 0.0);
  EXPECT_LT(t12.potential_energy, t_none.potential_energy);
}

INSTANTIATE_TEST_SUITE_P(Bonded, ExcludedPairs,
                         ::testing::Values("[pair]\na = 25.0\ngamma = 4.5",
                                           "[pair]\nstyle = \"mdpd\"\na = -40.0\nb = 25.0\nrd = 0.75\ngamma = 4.5"),
                         [](const auto& info) { return info.index == 0 ? std::string("Dpd") : std::string("ManyBody"); });

// A LAMMPS data file with Bonds and Angles (atom_style molecular) starts a run with that topology; a bond
// type without a [[bond_type]] block is refused naming the file.
TEST(Bonded, DataFileTopologyRunsAndTypesNeedParameters) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_bonds_data";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string data = "chain\n6 atoms\n1 atom types\n5 bonds\n2 bond types\n4 angles\n1 angle types\n"
                     "0 6 xlo xhi\n0 6 ylo yhi\n0 6 zlo zhi\n\nAtoms # molecular\n\n";
  for (int k = 1; k <= 6; ++k) data += fmt::format("{} 1 1 {} 3.0 3.0\n", k, 0.4 + 0.5 * k);
  data += "\nBonds\n\n";
  for (int k = 1; k <= 5; ++k) data += fmt::format("{} {} {} {}\n", k, k == 5 ? 2 : 1, k, k + 1);
  data += "\nAngles\n\n";
  for (int k = 1; k <= 4; ++k) data += fmt::format("{} 1 {} {} {}\n", k, k, k + 1, k + 2);
  std::ofstream(dir / "chain.data") << data;
  auto config = [&](int bond_types) {
    std::string text = "[system]\nbox = [6.0, 6.0, 6.0]\n\n[[species]]\nname = \"A\"\n\n[init]\nlammps_data = \"" +
                       (dir / "chain.data").string() + "\"\nvelocities = \"zero\"\n\n[output]\nprogress = false\n\n"
                       "[[angle_type]]\nname = \"bend\"\nk = 1.0\n\n";
    for (int t = 0; t < bond_types; ++t)
      text += fmt::format("[[bond_type]]\nname = \"b{}\"\nstyle = \"harmonic\"\nk = 10.0\nr0 = 0.5\n\n", t);
    return parse_config(text, (dir / "c.toml").string());
  };
  {
    Simulation sim(config(2), RunOptions{});
    ASSERT_EQ(sim.topology().bonds.size(), 5u);
    EXPECT_EQ(sim.topology().bonds[4].type, 1);
    EXPECT_EQ(sim.topology().angles.size(), 4u);
    EXPECT_EQ(sim.particles().mol[0], 1);
    // A straight chain at its rest length: no bond or angle force, zero energy.
    EXPECT_NEAR(sim.thermo().potential_energy, 25.0 / 2 * 0.25 * 5, 1e-9);  // only the pair repulsion at r = 0.5
    for (int s = 0; s < 20; ++s) sim.step();
  }
  try {
    Simulation sim(config(1), RunOptions{});
    FAIL() << "a bond type without parameters was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("2 bond types"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("chain.data"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// The GSD trajectory holds bonds, angles and molecule ids, and tools/chain_analysis.py measures it
// (and measures synthetic rigid rods exactly: tests/analysis/check_chain_analysis.py).
TEST(ChainAnalysis, GsdTrajectoryHoldsTheTopologyAndIsMeasured) {
  if (std::system("/usr/bin/python3 -c 'import numpy, gsd.hoomd, matplotlib' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with numpy, gsd and matplotlib is not available";
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_chain_analysis";
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = dir / "run";
  Simulation sim(chains_spec("[output.dump]\nformat = \"gsd\"\nevery = 10\n"
                             "fields = [\"id\", \"species\", \"position\", \"image\", \"mol\"]\n"),
                 o);
  sim.run();
  const std::string cmd = "/usr/bin/python3 -W ignore '" + test::source_dir() + "/tests/analysis/check_chain_analysis.py' '" +
                          test::source_dir() + "/tools' '" + (dir / "check").string() + "' '" +
                          (dir / "run" / "trajectory.gsd").string() + "' 210 190 > '" + (dir / "log.txt").string() +
                          "' 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << test::read_file(dir / "log.txt");
  fs::remove_all(dir);
}

// A closed membrane from a LAMMPS data file (atom_style molecular with Bonds and Dihedrals,
// tests/octahedra_data.hpp): the regular octahedron, 6 vertices, 12 edges (harmonic bonds at their rest
// length) and 12 dihedrals, one per edge. Each hinge's normals meet at 180 - 109.47 = 70.53 degrees
// (cos = 1/3), so the dihedral energy is 12 k (1 - 1/3); with no pair force it is the whole potential
// energy. A jittered one, released, is deformed by the flat-preferring hinges with total energy and
// momentum conserved (no thermostat), the GSD file holds the dihedrals, and the run is bit-identical on
// one and two threads and across a restart (the checkpoint keeps the dihedrals).
TEST(Bonded, DihedralsFromADataFileConserveEnergyAndRestartBitIdentical) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_dihedrals";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "octahedron.data") << test::octahedra_data({{4.0, 4.0, 4.0}}, 8.0, 0.0);
  std::ofstream(dir / "jittered.data") << test::octahedra_data({{4.0, 4.0, 4.0}}, 8.0, 0.15);
  const auto spec_with = [&](const std::string& extra, const std::string& file = "jittered.data") {
    return parse_config("[system]\nbox = [8.0, 8.0, 8.0]\n\n[[species]]\nname = \"V\"\n\n[pair]\na = 0.0\n"
                        "gamma = 0.0\n\n[init]\nlammps_data = \"" + (dir / file).string() +
                            "\"\nvelocities = \"zero\"\n\n[integrator]\ndt = 0.002\n\n[[bond_type]]\nname = "
                            "\"edge\"\nstyle = \"harmonic\"\nk = 50.0\nr0 = 1.4142135623730951\n\n[bonds]\nreach = 2.5\n\n"
                            "[[dihedral_type]]\n"
                            "name = \"hinge\"\nk = 2.0\n\n[output]\nthermo_every = 10\nprogress = false\n" + extra,
                        (dir / "c.toml").string());
  };
  {
    RunOptions o;
    o.out_dir = dir / "run";
    {
      Simulation regular(spec_with("", "octahedron.data"), RunOptions{});
      ASSERT_EQ(regular.topology().dihedrals.size(), 12u);
      EXPECT_NEAR(regular.thermo().potential_energy, 12 * 2.0 * (1.0 - 1.0 / 3.0), 1e-6);
    }
    Simulation sim(spec_with("[output.dump]\nformat = \"gsd\"\nevery = 100\n"), o);
    const ThermoState t0 = sim.thermo();
    double worst = 0;
    for (int s = 0; s < 2000; ++s) {
      sim.step();
      if (s % 10 != 9) continue;
      const ThermoState t = sim.thermo();
      worst = std::max(worst, std::abs(t.kinetic_energy + t.potential_energy - t0.potential_energy));
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(t.momentum[c], 0.0, 1e-10) << "step " << s + 1;
    }
    const ThermoState t1 = sim.thermo();
    std::printf("jittered octahedron: potential energy %.6f -> %.6f, kinetic %.6f, largest energy error %.2e\n",
                t0.potential_energy, t1.potential_energy, t1.kinetic_energy, worst);
    EXPECT_GT(t1.kinetic_energy, 0.01 * t0.potential_energy);  // the hinges moved it
    EXPECT_LT(worst, 1e-3 * t0.potential_energy);
    sim.finish();
    if (std::system("/usr/bin/python3 -c 'import gsd.hoomd' >/dev/null 2>&1") == 0) {
      const std::string cmd = "/usr/bin/python3 -c \"import gsd.hoomd as g, sys; t = g.open('" +
                              (dir / "run" / "trajectory.gsd").string() +
                              "', 'rb'); f = t[0]; sys.exit(not (f.dihedrals.N == 12 and list(f.dihedrals.types) == "
                              "['hinge'] and f.dihedrals.group.shape == (12, 4)))\"";
      EXPECT_EQ(std::system(cmd.c_str()), 0) << "trajectory.gsd lacks the dihedrals";
    }
  }
  test::expect_bit_identical_on_threads_and_restart(spec_with(""), dir / "restart");
  // Dihedral types need parameters: without the [[dihedral_type]] block the data file is refused.
  try {
    SimulationSpec bare = spec_with("");
    bare.dihedral_types.clear();
    Simulation sim(bare, RunOptions{});
    FAIL() << "a dihedral type without parameters was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dihedral"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("jittered.data"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

// --- statistics -----------------------------------------------------------------------------------

// Mean and standard error of a time series from 10 block means.
struct MeanError {
  double mean = 0, error = 0;
};
MeanError blocks(const std::vector<double>& series) {
  const std::size_t nb = 10, per = series.size() / nb;
  std::vector<double> means(nb, 0.0);
  for (std::size_t b = 0; b < nb; ++b) {
    for (std::size_t k = 0; k < per; ++k) means[b] += series[b * per + k];
    means[b] /= static_cast<double>(per);
  }
  MeanError out;
  for (double m : means) out.mean += m / nb;
  double var = 0;
  for (double m : means) var += (m - out.mean) * (m - out.mean);
  out.error = std::sqrt(var / (nb * (nb - 1)));
  return out;
}

// Ideal chains (no conservative pair force: a = 0; the DPD thermostat only): harmonic springs with
// rest length 0 give Gaussian chains, <b^2> = 3 kT / k and <R^2> = (N - 1) <b^2>, with the Gaussian
// ratio <R^4> / <R^2>^2 = 5/3.
TEST(BondStatistics, IdealHarmonicChainIsGaussian) {
  const std::string text = R"(
[system]
box = [7.0, 7.0, 7.0]
kT = 1.0
seed = 4242

[[species]]
name = "A"

[pair]
a = 0.0
gamma = 4.5

[[bond_type]]
name = "spring"
style = "harmonic"
k = 3.0

[[molecule]]
name = "chain"
sequence = "A8"
bond_type = "spring"
count = 100
bond_length = 0.9

[integrator]
dt = 0.02

[run]
steps = 100000

[output]
thermo_every = 100000
progress = false
)";
  const SimulationSpec spec = parse_config(text, "ideal.toml");
  Simulation sim(spec, RunOptions{});
  const double L = 7.0;
  std::vector<double> b2_series, r2_series, r4_series, temp_series;
  for (int s = 1; s <= 6000; ++s) {
    sim.step();
    if (s <= 500 || s % 10 != 0) continue;
    const ParticleData& p = sim.particles();
    std::vector<std::array<double, 3>> r(p.n_local + 1);
    double ke = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      r[p.id[i]] = {p.x[i] + p.ix[i] * L, p.y[i] + p.iy[i] * L, p.z[i] + p.iz[i] * L};
      ke += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    }
    temp_series.push_back(ke / (3.0 * static_cast<double>(p.n_local) - 3.0));
    double b2 = 0, r2 = 0, r4 = 0;
    for (const Bond& b : sim.topology().bonds)
      for (int d = 0; d < 3; ++d) b2 += std::pow(r[b.a][d] - r[b.b][d], 2);
    for (std::uint32_t c = 0; c < 100; ++c) {
      const std::uint32_t first = 1 + 8 * c, last = first + 7;
      double e2 = 0;
      for (int d = 0; d < 3; ++d) e2 += std::pow(r[last][d] - r[first][d], 2);
      r2 += e2;
      r4 += e2 * e2;
    }
    b2_series.push_back(b2 / 700.0);
    r2_series.push_back(r2 / 100.0);
    r4_series.push_back(r4 / 100.0);
  }
  const MeanError T = blocks(temp_series), b2 = blocks(b2_series), r2 = blocks(r2_series), r4 = blocks(r4_series);
  // The exact values at the measured kinetic temperature (dt = 0.02 keeps it within 1% of kT).
  EXPECT_NEAR(T.mean, 1.0, 0.02);
  const double b2_exact = 3.0 * T.mean / 3.0;
  EXPECT_NEAR(b2.mean, b2_exact, 4 * b2.error + 0.01) << "<b^2> = " << b2.mean << " +- " << b2.error;
  EXPECT_NEAR(r2.mean, 7.0 * b2_exact, 4 * r2.error + 0.07) << "<R^2> = " << r2.mean << " +- " << r2.error;
  EXPECT_NEAR(r4.mean / (r2.mean * r2.mean), 5.0 / 3.0, 0.08) << "<R^4>/<R^2>^2";
  std::printf("ideal chain N=8, k=3: T = %.4f +- %.4f, <b^2> = %.4f +- %.4f (exact %.4f), <R^2> = %.3f +- %.3f "
              "(exact %.3f), <R^4>/<R^2>^2 = %.3f (Gaussian 5/3)\n",
              T.mean, T.error, b2.mean, b2.error, b2_exact, r2.mean, r2.error, 7 * b2_exact,
              r4.mean / (r2.mean * r2.mean));
}

// An angle-only trimer (harmonic bonds, the cosine angle potential, no conservative pair force):
// the angle between the bond vectors follows P(cos theta) ~ exp(kappa cos theta), kappa = k / kT, so
// <cos theta> = coth(kappa) - 1 / kappa and the histogram of cos theta is that exponential.
TEST(BondStatistics, AngleOnlyTrimerFollowsBoltzmann) {
  const std::string text = R"(
[system]
box = [7.0, 7.0, 7.0]
kT = 1.0
seed = 777

[[species]]
name = "A"

[pair]
a = 0.0
gamma = 4.5

[[bond_type]]
name = "spring"
style = "harmonic"
k = 20.0
r0 = 0.5

[[angle_type]]
name = "bend"
k = 2.0

[[molecule]]
name = "trimer"
sequence = "A3"
bond_type = "spring"
angle_type = "bend"
count = 250
bond_length = 0.5

[integrator]
dt = 0.02

[run]
steps = 100000

[output]
thermo_every = 100000
progress = false
)";
  const SimulationSpec spec = parse_config(text, "trimer.toml");
  Simulation sim(spec, RunOptions{});
  constexpr int kBins = 8;
  std::vector<double> cos_series, temp_series;
  std::vector<std::vector<double>> hist_series(kBins);
  for (int s = 1; s <= 5000; ++s) {
    sim.step();
    if (s <= 500 || s % 10 != 0) continue;
    const ParticleData& p = sim.particles();
    std::vector<std::size_t> at(p.n_local + 1);
    double ke = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      at[p.id[i]] = i;
      ke += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    }
    temp_series.push_back(ke / (3.0 * static_cast<double>(p.n_local) - 3.0));
    double sum = 0;
    std::vector<double> h(kBins, 0.0);
    for (const Angle& a : sim.topology().angles) {
      double b1[3], b2[3];
      const std::size_t i = at[a.a], j = at[a.b], k = at[a.c];
      const double xi[3] = {p.x[i], p.y[i], p.z[i]}, xj[3] = {p.x[j], p.y[j], p.z[j]}, xk[3] = {p.x[k], p.y[k], p.z[k]};
      for (int d = 0; d < 3; ++d) {
        b1[d] = minimum_image(xj[d] - xi[d], 7.0, 3.5);
        b2[d] = minimum_image(xk[d] - xj[d], 7.0, 3.5);
      }
      const double c = (b1[0] * b2[0] + b1[1] * b2[1] + b1[2] * b2[2]) /
                       std::sqrt((b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2]) * (b2[0] * b2[0] + b2[1] * b2[1] + b2[2] * b2[2]));
      sum += c;
      h[static_cast<std::size_t>(std::min(kBins - 1, static_cast<int>((c + 1) / 2 * kBins)))] += 1.0 / 250.0;
    }
    cos_series.push_back(sum / 250.0);
    for (int b = 0; b < kBins; ++b) hist_series[static_cast<std::size_t>(b)].push_back(h[static_cast<std::size_t>(b)]);
  }
  // Compared at the measured kinetic temperature (the finite time step heats the stiff bonds ~2%).
  const MeanError T = blocks(temp_series);
  EXPECT_NEAR(T.mean, 1.0, 0.03);
  const double kappa = 2.0 / T.mean;
  std::printf("trimer: kinetic T = %.4f +- %.4f\n", T.mean, T.error);
  const MeanError c = blocks(cos_series);
  const double exact = 1.0 / std::tanh(kappa) - 1.0 / kappa;
  EXPECT_NEAR(c.mean, exact, 4 * c.error + 0.003) << "<cos theta> = " << c.mean << " +- " << c.error;
  std::printf("trimer k=2: <cos theta> = %.4f +- %.4f (Boltzmann %.4f)\n", c.mean, c.error, exact);
  // Bin probabilities of cos theta against the integral of kappa exp(kappa x) / (2 sinh kappa).
  for (int b = 0; b < kBins; ++b) {
    const double lo = -1 + 2.0 * b / kBins, hi = lo + 2.0 / kBins;
    const double expect = (std::exp(kappa * hi) - std::exp(kappa * lo)) / (2 * std::sinh(kappa));
    const MeanError m = blocks(hist_series[static_cast<std::size_t>(b)]);
    EXPECT_NEAR(m.mean, expect, 4 * m.error + 0.002) << "bin " << b;
    std::printf("  cos theta in [%5.2f, %5.2f): %.4f +- %.4f (Boltzmann %.4f)\n", lo, hi, m.mean, m.error, expect);
  }
}


// --- multiple time stepping (bonds.subcycles) ------------------------------------------------------

// Stiff chains (harmonic k = 1000, r0 = 0.5: the fastest chain mode has omega ~ 2 sqrt(2k) ~ 90, so
// omega dt ~ 3.6 at dt = 0.04, beyond velocity Verlet's limit of 2) in a solvent.
std::string stiff_config(double dt, int subcycles) {
  return fmt::format(R"(
[system]
box = [6.0, 6.0, 6.0]
kT = 1.0
seed = 7

[[species]]
name = "A"

[[species]]
name = "W"
density = 2.2

[pair]
a = 25.0
gamma = 4.5

[[bond_type]]
name = "stiff"
style = "harmonic"
k = 1000.0
r0 = 0.5

[[molecule]]
name = "chain"
sequence = "A10"
bond_type = "stiff"
count = 16
bond_length = 0.5

[bonds]
subcycles = {1}

[integrator]
dt = {0}

[run]
steps = 100000

[output]
thermo_every = 100000
progress = false
)",
                     dt, subcycles);
}

struct StiffStats {
  MeanError temperature, bond, bond_sd;
};

// Runs `time` time units after 10 of equilibration, sampling every 0.2: kinetic temperature, mean
// bond length and the standard deviation of the bond length.
StiffStats run_stiff(double dt, int subcycles, double time) {
  Simulation sim(parse_config(stiff_config(dt, subcycles), "stiff.toml"), RunOptions{});
  const auto skip = static_cast<int>(std::lround(10.0 / dt)), steps = static_cast<int>(std::lround(time / dt));
  const auto every = static_cast<int>(std::lround(0.2 / dt));
  const double L = 6.0;
  std::vector<double> t_series, b_series, sd_series;
  for (int s = 1; s <= skip + steps; ++s) {
    sim.step();
    if (s <= skip || s % every != 0) continue;
    const ParticleData& p = sim.particles();
    std::vector<std::array<double, 3>> r(p.n_local + 1);
    double ke = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      r[p.id[i]] = {p.x[i] + p.ix[i] * L, p.y[i] + p.iy[i] * L, p.z[i] + p.iz[i] * L};
      ke += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    }
    t_series.push_back(ke / (3.0 * static_cast<double>(p.n_local) - 3.0));
    double sum = 0, sum2 = 0;
    for (const Bond& b : sim.topology().bonds) {
      double d2 = 0;
      for (int d = 0; d < 3; ++d) d2 += std::pow(r[b.a][d] - r[b.b][d], 2);
      sum += std::sqrt(d2);
      sum2 += d2;
    }
    const double nb = static_cast<double>(sim.topology().bonds.size());
    b_series.push_back(sum / nb);
    sd_series.push_back(std::sqrt(std::max(0.0, sum2 / nb - (sum / nb) * (sum / nb))));
  }
  return {blocks(t_series), blocks(b_series), blocks(sd_series)};
}

// The issue's test of multiple time stepping: a chain too stiff for dt = 0.04 with one step per bond
// evaluation blows up; with 10 inner steps it runs stably with the temperature and bond-length
// distribution of a reference at dt = 0.004.
TEST(Subcycling, StiffChainUnstableAtDt004RunsWithInnerStepsLikeASmallStepReference) {
  {
    Simulation sim(parse_config(stiff_config(0.04, 1), "stiff.toml"), RunOptions{});
    bool blew_up = false;
    try {
      for (int s = 0; s < 1000; ++s) sim.step();
    } catch (const BlowUpError&) {
      blew_up = true;
    }
    EXPECT_TRUE(blew_up) << "dt = 0.04 without subcycles should be unstable for k = 1000";
  }
  const StiffStats mts = run_stiff(0.04, 10, 60.0);
  const StiffStats ref = run_stiff(0.004, 1, 30.0);
  std::printf("stiff chains k = 1000: dt = 0.04 x 10 inner steps: T = %.4f +- %.4f, <b> = %.5f +- %.5f, sd(b) = %.5f +- "
              "%.5f; dt = 0.004: T = %.4f +- %.4f, <b> = %.5f +- %.5f, sd(b) = %.5f +- %.5f\n",
              mts.temperature.mean, mts.temperature.error, mts.bond.mean, mts.bond.error, mts.bond_sd.mean,
              mts.bond_sd.error, ref.temperature.mean, ref.temperature.error, ref.bond.mean, ref.bond.error,
              ref.bond_sd.mean, ref.bond_sd.error);
  // Standard DPD at dt = 0.04 runs 1-3% hot (seed 000 Sect. 2.5.2); the bonds must add nothing visible.
  EXPECT_NEAR(mts.temperature.mean, ref.temperature.mean, 0.035);
  const double eb = std::hypot(mts.bond.error, ref.bond.error), es = std::hypot(mts.bond_sd.error, ref.bond_sd.error);
  EXPECT_NEAR(mts.bond.mean, ref.bond.mean, 4 * eb + 0.002);
  // The width of the bond-length distribution (sqrt(kT/k) ~ 0.032) within 5%.
  EXPECT_NEAR(mts.bond_sd.mean / ref.bond_sd.mean, 1.0, 0.05 + 4 * es / ref.bond_sd.mean);
}

TEST(Subcycling, ThreadsAndRestartGiveTheSameBits) {
  SimulationSpec spec = chains_spec("[bonds]\nsubcycles = 4\nexclude = \"1-2\"\n");
  ASSERT_EQ(spec.bond_subcycles, 4);
  EXPECT_EQ(positions_after(spec, 1, 60), positions_after(spec, 2, 60));
  // Subcycling changes the trajectory (the test above would be empty otherwise).
  SimulationSpec one = spec;
  one.bond_subcycles = 1;
  EXPECT_NE(positions_after(spec, 1, 20), positions_after(one, 1, 20));
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_subcycling_restart";
  fs::remove_all(dir);
  {
    RunOptions o;
    o.out_dir = dir / "whole";
    o.steps = 60;
    Simulation(spec, o).run();
  }
  {
    RunOptions o;
    o.out_dir = dir / "part";
    o.steps = 30;
    Simulation(spec, o).run();
  }
  {
    RunOptions o;
    o.out_dir = dir / "part";
    o.steps = 60;
    o.restart = dir / "part" / "checkpoint30.mdpd";
    fs::copy_file(dir / "part" / "checkpoint.mdpd", o.restart);
    Simulation(spec, o).run();
  }
  EXPECT_TRUE(test::read_file(dir / "whole" / "checkpoint.mdpd") == test::read_file(dir / "part" / "checkpoint.mdpd"));
  EXPECT_EQ(test::read_file(dir / "whole" / "thermo.csv"), test::read_file(dir / "part" / "thermo.csv"));
  fs::remove_all(dir);
}

TEST(Subcycling, ConfigErrorsNameTheKey) {
  auto error = [](const std::string& extra) {
    try {
      chains_spec(extra);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string m = error("[bonds]\nsubcycles = 0\n");
  EXPECT_NE(m.find("bonds.subcycles"), std::string::npos) << m;
  SimulationSpec spec = chains_spec("[bonds]\nsubcycles = 4\n");
  spec.integrator = IntegratorKind::Euler;
  try {
    validate(spec);
    m = "no error";
  } catch (const ConfigError& e) {
    m = e.what();
  }
  EXPECT_NE(m.find("bonds.subcycles"), std::string::npos) << m;
  EXPECT_NE(m.find("euler"), std::string::npos) << m;

}

// --- molecules between walls ----------------------------------------------------------------------

// Chains placed in a channel between two frozen plates: every bead starts at least 0.5 away from the
// walls (and its bond's midpoint outside them), and no bead is inside a wall after 300 steps of flow.
TEST(BondedWalls, ChainsArePlacedInTheFluidAndStayThere) {
  const std::string text = R"(
[system]
box = [8.0, 8.0, 10.0]
periodic = [true, true, false]
kT = 1.0
seed = 5

[[species]]
name = "W"
density = 3.0
body_force = [0.05, 0.0, 0.0]

[[species]]
name = "P"
body_force = [0.05, 0.0, 0.0]

[[species]]
name = "wall"
frozen = true

[[solid]]
name = "bottom"
species = "wall"
shape = "plane"
point = [0, 0, 1]
normal = [0, 0, 1]

[[solid]]
name = "top"
species = "wall"
shape = "plane"
point = [0, 0, 9]
normal = [0, 0, -1]

[pair]
a = 25.0
gamma = 4.5

[[bond_type]]
name = "spring"
style = "harmonic"
k = 20.0
r0 = 0.7

[[molecule]]
name = "chain"
sequence = "P12"
bond_type = "spring"
count = 12
bond_length = 0.7

[integrator]
dt = 0.02

[run]
steps = 300

[output]
thermo_every = 100
progress = false
)";
  const SimulationSpec spec = parse_config(text, "chains_in_channel.toml");
  // Subcycled bonds are refused with walls (the reflections predict a whole step's move).
  try {
    parse_config(text + "\n[bonds]\nsubcycles = 4\n", "chains_in_channel.toml");
    ADD_FAILURE() << "bonds.subcycles with walls accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bonds.subcycles"), std::string::npos) << e.what();
  }
  Simulation sim(spec, RunOptions{});
  ASSERT_EQ(sim.topology().bonds.size(), 12u * 11u);
  auto bead_heights = [&] {
    std::vector<double> z;
    const ParticleData& p = sim.particles();
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.mol[i] > 0) z.push_back(p.z[i]);
    return z;
  };
  std::vector<double> z0 = bead_heights();
  ASSERT_EQ(z0.size(), 144u);
  for (double z : z0) {
    EXPECT_GT(z, 1.5);
    EXPECT_LT(z, 8.5);
  }
  for (int s = 0; s < 300; ++s) sim.step();
  for (double z : bead_heights()) {
    EXPECT_GT(z, 1.0);
    EXPECT_LT(z, 9.0);
  }
  // The molecules are carried by the flow: after 6 time units under g = 0.05 (free acceleration would
  // give 0.3, the walls slow the fluid near them) the beads' mean velocity along x is well positive.
  double vx = 0;
  const ParticleData& p = sim.particles();
  for (std::size_t i = 0; i < p.n_local; ++i)
    if (p.mol[i] > 0) vx += p.vx[i] / 144.0;
  EXPECT_GT(vx, 0.1);
  std::printf("chains in a channel: mean bead vx after 300 steps %.3f\n", vx);
}

}  // namespace
}  // namespace mesodpd
