// What every pair force law receives and returns: the common vocabulary of the force-law functors
// (DESIGN.md "force law as a functor"). Includes nothing but the host/device annotation.
#pragma once
#include "core/hd.hpp"

namespace mesodpd {

// The most per-particle scalars a law may transport (kScalars): eDPD's temperature, tDPD's
// concentrations.
inline constexpr int kMaxScalars = 4;

// The most symmetric noise words a non-central law may draw per pair (kNoiseWords): smoothed DPD's
// symmetric Wiener matrix (physics/sdpd_pair.hpp) takes six.
inline constexpr int kMaxNoiseWords = 6;

// The pair geometry and state a law may read, for the pair (i, j) with r_ij = r_i - r_j. The pair
// loop fills only what the law asks for through its traits (kVelocity, kNoise, kDensity, kScalars);
// the other members are left zero.
template <class Real>
struct PairInput {
  Real r = 0;            // |r_ij| >= 0
  Real rv = 0;           // r_hat_ij . v_ij (kVelocity)
  Real xi = 0;           // symmetric unit-variance noise, xi_ij = xi_ji (kNoise; seed 000 Eq. 5)
  Real inv_sqrt_dt = 0;  // 1 / sqrt(dt): the random force scales as dt^-1/2 (seed 000 Eq. 7)
  Real rho_i = 0;        // local densities of both particles from a density pass (kDensity)
  Real rho_j = 0;
  // Laws with kScalars = n > 0: scalar s < n of both particles (the law's kScalarFields[s]: eDPD's
  // temperature, physics/edpd_pair.hpp; tDPD's concentrations, physics/tdpd_pair.hpp) and an
  // antisymmetric unit-variance noise for it, xs_ij = -xs_ji. Channels the run does not use are 0.
  Real si[kMaxScalars] = {};
  Real sj[kMaxScalars] = {};
  Real xs[kMaxScalars] = {};
  // Non-central laws (kNonCentral): the pair's displacement r_ij and velocity difference v_ij as vectors
  // (r = |d|; with Lees-Edwards images, v_ij includes the image velocity), and kNoiseWords symmetric
  // unit-variance noises xm_ij = xm_ji of their own (core/philox.hpp, pair_noise_words).
  Real d[3] = {};
  Real dv[3] = {};
  Real xm[kMaxNoiseWords] = {};
};

// The force on i due to j as magnitudes along r_hat_ij, kept in parts because the virial, the
// conservative pressure and the energy need them apart. The force on j is the opposite.
template <class Real>
struct PairForceT {
  Real fc = 0;      // conservative
  Real fd = 0;      // dissipative
  Real fr = 0;      // random
  Real energy = 0;  // pair potential energy U_ij (0 where the law has no potential)
  // Laws with kScalars: the pair's contributions to the rates d s_i/dt and d s_j/dt of each scalar (not
  // opposite in general: viscous heating warms both particles).
  Real qi[kMaxScalars] = {};
  Real qj[kMaxScalars] = {};
  // Non-central laws (kNonCentral): the part of the force on i that is not along r_hat_ij, as a vector
  // added to the central parts (smoothed DPD's shear friction -a_ij v_ij and its matrix noise). The force
  // on j is still the opposite, so momentum is conserved; angular momentum is not, in general.
  Real fn[3] = {};
};

// How many per-particle scalars a law transports (kScalars; 0 where it does not say). Such a law also
// names the particle fields that hold them and their rates (kScalarFields, kScalarRates, in
// core/particle_data.hpp); a run may enable fewer (a leading subset: tDPD with 2 solutes).
template <class Law>
inline constexpr int law_scalars = [] {
  if constexpr (requires { Law::kScalars; })
    return Law::kScalars;
  else
    return 0;
}();

// Whether a law reads the pair's vectors and returns a non-central part (kNonCentral; false where it
// does not say), and how many symmetric noise words it draws per pair (kNoiseWords; 0 where it does not
// say).
template <class Law>
inline constexpr bool law_non_central = [] {
  if constexpr (requires { Law::kNonCentral; })
    return Law::kNonCentral;
  else
    return false;
}();
template <class Law>
inline constexpr int law_noise_words = [] {
  if constexpr (requires { Law::kNoiseWords; })
    return Law::kNoiseWords;
  else
    return 0;
}();

}  // namespace mesodpd
