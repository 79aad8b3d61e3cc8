// The observers of a run: thermo rows, profile and viscosity, RDF, MSD, trajectory frames, progress.
#include "analysis/observers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <span>

#include "analysis/kinetic_theory.hpp"
#include "analysis/svg_plot.hpp"
#include "analysis/thermo.hpp"
#include "io/atomic_file.hpp"
#include "io/frame.hpp"
#include "io/json_number.hpp"
#include "parallel/comm.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

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

std::optional<std::string> temperature_warning(double mean_t, const SimulationSpec& spec, double dof,
                                               std::uint64_t samples) {
  const double deviation = mean_t / spec.kT - 1.0;
  // Canonical fluctuations alone move a mean of independent samples by about sqrt(2 / dof / samples)
  // (relative); three of those are added so that a small system is not flagged for its noise.
  const double noise = 3.0 * std::sqrt(2.0 / std::max(dof, 1.0) / static_cast<double>(std::max<std::uint64_t>(samples, 1)));
  if (!(std::fabs(deviation) > kTemperatureTolerance + noise)) return std::nullopt;
  std::string advice = fmt::format("reduce integrator.dt (now {})", spec.dt);
  if (spec.integrator == IntegratorKind::GrootWarren && deviation > 0 && spec.lambda < 0.65)
    advice += fmt::format(" or raise integrator.lambda (now {}; 0.65 keeps kT within 1% up to dt = 0.06 at rho = 3, "
                          "docs/validation.md)", spec.lambda);
  if (spec.integrator == IntegratorKind::Euler) advice += " or use integrator.type = \"groot-warren\"";
  return fmt::format("over the second half of the run the mean temperature {:.4g} is {:.1f}% {} the target kT = {} "
                     "(tolerance {:.0f}%): the time step is too large for these forces, or the run too short to "
                     "relax from its initial state; {}, or run longer",
                     mean_t, 100 * std::fabs(deviation), deviation > 0 ? "above" : "below", spec.kT,
                     100 * kTemperatureTolerance, advice);
}

Observers::Observers(const SimulationSpec& spec, ObserverSettings settings, const StepContext& start)
    : spec_(spec), opt_(std::move(settings)) {
  const SimulationSpec& s = spec_;
  const Comm& comm = start.comm;
  const bool restarted = opt_.restarted;
  if (opt_.progress && comm.root()) progress_.emplace(start.step, opt_.final_step);
  late_from_ = start.step + (opt_.final_step > start.step ? (opt_.final_step - start.step) / 2 : 0);
  for (const auto& sp : s.species) frozen_.push_back(sp.frozen ? 1 : 0);
  if (!measuring()) return;
  double mass = 0;
  if (s.poiseuille.enabled) {
    // The fluid's mass: integer counts per species (exact over ranks) times the species masses.
    std::vector<std::uint64_t> count(s.species.size(), 0);
    const ParticleData& own = start.particles;
    for (std::size_t i = 0; i < own.n_local; ++i) ++count[static_cast<std::size_t>(own.species[i])];
    comm.sum(std::span<std::uint64_t>(count));
    for (std::size_t k = 0; k < count.size(); ++k) mass += static_cast<double>(count[k]) * s.species[k].mass;
  }
  // Binned fields: every rank holds the same totals (each sample is summed over ranks).
  std::vector<std::string> names;
  for (const SpeciesSpec& sp : s.species) names.push_back(sp.name);
  for (const FieldsSpec& f : s.fields)
    fields_.emplace_back(f, start.species_mass, names, std::array<double, 3>{start.box.len.x, start.box.len.y, start.box.len.z},
                         start.box.periodic);
  // Files belong to the root; an error there stops every rank.
  comm.on_root([&] {
    if (files()) {
      std::filesystem::create_directories(opt_.out_dir);
      const auto thermo_path = out("thermo.csv");
      if (restarted && std::filesystem::exists(thermo_path)) trim_thermo_csv(thermo_path, start.step);
      const bool append =
          restarted && std::filesystem::exists(thermo_path) && std::filesystem::file_size(thermo_path) > 0;
      thermo_.open(thermo_path, append ? OutputFile::Mode::Append : OutputFile::Mode::Truncate);
      if (!append) {
        thermo_ << thermo_csv_header();
        for (const ThermoColumn& c : opt_.columns) thermo_ << ',' << c.name;
        thermo_ << '\n';
        thermo_.flush();
      }
    }
    const Box& box = start.box;
    const double len[3] = {box.len.x, box.len.y, box.len.z};
    if (s.poiseuille.enabled)
      profile_.emplace(static_cast<std::size_t>(s.poiseuille.bins), s.poiseuille.flow_axis, s.poiseuille.gradient_axis,
                       len[s.poiseuille.gradient_axis], static_cast<std::size_t>(s.poiseuille.blocks),
                       s.poiseuille.force, mass / box.volume());
    if (s.rdf.enabled) rdf_.emplace(static_cast<std::size_t>(s.rdf.bins), s.rdf.rmax);
    if (s.msd.enabled) msd_.emplace();
    if (s.surface_tension.enabled)
      tension_.emplace(s.surface_tension.axis, len[s.surface_tension.axis],
                       static_cast<std::size_t>(s.surface_tension.blocks));
    if (s.droplet.enabled) {
      if (!opt_.local_virial) throw std::logic_error("Observers: [analysis.droplet] needs ObserverSettings::local_virial");
      droplet_.emplace(s.droplet, box, opt_.interaction_range);
    }
    if (s.stress_profile.enabled) {
      if (!opt_.virial_terms)
        throw std::logic_error("Observers: [analysis.stress_profile] needs ObserverSettings::virial_terms");
      stress_.emplace(s.stress_profile, box);
    }
    if (s.dump.enabled && files()) {
      const bool gsd = s.dump.format == DumpFormat::Gsd;
      const std::string name = !s.dump.file.empty() ? s.dump.file : (gsd ? "trajectory.gsd" : "trajectory.lammpstrj");
      if (gsd) {
        // Frames after the checkpoint's step are dropped from the index, as trim_lammps_dump does for text.
        gsd_.emplace(out(name), s.dump.fields, restarted,
                     restarted ? std::optional<std::uint64_t>(start.step) : std::nullopt);
      } else {
        if (restarted && std::filesystem::exists(out(name))) trim_lammps_dump(out(name), start.step);
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
  // Binned fields by name: a restart finds its grid whatever the order of the tables, and a grid that
  // is new at the restart starts afresh.
  w.put<std::uint64_t>(fields_.size());
  for (const BinnedFields& f : fields_) {
    ByteWriter section;
    f.save(section);
    w.put_string(f.spec().name);
    w.put_vector(section.bytes());
  }
  save_section(w, tension_);
  // Other parts of the run by name, like the grids.
  w.put<std::uint64_t>(opt_.sections.size());
  for (const StateSection& s : opt_.sections) {
    ByteWriter section;
    s.save(section);
    w.put_string(s.name);
    w.put_vector(section.bytes());
  }
  save_section(w, droplet_);
  save_section(w, stress_);
}

void Observers::load(ByteReader& r, const std::string& context) {
  temperature_sum_ = r.get<double>();
  pressure_sum_ = r.get<double>();
  thermo_samples_ = r.get<std::uint64_t>();
  load_section(r, profile_, context);
  load_section(r, rdf_, context);
  load_section(r, msd_, context);
  if (r.remaining() == 0) return;  // a checkpoint from before binned fields existed
  const auto grids = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < grids; ++k) {
    const std::string name = r.get_string();
    const std::vector<std::byte> bytes = r.get_vector<std::byte>();
    for (BinnedFields& f : fields_)
      if (f.spec().name == name) {
        ByteReader section(bytes, context);
        f.load(section, context);
      }
  }
  if (r.remaining() == 0) return;  // a checkpoint from before the surface tension existed
  load_section(r, tension_, context);
  if (r.remaining() == 0) return;  // a checkpoint from before the state sections existed
  const auto sections = r.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < sections; ++k) {
    const std::string name = r.get_string();
    const std::vector<std::byte> bytes = r.get_vector<std::byte>();
    for (const StateSection& s : opt_.sections)
      if (s.name == name) {
        ByteReader section(bytes, context);
        s.load(section, context);
      }
  }
  if (r.remaining() == 0) return;  // a checkpoint from before the droplet analysis existed
  load_section(r, droplet_, context);
  if (r.remaining() == 0) return;  // a checkpoint from before the stress profile existed
  load_section(r, stress_, context);
}

void Observers::write_frame(std::uint64_t step, const StepContext& ctx, const ParticleData& p) {
  const SimulationSpec& s = spec_;
  std::vector<std::string> names;
  for (const auto& sp : s.species) names.push_back(sp.name);
  FrameView f;
  f.step = step;
  f.time = static_cast<double>(step) * s.dt;
  f.box_lo = {0, 0, 0};
  f.box_len = {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z};
  f.periodic = ctx.box.periodic;
  set_frame_arrays(f, p);
  f.species_names = &names;
  f.species_mass = &ctx.species_mass;
  std::vector<std::string> bond_names, angle_names;
  for (const auto& b : s.bond_types) bond_names.push_back(b.name);
  for (const auto& a : s.angle_types) angle_names.push_back(a.name);
  f.topology = ctx.topology;
  f.bond_type_names = &bond_names;
  f.angle_type_names = &angle_names;
  if (lammps_) lammps_->write_frame(f);
  if (gsd_) gsd_->write_frame(f);
}

void Observers::run(StepContext& ctx) {
  observe(ctx);
  if (progress_) progress_->update(ctx.step);
}

void Observers::observe(const StepContext& ctx) {
  const SimulationSpec& s = spec_;
  const Comm& comm = ctx.comm;
  const std::uint64_t step = ctx.step;
  if (thermo_due(step)) {
    if (!ctx.pair_sums) throw std::logic_error("Observers: thermo output due but no pair sums were computed");
    // Temperature across a driven flow only: the streaming velocity is not heat.
    const int flow_axis = s.poiseuille.enabled ? s.poiseuille.flow_axis : -1;
    ThermoState t =
        compute_thermo(ctx.particles, ctx.species_mass, ctx.box, *ctx.pair_sums, flow_axis, comm, frozen_);
    t.step = step;
    t.time = static_cast<double>(step) * s.dt;
    t.neighbor_builds = ctx.neighbor_builds;
    std::string extra;
    double column_temperature = 0;
    for (std::size_t k = 0; k < opt_.columns.size(); ++k) {
      const double value = opt_.columns[k].value(ctx);
      if (static_cast<int>(k) == opt_.temperature_column) column_temperature = value;
      extra += fmt::format(",{:.12g}", value);
    }
    const double temperature = opt_.temperature_column >= 0 ? column_temperature : t.temperature_transverse;
    // Written before the row is counted: a row that could not be written stops the run (on every rank).
    if (files())
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
    if (tension_ && step >= s.surface_tension.start) tension_->add(t.p_tensor);
  }
  // The velocity profile is summed in integers, so each rank bins its own particles. The other
  // analyses see the whole system in id order (gathered on the root under MPI), so their sums are
  // taken in the same order whatever the rank count or storage order.
  const bool measure = measuring();
  const bool profile_due = measure && s.poiseuille.enabled && step > s.poiseuille.start && step % s.poiseuille.every == 0;
  if (profile_due) {
    // Each rank bins its own particles into integer sums; only the per-bin totals travel.
    const ParticleData& own = ctx.particles;
    const auto& grad = s.poiseuille.gradient_axis == 0 ? own.x : (s.poiseuille.gradient_axis == 1 ? own.y : own.z);
    const auto& flow = s.poiseuille.flow_axis == 0 ? own.vx : (s.poiseuille.flow_axis == 1 ? own.vy : own.vz);
    const double len[3] = {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z};
    const auto bins = static_cast<std::size_t>(s.poiseuille.bins);
    profile_bins_.assign(2 * bins, 0);
    PoiseuilleProfile::bin(grad.data(), flow.data(), own.n_local, bins, len[s.poiseuille.gradient_axis],
                           profile_bins_.data());
    comm.sum(std::span<std::int64_t>(profile_bins_));
    if (comm.root()) profile_->add_binned(profile_bins_.data());
  }
  for (BinnedFields& f : fields_) {
    if (measure && step >= f.spec().start && step % f.spec().every == 0) f.sample(ctx.particles, comm, step);
    // The files so far, for long runs (the averages go on; the end of the run writes them again).
    const std::uint64_t w = f.spec().write_every;
    if (files() && w > 0 && step % w == 0 && step > f.spec().start && f.samples() > 0)
      comm.on_root([&] { f.write(opt_.out_dir); });
  }
  const bool rdf_due = measure && s.rdf.enabled && step >= s.rdf.start && step % s.rdf.every == 0;
  const bool msd_due = measure && s.msd.enabled && step >= s.msd.start && step % s.msd.every == 0;
  const bool dump_due = files() && s.dump.enabled && step % s.dump.every == 0;
  const bool droplet_due = measure && s.droplet.enabled && step >= s.droplet.start && step % s.droplet.every == 0;
  const bool stress_due = measure && s.stress_profile.enabled && step >= s.stress_profile.start &&
                          step % s.stress_profile.every == 0;
  if (!(rdf_due || msd_due || dump_due || droplet_due || stress_due)) return;
  // The whole system in increasing id on the root (collective).
  gather_by_id(ctx.particles, comm, ctx.total_particles, snapshot_);
  // The frame is written by the root; a failed write stops every rank.
  if (dump_due) comm.on_root([&] { write_frame(step, ctx, snapshot_); });
  if (!comm.root()) return;
  const ParticleData& p = snapshot_;
  const std::size_t n = p.n_local;
  if (rdf_due) rdf_->sample(p.x.data(), p.y.data(), p.z.data(), n, {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z},
                            ctx.box.periodic);
  if (msd_due) {
    scratch_a_.resize(n);
    scratch_b_.resize(n);
    scratch_c_.resize(n);
    const Box& b = ctx.box;
    for (std::size_t i = 0; i < n; ++i) {
      scratch_a_[i] = p.x[i] + p.ix[i] * b.len.x;
      scratch_b_[i] = p.y[i] + p.iy[i] * b.len.y;
      scratch_c_[i] = p.z[i] + p.iz[i] * b.len.z;
    }
    msd_->sample(step, static_cast<double>(step) * s.dt, p.id.data(), scratch_a_.data(), scratch_b_.data(),
                 scratch_c_.data(), n);
  }
  if (droplet_due) droplet_->sample(p, ctx.species_mass, ctx.box, opt_.local_virial);
  if (stress_due) {
    terms_.clear();
    opt_.virial_terms(p, ctx.box, terms_);
    stress_->sample(p, ctx.species_mass, frozen_, terms_);
  }
}

std::string Observers::finish(const StepContext& ctx) {
  const SimulationSpec& s = spec_;
  std::string summary;
  if (!ctx.comm.root()) return summary;
  warnings_.clear();  // finish() may be called again later in a longer run (the API)
  if (thermo_samples_ > 0) {
    summary += fmt::format("mean temperature {:.5f}{} (target {}), mean pressure {:.4f} over {} thermo rows\n",
                           temperature_sum_ / static_cast<double>(thermo_samples_),
                           s.poiseuille.enabled ? " (across the flow)"
                           : opt_.temperature_column >= 0
                               ? fmt::format(" ({})", opt_.columns[static_cast<std::size_t>(opt_.temperature_column)].name)
                               : std::string(),
                           s.kT,
                           pressure_sum_ / static_cast<double>(thermo_samples_), thermo_samples_);
  }
  if (late_samples_ > 0) {
    // Judged on the second half of this run's rows: a random initial placement heats the fluid for
    // the first few time units, which is not the integrator's steady error.
    const double late_t = late_temperature_sum_ / static_cast<double>(late_samples_);
    const double n = static_cast<double>(ctx.total_particles);
    const double dof = s.poiseuille.enabled ? 2 * n - 2 : 3 * n - 3;  // of the measured temperature
    if (auto w = temperature_warning(late_t, s, dof, late_samples_)) {
      summary += "warning: " + *w + "\n";
      warnings_.push_back(*w);
    }
  }
  if (profile_) {
    const double rho = static_cast<double>(ctx.total_particles) / ctx.box.volume();
    // Kinetic theory only where one set of pair parameters describes the fluid (kinetic_theory.hpp).
    const KineticViscosity theory = kinetic_viscosity_of(s, rho);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double eta_theory = theory.applies ? theory.eta : nan;
    const std::string theory_text =
        theory.applies ? fmt::format("kinetic theory, seed 000 Eq. 16 / Table 1: {:.4f}", theory.eta)
                       : fmt::format("no kinetic-theory value for {}", theory.why_not);
    // One `a` for the plot's legend where all pairs share it.
    bool one_a = true;
    for (const PairSpec& q : s.pairs) one_a = one_a && q.a == s.pairs.front().a;
    if (profile_->samples() < 2) {
      summary += "reverse Poiseuille: too few profile samples for a viscosity (run longer than poiseuille.start)\n";
    } else {
      const ViscosityFit fit = profile_->fit();
      summary += fmt::format(
          "reverse Poiseuille viscosity eta = {:.4f} +- {:.4f} ({})\n", fit.eta, fit.eta_err, theory_text);
      if (files()) {
        profile_->write_csv(out("poiseuille_profile.csv").string());
        write_viscosity_summary_csv(out("viscosity.csv").string(), fit, eta_theory);
        nlohmann::ordered_json summary_json;  // keys in the order written
        summary_json["eta"] = json_number(fit.eta);
        summary_json["eta_err"] = json_number(fit.eta_err);
        summary_json["eta_kinetic_theory"] = json_number(eta_theory);
        summary_json["blocks"] = fit.blocks_used;
        summary_json["samples"] = profile_->samples();
        summary_json["density"] = json_number(rho);
        summary_json["gamma"] = theory.applies ? json_number(theory.gamma) : nullptr;
        summary_json["s"] = theory.applies ? json_number(theory.s) : nullptr;
        summary_json["force"] = json_number(s.poiseuille.force);
        write_file_atomically(out("viscosity.json"), [&](std::ostream& os) { os << summary_json.dump(2) << '\n'; });
        SvgSeries data{profile_->z(), profile_->v_mean(), profile_->v_err(), "measured", "#1f77b4", false, true};
        SvgSeries model{profile_->z(), profile_->v_fit(), {}, "parabolic fit", "#d62728", true, false};
        const char* axes = "xyz";
        write_svg_plot(out("velocity_profile.svg").string(), "Reverse Poiseuille flow: velocity profile",
                       fmt::format("{} (gradient axis)", axes[s.poiseuille.gradient_axis]),
                       fmt::format("mean v_{}", axes[s.poiseuille.flow_axis]), {data, model},
                       {fmt::format("eta = {:.4f} +- {:.4f}", fit.eta, fit.eta_err),
                        theory.applies ? fmt::format("kinetic theory (seed 000 Eq. 16): {:.4f}", theory.eta)
                                       : fmt::format("kinetic theory: none for {}", theory.why_not),
                        theory.applies && one_a
                            ? fmt::format("rho = {:.3g}, a = {:.3g}, gamma = {:.3g}, s = {:.3g}, g = {:.3g}", rho,
                                          s.pairs.front().a, theory.gamma, theory.s, s.poiseuille.force)
                            : fmt::format("rho = {:.3g}, {} species, g = {:.3g}", rho, s.species.size(),
                                          s.poiseuille.force)});
      }
    }
  }
  for (const BinnedFields& f : fields_) {
    if (f.samples() == 0) {
      summary += fmt::format("{}: no samples (run longer than analysis.fields.start)\n", f.spec().name);
      continue;
    }
    if (files()) summary += f.write(opt_.out_dir);
  }
  if (files() && rdf_ && rdf_->samples() > 0) rdf_->write_csv(out("rdf.csv").string());
  if (tension_ && tension_->samples() > 0) {
    if (files()) tension_->write_json(out("surface_tension.json").string());
    const BlockMean b = tension_->result();
    summary += fmt::format("surface tension sigma = {:.4f} +- {:.4f} ({} thermo rows in {} blocks, normal {})\n", b.mean,
                           b.err, b.samples, b.blocks, "xyz"[s.surface_tension.axis]);
  }
  if (droplet_ && droplet_->samples() > 0) summary += files() ? droplet_->write(opt_.out_dir) : droplet_->summary();
  if (stress_ && stress_->samples() > 0) summary += files() ? stress_->write(opt_.out_dir) : stress_->summary();
  if (msd_ && msd_->size() > 2) {
    if (files()) msd_->write_csv(out("msd.csv").string());
    summary += fmt::format("self-diffusion coefficient D = {:.5f}\n", msd_->diffusion_coefficient());
  }
  if (progress_) progress_->finish();
  return summary;
}

}  // namespace mesodpd
