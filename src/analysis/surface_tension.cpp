// Surface tension of a planar slab from the pressure tensor, with a block error bar.
#include "analysis/surface_tension.hpp"
#include "analysis/thermo_output.hpp"
#include "parallel/comm.hpp"
#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "io/atomic_file.hpp"
#include "io/json_number.hpp"

namespace mesodpd {

BlockMean block_mean(const std::vector<double>& x, std::size_t blocks) {
  BlockMean out;
  const std::size_t per = blocks > 0 ? x.size() / blocks : 0;
  if (per == 0) {
    // Too few samples for blocks: the plain mean, no error bar.
    double s = 0;
    for (double v : x) s += v;
    out.samples = x.size();
    out.mean = x.empty() ? std::numeric_limits<double>::quiet_NaN() : s / static_cast<double>(x.size());
    out.err = std::numeric_limits<double>::quiet_NaN();
    return out;
  }
  const std::size_t first = x.size() - per * blocks;
  std::vector<double> means(blocks, 0.0);
  for (std::size_t b = 0; b < blocks; ++b) {
    double s = 0;
    for (std::size_t k = 0; k < per; ++k) s += x[first + b * per + k];
    means[b] = s / static_cast<double>(per);
  }
  double m = 0;
  for (double v : means) m += v;
  m /= static_cast<double>(blocks);
  double var = 0;
  for (double v : means) var += (v - m) * (v - m);
  var /= static_cast<double>(blocks - 1);
  out.mean = m;
  out.err = blocks >= 2 ? std::sqrt(var / static_cast<double>(blocks)) : std::numeric_limits<double>::quiet_NaN();
  out.samples = per * blocks;
  out.blocks = blocks;
  return out;
}

double normal_minus_tangential(const std::array<double, 6>& p, int normal_axis) {
  const int t1 = (normal_axis + 1) % 3, t2 = (normal_axis + 2) % 3;
  return p[static_cast<std::size_t>(normal_axis)] - 0.5 * (p[static_cast<std::size_t>(t1)] + p[static_cast<std::size_t>(t2)]);
}

SurfaceTension::SurfaceTension(int normal_axis, double length, std::size_t blocks)
    : axis_(normal_axis), length_(length), blocks_(blocks) {}

BlockMean SurfaceTension::result() const {
  BlockMean b = block_mean(anisotropy_, blocks_);
  b.mean *= 0.5 * length_;
  b.err *= 0.5 * length_;
  return b;
}

void SurfaceTension::write_json(const std::string& path) const {
  const BlockMean b = result();
  nlohmann::ordered_json j;
  j["sigma"] = json_number(b.mean);
  j["sigma_err"] = json_number(b.err);
  j["samples"] = b.samples;
  j["blocks"] = b.blocks;
  j["axis"] = std::string(1, "xyz"[axis_]);
  j["length"] = json_number(length_);
  write_file_atomically(path, [&](std::ostream& os) { os << j.dump(2) << '\n'; });
}

SurfaceTensionStage::SurfaceTensionStage(const SurfaceTensionSpec& spec, AnalysisOutput out, const ThermoOutput& thermo,
                                         double normal_length, const Comm& comm)
    : RootAnalysisStage(std::move(out)), spec_(spec), thermo_(thermo) {
  if (comm.root()) a_.emplace(spec_.axis, normal_length, static_cast<std::size_t>(spec_.blocks));
}

void SurfaceTensionStage::observe(const StepContext& ctx) {
  if (!a_ || ctx.step < spec_.start) return;
  if (const ThermoState* t = thermo_.row(ctx.step)) a_->add(t->p_tensor);
}

std::string SurfaceTensionStage::finish(const StepContext&) {
  if (!a_ || a_->samples() == 0) return {};
  if (out_.files()) a_->write_json((out_ / "surface_tension.json").string());
  const BlockMean b = a_->result();
  return fmt::format("surface tension sigma = {:.4f} +- {:.4f} ({} thermo rows in {} blocks, normal {})\n", b.mean,
                     b.err, b.samples, b.blocks, "xyz"[spec_.axis]);
}

}  // namespace mesodpd
