// Everything that watches a run, as one EndOfStep stage: thermo output, velocity profile and
// viscosity, RDF, MSD, binned fields, surface tension, droplet, stress profile, trajectory frames and progress; their running averages go into checkpoints.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "analysis/binned_fields.hpp"
#include "analysis/droplet.hpp"
#include "analysis/msd.hpp"
#include "analysis/rdf.hpp"
#include "analysis/stress_profile.hpp"
#include "analysis/surface_tension.hpp"
#include "analysis/thermo.hpp"
#include "analysis/velocity_profile.hpp"
#include "core/stage.hpp"
#include "io/byte_buffer.hpp"
#include "io/gsd_writer.hpp"
#include "io/lammps_dump_writer.hpp"
#include "io/output_file.hpp"
#include "io/progress.hpp"
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

// State of another part of the run (walls: drag averages, adaptive force) that travels in the
// checkpoint beside the observers' averages, by name. save() runs on the root only, so the state must
// be the same on every rank.
struct StateSection {
  std::string name;
  std::function<void(ByteWriter&)> save;
  std::function<void(ByteReader&, const std::string& context)> load;
};

struct ObserverSettings {
  std::filesystem::path out_dir;   // empty: no files (thermo, profiles, trajectories are not kept)
  bool progress = false;           // progress bar or log lines on the root
  bool restarted = false;          // continuing from a checkpoint: append to existing files
  std::uint64_t final_step = 0;    // for the progress bar
  // Measure (thermo rows, profile, RDF, MSD) and keep the results in memory even without an output
  // directory: for programs that read them through the API (the Python module) rather than from files.
  bool record = false;
  std::vector<ThermoColumn> columns;  // appended to every thermo row, in this order
  std::vector<StateSection> sections;  // saved and restored with the observers' state
  // [analysis.droplet]: the per-particle conservative virial of a set of particles with the run's force
  // law (set by the engine), and the interaction range (pair cutoff plus density-kernel range).
  LocalVirial local_virial;
  double interaction_range = 0;
  // [analysis.stress_profile]: appends the virial terms (conservative pair forces, bonds, angles) of the
  // whole system handed to it (set by the engine).
  std::function<void(const ParticleData&, const Box&, VirialTerms&)> virial_terms;
  // Index into `columns` of a temperature that the run's mean temperature and its end-of-run warning use
  // instead of thermo's own (walls: the peculiar temperature, without the flow's kinetic energy); -1: none.
  int temperature_column = -1;
};

class Observers final : public Stage {
 public:
  // `start` is the state the run begins from (step 0 or the checkpoint's step). Collective.
  Observers(const SimulationSpec& spec, ObserverSettings settings, const StepContext& start);

  // Collective under MPI: every rank runs it at every step; files are written by the root from the
  // particles gathered in id order, so they do not depend on the rank count.
  // Measures and writes what is due at ctx.step, then advances the progress report.
  void run(StepContext& ctx) override;
  // The measurements and files alone (the initial state at step 0 is observed without progress).
  void observe(const StepContext& ctx);
  bool wants_pair_sums(std::uint64_t step) const override { return thermo_due(step); }

  // The summaries at the end of a run (files on the root; text returned on the root, empty elsewhere).
  std::string finish(const StepContext& ctx);

  // Running averages (thermo means, profile, RDF, MSD) for checkpoints. Each part is a length-prefixed
  // section, so a restart with an analysis switched off skips it and one switched on starts afresh.
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

  // The mean measured temperature over the thermo rows of the second half of this run (the one the
  // end-of-run warning judges; the same on every rank), or nothing before such a row.
  std::optional<double> late_temperature() const {
    if (late_samples_ == 0) return std::nullopt;
    return late_temperature_sum_ / static_cast<double>(late_samples_);
  }
  // Warnings found by finish() (on the root), each also a "warning: " line of the summary.
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Results so far, for the API. The thermo rows of this process's run (every rank holds them all; a
  // restarted run starts a new history at the checkpoint's step, thermo.csv keeps the whole run).
  // The analyses exist on the root only, and only when configured and measured (an output directory
  // or ObserverSettings::record); elsewhere these return nullptr.
  const std::vector<ThermoState>& history() const { return history_; }
  const PoiseuilleProfile* profile() const { return profile_ ? &*profile_ : nullptr; }
  const RadialDistribution* rdf() const { return rdf_ ? &*rdf_ : nullptr; }
  const MeanSquaredDisplacement* msd() const { return msd_ ? &*msd_ : nullptr; }
  // The [analysis.fields] grids (the same totals on every rank).
  const std::vector<BinnedFields>& fields() const { return fields_; }
  const DropletAnalysis* droplet() const { return droplet_ ? &*droplet_ : nullptr; }
  const StressProfile* stress_profile() const { return stress_ ? &*stress_ : nullptr; }

 private:
  bool files() const { return !opt_.out_dir.empty(); }
  bool measuring() const { return files() || opt_.record; }
  bool thermo_due(std::uint64_t step) const { return measuring() && step % spec_.thermo_every == 0; }
  std::filesystem::path out(const std::string& name) const { return opt_.out_dir / name; }
  void write_frame(std::uint64_t step, const StepContext& ctx, const ParticleData& all);

  const SimulationSpec& spec_;
  ObserverSettings opt_;
  OutputFile thermo_;
  std::optional<PoiseuilleProfile> profile_;
  std::optional<RadialDistribution> rdf_;
  std::optional<MeanSquaredDisplacement> msd_;
  std::vector<BinnedFields> fields_;  // [analysis.fields] grids, summed on every rank alike
  std::optional<SurfaceTension> tension_;
  std::optional<DropletAnalysis> droplet_;
  std::optional<StressProfile> stress_;
  VirialTerms terms_;  // scratch: one stress-profile sample
  std::optional<LammpsDumpWriter> lammps_;
  std::optional<GsdWriter> gsd_;
  std::optional<ProgressReporter> progress_;
  std::vector<double> scratch_a_, scratch_b_, scratch_c_;
  ParticleData snapshot_;  // the whole system in id order (on the root), reused between samples
  std::vector<std::int64_t> profile_bins_;  // one profile sample: fixed-point flow sums, then counts
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
