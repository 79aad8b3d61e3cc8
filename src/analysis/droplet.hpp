// A droplet in its vapour ([analysis.droplet]): the measurements behind Laplace's law
// Delta P = P_in - P_out = 2 sigma / R (issue 11 item 3).
//
// Each sample (on the root, from the whole system in id order, so the result does not depend on ranks,
// threads or storage order):
// - the drop's centre: the periodic (circular) mean of the particle positions, weighted by mass, then
//   refined a few times as the mean of the minimum-image displacements within outer_radius, so that the
//   vapour far away does not pull it;
// - the radial number density profile around that centre (bins of bin_width up to half the smallest
//   box length), summed over samples;
// - the liquid density rho_in (particles within inner_radius) and the vapour density rho_out (the box
//   outside the sphere of outer_radius);
// - the equimolar radius R: the radius of the sphere of density rho_in that, with vapour of density
//   rho_out around it, holds the N particles of the box: (4 pi / 3) R^3 = (N - rho_out V) / (rho_in - rho_out);
// - the pressure in both regions from the per-particle virial of the conservative forces (seed 000
//   Eq. 24: the dissipative and random forces do not contribute on average):
//     P = (1 / 3 V_region) sum_{i in region} [ m_i v_i^2 + (1/2) sum_j r_ij . F^C_ij ].
//   Half of each pair's virial goes to each of its particles. In a homogeneous region this is the
//   bulk pressure exactly on average, so inner_radius must leave the particles within it (and their
//   neighbours up to the interaction range) inside the homogeneous liquid core: inner_radius +
//   r_c + r_d below the radius minus the interface's width.
// The virial per particle comes from the engine (the same force-law functors as the pair loop, through
// a callback, because analysis/ does not see the engine's law tables).
#pragma once
#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/surface_tension.hpp"
#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// For the particles of `subset` (locals only, positions in the full periodic `box`): w[i] = (1/2) sum_j
// r_ij . F^C_ij over the other particles j of the subset within range (and, for density-dependent laws,
// with local densities taken over the subset). Exact for the particles whose neighbours, and their
// neighbours' density neighbours, all belong to the subset.
using LocalVirial = std::function<void(const ParticleData& subset, const Box& box, std::vector<double>& w)>;

// The mass-weighted centre of the particles [0, p.n_local) in a periodic box: circular mean per axis,
// then `passes` refinements over the particles within `radius` (minimum image) of the current centre.
std::array<double, 3> droplet_centre(const ParticleData& p, const std::vector<double>& species_mass, const Box& box,
                                     double radius, int passes = 5);

struct DropletResult {
  BlockMean radius, rho_in, rho_out, p_in, p_out, delta_p;
  double half_density_radius = 0;  // the outermost crossing of (rho_in + rho_out) / 2 by the mean profile
  double sigma = 0, sigma_err = 0; // Laplace: Delta P R / 2 (error from Delta P and R)
};

class DropletAnalysis {
 public:
  // `range`: the largest interaction range (pair cutoff plus density-kernel range), so that the subsets
  // handed to the virial callback hold every neighbour that matters.
  DropletAnalysis(const DropletSpec& spec, const Box& box, double range);

  // One sample of the whole system `all` (root, id order) around the drop's centre (droplet_centre).
  void sample(const ParticleData& all, const std::vector<double>& species_mass, const Box& box,
              const LocalVirial& virial);
  // The same around a given centre (a test of the local pressure in a homogeneous fluid, where a
  // centre found from the particles would sit on a density fluctuation).
  void sample_at(const std::array<double, 3>& centre, const ParticleData& all, const std::vector<double>& species_mass,
                 const Box& box, const LocalVirial& virial);

  std::size_t samples() const { return radius_.size(); }
  DropletResult result() const;
  // The mean number density per radial bin (bin centres r).
  std::vector<double> profile_r() const;
  std::vector<double> profile_density() const;
  // droplet.json and droplet_profile.csv in `dir`; returns the summary line.
  std::string write(const std::filesystem::path& dir) const;
  std::string summary() const;

  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  DropletSpec spec_;
  std::array<double, 3> len_;
  double range_;
  std::vector<double> radius_, rho_in_, rho_out_, p_in_, p_out_;  // one entry per sample
  std::vector<std::uint64_t> counts_;                              // radial histogram, all samples
  ParticleData subset_;                                            // scratch
  std::vector<double> w_;                                          // scratch
};

class Comm;

// [analysis.droplet] as an EndOfStep stage: samples the system snapshot every droplet.every steps from
// droplet.start on (on the root) with `virial`, the run's force law on a subset of particles, and
// `range`, the interaction range (pair cutoff plus density-kernel range), both from the engine.
class DropletStage final : public SnapshotAnalysisStage<DropletAnalysis> {
 public:
  DropletStage(const DropletSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot, LocalVirial virial,
               double range, const Box& box, const Comm& comm);
  std::string finish(const StepContext& ctx) override;

 private:
  void sample(const StepContext& ctx, const ParticleData& all) override;
  LocalVirial virial_;
};

}  // namespace mesodpd
