// OpenMP pair loop over the half neighbour list; the force law itself lives in physics/dpd_pair.hpp.
#include "engine/force_compute.hpp"

#include <omp.h>

#include <cmath>

#include "engine/fixed_point.hpp"
#include "physics/dpd_pair.hpp"

namespace mesodpd {

void ForceCompute::compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step,
                           double dt, bool with_sums, PairSums& sums) {
  if (with_sums)
    compute_impl<true>(p, box, list, step, dt, sums);
  else
    compute_impl<false>(p, box, list, step, dt, sums);
}

template <bool kSums>
void ForceCompute::compute_impl(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step,
                                double dt, PairSums& sums) {
  const std::size_t n = p.n_local;
  const int nthreads = omp_get_max_threads();
  if (buffers_.size() != static_cast<std::size_t>(nthreads)) buffers_.resize(static_cast<std::size_t>(nthreads));
  const double inv_sqrt_dt = 1.0 / std::sqrt(dt);
  const double lx = box.len.x, ly = box.len.y, lz = box.len.z;
  const double hlx = 0.5 * lx, hly = 0.5 * ly, hlz = 0.5 * lz;  // half lengths
  const std::uint32_t* off = list.offsets().data();
  const std::uint32_t* nbr = list.neighbors().data();
  const int ns = table_.n_species;
  const DpdPairParams* params = table_.params.data();
  const std::uint64_t seed = noise_.seed;
  const NoiseKind kind = noise_.kind;

  // Integer sums: [0..5] virial tensor, [6] conservative virial trace, [7] energy, [8] pairs.
  std::int64_t total[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};

#pragma omp parallel num_threads(nthreads)
  {
    const int t = omp_get_thread_num();
    std::vector<std::int64_t>& buf = buffers_[static_cast<std::size_t>(t)];
    buf.assign(3 * n, 0);
    std::int64_t local[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    const double *x = p.x.data(), *y = p.y.data(), *z = p.z.data();
    const double *vx = p.vx.data(), *vy = p.vy.data(), *vz = p.vz.data();
    const std::int32_t* sp = p.species.data();
    const std::uint32_t* id = p.id.data();

#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      std::int64_t fix = 0, fiy = 0, fiz = 0;
      const double xi = x[i], yi = y[i], zi = z[i];
      const double vxi = vx[i], vyi = vy[i], vzi = vz[i];
      const DpdPairParams* row = params + sp[i] * ns;
      for (std::uint32_t k = off[i]; k < off[i + 1]; ++k) {
        const std::uint32_t j = nbr[k];
        const double dx = minimum_image(xi - x[j], lx, hlx);
        const double dy = minimum_image(yi - y[j], ly, hly);
        const double dz = minimum_image(zi - z[j], lz, hlz);
        const double r2 = dx * dx + dy * dy + dz * dz;
        const DpdPairParams& pp = row[sp[j]];
        if (r2 >= pp.rcut2) continue;
        const double r = std::sqrt(r2);
        const double inv_r = r > 0.0 ? 1.0 / r : 0.0;
        const double rv = (dx * (vxi - vx[j]) + dy * (vyi - vy[j]) + dz * (vzi - vz[j])) * inv_r;
        const double xi_ij = pair_noise(seed, step, id[i], id[j], kind);
        const DpdPairForce f = dpd_pair_force(pp, r, rv, xi_ij, inv_sqrt_dt);
        const double scale = (f.fc + f.fd + f.fr) * inv_r;
        const double fx = scale * dx, fy = scale * dy, fz = scale * dz;
        const std::int64_t qx = to_fixed(fx, kForceScale), qy = to_fixed(fy, kForceScale);
        const std::int64_t qz = to_fixed(fz, kForceScale);
        fix += qx;
        fiy += qy;
        fiz += qz;
        buf[3 * j] -= qx;
        buf[3 * j + 1] -= qy;
        buf[3 * j + 2] -= qz;
        if constexpr (kSums) {
          local[0] += to_fixed(dx * fx, kVirialScale);
          local[1] += to_fixed(dy * fy, kVirialScale);
          local[2] += to_fixed(dz * fz, kVirialScale);
          local[3] += to_fixed(dx * fy, kVirialScale);
          local[4] += to_fixed(dx * fz, kVirialScale);
          local[5] += to_fixed(dy * fz, kVirialScale);
          local[6] += to_fixed(f.fc * r, kVirialScale);
          local[7] += to_fixed(f.energy, kVirialScale);
          local[8] += 1;
        }
      }
      buf[3 * i] += fix;
      buf[3 * i + 1] += fiy;
      buf[3 * i + 2] += fiz;
    }
    if constexpr (kSums) {
#pragma omp critical
      for (int q = 0; q < 9; ++q) total[q] += local[q];  // integer sums: order does not matter
    }
#pragma omp barrier
    // Reduce the per-thread buffers; integer addition makes the result thread-count independent.
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      std::int64_t sx = 0, sy = 0, sz = 0;
      for (int u = 0; u < nthreads; ++u) {
        const std::int64_t* b = buffers_[static_cast<std::size_t>(u)].data();
        sx += b[3 * i];
        sy += b[3 * i + 1];
        sz += b[3 * i + 2];
      }
      p.fx[i] = static_cast<double>(sx) * kForceUnscale;
      p.fy[i] = static_cast<double>(sy) * kForceUnscale;
      p.fz[i] = static_cast<double>(sz) * kForceUnscale;
    }
  }
  if constexpr (kSums) {
    for (int q = 0; q < 6; ++q) sums.virial[static_cast<std::size_t>(q)] = static_cast<double>(total[q]) * kVirialUnscale;
    sums.virial_conservative = static_cast<double>(total[6]) * kVirialUnscale;
    sums.potential_energy = static_cast<double>(total[7]) * kVirialUnscale;
    sums.pairs_in_range = static_cast<std::uint64_t>(total[8]);
  }
}

}  // namespace mesodpd
