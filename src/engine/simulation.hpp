// A simulation: the particles, the pair forces, the integrator and the stages registered at named
// points of the step (external fields, walls, analyses, writers), with Simulation::step() as the one place
// that says what a time step is.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/box.hpp"
#include "analysis/observers.hpp"
#include "analysis/thermo.hpp"
#include "core/particle_data.hpp"
#include "core/stage.hpp"
#include "engine/blow_up_error.hpp"
#include "engine/bonded_forces.hpp"
#include "engine/installer.hpp"
#include "engine/pair_backend.hpp"
#include "integrate/integrator.hpp"
#include "io/output_lock.hpp"
#include "io/state_checkpoint.hpp"
#include "mesodpd/spec.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

struct RunOptions {
  std::filesystem::path out_dir;                 // empty: write no files (library and test use)
  std::optional<std::uint64_t> steps;            // overrides run.steps (the final step number)
  std::filesystem::path restart;                 // continue from this checkpoint
  bool progress = false;                         // progress bar (terminal) or log lines
  bool record = false;  // measure and keep thermo rows and analyses in memory even without out_dir
};

class Walls;      // reflections at [[solid]] walls (boundary/walls.hpp)
struct Installation;

class Simulation {
 public:
  Simulation(SimulationSpec spec, RunOptions options);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Advances to the final step (run.steps or the override), measuring and writing as configured,
  // then writes the final checkpoint and summaries. Returns a short human-readable summary.
  std::string run();
  // What run() does after its last step: the final checkpoint (with out_dir) and the analysis
  // summaries (files with out_dir; the text on the root). May be called at any step, more than once.
  std::string finish();
  // The measurements (thermo history, analyses; the index of analysis/observers.hpp) for the API.
  const Observers& observers() const { return observers_; }
  // Warnings about the finished run (on the root rank; also in run()'s summary): a mean temperature
  // away from kT. The command line prints them to stderr.
  const std::vector<std::string>& warnings() const;
  // The runaway guard (run.max_temperature_ratio): a message when the mean temperature over the second
  // half of this run's thermo rows exceeds that multiple of kT, nothing otherwise or when it is off.
  // The same on every rank.
  // Judged only for runs of at least kRunawayMinTime time units (this process's steps x dt).
  std::optional<std::string> runaway_temperature() const;
  static constexpr double kRunawayMinTime = 2.0;

  // One time step, in this order: integrate (first part), wrap, [AfterFirstHalf], neighbours and
  // ghost exchange, [AfterNeighbors], pair forces, [Forces], integrate (second part),
  // [AfterSecondHalf], health check, [EndOfStep]; [X] runs the stages registered at point X. The
  // force evaluation is the pair forces, then the bonded forces, then the [Forces] stages.
  void step();

  // Registers a stage after those already at `at` (the constructor's installers have registered theirs:
  // engine/installers.cpp). Returns the stage.
  template <class S>
  S& add_stage(StagePoint at, std::unique_ptr<S> stage) {
    return stages_.add(at, std::move(stage));
  }
  const StageList& stages() const { return stages_; }

  const SimulationSpec& spec() const { return spec_; }
  // This rank's particles: locals in [0, n_local), then ghosts.
  const ParticleData& particles() const { return p_; }
  ParticleData& particles() { return p_; }
  // Particles in the whole system (all ranks).
  std::uint64_t total_particles() const { return n_total_; }
  // The decomposition, the communicator and the ghost exchange (inactive on one rank).
  const Halo& halo() const { return halo_; }
  Halo& halo() { return halo_; }  // for extra pair passes run on the simulation's particles (tests, tools)
  const Box& box() const { return box_; }
  std::uint64_t current_step() const { return step_; }
  const std::vector<double>& species_mass() const { return mass_; }
  // Axis (0, 1, 2) of a driven reverse-Poiseuille flow or of the Lees-Edwards shear, or -1: thermo's
  // temperature across the flow.
  int flow_axis() const {
    return box_.sheared() ? box_.shear.flow : (spec_.poiseuille.enabled ? spec_.poiseuille.flow_axis : -1);
  }
  std::uint64_t final_step() const { return final_step_; }
  // The object of type T that an installer shared (engine/installer.hpp), or null: for instance the
  // Walls of a run with [[solid]] blocks.
  template <class T>
  T* component() const { return components_.find<T>(); }
  const Walls* walls() const { return component<Walls>(); }
  Walls* walls() { return component<Walls>(); }
  // The pair stages and the many-body law's density pass (none for pairwise laws).
  const PairBackend& pair_backend() const { return *forces_; }
  const std::optional<DensitySettings>& density_settings() const { return density_; }
  const NeighborList& neighbor_list() const { return nlist_; }
  // Bonds and angles (by global id) and their force evaluation; empty without molecules.
  const BondedForces& bonded() const { return bonds_; }
  const Topology& topology() const { return bonds_.topology(); }
  // Neighbour-list builds since step 0, including those before a restart.
  std::uint64_t neighbor_builds() const { return neighbor_builds_before_ + nlist_.builds(); }
  // Thermodynamic state at the current step. Where the step computed no pair sums (no thermo row due),
  // they are computed here from the end-of-step velocities (the dissipative and random virial then
  // differ slightly from a thermo row's, which uses the predicted velocities); the forces and hence
  // the trajectory are left unchanged.
  ThermoState thermo();
  // Serialises the full dynamic state; a run restarted from it continues bit-identically.
  void write_checkpoint(const std::filesystem::path& file) const;

 private:
  void compute_forces(bool with_sums);  // local densities (if the law needs them), pair forces, bonded
                                        // forces, then the Forces stages
  // Adds the bonded forces to p (with `fast`: writes them there instead, see BondedForces::compute);
  // throws BlowUpError for a broken or over-long bond.
  void add_bonded_forces(bool with_sums, std::vector<double>* fast = nullptr, bool only_fast = false);
  // bonds.subcycles > 1: the first part of the step as r-RESPA, the bonded forces in inner steps.
  void subcycle_bonded_forces();
  void make_bonded(Topology topology);
  // The density pass of a many-body law (nullptr when the law needs none); stops the run when a local
  // density exceeds run.max_density.
  const double* compute_density();
  // The largest local density over all ranks and the smallest id holding it (collective).
  std::pair<double, std::uint32_t> densest_particle() const;
  friend struct Installation;
  // The forces of the initial state (a new run), or what a restart needs besides the checkpoint's.
  void initial_forces();
  StepContext context();
  void run_stages(StagePoint at);
  void check_health() const;
  [[noreturn]] void report_lost_particle() const;  // collective: names the step and a lost/duplicated id
  // Collective: throws the BlowUpError of a pair out of the fixed-point range whose first id (over all
  // ranks) is `first_id`; `mine` is this rank's, if any.
  [[noreturn]] void report_overflow(const std::optional<FixedPointOverflow>& mine, std::uint64_t first_id) const;
  void check_initial_overflow() const;  // collective: the forces of the initial state
  void load_checkpoint(const std::filesystem::path& file);
  // Refuses a config whose box, periodicity or species differ from the checkpoint's (naming the key).
  void check_restart_config(const StateHeader& h, const std::filesystem::path& file) const;

  SimulationSpec spec_;
  RunOptions options_;
  // The output folder's lock (on the root, with an out_dir), held for the simulation's lifetime.
  std::optional<OutputLock> output_lock_;
  Box box_;
  ParticleData p_;
  NeighborList nlist_;
  Halo halo_;
  std::unique_ptr<PairBackend> forces_;  // the pair stages (engine/pair_backend.hpp)
  BondedForces bonds_;
  IntegratorVariant integrator_;
  std::vector<double> mass_, inv_mass_;
  std::uint64_t step_ = 0;
  std::uint64_t final_step_ = 0;
  std::uint64_t start_step_ = 0;  // where this process's run began (0, or the checkpoint's step)
  std::uint64_t n_total_ = 0;
  std::vector<CheckpointSection> pending_sections_;  // from a checkpoint, until every model is installed
  std::uint64_t neighbor_builds_before_ = 0;  // builds of the run that wrote the loaded checkpoint
  std::optional<DensitySettings> density_;  // the law's density pass (many-body DPD), if any
  std::vector<double> rho_;                 // local densities of locals and ghosts from that pass
  PairSums sums_;
  std::vector<std::vector<double>> thermo_forces_;  // the step's kForce fields, kept while thermo() recomputes
  bool sums_valid_ = false;
  double bonded_seconds_ = 0;  // wall time in BondedForces::compute (run summary)
  // Multiple time stepping (bonds.subcycles > 1): the bonded force on each local particle at the
  // current positions (storage order; x, y, z per particle); p.f then holds only the other forces.
  std::vector<double> fast_;
  double run_wall_seconds_ = 0, run_bonded_seconds_ = 0;  // of the last run(), for finish()
  StageList stages_;                 // owns the stages, the analyses among them
  Components components_;            // what the installers share (walls, thermo rows, snapshot)
  // The installers' end-of-run summaries, in the order of summary_order() (each with its place there).
  std::vector<std::pair<std::size_t, Summary>> summaries_;
  std::vector<StateSection> sections_;  // the models' checkpoint sections, in the order registered
  Observers observers_;              // the index of the analyses (for the API)
};


}  // namespace mesodpd
