// The membrane module: mesh generators and checks, each force against finite differences of its energy,
// zero total force and torque, the Juelicher energy of a sphere, the network's shear modulus.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>

#include <unistd.h>

#include "membrane/membrane_forces.hpp"
#include "membrane/mesh.hpp"

namespace mesodpd::membrane {
namespace {

std::vector<Vec3> jiggled(const std::vector<Vec3>& x, double amount, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  std::vector<Vec3> y = x;
  for (Vec3& p : y) p += Vec3{u(rng), u(rng), u(rng)};
  return y;
}

TEST(MembraneMesh, GeodesicSphereCountsAreaAndVolume) {
  for (int n : {1, 3, 8}) {
    const Mesh m = geodesic_sphere(n, 2.0);
    EXPECT_EQ(m.vertices.size(), static_cast<std::size_t>(10 * n * n + 2));
    EXPECT_EQ(m.triangles.size(), static_cast<std::size_t>(20 * n * n));
    const std::vector<Hinge> h = check_closed(m, "sphere");
    EXPECT_EQ(h.size(), static_cast<std::size_t>(30 * n * n));  // Euler: E = V + F - 2
    for (const Vec3& p : m.vertices) EXPECT_NEAR(std::sqrt(dot(p, p)), 2.0, 1e-12);
  }
  // Inscribed polyhedra approach the sphere from below, with an error falling as 1/n^2.
  const Mesh fine = geodesic_sphere(16, 1.0);
  EXPECT_NEAR(mesh_area(fine, fine.vertices) / (4 * std::numbers::pi), 1.0, 3e-3);
  EXPECT_NEAR(mesh_volume(fine, fine.vertices) / (4 * std::numbers::pi / 3), 1.0, 5e-3);
  EXPECT_LT(mesh_area(fine, fine.vertices), 4 * std::numbers::pi);
  EXPECT_EQ(frequency_for(500), 7);
  EXPECT_EQ(frequency_for(1000), 10);
  EXPECT_EQ(frequency_for(3000), 17);
}

// The mesh's area and volume converge (from below: inscribed) to those of the Evans-Fung surface, here
// by quadrature of its profile (134.1 um^2 and 94.1 um^3 at D = 7.82 um; the commonly quoted red-cell
// values are 135 um^2 and 94 um^3).
TEST(MembraneMesh, RedCellAreaAndVolumeMatchEvansFung) {
  const double D = 7.82, c0 = 0.0518, c1 = 2.0026, c2 = -4.491;
  auto profile = [&](double t) {  // (rho, z) at polar angle t of the mapped unit sphere
    const double u = std::sin(t) * std::sin(t);
    return std::pair<double, double>{D / 2 * std::sin(t), D * std::cos(t) * (c0 + c1 * u / 4 + c2 * u * u / 16)};
  };
  double area = 0, volume = 0;
  const int steps = 200000;
  auto prev = profile(0);
  for (int k = 1; k <= steps; ++k) {
    const auto cur = profile(k * std::numbers::pi / 2 / steps);
    const double rm = (prev.first + cur.first) / 2, zm = (prev.second + cur.second) / 2;
    area += 4 * std::numbers::pi * rm * std::hypot(cur.first - prev.first, cur.second - prev.second);
    volume += 4 * std::numbers::pi * rm * zm * (cur.first - prev.first);
    prev = cur;
  }
  const Mesh m = red_cell(frequency_for(3000), D);
  check_closed(m, "red cell");
  const double a = mesh_area(m, m.vertices), v = mesh_volume(m, m.vertices);
  std::printf("  Evans-Fung D = 7.82: quadrature A = %.3f V = %.3f; mesh of %zu vertices A = %.3f V = %.3f\n", area,
              volume, m.vertices.size(), a, v);
  EXPECT_NEAR(a / area, 1.0, 3e-3);
  EXPECT_NEAR(v / volume, 1.0, 3e-3);
  EXPECT_LT(a, area);
  EXPECT_NEAR(area, 135, 2);
  EXPECT_NEAR(volume, 94, 1);
  double thickest = 0, centre = 1e9;
  for (const Vec3& p : m.vertices) {
    thickest = std::max(thickest, 2 * std::abs(p.z));
    if (p.x * p.x + p.y * p.y < 0.25) centre = std::min(centre, 2 * std::abs(p.z));
  }
  EXPECT_NEAR(thickest, 2.5, 0.1);  // the rim
  EXPECT_NEAR(centre, 0.81, 0.05);  // the dimple
}

Parameters all_terms(Bending bending) {
  Parameters p;
  p.kT = 0.7;
  p.persistence = 0.3;
  p.x0 = 0.45;
  p.m = 2;
  p.stress_free = true;
  p.bending = bending;
  p.kb = 3.0;
  p.theta0 = 0.1;
  p.kappa = 2.5;
  p.ka = 40;
  p.kd = 5;
  p.kv = 60;
  p.area0 = 140;  // not the reference's: the global terms have a slope at the start
  p.volume0 = 90;
  return p;
}

// Each force is the negative gradient of its energy: central differences of the total energy on a
// jiggled red cell, term by term (the others switched off) and all together.
TEST(MembraneForces, MatchFiniteDifferencesOfTheEnergy) {
  const Mesh mesh = red_cell(4, 7.82);
  const std::vector<Vec3> x = jiggled(mesh.vertices, 0.05, 7);
  struct Case {
    const char* name;
    Parameters p;
  };
  std::vector<Case> cases;
  auto only = [&](const char* name, auto&& set) {
    Parameters p;
    p.kT = 0.7;
    set(p);
    cases.push_back({name, p});
  };
  only("wlc-pow", [](Parameters& p) { p.persistence = 0.3; p.x0 = 0.45; });
  only("wlc-pow m=1, uniform l0", [](Parameters& p) { p.persistence = 0.3; p.x0 = 0.3; p.m = 1; p.stress_free = false; });
  only("kantor-nelson", [](Parameters& p) { p.bending = Bending::KantorNelson; p.kb = 3; p.theta0 = 0.1; });
  only("juelicher", [](Parameters& p) { p.bending = Bending::Juelicher; p.kappa = 2.5; });
  only("local area", [](Parameters& p) { p.kd = 5; });
  only("global area", [](Parameters& p) { p.ka = 40; p.area0 = 140; });
  only("volume", [](Parameters& p) { p.kv = 60; p.volume0 = 90; });
  cases.push_back({"all, kantor-nelson", all_terms(Bending::KantorNelson)});
  cases.push_back({"all, juelicher", all_terms(Bending::Juelicher)});
  for (const Case& c : cases) {
    const CellModel cell(mesh, c.p);
    std::vector<Vec3> f(x.size());
    ASSERT_TRUE(cell.forces(x, f)) << c.name;
    double fmax = 0;
    for (const Vec3& v : f) fmax = std::max(fmax, std::sqrt(dot(v, v)));
    ASSERT_GT(fmax, 1e-3) << c.name << ": no force to compare";
    const double h = 1e-6;
    for (std::size_t i = 0; i < x.size(); i += 7)
      for (int d = 0; d < 3; ++d) {
        std::vector<Vec3> xp = x, xm = x;
        double& up = d == 0 ? xp[i].x : d == 1 ? xp[i].y : xp[i].z;
        double& dn = d == 0 ? xm[i].x : d == 1 ? xm[i].y : xm[i].z;
        up += h;
        dn -= h;
        const double numeric = -(cell.energies(xp).total() - cell.energies(xm).total()) / (2 * h);
        const double exact = d == 0 ? f[i].x : d == 1 ? f[i].y : f[i].z;
        EXPECT_NEAR(exact, numeric, 1e-6 * fmax + 1e-6 * std::abs(numeric)) << c.name << ", vertex " << i << ", axis " << d;
      }
  }
}

// The virial that the membrane adds to the pressure tensor (membrane::virial, PairSums' order) is minus
// the derivative of the energy under a homogeneous strain x_a -> x_a + eps_ab x_b: every component, by
// central differences, on a jiggled red cell with every term on. The cell sits far from the origin (the
// virial of internal forces does not depend on it) and off-diagonals are compared one at a time
// (eps_ab alone: flux of a-momentum through b-planes).
TEST(MembraneForces, VirialIsTheStrainDerivativeOfTheEnergy) {
  const Mesh mesh = red_cell(4, 7.82);
  for (Bending b : {Bending::KantorNelson, Bending::Juelicher}) {
    std::vector<Vec3> x = jiggled(mesh.vertices, 0.05, 3);
    for (Vec3& p : x) p += Vec3{-20.0, 7.0, 13.0};
    const CellModel cell(mesh, all_terms(b));
    std::vector<Vec3> f(x.size());
    ASSERT_TRUE(cell.forces(x, f));
    const std::array<double, 6> w = virial(x, f);
    const int comp[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};  // (a, b) of each entry
    double scale = 0;
    for (double v : w) scale = std::max(scale, std::abs(v));
    ASSERT_GT(scale, 1.0);
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      const int a = comp[k][0], bb = comp[k][1];
      auto strained = [&](double eps) {
        std::vector<Vec3> y = x;
        for (Vec3& p : y) {
          const double xb = bb == 0 ? p.x : bb == 1 ? p.y : p.z;
          (a == 0 ? p.x : a == 1 ? p.y : p.z) += eps * xb;
        }
        return cell.energies(y).total();
      };
      const double numeric = -(strained(h) - strained(-h)) / (2 * h);
      EXPECT_NEAR(w[static_cast<std::size_t>(k)], numeric, 1e-6 * scale) << "component " << k;
    }
  }
}

// The energy depends on distances, angles, areas and the volume only: the forces add up to no force and
// no torque, so momentum and angular momentum are conserved.
TEST(MembraneForces, TotalForceAndTorqueVanish) {
  const Mesh mesh = red_cell(5, 7.82);
  for (Bending b : {Bending::KantorNelson, Bending::Juelicher}) {
    std::vector<Vec3> x = jiggled(mesh.vertices, 0.08, 11);
    for (Vec3& p : x) p += Vec3{30.0, -12.0, 4.0};  // away from the origin: the torque is about it
    const CellModel cell(mesh, all_terms(b));
    std::vector<Vec3> f(x.size());
    ASSERT_TRUE(cell.forces(x, f));
    Vec3 total, torque;
    double scale = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
      total += f[i];
      torque += cross(x[i], f[i]);
      scale += std::sqrt(dot(f[i], f[i]));
    }
    EXPECT_LT(std::sqrt(dot(total, total)), 1e-11 * scale);
    EXPECT_LT(std::sqrt(dot(torque, torque)), 1e-11 * scale * 40);
  }
}

// A sphere's Helfrich energy kappa/2 (2H)^2 A = 8 pi kappa for any radius; the Juelicher sum on the
// geodesic sphere reaches it as the mesh is refined.
TEST(MembraneForces, JuelicherEnergyOfASphereIs8PiKappa) {
  Parameters p;
  p.bending = Bending::Juelicher;
  p.kappa = 1.0;
  double previous = 1e9;
  for (int n : {2, 4, 8, 16}) {
    for (double radius : {1.0, 7.0}) {
      const Mesh m = geodesic_sphere(n, radius);
      const CellModel cell(m, p);
      const double ratio = cell.energies(m.vertices).bend / (8 * std::numbers::pi);
      std::printf("  Juelicher sphere: frequency %2d (%4zu vertices), radius %.0f: E / 8 pi kappa = %.5f\n", n,
                  m.vertices.size(), radius, ratio);
      if (radius == 1.0) {
        EXPECT_LT(std::abs(ratio - 1), previous);
        previous = std::abs(ratio - 1);
      }
      if (n >= 8) {
        EXPECT_NEAR(ratio, 1.0, 0.005);
      }
    }
  }
}

// The linear shear modulus of the network, measured: a periodic triangular lattice of WLC-POW springs at
// rest length l0, sheared at constant area (x by 1 + e, y by 1/(1 + e)), stores W = 2 mu e^2 per unit
// area. Against the analytic value, and that against Fedosov et al.'s printed expression.
TEST(MembraneModuli, LatticeShearModulusMatchesTheAnalyticValue) {
  for (double m : {1.0, 2.0, 4.0}) {
    const double kT = 0.4, p = 0.02, x0 = 1 / 2.2, l0 = 0.6;
    const double lm = l0 / x0, kp = wlc_pow_kp(l0, x0, kT, p, m);
    EXPECT_NEAR(wlc_pow_dudl(l0, lm, kT, p, kp, m), 0.0, 1e-12 * kT / p);
    const double mu = shear_modulus(l0, x0, kT, p, m);
    const double fedosov = std::sqrt(3.0) * kT / (4 * p * lm * x0) *
                               (x0 / (2 * std::pow(1 - x0, 3)) - 1 / (4 * std::pow(1 - x0, 2)) + 0.25) +
                           std::sqrt(3.0) * kp * (m + 1) / (4 * std::pow(l0, m + 1));
    EXPECT_NEAR(mu / fedosov, 1.0, 1e-12);
    // Three bonds per lattice site at 0, 60 and 120 degrees; area per site sqrt(3)/2 l0^2.
    auto energy_density = [&](double e) {
      double w = 0;
      for (int k = 0; k < 3; ++k) {
        const double phi = k * std::numbers::pi / 3;
        const double dx = l0 * std::cos(phi) * (1 + e), dy = l0 * std::sin(phi) / (1 + e);
        w += wlc_pow_energy(std::hypot(dx, dy), lm, kT, p, kp, m) - wlc_pow_energy(l0, lm, kT, p, kp, m);
      }
      return w / (std::sqrt(3.0) / 2 * l0 * l0);
    };
    const double e = 1e-3;
    const double measured = (energy_density(e) + energy_density(-e)) / 2 / (2 * e * e);
    EXPECT_NEAR(measured / mu, 1.0, 2e-3) << "m = " << m;
    EXPECT_NEAR(persistence_for(mu, l0, x0, kT, m), p, 1e-12);
  }
}

class MeshFile : public ::testing::Test {
 protected:
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("mesodpd_mesh_" + std::to_string(::getpid()) + ".off");
  void TearDown() override { std::filesystem::remove(path); }
  void write(const Mesh& m, bool reverse = false) {
    std::ofstream out(path);
    out << "OFF\n# a comment\n" << m.vertices.size() << " " << m.triangles.size() << " 0\n";
    for (const Vec3& p : m.vertices) out << p.x << " " << p.y << " " << p.z << "\n";
    for (const auto& t : m.triangles) out << "3 " << t[0] << " " << (reverse ? t[2] : t[1]) << " " << (reverse ? t[1] : t[2]) << "\n";
  }
  std::string error_of(const Mesh& m) {
    try {
      check_closed(m, "cell.off");
    } catch (const MeshError& e) {
      return e.what();
    }
    return "";
  }
};

TEST_F(MeshFile, OffFilesReadBackOutwardOriented) {
  const Mesh sphere = geodesic_sphere(3, 1.5);
  write(sphere, true);  // inward: read_off turns it round
  const Mesh m = read_off(path.string());
  ASSERT_EQ(m.vertices.size(), sphere.vertices.size());
  EXPECT_GT(mesh_volume(m, m.vertices), 0);
  EXPECT_NEAR(mesh_volume(m, m.vertices), mesh_volume(sphere, sphere.vertices), 1e-4);
}

TEST_F(MeshFile, BadMeshesAreRefusedNamingTheProblem) {
  const Mesh sphere = geodesic_sphere(2, 1.0);
  Mesh open = sphere;
  open.triangles.pop_back();
  EXPECT_NE(error_of(open).find("not closed"), std::string::npos) << error_of(open);
  Mesh flipped = sphere;
  std::swap(flipped.triangles[5][1], flipped.triangles[5][2]);
  EXPECT_NE(error_of(flipped).find("not consistently oriented"), std::string::npos) << error_of(flipped);
  Mesh flat = sphere;
  const auto t = flat.triangles[3];
  flat.vertices[t[2]] = 0.5 * (flat.vertices[t[0]] + flat.vertices[t[1]]);
  EXPECT_NE(error_of(flat).find("triangle 3"), std::string::npos) << error_of(flat);
  EXPECT_NE(error_of(flat).find("zero area"), std::string::npos) << error_of(flat);
  Mesh stray = sphere;
  stray.vertices.push_back({5, 5, 5});
  EXPECT_NE(error_of(stray).find("is in no triangle"), std::string::npos) << error_of(stray);
  // A file: the line of a bad face.
  {
    std::ofstream out(path);
    out << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n4 0 3 2 1\n3 1 2 3\n";
  }
  try {
    read_off(path.string());
    FAIL() << "a quad was accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ":9: face 2: only triangles"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_off((path.string() + ".missing")), MeshError);
}

// A WLC-POW edge at its maximum length has an infinite force: forces() names it and adds nothing.
TEST(MembraneForces, AnEdgePastItsMaximumLengthIsNamed) {
  const Mesh mesh = geodesic_sphere(2, 1.0);
  Parameters p;
  p.persistence = 0.1;
  p.x0 = 0.5;
  const CellModel cell(mesh, p);
  std::vector<Vec3> x = mesh.vertices;
  const Hinge h = cell.hinges()[17];
  x[h.c] = x[h.b] + 2.5 * (x[h.c] - x[h.b]);
  std::vector<Vec3> f(x.size());
  std::size_t broken = 0;
  EXPECT_FALSE(cell.forces(x, f, &broken));
  const Hinge bad = cell.hinges()[broken];
  EXPECT_TRUE(bad.b == h.c || bad.c == h.c);
  for (const Vec3& v : f) EXPECT_EQ(dot(v, v), 0.0);
}

// The edge noise, uniform (the default) and Gaussian: the same nine variates for (a, b) and (b, a), each
// of mean 0 and variance 1 and uncorrelated with the others (over 20,000 edge-steps: standard errors
// 0.007 and 0.01); the uniform ones within +-sqrt(3), the Gaussian ones beyond it now and then (about
// 8 % of them) and with the normal's fourth moment 3 (the uniform's is 1.8).
TEST(MembraneViscosity, EdgeNoiseIsSymmetricWithUnitVariance) {
  for (const NoiseKind kind : {NoiseKind::Uniform, NoiseKind::Gaussian}) {
    double w[9], u[9], sum[9] = {}, sq[9] = {}, cross01 = 0, cross48 = 0, fourth = 0, widest = 0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) {
      const auto a = static_cast<std::uint32_t>(k % 97), b = static_cast<std::uint32_t>(100 + k % 89);
      edge_noise(7, static_cast<std::uint64_t>(k), a, b, w, kind);
      edge_noise(7, static_cast<std::uint64_t>(k), b, a, u, kind);
      for (int i = 0; i < 9; ++i) {
        ASSERT_EQ(w[i], u[i]);
        sum[i] += w[i];
        sq[i] += w[i] * w[i];
        fourth += w[i] * w[i] * w[i] * w[i];
        widest = std::max(widest, std::abs(w[i]));
      }
      cross01 += w[0] * w[1];
      cross48 += w[4] * w[8];
    }
    const char* name = kind == NoiseKind::Uniform ? "uniform" : "gaussian";
    for (int i = 0; i < 9; ++i) {
      EXPECT_NEAR(sum[i] / n, 0.0, 0.03) << name << " " << i;
      EXPECT_NEAR(sq[i] / n, 1.0, 0.05) << name << " " << i;
    }
    EXPECT_NEAR(cross01 / n, 0.0, 0.04) << name;
    EXPECT_NEAR(cross48 / n, 0.0, 0.04) << name;
    EXPECT_NEAR(fourth / (9.0 * n), kind == NoiseKind::Uniform ? 1.8 : 3.0, 0.1) << name;
    if (kind == NoiseKind::Uniform) {
      EXPECT_LT(widest, std::sqrt(3.0));
    } else {
      EXPECT_GT(widest, 3.0);
    }
  }
}

// A cell moving as a whole feels no viscous force (without noise: kT = 0), and the forces of any
// motion sum to zero (momentum is conserved; the gamma_T term is not central, so angular momentum is not,
// as in Fedosov et al. 2010).
TEST(MembraneViscosity, DissipationActsOnRelativeVelocitiesAndConservesMomentum) {
  Parameters p;
  p.kT = 0.0;
  p.gamma_t = 3.0;
  p.gamma_c = 2.0;
  const Mesh m = geodesic_sphere(3, 3.0);
  const CellModel cell(m, p);
  std::vector<Vec3> v(m.vertices.size(), Vec3{0.3, -0.2, 0.5}), f(m.vertices.size());
  cell.viscous_forces(m.vertices, v, 0.01, 1, 1, 0, f);
  for (const Vec3& g : f) EXPECT_EQ(dot(g, g), 0.0);
  const std::vector<Vec3> random_v = jiggled(std::vector<Vec3>(m.vertices.size()), 1.0, 5);
  f.assign(m.vertices.size(), Vec3{});
  cell.viscous_forces(m.vertices, random_v, 0.01, 1, 1, 0, f);
  Vec3 total;
  double power = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    total += f[i];
    power += dot(f[i], random_v[i]);
  }
  EXPECT_LT(norm(total), 1e-12);
  EXPECT_LT(power, 0.0);  // dissipation removes kinetic energy
}

// Fluctuation-dissipation: a cell of 92 vertices (m = 1) held together by its WLC-POW edges and
// thermostatted only by the membrane viscosity reaches the kinetic temperature kT. Integrated by
// velocity Verlet with the forces at the predicted velocity (Groot-Warren, lambda = 1/2); at dt = 0.002
// and gamma dt <= 0.006 the time-step error is far below the 2 % tolerance, which the statistics
// (90,000 velocity samples over 40 relaxation times) meet with a margin of about 4 standard errors.
// Both noise distributions (uniform, the default, and Gaussian).
TEST(MembraneViscosity, TheEdgeThermostatReachesKT) {
  for (const NoiseKind kind : {NoiseKind::Uniform, NoiseKind::Gaussian})
  for (const auto& [gt, gc] : {std::pair{3.0, 1.0}, std::pair{1.0, 2.0}}) {
    Parameters p;
    p.noise = kind;
    p.kT = 1.0;
    p.persistence = 1.0;
    p.gamma_t = gt;
    p.gamma_c = gc;
    const Mesh m = geodesic_sphere(3, 3.0);
    p.persistence = persistence_for(50.0, CellModel(m, Parameters{}).mean_length(), p.x0, p.kT, p.m);
    const CellModel cell(m, p);
    const std::size_t n = m.vertices.size();
    std::vector<Vec3> x = m.vertices, v(n), f(n), fn(n), vp(n);
    const double dt = 0.002;
    auto all = [&](std::uint64_t step, const std::vector<Vec3>& vel, std::vector<Vec3>& out) {
      out.assign(n, Vec3{});
      ASSERT_TRUE(cell.forces(x, out).has_value());
      cell.viscous_forces(x, vel, dt, 11, step, 0, out);
    };
    all(0, v, f);
    double sum = 0;
    int samples = 0;
    for (std::uint64_t step = 1; step <= 40000; ++step) {
      for (std::size_t i = 0; i < n; ++i) {
        x[i] += dt * v[i] + (0.5 * dt * dt) * f[i];
        vp[i] = v[i] + (0.5 * dt) * f[i];
      }
      all(step, vp, fn);
      for (std::size_t i = 0; i < n; ++i) v[i] = vp[i] + (0.5 * dt) * fn[i];
      f.swap(fn);
      if (step > 10000 && step % 100 == 0) {
        double k = 0;
        for (const Vec3& u : v) k += dot(u, u);
        sum += k / static_cast<double>(3 * n - 3);
        ++samples;
      }
    }
    const char* name = kind == NoiseKind::Uniform ? "uniform" : "gaussian";
    std::printf("%s noise, gamma_T %g, gamma_C %g: mean kinetic temperature %.4f\n", name, gt, gc, sum / samples);
    EXPECT_NEAR(sum / samples, 1.0, 0.02) << name << " noise, gamma_T " << gt << ", gamma_C " << gc;
  }
}

}  // namespace
}  // namespace mesodpd::membrane
