// The pressure tensor in slabs along an axis: kinetic and configurational parts, p_N, p_T, tension.
#include "analysis/stress_profile.hpp"
#include "parallel/comm.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "analysis/svg_plot.hpp"
#include "io/atomic_file.hpp"
#include "io/json_number.hpp"

namespace mesodpd {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kAxes = "xyz";
}  // namespace

StressProfile::StressProfile(const StressProfileSpec& spec, const Box& box)
    : spec_(spec),
      axis_(spec.axis),
      bins_(static_cast<std::size_t>(spec.bins)),
      len_(spec.axis == 0 ? box.len.x : (spec.axis == 1 ? box.len.y : box.len.z)),
      h_(len_ / static_cast<double>(bins_)),
      bin_volume_(box.volume() / static_cast<double>(bins_)),
      area_(box.volume() / len_),
      sums_(kPerBin * bins_, 0.0),
      blocks_(bins_, static_cast<std::size_t>(spec.blocks)) {}

void StressProfile::add_share(std::size_t bin, const double w[3], double fraction) {
  double* r = &row_[kPerBin * bin + 3];
  for (int c = 0; c < 3; ++c) r[c] += fraction * w[c];
}

void StressProfile::sample(const ParticleData& all, const std::vector<double>& species_mass,
                           const std::vector<std::uint8_t>& frozen, const VirialTerms& terms) {
  const std::size_t n = all.n_local;
  const auto& pos = axis_ == 0 ? all.x : (axis_ == 1 ? all.y : all.z);
  const auto n_bins = static_cast<std::ptrdiff_t>(bins_);
  // Slab of a coordinate, wrapped (a line of a contour may run below 0 or past L).
  auto slab = [&](double x) {
    std::ptrdiff_t k = static_cast<std::ptrdiff_t>(std::floor(x / h_)) % n_bins;
    return static_cast<std::size_t>(k < 0 ? k + n_bins : k);
  };
  auto mobile = [&](std::size_t i) { return frozen.empty() || !frozen[static_cast<std::size_t>(all.species[i])]; };
  row_.assign(kPerBin * bins_, 0.0);
  // Kinetic part: velocities relative to the centre of mass of the mobile particles.
  double mass = 0, mom[3] = {0, 0, 0};
  for (std::size_t i = 0; i < n; ++i) {
    if (!mobile(i)) continue;
    const double m = species_mass[static_cast<std::size_t>(all.species[i])];
    mass += m;
    mom[0] += m * all.vx[i];
    mom[1] += m * all.vy[i];
    mom[2] += m * all.vz[i];
  }
  const double vc[3] = {mass > 0 ? mom[0] / mass : 0, mass > 0 ? mom[1] / mass : 0, mass > 0 ? mom[2] / mass : 0};
  for (std::size_t i = 0; i < n; ++i) {
    double* r = &row_[kPerBin * slab(pos[i])];
    r[6] += 1.0;
    if (!mobile(i)) continue;
    const double m = species_mass[static_cast<std::size_t>(all.species[i])];
    const double u[3] = {all.vx[i] - vc[0], all.vy[i] - vc[1], all.vz[i] - vc[2]};
    for (int c = 0; c < 3; ++c) r[c] += m * u[c] * u[c];
  }
  // Configurational part: each term's d (x) f (diagonal) shared out over the slabs.
  for (const VirialTerm& t : terms) {
    const double w[3] = {t.d[0] * t.f[0], t.d[1] * t.f[1], t.d[2] * t.f[2]};
    const double zj = pos[t.j];
    if (spec_.assignment == StressAssignment::Half) {
      add_share(slab(pos[t.i]), w, 0.5);
      add_share(slab(zj), w, 0.5);
      continue;
    }
    // The straight line from r_j to r_j + d (= r_i, unwrapped) along the axis.
    const double zi = zj + t.d[axis_];
    const double lo = std::min(zi, zj), hi = std::max(zi, zj), length = hi - lo;
    const double k0 = std::floor(lo / h_), k1 = std::floor(hi / h_);
    if (k0 == k1) {  // within one slab (also a line normal to the axis)
      add_share(slab(lo), w, 1.0);
      continue;
    }
    for (double k = k0; k <= k1; k += 1.0) {
      const double a = std::max(lo, k * h_), b = std::min(hi, (k + 1.0) * h_);
      if (b > a) add_share(slab((k + 0.5) * h_), w, (b - a) / length);
    }
  }
  // Pressures per slab; the tension from p_N - p_T.
  aniso_.assign(bins_, 0.0);
  double gamma = 0;
  const int t1 = (axis_ + 1) % 3, t2 = (axis_ + 2) % 3;
  for (std::size_t b = 0; b < bins_; ++b) {
    double* r = &row_[kPerBin * b];
    for (std::size_t k = 0; k < 6; ++k) r[k] /= bin_volume_;
    r[6] /= bin_volume_;
    const double pn = r[axis_] + r[3 + axis_];
    const double pt = 0.5 * (r[t1] + r[3 + t1] + r[t2] + r[3 + t2]);
    aniso_[b] = pn - pt;
    gamma += aniso_[b];
    for (std::size_t k = 0; k < kPerBin; ++k) sums_[kPerBin * b + k] += r[k];
  }
  gamma_.push_back(gamma * h_);
  blocks_.add(aniso_.data());
}

double StressProfile::mean(std::size_t b, std::size_t k) const {
  return samples() == 0 ? kNaN : sums_[kPerBin * b + k] / static_cast<double>(samples());
}

double StressProfile::tangential(std::size_t b) const {
  const int t1 = (axis_ + 1) % 3, t2 = (axis_ + 2) % 3;
  return 0.5 * (pressure(b, t1) + pressure(b, t2));
}

std::vector<double> StressProfile::z() const {
  std::vector<double> out(bins_);
  for (std::size_t b = 0; b < bins_; ++b) out[b] = (static_cast<double>(b) + 0.5) * h_;
  return out;
}

std::vector<double> StressProfile::anisotropy_err() const {
  std::vector<double> out(bins_, kNaN);
  const std::size_t nb = blocks_.full_blocks();
  if (nb < 2) return out;
  const double per = static_cast<double>(blocks_.samples_per_block());
  for (std::size_t b = 0; b < bins_; ++b) {
    double m = 0, m2 = 0;
    for (std::size_t k = 0; k < nb; ++k) {
      const double v = blocks_.block(k)[b] / per;
      m += v;
      m2 += v * v;
    }
    m /= static_cast<double>(nb);
    const double var = std::max(0.0, (m2 - static_cast<double>(nb) * m * m) / static_cast<double>(nb - 1));
    out[b] = std::sqrt(var / static_cast<double>(nb));
  }
  return out;
}

std::array<double, 3> StressProfile::box_kinetic() const {
  std::array<double, 3> out{0, 0, 0};
  for (std::size_t b = 0; b < bins_; ++b)
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(c)] += kinetic(b, c) / static_cast<double>(bins_);
  return out;
}

std::array<double, 3> StressProfile::box_configurational() const {
  std::array<double, 3> out{0, 0, 0};
  for (std::size_t b = 0; b < bins_; ++b)
    for (int c = 0; c < 3; ++c) out[static_cast<std::size_t>(c)] += configurational(b, c) / static_cast<double>(bins_);
  return out;
}

BlockMean StressProfile::tension() const {
  BlockMean out = block_mean(gamma_, static_cast<std::size_t>(spec_.blocks));
  // The mean over every sample, so that it is the integral of the written profile.
  double s = 0;
  for (const double g : gamma_) s += g;
  out.mean = gamma_.empty() ? kNaN : s / static_cast<double>(gamma_.size());
  out.samples = gamma_.size();
  return out;
}

std::string StressProfile::summary() const {
  const BlockMean g = tension();
  const auto k = box_kinetic(), c = box_configurational();
  return fmt::format(
      "stress profile ({} bins along {}, {} assignment): tension int (p_N - p_T) d{} = {:.4f} +- {:.4f}; box "
      "P_xx, P_yy, P_zz = {:.4f}, {:.4f}, {:.4f} (kinetic {:.4f}, {:.4f}, {:.4f}) ({} samples, {} blocks)\n",
      bins_, kAxes[axis_], spec_.assignment == StressAssignment::Contour ? "contour" : "half", kAxes[axis_], g.mean,
      g.err, k[0] + c[0], k[1] + c[1], k[2] + c[2], k[0], k[1], k[2], g.samples, g.blocks);
}

std::string StressProfile::write(const std::filesystem::path& dir) const {
  const BlockMean g = tension();
  const auto kin = box_kinetic(), conf = box_configurational();
  nlohmann::ordered_json j;
  j["axis"] = std::string(1, kAxes[axis_]);
  j["bins"] = bins_;
  j["assignment"] = spec_.assignment == StressAssignment::Contour ? "contour" : "half";
  j["tension"] = json_number(g.mean);
  j["tension_err"] = json_number(g.err);
  j["samples"] = g.samples;
  j["blocks"] = g.blocks;
  j["length"] = json_number(len_);
  j["area"] = json_number(area_);
  for (int c = 0; c < 3; ++c) {
    const auto k = static_cast<std::size_t>(c);
    j[fmt::format("p_{0}{0}", kAxes[c])] = json_number(kin[k] + conf[k]);
  }
  for (int c = 0; c < 3; ++c) j[fmt::format("kinetic_{0}{0}", kAxes[c])] = json_number(kin[static_cast<std::size_t>(c)]);
  for (int c = 0; c < 3; ++c)
    j[fmt::format("configurational_{0}{0}", kAxes[c])] = json_number(conf[static_cast<std::size_t>(c)]);
  write_file_atomically(dir / "stress_profile.json", [&](std::ostream& os) { os << j.dump(2) << '\n'; });
  const std::vector<double> zs = z(), err = anisotropy_err();
  const int t1 = (axis_ + 1) % 3, t2 = (axis_ + 2) % 3;
  write_file_atomically(dir / "stress_profile.csv", [&](std::ostream& os) {
    os << "z,density,p_xx,p_yy,p_zz,p_n,p_t,p_n_minus_p_t,p_n_minus_p_t_err,kinetic_n,kinetic_t,configurational_n,"
          "configurational_t\n";
    for (std::size_t b = 0; b < bins_; ++b)
      os << fmt::format("{:.6g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.10g},{:.6g},{:.10g},{:.10g},{:.10g},{:.10g}\n",
                        zs[b], density(b), pressure(b, 0), pressure(b, 1), pressure(b, 2), normal(b), tangential(b),
                        normal(b) - tangential(b), err[b], kinetic(b, axis_),
                        0.5 * (kinetic(b, t1) + kinetic(b, t2)), configurational(b, axis_),
                        0.5 * (configurational(b, t1) + configurational(b, t2)));
  });
  std::vector<double> aniso(bins_), pn(bins_), pt(bins_);
  for (std::size_t b = 0; b < bins_; ++b) {
    pn[b] = normal(b);
    pt[b] = tangential(b);
    aniso[b] = pn[b] - pt[b];
  }
  write_svg_plot((dir / "stress_profile.svg").string(), "Stress profile", std::string(1, kAxes[axis_]), "pressure",
                 {SvgSeries{zs, aniso, err, "p_N - p_T", "#d62728", true, true},
                  SvgSeries{zs, pn, {}, "p_N", "#1f77b4", true, false},
                  SvgSeries{zs, pt, {}, "p_T", "#2ca02c", true, false}},
                 {fmt::format("tension = {:.4f} +- {:.4f}", g.mean, g.err)});
  return summary();
}

void StressProfile::save(ByteWriter& w) const {
  w.put_vector(sums_);
  w.put_vector(gamma_);
  blocks_.save(w);
}

void StressProfile::load(ByteReader& r, const std::string& context) {
  std::vector<double> sums = r.get_vector<double>();
  if (sums.size() != sums_.size())
    throw ConfigError(fmt::format("{}: the stress profile has {} bins in the checkpoint and {} in this run "
                                  "(analysis.stress_profile.bins changed)",
                                  context, sums.size() / kPerBin, bins_));
  sums_ = std::move(sums);
  gamma_ = r.get_vector<double>();
  blocks_.load(r, context);
}

StressProfileStage::StressProfileStage(const SimulationSpec& spec, AnalysisOutput out, SystemSnapshot& snapshot,
                                       VirialTermsOf virial_terms, const Box& box, const Comm& comm)
    : SnapshotAnalysisStage(std::move(out), snapshot, spec.stress_profile.start, spec.stress_profile.every),
      virial_terms_(std::move(virial_terms)) {
  for (const auto& sp : spec.species) frozen_.push_back(sp.frozen ? 1 : 0);
  comm.on_root([&] { a_.emplace(spec.stress_profile, box); });
}

void StressProfileStage::sample(const StepContext& ctx, const ParticleData& p) {
  terms_.clear();
  virial_terms_(p, ctx.box, terms_);
  a_->sample(p, ctx.species_mass, frozen_, terms_);
}

std::string StressProfileStage::finish(const StepContext&) {
  if (!a_ || a_->samples() == 0) return {};
  return out_.files() ? a_->write(out_.dir) : a_->summary();
}

}  // namespace mesodpd
