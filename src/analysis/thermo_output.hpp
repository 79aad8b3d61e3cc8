// The thermo rows: thermo.csv (thermo's columns, then the extra columns of other models), the running
// means of temperature and pressure, this run's history for the API and the end-of-run temperature
// warning. One EndOfStep stage; the first of the analyses, since the surface tension reads its rows.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/analysis_stage.hpp"
#include "analysis/thermo.hpp"
#include "io/output_file.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// A run whose mean measured temperature over the second half of its thermo rows leaves k_BT by more
// than this (relative) gets a warning.
// The Groot-Warren integrator at lambda = 0.5 runs 2.3% warm at the standard dt = 0.04 and 4.5% at
// dt = 0.06 (docs/validation.md), so 5% flags time steps beyond what the scheme handles.
inline constexpr double kTemperatureTolerance = 0.05;

// The warning for a mean temperature `mean_t` over `samples` thermo rows of `dof` degrees of freedom,
// or nothing when it is within kTemperatureTolerance (plus three times its expected noise) of kT.
std::optional<std::string> temperature_warning(double mean_t, const SimulationSpec& spec, double dof,
                                               std::uint64_t samples);

// An extra column of thermo.csv (walls: reflections, penetrations). value() is called on every rank at
// every thermo row (it may be collective) and its result on the root is written.
struct ThermoColumn {
  std::string name;
  std::function<double(const StepContext&)> value;
};

class ThermoOutput final : public AnalysisStage {
 public:
  // `columns` are appended to every row in this order; `temperature_column` is the index among them of a
  // temperature that the means and the warning use instead of thermo's own (walls: the peculiar
  // temperature, without the flow's kinetic energy), or -1. `start` is the state the run begins from
  // (step 0 or the checkpoint's step), `final_step` where this run ends. Collective.
  ThermoOutput(const SimulationSpec& spec, AnalysisOutput out, std::vector<ThermoColumn> columns,
               int temperature_column, const StepContext& start, std::uint64_t final_step);

  void observe(const StepContext& ctx) override;
  bool wants_pair_sums(std::uint64_t step) const override { return due(step); }
  bool due(std::uint64_t step) const { return step % spec_.thermo_every == 0; }
  // The row of `step`, if this stage wrote one there (the last row; every rank holds it).
  const ThermoState* row(std::uint64_t step) const {
    return !history_.empty() && history_.back().step == step ? &history_.back() : nullptr;
  }

  // temperature and pressure sums and the row count.
  void save(ByteWriter& w) const override;
  void load(ByteReader& r, const std::string& context) override;
  std::string finish(const StepContext& ctx) override;

  // The thermo rows of this process's run (every rank holds them all; a restarted run starts a new
  // history at the checkpoint's step, thermo.csv keeps the whole run).
  const std::vector<ThermoState>& history() const { return history_; }
  // The mean measured temperature over the thermo rows of the second half of this run (the one the
  // end-of-run warning judges; the same on every rank), or nothing before such a row.
  std::optional<double> late_temperature() const {
    if (late_samples_ == 0) return std::nullopt;
    return late_temperature_sum_ / static_cast<double>(late_samples_);
  }
  // Warnings found by finish() (on the root), each also a "warning: " line of the summary.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  const SimulationSpec& spec_;
  AnalysisOutput out_;
  std::vector<ThermoColumn> columns_;
  int temperature_column_;
  bool across_flow_ = false;  // the temperature is the one across a driven or sheared flow
  OutputFile thermo_;
  double temperature_sum_ = 0, pressure_sum_ = 0;
  std::uint64_t thermo_samples_ = 0;
  std::vector<std::string> warnings_;
  std::vector<std::uint8_t> frozen_;  // by species: wall particles, left out of the temperature
  std::vector<ThermoState> history_;
  // Thermo rows after the midpoint of this run (not of the runs before a restart), for the warning.
  std::uint64_t late_from_ = 0, late_samples_ = 0;
  double late_temperature_sum_ = 0;
};

}  // namespace mesodpd
