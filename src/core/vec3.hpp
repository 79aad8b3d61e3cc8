// Minimal 3-vector used by physics functors on every backend (no std library containers).
#pragma once
#include "core/hd.hpp"

namespace mesodpd {

struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

MESODPD_HD Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
MESODPD_HD Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
MESODPD_HD Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
MESODPD_HD Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
MESODPD_HD double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
MESODPD_HD Vec3& operator+=(Vec3& a, Vec3 b) {
  a.x += b.x;
  a.y += b.y;
  a.z += b.z;
  return a;
}
MESODPD_HD Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
// Component a (0: x, 1: y, 2: z), and the unit vector along axis a.
MESODPD_HD double& component(Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }
MESODPD_HD double component(const Vec3& v, int a) { return a == 0 ? v.x : (a == 1 ? v.y : v.z); }
MESODPD_HD Vec3 axis_vector(int a) {
  Vec3 e;
  component(e, a) = 1.0;
  return e;
}

}  // namespace mesodpd
