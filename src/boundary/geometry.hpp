// Solids as signed distances (negative inside the solid, positive in the fluid): planes, cylinders,
// spheres, boxes, periodic pillar arrays, voxel images ("shadow grid", seed 000 Sect. 3.2.2), their
// unions and differences. Frozen walls, reflections and the drag use them through Geometry.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/vec3.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// One shape. sdf() is the signed distance to its surface (exact for the primitives; for differences
// and images a close estimate with the right sign); normal() the unit vector pointing out of the solid
// into the fluid at the nearest surface.
class Shape {
 public:
  virtual ~Shape() = default;
  virtual double sdf(const Vec3& p) const = 0;
  // Default: the central-difference gradient of sdf(), normalised.
  virtual Vec3 normal(const Vec3& p) const;
  // How much sdf() can change per unit length: 1 for exact distances and for the minima and maxima of
  // such (unions, differences, periodic images, lattices); more for an interpolated image.
  virtual double lipschitz() const { return 1.0; }
};

// Builds a shape for a box (its lengths and periodic axes: spheres, cylinders and boxes are taken at
// their nearest periodic image, pillar lattices and images repeat with the box). Image files are read
// here; a bad file or one whose size does not match the box throws ConfigError naming `key` and the
// file.
std::unique_ptr<Shape> make_shape(const ShapeSpec& spec, const Box& box, const std::string& key);

// All solids of a run: body k is [[solid]] k.
class Geometry {
 public:
  Geometry() = default;
  // `released[k]` != 0 leaves solid k out (a solid another model moves, engine/rigid_bodies.hpp): its
  // index stays, but sdf() never returns it. Empty: every solid.
  Geometry(const std::vector<SolidSpec>& solids, const Box& box, const std::vector<std::uint8_t>& released = {});
  // No solid to act on (none, or every one released).
  bool empty() const {
    for (const auto& s : shapes_)
      if (s) return false;
    return true;
  }
  std::size_t bodies() const { return shapes_.size(); }
  // Signed distance to the nearest solid (+infinity without solids); `body` gets its index.
  double sdf(const Vec3& p) const {
    int body;
    return sdf(p, body);
  }
  double sdf(const Vec3& p, int& body) const;
  // Outward normal of body k at p.
  Vec3 normal(const Vec3& p, int body) const { return shapes_[static_cast<std::size_t>(body)]->normal(p); }
  const Shape& shape(std::size_t k) const { return *shapes_[k]; }  // not for a released solid
  bool released(std::size_t k) const { return !shapes_[k]; }
  // The largest Shape::lipschitz() of the solids (1 without any).
  double lipschitz() const;

 private:
  std::vector<std::unique_ptr<Shape>> shapes_;  // null for a released solid
  // With many solids, a grid over the box whose cells list the solids that can be the nearest anywhere
  // in the cell (from each solid's distance at the cell centre and its Lipschitz bound), so that sdf()
  // evaluates those only; the minimum and the solid that attains it are the same as over all solids.
  std::array<int, 3> cells_{0, 0, 0};
  std::array<double, 3> inverse_width_{0, 0, 0}, length_{0, 0, 0};
  std::vector<std::uint32_t> cell_start_, cell_solids_;
};

}  // namespace mesodpd
