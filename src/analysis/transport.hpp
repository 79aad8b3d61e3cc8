// Transport coefficients from equilibrium fluctuations ([analysis.transport]): the velocity
// autocorrelation function and the mean squared displacement over a window of lags with every sample a
// time origin, the stress autocorrelation, and from them the self-diffusion coefficient by Green-Kubo
// and by Einstein, the Green-Kubo shear viscosity and the Schmidt number, each with a block error bar.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/model_section.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

struct TransportSpec {
  std::uint64_t start = 0;      // first sampled step (equilibration before it)
  std::uint64_t every = 1;      // steps between samples; the stress is averaged over the steps between
  std::uint64_t lags = 100;     // the window of the VACF and MSD, in samples
  std::uint64_t origin_every = 1;  // a time origin of the VACF and MSD every this many samples
  std::uint64_t stress_lags = 0;   // the window of the stress autocorrelation (0: lags)
  std::uint64_t block = 5000;   // steps per block of the error bars
  bool normal_stress = false;   // also correlate the traceless normal stresses
};

const keys::KeyTable<TransportSpec>& transport_keys();
// The checks against the rest of the spec (each refusal names its key); also run by the installer.
void check_transport(const TransportSpec& t, const SimulationSpec& spec);
// The section the schema reads as [analysis.transport].
ModelSection transport_section();

// A value over the blocks: their mean and its standard error (NaN with fewer than two blocks).
struct TransportEstimate {
  double value = 0.0, error = 0.0;
};

// What one block measures (kT is its mean kinetic temperature, which the Green-Kubo viscosity divides by).
// d_vacf_window is the VACF's D on the MSD fit's terms: the MSD that the VACF implies,
// 2 Int_0^t (t - s) C_v(s) ds, fitted over the same lags, so that it differs from d_msd only by noise and
// discretisation where d_vacf also differs by the tail of C_v between the fit window and its end.
struct TransportBlockValues {
  double d_vacf = 0, d_vacf_window = 0, d_msd = 0, eta_shear = 0, eta_normal = 0, eta = 0, kT = 0;
};

struct TransportResult {
  std::size_t blocks = 0;          // complete blocks used
  double window = 0;               // lags x sample spacing: the upper limit of the D integral
  double stress_window = 0;        // the same for eta
  TransportEstimate d_vacf, d_vacf_window, d_msd, eta_shear, eta_normal, eta, schmidt, kT;
  std::vector<TransportBlockValues> per_block;
};

// The correlations of a fixed set of particles, sampled every `every` steps of length dt. Each sample
// is the whole system in a fixed particle order (the snapshot's increasing id), and the pressure tensor
// averaged over the steps since the previous sample (add_pressure at each of them). Every
// `origin_every`-th sample is a time origin of the VACF and MSD for the `lags` samples after it, every
// sample one of the stress correlation for the `stress_lags` after it; products go into the block of
// their later sample, a block being `block_steps` steps from the first sample on. Memory: 6 doubles
// per particle and lag.
class TransportCorrelations {
 public:
  TransportCorrelations(std::size_t lags, std::uint64_t every, double dt, std::uint64_t block_steps,
                        bool normal_stress, std::size_t origin_every = 1, std::size_t stress_lags = 0);

  // The pressure tensor (xx yy zz xy xz yz, kinetic part included) of one step between samples.
  void add_pressure(const std::array<double, 6>& p);
  // One sample at `step`: velocities, unwrapped positions, the kinetic temperature and the total mass of
  // the particles (for the mass density of the Schmidt number). Throws
  // std::invalid_argument if the spacing is not `every`, the particle count changes, or the steps
  // since the last sample did not each add a pressure.
  void sample(std::uint64_t step, const double* vx, const double* vy, const double* vz, const double* xu,
              const double* yu, const double* zu, std::size_t n, double kT, double total_mass);

  std::size_t lags() const { return lags_; }
  std::size_t stress_lags() const { return stress_lags_; }
  double spacing() const { return spacing_; }  // time between samples
  std::size_t samples() const { return samples_; }
  // Blocks whose every sample has been taken.
  std::size_t complete_blocks() const;

  double total_mass() const { return mass_; }
  // The estimates over the complete blocks, for a system of this volume.
  //   D (Green-Kubo) = 1/3 Int_0^T <v(0).v(t)> dt, trapezoidal in the samples;
  //   D (Einstein)   = slope / 6 of the MSD fitted over lags [T/2, T];
  //   eta            = V / kT Int_0^T <P_ab(0) P_ab(t)> dt over xy, xz, yz (and, with the normal
  //                    stresses, (3 eta_shear + 2 eta_normal) / 5, see docs/physics.md);
  //   Sc             = eta / (rho D_Einstein), its error by the jackknife over blocks.
  TransportResult result(double volume) const;

  // time, vacf, d_vacf(t), msd, g_shear(t), eta_shear(t), g_normal(t), eta_normal(t), pooled over
  // the complete blocks (g = V/kT C(t) and its running integral).
  void write_csv(const std::string& path, double volume) const;

  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  struct Block {
    std::vector<double> vacf, msd;            // sums over products, by lag (lags + 1)
    std::vector<std::uint64_t> count;
    std::vector<double> shear, normal;        // the same for the stress (stress_lags + 1)
    std::vector<std::uint64_t> stress_count;
    double temperature_sum = 0;
    std::uint64_t samples = 0;
  };
  Block& block_of(std::uint64_t step);
  // Per-lag means of a set of blocks (temperature: the mean of their samples).
  Block empty_block() const;
  Block pooled(std::size_t first, std::size_t last) const;
  TransportBlockValues values(const Block& b, double volume) const;

  std::size_t lags_, origin_every_, stress_lags_;
  std::uint64_t every_;
  double spacing_;
  std::uint64_t block_steps_;
  bool normal_;
  std::size_t n_ = 0;
  double mass_ = 0;
  std::uint64_t samples_ = 0, first_step_ = 0, last_step_ = 0;
  std::vector<double> vel_, pos_;  // ring of lags + 1 samples, 3 n values each (x y z interleaved)
  std::vector<double> stress_;     // ring of stress_lags + 1 samples: xy xz yz, then the traceless xx yy zz
  std::array<double, 6> interval_{};
  std::uint64_t interval_steps_ = 0;
  std::vector<Block> blocks_;
};

// [analysis.transport] as an EndOfStep stage: the pressure tensor at every step from one interval before
// the first sample (so the pair sums are computed there), the snapshot every `every` steps; the files
// transport.csv and transport.json and the summary at the end.
class TransportStage final : public RootAnalysisStage<TransportCorrelations> {
 public:
  TransportStage(const TransportSpec& spec, const SimulationSpec& sim, AnalysisOutput out, SystemSnapshot& snapshot,
                 const Comm& comm);
  bool wants_pair_sums(std::uint64_t step) const override { return step > first_ - spec_.every; }
  void observe(const StepContext& ctx) override;
  std::string finish(const StepContext& ctx) override;
  std::uint64_t first_sample_step() const { return first_; }

 private:
  TransportSpec spec_;
  const SimulationSpec& sim_;      // for the kinetic-theory values of the summary
  SystemSnapshot& snapshot_;
  std::uint64_t first_;            // the first sampled step: a multiple of every, >= start and >= every
  std::vector<double> v_, r_;      // scratch: one sample in id order
};

}  // namespace mesodpd
