// The DPD pair force law (seed 000 Eqs. 2-8), written once and called by every backend.
// Includes only our vector type and <cmath>, so it compiles under nvcc as well as g++. Written without
// branches (selects only) so that a loop over pairs vectorises.
#pragma once
#include <cmath>
#include <type_traits>

#include "core/vec3.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"
#include "physics/power.hpp"

namespace mesodpd {

// Parameters for one species pair. All lengths in units of the reference cutoff. Real is double, or
// float for the single-precision pair arithmetic (MESODPD_SINGLE).
template <class Real>
struct DpdPairParamsT {
  Real a = 0;       // conservative amplitude a_ij (seed 000 Eq. 3)
  Real gamma = 0;   // dissipative strength gamma_ij (seed 000 Eq. 4)
  Real sigma = 0;   // random amplitude sigma_ij, sigma^2 = 2 gamma k_BT (seed 000 Eq. 7)
  Real rc = 1;      // conservative cutoff r_c
  Real rd = 1;      // dissipative/random cutoff r_d (seed 000 Eq. 8)
  Real s = 2;       // weight exponent: w_D = w_R^2 = (1 - r/r_d)^s (seed 000 Eq. 8)
  Real rcut2 = 1;   // max(rc, rd)^2, the interaction range of this pair

  template <class Other>
  DpdPairParamsT<Other> as() const {
    return {Other(a), Other(gamma), Other(sigma), Other(rc), Other(rd), Other(s), Other(rcut2)};
  }
};
using DpdPairParams = DpdPairParamsT<double>;

// The three parts of the force on i due to j; energy U_ij = a rc/2 (1 - r/rc)^2, whose -dU/dr is the
// conservative force.
template <class Real>
using DpdPairForceT = PairForceT<Real>;
using DpdPairForce = DpdPairForceT<double>;

// Which exponent the weight w_D = (1 - r/r_d)^s has. The common ones get exact closed forms (no pow),
// chosen once per parameter table so the pair loop does not branch on s.
enum class WeightKind { Two, One, Half, Quarter, General };

MESODPD_HD WeightKind weight_kind_of(double s) {
  return s == 2.0 ? WeightKind::Two
         : s == 1.0 ? WeightKind::One
         : s == 0.5 ? WeightKind::Half
         : s == 0.25 ? WeightKind::Quarter
                     : WeightKind::General;
}

// w_D(om) and w_R(om) = sqrt(w_D(om)) for om = 1 - r/r_d >= 0 (seed 000 Eqs. 6, 8).
template <WeightKind W, class Real>
MESODPD_HD void dpd_weights(Real om, Real s, Real& wd, Real& wr) {
  if constexpr (W == WeightKind::Two) {
    wd = om * om;
    wr = om;
  } else if constexpr (W == WeightKind::One) {
    wd = om;
    wr = std::sqrt(om);
  } else if constexpr (W == WeightKind::Half) {
    wd = std::sqrt(om);
    wr = std::sqrt(wd);
  } else if constexpr (W == WeightKind::Quarter) {
    wd = std::sqrt(std::sqrt(om));
    wr = std::sqrt(wd);
  } else {
    wr = pow_pos(om, Real(0.5) * s);  // one power (physics/power.hpp): w_D = w_R^2
    wd = wr * wr;
  }
}

// Force magnitudes for a pair at distance r (0 <= r) with r_hat . v_ij = rv.
// xi is the symmetric unit-variance noise and inv_sqrt_dt = 1/sqrt(dt) (the random force
// scales as dt^-1/2 so that its impulse has the Wiener increment's variance).
// A pair at r = 0 has no defined direction: it gets zero force rather than NaN.
template <WeightKind W = WeightKind::General, class Real = double>
MESODPD_HD DpdPairForceT<Real> dpd_pair_force(const DpdPairParamsT<Real>& p, std::type_identity_t<Real> r,
                                              std::type_identity_t<Real> rv, std::type_identity_t<Real> xi,
                                              std::type_identity_t<Real> inv_sqrt_dt) {
  const bool apart = r > Real(0);
  const Real wc = (apart && r < p.rc) ? Real(1) - r / p.rc : Real(0);  // seed 000 Eq. 3
  const Real om = (apart && r < p.rd) ? Real(1) - r / p.rd : Real(0);
  Real wd, wr;
  dpd_weights<W>(om, p.s, wd, wr);
  DpdPairForceT<Real> out;
  out.fc = p.a * wc;
  out.energy = Real(0.5) * p.a * p.rc * wc * wc;
  out.fd = -p.gamma * wd * rv;                 // seed 000 Eq. 4
  out.fr = p.sigma * wr * xi * inv_sqrt_dt;    // seed 000 Eq. 5
  return out;
}

// Calls f(Eval<W>{}) with the closed-form weight W shared by every entry of `table` (s_of(entry) is its
// exponent s), or with the general pow form when they differ: the choice is made once per table, so
// the pair loop does not branch on s. Shared by every law with DPD dissipative and random forces.
template <template <WeightKind> class Eval, class Table, class S, class F>
void with_weight_evaluator(const Table& table, S&& s_of, F&& f) {
  WeightKind w = table.empty() ? WeightKind::General : weight_kind_of(static_cast<double>(s_of(table[0])));
  for (const auto& q : table)
    if (weight_kind_of(static_cast<double>(s_of(q))) != w) w = WeightKind::General;
  switch (w) {
    case WeightKind::Two: return f(Eval<WeightKind::Two>{});
    case WeightKind::One: return f(Eval<WeightKind::One>{});
    case WeightKind::Half: return f(Eval<WeightKind::Half>{});
    case WeightKind::Quarter: return f(Eval<WeightKind::Quarter>{});
    case WeightKind::General: return f(Eval<WeightKind::General>{});
  }
}

// The standard DPD law as a functor for the shared pair loop (engine/force_compute.cpp) and the
// reference loop. Parameters per species pair; the weight exponent picks a closed-form evaluator once
// per table so the pair loop does not branch on s.
struct DpdLaw {
  template <class Real>
  using Params = DpdPairParamsT<Real>;
  static constexpr bool kVelocity = true;  // dissipative force reads r_hat . v_ij
  static constexpr bool kNoise = true;     // random force reads xi_ij
  static constexpr bool kDensity = false;

  // The schema's view (physics/law_keys.hpp): pair.style = "dpd" reads the shared keys only.
  static constexpr std::string_view kStyle = "dpd";
  static constexpr std::string_view kDoc = "standard DPD (conservative, dissipative, random; seed 000 Eqs. 2-8).";
  static constexpr std::array<std::string_view, 6> kShared = kSharedPairKeys;
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr std::array<LawKey, 0> kOwn{};
  static constexpr double kMinA = 0;  // a repels
  static double range(const PairValues& v) { return v.rc > v.rd ? v.rc : v.rd; }
  static Params<double> make(const PairValues& v) {
    const double r = range(v);
    return {v.a, v.gamma, v.sigma, v.rc, v.rd, v.s, r * r};
  }
  static LawProblem problem(const PairValues&) { return {}; }

  template <WeightKind W>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      return dpd_pair_force<W>(p, in.r, in.rv, in.xi, in.inv_sqrt_dt);
    }
  };

  // Calls f(Eval<W>{}) with the closed form shared by every pair of `table`, or the general pow form.
  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    with_weight_evaluator<Eval>(table, [](const auto& q) { return q.s; }, f);
  }
};

}  // namespace mesodpd
