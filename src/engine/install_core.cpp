// The installers of the parts every run has: the external fields, the initial forces and the periodic
// checkpoint (engine/installers.cpp gives their place in the list; the analyses' are in
// install_analyses.cpp).
#include <memory>

#include "boundary/external_fields.hpp"
#include "engine/installer.hpp"
#include "engine/simulation.hpp"

namespace mesodpd {

// External fields act after the pair forces: species body forces, then reverse Poiseuille.
void install_external_fields(Installation& in) { add_external_fields(in.spec, in.stages); }

void install_initial_forces(Installation& in) { in.initial_forces(); }

void install_checkpoints(Installation& in) {
  // After the analyses, so that a checkpoint holds their averages up to its step.
  if (in.options.out_dir.empty() || in.spec.checkpoint_every == 0) return;
  Simulation& sim = in.sim;
  const std::filesystem::path file = in.options.out_dir / "checkpoint.mdpd";
  const std::uint64_t every = in.spec.checkpoint_every;
  in.stages.add(StagePoint::EndOfStep, make_stage([&sim, file, every](StepContext& ctx) {
    if (ctx.step % every == 0) sim.write_checkpoint(file);
  }));
}

}  // namespace mesodpd
