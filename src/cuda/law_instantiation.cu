// Compile-only check that the physics is device code: every pair law of the engine's list, every
// density kernel and every bond and angle law, with the per-pair accumulation, inside __global__
// kernels. A host-only line in any of them (a std::vector, a function without MESODPD_HD) fails the
// build here instead of in a future CUDA backend. Nothing links this object.
#include <cstdint>
#include <variant>
#include <vector>

#include "core/box.hpp"
#include "core/philox.hpp"
#include "engine/fixed_point.hpp"
#include "engine/pair_contribution.hpp"
#include "engine/pair_laws.hpp"
#include "physics/bond_laws.hpp"
#include "physics/density_kernel.hpp"

namespace mesodpd::cuda_check {

// One pair per thread, the way a CUDA pair loop would evaluate it: the geometry (minimum image), the
// pair noise, the law, then the integers the pair adds (engine/pair_contribution.hpp).
template <class Law, class Eval, class Real>
__global__ void pair_law_kernel(const typename Law::template Params<Real>* params, const double* xi_pos,
                                const double* xj_pos, const double* vij, const std::uint32_t* ids, const double* rho,
                                std::uint64_t seed, std::uint64_t step, Real inv_sqrt_dt, double len, double half_len,
                                std::int64_t* force_out, std::int64_t* sums, int n) {
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (k >= n) return;
  const Real dx = static_cast<Real>(minimum_image(xi_pos[3 * k] - xj_pos[3 * k], len, half_len));
  const Real dy = static_cast<Real>(minimum_image(xi_pos[3 * k + 1] - xj_pos[3 * k + 1], len, half_len));
  const Real dz = static_cast<Real>(minimum_image(xi_pos[3 * k + 2] - xj_pos[3 * k + 2], len, half_len));
  const Real r = std::sqrt(dx * dx + dy * dy + dz * dz);
  const Real inv_r = r > Real(0) ? Real(1) / r : Real(0);
  PairInput<Real> in;
  in.r = r;
  in.rv = (dx * static_cast<Real>(vij[3 * k]) + dy * static_cast<Real>(vij[3 * k + 1]) +
           dz * static_cast<Real>(vij[3 * k + 2])) * inv_r;
  in.xi = static_cast<Real>(pair_noise(seed, step, ids[2 * k], ids[2 * k + 1], NoiseKind::Uniform)) +
          static_cast<Real>(pair_noise(seed, step, ids[2 * k], ids[2 * k + 1], NoiseKind::Gaussian));
  in.inv_sqrt_dt = inv_sqrt_dt;
  if constexpr (Law::kDensity) {
    in.rho_i = static_cast<Real>(rho[2 * k]);
    in.rho_j = static_cast<Real>(rho[2 * k + 1]);
  }
  constexpr int kScalars = law_scalars<Law>;
  if constexpr (kScalars > 0) {  // eDPD, tDPD: each particle's scalars (here in rho's place), their noises
    double xi = 0, xs[kMaxScalars] = {};
    pair_noise_with_scalars(seed, step, ids[2 * k], ids[2 * k + 1], NoiseKind::Uniform, xi, xs, kScalars);
    for (int c = 0; c < kScalars; ++c) {
      in.xs[c] = static_cast<Real>(xs[c]);
      in.si[c] = static_cast<Real>(rho[2 * kScalars * k + c]);
      in.sj[c] = static_cast<Real>(rho[2 * kScalars * k + kScalars + c]);
    }
  }
  if constexpr (law_non_central<Law>) {
    in.d[0] = dx, in.d[1] = dy, in.d[2] = dz;
    for (int c = 0; c < 3; ++c) in.dv[c] = static_cast<Real>(vij[3 * k + c]);
  }
  if constexpr (law_noise_words<Law> > 0) {
    double xm[kMaxNoiseWords] = {};
    pair_noise_words(seed, step, ids[2 * k], ids[2 * k + 1], NoiseKind::Uniform, xm, law_noise_words<Law>);
    for (int c = 0; c < law_noise_words<Law>; ++c) in.xm[c] = static_cast<Real>(xm[c]);
  }
  const PairForceT<Real> f = Eval{}(params[k], in);
  for (int c = 0; c < kScalars; ++c) {
    force_out[3 * n + 2 * kScalars * k + c] = to_fixed(static_cast<double>(f.qi[c]), kForceScale);
    force_out[3 * n + 2 * kScalars * k + kScalars + c] = to_fixed(static_cast<double>(f.qj[c]), kForceScale);
  }
  const PairForceVector fv = pair_force_vector<law_non_central<Law>>(f, inv_r, dx, dy, dz);
  const PairForceFixed q = to_fixed(fv);
  force_out[3 * k] = q.x;
  force_out[3 * k + 1] = q.y;
  force_out[3 * k + 2] = q.z;
  add_pair_sums<law_non_central<Law>>(sums + 9 * k, f, fv, r, dx, dy, dz, params[k].rcut2);
}

template <class Kernel, class Real>
__global__ void density_kernel_kernel(Kernel kernel, const DensityParamsT<Real>* params, const Real* r,
                                      std::int64_t* out, int n) {
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (k < n) out[k] = to_fixed(static_cast<double>(kernel(params[k], r[k])), kForceScale);
}

__global__ void bonded_kernel(const BondParams* bonds, const AngleParams* angles, const double* b1, const double* b2,
                              double* out, int n) {
  const int k = static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x);
  if (k >= n) return;
  const BondForce bf = bond_force(bonds[k], b1[3 * k]);
  const AngleForce af = angle_force(angles[k], b1 + 3 * k, b2 + 3 * k);
  out[k] = bf.f_over_r + bf.energy + (bf.broken ? 1.0 : 0.0) + af.f1[0] + af.f3[2] + af.energy + af.cos_theta;
}

// Every evaluator a law's with_evaluator() can hand the CPU loop (all branches of its choice), in the
// given pair arithmetic type: taking the kernel's address instantiates its device code.
template <class Law, class Real>
void instantiate_law() {
  const std::vector<typename Law::template Params<double>> table;
  Law::with_evaluator(table, [](auto eval) { (void)&pair_law_kernel<Law, decltype(eval), Real>; });
}

// Every law of the engine's compile-time list (PairLawTables), so that a law added there is checked
// here without a further line.
template <class Real, class... Tables>
void instantiate_laws(const std::variant<Tables...>*) {
  (instantiate_law<typename Tables::LawType, Real>(), ...);
}

// Referenced nowhere; exists so that the templates above are instantiated.
void instantiate_all() {
  instantiate_laws<double>(static_cast<const PairLawTables*>(nullptr));
  instantiate_laws<float>(static_cast<const PairLawTables*>(nullptr));
  (void)&density_kernel_kernel<WarrenDensityKernel, double>;
  (void)&density_kernel_kernel<LucyDensityKernel, double>;
  (void)&density_kernel_kernel<WarrenDensityKernel, float>;
  (void)&density_kernel_kernel<LucyDensityKernel, float>;
  (void)&density_kernel_kernel<WendlandDensityKernel, double>;
  (void)&density_kernel_kernel<WendlandDensityKernel, float>;
  (void)&bonded_kernel;
}

}  // namespace mesodpd::cuda_check
