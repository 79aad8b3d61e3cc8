// Periodic orthorhombic simulation box: wrapping with image counters and the minimum-image displacement.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/hd.hpp"
#include "core/vec3.hpp"

namespace mesodpd {

struct Box {
  Vec3 len{10, 10, 10};  // edge lengths; the box spans [0, len) in each direction

  double volume() const { return len.x * len.y * len.z; }
};

// Nearest periodic image of the displacement between two wrapped coordinates (|d| < len). Every backend
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
