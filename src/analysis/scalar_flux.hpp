// The flux of a transported scalar ([analysis.flux]): the heat of eDPD (C_v T) or a solute of tDPD (C)
// through planes normal to one axis, what each wall exchanges with the fluid, and from the flux and the
// profile's gradient at each plane the conductivity and the diffusivity of a steady state (issue 25,
// "Measurements").
//
// Through a plane at z = P (axis z; A the box's area normal to it) the flux density in +z is
//   J = J_pair + J_conv,
//   J_pair = (1 / A) sum over pairs that straddle the plane of the pair's exchange, counted + where it
//            flows from the -z side to the +z side (the law's conduction or Fick term with its random term
//            at zero, its mean: engine/reference_pair_loop.hpp, reference_scalar_exchange; a symmetric
//            source such as viscous heating is no flux and is left out),
//   J_conv = (1 / (2 h A)) sum over mobile particles with |z_i - P| < h of cap_i (X_i - Xbar) v_z,i,
//            Xbar = sum cap X / sum cap over the same slab: the scalar the particles carry, relative to the
//            slab's barycentric motion (in a box without net flow through the plane, the lab-frame flux).
// cap is the species' capacity (C_v for heat, 1 for a solute). Each wall (frozen species) reports the
// amount it gives to the fluid per unit time, W = -sum over its particles of cap_i dX_i/dt (the wall side
// of every wall-fluid pair: conduction and random terms, no viscous share), taken at every step.
//
// At each plane the profile of the mobile particles' mean X in bins of width `bin` is fitted by a line
// over the bins within `fit` of the plane; with its slope g, the local number density n and mean
// capacity cbar there:
//   conductivity k = -J / g,   diffusivity D = k / (n cbar)   (heat: D_T = k / (n C_v); a solute: D).
// Error bars: `blocks` block averages (analysis/block_rows.hpp), each block its own J, g, k and D.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "analysis/analysis_stage.hpp"
#include "analysis/block_rows.hpp"
#include "analysis/system_snapshot.hpp"
#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/key_table.hpp"

namespace mesodpd {

class Comm;

struct FluxSpec {
  std::string field = "temp";  // "temp" (eDPD) or "conc1".."conc4" (tDPD)
  int axis = 2;                // the planes' normal
  double position = 0;         // the first plane
  int planes = 1;              // planes at position + k spacing, k < planes
  double spacing = 1.0;
  double slab = 1.0;           // half-width h of the convective slab about a plane
  double fit = 2.0;            // half-width of the gradient fit about a plane
  double bin = 0.5;            // width of the profile's bins (rounded to divide the box)
  std::uint64_t start = 0;     // first sampled step
  std::uint64_t every = 10;    // steps between plane samples; walls are read at every step
  int blocks = 10;             // blocks of the error bars
};

const keys::KeyTable<FluxSpec>& flux_keys();
// The checks against the box (planes inside it, windows narrower than it); each refusal names its key.
void check_flux(const FluxSpec& f, const std::array<double, 3>& box);

// The exchange of the run's pair law over a snapshot (the engine's: reference_scalar_exchange with the
// run's laws, channel and capacities): visit(i, j, q) for each pair that want(i, j, dx, dy, dz) accepts,
// q flowing from j into i.
using ScalarExchangeOf = std::function<void(
    const ParticleData& all, const Box& box, const std::function<bool(std::size_t, std::size_t, double, double, double)>& want,
    const std::function<void(std::size_t, std::size_t, double)>& visit)>;

struct FluxEstimate {
  double value = 0, error = 0;  // error: standard error over blocks (NaN with fewer than two)
};

struct PlaneFlux {
  double position = 0;
  FluxEstimate pair, conv, total, gradient, density, capacity, conductivity, diffusivity;
};

struct WallFlux {
  std::string species;
  FluxEstimate rate;  // amount per unit time given to the fluid
  FluxEstimate per_area;  // rate / A
};

struct FluxResult {
  std::size_t samples = 0, blocks = 0;
  std::vector<PlaneFlux> planes;
  std::vector<WallFlux> walls;
};

class ScalarFlux {
 public:
  // capacity and frozen by species; names for the walls' rows.
  ScalarFlux(const FluxSpec& spec, const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
             std::vector<double> capacity, std::vector<std::uint8_t> frozen, std::vector<std::string> names);

  // One sample of the whole system `all` (positions wrapped into the box) with the law's exchange, and
  // the walls' mean rates over the interval (one per frozen species, in species order).
  void sample(const ParticleData& all, const Box& box, const ScalarExchangeOf& exchange,
              const std::vector<double>& wall_rates);

  std::size_t samples() const { return samples_; }
  FluxResult result() const;
  // Bin centres and the pooled profile: number density and mean X of the mobile particles.
  std::vector<double> bin_centres() const;
  std::vector<double> profile_density() const;
  std::vector<double> profile_mean() const;

  // flux.csv, flux.json and flux_profile.csv in dir; returns the summary.
  std::string write(const std::filesystem::path& dir) const;
  std::string summary() const;

  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  // The per-plane values of one set of summed rows (`n` samples).
  void plane_values(const double* row, double n, std::vector<std::array<double, 7>>& out) const;
  std::size_t width() const { return 2 * planes_.size() + 3 * bins_ + walls_.size(); }

  FluxSpec spec_;
  int axis_;
  double len_, area_, bin_width_;
  bool periodic_;
  std::size_t bins_;
  std::vector<double> planes_;
  std::vector<double> capacity_;
  std::vector<std::uint8_t> frozen_;
  std::vector<std::string> names_;
  std::vector<std::size_t> walls_;  // frozen species
  std::vector<double> total_;       // summed rows of every sample
  std::uint64_t samples_ = 0;
  BlockRows blocks_;
  std::vector<double> row_;         // scratch
};

// [analysis.flux] as an EndOfStep stage: the walls' rates at every step of each sampling interval (summed
// over ranks in fixed point), the snapshot every `every` steps from the first multiple of it at or after
// max(start, every).
class ScalarFluxStage final : public RootAnalysisStage<ScalarFlux> {
 public:
  ScalarFluxStage(const FluxSpec& spec, const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
                  std::vector<double> capacity, std::vector<std::uint8_t> frozen, std::vector<std::string> names,
                  std::string rate_field, ScalarExchangeOf exchange, SystemSnapshot& snapshot, const Comm& comm,
                  AnalysisOutput out);
  void observe(const StepContext& ctx) override;
  std::string finish(const StepContext& ctx) override;
  void save(ByteWriter& w) const override;
  void load(ByteReader& r, const std::string& context) override;

 private:
  FluxSpec spec_;
  std::string rate_field_;
  ScalarExchangeOf exchange_;
  SystemSnapshot& snapshot_;
  std::uint64_t first_;
  std::vector<double> capacity_;
  std::vector<int> wall_of_;  // by species: its wall's index, -1 for a mobile species
  std::vector<double> acc_;  // the walls' rates summed over the steps of the current interval (root)
  std::uint64_t acc_steps_ = 0;
};

}  // namespace mesodpd
