// Membrane energies and their exact gradients (membrane/membrane_forces.hpp has the formulas).
#include "membrane/membrane_forces.hpp"

#include "core/philox.hpp"
#include "physics/bond_laws.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mesodpd::membrane {

namespace {

// The hinge angle at edge b-c and its gradient (physics/bond_laws.hpp's hinge_angle, shared with the
// bonded dihedrals): the angle between the outward normals of the triangles (a, b, c) and (d, c, b),
// positive where the surface is convex.
struct Dihedral {
  double theta = 0;
  Vec3 ga, gb, gc, gd;
};
Dihedral dihedral(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const double ra[3] = {a.x - b.x, a.y - b.y, a.z - b.z}, rc[3] = {c.x - b.x, c.y - b.y, c.z - b.z},
               rd[3] = {d.x - b.x, d.y - b.y, d.z - b.z};
  const mesodpd::Hinge g = hinge_angle(ra, rc, rd);
  const auto v = [](const double* q) { return Vec3{q[0], q[1], q[2]}; };
  return {g.theta, v(g.ga), v(g.gb), v(g.gc), v(g.gd)};
}

// Area of triangle (a, b, c) and its gradient with respect to each corner.
struct TriangleArea {
  double area = 0;
  Vec3 ga, gb, gc;
};
TriangleArea triangle_area(Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 n = cross(b - a, c - a);
  const double len = norm(n);
  const Vec3 u = (1.0 / len) * n;
  return {0.5 * len, 0.5 * cross(b - c, u), 0.5 * cross(c - a, u), 0.5 * cross(a - b, u)};
}

}  // namespace

double wlc_pow_dudl(double l, double lm, double kT, double p, double kp, double m) {
  const double x = l / lm;
  return kT / p * (0.25 / ((1 - x) * (1 - x)) - 0.25 + x) - kp / std::pow(l, m);
}

std::array<double, 6> virial(const std::vector<Vec3>& x, const std::vector<Vec3>& f) {
  std::array<double, 6> w{};
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Vec3 d = x[i] - x[0];
    w[0] += d.x * f[i].x;
    w[1] += d.y * f[i].y;
    w[2] += d.z * f[i].z;
    w[3] += d.y * f[i].x;
    w[4] += d.z * f[i].x;
    w[5] += d.z * f[i].y;
  }
  return w;
}

double wlc_pow_energy(double l, double lm, double kT, double p, double kp, double m) {
  const double x = l / lm;
  const double wlc = kT * lm / (4 * p) * (3 * x * x - 2 * x * x * x) / (1 - x);
  const double pow_part = m == 1.0 ? -kp * std::log(l) : kp / ((m - 1) * std::pow(l, m - 1));
  return wlc + pow_part;
}

double wlc_pow_kp(double l0, double x0, double kT, double p, double m) {
  return std::pow(l0, m) * kT / p * (0.25 / ((1 - x0) * (1 - x0)) - 0.25 + x0);
}

double shear_modulus(double l0, double x0, double kT, double p, double m) {
  const double lm = l0 / x0;
  const double kp = wlc_pow_kp(l0, x0, kT, p, m);
  const double wlc2 = kT / (p * lm) * (0.5 / ((1 - x0) * (1 - x0) * (1 - x0)) + 1.0);
  const double pow2 = m * kp / std::pow(l0, m + 1);
  return std::sqrt(3.0) / 4.0 * (wlc2 + pow2);
}

double persistence_for(double mu0, double l0, double x0, double kT, double m) {
  return shear_modulus(l0, x0, kT, 1.0, m) / mu0;  // mu0 is proportional to 1/p
}

double kantor_nelson_kb(double kappa) { return 2.0 * kappa / std::sqrt(3.0); }

double membrane_viscosity(double gamma_t, double gamma_c) { return std::sqrt(3.0) * (gamma_t + 0.25 * gamma_c); }

void edge_noise(std::uint64_t seed, std::uint64_t step, std::uint32_t a, std::uint32_t b, double w[9], NoiseKind noise) {
  // Streams 24-26 of the pair counter (core/philox.hpp numbers the engine's streams below 16). Uniform:
  // one variate per word (the first nine of twelve). Gaussian: Box-Muller on each pair of words gives two
  // (the cosine and the sine branch).
  for (std::uint32_t k = 0; k < 3; ++k) {
    const Philox4x32 r = pair_random_bits(seed, step, a, b, static_cast<RngStream>(24u + k));
    if (noise == NoiseKind::Uniform) {
      for (int h = 0; h < 4 && 4 * static_cast<int>(k) + h < 9; ++h) w[4 * k + static_cast<std::uint32_t>(h)] = uniform_unit_variance(r.v[h]);
      continue;
    }
    for (int h = 0; h < 2; ++h) {
      const double rad = std::sqrt(-2.0 * std::log(u01_open(r.v[2 * h])));
      const double phi = 2.0 * std::numbers::pi * u01_open(r.v[2 * h + 1]);
      const int i = 4 * static_cast<int>(k) + 2 * h;
      if (i < 9) w[i] = rad * std::cos(phi);
      if (i + 1 < 9) w[i + 1] = rad * std::sin(phi);
    }
  }
}

void CellModel::viscous_forces(const std::vector<Vec3>& x, const std::vector<Vec3>& v, double dt, std::uint64_t seed,
                               std::uint64_t step, std::uint32_t first_id, std::vector<Vec3>& f) const {
  if (!viscous()) return;
  const double gt = params_.gamma_t, gc = params_.gamma_c;
  const double amp = std::sqrt(2.0 * params_.kT / dt);
  const double as = std::sqrt(2.0 * gt), at = std::sqrt(std::max(0.0, 3.0 * gc - gt));
  double w[9];
  for (const Hinge& h : hinges_) {
    const std::size_t i = h.b, j = h.c;
    const Vec3 d = x[i] - x[j];
    const Vec3 e = (1.0 / norm(d)) * d;
    const Vec3 vij = v[i] - v[j];
    Vec3 force = -gt * vij - (gc * dot(vij, e)) * e;
    edge_noise(seed, step, first_id + static_cast<std::uint32_t>(i), first_id + static_cast<std::uint32_t>(j), w, params_.noise);
    const double tr3 = (w[0] + w[4] + w[8]) / 3.0;
    // dW^S . e: the symmetric part less a third of the trace on the diagonal.
    const double s01 = 0.5 * (w[1] + w[3]), s02 = 0.5 * (w[2] + w[6]), s12 = 0.5 * (w[5] + w[7]);
    const Vec3 ws{(w[0] - tr3) * e.x + s01 * e.y + s02 * e.z, s01 * e.x + (w[4] - tr3) * e.y + s12 * e.z,
                  s02 * e.x + s12 * e.y + (w[8] - tr3) * e.z};
    force += amp * (as * ws + (at * tr3) * e);
    f[i] += force;
    f[j] += -force;
  }
}

CellModel::CellModel(Mesh mesh, Parameters params, const std::vector<Vec3>* reference, const std::string& source)
    : mesh_(std::move(mesh)), params_(params) {
  hinges_ = check_closed(mesh_, source);
  const std::vector<Vec3>& ref = reference ? *reference : mesh_.vertices;
  if (ref.size() != mesh_.vertices.size())
    throw MeshError(fmt::format("{}: the reference shape has {} vertices, the mesh {}", source, ref.size(), mesh_.vertices.size()));
  const double ref_volume = mesh_volume(mesh_, ref);
  if (!(ref_volume > 0)) throw MeshError(fmt::format("{}: the reference shape encloses no volume (it is {})", source, ref_volume));
  for (const Hinge& h : hinges_) l0_.push_back(norm(ref[h.c] - ref[h.b]));
  double sum = 0;
  for (double l : l0_) sum += l;
  mean_l0_ = sum / static_cast<double>(l0_.size());
  if (!params_.stress_free) std::fill(l0_.begin(), l0_.end(), mean_l0_);
  for (double l : l0_) kp_.push_back(params_.persistence > 0 ? wlc_pow_kp(l, params_.x0, params_.kT, params_.persistence, params_.m) : 0.0);
  const double ref_area = mesh_area(mesh_, ref);
  for (const auto& t : mesh_.triangles)
    area0_t_.push_back(params_.stress_free ? triangle_area(ref[t[0]], ref[t[1]], ref[t[2]]).area
                                           : ref_area / static_cast<double>(mesh_.triangles.size()));
  area0_ = params_.area0 > 0 ? params_.area0 : ref_area;
  volume0_ = params_.volume0 > 0 ? params_.volume0 : ref_volume;
}

std::optional<Energies> CellModel::forces(const std::vector<Vec3>& x, std::vector<Vec3>& f, std::size_t* broken) const {
  const Parameters& P = params_;
  const std::size_t nv = mesh_.vertices.size(), nt = mesh_.triangles.size(), nh = hinges_.size();
  Energies e;
  std::vector<Vec3> g(nv);  // the gradient of the energy
  // Bonds.
  if (P.persistence > 0)
    for (std::size_t k = 0; k < nh; ++k) {
      const Hinge& h = hinges_[k];
      const Vec3 d = x[h.c] - x[h.b];
      const double l = norm(d), lm = l0_[k] / P.x0;
      if (!(l < lm)) {
        if (broken) *broken = k;
        return std::nullopt;
      }
      e.bond += wlc_pow_energy(l, lm, P.kT, P.persistence, kp_[k], P.m);
      const Vec3 gc = (wlc_pow_dudl(l, lm, P.kT, P.persistence, kp_[k], P.m) / l) * d;
      g[h.c] += gc;
      g[h.b] += -gc;
    }
  // Triangles: areas and their gradients.
  std::vector<TriangleArea> tri(nt);
  double area = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = mesh_.triangles[t];
    tri[t] = triangle_area(x[v[0]], x[v[1]], x[v[2]]);
    area += tri[t].area;
  }
  std::vector<double> dedA(nt, 0.0);  // dE/dA_t
  if (P.kd > 0)
    for (std::size_t t = 0; t < nt; ++t) {
      const double s = tri[t].area - area0_t_[t];
      e.area_local += P.kd * s * s / (2 * area0_t_[t]);
      dedA[t] += P.kd * s / area0_t_[t];
    }
  if (P.ka > 0) {
    const double s = area - area0_;
    e.area_global = P.ka * s * s / (2 * area0_);
    for (double& d : dedA) d += P.ka * s / area0_;
  }
  // Bending.
  if (P.bending != Bending::None) {
    std::vector<Dihedral> dih(nh);
    for (std::size_t k = 0; k < nh; ++k) {
      const Hinge& h = hinges_[k];
      dih[k] = dihedral(x[h.a], x[h.b], x[h.c], x[h.d]);
    }
    auto add_angle = [&](std::size_t k, double s) {  // s times the gradient of theta_k
      const Hinge& h = hinges_[k];
      g[h.a] += s * dih[k].ga;
      g[h.b] += s * dih[k].gb;
      g[h.c] += s * dih[k].gc;
      g[h.d] += s * dih[k].gd;
    };
    if (P.bending == Bending::KantorNelson) {
      for (std::size_t k = 0; k < nh; ++k) {
        e.bend += P.kb * (1 - std::cos(dih[k].theta - P.theta0));
        add_angle(k, P.kb * std::sin(dih[k].theta - P.theta0));
      }
    } else {
      std::vector<double> mi(nv, 0.0), ai(nv, 0.0), len(nh);
      for (std::size_t k = 0; k < nh; ++k) {
        const Hinge& h = hinges_[k];
        len[k] = norm(x[h.c] - x[h.b]);
        mi[h.b] += 0.25 * len[k] * dih[k].theta;
        mi[h.c] += 0.25 * len[k] * dih[k].theta;
      }
      for (std::size_t t = 0; t < nt; ++t)
        for (std::uint32_t v : mesh_.triangles[t]) ai[v] += tri[t].area / 3.0;
      for (std::size_t i = 0; i < nv; ++i) e.bend += 2 * P.kappa * mi[i] * mi[i] / ai[i];
      for (std::size_t k = 0; k < nh; ++k) {
        const Hinge& h = hinges_[k];
        const double c = P.kappa * (mi[h.b] / ai[h.b] + mi[h.c] / ai[h.c]);  // dE/dM_i dM_i/d(l theta)
        const Vec3 gl = (1.0 / len[k]) * (x[h.c] - x[h.b]);
        g[h.c] += (c * dih[k].theta) * gl;
        g[h.b] += (-c * dih[k].theta) * gl;
        add_angle(k, c * len[k]);
      }
      for (std::size_t t = 0; t < nt; ++t) {
        double s = 0;
        for (std::uint32_t v : mesh_.triangles[t]) s += mi[v] * mi[v] / (ai[v] * ai[v]);
        dedA[t] += -2 * P.kappa * s / 3.0;
      }
    }
  }
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& v = mesh_.triangles[t];
    g[v[0]] += dedA[t] * tri[t].ga;
    g[v[1]] += dedA[t] * tri[t].gb;
    g[v[2]] += dedA[t] * tri[t].gc;
  }
  // Volume.
  if (P.kv > 0) {
    const double volume = mesh_volume(mesh_, x);
    const double s = volume - volume0_;
    e.volume = P.kv * s * s / (2 * volume0_);
    const double c = P.kv * s / volume0_ / 6.0;
    const Vec3 o = x[0];
    for (const auto& v : mesh_.triangles) {
      const Vec3 a = x[v[0]] - o, b = x[v[1]] - o, cc = x[v[2]] - o;
      g[v[0]] += c * cross(b, cc);
      g[v[1]] += c * cross(cc, a);
      g[v[2]] += c * cross(a, b);
    }
  }
  for (std::size_t i = 0; i < nv; ++i) f[i] += -g[i];
  return e;
}

Energies CellModel::energies(const std::vector<Vec3>& x) const {
  std::vector<Vec3> scratch(x.size());
  std::size_t broken = 0;
  const std::optional<Energies> e = forces(x, scratch, &broken);
  if (!e) throw MeshError(fmt::format("membrane: edge {} is at or past its maximum length", broken));
  return *e;
}

Shape measure(const Mesh& mesh, const std::vector<Vec3>& x, int axis) {
  Shape s;
  const std::size_t n = x.size();
  for (const Vec3& p : x) s.centroid += p;
  s.centroid = (1.0 / static_cast<double>(n)) * s.centroid;
  auto along = [axis](Vec3 p) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; };
  double lo = along(x[0]), hi = lo;
  double gxx = 0, gyy = 0, gzz = 0, gxy = 0, gxz = 0, gyz = 0;
  for (const Vec3& p : x) {
    lo = std::min(lo, along(p));
    hi = std::max(hi, along(p));
    const Vec3 d = p - s.centroid;
    gxx += d.x * d.x;
    gyy += d.y * d.y;
    gzz += d.z * d.z;
    gxy += d.x * d.y;
    gxz += d.x * d.z;
    gyz += d.y * d.z;
  }
  s.axial = hi - lo;
  double widest = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      Vec3 d = x[i] - x[j];
      (axis == 0 ? d.x : axis == 1 ? d.y : d.z) = 0;
      widest = std::max(widest, dot(d, d));
    }
  s.transverse = std::sqrt(widest);
  s.area = mesh_area(mesh, x);
  s.volume = mesh_volume(mesh, x);
  const double tr = gxx + gyy + gzz;
  const double tr2 = gxx * gxx + gyy * gyy + gzz * gzz + 2 * (gxy * gxy + gxz * gxz + gyz * gyz);
  s.asphericity = tr > 0 ? (3 * tr2 - tr * tr) / (2 * tr * tr) : 0.0;
  return s;
}

}  // namespace mesodpd::membrane

namespace mesodpd::membrane {

std::vector<Vec3> tweezers(const Mesh& mesh, double force, double fraction, int axis) {
  const std::size_t n = mesh.vertices.size();
  auto along = [axis](Vec3 p) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; };
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return along(mesh.vertices[a]) < along(mesh.vertices[b]); });
  const auto grip = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(fraction * static_cast<double>(n))));
  Vec3 pull;
  (axis == 0 ? pull.x : axis == 1 ? pull.y : pull.z) = force / static_cast<double>(grip);
  std::vector<Vec3> external(n);
  for (std::size_t k = 0; k < grip; ++k) {
    external[order[k]] = -pull;
    external[order[n - 1 - k]] = pull;
  }
  return external;
}

Stretched stretch(const CellModel& cell, const std::vector<Vec3>& start, double force, double fraction, int axis,
                  double tolerance, std::size_t max_steps) {
  const std::size_t n = start.size();
  const std::vector<Vec3> external = tweezers(cell.mesh(), force, fraction, axis);
  Stretched out;
  out.x = start;
  std::vector<Vec3> v(n), f(n);
  double dt = 1e-4, alpha = 0.1;
  const double dt_max = 1e-2;
  std::size_t positive = 0;
  for (std::size_t step = 0; step < max_steps; ++step) {
    std::fill(f.begin(), f.end(), Vec3{});
    std::size_t broken = 0;
    if (!cell.forces(out.x, f, &broken))
      throw MeshError(fmt::format("stretch: at force {} the edge of hinge {} reached its maximum length", force, broken));
    double residual = 0, power = 0, vv = 0, ff = 0;
    for (std::size_t i = 0; i < n; ++i) {
      f[i] += external[i];
      residual = std::max(residual, dot(f[i], f[i]));
      power += dot(f[i], v[i]);
      vv += dot(v[i], v[i]);
      ff += dot(f[i], f[i]);
    }
    out.residual = std::sqrt(residual);
    out.steps = step;
    if (out.residual < tolerance) {
      out.shape = measure(cell.mesh(), out.x, axis);
      return out;
    }
    if (power > 0) {
      const double mix = ff > 0 ? alpha * std::sqrt(vv / ff) : 0.0;
      for (std::size_t i = 0; i < n; ++i) v[i] = (1 - alpha) * v[i] + mix * f[i];
      if (++positive > 5) {
        dt = std::min(dt * 1.1, dt_max);
        alpha *= 0.99;
      }
    } else {
      std::fill(v.begin(), v.end(), Vec3{});
      positive = 0;
      dt *= 0.5;
      alpha = 0.1;
    }
    for (std::size_t i = 0; i < n; ++i) {
      v[i] += dt * f[i];
      out.x[i] += dt * v[i];
    }
  }
  throw MeshError(fmt::format("stretch: no equilibrium at force {} after {} steps (largest net force {})", force,
                              max_steps, out.residual));
}

}  // namespace mesodpd::membrane
