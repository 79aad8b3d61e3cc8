// Time-averaged fields on a grid of bins: number density per species, mass-weighted velocity and the
// temperature of the peculiar velocity, over the box or a box-aligned sub-region, on 1-, 2- or 3-D grids
// ([analysis.fields], docs/config.md; issue 10 item 5, issue 11 item 3). Seed 004 Sect. 4 averages such
// maps (120 x 66 bins in the xz-plane) over 10^5 steps.
//
// Determinism: every sample is binned into integers (particle counts, and momentum m v and kinetic
// m v_d^2 in fixed point, kFixedScale units per unit), so the per-bin sums do not depend on the order of
// the particles, the thread count or the rank count; they are summed over ranks (integer all-reduce)
// and added to 128-bit running totals that are identical on every rank and go into checkpoints.
//
// Temperature (k_B = 1) of bin b along axis d, from its N particle-samples (selected species only),
// total mass M, momentum P_d = sum m v_d and kinetic sum K_d = sum m v_d^2 over all samples:
//   u_d = P_d / M                         (mass-weighted mean velocity of the bin over the run)
//   T_d = (K_d - P_d^2 / M) / (N - 1)     (peculiar velocity v - u, with N - 1 degrees of freedom)
// Subtracting the mean estimated from the same N samples removes one degree of freedom per component:
// for independent Maxwellian velocities E[sum m (v_d - u_d)^2] = (N - 1) kT for any masses, so T_d is
// unbiased. (Samples of one particle at nearby times are correlated, which adds a bias of order
// tau / N, negligible for the long averages this is for.) T is the mean of T_x, T_y, T_z. The reference
// velocity is the bin's mean over the whole run, the steady streaming velocity of a steady flow; a
// drifting system (a slab that wanders) should be centred (centre_axis) or it reads its drift as heat.
#pragma once
#include "analysis/analysis_stage.hpp"
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "analysis/block_rows.hpp"
#include "core/particle_data.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class Comm;

__extension__ typedef __int128 FieldSum;

// The result of fitting a slab's 1-D density profile (fit_slab_profile).
struct SlabFit {
  bool converged = false;
  double rho_l = 0, rho_v = 0;  // liquid (inside) and vapour (outside) densities
  double z0 = 0;                // centre of the slab
  double half_width = 0;        // h: distance from z0 to each interface
  double width = 0;             // w of tanh: the 10-90 thickness is 2 atanh(0.8) w = 2.197 w
  double rms = 0;               // root-mean-square residual of the fit
  int iterations = 0;
  // Standard errors from fitting each block of samples on its own (NaN with fewer than 2 blocks).
  double rho_l_err = 0, rho_v_err = 0, half_width_err = 0, width_err = 0;
  int blocks_used = 0;
};

// Least-squares fit of rho(z) = (rho_l + rho_v)/2 - (rho_l - rho_v)/2 tanh((|z - z0| - h) / w) to the
// points (z[k], rho[k]) (non-finite rho skipped), by Levenberg-Marquardt from a guess taken from the
// profile itself. `period` > 0: |z - z0| is the periodic minimum-image distance.
SlabFit fit_slab_profile(const std::vector<double>& z, const std::vector<double>& rho, double period);

// The time-averaged fields of one grid (one [analysis.fields] table).
class BinnedFields {
 public:
  static constexpr double kFixedScale = 4294967296.0;  // 2^32 fixed-point units per unit of m v, m v^2

  // `box_len`, `periodic`: the box; species_mass by species index; species_names label the output.
  BinnedFields(const FieldsSpec& spec, std::vector<double> species_mass, std::vector<std::string> species_names,
               std::array<double, 3> box_len, std::array<bool, 3> periodic = {true, true, true});

  // Collective under MPI: bins this rank's n_local particles, sums over ranks and adds the sample.
  void sample(const ParticleData& own, const Comm& comm, std::uint64_t step);

  std::size_t cells() const { return n_cells_; }
  std::uint64_t samples() const { return samples_; }
  const FieldsSpec& spec() const { return spec_; }

  // Results per bin (index ix + nx (iy + ny iz)); NaN where a bin has no particle-samples (velocity)
  // or fewer than two (temperature); all NaN before the first sample.
  std::vector<double> density() const;                   // selected species, particles per volume
  std::vector<double> species_density(int species) const;  // any species
  std::vector<double> velocity(int axis) const;
  std::vector<double> temperature(int axis) const;       // axis 0..2, or -1 for the mean of the three
  std::vector<double> mean(std::size_t m) const;         // the per-particle field spec().means[m], per bin
  std::array<double, 3> centre(std::size_t cell) const;  // bin centre in box coordinates
  double cell_volume() const;
  // The axis of a 1-D grid (bins > 1 along exactly one axis), or -1.
  int profile_axis() const;

  // Writes <name>.vti, <name>.csv, <name>.json and, for a 1-D grid, <name>_profile.svg in `dir`
  // (atomically, each file). Returns one summary line per result worth printing.
  std::string write(const std::filesystem::path& dir) const;
  SlabFit slab_fit() const;  // fit of the 1-D density profile (spec.fit == Slab)
  // The period of the minimum image in the slab fit: the box length where a 1-D profile spans a whole
  // periodic axis, else 0.
  double fit_period() const;

  // Running totals for checkpoints; load() refuses state recorded for another grid.
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  std::size_t bin_of(double x, int axis) const;  // kNoBin when outside the region
  double centring_shift(const ParticleData& own, const Comm& comm) const;
  long double total(std::size_t cell, std::size_t slot) const { return static_cast<long double>(sums_[cell * stride_ + slot]); }

  FieldsSpec spec_;
  std::vector<double> mass_;
  std::vector<std::string> names_;
  std::array<double, 3> box_len_;
  std::array<bool, 3> periodic_;
  std::array<double, 3> inv_width_{};
  std::vector<char> selected_;  // by species index
  std::size_t n_species_ = 0, stride_ = 0, n_cells_ = 0;
  // Per cell: count of each species, then the selected species' P_x, P_y, P_z, K_x, K_y, K_z.
  std::vector<FieldSum> sums_;     // running totals over all samples
  std::vector<FieldSum> scratch_;  // one sample
  std::vector<double> row_;        // one sample's 1-D density counts, for the blocks
  BlockRows blocks_;               // per-block 1-D profiles of the selected species (fit = "slab")
  bool blocked_ = false;
  std::uint64_t samples_ = 0, first_step_ = 0, last_step_ = 0;
};

// One [analysis.fields] grid as an EndOfStep stage: samples every `every` steps from `start` on (every
// rank holds the same totals), writes its files every `write_every` steps and at the end.
class BinnedFieldsStage final : public AnalysisStage {
 public:
  BinnedFieldsStage(BinnedFields grid, AnalysisOutput out) : grid_(std::move(grid)), out_(std::move(out)) {}
  void observe(const StepContext& ctx) override;
  void save(ByteWriter& w) const override { grid_.save(w); }
  void load(ByteReader& r, const std::string& context) override { grid_.load(r, context); }
  std::string finish(const StepContext& ctx) override;
  const BinnedFields& grid() const { return grid_; }

 private:
  BinnedFields grid_;
  AnalysisOutput out_;
};

}  // namespace mesodpd
