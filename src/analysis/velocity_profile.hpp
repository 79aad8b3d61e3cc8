// Binned flow profile of reverse Poiseuille flow and the shear viscosity fitted to it, with block errors.
#pragma once
#include "analysis/analysis_stage.hpp"
#include "mesodpd/spec.hpp"
#include "analysis/block_rows.hpp"
#include "io/byte_buffer.hpp"
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace mesodpd {

struct ViscosityFit {
  double eta;          // viscosity from the fit to the profile averaged over all samples
  double eta_err;      // standard error from the spread of per-block fits; NaN if blocks_used < 2
  double v_amplitude;  // fitted peak speed relative to v0, c (L/4)^2, at the middle of each half
  int blocks_used;     // equal-size blocks behind eta_err
};

// Reverse (periodic) Poiseuille flow of Backer et al. (seed 002, "Boundary Conditions"): body
// acceleration +g along the flow axis for gradient coordinate z in [0, L/2) and -g in [L/2, L).
// Stokes flow in each half then gives (z' = z - L/2 in the upper half)
//   v(z) = +c z (L/2 - z) + v0   (lower),   v(z) = -c z' (L/2 - z') + v0   (upper),
// with c = rho_m g / (2 eta); c and v0 are fitted by linear least squares and eta = rho_m g / (2 c).
//
// Blocking without knowing the run length (BlockRows): samples go into up to 2B equal-size blocks (B = `blocks`
// given to the constructor); when all 2B are full, neighbours are merged pairwise and the block size
// doubles. So at any time there are between B and 2B - 1 full blocks of equal sample count, memory
// stays O(B * bins), and ViscosityFit::blocks_used reports how many there were. The mean profile
// uses every sample, including those of the unfinished block.
class PoiseuilleProfile {
 public:
  // bins > 1 along the gradient axis of length box_len (> 0); blocks >= 2; force_g != 0 is the body
  // acceleration (force per unit mass); mass_density > 0 is rho_m (number density for unit mass).
  // flow_axis and gradient_axis (0, 1, 2 for x, y, z, distinct) only label the output.
  PoiseuilleProfile(std::size_t bins, int flow_axis, int gradient_axis, double box_len, std::size_t blocks,
                    double force_g, double mass_density);

  // Adds one snapshot: gradient coordinate (wrapped into [0, L) here) and flow velocity of n particles.
  void sample(const double* pos_gradient_coord, const double* v_flow, std::size_t n);

  // The same in two parts, for particles spread over ranks: bin() accumulates a part of the snapshot
  // into integer per-bin sums (2 x bins entries: fixed-point flow velocity, then counts), which do not
  // depend on the order of the particles or of the parts; add_binned() adds the completed snapshot.
  static void bin(const double* pos_gradient_coord, const double* v_flow, std::size_t n, std::size_t bins,
                  double box_len, std::int64_t* sums);
  void add_binned(const std::int64_t* sums);

  ViscosityFit fit() const;

  std::vector<double> z() const;       // bin centres
  std::vector<double> v_mean() const;  // mean flow velocity per bin over all samples (NaN if empty)
  std::vector<double> v_err() const;   // standard error per bin from the full blocks (NaN if < 2)
  std::vector<double> v_fit() const;   // fitted profile, averaged over each bin like the data
  std::size_t samples() const { return samples_; }
  std::size_t samples_per_block() const { return blocks_rows_.samples_per_block(); }
  int flow_axis() const { return flow_axis_; }
  int gradient_axis() const { return gradient_axis_; }

  void write_csv(const std::string& path) const;  // columns z,v_mean,v_err,v_fit

  // Accumulated state for checkpoints, so a restarted run continues the same averages. load() refuses
  // state recorded with different settings (naming `context`, the checkpoint file).
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  struct LineFit {
    double c;
    double v0;
  };
  // Least squares of v ~ c * basis + v0 over bins with data; NaNs if fewer than two such bins.
  LineFit fit_profile(const double* vsum, const double* count) const;

  std::size_t bins_;
  int flow_axis_;
  int gradient_axis_;
  double len_;
  std::size_t blocks_;
  double force_g_;
  double mass_density_;
  std::vector<double> basis_;  // exact bin average of the signed parabola z (L/2 - z)

  std::size_t samples_ = 0;
  BlockRows blocks_rows_;            // per block and bin: sum of flow velocity (bins), then counts (bins)
  std::vector<double> row_;          // one sample in that layout
  std::vector<double> total_vsum_;
  std::vector<double> total_count_;
};

// One-row CSV beside the profile for plots and reports: eta,eta_err,v_amplitude,blocks_used,eta_kinetic
// (eta_kinetic is e.g. kinetic_viscosity() from analysis/kinetic_theory.hpp; NaN if unknown).
void write_viscosity_summary_csv(const std::string& path, const ViscosityFit& fit, double eta_kinetic);

// [poiseuille] profile and viscosity as an EndOfStep stage: every poiseuille.every steps after
// poiseuille.start each rank bins its own particles into integer sums, and only the per-bin totals
// travel (to the root, which holds the profile); at the end the viscosity fit, poiseuille_profile.csv,
// viscosity.csv, viscosity.json and velocity_profile.svg.
class VelocityProfileStage final : public RootAnalysisStage<PoiseuilleProfile> {
 public:
  // `start` is the state the run begins from (the fluid's mass is counted over ranks). Collective.
  VelocityProfileStage(const SimulationSpec& spec, AnalysisOutput out, const StepContext& start);
  bool due(std::uint64_t step) const {
    return step > spec_.poiseuille.start && step % spec_.poiseuille.every == 0;
  }
  void observe(const StepContext& ctx) override;
  std::string finish(const StepContext& ctx) override;

 private:
  const SimulationSpec& spec_;
  std::vector<std::int64_t> bins_;  // one sample: fixed-point flow sums, then counts
};

}  // namespace mesodpd
