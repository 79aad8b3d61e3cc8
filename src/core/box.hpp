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

// Nearest periodic image of a displacement. Every backend computes pair displacements this way from
// wrapped coordinates, so a pair's geometry has the same rounding whichever particle (or rank) finds it.
MESODPD_HD double minimum_image(double d, double len, double inv_len) { return d - len * std::nearbyint(d * inv_len); }

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
