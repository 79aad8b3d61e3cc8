// The drag on solid bodies and the adaptive wall force's log (analysis/wall_drag.hpp).
#include "analysis/wall_drag.hpp"

#include <fmt/format.h>

#include <cmath>

#include "boundary/walls.hpp"
#include "io/atomic_file.hpp"
#include "io/byte_buffer.hpp"
#include "io/output_file.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

// Opens `path` for a new run (header written) unless a restart continues it.
void start_csv(const std::filesystem::path& path, bool restarted, const std::string& header) {
  if (restarted && std::filesystem::exists(path)) return;
  OutputFile f(path, OutputFile::Mode::Truncate);
  f << header << "\n";
  f.close();
}

}  // namespace

WallDrag::WallDrag(const SimulationSpec& spec, const Walls& walls, std::filesystem::path out_dir, bool restarted,
                   const Comm& comm)
    : spec_(spec), walls_(walls), out_dir_(std::move(out_dir)) {
  for (const auto& s : spec.species) frozen_.push_back(s.frozen ? 1 : 0);
  const std::size_t nb = walls.geometry().bodies();
  blocks_ = BlockRows(6 * nb, static_cast<std::size_t>(spec.walls.drag_blocks));
  total_.assign(6 * nb, 0.0);
  if (out_dir_.empty()) return;
  comm.on_root([&] {
    std::filesystem::create_directories(out_dir_);
    std::string header = "step";
    for (const auto& s : spec_.solids) header += fmt::format(",{0}_fx,{0}_fy,{0}_fz", s.name);
    start_csv(out_dir_ / "drag.csv", restarted, header + ",fluid_vx,fluid_vy,fluid_vz");
  });
}

void WallDrag::run(StepContext& ctx) {
  const WallsSpec& w = spec_.walls;
  if (ctx.step <= w.drag_start || ctx.step % w.drag_every != 0) return;
  if (walls_.geometry().empty()) return;  // every solid moved by a model (rigid bodies report their own forces)
  const ParticleData& p = ctx.particles;
  const std::size_t nb = walls_.geometry().bodies();
  // Per body three force sums (the walls' own, then the pair forces on its frozen particles), then the
  // fluid's momentum and mass, all in 2^32 fixed point.
  std::vector<std::int64_t> q = walls_.wall_forces();
  q.resize(3 * nb + 4, 0);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.body[i] > 0) {
      const std::size_t b = static_cast<std::size_t>(p.body[i] - 1);
      q[3 * b] += wall_fixed(p.fx[i]);
      q[3 * b + 1] += wall_fixed(p.fy[i]);
      q[3 * b + 2] += wall_fixed(p.fz[i]);
    } else if (!frozen_[static_cast<std::size_t>(p.species[i])]) {
      const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
      q[3 * nb] += wall_fixed(m * p.vx[i]);
      q[3 * nb + 1] += wall_fixed(m * p.vy[i]);
      q[3 * nb + 2] += wall_fixed(m * p.vz[i]);
      q[3 * nb + 3] += wall_fixed(m);
    }
  }
  ctx.comm.sum(std::span<std::int64_t>(q));
  const double mass = static_cast<double>(q[3 * nb + 3]);
  const double u[3] = {static_cast<double>(q[3 * nb]) / mass, static_cast<double>(q[3 * nb + 1]) / mass,
                       static_cast<double>(q[3 * nb + 2]) / mass};
  // Per body the three force components, then the fluid velocity (the same for every body).
  std::vector<double> row(6 * nb);
  for (std::size_t b = 0; b < nb; ++b)
    for (std::size_t c = 0; c < 3; ++c) {
      row[6 * b + c] = static_cast<double>(q[3 * b + c]) / kWallFixedScale;
      row[6 * b + 3 + c] = u[c];
    }
  blocks_.add(row.data());
  for (std::size_t k = 0; k < row.size(); ++k) total_[k] += row[k];
  ++samples_;
  if (!out_dir_.empty())
    ctx.comm.on_root([&] {
      OutputFile f(out_dir_ / "drag.csv", OutputFile::Mode::Append);
      f << ctx.step;
      for (std::size_t k = 0; k < 3 * nb; ++k) f << fmt::format(",{:.10g}", static_cast<double>(q[k]) / kWallFixedScale);
      f << fmt::format(",{:.10g},{:.10g},{:.10g}\n", u[0], u[1], u[2]);
      f.close();
    });
}

void WallDrag::save(ByteWriter& w) const {
  w.put<std::uint64_t>(walls_.geometry().bodies());
  w.put<std::uint64_t>(samples_);
  w.put_vector(total_);
  blocks_.save(w);
}

void WallDrag::load(ByteReader& r, const std::string& context) {
  const auto bodies = r.get<std::uint64_t>();
  if (bodies != walls_.geometry().bodies())
    throw ConfigError(fmt::format("{}: the checkpoint's walls have {} solids, the config {} ([[solid]])", context,
                                  bodies, walls_.geometry().bodies()));
  samples_ = r.get<std::uint64_t>();
  total_ = r.get_vector<double>();
  if (total_.size() != 6 * bodies) throw ConfigError(fmt::format("{}: damaged walls section", context));
  blocks_.load(r, context + " (walls.drag_blocks)");
}

std::vector<DragResult> WallDrag::results() const {
  const std::size_t nb = walls_.geometry().bodies();
  const WallsSpec& w = spec_.walls;
  const double density = walls_.fill_density();
  std::vector<DragResult> out(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    DragResult& r = out[b];
    r.name = spec_.solids[b].name;
    r.samples = samples_;
    if (samples_ == 0) continue;
    // The mean over all samples; the error bar from the full blocks.
    std::vector<std::array<double, 6>> means;
    std::array<double, 6> total{0, 0, 0, 0, 0, 0};
    for (std::size_t k = 0; k < blocks_.full_blocks(); ++k) {
      std::array<double, 6> m{};
      for (std::size_t c = 0; c < 6; ++c)
        m[c] = blocks_.block(k)[6 * b + c] / static_cast<double>(blocks_.samples_per_block());
      means.push_back(m);
    }
    for (std::size_t c = 0; c < 6; ++c) total[c] = total_[6 * b + c] / static_cast<double>(samples_);
    const double nblk = static_cast<double>(means.size());
    auto block_error = [&](auto value) {
      if (means.size() < 2) return 0.0;
      double mean = 0, var = 0;
      for (const auto& m : means) mean += value(m);
      mean /= nblk;
      for (const auto& m : means) var += (value(m) - mean) * (value(m) - mean);
      return std::sqrt(var / (nblk - 1) / nblk);
    };
    for (std::size_t c = 0; c < 3; ++c) {
      r.force[c] = total[c];
      r.fluid_velocity[c] = total[3 + c];
      r.error[c] = block_error([c](const std::array<double, 6>& m) { return m[c]; });
    }
    const double speed = std::sqrt(total[3] * total[3] + total[4] * total[4] + total[5] * total[5]);
    if (speed > 0) {
      const double e[3] = {total[3] / speed, total[4] / speed, total[5] / speed};
      auto along = [e](const std::array<double, 6>& m) { return m[0] * e[0] + m[1] * e[1] + m[2] * e[2]; };
      r.drag = along(total);
      r.drag_error = block_error(along);
      if (w.reference_area > 0) {
        const double scale = 2.0 / (density * speed * speed * w.reference_area);
        r.cd = scale * r.drag;
        r.cd_error = scale * r.drag_error;
      }
      if (w.reference_length > 0 && w.viscosity > 0) r.re = density * speed * w.reference_length / w.viscosity;
    }
  }
  return out;
}

std::string WallDrag::finish(const Comm& comm) const {
  const auto [pen, pushes] = walls_.totals(comm);
  const std::vector<DragResult> drag = results();
  std::string summary = fmt::format(
      "walls: {} penetrations of a solid during the run ({} force kicks stopped at a surface)\n", pen, pushes);
  for (std::size_t b = 0; b < drag.size(); ++b) {
    const DragResult& r = drag[b];
    // A solid that a model moves (a rigid body) reports its own force, with the momentum of its own
    // bounce-backs, which the pair forces here leave out.
    if (walls_.geometry().released(b)) {
      summary += fmt::format("drag on {}: moved by a model (a [[body]]): its force is in that model's output\n", r.name);
      continue;
    }
    summary += fmt::format("drag on {}: ({:.5g} +- {:.2g}, {:.5g} +- {:.2g}, {:.5g} +- {:.2g}) over {} samples{}\n", r.name,
                           r.force[0], r.error[0], r.force[1], r.error[1], r.force[2], r.error[2], r.samples,
                           r.cd >= 0 ? fmt::format(", C_D = {:.4g} +- {:.2g}", r.cd, r.cd_error) : "");
  }
  if (out_dir_.empty()) return summary;
  comm.on_root([&] {
    write_file_atomically(out_dir_ / "drag_summary.csv", [&](std::ostream& f) {
      f << "body,fx,fy,fz,fx_err,fy_err,fz_err,fluid_vx,fluid_vy,fluid_vz,samples,drag,drag_err,cd,cd_err,re,"
           "penetrations\n";
      for (const DragResult& r : drag)
        f << fmt::format("{},{:.10g},{:.10g},{:.10g},{:.4g},{:.4g},{:.4g},{:.10g},{:.10g},{:.10g},{},{:.10g},{:.4g},{:.8g},"
                         "{:.4g},{:.8g},{}\n",
                         r.name, r.force[0], r.force[1], r.force[2], r.error[0], r.error[1], r.error[2],
                         r.fluid_velocity[0], r.fluid_velocity[1], r.fluid_velocity[2], r.samples, r.drag, r.drag_error,
                         r.cd, r.cd_error, r.re, pen);
    });
  });
  return summary;
}

AdaptiveLog::AdaptiveLog(const SimulationSpec& spec, const Walls& walls, std::filesystem::path out_dir,
                         bool restarted, const Comm& comm)
    : walls_(walls), out_dir_(std::move(out_dir)) {
  if (out_dir_.empty()) return;
  comm.on_root([&] {
    std::filesystem::create_directories(out_dir_);
    std::string header = "step";
    for (const char* what : {"U", "rho"})
      for (const auto& s : spec.solids)
        for (int k = 0; k < spec.walls.adaptive_bins; ++k) header += fmt::format(",{}_{}{}", s.name, what, k);
    start_csv(out_dir_ / "adaptive.csv", restarted, header);
  });
}

void AdaptiveLog::run(StepContext& ctx) {
  // The update step is the same on every rank, so the root's write is collective as on_root needs.
  if (out_dir_.empty() || walls_.last_adaptive_update() != ctx.step) return;
  ctx.comm.on_root([&] {
    OutputFile f(out_dir_ / "adaptive.csv", OutputFile::Mode::Append);
    f << ctx.step;
    for (double x : walls_.adaptive_potential()) f << fmt::format(",{:.8g}", x);
    for (double x : walls_.adaptive_density()) f << fmt::format(",{:.6g}", x);
    f << "\n";
    f.close();
  });
}

}  // namespace mesodpd
