// The pressure tensor binned along one axis ([analysis.stress_profile]): the lateral stress profile of
// a membrane or an interface and its tension integral (issue 12, "Amphiphiles"; seed 002 "Amphiphilic
// Systems": the lateral stress profile of Shillcock and Lipowsky's bilayers).
//
// Each sample (on the root, from the whole system in id order, so the result depends on neither ranks
// nor threads) divides the box into `bins` slabs of width h = L / bins normal to the axis and adds, per
// slab of volume V_b = V / bins, the diagonal of
//   P_b = (1 / V_b) [ sum_{i in b} m_i u_i (x) u_i  +  sum over virial terms of their share in b of d (x) f ]
// with u_i the velocity minus the centre-of-mass velocity of the mobile particles (zero in a run that
// conserves momentum from a start at rest; frozen wall particles have no kinetic part, as in thermo).
// The virial terms (core/pair_sums.hpp: one per conservative pair force, bond, and two per angle) come
// from the engine. The dissipative and random pair forces are left out: they average to zero in
// equilibrium (seed 000 Eq. 24) and depend on the step's predicted velocities, which the end of a step no
// longer has. Two ways to share a term's virial between slabs (StressAssignment):
//   contour: along the straight line from r_j to r_i, in proportion to the length of the line inside
//            each slab (Irving-Kirkwood with the straight contour). In mechanical equilibrium p_N(z)
//            is then flat, as it must be; p_T(z) is the usual lateral profile (the contour is not
//            unique, which leaves p_T(z) uncertain at the scale of the force range, but not its
//            integral).
//   half:    half into the slab of each end (the per-atom virial of MD codes). Simpler, but p_N(z)
//            is not flat across an interface: structure narrower than the force range is smeared
//            and shifted.
// Both give exactly the same sums over slabs: sum_b P_b V_b is the whole-box tensor of thermo.csv
// (conservative part), so the tension integral
//   gamma = int (p_N - p_T) dz = h sum_b (p_N - p_T)_b = L (P_N - P_T)
// with p_T the mean of the two lateral diagonal components, is the same with either, to rounding.
// For a single membrane in a periodic box gamma is its tension; a slab of liquid (two interfaces) has
// gamma = 2 sigma.
#pragma once
#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include <functional>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/block_rows.hpp"
#include "analysis/surface_tension.hpp"
#include "core/box.hpp"
#include "core/pair_sums.hpp"
#include "core/particle_data.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class StressProfile {
 public:
  StressProfile(const StressProfileSpec& spec, const Box& box);

  // One sample of the whole system `all` (locals, positions wrapped into the box) and the virial terms
  // on it. `frozen[species]` != 0: wall particles, without a kinetic part (empty: none).
  void sample(const ParticleData& all, const std::vector<double>& species_mass, const std::vector<std::uint8_t>& frozen,
              const VirialTerms& terms);

  std::size_t samples() const { return gamma_.size(); }
  std::size_t bins() const { return bins_; }
  // Bin centres along the axis.
  std::vector<double> z() const;
  // Mean diagonal pressure component c (0 = xx, 1 = yy, 2 = zz) of bin b: kinetic, configurational.
  double kinetic(std::size_t b, int c) const { return mean(b, c); }
  double configurational(std::size_t b, int c) const { return mean(b, 3 + c); }
  double pressure(std::size_t b, int c) const { return kinetic(b, c) + configurational(b, c); }
  double normal(std::size_t b) const { return pressure(b, axis_); }
  double tangential(std::size_t b) const;
  double density(std::size_t b) const { return mean(b, 6); }  // number density
  // Standard error of (p_N - p_T) in bin b from the block averages (NaN with fewer than two blocks).
  std::vector<double> anisotropy_err() const;
  // The whole-box mean diagonal, kinetic and configurational: the bins' average.
  std::array<double, 3> box_kinetic() const;
  std::array<double, 3> box_configurational() const;
  // gamma = int (p_N - p_T) dz: mean over all samples, error bar from `blocks` blocks of the series.
  BlockMean tension() const;
  // The per-sample tension series (for tests).
  const std::vector<double>& tension_series() const { return gamma_; }

  // stress_profile.csv, stress_profile.json and stress_profile.svg in `dir`; returns the summary line.
  std::string write(const std::filesystem::path& dir) const;
  std::string summary() const;

  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  static constexpr std::size_t kPerBin = 7;  // kinetic xx yy zz, configurational xx yy zz, count
  double mean(std::size_t b, std::size_t k) const;
  void add_share(std::size_t bin, const double w[3], double fraction);

  StressProfileSpec spec_;
  int axis_;
  std::size_t bins_;
  double len_, h_, bin_volume_, area_;
  std::vector<double> sums_;   // kPerBin per bin, summed over samples (in pressure units)
  std::vector<double> gamma_;  // tension per sample
  BlockRows blocks_;           // (p_N - p_T) per bin, per block
  std::vector<double> row_, aniso_;  // scratch: one sample
};

class Comm;

// The virial terms (conservative pair forces, bonds, angles) of the whole system handed to it, appended
// to `terms` (set by the engine: the run's laws by the reference loop).
using VirialTermsOf = std::function<void(const ParticleData& all, const Box& box, VirialTerms& terms)>;

// [analysis.stress_profile] as an EndOfStep stage: samples the system snapshot every stress_profile.every
// steps from stress_profile.start on (on the root).
class StressProfileStage final : public SnapshotAnalysisStage<StressProfile> {
 public:
  StressProfileStage(const SimulationSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot,
                     VirialTermsOf virial_terms, const Box& box, const Comm& comm);
  std::string finish(const StepContext& ctx) override;

 private:
  void sample(const StepContext& ctx, const ParticleData& all) override;
  VirialTermsOf virial_terms_;
  VirialTerms terms_;                 // scratch: one sample
  std::vector<std::uint8_t> frozen_;  // by species
};

}  // namespace mesodpd
