// Tests of the transport correlations (analysis/transport.hpp) on synthetic signals whose correlation
// functions and integrals are known: the multiple-origin averages against direct sums, Ornstein-Uhlenbeck
// velocities and stresses against their exact D and eta, and a checkpoint that continues bit for bit.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <tuple>
#include <stdexcept>
#include <vector>

#include "analysis/transport.hpp"
#include "io/byte_buffer.hpp"

namespace mesodpd {
namespace {

// One sample of velocities and positions held x y z interleaved per particle, as the test signals keep them.
void sample_interleaved(TransportCorrelations& c, std::uint64_t step, const std::vector<double>& v,
                        const std::vector<double>& r, double kT) {
  const std::size_t n = v.size() / 3;
  std::vector<double> vx(n), vy(n), vz(n), x(n), y(n), z(n);
  for (std::size_t i = 0; i < n; ++i) {
    vx[i] = v[3 * i], vy[i] = v[3 * i + 1], vz[i] = v[3 * i + 2];
    x[i] = r[3 * i], y[i] = r[3 * i + 1], z[i] = r[3 * i + 2];
  }
  c.sample(step, vx.data(), vy.data(), vz.data(), x.data(), y.data(), z.data(), n, kT, static_cast<double>(n));
}

// n particles, each velocity component an Ornstein-Uhlenbeck process of variance kT (unit mass) and
// relaxation time tau, positions integrated exactly over each interval h in the mean velocity (x advances
// by h (v_k + v_k+1) / 2); and a stress tensor whose six components are independent OU processes of
// variance s2 and time tau_s, each step's value fed in as it is.
struct Synthetic {
  std::size_t n;
  double kT, tau, s2, tau_s, dt;
  std::uint64_t every;
  std::mt19937_64 rng;
  std::normal_distribution<double> gauss{0.0, 1.0};
  std::vector<double> v, r;
  std::array<double, 6> p{};

  Synthetic(std::size_t n_, double kT_, double tau_, double s2_, double tau_s_, double dt_, std::uint64_t every_,
            std::uint64_t seed)
      : n(n_), kT(kT_), tau(tau_), s2(s2_), tau_s(tau_s_), dt(dt_), every(every_), rng(seed), v(3 * n_), r(3 * n_) {
    for (double& x : v) x = std::sqrt(kT) * gauss(rng);
    for (double& x : p) x = std::sqrt(s2) * gauss(rng);
  }
  void step() {
    const double a = std::exp(-dt / tau), b = std::sqrt(kT * (1 - a * a));
    for (std::size_t k = 0; k < v.size(); ++k) {
      const double old = v[k];
      v[k] = a * v[k] + b * gauss(rng);
      r[k] += 0.5 * dt * (old + v[k]);
    }
    const double as = std::exp(-dt / tau_s), bs = std::sqrt(s2 * (1 - as * as));
    for (double& x : p) x = as * x + bs * gauss(rng);
  }
  // Runs `steps` steps into c, sampling every `every`; the first sample at step `every`.
  void run(TransportCorrelations& c, std::uint64_t from, std::uint64_t to) {
    for (std::uint64_t s = from + 1; s <= to; ++s) {
      step();
      c.add_pressure(p);
      if (s % every == 0) sample_interleaved(c, s, v, r, kT);
    }
  }
};

// OU velocities: <v(0).v(t)> = 3 kT exp(-t / tau), so D = kT tau = 0.1 (the window of 10 tau leaves out
// 5e-5 of it, and the MSD's slope over [5 tau, 10 tau] is 6 D to 0.3%). Stress: C(t) = s2 exp(-t / tau_s)
// in every shear-like component, so eta = V / kT s2 tau_s for the off-diagonal ones; the traceless
// normal stresses d_a = P_aa - p of three independent components have sum_a <d_a d_a> = 2 s2 (not 4 s2
// as in a fluid), so eta_normal = eta / 2 here. 800 time units in 10 blocks: the block errors must cover
// the truth (4 standard errors) and be small enough to mean something (D < 2%, eta_shear < 8%, eta_normal < 12%; measured 0.2%, 5.7%, 7.5%).
TEST(TransportCorrelations, RecoversOrnsteinUhlenbeckDiffusionAndViscosity) {
  const double kT = 1.0, tau = 0.1, s2 = 0.04, tau_s = 0.1, dt = 0.01, volume = 50.0;
  Synthetic sys(200, kT, tau, s2, tau_s, dt, 2, 7);
  TransportCorrelations c(50, 2, dt, 8000, true);
  sys.run(c, 0, 80000);
  const TransportResult res = c.result(volume);
  ASSERT_EQ(res.blocks, 10u);
  EXPECT_DOUBLE_EQ(res.window, 1.0);
  const double d_true = kT * tau, eta_true = volume / kT * s2 * tau_s;
  // (The normal stresses here are two independent combinations at half the value: twice the relative error.)
  for (const auto& [name, e, truth, band] :
       {std::tuple{"d_vacf", res.d_vacf, d_true, 0.02}, std::tuple{"d_msd", res.d_msd, d_true, 0.02},
        std::tuple{"eta_shear", res.eta_shear, eta_true, 0.08}, std::tuple{"eta_normal", res.eta_normal, eta_true / 2, 0.12}}) {
    EXPECT_LT(e.error, band * truth) << name;
    EXPECT_NEAR(e.value, truth, 4 * e.error) << name << " " << e.value << " +- " << e.error;
  }
  EXPECT_NEAR(res.kT.value, kT, 1e-12);
  // Sc = eta / (rho D) with rho = n / V, the combination of the five stress components.
  const double eta = (3 * res.eta_shear.value + 2 * res.eta_normal.value) / 5;
  EXPECT_NEAR(res.eta.value, eta, 1e-12 * eta);
  EXPECT_NEAR(res.schmidt.value, res.eta.value / (200.0 / volume * res.d_msd.value), 1e-9);
  EXPECT_GT(res.schmidt.error, 0.0);
}

// The multiple-origin averages of one block equal direct sums over every (origin, lag) pair: VACF, MSD
// and the stress products, on a short made-up series whose particle count is small.
TEST(TransportCorrelations, OriginAveragesMatchDirectSums) {
  const std::size_t n = 3, samples = 9, lags = 4;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<std::vector<double>> v(samples, std::vector<double>(3 * n)), r = v;
  std::vector<std::array<double, 6>> p(samples);
  for (std::size_t s = 0; s < samples; ++s) {
    for (double& x : v[s]) x = g(rng);
    for (double& x : r[s]) x = 3 * g(rng);
    for (double& x : p[s]) x = g(rng);
  }
  const auto feed = [&](TransportCorrelations& c) {
    for (std::size_t s = 0; s < samples; ++s) {
      c.add_pressure(p[s]);
      sample_interleaved(c, 10 + s, v[s], r[s], 2.0);
    }
  };
  TransportCorrelations longer(lags, 1, 0.5, 100, true);
  feed(longer);
  EXPECT_EQ(longer.complete_blocks(), 0u);  // 100 steps per block: nothing to report yet
  // Direct sums: the VACF over every origin and over every second one (origin_every = 2), the stress
  // over every origin.
  double vacf[lags + 1] = {}, vacf2[lags + 1] = {}, shear[lags + 1] = {};
  int count[lags + 1] = {}, count2[lags + 1] = {};
  for (std::size_t lag = 0; lag <= lags; ++lag)
    for (std::size_t o = 0; o + lag < samples; ++o) {
      double dot = 0;
      for (std::size_t k = 0; k < 3 * n; ++k) dot += v[o][k] * v[o + lag][k];
      vacf[lag] += dot / n;
      shear[lag] += (p[o][3] * p[o + lag][3] + p[o][4] * p[o + lag][4] + p[o][5] * p[o + lag][5]) / 3;
      ++count[lag];
      if (o % 2 == 0) vacf2[lag] += dot / n, ++count2[lag];
    }
  // The same series in one block of exactly its length: complete, and its integrals are the direct sums'.
  TransportCorrelations one(lags, 1, 0.5, samples, true);
  feed(one);
  TransportCorrelations halves(lags, 1, 0.5, samples, true, 2);
  feed(halves);
  ASSERT_EQ(one.complete_blocks(), 1u);
  const TransportResult res = one.result(7.0), res2 = halves.result(7.0);
  double d = 0, d2 = 0, eta = 0;
  for (std::size_t lag = 0; lag <= lags; ++lag) {
    const double w = (lag == 0 || lag == lags) ? 0.5 : 1.0;
    d += w * 0.5 * vacf[lag] / count[lag] / 3;
    d2 += w * 0.5 * vacf2[lag] / count2[lag] / 3;
    eta += w * 0.5 * 7.0 / 2.0 * shear[lag] / count[lag];
  }
  EXPECT_NEAR(res.d_vacf.value, d, 1e-12);
  EXPECT_NEAR(res2.d_vacf.value, d2, 1e-12);
  EXPECT_GT(std::fabs(d2 - d), 1e-3);  // the origins matter on this short series
  EXPECT_NEAR(res.eta_shear.value, eta, 1e-12);
  EXPECT_EQ(res2.eta_shear.value, res.eta_shear.value);  // the stress takes every origin
  EXPECT_TRUE(std::isnan(res.d_vacf.error));  // one block: no error bar
}

// Saved in the middle of a block and loaded into a fresh object, the correlations continue to the same
// bits as an uninterrupted series; settings that differ are refused.
TEST(TransportCorrelations, CheckpointContinuesBitIdentically) {
  const auto make = [] { return TransportCorrelations(20, 2, 0.01, 100, true); };
  Synthetic a(50, 1.0, 0.1, 0.01, 0.05, 0.01, 2, 11);
  TransportCorrelations whole = make();
  a.run(whole, 0, 1000);

  Synthetic b(50, 1.0, 0.1, 0.01, 0.05, 0.01, 2, 11);
  TransportCorrelations first = make();
  b.run(first, 0, 437);  // an odd step: mid-interval, one pressure pending
  ByteWriter w;
  first.save(w);
  TransportCorrelations second = make();
  ByteReader rd(w.bytes(), "test");
  second.load(rd, "test");
  b.run(second, 437, 1000);
  const TransportResult x = whole.result(10.0), y = second.result(10.0);
  ASSERT_EQ(x.blocks, 10u);
  ASSERT_EQ(y.blocks, 10u);
  EXPECT_EQ(x.d_vacf.value, y.d_vacf.value);
  EXPECT_EQ(x.d_msd.value, y.d_msd.value);
  EXPECT_EQ(x.eta.value, y.eta.value);
  EXPECT_EQ(x.schmidt.error, y.schmidt.error);

  TransportCorrelations other(20, 2, 0.01, 200, true);
  ByteReader rd2(w.bytes(), "test");
  EXPECT_THROW(other.load(rd2, "test"), ConfigError);
}

TEST(TransportCorrelations, RefusesIrregularSamples) {
  TransportCorrelations c(10, 2, 0.01, 100, false);
  std::vector<double> z(4, 0.0);
  EXPECT_THROW(c.sample(2, z.data(), z.data(), z.data(), z.data(), z.data(), z.data(), 4, 1.0, 4.0),
               std::invalid_argument);  // no pressure added for the interval
  c.add_pressure({});
  c.add_pressure({});
  c.sample(2, z.data(), z.data(), z.data(), z.data(), z.data(), z.data(), 4, 1.0, 4.0);
  c.add_pressure({});
  c.add_pressure({});
  EXPECT_THROW(c.sample(6, z.data(), z.data(), z.data(), z.data(), z.data(), z.data(), 4, 1.0, 4.0),
               std::invalid_argument);  // a sample skipped
}

}  // namespace
}  // namespace mesodpd
