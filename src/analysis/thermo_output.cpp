// The thermo rows (thermo_output.hpp).
#include "analysis/thermo_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

std::optional<std::string> temperature_warning(double mean_t, const SimulationSpec& spec, double dof,
                                               std::uint64_t samples) {
  const double deviation = mean_t / spec.kT - 1.0;
  // Canonical fluctuations alone move a mean of independent samples by about sqrt(2 / dof / samples)
  // (relative); three of those are added so that a small system is not flagged for its noise.
  const double noise = 3.0 * std::sqrt(2.0 / std::max(dof, 1.0) / static_cast<double>(std::max<std::uint64_t>(samples, 1)));
  if (!(std::fabs(deviation) > kTemperatureTolerance + noise)) return std::nullopt;
  std::string advice = fmt::format("reduce integrator.dt (now {})", spec.dt);
  // lambda predicts the velocity the dissipative force sees: no advice to raise it where no pair has
  // friction (a conservative law, or a pairwise [thermostat] that does the dissipation itself). A spec
  // not yet resolved (no pairs) has the default gamma = 4.5.
  const bool friction = spec.pairs.empty() ||
                        std::any_of(spec.pairs.begin(), spec.pairs.end(), [](const PairSpec& p) { return p.gamma > 0; });
  if (spec.integrator == IntegratorKind::GrootWarren && deviation > 0 && spec.lambda < 0.65 && friction)
    advice += fmt::format(" or raise integrator.lambda (now {}; 0.65 keeps kT within 1% up to dt = 0.06 at rho = 3, "
                          "docs/validation.md)", spec.lambda);
  if (spec.integrator == IntegratorKind::Euler) advice += " or use integrator.type = \"groot-warren\"";
  return fmt::format("over the second half of the run the mean temperature {:.4g} is {:.1f}% {} the target kT = {} "
                     "(tolerance {:.0f}%): the time step is too large for these forces, or the run too short to "
                     "relax from its initial state; {}, or run longer",
                     mean_t, 100 * std::fabs(deviation), deviation > 0 ? "above" : "below", spec.kT,
                     100 * kTemperatureTolerance, advice);
}

ThermoOutput::ThermoOutput(const SimulationSpec& spec, AnalysisOutput out, std::vector<ThermoColumn> columns,
                           int temperature_column, const StepContext& start, std::uint64_t final_step)
    : spec_(spec), out_(std::move(out)), columns_(std::move(columns)), temperature_column_(temperature_column) {
  late_from_ = start.step + (final_step > start.step ? (final_step - start.step) / 2 : 0);
  for (const auto& sp : spec_.species) frozen_.push_back(sp.frozen ? 1 : 0);
  if (!out_.files()) return;
  // The file belongs to the root; an error there stops every rank.
  start.comm.on_root([&] {
    std::filesystem::create_directories(out_.dir);
    const auto path = out_ / "thermo.csv";
    if (out_.restarted && std::filesystem::exists(path)) trim_csv_after_step(path, start.step);
    const bool append = out_.restarted && std::filesystem::exists(path) && std::filesystem::file_size(path) > 0;
    thermo_.open(path, append ? OutputFile::Mode::Append : OutputFile::Mode::Truncate);
    if (!append) {
      thermo_ << thermo_csv_header();
      for (const ThermoColumn& c : columns_) thermo_ << ',' << c.name;
      thermo_ << '\n';
      thermo_.flush();
    }
  });
}

void ThermoOutput::save(ByteWriter& w) const {
  w.put<double>(temperature_sum_);
  w.put<double>(pressure_sum_);
  w.put<std::uint64_t>(thermo_samples_);
}

void ThermoOutput::load(ByteReader& r, const std::string&) {
  temperature_sum_ = r.get<double>();
  pressure_sum_ = r.get<double>();
  thermo_samples_ = r.get<std::uint64_t>();
}

void ThermoOutput::observe(const StepContext& ctx) {
  const std::uint64_t step = ctx.step;
  if (!due(step)) return;
  if (!ctx.pair_sums) throw std::logic_error("ThermoOutput: thermo output due but no pair sums were computed");
  const SimulationSpec& s = spec_;
  const Comm& comm = ctx.comm;
  // Temperature across a driven or sheared flow only: the streaming velocity is not heat.
  const int flow_axis = ctx.box.sheared() ? ctx.box.shear.flow : (s.poiseuille.enabled ? s.poiseuille.flow_axis : -1);
  across_flow_ = flow_axis >= 0;
  ThermoState t = compute_thermo(ctx.particles, ctx.species_mass, ctx.box, *ctx.pair_sums, flow_axis, comm, frozen_);
  t.step = step;
  t.time = static_cast<double>(step) * s.dt;
  t.neighbor_builds = ctx.neighbor_builds;
  std::string extra;
  double column_temperature = 0;
  for (std::size_t k = 0; k < columns_.size(); ++k) {
    const double value = columns_[k].value(ctx);
    if (static_cast<int>(k) == temperature_column_) column_temperature = value;
    extra += fmt::format(",{:.12g}", value);
  }
  const double temperature = temperature_column_ >= 0 ? column_temperature : t.temperature_transverse;
  // Written before the row is counted: a row that could not be written stops the run (on every rank).
  if (out_.files())
    comm.on_root([&] {
      thermo_ << thermo_csv_row(t) << extra << '\n';
      thermo_.flush();
    });
  history_.push_back(t);
  temperature_sum_ += temperature;
  if (step > late_from_) {
    late_temperature_sum_ += temperature;
    ++late_samples_;
  }
  pressure_sum_ += t.pressure;
  ++thermo_samples_;
}

std::string ThermoOutput::finish(const StepContext& ctx) {
  const SimulationSpec& s = spec_;
  std::string summary;
  warnings_.clear();  // finish() may be called again later in a longer run (the API)
  if (thermo_samples_ > 0) {
    summary += fmt::format("mean temperature {:.5f}{} (target {}), mean pressure {:.4f} over {} thermo rows\n",
                           temperature_sum_ / static_cast<double>(thermo_samples_),
                           across_flow_ ? " (across the flow)"
                           : temperature_column_ >= 0
                               ? fmt::format(" ({})", columns_[static_cast<std::size_t>(temperature_column_)].name)
                               : std::string(),
                           s.kT,
                           pressure_sum_ / static_cast<double>(thermo_samples_), thermo_samples_);
  }
  if (late_samples_ > 0) {
    // Judged on the second half of this run's rows: a random initial placement heats the fluid for
    // the first few time units, which is not the integrator's steady error.
    const double late_t = late_temperature_sum_ / static_cast<double>(late_samples_);
    const double n = static_cast<double>(ctx.total_particles);
    const double dof = across_flow_ ? 2 * n - 2 : 3 * n - 3;  // of the measured temperature
    if (auto w = temperature_warning(late_t, s, dof, late_samples_)) {
      summary += "warning: " + *w + "\n";
      warnings_.push_back(*w);
    }
  }
  return summary;
}

}  // namespace mesodpd
