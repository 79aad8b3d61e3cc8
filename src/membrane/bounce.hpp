// Keeping fluids on their side of a moving membrane: the first time at which a point moving on a straight
// line meets a triangle whose corners also move on straight lines (continuous collision detection), the
// bounce-back of the point's velocity relative to the triangle there, and the inside test of a closed
// mesh (its winding number) that counts the particles that got through all the same.
#pragma once
#include <array>
#include <optional>
#include <vector>

#include "membrane/mesh.hpp"

namespace mesodpd::membrane {

// Where and when a moving point meets a moving triangle within a step: t in (0, 1] of the step, and the
// barycentric weights (w_a, w_b, w_c) of the point on the triangle at that time.
struct Hit {
  double t = 0;
  std::array<double, 3> w{0, 0, 0};
};

// The point goes from p0 to p1, the corners from a0, b0, c0 to a1, b1, c1, all linearly in t over the
// step. The point lies in the triangle's plane where ((b - a) x (c - a)) . (p - a) = 0, a cubic in t; its
// roots in (0, 1] are found between the cubic's turning points by bisection, in increasing order, and
// the first at which the point is inside the triangle (weights >= -tolerance) is returned.
std::optional<Hit> first_contact(Vec3 p0, Vec3 p1, Vec3 a0, Vec3 a1, Vec3 b0, Vec3 b1, Vec3 c0, Vec3 c1,
                                 double tolerance = 1e-10);

// The generalised winding number of a closed, outward-oriented mesh at q: the sum of the solid angles
// of its triangles seen from q over 4 pi (Van Oosterom & Strackee's formula for each). 1 inside, 0
// outside (to rounding, away from the surface); q is inside where it exceeds 1/2.
double winding_number(const Mesh& m, const std::vector<Vec3>& x, Vec3 q);

}  // namespace mesodpd::membrane
