// What every pair force law receives and returns: the common vocabulary of the force-law functors
// (DESIGN.md "force law as a functor"). Includes nothing but the host/device annotation.
#pragma once
#include "core/hd.hpp"

namespace mesodpd {

// The pair geometry and state a law may read, for the pair (i, j) with r_ij = r_i - r_j. The pair
// loop fills only what the law asks for through its traits (kVelocity, kNoise, kDensity, kTemperature);
// the other members are left zero.
template <class Real>
struct PairInput {
  Real r = 0;            // |r_ij| >= 0
  Real rv = 0;           // r_hat_ij . v_ij (kVelocity)
  Real xi = 0;           // symmetric unit-variance noise, xi_ij = xi_ji (kNoise; seed 000 Eq. 5)
  Real inv_sqrt_dt = 0;  // 1 / sqrt(dt): the random force scales as dt^-1/2 (seed 000 Eq. 7)
  Real rho_i = 0;        // local densities of both particles from a density pass (kDensity)
  Real rho_j = 0;
  Real ti = 0;           // internal temperatures of both particles (kTemperature; eDPD, physics/edpd_pair.hpp)
  Real tj = 0;
  Real xe = 0;           // antisymmetric unit-variance heat noise, xe_ij = -xe_ji (kTemperature)
};

// The force on i due to j as magnitudes along r_hat_ij, kept in parts because the virial, the
// conservative pressure and the energy need them apart. The force on j is the opposite.
template <class Real>
struct PairForceT {
  Real fc = 0;      // conservative
  Real fd = 0;      // dissipative
  Real fr = 0;      // random
  Real energy = 0;  // pair potential energy U_ij (0 where the law has no potential)
  // Laws with kTemperature: the pair's contributions to dT_i/dt and dT_j/dt (not opposite: viscous
  // heating warms both).
  Real qi = 0;
  Real qj = 0;
};

// Whether a law carries per-particle temperatures (kTemperature; false where it does not say).
template <class Law>
inline constexpr bool law_has_temperature = [] {
  if constexpr (requires { Law::kTemperature; })
    return Law::kTemperature;
  else
    return false;
}();

}  // namespace mesodpd
