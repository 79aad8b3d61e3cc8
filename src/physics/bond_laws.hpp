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

}  // namespace mesodpd
