// The public simulation object: build a run from a SimulationSpec, advance it, read its state. A thin
// facade over the engine (src/engine/simulation.hpp); a program or the Python module needs only the
// headers in include/mesodpd/. Units: DPD reduced units throughout (lengths in r_c, masses in particle
// mass, energies in k_BT, time in r_c sqrt(m / k_BT)).
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <stdexcept>
#include <string>
#include <vector>

#include "mesodpd/spec.hpp"
#include "mesodpd/validate.hpp"

namespace mesodpd::api {

// How a run is driven; the physics is all in the spec.
struct Options {
  std::filesystem::path output_dir;          // thermo.csv, trajectory, analyses, checkpoint; empty: no files
  std::filesystem::path restart;             // continue from this checkpoint file; empty: a new run
  std::optional<std::uint64_t> final_step;   // where run() stops, instead of spec.steps
  bool progress = false;                     // progress bar on the terminal
  // Measure thermo rows, profile, RDF and MSD (as the spec configures them) and keep them in memory
  // even without an output_dir (thermo_history(), profile(), rdf(), msd()). With an output_dir they are
  // always kept. Does not change the trajectory.
  bool record = false;
};

// The run went unstable (NaN, or a particle faster than spec.max_velocity); the state is that of the
// failed step.
class BlowUpError : public std::runtime_error {
 public:
  BlowUpError(const std::string& what, std::uint64_t step, std::uint32_t particle_id)
      : std::runtime_error(what), step_(step), id_(particle_id) {}
  std::uint64_t step() const { return step_; }
  std::uint32_t particle_id() const { return id_; }

 private:
  std::uint64_t step_;
  std::uint32_t id_;
};

// Instantaneous thermodynamic state of the whole system (all ranks).
struct Thermo {
  std::uint64_t step = 0;
  double time = 0.0;                        // step x dt
  double temperature = 0.0;                 // k_B T from sum m v^2 / (3N - 3), in units of energy
  double temperature_transverse = 0.0;      // the same without the flow axis of a Poiseuille run
  double pressure = 0.0;                    // trace / 3 of the pressure tensor (seed 000 Eqs. 11-12)
  std::array<double, 6> pressure_tensor{};  // xx yy zz xy xz yz: (sum m v v + sum r_ij F_ij) / V
  double pressure_conservative = 0.0;       // kinetic + conservative virial only
  std::array<double, 3> momentum{};         // total momentum sum m v
  double potential_energy = 0.0;            // total conservative pair energy
  double kinetic_energy = 0.0;              // total sum m v^2 / 2
};

// Read-only views of this rank's owned particles, in storage order (not id order: the engine sorts
// particles by cell). Valid until the next call that advances the simulation.
struct Particles {
  std::span<const std::uint32_t> id;          // global id, 1..N, stable for the whole run
  std::span<const std::int32_t> species;      // index into spec.species
  std::span<const double> x, y, z;            // positions, wrapped into [0, box)
  std::span<const double> vx, vy, vz;         // velocities
  std::span<const double> fx, fy, fz;         // total force of the last force evaluation
  std::span<const std::int32_t> ix, iy, iz;   // image counters: unwrapped x = x + ix * box[0]
};

// The whole system in increasing id order (a copy, gathered from every rank to rank 0).
struct Snapshot {
  std::vector<std::uint32_t> id;
  std::vector<std::int32_t> species;
  std::vector<double> x, y, z, vx, vy, vz, fx, fy, fz;
  std::vector<std::int32_t> ix, iy, iz;
};

// The reverse-Poiseuille velocity profile averaged so far and the viscosity fitted to it
// (analysis/velocity_profile.hpp): mean flow velocity per bin of the gradient coordinate.
struct Profile {
  int flow_axis = 0, gradient_axis = 2;       // 0, 1, 2 = x, y, z
  std::vector<double> z, v_mean, v_err, v_fit;  // bin centres, mean, standard error (NaN < 2 blocks), fit
  double eta = 0, eta_err = 0;                // fitted shear viscosity and its block error (NaN if unknown)
  int blocks_used = 0;
  std::uint64_t samples = 0;
};

// g(r) averaged over the samples so far.
struct Rdf {
  std::vector<double> r, g;  // bin centres, g(r)
  std::uint64_t samples = 0;
};

// Mean squared displacement against lag time, and D from its slope (analysis/msd.hpp).
struct Msd {
  std::vector<double> time, msd;
  double diffusion = 0;  // NaN when too few points
};

// One [analysis.fields] grid averaged so far (analysis/binned_fields.hpp). Per-cell arrays have
// bins[0] x bins[1] x bins[2] entries, x fastest.
struct Fields {
  std::string name;
  std::array<int, 3> bins{1, 1, 1};
  std::uint64_t samples = 0;
  std::vector<double> x, y, z;          // cell centres (box coordinates)
  std::vector<double> density;          // selected species, particles per volume
  std::vector<double> vx, vy, vz;       // mass-weighted mean velocity
  std::vector<double> temperature;      // mean of the three components' temperatures
};

// One [[body]] rigid body now (docs/physics.md, "Rigid bodies of frozen particles").
struct Body {
  std::string solid;                             // the [[solid]] it moves
  double mass = 0;
  std::size_t particles = 0;                     // its frozen particles
  std::array<double, 3> position{};              // centre of mass, unwrapped
  std::array<double, 4> orientation{1, 0, 0, 0};  // unit quaternion w, x, y, z: body frame to lab frame
  std::array<double, 3> velocity{}, angular_velocity{};
  std::array<double, 3> force{}, torque{};       // of this step: pair forces, bounce-backs, external, contacts
  // Of this step: the stresslet, the symmetric first moment of the forces on it about its centre (xx, yy,
  // zz, xy, xz, yz; the body's share of the stress, docs/physics.md "The stress of a suspension").
  std::array<double, 6> stresslet{};
};

class Simulation {
 public:
  // Validates `spec` (validate(); throws SpecError naming the key) and builds the initial state with
  // the forces of step 0 (throws ConfigError for a data file or checkpoint that does not fit). Sets
  // the OpenMP thread count when spec.threads > 0. Under MPI, initialise MPI first (every rank
  // constructs the same Simulation); without it the run is serial.
  explicit Simulation(SimulationSpec spec, Options options = {});
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;

  // Advances `steps` time steps, measuring and writing output as the spec says. Throws BlowUpError.
  void step(std::uint64_t steps = 1);
  // Advances to final_step(), then writes the final checkpoint and the analysis summaries (with an
  // output_dir). Returns the human-readable summary (mean temperature, viscosity, ...).
  std::string run();

  const SimulationSpec& spec() const;  // as validated
  std::uint64_t current_step() const;
  std::uint64_t final_step() const;
  double time() const;                         // current_step() x dt
  std::array<double, 3> box() const;           // box lengths
  std::uint64_t total_particles() const;       // over all ranks
  Particles particles() const;                 // this rank's owned particles
  // A model's per-particle scalar of this rank's owned particles, in the order of particles(): eDPD's
  // internal temperature "temp", tDPD's concentrations "conc1" .. "conc4" and their rates "temp_rate",
  // "conc_rate1", ... Throws std::invalid_argument naming the field when the run does not hold it.
  std::span<const double> scalar_field(std::string_view name) const;
  // Sets such a scalar ("temp", "conc<k>"; not a rate) of the owned particles from `values` (one per
  // owned particle, in the order of particles()); the next step carries the new values to the ghost
  // copies. Throws std::invalid_argument naming the field or the length that is wrong.
  void set_scalar_field(std::string_view name, std::span<const double> values);
  Thermo thermo();                             // collective under MPI: every rank calls it
  // The full dynamic state; a run restarted from it (Options::restart) continues bit-identically.
  void write_checkpoint(const std::filesystem::path& file) const;
  // What run() does after its last step, at the current step: the final checkpoint and analysis files
  // (with an output_dir) and the summary text (on rank 0). May be called more than once.
  std::string finish();

  // MPI rank of this process and the number of ranks (0 and 1 without MPI).
  int rank() const;
  int ranks() const;
  // The whole system in id order. Collective under MPI: every rank calls it; rank 0 gets the data,
  // the others an empty Snapshot.
  Snapshot gather() const;
  // The thermo rows measured so far in this process (every thermo_every steps, with an output_dir or
  // Options::record; a restarted run's history starts at the checkpoint). The same on every rank.
  std::vector<Thermo> thermo_history() const;
  // The analyses configured in the spec and measured so far; nullopt when not configured or not
  // measured (no output_dir and no Options::record). Collective: every rank gets rank 0's values.
  std::optional<Profile> profile() const;
  std::optional<Rdf> rdf() const;
  std::optional<Msd> msd() const;
  // The [analysis.fields] grids, in spec order (empty without them or without measurement).
  std::vector<Fields> fields() const;
  // The [[body]] rigid bodies in block order (empty without them); the same on every rank.
  std::vector<Body> bodies() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mesodpd::api
