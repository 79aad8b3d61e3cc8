// Stateless counter-based random numbers (Philox-4x32-10, Salmon et al. SC'11), our own implementation.
// The pair noise of DPD is drawn as a pure function of (seed, stream, step, min id, max id), so
// xi_ij = xi_ji exactly and the result does not depend on thread count, rank count or loop order
// (DESIGN.md aim 2). Compiles under nvcc.
#pragma once
#include <cmath>
#include <cstdint>

#include "core/hd.hpp"
#include "core/portable_math.hpp"

namespace mesodpd {

struct Philox4x32 {
  std::uint32_t v[4];
};

// Multiply two 32-bit words giving the high and low halves of the 64-bit product.
MESODPD_HD void mulhilo32(std::uint32_t a, std::uint32_t b, std::uint32_t& hi, std::uint32_t& lo) {
  const std::uint64_t p = static_cast<std::uint64_t>(a) * static_cast<std::uint64_t>(b);
  hi = static_cast<std::uint32_t>(p >> 32);
  lo = static_cast<std::uint32_t>(p);
}

// The published Philox-4x32 multipliers and Weyl key increments (shared with the vector version of the
// pair noise in engine/force_compute.cpp).
inline constexpr std::uint32_t kPhiloxM0 = 0xD2511F53u, kPhiloxM1 = 0xCD9E8D57u;
inline constexpr std::uint32_t kPhiloxW0 = 0x9E3779B9u, kPhiloxW1 = 0xBB67AE85u;
inline constexpr int kPhiloxRounds = 10;

// Ten rounds of the Philox-4x32 bijection.
MESODPD_HD Philox4x32 philox4x32_10(Philox4x32 ctr, std::uint32_t k0, std::uint32_t k1) {
  constexpr std::uint32_t kM0 = kPhiloxM0, kM1 = kPhiloxM1;
  constexpr std::uint32_t kW0 = kPhiloxW0, kW1 = kPhiloxW1;
  for (int round = 0; round < kPhiloxRounds; ++round) {
    std::uint32_t hi0, lo0, hi1, lo1;
    mulhilo32(kM0, ctr.v[0], hi0, lo0);
    mulhilo32(kM1, ctr.v[2], hi1, lo1);
    ctr = Philox4x32{{hi1 ^ ctr.v[1] ^ k0, lo1, hi0 ^ ctr.v[3] ^ k1, lo0}};
    k0 += kW0;
    k1 += kW1;
  }
  return ctr;
}

// Map a 32-bit word to the open interval (0, 1): never exactly 0 or 1, so log() is safe.
MESODPD_HD double u01_open(std::uint32_t w) { return (static_cast<double>(w) + 0.5) * (1.0 / 4294967296.0); }

// Streams separate independent uses of one seed (pair noise, initial velocities, placement, ...).
// PairThermostat: the pair draws of [thermostat] (integrate/pair_thermostat.hpp).
// ScalarNoise, ScalarNoise2: the antisymmetric noises of a law's scalars 1-2 and 3 (pair_noise_with_scalars).
// PairMatrix, PairMatrix2, PairMatrix3: the symmetric noise words of a non-central law (pair_noise_words).
enum class RngStream : std::uint32_t {
  PairNoise = 1, InitVelocity = 2, InitPosition = 3, WallReflection = 4, InitMolecule = 5, PairThermostat = 6,
  ScalarNoise = 7, ScalarNoise2 = 8, PairMatrix = 9, PairMatrix2 = 10, PairMatrix3 = 11
};

// Symmetric pair noise: one draw per unordered pair (i, j) per step. The key holds the seed;
// the counter holds (min id, max id, step low, step high ^ stream).
// The counter's last word: the step's high half and the stream.
MESODPD_HD std::uint32_t pair_counter_word3(std::uint64_t step, RngStream stream) {
  return static_cast<std::uint32_t>(step >> 32) ^ (static_cast<std::uint32_t>(stream) << 24);
}

MESODPD_HD Philox4x32 pair_random_bits(std::uint64_t seed, std::uint64_t step, std::uint32_t id_a,
                                       std::uint32_t id_b, RngStream stream) {
  const std::uint32_t lo = id_a < id_b ? id_a : id_b;
  const std::uint32_t hi = id_a < id_b ? id_b : id_a;
  Philox4x32 ctr{{lo, hi, static_cast<std::uint32_t>(step), pair_counter_word3(step, stream)}};
  return philox4x32_10(ctr, static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32));
}

// Zero-mean, unit-variance uniform variate on (-sqrt3, sqrt3): the variance-matched choice that
// Groot and Warren found statistically equivalent to a Gaussian (seed 000 Sect. 2.5.1).
MESODPD_HD double uniform_unit_variance(std::uint32_t w) { return 1.7320508075688772 * (2.0 * u01_open(w) - 1.0); }

// Standard normal variate by Box-Muller from two words.
MESODPD_HD double gaussian_unit(std::uint32_t w0, std::uint32_t w1) {
  const double r = std::sqrt(-2.0 * std::log(u01_open(w0)));
  return r * std::cos(6.283185307179586 * u01_open(w1));
}

// The same variate for the pair noise, with the logarithm and cosine of core/portable_math.hpp in place
// of the library's: the pair loop draws it a vector of pairs at a time (engine/force_compute.cpp) and the
// scalar reference loop one pair at a time, with the same bits on every SIMD target. (gaussian_unit keeps
// the library functions for the draws made outside the pair loop: initial velocities, wall reflections,
// the pair thermostats; their bits stay as they were.) Agrees with gaussian_unit to a few units in the
// last place (tests/physics/test_pair_force.cpp, PortableMath.*).
MESODPD_HD_FORCE double gaussian_unit_portable(std::uint32_t w0, std::uint32_t w1) {
  const double r = std::sqrt(-2.0 * ln_pos(u01_open(w0)));
  return r * cos_two_pi(u01_open(w1));
}

enum class NoiseKind : int { Uniform = 0, Gaussian = 1 };

MESODPD_HD double pair_noise(std::uint64_t seed, std::uint64_t step, std::uint32_t id_a, std::uint32_t id_b,
                             NoiseKind kind) {
  const Philox4x32 r = pair_random_bits(seed, step, id_a, id_b, RngStream::PairNoise);
  return kind == NoiseKind::Uniform ? uniform_unit_variance(r.v[0]) : gaussian_unit_portable(r.v[0], r.v[1]);
}

// A unit-variance variate of either kind from two words (a uniform one reads the first).
MESODPD_HD double unit_noise(NoiseKind kind, std::uint32_t w0, std::uint32_t w1) {
  return kind == NoiseKind::Uniform ? uniform_unit_variance(w0) : gaussian_unit_portable(w0, w1);
}

// The pair noise xi of pair_noise (the same bits) and n <= 4 unit-variance noises that are antisymmetric,
// xs(a, b) = -xs(b, a) with the positive sign for id_a < id_b, for the scalars a law transports
// (physics/pair_force.hpp, kScalars: eDPD's fluctuating heat flux, tDPD's random solute fluxes). The
// first comes from the other two words of xi's draw; scalars 1 and 2 from one draw of
// RngStream::ScalarNoise, scalar 3 from one of ScalarNoise2 (each draw: words 0-1, then 2-3; a uniform
// variate reads the first word of its pair).
MESODPD_HD void pair_noise_with_scalars(std::uint64_t seed, std::uint64_t step, std::uint32_t id_a, std::uint32_t id_b,
                                        NoiseKind kind, double& xi, double* xs, int n) {
  const double sign = id_a < id_b ? 1.0 : -1.0;
  const Philox4x32 r = pair_random_bits(seed, step, id_a, id_b, RngStream::PairNoise);
  xi = unit_noise(kind, r.v[0], r.v[1]);
  if (n > 0) xs[0] = sign * unit_noise(kind, r.v[2], r.v[3]);
  if (n > 1) {
    const Philox4x32 q = pair_random_bits(seed, step, id_a, id_b, RngStream::ScalarNoise);
    xs[1] = sign * unit_noise(kind, q.v[0], q.v[1]);
    if (n > 2) xs[2] = sign * unit_noise(kind, q.v[2], q.v[3]);
  }
  if (n > 3) {
    const Philox4x32 q = pair_random_bits(seed, step, id_a, id_b, RngStream::ScalarNoise2);
    xs[3] = sign * unit_noise(kind, q.v[0], q.v[1]);
  }
}

// n <= 6 symmetric unit-variance noises, out(a, b) = out(b, a), for a law that draws noise words of its
// own (physics/pair_force.hpp, kNoiseWords: smoothed DPD's Wiener matrix): words 2k and 2k + 1 from one
// draw of stream PairMatrix + k (words 0-1, then 2-3 of the draw; a uniform variate reads the first of
// its pair).
MESODPD_HD void pair_noise_words(std::uint64_t seed, std::uint64_t step, std::uint32_t id_a, std::uint32_t id_b,
                                 NoiseKind kind, double* out, int n) {
  for (int k = 0; 2 * k < n; ++k) {
    const auto stream = static_cast<RngStream>(static_cast<std::uint32_t>(RngStream::PairMatrix) + static_cast<std::uint32_t>(k));
    const Philox4x32 q = pair_random_bits(seed, step, id_a, id_b, stream);
    out[2 * k] = unit_noise(kind, q.v[0], q.v[1]);
    if (2 * k + 1 < n) out[2 * k + 1] = unit_noise(kind, q.v[2], q.v[3]);
  }
}

}  // namespace mesodpd
