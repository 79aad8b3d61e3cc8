// A test-only pair law that joins the law list from outside src/, for the recipe "add a pair force
// law" of docs/architecture.md: a conservative power-law soft repulsion with a key of its own,
//   F(r) = a (1 - r/r_c)^n,   U(r) = a r_c (1 - r/r_c)^(n+1) / (n + 1)   for r < r_c,
// which for n = 1 is the conservative force of standard DPD (seed 000 Eq. 3) and for larger n a softer
// core. No dissipative or random part. Force-included (with extra_law.hpp) into a second build of the
// engine, the schema and the api (tests/modules/CMakeLists.txt).
#pragma once
#include <cmath>

#include "core/hd.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd::test_models {

template <class Real>
struct PowerPairParamsT {
  Real a = 0;      // amplitude: the force at r = 0
  Real rc = 1;     // cutoff r_c
  Real n = 1;      // exponent of (1 - r/r_c)
  Real rcut2 = 1;  // r_c^2, the interaction range of this pair

  template <class Other>
  PowerPairParamsT<Other> as() const {
    return {Other(a), Other(rc), Other(n), Other(rcut2)};
  }
};

struct PowerLaw {
  template <class Real>
  using Params = PowerPairParamsT<Real>;
  static constexpr bool kVelocity = false;
  static constexpr bool kNoise = false;
  static constexpr bool kDensity = false;

  static constexpr std::string_view kStyle = "test_power";
  static constexpr std::string_view kDoc =
      "a test-only power-law repulsion F = a (1 - r/r_c)^n, conservative only (tests/modules/power_law.hpp).";
  static constexpr std::array<std::string_view, 2> kShared{"a", "rc"};
  static constexpr std::array<std::string_view, 0> kRequired{};
  // Its own key: the exponent, 1 (DPD's conservative force) by default, up to 6.
  static constexpr std::array<LawKey, 1> kOwn{
      LawKey{"n", 1, 6, true, true, false, 1, "", "Exponent n of F = a (1 - r/r_c)^n."}};
  static constexpr double kMinA = 0;
  static double range(const PairValues& v) { return v.rc; }
  static Params<double> make(const PairValues& v) { return {v.a, v.rc, v.own[0], v.rc * v.rc}; }
  // A cross-check on a resolved pair: a steep core needs a cutoff long enough to resolve it.
  static LawProblem problem(const PairValues& v) {
    if (v.own[0] > 3 && v.rc < 0.5) return {"n", "above 3 needs rc >= 0.5, not {value}, for {pair}", v.rc};
    return {};
  }

  struct Eval {
    template <class Real>
    MESODPD_HD PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      const bool inside = in.r < p.rc;
      const Real w = inside ? Real(1) - in.r / p.rc : Real(0);
      const Real wn = std::pow(w, p.n);
      PairForceT<Real> out;
      out.fc = inside && in.r > Real(0) ? p.a * wn : Real(0);
      out.energy = inside ? p.a * p.rc * wn * w / (p.n + Real(1)) : Real(0);
      return out;
    }
  };

  template <class Table, class F>
  static void with_evaluator(const Table&, F&& f) {
    f(Eval{});
  }
};

}  // namespace mesodpd::test_models
