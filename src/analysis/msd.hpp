// Mean squared displacement from unwrapped positions, and the self-diffusion coefficient from it.
#pragma once
#include "analysis/analysis_stage.hpp"
#include "analysis/system_snapshot.hpp"
#include "mesodpd/spec.hpp"
#include "io/byte_buffer.hpp"
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace mesodpd {

// MSD(t) = < |r_i(t0 + t) - r_i(t0)|^2 > averaged over particles and over time origins t0.
// Particles are matched by id, so the storage order may change between samples (sorting,
// migration). Every sample must contain exactly the ids of the first one.
class MeanSquaredDisplacement {
 public:
  // A new time origin starts at the first sample and then every `origin_every` samples until
  // `max_origins` exist. Averaging over origins assumes samples equally spaced in step; with more
  // than one origin, sample() throws std::invalid_argument if the spacing changes. The default
  // (one origin) accepts any spacing. Memory is 3 doubles per particle per origin.
  explicit MeanSquaredDisplacement(std::size_t max_origins = 1, std::size_t origin_every = 1);

  // Adds one sample of UNWRAPPED positions (x + image * L). Throws std::invalid_argument on an id
  // that is not in the first sample, or a different particle count.
  void sample(std::uint64_t step, double time, const std::uint32_t* id, const double* xu, const double* yu,
              const double* zu, std::size_t n);

  std::size_t size() const { return lag_time_.size(); }          // points in the series (lag 0 included)
  const std::vector<double>& time() const { return lag_time_; }  // lag times t, starting at 0
  std::vector<double> msd() const;                               // MSD at each lag time

  // D from a least-squares fit MSD = 6 D t + c over the second half of the series, where the
  // ballistic start has decayed. Returns NaN if fewer than two points fall in that half.
  double diffusion_coefficient() const;

  void write_csv(const std::string& path) const;  // columns time,msd

  // Accumulated state for checkpoints, so a restarted run continues the same averages. load() refuses
  // state recorded with different settings (naming `context`, the checkpoint file).
  void save(ByteWriter& w) const;
  void load(ByteReader& r, const std::string& context);

 private:
  struct Origin {
    std::size_t first_sample;  // index of the sample that is this origin
    std::vector<double> pos;   // x, y, z interleaved, indexed by slot
  };

  std::size_t max_origins_;
  std::size_t origin_every_;
  std::size_t samples_ = 0;
  std::uint64_t step_spacing_ = 0;
  std::uint64_t last_step_ = 0;
  double first_time_ = 0.0;
  std::unordered_map<std::uint32_t, std::size_t> slot_of_id_;  // id -> slot in Origin::pos
  std::vector<Origin> origins_;
  std::vector<double> lag_time_;
  std::vector<double> msd_sum_;
  std::vector<std::size_t> msd_count_;
  std::vector<std::size_t> slot_scratch_;
};

// [analysis.msd] as an EndOfStep stage: samples the unwrapped positions of the system snapshot every
// msd.every steps from msd.start on (on the root); msd.csv and D at the end.
class MsdStage final : public SnapshotAnalysisStage<MeanSquaredDisplacement> {
 public:
  MsdStage(const SimulationSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot, const Comm& comm);
  std::string finish(const StepContext& ctx) override;

 private:
  void sample(const StepContext& ctx, const ParticleData& all) override;
  double dt_;
  std::vector<double> xu_, yu_, zu_;  // scratch: unwrapped positions of one sample
};

}  // namespace mesodpd
