// Internal to the pair loop (engine/force_compute.cpp): the per-thread batch of candidate pairs with the
// arrays of the evaluation passes, and the description of one pair computation handed to the loop
// compiled for the CPU's instruction set.
#pragma once
#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "engine/fixed_point.hpp"
#include "engine/force_compute.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

// Pairs (i, j) waiting for evaluation, with the arrays of the evaluation passes. Arrays that vector
// stores may overrun carry kSlack extra entries (one vector of the widest target).
struct PairBatch {
  static constexpr std::size_t kCapacity = 1024;
  static constexpr std::size_t kSlack = 16;
  std::size_t m = 0;
  alignas(64) std::uint32_t i[kCapacity + kSlack];
  // Copies of particle i's position, velocity and id for every pair, written a vector at a time when
  // the pairs of one i are appended, so the passes read them contiguously instead of gathering.
  alignas(64) double ix[kCapacity + kSlack], iy[kCapacity + kSlack], iz[kCapacity + kSlack];
  alignas(64) double ivx[kCapacity + kSlack], ivy[kCapacity + kSlack], ivz[kCapacity + kSlack];
  alignas(64) std::uint32_t iid[kCapacity + kSlack];
  alignas(64) std::uint32_t j[kCapacity + kSlack];  // compressed stores may run past m
  // Copies of particle j's position, velocity and id, gathered once per batch so that the evaluation
  // passes read contiguous arrays (and vectorise on targets without fast gathers).
  alignas(64) double jx[kCapacity + kSlack], jy[kCapacity + kSlack], jz[kCapacity + kSlack];
  alignas(64) double jvx[kCapacity + kSlack], jvy[kCapacity + kSlack], jvz[kCapacity + kSlack];
  alignas(64) std::uint32_t jid[kCapacity + kSlack];
  // Force components (or density contributions in fx) in double before the fixed-point conversion.
  alignas(64) double fx[kCapacity], fy[kCapacity], fz[kCapacity];
  alignas(64) PairReal dx[kCapacity];
  alignas(64) PairReal dy[kCapacity];
  alignas(64) PairReal dz[kCapacity];
  alignas(64) PairReal r[kCapacity];
  alignas(64) PairReal inv_r[kCapacity];
  alignas(64) PairReal rv[kCapacity];
  alignas(64) PairReal xi[kCapacity];
  // Non-central laws (kNonCentral): the velocity difference v_ij as a vector; laws with noise words
  // (kNoiseWords): their symmetric noises.
  alignas(64) PairReal dvx[kCapacity], dvy[kCapacity], dvz[kCapacity];
  alignas(64) PairReal xm[kMaxNoiseWords][kCapacity];
  alignas(64) std::int64_t qx[kCapacity];
  alignas(64) std::int64_t qy[kCapacity];
  alignas(64) std::int64_t qz[kCapacity];
  // Laws with per-particle scalars (kScalars; physics/pair_force.hpp), per scalar: its values at i and
  // j, the antisymmetric noise, the rates of i and j in double and in fixed point. Channels a run does
  // not use hold zeros (evaluate_batch).
  alignas(64) double si[kMaxScalars][kCapacity + kSlack], sj[kMaxScalars][kCapacity + kSlack];
  alignas(64) PairReal xs[kMaxScalars][kCapacity];
  alignas(64) double hi[kMaxScalars][kCapacity], hj[kMaxScalars][kCapacity];
  alignas(64) std::int64_t qhi[kMaxScalars][kCapacity], qhj[kMaxScalars][kCapacity];
  // Candidates of the current cell, nearest-image coordinates relative to a particle of the cell.
  std::vector<PairReal> cand_x, cand_y, cand_z;
  std::vector<std::uint32_t> cand_j;
  std::vector<std::uint32_t> cand_body;  // body of each candidate, gathered only when frozen particles exist
  // The pair of the batch (smallest ids) whose contribution left the fixed-point range, if any; set by
  // the passes, taken by the accumulation.
  std::optional<FixedPointOverflow> overflow;
  void note_overflow(std::uint32_t id_i, std::uint32_t id_j, double value, FixedPointOverflow::What what) {
    const std::uint32_t a = std::min(id_i, id_j), c = std::max(id_i, id_j);
    if (overflow && (overflow->id_a < a || (overflow->id_a == a && overflow->id_b <= c))) return;
    overflow = FixedPointOverflow{what, a, c, value, 0.0};
  }
};

struct PairWorkspace {
  std::vector<std::vector<std::int64_t>> buffers;  // per thread: components interleaved; all zero between calls
  std::vector<std::int64_t> fixed;                 // summed over threads, when there are ghosts
  std::vector<std::unique_ptr<PairBatch>> batches;  // per thread
};

// One pair computation. Forces: `laws` set, results in p.f{x,y,z} (no ghosts) or `ws->fixed` (3 per
// particle; 3 + kScalars for a law with scalars, whose rates go to `rate`). Density: `density` set,
// results in `out` (no ghosts) or `ws->fixed` (1 per particle).
struct PairJob {
  ParticleData* p = nullptr;
  const Box* box = nullptr;
  const NeighborList* list = nullptr;
  const PairLawTables* laws = nullptr;
  const DensitySettings* density = nullptr;
  const double* rho = nullptr;  // local density of locals and ghosts, for laws with kDensity
  double* out = nullptr;
  // A law with scalars (kScalars): the first n_scalars of its kScalarFields are held, read from
  // `scalar` and their rates written to `rate` (the ghost path leaves them in ws->fixed).
  int n_scalars = 0;
  const double* scalar[kMaxScalars] = {};
  double* rate[kMaxScalars] = {};
  std::uint64_t step = 0;
  double dt = 1;
  NoiseSettings noise;
  bool with_sums = false;
  // The ghost exchange is active (a decomposed run): the sums take the ghost path on every rank, also
  // on one that holds no ghosts, since returning ghost totals to their owners is collective.
  bool exchange = false;
  PairWorkspace* ws = nullptr;
  // Integer sums of this rank: [0..5] virial tensor, [6] conservative virial trace, [7] energy, [8] pairs.
  std::int64_t totals[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  // Listed pairs instead of the traversal (ForceCompute::subtract_pairs): storage indices i, j of pair k at
  // pairs[2k], pairs[2k + 1]; their forces are subtracted from `subtract_into` (3 per particle) and
  // their sums from `totals`.
  const std::uint32_t* pairs = nullptr;
  std::size_t n_pairs = 0;
  std::int64_t* subtract_into = nullptr;
  // The largest |value x scale| of one pair's contribution taken (engine/fixed_point.hpp), and the
  // first pair found past it (smallest first id over the threads), if any.
  double fixed_limit = kPairFixedLimit;
  std::optional<FixedPointOverflow> overflow;
};

}  // namespace mesodpd
