// Orthorhombic simulation box, periodic or bounded per axis: wrapping with image counters and the
// minimum-image displacement, with Lees-Edwards images for shear flow (ShearImages).
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/hd.hpp"
#include "core/vec3.hpp"

namespace mesodpd {

// Lees-Edwards images (Lees & Edwards, J. Phys. C 5, 1921 (1972); seed 002, "the classical method" for
// shear): the periodic image one box length up the gradient axis g sits `offset` further along the flow
// axis f and moves `velocity` = dU faster along it. A particle crossing the top face along g therefore
// comes back at the bottom displaced by -offset along f with -velocity added to its f velocity. The
// offset is a function of the time alone (set_time), so a restart continues it exactly.
//   steady:      U = rate L_g, offset = U t (wrapped into [-L_f/2, L_f/2));
//   oscillatory: strain gamma(t) = strain_amplitude sin(omega t), offset = gamma L_g, U = d offset/dt.
// The flow axis precedes the gradient axis (xy, xz or yz, as LAMMPS's tilt factors), which is what lets
// the half stencil of the cell grid stay a half stencil (neighbor/cell_grid.hpp).
struct ShearImages {
  int flow = -1, gradient = -1;  // flow < 0: plain periodic images
  double rate = 0.0;             // steady shear rate (used when omega == 0)
  double strain_amplitude = 0.0, omega = 0.0;
  double offset = 0.0;    // current image offset along the flow axis, |offset| <= L_f / 2
  double velocity = 0.0;  // current image velocity along the flow axis
  // Current shear rate dU/dL_g (the steady rate, or strain_amplitude omega cos(omega t)).
  double current_rate = 0.0;
};

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

  ShearImages shear{};
  bool sheared() const { return shear.flow >= 0; }
  // Sets the image offset and velocity of time t (nothing without shear).
  void set_time(double t) {
    if (!sheared()) return;
    const double lg = length(shear.gradient), lf = length(shear.flow);
    double off;
    if (shear.omega > 0.0) {
      off = shear.strain_amplitude * lg * std::sin(shear.omega * t);
      shear.current_rate = shear.strain_amplitude * shear.omega * std::cos(shear.omega * t);
    } else {
      off = shear.rate * lg * t;
      shear.current_rate = shear.rate;
    }
    shear.velocity = shear.current_rate * lg;
    shear.offset = off - lf * std::floor(off / lf + 0.5);
  }
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

// The image count along the gradient axis that minimum_image() applies to a difference d there: +1 when
// j's nearest image is one box length above (d > half_len), -1 below, else 0.
MESODPD_HD double image_count(double d, double half_len) { return d > half_len ? 1.0 : (d < -half_len ? -1.0 : 0.0); }

// The pair displacement r_i - r_j of two wrapped positions under the box's images, d[3] in place (the
// raw differences in, the displacement out), and the image count n of j along the gradient axis: the
// relative velocity of the pair is then v_i - v_j - n velocity e_f. Exactly odd in (i, j) like
// minimum_image(). Without shear, minimum_image() per axis and n = 0.
inline double box_displacement(const Box& box, double d[3]) {
  double n = 0.0;
  if (box.sheared()) {
    const int g = box.shear.gradient, f = box.shear.flow;
    n = image_count(d[g], box.half_image_len(g));
    d[f] -= n * box.shear.offset;  // |d_f| < 1.5 L_f: minimum_image() below brings it into range
  }
  for (int a = 0; a < 3; ++a) d[a] = minimum_image(d[a], box.image_len(a), box.half_image_len(a));
  return n;
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

// Lees-Edwards crossing of the gradient faces (box sheared): wraps the gradient coordinate r_g (image
// counter i_g) into [0, L_g) and moves the flow coordinate r_f by -k offset, k the crossings (returned:
// the flow velocity then changes by -k velocity). The engine's wrap of the particles and the rigid bodies'
// wrap of their centres and particles share it, so a body's image sits where a particle's would.
inline double wrap_sheared_gradient(const Box& box, double& r_g, std::int32_t& i_g, double& r_f) {
  const std::int32_t before = i_g;
  wrap_coordinate(r_g, i_g, box.length(box.shear.gradient));
  const double k = static_cast<double>(i_g - before);
  if (k != 0.0) r_f -= k * box.shear.offset;
  return k;
}

}  // namespace mesodpd
