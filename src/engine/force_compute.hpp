// The pair stages: the shared pair loop (cell or Verlet traversal, SIMD distance filter, batched
// evaluation, fixed-point accumulation) run with a force law from engine/pair_laws.hpp, or with a
// density kernel for a first pass of a multi-pass model. Results do not depend on thread count, rank
// count or pair order.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "core/philox.hpp"
#include "engine/pair_laws.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"
#include "physics/density_kernel.hpp"

namespace mesodpd {

struct NoiseSettings {
  std::uint64_t seed = 1;
  NoiseKind kind = NoiseKind::Uniform;
};


struct PairWorkspace;  // per-thread batches and integer buffers (engine/pair_batch.hpp)

class ForceCompute {
 public:
  ForceCompute(PairLawTables laws, NoiseSettings noise);
  ~ForceCompute();
  ForceCompute(ForceCompute&&) noexcept;
  ForceCompute& operator=(ForceCompute&&) noexcept;

  // Overwrites p.f{x,y,z} of local particles with the pair forces at step `step` (the random force
  // is keyed on it). With `with_sums`, also fills `sums` (summed over all ranks of `halo`). Forces on
  // ghosts are sent back to their owners through `halo`. `density` (local and ghost entries) is read by
  // laws that depend on the local density (kDensity); nullptr otherwise.
  void compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step, double dt,
               bool with_sums, PairSums& sums, Halo* halo = nullptr, const double* density = nullptr);

  // A first pair pass: rho[i] = sum over j != i of w(r_ij) for every local particle, with ghost
  // contributions sent back to their owners; then the owners' values are copied to the ghost entries
  // (a forward exchange), so a second pass can read rho of both particles of a pair. Fixed-point sums
  // (2^32 units): bit-identical for any thread and rank count. `rho` is resized to p.size().
  void compute_density(ParticleData& p, const Box& box, const NeighborList& list, const DensitySettings& density,
                       std::vector<double>& rho, Halo* halo = nullptr);

  // For listed pairs (storage indices i, j of pair k at pairs[2k], pairs[2k + 1], as compute() saw
  // them at `step`), subtracts from `fixed` (3 integers per stored particle) exactly the integers
  // compute() added for them, computed by the same passes, and with `with_sums` adds the negated
  // virial, energy and pair count to `totals` ([0..5] virial, [6] its conservative trace, [7] energy,
  // [8] pairs). Used to exclude bonded pairs from the pair force (bonds.exclude). Serial.
  void subtract_pairs(ParticleData& p, const Box& box, std::span<const std::uint32_t> pairs, std::uint64_t step,
                      double dt, bool with_sums, std::int64_t* fixed, std::int64_t* totals,
                      const double* density = nullptr);

  const PairLawTables& laws() const { return laws_; }
  double max_cutoff() const { return mesodpd::max_cutoff(laws_); }

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
};

}  // namespace mesodpd
