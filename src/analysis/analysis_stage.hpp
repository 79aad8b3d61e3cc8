// What every analysis stage shares: an EndOfStep stage that also observes the initial state, keeps its
// running averages in a checkpoint section of its own and writes its files and summary at the end of
// the run. Each analysis (thermo rows, velocity profile, RDF, MSD, binned fields, surface tension,
// droplet, stress profile, trajectory frames) is one such stage, installed by its own model
// (engine/install_analyses.cpp); run() must return at once at a step where the analysis is not due.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "core/stage.hpp"
#include "io/byte_buffer.hpp"

namespace mesodpd {

// Where an analysis writes: the output folder (empty: no files; the results stay in memory for the API).
struct AnalysisOutput {
  std::filesystem::path dir;
  bool restarted = false;  // continuing from a checkpoint: files are appended to, not started afresh
  bool files() const { return !dir.empty(); }
  std::filesystem::path operator/(const std::string& name) const { return dir / name; }
};

class AnalysisStage : public Stage {
 public:
  // Collective under MPI, like run(): every rank calls it at every step.
  void run(StepContext& ctx) override { observe(ctx); }
  // Measures and writes what is due at ctx.step (also the initial state, at step 0 of a new run).
  virtual void observe(const StepContext& ctx) = 0;
  // The checkpoint section (the state must be the same on every rank, or held on the root only: save()
  // runs on the root).
  virtual void save(ByteWriter& /*w*/) const {}
  virtual void load(ByteReader& /*r*/, const std::string& /*context*/) {}
  // The end-of-run files and summary text; on the root only.
  virtual std::string finish(const StepContext& /*ctx*/) { return {}; }
};

// An analysis of type A that the root holds alone (it samples the snapshot gathered there, or sums
// that arrive there): its checkpoint section is A's save() and load(), and result() is null elsewhere.
template <class A>
class RootAnalysisStage : public AnalysisStage {
 public:
  void save(ByteWriter& w) const override {
    if (a_) a_->save(w);
  }
  void load(ByteReader& r, const std::string& context) override {
    if (a_) a_->load(r, context);
  }
  const A* result() const { return a_ ? &*a_ : nullptr; }

 protected:
  explicit RootAnalysisStage(AnalysisOutput out) : out_(std::move(out)) {}
  AnalysisOutput out_;
  std::optional<A> a_;  // on the root only
};

}  // namespace mesodpd
