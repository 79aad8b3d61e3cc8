// OpenMP pair loop. Candidate pairs are first filtered by distance (cheap, vectorised), collected in
// a per-thread batch, then evaluated in a few array passes — geometry, noise, the force law of
// physics/dpd_pair.hpp, fixed-point conversion — and finally scattered into per-thread integer buffers.
#include "engine/force_compute.hpp"

#include <immintrin.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "engine/fixed_point.hpp"
#include "physics/dpd_pair.hpp"

namespace mesodpd {

#ifdef MESODPD_SINGLE_PRECISION
constexpr double kFilterMargin = 1e-4;  // float rounding of the filter's displacement
#else
constexpr double kFilterMargin = 1e-10;
#endif

// Pairs (i, j) waiting for evaluation, with the arrays of the evaluation passes.
struct PairBatch {
  static constexpr std::size_t kCapacity = 1024;
  std::size_t m = 0;
  alignas(64) std::uint32_t i[kCapacity + 16];  // + one vector: broadcast stores may run past m
  // Copies of particle i's position, velocity and id for every pair, written a vector at a time when
  // the pairs of one i are appended, so the passes read them contiguously instead of gathering.
  alignas(64) double ix[kCapacity + 8], iy[kCapacity + 8], iz[kCapacity + 8];
  alignas(64) double ivx[kCapacity + 8], ivy[kCapacity + 8], ivz[kCapacity + 8];
  alignas(64) std::uint32_t iid[kCapacity + 16];
  alignas(64) std::uint32_t j[kCapacity + 16];  // + one vector: compressed stores may run past m
  alignas(64) PairReal dx[kCapacity];
  alignas(64) PairReal dy[kCapacity];
  alignas(64) PairReal dz[kCapacity];
  alignas(64) PairReal r[kCapacity];
  alignas(64) PairReal inv_r[kCapacity];
  alignas(64) PairReal rv[kCapacity];
  alignas(64) PairReal xi[kCapacity];
  alignas(64) std::int64_t qx[kCapacity];
  alignas(64) std::int64_t qy[kCapacity];
  alignas(64) std::int64_t qz[kCapacity];
  alignas(64) PairReal r2[kCapacity / 2];  // distance filter scratch for one chunk of candidates
  std::vector<PairReal> cand_x, cand_y, cand_z;  // candidates of the current cell, nearest-image coordinates
  std::vector<std::uint32_t> cand_j;
};

#if defined(__AVX512F__) && defined(__AVX512VL__)
// Stores 8 doubles as the candidate arrays' type.
inline void store8(double* dst, __m512d v) { _mm512_storeu_pd(dst, v); }
inline void store8(float* dst, __m512d v) { _mm256_storeu_ps(dst, _mm512_maskz_cvtpd_ps(0xFF, v)); }
#endif

ForceCompute::ForceCompute(PairTable table, NoiseSettings noise) : table_(std::move(table)), noise_(noise) {
  weight_kind_ = table_.params.empty() ? WeightKind::General : weight_kind_of(table_.params[0].s);
  for (const DpdPairParams& q : table_.params) {
    if (weight_kind_of(q.s) != weight_kind_) weight_kind_ = WeightKind::General;
    params_real_.push_back(q.as<PairReal>());
  }
}
ForceCompute::~ForceCompute() = default;
ForceCompute::ForceCompute(ForceCompute&&) noexcept = default;
ForceCompute& ForceCompute::operator=(ForceCompute&&) noexcept = default;

void ForceCompute::compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step,
                           double dt, bool with_sums, PairSums& sums, Halo* halo) {
  auto dispatch = [&]<bool kSums>() {
    switch (weight_kind_) {
      case WeightKind::Two: return compute_impl<kSums, WeightKind::Two>(p, box, list, step, dt, sums, halo);
      case WeightKind::One: return compute_impl<kSums, WeightKind::One>(p, box, list, step, dt, sums, halo);
      case WeightKind::Half: return compute_impl<kSums, WeightKind::Half>(p, box, list, step, dt, sums, halo);
      case WeightKind::Quarter: return compute_impl<kSums, WeightKind::Quarter>(p, box, list, step, dt, sums, halo);
      case WeightKind::General: return compute_impl<kSums, WeightKind::General>(p, box, list, step, dt, sums, halo);
    }
  };
  if (with_sums)
    dispatch.template operator()<true>();
  else
    dispatch.template operator()<false>();
}

template <bool kSums, WeightKind W>
void ForceCompute::compute_impl(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step,
                                double dt, PairSums& sums, Halo* halo) {
  const std::size_t n = p.n_local;
  const std::size_t ntot = p.size();  // local particles, then ghosts
  const bool ghosts = p.n_ghost > 0;
  if (ghosts) {
    if (3 * ntot > fixed_.capacity()) fixed_.reserve(3 * ntot + 3 * ntot / 8);  // not the usual doubling
    fixed_.resize(3 * ntot);
  }
  const int nthreads = omp_get_max_threads();
  buffers_.resize(static_cast<std::size_t>(nthreads));
  while (batches_.size() < static_cast<std::size_t>(nthreads)) batches_.push_back(std::make_unique<PairBatch>());
  const double lx = box.len.x, ly = box.len.y, lz = box.len.z;  // shifts of wrapped cell runs
  // Minimum image on periodic axes, the plain difference on bounded ones (Box::image_len).
  const double ilx = box.image_len(0), ily = box.image_len(1), ilz = box.image_len(2);
  const double hlx = box.half_image_len(0), hly = box.half_image_len(1), hlz = box.half_image_len(2);
  const int ns = table_.n_species;
  const DpdPairParamsT<PairReal>* params = params_real_.data();
  const PairReal inv_sqrt_dt_r = static_cast<PairReal>(1.0 / std::sqrt(dt));
  const std::uint64_t seed = noise_.seed;
  const NoiseKind kind = noise_.kind;
  // The filter keeps a relative margin so that no pair the exact evaluation would count is dropped
  // because the filter's displacement was rounded differently.
  const PairReal filter2 = static_cast<PairReal>(table_.max_cutoff * table_.max_cutoff * (1.0 + kFilterMargin));

  // Integer sums: [0..5] virial tensor, [6] conservative virial trace, [7] energy, [8] pairs.
  std::int64_t total[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};

#pragma omp parallel num_threads(nthreads)
  {
    const int t = omp_get_thread_num();
    std::vector<std::int64_t>& bufv = buffers_[static_cast<std::size_t>(t)];
    // Buffers are left all zero by the reduction below, which clears each entry as it reads it (the
    // cache line is already there), so only entries added by growth need zeroing here.
    if (bufv.size() != 3 * ntot) bufv.resize(3 * ntot, 0);
    std::int64_t* buf = bufv.data();
    PairBatch& b = *batches_[static_cast<std::size_t>(t)];
    b.m = 0;
    std::int64_t local[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    const double* __restrict x = p.x.data();
    const double* __restrict y = p.y.data();
    const double* __restrict z = p.z.data();
    const double* __restrict vx = p.vx.data();
    const double* __restrict vy = p.vy.data();
    const double* __restrict vz = p.vz.data();
    const std::int32_t* __restrict sp = p.species.data();
    const std::uint32_t* __restrict id = p.id.data();

    // Evaluate and scatter every pair in the batch. Each pass is a simple loop over arrays.
    auto flush = [&] {
      const std::size_t m = b.m;
      // Pass 1: exact geometry. minimum_image() gives the same bits whichever side finds the pair.
      for (std::size_t k = 0; k < m; ++k) {
        const std::uint32_t j = b.j[k];
        const PairReal dx = static_cast<PairReal>(minimum_image(b.ix[k] - x[j], ilx, hlx));
        const PairReal dy = static_cast<PairReal>(minimum_image(b.iy[k] - y[j], ily, hly));
        const PairReal dz = static_cast<PairReal>(minimum_image(b.iz[k] - z[j], ilz, hlz));
        const PairReal r = std::sqrt(dx * dx + dy * dy + dz * dz);
        const PairReal inv_r = r > PairReal(0) ? PairReal(1) / r : PairReal(0);
        b.dx[k] = dx;
        b.dy[k] = dy;
        b.dz[k] = dz;
        b.r[k] = r;
        b.inv_r[k] = inv_r;
        b.rv[k] = (dx * static_cast<PairReal>(b.ivx[k] - vx[j]) + dy * static_cast<PairReal>(b.ivy[k] - vy[j]) +
                   dz * static_cast<PairReal>(b.ivz[k] - vz[j])) *
                  inv_r;
      }
      // Pass 2: the symmetric pair noise (seed 000 Eq. 5), one loop per distribution.
      if (kind == NoiseKind::Uniform) {
        for (std::size_t k = 0; k < m; ++k)
          b.xi[k] = static_cast<PairReal>(pair_noise(seed, step, b.iid[k], id[b.j[k]], NoiseKind::Uniform));
      } else {
        for (std::size_t k = 0; k < m; ++k)
          b.xi[k] = static_cast<PairReal>(pair_noise(seed, step, b.iid[k], id[b.j[k]], NoiseKind::Gaussian));
      }
      // Pass 3: the force law and the fixed-point conversion. One species pair: its parameters are
      // loop constants (no per-pair lookup, which would make the vectorised loop gather them).
      auto pass3 = [&]<bool kOne>() {
        const DpdPairParamsT<PairReal> p0 = params[0];
        for (std::size_t k = 0; k < m; ++k) {
          const DpdPairParamsT<PairReal>& pp = kOne ? p0 : params[sp[b.i[k]] * ns + sp[b.j[k]]];
          const DpdPairForceT<PairReal> f = dpd_pair_force<W>(pp, b.r[k], b.rv[k], b.xi[k], inv_sqrt_dt_r);
          const PairReal scale = (f.fc + f.fd + f.fr) * b.inv_r[k];
          const double fx = scale * b.dx[k], fy = scale * b.dy[k], fz = scale * b.dz[k];
          b.qx[k] = to_fixed(fx, kForceScale);
          b.qy[k] = to_fixed(fy, kForceScale);
          b.qz[k] = to_fixed(fz, kForceScale);
          if constexpr (kSums) {
            const bool in_range = b.r[k] * b.r[k] < pp.rcut2;
            local[0] += to_fixed(b.dx[k] * fx, kVirialScale);
            local[1] += to_fixed(b.dy[k] * fy, kVirialScale);
            local[2] += to_fixed(b.dz[k] * fz, kVirialScale);
            local[3] += to_fixed(b.dx[k] * fy, kVirialScale);
            local[4] += to_fixed(b.dx[k] * fz, kVirialScale);
            local[5] += to_fixed(b.dy[k] * fz, kVirialScale);
            local[6] += to_fixed(f.fc * b.r[k], kVirialScale);
            local[7] += to_fixed(f.energy, kVirialScale);
            local[8] += in_range ? 1 : 0;
          }
        }
      };
      if (ns == 1)
        pass3.template operator()<true>();
      else
        pass3.template operator()<false>();
      // Pass 4: scatter (integer adds: the order does not matter).
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t i = b.i[k], j = b.j[k];
        buf[3 * i] += b.qx[k];
        buf[3 * i + 1] += b.qy[k];
        buf[3 * i + 2] += b.qz[k];
        buf[3 * j] -= b.qx[k];
        buf[3 * j + 1] -= b.qy[k];
        buf[3 * j + 2] -= b.qz[k];
      }
      b.m = 0;
    };
    // Marks batch entries [m0, m) as pairs of particle i (see PairBatch::ix).
    auto spread_i = [&](std::uint32_t i, std::size_t m0, std::size_t m) {
#if defined(__AVX512F__) && defined(__AVX512VL__)
      const __m512d px = _mm512_set1_pd(x[i]), py = _mm512_set1_pd(y[i]), pz = _mm512_set1_pd(z[i]);
      const __m512d pvx = _mm512_set1_pd(vx[i]), pvy = _mm512_set1_pd(vy[i]), pvz = _mm512_set1_pd(vz[i]);
      const __m256i pi = _mm256_set1_epi32(static_cast<int>(i)), pid = _mm256_set1_epi32(static_cast<int>(id[i]));
      for (std::size_t k = m0; k < m; k += 8) {
        _mm512_storeu_pd(b.ix + k, px);
        _mm512_storeu_pd(b.iy + k, py);
        _mm512_storeu_pd(b.iz + k, pz);
        _mm512_storeu_pd(b.ivx + k, pvx);
        _mm512_storeu_pd(b.ivy + k, pvy);
        _mm512_storeu_pd(b.ivz + k, pvz);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(b.i + k), pi);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(b.iid + k), pid);
      }
#else
      for (std::size_t k = m0; k < m; ++k) {
        b.ix[k] = x[i];
        b.iy[k] = y[i];
        b.iz[k] = z[i];
        b.ivx[k] = vx[i];
        b.ivy[k] = vy[i];
        b.ivz[k] = vz[i];
        b.i[k] = i;
        b.iid[k] = id[i];
      }
#endif
    };
    // Distance filter of particle i against candidates [k0, k1) of the cell's candidate arrays, which
    // hold nearest-image coordinates. Survivors are appended to the batch without branches.
    auto filter = [&](std::uint32_t i, std::size_t k0, std::size_t k1, double ox, double oy, double oz) {
      constexpr std::size_t kChunk = PairBatch::kCapacity / 2;  // dense cells are taken in chunks
      const PairReal xi = static_cast<PairReal>(x[i] - ox), yi = static_cast<PairReal>(y[i] - oy),
                     zi = static_cast<PairReal>(z[i] - oz);
      for (std::size_t a = k0; a < k1; a += kChunk) {
        const std::size_t cnt = std::min(k1, a + kChunk) - a;
        const PairReal* __restrict cx = b.cand_x.data() + a;
        const PairReal* __restrict cy = b.cand_y.data() + a;
        const PairReal* __restrict cz = b.cand_z.data() + a;
        const std::uint32_t* __restrict cj = b.cand_j.data() + a;
        if (b.m + cnt > PairBatch::kCapacity) flush();
        const std::size_t m0 = b.m;
        std::size_t m = m0;
#if defined(__AVX512F__) && defined(__AVX512VL__)
        // One vector of candidates per step: squared distance, compare, and the survivors' indices packed
        // with an in-register compress and a plain store (the memory form of vpcompress is slow on some
        // cores). The last, partial vector is masked, so there is no scalar tail. The filter only selects
        // (a superset of the pairs in range, see filter2), so its rounding may differ from pass 1's.
        if constexpr (std::is_same_v<PairReal, double>) {
          const __m512d lim = _mm512_set1_pd(filter2);
          const __m512d vx = _mm512_set1_pd(xi), vy = _mm512_set1_pd(yi), vz = _mm512_set1_pd(zi);
          for (std::size_t k = 0; k < cnt; k += 8) {
            const __mmask8 valid = cnt - k >= 8 ? __mmask8(0xFF) : __mmask8((1u << (cnt - k)) - 1u);
            const __m512d dx = _mm512_sub_pd(vx, _mm512_maskz_loadu_pd(valid, cx + k));
            const __m512d dy = _mm512_sub_pd(vy, _mm512_maskz_loadu_pd(valid, cy + k));
            const __m512d dz = _mm512_sub_pd(vz, _mm512_maskz_loadu_pd(valid, cz + k));
            const __m512d r2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
            const __mmask8 keep = _mm512_mask_cmp_pd_mask(valid, r2, lim, _CMP_LT_OQ);
            const __m256i js = _mm256_maskz_loadu_epi32(valid, cj + k);
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(b.j + m), _mm256_maskz_compress_epi32(keep, js));
            m += static_cast<std::size_t>(__builtin_popcount(keep));
          }
        } else {
          const __m512 lim = _mm512_set1_ps(filter2);
          const __m512 vx = _mm512_set1_ps(xi), vy = _mm512_set1_ps(yi), vz = _mm512_set1_ps(zi);
          for (std::size_t k = 0; k < cnt; k += 16) {
            const __mmask16 valid = cnt - k >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << (cnt - k)) - 1u);
            const __m512 dx = _mm512_sub_ps(vx, _mm512_maskz_loadu_ps(valid, cx + k));
            const __m512 dy = _mm512_sub_ps(vy, _mm512_maskz_loadu_ps(valid, cy + k));
            const __m512 dz = _mm512_sub_ps(vz, _mm512_maskz_loadu_ps(valid, cz + k));
            const __m512 r2 = _mm512_fmadd_ps(dz, dz, _mm512_fmadd_ps(dy, dy, _mm512_mul_ps(dx, dx)));
            const __mmask16 keep = _mm512_mask_cmp_ps_mask(valid, r2, lim, _CMP_LT_OQ);
            const __m512i js = _mm512_maskz_loadu_epi32(valid, cj + k);
            _mm512_storeu_si512(b.j + m, _mm512_maskz_compress_epi32(keep, js));
            m += static_cast<std::size_t>(__builtin_popcount(keep));
          }
        }
#else
        PairReal* __restrict r2 = b.r2;
        for (std::size_t k = 0; k < cnt; ++k) {
          const PairReal dx = xi - cx[k], dy = yi - cy[k], dz = zi - cz[k];
          r2[k] = dx * dx + dy * dy + dz * dz;
        }
        for (std::size_t k = 0; k < cnt; ++k) {
          b.j[m] = cj[k];
          m += r2[k] < filter2 ? 1 : 0;
        }
#endif
        spread_i(i, m0, m);
        b.m = m;
      }
    };

    if (list.cells_only()) {
      // Cell pairs: particle i against the rest of its own cell and the 13 forward neighbour cells.
      // The candidates of a cell are gathered once, with periodic shifts applied, own cell first; the
      // q-th particle of the cell then scans candidates q+1 onwards in one loop.
      const CellGrid& grid = list.grid();
      const std::uint32_t* start = list.cell_start().data();
      const std::size_t ncells = grid.num_owned_cells();  // ghost cells are only partners
#pragma omp for schedule(static)
      for (std::size_t c = 0; c < ncells; ++c) {
        if (start[c] == start[c + 1]) continue;
        CellRun runs[CellGrid::kMaxHalfRuns];
        const int nr = grid.half_runs(static_cast<int>(c), runs);
        std::size_t total = 0;
        for (int r = 0; r < nr; ++r) total += start[runs[r].last + 1] - start[runs[r].first];
        if (b.cand_x.size() < total + 8) {  // + one vector of slack for the vector stores
          b.cand_x.resize(2 * total + 8);
          b.cand_y.resize(2 * total + 8);
          b.cand_z.resize(2 * total + 8);
          b.cand_j.resize(2 * total + 8);
        }
        // Candidate coordinates are taken relative to a particle of the cell, so that they are small
        // numbers whose float rounding (single-precision build) stays far below the filter's margin
        // however large the box.
        const double ox = x[start[c]], oy = y[start[c]], oz = z[start[c]];
        std::size_t mc = 0;
        for (int r = 0; r < nr; ++r) {
          const CellRun& e = runs[r];
          const double sx = e.wx * lx - ox, sy = e.wy * ly - oy, sz = e.wz * lz - oz;
          const std::uint32_t j0 = start[e.first], j1 = start[e.last + 1];
#if defined(__AVX512F__) && defined(__AVX512VL__)
          // A vector at a time: masked loads of the (short) run, plain stores into the slack-padded arrays.
          const __m512d vsx = _mm512_set1_pd(sx), vsy = _mm512_set1_pd(sy), vsz = _mm512_set1_pd(sz);
          const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
          for (std::uint32_t j = j0; j < j1; j += 8, mc += 8) {
            const __mmask8 valid = j1 - j >= 8 ? __mmask8(0xFF) : __mmask8((1u << (j1 - j)) - 1u);
            const __m512d cx = _mm512_add_pd(_mm512_maskz_loadu_pd(valid, x + j), vsx);
            const __m512d cy = _mm512_add_pd(_mm512_maskz_loadu_pd(valid, y + j), vsy);
            const __m512d cz = _mm512_add_pd(_mm512_maskz_loadu_pd(valid, z + j), vsz);
            store8(b.cand_x.data() + mc, cx);
            store8(b.cand_y.data() + mc, cy);
            store8(b.cand_z.data() + mc, cz);
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(b.cand_j.data() + mc),
                                _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(j)), iota));
          }
          mc -= (8 - (j1 - j0) % 8) % 8;  // back to the end of the run
#else
          for (std::uint32_t j = j0; j < j1; ++j, ++mc) {
            b.cand_x[mc] = static_cast<PairReal>(x[j] + sx);
            b.cand_y[mc] = static_cast<PairReal>(y[j] + sy);
            b.cand_z[mc] = static_cast<PairReal>(z[j] + sz);
            b.cand_j[mc] = j;
          }
#endif
        }
        for (std::uint32_t i = start[c]; i < start[c + 1]; ++i) filter(i, i - start[c] + 1, mc, ox, oy, oz);
      }
    } else {
      const std::uint32_t* off = list.offsets().data();
      const std::uint32_t* nbr = list.neighbors().data();
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        for (std::uint32_t k = off[i]; k < off[i + 1];) {
          if (b.m == PairBatch::kCapacity) flush();
          const std::size_t m0 = b.m;
          const std::size_t take = std::min<std::size_t>(off[i + 1] - k, PairBatch::kCapacity - m0);
          for (std::size_t t = 0; t < take; ++t) b.j[m0 + t] = nbr[k + t];
          k += static_cast<std::uint32_t>(take);
          b.m = m0 + take;
          spread_i(static_cast<std::uint32_t>(i), m0, b.m);
        }
      }
    }
    flush();
    if constexpr (kSums) {
#pragma omp critical
      for (int q = 0; q < 9; ++q) total[q] += local[q];  // integer sums: order does not matter
    }
#pragma omp barrier
    // Reduce the per-thread buffers; integer addition makes the result thread-count independent.
    if (!ghosts) {
#pragma omp for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        std::int64_t sx = 0, sy = 0, sz = 0;
        for (int u = 0; u < nthreads; ++u) {
          std::int64_t* bu = buffers_[static_cast<std::size_t>(u)].data();
          sx += bu[3 * i];
          sy += bu[3 * i + 1];
          sz += bu[3 * i + 2];
          bu[3 * i] = bu[3 * i + 1] = bu[3 * i + 2] = 0;
        }
        p.fx[i] = static_cast<double>(sx) * kForceUnscale;
        p.fy[i] = static_cast<double>(sy) * kForceUnscale;
        p.fz[i] = static_cast<double>(sz) * kForceUnscale;
      }
    } else {
      // With ghosts, the integer totals of ghosts go back to their owners before the conversion.
#pragma omp for schedule(static)
      for (std::size_t k = 0; k < 3 * ntot; ++k) {
        std::int64_t s = 0;
        for (int u = 0; u < nthreads; ++u) {
          s += buffers_[static_cast<std::size_t>(u)][k];
          buffers_[static_cast<std::size_t>(u)][k] = 0;
        }
        fixed_[k] = s;
      }
    }
  }
  if (ghosts) {
    if (halo != nullptr) halo->reverse_forces(fixed_.data(), p);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      p.fx[i] = static_cast<double>(fixed_[3 * i]) * kForceUnscale;
      p.fy[i] = static_cast<double>(fixed_[3 * i + 1]) * kForceUnscale;
      p.fz[i] = static_cast<double>(fixed_[3 * i + 2]) * kForceUnscale;
    }
  }
  if constexpr (kSums) {
    // Each pair was evaluated on exactly one rank: the integer totals add up to the single-rank ones.
    if (halo != nullptr) halo->comm().sum(std::span<std::int64_t>(total, 9));
  }
  if constexpr (kSums) {
    for (int q = 0; q < 6; ++q) sums.virial[static_cast<std::size_t>(q)] = static_cast<double>(total[q]) * kVirialUnscale;
    sums.virial_conservative = static_cast<double>(total[6]) * kVirialUnscale;
    sums.potential_energy = static_cast<double>(total[7]) * kVirialUnscale;
    sums.pairs_in_range = static_cast<std::uint64_t>(total[8]);
  }
}

}  // namespace mesodpd
