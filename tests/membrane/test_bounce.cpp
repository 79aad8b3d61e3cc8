// The membrane's solvent bounce-back geometry: the first contact of a moving point with a moving
// triangle, and the winding number of a closed mesh.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "membrane/bounce.hpp"
#include "membrane/mesh.hpp"

namespace mesodpd::membrane {
namespace {

TEST(MembraneBounce, APointThroughAStillTriangleMeetsItWhereItCrossesThePlane) {
  const Vec3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
  const auto hit = first_contact({0.5, 0.5, 1.0}, {0.5, 0.5, -3.0}, a, a, b, b, c, c);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.25, 1e-14);
  EXPECT_NEAR(hit->w[0], 0.5, 1e-14);
  EXPECT_NEAR(hit->w[1], 0.25, 1e-14);
  EXPECT_NEAR(hit->w[2], 0.25, 1e-14);
  // Beside the triangle, or stopping short of it: no contact.
  EXPECT_FALSE(first_contact({1.5, 1.5, 1.0}, {1.5, 1.5, -1.0}, a, a, b, b, c, c).has_value());
  EXPECT_FALSE(first_contact({0.5, 0.5, 1.0}, {0.5, 0.5, 0.1}, a, a, b, b, c, c).has_value());
}

TEST(MembraneBounce, AMovingTriangleMeetsAStillPoint) {
  // The triangle rises from z = 0 to z = 2 over the step; the point waits at z = 0.5.
  const Vec3 a0{0, 0, 0}, b0{2, 0, 0}, c0{0, 2, 0}, up{0, 0, 2};
  const Vec3 p{0.4, 0.4, 0.5};
  const auto hit = first_contact(p, p, a0, a0 + up, b0, b0 + up, c0, c0 + up);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->t, 0.25, 1e-14);
  // A triangle that tilts through the point: the plane sweeps it at the cubic's root.
  const Vec3 q{0.5, 0.5, 0.2};
  const auto tilt = first_contact(q, q, a0, a0, b0, b0 + Vec3{0, 0, 1}, c0, c0 + Vec3{0, 0, 1});
  ASSERT_TRUE(tilt.has_value());
  // At t the plane z = t (x + y)/2 passes through q: t = 0.2 / 0.5.
  EXPECT_NEAR(tilt->t, 0.4, 1e-12);
}

TEST(MembraneBounce, WindingNumberIsOneInsideAndZeroOutside) {
  const Mesh m = red_cell(5, 7.82);
  EXPECT_NEAR(winding_number(m, m.vertices, {0, 0, 0}), 1.0, 1e-12);
  EXPECT_NEAR(winding_number(m, m.vertices, {3.0, 0.5, 0.2}), 1.0, 1e-12);  // in the rim
  EXPECT_NEAR(winding_number(m, m.vertices, {0, 0, 1.0}), 0.0, 1e-12);      // above the dimple
  EXPECT_NEAR(winding_number(m, m.vertices, {5, 5, 5}), 0.0, 1e-12);
}

// Every point that changes side of a moving, deforming closed mesh within a step meets one of its
// triangles on the way (10,000 random points near a sphere of 162 vertices whose vertices each move by up
// to 0.15 and the points by up to 0.3); and points that stay on their side almost never report one (a
// point may cross twice, out and back in, within a step: allowed, but rare).
TEST(MembraneBounce, EveryPointThatChangesSideMeetsATriangle) {
  const Mesh m = geodesic_sphere(4, 2.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  int changed = 0, found = 0, stayed_hit = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Vec3> x1 = m.vertices;
    for (Vec3& p : x1) p += Vec3{0.15 * u(rng), 0.15 * u(rng), 0.15 * u(rng)};
    for (int k = 0; k < 50; ++k) {
      Vec3 p0{u(rng), u(rng), u(rng)};
      p0 = (2.0 + 0.3 * u(rng)) / norm(p0) * p0;
      const Vec3 p1 = p0 + Vec3{0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)};
      const bool in0 = winding_number(m, m.vertices, p0) > 0.5, in1 = winding_number(m, x1, p1) > 0.5;
      bool hit = false;
      for (const auto& t : m.triangles)
        hit = hit || first_contact(p0, p1, m.vertices[t[0]], x1[t[0]], m.vertices[t[1]], x1[t[1]], m.vertices[t[2]],
                                   x1[t[2]])
                         .has_value();
      if (in0 != in1) {
        ++changed;
        found += hit ? 1 : 0;
      } else {
        stayed_hit += hit ? 1 : 0;
      }
    }
  }
  EXPECT_GT(changed, 1000);
  EXPECT_EQ(found, changed);
  EXPECT_LT(stayed_hit, changed / 20);
}

}  // namespace
}  // namespace mesodpd::membrane
