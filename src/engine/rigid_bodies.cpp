// Rigid bodies of frozen particles: their mass properties, their velocity-Verlet step, the bounce-back
// of fluid particles at their moving surfaces and their contact forces.
#include "engine/rigid_bodies.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>

#include "boundary/walls.hpp"
#include "engine/blow_up_error.hpp"
#include "engine/lees_edwards_spec.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/config_error.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

Quat operator*(const Quat& a, const Quat& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quat turned(const Quat& q, const Vec3& omega, double t) {
  const double w = std::sqrt(dot(omega, omega));
  if (w * t == 0.0) return q;
  const double half = 0.5 * w * t, s = std::sin(half) / w;
  Quat r = Quat{std::cos(half), s * omega.x, s * omega.y, s * omega.z} * q;
  const double n = std::sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
  return {r.w / n, r.x / n, r.y / n, r.z / n};
}

namespace {

using Mat3 = std::array<double, 9>;

Vec3 times(const Mat3& m, const Vec3& v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
          m[6] * v.x + m[7] * v.y + m[8] * v.z};
}

}  // namespace

Vec3 angular_velocity(const Quat& q, const Vec3& l, const std::array<double, 9>& inertia_inverse) {
  return rotate(q, times(inertia_inverse, rotate_back(q, l)));
}

Quat turn_free(const Quat& q, const Vec3& l, const std::array<double, 9>& inertia_inverse, double dt) {
  const Vec3 w1 = angular_velocity(q, l, inertia_inverse);
  const Vec3 w2 = angular_velocity(turned(q, w1, 0.5 * dt), l, inertia_inverse);
  return turned(q, w2, dt);
}

namespace {

Mat3 inverse(const Mat3& m) {
  const double c00 = m[4] * m[8] - m[5] * m[7], c01 = m[5] * m[6] - m[3] * m[8], c02 = m[3] * m[7] - m[4] * m[6];
  const double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  const double inv = 1.0 / det;
  return {c00 * inv, (m[2] * m[7] - m[1] * m[8]) * inv, (m[1] * m[5] - m[2] * m[4]) * inv,
          c01 * inv, (m[0] * m[8] - m[2] * m[6]) * inv, (m[2] * m[3] - m[0] * m[5]) * inv,
          c02 * inv, (m[1] * m[6] - m[0] * m[7]) * inv, (m[0] * m[4] - m[1] * m[3]) * inv};
}

// The smallest eigenvalue's sign test of a symmetric 3x3 matrix: positive definite (Sylvester).
bool positive_definite(const Mat3& m) {
  const double d1 = m[0], d2 = m[0] * m[4] - m[1] * m[3];
  const double d3 = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
  return d1 > 0 && d2 > 0 && d3 > 0;
}

// Axis-aligned bounds of a bounded shape; throws for an unbounded one.
void bounds(const ShapeSpec& s, const std::string& key, Vec3& lo, Vec3& hi) {
  switch (s.kind) {
    case ShapeKind::Sphere:
      lo = Vec3{s.center[0], s.center[1], s.center[2]} - Vec3{s.radius, s.radius, s.radius};
      hi = Vec3{s.center[0], s.center[1], s.center[2]} + Vec3{s.radius, s.radius, s.radius};
      return;
    case ShapeKind::Box:
      lo = {s.lo[0], s.lo[1], s.lo[2]};
      hi = {s.hi[0], s.hi[1], s.hi[2]};
      return;
    case ShapeKind::Union: {
      lo = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity()};
      hi = -1.0 * lo;
      for (std::size_t k = 0; k < s.parts.size(); ++k) {
        Vec3 a, b;
        bounds(s.parts[k], fmt::format("{}.parts[{}]", key, k), a, b);
        lo = {std::min(lo.x, a.x), std::min(lo.y, a.y), std::min(lo.z, a.z)};
        hi = {std::max(hi.x, b.x), std::max(hi.y, b.y), std::max(hi.z, b.z)};
      }
      return;
    }
    case ShapeKind::Difference:
      if (!s.parts.empty()) return bounds(s.parts[0], key + ".parts[0]", lo, hi);
      break;
    default:
      break;
  }
  throw ConfigError(fmt::format("{}: a [[body]] must be bounded: a sphere, a box, or a union or difference of them "
                                "(planes, cylinders, pillars and images extend across the box)",
                                key));
}

// Wraps r into the box along every periodic axis, as the engine wraps particles (apply_box_boundaries):
// under Lees-Edwards shear a crossing of the gradient faces first moves it by -k offset along the flow
// axis. Returns k, the crossings of the gradient faces (the velocity then changes by -k dU along f);
// `image` counts the crossings per axis.
double wrap_point(const Box& box, double r[3], std::int32_t image[3]) {
  const double k = box.sheared() ? wrap_sheared_gradient(box, r[box.shear.gradient], image[box.shear.gradient], r[box.shear.flow]) : 0.0;
  for (int a = 0; a < 3; ++a)
    if (box.periodic[static_cast<std::size_t>(a)]) wrap_coordinate(r[a], image[a], box.length(a));
  return k;
}

// sym(a (x) b) in the order xx, yy, zz, xy, xz, yz.
Sym6 sym_outer(const Vec3& a, const Vec3& b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z, 0.5 * (a.x * b.y + a.y * b.x), 0.5 * (a.x * b.z + a.z * b.x),
          0.5 * (a.y * b.z + a.z * b.y)};
}

void add_to(Sym6& s, const Sym6& t, double c = 1.0) {
  for (std::size_t q = 0; q < 6; ++q) s[q] += c * t[q];
}

Box unbounded_box() {
  Box b;
  b.periodic = {false, false, false};
  b.len = {1e300, 1e300, 1e300};
  return b;
}

}  // namespace

MassProperties mass_properties(const ShapeSpec& shape, const std::string& key) {
  MassProperties out;
  if (shape.kind == ShapeKind::Sphere) {
    const double r = shape.radius;
    out.volume = 4.0 / 3.0 * std::numbers::pi * r * r * r;
    out.center = {shape.center[0], shape.center[1], shape.center[2]};
    const double i = 0.4 * out.volume * r * r;
    out.inertia = {i, 0, 0, 0, i, 0, 0, 0, i};
    out.radius = r;
    return out;
  }
  Vec3 lo, hi;
  bounds(shape, key, lo, hi);
  const std::unique_ptr<Shape> s = make_shape(shape, unbounded_box(), key);
  const Vec3 ext = hi - lo;
  const double h = std::max({ext.x, ext.y, ext.z}) / 100.0;
  const int n[3] = {std::max(1, static_cast<int>(std::ceil(ext.x / h))), std::max(1, static_cast<int>(std::ceil(ext.y / h))),
                    std::max(1, static_cast<int>(std::ceil(ext.z / h)))};
  // Cell-centre quadrature: first the volume and centre, then the second moments about the centre.
  std::vector<Vec3> inside;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Vec3 p = lo + Vec3{(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
        if (s->sdf(p) < 0) inside.push_back(p);
      }
  if (inside.empty()) throw ConfigError(fmt::format("{}: the shape of a [[body]] has no volume", key));
  const double cell = h * h * h;
  Vec3 sum;
  for (const Vec3& p : inside) sum += p;
  out.volume = static_cast<double>(inside.size()) * cell;
  out.center = (1.0 / static_cast<double>(inside.size())) * sum;
  double far = 0;
  for (const Vec3& p : inside) {
    const Vec3 d = p - out.center;
    const double r2 = dot(d, d);
    far = std::max(far, r2);
    const double c[3] = {d.x, d.y, d.z};
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) out.inertia[static_cast<std::size_t>(3 * a + b)] += cell * ((a == b ? r2 : 0.0) - c[a] * c[b]);
  }
  out.radius = std::sqrt(far) + std::sqrt(3.0) * h;
  return out;
}

RigidBodies::RigidBodies(std::vector<BodySpec> bodies, const SimulationSpec& spec, const Box& box, bool half_velocity)
    : specs_(std::move(bodies)), box_(box), half_velocity_(half_velocity) {
  body_of_.assign(spec.solids.size(), -1);
  double fluid_mass = 0;
  for (const SpeciesSpec& s : spec.species) {
    frozen_.push_back(s.frozen ? 1 : 0);
    species_mass_.push_back(s.mass);
    if (!s.frozen) fluid_mass += s.mass * static_cast<double>(s.count);
  }
  const double fluid_density = fluid_mass / box.volume();
  for (std::size_t k = 0; k < specs_.size(); ++k) {
    const BodySpec& b = specs_[k];
    const std::string key = fmt::format("body[{}]", k);
    int solid = -1;
    for (std::size_t s = 0; s < spec.solids.size(); ++s)
      if (spec.solids[s].name == b.solid) solid = static_cast<int>(s);
    if (solid < 0) throw ConfigError(fmt::format("{}.solid: no [[solid]] is named '{}'", key, b.solid));
    if (body_of_[static_cast<std::size_t>(solid)] >= 0)
      throw ConfigError(fmt::format("{}.solid: solid '{}' is already moved by body[{}]", key, b.solid,
                                    body_of_[static_cast<std::size_t>(solid)]));
    body_of_[static_cast<std::size_t>(solid)] = static_cast<int>(k);
    solid_of_.push_back(solid);
    names_.push_back(b.solid);
    const MassProperties mp = mass_properties(spec.solids[static_cast<std::size_t>(solid)].shape, fmt::format("{}.solid ('{}')", key, b.solid));
    const double density = b.density > 0 ? b.density : fluid_density;
    if (!(density > 0))
      throw ConfigError(fmt::format("{}.density: the body's density is {} (the fluid's mass density when not given); it must be positive",
                                    key, density));
    Mat3 inertia;
    for (std::size_t a = 0; a < 9; ++a) inertia[a] = density * mp.inertia[a];
    if (!positive_definite(inertia))
      throw ConfigError(fmt::format("{}: the inertia tensor of solid '{}' is not positive definite", key, b.solid));
    // A body must fit its own nearest-image lookups: its diameter below half of every periodic length.
    for (int a = 0; a < 3; ++a)
      if (box.periodic[static_cast<std::size_t>(a)] && 4.0 * mp.radius >= box.length(a))
        throw ConfigError(fmt::format("{}.solid: solid '{}' reaches {:.4g} from its centre, more than a quarter of the "
                                      "periodic box length {} along {}; make the box larger or the body smaller",
                                      key, b.solid, mp.radius, box.length(a), "xyz"[a]));
    mass_.push_back(density * mp.volume);
    radius_.push_back(mp.radius);
    inertia_body_.push_back(inertia);
    inertia_inverse_.push_back(inverse(inertia));
    origin_.push_back(mp.center);
    shapes_.push_back(make_shape(spec.solids[static_cast<std::size_t>(solid)].shape, unbounded_box(), key));
    BodyState st;
    st.x = mp.center;
    st.v = {b.velocity[0], b.velocity[1], b.velocity[2]};
    Vec3 w{b.angular_velocity[0], b.angular_velocity[1], b.angular_velocity[2]};
    const LeesEdwardsSpec* le = spec.model<LeesEdwardsSpec>("lees_edwards");
    if (le && le->initial_profile && b.motion == BodyMotion::Free) {
      // The imposed flow u = rate x_g e_f (zero at the middle of g) at the centre, and half its vorticity.
      const int f = le->flow, g = le->gradient;
      double cg = component(st.x, g);
      std::int32_t image = 0;
      wrap_coordinate(cg, image, box.length(g));
      st.v += (le->initial_rate() * (cg - 0.5 * box.length(g))) * axis_vector(f);
      w += (0.5 * le->initial_rate()) * cross(axis_vector(g), axis_vector(f));
    }
    st.l = times(inertia, w);
    state_.push_back(st);
  }
  stresslet_.assign(specs_.size(), Sym6{});
  bounce_stresslet_.assign(specs_.size(), Sym6{});
  stresslet_sum_.assign(specs_.size(), Sym6{});
  stresslet_steps_.assign(specs_.size(), 0);
  walls_ = Geometry(spec.solids, box, released());
}

std::vector<std::uint8_t> RigidBodies::released() const {
  std::vector<std::uint8_t> r(body_of_.size(), 0);
  for (int s : solid_of_) r[static_cast<std::size_t>(s)] = 1;
  return r;
}

Vec3 RigidBodies::omega_at(std::size_t k, const Quat& q) const {
  if (specs_[k].motion == BodyMotion::Towed) {
    const auto& w = specs_[k].angular_velocity;
    return {w[0], w[1], w[2]};
  }
  return angular_velocity(q, state_[k].l, inertia_inverse_[k]);
}

std::array<double, 9> RigidBodies::inertia(std::size_t k) const {
  Mat3 out{};
  const Quat& q = state_[k].q;
  for (int b = 0; b < 3; ++b) {
    const Vec3 col = rotate(q, times(inertia_body_[k], rotate_back(q, axis_vector(b))));
    out[static_cast<std::size_t>(b)] = col.x;
    out[static_cast<std::size_t>(3 + b)] = col.y;
    out[static_cast<std::size_t>(6 + b)] = col.z;
  }
  return out;
}

Vec3 RigidBodies::wrapped_center(std::size_t k) const {
  Vec3 c = state_[k].x;
  double* xyz[3] = {&c.x, &c.y, &c.z};
  for (int a = 0; a < 3; ++a)
    if (box_.periodic[static_cast<std::size_t>(a)]) {
      std::int32_t image = 0;
      wrap_coordinate(*xyz[a], image, box_.length(a));
    }
  return c;
}

Vec3 RigidBodies::displacement(const Vec3& a, const Vec3& b, double* n) const {
  double d[3] = {a.x - b.x, a.y - b.y, a.z - b.z};
  const double k = box_displacement(box_, d);
  if (n) *n = k;
  return {d[0], d[1], d[2]};
}

Sym6 RigidBodies::mean_stresslet(std::size_t k) const {
  Sym6 m{};
  if (stresslet_steps_[k] > 0) add_to(m, stresslet_sum_[k], 1.0 / static_cast<double>(stresslet_steps_[k]));
  return m;
}

long RigidBodies::find(std::uint32_t id) const { return id < index_of_id_.size() ? index_of_id_[id] : -1; }

const std::vector<std::int32_t>& RigidBodies::slots(const ParticleData& p) {
  if (slot_generation_ != p.generation() || slot_count_ != p.n_local || slot_.size() != p.n_local) {
    slot_.resize(p.n_local);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < p.n_local; ++i) slot_[i] = p.body[i] > 0 ? static_cast<std::int32_t>(find(p.id[i])) : -1;
    slot_generation_ = p.generation();
    slot_count_ = p.n_local;
  }
  return slot_;
}

void RigidBodies::attach(StepContext& ctx) {
  ParticleData& p = ctx.particles;
  // Every body particle's (id, body, position), gathered from every rank onto every rank.
  std::vector<std::byte> mine;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.body[i] <= 0) continue;
    const int body = body_of_[static_cast<std::size_t>(p.body[i] - 1)];
    if (body < 0) continue;
    const std::uint32_t id = p.id[i];
    const std::int32_t b = body;
    const double r[3] = {p.x[i], p.y[i], p.z[i]};
    const std::size_t at = mine.size();
    mine.resize(at + sizeof id + sizeof b + sizeof r);
    std::memcpy(mine.data() + at, &id, sizeof id);
    std::memcpy(mine.data() + at + sizeof id, &b, sizeof b);
    std::memcpy(mine.data() + at + sizeof id + sizeof b, r, sizeof r);
  }
  std::vector<std::byte> all = ctx.comm.distributed() ? ctx.comm.gather(mine) : mine;
  if (ctx.comm.distributed()) ctx.comm.broadcast(all);
  const std::size_t rec = sizeof(std::uint32_t) + sizeof(std::int32_t) + 3 * sizeof(double);
  struct Entry {
    std::uint32_t id;
    std::int32_t body;
    Vec3 b;
  };
  std::vector<Entry> entries;
  for (std::size_t at = 0; at + rec <= all.size(); at += rec) {
    Entry e{};
    double r[3];
    std::memcpy(&e.id, all.data() + at, sizeof e.id);
    std::memcpy(&e.body, all.data() + at + sizeof e.id, sizeof e.body);
    std::memcpy(r, all.data() + at + sizeof e.id + sizeof e.body, sizeof r);
    e.b = displacement(Vec3{r[0], r[1], r[2]}, wrapped_center(static_cast<std::size_t>(e.body)));
    entries.push_back(e);
  }
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.id < b.id; });
  ids_.clear();
  owner_.clear();
  offset_.clear();
  std::vector<std::size_t> count(specs_.size(), 0);
  for (const Entry& e : entries) {
    ids_.push_back(e.id);
    owner_.push_back(e.body);
    offset_.push_back(e.b);
    ++count[static_cast<std::size_t>(e.body)];
  }
  for (std::size_t k = 0; k < specs_.size(); ++k)
    if (count[k] == 0)
      throw ConfigError(fmt::format("body[{}]: solid '{}' holds no frozen particle (is it smaller than the particle "
                                    "spacing, or is walls.depth 0?)",
                                    k, names_[k]));
  index_points();
  // Bodies may not start inside each other or inside a fixed wall.
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    const std::size_t a = static_cast<std::size_t>(owner_[n]);
    const Vec3 r = state_[a].x + offset_[n];
    for (std::size_t k = 0; k < specs_.size(); ++k) {
      if (k == a) continue;
      const Vec3 d = displacement(r, state_[k].x);
      if (dot(d, d) < radius_[k] * radius_[k] && body_sdf(k, d) < 0)
        throw ConfigError(fmt::format("body[{}] and body[{}] (solids '{}' and '{}') overlap at the start: particle id {} "
                                      "of the first lies inside the second; move them apart",
                                      a, k, names_[a], names_[k], ids_[n]));
    }
    if (!walls_.empty()) {
      const Vec3 w = wrapped_center(a) + offset_[n];
      if (walls_.sdf(w) < 0)
        throw ConfigError(fmt::format("body[{}] (solid '{}') overlaps a fixed [[solid]] at the start (particle id {}); "
                                      "move it into the fluid",
                                      a, names_[a], ids_[n]));
    }
  }
  check_box(ctx.step);
  ready_ = true;
  place(ctx, false);
}

void RigidBodies::index_points() {
  // The table from id to index (ids up to the largest body particle's: 4 bytes each).
  index_of_id_.assign(ids_.empty() ? 0 : static_cast<std::size_t>(ids_.back()) + 1, -1);
  for (std::size_t n = 0; n < ids_.size(); ++n) index_of_id_[ids_[n]] = static_cast<std::int32_t>(n);
  points_.assign(specs_.size(), {});
  for (std::size_t n = 0; n < ids_.size(); ++n) {
    const std::size_t k = static_cast<std::size_t>(owner_[n]);
    if (body_sdf(k, offset_[n]) > -specs_[k].repulsion_range) points_[k].push_back(offset_[n]);
  }
}

void RigidBodies::check_box(std::uint64_t step) const {
  for (std::size_t k = 0; k < specs_.size(); ++k)
    for (int a = 0; a < 3; ++a) {
      if (box_.periodic[static_cast<std::size_t>(a)]) continue;
      const double c = component(state_[k].x, a);
      if (c - radius_[k] < 0 || c + radius_[k] > box_.length(a))
        throw BlowUpError(step, 0,
                          fmt::format("body[{}] (solid '{}') left the box along {} at step {}: its centre is at {:.6g} "
                                      "and it reaches {:.4g} from there, past a bounded face of [0, {}] (walls keep the "
                                      "fluid in, not the bodies: give the walls a body repulsion range or more room)",
                                      k, names_[k], "xyz"[a], step, c, radius_[k], box_.length(a)));
    }
}

void RigidBodies::add_contacts(std::vector<Vec3>& f, std::vector<Vec3>& t, std::vector<Sym6>& st) const {
  const std::size_t nb = specs_.size();
  std::vector<Vec3> center(nb);
  for (std::size_t k = 0; k < nb; ++k) center[k] = wrapped_center(k);
  // Each surface point of body a within repulsion_range of body c (or a fixed wall) is pushed out along
  // that surface's normal by repulsion (1 - gap / range), and c takes the opposite force at the point.
  for (std::size_t a = 0; a < nb; ++a) {
    const BodySpec& s = specs_[a];
    if (s.repulsion <= 0) continue;
    const Quat& qa = state_[a].q;
    for (std::size_t c = 0; c < nb; ++c) {
      if (c == a) continue;
      const Vec3 dc = displacement(center[a], center[c]);
      const double reach = radius_[a] + radius_[c] + s.repulsion_range;
      if (dot(dc, dc) >= reach * reach) continue;
      const Quat& qc = state_[c].q;
      for (const Vec3& b : points_[a]) {
        const Vec3 arm = rotate(qa, b);
        const Vec3 d = dc + arm;  // the point relative to c's centre
        const Vec3 in_c = rotate_back(qc, d);
        const double gap = body_sdf(c, in_c);
        if (gap >= s.repulsion_range) continue;
        const Vec3 force = (s.repulsion * (1.0 - gap / s.repulsion_range)) * rotate(qc, body_normal(c, in_c));
        f[a] += force;
        t[a] += cross(arm, force);
        add_to(st[a], sym_outer(arm, force));
        f[c] += -1.0 * force;
        t[c] += cross(d, -1.0 * force);
        add_to(st[c], sym_outer(d, force), -1.0);
      }
    }
    if (walls_.empty()) continue;
    for (const Vec3& b : points_[a]) {
      const Vec3 arm = rotate(qa, b);
      const Vec3 at = center[a] + arm;
      double xyz[3] = {at.x, at.y, at.z};
      std::int32_t image[3] = {0, 0, 0};
      wrap_point(box_, xyz, image);
      const Vec3 r{xyz[0], xyz[1], xyz[2]};
      int wall = -1;
      const double gap = walls_.sdf(r, wall);
      if (gap >= s.repulsion_range || wall < 0) continue;
      const Vec3 force = (s.repulsion * (1.0 - gap / s.repulsion_range)) * walls_.normal(r, wall);
      f[a] += force;
      t[a] += cross(arm, force);
      add_to(st[a], sym_outer(arm, force));
    }
  }
}

void RigidBodies::compute_forces(const StepContext& ctx, double time) {
  const ParticleData& p = ctx.particles;
  const std::size_t nb = specs_.size();
  // Force, torque and stresslet of the pair forces on this rank's body particles, in 2^32 fixed point (the
  // sum is exact whatever the order, so it is the same on any thread or rank count).
  constexpr std::size_t kw = 12;
  std::vector<std::int64_t> sums(kw * nb, 0);
  const std::vector<std::int32_t>& slot = slots(p);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const std::int32_t n = slot[i];
    if (n < 0) continue;
    const std::size_t k = static_cast<std::size_t>(owner_[static_cast<std::size_t>(n)]);
    const Vec3 f{p.fx[i], p.fy[i], p.fz[i]};
    const Vec3 arm = rotate(state_[k].q, offset_[static_cast<std::size_t>(n)]);
    const Vec3 torque = cross(arm, f);
    const Sym6 st = sym_outer(arm, f);
    const double v[kw] = {f.x, f.y, f.z, torque.x, torque.y, torque.z, st[0], st[1], st[2], st[3], st[4], st[5]};
    for (std::size_t c = 0; c < kw; ++c) sums[kw * k + c] += wall_fixed(v[c]);
  }
  if (ctx.comm.distributed()) ctx.comm.sum(std::span<std::int64_t>(sums));
  std::vector<Vec3> f(nb), t(nb);
  std::vector<Sym6> st(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    const auto s = [&](std::size_t c) { return static_cast<double>(sums[kw * k + c]) / kWallFixedScale; };
    f[k] = {s(0), s(1), s(2)};
    t[k] = {s(3), s(4), s(5)};
    for (std::size_t c = 0; c < 6; ++c) st[k][c] = s(6 + c);
    const BodySpec& b = specs_[k];
    f[k] += Vec3{b.force[0], b.force[1], b.force[2]};
    t[k] += Vec3{b.torque[0], b.torque[1], b.torque[2]};
  }
  if (box_.sheared() && box_.shear.omega > 0.0) {
    // Oscillatory shear: the homogeneous-shear force of SLLOD (engine/install_lees_edwards.cpp) on every
    // element of the body, m (d rate/dt) (x_g - L_g/2) e_f: M (d rate/dt) (X_g - L_g/2) e_f on the
    // centre and the torque (d rate/dt) sum m a_g (a x e_f) = (d rate/dt) (M2 e_g) x e_f, with the second
    // moment M2 = sum m a (x) a = (tr I / 2) 1 - I of the body's mass about its centre.
    const int g = box_.shear.gradient;
    const double accel = -box_.shear.strain_amplitude * box_.shear.omega * box_.shear.omega * std::sin(box_.shear.omega * time);
    const Vec3 ef = axis_vector(box_.shear.flow), eg = axis_vector(g);
    for (std::size_t k = 0; k < nb; ++k) {
      const double cg = component(wrapped_center(k), g);
      f[k] += (mass_[k] * accel * (cg - 0.5 * box_.length(g))) * ef;
      const Mat3 in = inertia(k);
      const double half_trace = 0.5 * (in[0] + in[4] + in[8]);
      const Vec3 second{half_trace * eg.x - (in[0] * eg.x + in[1] * eg.y + in[2] * eg.z),
                        half_trace * eg.y - (in[3] * eg.x + in[4] * eg.y + in[5] * eg.z),
                        half_trace * eg.z - (in[6] * eg.x + in[7] * eg.y + in[8] * eg.z)};
      t[k] += accel * cross(second, ef);
    }
  }
  add_contacts(f, t, st);
  for (std::size_t k = 0; k < nb; ++k) {
    state_[k].f = f[k];
    state_[k].t = t[k];
    add_to(st[k], bounce_stresslet_[k]);
    stresslet_[k] = st[k];
  }
  forces_known_ = true;
}

void RigidBodies::place(StepContext& ctx, bool positions) {
  ParticleData& p = ctx.particles;
  const std::size_t n = p.n_local;
  std::vector<Vec3> omega(specs_.size());
  for (std::size_t k = 0; k < specs_.size(); ++k) omega[k] = omega_at(k, state_[k].q);
  const std::vector<std::int32_t>& slot = slots(p);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t at = slot[i];
    if (at < 0) continue;
    const std::size_t k = static_cast<std::size_t>(owner_[static_cast<std::size_t>(at)]);
    const BodyState& s = state_[k];
    const Vec3 arm = rotate(s.q, offset_[static_cast<std::size_t>(at)]);
    const Vec3 r = s.x + arm;
    double q[3] = {r.x, r.y, r.z};
    std::int32_t image[3] = {0, 0, 0};
    // Under shear a particle that sits across the gradient faces from the centre is the body's image
    // there: moved by the offset and moving faster by the image velocity.
    const double crossed = wrap_point(box_, q, image);
    if (positions) {
      p.x[i] = q[0];
      p.y[i] = q[1];
      p.z[i] = q[2];
      p.ix[i] = image[0];
      p.iy[i] = image[1];
      p.iz[i] = image[2];
    }
    Vec3 v = s.v + cross(omega[k], arm);
    if (crossed != 0.0) component(v, box_.shear.flow) -= crossed * box_.shear.velocity;
    p.vx[i] = p.hx[i] = v.x;
    p.vy[i] = p.hy[i] = v.y;
    p.vz[i] = p.hz[i] = v.z;
  }
}

namespace {

// One fluid particle found inside a body after its move (already mirrored out): what the collision needs.
struct Hit {
  std::uint32_t id = 0;
  std::int32_t body = 0;
  std::int32_t rank = 0;
  std::uint32_t index = 0;  // local index on its rank
  double mass = 0;
  Vec3 arm, normal, velocity;  // surface point from the centre, outward normal (lab), physical velocity
};

}  // namespace

void RigidBodies::bounce(StepContext& ctx) {
  ParticleData& p = ctx.particles;
  const std::size_t nb = specs_.size(), n = p.n_local;
  std::vector<Vec3> center(nb), omega(nb);
  double widest = 0;
  for (std::size_t k = 0; k < nb; ++k) {
    center[k] = wrapped_center(k);
    omega[k] = omega_at(k, state_[k].q);
    widest = std::max(widest, radius_[k]);
  }
  // A coarse grid of the bodies' bounding spheres (cells at least as wide as the widest radius), so that
  // a particle looks only at the bodies whose spheres reach its cell.
  std::array<int, 3> cells{};
  std::array<double, 3> width{};
  for (int a = 0; a < 3; ++a) {
    cells[static_cast<std::size_t>(a)] = std::max(1, std::min(64, static_cast<int>(box_.length(a) / widest)));
    width[static_cast<std::size_t>(a)] = box_.length(a) / cells[static_cast<std::size_t>(a)];
  }
  std::vector<std::vector<std::uint32_t>> grid(static_cast<std::size_t>(cells[0] * cells[1] * cells[2]));
  for (std::size_t k = 0; k < nb; ++k) {
    std::array<std::vector<int>, 3> span;
    const double c[3] = {center[k].x, center[k].y, center[k].z};
    // Under shear the image across the gradient faces is shifted along the flow axis: a body whose sphere
    // reaches those faces is listed along the whole flow axis there.
    const bool across = box_.sheared() && (c[box_.shear.gradient] - radius_[k] < 0.0 ||
                                           c[box_.shear.gradient] + radius_[k] >= box_.length(box_.shear.gradient));
    for (int a = 0; a < 3; ++a) {
      auto& list = span[static_cast<std::size_t>(a)];
      const int na = cells[static_cast<std::size_t>(a)];
      int lo = static_cast<int>(std::floor((c[a] - radius_[k]) / width[static_cast<std::size_t>(a)]));
      int hi = static_cast<int>(std::floor((c[a] + radius_[k]) / width[static_cast<std::size_t>(a)]));
      if (across && a == box_.shear.flow) lo = 0, hi = na - 1;
      for (int j = lo; j <= hi && static_cast<int>(list.size()) < na; ++j) {
        const int w = box_.periodic[static_cast<std::size_t>(a)] ? ((j % na) + na) % na : std::clamp(j, 0, na - 1);
        if (std::find(list.begin(), list.end(), w) == list.end()) list.push_back(w);
      }
    }
    for (int z : span[2])
      for (int y : span[1])
        for (int x : span[0]) grid[static_cast<std::size_t>((z * cells[1] + y) * cells[0] + x)].push_back(static_cast<std::uint32_t>(k));
  }
  // 1. In parallel: every mobile particle inside a body is mirrored out through the surface (in the body
  //    frame, stepping further out along the normal where the mirror image is still inside: a concave
  //    corner), and noted with its surface point for the collision.
  const int threads = omp_get_max_threads();
  std::vector<std::vector<Hit>> found(static_cast<std::size_t>(threads));
  double* vel[3] = {half_velocity_ ? p.hx.data() : p.vx.data(), half_velocity_ ? p.hy.data() : p.vy.data(),
                    half_velocity_ ? p.hz.data() : p.vz.data()};
  const int shear_flow = box_.shear.flow;
#pragma omp parallel
  {
    std::vector<Hit>& mine = found[static_cast<std::size_t>(omp_get_thread_num())];
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (p.body[i] != 0 || frozen_[static_cast<std::size_t>(p.species[i])]) continue;
      const double xyz[3] = {p.x[i], p.y[i], p.z[i]};
      int cell[3];
      for (int a = 0; a < 3; ++a)
        cell[a] = std::clamp(static_cast<int>(xyz[a] / width[static_cast<std::size_t>(a)]), 0, cells[static_cast<std::size_t>(a)] - 1);
      for (std::uint32_t k : grid[static_cast<std::size_t>((cell[2] * cells[1] + cell[1]) * cells[0] + cell[0])]) {
        double image = 0;
        const Vec3 d = displacement(Vec3{xyz[0], xyz[1], xyz[2]}, center[k], &image);
        if (dot(d, d) >= radius_[k] * radius_[k]) continue;
        const Quat& q = state_[k].q;
        const Vec3 b = rotate_back(q, d);
        const double depth = body_sdf(k, b);
        if (!(depth < 0)) continue;
        const Vec3 nrm = body_normal(k, b);
        // Moving in relative to the surface (u . n < 0): back along its relative path by twice the time
        // since it crossed, tau = depth / |u . n| (at most dt), as bounce-back retraces it; otherwise (the
        // body came onto it) mirrored through the surface.
        // The particle's velocity in the frame of the body's image it is in (Lees-Edwards: -image dU e_f).
        Vec3 h_now{vel[0][i], vel[1][i], vel[2][i]};
        if (image != 0.0) component(h_now, shear_flow) -= image * box_.shear.velocity;
        const Vec3 u = rotate_back(q, h_now - (state_[k].v + cross(omega[k], rotate(q, b))));
        const double un = dot(u, nrm);
        Vec3 out = b - 2.0 * depth * nrm;
        if (un < 0) out = b - (2.0 * std::min(ctx.dt, depth / un)) * u;
        for (int tries = 0; tries < 8; ++tries) {
          const double d2 = body_sdf(k, out);
          if (d2 >= 0) break;
          out = out + (-d2 + 1e-9) * body_normal(k, out);
        }
        const Vec3 shift = rotate(q, out - b);
        double pos[3] = {p.x[i] + shift.x, p.y[i] + shift.y, p.z[i] + shift.z};
        std::int32_t img[3] = {p.ix[i], p.iy[i], p.iz[i]};
        const double crossed = wrap_point(box_, pos, img);
        p.x[i] = pos[0], p.y[i] = pos[1], p.z[i] = pos[2];
        p.ix[i] = img[0], p.iy[i] = img[1], p.iz[i] = img[2];
        if (crossed != 0.0) {  // out through a sheared face: the image velocity, as the engine's wrap
          (shear_flow == 0 ? p.vx : shear_flow == 1 ? p.vy : p.vz)[i] -= crossed * box_.shear.velocity;
          if (p.hx.size() >= n) (shear_flow == 0 ? p.hx : shear_flow == 1 ? p.hy : p.hz)[i] -= crossed * box_.shear.velocity;
        }
        Hit h;
        h.id = p.id[i];
        h.body = static_cast<std::int32_t>(k);
        h.rank = ctx.comm.rank();
        h.index = static_cast<std::uint32_t>(i);
        h.mass = species_mass_[static_cast<std::size_t>(p.species[i])];
        h.arm = rotate(q, b - depth * nrm);
        h.normal = rotate(q, nrm);
        h.velocity = h_now;
        mine.push_back(h);
        break;  // one body per particle and step
      }
    }
  }
  std::vector<Hit> hits;
  for (const auto& f : found) hits.insert(hits.end(), f.begin(), f.end());
  // 2. Every rank sees every collision (they are few: those of the particles that got in this step).
  if (ctx.comm.distributed()) {
    std::vector<std::byte> bytes(hits.size() * sizeof(Hit));
    if (!hits.empty()) std::memcpy(bytes.data(), hits.data(), bytes.size());
    std::vector<std::byte> all = ctx.comm.gather(bytes);
    ctx.comm.broadcast(all);
    hits.resize(all.size() / sizeof(Hit));
    if (!hits.empty()) std::memcpy(hits.data(), all.data(), hits.size() * sizeof(Hit));
  }
  std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.body != b.body ? a.body < b.body : a.id < b.id; });
  bounces_ += hits.size();  // all ranks' (the same count on every rank)
  // 3. The collisions one after another, body by body in particle-id order (the same sequence on every
  //    rank and thread count): where the particle moves into the body relative to the surface point's
  //    velocity u = v - (V + Omega x a), the impulse J on it reverses that relative velocity with both
  //    moving, (1/m + K) J = -2 u, K J = J / M + (I^-1 (a x J)) x a the body's mobility at the point (0
  //    for a towed body): the pair's momentum, angular momentum and energy are kept. The body's V and L
  //    change before the next collision; taking them all from the same V would heat a light body (the
  //    kicks of one step pile up on it: measured +15% at M = 14, dt = 0.02).
  std::vector<Vec3> impulse(nb), turn(nb);
  bounce_stresslet_.assign(nb, Sym6{});
  std::vector<Mat3> inverse_inertia(nb);  // lab frame; the orientations do not change here
  std::vector<std::uint8_t> known(nb, 0);
  for (const Hit& h : hits) {
    const std::size_t k = static_cast<std::size_t>(h.body);
    BodyState& s = state_[k];
    const bool free = specs_[k].motion == BodyMotion::Free;
    const Vec3 w = omega_at(k, s.q);
    const Vec3 u = h.velocity - (s.v + cross(w, h.arm));
    if (!(dot(u, h.normal) < 0)) continue;
    Vec3 j = -2.0 * h.mass * u;
    if (free) {
      if (!known[k]) inverse_inertia[k] = inverse(inertia(k)), known[k] = 1;
      const Mat3& inv = inverse_inertia[k];
      Mat3 a{};
      for (int c = 0; c < 3; ++c) {
        const Vec3 e = axis_vector(c);
        const Vec3 col = (1.0 / h.mass + 1.0 / mass_[k]) * e + cross(times(inv, cross(h.arm, e)), h.arm);
        a[static_cast<std::size_t>(c)] = col.x;
        a[static_cast<std::size_t>(3 + c)] = col.y;
        a[static_cast<std::size_t>(6 + c)] = col.z;
      }
      j = times(inverse(a), -2.0 * u);
      s.v += (-1.0 / mass_[k]) * j;
      s.l += cross(h.arm, -1.0 * j);
    }
    impulse[k] += -1.0 * j;
    turn[k] += cross(h.arm, -1.0 * j);
    add_to(bounce_stresslet_[k], sym_outer(h.arm, j), -1.0 / ctx.dt);
    if (h.rank != ctx.comm.rank()) continue;
    const Vec3 dv = (1.0 / h.mass) * j;
    vel[0][h.index] += dv.x;
    vel[1][h.index] += dv.y;
    vel[2][h.index] += dv.z;
    if (half_velocity_) {  // the predicted velocity keeps its offset from the physical one
      p.vx[h.index] += dv.x;
      p.vy[h.index] += dv.y;
      p.vz[h.index] += dv.z;
    }
  }
  for (std::size_t k = 0; k < nb; ++k) {
    state_[k].f_bounce = (1.0 / ctx.dt) * impulse[k];
    state_[k].t_bounce = (1.0 / ctx.dt) * turn[k];
  }
}

void RigidBodies::move(StepContext& ctx) {
  if (!ready_)
    throw ConfigError("[[body]]: the restart's checkpoint carries no rigid-body state (it was written by a run without "
                      "[[body]] blocks); start a new run instead");
  if (!forces_known_) compute_forces(ctx, static_cast<double>(ctx.step - 1) * ctx.dt);  // a new run's initial forces
  const double dt = ctx.dt;
  for (std::size_t k = 0; k < specs_.size(); ++k) {
    BodyState& s = state_[k];
    const BodySpec& b = specs_[k];
    if (b.motion == BodyMotion::Free) {
      s.v += (0.5 * dt / mass_[k]) * s.f;
      s.l += (0.5 * dt) * s.t;
      s.q = turn_free(s.q, s.l, inertia_inverse_[k], dt);
    } else {
      s.v = {b.velocity[0], b.velocity[1], b.velocity[2]};
      s.q = turned(s.q, omega_at(k, s.q), dt);
    }
    s.x += dt * s.v;
    if (box_.sheared()) {
      // Across the sheared faces the centre comes back at the other face, moved by the image offset and
      // slowed by the image velocity along the flow axis, as a fluid particle does (so X_g stays in the
      // box; the other coordinates stay unwrapped).
      std::int32_t image = 0;
      const double k = wrap_sheared_gradient(box_, component(s.x, box_.shear.gradient), image, component(s.x, box_.shear.flow));
      component(s.v, box_.shear.flow) -= k * box_.shear.velocity;
    }
  }
  check_box(ctx.step);
  bounce(ctx);
  place(ctx, true);
}

void RigidBodies::kick(StepContext& ctx) {
  compute_forces(ctx, static_cast<double>(ctx.step) * ctx.dt);
  const double dt = ctx.dt;
  const std::size_t nb = specs_.size();
  for (std::size_t k = 0; k < nb; ++k) {
    if (specs_[k].motion != BodyMotion::Free) continue;
    state_[k].v += (0.5 * dt / mass_[k]) * state_[k].f;
    state_[k].l += (0.5 * dt) * state_[k].t;
  }
  place(ctx, false);
  for (std::size_t k = 0; k < nb; ++k) {
    const std::uint64_t every = specs_[k].output_every;
    if (every > 0 && (ctx.step - 1) % every == 0) {  // the previous row's interval is over
      stresslet_sum_[k] = Sym6{};
      stresslet_steps_[k] = 0;
    }
    add_to(stresslet_sum_[k], stresslet_[k]);
    ++stresslet_steps_[k];
  }
  if (!ctx.pair_sums) return;
  // The molecular virial of the bodies (see stresslet()): the same on every rank, as the pair sums are.
  const int f = box_.shear.flow, g = box_.shear.gradient;
  for (std::size_t k = 0; k < nb; ++k) {
    Vec3 u = state_[k].v;
    if (box_.sheared())
      component(u, f) -= box_.shear.current_rate * (component(wrapped_center(k), g) - 0.5 * box_.length(g));
    Sym6 w = sym_outer(u, u);
    for (double& x : w) x *= mass_[k];
    add_to(w, stresslet_[k], -1.0);
    for (std::size_t q = 0; q < 6; ++q) ctx.pair_sums->virial[q] += w[q];
  }
}

std::uint64_t RigidBodies::inside(const StepContext& ctx) const {
  const ParticleData& p = ctx.particles;
  std::vector<Vec3> center(specs_.size());
  for (std::size_t k = 0; k < specs_.size(); ++k) center[k] = wrapped_center(k);
  std::uint64_t count = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (p.body[i] != 0 || frozen_[static_cast<std::size_t>(p.species[i])]) continue;
    const Vec3 r{p.x[i], p.y[i], p.z[i]};
    for (std::size_t k = 0; k < specs_.size(); ++k) {
      const Vec3 d = displacement(r, center[k]);
      if (dot(d, d) < radius_[k] * radius_[k] && body_sdf(k, rotate_back(state_[k].q, d)) < 0) {
        ++count;
        break;
      }
    }
  }
  std::uint64_t total[1] = {count};
  if (ctx.comm.distributed()) ctx.comm.sum(std::span<std::uint64_t>(total, 1));
  return total[0];
}

void RigidBodies::save(ByteWriter& w) const {
  w.put<std::uint64_t>(specs_.size());
  for (const BodyState& s : state_) {
    const double v[19] = {s.x.x, s.x.y, s.x.z, s.q.w, s.q.x, s.q.y, s.q.z, s.v.x, s.v.y, s.v.z,
                          s.l.x, s.l.y, s.l.z, s.f.x, s.f.y, s.f.z, s.t.x, s.t.y, s.t.z};
    for (double x : v) w.put(x);
  }
  w.put<std::uint8_t>(forces_known_ ? 1 : 0);
  w.put_vector(ids_);
  w.put_vector(owner_);
  std::vector<double> off;
  for (const Vec3& b : offset_) off.insert(off.end(), {b.x, b.y, b.z});
  w.put_vector(off);
  std::vector<double> sums;
  for (const Sym6& x : stresslet_sum_) sums.insert(sums.end(), x.begin(), x.end());
  w.put_vector(sums);
  w.put_vector(stresslet_steps_);
  w.put<std::uint64_t>(bounces_);
  w.put<std::uint64_t>(bounces_at_row_);
}

void RigidBodies::load(ByteReader& r, const std::string& context) {
  const auto n = r.get<std::uint64_t>();
  if (n != specs_.size())
    throw ConfigError(fmt::format("{}: the checkpoint has {} rigid bodies, the config {} [[body]] blocks", context, n, specs_.size()));
  for (BodyState& s : state_) {
    double v[19];
    for (double& x : v) x = r.get<double>();
    s.x = {v[0], v[1], v[2]};
    s.q = {v[3], v[4], v[5], v[6]};
    s.v = {v[7], v[8], v[9]};
    s.l = {v[10], v[11], v[12]};
    s.f = {v[13], v[14], v[15]};
    s.t = {v[16], v[17], v[18]};
  }
  forces_known_ = r.get<std::uint8_t>() != 0;
  ids_ = r.get_vector<std::uint32_t>();
  owner_ = r.get_vector<std::int32_t>();
  const std::vector<double> off = r.get_vector<double>();
  if (owner_.size() != ids_.size() || off.size() != 3 * ids_.size())
    throw ConfigError(context + ": the rigid bodies' particle table is inconsistent");
  offset_.clear();
  for (std::size_t k = 0; k < ids_.size(); ++k) {
    if (owner_[k] < 0 || static_cast<std::size_t>(owner_[k]) >= specs_.size())
      throw ConfigError(context + ": a rigid-body particle names a body that does not exist");
    offset_.push_back({off[3 * k], off[3 * k + 1], off[3 * k + 2]});
  }
  const std::vector<double> sums = r.get_vector<double>();
  stresslet_steps_ = r.get_vector<std::uint64_t>();
  if (sums.size() != 6 * specs_.size() || stresslet_steps_.size() != specs_.size())
    throw ConfigError(context + ": the rigid bodies' stresslet sums are inconsistent");
  bounces_ = r.get<std::uint64_t>();
  bounces_at_row_ = r.get<std::uint64_t>();
  bounces_at_start_ = bounces_;
  for (std::size_t k = 0; k < specs_.size(); ++k)
    for (std::size_t q = 0; q < 6; ++q) stresslet_sum_[k][q] = sums[6 * k + q];
  index_points();
  ready_ = true;
}

}  // namespace mesodpd
