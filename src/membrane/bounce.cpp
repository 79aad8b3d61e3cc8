// Continuous collision of a point with a moving triangle, and the winding number of a closed mesh
// (membrane/bounce.hpp).
#include "membrane/bounce.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mesodpd::membrane {

namespace {

// Barycentric weights of q's projection on the plane of (a, b, c).
std::array<double, 3> barycentric(Vec3 q, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 n = cross(b - a, c - a);
  const double nn = dot(n, n);
  const double wa = dot(cross(c - b, q - b), n) / nn;
  const double wb = dot(cross(a - c, q - c), n) / nn;
  return {wa, wb, 1.0 - wa - wb};
}

}  // namespace

std::optional<Hit> first_contact(Vec3 p0, Vec3 p1, Vec3 a0, Vec3 a1, Vec3 b0, Vec3 b1, Vec3 c0, Vec3 c1,
                                 double tolerance) {
  // Edges u(t) = u0 + t u1, v(t) = v0 + t v1 from a; normal n(t) = n0 + t n1 + t^2 n2; q(t) = p - a.
  const Vec3 u0 = b0 - a0, u1 = (b1 - a1) - u0;
  const Vec3 v0 = c0 - a0, v1 = (c1 - a1) - v0;
  const Vec3 q0 = p0 - a0, q1 = (p1 - a1) - q0;
  const Vec3 n0 = cross(u0, v0), n1 = cross(u0, v1) + cross(u1, v0), n2 = cross(u1, v1);
  const double c[4] = {dot(n0, q0), dot(n1, q0) + dot(n0, q1), dot(n2, q0) + dot(n1, q1), dot(n2, q1)};
  auto f = [&](double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; };
  // The cubic is monotone between 0, its turning points in (0, 1) and 1.
  std::array<double, 4> knots{0.0, 1.0, 1.0, 1.0};
  int nk = 1;
  const double qa = 3 * c[3], qb = 2 * c[2], qc = c[1];
  if (qa != 0) {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc > 0) {
      const double s = std::sqrt(disc);
      double r1 = (-qb - s) / (2 * qa), r2 = (-qb + s) / (2 * qa);
      if (r1 > r2) std::swap(r1, r2);
      if (r1 > 0 && r1 < 1) knots[static_cast<std::size_t>(nk++)] = r1;
      if (r2 > 0 && r2 < 1) knots[static_cast<std::size_t>(nk++)] = r2;
    }
  } else if (qb != 0) {
    const double r = -qc / qb;
    if (r > 0 && r < 1) knots[static_cast<std::size_t>(nk++)] = r;
  }
  knots[static_cast<std::size_t>(nk++)] = 1.0;
  for (int k = 0; k + 1 < nk; ++k) {
    double lo = knots[static_cast<std::size_t>(k)], hi = knots[static_cast<std::size_t>(k + 1)];
    double flo = f(lo), fhi = f(hi);
    // A root at the start of the step is where a previous bounce left the point: not a new contact.
    if (k == 0 && flo == 0) continue;
    if (flo * fhi > 0 || hi <= lo) continue;
    for (int it = 0; it < 60 && hi - lo > 1e-15; ++it) {
      const double mid = 0.5 * (lo + hi), fm = f(mid);
      if ((fm <= 0) == (flo <= 0)) {
        lo = mid;
        flo = fm;
      } else {
        hi = mid;
      }
    }
    const double t = hi;
    const Vec3 p = p0 + t * (p1 - p0), a = a0 + t * (a1 - a0), b = b0 + t * (b1 - b0), cc = c0 + t * (c1 - c0);
    const std::array<double, 3> w = barycentric(p, a, b, cc);
    if (w[0] >= -tolerance && w[1] >= -tolerance && w[2] >= -tolerance) return Hit{t, w};
  }
  return std::nullopt;
}

double winding_number(const Mesh& m, const std::vector<Vec3>& x, Vec3 q) {
  double sum = 0;
  for (const auto& tri : m.triangles) {
    const Vec3 a = x[tri[0]] - q, b = x[tri[1]] - q, c = x[tri[2]] - q;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    sum += 2.0 * std::atan2(num, den);
  }
  return sum / (4.0 * std::numbers::pi);
}

}  // namespace mesodpd::membrane
