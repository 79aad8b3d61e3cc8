// The whole system in increasing id on the root, gathered at most once per step for the analyses that
// read it (trajectory frames, RDF, MSD, droplet, stress profile), so that their sums are taken in the
// same order whatever the rank count or storage order. The first reader due at a step gathers it (a
// collective call, made on every rank alike since readers are due by step alone); the others reuse it.
// As an EndOfStep stage before the readers it only forgets the last step's snapshot.
#pragma once
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

}  // namespace mesodpd
