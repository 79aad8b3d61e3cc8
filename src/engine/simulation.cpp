// Simulation: construction, the time step and the stages it runs, health checks, checkpoints.
#include "engine/simulation.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <type_traits>
#include <bit>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <cstring>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "analysis/thermo.hpp"
#include "engine/domain_exchange.hpp"
#include "engine/installer.hpp"
#include "engine/initial_state.hpp"
#include "engine/reference_pair_loop.hpp"
#include "io/byte_buffer.hpp"
#include "io/checkpoint_file.hpp"
#include "io/state_checkpoint.hpp"

namespace mesodpd {

namespace {

// walls.equilibrate (seed 000 Sect. 3.2.2: fill the domain at the fluid's density, equilibrate, then
// freeze the particles inside the solids): the same particles as the run draws, simulated for that many
// steps as one fluid in a fully periodic box, without solids, regions, body forces or flows, with its
// own noise (a seed derived from system.seed). Returns x, y, z of every particle in id (= draw) order
// on every rank; the run then cuts its walls and regions from these positions. A bounded axis is made
// periodic here: the fluid that meets across it lies inside the walls that close that axis.
std::vector<double> equilibrated_fill(const SimulationSpec& spec, const Comm& comm) {
  SimulationSpec pre = spec;
  pre.solids.clear();
  pre.walls = WallsSpec{};
  pre.periodic = {true, true, true};
  pre.poiseuille.enabled = false;
  pre.seed = spec.seed ^ 0x9e3779b97f4a7c15ULL;
  for (SpeciesSpec& s : pre.species) {
    s.region.reset();
    s.frozen = false;
    s.body_force = {0, 0, 0};
  }
  Simulation sim(std::move(pre), RunOptions{{}, spec.walls.equilibrate, {}, false, false});
  while (sim.current_step() < spec.walls.equilibrate) sim.step();
  const ParticleData all = gather_by_id(sim.particles(), sim.halo().comm(), sim.total_particles());
  std::vector<double> xyz(3 * sim.total_particles());
  if (comm.root())
    for (std::size_t k = 0; k < all.n_local; ++k) {
      xyz[3 * k] = all.x[k];
      xyz[3 * k + 1] = all.y[k];
      xyz[3 * k + 2] = all.z[k];
    }
  if (comm.distributed()) {
    std::vector<std::byte> bytes(xyz.size() * sizeof(double));
    if (comm.root()) std::memcpy(bytes.data(), xyz.data(), bytes.size());
    comm.broadcast(bytes);
    std::memcpy(xyz.data(), bytes.data(), bytes.size());
  }
  return xyz;
}

}  // namespace

Simulation::Simulation(SimulationSpec spec, RunOptions options)
    : spec_(std::move(spec)),
      options_(std::move(options)),
      nlist_(NeighborSettings{}),
      forces_(make_pair_backend(make_pair_laws(spec_),
                                NoiseSettings{spec_.seed, spec_.noise == NoiseDistribution::Gaussian ? NoiseKind::Gaussian : NoiseKind::Uniform})) {
  if (spec_.species.empty()) throw ConfigError("species: at least one species is required");
  // One run per output folder, taken before anything is written there (the root writes every file).
  if (!options_.out_dir.empty()) Comm::world().on_root([&] { output_lock_.emplace(options_.out_dir); });
  density_ = make_density_settings(spec_);
  // Cells (and so ghost layers) also reach as far as the longest bond allowed (bonds.reach).
  nlist_ = NeighborList(NeighborSettings{std::max(forces_->max_cutoff(), spec_.bond_reach),
                                         spec_.neighbor == NeighborMethod::Verlet ? spec_.skin : 0.0, true});
  if (spec_.integrator == IntegratorKind::GrootWarren)
    integrator_ = GrootWarrenIntegrator{spec_.lambda};
  else
    integrator_ = EulerIntegrator{};
  for (const auto& s : spec_.species) {
    mass_.push_back(s.mass);
    // Frozen wall particles have infinite mass: the integrator leaves their velocity (the wall's) alone.
    inv_mass_.push_back(s.frozen ? 0.0 : 1.0 / s.mass);
  }
  final_step_ = options_.steps ? *options_.steps : spec_.steps;
  const bool restarted = !options_.restart.empty();
  const Comm comm = Comm::world();
  box_.periodic = spec_.periodic;
  // Moving images, if a model imposes them (Lees-Edwards shear; engine/installer.hpp, Model::shear).
  for (const Model& model : models())
    if (model.shear)
      if (const std::optional<ShearImages> images = model.shear(spec_)) {
        if (box_.sheared()) throw std::logic_error("two models set the box's shear images (" + model.name + ")");
        box_.shear = *images;
      }
  std::array<int, 3> rank_grid = spec_.parallel_grid;
  if (box_.sheared()) {
    // The flow axis stays whole on every rank: the shifted images across the gradient faces then lie
    // on the same rank as the unshifted ones.
    const auto f = static_cast<std::size_t>(box_.shear.flow);
    if (rank_grid[f] > 1)
      throw ConfigError(fmt::format("parallel.grid: {} splits the flow axis {} of the Lees-Edwards shear over {} ranks; "
                                    "use 1 (or 0) along {}",
                                    format_grid(rank_grid), "xyz"[f], rank_grid[f], "xyz"[f]),
                        "parallel.grid");
    rank_grid[f] = 1;
  }
  const double range = nlist_.settings().cutoff + nlist_.settings().skin;
  auto check_box = [&] {
    const double two_rc = 2 * forces_->max_cutoff();
    if (box_.len.x < two_rc || box_.len.y < two_rc || box_.len.z < two_rc)
      throw ConfigError("system.box: every box length must be at least twice the largest cutoff");
  };
  auto decompose = [&] {
    halo_ = Halo(comm, Decomposition::make(comm.size(), comm.rank(), CellGrid::dims_for(box_, range),
                                           {box_.len.x, box_.len.y, box_.len.z}, rank_grid, range,
                                           box_.periodic));
  };
  std::vector<double> equilibrated;
  if (!restarted && spec_.walls.equilibrate > 0) equilibrated = equilibrated_fill(spec_, comm);
  const std::vector<double>* placed = equilibrated.empty() ? nullptr : &equilibrated;
  if (!restarted && spec_.data_file.empty() && comm.distributed()) {
    // A generated system: each rank creates only the particles of its own cells.
    box_.len = {spec_.box[0], spec_.box[1], spec_.box[2]};
    check_box();
    decompose();
    const CellGrid global(box_, range);
    Topology topology;
    n_total_ = make_initial_state(spec_, box_, p_,
                                  [&](double x, double y, double z) { return halo_.owns(x, y, z, global); },
                                  &topology, placed);
    make_bonded(std::move(topology));
  } else {
    // A checkpoint or data file is read whole on every rank, which then keeps its own particles.
    if (restarted) {
      load_checkpoint(options_.restart);
    } else {
      Topology topology;
      make_initial_state(spec_, box_, p_, {}, &topology, placed);
      make_bonded(std::move(topology));
    }
    n_total_ = p_.n_local;
    check_box();
    decompose();
    halo_.keep_owned(p_, CellGrid(box_, range));
#if defined(__GLIBC__)
    // Hand the memory of the whole system back to the system.
    if (comm.distributed()) malloc_trim(0);
#endif
  }
  // The images of the starting time (a restart continues the offset exactly: it is a function of the step).
  box_.set_time(static_cast<double>(step_) * spec_.dt);
  start_step_ = step_;
  // Every model joins through its installer, in the order of engine/installers.cpp.
  std::vector<Summary> summaries;
  Installation setup{*this, spec_, options_, restarted, stages_, components_, summaries, sections_, observers_, {}, -1};
  const std::vector<std::string>& order = summary_order();
  bool thermo_installed = false;
  for (const Model& model : models()) {
    model.install(setup);
    // Thermo columns reach the thermo rows only from models installed before them; a later one would be
    // dropped in silence.
    if (thermo_installed && !setup.thermo_columns.empty())
      throw std::logic_error("model " + model.name +
                             " adds thermo columns after the thermo rows; register it before \"thermo\" "
                             "(engine/installer.hpp)");
    if (model.name == "thermo") thermo_installed = true;
    const auto place = static_cast<std::size_t>(std::find(order.begin(), order.end(), model.name) - order.begin());
    for (Summary& part : summaries) summaries_.emplace_back(place, std::move(part));
    summaries.clear();
  }
  std::stable_sort(summaries_.begin(), summaries_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  // The models' checkpoint sections, by name: each loads its own from the restart's checkpoint.
  for (std::size_t k = 0; k < sections_.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      if (sections_[j].name == sections_[k].name)
        throw std::logic_error("two checkpoint sections are named " + sections_[k].name + " (engine/installer.hpp)");
  const std::string file = options_.restart.string();
  for (const StateSection& section : sections_)
    for (const CheckpointSection& stored : pending_sections_)
      if (stored.name == section.name) {
        ByteReader r(stored.bytes, file);
        section.load(r, file);
      }
  pending_sections_.clear();
}

StepContext Installation::context() const { return sim.context(); }

void Installation::initial_forces() { sim.initial_forces(); }

void Installation::refresh() {
  rebuild_neighbors(sim.nlist_, sim.p_, sim.box_, sim.halo_);
  sim.compute_forces(true);
}

void Simulation::initial_forces() {
  if (options_.restart.empty()) {
    rebuild_neighbors(nlist_, p_, box_, halo_);
    compute_forces(true);
    // The initial forces must be representable too (collective; a restart's were checked when written).
    check_initial_overflow();
  } else if (spec_.bond_subcycles > 1) {
    // The checkpoint holds the other forces; the bonded ones at the same positions are recomputed
    // (integer sums: the same bits as the interrupted run had). They need the ghosts, whose build is
    // not counted as a neighbour-list build of the run.
    rebuild_neighbors(nlist_, p_, box_, halo_, ParticleData::Forces::Keep);
    if (neighbor_builds_before_ > 0) --neighbor_builds_before_;
    add_bonded_forces(false, &fast_, true);
  }
}


Simulation::~Simulation() = default;

StepContext Simulation::context() {
  const bool by_cell = nlist_.cell_order_of(p_);
  return StepContext{.particles = p_,
                     .box = box_,
                     .comm = halo_.comm(),
                     .step = step_,
                     .dt = spec_.dt,
                     .species_mass = mass_,
                     .pair_sums = sums_valid_ ? &sums_ : nullptr,
                     .total_particles = n_total_,
                     .neighbor_builds = neighbor_builds(),
                     .topology = &bonds_.topology(),
                     .cells = by_cell ? &nlist_.grid() : nullptr,
                     .cell_start = by_cell ? nlist_.cell_start().data() : nullptr,
                     .cell_slack = 0.5 * nlist_.settings().skin};
}

void Simulation::run_stages(StagePoint at) {
  if (stages_.empty(at)) return;
  StepContext ctx = context();
  stages_.run(at, ctx);
}

void Simulation::make_bonded(Topology topology) {
  if (topology.empty()) return;
  std::vector<BondParams> bt;
  for (const BondTypeSpec& b : spec_.bond_types) {
    BondParams q;
    q.style = b.style == BondStyleSpec::Harmonic ? BondStyle::Harmonic
                                                 : (b.style == BondStyleSpec::Fene ? BondStyle::Fene : BondStyle::Wlc);
    q.k = b.style == BondStyleSpec::Wlc ? spec_.kT / (4.0 * b.persistence) : b.k;  // seed 000 Eq. 26
    q.r0 = b.r0;
    q.rmax = b.rmax;
    bt.push_back(q);
  }
  std::vector<AngleParams> at;
  for (const AngleTypeSpec& a : spec_.angle_types) at.push_back(make_angle_params(a.k, a.theta0_deg * M_PI / 180.0));
  std::uint32_t max_id = 0;
  for (const Bond& b : topology.bonds) {
    max_id = std::max({max_id, b.a, b.b});
    if (b.type < 0 || static_cast<std::size_t>(b.type) >= bt.size())
      throw ConfigError(fmt::format("bond {}-{} has type {}, but the config defines {} [[bond_type]] blocks (a bond "
                                    "type without parameters)", b.a, b.b, b.type + 1, bt.size()));
  }
  for (const Angle& a : topology.angles) {
    max_id = std::max({max_id, a.a, a.b, a.c});
    if (a.type < 0 || static_cast<std::size_t>(a.type) >= at.size())
      throw ConfigError(fmt::format("angle {}-{}-{} has type {}, but the config defines {} [[angle_type]] blocks (an "
                                    "angle type without parameters)", a.a, a.b, a.c, a.type + 1, at.size()));
  }
  std::vector<DihedralParams> dt;
  for (const DihedralTypeSpec& d : spec_.dihedral_types) dt.push_back({d.k, d.theta0_deg * M_PI / 180.0});
  for (const Dihedral& d : topology.dihedrals) {
    max_id = std::max({max_id, d.a, d.b, d.c, d.d});
    if (d.type < 0 || static_cast<std::size_t>(d.type) >= dt.size())
      throw ConfigError(fmt::format("dihedral {}-{}-{}-{} has type {}, but the config defines {} [[dihedral_type]] "
                                    "blocks (a dihedral type without parameters)", d.a, d.b, d.c, d.d, d.type + 1,
                                    dt.size()));
  }
  bonds_ = BondedForces(std::move(topology), std::move(bt), std::move(at),
                        std::max(spec_.bond_reach, forces_->max_cutoff()), max_id, spec_.bond_exclusion,
                        std::move(dt));
}

void Simulation::add_bonded_forces(bool with_sums, std::vector<double>* fast, bool only_fast) {
  // Excluded bonded pairs (bonds.exclude): the pair loop's own passes recompute their pair force, which
  // is subtracted in integers, so the shared loop needs no per-pair test.
  const PairSubtractor subtract = [&](std::span<const std::uint32_t> pairs, std::int64_t* fixed, std::int64_t* totals) {
    // Many-body laws read the local densities of this step's density pass (locals and ghosts, the same
    // storage order as the pairs' indices).
    forces_->subtract_pairs(p_, box_, pairs, step_, spec_.dt, with_sums, fixed, totals,
                            density_ ? rho_.data() : nullptr);
  };
  const double t0 = omp_get_wtime();
  const std::optional<BondProblem> problem =
      bonds_.compute(p_, box_, halo_, with_sums, sums_, subtract, fast, only_fast);
  bonded_seconds_ += omp_get_wtime() - t0;
  if (!problem) return;
  const Topology& t = bonds_.topology();
  if (problem->kind == BondProblem::AngleTooLong || problem->kind == BondProblem::DihedralTooLong) {
    // A partner of the evaluating atom (an angle's centre, a dihedral's b) beyond the ghost layer.
    const bool angle = problem->kind == BondProblem::AngleTooLong;
    const std::uint32_t owner = angle ? t.angles[problem->index].b : t.dihedrals[problem->index].b;
    const std::string ids = angle ? fmt::format("{}, {}, {}", t.angles[problem->index].a, owner, t.angles[problem->index].c)
                                  : fmt::format("{}, {}, {}, {}", t.dihedrals[problem->index].a, owner,
                                                t.dihedrals[problem->index].c, t.dihedrals[problem->index].d);
    throw BlowUpError(step_, owner,
                      fmt::format("{} {} (particle ids {}) at step {}: a partner of atom {} lies beyond the ghost layer "
                                  "of its rank (which reaches at least bonds.reach = {}); raise bonds.reach (wider "
                                  "neighbour cells) or use stiffer bonds",
                                  angle ? "angle" : "dihedral", problem->index + 1, ids, step_, owner, bonds_.reach()));
  }
  const Bond& b = t.bonds[problem->index];
  if (problem->kind == BondProblem::Broken) {
    const BondParams& q = bonds_.bond_types()[static_cast<std::size_t>(b.type)];
    throw BlowUpError(step_, std::min(b.a, b.b),
                      fmt::format("bond {} (particle ids {} and {}, type {}) is stretched to {} at step {}, at or past "
                                  "its maximum length rmax = {} ({}); reduce integrator.dt or check the forces",
                                  problem->index + 1, b.a, b.b, b.type + 1, problem->length, step_, q.rmax,
                                  q.style == BondStyle::Fene ? "FENE" : "worm-like chain"));
  }
  throw BlowUpError(step_, std::min(b.a, b.b),
                    fmt::format("bond {} (particle ids {} and {}) at step {}: the partner lies beyond the ghost layer "
                                "of the rank that evaluates the bond (which reaches at least bonds.reach = {}); raise "
                                "bonds.reach (wider neighbour cells) or use stiffer bonds",
                                problem->index + 1, b.a, b.b, step_, bonds_.reach()));
}

void Simulation::compute_forces(bool with_sums) {
  // A many-body law first needs every particle's local density (ghosts included), then the force pass.
  const double* rho = compute_density();
  forces_->compute(p_, box_, nlist_, step_, spec_.dt, with_sums, sums_, &halo_, rho);
  // With subcycles, the bonded forces go to fast_ for the inner steps of the next step.
  add_bonded_forces(with_sums, spec_.bond_subcycles > 1 ? &fast_ : nullptr);
  sums_valid_ = with_sums;
  // External fields, walls, bonds: each adds to the pair forces, in registration order.
  run_stages(StagePoint::Forces);
}

void Simulation::step() {
  // 1. First part of the integrator: positions and the velocity the forces will see (with
  //    bonds.subcycles > 1 the bonded forces act in inner steps here, and the rest below).
  if (spec_.bond_subcycles > 1)
    subcycle_bonded_forces();
  else
    std::visit([&](const auto& integ) { integ.pre_force(p_, inv_mass_, spec_.dt); }, integrator_);
  // 2. Box boundaries: periodic wrap of the local particles (with shear, the images of the new time); a
  //    particle outside a bounded axis is lost.
  box_.set_time(static_cast<double>(step_ + 1) * spec_.dt);
  if (const auto lost = apply_box_boundaries(p_, box_, halo_.comm()))
    throw BlowUpError(step_ + 1, lost->id,
                      fmt::format("particle id {} left the box at step {}: position ({}, {}, {}) is outside [0, {}) "
                                  "along {}, which is bounded (system.periodic) with nothing to keep it in",
                                  lost->id, step_ + 1, lost->x, lost->y, lost->z, box_.length(lost->axis),
                                  "xyz"[lost->axis]));
  ++step_;
  // Constraints on the new positions (reflections at walls).
  run_stages(StagePoint::AfterFirstHalf);
  // 3. Neighbour list, rebuilt only when some particle has moved half the skin. Under MPI a rebuild
  //    migrates particles to their owners and rebuilds the ghosts; otherwise the ghosts are refreshed.
  update_neighbors(nlist_, p_, box_, halo_);
  run_stages(StagePoint::AfterNeighbors);
  // 4. Forces at the new positions: pair forces (ghost forces back to their owners), then the Forces
  //    stages (external fields); pair sums only where a stage reads them at this step (thermo output).
  compute_forces(stages_.wants_pair_sums(step_));
  // 5. Second part of the integrator, then the stages that act on its velocities (thermostats).
  std::visit([&](const auto& integ) { integ.post_force(p_, inv_mass_, spec_.dt); }, integrator_);
  run_stages(StagePoint::AfterSecondHalf);
  // 6. Stop on NaN or runaway velocity before anything is written.
  check_health();
  // 7. Measure and write: the analyses, then the periodic checkpoint.
  run_stages(StagePoint::EndOfStep);
}

void Simulation::subcycle_bonded_forces() {
  // r-RESPA (Tuckerman, Berne and Martyna, J. Chem. Phys. 97, 1990 (1992); the "subcycling" of seed
  // 002): the pair and external forces F (in p.f) kick for half an outer step dt, the bonded forces
  // F_b (in fast_) are integrated by velocity Verlet with n inner steps dt/n, and F at the new positions
  // kicks for the other half in post_force(). The velocity the new F sees is predicted as Groot-Warren's
  // with lambda: v~ = v + (lambda - 1/2) dt F/m after the inner steps (lambda = 1/2: no prediction).
  const std::size_t n = p_.n_local;
  const double dt = spec_.dt, h = dt / spec_.bond_subcycles, lambda = spec_.lambda;
  auto kick = [&](double tau, const double* fx, const double* fy, const double* fz, std::size_t stride) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double c = tau * inv_mass_[static_cast<std::size_t>(p_.species[i])];
      p_.vx[i] += c * fx[stride * i];
      p_.vy[i] += c * fy[stride * i];
      p_.vz[i] += c * fz[stride * i];
    }
  };
  kick(0.5 * dt, p_.fx.data(), p_.fy.data(), p_.fz.data(), 1);
  for (int k = 0; k < spec_.bond_subcycles; ++k) {
    kick(0.5 * h, fast_.data(), fast_.data() + 1, fast_.data() + 2, 3);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      p_.x[i] += h * p_.vx[i];
      p_.y[i] += h * p_.vy[i];
      p_.z[i] += h * p_.vz[i];
    }
    halo_.update_ghosts(p_);  // partners on other ranks (positions only matter: the laws are conservative)
    add_bonded_forces(false, &fast_, true);
    kick(0.5 * h, fast_.data(), fast_.data() + 1, fast_.data() + 2, 3);
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    p_.hx[i] = p_.vx[i];
    p_.hy[i] = p_.vy[i];
    p_.hz[i] = p_.vz[i];
  }
  kick((lambda - 0.5) * dt, p_.fx.data(), p_.fy.data(), p_.fz.data(), 1);
}

const double* Simulation::compute_density() {
  if (!density_) return nullptr;
  rho_.resize(p_.size());  // locals and ghosts; the backend fills it, it does not size it
  forces_->compute_density(p_, box_, nlist_, *density_, rho_, &halo_);
  const auto [rho, id] = densest_particle();
  if (rho > spec_.max_density)
    throw BlowUpError(step_, id,
                      fmt::format("simulation blew up at step {}: particle id {} has local density {:.4g} > "
                                  "run.max_density = {} (the fluid is collapsing: check that B_ij > 0 is large enough "
                                  "against A_ij < 0, or reduce integrator.dt)",
                                  step_, id, rho, spec_.max_density));
  return rho_.data();
}

std::pair<double, std::uint32_t> Simulation::densest_particle() const {
  // Non-negative doubles order like their bit patterns, so an integer max over ranks finds the largest.
  std::uint64_t best = 0;
  const std::size_t n = std::min(p_.n_local, rho_.size());
  for (std::size_t i = 0; i < n; ++i) best = std::max(best, std::bit_cast<std::uint64_t>(std::abs(rho_[i])));
  const Comm& comm = halo_.comm();
  if (comm.distributed()) best = comm.max(best);
  std::uint64_t id = std::numeric_limits<std::uint64_t>::max();
  for (std::size_t i = 0; i < n; ++i)
    if (std::bit_cast<std::uint64_t>(std::abs(rho_[i])) == best) id = std::min<std::uint64_t>(id, p_.id[i]);
  if (comm.distributed()) id = comm.min(id);
  return {std::bit_cast<double>(best), static_cast<std::uint32_t>(id)};
}

void Simulation::check_health() const {
  const std::size_t n = p_.n_local;
  if (halo_.active() && halo_.total_after_migration() != n_total_) report_lost_particle();
  const double vmax2 = spec_.max_velocity * spec_.max_velocity;
  auto unhealthy = [&](std::size_t i) {
    const double v2 = p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i] + p_.vz[i] * p_.vz[i];
    const bool finite = std::isfinite(p_.x[i]) && std::isfinite(p_.y[i]) && std::isfinite(p_.z[i]) && std::isfinite(v2);
    return !finite || v2 > vmax2;
  };
  std::size_t bad = n;
#pragma omp parallel for reduction(min : bad) schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    if (unhealthy(i)) bad = std::min(bad, i);
  // Report the smallest id among offenders (over all ranks) so the message does not depend on storage
  // order or rank count.
  std::uint64_t id = std::numeric_limits<std::uint64_t>::max();
  if (bad != n) {
    id = p_.id[bad];
    for (std::size_t i = bad + 1; i < n; ++i)
      if (p_.id[i] < id && unhealthy(i)) {
        id = p_.id[i];
        bad = i;
      }
  }
  // A pair contribution out of the fixed-point range (ForceCompute: free while every value is in
  // range) comes first: it is the cause when both trip. One reduction finds either: keys below 2^32
  // are the first id of such a pair, keys from 2^32 on a fast or non-finite particle.
  const std::optional<FixedPointOverflow> overflow = forces_->take_overflow();
  constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max(), kParticle = std::uint64_t{1} << 32;
  std::uint64_t key = overflow ? overflow->id_a : (id == kNone ? kNone : kParticle + id);
  const Comm& comm = halo_.comm();
  if (comm.distributed()) key = comm.min(key);
  if (key < kParticle) report_overflow(overflow, key);
  id = key == kNone ? kNone : key - kParticle;
  if (id == std::numeric_limits<std::uint64_t>::max()) return;
  // The owner contributes the particle's state; the others add zeros.
  double state[4] = {0, 0, 0, 0};
  if (bad != n && p_.id[bad] == id) {
    state[0] = p_.x[bad];
    state[1] = p_.y[bad];
    state[2] = p_.z[bad];
    state[3] = std::sqrt(p_.vx[bad] * p_.vx[bad] + p_.vy[bad] * p_.vy[bad] + p_.vz[bad] * p_.vz[bad]);
  }
  comm.sum(std::span<double>(state, 4));
  std::string density;
  if (density_) {
    const auto [rho, densest] = densest_particle();
    density = fmt::format("; the largest local density at this step's force evaluation was {:.4g} (particle id {})",
                          rho, densest);
  }
  throw BlowUpError(step_, static_cast<std::uint32_t>(id),
                    fmt::format("simulation blew up at step {}: particle id {} has position ({}, {}, {}) and speed {} "
                                "(run.max_velocity = {}){}; reduce integrator.dt or check the forces",
                                step_, id, state[0], state[1], state[2], state[3], spec_.max_velocity, density));
}

void Simulation::report_overflow(const std::optional<FixedPointOverflow>& mine, std::uint64_t first_id) const {
  // Collective, on every rank after the same reduction. The lowest rank holding a pair with that first
  // id describes it; the others add zeros.
  const Comm& comm = halo_.comm();
  constexpr std::uint64_t kNone = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t partner = mine && mine->id_a == first_id ? mine->id_b : kNone;
  if (comm.distributed()) partner = comm.min(partner);
  const bool holder = mine && mine->id_a == first_id && mine->id_b == partner;
  std::uint64_t rank = holder ? static_cast<std::uint64_t>(comm.rank()) : kNone;
  if (comm.distributed()) rank = comm.min(rank);
  double info[4] = {0, 0, 0, 0};  // kind, other id, value, limit
  if (holder && rank == static_cast<std::uint64_t>(comm.rank()))
    info[0] = static_cast<double>(mine->what), info[1] = mine->id_b, info[2] = mine->value, info[3] = mine->limit;
  if (comm.distributed()) comm.sum(std::span<double>(info, 4));
  const auto what = static_cast<FixedPointOverflow::What>(static_cast<int>(info[0]));
  const auto other = static_cast<std::uint32_t>(info[1]);
  const double value = info[2], limit = info[3];
  const auto id = static_cast<std::uint32_t>(first_id);
  if (std::isnan(value))
    throw BlowUpError(step_, id,
                      fmt::format("simulation blew up at step {}: the pair force between particle ids {} and {} is not a "
                                  "number; reduce integrator.dt or check the forces",
                                  step_, id, other));
  const std::string advice =
      "forces this large are far from DPD scales: express the system in reduced units where pair.a, the bond "
      "constants and the masses are of order 1 to 100 (a mass of 1e6 with a = 1e8 is the same physics as mass 1 "
      "with a = 100), or raise integrator.dt if it is the random force sigma / sqrt(dt) that is large";
  if (what == FixedPointOverflow::What::PairVirial && std::isinf(value))
    throw BlowUpError(step_, id,
                      fmt::format("fixed-point overflow at step {}: the virial (pressure) or energy totals of the pairs "
                                  "left the 64-bit range of the fixed-point sums, so the pressure and energy would be "
                                  "wrong; {}",
                                  step_, advice));
  if (what == FixedPointOverflow::What::PairVirial)
    throw BlowUpError(step_, id,
                      fmt::format("fixed-point overflow at step {}: the virial (pressure) sums of the pair of particle "
                                  "ids {} and {} left the range of the fixed-point sums (|r F| up to {:.3g} per pair, "
                                  "totals within 64 bits), so the pressure and energy would be wrong; {}",
                                  step_, id, other, limit, advice));
  if (what == FixedPointOverflow::What::ScalarRate)
    throw BlowUpError(step_, id,
                      fmt::format("fixed-point overflow at step {}: the rate of a transported scalar (eDPD's dT/dt, "
                                  "tDPD's dC/dt) from the pair of particle ids {} and {} is {:.4g}, beyond the {:.4g} per "
                                  "pair that the fixed-point sums represent: the scalar has diverged (a time step too "
                                  "large for kappa, or a random flux too strong) or its coefficients are far from "
                                  "reduced units",
                                  step_, id, other, value, limit));
  throw BlowUpError(step_, id,
                    fmt::format("fixed-point overflow at step {}: the {} of the pair of particle ids {} and {} is {:.4g}, "
                                "beyond the {:.4g} per pair that the fixed-point sums represent (engine/fixed_point.hpp), "
                                "so the forces would be clamped or wrap; {}",
                                step_, what == FixedPointOverflow::What::Density ? "density weight" : "force component", id,
                                other, value, limit, advice));
}

void Simulation::report_lost_particle() const {
  // Every rank sees the same total (it came from an all-reduce), so all of them get here together.
  const Comm& comm = halo_.comm();
  const std::uint64_t count = halo_.total_after_migration();
  // Name the smallest id that is missing or held twice.
  std::vector<std::uint32_t> mine(p_.id.begin(), p_.id.begin() + static_cast<std::ptrdiff_t>(p_.n_local));
  const std::vector<std::byte> bytes = comm.gather(std::as_bytes(std::span<const std::uint32_t>(mine)));
  std::uint64_t culprit = std::numeric_limits<std::uint64_t>::max();
  if (comm.root()) {
    std::vector<std::uint32_t> ids(bytes.size() / sizeof(std::uint32_t));
    if (!ids.empty()) std::memcpy(ids.data(), bytes.data(), ids.size() * sizeof(std::uint32_t));
    std::sort(ids.begin(), ids.end());
    for (std::size_t k = 1; k < ids.size() && culprit == std::numeric_limits<std::uint64_t>::max(); ++k)
      if (ids[k] == ids[k - 1]) culprit = ids[k];
    for (std::size_t k = 1; k < ids.size() && culprit == std::numeric_limits<std::uint64_t>::max(); ++k)
      if (ids[k] != ids[k - 1] + 1) culprit = ids[k - 1] + 1;
  }
  culprit = comm.min(culprit);
  throw BlowUpError(step_, static_cast<std::uint32_t>(culprit),
                    fmt::format("particle lost or duplicated at step {}: {} particles on {} ranks, {} expected (first "
                                "affected id {}); this is a bug in the domain decomposition, please report it",
                                step_, count, comm.size(), n_total_, culprit));
}

void Simulation::check_initial_overflow() const {
  const std::optional<FixedPointOverflow> overflow = forces_->take_overflow();
  std::uint64_t key = overflow ? overflow->id_a : std::numeric_limits<std::uint64_t>::max();
  if (halo_.comm().distributed()) key = halo_.comm().min(key);
  if (key != std::numeric_limits<std::uint64_t>::max()) report_overflow(overflow, key);
}

const std::vector<std::string>& Simulation::warnings() const {
  return observers_.warnings();
}

std::optional<std::string> Simulation::runaway_temperature() const {
  const double ratio = spec_.max_temperature_ratio;
  if (!(ratio > 0)) return std::nullopt;
  // A short run may still carry the heat of a random start (an mDPD slab is at 5.8 kT after 20 steps of
  // dt = 0.01, 1.7 kT after 200): those get the warning only.
  if (static_cast<double>(final_step_ - start_step_) * spec_.dt < kRunawayMinTime) return std::nullopt;
  const std::optional<double> t = observers_.late_temperature();
  if (!t || (!(*t > ratio * spec_.kT) && std::isfinite(*t))) return std::nullopt;  // NaN and infinity are runaways
  return fmt::format("the run ran away: its mean temperature over the second half of the run, {:.4g}, is {:.3g} "
                     "times the target kT = {} (more than run.max_temperature_ratio = {}), so its results are not to "
                     "be trusted; reduce integrator.dt or check the forces (set run.max_temperature_ratio = 0 to "
                     "accept a run that heats up)",
                     *t, *t / spec_.kT, spec_.kT, ratio);
}

ThermoState Simulation::thermo() {
  if (!sums_valid_) {
    // Pair sums of the current state. The forces the next step integrates with were evaluated at the
    // integrator's predicted velocities, which are gone: a recomputation from the end-of-step velocities
    // would differ, so every field the force stage writes (kForce: the forces, eDPD's temperature
    // rates) is put back and sampling does not change the trajectory.
    std::size_t k = 0;
    p_.for_each_field([&](const FieldInfo& info, auto& v) {
      if constexpr (std::is_same_v<typename std::decay_t<decltype(v)>::value_type, double>)
        if (info.flags & field::kForce) {
          if (thermo_forces_.size() <= k) thermo_forces_.emplace_back();
          thermo_forces_[k++] = v;
        }
    });
    const double* rho = compute_density();  // positions unchanged: the same densities as the step's
    forces_->compute(p_, box_, nlist_, step_, spec_.dt, true, sums_, &halo_, rho);
    add_bonded_forces(true);
    k = 0;
    p_.for_each_field([&](const FieldInfo& info, auto& v) {
      if constexpr (std::is_same_v<typename std::decay_t<decltype(v)>::value_type, double>)
        if (info.flags & field::kForce) thermo_forces_[k++].swap(v);
    });
    sums_valid_ = true;
  }
  std::vector<std::uint8_t> frozen;
  for (const auto& s : spec_.species) frozen.push_back(s.frozen ? 1 : 0);
  ThermoState t = compute_thermo(p_, mass_, box_, sums_, flow_axis(), halo_.comm(), frozen);
  t.step = step_;
  t.time = static_cast<double>(step_) * spec_.dt;
  t.neighbor_builds = neighbor_builds();
  return t;
}

std::string Simulation::run() {
  const double t0 = omp_get_wtime();
  const double bonded0 = bonded_seconds_;
  while (step_ < final_step_) step();
  run_wall_seconds_ = omp_get_wtime() - t0;
  run_bonded_seconds_ = bonded_seconds_ - bonded0;
  return finish();
}

std::string Simulation::finish() {
  std::string summary;
  if (!bonds_.empty() && halo_.comm().root() && run_wall_seconds_ > 0)
    summary += fmt::format("bonded forces: {} bonds, {} angles, {} dihedrals, {:.3g} s of {:.3g} s ({:.1f}% of the steps)\n",
                           bonds_.topology().bonds.size(), bonds_.topology().angles.size(),
                           bonds_.topology().dihedrals.size(), run_bonded_seconds_,
                           run_wall_seconds_, 100.0 * run_bonded_seconds_ / run_wall_seconds_);
  if (!options_.out_dir.empty()) write_checkpoint(options_.out_dir / "checkpoint.mdpd");
  // The summaries are collective (the analyses' write their files and text on the root, and a failed
  // write there stops every rank).
  const StepContext ctx = context();
  for (const auto& entry : summaries_) summary += entry.second(ctx);
  return summary;
}

void Simulation::write_checkpoint(const std::filesystem::path& file) const {
  // The whole system in id order, written by the root: the file does not depend on the rank count,
  // and a run restarts from it on any number of ranks.
  const ParticleData all = gather_by_id(p_, halo_.comm(), n_total_);
  halo_.comm().on_root([&] {
    StateHeader h;
    h.step = step_;
    h.neighbor_builds = neighbor_builds();
    h.seed = spec_.seed;
    h.dt = spec_.dt;
    h.n_species = spec_.species.size();
    h.box = {box_.len.x, box_.len.y, box_.len.z};
    h.has_config = true;
    h.periodic = box_.periodic;
    for (const SpeciesSpec& sp : spec_.species) h.species.push_back({sp.name, sp.mass, sp.count, sp.frozen});
    std::vector<CheckpointSection> sections;
    for (const StateSection& section : sections_) {
      ByteWriter w;
      section.save(w);
      sections.push_back({section.name, w.take()});
    }
    write_state_checkpoint(file, h, all, sections, &bonds_.topology());
  });
}

void Simulation::check_restart_config(const StateHeader& h, const std::filesystem::path& file) const {
  // The particles, their box and their species come from the checkpoint: a config that describes
  // another system would be ignored in silence, so every such key must keep the checkpoint's value.
  auto refuse = [&](const std::string& key, const std::string& ours, const std::string& theirs) {
    throw ConfigError(fmt::format("{}: {} differs from the checkpoint's {} ({}); the checkpoint fixes it, so set {} = {} "
                                  "to continue that run, or start a new run without --restart",
                                  key, ours, theirs, file.string(), key, theirs),
                      key);
  };
  auto triple = [](const auto& v) { return fmt::format("[{}, {}, {}]", v[0], v[1], v[2]); };
  if (h.box != spec_.box) refuse("system.box", triple(spec_.box), triple(h.box));
  if (!h.has_config) return;  // a format 5 checkpoint stores no more
  if (h.periodic != spec_.periodic) refuse("system.periodic", triple(spec_.periodic), triple(h.periodic));
  for (std::size_t k = 0; k < h.species.size() && k < spec_.species.size(); ++k) {
    const CheckpointSpecies& theirs = h.species[k];
    const SpeciesSpec& ours = spec_.species[k];
    const std::string key = fmt::format("species[{}]", k);
    if (ours.name != theirs.name) refuse(key + ".name", fmt::format("\"{}\"", ours.name), fmt::format("\"{}\"", theirs.name));
    if (ours.mass != theirs.mass) refuse(key + ".mass", fmt::format("{}", ours.mass), fmt::format("{}", theirs.mass));
    if (ours.count != theirs.count)
      refuse(key + ".count", fmt::format("{} (from count or density)", ours.count), fmt::format("{}", theirs.count));
    if (ours.frozen != theirs.frozen)
      refuse(key + ".frozen", ours.frozen ? "true" : "false", theirs.frozen ? "true" : "false");
  }
}

void Simulation::load_checkpoint(const std::filesystem::path& file) {
  StateCheckpoint c = read_state_checkpoint(file);
  const StateHeader& h = c.header;
  if (h.n_species != spec_.species.size())
    throw ConfigError(fmt::format("{}: checkpoint has {} species but the config defines {}", file.string(), h.n_species,
                                  spec_.species.size()));
  if (h.seed != spec_.seed)
    throw ConfigError(fmt::format("system.seed: {} differs from the checkpoint's seed {} ({})", spec_.seed, h.seed,
                                  file.string()),
                      "system.seed");
  // The stored forces and the integrator's state belong to the checkpoint's time step, and the noise
  // amplitude scales with 1/sqrt(dt): continuing with another dt would silently be another run.
  if (h.dt != spec_.dt)
    throw ConfigError(fmt::format("integrator.dt: {} differs from the checkpoint's dt {} ({}); set integrator.dt = {} "
                                  "to continue that run",
                                  spec_.dt, h.dt, file.string(), h.dt),
                      "integrator.dt");
  check_restart_config(h, file);
  step_ = h.step;
  neighbor_builds_before_ = h.neighbor_builds;
  box_.len = {h.box[0], h.box[1], h.box[2]};
  p_ = std::move(c.particles);
  make_bonded(std::move(c.topology));
  // The models' sections are loaded once every model is installed (end of the constructor).
  pending_sections_ = std::move(c.sections);
  const std::size_t n = p_.n_local;
  for (std::size_t i = 0; i < n; ++i)
    if (p_.species[i] < 0 || static_cast<std::size_t>(p_.species[i]) >= h.n_species)
      throw ConfigError(fmt::format("{}: particle {} has an invalid species", file.string(), p_.id[i]));
  if (step_ > final_step_)
    throw ConfigError(fmt::format("{}: the checkpoint {} is already at step {}, beyond the requested {}",
                                  options_.steps ? "--steps" : "run.steps", file.string(), step_, final_step_));
}

}  // namespace mesodpd
