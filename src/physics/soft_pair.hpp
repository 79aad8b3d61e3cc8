// A soft cosine pair potential, U = A [1 + cos(pi r / r_c)] for r < r_c (the form of LAMMPS's
// `pair_style soft`), with no dissipative or random part: a conservative soft fluid. It exists to show
// and test that a second force law plugs into the shared pair loop (docs/architecture.md, "Add a pair
// force law"), and is useful on its own to push apart overlapping particles before a DPD run.
#pragma once
#include <cmath>

#include "core/hd.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

template <class Real>
struct SoftPairParamsT {
  Real a = 0;      // amplitude A (energy); the force peaks at pi A / r_c at r = r_c / 2
  Real rc = 1;     // cutoff r_c
  Real rcut2 = 1;  // r_c^2, the interaction range of this pair

  template <class Other>
  SoftPairParamsT<Other> as() const {
    return {Other(a), Other(rc), Other(rcut2)};
  }
};

struct SoftLaw {
  template <class Real>
  using Params = SoftPairParamsT<Real>;
  static constexpr bool kVelocity = false;
  static constexpr bool kNoise = false;
  static constexpr bool kDensity = false;

  // The schema's view (physics/law_keys.hpp): a and rc only; a thermostat key is refused.
  static constexpr std::string_view kStyle = "soft";
  static constexpr std::string_view kDoc =
      "the soft cosine potential U = a [1 + cos(pi r / r_c)] of LAMMPS's `pair_style soft`, conservative only (no "
      "thermostat: an NVE soft fluid, or a relaxation step that pushes overlapping particles apart); it reads `a` and "
      "`rc` of each pair and refuses `gamma`, `sigma`, `rd` and `s`.";
  static constexpr std::array<std::string_view, 2> kShared{"a", "rc"};
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr std::array<LawKey, 0> kOwn{};
  static constexpr double kMinA = 0;
  static double range(const PairValues& v) { return v.rc; }
  static Params<double> make(const PairValues& v) { return {v.a, v.rc, v.rc * v.rc}; }
  static LawProblem problem(const PairValues&) { return {}; }

  struct Eval {
    // F = -dU/dr = (pi A / r_c) sin(pi r / r_c); zero at r = 0 (no direction) and beyond r_c.
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      constexpr Real kPi = Real(3.14159265358979323846);
      const bool inside = in.r < p.rc;
      const Real phase = kPi * in.r / p.rc;
      PairForceT<Real> out;
      out.fc = inside && in.r > Real(0) ? kPi * p.a / p.rc * std::sin(phase) : Real(0);
      out.energy = inside ? p.a * (Real(1) + std::cos(phase)) : Real(0);
      return out;
    }
  };

  template <class Table, class F>
  static void with_evaluator(const Table&, F&& f) {
    f(Eval{});
  }
};

}  // namespace mesodpd
