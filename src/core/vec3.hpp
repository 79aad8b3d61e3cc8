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

}  // namespace mesodpd
