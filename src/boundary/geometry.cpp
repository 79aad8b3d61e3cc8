// Signed distances of the solid primitives and their combinations.
#include "boundary/geometry.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "boundary/voxel_image.hpp"

namespace mesodpd {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
Vec3 unit(Vec3 a) {
  const double l = norm(a);
  return l > 0 ? (1.0 / l) * a : Vec3{0, 0, 0};
}
Vec3 vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
double comp(const Vec3& v, int d) { return d == 0 ? v.x : (d == 1 ? v.y : v.z); }

// p - c at the nearest periodic image along the box's periodic axes.
Vec3 image_offset(const Vec3& p, const Vec3& c, const Box& box) {
  return {minimum_image(p.x - c.x, box.image_len(0), box.half_image_len(0)),
          minimum_image(p.y - c.y, box.image_len(1), box.half_image_len(1)),
          minimum_image(p.z - c.z, box.image_len(2), box.half_image_len(2))};
}

// Half space behind a plane: d = (p - point) . n, n pointing into the fluid.
class PlaneShape final : public Shape {
 public:
  PlaneShape(Vec3 point, Vec3 normal) : point_(point), n_(unit(normal)) {}
  double sdf(const Vec3& p) const override { return dot(p - point_, n_); }
  Vec3 normal(const Vec3&) const override { return n_; }

 private:
  Vec3 point_, n_;
};

// Infinite circular cylinder: distance from the axis minus the radius.
class CylinderShape final : public Shape {
 public:
  CylinderShape(Vec3 c, Vec3 dir, double r, const Box& box) : c_(c), u_(unit(dir)), r_(r), box_(box) {}
  double sdf(const Vec3& p) const override { return norm(radial(p)) - r_; }
  Vec3 normal(const Vec3& p) const override { return unit(radial(p)); }

 private:
  Vec3 radial(const Vec3& p) const {
    const Vec3 d = image_offset(p, c_, box_);
    return d - dot(d, u_) * u_;
  }
  Vec3 c_, u_;
  double r_;
  Box box_;
};

class SphereShape final : public Shape {
 public:
  SphereShape(Vec3 c, double r, const Box& box) : c_(c), r_(r), box_(box) {}
  double sdf(const Vec3& p) const override { return norm(image_offset(p, c_, box_)) - r_; }
  Vec3 normal(const Vec3& p) const override { return unit(image_offset(p, c_, box_)); }

 private:
  Vec3 c_;
  double r_;
  Box box_;
};

// Axis-aligned box [lo, hi]: the usual exact distance (outside: to the nearest point of the box;
// inside: minus the distance to the nearest face).
class BoxShape final : public Shape {
 public:
  BoxShape(Vec3 lo, Vec3 hi, const Box& box)
      : c_(0.5 * (lo + hi)), half_(0.5 * (hi - lo)), box_(box) {}
  double sdf(const Vec3& p) const override {
    const Vec3 d = image_offset(p, c_, box_);
    const Vec3 q{std::abs(d.x) - half_.x, std::abs(d.y) - half_.y, std::abs(d.z) - half_.z};
    const Vec3 out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
    return norm(out) + std::min(std::max({q.x, q.y, q.z}), 0.0);
  }

 private:
  Vec3 c_, half_;
  Box box_;
};

// Infinite parallel pillars of radius r along `axis`, centred on a square lattice of spacing L or a
// hexagonal one (rows of spacing L along the first in-plane axis, rows L sqrt(3)/2 apart along the
// second, alternate rows shifted by L/2; seed 004 Figs 2-3), through `origin`.
class PillarShape final : public Shape {
 public:
  PillarShape(Vec3 origin, int axis, double r, double spacing, Lattice lattice)
      : o_(origin), axis_(axis), r_(r), l_(spacing), hex_(lattice == Lattice::Hexagonal) {
    a0_ = axis == 0 ? 1 : 0;
    a1_ = axis == 2 ? 1 : 2;
  }
  double sdf(const Vec3& p) const override {
    double u, v;
    return nearest(p, u, v) - r_;
  }
  Vec3 normal(const Vec3& p) const override {
    double u, v;
    const double d = nearest(p, u, v);
    if (d == 0) return {0, 0, 0};
    double n[3] = {0, 0, 0};
    n[a0_] = u / d;
    n[a1_] = v / d;
    return {n[0], n[1], n[2]};
  }

 private:
  // Distance in the plane to the nearest pillar axis; (u, v) the offset from it.
  double nearest(const Vec3& p, double& u, double& v) const {
    const double x = comp(p, a0_) - comp(o_, a0_), y = comp(p, a1_) - comp(o_, a1_);
    if (!hex_) {
      u = x - l_ * std::round(x / l_);
      v = y - l_ * std::round(y / l_);
      return std::hypot(u, v);
    }
    // Two rectangular sublattices of period (L, L sqrt 3), the second shifted by (L/2, L sqrt(3)/2).
    const double py = l_ * std::sqrt(3.0);
    const double u1 = x - l_ * std::round(x / l_), v1 = y - py * std::round(y / py);
    const double x2 = x - 0.5 * l_, y2 = y - 0.5 * py;
    const double u2 = x2 - l_ * std::round(x2 / l_), v2 = y2 - py * std::round(y2 / py);
    const double d1 = std::hypot(u1, v1), d2 = std::hypot(u2, v2);
    if (d1 <= d2) {
      u = u1, v = v1;
      return d1;
    }
    u = u2, v = v2;
    return d2;
  }
  Vec3 o_;
  int axis_, a0_, a1_;
  double r_, l_;
  bool hex_;
};

double largest_lipschitz(const std::vector<std::unique_ptr<Shape>>& parts) {
  double l = 1.0;
  for (const auto& s : parts)
    if (s) l = std::max(l, s->lipschitz());
  return l;
}

class UnionShape final : public Shape {
 public:
  explicit UnionShape(std::vector<std::unique_ptr<Shape>> parts) : parts_(std::move(parts)) {}
  double sdf(const Vec3& p) const override {
    double d = kInf;
    for (const auto& s : parts_) d = std::min(d, s->sdf(p));
    return d;
  }
  double lipschitz() const override { return largest_lipschitz(parts_); }
  Vec3 normal(const Vec3& p) const override {
    std::size_t best = 0;
    double d = kInf;
    for (std::size_t k = 0; k < parts_.size(); ++k)
      if (const double dk = parts_[k]->sdf(p); dk < d) d = dk, best = k;
    return parts_[best]->normal(p);
  }

 private:
  std::vector<std::unique_ptr<Shape>> parts_;
};

// The first part minus the others: max(d_0, -d_1, -d_2, ...), a bound on the distance with the exact
// sign; the normal is the one of the part that decides.
class DifferenceShape final : public Shape {
 public:
  explicit DifferenceShape(std::vector<std::unique_ptr<Shape>> parts) : parts_(std::move(parts)) {}
  double sdf(const Vec3& p) const override {
    double d = parts_[0]->sdf(p);
    for (std::size_t k = 1; k < parts_.size(); ++k) d = std::max(d, -parts_[k]->sdf(p));
    return d;
  }
  double lipschitz() const override { return largest_lipschitz(parts_); }
  Vec3 normal(const Vec3& p) const override {
    double d = parts_[0]->sdf(p);
    std::size_t best = 0;
    for (std::size_t k = 1; k < parts_.size(); ++k)
      if (const double dk = -parts_[k]->sdf(p); dk > d) d = dk, best = k;
    return best == 0 ? parts_[0]->normal(p) : -parts_[best]->normal(p);
  }

 private:
  std::vector<std::unique_ptr<Shape>> parts_;
};

}  // namespace

double Geometry::lipschitz() const {
  return largest_lipschitz(shapes_);
}

Vec3 Shape::normal(const Vec3& p) const {
  constexpr double h = 1e-5;
  const Vec3 g{sdf(p + Vec3{h, 0, 0}) - sdf(p - Vec3{h, 0, 0}), sdf(p + Vec3{0, h, 0}) - sdf(p - Vec3{0, h, 0}),
               sdf(p + Vec3{0, 0, h}) - sdf(p - Vec3{0, 0, h})};
  return unit(g);
}

std::unique_ptr<Shape> make_shape(const ShapeSpec& s, const Box& box, const std::string& key) {
  switch (s.kind) {
    case ShapeKind::Plane:
      return std::make_unique<PlaneShape>(vec(s.point), vec(s.normal));
    case ShapeKind::Cylinder:
      return std::make_unique<CylinderShape>(vec(s.center), vec(s.direction), s.radius, box);
    case ShapeKind::Sphere:
      return std::make_unique<SphereShape>(vec(s.center), s.radius, box);
    case ShapeKind::Box:
      return std::make_unique<BoxShape>(vec(s.lo), vec(s.hi), box);
    case ShapeKind::Pillars:
      return std::make_unique<PillarShape>(vec(s.point), s.axis, s.radius, s.spacing, s.lattice);
    case ShapeKind::Image:
      return std::make_unique<ImageShape>(load_image(s, box, key), box);
    case ShapeKind::Union:
    case ShapeKind::Difference: {
      std::vector<std::unique_ptr<Shape>> parts;
      for (std::size_t k = 0; k < s.parts.size(); ++k)
        parts.push_back(make_shape(s.parts[k], box, fmt::format("{}.parts[{}]", key, k)));
      if (parts.empty()) throw ConfigError(fmt::format("{}.parts: at least one part is needed", key));
      if (s.kind == ShapeKind::Union) return std::make_unique<UnionShape>(std::move(parts));
      return std::make_unique<DifferenceShape>(std::move(parts));
    }
  }
  throw ConfigError(fmt::format("{}.shape: unknown shape", key));
}

Geometry::Geometry(const std::vector<SolidSpec>& solids, const Box& box, const std::vector<std::uint8_t>& released) {
  for (std::size_t k = 0; k < solids.size(); ++k)
    shapes_.push_back(k < released.size() && released[k] ? nullptr
                                                          : make_shape(solids[k].shape, box, fmt::format("solid[{}]", k)));
  std::size_t live = 0;
  for (const auto& s : shapes_) live += s ? 1 : 0;
  if (live < 8) return;  // few solids: the plain loop is as fast
  // Cells about 2 wide (at most 32 per axis). A solid k with distance d_k at a cell's centre and
  // Lipschitz constant l_k lies within d_k +- l_k h anywhere in the cell (h the half diagonal); the
  // solids whose lower end is below the smallest upper end are the only ones that can be nearest there.
  // The ends are widened by 1e-9 (and relatively), far beyond rounding, so no candidate is lost to it.
  double half_diagonal = 0;
  for (int a = 0; a < 3; ++a) {
    const double len = box.length(a);
    const int n = std::clamp(static_cast<int>(len / 2.0), 1, 32);
    cells_[static_cast<std::size_t>(a)] = n;
    length_[static_cast<std::size_t>(a)] = len;
    inverse_width_[static_cast<std::size_t>(a)] = n / len;
    half_diagonal += 0.25 * (len / n) * (len / n);
  }
  half_diagonal = std::sqrt(half_diagonal);
  const std::size_t ncell = static_cast<std::size_t>(cells_[0]) * static_cast<std::size_t>(cells_[1]) *
                            static_cast<std::size_t>(cells_[2]);
  std::vector<std::vector<std::uint32_t>> lists(ncell);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < ncell; ++c) {
    const std::size_t ix = c % static_cast<std::size_t>(cells_[0]);
    const std::size_t iy = (c / static_cast<std::size_t>(cells_[0])) % static_cast<std::size_t>(cells_[1]);
    const std::size_t iz = c / (static_cast<std::size_t>(cells_[0]) * static_cast<std::size_t>(cells_[1]));
    const Vec3 centre{(static_cast<double>(ix) + 0.5) / inverse_width_[0], (static_cast<double>(iy) + 0.5) / inverse_width_[1],
                      (static_cast<double>(iz) + 0.5) / inverse_width_[2]};
    std::vector<double> lo(shapes_.size(), kInf);
    double upper = kInf;
    for (std::size_t k = 0; k < shapes_.size(); ++k) {
      if (!shapes_[k]) continue;
      const double d = shapes_[k]->sdf(centre), slack = shapes_[k]->lipschitz() * half_diagonal;
      const double margin = 1e-9 * (1.0 + std::abs(d) + slack);
      lo[k] = d - slack - margin;
      upper = std::min(upper, d + slack + margin);
    }
    for (std::size_t k = 0; k < shapes_.size(); ++k)
      if (shapes_[k] && lo[k] <= upper) lists[c].push_back(static_cast<std::uint32_t>(k));
  }
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] = cell_start_[c] + static_cast<std::uint32_t>(lists[c].size());
  cell_solids_.reserve(cell_start_[ncell]);
  for (const auto& l : lists) cell_solids_.insert(cell_solids_.end(), l.begin(), l.end());
}

double Geometry::sdf(const Vec3& p, int& body) const {
  double d = kInf;
  body = -1;
  if (!cell_start_.empty()) {
    const double q[3] = {p.x, p.y, p.z};
    bool inside = true;
    std::size_t cell = 0;
    for (int a = 2; a >= 0; --a) {
      const std::size_t u = static_cast<std::size_t>(a);
      inside = inside && q[a] >= 0.0 && q[a] < length_[u];
      const int i = inside ? std::min(static_cast<int>(q[a] * inverse_width_[u]), cells_[u] - 1) : 0;
      cell = cell * static_cast<std::size_t>(cells_[u]) + static_cast<std::size_t>(i);
    }
    if (inside) {
      // The candidates in increasing solid index, as the full loop visits them: the same minimum and
      // the same solid on a tie.
      for (std::uint32_t n = cell_start_[cell]; n < cell_start_[cell + 1]; ++n) {
        const std::size_t k = cell_solids_[n];
        if (const double dk = shapes_[k]->sdf(p); dk < d) d = dk, body = static_cast<int>(k);
      }
      return d;
    }
  }
  for (std::size_t k = 0; k < shapes_.size(); ++k)
    if (shapes_[k])
      if (const double dk = shapes_[k]->sdf(p); dk < d) d = dk, body = static_cast<int>(k);
  return d;
}

}  // namespace mesodpd
