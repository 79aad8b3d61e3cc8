// The DPD pair force law (seed 000 Eqs. 2-8), written once and called by every backend.
// Includes only our vector type and <cmath>, so it compiles under nvcc as well as g++. Written without
// branches (selects only) so that a loop over pairs vectorises.
#pragma once
#include <cmath>

#include "core/vec3.hpp"

namespace mesodpd {

// Parameters for one species pair. All lengths in units of the reference cutoff.
struct DpdPairParams {
  double a = 0.0;       // conservative amplitude a_ij (seed 000 Eq. 3)
  double gamma = 0.0;   // dissipative strength gamma_ij (seed 000 Eq. 4)
  double sigma = 0.0;   // random amplitude sigma_ij, sigma^2 = 2 gamma k_BT (seed 000 Eq. 7)
  double rc = 1.0;      // conservative cutoff r_c
  double rd = 1.0;      // dissipative/random cutoff r_d (seed 000 Eq. 8)
  double s = 2.0;       // weight exponent: w_D = w_R^2 = (1 - r/r_d)^s (seed 000 Eq. 8)
  double rcut2 = 1.0;   // max(rc, rd)^2, the interaction range of this pair
};

// The three parts of the force on i due to j, each along r_hat_ij, kept apart because the
// virial and the conservative pressure need them separately.
struct DpdPairForce {
  double fc = 0.0;      // conservative magnitude along r_hat
  double fd = 0.0;      // dissipative magnitude along r_hat
  double fr = 0.0;      // random magnitude along r_hat
  double energy = 0.0;  // U_ij = a rc/2 (1 - r/rc)^2, whose -dU/dr is the conservative force
};

// Which exponent the weight w_D = (1 - r/r_d)^s has. The common ones get exact closed forms (no pow),
// chosen once per parameter table so the pair loop does not branch on s.
enum class WeightKind { Two, One, Half, Quarter, General };

MESODPD_HD WeightKind weight_kind_of(double s) {
  return s == 2.0 ? WeightKind::Two
         : s == 1.0 ? WeightKind::One
         : s == 0.5 ? WeightKind::Half
         : s == 0.25 ? WeightKind::Quarter
                     : WeightKind::General;
}

// w_D(om) and w_R(om) = sqrt(w_D(om)) for om = 1 - r/r_d >= 0 (seed 000 Eqs. 6, 8).
template <WeightKind W>
MESODPD_HD void dpd_weights(double om, double s, double& wd, double& wr) {
  if constexpr (W == WeightKind::Two) {
    wd = om * om;
    wr = om;
  } else if constexpr (W == WeightKind::One) {
    wd = om;
    wr = std::sqrt(om);
  } else if constexpr (W == WeightKind::Half) {
    wd = std::sqrt(om);
    wr = std::sqrt(wd);
  } else if constexpr (W == WeightKind::Quarter) {
    wd = std::sqrt(std::sqrt(om));
    wr = std::sqrt(wd);
  } else {
    wd = std::pow(om, s);
    wr = std::pow(om, 0.5 * s);
  }
}

// Force magnitudes for a pair at distance r (0 <= r) with r_hat . v_ij = rv.
// xi is the symmetric unit-variance noise and inv_sqrt_dt = 1/sqrt(dt) (the random force
// scales as dt^-1/2 so that its impulse has the Wiener increment's variance).
// A pair at r = 0 has no defined direction: it gets zero force rather than NaN.
template <WeightKind W = WeightKind::General>
MESODPD_HD DpdPairForce dpd_pair_force(const DpdPairParams& p, double r, double rv, double xi, double inv_sqrt_dt) {
  const bool apart = r > 0.0;
  const double wc = (apart && r < p.rc) ? 1.0 - r / p.rc : 0.0;  // seed 000 Eq. 3
  const double om = (apart && r < p.rd) ? 1.0 - r / p.rd : 0.0;
  double wd, wr;
  dpd_weights<W>(om, p.s, wd, wr);
  DpdPairForce out;
  out.fc = p.a * wc;
  out.energy = 0.5 * p.a * p.rc * wc * wc;
  out.fd = -p.gamma * wd * rv;                 // seed 000 Eq. 4
  out.fr = p.sigma * wr * xi * inv_sqrt_dt;    // seed 000 Eq. 5
  return out;
}

}  // namespace mesodpd
