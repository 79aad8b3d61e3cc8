// Liu's spline potentials (seed 000 Eqs. 18-23): U_ij(r) = a_ij [A W(r, r_c1) - B W(r, r_c2)] with the
// cubic spline W of Eq. 18, a short-range repulsion minus a longer-range attraction, and
// F^C = -dU/dr (Eq. 20); the standard DPD dissipative and random forces act over r_d with exponent s.
#pragma once
#include <cmath>

#include "core/hd.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

template <class Real>
struct SplinePairParamsT {
  Real a = 0;      // a_ij: interaction strength (Eqs. 21-23)
  Real ka = 0;     // A: coefficient of the repulsive spline W(r, r_c1)
  Real rc1 = 1;    // r_c1
  Real kb = 0;     // B: coefficient of the attractive spline W(r, r_c2)
  Real rc2 = 1;    // r_c2
  DpdPairParamsT<Real> dpd;  // gamma, sigma, rd, s of the dissipative and random forces; dpd.a is 0
  Real rcut2 = 1;  // max(r_c1, r_c2, r_d)^2

  template <class Other>
  SplinePairParamsT<Other> as() const {
    return {Other(a), Other(ka), Other(rc1), Other(kb), Other(rc2), dpd.template as<Other>(), Other(rcut2)};
  }
};

// The cubic spline W(r, r_c) of seed 000 Eq. 18 (q = 2r/r_c) and its derivative dW/dr.
template <class Real>
MESODPD_HD void cubic_spline(Real r, Real rc, Real& w, Real& dw) {
  const Real q = Real(2) * r / rc;
  const Real t = Real(2) - q;
  const bool inner = q < Real(1), inside = q < Real(2);
  const Real w_in = Real(1) - Real(1.5) * q * q + Real(0.75) * q * q * q;
  const Real w_out = Real(0.25) * t * t * t;
  const Real d_in = -Real(3) * q + Real(2.25) * q * q;  // dW/dq
  const Real d_out = -Real(0.75) * t * t;
  w = inner ? w_in : (inside ? w_out : Real(0));
  dw = (inner ? d_in : (inside ? d_out : Real(0))) * Real(2) / rc;
}

struct SplineLaw {
  template <class Real>
  using Params = SplinePairParamsT<Real>;
  static constexpr bool kVelocity = true;
  static constexpr bool kNoise = true;
  static constexpr bool kDensity = false;

  // The schema's view (physics/law_keys.hpp): A, r_c1, B, r_c2 of seed 000 Eq. 19, all required; the
  // dissipative and random forces act over rd.
  static constexpr std::string_view kStyle = "spline";
  static constexpr std::string_view kDoc =
      "Liu's potentials U = a_ij [A W(r, r_c1) - B W(r, r_c2)] with the cubic spline W of seed 000 Eq. 18, F^C = "
      "-dU/dr; `a`, `repulsion` (A), `rc1`, `attraction` (B), `rc2` are required; the dissipative and random forces "
      "act over `rd` (default `rc`). See docs/physics.md.";
  static constexpr std::array<std::string_view, 6> kShared = kSharedPairKeys;
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr std::array<LawKey, 4> kOwn{{
      {"repulsion", 0.0, kInf, true, true, true, 0.0, "A of seed 000 Eq. 19 (Liu: repulsion = 2.0)",
       "A of seed 000 Eq. 19, the coefficient of the repulsive spline W(r, r_c1)."},
      {"rc1", 0.0, 10.0, false, true, true, 0.0, "r_c1 of seed 000 Eq. 19 (Liu: rc1 = 0.8)",
       "the range r_c1 of the repulsive spline."},
      {"attraction", 0.0, kInf, true, true, true, 0.0, "B of seed 000 Eq. 19 (Liu: attraction = 0..1.1)",
       "B of seed 000 Eq. 19, the coefficient of the attractive spline W(r, r_c2); must be smaller than `repulsion` "
       "(U(0) = a (A - B) > 0, else the particles collapse)."},
      {"rc2", 0.0, 10.0, false, true, true, 0.0, "r_c2 of seed 000 Eq. 19 (Liu: rc2 = 1.0)",
       "the range r_c2 of the attractive spline."},
  }};
  static constexpr double kMinA = 0;
  static double range(const PairValues& v) {
    const double r12 = v.own[1] > v.own[3] ? v.own[1] : v.own[3];
    return r12 > v.rd ? r12 : v.rd;
  }
  static Params<double> make(const PairValues& v) {
    const double r = range(v);
    // seed 000 Eqs. 19-23; the dissipative and random forces act over rd.
    return {v.a, v.own[0], v.own[1], v.own[2], v.own[3],
            DpdPairParamsT<double>{0.0, v.gamma, v.sigma, v.rc, v.rd, v.s, r * r}, r * r};
  }
  static LawProblem problem(const PairValues& v) {
    if (v.own[2] > 0 && v.own[0] <= v.own[2])
      return {"attraction",
              "must be smaller than repulsion = {value} for {pair}: U(0) = a (A - B) must be positive, or the "
              "particles collapse onto each other",
              v.own[0]};
    return {};
  }

  template <WeightKind W>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      PairForceT<Real> out = dpd_pair_force<W>(p.dpd, in.r, in.rv, in.xi, in.inv_sqrt_dt);
      Real w1, d1, w2, d2;
      cubic_spline(in.r, p.rc1, w1, d1);
      cubic_spline(in.r, p.rc2, w2, d2);
      out.energy = p.a * (p.ka * w1 - p.kb * w2);  // seed 000 Eq. 19
      // -dU/dr (Eq. 20); the splines are flat at r = 0, so the force vanishes there without a branch.
      out.fc = -p.a * (p.ka * d1 - p.kb * d2);
      return out;
    }
  };

  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    with_weight_evaluator<Eval>(table, [](const auto& q) { return q.dpd.s; }, f);
  }
};

}  // namespace mesodpd
