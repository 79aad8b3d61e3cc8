// Transport coefficients from equilibrium fluctuations ([analysis.transport], transport.hpp).
#include "analysis/transport.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "analysis/kinetic_theory.hpp"
#include "analysis/thermo.hpp"
#include "io/atomic_file.hpp"
#include "io/json_number.hpp"
#include "parallel/comm.hpp"

namespace mesodpd {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Int_0^T f dt by the trapezoidal rule over samples h apart. With f the correlation of values that are
// each a mean over their sampling interval (the stress), this is exactly the long-time growth rate of
// the variance of the summed values (Helfand's form), so the weight 1/2 of the first point is not an
// approximation there.
double trapezoid(const std::vector<double>& f, double h) {
  if (f.empty()) return 0.0;
  double sum = 0.5 * (f.front() + f.back());
  for (std::size_t k = 1; k + 1 < f.size(); ++k) sum += f[k];
  return f.size() > 1 ? sum * h : 0.0;
}

// The slope of a least-squares line through y(k h) over the second half of the lags, k in [K/2, K].
double msd_slope(const std::vector<double>& y, double h) {
  const std::size_t last = y.size() - 1, lo = last / 2;
  const auto np = static_cast<double>(last - lo + 1);
  double tm = 0, ym = 0;
  for (std::size_t k = lo; k <= last; ++k) tm += static_cast<double>(k) * h, ym += y[k];
  tm /= np, ym /= np;
  double stt = 0, sty = 0;
  for (std::size_t k = lo; k <= last; ++k) {
    const double dt = static_cast<double>(k) * h - tm;
    stt += dt * dt;
    sty += dt * (y[k] - ym);
  }
  return sty / stt;
}

// The mean and its standard error over the blocks.
TransportEstimate over_blocks(const std::vector<double>& v) {
  TransportEstimate e;
  const auto n = static_cast<double>(v.size());
  if (v.empty()) return {kNaN, kNaN};
  for (double x : v) e.value += x;
  e.value /= n;
  if (v.size() < 2) return {e.value, kNaN};
  double ss = 0;
  for (double x : v) ss += (x - e.value) * (x - e.value);
  e.error = std::sqrt(ss / (n - 1.0) / n);
  return e;
}

void require(bool ok, const char* what) {
  if (!ok) throw std::invalid_argument(std::string("TransportCorrelations: ") + what);
}

}  // namespace

const keys::KeyTable<TransportSpec>& transport_keys() {
  using T = TransportSpec;
  static const keys::KeyTable<T> table = [] {
    keys::KeyTable<T> t("analysis.transport");
    t.integer("start", &T::start, {0}, "First sampled step (equilibrate before it).");
    t.integer("every", &T::every, {1},
              "Steps between samples of the velocities and positions. The pressure tensor is taken at every "
              "step and averaged over the steps of each interval.");
    t.integer("lags", &T::lags, {10, 100000},
              "Window of the VACF and the MSD in samples: D (Green-Kubo) integrates the VACF to lags x every x "
              "dt, D (Einstein) fits the MSD over the second half of the window. Memory: 6 doubles per particle "
              "and lag; time: 6 multiply-adds per particle, lag and origin.");
    t.integer("origin_every", &T::origin_every, {1},
              "A time origin of the VACF and MSD every this many samples (1: every sample). The stress, one "
              "tensor per sample, takes every sample as an origin whatever this is.");
    t.integer("stress_lags", &T::stress_lags, {0, 100000},
              "Window of the stress autocorrelation in samples (0: `lags`). The stress correlation usually "
              "decays faster than the VACF's tail, and the noise of the eta integral grows with its window.");
    t.integer("block", &T::block, {1},
              "Steps per block of the error bars: each complete block gives its own D, eta and Sc; the error is "
              "the standard error of the block values (Sc: the jackknife). A final incomplete block is left out.")
        .allowed("a multiple of `every`, at least 2 x max(`lags`, `stress_lags`) x `every`");
    t.boolean("normal_stress", &T::normal_stress,
              "Also correlate the traceless normal stresses P_aa - p (two more independent shear-like "
              "components of an isotropic fluid), reported as eta_normal; eta then combines the five as (3 eta_shear + "
              "2 eta_normal) / 5. Off by default: in the a = 25 fluid the normal stresses were twice as noisy as the "
              "shear stresses, so the combination had a larger error than eta_shear alone (docs/validation.md).");
    return t;
  }();
  return table;
}

void check_transport(const TransportSpec& t, const SimulationSpec& spec) {
  const std::string p = "analysis.transport.";
  if (t.block % t.every != 0)
    keys::fail(p + "block", std::to_string(t.block),
               "must be a multiple of analysis.transport.every = " + std::to_string(t.every));
  const std::uint64_t window = std::max(t.lags, t.stress_lags) * t.every;
  if (t.block < 2 * window)
    keys::fail(p + "block", std::to_string(t.block),
               "must be at least 2 x max(lags, stress_lags) x every = " + std::to_string(2 * window) +
                   " steps, so that blocks are longer than the correlation windows");
  if (t.stress_lags != 0 && t.stress_lags < 2)
    keys::fail(p + "stress_lags", std::to_string(t.stress_lags), "must be 0 (the same as lags) or at least 2");
  for (int d = 0; d < 3; ++d)
    if (!spec.periodic[static_cast<std::size_t>(d)])
      keys::fail(p + "start", "", "needs a periodic box (system.periodic is bounded along " +
                                      std::string(1, "xyz"[d]) + "): equilibrium correlations of a bulk fluid");
  if (!spec.solids.empty())
    keys::fail(p + "start", "", "is not supported with [[solid]] walls (it measures a bulk fluid)");
  for (const SpeciesSpec& s : spec.species) {
    if (s.frozen)
      keys::fail(p + "start", "", "is not supported with frozen species (species \"" + s.name + "\")");
    if (s.body_force != std::array<double, 3>{0, 0, 0})
      keys::fail(p + "start", "",
                 "measures equilibrium fluctuations; species \"" + s.name + "\" has a body_force that drives a flow");
  }
  if (spec.poiseuille.enabled)
    keys::fail(p + "start", "", "measures equilibrium fluctuations; [poiseuille] drives a flow");
}

ModelSection transport_section() { return model_section(transport_keys(), check_transport); }

// ---------------------------------------------------------------------------------------------------

TransportCorrelations::TransportCorrelations(std::size_t lags, std::uint64_t every, double dt,
                                             std::uint64_t block_steps, bool normal_stress, std::size_t origin_every,
                                             std::size_t stress_lags)
    : lags_(lags), origin_every_(origin_every), stress_lags_(stress_lags ? stress_lags : lags), every_(every), spacing_(static_cast<double>(every) * dt), block_steps_(block_steps),
      normal_(normal_stress) {
  require(lags >= 2, "lags must be >= 2");
  require(every >= 1, "every must be >= 1");
  require(dt > 0, "dt must be > 0");
  require(block_steps >= every && block_steps % every == 0, "block_steps must be a multiple of every");
  require(origin_every >= 1, "origin_every must be >= 1");
  stress_.assign(6 * (stress_lags_ + 1), 0.0);
}

void TransportCorrelations::add_pressure(const std::array<double, 6>& p) {
  for (std::size_t q = 0; q < 6; ++q) interval_[q] += p[q];
  ++interval_steps_;
}

TransportCorrelations::Block& TransportCorrelations::block_of(std::uint64_t step) {
  const auto b = static_cast<std::size_t>((step - first_step_) / block_steps_);
  while (blocks_.size() <= b) {
    blocks_.push_back(empty_block());
  }
  return blocks_[b];
}

void TransportCorrelations::sample(std::uint64_t step, const double* vx, const double* vy, const double* vz,
                                   const double* xu, const double* yu, const double* zu, std::size_t n, double kT,
                                   double total_mass) {
  require(interval_steps_ == every_, "every step between two samples must add a pressure");
  if (samples_ == 0) {
    require(n > 0, "no particles");
    n_ = n;
    mass_ = total_mass;
    first_step_ = step;
    vel_.assign((lags_ + 1) * 3 * n, 0.0);
    pos_.assign((lags_ + 1) * 3 * n, 0.0);
  } else {
    require(step == last_step_ + every_, "samples must be `every` steps apart");
    require(n == n_, "the particle count changed");
  }
  const std::size_t ring = lags_ + 1, m = 3 * n;
  const std::size_t slot = static_cast<std::size_t>(samples_ % ring);
  double* v = &vel_[slot * m];
  double* r = &pos_[slot * m];
  for (std::size_t i = 0; i < n; ++i) {
    v[3 * i] = vx[i], v[3 * i + 1] = vy[i], v[3 * i + 2] = vz[i];
    r[3 * i] = xu[i], r[3 * i + 1] = yu[i], r[3 * i + 2] = zu[i];
  }
  // The interval's mean pressure tensor: the shear stresses, then the traceless normal stresses.
  const std::size_t stress_ring = stress_lags_ + 1;
  double* s = &stress_[6 * static_cast<std::size_t>(samples_ % stress_ring)];
  double mean[6];
  for (std::size_t q = 0; q < 6; ++q) mean[q] = interval_[q] / static_cast<double>(interval_steps_);
  const double p = (mean[0] + mean[1] + mean[2]) / 3.0;
  s[0] = mean[3], s[1] = mean[4], s[2] = mean[5];
  s[3] = mean[0] - p, s[4] = mean[1] - p, s[5] = mean[2] - p;
  interval_ = {};
  interval_steps_ = 0;

  Block& blk = block_of(step);
  const double inv_n = 1.0 / static_cast<double>(n);
  const std::size_t reach = static_cast<std::size_t>(std::min<std::uint64_t>(samples_, lags_));
  for (std::size_t lag = 0; lag <= reach; ++lag) {
    if ((samples_ - lag) % origin_every_ != 0) continue;  // not an origin
    const std::size_t o = static_cast<std::size_t>((samples_ - lag) % ring);
    const double* vo = &vel_[o * m];
    const double* ro = &pos_[o * m];
    // Four partial sums each: independent chains the compiler can keep in one vector register (one
    // chain is bound by the add latency), still in a fixed order.
    double vv4[4] = {0, 0, 0, 0}, dd4[4] = {0, 0, 0, 0};
    std::size_t k = 0;
    for (; k + 4 <= m; k += 4)
      for (std::size_t l = 0; l < 4; ++l) {
        vv4[l] += vo[k + l] * v[k + l];
        const double d = r[k + l] - ro[k + l];
        dd4[l] += d * d;
      }
    for (; k < m; ++k) {
      vv4[0] += vo[k] * v[k];
      const double d = r[k] - ro[k];
      dd4[0] += d * d;
    }
    blk.vacf[lag] += ((vv4[0] + vv4[1]) + (vv4[2] + vv4[3])) * inv_n;
    blk.msd[lag] += ((dd4[0] + dd4[1]) + (dd4[2] + dd4[3])) * inv_n;
    ++blk.count[lag];
  }
  const std::size_t stress_reach = static_cast<std::size_t>(std::min<std::uint64_t>(samples_, stress_lags_));
  for (std::size_t lag = 0; lag <= stress_reach; ++lag) {
    const double* so = &stress_[6 * static_cast<std::size_t>((samples_ - lag) % stress_ring)];
    blk.shear[lag] += (so[0] * s[0] + so[1] * s[1] + so[2] * s[2]) / 3.0;
    // For an isotropic fluid sum_a <d_a(0) d_a(t)> = 4 <P_xy(0) P_xy(t)>, d_a = P_aa - p.
    blk.normal[lag] += (so[3] * s[3] + so[4] * s[4] + so[5] * s[5]) / 4.0;
    ++blk.stress_count[lag];
  }
  blk.temperature_sum += kT;
  ++blk.samples;
  last_step_ = step;
  ++samples_;
}

std::size_t TransportCorrelations::complete_blocks() const {
  if (samples_ == 0) return 0;
  // Block b holds the samples at first + b block .. first + (b + 1) block - every.
  return static_cast<std::size_t>((last_step_ - first_step_ + every_) / block_steps_);
}

TransportCorrelations::Block TransportCorrelations::empty_block() const {
  Block b;
  b.vacf.assign(lags_ + 1, 0.0);
  b.msd = b.vacf;
  b.count.assign(lags_ + 1, 0);
  b.shear.assign(stress_lags_ + 1, 0.0);
  b.normal = b.shear;
  b.stress_count.assign(stress_lags_ + 1, 0);
  return b;
}

TransportCorrelations::Block TransportCorrelations::pooled(std::size_t first, std::size_t last) const {
  Block out = empty_block();
  const auto add = [](std::vector<double>& to, const std::vector<double>& from) {
    for (std::size_t k = 0; k < to.size(); ++k) to[k] += from[k];
  };
  for (std::size_t b = first; b < last; ++b) {
    const Block& in = blocks_[b];
    add(out.vacf, in.vacf), add(out.msd, in.msd), add(out.shear, in.shear), add(out.normal, in.normal);
    for (std::size_t k = 0; k <= lags_; ++k) out.count[k] += in.count[k];
    for (std::size_t k = 0; k <= stress_lags_; ++k) out.stress_count[k] += in.stress_count[k];
    out.temperature_sum += in.temperature_sum;
    out.samples += in.samples;
  }
  const auto per = [](std::uint64_t c) { return c ? static_cast<double>(c) : kNaN; };
  for (std::size_t k = 0; k <= lags_; ++k) out.vacf[k] /= per(out.count[k]), out.msd[k] /= per(out.count[k]);
  for (std::size_t k = 0; k <= stress_lags_; ++k)
    out.shear[k] /= per(out.stress_count[k]), out.normal[k] /= per(out.stress_count[k]);
  return out;
}

TransportBlockValues TransportCorrelations::values(const Block& mean, double volume) const {
  TransportBlockValues v;
  v.kT = mean.temperature_sum / static_cast<double>(mean.samples);
  v.d_vacf = trapezoid(mean.vacf, spacing_) / 3.0;
  v.d_msd = msd_slope(mean.msd, spacing_) / 6.0;
  // The MSD the VACF implies, 6 Int_0^t D(t') dt' with D(t) its running integral (both trapezoidal).
  std::vector<double> implied(lags_ + 1, 0.0);
  double d_prev = 0, d = 0;
  for (std::size_t k = 1; k <= lags_; ++k) {
    d += 0.5 * spacing_ * (mean.vacf[k - 1] + mean.vacf[k]) / 3.0;
    implied[k] = implied[k - 1] + 6.0 * 0.5 * spacing_ * (d_prev + d);
    d_prev = d;
  }
  v.d_vacf_window = msd_slope(implied, spacing_) / 6.0;
  v.eta_shear = volume / v.kT * trapezoid(mean.shear, spacing_);
  v.eta_normal = normal_ ? volume / v.kT * trapezoid(mean.normal, spacing_) : kNaN;
  v.eta = normal_ ? (3.0 * v.eta_shear + 2.0 * v.eta_normal) / 5.0 : v.eta_shear;
  return v;
}

TransportResult TransportCorrelations::result(double volume) const {
  TransportResult out;
  out.window = static_cast<double>(lags_) * spacing_;
  out.stress_window = static_cast<double>(stress_lags_) * spacing_;
  out.blocks = complete_blocks();
  if (out.blocks == 0) return out;
  std::vector<double> dv, dw, dm, es, en, e, kt;
  for (std::size_t b = 0; b < out.blocks; ++b) {
    const TransportBlockValues v = values(pooled(b, b + 1), volume);
    out.per_block.push_back(v);
    dv.push_back(v.d_vacf), dw.push_back(v.d_vacf_window), dm.push_back(v.d_msd), es.push_back(v.eta_shear);
    en.push_back(v.eta_normal), e.push_back(v.eta), kt.push_back(v.kT);
  }
  out.d_vacf = over_blocks(dv), out.d_vacf_window = over_blocks(dw), out.d_msd = over_blocks(dm), out.eta_shear = over_blocks(es);
  out.eta_normal = normal_ ? over_blocks(en) : TransportEstimate{kNaN, kNaN};
  out.eta = over_blocks(e), out.kT = over_blocks(kt);
  // Sc = eta / (rho D): a ratio of two block means, so its error comes from the jackknife (leave one block
  // out), which carries the correlation between the eta and D of a block.
  const double rho = mass_ / volume;
  out.schmidt = {out.eta.value / (rho * out.d_msd.value), kNaN};
  const std::size_t nb = out.blocks;
  if (nb >= 2) {
    std::vector<double> jack;
    double se = 0, sd = 0;
    for (std::size_t b = 0; b < nb; ++b) se += e[b], sd += dm[b];
    for (std::size_t b = 0; b < nb; ++b) jack.push_back((se - e[b]) / ((sd - dm[b]) * rho));
    double mean = 0;
    for (double x : jack) mean += x;
    mean /= static_cast<double>(nb);
    double ss = 0;
    for (double x : jack) ss += (x - mean) * (x - mean);
    out.schmidt.error = std::sqrt(ss * static_cast<double>(nb - 1) / static_cast<double>(nb));
  }
  return out;
}

void TransportCorrelations::write_csv(const std::string& path, double volume) const {
  const std::size_t nb = complete_blocks();
  const Block mean = pooled(0, nb);
  const double kT = nb ? mean.temperature_sum / static_cast<double>(mean.samples) : kNaN;
  const double g = volume / kT;
  write_file_atomically(path, [&](std::ostream& os) {
    os << "time,vacf,d_vacf,msd,g_shear,eta_shear,g_normal,eta_normal\n";
    double dv = 0, es = 0, en = 0;  // running trapezoidal integrals
    // Columns past their window are left empty.
    const auto cell = [](bool in, double x) { return in ? fmt::format(",{:.10g}", x) : std::string(","); };
    for (std::size_t k = 0; k <= std::max(lags_, stress_lags_); ++k) {
      const bool p = k <= lags_, q = k <= stress_lags_;
      if (k > 0 && p) dv += 0.5 * spacing_ * (mean.vacf[k - 1] + mean.vacf[k]) / 3.0;
      if (k > 0 && q) {
        es += 0.5 * spacing_ * g * (mean.shear[k - 1] + mean.shear[k]);
        en += 0.5 * spacing_ * g * (mean.normal[k - 1] + mean.normal[k]);
      }
      os << fmt::format("{:.10g}", static_cast<double>(k) * spacing_) << cell(p, p ? mean.vacf[k] : 0)
         << cell(p, dv) << cell(p, p ? mean.msd[k] : 0) << cell(q, q ? g * mean.shear[k] : 0) << cell(q, es)
         << cell(q && normal_, q ? g * mean.normal[k] : 0) << cell(q && normal_, en) << '\n';
    }
  });
}

void TransportCorrelations::save(ByteWriter& w) const {
  w.put<std::uint64_t>(lags_);
  w.put<std::uint64_t>(origin_every_);
  w.put<std::uint64_t>(stress_lags_);
  w.put<std::uint64_t>(every_);
  w.put<std::uint64_t>(block_steps_);
  w.put<std::uint8_t>(normal_ ? 1 : 0);
  w.put<std::uint64_t>(n_);
  w.put<double>(mass_);
  w.put<std::uint64_t>(samples_);
  w.put<std::uint64_t>(first_step_);
  w.put<std::uint64_t>(last_step_);
  w.put_vector(vel_);
  w.put_vector(pos_);
  w.put_vector(stress_);
  for (double x : interval_) w.put<double>(x);
  w.put<std::uint64_t>(interval_steps_);
  w.put<std::uint64_t>(blocks_.size());
  for (const Block& b : blocks_) {
    w.put_vector(b.vacf);
    w.put_vector(b.msd);
    w.put_vector(b.shear);
    w.put_vector(b.normal);
    w.put_vector(b.count);
    w.put_vector(b.stress_count);
    w.put<double>(b.temperature_sum);
    w.put<std::uint64_t>(b.samples);
  }
}

void TransportCorrelations::load(ByteReader& r, const std::string& context) {
  const auto lags = r.get<std::uint64_t>(), origins = r.get<std::uint64_t>(), stress_lags = r.get<std::uint64_t>();
  const auto every = r.get<std::uint64_t>(), block = r.get<std::uint64_t>();
  const bool normal = r.get<std::uint8_t>() != 0;
  if (lags != lags_ || origins != origin_every_ || stress_lags != stress_lags_ || every != every_ ||
      block != block_steps_ || normal != normal_)
    throw ConfigError(fmt::format(
        "{}: analysis.transport settings (lags, origin_every, stress_lags, every, block, normal_stress) differ "
        "from the checkpoint's ({}, {}, {}, {}, {}, {})",
        context, lags, origins, stress_lags, every, block, normal));
  n_ = r.get<std::uint64_t>();
  mass_ = r.get<double>();
  samples_ = r.get<std::uint64_t>();
  first_step_ = r.get<std::uint64_t>();
  last_step_ = r.get<std::uint64_t>();
  vel_ = r.get_vector<double>();
  pos_ = r.get_vector<double>();
  stress_ = r.get_vector<double>();
  for (double& x : interval_) x = r.get<double>();
  interval_steps_ = r.get<std::uint64_t>();
  blocks_.resize(r.get<std::uint64_t>());
  const auto bad = [&] { return ConfigError(fmt::format("{}: inconsistent analysis.transport state", context)); };
  for (Block& b : blocks_) {
    b.vacf = r.get_vector<double>();
    b.msd = r.get_vector<double>();
    b.shear = r.get_vector<double>();
    b.normal = r.get_vector<double>();
    b.count = r.get_vector<std::uint64_t>();
    b.stress_count = r.get_vector<std::uint64_t>();
    b.temperature_sum = r.get<double>();
    b.samples = r.get<std::uint64_t>();
    for (std::size_t size : {b.vacf.size(), b.msd.size(), b.count.size()})
      if (size != lags_ + 1) throw bad();
    for (std::size_t size : {b.shear.size(), b.normal.size(), b.stress_count.size()})
      if (size != stress_lags_ + 1) throw bad();
  }
  const std::size_t ring = (lags_ + 1) * 3 * n_;
  if (stress_.size() != 6 * (stress_lags_ + 1) || (samples_ > 0 && (vel_.size() != ring || pos_.size() != ring)))
    throw bad();
}

// ---------------------------------------------------------------------------------------------------

TransportStage::TransportStage(const TransportSpec& spec, const SimulationSpec& sim, AnalysisOutput out,
                               SystemSnapshot& snapshot, const Comm& comm)
    : RootAnalysisStage(std::move(out)), spec_(spec), sim_(sim), snapshot_(snapshot) {
  // The first sample is a multiple of every at or after start, and at least one interval into the run, so
  // that the steps it averages the stress over all come after the initial state.
  const std::uint64_t from = std::max(spec.start, spec.every);
  first_ = (from + spec.every - 1) / spec.every * spec.every;
  if (comm.root())
    a_.emplace(spec.lags, spec.every, sim.dt, spec.block, spec.normal_stress, spec.origin_every, spec.stress_lags);
}

void TransportStage::observe(const StepContext& ctx) {
  if (!wants_pair_sums(ctx.step)) return;
  if (!ctx.pair_sums) throw std::logic_error("TransportStage: the pressure is due but no pair sums were computed");
  // Kinetic and pair parts of the pressure tensor, and the temperature (collective).
  const ThermoState t = compute_thermo(ctx.particles, ctx.species_mass, ctx.box, *ctx.pair_sums, -1, ctx.comm);
  if (a_) a_->add_pressure(t.p_tensor);
  if (ctx.step < first_ || ctx.step % spec_.every != 0) return;
  const ParticleData& all = snapshot_.of(ctx);  // collective
  if (!a_) return;
  const std::size_t n = all.n_local;
  v_.resize(3 * n);
  r_.resize(3 * n);
  const Box& b = ctx.box;
  double mass = 0;
  for (std::size_t i = 0; i < n; ++i) {
    v_[i] = all.vx[i], v_[n + i] = all.vy[i], v_[2 * n + i] = all.vz[i];
    r_[i] = all.x[i] + all.ix[i] * b.len.x;
    r_[n + i] = all.y[i] + all.iy[i] * b.len.y;
    r_[2 * n + i] = all.z[i] + all.iz[i] * b.len.z;
    mass += ctx.species_mass[static_cast<std::size_t>(all.species[i])];
  }
  a_->sample(ctx.step, v_.data(), v_.data() + n, v_.data() + 2 * n, r_.data(), r_.data() + n, r_.data() + 2 * n, n,
             t.temperature, mass);
}

std::string TransportStage::finish(const StepContext& ctx) {
  if (!a_) return {};
  const TransportCorrelations& c = *a_;
  const double volume = ctx.box.volume();
  const TransportResult res = c.result(volume);
  if (res.blocks == 0)
    return fmt::format("transport: no complete block of {} steps after step {} (run longer)\n", spec_.block, first_);
  const double rho = c.total_mass() / volume;
  const double number_density = static_cast<double>(ctx.total_particles) / volume;
  // Kinetic theory (g(r) = 1): seed 000 Table 1 for D and eta, and Sc = eta / (rho D) from them.
  const KineticViscosity theory = kinetic_viscosity_of(sim_, number_density);
  const double d_theory = theory.applies ? kinetic_diffusivity(number_density, theory.gamma, sim_.kT, theory.rd, theory.s)
                                         : kNaN;
  const double eta_theory = theory.applies ? theory.eta : kNaN;
  const double sc_theory = eta_theory / (rho * d_theory);
  // Periodic images slow the diffusion in a cubic box of side L by 2.837297 kT / (6 pi eta L) (Yeh and
  // Hummer, J. Phys. Chem. B 108, 15873 (2004)); the corrected value estimates the infinite system's D.
  const bool cubic = ctx.box.len.x == ctx.box.len.y && ctx.box.len.y == ctx.box.len.z;
  const double d_correction =
      cubic ? 2.837297 * res.kT.value / (6.0 * std::numbers::pi * res.eta.value * ctx.box.len.x) : kNaN;
  const auto pm = [](const TransportEstimate& e) { return fmt::format("{:.5g} +- {:.2g}", e.value, e.error); };
  std::string text = fmt::format(
      "transport ({} blocks of {} steps, windows {:.4g} (D) and {:.4g} (eta), kT {:.4f}): D (VACF) = {} "
      "(on the MSD's fit window {}), D (MSD) = {}, eta = {} (shear {}{}), Sc = {}\n",
      res.blocks, spec_.block, res.window, res.stress_window, res.kT.value, pm(res.d_vacf), pm(res.d_vacf_window),
      pm(res.d_msd), pm(res.eta),
      pm(res.eta_shear), spec_.normal_stress ? ", normal " + pm(res.eta_normal) : std::string(), pm(res.schmidt));
  if (cubic) text += fmt::format("  D (MSD) + finite-size correction {:.4g} = {:.5g}\n", d_correction,
                                 res.d_msd.value + d_correction);
  text += theory.applies ? fmt::format("  kinetic theory (seed 000 Table 1): D = {:.5g}, eta = {:.5g}, Sc = {:.5g}\n",
                                       d_theory, eta_theory, sc_theory)
                         : fmt::format("  no kinetic-theory values for {}\n", theory.why_not);
  if (!out_.files()) return text;
  c.write_csv((out_ / "transport.csv").string(), volume);
  nlohmann::ordered_json j;
  const auto put = [&j](const std::string& key, const TransportEstimate& e) {
    j[key] = json_number(e.value);
    j[key + "_err"] = json_number(e.error);
  };
  put("d_vacf", res.d_vacf);
  put("d_vacf_window", res.d_vacf_window);
  put("d_msd", res.d_msd);
  j["d_msd_finite_size_corrected"] = json_number(res.d_msd.value + d_correction);
  put("eta", res.eta);
  put("eta_shear", res.eta_shear);
  put("eta_normal", res.eta_normal);
  put("schmidt", res.schmidt);
  put("kT", res.kT);
  j["d_kinetic_theory"] = json_number(d_theory);
  j["eta_kinetic_theory"] = json_number(eta_theory);
  j["schmidt_kinetic_theory"] = json_number(sc_theory);
  j["blocks"] = res.blocks;
  j["block_steps"] = spec_.block;
  j["window"] = json_number(res.window);
  j["stress_window"] = json_number(res.stress_window);
  j["sample_spacing"] = json_number(c.spacing());
  j["samples"] = c.samples();
  j["particles"] = ctx.total_particles;
  j["volume"] = json_number(volume);
  j["mass_density"] = json_number(rho);
  nlohmann::ordered_json blocks = nlohmann::ordered_json::array();
  for (const TransportBlockValues& v : res.per_block)
    blocks.push_back({{"d_vacf", json_number(v.d_vacf)},
                      {"d_vacf_window", json_number(v.d_vacf_window)},
                      {"d_msd", json_number(v.d_msd)},
                      {"eta_shear", json_number(v.eta_shear)},
                      {"eta_normal", json_number(v.eta_normal)},
                      {"kT", json_number(v.kT)}});
  j["per_block"] = std::move(blocks);
  write_file_atomically(out_ / "transport.json", [&](std::ostream& os) { os << j.dump(2) << '\n'; });
  return text;
}

}  // namespace mesodpd
