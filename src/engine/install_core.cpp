// The installers of the parts every run has: the external fields, the initial forces, the observers
// and the periodic checkpoint (engine/installers.cpp gives their place in the list).
#include <memory>

#include "analysis/observers.hpp"
#include "boundary/external_fields.hpp"
#include "engine/installer.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "io/byte_buffer.hpp"

namespace mesodpd {

// External fields act after the pair forces: species body forces, then reverse Poiseuille.
void install_external_fields(Installation& in) { add_external_fields(in.spec, in.stages); }

void install_initial_forces(Installation& in) { in.initial_forces(); }

void install_observers(Installation& in) {
  Simulation& sim = in.sim;
  const SimulationSpec& spec = in.spec;
  ObserverSettings& settings = in.observers;
  const PairBackend& forces = sim.pair_backend();
  const std::optional<DensitySettings>& density = sim.density_settings();
  if (spec.droplet.enabled) {
    // The droplet's local pressures: the run's force law on a subset of particles, by the reference
    // loop (serial, in index order, so the result depends on neither threads nor ranks).
    settings.interaction_range = forces.max_cutoff() + (density ? density->table.max_cutoff : 0.0);
    settings.local_virial = make_local_virial(forces.laws(), density);
  }
  if (spec.stress_profile.enabled) {
    // The stress profile's virial terms: the run's pair law by the reference loop (with densities over
    // the whole system for many-body laws) without the excluded pairs, then the bonds and angles;
    // serial and in index order, so independent of threads and ranks.
    settings.virial_terms = [&sim](const ParticleData& all, const Box& box, VirialTerms& terms) {
      const std::optional<DensitySettings>& dens = sim.density_settings();
      const BondedForces& bonds = sim.bonded();
      std::vector<double> rho;
      if (dens) reference_density(all, box, *dens, rho);
      ExcludedPair excluded;
      if (bonds.excluded_pairs() > 0)
        excluded = [&bonds](std::uint32_t a, std::uint32_t b) { return bonds.excluded(a, b); };
      reference_conservative_virial_terms(all, box, sim.pair_backend().laws(), terms, dens ? rho.data() : nullptr,
                                          excluded);
      bonds.virial_terms(all, box, terms);
    };
  }
  const StepContext start = in.context();
  auto observers = std::make_unique<Observers>(spec, std::move(settings), start);
  if (!in.observer_state.empty()) {
    const std::string file = in.options.restart.string();
    ByteReader r(in.observer_state, file);
    observers->load(r, file);
    in.observer_state.clear();
  }
  if (!in.restarted) observers->observe(start);
  in.components.share(in.stages.add(StagePoint::EndOfStep, std::move(observers)));
}

void install_checkpoints(Installation& in) {
  // After the observers, so that a checkpoint holds their averages up to its step.
  if (in.options.out_dir.empty() || in.spec.checkpoint_every == 0) return;
  Simulation& sim = in.sim;
  const std::filesystem::path file = in.options.out_dir / "checkpoint.mdpd";
  const std::uint64_t every = in.spec.checkpoint_every;
  in.stages.add(StagePoint::EndOfStep, make_stage([&sim, file, every](StepContext& ctx) {
    if (ctx.step % every == 0) sim.write_checkpoint(file);
  }));
}

}  // namespace mesodpd
