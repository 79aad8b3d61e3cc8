// Named points of a time step and the stages (external fields, walls, constraints, analyses,
// writers) that register at them; Simulation::step() runs each point's stages in registration order.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/topology.hpp"
#include "core/particle_data.hpp"

namespace mesodpd {

class CellGrid;
class Comm;

// Where in Simulation::step() a stage runs. The step reads:
//   integrator first half, periodic wrap, step += 1   -> AfterFirstHalf  (constraints on positions)
//   neighbour search and ghost exchange               -> AfterNeighbors
//   pair forces                                       -> Forces          (external fields, walls, bonds)
//   integrator second half                            -> AfterSecondHalf (thermostats acting on velocities)
//   health check                                      -> EndOfStep       (analyses, writers, checkpoints)
enum class StagePoint : std::uint8_t { AfterFirstHalf, AfterNeighbors, Forces, AfterSecondHalf, EndOfStep };
inline constexpr std::size_t kStagePointCount = 5;

// What a stage sees. Built afresh at every stage point, so every field is current.
struct StepContext {
  ParticleData& particles;                 // this rank's locals in [0, n_local), then ghosts
  const Box& box;
  const Comm& comm;                        // collective stages (analyses) use it; one rank: serial
  std::uint64_t step = 0;                  // the step being completed (already incremented)
  double dt = 0.0;
  const std::vector<double>& species_mass;  // by species index
  // This step's pair sums where a stage asked for them, else null. Forces stages and AfterSecondHalf
  // stages whose forces or impulses act between particles outside the pair loop (membranes, pairwise
  // thermostats) add their virial here, so every reader of the stress (thermo, Lees-Edwards,
  // Green-Kubo) sees the whole of it; readers run at EndOfStep.
  PairSums* pair_sums = nullptr;
  std::uint64_t total_particles = 0;       // over all ranks
  std::uint64_t neighbor_builds = 0;       // since step 0, across restarts
  const Topology* topology = nullptr;      // bonds and angles by global id (empty without molecules)
  // Where the storage is in the cell order of the last neighbour build (else null): the local particles
  // of owned cell c of `cells` are at [cell_start[c], cell_start[c + 1]), each within cell_slack of its
  // cell's box as of the last neighbour check (skin/2 with a Verlet list, 0 with cell pairs; particles
  // have moved once more at AfterFirstHalf). Lets a stage skip whole cells that are far from something.
  const CellGrid* cells = nullptr;
  const std::uint32_t* cell_start = nullptr;
  double cell_slack = 0.0;
};

// One action at one stage point. Forces stages run at every force evaluation (also when
// Simulation::thermo() recomputes the forces of the current step), so they must only add to the
// forces, as a function of the current state.
class Stage {
 public:
  virtual ~Stage() = default;
  virtual void run(StepContext& ctx) = 0;
  // True where run() at `step` reads ctx.pair_sums: the force evaluation of that step then fills them.
  virtual bool wants_pair_sums(std::uint64_t /*step*/) const { return false; }
};

// A stage from a callable, for small hooks (tests, the periodic checkpoint).
template <class F>
class FunctionStage final : public Stage {
 public:
  explicit FunctionStage(F f) : f_(std::move(f)) {}
  void run(StepContext& ctx) override { f_(ctx); }

 private:
  F f_;
};

template <class F>
std::unique_ptr<FunctionStage<F>> make_stage(F f) {
  return std::make_unique<FunctionStage<F>>(std::move(f));
}

// The stages of a simulation, per point, in registration order.
class StageList {
 public:
  // Registers `stage` after those already at `at`; returns it (the list owns it).
  template <class S>
  S& add(StagePoint at, std::unique_ptr<S> stage) {
    S& ref = *stage;
    at_[index(at)].push_back(std::move(stage));
    return ref;
  }
  void run(StagePoint at, StepContext& ctx) const {
    for (const auto& s : at_[index(at)]) s->run(ctx);
  }
  bool empty(StagePoint at) const { return at_[index(at)].empty(); }
  std::size_t size(StagePoint at) const { return at_[index(at)].size(); }
  bool wants_pair_sums(std::uint64_t step) const {
    for (const auto& list : at_)
      for (const auto& s : list)
        if (s->wants_pair_sums(step)) return true;
    return false;
  }

 private:
  static std::size_t index(StagePoint at) { return static_cast<std::size_t>(at); }
  std::array<std::vector<std::unique_ptr<Stage>>, kStagePointCount> at_;
};

}  // namespace mesodpd
