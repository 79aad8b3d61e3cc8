// The DPD pair force law (seed 000 Eqs. 2-8), written once and called by every backend.
// Includes only our vector type and <cmath>, so it compiles under nvcc as well as g++.
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

// w_D(r) = (1 - r/r_d)^s; the common exponents get exact fast paths.
MESODPD_HD double dpd_weight_d(double one_minus, double s) {
  if (s == 2.0) return one_minus * one_minus;
  if (s == 1.0) return one_minus;
  if (s == 0.5) return std::sqrt(one_minus);
  if (s == 0.25) return std::sqrt(std::sqrt(one_minus));
  return std::pow(one_minus, s);
}

// Force magnitudes for a pair at distance r (0 <= r) with r_hat . v_ij = rv.
// xi is the symmetric unit-variance noise and inv_sqrt_dt = 1/sqrt(dt) (the random force
// scales as dt^-1/2 so that its impulse has the Wiener increment's variance).
// A pair at r = 0 has no defined direction: it gets zero force rather than NaN.
MESODPD_HD DpdPairForce dpd_pair_force(const DpdPairParams& p, double r, double rv, double xi,
                                       double inv_sqrt_dt) {
  DpdPairForce out;
  if (!(r > 0.0)) return out;
  if (r < p.rc) {
    const double wc = 1.0 - r / p.rc;  // seed 000 Eq. 3
    out.fc = p.a * wc;
    out.energy = 0.5 * p.a * p.rc * wc * wc;
  }
  if (r < p.rd) {
    const double wd = dpd_weight_d(1.0 - r / p.rd, p.s);
    const double wr = dpd_weight_d(1.0 - r / p.rd, 0.5 * p.s);  // w_R = sqrt(w_D), seed 000 Eq. 6
    out.fd = -p.gamma * wd * rv;                               // seed 000 Eq. 4
    out.fr = p.sigma * wr * xi * inv_sqrt_dt;                  // seed 000 Eq. 5
  }
  return out;
}

}  // namespace mesodpd
