// The seam between the engine and a pair-loop backend: what Simulation asks of the pair stages. The
// CPU loop (ForceCompute: OpenMP threads, SIMD chosen at run time) is one implementation; a CUDA loop
// calling the same physics headers (src/cuda/) is meant to be another.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "core/philox.hpp"
#include "engine/pair_laws.hpp"
#include "neighbor/neighbor_list.hpp"
#include "parallel/halo.hpp"

namespace mesodpd {

// The random-force settings a backend keys its pair noise on (core/philox.hpp).
struct NoiseSettings {
  std::uint64_t seed = 1;
  NoiseKind kind = NoiseKind::Uniform;
};

// A pair whose contribution left the range the fixed-point sums hold (engine/fixed_point.hpp): the
// run cannot go on with correct sums. `value` is the offending quantity in reduced units (NaN stays NaN).
struct FixedPointOverflow {
  enum class What { PairForce, PairVirial, Density, ScalarRate };  // ScalarRate: dT/dt, dC/dt (kScalars)
  What what = What::PairForce;
  std::uint32_t id_a = 0, id_b = 0;  // the pair's global ids (both 0 when only a total overflowed)
  double value = 0;
  double limit = 0;  // the largest magnitude the sums take for it
};

// Every implementation gives the same bits: forces and sums are accumulated in the fixed point of
// engine/fixed_point.hpp, each pair's integers come from engine/pair_contribution.hpp, so neither the
// backend nor its thread, rank or pair order reaches the results. The calls are once per step, so a
// virtual call costs nothing measurable.
class PairBackend {
 public:
  virtual ~PairBackend() = default;

  // Overwrites p.f{x,y,z} of local particles with the pair forces at step `step` (the random force
  // is keyed on it). With `with_sums`, also fills `sums` (summed over all ranks of `halo`). Forces on
  // ghosts are sent back to their owners through `halo`. `density` (local and ghost entries) is read by
  // laws that depend on the local density (kDensity); nullptr otherwise.
  virtual void compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step, double dt,
                       bool with_sums, PairSums& sums, Halo* halo, const double* density) = 0;

  // A first pair pass: rho[i] = sum over j != i of w(r_ij) for every local particle, with ghost
  // contributions sent back to their owners; then the owners' values are copied to the ghost entries
  // (a forward exchange), so a second pass can read rho of both particles of a pair. Fixed-point sums
  // (2^32 units): bit-identical for any thread and rank count. `rho` has at least p.size() entries
  // (locals, then ghosts): the caller sizes it.
  virtual void compute_density(ParticleData& p, const Box& box, const NeighborList& list,
                               const DensitySettings& density, std::span<double> rho, Halo* halo) = 0;

  // For listed pairs (storage indices i, j of pair k at pairs[2k], pairs[2k + 1], as compute() saw
  // them at `step`), subtracts from `fixed` (3 integers per stored particle) exactly the integers
  // compute() added for them, and with `with_sums` adds the negated virial, energy and pair count to
  // `totals` ([0..5] virial, [6] its conservative trace, [7] energy, [8] pairs). Used to exclude bonded
  // pairs from the pair force (bonds.exclude).
  virtual void subtract_pairs(ParticleData& p, const Box& box, std::span<const std::uint32_t> pairs,
                              std::uint64_t step, double dt, bool with_sums, std::int64_t* fixed,
                              std::int64_t* totals, const double* density) = 0;

  // The first pair (smallest id) whose contribution to the sums of the calls since the last
  // take_overflow() left the fixed-point range, then forgets it; nothing if none did. Checked by the
  // engine after every force evaluation (collectively, in its health check).
  virtual std::optional<FixedPointOverflow> take_overflow() = 0;

  // The law and its tables the backend runs (analyses evaluate the same ones with the reference loop).
  virtual const PairLawTables& laws() const = 0;
  double max_cutoff() const { return mesodpd::max_cutoff(laws()); }
};

// The backend the engine runs: today the CPU loop (engine/force_compute.hpp).
std::unique_ptr<PairBackend> make_pair_backend(PairLawTables laws, NoiseSettings noise);

}  // namespace mesodpd
