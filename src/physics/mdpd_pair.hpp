// Many-body DPD (Warren; seed 000 Eq. 17, seed 003 "Many-body DPD"): a conservative force that is
// attractive at long range and repulsive, in proportion to the local densities, at short range,
//   F^C_ij = [A_ij w_C(r) + B_ij (rho_i + rho_j) w_d(r)] e_ij,  w_C = 1 - r/r_c,  w_d = 1 - r/r_d,
// with the standard DPD dissipative and random forces over r_c. The local densities rho_i come from a
// first pair pass with a density kernel (physics/density_kernel.hpp) and reach the law through
// PairInput::rho_i / rho_j (kDensity).
#pragma once
#include <cmath>

#include "core/hd.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

template <class Real>
struct MdpdPairParamsT {
  Real a = 0;      // A_ij: amplitude of the w_C term (negative: attraction)
  Real b = 0;      // B_ij: amplitude of the density-dependent repulsion (>= 0)
  Real rd = 1;     // r_d: range of the many-body term and of the density kernel (r_d <= r_c)
  DpdPairParamsT<Real> dpd;  // gamma, sigma, rc (= dissipative range), s; dpd.a is 0
  Real rcut2 = 1;  // r_c^2

  template <class Other>
  MdpdPairParamsT<Other> as() const {
    return {Other(a), Other(b), Other(rd), dpd.template as<Other>(), Other(rcut2)};
  }
};

// Pair energy. With Warren's normalised kernel w_rho = 15/(2 pi r_d^3)(1 - r/r_d)^2 and one B for every
// pair, the many-body force is -grad of U = sum_i (pi r_d^4 / 30) B rho_i^2 (Warren 2003): the self
// energy per particle grows as rho^2. Because sum_i rho_i^2 = sum_pairs w_rho(r_ij)(rho_i + rho_j), this
// total splits into pair terms (r_d / 4) B (rho_i + rho_j)(1 - r/r_d)^2, which is what the law reports
// besides the A_ij term A r_c / 2 (1 - r/r_c)^2. With Lucy's kernel, or B_ij or r_d that differ between
// pairs, no potential exists (docs/physics.md) and the same expression is only a diagnostic.
struct MdpdLaw {
  template <class Real>
  using Params = MdpdPairParamsT<Real>;
  static constexpr bool kVelocity = true;
  static constexpr bool kNoise = true;
  static constexpr bool kDensity = true;

  // The schema's view (physics/law_keys.hpp): A_ij (a, may be negative), B_ij (b) and the many-body range
  // r_d (rd) have no neutral value and are required; the dissipative and random forces act over rc (as
  // LAMMPS's pair_style mdpd).
  static constexpr std::string_view kStyle = "mdpd";
  static constexpr std::string_view kDoc =
      "Warren's many-body DPD, F^C = [A_ij (1 - r/r_c) + B_ij (rho_i + rho_j)(1 - r/r_d)] r-hat (seed 000 Eq. 17) "
      "with A_ij = `a` (may be negative), B_ij = `b`, r_d = `rd` (here the many-body range, <= `rc`), local densities "
      "from `kernel`; the dissipative and random forces act over `rc` (as LAMMPS's `pair_style mdpd`). `a`, `b` and "
      "`rd` are required (no default).";
  static constexpr std::array<std::string_view, 6> kShared = kSharedPairKeys;
  static constexpr std::array<std::string_view, 2> kRequired{"a", "rd"};
  static constexpr std::array<std::string_view, 2> kRequiredHints{"A_ij (Warren's liquid: a = -40)",
                                                                  "the many-body range r_d (Warren: rd = 0.75)"};
  static constexpr std::array<LawKey, 1> kOwn{{
      {"b", 0.0, std::numeric_limits<double>::infinity(), true, true, true, 0.0, "B_ij (Warren's liquid: b = 25)",
       "the many-body repulsion B_ij. b = 0 with a < 0 is refused (the fluid collapses). B_ij that differ between "
       "pairs are allowed with a warning: such a force has no potential (Warren 2003)."},
  }};
  static constexpr double kMinA = -std::numeric_limits<double>::infinity();
  static double range(const PairValues& v) { return v.rc; }  // r_d <= r_c (checked below)
  static Params<double> make(const PairValues& v) {
    const double r = range(v);
    // seed 000 Eq. 17; the dissipative and random forces act over r_c.
    return {v.a, v.own[0], v.rd, DpdPairParamsT<double>{0.0, v.gamma, v.sigma, v.rc, v.rc, v.s, r * r}, r * r};
  }
  static LawProblem problem(const PairValues& v) {
    if (v.rd > v.rc)
      return {"rd", "the many-body range r_d must not exceed rc = {value} for {pair} (seed 000 Eq. 17)", v.rc};
    if (v.a < 0 && v.own[0] == 0)
      return {"b",
              "with a = {value} < 0 and no density-dependent repulsion the fluid of {pair} collapses; set b > 0 "
              "(Warren's liquid: a = -40, b = 25)",
              v.a};
    return {};
  }

  template <WeightKind W>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      PairForceT<Real> out = dpd_pair_force<W>(p.dpd, in.r, in.rv, in.xi, in.inv_sqrt_dt);
      const bool apart = in.r > Real(0);
      const Real wc = (apart && in.r < p.dpd.rc) ? Real(1) - in.r / p.dpd.rc : Real(0);
      const Real wd = (apart && in.r < p.rd) ? Real(1) - in.r / p.rd : Real(0);
      const Real rho = in.rho_i + in.rho_j;
      out.fc = p.a * wc + p.b * rho * wd;  // seed 000 Eq. 17
      out.energy = Real(0.5) * p.a * p.dpd.rc * wc * wc + Real(0.25) * p.b * p.rd * rho * wd * wd;
      return out;
    }
  };

  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    with_weight_evaluator<Eval>(table, [](const auto& q) { return q.dpd.s; }, f);
  }
};

}  // namespace mesodpd
