// Simulation: construction, the time step, and the measurements and writers it drives.
#include "engine/simulation.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <charconv>
#include <cstring>
#include <cmath>
#include <limits>

#include "analysis/kinetic_theory.hpp"
#include "analysis/msd.hpp"
#include "analysis/rdf.hpp"
#include "analysis/svg_plot.hpp"
#include "analysis/velocity_profile.hpp"
#include "engine/initial_state.hpp"
#include "engine/progress.hpp"
#include "io/atomic_file.hpp"
#include "io/byte_buffer.hpp"
#include "io/checkpoint_file.hpp"
#include "io/frame.hpp"
#include "io/gsd_writer.hpp"
#include "io/state_checkpoint.hpp"
#include "io/lammps_dump_writer.hpp"

namespace mesodpd {

PairTable make_pair_table(const SimulationSpec& spec) {
  PairTable t;
  t.n_species = static_cast<int>(spec.species.size());
  t.params.resize(static_cast<std::size_t>(t.n_species * t.n_species));
  for (int a = 0; a < t.n_species; ++a)
    for (int b = 0; b < t.n_species; ++b) {
      const PairSpec& ps = spec.pair(a, b);
      DpdPairParams& q = t.params[static_cast<std::size_t>(a * t.n_species + b)];
      q.a = ps.a;
      q.gamma = ps.gamma;
      q.sigma = std::sqrt(2.0 * ps.gamma * spec.kT);  // seed 000 Eq. 7
      q.rc = ps.rc;
      q.rd = ps.rd;
      q.s = ps.s;
      const double range = std::max(ps.rc, ps.rd);
      q.rcut2 = range * range;
      t.max_cutoff = std::max(t.max_cutoff, range);
    }
  return t;
}

namespace {

// Leading unsigned integer of `text` (the step of a thermo row or of a dump frame).
std::optional<std::uint64_t> parse_step(const std::string& text) {
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc{} || end == text.data()) return std::nullopt;
  return v;
}

// A restarted run continues from the checkpoint's step K, but the files in the output directory may
// go further: the run that wrote the checkpoint went on (and perhaps blew up) before the restart.
// Output after K is dropped so that appending does not duplicate steps. Rows and frames are in
// increasing step order, so everything from the first one after K (or the first damaged one) goes.
void trim_thermo_csv(const std::filesystem::path& path, std::uint64_t last_step) {
  std::ifstream in(path, std::ios::binary);
  std::string line, kept;
  bool trimmed = false;
  for (bool header = true; std::getline(in, line); header = false) {
    const bool complete = !in.eof();  // a last line without '\n' was cut short by a crash
    const auto step = parse_step(line);
    if (!complete || (!header && (!step || *step > last_step))) {
      trimmed = true;
      break;
    }
    kept += line;
    kept += '\n';
  }
  in.close();
  if (trimmed) write_file_atomically(path, [&](std::ostream& os) { os << kept; });
}

void trim_lammps_dump(const std::filesystem::path& path, std::uint64_t last_step) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::optional<std::uintmax_t> cut;
  while (true) {
    const std::streamoff pos = in.tellg();
    if (!std::getline(in, line)) break;
    if (line != "ITEM: TIMESTEP") continue;
    std::optional<std::uint64_t> step;
    if (std::getline(in, line)) step = parse_step(line);
    if (!step || *step > last_step) {
      cut = static_cast<std::uintmax_t>(pos);
      break;
    }
  }
  in.close();
  if (cut) std::filesystem::resize_file(path, *cut);
}

}  // namespace

// Everything that watches the run: thermo output, profiles, RDF, MSD, trajectory, progress.
class Observers {
 public:
  Observers(const Simulation& sim, const RunOptions& opt, bool restarted);
  bool thermo_due(std::uint64_t step) const {
    return !opt_.out_dir.empty() && step % sim_.spec().thermo_every == 0;
  }
  bool wants_sums(std::uint64_t step) const { return thermo_due(step); }
  // Collective under MPI: every rank calls it at every step; files are written by the root from the
  // particles gathered in id order, so they do not depend on the rank count.
  void observe(std::uint64_t step, const PairSums& sums);
  std::string finish();
  void progress(std::uint64_t step) {
    if (progress_) progress_->update(step);
  }
  // The whole system in increasing id on the root (collective).
  const ParticleData& gather() {
    gather_by_id(sim_.particles(), comm(), sim_.total_particles(), snapshot_);
    return snapshot_;
  }
  // Running averages (thermo means, profile, RDF, MSD) for checkpoints. Each part is a length-prefixed
  // section, so a restart with an analysis switched off skips it and one switched on starts afresh.
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  std::filesystem::path out(const std::string& name) const { return opt_.out_dir / name; }
  const Comm& comm() const { return sim_.halo().comm(); }
  void write_frame(std::uint64_t step, const ParticleData& all);

  const Simulation& sim_;
  RunOptions opt_;
  std::ofstream thermo_;
  std::optional<PoiseuilleProfile> profile_;
  std::optional<RadialDistribution> rdf_;
  std::optional<MeanSquaredDisplacement> msd_;
  std::optional<LammpsDumpWriter> lammps_;
  std::optional<GsdWriter> gsd_;
  std::optional<ProgressReporter> progress_;
  std::vector<double> scratch_a_, scratch_b_, scratch_c_;
  ParticleData snapshot_;  // the whole system in id order (on the root), reused between samples
  std::vector<std::int64_t> profile_bins_;  // one profile sample: fixed-point flow sums, then counts
  double temperature_sum_ = 0, pressure_sum_ = 0;
  std::uint64_t thermo_samples_ = 0;
};

Observers::Observers(const Simulation& sim, const RunOptions& opt, bool restarted) : sim_(sim), opt_(opt) {
  const SimulationSpec& s = sim.spec();
  if (opt_.progress && comm().root()) progress_.emplace(sim.current_step(), sim.final_step());
  if (opt_.out_dir.empty()) return;
  double mass = 0;
  if (s.poiseuille.enabled) {
    // The fluid's mass: integer counts per species (exact over ranks) times the species masses.
    std::vector<std::uint64_t> count(s.species.size(), 0);
    const ParticleData& own = sim.particles();
    for (std::size_t i = 0; i < own.n_local; ++i) ++count[static_cast<std::size_t>(own.species[i])];
    comm().sum(std::span<std::uint64_t>(count));
    for (std::size_t k = 0; k < count.size(); ++k) mass += static_cast<double>(count[k]) * s.species[k].mass;
  }
  // Files belong to the root; an error there stops every rank.
  comm().on_root([&] {
    std::filesystem::create_directories(opt_.out_dir);
    const auto thermo_path = out("thermo.csv");
    if (restarted && std::filesystem::exists(thermo_path)) trim_thermo_csv(thermo_path, sim.current_step());
    const bool append =
        restarted && std::filesystem::exists(thermo_path) && std::filesystem::file_size(thermo_path) > 0;
    thermo_.open(thermo_path, append ? std::ios::app : std::ios::trunc);
    if (!thermo_) throw ConfigError(fmt::format("{}: cannot open for writing", thermo_path.string()));
    if (!append) thermo_ << thermo_csv_header() << '\n';
    const Box& box = sim.box();
    const double len[3] = {box.len.x, box.len.y, box.len.z};
    if (s.poiseuille.enabled)
      profile_.emplace(static_cast<std::size_t>(s.poiseuille.bins), s.poiseuille.flow_axis, s.poiseuille.gradient_axis,
                       len[s.poiseuille.gradient_axis], static_cast<std::size_t>(s.poiseuille.blocks),
                       s.poiseuille.force, mass / box.volume());
    if (s.rdf.enabled) rdf_.emplace(static_cast<std::size_t>(s.rdf.bins), s.rdf.rmax);
    if (s.msd.enabled) msd_.emplace();
    if (s.dump.enabled) {
      const bool gsd = s.dump.format == DumpFormat::Gsd;
      const std::string name = !s.dump.file.empty() ? s.dump.file : (gsd ? "trajectory.gsd" : "trajectory.lammpstrj");
      if (gsd) {
        // Frames after the checkpoint's step are dropped from the index, as trim_lammps_dump does for text.
        gsd_.emplace(out(name), s.dump.fields, restarted,
                     restarted ? std::optional<std::uint64_t>(sim.current_step()) : std::nullopt);
      } else {
        if (restarted && std::filesystem::exists(out(name))) trim_lammps_dump(out(name), sim.current_step());
        lammps_.emplace(out(name), s.dump.fields, restarted);
      }
    }
  });
}

namespace {
template <class T>
void save_section(ByteWriter& w, const std::optional<T>& part) {
  ByteWriter section;
  if (part) part->save(section);
  w.put<std::uint8_t>(part ? 1 : 0);
  w.put_vector(section.bytes());
}
template <class T>
void load_section(ByteReader& r, std::optional<T>& part, const std::string& context) {
  const bool present = r.get<std::uint8_t>() != 0;
  const std::vector<std::byte> bytes = r.get_vector<std::byte>();
  if (!present || !part) return;
  ByteReader section(bytes, context);
  part->load(section, context);
}
}  // namespace

void Observers::save(ByteWriter& w) const {
  w.put<double>(temperature_sum_);
  w.put<double>(pressure_sum_);
  w.put<std::uint64_t>(thermo_samples_);
  save_section(w, profile_);
  save_section(w, rdf_);
  save_section(w, msd_);
}

void Observers::load(ByteReader& r, const std::string& context) {
  temperature_sum_ = r.get<double>();
  pressure_sum_ = r.get<double>();
  thermo_samples_ = r.get<std::uint64_t>();
  load_section(r, profile_, context);
  load_section(r, rdf_, context);
  load_section(r, msd_, context);
}

void Observers::write_frame(std::uint64_t step, const ParticleData& p) {
  const SimulationSpec& s = sim_.spec();
  std::vector<std::string> names;
  for (const auto& sp : s.species) names.push_back(sp.name);
  FrameView f;
  f.step = step;
  f.time = static_cast<double>(step) * s.dt;
  f.box_lo = {0, 0, 0};
  f.box_len = {sim_.box().len.x, sim_.box().len.y, sim_.box().len.z};
  f.n = p.n_local;
  f.id = p.id.data();
  f.species = p.species.data();
  f.x = p.x.data();
  f.y = p.y.data();
  f.z = p.z.data();
  f.vx = p.vx.data();
  f.vy = p.vy.data();
  f.vz = p.vz.data();
  f.fx = p.fx.data();
  f.fy = p.fy.data();
  f.fz = p.fz.data();
  f.ix = p.ix.data();
  f.iy = p.iy.data();
  f.iz = p.iz.data();
  f.species_names = &names;
  f.species_mass = &sim_.species_mass();
  if (lammps_) lammps_->write_frame(f);
  if (gsd_) gsd_->write_frame(f);
}

void Observers::observe(std::uint64_t step, const PairSums& sums) {
  const SimulationSpec& s = sim_.spec();
  if (thermo_due(step)) {
    ThermoState t = compute_thermo(sim_.particles(), sim_.species_mass(), sim_.box(), sums, sim_.flow_axis(), comm());
    t.step = step;
    t.time = static_cast<double>(step) * s.dt;
    t.neighbor_builds = sim_.neighbor_builds();
    if (comm().root()) {
      thermo_ << thermo_csv_row(t) << '\n';
      thermo_.flush();
    }
    temperature_sum_ += t.temperature_transverse;
    pressure_sum_ += t.pressure;
    ++thermo_samples_;
  }
  // The velocity profile is summed in integers, so each rank bins its own particles. The other
  // analyses see the whole system in id order (gathered on the root under MPI), so their sums are
  // taken in the same order whatever the rank count or storage order.
  const bool files = !opt_.out_dir.empty();
  const bool profile_due = files && s.poiseuille.enabled && step > s.poiseuille.start && step % s.poiseuille.every == 0;
  if (profile_due) {
    // Each rank bins its own particles into integer sums; only the per-bin totals travel.
    const ParticleData& own = sim_.particles();
    const auto& grad = s.poiseuille.gradient_axis == 0 ? own.x : (s.poiseuille.gradient_axis == 1 ? own.y : own.z);
    const auto& flow = s.poiseuille.flow_axis == 0 ? own.vx : (s.poiseuille.flow_axis == 1 ? own.vy : own.vz);
    const double len[3] = {sim_.box().len.x, sim_.box().len.y, sim_.box().len.z};
    const auto bins = static_cast<std::size_t>(s.poiseuille.bins);
    profile_bins_.assign(2 * bins, 0);
    PoiseuilleProfile::bin(grad.data(), flow.data(), own.n_local, bins, len[s.poiseuille.gradient_axis],
                           profile_bins_.data());
    comm().sum(std::span<std::int64_t>(profile_bins_));
    if (comm().root()) profile_->add_binned(profile_bins_.data());
  }
  const bool rdf_due = files && s.rdf.enabled && step >= s.rdf.start && step % s.rdf.every == 0;
  const bool msd_due = files && s.msd.enabled && step >= s.msd.start && step % s.msd.every == 0;
  const bool dump_due = files && s.dump.enabled && step % s.dump.every == 0;
  if (!(rdf_due || msd_due || dump_due)) return;
  const ParticleData& p = gather();
  if (!comm().root()) return;
  const std::size_t n = p.n_local;
  if (rdf_due) rdf_->sample(p.x.data(), p.y.data(), p.z.data(), n, {sim_.box().len.x, sim_.box().len.y, sim_.box().len.z});
  if (msd_due) {
    scratch_a_.resize(n);
    scratch_b_.resize(n);
    scratch_c_.resize(n);
    const Box& b = sim_.box();
    for (std::size_t i = 0; i < n; ++i) {
      scratch_a_[i] = p.x[i] + p.ix[i] * b.len.x;
      scratch_b_[i] = p.y[i] + p.iy[i] * b.len.y;
      scratch_c_[i] = p.z[i] + p.iz[i] * b.len.z;
    }
    msd_->sample(step, static_cast<double>(step) * s.dt, p.id.data(), scratch_a_.data(), scratch_b_.data(),
                 scratch_c_.data(), n);
  }
  if (dump_due) write_frame(step, p);
}

std::string Observers::finish() {
  const SimulationSpec& s = sim_.spec();
  std::string summary;
  if (!comm().root()) return summary;
  if (thermo_samples_ > 0)
    summary += fmt::format("mean temperature {:.5f}{} (target {}), mean pressure {:.4f} over {} thermo rows\n",
                           temperature_sum_ / static_cast<double>(thermo_samples_),
                           s.poiseuille.enabled ? " (across the flow)" : "", s.kT,
                           pressure_sum_ / static_cast<double>(thermo_samples_), thermo_samples_);
  if (profile_) {
    const double rho = static_cast<double>(sim_.total_particles()) / sim_.box().volume();
    const PairSpec& pp = s.pair(0, 0);
    const double eta_theory = kinetic_viscosity(rho, pp.gamma, s.kT, pp.rd, pp.s);
    if (profile_->samples() < 2) {
      summary += "reverse Poiseuille: too few profile samples for a viscosity (run longer than poiseuille.start)\n";
    } else {
      const ViscosityFit fit = profile_->fit();
      summary += fmt::format(
          "reverse Poiseuille viscosity eta = {:.4f} +- {:.4f} (kinetic theory, seed 000 Eq. 16 / Table 1: {:.4f})\n",
          fit.eta, fit.eta_err, eta_theory);
      profile_->write_csv(out("poiseuille_profile.csv").string());
      write_viscosity_summary_csv(out("viscosity.csv").string(), fit, eta_theory);
      write_file_atomically(out("viscosity.json"), [&](std::ostream& os) {
        os << fmt::format(
            "{{\n  \"eta\": {:.8g},\n  \"eta_err\": {:.8g},\n  \"eta_kinetic_theory\": {:.8g},\n  \"blocks\": {},\n"
            "  \"samples\": {},\n  \"density\": {:.8g},\n  \"gamma\": {:.8g},\n  \"s\": {:.8g},\n  \"force\": {:.8g}\n}}\n",
            fit.eta, fit.eta_err, eta_theory, fit.blocks_used, profile_->samples(), rho, pp.gamma, pp.s,
            s.poiseuille.force);
      });
      SvgSeries data{profile_->z(), profile_->v_mean(), profile_->v_err(), "measured", "#1f77b4", false, true};
      SvgSeries model{profile_->z(), profile_->v_fit(), {}, "parabolic fit", "#d62728", true, false};
      const char* axes = "xyz";
      write_svg_plot(out("velocity_profile.svg").string(), "Reverse Poiseuille flow: velocity profile",
                     fmt::format("{} (gradient axis)", axes[s.poiseuille.gradient_axis]),
                     fmt::format("mean v_{}", axes[s.poiseuille.flow_axis]), {data, model},
                     {fmt::format("eta = {:.4f} +- {:.4f}", fit.eta, fit.eta_err),
                      fmt::format("kinetic theory (seed 000 Eq. 16): {:.4f}", eta_theory),
                      fmt::format("rho = {:.3g}, a = {:.3g}, gamma = {:.3g}, s = {:.3g}, g = {:.3g}", rho, pp.a,
                                  pp.gamma, pp.s, s.poiseuille.force)});
    }
  }
  if (rdf_ && rdf_->samples() > 0) rdf_->write_csv(out("rdf.csv").string());
  if (msd_ && msd_->size() > 2) {
    msd_->write_csv(out("msd.csv").string());
    summary += fmt::format("self-diffusion coefficient D = {:.5f}\n", msd_->diffusion_coefficient());
  }
  if (progress_) progress_->finish();
  return summary;
}

Simulation::Simulation(SimulationSpec spec, RunOptions options)
    : spec_(std::move(spec)),
      options_(std::move(options)),
      nlist_(NeighborSettings{}),
      forces_(make_pair_table(spec_),
              NoiseSettings{spec_.seed, spec_.noise == NoiseDistribution::Gaussian ? NoiseKind::Gaussian : NoiseKind::Uniform}) {
  if (spec_.species.empty()) throw ConfigError("species: at least one species is required");
  nlist_ = NeighborList(NeighborSettings{forces_.table().max_cutoff,
                                         spec_.neighbor == NeighborMethod::Verlet ? spec_.skin : 0.0, true});
  if (spec_.integrator == IntegratorKind::GrootWarren)
    integrator_ = GrootWarrenIntegrator{spec_.lambda};
  else
    integrator_ = EulerIntegrator{};
  for (const auto& s : spec_.species) {
    mass_.push_back(s.mass);
    inv_mass_.push_back(1.0 / s.mass);
  }
  final_step_ = options_.steps ? *options_.steps : spec_.steps;
  const bool restarted = !options_.restart.empty();
  const Comm comm = Comm::world();
  const double range = nlist_.settings().cutoff + nlist_.settings().skin;
  auto check_box = [&] {
    const double two_rc = 2 * forces_.table().max_cutoff;
    if (box_.len.x < two_rc || box_.len.y < two_rc || box_.len.z < two_rc)
      throw ConfigError("system.box: every box length must be at least twice the largest cutoff");
  };
  auto decompose = [&] {
    halo_ = Halo(comm, Decomposition::make(comm.size(), comm.rank(), CellGrid::dims_for(box_, range),
                                           {box_.len.x, box_.len.y, box_.len.z}, spec_.parallel_grid, range));
  };
  if (!restarted && spec_.data_file.empty() && comm.distributed()) {
    // A generated system: each rank creates only the particles of its own cells.
    box_.len = {spec_.box[0], spec_.box[1], spec_.box[2]};
    check_box();
    decompose();
    const CellGrid global(box_, range);
    make_initial_state(spec_, box_, p_, [&](double x, double y, double z) { return halo_.owns(x, y, z, global); });
    n_total_ = 0;
    for (const auto& s : spec_.species) n_total_ += s.count;
  } else {
    // A checkpoint or data file is read whole on every rank, which then keeps its own particles.
    if (restarted)
      load_checkpoint(options_.restart);
    else
      make_initial_state(spec_, box_, p_);
    n_total_ = p_.n_local;
    check_box();
    decompose();
    halo_.keep_owned(p_, CellGrid(box_, range));
#if defined(__GLIBC__)
    // Hand the memory of the whole system back to the system.
    if (comm.distributed()) malloc_trim(0);
#endif
  }
  if (!restarted) {
    nlist_.build(p_, box_, &halo_);
    compute_forces(true);
  }
  observers_ = std::make_unique<Observers>(*this, options_, restarted);
  if (!pending_observer_state_.empty()) {
    ByteReader r(pending_observer_state_, options_.restart.string());
    observers_->load(r, options_.restart.string());
    pending_observer_state_.clear();
  }
  if (!restarted) observers_->observe(step_, sums_);
}

Simulation::~Simulation() = default;

void Simulation::compute_forces(bool with_sums) {
  forces_.compute(p_, box_, nlist_, step_, spec_.dt, with_sums, sums_, &halo_);
  sums_valid_ = with_sums;
  // External forces after the pair forces, in a fixed per-particle order.
  const std::size_t n = p_.n_local;
  const auto& sp = spec_.species;
  const bool any_body = std::any_of(sp.begin(), sp.end(), [](const SpeciesSpec& s) {
    return s.body_force[0] != 0 || s.body_force[1] != 0 || s.body_force[2] != 0;
  });
  if (any_body) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const auto& bf = sp[static_cast<std::size_t>(p_.species[i])].body_force;
      p_.fx[i] += bf[0];
      p_.fy[i] += bf[1];
      p_.fz[i] += bf[2];
    }
  }
  if (spec_.poiseuille.enabled) {
    // Reverse Poiseuille (Backer et al., seed 002): +g in the lower half of the gradient axis, -g above.
    const int ga = spec_.poiseuille.gradient_axis, fa = spec_.poiseuille.flow_axis;
    const double half = 0.5 * (ga == 0 ? box_.len.x : ga == 1 ? box_.len.y : box_.len.z);
    const auto& coord = ga == 0 ? p_.x : ga == 1 ? p_.y : p_.z;
    auto& f = fa == 0 ? p_.fx : fa == 1 ? p_.fy : p_.fz;
    const double g = spec_.poiseuille.force;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) f[i] += mass_[static_cast<std::size_t>(p_.species[i])] * (coord[i] < half ? g : -g);
  }
}

void Simulation::step() {
  // 1. First part of the integrator: positions and the velocity the forces will see.
  std::visit([&](const auto& integ) { integ.pre_force(p_, inv_mass_, spec_.dt); }, integrator_);
  // 2. Periodic wrap of the local particles.
  const std::size_t n = p_.n_local;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    wrap_coordinate(p_.x[i], p_.ix[i], box_.len.x);
    wrap_coordinate(p_.y[i], p_.iy[i], box_.len.y);
    wrap_coordinate(p_.z[i], p_.iz[i], box_.len.z);
  }
  ++step_;
  // 3. Neighbour list, rebuilt only when some particle has moved half the skin. Under MPI a rebuild
  //    migrates particles to their owners and rebuilds the ghosts; otherwise the ghosts are refreshed.
  if (nlist_.needs_rebuild(p_, box_, &halo_))
    nlist_.build(p_, box_, &halo_);
  else
    halo_.update_ghosts(p_);
  // 4. Forces at the new positions (pair forces, ghost forces back to their owners, external forces).
  compute_forces(observers_ && observers_->wants_sums(step_));
  // 5. Second part of the integrator.
  std::visit([&](const auto& integ) { integ.post_force(p_, inv_mass_, spec_.dt); }, integrator_);
  // 6. Stop on NaN or runaway velocity before anything is written.
  check_health();
  // 7. Measure and write.
  if (observers_) {
    observers_->observe(step_, sums_);
    observers_->progress(step_);
  }
  if (!options_.out_dir.empty() && spec_.checkpoint_every > 0 && step_ % spec_.checkpoint_every == 0)
    write_checkpoint(options_.out_dir / "checkpoint.mdpd");
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
  const Comm& comm = halo_.comm();
  if (comm.distributed()) id = comm.min(id);
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
  throw BlowUpError(step_, static_cast<std::uint32_t>(id),
                    fmt::format("simulation blew up at step {}: particle id {} has position ({}, {}, {}) and speed {} "
                                "(run.max_velocity = {}); reduce integrator.dt or check the forces",
                                step_, id, state[0], state[1], state[2], state[3], spec_.max_velocity));
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

ThermoState Simulation::thermo() {
  if (!sums_valid_) {
    // Recompute the pair sums at the current step; the forces come out bit-identical.
    compute_forces(true);
  }
  ThermoState t = compute_thermo(p_, mass_, box_, sums_, flow_axis(), halo_.comm());
  t.step = step_;
  t.time = static_cast<double>(step_) * spec_.dt;
  t.neighbor_builds = neighbor_builds();
  return t;
}

std::string Simulation::run() {
  while (step_ < final_step_) step();
  std::string summary;
  if (!options_.out_dir.empty()) write_checkpoint(options_.out_dir / "checkpoint.mdpd");
  if (observers_) summary = observers_->finish();
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
    std::vector<std::byte> observer_state;
    if (observers_) {
      ByteWriter w;
      observers_->save(w);
      observer_state = w.take();
    }
    write_state_checkpoint(file, h, all, observers_ ? &observer_state : nullptr);
  });
}

void Simulation::load_checkpoint(const std::filesystem::path& file) {
  StateCheckpoint c = read_state_checkpoint(file);
  const StateHeader& h = c.header;
  if (h.n_species != spec_.species.size())
    throw ConfigError(fmt::format("{}: checkpoint has {} species but the config defines {}", file.string(), h.n_species,
                                  spec_.species.size()));
  if (h.seed != spec_.seed)
    throw ConfigError(fmt::format("system.seed: {} differs from the checkpoint's seed {} ({})", spec_.seed, h.seed,
                                  file.string()));
  // The stored forces and the integrator's state belong to the checkpoint's time step, and the noise
  // amplitude scales with 1/sqrt(dt): continuing with another dt would silently be another run.
  if (h.dt != spec_.dt)
    throw ConfigError(fmt::format("integrator.dt: {} differs from the checkpoint's dt {} ({}); set integrator.dt = {} "
                                  "to continue that run",
                                  spec_.dt, h.dt, file.string(), h.dt));
  step_ = h.step;
  neighbor_builds_before_ = h.neighbor_builds;
  box_.len = {h.box[0], h.box[1], h.box[2]};
  p_ = std::move(c.particles);
  // Observer state is applied once the observers exist (end of the constructor).
  if (c.observer_state) pending_observer_state_ = std::move(*c.observer_state);
  const std::size_t n = p_.n_local;
  for (std::size_t i = 0; i < n; ++i)
    if (p_.species[i] < 0 || static_cast<std::size_t>(p_.species[i]) >= h.n_species)
      throw ConfigError(fmt::format("{}: particle {} has an invalid species", file.string(), p_.id[i]));
  if (step_ > final_step_)
    throw ConfigError(fmt::format("{}: the checkpoint {} is already at step {}, beyond the requested {}",
                                  options_.steps ? "--steps" : "run.steps", file.string(), step_, final_step_));
}

}  // namespace mesodpd
