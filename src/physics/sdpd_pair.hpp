// Smoothed DPD (SDPD; seed 003 §4 "Equations of Smoothed DPD", after Español & Revenga, Phys. Rev. E 67,
// 026705 (2003)), isothermal form: the fluctuating Navier-Stokes equations discretised the SPH way, with
// the equation of state, the shear and bulk viscosities and the temperature as inputs. Written once for
// every backend, like the other laws.
//
// Each particle's number density d_i = W(0) + sum_j W(r_ij) comes from the density pass (the pass sums
// the neighbours, the law adds the self term W(0)); its pressure is P_i = P(m_i d_i) of the mass density.
// With F(r) >= 0 defined by grad W(r) = -r F(r), the force on i due to j is (seed 003 §4)
//   F^C = [P_i / d_i^2 + P_j / d_j^2] F(r) r_ij,
//   F^D = -(F / (d_i d_j)) [alpha v_ij + beta e_ij (e_ij . v_ij)],  alpha = 5 eta / 3 - zeta,
//                                                                  beta = 5 (zeta + eta / 3),
//   F^R = sqrt(F / (d_i d_j)) [A dW^S_ij + B (tr dW_ij / 3) 1] . e_ij / dt,
//   A = sqrt(4 kT alpha),  B = sqrt(2 kT (3 beta - alpha)),
// with dW_ij = dW_ji a matrix of independent Wiener increments and dW^S its symmetric traceless part.
// alpha and beta are the ones whose continuum limit is eta lap v + (zeta + eta/3) grad div v (the
// second moments of the kernel: sum_j F_ij / d_j r_ij r_ij -> 1); the seed prints the e e term's
// coefficient as a_ij / 3 + b_ij with a_ij = alpha F / (d_i d_j), so its b_ij is beta - alpha / 3
// (docs/physics.md, "Smoothed DPD"). A and B follow from the fluctuation-dissipation theorem for that
// friction: the noise's covariance is 2 kT (alpha 1 + beta e e) F / (d_i d_j) / dt, since the symmetric
// traceless part of a unit Wiener matrix gives (1/2) 1 + (1/6) e e and the trace part (1/3) e e.
//
// The equation of state is P(rho) = (c^2 rho_0 / n) [(rho / rho_0)^n - 1] + p_b: n = 1 is the linear
// law c^2 (rho - rho_0) + p_b, n = 7 Tait's for water; dP/drho = c^2 at rho_0 either way.
#pragma once
#include <array>
#include <cmath>
#include <type_traits>

#include "core/hd.hpp"
#include "physics/power.hpp"
#include "physics/density_kernel.hpp"
#include "physics/law_keys.hpp"
#include "physics/pair_force.hpp"

namespace mesodpd {

template <class Real>
struct SdpdPairParamsT {
  Real h = 1;          // kernel cutoff
  Real inv_h = 1;
  Real fnorm = 0;      // F(r) = fnorm (1 - r/h)^k: Lucy k = 2, Wendland k = 3
  Real w0 = 0;         // W(0), the self term of d_i
  Real mass_i = 1, mass_j = 1;  // of the pair's species in this entry's order
  Real rho0 = 1;       // reference mass density
  Real inv_rho0 = 1;
  Real p0 = 1;         // c^2 rho_0 / n
  Real pb = 0;         // background pressure
  Real eos_n = 1;      // exponent n
  Real alpha = 0;      // 5 eta / 3 - zeta
  Real beta = 0;       // 5 (zeta + eta / 3)
  Real amp_a = 0;      // sqrt(4 kT alpha)
  Real amp_b = 0;      // sqrt(2 kT (3 beta - alpha))
  Real kernel = 0;     // 0 Lucy, 1 Wendland (chooses the evaluator)
  Real rcut2 = 1;      // h^2

  template <class Other>
  SdpdPairParamsT<Other> as() const {
    return {Other(h),    Other(inv_h), Other(fnorm), Other(w0),     Other(mass_i), Other(mass_j),
            Other(rho0), Other(inv_rho0), Other(p0), Other(pb),     Other(eos_n),  Other(alpha),
            Other(beta), Other(amp_a), Other(amp_b), Other(kernel), Other(rcut2)};
  }
};

// The equation of state with exponent N known at compile time (1, 7) or read from the parameters (0).
template <int N, class Real>
MESODPD_HD Real sdpd_pressure(const SdpdPairParamsT<Real>& p, Real rho) {
  const Real x = rho * p.inv_rho0;
  Real xn;
  if constexpr (N == 1) {
    xn = x;
  } else if constexpr (N == 7) {
    const Real x2 = x * x, x3 = x2 * x;
    xn = x3 * x3 * x;
  } else {
    xn = pow_pos(x, p.eos_n);
  }
  return p.p0 * (xn - Real(1)) + p.pb;
}

struct SdpdLaw {
  template <class Real>
  using Params = SdpdPairParamsT<Real>;
  static constexpr bool kVelocity = true;
  static constexpr bool kNoise = false;  // its noise is the matrix of kNoiseWords
  static constexpr bool kDensity = true;
  static constexpr bool kNonCentral = true;
  static constexpr int kNoiseWords = 6;  // the symmetric part of a 3 x 3 Wiener matrix
  static constexpr DensityKernelKind kDefaultKernel = DensityKernelKind::Lucy;
  // Warren's kernel is refused: its gradient does not vanish at r = 0, so F(r) = -W'(r)/r diverges.
  static constexpr std::array<DensityKernelKind, 2> kKernels{DensityKernelKind::Lucy, DensityKernelKind::Wendland};

  static constexpr std::string_view kStyle = "sdpd";
  static constexpr std::string_view kDoc =
      "isothermal smoothed DPD (seed 003 §4; Español & Revenga 2003): an SPH discretisation of the fluctuating "
      "Navier-Stokes equations with the shear viscosity `eta`, the bulk viscosity `zeta`, the equation of state "
      "P = (c^2 rho_0 / n)[(rho/rho_0)^n - 1] + p_b (`c`, `rho0`, `eos_exponent` n, `p_b`) and the temperature "
      "`system.kT` as inputs, over the kernel cutoff `rc` with `kernel` (Lucy by default, or Wendland C2); see "
      "docs/physics.md, \"Smoothed DPD\".";
  static constexpr std::array<std::string_view, 1> kShared{"rc"};
  static constexpr std::array<std::string_view, 0> kRequired{};
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  static constexpr double kPi = 3.14159265358979323846;
  static constexpr std::array<LawKey, 7> kOwn{{
      {"eta", 0.0, kInf, true, true, true, 0.0, "the shear viscosity eta (say 1)",
       "the shear viscosity eta (dynamic, mass / (length time)) that the SDPD fluid has by construction."},
      {"zeta", 0.0, kInf, true, true, false, 0.0, "",
       "the bulk viscosity zeta; at most 5 eta / 3 (the shear friction 5 eta / 3 - zeta must not be negative)."},
      {"c", 0.0, kInf, false, true, true, 0.0, "the sound speed c (say 10 times the fastest flow)",
       "the sound speed c of the equation of state at rho_0: dP/drho = c^2 there."},
      {"rho0", 0.0, kInf, false, true, true, 0.0,
       "the reference mass density rho_0 (usually the species' mass times its number density)",
       "the reference mass density rho_0 of the equation of state (mass / volume)."},
      {"eos_exponent", 1.0, 10.0, true, true, false, 1.0, "",
       "the exponent n of the equation of state: 1 (the default) is the linear law P = c^2 (rho - rho_0) + p_b, 7 "
       "Tait's law for water."},
      {"p_b", -kInf, kInf, true, true, false, 0.0, "",
       "the background pressure p_b added to the equation of state. A positive p_b orders the particles, which "
       "brings the measured sound speed to c, but at low kT it also makes the fluid elastic and raises its shear "
       "viscosity (docs/validation.md §12)."},
      {"interact", 0.0, 1.0, true, true, false, 1.0, "",
       "1 (the default): the pair interacts; 0: the two species do not see each other, neither in the density "
       "nor in any force (e.g. membrane vertices that meet the solvent only through the bounce-back); no other "
       "value."},
  }};
  // A pair with interact = 0 (kOwn[6]) takes no part: its density range is negative (no r is inside it, and
  // the kernels stay finite) and its F(r) is zero, which zeroes every force term.
  static bool excluded(const PairValues& v) { return v.own[6] == 0.0; }
  static constexpr double kMinA = 0;
  static double range(const PairValues& v) { return v.rc; }
  static double density_range(const PairValues& v) { return excluded(v) ? -1.0 : v.rc; }
  static Params<double> make(const PairValues& v) {
    Params<double> p;
    p.h = v.rc;
    p.inv_h = 1.0 / v.rc;
    const double h3 = v.rc * v.rc * v.rc, h5 = h3 * v.rc * v.rc;
    // grad W = -r F: Lucy's W' = -12 C q (1 - q)^2 / h^4 gives F = 12 C (1 - q)^2 / h^5 (C = 105/(16 pi));
    // Wendland's W' = -20 C q (1 - q)^3 / h^4 gives F = 20 C (1 - q)^3 / h^5 (C = 21/(2 pi)).
    const bool wendland = v.kernel == DensityKernelKind::Wendland;
    const double c_norm = wendland ? 21.0 / (2.0 * kPi) : 105.0 / (16.0 * kPi);
    p.fnorm = (wendland ? 20.0 : 12.0) * c_norm / h5;
    p.w0 = c_norm / h3;
    p.kernel = wendland ? 1.0 : 0.0;
    p.mass_i = v.mass_i;
    p.mass_j = v.mass_j;
    const double eta = v.own[0], zeta = v.own[1], c = v.own[2];
    p.rho0 = v.own[3];
    p.inv_rho0 = 1.0 / p.rho0;
    p.eos_n = v.own[4];
    p.p0 = c * c * p.rho0 / p.eos_n;
    p.pb = v.own[5];
    p.alpha = 5.0 * eta / 3.0 - zeta;
    p.beta = 5.0 * (zeta + eta / 3.0);
    p.amp_a = std::sqrt(4.0 * v.kT * (p.alpha > 0 ? p.alpha : 0.0));
    p.amp_b = std::sqrt(2.0 * v.kT * (3.0 * p.beta - p.alpha));
    p.rcut2 = v.rc * v.rc;
    if (excluded(v)) {
      p.fnorm = 0;
      p.rcut2 = 0;
    }
    return p;
  }
  // The time-step limits of SPH (Morris, Fox & Zhu, J. Comput. Phys. 136, 214 (1997)): the sound
  // crossing of a quarter kernel, dt <= 0.25 h / c, and viscous diffusion, dt <= C h^2 / nu with
  // nu = eta / rho_0. Morris's C = 0.125 is for a smoothing length of half our cutoff h; measured here
  // (docs/validation.md §12, kT = 0.0178, c = 4, n = 3, h = 1.5), a Wendland fluid keeps its temperature
  // up to C = 0.058 and heats (k_BT x 1.7-4) from C = 0.067, Lucy's holds at 0.067 and blows up at 0.089:
  // C = 0.05. `mesodpd check` prints both.
  static double cfl_limit(const PairValues& v) { return 0.25 * v.rc / v.own[2]; }
  static double viscous_limit(const PairValues& v) {
    return v.own[0] > 0 ? 0.05 * v.rc * v.rc * v.own[3] / v.own[0] : std::numeric_limits<double>::infinity();
  }
  // Neighbours inside the kernel: n 4 pi h^3 / 3.
  static double neighbours(const PairValues& v) { return v.number_density * 4.0 * kPi / 3.0 * v.rc * v.rc * v.rc; }
  static LawProblem problem(const PairValues& v) {
    if (v.own[6] != 0.0 && v.own[6] != 1.0)
      return {"interact", "interact must be 1 (the pair interacts) or 0 (it does not) for {pair}, not {value}", v.own[6]};
    if (excluded(v)) return {};
    if (v.own[1] > 5.0 * v.own[0] / 3.0)
      return {"zeta",
              "the bulk viscosity may not exceed 5 eta / 3 = {value} for {pair}: the shear friction 5 eta / 3 - zeta "
              "would be negative (docs/physics.md, \"Smoothed DPD\")",
              5.0 * v.own[0] / 3.0};
    if (v.number_density > 0 && v.rc < std::cbrt(1.0 / v.number_density))
      return {"rc",
              "the kernel cutoff is below the particle spacing n^(-1/3) = {value} for {pair}: a particle would have "
              "almost no neighbours inside its kernel (use rc of 2-3 spacings)",
              std::cbrt(1.0 / v.number_density)};
    if (v.dt > cfl_limit(v))
      return {"c",
              "integrator.dt exceeds the sound (CFL) limit 0.25 rc / c = {value} for {pair}: lower integrator.dt or "
              "the sound speed c",
              cfl_limit(v)};
    if (v.dt > viscous_limit(v))
      return {"eta",
              "integrator.dt exceeds the viscous limit 0.05 rc^2 rho0 / eta = {value} for {pair}: lower "
              "integrator.dt or eta",
              viscous_limit(v)};
    return {};
  }
  // eta over rho_0 c rc: below about 0.05 the pressure forces' numerical viscosity (~0.005 rho_0 c rc
  // at 42 neighbours) adds visibly to the input (docs/validation.md §12).
  static double viscosity_ratio(const PairValues& v) { return v.own[0] / (v.own[3] * v.own[2] * v.rc); }
  static LawProblem warning(const PairValues& v) {
    if (excluded(v)) return {};
    if (v.number_density > 0 && neighbours(v) < 20)
      return {"rc",
              "{pair} has about {value} neighbours inside the kernel cutoff (n 4 pi rc^3 / 3); SPH estimates of the "
              "density and the viscous terms want 20 or more (docs/physics.md, \"Smoothed DPD\")",
              neighbours(v)};
    if (viscosity_ratio(v) < 0.05)
      return {"eta",
              "{pair} has eta = {value} rho0 c rc, below the 0.05 under which the measured viscosity exceeds the input "
              "(the pressure forces add about 0.005 rho0 c rc: +20% or more here; docs/validation.md §12); raise eta "
              "against rho0 c rc, or lower c as far as the Mach number allows",
              viscosity_ratio(v)};
    return {};
  }

  template <int Kernel, int N>
  struct Eval {
    template <class Real>
    MESODPD_HD_FORCE PairForceT<Real> operator()(const Params<Real>& p, const PairInput<Real>& in) const {
      const bool apart = in.r > Real(0);
      const Real om = (apart && in.r < p.h) ? Real(1) - in.r * p.inv_h : Real(0);
      const Real f = Kernel == 1 ? p.fnorm * om * om * om : p.fnorm * om * om;  // F(r), 0 beyond h
      const Real di = in.rho_i + p.w0, dj = in.rho_j + p.w0;
      const Real inv_di = Real(1) / di, inv_dj = Real(1) / dj;
      const Real pi = sdpd_pressure<N>(p, p.mass_i * di), pj = sdpd_pressure<N>(p, p.mass_j * dj);
      const Real g = f * inv_di * inv_dj;  // F / (d_i d_j)
      PairForceT<Real> out;
      out.fc = (pi * inv_di * inv_di + pj * inv_dj * inv_dj) * f * in.r;
      out.fd = -p.beta * g * in.rv;
      // The random term: A S e + (B - A)(tr / 3) e with S the symmetric part of the unit matrix
      // (diagonal xm0..2, off-diagonal xm3..5 / sqrt 2), so that A (S - tr/3) e is A dW^S e.
      const Real inv_r = apart ? Real(1) / (apart ? in.r : Real(1)) : Real(0);
      const Real ex = in.d[0] * inv_r, ey = in.d[1] * inv_r, ez = in.d[2] * inv_r;
      constexpr Real kHalfSqrt2 = Real(0.70710678118654752440);
      const Real sxy = in.xm[3] * kHalfSqrt2, sxz = in.xm[4] * kHalfSqrt2, syz = in.xm[5] * kHalfSqrt2;
      const Real amp = std::sqrt(g) * in.inv_sqrt_dt;
      const Real ra = p.amp_a * amp;
      const Real tr3 = (in.xm[0] + in.xm[1] + in.xm[2]) * Real(1.0 / 3.0);
      out.fr = (p.amp_b - p.amp_a) * amp * tr3;
      const Real ga = -p.alpha * g;
      out.fn[0] = ga * in.dv[0] + ra * (in.xm[0] * ex + sxy * ey + sxz * ez);
      out.fn[1] = ga * in.dv[1] + ra * (sxy * ex + in.xm[1] * ey + syz * ez);
      out.fn[2] = ga * in.dv[2] + ra * (sxz * ex + syz * ey + in.xm[2] * ez);
      return out;
    }
  };

  // The kernel's and the equation of state's closed forms when every pair shares them.
  template <class Table, class F>
  static void with_evaluator(const Table& table, F&& f) {
    const bool wendland = !table.empty() && table.front().kernel == 1;
    bool n1 = true, n7 = true;
    for (const auto& q : table) {
      n1 = n1 && q.eos_n == 1;
      n7 = n7 && q.eos_n == 7;
    }
    const auto with_eos = [&](auto kernel) {
      constexpr int K = decltype(kernel)::value;
      if (n1) return f(Eval<K, 1>{});
      if (n7) return f(Eval<K, 7>{});
      return f(Eval<K, 0>{});
    };
    if (wendland) return with_eos(std::integral_constant<int, 1>{});
    with_eos(std::integral_constant<int, 0>{});
  }
};

}  // namespace mesodpd
