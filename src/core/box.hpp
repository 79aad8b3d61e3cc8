// Orthorhombic simulation box, periodic or bounded per axis: wrapping with image counters and the
// minimum-image displacement.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/hd.hpp"
#include "core/vec3.hpp"

namespace mesodpd {

struct Box {
  Vec3 len{10, 10, 10};  // edge lengths; the box spans [0, len) in each direction
  // Per axis: periodic (particles leaving at one face come back at the other) or bounded (nothing
  // crosses the face; a particle found outside [0, len) is lost).
  std::array<bool, 3> periodic{true, true, true};

  double volume() const { return len.x * len.y * len.z; }
  double length(int d) const { return d == 0 ? len.x : (d == 1 ? len.y : len.z); }
  // The period of axis d and half of it, as minimum_image() takes them: the box length on a periodic
  // axis, +infinity on a bounded one, where minimum_image() then returns the displacement unchanged
  // without a branch.
  double image_len(int d) const {
    return periodic[static_cast<std::size_t>(d)] ? length(d) : std::numeric_limits<double>::infinity();
  }
  double half_image_len(int d) const {
    return periodic[static_cast<std::size_t>(d)] ? 0.5 * length(d) : std::numeric_limits<double>::infinity();
  }
  bool all_periodic() const { return periodic[0] && periodic[1] && periodic[2]; }
};

// Nearest periodic image of the displacement between two wrapped coordinates (|d| < len); with len =
// half_len = +infinity (a bounded axis, Box::image_len) d itself. Every backend
// computes pair displacements this way, so a pair's geometry has the same rounding whichever particle
// (or rank) finds it, and minimum_image(-d) == -minimum_image(d) exactly. Written as selects rather than
// rounding so that it vectorises and needs no SSE4.1 round instruction.
MESODPD_HD double minimum_image(double d, double len, double half_len) {
  d = d > half_len ? d - len : d;
  d = d < -half_len ? d + len : d;
  return d;
}

// Wrap one coordinate into [0, len), counting box crossings in `image`.
MESODPD_HD void wrap_coordinate(double& x, std::int32_t& image, double len) {
  if (x >= len || x < 0.0) {
    const double shift = std::floor(x / len);
    x -= shift * len;
    image += static_cast<std::int32_t>(shift);
    if (x >= len) x -= len;  // rounding can leave x == len
    if (x < 0.0) x = 0.0;
  }
}

}  // namespace mesodpd
