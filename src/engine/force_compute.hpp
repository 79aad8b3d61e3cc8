// The pair-force stage: evaluates the DPD force law over candidate pairs on the OpenMP backend,
// accumulating in fixed point so the result is independent of thread count and pair order.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "core/philox.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/pair_table.hpp"

namespace mesodpd {

struct NoiseSettings {
  std::uint64_t seed = 1;
  NoiseKind kind = NoiseKind::Uniform;
};

// Arithmetic type of the pair passes: double, or float with -DMESODPD_SINGLE=ON. Positions,
// velocities and the fixed-point sums stay double/integer either way (docs/performance.md).
#ifdef MESODPD_SINGLE_PRECISION
using PairReal = float;
#else
using PairReal = double;
#endif

struct PairBatch;  // per-thread workspace, defined in force_compute.cpp

class ForceCompute {
 public:
  ForceCompute(PairTable table, NoiseSettings noise);
  ~ForceCompute();
  ForceCompute(ForceCompute&&) noexcept;
  ForceCompute& operator=(ForceCompute&&) noexcept;

  // Overwrites p.f{x,y,z} of local particles with the pair forces at step `step` (the random force
  // is keyed on it). With `with_sums`, also fills `sums` (summed over all ranks of `halo`). Forces on
  // ghosts are sent back to their owners through `halo`.
  void compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step, double dt,
               bool with_sums, PairSums& sums, Halo* halo = nullptr);

  const PairTable& table() const { return table_; }

 private:
  template <bool kSums, WeightKind W>
  void compute_impl(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step, double dt,
                    PairSums& sums, Halo* halo);

  PairTable table_;
  std::vector<DpdPairParamsT<PairReal>> params_real_;  // table_.params in the pair arithmetic type
  NoiseSettings noise_;
  WeightKind weight_kind_ = WeightKind::General;  // shared by all pairs, else General
  std::vector<std::vector<std::int64_t>> buffers_;  // per thread: fx, fy, fz interleaved; all zero between calls
  std::vector<std::int64_t> fixed_;                 // summed over threads, when there are ghosts
  std::vector<std::unique_ptr<PairBatch>> batches_;  // per thread
};

}  // namespace mesodpd
