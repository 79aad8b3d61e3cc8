// Reflections at solid surfaces, the momentum they take from the fluid, and the adaptive near-wall force.
#include "boundary/walls.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/philox.hpp"
#include "neighbor/cell_grid.hpp"
#include "io/byte_buffer.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

// Two unit vectors completing n to an orthonormal basis.
void tangents(const Vec3& n, Vec3& t1, Vec3& t2) {
  const Vec3 a = std::abs(n.x) < 0.6 ? Vec3{1, 0, 0} : (std::abs(n.y) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  const Vec3 t = a - dot(a, n) * n;
  t1 = (1.0 / std::sqrt(dot(t, t))) * t;
  t2 = {n.y * t1.z - n.z * t1.y, n.z * t1.x - n.x * t1.z, n.x * t1.y - n.y * t1.x};
}

}  // namespace

Walls::Walls(const SimulationSpec& spec, const Box& box, bool half_velocity, const std::vector<std::uint8_t>& released)
    : spec_(spec), geometry_(spec.solids, box, released), half_velocity_(half_velocity) {
  for (const auto& s : spec.species) frozen_.push_back(s.frozen ? 1 : 0);
  double mass = 0;
  for (const auto& s : spec.species)
    if (!s.frozen) mass += s.mass * static_cast<double>(s.count);
  fill_density_ = mass / box.volume();
  impulse_.assign(3 * geometry_.bodies(), 0);
  // The far-field grid: cells about 0.5 wide (wider in large boxes: at most ~2 million cells).
  const double len[3] = {box.len.x, box.len.y, box.len.z};
  const double width = std::max(0.5, std::cbrt(box.volume() / 2.0e6));
  double half_diagonal = 0;
  for (int d = 0; d < 3; ++d) {
    const int n = std::max(1, static_cast<int>(std::ceil(len[d] / width)));
    bound_cells_[static_cast<std::size_t>(d)] = n;
    bound_inverse_width_[static_cast<std::size_t>(d)] = n / len[d];
    half_diagonal += 0.25 * (len[d] / n) * (len[d] / n);
  }
  half_diagonal = std::sqrt(half_diagonal);
  const double lipschitz = geometry_.lipschitz();
  bound_.resize(static_cast<std::size_t>(bound_cells_[0]) * static_cast<std::size_t>(bound_cells_[1]) *
                static_cast<std::size_t>(bound_cells_[2]));
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < bound_.size(); ++k) {
    const std::size_t ix = k % static_cast<std::size_t>(bound_cells_[0]);
    const std::size_t iy = (k / static_cast<std::size_t>(bound_cells_[0])) % static_cast<std::size_t>(bound_cells_[1]);
    const std::size_t iz = k / (static_cast<std::size_t>(bound_cells_[0]) * static_cast<std::size_t>(bound_cells_[1]));
    const Vec3 centre{(static_cast<double>(ix) + 0.5) * len[0] / bound_cells_[0],
                      (static_cast<double>(iy) + 0.5) * len[1] / bound_cells_[1],
                      (static_cast<double>(iz) + 0.5) * len[2] / bound_cells_[2]};
    const double lower = geometry_.sdf(centre) - lipschitz * half_diagonal;
    // Rounded towards minus infinity so that the float is still a lower bound.
    float f = static_cast<float>(lower);
    if (static_cast<double>(f) > lower) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    bound_[k] = f;
  }
  const WallsSpec& w = spec.walls;
  adaptive_impulse_.assign(3 * geometry_.bodies(), 0);
  if (w.adaptive) {
    // Bins per solid (each has its own frozen structure and curvature), then the bulk.
    const std::size_t bins = static_cast<std::size_t>(w.adaptive_bins) * geometry_.bodies();
    bin_width_ = (w.adaptive_range - w.layer) / static_cast<double>(w.adaptive_bins);
    potential_.assign(bins, 0.0);
    segment_force_.assign(bins, 0.0);
    bin_counts_.assign(bins + 1, 0);
    // The fluid volume of each bin and of the bulk, from a fixed low-discrepancy point set (the R2
    // sequence) over the box: the same numbers on every rank, for any solid.
    constexpr std::uint64_t points = std::uint64_t{1} << 21;
    constexpr double g = 1.2207440846057596;  // the real root of x^4 = x + 1
    const double step[3] = {1 / g, 1 / (g * g), 1 / (g * g * g)};
    std::vector<std::uint64_t> hits(bins + 1, 0);
#pragma omp parallel
    {
      std::vector<std::uint64_t> mine(bins + 1, 0);
#pragma omp for schedule(static)
      for (std::uint64_t k = 0; k < points; ++k) {
        double q[3];
        for (int a = 0; a < 3; ++a) {
          const double t = 0.5 + static_cast<double>(k) * step[a];
          q[a] = (t - std::floor(t)) * box.length(a);
        }
        int b = -1;
        const double d = geometry_.sdf(Vec3{q[0], q[1], q[2]}, b);
        const int bin = adaptive_bin(d, b);
        if (bin >= 0) ++mine[static_cast<std::size_t>(bin)];
      }
#pragma omp critical
      for (std::size_t k = 0; k <= bins; ++k) hits[k] += mine[k];
    }
    for (std::uint64_t h : hits) bin_volume_.push_back(static_cast<double>(h) / static_cast<double>(points) * box.volume());
  }
}

void Walls::update_segment_forces() {
  // Nodes at the bin centres c_k = layer + (k + 1/2) h with U_k, and at the range with U = 0; segment k
  // runs from c_k to the next node (the last one h/2 long), and the part of bin 0 below c_0 continues
  // segment 0.
  const std::size_t n = static_cast<std::size_t>(spec_.walls.adaptive_bins);
  for (std::size_t at = 0; at < potential_.size(); at += n)
    for (std::size_t k = 0; k < n; ++k) {
      const double next = k + 1 < n ? potential_[at + k + 1] : 0.0;
      const double length = k + 1 < n ? bin_width_ : 0.5 * bin_width_;
      segment_force_[at + k] = -(next - potential_[at + k]) / length;
    }
}

double Walls::adaptive_force_at(double d, int body) const {
  const WallsSpec& w = spec_.walls;
  if (!(d >= w.layer) || d >= w.adaptive_range || body < 0) return 0.0;
  const int k = std::clamp(static_cast<int>(std::floor((d - w.layer) / bin_width_ - 0.5)), 0, w.adaptive_bins - 1);
  return segment_force_[static_cast<std::size_t>(body * w.adaptive_bins + k)];
}

int Walls::adaptive_bin(double d, int body) const {
  const WallsSpec& w = spec_.walls;
  if (!(d >= w.layer) || body < 0) return -1;
  if (d >= w.adaptive_range) return static_cast<int>(potential_.size());
  return body * w.adaptive_bins + std::min(w.adaptive_bins - 1, static_cast<int>((d - w.layer) / bin_width_));
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

double Walls::distance_bound(const Vec3& r) const {
  const double q[3] = {r.x, r.y, r.z};
  std::size_t k = 0;
  for (int d = 2; d >= 0; --d) {
    const int n = bound_cells_[static_cast<std::size_t>(d)];
    // Positions are wrapped or inside a bounded box; the comparisons in double also send a stray NaN or
    // a far-away value to a valid cell before any conversion.
    const double t = q[d] * bound_inverse_width_[static_cast<std::size_t>(d)];
    const int c = t >= n ? n - 1 : (t >= 0 ? static_cast<int>(t) : 0);
    k = k * static_cast<std::size_t>(n) + static_cast<std::size_t>(c);
  }
  return bound_[k];
}

const std::vector<float>& Walls::cell_bounds(const StepContext& ctx) {
  const CellGrid& g = *ctx.cells;
  const std::array<int, 9> key{g.dims()[0],       g.dims()[1],       g.dims()[2],       g.owned_lo()[0], g.owned_lo()[1],
                               g.owned_lo()[2],   g.owned_dims()[0], g.owned_dims()[1], g.owned_dims()[2]};
  const std::array<double, 4> lengths{ctx.box.len.x, ctx.box.len.y, ctx.box.len.z, ctx.cell_slack};
  if (key == cell_bound_grid_ && lengths == cell_bound_lengths_) return cell_bound_;
  cell_bound_grid_ = key;
  cell_bound_lengths_ = lengths;
  const double len[3] = {ctx.box.len.x, ctx.box.len.y, ctx.box.len.z};
  const int ox = g.owned_dims()[0], oy = g.owned_dims()[1];
  double size[3], half_diagonal = 0;
  for (std::size_t d = 0; d < 3; ++d) {
    size[d] = len[d] / g.dims()[d];
    half_diagonal += (0.5 * size[d] + ctx.cell_slack) * (0.5 * size[d] + ctx.cell_slack);
  }
  half_diagonal = std::sqrt(half_diagonal);
  const double lipschitz = geometry_.lipschitz();
  cell_bound_.resize(g.num_owned_cells());
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < cell_bound_.size(); ++c) {
    const int l[3] = {static_cast<int>(c) % ox, (static_cast<int>(c) / ox) % oy, static_cast<int>(c) / (ox * oy)};
    double centre[3];
    for (std::size_t d = 0; d < 3; ++d) centre[d] = (g.owned_lo()[d] + l[d] + 0.5) * size[d];
    // As distance_bound(), with a small absolute margin for the rounding of the geometry's own
    // arithmetic; rounded down to float.
    const double lower = geometry_.sdf(Vec3{centre[0], centre[1], centre[2]}) - lipschitz * half_diagonal - 1e-9;
    float f = static_cast<float>(lower);
    if (static_cast<double>(f) > lower) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    cell_bound_[c] = f;
  }
  return cell_bound_;
}

double Walls::longest_move(const StepContext& ctx, double kick) const {
  // dt |v| + kick |f| / m bounds every move; the largest speed and acceleration are taken separately
  // (a simple loop, not one evaluation of the move per particle), frozen species excluded.
  const ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local;
  std::vector<double> inv_mass2(frozen_.size());
  for (std::size_t s = 0; s < frozen_.size(); ++s)
    inv_mass2[s] = frozen_[s] ? 0.0 : 1.0 / (ctx.species_mass[s] * ctx.species_mass[s]);
  const double* w = inv_mass2.data();
  double v2max = 0, a2max = 0;
#pragma omp parallel for schedule(static) reduction(max : v2max, a2max)
  for (std::size_t i = 0; i < n; ++i) {
    const double mobile = w[p.species[i]] > 0 ? 1.0 : 0.0;
    const double v2 = mobile * (p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]);
    const double a2 = w[p.species[i]] * (p.fx[i] * p.fx[i] + p.fy[i] * p.fy[i] + p.fz[i] * p.fz[i]);
    // (A NaN compares false and is ignored here; the health check at the end of the step stops the run.)
    v2max = v2 > v2max ? v2 : v2max;
    a2max = a2 > a2max ? a2 : a2max;
  }
  // Rounding: the bound exceeds any move computed from the same numbers by far more than 1e-12.
  return (ctx.dt * std::sqrt(v2max) + kick * std::sqrt(a2max)) * (1.0 + 1e-12) + 1e-300;
}

template <class Far, class Act>
void Walls::for_near_wall(StepContext& ctx, double below, double skip_at, Far&& far, Act&& act) {
  ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local, nb = geometry_.bodies();
  // Particles are visited by cell where the step says where its cells are, and whole cells whose lower
  // bound reaches skip_at are left out (particles sorted by cell: each cell is one contiguous range).
  const bool by_cell = cell_skip_ && ctx.cells != nullptr && skip_at < std::numeric_limits<double>::infinity();
  const std::vector<float>* bounds = by_cell ? &cell_bounds(ctx) : nullptr;
  std::uint64_t examined = 0;
#pragma omp parallel reduction(+ : examined)
  {
    std::vector<std::int64_t> impulse(3 * nb, 0);
    std::array<std::uint64_t, 2> count{0, 0};
    auto visit = [&](std::size_t i) {
      if (p.body[i] != 0 || frozen_[static_cast<std::size_t>(p.species[i])]) return;
      ++examined;
      const Vec3 r{p.x[i], p.y[i], p.z[i]};
      const double m = ctx.species_mass[static_cast<std::size_t>(p.species[i])];
      if (far(i, m, distance_bound(r))) return;
      int b = -1;
      const double d = geometry_.sdf(r, b);
      if (!(d < below)) return;
      // act() returns the velocity change of the particle (zero if none).
      const Vec3 dv = act(i, r, d, b, m, count);
      // The wall takes the momentum the particle gains, with the opposite sign, as a force over dt.
      impulse[3 * static_cast<std::size_t>(b)] -= wall_fixed(m * dv.x / ctx.dt);
      impulse[3 * static_cast<std::size_t>(b) + 1] -= wall_fixed(m * dv.y / ctx.dt);
      impulse[3 * static_cast<std::size_t>(b) + 2] -= wall_fixed(m * dv.z / ctx.dt);
    };
    if (by_cell) {
      const std::uint32_t* start = ctx.cell_start;
      const float* cb = bounds->data();
      const std::size_t nc = bounds->size();
      // Dynamic: the cells near surfaces, which hold the work, may all lie in one thread's share.
#pragma omp for schedule(dynamic, 64)
      for (std::size_t c = 0; c < nc; ++c) {
        if (static_cast<double>(cb[c]) >= skip_at) continue;
        for (std::size_t i = start[c]; i < start[c + 1]; ++i) visit(i);
      }
    } else {
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) visit(i);
    }
#pragma omp critical
    {
      for (std::size_t k = 0; k < impulse.size(); ++k) impulse_[k] += impulse[k];  // integers: order-free
      counted_[0] += count[0];
      counted_[1] += count[1];
    }
  }
  examined_ = examined;
}

void Walls::mirror_positions(StepContext& ctx) {
  std::fill(impulse_.begin(), impulse_.end(), 0);
  if (geometry_.empty()) return;  // every solid released to a model that moves it
  ParticleData& p = ctx.particles;
  const Box& box = ctx.box;
  counted_ = {0, 0};
  // A particle whose distance bound is not negative is outside every solid.
  auto far = [](std::size_t, double, double bound) { return bound >= 0.0; };
  // Whole cells: every particle was at least its cell's bound from any surface when the last
  // reflect_velocities() ran and has since moved by at most next_move_ (where that call belongs to the
  // previous step, nothing was reordered since, and the move was a single position update); the signed
  // distance changes by at most twice the move (Geometry::lipschitz() times it, as in reflect_velocities).
  const bool moved_once = next_move_step_ + 1 == ctx.step && next_move_generation_ == p.generation() &&
                          spec_.bond_subcycles <= 1;
  const double skip_at = moved_once ? 2.0 * next_move_ : std::numeric_limits<double>::infinity();
  for_near_wall(ctx, 0.0, skip_at, far, [&](std::size_t i, Vec3 r, double d, int b, double m, std::array<std::uint64_t, 2>& count) {
    // Inside the solid: mirror the position through the surface; where the mirror image is still inside
    // (a concave corner, a staircase image surface), step out along the normal.
    ++count[0];
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
  penetrations_ += counted_[0];
  penetrations_total_ += counted_[0];
}

void Walls::reflect_velocities(StepContext& ctx) {
  if (spec_.walls.reflection == ReflectionKind::None || geometry_.empty()) return;  // empty: every solid released
  ParticleData& p = ctx.particles;
  const double dt = ctx.dt;
  // The next position update moves a particle by dt v + (dt^2 / 2) f / m (modified velocity-Verlet) or
  // dt v (Euler), with this step's velocity and force: both are final here, so the move is known.
  const double kick = half_velocity_ ? 0.5 * dt * dt : 0.0;
  const double layer = spec_.walls.layer;
  counted_ = {0, 0};
  // Out of reach: at least layer + twice the next move from every surface (act() below returns no change
  // for such a particle; the bound only saves evaluating the geometry).
  auto far = [&](std::size_t i, double m, double bound) {
    const Vec3 s = dt * Vec3{p.vx[i], p.vy[i], p.vz[i]} + (kick / m) * Vec3{p.fx[i], p.fy[i], p.fz[i]};
    return bound >= layer + 2.0 * std::sqrt(dot(s, s));
  };
  // Whole cells out of reach: every particle of the cell is at least layer + twice the longest move of
  // any particle from every surface.
  const double longest = longest_move(ctx, kick);
  std::vector<double> changed_move(static_cast<std::size_t>(omp_get_max_threads()), 0.0);
  for_near_wall(ctx, std::numeric_limits<double>::infinity(), layer + 2.0 * longest, far,
                [&](std::size_t i, Vec3 r, double d, int b, double m, std::array<std::uint64_t, 2>& count) {
    const Vec3 f{p.fx[i], p.fy[i], p.fz[i]};
    const Vec3 v0{p.vx[i], p.vy[i], p.vz[i]};
    auto move = [&](const Vec3& v) { return dt * v + (kick / m) * f; };
    // Where the next move would end inside a solid (the signed distance changes by at most the length
    // of the move: a far particle needs no second look), the solid it would enter decides.
    auto entered = [&](const Vec3& v, double& depth) {
      const Vec3 s = move(v);
      if (d >= layer + 2.0 * std::sqrt(dot(s, s))) return -1;
      int b2 = -1;
      depth = geometry_.sdf(r + s, b2);
      return depth < 0 ? b2 : -1;
    };
    double depth = 0;
    int hit = entered(v0, depth);
    if (hit < 0 && d >= layer) return Vec3{0, 0, 0};
    if (hit < 0) hit = b;
    Vec3 v = v0;
    // The walls.reflection rule for a particle in the layer, or about to cross the surface, moving
    // into the solid relative to the wall (seed 000 Sect. 3.2.1).
    const Vec3 nrm = geometry_.normal(r, hit);
    const auto& wv = spec_.solids[static_cast<std::size_t>(hit)].velocity;
    const Vec3 w{wv[0], wv[1], wv[2]};
    if (dot(v - w, nrm) < 0) {
      ++count[0];
      v = reflected(v - w, nrm, m, ctx.step, p.id[i]) + w;
    }
    // A reflected (or outgoing) particle that the force kick alone would still carry in: the solid is
    // impenetrable, so it takes the normal momentum that stops the move on its surface (rare: a large
    // random force on a particle within a few hundredths of the surface). Where the normal is not the
    // gradient of the signed distance (an image surface: the normal comes from the smoothed indicator,
    // the distance from the staircase of cells, up to ~45 degrees apart at a step), a push of the depth
    // leaves the end point a fraction of it inside: later pushes double until it is out, and if that
    // fails the move stops where the particle is (outside: earlier penetrations were mirrored out).
    // Exact-distance shapes clear on the first push, so their results do not depend on the later ones.
    int tries = 0;
    for (int into = entered(v, depth); into >= 0; into = entered(v, depth), ++tries) {
      ++count[1];
      if (tries == 8) {
        v = (-kick / (m * dt)) * f;
        break;
      }
      v = v + (std::ldexp(-depth, tries) / dt * (1 + 1e-9) + 1e-12) * geometry_.normal(r, into);
    }
    const Vec3 dv = v - v0;
    p.vx[i] = v.x;
    p.vy[i] = v.y;
    p.vz[i] = v.z;
    if (dv.x != 0 || dv.y != 0 || dv.z != 0) {
      const Vec3 s = move(v);
      double& c = changed_move[static_cast<std::size_t>(omp_get_thread_num())];
      c = std::max(c, std::sqrt(dot(s, s)));
    }
    return dv;
  });
  reflections_ += counted_[0];
  pushes_ += counted_[1];
  // The next position update moves every particle by at most this (mirror_positions uses it).
  next_move_ = std::max(longest, *std::max_element(changed_move.begin(), changed_move.end()));
  next_move_step_ = ctx.step;
  next_move_generation_ = p.generation();
}

std::array<std::uint64_t, 2> Walls::take_counts(const Comm& comm) {
  std::uint64_t c[2] = {reflections_, penetrations_};
  comm.sum(std::span<std::uint64_t>(c, 2));
  reflections_ = penetrations_ = 0;
  return {c[0], c[1]};
}

std::array<std::uint64_t, 2> Walls::totals(const Comm& comm) const {
  std::uint64_t c[2] = {penetrations_total_, pushes_};
  comm.sum(std::span<std::uint64_t>(c, 2));
  return {c[0], c[1]};
}

std::uint64_t Walls::last_changes(const Comm& comm) const {
  std::uint64_t c = counted_[0] + counted_[1];
  comm.sum(std::span<std::uint64_t>(&c, 1));
  return c;
}

void Walls::add_adaptive_force(StepContext& ctx) {
  // The force on each solid is set afresh at every force evaluation: it is a function of the positions.
  std::fill(adaptive_impulse_.begin(), adaptive_impulse_.end(), 0);
  if (std::all_of(segment_force_.begin(), segment_force_.end(), [](double f) { return f == 0; })) return;
  ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local;
#pragma omp parallel
  {
    std::vector<std::int64_t> taken(adaptive_impulse_.size(), 0);
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (p.body[i] != 0 || frozen_[static_cast<std::size_t>(p.species[i])]) continue;
      const Vec3 r{p.x[i], p.y[i], p.z[i]};
      int b = -1;
      const double d = geometry_.sdf(r, b);
      const double fa = adaptive_force_at(d, b);
      if (fa == 0) continue;
      const Vec3 f = fa * geometry_.normal(r, b);
      p.fx[i] += f.x;
      p.fy[i] += f.y;
      p.fz[i] += f.z;
      // The solid feels the opposite force.
      const std::size_t k = 3 * static_cast<std::size_t>(b);
      taken[k] -= wall_fixed(f.x);
      taken[k + 1] -= wall_fixed(f.y);
      taken[k + 2] -= wall_fixed(f.z);
    }
#pragma omp critical
    for (std::size_t k = 0; k < taken.size(); ++k) adaptive_impulse_[k] += taken[k];  // integers: order-free
  }
}

std::vector<std::int64_t> Walls::wall_forces() const {
  std::vector<std::int64_t> q(impulse_);
  for (std::size_t k = 0; k < q.size(); ++k) q[k] += adaptive_impulse_[k];
  return q;
}

void Walls::adapt(StepContext& ctx) {
  const WallsSpec& w = spec_.walls;
  if (!w.adaptive || (w.adaptive_stop > 0 && ctx.step > w.adaptive_stop)) return;
  const ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local, bins = potential_.size();
  std::vector<std::uint64_t> counts(bins + 1, 0);
#pragma omp parallel
  {
    std::vector<std::uint64_t> mine(bins + 1, 0);
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (p.body[i] != 0 || frozen_[static_cast<std::size_t>(p.species[i])]) continue;
      int b = -1;
      const double d = geometry_.sdf(Vec3{p.x[i], p.y[i], p.z[i]}, b);
      const int k = adaptive_bin(d, b);
      if (k >= 0) ++mine[static_cast<std::size_t>(k)];
    }
#pragma omp critical
    for (std::size_t k = 0; k <= bins; ++k) counts[k] += mine[k];
  }
  ctx.comm.sum(std::span<std::uint64_t>(counts));
  for (std::size_t k = 0; k <= bins; ++k) bin_counts_[k] += counts[k];
  ++bin_samples_;
  if (ctx.step % w.adaptive_every != 0) return;
  // Proportional control of each bin's density towards the bulk's, on the bin's potential (seed 002: a
  // bin denser than desired gets a stronger push away from the wall, a thinner one a weaker push or a
  // pull). The step gain kT ln(rho_k / rho_bulk) is the whole correction for an ideal gas, which fills
  // the bins as exp(-U_k / kT); a dense fluid responds less, so gain <= 1 converges without overshoot.
  if (bin_counts_[bins] > 0 && bin_volume_[bins] > 0) {
    const double bulk = static_cast<double>(bin_counts_[bins]) / bin_volume_[bins];
    ratio_.assign(bins, 1.0);
    for (std::size_t k = 0; k < bins; ++k) {
      if (bin_volume_[k] <= 0 || bin_counts_[k] == 0) continue;
      ratio_[k] = static_cast<double>(bin_counts_[k]) / bin_volume_[k] / bulk;
      potential_[k] += w.adaptive_gain * spec_.kT * std::log(ratio_[k]);
    }
    update_segment_forces();
    last_update_ = ctx.step;
  }
  std::fill(bin_counts_.begin(), bin_counts_.end(), 0);
  bin_samples_ = 0;
}

void Walls::save(ByteWriter& w) const {
  w.put_vector(potential_);
  w.put_vector(bin_counts_);
  w.put<std::uint64_t>(bin_samples_);
  w.put_vector(ratio_);
}

void Walls::load(ByteReader& r, const std::string& context) {
  std::vector<double> force = r.get_vector<double>();
  std::vector<std::uint64_t> bin_counts = r.get_vector<std::uint64_t>();
  const auto bin_samples = r.get<std::uint64_t>();
  std::vector<double> ratio = r.get_vector<double>();
  // A run that turns the adaptive force on at a restart starts it afresh; a changed bin count is refused.
  if (!spec_.walls.adaptive || force.empty()) return;
  if (force.size() != potential_.size() || bin_counts.size() != bin_counts_.size())
    throw ConfigError(fmt::format("{}: the checkpoint's adaptive wall force has {} bins in all, this run {} "
                                  "(walls.adaptive_bins per [[solid]])",
                                  context, force.size(), potential_.size()));
  potential_ = std::move(force);
  update_segment_forces();
  bin_counts_ = std::move(bin_counts);
  bin_samples_ = bin_samples;
  ratio_ = std::move(ratio);
}

}  // namespace mesodpd
