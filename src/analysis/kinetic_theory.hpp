// Kinetic-theory estimates (g(r) = 1) of DPD transport coefficients, used to check measured values.
#pragma once
#include <numbers>

namespace mesodpd {

// Self-diffusion coefficient for dissipative weight w_D = (1 - r/r_d)^s, unit particle mass.
// The Groot-Warren/Marsh estimate D = 3 kT / (gamma rho Int w_D d^3r) with g(r) = 1; the
// integral is 4 pi r_d^3 * 2 / ((s+1)(s+2)(s+3)), giving 45/(2 pi), 9/pi and 315/(64 pi) for
// s = 2, 1, 1/2 (seed 000 Table 1). Valid for any s > -1.
inline double kinetic_diffusivity(double rho, double gamma, double kT, double rd, double s) {
  return 3.0 * kT * (s + 1.0) * (s + 2.0) * (s + 3.0) / (8.0 * std::numbers::pi * gamma * rho * rd * rd * rd);
}

// Dissipative (collisional) part of the shear viscosity, seed 000 Eq. 16. The bracket is the
// moment Int_0^1 x^4 (1 - x)^s dx expanded for the binomial, which is why it has five terms.
inline double kinetic_dissipative_viscosity(double rho, double gamma, double rd, double s) {
  const double bracket =
      1.0 / (s + 1.0) - 4.0 / (s + 2.0) + 6.0 / (s + 3.0) - 4.0 / (s + 4.0) + 1.0 / (s + 5.0);
  const double rd5 = rd * rd * rd * rd * rd;
  return 2.0 * std::numbers::pi * gamma * rho * rho * rd5 / 15.0 * bracket;
}

// Total shear viscosity = kinetic part rho D / 2 (unit mass) + dissipative part (seed 000 Table 1).
inline double kinetic_viscosity(double rho, double gamma, double kT, double rd, double s) {
  return rho * kinetic_diffusivity(rho, gamma, kT, rd, s) / 2.0 +
         kinetic_dissipative_viscosity(rho, gamma, rd, s);
}

}  // namespace mesodpd
