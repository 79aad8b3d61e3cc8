// Flow through a porous medium read from a voxel image: the short version of examples/porous
// (docs/validation.md "Porous medium from an image"). Seed 004's fluid is driven by a body force through
// examples/porous/packing_small.pgm (6 random discs of radius 2 in a periodic 16 x 16 plane, solid
// fraction 0.297, extruded 3 along z) with Maxwellian walls.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/wall_drag.hpp"
#include "boundary/walls.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

std::string porous(double g) {
  return R"(
[system]
box = [16, 16, 3]
periodic = [true, true, true]
seed = 5
[[species]]
name = "fluid"
density = 4
body_force = [)" + std::to_string(g) + R"(, 0, 0]
[[species]]
name = "wall"
frozen = true
[pair]
a = 18.75
gamma = 4.5
s = 0.25
[[solid]]
name = "discs"
species = "wall"
shape = "image"
file = ")" + test::source_dir() + R"(/examples/porous/packing_small.pgm"
voxel_size = 0.25
axis = "z"
[walls]
reflection = "maxwell"
drag_start = 800
drag_every = 4
drag_blocks = 8
[integrator]
dt = 0.02
[output]
progress = false
)";
}

// The fluid's mean x velocity at the end of every step after `start`.
class VelocitySampler final : public Stage {
 public:
  explicit VelocitySampler(std::uint64_t start) : start_(start) {}
  void run(StepContext& ctx) override {
    if (ctx.step <= start_) return;
    const ParticleData& p = ctx.particles;
    double sum = 0, n = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.body[i] == 0) sum += p.vx[i], n += 1;
    u.push_back(sum / n);
  }
  std::uint64_t start_;
  std::vector<double> u;
};

struct Flow {
  double u = 0, u_err = 0;          // interstitial velocity, block error (8 blocks)
  double drag = 0, drag_err = 0;    // force on the discs along x
  double body_force = 0;            // N m g
  double fluid = 0;                 // N
  std::uint64_t penetrations = 0;
};

Flow run_porous(double g, int steps) {
  Simulation sim(parse_config(porous(g), "porous_test.toml"), RunOptions{});
  auto& sampler = sim.add_stage(StagePoint::EndOfStep, std::make_unique<VelocitySampler>(800));
  Flow f;
  for (std::size_t i = 0; i < sim.particles().n_local; ++i) f.fluid += sim.particles().body[i] == 0 ? 1 : 0;
  for (int s = 0; s < steps; ++s) sim.step();
  const int blocks = 8;
  const std::size_t per = sampler.u.size() / blocks;
  std::vector<double> means(blocks, 0.0);
  for (int b = 0; b < blocks; ++b) {
    for (std::size_t k = 0; k < per; ++k) means[static_cast<std::size_t>(b)] += sampler.u[static_cast<std::size_t>(b) * per + k];
    means[static_cast<std::size_t>(b)] /= static_cast<double>(per);
    f.u += means[static_cast<std::size_t>(b)] / blocks;
  }
  double var = 0;
  for (double m : means) var += (m - f.u) * (m - f.u);
  f.u_err = std::sqrt(var / (blocks - 1) / blocks);
  const auto drag = sim.component<WallDrag>()->results();
  f.drag = drag.at(0).force[0];
  f.drag_err = drag.at(0).error[0];
  f.body_force = f.fluid * g;
  f.penetrations = sim.walls()->totals(sim.halo().comm())[0];
  return f;
}

// Spielman-Goren permeability of fibres of radius a perpendicular to the flow at solid fraction phi:
// 1/(4 phi) = 1/2 + (sqrt(K)/a) K1(a/sqrt(K)) / K0(a/sqrt(K)) (Spielman and Goren's form with the fibre
// radius; seed 004 Eq. 12 prints the diameter in its place), by bisection in x = a / sqrt(K) (the right
// side falls with x).
double spielman_goren(double phi, double a) {
  const double lhs = 1 / (4 * phi) - 0.5;
  double lo = 1e-3, hi = 50;
  for (int k = 0; k < 200; ++k) {
    const double x = 0.5 * (lo + hi);
    (std::cyl_bessel_k(1.0, x) / (x * std::cyl_bessel_k(0.0, x)) > lhs ? lo : hi) = x;
  }
  const double x = 0.5 * (lo + hi);
  return a * a / (x * x);
}

TEST(Porous, ImageMediumObeysDarcyAndTheDiscsTakeTheBodyForce) {
  // Two body forces, g = 0.1 and 0.2 (Re = rho u d / mu about 0.3 and 0.6 with mu = 3.64): Darcy's law
  // makes the mean velocity proportional to g (ratio 2 within 3 combined block errors, which must be
  // below 0.15); in steady state the drag on the discs equals the body force on the fluid N m g (3 block
  // errors + 2%); no particle ends a step inside the image's staircase surface. K = q mu / (rho g)
  // (seed 004 Eq. 13, q = N u / (rho V), mu = 3.64 measured for this fluid) must lie within 0.8-1.6 of
  // Spielman-Goren at the image's solid fraction (examples/porous: 1.14; this 6-disc packing: 1.24);
  // walls that let the fluid slip would give a much larger K.
  const Flow low = run_porous(0.1, 5000), high = run_porous(0.2, 5000);
  for (const Flow* f : {&low, &high}) {
    EXPECT_EQ(f->penetrations, 0u);
    EXPECT_GT(f->u, 0.0);
    EXPECT_GT(f->drag, 0.0);
    EXPECT_LT(std::abs(f->drag - f->body_force), 3 * f->drag_err + 0.02 * f->body_force)
        << "drag " << f->drag << " +- " << f->drag_err << ", N m g " << f->body_force;
  }
  const double ratio = high.u / low.u;
  const double ratio_err = ratio * std::hypot(high.u_err / high.u, low.u_err / low.u);
  const double rho = 4, mu = 3.64, volume = 16 * 16 * 3, phi = 0.2971, radius = 2.0;
  const double K = high.fluid * high.u / (rho * volume) * mu / (rho * 0.2);
  const double K_sg = spielman_goren(phi, radius);
  std::printf("u = %.5f +- %.5f (g = 0.1), %.5f +- %.5f (g = 0.2), ratio %.3f +- %.3f; drag %.1f +- %.1f / %.1f and "
              "%.1f +- %.1f / %.1f; K %.4f, Spielman-Goren %.4f\n",
              low.u, low.u_err, high.u, high.u_err, ratio, ratio_err, low.drag, low.drag_err, low.body_force, high.drag,
              high.drag_err, high.body_force, K, K_sg);
  EXPECT_LT(std::abs(ratio - 2.0), 3 * ratio_err);
  EXPECT_LT(ratio_err, 0.15) << "too noisy to test Darcy's law";
  EXPECT_GT(K / K_sg, 0.8);
  EXPECT_LT(K / K_sg, 1.6);
}

}  // namespace
}  // namespace mesodpd
