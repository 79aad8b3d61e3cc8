// Single-particle DPD (seed 003 §1, "Single Particle DPD model"; Pan, Pivkin & Karniadakis, Europhys.
// Lett. 84, 10012 (2008)): each particle carries an angular velocity Omega_i and a radius R_i, and the
// pair friction acts on the relative velocity of the two surfaces, not only on its component along the
// line of centres. Written once for every backend, like the other laws.
//
// With r_ij = r_i - r_j, e = r_ij / r and lambda_ij = R_i / (R_i + R_j) (seed 003 §1), the surfaces'
// relative velocity at the contact point is
//   u_ij = v_ij + r_ij x (lambda_ij Omega_i + lambda_ji Omega_j),
// and the force on i due to j is
//   F_ij = a w_C(r) e                                          (conservative, seed 003: -V'(r) e)
//        - w(r) [gamma e e + gamma_perp (1 - e e)] . u_ij     (translational + rotational, F^T + F^R)
//        + sqrt(w(r) / dt) [sigma xi e + sigma_perp (1 - e e) . zeta]   (random),
// with w(r) = (1 - r/r_d)^s along e and w_perp(r) = (1 - r/r_d)^{s_perp} across it, sigma^2 = 2 kT gamma,
// sigma_perp^2 = 2 kT gamma_perp, xi a symmetric unit noise and zeta an antisymmetric unit 3-vector. The
// seed's friction -gamma m Gamma . u with Gamma = A(r) 1 + B(r) e e is this with gamma m A = gamma_perp
// w_perp and gamma m (A + B) = gamma w. The torques are T_i = -lambda_ij r_ij x F_ij and T_j =
// -lambda_ji r_ij x F_ij (seed 003 §1): they sum to -r_ij x F_ij, the pair's change of orbital angular
// momentum with the sign reversed, so orbital plus spin angular momentum is conserved pair by pair.
//
// The random force. The seed writes it with a matrix of Wiener increments dW_ij = dW_ji,
//   (2 kT gamma m)^{1/2} [A~ dW^S + B~ (tr dW / 3) 1 + C~ dW^A] . e,
// symmetric traceless, trace and antisymmetric parts, and the fluctuation-dissipation theorem fixes
// A = (A~^2 + C~^2)/2, B = (A~^2 - C~^2)/2 + (B~^2 - A~^2)/3 (docs/physics.md, "Single-particle DPD",
// derives it): only the covariance 2 kT gamma m Gamma / dt of the random force enters, across e from the
// symmetric and antisymmetric parts, along e from the symmetric and trace parts. The law draws a noise
// with exactly that covariance from four words instead of nine: xi along e (the trace part; the
// pair's DPD noise, so that gamma_perp = 0 is standard DPD bit for bit) and the projection (1 - e e) .
// zeta across it (the antisymmetric part dW^A . e is such a vector, with covariance (1 - e e)/2). For
// Gaussian noise the two forms have the same distribution.
//
// The angular velocities are the law's three scalars (kScalarFields), and what it returns for them is
// their rate dOmega/dt = T / I with I the species' moment of inertia (0 for a frozen particle, which
// never turns): the shared pair loop carries them like eDPD's temperature, ghosts and halo sums included.
#pragma once
#include <array>
#include <cmath>
#include <limits>
#include <string_view>

#include "core/hd.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"
#include "physics/power.hpp"

namespace mesodpd {

template <class Real>
struct SpdpdPairParamsT {
  // The central parts, as DPD's (DpdPairParamsT): gamma is the friction along e.
  Real a = 0, gamma = 0, sigma = 0, rc = 1, rd = 1, s = 2;
  Real rcut2 = 1;
  Real gamma_perp = 0;   // the friction across e (seed 003 §1: gamma m A(r) = gamma_perp w_perp(r))
  Real sigma_perp = 0;   // sqrt(2 kT gamma_perp)
  Real s_perp = 2;       // w_perp = (1 - r/r_d)^{s_perp}
  Real lambda_i = 0.5;   // R_i / (R_i + R_j) for i of this entry's first species
  Real lambda_j = 0.5;
  Real inv_inertia_i = 0, inv_inertia_j = 0;  // 1 / I (0: frozen)

  MESODPD_HD DpdPairParamsT<Real> central() const { return {a, gamma, sigma, rc, rd, s, rcut2}; }

  template <class Other>
  SpdpdPairParamsT<Other> as() const {
    return {Other(a),          Other(gamma),    Other(sigma),    Other(rc),
            Other(rd),         Other(s),        Other(rcut2),    Other(gamma_perp),
            Other(sigma_perp), Other(s_perp),   Other(lambda_i), Other(lambda_j),
            Other(inv_inertia_i), Other(inv_inertia_j)};
  }
};

struct SpdpdLaw {
  template <class Real>
  using Params = SpdpdPairParamsT<Real>;
  static constexpr bool kVelocity = true;
  static constexpr bool kNoise = true;  // xi along e; the three antisymmetric scalar noises across it
  static constexpr bool kDensity = false;
  static constexpr bool kNonCentral = true;
  // The angular velocity's components, and their rates dOmega/dt = T / I.
  static constexpr int kScalars = 3;
  static constexpr std::array<std::string_view, 3> kScalarFields{"omega_x", "omega_y", "omega_z"};
  static constexpr std::array<std::string_view, 3> kScalarRates{"omega_rate_x", "omega_rate_y", "omega_rate_z"};

  static constexpr std::string_view kStyle = "spdpd";
  static constexpr std::string_view kDoc =
      "single-particle DPD (seed 003 §1; Pan, Pivkin & Karniadakis 2008): particles with a radius (species key "
      "`radius`) and an angular velocity, a friction `gamma` along and `gamma_perp` across the line of centres on "
      "the surfaces' relative velocity, torques -lambda_ij r_ij x F_ij; `gamma_perp = 0` is standard DPD. See "
      "docs/physics.md, \"Single-particle DPD\".";
  static constexpr std::array<std::string_view, 6> kShared = kSharedPairKeys;
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr std::array<LawKey, 2> kOwn{{
      {"gamma_perp", 0.0, kInf, true, true, true, 0.0,
       "the friction across the line of centres (say equal to gamma; 0 is standard DPD)",
       "the friction gamma_perp on the part of the surfaces' relative velocity across e_ij (seed 003 §1: "
       "gamma m A(r) = gamma_perp w_perp(r)); it couples the spins to the flow. Its random force has "
       "sigma_perp^2 = 2 kT gamma_perp."},
      {"s_perp", 0.0, 10.0, true, true, false, 0.0, "",
       "the exponent of w_perp = (1 - r/r_d)^{s_perp}; 0 (the default) means the pair's `s`."},
  }};
  // [[species]] keys: the particle's radius (the torque's lever arms) and its moment of inertia.
  static constexpr std::array<LawKey, 2> kSpeciesOwn{{
      {"radius", 0.0, kInf, false, true, true, 0.0, "the particle radius R (say rc / 2 for a solvent particle)",
       "the radius R of the species' particles: lambda_ij = R_i / (R_i + R_j) splits a pair's torque (seed 003 "
       "§1), and the default moment of inertia is that of a solid sphere."},
      {"inertia", 0.0, kInf, true, true, false, 0.0, "",
       "the moment of inertia I of one particle; 0 (the default) means a solid sphere's 2 m R^2 / 5."},
  }};
  static constexpr double kMinA = 0;
  static double range(const PairValues& v) { return v.rc > v.rd ? v.rc : v.rd; }
  static double inertia(double mass, const std::array<double, PairValues::kMaxSpeciesOwn>& own) {
    return own[1] > 0 ? own[1] : 0.4 * mass * own[0] * own[0];
  }
  static Params<double> make(const PairValues& v) {
    Params<double> p;
    p.a = v.a;
    p.gamma = v.gamma;
    p.sigma = v.sigma;
    p.rc = v.rc;
    p.rd = v.rd;
    p.s = v.s;
    const double r = range(v);
    p.rcut2 = r * r;
    p.gamma_perp = v.own[0];
    p.sigma_perp = std::sqrt(2.0 * v.kT * v.own[0]);
    p.s_perp = v.own[1] > 0 ? v.own[1] : v.s;
    p.lambda_i = v.species_i[0] / (v.species_i[0] + v.species_j[0]);
    p.lambda_j = v.species_j[0] / (v.species_i[0] + v.species_j[0]);
    p.inv_inertia_i = v.frozen_i ? 0.0 : 1.0 / inertia(v.mass_i, v.species_i);
    p.inv_inertia_j = v.frozen_j ? 0.0 : 1.0 / inertia(v.mass_j, v.species_j);
    return p;
  }
  static LawProblem problem(const PairValues&) { return {}; }

  // W: the closed form of w(r) = (1 - r/r_d)^s (as DPD's); kSame: s_perp = s for every pair (w_perp = w),
  // else w_perp by pow.
  template <WeightKind W, bool kSame>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      // Along e: DPD's conservative, dissipative and random forces (e . u_ij = e . v_ij).
      PairForceT<Real> out = dpd_pair_force<W>(p.central(), in.r, in.rv, in.xi, in.inv_sqrt_dt);
      const bool apart = in.r > Real(0);
      const Real inv_r = apart ? Real(1) / (apart ? in.r : Real(1)) : Real(0);
      const Real ex = in.d[0] * inv_r, ey = in.d[1] * inv_r, ez = in.d[2] * inv_r;
      const Real om = (apart && in.r < p.rd) ? Real(1) - in.r / p.rd : Real(0);
      Real wd, wr;
      if constexpr (kSame) {
        dpd_weights<W>(om, p.s, wd, wr);
      } else {
        wr = pow_pos(om, Real(0.5) * p.s_perp);
        wd = wr * wr;
      }
      // The surfaces' relative velocity u = v_ij + r_ij x (lambda_ij Omega_i + lambda_ji Omega_j).
      const Real wx = p.lambda_i * in.si[0] + p.lambda_j * in.sj[0];
      const Real wy = p.lambda_i * in.si[1] + p.lambda_j * in.sj[1];
      const Real wz = p.lambda_i * in.si[2] + p.lambda_j * in.sj[2];
      const Real ux = in.dv[0] + (in.d[1] * wz - in.d[2] * wy);
      const Real uy = in.dv[1] + (in.d[2] * wx - in.d[0] * wz);
      const Real uz = in.dv[2] + (in.d[0] * wy - in.d[1] * wx);
      // Across e: -gamma_perp w_perp (1 - e e) . u + sigma_perp sqrt(w_perp / dt) (1 - e e) . zeta.
      const Real fu = -p.gamma_perp * wd, fz = p.sigma_perp * wr * in.inv_sqrt_dt;
      const Real gx = fu * ux + fz * in.xs[0], gy = fu * uy + fz * in.xs[1], gz = fu * uz + fz * in.xs[2];
      const Real ge = gx * ex + gy * ey + gz * ez;
      out.fn[0] = gx - ge * ex;
      out.fn[1] = gy - ge * ey;
      out.fn[2] = gz - ge * ez;
      // Torques -lambda r_ij x F_ij (the central part has no moment), as rates T / I.
      const Real tx = in.d[1] * out.fn[2] - in.d[2] * out.fn[1];
      const Real ty = in.d[2] * out.fn[0] - in.d[0] * out.fn[2];
      const Real tz = in.d[0] * out.fn[1] - in.d[1] * out.fn[0];
      const Real ci = -p.lambda_i * p.inv_inertia_i, cj = -p.lambda_j * p.inv_inertia_j;
      out.qi[0] = ci * tx;
      out.qi[1] = ci * ty;
      out.qi[2] = ci * tz;
      out.qj[0] = cj * tx;
      out.qj[1] = cj * ty;
      out.qj[2] = cj * tz;
      return out;
    }
  };

  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    bool same = true;
    for (const auto& q : table) same = same && q.s_perp == q.s;
    if (same) {
      with_weight_evaluator<EvalSame>(table, [](const auto& q) { return q.s; }, f);
    } else {
      with_weight_evaluator<EvalOwn>(table, [](const auto& q) { return q.s; }, f);
    }
  }
  template <WeightKind W>
  using EvalSame = Eval<W, true>;
  template <WeightKind W>
  using EvalOwn = Eval<W, false>;
};

}  // namespace mesodpd
