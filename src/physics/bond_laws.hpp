// Bonded force laws, once, as host/device functions: bond springs (harmonic with a rest length, FENE,
// worm-like chain) and the cosine angle potential. Any backend calls the same lines; the engine's
// bonded stage (engine/bonded_forces.cpp) adds the fixed-point accumulation and the lookup by id.
#pragma once
#include <cmath>

#include "core/hd.hpp"

namespace mesodpd {

enum class BondStyle : int { Harmonic = 0, Fene = 1, Wlc = 2 };

// Parameters of one bond type. Which members are read depends on the style:
//   harmonic  U = k/2 (r - r0)^2                                   (k, r0)
//   fene      F = -k r / (1 - (r/rmax)^2)     (seed 000 Eq. 27, H = k, r_m = rmax)
//             U = -k rmax^2 / 2 ln(1 - (r/rmax)^2)                  (k, rmax)
//   wlc       F = -(kT / 4 l_p) [(1 - r/l)^-2 + 4 r/l - 1]  (seed 000 Eq. 26, l = rmax, k = kT / (4 l_p))
//             U = k [r^2 / (l - r) + 2 r^2 / l]                     (k, rmax)
// FENE and WLC diverge at r = rmax: past it the bond is broken and the force is meaningless.
struct BondParams {
  BondStyle style = BondStyle::Harmonic;
  double k = 0;     // spring constant (harmonic, fene) or kT / (4 l_p) (wlc)
  double r0 = 0;    // rest length (harmonic)
  double rmax = 0;  // maximum extension (fene r_m, wlc l)
};

// Result of one bond: the force on the first atom is f_over_r * (r_1 - r_2) (the second gets the
// opposite), the energy, and whether r reached the maximum extension (then both are zero).
struct BondForce {
  double f_over_r = 0;
  double energy = 0;
  bool broken = false;
};

// The bond law for bond length r > 0 (r = 0 gives a zero force for the laws with a rest length of zero).
MESODPD_HD BondForce bond_force(const BondParams& p, double r) {
  BondForce out;
  switch (p.style) {
    case BondStyle::Harmonic: {
      const double dr = r - p.r0;
      out.energy = 0.5 * p.k * dr * dr;
      // -dU/dr / r; with r0 = 0 this is -k even at r = 0 (no division).
      out.f_over_r = p.r0 == 0.0 ? -p.k : (r > 0.0 ? -p.k * dr / r : 0.0);
      break;
    }
    case BondStyle::Fene: {
      const double x2 = (r * r) / (p.rmax * p.rmax);
      if (!(x2 < 1.0)) {
        out.broken = true;
        break;
      }
      out.f_over_r = -p.k / (1.0 - x2);
      out.energy = -0.5 * p.k * p.rmax * p.rmax * std::log(1.0 - x2);
      break;
    }
    case BondStyle::Wlc: {
      const double l = p.rmax;
      if (!(r < l)) {
        out.broken = true;
        break;
      }
      const double s = 1.0 - r / l;
      const double f = -p.k * (1.0 / (s * s) + 4.0 * r / l - 1.0);  // along r-hat
      // f / r stays finite at r -> 0: (1/s^2 - 1) / r -> 2 / l, 4 / l from the linear term.
      out.f_over_r = r > 0.0 ? f / r : -p.k * 6.0 / l;
      out.energy = p.k * (r * r / (l - r) + 2.0 * r * r / l);
      break;
    }
  }
  return out;
}

// Parameters of one angle type: U = k [1 - cos(theta - theta0)] (seed 002 Eq. 32, the bending
// potential of Shillcock and Lipowsky), theta the angle between the two bond vectors b1 = r_2 - r_1
// and b2 = r_3 - r_2, so a straight triple has theta = 0 (not pi as with LAMMPS's angle at the centre).
struct AngleParams {
  double k = 0;
  double theta0 = 0;  // radians
  double cos0 = 1, sin0 = 0;  // cos(theta0), sin(theta0)
};

inline AngleParams make_angle_params(double k, double theta0) {
  return AngleParams{k, theta0, std::cos(theta0), std::sin(theta0)};
}

// Forces on the three atoms of an angle from the two bond vectors (f2 = -(f1 + f3)).
struct AngleForce {
  double f1[3] = {0, 0, 0};
  double f3[3] = {0, 0, 0};
  double energy = 0;
  double cos_theta = 1;
};

MESODPD_HD AngleForce angle_force(const AngleParams& p, const double b1[3], const double b2[3]) {
  AngleForce out;
  const double n1sq = b1[0] * b1[0] + b1[1] * b1[1] + b1[2] * b1[2];
  const double n2sq = b2[0] * b2[0] + b2[1] * b2[1] + b2[2] * b2[2];
  if (!(n1sq > 0.0) || !(n2sq > 0.0)) return out;  // coincident atoms: no direction, no force
  const double inv12 = 1.0 / std::sqrt(n1sq * n2sq);
  double c = (b1[0] * b2[0] + b1[1] * b2[1] + b1[2] * b2[2]) * inv12;
  c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
  const double s2 = 1.0 - c * c;
  const double s = std::sqrt(s2);
  // U = k [1 - cos(theta) cos0 - sin(theta) sin0]; dU/dcos(theta) = -k [cos0 - sin0 cos(theta) / sin(theta)].
  // With theta0 != 0, U has a cusp at theta = 0 and pi (sin(theta) = 0); sin is floored there.
  constexpr double kMinSin = 1e-8;
  const double dudc = -p.k * (p.cos0 - (p.sin0 != 0.0 ? p.sin0 * c / (s > kMinSin ? s : kMinSin) : 0.0));
  out.energy = p.k * (1.0 - c * p.cos0 - s * p.sin0);
  out.cos_theta = c;
  // dc/db1 = b2 / (|b1||b2|) - c b1 / |b1|^2; dc/db2 = b1 / (|b1||b2|) - c b2 / |b2|^2.
  // b1 = r2 - r1, so F1 = -dU/dr1 = dudc dc/db1; b2 = r3 - r2, so F3 = -dudc dc/db2.
  for (int d = 0; d < 3; ++d) {
    out.f1[d] = dudc * (b2[d] * inv12 - c * b1[d] / n1sq);
    out.f3[d] = -dudc * (b1[d] * inv12 - c * b2[d] / n2sq);
  }
  return out;
}

// The hinge angle theta between the outward normals of the triangles (a, b, c) and (d, c, b) at their
// shared edge b-c (LAMMPS's dihedral i, j, k, l = a, b, c, d), positive where the hinge is convex, 0 when
// the four atoms lie flat with a and d on opposite sides of b-c; and its gradient with respect to each
// atom (the form of Bridson, Marino & Fedkiw, SCA 2003). Positions relative to b: a - b, c - b, d - b.
// Written once for the bonded dihedrals and the membrane's bending (membrane/membrane_forces.cpp).
struct Hinge {
  double theta = 0;
  double ga[3] = {0, 0, 0}, gb[3] = {0, 0, 0}, gc[3] = {0, 0, 0}, gd[3] = {0, 0, 0};
  bool flat = false;  // a triangle of zero area: no normal, no angle and no gradient
};

MESODPD_HD void cross3(const double u[3], const double v[3], double out[3]) {
  out[0] = u[1] * v[2] - u[2] * v[1];
  out[1] = u[2] * v[0] - u[0] * v[2];
  out[2] = u[0] * v[1] - u[1] * v[0];
}
MESODPD_HD double dot3(const double u[3], const double v[3]) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

MESODPD_HD Hinge hinge_angle(const double a[3], const double c[3], const double d[3]) {
  Hinge h;
  const double* e = c;  // c - b
  const double le = std::sqrt(dot3(e, e));
  const double ma[3] = {-a[0], -a[1], -a[2]};                    // b - a
  const double ca[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};  // c - a
  const double cd[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};  // c - d
  const double md[3] = {-d[0], -d[1], -d[2]};                    // b - d
  double n1[3], n2[3], n12[3];
  cross3(ma, ca, n1);
  cross3(cd, md, n2);
  const double q1 = dot3(n1, n1), q2 = dot3(n2, n2);
  if (!(q1 > 0.0) || !(q2 > 0.0) || !(le > 0.0)) {
    h.flat = true;
    return h;
  }
  cross3(n1, n2, n12);
  h.theta = std::atan2(dot3(n12, e) / le, dot3(n1, n2));
  const double ac_e = (a[0] - c[0]) * e[0] + (a[1] - c[1]) * e[1] + (a[2] - c[2]) * e[2];  // (a - c) . e
  const double dc_e = (d[0] - c[0]) * e[0] + (d[1] - c[1]) * e[1] + (d[2] - c[2]) * e[2];  // (d - c) . e
  const double ab_e = dot3(a, e), db_e = dot3(d, e);                                      // (a - b) . e, (d - b) . e
  for (int k = 0; k < 3; ++k) {
    const double u1 = n1[k] / q1, u2 = n2[k] / q2;
    h.ga[k] = -le * u1;
    h.gd[k] = -le * u2;
    h.gb[k] = (-ac_e / le) * u1 + (-dc_e / le) * u2;
    h.gc[k] = (ab_e / le) * u1 + (db_e / le) * u2;
  }
  return h;
}

// Parameters of one dihedral type: U = k [1 - cos(theta - theta0)] with theta the hinge angle above (the
// Kantor-Nelson bending of a triangulated membrane; with theta0 = 0 it is LAMMPS's `dihedral_style
// harmonic` K [1 + d cos(n phi)] with K = k, d = +1, n = 1, whose phi is pi - theta).
struct DihedralParams {
  double k = 0;
  double theta0 = 0;  // radians
};

// Forces on the four atoms of a dihedral (positions relative to b), its energy and its angle.
struct DihedralForce {
  double fa[3] = {0, 0, 0}, fb[3] = {0, 0, 0}, fc[3] = {0, 0, 0}, fd[3] = {0, 0, 0};
  double energy = 0;
  double theta = 0;
};

MESODPD_HD DihedralForce dihedral_force(const DihedralParams& p, const double a[3], const double c[3],
                                               const double d[3]) {
  DihedralForce out;
  const Hinge h = hinge_angle(a, c, d);
  if (h.flat) return out;  // a degenerate triangle: no normal, no force
  out.theta = h.theta;
  out.energy = p.k * (1.0 - std::cos(h.theta - p.theta0));
  const double dudt = p.k * std::sin(h.theta - p.theta0);
  for (int k = 0; k < 3; ++k) {
    out.fa[k] = -dudt * h.ga[k];
    out.fb[k] = -dudt * h.gb[k];
    out.fc[k] = -dudt * h.gc[k];
    out.fd[k] = -dudt * h.gd[k];
  }
  return out;
}

}  // namespace mesodpd
