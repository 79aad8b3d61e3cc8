// Transport DPD (tDPD; Li, Yazdani, Tartakovsky & Karniadakis, J. Chem. Phys. 143, 014101 (2015); seed
// 003's "Concentration field (tDPD)"): every particle carries up to 4 solute concentrations C_i^k, which
// the pairs exchange by a Fick flux and a random flux, on top of standard DPD forces. Written once for
// every backend, without branches (selects only), like the other laws.
//
// The force on i due to j is standard DPD (seed 000 Eqs. 3-8, with the conservative cutoff rc and the
// dissipative/random cutoff rd):
//   F^C = a_ij w_C e,  F^D = -gamma w_D (e.v) e,  F^R = sigma w_R xi dt^-1/2 e,  w_D = w_R^2 = (1 - r/r_d)^s.
// The rate of solute k of i due to j (Li et al. 2015, Eqs. 5-7; j gets the opposite, so every solute is
// conserved pair by pair):
//   dC_i^k/dt += Q^D + Q^R,  Q^D = -kappa^k_ij w_DC (C_i^k - C_j^k),
//   Q^R = epsilon^k_ij w_RC (C_i^k + C_j^k) xs^k dt^-1/2,  w_DC = w_RC^2 = (1 - r/r_cc)^{s_C^k},
// with xs^k_ij = -xs^k_ji a unit-variance noise per solute. In the continuum limit the Fick flux is
// diffusion with D^k = 2 pi n kappa^k r_cc^5 / 315 for s_C = 2 (docs/physics.md, "tDPD").
//
// The law returns the rates in PairForceT::qi[k], qj[k] = -qi[k]. A wall (frozen) particle of a species
// without `solute_wall = 1` exchanges nothing (an impermeable wall): its pairs get kappa = epsilon = 0.
#pragma once
#include <array>
#include <cmath>
#include <limits>
#include <string_view>

#include "core/hd.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/power.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

inline constexpr int kMaxSolutes = kMaxScalars;

template <class Real>
struct TdpdPairParamsT {
  Real a = 0;      // a_ij
  Real gamma = 0;  // gamma_ij
  Real sigma = 0;  // sigma_ij = sqrt(2 gamma kT)
  Real rc = 1;     // conservative cutoff
  Real rd = 1;     // dissipative and random cutoff
  Real s = 2;      // weight exponent
  Real rcc = 1;    // solute cutoff r_cc
  Real kappa[kMaxSolutes] = {0, 0, 0, 0};    // Fick coefficients kappa^k_ij
  Real epsilon[kMaxSolutes] = {0, 0, 0, 0};  // random-flux amplitudes epsilon^k_ij
  Real sc[kMaxSolutes] = {2, 2, 2, 2};       // solute weight exponents s_C^k
  Real rcut2 = 1;  // max(rc, rd, rcc)^2

  template <class Other>
  TdpdPairParamsT<Other> as() const {
    TdpdPairParamsT<Other> o;
    o.a = Other(a);
    o.gamma = Other(gamma);
    o.sigma = Other(sigma);
    o.rc = Other(rc);
    o.rd = Other(rd);
    o.s = Other(s);
    o.rcc = Other(rcc);
    for (int k = 0; k < kMaxSolutes; ++k) {
      o.kappa[k] = Other(kappa[k]);
      o.epsilon[k] = Other(epsilon[k]);
      o.sc[k] = Other(sc[k]);
    }
    o.rcut2 = Other(rcut2);
    return o;
  }
};

struct TdpdLaw {
  template <class Real>
  using Params = TdpdPairParamsT<Real>;
  static constexpr bool kVelocity = true;
  static constexpr bool kNoise = true;
  static constexpr bool kDensity = false;
  // Four scalars, the concentrations; a run holds the first [tdpd] solutes of them.
  static constexpr int kScalars = kMaxSolutes;
  static constexpr std::array<std::string_view, kMaxSolutes> kScalarFields{"conc1", "conc2", "conc3", "conc4"};
  static constexpr std::array<std::string_view, kMaxSolutes> kScalarRates{"conc_rate1", "conc_rate2", "conc_rate3",
                                                                          "conc_rate4"};

  static constexpr std::string_view kStyle = "tdpd";
  static constexpr std::string_view kDoc =
      "transport DPD (Li et al. 2015): standard DPD forces plus up to 4 solute concentrations per particle "
      "([tdpd] solutes; species keys `conc1`..`conc4`), exchanged by a Fick flux -kappa_k w_DC (C_i - C_j) and a "
      "random flux epsilon_k w_RC (C_i + C_j) over `rcc`; see docs/physics.md, \"tDPD\".";
  static constexpr std::array<std::string_view, 5> kShared{"a", "gamma", "rc", "rd", "s"};
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr std::array<LawKey, 13> kOwn{{
      {"rcc", 0.0, 10.0, true, true, false, 0.0, "",
       "the solute cutoff r_cc of w_DC = w_RC^2 = (1 - r/r_cc)^{s_C}; 0 (the default) means the pair's rc."},
      {"kappa1", 0.0, kInf, true, true, false, 0.0, "",
       "the Fick coefficient kappa of solute 1: Q^D = -kappa w_DC (C_i - C_j); for s_C = 2 the diffusivity is "
       "D = 2 pi n kappa r_cc^5 / 315 (docs/physics.md, \"tDPD\")."},
      {"kappa2", 0.0, kInf, true, true, false, 0.0, "", "see `kappa1`, for solute 2."},
      {"kappa3", 0.0, kInf, true, true, false, 0.0, "", "see `kappa1`, for solute 3."},
      {"kappa4", 0.0, kInf, true, true, false, 0.0, "", "see `kappa1`, for solute 4."},
      {"epsilon1", 0.0, kInf, true, true, false, 0.0, "",
       "the random-flux amplitude of solute 1: Q^R = epsilon w_RC (C_i + C_j) xi dt^-1/2 (Li et al. 2015); 0 (the "
       "default) makes the solute flux deterministic."},
      {"epsilon2", 0.0, kInf, true, true, false, 0.0, "", "see `epsilon1`, for solute 2."},
      {"epsilon3", 0.0, kInf, true, true, false, 0.0, "", "see `epsilon1`, for solute 3."},
      {"epsilon4", 0.0, kInf, true, true, false, 0.0, "", "see `epsilon1`, for solute 4."},
      {"sc1", 0.0, 10.0, false, true, false, 2.0, "", "the weight exponent s_C of solute 1."},
      {"sc2", 0.0, 10.0, false, true, false, 2.0, "", "see `sc1`, for solute 2."},
      {"sc3", 0.0, 10.0, false, true, false, 2.0, "", "see `sc1`, for solute 3."},
      {"sc4", 0.0, 10.0, false, true, false, 2.0, "", "see `sc1`, for solute 4."},
  }};
  // [[species]] keys: the starting concentrations, and whether a frozen species is a solute wall.
  static constexpr std::array<LawKey, 5> kSpeciesOwn{{
      {"conc1", 0.0, kInf, true, true, false, 0.0, "",
       "the starting concentration of solute 1 on the species' particles (solutes per particle). On a frozen "
       "species with `solute_wall = 1`: the concentration the wall is held at."},
      {"conc2", 0.0, kInf, true, true, false, 0.0, "", "see `conc1`, for solute 2."},
      {"conc3", 0.0, kInf, true, true, false, 0.0, "", "see `conc1`, for solute 3."},
      {"conc4", 0.0, kInf, true, true, false, 0.0, "", "see `conc1`, for solute 4."},
      {"solute_wall", 0.0, 1.0, true, true, false, 0.0, "",
       "for a frozen (wall) species: 1 holds its particles at `conc1`..`conc4`, so solute flows between the wall "
       "and the fluid; 0 (the default) makes the wall impermeable (no solute flux)."},
  }};
  static constexpr double kMinA = 0;
  static double solute_range(const PairValues& v) { return v.own[0] > 0 ? v.own[0] : v.rc; }
  static double range(const PairValues& v) {
    const double r = v.rc > v.rd ? v.rc : v.rd;
    return r > solute_range(v) ? r : solute_range(v);
  }
  static Params<double> make(const PairValues& v) {
    Params<double> p;
    p.a = v.a;
    p.gamma = v.gamma;
    p.sigma = v.sigma;
    p.rc = v.rc;
    p.rd = v.rd;
    p.s = v.s;
    p.rcc = solute_range(v);
    // An impermeable wall (a frozen species without solute_wall = 1) exchanges no solute.
    const bool sealed = (v.frozen_i && !(v.species_i[4] > 0.5)) || (v.frozen_j && !(v.species_j[4] > 0.5));
    for (int k = 0; k < kMaxSolutes; ++k) {
      p.kappa[k] = sealed ? 0.0 : v.own[1 + static_cast<std::size_t>(k)];
      p.epsilon[k] = sealed ? 0.0 : v.own[5 + static_cast<std::size_t>(k)];
      p.sc[k] = v.own[9 + static_cast<std::size_t>(k)];
    }
    const double r = range(v);
    p.rcut2 = r * r;
    return p;
  }
  static LawProblem problem(const PairValues&) { return {}; }

  // kQuadratic: every weight exponent (s and each s_C) is 2, the closed form; else pow.
  template <bool kQuadratic>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      const bool apart = in.r > Real(0);
      const Real wc = (apart && in.r < p.rc) ? Real(1) - in.r / p.rc : Real(0);
      const Real om = (apart && in.r < p.rd) ? Real(1) - in.r / p.rd : Real(0);
      Real wd, wr;
      if constexpr (kQuadratic)
        dpd_weights<WeightKind::Two>(om, p.s, wd, wr);
      else
        dpd_weights<WeightKind::General>(om, p.s, wd, wr);
      PairForceT<Real> out;
      out.fc = p.a * wc;
      out.energy = Real(0.5) * p.a * p.rc * wc * wc;
      out.fd = -p.gamma * wd * in.rv;
      out.fr = p.sigma * wr * in.xi * in.inv_sqrt_dt;
      const Real omc = (apart && in.r < p.rcc) ? Real(1) - in.r / p.rcc : Real(0);
      for (int k = 0; k < kMaxSolutes; ++k) {
        Real wdc, wrc;
        if constexpr (kQuadratic) {
          wdc = omc * omc;
          wrc = omc;
        } else {
          wdc = pow_pos(omc, p.sc[k]);
          wrc = std::sqrt(wdc);
        }
        const Real q = -p.kappa[k] * wdc * (in.si[k] - in.sj[k]) +
                       p.epsilon[k] * wrc * (in.si[k] + in.sj[k]) * in.xs[k] * in.inv_sqrt_dt;
        out.qi[k] = q;
        out.qj[k] = -q;
      }
      return out;
    }
  };

  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    bool quadratic = true;
    for (const auto& q : table) {
      quadratic = quadratic && q.s == 2;
      for (int k = 0; k < kMaxSolutes; ++k) quadratic = quadratic && q.sc[k] == 2;
    }
    if (quadratic) return f(Eval<true>{});
    f(Eval<false>{});
  }
};

}  // namespace mesodpd
