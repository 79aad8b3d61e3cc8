// A droplet in its vapour: centre, radial profile, equimolar radius, inside and outside pressure.
#include "analysis/droplet.hpp"
#include "parallel/comm.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

#include "io/atomic_file.hpp"
#include "io/json_number.hpp"

namespace mesodpd {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double sphere_volume(double r) { return 4.0 / 3.0 * std::numbers::pi * r * r * r; }

std::array<double, 3> lengths(const Box& box) { return {box.len.x, box.len.y, box.len.z}; }

// Minimum-image displacement of particle i from the point c.
std::array<double, 3> displacement(const ParticleData& p, std::size_t i, const std::array<double, 3>& c, const Box& box) {
  return {minimum_image(p.x[i] - c[0], box.image_len(0), box.half_image_len(0)),
          minimum_image(p.y[i] - c[1], box.image_len(1), box.half_image_len(1)),
          minimum_image(p.z[i] - c[2], box.image_len(2), box.half_image_len(2))};
}

}  // namespace

std::array<double, 3> droplet_centre(const ParticleData& p, const std::vector<double>& species_mass, const Box& box,
                                     double radius, int passes) {
  const std::array<double, 3> len = lengths(box);
  const double* pos[3] = {p.x.data(), p.y.data(), p.z.data()};
  std::array<double, 3> c{0, 0, 0};
  // Circular mean: each coordinate as an angle on the circle of its axis.
  for (std::size_t d = 0; d < 3; ++d) {
    double sc = 0, ss = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const double m = species_mass[static_cast<std::size_t>(p.species[i])];
      const double theta = 2.0 * std::numbers::pi * pos[d][i] / len[d];
      sc += m * std::cos(theta);
      ss += m * std::sin(theta);
    }
    c[d] = len[d] * (std::atan2(-ss, -sc) + std::numbers::pi) / (2.0 * std::numbers::pi);
  }
  // Refinement: the mean displacement of the particles near the current centre (the drop), which the
  // vapour beyond `radius` does not shift.
  const double r2max = radius * radius;
  for (int pass = 0; pass < passes; ++pass) {
    double sm = 0, sd[3] = {0, 0, 0};
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const auto d = displacement(p, i, c, box);
      if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= r2max) continue;
      const double m = species_mass[static_cast<std::size_t>(p.species[i])];
      sm += m;
      for (std::size_t k = 0; k < 3; ++k) sd[k] += m * d[k];
    }
    if (sm == 0) break;
    for (std::size_t k = 0; k < 3; ++k) {
      c[k] += sd[k] / sm;
      c[k] -= len[k] * std::floor(c[k] / len[k]);
    }
  }
  return c;
}

DropletAnalysis::DropletAnalysis(const DropletSpec& spec, const Box& box, double range)
    : spec_(spec), len_(lengths(box)), range_(range) {
  const double half = 0.5 * std::min({len_[0], len_[1], len_[2]});
  counts_.assign(static_cast<std::size_t>(std::floor(half / spec_.bin_width)), 0);
}

void DropletAnalysis::sample(const ParticleData& all, const std::vector<double>& species_mass, const Box& box,
                             const LocalVirial& virial) {
  sample_at(droplet_centre(all, species_mass, box, spec_.outer_radius), all, species_mass, box, virial);
}

void DropletAnalysis::sample_at(const std::array<double, 3>& c, const ParticleData& all,
                                const std::vector<double>& species_mass, const Box& box, const LocalVirial& virial) {
  const std::size_t n = all.n_local;
  std::vector<double> r(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto d = displacement(all, i, c, box);
    r[i] = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const auto bin = static_cast<std::size_t>(r[i] / spec_.bin_width);
    if (bin < counts_.size()) ++counts_[bin];
  }
  // The pressure of the particles `in_region` from their kinetic term and their share of the virial,
  // computed on the subset of particles within the interaction range of the region.
  auto pressure = [&](auto in_region, auto in_subset, double volume, double& density) {
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) m += in_subset(r[i]) ? 1 : 0;
    subset_.resize(m);
    subset_.n_local = m;
    subset_.n_ghost = 0;
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (in_subset(r[i])) all.copy_to<field::kGhost>(i, subset_, k++);
    virial(subset_, box, w_);
    double sum = 0;
    std::size_t count = 0;
    k = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (!in_subset(r[i])) continue;
      if (in_region(r[i])) {
        const double mass = species_mass[static_cast<std::size_t>(all.species[i])];
        sum += mass * (all.vx[i] * all.vx[i] + all.vy[i] * all.vy[i] + all.vz[i] * all.vz[i]) + w_[k];
        ++count;
      }
      ++k;
    }
    density = static_cast<double>(count) / volume;
    return sum / (3.0 * volume);
  };
  const double ri = spec_.inner_radius, ro = spec_.outer_radius;
  const double v_in = sphere_volume(ri), v_box = box.volume(), v_out = v_box - sphere_volume(ro);
  double rho_in = 0, rho_out = 0;
  const double p_in = pressure([&](double x) { return x < ri; }, [&](double x) { return x < ri + range_; }, v_in, rho_in);
  const double p_out = pressure([&](double x) { return x > ro; }, [&](double x) { return x > ro - range_; }, v_out, rho_out);
  // Equimolar radius: a step profile rho_in | rho_out with the box's N particles.
  const double v_e = (static_cast<double>(n) - rho_out * v_box) / (rho_in - rho_out);
  const double radius = rho_in > rho_out && v_e > 0 ? std::cbrt(3.0 * v_e / (4.0 * std::numbers::pi)) : kNaN;
  radius_.push_back(radius);
  rho_in_.push_back(rho_in);
  rho_out_.push_back(rho_out);
  p_in_.push_back(p_in);
  p_out_.push_back(p_out);
}

std::vector<double> DropletAnalysis::profile_r() const {
  std::vector<double> out(counts_.size());
  for (std::size_t b = 0; b < out.size(); ++b) out[b] = (static_cast<double>(b) + 0.5) * spec_.bin_width;
  return out;
}

std::vector<double> DropletAnalysis::profile_density() const {
  std::vector<double> out(counts_.size(), kNaN);
  if (samples() == 0) return out;
  for (std::size_t b = 0; b < out.size(); ++b) {
    const double shell = sphere_volume(static_cast<double>(b + 1) * spec_.bin_width) -
                         sphere_volume(static_cast<double>(b) * spec_.bin_width);
    out[b] = static_cast<double>(counts_[b]) / (shell * static_cast<double>(samples()));
  }
  return out;
}

DropletResult DropletAnalysis::result() const {
  const auto blocks = static_cast<std::size_t>(spec_.blocks);
  DropletResult out;
  out.radius = block_mean(radius_, blocks);
  out.rho_in = block_mean(rho_in_, blocks);
  out.rho_out = block_mean(rho_out_, blocks);
  out.p_in = block_mean(p_in_, blocks);
  out.p_out = block_mean(p_out_, blocks);
  std::vector<double> dp(p_in_.size());
  for (std::size_t k = 0; k < dp.size(); ++k) dp[k] = p_in_[k] - p_out_[k];
  out.delta_p = block_mean(dp, blocks);
  // Half-density radius: the outermost bin at or above the midpoint density, interpolated linearly
  // towards the next bin out (from outside, so that the few counts of the innermost bins do not matter).
  out.half_density_radius = kNaN;
  const std::vector<double> rho = profile_density(), r = profile_r();
  const double mid = 0.5 * (out.rho_in.mean + out.rho_out.mean);
  for (std::size_t b = rho.size() - 1; b >= 1; --b)
    if (rho[b - 1] >= mid && rho[b] < mid) {
      out.half_density_radius = r[b - 1] + (rho[b - 1] - mid) / (rho[b - 1] - rho[b]) * (r[b] - r[b - 1]);
      break;
    }
  out.sigma = 0.5 * out.delta_p.mean * out.radius.mean;
  const double rel_p = out.delta_p.err / out.delta_p.mean, rel_r = out.radius.err / out.radius.mean;
  out.sigma_err = std::fabs(out.sigma) * std::sqrt(rel_p * rel_p + rel_r * rel_r);
  return out;
}

std::string DropletAnalysis::summary() const {
  const DropletResult d = result();
  return fmt::format(
      "droplet: equimolar radius R = {:.4f} +- {:.4f} (half density {:.4f}), rho_in = {:.4f} +- {:.4f}, rho_out = "
      "{:.5f}, P_in = {:.4f} +- {:.4f}, P_out = {:.5f} +- {:.5f}, Delta P = {:.4f} +- {:.4f}, Delta P R / 2 = {:.4f} "
      "+- {:.4f} ({} samples in {} blocks)\n",
      d.radius.mean, d.radius.err, d.half_density_radius, d.rho_in.mean, d.rho_in.err, d.rho_out.mean, d.p_in.mean,
      d.p_in.err, d.p_out.mean, d.p_out.err, d.delta_p.mean, d.delta_p.err, d.sigma, d.sigma_err, d.delta_p.samples,
      d.delta_p.blocks);
}

std::string DropletAnalysis::write(const std::filesystem::path& dir) const {
  const DropletResult d = result();
  nlohmann::ordered_json j;
  auto put = [&](const std::string& key, const BlockMean& b) {
    j[key] = json_number(b.mean);
    j[key + "_err"] = json_number(b.err);
  };
  put("radius", d.radius);
  j["half_density_radius"] = json_number(d.half_density_radius);
  put("rho_in", d.rho_in);
  put("rho_out", d.rho_out);
  put("p_in", d.p_in);
  put("p_out", d.p_out);
  put("delta_p", d.delta_p);
  j["sigma_laplace"] = json_number(d.sigma);
  j["sigma_laplace_err"] = json_number(d.sigma_err);
  j["samples"] = d.delta_p.samples;
  j["blocks"] = d.delta_p.blocks;
  j["inner_radius"] = json_number(spec_.inner_radius);
  j["outer_radius"] = json_number(spec_.outer_radius);
  write_file_atomically(dir / "droplet.json", [&](std::ostream& os) { os << j.dump(2) << '\n'; });
  const std::vector<double> r = profile_r(), rho = profile_density();
  write_file_atomically(dir / "droplet_profile.csv", [&](std::ostream& os) {
    os << "r,density,count\n";
    for (std::size_t b = 0; b < r.size(); ++b) os << fmt::format("{:.6g},{:.8g},{}\n", r[b], rho[b], counts_[b]);
  });
  return summary();
}

void DropletAnalysis::save(ByteWriter& w) const {
  w.put_vector(radius_);
  w.put_vector(rho_in_);
  w.put_vector(rho_out_);
  w.put_vector(p_in_);
  w.put_vector(p_out_);
  w.put_vector(counts_);
}

void DropletAnalysis::load(ByteReader& r, const std::string& context) {
  radius_ = r.get_vector<double>();
  rho_in_ = r.get_vector<double>();
  rho_out_ = r.get_vector<double>();
  p_in_ = r.get_vector<double>();
  p_out_ = r.get_vector<double>();
  std::vector<std::uint64_t> counts = r.get_vector<std::uint64_t>();
  if (counts.size() != counts_.size())
    throw ConfigError(fmt::format("{}: the droplet profile has {} bins in the checkpoint and {} in this run "
                                  "(analysis.droplet.bin_width or the box changed)",
                                  context, counts.size(), counts_.size()));
  counts_ = std::move(counts);
}

DropletStage::DropletStage(const DropletSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot,
                           LocalVirial virial, double range, const Box& box, const Comm& comm)
    : SnapshotAnalysisStage(std::move(out), snapshot, spec.start, spec.every), virial_(std::move(virial)) {
  comm.on_root([&] { a_.emplace(spec, box, range); });
}

void DropletStage::sample(const StepContext& ctx, const ParticleData& all) {
  a_->sample(all, ctx.species_mass, ctx.box, virial_);
}

std::string DropletStage::finish(const StepContext&) {
  if (!a_ || a_->samples() == 0) return {};
  return out_.files() ? a_->write(out_.dir) : a_->summary();
}

}  // namespace mesodpd
