// The installers of the analyses: each is its own EndOfStep stage with its own checkpoint section and
// summary (analysis/analysis_stage.hpp), measured only with an output folder or RunOptions::record.
// Their order in engine/installers.cpp is the order their stages run in; the order of their summaries
// is summary_order() there.
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "analysis/binned_fields.hpp"
#include "analysis/droplet.hpp"
#include "analysis/msd.hpp"
#include "analysis/observers.hpp"
#include "analysis/rdf.hpp"
#include "analysis/stress_profile.hpp"
#include "analysis/surface_tension.hpp"
#include "analysis/system_snapshot.hpp"
#include "analysis/thermo_output.hpp"
#include "analysis/trajectory_output.hpp"
#include "analysis/transport.hpp"
#include "analysis/velocity_profile.hpp"
#include "engine/analysis_installer.hpp"
#include "engine/installer.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "io/progress.hpp"
#include "io/state_checkpoint.hpp"

namespace mesodpd {

namespace {

// The progress bar on the root, advanced at every step after the analyses.
class ProgressStage final : public Stage {
 public:
  ProgressStage(bool root, std::uint64_t first, std::uint64_t last) {
    if (root) progress_.emplace(first, last);
  }
  void run(StepContext& ctx) override {
    if (progress_) progress_->update(ctx.step);
  }
  void finish() {
    if (progress_) progress_->finish();
  }

 private:
  std::optional<ProgressReporter> progress_;
};

}  // namespace

void install_thermo(Installation& in) {
  if (measuring(in)) {
    ThermoOutput& t = add_analysis(in,
                                   std::make_unique<ThermoOutput>(in.spec, output(in), std::move(in.thermo_columns),
                                                                  in.temperature_column, in.context(),
                                                                  in.sim.final_step()),
                                   section_name::kThermo);
    in.components.share(t);
    in.observers.add(t);
  }
  in.thermo_columns.clear();
  in.temperature_column = -1;
}

void install_surface_tension(Installation& in) {
  const SurfaceTensionSpec& spec = in.spec.surface_tension;
  const ThermoOutput* thermo = in.components.find<ThermoOutput>();
  if (!spec.enabled || !thermo) return;
  add_analysis(in,
               std::make_unique<SurfaceTensionStage>(spec, output(in), *thermo, in.sim.box().length(spec.axis),
                                                     in.sim.halo().comm()),
               section_name::kSurfaceTension);
}

void install_velocity_profile(Installation& in) {
  if (!measuring(in) || !in.spec.poiseuille.enabled) return;
  in.observers.add(add_analysis(in, std::make_unique<VelocityProfileStage>(in.spec, output(in), in.context()),
                                section_name::kVelocityProfile));
}

void install_fields(Installation& in) {
  if (!measuring(in)) return;
  // Every rank holds the same totals (each sample is summed over ranks).
  std::vector<std::string> names;
  for (const SpeciesSpec& sp : in.spec.species) names.push_back(sp.name);
  const Box& box = in.sim.box();
  for (const FieldsSpec& f : in.spec.fields) {
    BinnedFields grid(f, in.sim.species_mass(), names, std::array<double, 3>{box.len.x, box.len.y, box.len.z},
                      box.periodic);
    in.observers.add(add_analysis(in, std::make_unique<BinnedFieldsStage>(std::move(grid), output(in)),
                                  section_name::kFieldsPrefix + f.name));
  }
}

void install_snapshot(Installation& in) {
  if (!measuring(in)) return;
  in.components.share(in.stages.add(StagePoint::EndOfStep, std::make_unique<SystemSnapshot>()));
}

void install_trajectory(Installation& in) {
  if (in.options.out_dir.empty() || !in.spec.dump.enabled) return;
  add_analysis(in, std::make_unique<TrajectoryOutput>(in.spec, output(in), snapshot(in), in.context()), {});
}

void install_rdf(Installation& in) {
  if (!measuring(in) || !in.spec.rdf.enabled) return;
  in.observers.add(add_analysis(
      in, std::make_unique<RdfStage>(in.spec.rdf, output(in), snapshot(in), in.sim.halo().comm()), section_name::kRdf));
}

void install_msd(Installation& in) {
  if (!measuring(in) || !in.spec.msd.enabled) return;
  in.observers.add(add_analysis(
      in, std::make_unique<MsdStage>(in.spec, output(in), snapshot(in), in.sim.halo().comm()), section_name::kMsd));
}

void install_transport(Installation& in) {
  const TransportSpec* t = in.spec.model<TransportSpec>("analysis.transport");
  if (!measuring(in) || !t) return;
  check_transport(*t, in.spec);  // again, for specs built in code
  // Not in the observers' index (that would be a shared file for one analysis): the API and tests find
  // the stage as a component.
  in.components.share(add_analysis(
      in, std::make_unique<TransportStage>(*t, in.spec, output(in), snapshot(in), in.sim.halo().comm()), "transport"));
}

void install_droplet(Installation& in) {
  if (!measuring(in) || !in.spec.droplet.enabled) return;
  // The droplet's local pressures: the run's force law on a subset of particles, by the reference loop
  // (serial, in index order, so the result depends on neither threads nor ranks).
  const PairBackend& forces = in.sim.pair_backend();
  const std::optional<DensitySettings>& density = in.sim.density_settings();
  const double range = forces.max_cutoff() + (density ? density->table.max_cutoff : 0.0);
  in.observers.add(add_analysis(in,
                                std::make_unique<DropletStage>(in.spec.droplet, output(in), snapshot(in),
                                                               make_local_virial(forces.laws(), density), range,
                                                               in.sim.box(), in.sim.halo().comm()),
                                section_name::kDroplet));
}

void install_stress_profile(Installation& in) {
  if (!measuring(in) || !in.spec.stress_profile.enabled) return;
  // The virial terms: the run's pair law by the reference loop (with densities over the whole system for
  // many-body laws) without the excluded pairs, then the bonds and angles; serial and in index order, so
  // independent of threads and ranks.
  Simulation& sim = in.sim;
  VirialTermsOf terms = [&sim](const ParticleData& all, const Box& box, VirialTerms& out) {
    const std::optional<DensitySettings>& dens = sim.density_settings();
    const BondedForces& bonds = sim.bonded();
    std::vector<double> rho;
    if (dens) reference_density(all, box, *dens, rho);
    ExcludedPair excluded;
    if (bonds.excluded_pairs() > 0)
      excluded = [&bonds](std::uint32_t a, std::uint32_t b) { return bonds.excluded(a, b); };
    reference_conservative_virial_terms(all, box, sim.pair_backend().laws(), out, dens ? rho.data() : nullptr,
                                        excluded);
    bonds.virial_terms(all, box, out);
  };
  in.observers.add(add_analysis(in,
                                std::make_unique<StressProfileStage>(in.spec, output(in), snapshot(in), std::move(terms),
                                                                     in.sim.box(), in.sim.halo().comm()),
                                section_name::kStressProfile));
}

void install_progress(Installation& in) {
  if (!in.options.progress) return;
  ProgressStage& p = in.stages.add(
      StagePoint::EndOfStep,
      std::make_unique<ProgressStage>(in.sim.halo().comm().root(), in.sim.current_step(), in.sim.final_step()));
  in.summaries.push_back([&p](const StepContext&) {
    p.finish();
    return std::string();
  });
}

}  // namespace mesodpd
