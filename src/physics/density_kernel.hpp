// Weight functions for a local-density pair pass, rho_i = sum_{j != i} w_rho(r_ij): the first pass of
// many-body DPD (seed 000 Eq. 17; seed 003 "Many-body DPD") and of other multi-pass models. Both
// kernels are normalised so that their integral over space is 1.
#pragma once
#include "core/hd.hpp"

namespace mesodpd {

enum class DensityKernelKind { Warren, Lucy, Wendland };

template <class Real>
struct DensityParamsT {
  Real rd = 1;     // kernel range r_d
  Real rcut2 = 1;  // r_d^2

  template <class Other>
  DensityParamsT<Other> as() const {
    return {Other(rd), Other(rcut2)};
  }
};

// Warren's kernel w_rho = 15 / (2 pi r_d^3) (1 - r/r_d)^2 (Warren, Phys. Rev. E 68, 066702 (2003),
// cited by seed 003).
struct WarrenDensityKernel {
  template <class Real>
  MESODPD_HD Real operator()(const DensityParamsT<Real>& p, Real r) const {
    constexpr Real kNorm = Real(15.0 / (2.0 * 3.14159265358979323846));
    const Real om = r < p.rd ? Real(1) - r / p.rd : Real(0);
    return kNorm / (p.rd * p.rd * p.rd) * om * om;
  }
};

// Lucy's kernel w_rho = 105 / (16 pi r_d^3) (1 + 3 r/r_d) (1 - r/r_d)^3, the one LAMMPS's
// `mdpd/rhosum` uses.
struct LucyDensityKernel {
  template <class Real>
  MESODPD_HD Real operator()(const DensityParamsT<Real>& p, Real r) const {
    constexpr Real kNorm = Real(105.0 / (16.0 * 3.14159265358979323846));
    const Real q = r / p.rd;
    const Real om = r < p.rd ? Real(1) - q : Real(0);
    return kNorm / (p.rd * p.rd * p.rd) * (Real(1) + Real(3) * q) * om * om * om;
  }
};

// Wendland's C2 kernel in three dimensions, w_rho = 21 / (2 pi r_d^3) (1 - r/r_d)^4 (1 + 4 r/r_d)
// (Wendland, Adv. Comput. Math. 4, 389 (1995)): smooth to the second derivative, the usual choice of
// smoothed DPD and SPH codes that want no pairing instability.
struct WendlandDensityKernel {
  template <class Real>
  MESODPD_HD Real operator()(const DensityParamsT<Real>& p, Real r) const {
    constexpr Real kNorm = Real(21.0 / (2.0 * 3.14159265358979323846));
    const Real q = r / p.rd;
    const Real om = r < p.rd ? Real(1) - q : Real(0);
    const Real om2 = om * om;
    return kNorm / (p.rd * p.rd * p.rd) * (Real(1) + Real(4) * q) * om2 * om2;
  }
};

// The kernel's word in pair.kernel.
constexpr const char* density_kernel_name(DensityKernelKind kind) {
  return kind == DensityKernelKind::Lucy ? "lucy" : kind == DensityKernelKind::Wendland ? "wendland" : "warren";
}

// Calls f with the kernel functor of `kind`.
template <class F>
decltype(auto) with_density_kernel(DensityKernelKind kind, F&& f) {
  switch (kind) {
    case DensityKernelKind::Lucy: return f(LucyDensityKernel{});
    case DensityKernelKind::Wendland: return f(WendlandDensityKernel{});
    case DensityKernelKind::Warren: break;
  }
  return f(WarrenDensityKernel{});
}

}  // namespace mesodpd
