// Trajectory frames ([output.dump]: GSD or LAMMPS dump) of the whole system in id order, every
// dump.every steps: an EndOfStep stage that reads the system snapshot (analysis/system_snapshot.hpp).
#pragma once
#include <cstdint>
#include <optional>

#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include "io/gsd_writer.hpp"
#include "io/lammps_dump_writer.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class TrajectoryOutput final : public AnalysisStage {
 public:
  // Opens the file on the root (a restarted run drops the frames after `start`'s step and appends).
  // Needs an output folder. Collective.
  TrajectoryOutput(const SimulationSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot,
                   const StepContext& start);
  bool due(std::uint64_t step) const { return step % spec_.dump.every == 0; }
  void observe(const StepContext& ctx) override;

 private:
  void write_frame(std::uint64_t step, const StepContext& ctx, const ParticleData& all);

  const SimulationSpec& spec_;
  SystemSnapshot& snapshot_;
  std::optional<LammpsDumpWriter> lammps_;
  std::optional<GsdWriter> gsd_;
};

}  // namespace mesodpd
