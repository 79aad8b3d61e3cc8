// Stage tests: registered stages run at their point of the step in registration order, a Forces stage
// changes the dynamics by exactly its force, and the external fields act as their formulas say.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "boundary/external_fields.hpp"
#include "engine/simulation.hpp"
#include "parallel/comm.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

// A test-only external field: the same force on every local particle along x.
class ConstantFieldX final : public Stage {
 public:
  explicit ConstantFieldX(double f) : f_(f) {}
  void run(StepContext& ctx) override {
    ParticleData& p = ctx.particles;
    // Pair forces are sums of 2^-32 units, so their total over particles is exactly zero in double.
    double before = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) before += p.fx[i];
    pair_total_x.push_back(before);
    for (std::size_t i = 0; i < p.n_local; ++i) p.fx[i] += f_;
    ++calls;
  }
  std::vector<double> pair_total_x;
  int calls = 0;

 private:
  double f_;
};

double momentum_x(const Simulation& sim) {
  const ParticleData& p = sim.particles();
  double px = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) px += sim.species_mass()[static_cast<std::size_t>(p.species[i])] * p.vx[i];
  return px;
}

double force_total_x(const Simulation& sim) {
  const ParticleData& p = sim.particles();
  double f = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) f += p.fx[i];
  return f;
}

}  // namespace

TEST(Stages, RunAtTheirPointsInRegistrationOrderEveryStep) {
  Simulation sim(test::fluid_spec(6, 6, 6, 3), RunOptions{});
  std::vector<std::string> log;
  auto record = [&](const char* name) {
    return [&log, name](StepContext& ctx) { log.push_back(std::string(name) + "@" + std::to_string(ctx.step)); };
  };
  // Registered out of step order, and two at one point: the step, not the registration, orders points.
  sim.add_stage(StagePoint::EndOfStep, make_stage(record("end")));
  sim.add_stage(StagePoint::Forces, make_stage(record("forces1")));
  sim.add_stage(StagePoint::AfterSecondHalf, make_stage(record("second")));
  sim.add_stage(StagePoint::Forces, make_stage(record("forces2")));
  sim.add_stage(StagePoint::AfterNeighbors, make_stage(record("nbr")));
  sim.add_stage(StagePoint::AfterFirstHalf, make_stage(record("first")));
  sim.step();
  sim.step();
  const std::vector<std::string> expected = {"first@1", "nbr@1", "forces1@1", "forces2@1", "second@1", "end@1",
                                             "first@2", "nbr@2", "forces1@2", "forces2@2", "second@2", "end@2"};
  EXPECT_EQ(log, expected);
}

TEST(Stages, ConstantFieldChangesMomentumByItsForceEveryStep) {
  const SimulationSpec spec = test::fluid_spec(6, 6, 6, 3);
  Simulation sim(spec, RunOptions{});
  const double f = 0.375;  // a binary fraction: pair force + f is exact in double
  auto& field = sim.add_stage(StagePoint::Forces, std::make_unique<ConstantFieldX>(f));
  const auto n = static_cast<double>(sim.total_particles());
  const double dt = spec.dt;
  // The step-0 forces predate the field, so the first step's kick has half of it (velocity Verlet).
  double p_prev = momentum_x(sim);
  EXPECT_NEAR(p_prev, 0.0, 1e-9);  // the initial state has no centre-of-mass velocity
  for (int k = 1; k <= 20; ++k) {
    sim.step();
    // The field ran once per force evaluation, after the pair forces (which total exactly zero), and
    // the integrator saw exactly N f in total.
    ASSERT_EQ(field.calls, k);
    EXPECT_EQ(field.pair_total_x.back(), 0.0);
    EXPECT_EQ(force_total_x(sim), n * f);
    const double p = momentum_x(sim);
    const double expected = (k == 1 ? 0.5 : 1.0) * n * f * dt;
    EXPECT_NEAR(p - p_prev, expected, 1e-9) << "step " << k;
    p_prev = p;
  }
  EXPECT_NEAR(p_prev, n * f * dt * 19.5, 1e-8);
  // thermo() between thermo rows computes pair sums only: no second run of the field, forces kept.
  const std::vector<double> fx = sim.particles().fx;
  sim.thermo();
  EXPECT_EQ(field.calls, 20);
  EXPECT_EQ(sim.particles().fx, fx);
}

TEST(Stages, ExternalFieldsAreForcesStagesInSpecOrder) {
  SimulationSpec spec = test::fluid_spec(6, 6, 6, 3);
  {
    Simulation sim(spec, RunOptions{});
    EXPECT_EQ(sim.stages().size(StagePoint::Forces), 0u);
  }
  spec.species[0].body_force = {0.0, 0.25, 0.0};
  spec.poiseuille.enabled = true;
  spec.poiseuille.force = 0.5;
  {
    Simulation sim(spec, RunOptions{});
    EXPECT_EQ(sim.stages().size(StagePoint::Forces), 2u);
    // Pair forces total zero; the fields add N * 0.25 along y, and +-m g along x that cancels over
    // the two halves only as far as the particle counts do.
    const ParticleData& p = sim.particles();
    double fy = 0, fx = 0;
    std::int64_t lower = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      fy += p.fy[i];
      fx += p.fx[i];
      lower += p.z[i] < 3.0 ? 1 : -1;
    }
    EXPECT_EQ(fy, 0.25 * static_cast<double>(p.n_local));
    EXPECT_EQ(fx, 0.5 * static_cast<double>(lower));
  }
}

TEST(ExternalFields, BodyForceAddsPerSpeciesAndPoiseuilleFollowsTheGradientCoordinate) {
  ParticleData p;
  p.resize(4);
  p.n_local = 4;
  p.species = {0, 1, 1, 0};
  p.y = {0.5, 1.5, 2.5, 3.5};  // the gradient axis is y; the box is 4 long there
  Box box;
  box.len = {5.0, 4.0, 6.0};
  const std::vector<double> mass = {1.0, 2.0};
  const Comm serial = Comm::serial();
  StepContext ctx{.particles = p, .box = box, .comm = serial, .species_mass = mass};
  SpeciesBodyForce body({{0.0, 0.0, 0.125}, {1.0, -2.0, 0.0}});
  body.run(ctx);
  EXPECT_EQ(p.fx, (std::vector<double>{0.0, 1.0, 1.0, 0.0}));
  EXPECT_EQ(p.fy, (std::vector<double>{0.0, -2.0, -2.0, 0.0}));
  EXPECT_EQ(p.fz, (std::vector<double>{0.125, 0.0, 0.0, 0.125}));
  // Flow along z, gradient along y: +m g below y = 2, -m g above (seed 002).
  ReversePoiseuilleField pois(0.5, 2, 1);
  pois.run(ctx);
  EXPECT_EQ(p.fz, (std::vector<double>{0.625, 1.0, -1.0, -0.375}));
  EXPECT_EQ(p.fx, (std::vector<double>{0.0, 1.0, 1.0, 0.0}));  // other axes untouched
}
