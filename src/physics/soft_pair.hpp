// A soft cosine pair potential, U = A [1 + cos(pi r / r_c)] for r < r_c (the form of LAMMPS's
// `pair_style soft`), with no dissipative or random part: a conservative soft fluid. It exists to show
// and test that a second force law plugs into the shared pair loop (docs/architecture.md, "Add a pair
// force law"), and is useful on its own to push apart overlapping particles before a DPD run.
#pragma once
#include <cmath>

#include "core/hd.hpp"
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

  struct Eval {
    // F = -dU/dr = (pi A / r_c) sin(pi r / r_c); zero at r = 0 (no direction) and beyond r_c.
    template <class Real>
    MESODPD_HD PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
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
