// What the installers of analyses share (engine/install_analyses.cpp and an analysis model's own
// installer file): whether the run measures, where it writes, and how an analysis stage joins the step
// with its checkpoint section, its summary and the observation of the initial state.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>

#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include "engine/installer.hpp"
#include "engine/simulation.hpp"

namespace mesodpd {

inline bool measuring(const Installation& in) { return !in.options.out_dir.empty() || in.options.record; }
inline AnalysisOutput output(const Installation& in) { return {in.options.out_dir, in.restarted}; }

// Registers an analysis at EndOfStep with its checkpoint section (none where `section` is empty) and
// its summary (on the root), and observes the initial state of a new run.
template <class S>
S& add_analysis(Installation& in, std::unique_ptr<S> stage, const std::string& section) {
  S& s = in.stages.add(StagePoint::EndOfStep, std::move(stage));
  if (!section.empty())
    in.sections.push_back({section, [&s](ByteWriter& w) { s.save(w); },
                           [&s](ByteReader& r, const std::string& context) { s.load(r, context); }});
  in.summaries.push_back([&s](const StepContext& ctx) {
    std::string text;
    ctx.comm.on_root([&] { text = s.finish(ctx); });
    return text;
  });
  if (!in.restarted) s.observe(in.context());
  return s;
}

// The snapshot that the analyses of the whole system read (installed before them).
inline SystemSnapshot& snapshot(const Installation& in) {
  SystemSnapshot* s = in.components.find<SystemSnapshot>();
  if (!s) throw std::logic_error("an analysis of the whole system is installed before the \"snapshot\" model");
  return *s;
}

}  // namespace mesodpd
