// The flux of a transported scalar through planes and out of walls ([analysis.flux], scalar_flux.hpp).
#include "analysis/scalar_flux.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analysis/surface_tension.hpp"
#include "io/atomic_file.hpp"
#include "io/json_number.hpp"
#include "mesodpd/config_error.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kRateScale = 4294967296.0;  // 2^32: the fixed point of the walls' per-step sums
__extension__ using Int128 = __int128;

// The pooled value with the standard error of the per-block values (block_mean with one value a block).
FluxEstimate over_blocks(const std::vector<double>& v, double pooled) { return {pooled, block_mean(v, v.size()).err}; }

std::string pm(const FluxEstimate& e) { return fmt::format("{:.5g} +- {:.2g}", e.value, e.error); }

}  // namespace

const keys::KeyTable<FluxSpec>& flux_keys() {
  using T = FluxSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.flux");
    t.string("field", &T::field,
             "The transported scalar: `temp` (pair.style = \"edpd\": the heat C_v T) or `conc1` .. `conc4` "
             "(pair.style = \"tdpd\": a solute).")
        .default_text("\"temp\"");
    t.axis("axis", &T::axis, "The planes' normal; the flux is counted positive towards +axis.").required("(x, y or z)");
    t.number("position", &T::position, keys::kFinite, "Where the first plane lies along `axis`.")
        .required("(a coordinate inside the box)")
        .unit("r_c");
    t.integer("planes", &T::planes, {1, 1000}, "Number of planes, at position + k x spacing, k = 0 .. planes - 1.");
    t.number("spacing", &T::spacing, keys::kPositive, "Distance between neighbouring planes.").unit("r_c");
    t.number("slab", &T::slab, keys::kPositive,
             "Half-width h of the slab about a plane whose particles give the convective part, (1 / 2hA) sum "
             "cap_i (X_i - Xbar) v_i.")
        .unit("r_c");
    t.number("fit", &T::fit, keys::kPositive,
             "Half-width of the window about a plane over which the profile's gradient (and the local density) is "
             "fitted for the conductivity and the diffusivity.")
        .unit("r_c");
    t.number("bin", &T::bin, keys::kPositive, "Width of the profile's bins along `axis` (rounded so that they divide the box).")
        .unit("r_c");
    t.integer("start", &T::start, {0}, "First sampled step (let the profile reach its steady state before it).");
    t.integer("every", &T::every, {1},
              "Steps between samples of the planes; the walls' exchange is read at every step. A sample gathers the "
              "system on rank 0 and passes over its pairs (serial): at every = 10 a 2,160-particle run took 1.5 "
              "times as long as without the analysis (docs/performance.md, session 18); sample less often in large "
              "systems.");
    t.integer("blocks", &T::blocks, {2, 1000}, "Blocks of the error bars (each its own flux, gradient, conductivity).");
    return t;
  }();
  return table;
}

void check_flux(const FluxSpec& f, const std::array<double, 3>& box) {
  const double len = box[static_cast<std::size_t>(f.axis)];
  const std::string p = "analysis.flux.";
  for (int k = 0; k < f.planes; ++k) {
    const double z = f.position + k * f.spacing;
    if (!(z > 0 && z < len))
      keys::fail(k == 0 ? p + "position" : p + "spacing", fmt::format("{}", k == 0 ? f.position : f.spacing),
                 fmt::format("plane {} (of {}) lies at {}, outside the box: every plane must lie strictly between 0 "
                             "and {} along {}",
                             k + 1, f.planes, z, len, "xyz"[f.axis]));
  }
  if (2 * f.slab >= len)
    keys::fail(p + "slab", fmt::format("{}", f.slab), fmt::format("the slab (2 x slab) must be narrower than the box ({})", len));
  if (2 * f.fit >= len)
    keys::fail(p + "fit", fmt::format("{}", f.fit), fmt::format("the fit window (2 x fit) must be narrower than the box ({})", len));
  if (f.bin > f.fit)
    keys::fail(p + "bin", fmt::format("{}", f.bin),
               fmt::format("must not exceed analysis.flux.fit = {} (the fit needs two bins or more)", f.fit));
}

ScalarFlux::ScalarFlux(const FluxSpec& spec, const std::array<double, 3>& box, const std::array<bool, 3>& periodic,
                       std::vector<double> capacity, std::vector<std::uint8_t> frozen, std::vector<std::string> names)
    : spec_(spec),
      axis_(spec.axis),
      len_(box[static_cast<std::size_t>(spec.axis)]),
      area_(box[0] * box[1] * box[2] / box[static_cast<std::size_t>(spec.axis)]),
      periodic_(periodic[static_cast<std::size_t>(spec.axis)]),
      capacity_(std::move(capacity)),
      frozen_(std::move(frozen)),
      names_(std::move(names)) {
  bins_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(len_ / spec.bin)));
  bin_width_ = len_ / static_cast<double>(bins_);
  for (int k = 0; k < spec.planes; ++k) planes_.push_back(spec.position + k * spec.spacing);
  for (std::size_t s = 0; s < frozen_.size(); ++s)
    if (frozen_[s]) walls_.push_back(s);
  total_.assign(width(), 0.0);
  row_.assign(width(), 0.0);
  blocks_ = BlockRows(width(), static_cast<std::size_t>(spec.blocks));
}

void ScalarFlux::sample(const ParticleData& all, const Box& box, const ScalarExchangeOf& exchange,
                        const std::vector<double>& wall_rates) {
  if (wall_rates.size() != walls_.size()) throw std::invalid_argument("ScalarFlux: one rate per wall expected");
  const std::vector<double>* xs = all.doubles(spec_.field);
  if (xs == nullptr) throw std::invalid_argument("ScalarFlux: the snapshot does not hold " + spec_.field);
  const std::vector<double>& x = *xs;
  const std::vector<double>& pos = axis_ == 0 ? all.x : (axis_ == 1 ? all.y : all.z);
  const std::vector<double>& vel = axis_ == 0 ? all.vx : (axis_ == 1 ? all.vy : all.vz);
  const std::size_t np = planes_.size();
  std::fill(row_.begin(), row_.end(), 0.0);
  // The signed distance of z from plane P (minimum image along a periodic axis).
  const auto from = [&](double z, double plane) {
    double d = z - plane;
    if (periodic_) d -= len_ * std::round(d / len_);
    return d;
  };
  // Pairs: i at z_j + d (d = z_i - z_j, the minimum image), j at z_j; the pair straddles P where the two
  // ends lie on opposite sides of P or of one of its images.
  const auto side = [&](double zj, double d, double plane) {
    // +1: i above, j below; -1: i below, j above; 0: not straddling.
    for (int m = periodic_ ? -1 : 0; m <= (periodic_ ? 1 : 0); ++m) {
      const double p = plane + m * len_;
      const double a = zj - p, b = zj + d - p;
      if (a < 0 && b >= 0) return 1;
      if (a >= 0 && b < 0) return -1;
    }
    return 0;
  };
  // The exchange calls want() and then, for an accepted pair, visit() for the same pair: the pair's
  // displacement along the axis is kept between the two.
  double last_d = 0;
  exchange(
      all, box,
      [&](std::size_t, std::size_t j, double dx, double dy, double dz) {
        last_d = axis_ == 0 ? dx : (axis_ == 1 ? dy : dz);
        for (std::size_t k = 0; k < np; ++k)
          if (side(pos[j], last_d, planes_[k]) != 0) return true;
        return false;
      },
      [&](std::size_t, std::size_t j, double q) {
        // q flows from j into i: towards +axis where i is above.
        for (std::size_t k = 0; k < np; ++k) row_[2 * k] += side(pos[j], last_d, planes_[k]) * q / area_;
      });
  // Convective part and profile, over the mobile particles.
  std::vector<double> cap_sum(np, 0.0), capx_sum(np, 0.0), capxv(np, 0.0), capv(np, 0.0);
  double* prof = &row_[2 * np];
  for (std::size_t i = 0; i < all.n_local; ++i) {
    const auto sp = static_cast<std::size_t>(all.species[i]);
    if (frozen_[sp] || all.body[i] != 0) continue;
    const double c = capacity_[sp];
    for (std::size_t k = 0; k < np; ++k) {
      if (std::abs(from(pos[i], planes_[k])) >= spec_.slab) continue;
      cap_sum[k] += c;
      capx_sum[k] += c * x[i];
      capxv[k] += c * x[i] * vel[i];
      capv[k] += c * vel[i];
    }
    double t = pos[i] / bin_width_;
    auto b = static_cast<std::size_t>(t < 0 ? 0 : t);
    if (b >= bins_) b = bins_ - 1;
    prof[3 * b] += 1;
    prof[3 * b + 1] += x[i];
    prof[3 * b + 2] += c;
  }
  for (std::size_t k = 0; k < np; ++k) {
    // sum cap (X - Xbar) v = sum cap X v - Xbar sum cap v.
    const double xbar = cap_sum[k] > 0 ? capx_sum[k] / cap_sum[k] : 0.0;
    row_[2 * k + 1] = (capxv[k] - xbar * capv[k]) / (2.0 * spec_.slab * area_);
  }
  double* w = &row_[2 * np + 3 * bins_];
  for (std::size_t k = 0; k < walls_.size(); ++k) w[k] = wall_rates[k];
  for (std::size_t k = 0; k < row_.size(); ++k) total_[k] += row_[k];
  blocks_.add(row_.data());
  ++samples_;
}

void ScalarFlux::plane_values(const double* row, double n, std::vector<std::array<double, 7>>& out) const {
  // out[k]: pair, conv, total flux; gradient; density; capacity; (unused)
  const std::size_t np = planes_.size();
  out.assign(np, {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN});
  if (n <= 0) return;
  const double* prof = row + 2 * np;
  const double bin_volume = bin_width_ * area_;
  for (std::size_t k = 0; k < np; ++k) {
    std::array<double, 7>& o = out[k];
    o[0] = row[2 * k] / n;
    o[1] = row[2 * k + 1] / n;
    o[2] = o[0] + o[1];
    double s1 = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, count = 0, cap = 0;
    std::size_t used = 0;
    for (std::size_t b = 0; b < bins_; ++b) {
      const double centre = (static_cast<double>(b) + 0.5) * bin_width_;
      double d = centre - planes_[k];
      if (periodic_) d -= len_ * std::round(d / len_);
      if (std::abs(d) > spec_.fit || prof[3 * b] <= 0) continue;
      const double y = prof[3 * b + 1] / prof[3 * b];
      s1 += 1, sx += d, sy += y, sxx += d * d, sxy += d * y;
      count += prof[3 * b];
      cap += prof[3 * b + 2];
      ++used;
    }
    if (used < 2) continue;
    const double den = s1 * sxx - sx * sx;
    o[3] = den > 0 ? (s1 * sxy - sx * sy) / den : kNaN;
    o[4] = count / (n * bin_volume * static_cast<double>(used));
    o[5] = count > 0 ? cap / count : kNaN;
  }
}

FluxResult ScalarFlux::result() const {
  FluxResult r;
  r.samples = samples_;
  r.blocks = blocks_.full_blocks();
  const std::size_t np = planes_.size();
  std::vector<std::array<double, 7>> pooled, one;
  plane_values(total_.data(), static_cast<double>(samples_), pooled);
  // Per block: the same values.
  std::vector<std::vector<std::array<double, 7>>> per(r.blocks);
  const auto per_block = static_cast<double>(blocks_.samples_per_block());
  for (std::size_t b = 0; b < r.blocks; ++b) plane_values(blocks_.block(b), per_block, per[b]);
  const auto k_of = [](const std::array<double, 7>& v) { return -v[2] / v[3]; };
  const auto d_of = [&](const std::array<double, 7>& v) { return k_of(v) / (v[4] * v[5]); };
  for (std::size_t k = 0; k < np; ++k) {
    PlaneFlux p;
    p.position = planes_[k];
    const auto est = [&](auto f) {
      std::vector<double> v;
      for (std::size_t b = 0; b < r.blocks; ++b) v.push_back(f(per[b][k]));
      return over_blocks(v, f(pooled[k]));
    };
    p.pair = est([](const auto& v) { return v[0]; });
    p.conv = est([](const auto& v) { return v[1]; });
    p.total = est([](const auto& v) { return v[2]; });
    p.gradient = est([](const auto& v) { return v[3]; });
    p.density = est([](const auto& v) { return v[4]; });
    p.capacity = est([](const auto& v) { return v[5]; });
    p.conductivity = est(k_of);
    p.diffusivity = est(d_of);
    r.planes.push_back(p);
  }
  const std::size_t off = 2 * np + 3 * bins_;
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    WallFlux f;
    f.species = names_[walls_[w]];
    std::vector<double> v;
    for (std::size_t b = 0; b < r.blocks; ++b) v.push_back(blocks_.block(b)[off + w] / per_block);
    f.rate = over_blocks(v, samples_ > 0 ? total_[off + w] / static_cast<double>(samples_) : kNaN);
    f.per_area = {f.rate.value / area_, f.rate.error / area_};
    r.walls.push_back(f);
  }
  return r;
}

std::vector<double> ScalarFlux::bin_centres() const {
  std::vector<double> c(bins_);
  for (std::size_t b = 0; b < bins_; ++b) c[b] = (static_cast<double>(b) + 0.5) * bin_width_;
  return c;
}

std::vector<double> ScalarFlux::profile_density() const {
  std::vector<double> d(bins_, kNaN);
  const double* prof = &total_[2 * planes_.size()];
  if (samples_ == 0) return d;
  for (std::size_t b = 0; b < bins_; ++b) d[b] = prof[3 * b] / (static_cast<double>(samples_) * bin_width_ * area_);
  return d;
}

std::vector<double> ScalarFlux::profile_mean() const {
  std::vector<double> m(bins_, kNaN);
  const double* prof = &total_[2 * planes_.size()];
  for (std::size_t b = 0; b < bins_; ++b)
    if (prof[3 * b] > 0) m[b] = prof[3 * b + 1] / prof[3 * b];
  return m;
}

std::string ScalarFlux::summary() const {
  const FluxResult r = result();
  const bool heat = spec_.field == "temp";
  std::string text = fmt::format("flux of {} along {} ({} samples, {} blocks of {} samples):\n",
                                 heat ? "heat (C_v T)" : "solute " + spec_.field, "xyz"[axis_], r.samples, r.blocks,
                                 blocks_.samples_per_block());
  for (const PlaneFlux& p : r.planes)
    text += fmt::format(
        "  plane {:.4g}: J = {} (pairs {}, convection {}), gradient {}, {} {}, {} {}\n", p.position, pm(p.total),
        pm(p.pair), pm(p.conv), pm(p.gradient), heat ? "conductivity" : "J / -gradient", pm(p.conductivity),
        heat ? "thermal diffusivity k / (n C_v)" : "diffusivity J / (-n gradient)", pm(p.diffusivity));
  for (const WallFlux& w : r.walls)
    text += fmt::format("  wall \"{}\" gives the fluid {} per unit time ({} per unit area normal to {})\n", w.species,
                        pm(w.rate), pm(w.per_area), "xyz"[axis_]);
  return text;
}

std::string ScalarFlux::write(const std::filesystem::path& dir) const {
  const FluxResult r = result();
  write_file_atomically(dir / "flux.csv", [&](std::ostream& os) {
    os << "position,flux,flux_err,pair,pair_err,convection,convection_err,gradient,gradient_err,density,capacity,"
          "conductivity,conductivity_err,diffusivity,diffusivity_err\n";
    for (const PlaneFlux& p : r.planes)
      os << fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", p.position, p.total.value, p.total.error,
                        p.pair.value, p.pair.error, p.conv.value, p.conv.error, p.gradient.value, p.gradient.error,
                        p.density.value, p.capacity.value, p.conductivity.value, p.conductivity.error,
                        p.diffusivity.value, p.diffusivity.error);
  });
  write_file_atomically(dir / "flux_profile.csv", [&](std::ostream& os) {
    os << "position,density,mean_" << spec_.field << "\n";
    const std::vector<double> c = bin_centres(), d = profile_density(), m = profile_mean();
    for (std::size_t b = 0; b < bins_; ++b) os << fmt::format("{},{},{}\n", c[b], d[b], m[b]);
  });
  nlohmann::ordered_json j;
  const auto put = [](nlohmann::ordered_json& o, const std::string& key, const FluxEstimate& e) {
    o[key] = json_number(e.value);
    o[key + "_err"] = json_number(e.error);
  };
  j["field"] = spec_.field;
  j["axis"] = std::string(1, "xyz"[axis_]);
  j["area"] = json_number(area_);
  j["samples"] = r.samples;
  j["blocks"] = r.blocks;
  nlohmann::ordered_json planes = nlohmann::ordered_json::array();
  for (const PlaneFlux& p : r.planes) {
    nlohmann::ordered_json o;
    o["position"] = json_number(p.position);
    put(o, "flux", p.total);
    put(o, "pair", p.pair);
    put(o, "convection", p.conv);
    put(o, "gradient", p.gradient);
    put(o, "density", p.density);
    put(o, "capacity", p.capacity);
    put(o, "conductivity", p.conductivity);
    put(o, "diffusivity", p.diffusivity);
    planes.push_back(std::move(o));
  }
  j["planes"] = std::move(planes);
  nlohmann::ordered_json walls = nlohmann::ordered_json::array();
  for (const WallFlux& w : r.walls) {
    nlohmann::ordered_json o;
    o["species"] = w.species;
    put(o, "rate", w.rate);
    put(o, "per_area", w.per_area);
    walls.push_back(std::move(o));
  }
  j["walls"] = std::move(walls);
  write_file_atomically(dir / "flux.json", [&](std::ostream& os) { os << j.dump(2) << '\n'; });
  return summary();
}

void ScalarFlux::save(ByteWriter& w) const {
  w.put<std::uint64_t>(samples_);
  w.put_vector(total_);
  blocks_.save(w);
}

void ScalarFlux::load(ByteReader& r, const std::string& context) {
  samples_ = r.get<std::uint64_t>();
  std::vector<double> total = r.get_vector<double>();
  if (total.size() != total_.size())
    throw ConfigError(context + ": analysis.flux was recorded with other planes, bins or walls");
  total_ = std::move(total);
  blocks_.load(r, context);
}

ScalarFluxStage::ScalarFluxStage(const FluxSpec& spec, const std::array<double, 3>& box,
                                 const std::array<bool, 3>& periodic, std::vector<double> capacity,
                                 std::vector<std::uint8_t> frozen, std::vector<std::string> names,
                                 std::string rate_field, ScalarExchangeOf exchange, SystemSnapshot& snapshot,
                                 const Comm& comm, AnalysisOutput out)
    : RootAnalysisStage(std::move(out)),
      spec_(spec),
      rate_field_(std::move(rate_field)),
      exchange_(std::move(exchange)),
      snapshot_(snapshot),
      capacity_(capacity) {
  const std::uint64_t from = std::max(spec.start, spec.every);
  first_ = (from + spec.every - 1) / spec.every * spec.every;
  // The walls are the frozen species, numbered in species order (ScalarFlux's rows).
  int walls = 0;
  for (std::uint8_t f : frozen) wall_of_.push_back(f ? walls++ : -1);
  acc_.assign(static_cast<std::size_t>(walls), 0.0);
  if (comm.root()) a_.emplace(spec, box, periodic, std::move(capacity), std::move(frozen), std::move(names));
}

void ScalarFluxStage::observe(const StepContext& ctx) {
  // The interval before a sample: the `every` steps that end with it.
  if (ctx.step + spec_.every <= first_) return;
  if (!acc_.empty()) {
    const ParticleData& p = ctx.particles;
    const std::vector<double>* rate = p.doubles(rate_field_);
    if (rate == nullptr) throw std::logic_error("ScalarFluxStage: the particles hold no " + rate_field_);
    std::vector<Int128> sums(acc_.size(), 0);
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const auto sp = static_cast<std::size_t>(p.species[i]);
      if (wall_of_[sp] < 0) continue;
      sums[static_cast<std::size_t>(wall_of_[sp])] +=
          static_cast<Int128>(std::llround(-capacity_[sp] * (*rate)[i] * kRateScale));
    }
    ctx.comm.sum(std::span<Int128>(sums));
    for (std::size_t w = 0; w < acc_.size(); ++w) acc_[w] += static_cast<double>(sums[w]) / kRateScale;
  }
  ++acc_steps_;
  if (ctx.step < first_ || ctx.step % spec_.every != 0) return;
  const ParticleData& all = snapshot_.of(ctx);  // collective
  std::vector<double> means(acc_.size(), 0.0);
  for (std::size_t w = 0; w < acc_.size(); ++w) means[w] = acc_[w] / static_cast<double>(acc_steps_);
  std::fill(acc_.begin(), acc_.end(), 0.0);
  acc_steps_ = 0;
  if (a_) a_->sample(all, ctx.box, exchange_, means);
}

std::string ScalarFluxStage::finish(const StepContext&) {
  if (!a_) return {};
  if (a_->samples() == 0) return fmt::format("flux: no sample (the first is at step {}; run longer)\n", first_);
  return out_.files() ? a_->write(out_.dir) : a_->summary();
}

void ScalarFluxStage::save(ByteWriter& w) const {
  if (!a_) return;
  a_->save(w);
  w.put<std::uint64_t>(acc_steps_);
  w.put_vector(acc_);
}

void ScalarFluxStage::load(ByteReader& r, const std::string& context) {
  if (!a_) return;
  a_->load(r, context);
  acc_steps_ = r.get<std::uint64_t>();
  std::vector<double> acc = r.get_vector<double>();
  if (acc.size() != acc_.size()) throw ConfigError(context + ": analysis.flux was recorded with other walls");
  acc_ = std::move(acc);
}

}  // namespace mesodpd
