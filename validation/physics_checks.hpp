// Physical validation measurements shared by mesodpd-validate and tests/physics/test_validation.cpp:
// temperature control, equation of state (virial and g(r) routes), ideal-gas g(r), reverse-Poiseuille
// viscosity. One body per measurement, so the program's long runs and the tests' short runs measure
// the same thing in the same way; only the run lengths differ.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/kinetic_theory.hpp"
#include "analysis/rdf.hpp"
#include "analysis/velocity_profile.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd::validation {

// Mean and standard error of a correlated time series by block averaging: the series (after dropping
// the oldest samples that do not fill a block) is cut into `blocks` equal blocks and the error is the
// standard deviation of the block means over sqrt(blocks). Valid when a block is much longer than the
// correlation time; the callers choose blocks of at least several correlation times.
struct Estimate {
  double mean = NAN;
  double err = NAN;
  int blocks = 0;
};

inline Estimate block_estimate(const std::vector<double>& x, int blocks) {
  Estimate e;
  const std::size_t nb = static_cast<std::size_t>(blocks);
  if (blocks < 2 || x.size() < nb) return e;
  const std::size_t len = x.size() / nb;
  const std::size_t skip = x.size() - len * nb;
  std::vector<double> means(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    double s = 0;
    for (std::size_t k = 0; k < len; ++k) s += x[skip + b * len + k];
    means[b] = s / static_cast<double>(len);
  }
  const double m = std::accumulate(means.begin(), means.end(), 0.0) / static_cast<double>(nb);
  double var = 0;
  for (double v : means) var += (v - m) * (v - m);
  var /= static_cast<double>(nb - 1);
  e.mean = m;
  e.err = std::sqrt(var / static_cast<double>(nb));
  e.blocks = blocks;
  return e;
}

// One-species DPD fluid in code (seed 000 Sect. 2: Eqs. 3-8, integrator Eq. 10).
struct FluidCase {
  double lx = 10, ly = 10, lz = 10;
  double rho = 3.0, a = 25.0, gamma = 4.5, s = 2.0, dt = 0.04, lambda = 0.5, kT = 1.0;
  std::uint64_t seed = 20261123;
};

inline SimulationSpec make_spec(const FluidCase& c) {
  SimulationSpec spec;
  spec.source = "validation";
  spec.box = {c.lx, c.ly, c.lz};
  spec.kT = c.kT;
  spec.seed = c.seed;
  SpeciesSpec sp;
  sp.name = "A";
  sp.mass = 1.0;
  sp.count = static_cast<std::uint64_t>(std::llround(c.rho * c.lx * c.ly * c.lz));
  spec.species = {sp};
  PairSpec pp;
  pp.a = c.a;
  pp.gamma = c.gamma;
  pp.s = c.s;
  spec.pairs = {pp};
  spec.integrator = IntegratorKind::GrootWarren;
  spec.dt = c.dt;
  spec.lambda = c.lambda;
  spec.progress = false;
  return spec;
}

// Steps of a run: `equil` discarded steps, then `prod` steps sampled every `every`, into `blocks` blocks.
struct RunLength {
  std::uint64_t equil = 1000;
  std::uint64_t prod = 10000;
  std::uint64_t every = 10;
  int blocks = 20;
};

// --- Temperature (seed 000 Sect. 2.5.2) -------------------------------------------------------------
struct TemperatureResult {
  Estimate kT;
  std::uint64_t n = 0;
};

inline TemperatureResult measure_temperature(const FluidCase& c, const RunLength& run) {
  Simulation sim(make_spec(c), RunOptions{});
  for (std::uint64_t k = 0; k < run.equil; ++k) sim.step();
  std::vector<double> t;
  for (std::uint64_t k = 1; k <= run.prod; ++k) {
    sim.step();
    if (k % run.every == 0) t.push_back(sim.thermo().temperature);
  }
  return {block_estimate(t, run.blocks), sim.particles().n_local};
}

// --- Equation of state (seed 000 Eq. 13; seed 003 virial EOS integral) -------------------------------
struct EosResult {
  Estimate kT;              // measured temperature
  Estimate p_conservative;  // kinetic + conservative virial, ThermoState::pressure_conservative
  Estimate alpha;           // <W_C / 3V> / (a rho^2): (p_C - p_kinetic) / (a rho^2), sample by sample
  Estimate p_rdf;           // p_kin + (2 pi/3) rho^2 Int r F^C g r^2 dr over per-block g(r) (seed 003), p_kin
                            // = rho kT_meas (1 - 1/N) the kinetic term of p_C
  Estimate delta;           // p_rdf(corrected) - p_C, per block: the two routes on the same snapshots
  double rdf_disc = NAN;    // discretisation estimate: p_rdf(bin 2dr) - p_rdf(bin dr), ~3x the error at dr
  double rdf_dr = NAN;
  std::uint64_t n = 0;
};

// Virial excess from a g(r) histogram: p_rdf - rho kT via analysis::virial_pressure_from_rdf, with g
// re-binned by merging `merge` neighbouring bins (counts and shell volumes added, then normalised).
inline double rdf_excess_pressure(const RadialDistribution& rdf, std::size_t merge, double rho, double a) {
  const auto& counts = rdf.counts();
  const std::vector<double> g_fine = rdf.g();
  const double dr = rdf.bin_width();
  const std::size_t nb = counts.size() / merge;
  std::vector<double> r(nb), g(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    double num = 0, den = 0;
    for (std::size_t k = 0; k < merge; ++k) {
      const std::size_t i = b * merge + k;
      const double lo = static_cast<double>(i) * dr, hi = lo + dr;
      const double shell = hi * hi * hi - lo * lo * lo;
      num += g_fine[i] * shell;  // g * shell is proportional to the count
      den += shell;
    }
    r[b] = (static_cast<double>(b) + 0.5) * dr * static_cast<double>(merge);
    g[b] = num / den;
  }
  return virial_pressure_from_rdf(r, g, dr * static_cast<double>(merge), rho, 0.0, a, 1.0);
}

// The g(r) histogram is normalised by the pair density N(N-1)/V^2 while seed 003's integral carries rho^2
// = N^2/V^2, so the g(r) route overstates the virial by N/(N-1); `(N-1)/N` below undoes that exactly.
inline EosResult measure_eos(const FluidCase& c, const RunLength& run, std::size_t rdf_bins = 200) {
  Simulation sim(make_spec(c), RunOptions{});
  const double vol = c.lx * c.ly * c.lz;
  const std::size_t n = sim.particles().n_local;
  const double rho = static_cast<double>(n) / vol;
  const double nfac = (static_cast<double>(n) - 1.0) / static_cast<double>(n);
  // The kinetic term: sum m v^2 / 3V = rho kT (1 - 1/N) with kT on 3N - 3 degrees of freedom, the same term
  // p_C carries, so that p_rdf - p_C compares the two virial routes only.
  const double p_kinetic_per_kT = (3.0 * static_cast<double>(n) - 3.0) / (3.0 * vol);
  for (std::uint64_t k = 0; k < run.equil; ++k) sim.step();
  const std::uint64_t samples = run.prod / run.every;
  const std::uint64_t per_block = samples / static_cast<std::uint64_t>(run.blocks);
  if (per_block < 1) throw std::invalid_argument("measure_eos: fewer samples than blocks");
  std::vector<double> kt, pc, al;
  std::vector<double> prdf_b, delta_b;
  RadialDistribution all(rdf_bins, 1.0);  // rc = 1 is the last bin edge: no bin straddles the cutoff
  RadialDistribution blk(rdf_bins, 1.0);
  double blk_pc = 0, blk_kt = 0;
  std::uint64_t in_blk = 0;
  const std::array<double, 3> len{c.lx, c.ly, c.lz};
  for (std::uint64_t k = 1; k <= per_block * run.blocks * run.every; ++k) {
    sim.step();
    if (k % run.every != 0) continue;
    const ThermoState t = sim.thermo();
    const ParticleData& p = sim.particles();
    const double p_kin = t.temperature * (3.0 * static_cast<double>(n) - 3.0) / (3.0 * vol);
    kt.push_back(t.temperature);
    pc.push_back(t.pressure_conservative);
    al.push_back((t.pressure_conservative - p_kin) / (c.a * rho * rho));
    all.sample(p.x.data(), p.y.data(), p.z.data(), n, len);
    blk.sample(p.x.data(), p.y.data(), p.z.data(), n, len);
    blk_pc += t.pressure_conservative - p_kin;
    blk_kt += t.temperature;
    if (++in_blk == per_block) {
      const double ex_rdf = nfac * rdf_excess_pressure(blk, 1, rho, c.a);
      const double kt_b = blk_kt / static_cast<double>(in_blk);
      prdf_b.push_back(p_kinetic_per_kT * kt_b + ex_rdf);
      delta_b.push_back(ex_rdf - blk_pc / static_cast<double>(in_blk));
      blk = RadialDistribution(rdf_bins, 1.0);
      blk_pc = blk_kt = 0;
      in_blk = 0;
    }
  }
  EosResult r;
  r.n = n;
  r.kT = block_estimate(kt, run.blocks);
  r.p_conservative = block_estimate(pc, run.blocks);
  r.alpha = block_estimate(al, run.blocks);
  r.p_rdf = block_estimate(prdf_b, run.blocks);
  r.delta = block_estimate(delta_b, run.blocks);
  r.rdf_dr = all.bin_width();
  r.rdf_disc = nfac * (rdf_excess_pressure(all, 2, rho, c.a) - rdf_excess_pressure(all, 1, rho, c.a));
  return r;
}

// --- Ideal gas g(r) (a = 0) ------------------------------------------------------------------------------
struct IdealGasResult {
  double max_abs_dev = NAN;      // max_b |g_b - 1|
  double max_z = NAN;            // max_b |g_b - 1| / sigma_b
  double chi2_per_bin = NAN;     // (1/B) sum_b (g_b - 1)^2 / sigma_b^2; ~1 for a flat g(r)
  double chi2_inside = NAN;      // the same over the bins with r < 1 (inside the DPD interaction range)
  double chi2_outside = NAN;     // and over r >= 1
  double r_max_z = NAN;          // bin centre of the largest |g - 1| / sigma
  double mean_dev_inside = NAN;  // count-weighted mean of g - 1 over r < 1, and its Poisson error
  double mean_dev_inside_err = NAN;
  double sigma_min = NAN, sigma_max = NAN;  // Poisson standard error of g per bin (inner, outer bin)
  std::size_t bins = 0;
  std::uint64_t samples = 0;
  std::uint64_t n = 0;
};

// Snapshots `every` steps apart are treated as independent (choose `every` so a particle moves further than
// a bin, as for the run lengths used here). For uniformly, independently placed particles in a periodic box
// the pair indicators of a bin are pairwise independent, so the unordered pair count in bin b is Poisson to
// O(1/N) with mean mu_b = S N(N-1)/2 * shell_b / V over S snapshots; sigma(g_b) = 1/sqrt(mu_b).
inline IdealGasResult measure_ideal_gas(const FluidCase& c, const RunLength& run, std::size_t bins,
                                        double rmax) {
  FluidCase ic = c;
  ic.a = 0.0;
  Simulation sim(make_spec(ic), RunOptions{});
  for (std::uint64_t k = 0; k < run.equil; ++k) sim.step();
  RadialDistribution rdf(bins, rmax);
  const std::array<double, 3> len{c.lx, c.ly, c.lz};
  const std::size_t n = sim.particles().n_local;
  for (std::uint64_t k = 1; k <= run.prod; ++k) {
    sim.step();
    if (k % run.every == 0) {
      const ParticleData& p = sim.particles();
      rdf.sample(p.x.data(), p.y.data(), p.z.data(), n, len);
    }
  }
  IdealGasResult r;
  r.bins = bins;
  r.samples = rdf.samples();
  r.n = n;
  const std::vector<double> g = rdf.g();
  const double vol = c.lx * c.ly * c.lz;
  const double pairs =
      0.5 * static_cast<double>(n) * static_cast<double>(n - 1) * static_cast<double>(r.samples);
  const double dr = rdf.bin_width();
  double chi2 = 0, maxdev = 0, maxz = 0, chi2_in = 0, mu_in = 0, dev_in = 0;
  std::size_t bins_in = 0;
  r.sigma_min = INFINITY;
  r.sigma_max = 0;
  for (std::size_t b = 0; b < bins; ++b) {
    const double lo = static_cast<double>(b) * dr, hi = lo + dr;
    const double mu = pairs * 4.0 / 3.0 * std::numbers::pi * (hi * hi * hi - lo * lo * lo) / vol;
    const double sigma = 1.0 / std::sqrt(mu);
    const double dev = g[b] - 1.0;
    chi2 += dev * dev / (sigma * sigma);
    maxdev = std::max(maxdev, std::abs(dev));
    if (std::abs(dev) / sigma > maxz) r.r_max_z = lo + 0.5 * dr;
    maxz = std::max(maxz, std::abs(dev) / sigma);
    if (hi <= 1.0 + 1e-12) {
      chi2_in += dev * dev / (sigma * sigma);
      ++bins_in;
      mu_in += mu;
      dev_in += mu * dev;
    }
    r.sigma_min = std::min(r.sigma_min, sigma);
    r.sigma_max = std::max(r.sigma_max, sigma);
  }
  r.max_abs_dev = maxdev;
  r.max_z = maxz;
  r.chi2_per_bin = chi2 / static_cast<double>(bins);
  r.chi2_inside = bins_in > 0 ? chi2_in / static_cast<double>(bins_in) : NAN;
  r.chi2_outside = bins > bins_in ? (chi2 - chi2_in) / static_cast<double>(bins - bins_in) : NAN;
  r.mean_dev_inside = mu_in > 0 ? dev_in / mu_in : NAN;
  r.mean_dev_inside_err = mu_in > 0 ? 1.0 / std::sqrt(mu_in) : NAN;
  return r;
}

// --- Reverse Poiseuille viscosity (seed 002; theory seed 000 Eq. 16 / Table 1) ---------------------------
struct ViscosityResult {
  double eta = NAN;      // fit to the profile averaged over the whole production run
  double eta_err = NAN;  // standard error from `blocks` fixed, equal blocks (each fitted on its own)
  int blocks = 0;
  double eta_err_library =
      NAN;  // PoiseuilleProfile's own error (B..2B-1 blocks of doubling size), for comparison
  double eta_kinetic = NAN;     // kinetic_viscosity(rho, gamma, kT, rd = 1, s)
  Estimate kT_transverse;       // sum m (vy^2 + vz^2) / 2N during the flow: the flow (x) does not enter it
  double v_max = NAN;           // fitted peak flow speed c (Lz/4)^2
  double shear_rate_max = NAN;  // rho g Lz / (4 eta), at the force discontinuities
  double relax_time = NAN;      // rho (Lz / 2 pi)^2 / eta: relaxation time of the slowest flow mode
  std::uint64_t n = 0;
};

// Flow along x, gradient along z; the profile is sampled every step after `equil` steps (start-up of the
// flow: a few relax_time). The error comes from `blocks` fixed blocks, each fitted separately: block means of
// a flow mode are independent only if a block is several relax_time long, so choose prod >= ~3 blocks
// relax_time (PoiseuilleProfile's own error, which keeps 10..19 blocks, is kept for comparison and is too
// small on short runs). eta = rho g / (2 c) and the block fits are combined through 1/eta, which is linear in
// the data.
inline ViscosityResult measure_viscosity(const FluidCase& c, double g, const RunLength& run, int bins = 40) {
  SimulationSpec spec = make_spec(c);
  spec.poiseuille.enabled = true;
  spec.poiseuille.force = g;
  spec.poiseuille.flow_axis = 0;
  spec.poiseuille.gradient_axis = 2;
  Simulation sim(std::move(spec), RunOptions{});
  const std::size_t n = sim.particles().n_local;
  const double rho = static_cast<double>(n) / (c.lx * c.ly * c.lz);
  const auto nbins = static_cast<std::size_t>(bins);
  PoiseuilleProfile total(nbins, 0, 2, c.lz, 10, g, rho);
  std::vector<PoiseuilleProfile> block(static_cast<std::size_t>(run.blocks),
                                       PoiseuilleProfile(nbins, 0, 2, c.lz, 2, g, rho));
  const std::uint64_t per_block = run.prod / static_cast<std::uint64_t>(run.blocks);
  for (std::uint64_t k = 0; k < run.equil; ++k) sim.step();
  std::vector<double> kt;
  for (std::uint64_t k = 0; k < per_block * block.size(); ++k) {
    sim.step();
    const ParticleData& p = sim.particles();
    total.sample(p.z.data(), p.vx.data(), n);
    block[k / per_block].sample(p.z.data(), p.vx.data(), n);
    if ((k + 1) % run.every == 0) {
      double s2 = 0;
      for (std::size_t i = 0; i < n; ++i) s2 += p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
      kt.push_back(s2 / (2.0 * static_cast<double>(n)));
    }
  }
  ViscosityResult r;
  const ViscosityFit fit = total.fit();
  r.eta = fit.eta;
  r.eta_err_library = fit.eta_err;
  std::vector<double> inv;
  for (const auto& b : block) inv.push_back(1.0 / b.fit().eta);
  const Estimate e = block_estimate(inv, run.blocks);
  r.eta_err = r.eta * e.err / e.mean;  // relative error of 1/eta = relative error of eta
  r.blocks = run.blocks;
  r.eta_kinetic = kinetic_viscosity(rho, c.gamma, c.kT, 1.0, c.s);
  r.kT_transverse = block_estimate(kt, run.blocks);
  r.v_max = fit.v_amplitude;
  r.shear_rate_max = rho * g * c.lz / (4.0 * r.eta);
  r.relax_time = rho * std::pow(c.lz / (2.0 * std::numbers::pi), 2) / r.eta;
  r.n = n;
  return r;
}

}  // namespace mesodpd::validation
