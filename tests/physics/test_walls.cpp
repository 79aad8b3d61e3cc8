// Tests of frozen-particle walls: how the walls are built, the pair loop against the reference loop
// with frozen particles (frozen-frozen pairs skipped), frozen particles not integrated and left out of
// the temperature, reflections (no particle ends a step inside a solid), moving walls, and the drag
// (sign, and the momentum balance of a driven channel in steady state).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "analysis/wall_drag.hpp"
#include "boundary/walls.hpp"
#include "engine/pair_laws.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

// A channel between plates at z = 1 and z = 7 (bounded z), with a cylinder across y between them.
std::string channel(const std::string& extra, const std::string& walls = "", double g = 0.0) {
  return R"(
[system]
box = [8, 5, 8]
periodic = [true, true, false]
seed = 11
[[species]]
name = "fluid"
density = 3
body_force = [)" +
         std::to_string(g) + R"(, 0, 0]
[[species]]
name = "wall"
frozen = true
[pair]
a = 25
gamma = 4.5
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
point = [0, 0, 7]
normal = [0, 0, -1]
)" + extra + "\n[walls]\n" +
         walls + "\n[output]\nprogress = false\n";
}

const char* kPillar = R"(
[[solid]]
name = "pillar"
species = "wall"
shape = "cylinder"
center = [4, 2.5, 4]
direction = [0, 1, 0]
radius = 1.2
)";

SimulationSpec spec_of(const std::string& text) { return parse_config(text, "walls_test.toml"); }

TEST(Walls, FrozenShellIsBuiltFromTheFluidAndNothingDeeper) {
  const SimulationSpec spec = spec_of(channel(kPillar));
  Simulation sim(spec, RunOptions{});
  const ParticleData& p = sim.particles();
  const Geometry& geo = sim.walls()->geometry();
  std::size_t frozen = 0, fluid = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    int b = -1;
    const double d = geo.sdf(Vec3{p.x[i], p.y[i], p.z[i]}, b);
    if (p.body[i] != 0) {
      ++frozen;
      EXPECT_EQ(p.species[i], 1);
      EXPECT_EQ(p.body[i], b + 1) << "frozen particle in the wrong body";
      EXPECT_LT(d, 0.0);
      EXPECT_GE(d, -spec.walls.depth);
      EXPECT_EQ(p.vx[i], 0.0);
    } else {
      ++fluid;
      EXPECT_EQ(p.species[i], 0);
      EXPECT_GE(d, 0.0) << "fluid particle inside a solid at start";
    }
  }
  // Ids are consecutive (1..N) and N is what the spec's density gives minus the particles left out.
  EXPECT_EQ(sim.total_particles(), p.n_local);
  // The walls are 1 thick (the whole solid here): frozen density equals the fluid's, within noise.
  const double fluid_volume = 8.0 * 5.0 * 6.0 - M_PI * 1.2 * 1.2 * 5.0;
  const double solid_volume = 8.0 * 5.0 * 2.0 + M_PI * (1.2 * 1.2 - 0.2 * 0.2) * 5.0;
  EXPECT_NEAR(static_cast<double>(fluid) / fluid_volume, 3.0, 0.25);
  EXPECT_NEAR(static_cast<double>(frozen) / solid_volume, 3.0, 0.3);
}

// Frozen particles cut from an equilibrated fluid (walls.equilibrate, seed 000 Sect. 3.2.2) keep its
// structure: few close pairs, where walls cut from the initial random (ideal-gas) placement have as many
// as an ideal gas. Counted over frozen-frozen pairs closer than 0.3, minimum image along x and y.
std::size_t close_frozen_pairs(const ParticleData& p, const Box& box) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.n_local; ++i)
    for (std::size_t j = i + 1; j < p.n_local; ++j) {
      if (p.body[i] == 0 || p.body[j] == 0) continue;
      double dx = p.x[i] - p.x[j], dy = p.y[i] - p.y[j];
      const double dz = p.z[i] - p.z[j];
      dx -= box.len.x * std::round(dx / box.len.x);
      dy -= box.len.y * std::round(dy / box.len.y);
      n += dx * dx + dy * dy + dz * dz < 0.09 ? 1 : 0;
    }
  return n;
}

TEST(Walls, EquilibrationBeforeFreezingGivesTheWallsTheFluidsStructure) {
  Simulation drawn(spec_of(channel(kPillar)), RunOptions{});
  Simulation equilibrated(spec_of(channel(kPillar, "equilibrate = 150")), RunOptions{});
  const ParticleData &a = drawn.particles(), &b = equilibrated.particles();
  std::size_t frozen_a = 0, frozen_b = 0;
  for (std::size_t i = 0; i < a.n_local; ++i) frozen_a += a.body[i] != 0 ? 1 : 0;
  for (std::size_t i = 0; i < b.n_local; ++i) frozen_b += b.body[i] != 0 ? 1 : 0;
  // Ideal gas: each particle has 3 x 4/3 pi 0.3^3 = 0.34 neighbours closer than 0.3 (fewer at the
  // plates' outer faces).
  const double per_particle_a = 2.0 * static_cast<double>(close_frozen_pairs(a, drawn.box())) / static_cast<double>(frozen_a);
  const double per_particle_b =
      2.0 * static_cast<double>(close_frozen_pairs(b, equilibrated.box())) / static_cast<double>(frozen_b);
  EXPECT_GT(per_particle_a, 0.2);
  EXPECT_LT(per_particle_b, 0.25 * per_particle_a) << "drawn " << per_particle_a << ", equilibrated " << per_particle_b;
  // The same wall thickness and density, and no fluid inside a solid.
  EXPECT_NEAR(static_cast<double>(frozen_b) / static_cast<double>(frozen_a), 1.0, 0.1);
  const Geometry& geo = equilibrated.walls()->geometry();
  for (std::size_t i = 0; i < b.n_local; ++i) {
    if (b.body[i] == 0) {
      EXPECT_GE(geo.sdf(Vec3{b.x[i], b.y[i], b.z[i]}), 0.0);
    }
  }
}

TEST(Walls, SpeciesRegionKeepsItsFluidInsideAndTheWholeWall) {
  // examples/wetting: the fluid is kept only inside its region (here a ball in the channel), but the
  // walls are built from the whole box's draws as without a region, so they are the same.
  std::string with_region = channel(kPillar);
  const std::string at = "density = 3\n";
  with_region.replace(with_region.find(at), at.size(), at + "region = {shape = \"sphere\", center = [0, 2.5, 4], radius = 1.8}\n");
  const SimulationSpec plain = spec_of(channel(kPillar)), spec = spec_of(with_region);
  Simulation a(plain, RunOptions{}), b(spec, RunOptions{});
  const ParticleData &p = a.particles(), &q = b.particles();
  std::vector<std::array<double, 3>> wall_a, wall_b;
  std::size_t fluid = 0;
  std::vector<std::uint32_t> ids;
  for (std::size_t i = 0; i < p.n_local; ++i)
    if (p.body[i] != 0) wall_a.push_back({p.x[i], p.y[i], p.z[i]});
  for (std::size_t i = 0; i < q.n_local; ++i) {
    ids.push_back(q.id[i]);
    if (q.body[i] != 0) {
      wall_b.push_back({q.x[i], q.y[i], q.z[i]});
    } else {
      ++fluid;
      const double dx = std::min(q.x[i], 8.0 - q.x[i]);  // nearest periodic image of the centre x = 0
      EXPECT_LT(std::hypot(dx, q.y[i] - 2.5, q.z[i] - 4), 1.8) << "fluid particle outside its region";
    }
  }
  // Ids are consecutive (1..N) in any order (the particles are sorted by cell).
  std::sort(ids.begin(), ids.end());
  for (std::size_t k = 0; k < ids.size(); ++k) ASSERT_EQ(ids[k], k + 1);
  std::sort(wall_a.begin(), wall_a.end());
  std::sort(wall_b.begin(), wall_b.end());
  EXPECT_EQ(wall_a, wall_b);
  // The ball (across the periodic face x = 0, clear of the plates and the pillar) holds density 3:
  // its count within 4 Poisson standard deviations.
  const double expected = 3.0 * 4 * M_PI / 3 * 1.8 * 1.8 * 1.8;
  EXPECT_NEAR(static_cast<double>(fluid), expected, 4 * std::sqrt(expected));
  EXPECT_EQ(b.total_particles(), q.n_local);
}

TEST(Walls, PairLoopSkipsFrozenPairsAndEqualsTheReferenceLoop) {
  for (const char* method : {"cells", "verlet"}) {
    SimulationSpec spec = spec_of(channel(kPillar) + "[neighbor]\nmethod = \"" + method + "\"\n");
    Simulation sim(spec, RunOptions{});
    std::vector<std::array<double, 3>> f;
    PairSums sums;
    reference_forces(sim.particles(), sim.box(), make_pair_laws(spec), NoiseSettings{spec.seed, NoiseKind::Uniform}, 0,
                     spec.dt, f, sums);
    const ParticleData& p = sim.particles();
    std::size_t checked_frozen = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      ASSERT_EQ(p.fx[i], f[i][0]) << method << " particle " << p.id[i];
      ASSERT_EQ(p.fy[i], f[i][1]) << method;
      ASSERT_EQ(p.fz[i], f[i][2]) << method;
      checked_frozen += p.body[i] != 0 ? 1 : 0;
    }
    EXPECT_GT(checked_frozen, 100u);
  }
}

// Checks at the end of every step that no mobile particle is inside a solid and that frozen particles
// move only with their wall.
class InsideCheck final : public Stage {
 public:
  explicit InsideCheck(const Walls& w) : walls_(w) {}
  void run(StepContext& ctx) override {
    const ParticleData& p = ctx.particles;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      if (p.body[i] != 0) continue;
      const double d = walls_.geometry().sdf(Vec3{p.x[i], p.y[i], p.z[i]});
      if (d < 0) ++inside;
      min_d = std::min(min_d, d);
    }
  }
  const Walls& walls_;
  std::uint64_t inside = 0;
  double min_d = 1e9;
};

TEST(Walls, NoParticleEndsAStepInsideASolidForEveryReflection) {
  for (const char* kind : {"bounce_back", "specular", "maxwell"}) {
    SimulationSpec spec = spec_of(channel(kPillar, std::string("reflection = \"") + kind + "\"", 0.02));
    Simulation sim(spec, RunOptions{});
    auto& check = sim.add_stage(StagePoint::EndOfStep, std::make_unique<InsideCheck>(*sim.walls()));
    std::vector<double> x0;
    const ParticleData& p = sim.particles();
    double frozen_x = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.body[i] != 0) frozen_x += p.x[i] + p.y[i] + p.z[i];
    for (int s = 0; s < 300; ++s) sim.step();
    EXPECT_EQ(check.inside, 0u) << kind;
    EXPECT_GE(check.min_d, 0.0) << kind;
    const auto counts = sim.walls()->take_counts(sim.halo().comm());
    EXPECT_GT(counts[0], 1000u) << kind << ": reflections";
    // The reflection sees the next move coming (fast particles outside the layer included), so no
    // particle ever crosses a surface and the mirror after the position update finds none.
    EXPECT_EQ(counts[1], 0u) << kind << ": penetrations";
    double frozen_x1 = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.body[i] != 0) frozen_x1 += p.x[i] + p.y[i] + p.z[i];
    EXPECT_EQ(frozen_x, frozen_x1) << kind << ": frozen particles moved";
  }
}

// Gives one particle a kick towards the bottom wall at one step: a move of several times the layer,
// from a cell far from every surface (the case that forbids skipping cells by position alone).
class Kick final : public Stage {
 public:
  Kick(std::uint32_t id, std::uint64_t at) : id_(id), at_(at) {}
  void run(StepContext& ctx) override {
    if (ctx.step != at_) return;
    ParticleData& p = ctx.particles;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.id[i] == id_) p.fz[i] -= 2500.0;  // dv = -dt f / 2 = -50 at dt = 0.04: a move of -2 per step
  }
  std::uint32_t id_;
  std::uint64_t at_;
};

TEST(Walls, SkippingFarCellsChangesNothing) {
  // The reflection and mirror passes skip whole cells far from every surface (by the cell order of the
  // neighbour build and the longest move of any particle); with and without the skip the runs must be
  // bit-identical, with cell pairs and with a Verlet list (cells widened by half the skin), including
  // a particle kicked hard towards a wall from the middle of the channel. A wider, taller channel than
  // the others here, so that some cells are far from every surface.
  std::string text = channel(kPillar, "reflection = \"maxwell\"", 0.05);
  text.replace(text.find("box = [8, 5, 8]"), 15, "box = [16, 5, 12]");
  text.replace(text.find("point = [0, 0, 7]"), 17, "point = [0, 0, 11]");
  for (const char* neighbor : {"", "[neighbor]\nmethod = \"verlet\"\nskin = 0.3\n"}) {
    const SimulationSpec spec = spec_of(text + neighbor);
    Simulation skip(spec, RunOptions{}), all(spec, RunOptions{});
    all.walls()->set_cell_skip(false);
    // A mobile particle at least 3 from every surface, kicked at step 40.
    std::uint32_t kicked = 0;
    bool found = false;
    {
      const ParticleData& p = skip.particles();
      for (std::size_t i = 0; i < p.n_local && !found; ++i)
        if (p.body[i] == 0 && skip.walls()->geometry().sdf(Vec3{p.x[i], p.y[i], p.z[i]}) > 3.0) {
          kicked = p.id[i];
          found = true;
        }
    }
    ASSERT_TRUE(found);
    skip.add_stage(StagePoint::Forces, std::make_unique<Kick>(kicked, 40));
    all.add_stage(StagePoint::Forces, std::make_unique<Kick>(kicked, 40));
    std::size_t mobile = 0;
    for (std::size_t i = 0; i < skip.particles().n_local; ++i) mobile += skip.particles().body[i] == 0 ? 1 : 0;
    std::uint64_t examined_skip = 0, examined_all = 0;
    int skipped_nothing = 0;  // steps at which the skip run's reflection looked at every particle
    for (int s = 0; s < 80; ++s) {
      skip.step();
      all.step();
      examined_skip += skip.walls()->examined();
      examined_all += all.walls()->examined();
      skipped_nothing += skip.walls()->examined() == mobile ? 1 : 0;
    }
    const ParticleData &a = skip.particles(), &b = all.particles();
    ASSERT_EQ(a.n_local, b.n_local);
    for (std::size_t i = 0; i < a.n_local; ++i) {
      ASSERT_EQ(a.id[i], b.id[i]) << neighbor;
      ASSERT_EQ(a.x[i], b.x[i]) << neighbor;
      ASSERT_EQ(a.z[i], b.z[i]) << neighbor;
      ASSERT_EQ(a.vx[i], b.vx[i]) << neighbor;
      ASSERT_EQ(a.vz[i], b.vz[i]) << neighbor;
    }
    const auto ca = skip.walls()->take_counts(skip.halo().comm()), cb = all.walls()->take_counts(all.halo().comm());
    EXPECT_EQ(ca, cb) << neighbor;
    EXPECT_GT(ca[0], 1000u) << neighbor << ": reflections";
    EXPECT_EQ(ca[1], 0u) << neighbor << ": penetrations";
    // Without the skip every mobile particle is looked at; with it a good part of them is left out
    // (measured: 54% of them looked at with cell pairs, 78% with the wider Verlet cells), except while
    // the kicked particle's long move makes every cell reachable (1-2 steps).
    EXPECT_EQ(all.walls()->examined(), mobile) << neighbor;
    EXPECT_LT(examined_skip, examined_all * 9 / 10) << neighbor;
    EXPECT_GE(skipped_nothing, 1) << neighbor << ": the kick did not reach the skip";
    EXPECT_LE(skipped_nothing, 5) << neighbor;
  }
}

TEST(Walls, FrozenParticlesAreLeftOutOfTheTemperature) {
  // Only the fluid has kinetic energy at start (frozen velocities are 0), and Maxwell velocities are
  // rescaled to exactly kT over the fluid's 3N - 3 degrees of freedom.
  Simulation sim(spec_of(channel("")), RunOptions{});
  EXPECT_NEAR(sim.thermo().temperature, 1.0, 1e-12);
  // A moving wall's particles move with it and nothing else.
  std::string text = channel("");
  text.insert(text.find("normal = [0, 0, -1]") + 19, "\nvelocity = [0.3, 0, 0]");
  Simulation couette(spec_of(text), RunOptions{});
  for (int s = 0; s < 50; ++s) couette.step();
  const ParticleData& p = couette.particles();
  std::size_t moving = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.body[i] == 2) {
      ++moving;
      ASSERT_EQ(p.vx[i], 0.3);
      ASSERT_EQ(p.vz[i], 0.0);
    }
    if (p.body[i] == 1) {
      ASSERT_EQ(p.vx[i], 0.0);
    }
  }
  EXPECT_GT(moving, 100u);
}

TEST(Walls, DragOnTheWallsBalancesTheBodyForceInSteadyState) {
  // Fluid driven along x by g between plates: in steady state the walls take the whole body force,
  // N_fluid m g, and the drag on each points along the flow.
  const double g = 0.02;
  SimulationSpec spec = spec_of(channel("", "drag_start = 1000\ndrag_every = 2\ndrag_blocks = 8", g));
  spec.steps = 3000;
  Simulation sim(spec, RunOptions{});
  std::uint64_t fluid = 0;
  for (std::size_t i = 0; i < sim.particles().n_local; ++i) fluid += sim.particles().body[i] == 0 ? 1 : 0;
  sim.run();
  const auto drag = sim.component<WallDrag>()->results();
  ASSERT_EQ(drag.size(), 2u);
  const double total = drag[0].force[0] + drag[1].force[0];
  const double error = std::hypot(drag[0].error[0], drag[1].error[0]);
  const double expected = static_cast<double>(fluid) * g;
  EXPECT_GT(drag[0].force[0], 0.0);
  EXPECT_GT(drag[1].force[0], 0.0);
  EXPECT_GT(drag[0].fluid_velocity[0], 0.0);
  EXPECT_LT(std::abs(total - expected), 3 * error + 0.02 * expected)
      << "walls take " << total << " +- " << error << ", body force " << expected;
  EXPECT_GT(error, 0.0);
  EXPECT_EQ(drag[0].samples, 1000u);
  // Normal forces of the two walls balance each other (the fluid pushes both outwards).
  EXPECT_LT(drag[0].force[2], 0.0);
  EXPECT_GT(drag[1].force[2], 0.0);
}

// Bins the fluid's x velocity along z at the end of every step after `start`.
class ProfileSampler final : public Stage {
 public:
  ProfileSampler(double lz, double bin, std::uint64_t start)
      : bin_(bin), start_(start), sum(static_cast<std::size_t>(std::lround(lz / bin)), 0.0), count(sum.size(), 0.0) {}
  void run(StepContext& ctx) override {
    if (ctx.step <= start_) return;
    const ParticleData& p = ctx.particles;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      if (p.body[i] != 0) continue;
      const auto k = std::min(sum.size() - 1, static_cast<std::size_t>(p.z[i] / bin_));
      sum[k] += p.vx[i];
      count[k] += 1;
    }
    ++samples;
  }
  double bin_;
  std::uint64_t start_;
  std::vector<double> sum, count;
  std::uint64_t samples = 0;
};

// Least-squares parabola u = c0 + c1 z + c2 z^2 through (z, u) weighted by w.
std::array<double, 3> fit_parabola(const std::vector<double>& z, const std::vector<double>& u, const std::vector<double>& w) {
  double a[3][4] = {};
  for (std::size_t k = 0; k < z.size(); ++k) {
    const double p[3] = {1, z[k], z[k] * z[k]};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) a[r][c] += w[k] * p[r] * p[c];
      a[r][3] += w[k] * p[r] * u[k];
    }
  }
  for (int c = 0; c < 3; ++c)
    for (int r = c + 1; r < 3; ++r) {
      const double f = a[r][c] / a[c][c];
      for (int q = c; q < 4; ++q) a[r][q] -= f * a[c][q];
    }
  std::array<double, 3> x{};
  for (int r = 2; r >= 0; --r) {
    double v = a[r][3];
    for (int q = r + 1; q < 3; ++q) v -= a[r][q] * x[static_cast<std::size_t>(q)];
    x[static_cast<std::size_t>(r)] = v / a[r][r];
  }
  return x;
}

TEST(Walls, ShortChannelGivesTheReversePoiseuilleViscosityAndNoSlip) {
  // The short version of examples/channel (docs/validation.md "Walls"): the standard fluid driven by
  // g = 0.04 between bounce-back frozen walls at z = 1 and 9. The parabola fitted more than 1 r_c from
  // the walls gives eta = rho g / (-u''), which must match the reverse-Poiseuille value of this fluid
  // (0.867 +- 0.003, examples/poiseuille) within 8% here (the example reaches 3% with 10x more data;
  // the statistical error of this run is about 2-3%), and the parabola must reach zero within 0.25 of
  // each wall (the example: < 0.1).
  std::string text = channel("", "", 0.04);
  text.replace(text.find("box = [8, 5, 8]"), 15, "box = [8, 4, 10]");
  text.replace(text.find("point = [0, 0, 7]"), 17, "point = [0, 0, 9]");
  SimulationSpec spec = spec_of(text);
  Simulation sim(spec, RunOptions{});
  auto& prof = sim.add_stage(StagePoint::EndOfStep, std::make_unique<ProfileSampler>(10.0, 0.25, 1200));
  for (int s = 0; s < 4500; ++s) sim.step();
  std::vector<double> z, u, w;
  double n_interior = 0, bins_interior = 0;
  for (std::size_t k = 0; k < prof.sum.size(); ++k) {
    const double zc = (static_cast<double>(k) + 0.5) * 0.25;
    if (zc < 2.0 || zc > 8.0 || prof.count[k] == 0) continue;
    z.push_back(zc);
    u.push_back(prof.sum[k] / prof.count[k]);
    w.push_back(prof.count[k]);
    n_interior += prof.count[k];
    bins_interior += 1;
  }
  const double rho = n_interior / (static_cast<double>(prof.samples) * bins_interior * 8.0 * 4.0 * 0.25);
  const auto c = fit_parabola(z, u, w);
  const double eta = -rho * 0.04 / (2 * c[2]);
  const double disc = std::sqrt(c[1] * c[1] - 4 * c[2] * c[0]);
  const double z0 = std::min((-c[1] + disc) / (2 * c[2]), (-c[1] - disc) / (2 * c[2]));
  const double z1 = std::max((-c[1] + disc) / (2 * c[2]), (-c[1] - disc) / (2 * c[2]));
  EXPECT_NEAR(rho, 3.0, 0.1);
  EXPECT_NEAR(eta / 0.867, 1.0, 0.08) << "eta " << eta;
  EXPECT_NEAR(z0, 1.0, 0.25) << "slip at the bottom wall";
  EXPECT_NEAR(z1, 9.0, 0.25) << "slip at the top wall";
}

// Histogram of the fluid's z coordinate (bins of 0.1) at the end of every step after `start`.
class DensitySampler final : public Stage {
 public:
  DensitySampler(double lz, std::uint64_t start) : start_(start), count(static_cast<std::size_t>(std::lround(lz * 10)), 0) {}
  void run(StepContext& ctx) override {
    if (ctx.step <= start_) return;
    const ParticleData& p = ctx.particles;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.body[i] == 0) ++count[std::min(count.size() - 1, static_cast<std::size_t>(p.z[i] * 10))];
  }
  // Mean count per 0.1 bin over [z0, z1).
  double mean(double z0, double z1) const {
    double c = 0, n = 0;
    for (std::size_t k = static_cast<std::size_t>(std::lround(z0 * 10)); k < static_cast<std::size_t>(std::lround(z1 * 10)); ++k)
      c += static_cast<double>(count[k]), n += 1;
    return c / n;
  }
  std::uint64_t start_;
  std::vector<std::uint64_t> count;
};

TEST(Walls, AdaptiveForceFlattensTheNearWallDensity) {
  // The channel between plates at z = 1 and 7 with bounce-back walls: beyond the reflecting layer the
  // fluid piles up against the frozen walls (+10% to +45% in the first 0.2, different at the two walls:
  // their random frozen structures differ, hence bins per solid). With the adaptive force
  // (updates every 50 steps) the density from the layer (0.1) to 1 r_c from each wall must come
  // within 5% of the bulk (z in [2.5, 5.5]) in 0.2-wide bins, averaged over steps 2500-4000.
  double worst[2] = {0, 0};
  for (const bool adaptive : {false, true}) {
    SimulationSpec spec = spec_of(channel("", adaptive ? "adaptive = true\nadaptive_every = 50" : ""));
    Simulation sim(spec, RunOptions{});
    auto& hist = sim.add_stage(StagePoint::EndOfStep, std::make_unique<DensitySampler>(8.0, 2500));
    for (int s = 0; s < 4000; ++s) sim.step();
    const double bulk = hist.mean(2.5, 5.5);
    for (double z = 1.1; z < 1.85; z += 0.2) {
      const double lo = hist.mean(z, z + 0.2) / bulk - 1, hi = hist.mean(8 - z - 0.2, 8 - z) / bulk - 1;
      worst[adaptive] = std::max({worst[adaptive], std::abs(lo), std::abs(hi)});
      std::printf("%s: z %.1f-%.1f from the wall: %+.3f (bottom) %+.3f (top)\n", adaptive ? "adaptive" : "plain",
                  z - 1, z - 0.8, lo, hi);
    }
    if (adaptive) {
      ASSERT_EQ(sim.walls()->adaptive_density().size(), 20u);  // 10 bins for each plate
      EXPECT_GT(sim.walls()->adaptive_potential()[0], 0.0) << "the pile-up needs a push away from the wall";
      EXPECT_GT(sim.walls()->adaptive_potential()[10], 0.0) << "the pile-up needs a push away from the wall";
    }
  }
  EXPECT_GT(worst[0], 0.1) << "without the adaptive force the near-wall density is not flat";
  EXPECT_LT(worst[1], 0.05) << "with the adaptive force: largest deviation " << worst[1];
}

TEST(Walls, RestartContinuesDragAveragesAndAdaptiveForceByteForByte) {
  // A driven channel with a pillar, Maxwellian walls and the adaptive force, interrupted at step 150
  // and restarted: the drag averages (drag_summary.csv), the adaptive potentials (adaptive.csv), thermo
  // and the final checkpoint equal those of the uninterrupted 400-step run byte for byte.
  SimulationSpec spec = spec_of(channel(kPillar,
                                        "reflection = \"maxwell\"\ndrag_start = 20\ndrag_every = 3\ndrag_blocks = 4\n"
                                        "adaptive = true\nadaptive_every = 20",
                                        0.05));
  spec.thermo_every = 50;
  const auto dir = std::filesystem::temp_directory_path() / "walls_restart";
  std::filesystem::remove_all(dir);
  RunOptions whole;
  whole.out_dir = dir / "whole";
  whole.steps = 400;
  Simulation(spec, whole).run();
  RunOptions first = whole;
  first.out_dir = dir / "split";
  first.steps = 150;
  Simulation(spec, first).run();
  RunOptions second = first;
  second.steps = 400;
  second.restart = first.out_dir / "checkpoint.mdpd";
  Simulation restarted(spec, second);
  restarted.run();
  for (const char* f : {"drag_summary.csv", "drag.csv", "adaptive.csv", "thermo.csv", "checkpoint.mdpd"}) {
    const std::string a = test::read_file(whole.out_dir / f);
    ASSERT_GT(a.size(), 100u) << f;
    EXPECT_TRUE(a == test::read_file(first.out_dir / f)) << f << " differs after a restart";
  }
  EXPECT_EQ(restarted.component<WallDrag>()->results()[2].samples, 127u);  // steps 21..400 every 3
  EXPECT_NE(restarted.walls()->adaptive_potential()[0], 0.0);
}

TEST(Walls, ChannelExampleHasNoPenetrations) {
  // examples/channel/poiseuille.toml, shortened: at dt = 0.04 a particle moves up to ~0.2 per step
  // normal to a wall, more than the 0.1 layer, so a layer-only reflection let about 0.14 particles per
  // step into the walls of this channel. The predicted-move reflection must let none in, with each rule.
  for (const char* kind : {"bounce_back", "specular", "maxwell"}) {
    SimulationSpec spec = load_config(std::filesystem::path(test::source_dir()) / "examples/channel/poiseuille.toml");
    spec.walls.reflection = std::string(kind) == "bounce_back" ? ReflectionKind::BounceBack
                            : std::string(kind) == "specular"  ? ReflectionKind::Specular
                                                               : ReflectionKind::Maxwell;
    RunOptions options;
    options.steps = 600;
    Simulation sim(spec, options);
    auto& check = sim.add_stage(StagePoint::EndOfStep, std::make_unique<InsideCheck>(*sim.walls()));
    sim.run();
    const auto totals = sim.walls()->totals(sim.halo().comm());
    EXPECT_EQ(totals[0], 0u) << kind << ": penetrations";
    EXPECT_EQ(check.inside, 0u) << kind;
    std::printf("%s: %llu force kicks stopped at a surface in 600 steps\n", kind,
                static_cast<unsigned long long>(totals[1]));
  }
}

}  // namespace
}  // namespace mesodpd
