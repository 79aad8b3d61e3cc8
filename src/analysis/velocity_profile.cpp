// Binned flow profile of reverse Poiseuille flow and the shear viscosity fitted to it, with block errors.
#include "analysis/velocity_profile.hpp"
#include <nlohmann/json.hpp>
#include <span>
#include "analysis/kinetic_theory.hpp"
#include "analysis/svg_plot.hpp"
#include "io/json_number.hpp"
#include "parallel/comm.hpp"
#include "io/atomic_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mesodpd {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Antiderivative of the signed parabola phi(z) = z (h - z) on [0, h], -(z - h)(2h - z) on [h, 2h].
// Bin-averaging phi exactly (instead of taking it at the bin centre) removes an offset of
// -/+ dz^2 / 12 that has opposite signs in the two halves and would bias the fitted c.
double basis_antiderivative(double z, double h) {
  const auto lower = [h](double u) { return h * u * u / 2.0 - u * u * u / 3.0; };
  if (z <= h) return lower(z);
  return lower(h) - lower(z - h);
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

// Standard error of the mean of independent estimates (sample std / sqrt(n)).
double standard_error(const std::vector<double>& v) {
  if (v.size() < 2) return kNaN;
  const double m = mean(v);
  double ss = 0.0;
  for (double x : v) ss += (x - m) * (x - m);
  const auto n = static_cast<double>(v.size());
  return std::sqrt(ss / (n - 1.0) / n);
}

}  // namespace

PoiseuilleProfile::PoiseuilleProfile(std::size_t bins, int flow_axis, int gradient_axis, double box_len,
                                     std::size_t blocks, double force_g, double mass_density)
    : bins_(bins),
      flow_axis_(flow_axis),
      gradient_axis_(gradient_axis),
      len_(box_len),
      blocks_(blocks),
      force_g_(force_g),
      mass_density_(mass_density) {
  if (bins < 2) throw std::invalid_argument("PoiseuilleProfile: bins must be >= 2");
  if (flow_axis < 0 || flow_axis > 2 || gradient_axis < 0 || gradient_axis > 2 ||
      flow_axis == gradient_axis) {
    throw std::invalid_argument(
        "PoiseuilleProfile: flow_axis and gradient_axis must be distinct axes in 0..2");
  }
  if (!(box_len > 0.0)) throw std::invalid_argument("PoiseuilleProfile: box_len must be > 0");
  if (blocks < 2) throw std::invalid_argument("PoiseuilleProfile: blocks must be >= 2");
  if (!(force_g != 0.0) || !std::isfinite(force_g)) {
    throw std::invalid_argument("PoiseuilleProfile: force_g must be finite and non-zero");
  }
  if (!(mass_density > 0.0)) throw std::invalid_argument("PoiseuilleProfile: mass_density must be > 0");

  const double h = 0.5 * len_;
  const double dz = len_ / static_cast<double>(bins_);
  basis_.resize(bins_);
  for (std::size_t b = 0; b < bins_; ++b) {
    const double lo = static_cast<double>(b) * dz;
    basis_[b] = (basis_antiderivative(lo + dz, h) - basis_antiderivative(lo, h)) / dz;
  }
  blocks_rows_ = BlockRows(2 * bins_, blocks_);
  row_.assign(2 * bins_, 0.0);
  total_vsum_.assign(bins_, 0.0);
  total_count_.assign(bins_, 0.0);
}

namespace {
constexpr double kVelocityScale = 4294967296.0;  // 2^32 fixed-point units per velocity unit
}

void PoiseuilleProfile::bin(const double* pos_gradient_coord, const double* v_flow, std::size_t n, std::size_t bins,
                            double box_len, std::int64_t* sums) {
  const double inv_dz = static_cast<double>(bins) / box_len;
  for (std::size_t i = 0; i < n; ++i) {
    const double w = pos_gradient_coord[i] - box_len * std::floor(pos_gradient_coord[i] / box_len);
    const std::size_t b = std::min(static_cast<std::size_t>(w * inv_dz), bins - 1);
    sums[b] += static_cast<std::int64_t>(std::llround(v_flow[i] * kVelocityScale));
    sums[bins + b] += 1;
  }
}

void PoiseuilleProfile::sample(const double* pos_gradient_coord, const double* v_flow, std::size_t n) {
  std::vector<std::int64_t> sums(2 * bins_, 0);
  bin(pos_gradient_coord, v_flow, n, bins_, len_, sums.data());
  add_binned(sums.data());
}

void PoiseuilleProfile::add_binned(const std::int64_t* sums) {
  for (std::size_t b = 0; b < bins_; ++b) {
    const double v = static_cast<double>(sums[b]) / kVelocityScale;
    const double c = static_cast<double>(sums[bins_ + b]);
    row_[b] = v;
    row_[bins_ + b] = c;
    total_vsum_[b] += v;
    total_count_[b] += c;
  }
  ++samples_;
  blocks_rows_.add(row_.data());
}

PoiseuilleProfile::LineFit PoiseuilleProfile::fit_profile(const double* vsum, const double* count) const {
  // Centred normal equations for v = c * basis + v0 over the bins that hold particles.
  double np = 0.0, xm = 0.0, ym = 0.0;
  for (std::size_t b = 0; b < bins_; ++b) {
    if (count[b] <= 0.0) continue;
    np += 1.0;
    xm += basis_[b];
    ym += vsum[b] / count[b];
  }
  if (np < 2.0) return {kNaN, kNaN};
  xm /= np;
  ym /= np;
  double sxx = 0.0, sxy = 0.0;
  for (std::size_t b = 0; b < bins_; ++b) {
    if (count[b] <= 0.0) continue;
    const double dx = basis_[b] - xm;
    sxx += dx * dx;
    sxy += dx * (vsum[b] / count[b] - ym);
  }
  if (!(sxx > 0.0)) return {kNaN, kNaN};
  const double c = sxy / sxx;
  return {c, ym - c * xm};
}

ViscosityFit PoiseuilleProfile::fit() const {
  const double rho_g = mass_density_ * force_g_;
  const LineFit all = fit_profile(total_vsum_.data(), total_count_.data());
  ViscosityFit out{};
  out.eta = rho_g / (2.0 * all.c);  // c = rho_m g / (2 eta)
  out.v_amplitude = all.c * len_ * len_ / 16.0;
  std::vector<double> etas;
  for (std::size_t k = 0; k < blocks_rows_.full_blocks(); ++k) {
    const LineFit f = fit_profile(blocks_rows_.block(k), blocks_rows_.block(k) + bins_);
    etas.push_back(rho_g / (2.0 * f.c));
  }
  out.blocks_used = static_cast<int>(blocks_rows_.full_blocks());
  out.eta_err = standard_error(etas);
  return out;
}

std::vector<double> PoiseuilleProfile::z() const {
  std::vector<double> out(bins_);
  const double dz = len_ / static_cast<double>(bins_);
  for (std::size_t b = 0; b < bins_; ++b) out[b] = (static_cast<double>(b) + 0.5) * dz;
  return out;
}

std::vector<double> PoiseuilleProfile::v_mean() const {
  std::vector<double> out(bins_, kNaN);
  for (std::size_t b = 0; b < bins_; ++b) {
    if (total_count_[b] > 0.0) out[b] = total_vsum_[b] / total_count_[b];
  }
  return out;
}

std::vector<double> PoiseuilleProfile::v_err() const {
  std::vector<double> out(bins_, kNaN);
  std::vector<double> means;
  for (std::size_t b = 0; b < bins_; ++b) {
    means.clear();
    for (std::size_t k = 0; k < blocks_rows_.full_blocks(); ++k) {
      const double cnt = blocks_rows_.block(k)[bins_ + b];
      if (cnt > 0.0) means.push_back(blocks_rows_.block(k)[b] / cnt);
    }
    out[b] = standard_error(means);
  }
  return out;
}

std::vector<double> PoiseuilleProfile::v_fit() const {
  const LineFit f = fit_profile(total_vsum_.data(), total_count_.data());
  std::vector<double> out(bins_);
  for (std::size_t b = 0; b < bins_; ++b) out[b] = f.c * basis_[b] + f.v0;
  return out;
}

void PoiseuilleProfile::write_csv(const std::string& path) const {
  const auto zz = z();
  const auto vm = v_mean();
  const auto ve = v_err();
  const auto vf = v_fit();
  write_file_atomically(path, [&](std::ostream& os) {
    os << "z,v_mean,v_err,v_fit\n";
    for (std::size_t b = 0; b < bins_; ++b) os << fmt::format("{:.10g},{:.10g},{:.10g},{:.10g}\n", zz[b], vm[b], ve[b], vf[b]);
  });
}

void write_viscosity_summary_csv(const std::string& path, const ViscosityFit& fit, double eta_kinetic) {
  write_file_atomically(path, [&](std::ostream& os) {
    os << "eta,eta_err,v_amplitude,blocks_used,eta_kinetic\n";
    os << fmt::format("{:.10g},{:.10g},{:.10g},{},{:.10g}\n", fit.eta, fit.eta_err, fit.v_amplitude, fit.blocks_used,
                      eta_kinetic);
  });
}

void PoiseuilleProfile::save(ByteWriter& w) const {
  w.put<std::uint64_t>(bins_);
  w.put<std::uint64_t>(blocks_);
  w.put<std::uint64_t>(samples_);
  w.put<std::uint64_t>(blocks_rows_.samples_per_block());
  w.put<std::uint64_t>(blocks_rows_.full_blocks());
  w.put<std::uint64_t>(blocks_rows_.in_current());
  // Flow sums and counts as two 2B x bins arrays (the checkpoint layout from before BlockRows).
  const std::vector<double>& rows = blocks_rows_.sums();
  std::vector<double> vsum(2 * blocks_ * bins_), count(2 * blocks_ * bins_);
  for (std::size_t r = 0; r < 2 * blocks_; ++r)
    for (std::size_t b = 0; b < bins_; ++b) {
      vsum[r * bins_ + b] = rows[r * 2 * bins_ + b];
      count[r * bins_ + b] = rows[r * 2 * bins_ + bins_ + b];
    }
  w.put_vector(vsum);
  w.put_vector(count);
  w.put_vector(total_vsum_);
  w.put_vector(total_count_);
}

void PoiseuilleProfile::load(ByteReader& r, const std::string& context) {
  const auto bins = r.get<std::uint64_t>(), blocks = r.get<std::uint64_t>();
  if (bins != bins_ || blocks != blocks_)
    throw ConfigError(fmt::format("poiseuille.bins/blocks: {}/{} differ from the checkpoint's {}/{} ({})", bins_,
                                  blocks_, bins, blocks, context));
  samples_ = r.get<std::uint64_t>();
  const auto block_size = r.get<std::uint64_t>(), full = r.get<std::uint64_t>(), in_current = r.get<std::uint64_t>();
  const std::vector<double> vsum = r.get_vector<double>(), count = r.get_vector<double>();
  total_vsum_ = r.get_vector<double>();
  total_count_ = r.get_vector<double>();
  if (total_vsum_.size() != bins_ || total_count_.size() != bins_ || vsum.size() != 2 * blocks_ * bins_ ||
      count.size() != vsum.size())
    throw ConfigError(fmt::format("{}: inconsistent Poiseuille profile state", context));
  std::vector<double> rows(4 * blocks_ * bins_);
  for (std::size_t r2 = 0; r2 < 2 * blocks_; ++r2)
    for (std::size_t b = 0; b < bins_; ++b) {
      rows[r2 * 2 * bins_ + b] = vsum[r2 * bins_ + b];
      rows[r2 * 2 * bins_ + bins_ + b] = count[r2 * bins_ + b];
    }
  blocks_rows_.restore(block_size, full, in_current, std::move(rows), context);
}

VelocityProfileStage::VelocityProfileStage(const SimulationSpec& spec, AnalysisOutput out, const StepContext& start)
    : RootAnalysisStage(std::move(out)), spec_(spec) {
  const PoiseuilleSpec& q = spec_.poiseuille;
  // The fluid's mass: integer counts per species (exact over ranks) times the species masses.
  std::vector<std::uint64_t> count(spec_.species.size(), 0);
  const ParticleData& own = start.particles;
  for (std::size_t i = 0; i < own.n_local; ++i) ++count[static_cast<std::size_t>(own.species[i])];
  start.comm.sum(std::span<std::uint64_t>(count));
  double mass = 0;
  for (std::size_t k = 0; k < count.size(); ++k) mass += static_cast<double>(count[k]) * spec_.species[k].mass;
  const Box& box = start.box;
  start.comm.on_root([&] {
    a_.emplace(static_cast<std::size_t>(q.bins), q.flow_axis, q.gradient_axis, box.length(q.gradient_axis),
               static_cast<std::size_t>(q.blocks), q.force, mass / box.volume());
  });
}

void VelocityProfileStage::observe(const StepContext& ctx) {
  if (!due(ctx.step)) return;
  const PoiseuilleSpec& q = spec_.poiseuille;
  // Each rank bins its own particles into integer sums; only the per-bin totals travel.
  const ParticleData& own = ctx.particles;
  const auto& grad = q.gradient_axis == 0 ? own.x : (q.gradient_axis == 1 ? own.y : own.z);
  const auto& flow = q.flow_axis == 0 ? own.vx : (q.flow_axis == 1 ? own.vy : own.vz);
  const auto bins = static_cast<std::size_t>(q.bins);
  bins_.assign(2 * bins, 0);
  PoiseuilleProfile::bin(grad.data(), flow.data(), own.n_local, bins, ctx.box.length(q.gradient_axis), bins_.data());
  ctx.comm.sum(std::span<std::int64_t>(bins_));
  if (a_) a_->add_binned(bins_.data());
}

std::string VelocityProfileStage::finish(const StepContext& ctx) {
  if (!a_) return {};
  const SimulationSpec& s = spec_;
  const PoiseuilleProfile& profile = *a_;
  const double rho = static_cast<double>(ctx.total_particles) / ctx.box.volume();
  // Kinetic theory only where one set of pair parameters describes the fluid (kinetic_theory.hpp).
  const KineticViscosity theory = kinetic_viscosity_of(s, rho);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double eta_theory = theory.applies ? theory.eta : nan;
  const std::string theory_text =
      theory.applies ? fmt::format("kinetic theory, seed 000 Eq. 16 / Table 1: {:.4f}", theory.eta)
                     : fmt::format("no kinetic-theory value for {}", theory.why_not);
  // One `a` for the plot's legend where all pairs share it.
  bool one_a = true;
  for (const PairSpec& q : s.pairs) one_a = one_a && q.a == s.pairs.front().a;
  if (profile.samples() < 2)
    return "reverse Poiseuille: too few profile samples for a viscosity (run longer than poiseuille.start)\n";
  const ViscosityFit fit = profile.fit();
  std::string summary =
      fmt::format("reverse Poiseuille viscosity eta = {:.4f} +- {:.4f} ({})\n", fit.eta, fit.eta_err, theory_text);
  if (!out_.files()) return summary;
  profile.write_csv((out_ / "poiseuille_profile.csv").string());
  write_viscosity_summary_csv((out_ / "viscosity.csv").string(), fit, eta_theory);
  nlohmann::ordered_json summary_json;  // keys in the order written
  summary_json["eta"] = json_number(fit.eta);
  summary_json["eta_err"] = json_number(fit.eta_err);
  summary_json["eta_kinetic_theory"] = json_number(eta_theory);
  summary_json["blocks"] = fit.blocks_used;
  summary_json["samples"] = profile.samples();
  summary_json["density"] = json_number(rho);
  summary_json["gamma"] = theory.applies ? json_number(theory.gamma) : nullptr;
  summary_json["s"] = theory.applies ? json_number(theory.s) : nullptr;
  summary_json["force"] = json_number(s.poiseuille.force);
  write_file_atomically(out_ / "viscosity.json", [&](std::ostream& os) { os << summary_json.dump(2) << '\n'; });
  SvgSeries data{profile.z(), profile.v_mean(), profile.v_err(), "measured", "#1f77b4", false, true};
  SvgSeries model{profile.z(), profile.v_fit(), {}, "parabolic fit", "#d62728", true, false};
  const char* axes = "xyz";
  write_svg_plot((out_ / "velocity_profile.svg").string(), "Reverse Poiseuille flow: velocity profile",
                 fmt::format("{} (gradient axis)", axes[s.poiseuille.gradient_axis]),
                 fmt::format("mean v_{}", axes[s.poiseuille.flow_axis]), {data, model},
                 {fmt::format("eta = {:.4f} +- {:.4f}", fit.eta, fit.eta_err),
                  theory.applies ? fmt::format("kinetic theory (seed 000 Eq. 16): {:.4f}", theory.eta)
                                 : fmt::format("kinetic theory: none for {}", theory.why_not),
                  theory.applies && one_a
                      ? fmt::format("rho = {:.3g}, a = {:.3g}, gamma = {:.3g}, s = {:.3g}, g = {:.3g}", rho,
                                    s.pairs.front().a, theory.gamma, theory.s, s.poiseuille.force)
                      : fmt::format("rho = {:.3g}, {} species, g = {:.3g}", rho, s.species.size(),
                                    s.poiseuille.force)});
  return summary;
}

}  // namespace mesodpd
