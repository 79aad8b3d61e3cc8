// The whole system in increasing id on the root, gathered at most once per step for the analyses that
// read it (trajectory frames, RDF, MSD, droplet, stress profile), so that their sums are taken in the
// same order whatever the rank count or storage order. The first reader due at a step gathers it (a
// collective call, made on every rank alike since readers are due by step alone); the others reuse it.
// As an EndOfStep stage before the readers it only forgets the last step's snapshot.
#pragma once
#include <cstdint>

#include "analysis/analysis_stage.hpp"
#include "core/particle_data.hpp"
#include "core/stage.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

class SystemSnapshot final : public Stage {
 public:
  void run(StepContext&) override { taken_ = false; }
  // The snapshot of ctx's state (the root's; empty elsewhere). Collective: every rank calls it.
  const ParticleData& of(const StepContext& ctx) {
    if (!taken_) gather_by_id(ctx.particles, ctx.comm, ctx.total_particles, all_);
    taken_ = true;
    return all_;
  }

 private:
  ParticleData all_;  // reused between samples
  bool taken_ = false;
};

// An analysis of the whole system, held by the root, that samples the snapshot every `every` steps from
// `start` on: RDF, MSD, droplet, stress profile.
template <class A>
class SnapshotAnalysisStage : public RootAnalysisStage<A> {
 public:
  bool due(std::uint64_t step) const { return step >= start_ && step % every_ == 0; }
  void observe(const StepContext& ctx) final {
    if (!due(ctx.step)) return;
    const ParticleData& all = snapshot_.of(ctx);  // collective
    if (this->a_) sample(ctx, all);
  }

 protected:
  SnapshotAnalysisStage(AnalysisOutput out, SystemSnapshot& snapshot, std::uint64_t start, std::uint64_t every)
      : RootAnalysisStage<A>(std::move(out)), snapshot_(snapshot), start_(start), every_(every) {}
  // One sample of `all` (the root's snapshot) into this->a_.
  virtual void sample(const StepContext& ctx, const ParticleData& all) = 0;

 private:
  SystemSnapshot& snapshot_;
  std::uint64_t start_, every_;
};

}  // namespace mesodpd
