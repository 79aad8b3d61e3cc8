// What a run has measured so far, for the API (Simulation::observers()): an index of the analysis
// stages, each of which is a stage of its own installed by its own model (engine/install_analyses.cpp).
// The index holds no state and runs nothing; an analysis that is not configured (or not measured: no
// output folder and no RunOptions::record) is absent from it.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/binned_fields.hpp"
#include "analysis/droplet.hpp"
#include "analysis/msd.hpp"
#include "analysis/rdf.hpp"
#include "analysis/stress_profile.hpp"
#include "analysis/thermo_output.hpp"
#include "analysis/velocity_profile.hpp"

namespace mesodpd {

class Observers {
 public:
  // The thermo rows of this process's run (every rank holds them all; a restarted run starts a new
  // history at the checkpoint's step, thermo.csv keeps the whole run).
  const std::vector<ThermoState>& history() const { return thermo_ ? thermo_->history() : kNoRows; }
  // The mean measured temperature over the thermo rows of the second half of this run, or nothing.
  std::optional<double> late_temperature() const { return thermo_ ? thermo_->late_temperature() : std::nullopt; }
  // Warnings of the last end-of-run summary (on the root).
  const std::vector<std::string>& warnings() const { return thermo_ ? thermo_->warnings() : kNoWarnings; }
  // The analyses exist on the root only; elsewhere these return nullptr.
  const PoiseuilleProfile* profile() const { return profile_ ? profile_->result() : nullptr; }
  const RadialDistribution* rdf() const { return rdf_ ? rdf_->result() : nullptr; }
  const MeanSquaredDisplacement* msd() const { return msd_ ? msd_->result() : nullptr; }
  const DropletAnalysis* droplet() const { return droplet_ ? droplet_->result() : nullptr; }
  const StressProfile* stress_profile() const { return stress_ ? stress_->result() : nullptr; }
  // The [analysis.fields] grids in the order of their tables (the same totals on every rank).
  const std::vector<std::reference_wrapper<const BinnedFields>>& fields() const { return fields_; }

  // For the installers: the stages, once each is registered.
  void add(const ThermoOutput& s) { thermo_ = &s; }
  void add(const VelocityProfileStage& s) { profile_ = &s; }
  void add(const RdfStage& s) { rdf_ = &s; }
  void add(const MsdStage& s) { msd_ = &s; }
  void add(const DropletStage& s) { droplet_ = &s; }
  void add(const StressProfileStage& s) { stress_ = &s; }
  void add(const BinnedFieldsStage& s) { fields_.emplace_back(s.grid()); }

 private:
  inline static const std::vector<ThermoState> kNoRows{};
  inline static const std::vector<std::string> kNoWarnings{};
  const ThermoOutput* thermo_ = nullptr;
  const VelocityProfileStage* profile_ = nullptr;
  const RdfStage* rdf_ = nullptr;
  const MsdStage* msd_ = nullptr;
  const DropletStage* droplet_ = nullptr;
  const StressProfileStage* stress_ = nullptr;
  std::vector<std::reference_wrapper<const BinnedFields>> fields_;
};

}  // namespace mesodpd
