// Energy-conserving DPD (eDPD; seed 003 §3 "Energy-conserving DPD", after Ripoll & Español 1998 and Li,
// Tang, Lei, Caswell & Karniadakis, J. Comput. Phys. 265, 113 (2014)): every particle carries an internal
// temperature T_i, the random force of a pair follows from the two temperatures and the pair exchanges
// heat by conduction, viscous heating and a fluctuating flux. Written once for every backend, without
// branches (selects only), like the other laws.
//
// The force on i due to j (seed 003 §3):
//   F^C = a_ij (Tbar / kT)^{a_t} w_C e,  F^D = -gamma w_D (e.v) e,  F^R = sigma_ij w_R zeta dt^-1/2 e,
//   sigma_ij^2 = 4 gamma T_i T_j / (T_i + T_j),  Tbar = (T_i + T_j) / 2,  w_D = w_R^2 = (1 - r/r_d)^{s(T)}.
// The heat that flows into i (energy per time; j gets the conduction and random terms with the opposite
// sign and the same viscous share):
//   q^cond = k_ij w_CT (1/T_i - 1/T_j),  k_ij = C_v,i C_v,j kappa(T) Tbar^2
//   q^R    = sqrt(2 k_ij) w_RT zeta^e dt^-1/2,  zeta^e_ij = -zeta^e_ji
//   q^visc = (1/2) [w_D (gamma (e.v)^2 - sigma^2 (1/m_i + 1/m_j)/2) - sigma w_R (e.v) zeta dt^-1/2]
// (all of it to the mobile particle of a wall-fluid pair, where the wall's 1/m is 0)
// with w_CT = w_RT^2 = (1 - r/r_cT)^{s_T}. For one species (C_v,i = C_v,j = C_v, m = 1) k_ij is the seed's
// C_v^2 kappa (T_i + T_j)^2 / 4. q^visc is the mechanical energy the pair's dissipative and random forces
// take from the relative motion (with the Ito term sigma^2 w_D / m that the random kicks add on average),
// shared half and half, so that kinetic plus internal energy is conserved. The seed prints the factor as
// 1/(2 C_v) inside C_v dT_i = ... dt, which conserves energy only for C_v = 1 (docs/physics.md, "eDPD").
// The law returns the temperature rates dT_i/dt = q_i / C_v,i and dT_j/dt = q_j / C_v,j (PairForceT::qi,
// qj), numbers of order T/dt whatever C_v is, so that they fit the fixed-point sums.
//
// The temperature-dependent exponent and conductivity are LAMMPS's (pair_style edpd) polynomials in
// theta = Tbar/kT - 1: s(T) = s (1 + sum_k s_tk theta^k), kappa(T) = kappa (1 + sum_k kappa_tk theta^k),
// k = 1..4; s(T) is kept at 0.01 or more so that a hot pair cannot reach a non-positive exponent.
#pragma once
#include <cmath>

#include "core/hd.hpp"
#include "physics/dpd_pair.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"
#include "physics/power.hpp"

namespace mesodpd {

template <class Real>
struct EdpdPairParamsT {
  Real a = 0;          // a_ij
  Real a_t = 0;        // exponent of the conservative amplitude's temperature factor (Tbar/kT)^{a_t}
  Real gamma = 0;      // gamma_ij
  Real rc = 1;         // conservative cutoff
  Real rd = 1;         // dissipative and random cutoff
  Real s = 2;          // weight exponent at Tbar = kT
  Real s_t[4] = {0, 0, 0, 0};      // s(T) coefficients
  Real kappa = 0;      // kappa_ij of k_ij
  Real kappa_t[4] = {0, 0, 0, 0};  // kappa(T) coefficients
  Real rct = 1;        // heat cutoff r_cT
  Real st = 2;         // heat weight exponent s_T
  Real cv_i = 1, cv_j = 1;         // heat capacities of the pair's two species (this entry's order)
  Real inv_cv_i = 1, inv_cv_j = 1;
  Real ito = 1;        // (1/m_i + 1/m_j) / 2: the Ito term's inverse mass (a frozen particle's is 0)
  Real visc_i = 0.5, visc_j = 0.5;  // shares of the viscous heat: 1/2 each, all of it to the mobile one
                                    // of a wall-fluid pair
  Real inv_kt = 1;     // 1 / kT
  Real rcut2 = 1;      // max(rc, rd, rct)^2

  template <class Other>
  EdpdPairParamsT<Other> as() const {
    EdpdPairParamsT<Other> o;
    o.a = Other(a);
    o.a_t = Other(a_t);
    o.gamma = Other(gamma);
    o.rc = Other(rc);
    o.rd = Other(rd);
    o.s = Other(s);
    o.kappa = Other(kappa);
    for (int k = 0; k < 4; ++k) {
      o.s_t[k] = Other(s_t[k]);
      o.kappa_t[k] = Other(kappa_t[k]);
    }
    o.rct = Other(rct);
    o.st = Other(st);
    o.cv_i = Other(cv_i);
    o.cv_j = Other(cv_j);
    o.inv_cv_i = Other(inv_cv_i);
    o.inv_cv_j = Other(inv_cv_j);
    o.ito = Other(ito);
    o.visc_i = Other(visc_i);
    o.visc_j = Other(visc_j);
    o.inv_kt = Other(inv_kt);
    o.rcut2 = Other(rcut2);
    return o;
  }
};

// 1 + c1 t + c2 t^2 + c3 t^3 + c4 t^4 (Horner).
template <class Real>
MESODPD_HD Real edpd_poly(const Real (&c)[4], Real t) {
  return Real(1) + t * (c[0] + t * (c[1] + t * (c[2] + t * c[3])));
}

struct EdpdLaw {
  template <class Real>
  using Params = EdpdPairParamsT<Real>;
  static constexpr bool kVelocity = true;
  static constexpr bool kNoise = true;
  static constexpr bool kDensity = false;
  // One scalar, the temperature: reads T_i, T_j and zeta^e; returns dT_i/dt, dT_j/dt.
  static constexpr int kScalars = 1;
  static constexpr std::array<std::string_view, 1> kScalarFields{"temp"};
  static constexpr std::array<std::string_view, 1> kScalarRates{"temp_rate"};

  static constexpr std::string_view kStyle = "edpd";
  static constexpr std::string_view kDoc =
      "energy-conserving DPD (seed 003 §3): per-particle temperatures T_i (species keys `cv`, `temperature`), "
      "sigma_ij^2 = 4 gamma T_i T_j / (T_i + T_j), heat conduction, viscous heating and a fluctuating heat flux "
      "over `rct` with exponent `st`; see docs/physics.md, \"eDPD\".";
  static constexpr std::array<std::string_view, 5> kShared{"a", "gamma", "rc", "rd", "s"};
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr std::array<LawKey, 12> kOwn{{
      {"kappa", 0.0, kInf, true, true, true, 0.0, "the heat conduction coefficient kappa_ij (LAMMPS's example: 1.42e-5 with cv = 1e5)",
       "the heat conduction coefficient kappa_ij of k_ij = C_v,i C_v,j kappa_ij Tbar^2 (seed 003 §3; the thermal "
       "diffusivity of one species is D_T = 2 pi n C_v kappa r_cT^5 / 315 for s_T = 2, docs/physics.md)."},
      {"rct", 0.0, 10.0, true, true, false, 0.0, "",
       "the heat cutoff r_cT of w_CT = w_RT^2 = (1 - r/r_cT)^{s_T}; 0 (the default) means the pair's rc."},
      {"st", 0.0, 10.0, false, true, false, 2.0, "", "the heat weight exponent s_T."},
      {"a_t", 0.0, 10.0, true, true, false, 0.0, "",
       "the conservative amplitude's temperature exponent: a_ij (Tbar/kT)^{a_t}; 1 makes the pressure scale with "
       "the temperature (Li et al. 2014), 0 keeps a_ij fixed."},
      {"s_t1", -kInf, kInf, true, true, false, 0.0, "", "s(T) = s (1 + s_t1 theta + ... + s_t4 theta^4), theta = Tbar/kT - 1."},
      {"s_t2", -kInf, kInf, true, true, false, 0.0, "", "see `s_t1`."},
      {"s_t3", -kInf, kInf, true, true, false, 0.0, "", "see `s_t1`."},
      {"s_t4", -kInf, kInf, true, true, false, 0.0, "", "see `s_t1`."},
      {"kappa_t1", -kInf, kInf, true, true, false, 0.0, "",
       "kappa(T) = kappa (1 + kappa_t1 theta + ... + kappa_t4 theta^4), theta = Tbar/kT - 1 (kept >= 0)."},
      {"kappa_t2", -kInf, kInf, true, true, false, 0.0, "", "see `kappa_t1`."},
      {"kappa_t3", -kInf, kInf, true, true, false, 0.0, "", "see `kappa_t1`."},
      {"kappa_t4", -kInf, kInf, true, true, false, 0.0, "", "see `kappa_t1`."},
  }};
  // [[species]] keys: the heat capacity and the starting temperature of the species' particles.
  static constexpr std::array<LawKey, 3> kSpeciesOwn{{
      {"cv", 0.0, kInf, false, true, true, 0.0, "the heat capacity C_v per particle (LAMMPS's eDPD example: cv = 1e5)",
       "the heat capacity C_v per particle of this species (in units of k_B): U_i = C_v T_i."},
      {"temperature", 0.0, kInf, true, true, false, 0.0, "",
       "the starting internal temperature T_i of the species' particles; 0 (the default) means `system.kT`. For a "
       "frozen (wall) species: the temperature the wall is held at, through which it exchanges heat with the fluid; "
       "a wall species without it is adiabatic (no conduction)."},
      {"heat_source", -kInf, kInf, true, true, false, 0.0, "",
       "a constant heat source per particle of this species (energy per unit time; negative: a sink), added to "
       "C_v dT_i/dt of its mobile particles (engine/install_edpd.cpp)."},
  }};
  static constexpr double kMinA = 0;
  static double heat_range(const PairValues& v) { return v.own[1] > 0 ? v.own[1] : v.rc; }
  static double range(const PairValues& v) {
    const double r = v.rc > v.rd ? v.rc : v.rd;
    return r > heat_range(v) ? r : heat_range(v);
  }
  static Params<double> make(const PairValues& v) {
    Params<double> p;
    p.a = v.a;
    p.a_t = v.own[3];
    p.gamma = v.gamma;
    p.rc = v.rc;
    p.rd = v.rd;
    p.s = v.s;
    p.kappa = v.own[0];
    for (int k = 0; k < 4; ++k) {
      p.s_t[k] = v.own[4 + k];
      p.kappa_t[k] = v.own[8 + k];
    }
    p.rct = heat_range(v);
    p.st = v.own[2];
    p.cv_i = v.species_i[0];
    p.cv_j = v.species_j[0];
    p.inv_cv_i = 1.0 / p.cv_i;
    p.inv_cv_j = 1.0 / p.cv_j;
    // Walls (frozen species): infinite mass, so the random kicks' mean energy is the mobile particle's
    // alone; the pair's viscous heat all goes to the mobile particle (the wall has no heat budget); and
    // a wall exchanges heat by conduction only if its species sets `temperature` (a wall held at it),
    // else it is adiabatic.
    p.ito = 0.5 * ((v.frozen_i ? 0.0 : 1.0 / v.mass_i) + (v.frozen_j ? 0.0 : 1.0 / v.mass_j));
    p.visc_i = v.frozen_j ? 1.0 : (v.frozen_i ? 0.0 : 0.5);
    p.visc_j = v.frozen_i ? 1.0 : (v.frozen_j ? 0.0 : 0.5);
    if ((v.frozen_i && !(v.species_i[1] > 0)) || (v.frozen_j && !(v.species_j[1] > 0))) p.kappa = 0;
    p.inv_kt = 1.0 / v.kT;
    const double r = range(v);
    p.rcut2 = r * r;
    return p;
  }
  static LawProblem problem(const PairValues&) { return {}; }

  // kPowers: some pair has a_t other than 0 or 1 or s_T other than 2, which take a power per pair; else
  // those factors are plain arithmetic. (Both are choices per table, not per pair: a select on a loop
  // constant inside the law keeps the compiler from vectorising the pair loop.)
  template <WeightKind W, bool kPowers = false>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      const bool apart = in.r > Real(0);
      const Real ti = in.si[0], tj = in.sj[0];
      const Real tbar = Real(0.5) * (ti + tj);
      const Real theta = tbar * p.inv_kt - Real(1);
      // Forces (seed 003 §3).
      const Real wc = (apart && in.r < p.rc) ? Real(1) - in.r / p.rc : Real(0);
      const Real om = (apart && in.r < p.rd) ? Real(1) - in.r / p.rd : Real(0);
      Real wd, wr;
      if constexpr (W == WeightKind::General) {
        Real s = p.s * edpd_poly(p.s_t, theta);
        s = s > Real(0.01) ? s : Real(0.01);
        wr = pow_pos(om, Real(0.5) * s);  // one power (physics/power.hpp): w_D = w_R^2
        wd = wr * wr;
      } else {
        dpd_weights<W>(om, p.s, wd, wr);
      }
      const Real sigma = std::sqrt(Real(4) * p.gamma * ti * tj / (ti + tj));
      // (Tbar/kT)^{a_t}: a_t = 1 (Li et al. 2014's choice, LAMMPS's example) and 0 without a power, as
      // (1 - a_t) + a_t x, which is exactly 1 or x.
      const Real x = tbar * p.inv_kt;
      Real amp;
      if constexpr (kPowers) amp = p.a * pow_pos(x, p.a_t);
      else amp = p.a * ((Real(1) - p.a_t) + p.a_t * x);
      PairForceT<Real> out;
      out.fc = amp * wc;
      out.energy = Real(0.5) * amp * p.rc * wc * wc;
      out.fd = -p.gamma * wd * in.rv;
      out.fr = sigma * wr * in.xi * in.inv_sqrt_dt;
      // Heat (energy per time into i).
      const Real omt = (apart && in.r < p.rct) ? Real(1) - in.r / p.rct : Real(0);
      Real wct;
      if constexpr (kPowers) wct = pow_pos(omt, p.st);
      else wct = omt * omt;
      const Real wrt = std::sqrt(wct);
      Real kap = p.kappa * edpd_poly(p.kappa_t, theta);
      kap = kap > Real(0) ? kap : Real(0);
      const Real kij = p.cv_i * p.cv_j * kap * tbar * tbar;
      const Real q_anti = kij * wct * (Real(1) / ti - Real(1) / tj) + std::sqrt(Real(2) * kij) * wrt * in.xs[0] * in.inv_sqrt_dt;
      const Real work = wd * (p.gamma * in.rv * in.rv - sigma * sigma * p.ito) - out.fr * in.rv;
      out.qi[0] = (q_anti + p.visc_i * work) * p.inv_cv_i;
      out.qj[0] = (p.visc_j * work - q_anti) * p.inv_cv_j;
      return out;
    }
  };

  // The closed-form weights when every pair has the same s and no s(T); the general pow form otherwise.
  // A temperature exponent a_t other than 0 and 1 or a heat exponent s_T other than 2 takes the
  // evaluator with every power general.
  template <WeightKind W>
  using EvalPlain = Eval<W, false>;
  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    bool varies = false, powers = false;
    for (const auto& q : table) {
      for (int k = 0; k < 4; ++k) varies = varies || q.s_t[k] != 0;
      powers = powers || !(q.a_t == 0 || q.a_t == 1) || q.st != 2;
    }
    if (powers) return f(Eval<WeightKind::General, true>{});
    if (varies) return f(Eval<WeightKind::General>{});
    with_weight_evaluator<EvalPlain>(table, [](const auto& q) { return q.s; }, f);
  }
};

}  // namespace mesodpd
