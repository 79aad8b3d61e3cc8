// Radial distribution function g(r) of a periodic orthorhombic box, and the virial EOS from it.
#pragma once
#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include "mesodpd/spec.hpp"
#include "io/byte_buffer.hpp"
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mesodpd {

// Accumulates g(r) over snapshots. Reads the position arrays it is given and keeps only a pair
// histogram, so it can be fed from any storage (engine, trajectory file, test).
class RadialDistribution {
 public:
  // bins > 0 equal-width bins over [0, rmax), rmax > 0.
  RadialDistribution(std::size_t bins, double rmax);

  // Adds one snapshot: positions (x[i], y[i], z[i]) of n particles in a box of edge lengths box_len,
  // nominally inside [0, L) (others are wrapped on periodic axes). O(n) via cell binning. Pairs are
  // taken at their minimum image along periodic axes and straight along bounded ones (periodic[d]
  // false); the ideal-gas normalisation of g() assumes a periodic box, so near bounded faces g(r)
  // reads low by the fraction of each shell outside the box (about r / 2L per bounded axis).
  // Throws std::invalid_argument unless rmax < min(box_len) / 2, which keeps the minimum image
  // the only image within rmax.
  void sample(const double* x, const double* y, const double* z, std::size_t n,
              std::array<double, 3> box_len, std::array<bool, 3> periodic = {true, true, true});

  std::vector<double> r() const;  // bin centres
  // Pair counts normalised by the ideal-gas count N(N-1)/V * shell volume, summed over samples.
  // Using N-1 (not N) makes an ideal gas give exactly g = 1 in expectation.
  std::vector<double> g() const;
  // Ordered-pair counts per bin summed over samples (each unordered pair counted twice).
  const std::vector<std::uint64_t>& counts() const { return counts_; }
  std::size_t samples() const { return samples_; }
  double bin_width() const { return dr_; }

  void write_csv(const std::string& path) const;  // columns r,g

  // Accumulated state for checkpoints, so a restarted run continues the same averages. load() refuses
  // state recorded with different settings (naming `context`, the checkpoint file).
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  std::size_t bins_;
  double rmax_;
  double dr_;
  std::vector<std::uint64_t> counts_;
  double ideal_pair_density_sum_ = 0.0;  // sum over samples of N (N-1) / V
  std::size_t samples_ = 0;
  // Scratch for cell binning, kept between samples to avoid reallocation.
  std::vector<std::size_t> cell_start_;
  std::vector<std::size_t> order_;
  std::vector<std::size_t> cell_of_;
};

// Pressure from the virial route, seed 003 (line ~303):
//   p = rho kT + (2 pi / 3) rho^2 Int r F^C(r) g(r) r^2 dr,  F^C(r) = a (1 - r/rc) for r < rc,
// integrated by the midpoint rule with r the bin centres and dr the bin width.
// Throws std::invalid_argument if r and g differ in length.
double virial_pressure_from_rdf(const std::vector<double>& r, const std::vector<double>& g, double dr,
                                double rho, double kT, double a, double rc);

// [analysis.rdf] as an EndOfStep stage: samples the system snapshot every rdf.every steps from
// rdf.start on (the root holds the histogram); rdf.csv at the end; the histogram in its checkpoint
// section.
class RdfStage final : public SnapshotAnalysisStage<RadialDistribution> {
 public:
  RdfStage(const RdfSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot, const Comm& comm);
  std::string finish(const StepContext& ctx) override;

 private:
  void sample(const StepContext& ctx, const ParticleData& all) override;
};

}  // namespace mesodpd
