// Reflections at solid surfaces and the drag on solid bodies.
#include "boundary/walls.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/philox.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

constexpr double kFixed = 4294967296.0;  // 2^32: force and momentum sums in integers (order-free)
std::int64_t fixed(double v) { return static_cast<std::int64_t>(std::llround(v * kFixed)); }

// Two unit vectors completing n to an orthonormal basis.
void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 a = std::abs(n.x) < 0.6 ? Vec3{1, 0, 0} : (std::abs(n.y) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  const Vec3 t = a - dot(a, n) * n;
  t1 = (1.0 / std::sqrt(dot(t, t))) * t;
  t2 = {n.y * t1.z - n.z * t1.y, n.z * t1.x - n.x * t1.z, n.x * t1.y - n.y * t1.x};
}

}  // namespace

Walls::Walls(const SimulationSpec& spec, const Box& box, bool half_velocity, std::uint64_t first_step,
             std::uint64_t final_step)
    : spec_(spec), geometry_(spec.solids, box), half_velocity_(half_velocity) {
  for (const auto& s : spec.species) frozen_.push_back(s.frozen ? 1 : 0);
  double mass = 0;
  for (const auto& s : spec.species)
    if (!s.frozen) mass += s.mass * static_cast<double>(s.count);
  fill_density_ = mass / box.volume();
  impulse_.assign(3 * geometry_.bodies(), 0);
  const WallsSpec& w = spec.walls;
  const std::uint64_t from = std::max(first_step, w.drag_start);
  samples_expected_ = final_step > from ? final_step / w.drag_every - from / w.drag_every : 0;
  block_size_ = std::max<std::uint64_t>(1, samples_expected_ / static_cast<std::uint64_t>(w.drag_blocks));
  block_sums_.assign(static_cast<std::size_t>(w.drag_blocks) * geometry_.bodies(), {0, 0, 0, 0, 0, 0});
  block_counts_.assign(static_cast<std::size_t>(w.drag_blocks), 0);
}

void Walls::set_output(const std::filesystem::path& out_dir, bool restarted, const Comm& comm) {
  out_dir_ = out_dir;
  if (out_dir_.empty()) return;
  comm.on_root([&] {
    std::filesystem::create_directories(out_dir_);
    const auto path = out_dir_ / "drag.csv";
    if (restarted && std::filesystem::exists(path)) return;
    std::ofstream f(path, std::ios::trunc);
    if (!f) throw ConfigError(fmt::format("{}: cannot open for writing", path.string()));
    f << "step";
    for (const auto& s : spec_.solids) f << fmt::format(",{0}_fx,{0}_fy,{0}_fz", s.name);
    f << ",fluid_vx,fluid_vy,fluid_vz\n";
  });
}

// The velocity rule of walls.reflection applied to u, the velocity relative to the wall, which points
// into the solid (u . n < 0).
Vec3 Walls::reflected(const Vec3& u, const Vec3& nrm, double m, std::uint64_t step, std::uint32_t id) const {
  switch (spec_.walls.reflection) {
    case ReflectionKind::Specular:
      return u - 2.0 * dot(u, nrm) * nrm;
    case ReflectionKind::BounceBack:
      return -u;
    case ReflectionKind::Maxwell:
    default: {
      // Maxwellian wall at kT moving with the wall: tangential components Gaussian, the normal one from
      // the flux-weighted (Rayleigh) distribution, pointing into the fluid.
      const double sd = std::sqrt(spec_.kT / m);
      const Philox4x32 bits = pair_random_bits(spec_.seed, step, id, id, RngStream::WallReflection);
      const Philox4x32 more = pair_random_bits(spec_.seed, step, 0, id, RngStream::WallReflection);
      Vec3 t1, t2;
      tangents(nrm, t1, t2);
      const double vn = sd * std::sqrt(-2.0 * std::log(u01_open(bits.v[0])));
      return vn * nrm + (sd * gaussian_unit(bits.v[1], bits.v[2])) * t1 + (sd * gaussian_unit(bits.v[3], more.v[0])) * t2;
    }
  }
}

template <class Act>
void Walls::for_near_wall(StepContext& ctx, double below, Act&& act) {
  ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local, nb = geometry_.bodies();
#pragma omp parallel
  {
    std::vector<std::int64_t> impulse(3 * nb, 0);
    std::uint64_t count = 0;
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (p.body[i] != 0 || frozen_[static_cast<std::size_t>(p.species[i])]) continue;
      const Vec3 r{p.x[i], p.y[i], p.z[i]};
      int b = -1;
      const double d = geometry_.sdf(r, b);
      if (!(d < below)) continue;
      // act() returns the velocity change of the particle (zero if none).
      const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
      const Vec3 dv = act(i, r, d, b, m, count);
      // The wall takes the momentum the particle gains, with the opposite sign, as a force over dt.
      impulse[3 * static_cast<std::size_t>(b)] -= fixed(m * dv.x / ctx.dt);
      impulse[3 * static_cast<std::size_t>(b) + 1] -= fixed(m * dv.y / ctx.dt);
      impulse[3 * static_cast<std::size_t>(b) + 2] -= fixed(m * dv.z / ctx.dt);
    }
#pragma omp critical
    {
      for (std::size_t k = 0; k < impulse.size(); ++k) impulse_[k] += impulse[k];  // integers: order-free
      counted_ += count;
    }
  }
}

void Walls::mirror_positions(StepContext& ctx) {
  std::fill(impulse_.begin(), impulse_.end(), 0);
  ParticleData& p = ctx.particles;
  const Box& box = ctx.box;
  counted_ = 0;
  for_near_wall(ctx, 0.0, [&](std::size_t i, Vec3 r, double d, int b, double m, std::uint64_t& count) {
    // Inside the solid: mirror the position through the surface; where the mirror image is still inside
    // (a concave corner, a staircase image surface), step out along the normal.
    ++count;
    const Vec3 nrm = geometry_.normal(r, b);
    r = r - 2.0 * d * nrm;
    for (int tries = 0; tries < 8; ++tries) {
      int b2 = -1;
      const double d2 = geometry_.sdf(r, b2);
      if (d2 >= 0) break;
      r = r + (-d2 + 1e-6) * geometry_.normal(r, b2);
    }
    double* xyz[3] = {&p.x[i], &p.y[i], &p.z[i]};
    std::int32_t* img[3] = {&p.ix[i], &p.iy[i], &p.iz[i]};
    const double q[3] = {r.x, r.y, r.z};
    for (int a = 0; a < 3; ++a) {
      *xyz[a] = q[a];
      if (box.periodic[static_cast<std::size_t>(a)]) wrap_coordinate(*xyz[a], *img[a], box.length(a));
    }
    // The physical velocity (modified velocity-Verlet: the half-step one) relative to the wall.
    const auto& wv = spec_.solids[static_cast<std::size_t>(b)].velocity;
    double* v[3] = {half_velocity_ ? &p.hx[i] : &p.vx[i], half_velocity_ ? &p.hy[i] : &p.vy[i],
                    half_velocity_ ? &p.hz[i] : &p.vz[i]};
    const Vec3 u{*v[0] - wv[0], *v[1] - wv[1], *v[2] - wv[2]};
    if (!(dot(u, nrm) < 0) || spec_.walls.reflection == ReflectionKind::None) return Vec3{0, 0, 0};
    const Vec3 dv = reflected(u, nrm, m, ctx.step, p.id[i]) - u;
    *v[0] += dv.x;
    *v[1] += dv.y;
    *v[2] += dv.z;
    // The predicted velocity keeps its offset from the physical one.
    if (half_velocity_) {
      p.vx[i] += dv.x;
      p.vy[i] += dv.y;
      p.vz[i] += dv.z;
    }
    return dv;
  });
  penetrations_ += counted_;
  penetrations_total_ += counted_;
}

void Walls::reflect_velocities(StepContext& ctx) {
  if (spec_.walls.reflection == ReflectionKind::None) return;
  ParticleData& p = ctx.particles;
  counted_ = 0;
  for_near_wall(ctx, spec_.walls.layer, [&](std::size_t i, Vec3 r, double, int b, double m, std::uint64_t& count) {
    const Vec3 nrm = geometry_.normal(r, b);
    const auto& wv = spec_.solids[static_cast<std::size_t>(b)].velocity;
    const Vec3 u{p.vx[i] - wv[0], p.vy[i] - wv[1], p.vz[i] - wv[2]};
    if (!(dot(u, nrm) < 0)) return Vec3{0, 0, 0};
    ++count;
    const Vec3 dv = reflected(u, nrm, m, ctx.step, p.id[i]) - u;
    p.vx[i] += dv.x;
    p.vy[i] += dv.y;
    p.vz[i] += dv.z;
    return dv;
  });
  reflections_ += counted_;
}

std::array<std::uint64_t, 2> Walls::take_counts(const Comm& comm) {
  std::uint64_t c[2] = {reflections_, penetrations_};
  comm.sum(std::span<std::uint64_t>(c, 2));
  reflections_ = penetrations_ = 0;
  return {c[0], c[1]};
}

std::uint64_t Walls::total_penetrations(const Comm& comm) const {
  std::uint64_t c[1] = {penetrations_total_};
  comm.sum(std::span<std::uint64_t>(c, 1));
  return c[0];
}

void Walls::sample_drag(StepContext& ctx) {
  const WallsSpec& w = spec_.walls;
  if (ctx.step <= w.drag_start || ctx.step % w.drag_every != 0) return;
  const ParticleData& p = ctx.particles;
  const std::size_t nb = geometry_.bodies();
  // Per body three force sums, then the fluid's momentum and mass, all in 2^32 fixed point.
  std::vector<std::int64_t> q(impulse_);
  q.resize(3 * nb + 4, 0);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.body[i] > 0) {
      const std::size_t b = static_cast<std::size_t>(p.body[i] - 1);
      q[3 * b] += fixed(p.fx[i]);
      q[3 * b + 1] += fixed(p.fy[i]);
      q[3 * b + 2] += fixed(p.fz[i]);
    } else if (!frozen_[static_cast<std::size_t>(p.species[i])]) {
      const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
      q[3 * nb] += fixed(m * p.vx[i]);
      q[3 * nb + 1] += fixed(m * p.vy[i]);
      q[3 * nb + 2] += fixed(m * p.vz[i]);
      q[3 * nb + 3] += fixed(m);
    }
  }
  ctx.comm.sum(std::span<std::int64_t>(q));
  const double mass = static_cast<double>(q[3 * nb + 3]);
  const double u[3] = {static_cast<double>(q[3 * nb]) / mass, static_cast<double>(q[3 * nb + 1]) / mass,
                       static_cast<double>(q[3 * nb + 2]) / mass};
  const std::size_t block =
      std::min<std::size_t>(static_cast<std::size_t>(samples_ / block_size_), block_counts_.size() - 1);
  for (std::size_t b = 0; b < nb; ++b) {
    auto& s = block_sums_[block * nb + b];
    for (int c = 0; c < 3; ++c) {
      s[static_cast<std::size_t>(c)] += static_cast<double>(q[3 * b + static_cast<std::size_t>(c)]) / kFixed;
      s[3 + static_cast<std::size_t>(c)] += u[c];
    }
  }
  ++block_counts_[block];
  ++samples_;
  if (!out_dir_.empty() && ctx.comm.root()) {
    std::ofstream f(out_dir_ / "drag.csv", std::ios::app);
    f << ctx.step;
    for (std::size_t k = 0; k < 3 * nb; ++k) f << fmt::format(",{:.10g}", static_cast<double>(q[k]) / kFixed);
    f << fmt::format(",{:.10g},{:.10g},{:.10g}\n", u[0], u[1], u[2]);
  }
}

std::vector<DragResult> Walls::drag() const {
  const std::size_t nb = geometry_.bodies();
  const WallsSpec& w = spec_.walls;
  std::vector<DragResult> out(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    DragResult& r = out[b];
    r.name = spec_.solids[b].name;
    r.samples = samples_;
    if (samples_ == 0) continue;
    std::vector<std::array<double, 6>> means;
    std::array<double, 6> total{0, 0, 0, 0, 0, 0};
    for (std::size_t k = 0; k < block_counts_.size(); ++k) {
      if (block_counts_[k] == 0) continue;
      std::array<double, 6> m{};
      for (std::size_t c = 0; c < 6; ++c) {
        m[c] = block_sums_[k * nb + b][c] / static_cast<double>(block_counts_[k]);
        total[c] += block_sums_[k * nb + b][c];
      }
      means.push_back(m);
    }
    for (std::size_t c = 0; c < 6; ++c) total[c] /= static_cast<double>(samples_);
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
        const double scale = 2.0 / (fill_density_ * speed * speed * w.reference_area);
        r.cd = scale * r.drag;
        r.cd_error = scale * r.drag_error;
      }
      if (w.reference_length > 0 && w.viscosity > 0) r.re = fill_density_ * speed * w.reference_length / w.viscosity;
    }
  }
  return out;
}

std::string Walls::finish(const Comm& comm, const std::filesystem::path& out_dir) const {
  const std::uint64_t pen = total_penetrations(comm);
  const std::vector<DragResult> results = drag();
  std::string summary = fmt::format("walls: {} penetrations of a solid during the run\n", pen);
  for (const DragResult& r : results)
    summary += fmt::format("drag on {}: ({:.5g} +- {:.2g}, {:.5g} +- {:.2g}, {:.5g} +- {:.2g}) over {} samples{}\n", r.name,
                           r.force[0], r.error[0], r.force[1], r.error[1], r.force[2], r.error[2], r.samples,
                           r.cd >= 0 ? fmt::format(", C_D = {:.4g} +- {:.2g}", r.cd, r.cd_error) : "");
  if (out_dir.empty()) return summary;
  comm.on_root([&] {
    std::ofstream f(out_dir / "drag_summary.csv", std::ios::trunc);
    if (!f) throw ConfigError(fmt::format("{}: cannot open for writing", (out_dir / "drag_summary.csv").string()));
    f << "body,fx,fy,fz,fx_err,fy_err,fz_err,fluid_vx,fluid_vy,fluid_vz,samples,drag,drag_err,cd,cd_err,re,"
         "penetrations\n";
    for (const DragResult& r : results)
      f << fmt::format("{},{:.10g},{:.10g},{:.10g},{:.4g},{:.4g},{:.4g},{:.10g},{:.10g},{:.10g},{},{:.10g},{:.4g},{:.8g},"
                       "{:.4g},{:.8g},{}\n",
                       r.name, r.force[0], r.force[1], r.force[2], r.error[0], r.error[1], r.error[2],
                       r.fluid_velocity[0], r.fluid_velocity[1], r.fluid_velocity[2], r.samples, r.drag, r.drag_error,
                       r.cd, r.cd_error, r.re, pen);
  });
  return summary;
}

}  // namespace mesodpd
