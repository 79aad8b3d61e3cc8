// The CPU pair backend: the shared pair loop (cell or Verlet traversal, SIMD distance filter, batched
// evaluation, fixed-point accumulation) run with a force law from engine/pair_laws.hpp, or with a
// density kernel for a first pass of a multi-pass model. Results do not depend on thread count, rank
// count or pair order.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <span>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "core/philox.hpp"
#include "engine/fixed_point.hpp"
#include "engine/pair_backend.hpp"
#include "engine/pair_laws.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"
#include "physics/density_kernel.hpp"

namespace mesodpd {

struct PairWorkspace;  // per-thread batches and integer buffers (engine/pair_batch.hpp)

// The CPU backend: the pair loop over OpenMP threads with the SIMD instruction set chosen at run time
// (Google Highway). Contracts of the calls in engine/pair_backend.hpp.
class ForceCompute final : public PairBackend {
 public:
  ForceCompute(PairLawTables laws, NoiseSettings noise);
  ~ForceCompute() override;
  ForceCompute(ForceCompute&&) noexcept;
  ForceCompute& operator=(ForceCompute&&) noexcept;

  void compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step, double dt,
               bool with_sums, PairSums& sums, Halo* halo, const double* density) override;
  void compute_density(ParticleData& p, const Box& box, const NeighborList& list, const DensitySettings& density,
                       std::span<double> rho, Halo* halo) override;
  // Serial (the lists are short: bonded pairs), with the loop's own evaluation passes.
  void subtract_pairs(ParticleData& p, const Box& box, std::span<const std::uint32_t> pairs, std::uint64_t step,
                      double dt, bool with_sums, std::int64_t* fixed, std::int64_t* totals,
                      const double* density) override;

  const PairLawTables& laws() const override { return laws_; }
  std::optional<FixedPointOverflow> take_overflow() override { return std::exchange(overflow_, std::nullopt); }

  // The instruction set the pair loop runs with on this CPU (e.g. "AVX3", "AVX2", "SSE4"), chosen at
  // run time. The environment variable MESODPD_SIMD = avx512 | avx2 | sse4 | scalar caps it (for
  // benchmarks and tests of the other paths); it is read once, at the first pair computation.
  static std::string simd_target();
  // The instruction sets (Highway target bits) the pair loop was compiled for that this CPU runs, best
  // first: tests run each of them.
  static std::vector<std::int64_t> simd_targets();

 private:
  PairLawTables laws_;
  NoiseSettings noise_;
  std::unique_ptr<PairWorkspace> ws_;
  std::optional<FixedPointOverflow> overflow_;  // since the last take_overflow()
  double fixed_limit_ = kPairFixedLimit;        // the per-pair limit of the last loop (listed pairs reuse it)
  void note(const std::optional<FixedPointOverflow>& found);
};

}  // namespace mesodpd
