// Mean squared displacement from unwrapped positions, and the self-diffusion coefficient from it.
#include "analysis/msd.hpp"
#include "parallel/comm.hpp"
#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <utility>
#include <limits>
#include <stdexcept>

namespace mesodpd {

MeanSquaredDisplacement::MeanSquaredDisplacement(std::size_t max_origins, std::size_t origin_every)
    : max_origins_(max_origins), origin_every_(origin_every) {
  if (max_origins == 0) throw std::invalid_argument("MeanSquaredDisplacement: max_origins must be > 0");
  if (origin_every == 0) throw std::invalid_argument("MeanSquaredDisplacement: origin_every must be > 0");
}

void MeanSquaredDisplacement::sample(std::uint64_t step, double time, const std::uint32_t* id,
                                     const double* xu, const double* yu, const double* zu, std::size_t n) {
  if (samples_ == 0) {
    // The first sample fixes the particle set; its storage order defines the slots.
    slot_of_id_.clear();
    slot_of_id_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!slot_of_id_.emplace(id[i], i).second) {
        throw std::invalid_argument(fmt::format("MeanSquaredDisplacement: duplicate id {}", id[i]));
      }
    }
    first_time_ = time;
  } else {
    if (step <= last_step_) throw std::invalid_argument("MeanSquaredDisplacement: steps must increase");
    // Origins are averaged per lag index, which only means a fixed lag time if spacing is fixed.
    if (max_origins_ > 1) {
      const std::uint64_t spacing = step - last_step_;
      if (samples_ > 1 && spacing != step_spacing_) {
        throw std::invalid_argument(fmt::format(
            "MeanSquaredDisplacement: sample spacing changed from {} to {} steps with multiple origins",
            step_spacing_, spacing));
      }
    }
    if (n != slot_of_id_.size()) {
      throw std::invalid_argument(fmt::format(
          "MeanSquaredDisplacement: sample has {} particles, origin had {}", n, slot_of_id_.size()));
    }
  }

  // Map storage index -> slot, checking that every id of the origin appears exactly once.
  slot_scratch_.resize(n);
  std::vector<bool> seen(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    const auto it = slot_of_id_.find(id[i]);
    if (it == slot_of_id_.end()) {
      throw std::invalid_argument(
          fmt::format("MeanSquaredDisplacement: id {} not in the first sample", id[i]));
    }
    if (seen[it->second])
      throw std::invalid_argument(fmt::format("MeanSquaredDisplacement: duplicate id {}", id[i]));
    seen[it->second] = true;
    slot_scratch_[i] = it->second;
  }

  if (origins_.size() < max_origins_ && samples_ % origin_every_ == 0) {
    Origin o{samples_, std::vector<double>(3 * n)};
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t s = slot_scratch_[i];
      o.pos[3 * s] = xu[i];
      o.pos[3 * s + 1] = yu[i];
      o.pos[3 * s + 2] = zu[i];
    }
    origins_.push_back(std::move(o));
  }

  // The first origin is at sample 0, so this sample's lag from it is samples_: one new lag each time.
  lag_time_.push_back(time - first_time_);
  msd_sum_.push_back(0.0);
  msd_count_.push_back(0);
  for (const Origin& o : origins_) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t s = slot_scratch_[i];
      const double dx = xu[i] - o.pos[3 * s];
      const double dy = yu[i] - o.pos[3 * s + 1];
      const double dz = zu[i] - o.pos[3 * s + 2];
      sum += dx * dx + dy * dy + dz * dz;
    }
    const std::size_t lag = samples_ - o.first_sample;
    msd_sum_[lag] += n > 0 ? sum / static_cast<double>(n) : 0.0;
    ++msd_count_[lag];
  }

  if (samples_ == 1) step_spacing_ = step - last_step_;
  last_step_ = step;
  ++samples_;
}

std::vector<double> MeanSquaredDisplacement::msd() const {
  std::vector<double> out(msd_sum_.size(), 0.0);
  for (std::size_t k = 0; k < out.size(); ++k) {
    if (msd_count_[k] > 0) out[k] = msd_sum_[k] / static_cast<double>(msd_count_[k]);
  }
  return out;
}

double MeanSquaredDisplacement::diffusion_coefficient() const {
  const std::size_t m = size();
  const std::size_t start = m / 2;
  if (m < start + 2) return std::numeric_limits<double>::quiet_NaN();
  const auto y = msd();
  // Least squares for y = slope t + c, centred to avoid cancellation at late times.
  double tm = 0.0, ym = 0.0;
  for (std::size_t k = start; k < m; ++k) {
    tm += lag_time_[k];
    ym += y[k];
  }
  const auto np = static_cast<double>(m - start);
  tm /= np;
  ym /= np;
  double stt = 0.0, sty = 0.0;
  for (std::size_t k = start; k < m; ++k) {
    stt += (lag_time_[k] - tm) * (lag_time_[k] - tm);
    sty += (lag_time_[k] - tm) * (y[k] - ym);
  }
  if (stt <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  return sty / stt / 6.0;  // MSD = 6 D t in three dimensions
}

void MeanSquaredDisplacement::write_csv(const std::string& path) const {
  const auto y = msd();
  write_file_atomically(path, [&](std::ostream& os) {
    os << "time,msd\n";
    for (std::size_t k = 0; k < y.size(); ++k) os << fmt::format("{:.10g},{:.10g}\n", lag_time_[k], y[k]);
  });
}

void MeanSquaredDisplacement::save(ByteWriter& w) const {
  w.put<std::uint64_t>(max_origins_);
  w.put<std::uint64_t>(origin_every_);
  w.put<std::uint64_t>(samples_);
  w.put<std::uint64_t>(step_spacing_);
  w.put<std::uint64_t>(last_step_);
  w.put<double>(first_time_);
  // The id -> slot map in id order, so the checkpoint bytes do not depend on hash-table order.
  std::vector<std::pair<std::uint32_t, std::uint64_t>> slots(slot_of_id_.begin(), slot_of_id_.end());
  std::sort(slots.begin(), slots.end());
  std::vector<std::uint32_t> ids;
  std::vector<std::uint64_t> slot_of;
  for (const auto& [id, slot] : slots) {
    ids.push_back(id);
    slot_of.push_back(slot);
  }
  w.put_vector(ids);
  w.put_vector(slot_of);
  w.put<std::uint64_t>(origins_.size());
  for (const Origin& o : origins_) {
    w.put<std::uint64_t>(o.first_sample);
    w.put_vector(o.pos);
  }
  w.put_vector(lag_time_);
  w.put_vector(msd_sum_);
  w.put_vector(msd_count_);
}

void MeanSquaredDisplacement::load(ByteReader& r, const std::string& context) {
  const auto max_origins = r.get<std::uint64_t>(), origin_every = r.get<std::uint64_t>();
  if (max_origins != max_origins_ || origin_every != origin_every_)
    throw ConfigError(fmt::format("{}: MSD origin settings differ from the checkpoint", context));
  samples_ = r.get<std::uint64_t>();
  step_spacing_ = r.get<std::uint64_t>();
  last_step_ = r.get<std::uint64_t>();
  first_time_ = r.get<double>();
  slot_of_id_.clear();
  const auto ids = r.get_vector<std::uint32_t>();
  const auto slot_of = r.get_vector<std::uint64_t>();
  if (ids.size() != slot_of.size()) throw ConfigError(fmt::format("{}: inconsistent MSD state", context));
  for (std::size_t k = 0; k < ids.size(); ++k) slot_of_id_[ids[k]] = slot_of[k];
  origins_.resize(r.get<std::uint64_t>());
  for (Origin& o : origins_) {
    o.first_sample = r.get<std::uint64_t>();
    o.pos = r.get_vector<double>();
  }
  lag_time_ = r.get_vector<double>();
  msd_sum_ = r.get_vector<double>();
  msd_count_ = r.get_vector<std::size_t>();
  if (msd_sum_.size() != lag_time_.size() || msd_count_.size() != lag_time_.size())
    throw ConfigError(fmt::format("{}: inconsistent MSD state", context));
}

MsdStage::MsdStage(const SimulationSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot, const Comm& comm)
    : SnapshotAnalysisStage(std::move(out), snapshot, spec.msd.start, spec.msd.every), dt_(spec.dt) {
  if (comm.root()) a_.emplace();
}

void MsdStage::sample(const StepContext& ctx, const ParticleData& p) {
  const std::size_t n = p.n_local;
  xu_.resize(n);
  yu_.resize(n);
  zu_.resize(n);
  const Box& b = ctx.box;
  for (std::size_t i = 0; i < n; ++i) {
    xu_[i] = p.x[i] + p.ix[i] * b.len.x;
    yu_[i] = p.y[i] + p.iy[i] * b.len.y;
    zu_[i] = p.z[i] + p.iz[i] * b.len.z;
  }
  a_->sample(ctx.step, static_cast<double>(ctx.step) * dt_, p.id.data(), xu_.data(), yu_.data(), zu_.data(), n);
}

std::string MsdStage::finish(const StepContext&) {
  if (!a_ || a_->size() <= 2) return {};
  if (out_.files()) a_->write_csv((out_ / "msd.csv").string());
  return fmt::format("self-diffusion coefficient D = {:.5f}\n", a_->diffusion_coefficient());
}

}  // namespace mesodpd
