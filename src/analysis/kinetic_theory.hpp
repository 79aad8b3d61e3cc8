// Kinetic-theory estimates (g(r) = 1) of DPD transport coefficients, used to check measured values.
#pragma once
#include <numbers>

#include "mesodpd/spec.hpp"

namespace mesodpd {

// Self-diffusion coefficient for dissipative weight w_D = (1 - r/r_d)^s, unit particle mass.
// The Groot-Warren/Marsh estimate D = 3 kT / (gamma rho Int w_D d^3r) with g(r) = 1; the
// integral is 4 pi r_d^3 * 2 / ((s+1)(s+2)(s+3)), giving 45/(2 pi), 9/pi and 315/(64 pi) for
// s = 2, 1, 1/2 (seed 000 Table 1). Valid for any s > -1.
inline double kinetic_diffusivity(double rho, double gamma, double kT, double rd, double s) {
  return 3.0 * kT * (s + 1.0) * (s + 2.0) * (s + 3.0) / (8.0 * std::numbers::pi * gamma * rho * rd * rd * rd);
}

// The moment Int_0^1 x^4 (1 - x)^s dx of a weight (1 - r/r_d)^s, as seed 000 Eq. 16's bracket writes it
// (the binomial expanded, hence five terms; it equals 24 / ((s+1)(s+2)(s+3)(s+4)(s+5))). The friction of a
// pair weighted by r^2 over a sphere of neighbours: the dissipative viscosity below and single-particle
// DPD's spin relaxation rate (engine/install_spdpd.cpp).
inline double weight_moment4(double s) {
  return 1.0 / (s + 1.0) - 4.0 / (s + 2.0) + 6.0 / (s + 3.0) - 4.0 / (s + 4.0) + 1.0 / (s + 5.0);
}

// Dissipative (collisional) part of the shear viscosity, seed 000 Eq. 16.
inline double kinetic_dissipative_viscosity(double rho, double gamma, double rd, double s) {
  const double rd5 = rd * rd * rd * rd * rd;
  return 2.0 * std::numbers::pi * gamma * rho * rho * rd5 / 15.0 * weight_moment4(s);
}

// Total shear viscosity = kinetic part rho D / 2 (unit mass) + dissipative part (seed 000 Table 1).
inline double kinetic_viscosity(double rho, double gamma, double kT, double rd, double s) {
  return rho * kinetic_diffusivity(rho, gamma, kT, rd, s) / 2.0 +
         kinetic_dissipative_viscosity(rho, gamma, rd, s);
}

// The kinetic-theory viscosity of a run's fluid, or the reason it has none. The formulas above are for
// one species of unit mass; they do not involve the conservative force (g(r) = 1). So a mixture whose
// species all have unit mass and whose pairs all share gamma, r_d and s (only a differs, the usual way
// to make species immiscible) is, to kinetic theory, that one fluid, and gets its value. Pairs that
// differ in gamma, r_d or s, or masses other than 1, would need a mixture theory (per-species friction
// and cross terms) that we do not implement: then `applies` is false and `why_not` says why, rather than
// quoting the (0, 0) pair's value as if it described the whole fluid.
struct KineticViscosity {
  bool applies = false;
  double eta = 0.0;                  // seed 000 Eq. 16 / Table 1 with the shared pair parameters
  double gamma = 0.0, rd = 0.0, s = 0.0;  // the shared pair parameters (where `applies`)
  const char* why_not = "";          // where not `applies`: what differs
};

inline KineticViscosity kinetic_viscosity_of(const SimulationSpec& spec, double rho) {
  KineticViscosity out;
  const int n = static_cast<int>(spec.species.size());
  for (int a = 0; a < n; ++a)
    if (spec.species[static_cast<std::size_t>(a)].mass != 1.0) {
      out.why_not = "species masses other than 1";
      return out;
    }
  const PairSpec& first = spec.pair(0, 0);
  for (int a = 0; a < n; ++a)
    for (int b = a; b < n; ++b) {
      const PairSpec& p = spec.pair(a, b);
      if (p.gamma != first.gamma || p.rd != first.rd || p.s != first.s) {
        out.why_not = "species pairs with different gamma, r_d or s";
        return out;
      }
    }
  if (first.gamma == 0.0) {  // a conservative pair law (e.g. under [thermostat]): the formulas diverge
    out.why_not = "pair.gamma = 0 (no pair friction)";
    return out;
  }
  out.applies = true;
  out.gamma = first.gamma;
  out.rd = first.rd;
  out.s = first.s;
  out.eta = kinetic_viscosity(rho, first.gamma, spec.kT, first.rd, first.s);
  return out;
}

}  // namespace mesodpd
