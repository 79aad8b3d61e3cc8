// The CPU pair backend: the shared OpenMP pair loop, compiled once per SIMD instruction set with Google
// Highway and chosen at run time. Candidate pairs are filtered by distance (vectorised), collected in a
// per-thread batch, then evaluated in array passes (geometry, noise, the force law or density kernel,
// fixed-point conversion) and scattered into per-thread integer buffers. The traversal is written
// once; what is evaluated is a template parameter: a force law of engine/pair_laws.hpp or a density
// kernel. run_loop puts together the parts defined just above it: workspace, accumulation, candidate
// filter, traversals, reduction.
#include "engine/force_compute.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "engine/fixed_point.hpp"
#include "engine/pair_batch.hpp"
#include "engine/pair_contribution.hpp"

// Compiled once, not per target (this file is re-included for every instruction set below).
#ifndef MESODPD_FORCE_COMPUTE_SHARED
#define MESODPD_FORCE_COMPUTE_SHARED
namespace mesodpd {
// Byte shuffles that move the 32-bit lanes of a 4-lane vector selected by a 4-bit mask to the front,
// in order: the distance filter's compress where the instruction set has no compress instruction
// (AVX2). A static table, so that no target rebuilds it on the stack per call.
struct Compress4Table {
  alignas(16) std::uint8_t idx[16][16];
};
constexpr Compress4Table make_compress4_table() {
  Compress4Table t{};
  for (int bits = 0; bits < 16; ++bits) {
    int out = 0;
    for (int lane = 0; lane < 4; ++lane)
      if (bits & (1 << lane)) {
        for (int byte = 0; byte < 4; ++byte) t.idx[bits][4 * out + byte] = static_cast<std::uint8_t>(4 * lane + byte);
        ++out;
      }
    for (; out < 4; ++out)  // unused lanes: anything; repeat lane 0
      for (int byte = 0; byte < 4; ++byte) t.idx[bits][4 * out + byte] = static_cast<std::uint8_t>(byte);
  }
  return t;
}
inline constexpr Compress4Table kCompress4 = make_compress4_table();
}  // namespace mesodpd
#endif

// Targets compiled: the portable fallback, SSE4, AVX2 and AVX-512 on x86 (and NEON/SVE on ARM), less
// SSSE3, which adds compile time and no user.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS HWY_SSSE3
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "engine/force_compute.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace mesodpd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

#ifdef MESODPD_SINGLE_PRECISION
constexpr double kFilterMargin = 1e-4;  // float rounding of the filter's displacement
#else
constexpr double kFilterMargin = 1e-10;
#endif

// Masked loads that never touch memory in masked-off lanes exist on AVX2 and AVX-512; elsewhere a
// partial vector at the end of an array is read by a scalar loop instead.
#if HWY_TARGET <= HWY_AVX2
constexpr bool kFaultFreeMaskedLoad = true;
#else
constexpr bool kFaultFreeMaskedLoad = false;
#endif

// q[k] = to_fixed(v[k], scale) for k in [0, m), a vector at a time, with the same bits as the scalar
// function: the same product, clamp and NaN rule, and a truncating conversion that is exact for every
// clamped value (native on AVX-512; emulated exactly elsewhere, where a scalar loop would stall on one
// conversion per value). Reads and writes up to the next multiple of the lane count, which never passes
// PairBatch::kCapacity (a multiple of every target's lane count).
//
// Returns whether some vector held a value at or past `limit` (<= 2^51) in magnitude, or a NaN: the
// fast path's own test, so the check costs nothing while every value is in range. Lanes past m may
// hold stale values and raise it too; the caller looks at [0, m) to find the entry (note_overflow_in).
HWY_INLINE bool to_fixed_array(const double* HWY_RESTRICT v, std::int64_t* HWY_RESTRICT q, std::size_t m,
                               double scale, double limit) {
  const hn::ScalableTag<double> d;
  const hn::RebindToSigned<decltype(d)> di;
  const auto vs = hn::Set(d, scale), hi = hn::Set(d, kFixedLimit), lo = hn::Set(d, -kFixedLimit);
  // Below 2^51 in magnitude (every force short of a blow-up) the truncated value t is an integer that
  // t + 1.5 * 2^52 holds exactly in its low mantissa bits: four cheap instructions instead of the full
  // conversion, which the other values (large, infinite, NaN) still take.
  const auto small = hn::Set(d, limit);               // at most 2^51
  const auto magic = hn::Set(d, 6755399441055744.0);  // 1.5 * 2^52
  const auto magic_bits = hn::BitCast(di, magic);
  bool out_of_range = false;
  for (std::size_t k = 0; k < m; k += hn::Lanes(d)) {
    auto x = hn::Mul(hn::LoadU(d, v + k), vs);
    if (hn::AllTrue(d, hn::Lt(hn::Abs(x), small))) {
      hn::StoreU(hn::Sub(hn::BitCast(di, hn::Add(hn::Trunc(x), magic)), magic_bits), di, q + k);
      continue;
    }
    out_of_range = true;
    x = hn::IfThenElse(hn::Gt(x, hi), hi, x);
    x = hn::IfThenElse(hn::Lt(x, lo), lo, x);
    x = hn::IfThenElse(hn::Eq(x, x), x, hi);  // NaN becomes the largest value, as in to_fixed()
    hn::StoreU(hn::ConvertTo(di, x), di, q + k);
  }
  return out_of_range;
}

// Whether one value's contribution (value x scale) lies within the limit of the per-pair sums.
inline bool in_fixed_range(double value, double scale, double limit) { return std::fabs(value * scale) < limit; }

// After to_fixed_array reported a value out of range: every entry of [0, m) that is, into the batch's
// report (which keeps the smallest ids; `id` are the global ids of the stored particles).
inline void note_overflow_in(PairBatch& b, std::size_t m, double scale, double limit, const std::uint32_t* id,
                             const double* fx, const double* fy, const double* fz, FixedPointOverflow::What what) {
  for (std::size_t k = 0; k < m; ++k) {
    const double c[3] = {fx[k], fy != nullptr ? fy[k] : 0.0, fz != nullptr ? fz[k] : 0.0};
    for (const double v : c)
      if (!in_fixed_range(v, scale, limit)) {
        b.note_overflow(id[b.i[k]], id[b.j[k]], v, what);
        break;
      }
  }
}
static_assert(PairBatch::kCapacity % 16 == 0, "to_fixed_array rounds batch lengths up to whole vectors");

// The pair noise of core/philox.hpp a vector of pairs at a time, with the same bits as its scalar
// functions. x86 SIMD targets only; elsewhere the scalar loop runs.
#undef MESODPD_VECTOR_NOISE
#if HWY_ARCH_X86 && HWY_TARGET != HWY_SCALAR && HWY_TARGET != HWY_EMU128
#define MESODPD_VECTOR_NOISE 1
// The Philox draw pair_random_bits(seed, step, ids_a[k], ids_b[k], stream) for k in [0, m), a vector of
// pairs at a time: calls emit(k, a, b, c0, c1, c2, c3) with the pairs' ids (32-bit lanes) and the four
// words of their draws, each 32-bit word in the low half of a 64-bit lane, where one 32 x 32 -> 64
// multiply (MulEven) gives both halves of a round's product. Upper halves may hold garbage; MulEven reads
// only the low halves, and emit must mask them. (GCC vectorises the scalar version too, but spends most
// of it packing and unpacking 32-bit lanes.) m is rounded up to whole vectors: the id arrays must be
// readable that far (PairBatch's capacity is a multiple of 16).
template <class Emit>
HWY_INLINE void philox_array(const std::uint32_t* HWY_RESTRICT ids_a, const std::uint32_t* HWY_RESTRICT ids_b,
                             std::size_t m, std::uint64_t seed, std::uint64_t step, RngStream stream, const Emit& emit) {
  const hn::ScalableTag<std::uint64_t> d64;
  const hn::Rebind<std::uint32_t, decltype(d64)> d32;      // one id per 64-bit lane
  const hn::Repartition<std::uint32_t, decltype(d64)> dw;  // a 64-bit vector seen as 32-bit words
  const auto m0 = hn::BitCast(dw, hn::Set(d64, kPhiloxM0));
  const auto m1 = hn::BitCast(dw, hn::Set(d64, kPhiloxM1));
  std::uint64_t key0[kPhiloxRounds], key1[kPhiloxRounds];  // the keys of each round
  std::uint32_t k0 = static_cast<std::uint32_t>(seed), k1 = static_cast<std::uint32_t>(seed >> 32);
  for (int r = 0; r < kPhiloxRounds; ++r, k0 += kPhiloxW0, k1 += kPhiloxW1) {
    key0[r] = k0;
    key1[r] = k1;
  }
  const auto word2 = hn::Set(d64, static_cast<std::uint32_t>(step));
  const auto word3 = hn::Set(d64, pair_counter_word3(step, stream));
  for (std::size_t k = 0; k < m; k += hn::Lanes(d64)) {
    const auto a = hn::LoadU(d32, ids_a + k), b = hn::LoadU(d32, ids_b + k);
    auto c0 = hn::PromoteTo(d64, hn::Min(a, b)), c1 = hn::PromoteTo(d64, hn::Max(a, b));
    auto c2 = word2, c3 = word3;
    for (int r = 0; r < kPhiloxRounds; ++r) {
      const auto p0 = hn::MulEven(m0, hn::BitCast(dw, c0));
      const auto p1 = hn::MulEven(m1, hn::BitCast(dw, c2));
      c0 = hn::Xor(hn::Xor(hn::ShiftRight<32>(p1), c1), hn::Set(d64, key0[r]));
      c2 = hn::Xor(hn::Xor(hn::ShiftRight<32>(p0), c3), hn::Set(d64, key1[r]));
      c1 = p1;
      c3 = p0;
    }
    emit(k, a, b, c0, c1, c2, c3);
  }
}

// The uniform noise (NoiseKind::Uniform). Word 0 of the draw goes to `w0`, word 2 to `w2` (not computed
// where null), each antisymmetric (the sign of id_a < id_b) where asked: the layouts of pair_noise,
// pair_noise_with_scalars and pair_noise_words, the same bits.
template <class Real>
HWY_INLINE void uniform_noise_array(const std::uint32_t* HWY_RESTRICT ids_a, const std::uint32_t* HWY_RESTRICT ids_b,
                                    Real* HWY_RESTRICT w0, bool w0_antisymmetric, Real* HWY_RESTRICT w2,
                                    bool w2_antisymmetric, std::size_t m, std::uint64_t seed, std::uint64_t step,
                                    RngStream stream) {
  const hn::ScalableTag<std::uint64_t> d64;
  const hn::Rebind<double, decltype(d64)> dd;
  const auto low32 = hn::Set(d64, 0xFFFFFFFFull);
  const auto exp52 = hn::Set(d64, 0x4330000000000000ull);  // the bits of 2^52
  const auto two52 = hn::Set(dd, 4503599627370496.0);
  philox_array(ids_a, ids_b, m, seed, step, stream, [&](std::size_t k, auto a, auto b, auto c0, auto, auto c2, auto) {
    // u01_open(w) = (w + 0.5) / 2^32 with w converted exactly (2^52 + w, less 2^52); then
    // uniform_unit_variance: sqrt(3) (2 u - 1), in the scalar version's order.
    const auto unit = [&](auto word) {
      const auto w = hn::Sub(hn::BitCast(dd, hn::Or(hn::And(word, low32), exp52)), two52);
      const auto u = hn::Mul(hn::Add(w, hn::Set(dd, 0.5)), hn::Set(dd, 1.0 / 4294967296.0));
      return hn::Mul(hn::Set(dd, 1.7320508075688772), hn::Sub(hn::Mul(hn::Set(dd, 2.0), u), hn::Set(dd, 1.0)));
    };
    // The antisymmetric sign: + where id_a < id_b (pair_noise_with_scalars), as an exact negation.
    const auto flip = hn::RebindMask(dd, hn::Lt(hn::PromoteTo(d64, b), hn::PromoteTo(d64, a)));
    auto store = [&](auto x, Real* out) {
      if constexpr (std::is_same_v<Real, double>) {
        hn::StoreU(x, dd, out + k);
      } else {
        const hn::Rebind<Real, decltype(dd)> dr;
        hn::StoreU(hn::DemoteTo(dr, x), dr, out + k);
      }
    };
    const auto x0 = unit(c0);
    store(w0_antisymmetric ? hn::IfThenElse(flip, hn::Neg(x0), x0) : x0, w0);
    if (w2) {
      const auto x2 = unit(c2);
      store(w2_antisymmetric ? hn::IfThenElse(flip, hn::Neg(x2), x2) : x2, w2);
    }
  });
}

// The Gaussian noise (NoiseKind::Gaussian, gaussian_unit_portable): words 0 and 1 of the draw to `w01`,
// words 2 and 3 to `w23` (not computed where null), each antisymmetric (the sign of id_a < id_b) where
// asked; the layouts of pair_noise, pair_noise_with_scalars and pair_noise_words, the same bits. The
// words of a chunk of pairs go through a buffer; the Box-Muller loops over it are plain code that the
// compiler vectorises (the logarithm and cosine of core/portable_math.hpp, no library call). Not
// inlined: one call per batch costs nothing, while a copy in every pass's flush (three call sites each)
// made those functions three times their size, and tDPD runs with the uniform noise 5-10 % slower
// (docs/performance.md, session 29).
template <class Real>
HWY_NOINLINE void gaussian_noise_array(const std::uint32_t* HWY_RESTRICT ids_a, const std::uint32_t* HWY_RESTRICT ids_b,
                                     Real* HWY_RESTRICT w01, bool w01_antisymmetric, Real* HWY_RESTRICT w23,
                                     bool w23_antisymmetric, std::size_t m, std::uint64_t seed, std::uint64_t step,
                                     RngStream stream) {
  constexpr std::size_t kChunk = 128;  // a multiple of every vector length
  static_assert(PairBatch::kCapacity % kChunk == 0, "chunks must tile the batch");
  const hn::ScalableTag<std::uint64_t> d64;
  alignas(64) std::uint64_t word[4][kChunk];
  // A loop constant would be a select GCC 12 does not vectorise (docs/architecture.md): the sign is
  // instead a choice between two constants by the pair's ids.
  const double other01 = w01_antisymmetric ? -1.0 : 1.0, other23 = w23_antisymmetric ? -1.0 : 1.0;
  for (std::size_t k0 = 0; k0 < m; k0 += kChunk) {
    const std::size_t c = std::min(kChunk, m - k0);
    const std::uint32_t* HWY_RESTRICT a = ids_a + k0;
    const std::uint32_t* HWY_RESTRICT b = ids_b + k0;
    philox_array(a, b, c, seed, step, stream, [&](std::size_t k, auto, auto, auto c0, auto c1, auto c2, auto c3) {
      hn::Store(c0, d64, word[0] + k);
      hn::Store(c1, d64, word[1] + k);
      if (w23) {
        hn::Store(c2, d64, word[2] + k);
        hn::Store(c3, d64, word[3] + k);
      }
    });
    Real* HWY_RESTRICT out01 = w01 + k0;
    for (std::size_t k = 0; k < c; ++k) {
      const double sign = a[k] < b[k] ? 1.0 : other01;
      out01[k] = static_cast<Real>(sign * gaussian_unit_portable(static_cast<std::uint32_t>(word[0][k]),
                                                                 static_cast<std::uint32_t>(word[1][k])));
    }
    if (!w23) continue;
    Real* HWY_RESTRICT out23 = w23 + k0;
    for (std::size_t k = 0; k < c; ++k) {
      const double sign = a[k] < b[k] ? 1.0 : other23;
      out23[k] = static_cast<Real>(sign * gaussian_unit_portable(static_cast<std::uint32_t>(word[2][k]),
                                                                 static_cast<std::uint32_t>(word[3][k])));
    }
  }
}
// Either kind: the first variate of the draw (word 0, or words 0 and 1) to `first`, the second (word 2,
// or words 2 and 3) to `second` where not null.
template <class Real>
HWY_INLINE void noise_array(NoiseKind kind, const std::uint32_t* ids_a, const std::uint32_t* ids_b, Real* first,
                            bool first_antisymmetric, Real* second, bool second_antisymmetric, std::size_t m,
                            std::uint64_t seed, std::uint64_t step, RngStream stream) {
  if (kind == NoiseKind::Uniform)
    uniform_noise_array(ids_a, ids_b, first, first_antisymmetric, second, second_antisymmetric, m, seed, step, stream);
  else
    gaussian_noise_array(ids_a, ids_b, first, first_antisymmetric, second, second_antisymmetric, m, seed, step, stream);
}
#else
#define MESODPD_VECTOR_NOISE 0
#endif

// Calls pair(pp, k) for the batch entries k in [0, m) in order, pp the parameters of pair k's species
// pair (params: ns x ns table). With one species pair they are loop constants and the caller's loop
// vectorises. With several, a lookup per pair inside that loop would make the compiler gather every
// field or give up vectorising it (a 2-species wall run spent 21% of its time there, scalar); so the
// parameters of a chunk of pairs are first copied into columns, which the loop then reads
// contiguously, and a chunk whose pairs all share one species pair (the bulk of a fluid beside a wall)
// runs with constants. Same values, same arithmetic, same bits.
// The pair callback is always inlined into these loops (as the laws' evaluators are into it,
// MESODPD_HD_FORCE), so that they vectorise.
template <class Params, class Pair>
inline void for_each_pair_params(const PairBatch& b, std::size_t m, const Params* params, int ns,
                                 const std::int32_t* species, const Pair& pair) {
  if (ns == 1) {
    const Params p0 = params[0];
    for (std::size_t k = 0; k < m; ++k) pair(p0, k);
    return;
  }
  static_assert(std::is_trivially_copyable_v<Params> && sizeof(Params) % sizeof(PairReal) == 0,
                "pair parameters must be a plain set of PairReal fields");
  constexpr std::size_t kFields = sizeof(Params) / sizeof(PairReal);
  constexpr std::size_t kChunk = 64;
  alignas(64) PairReal col[kFields][kChunk];
  std::int32_t which[kChunk];
  for (std::size_t k0 = 0; k0 < m; k0 += kChunk) {
    const std::size_t c = std::min(kChunk, m - k0);
    bool one = true;
    for (std::size_t k = 0; k < c; ++k) {
      which[k] = species[b.i[k0 + k]] * ns + species[b.j[k0 + k]];
      one = one && which[k] == which[0];
    }
    if (one) {
      const Params pc = params[which[0]];
      for (std::size_t k = 0; k < c; ++k) pair(pc, k0 + k);
      continue;
    }
    for (std::size_t k = 0; k < c; ++k) {
      const auto* src = reinterpret_cast<const unsigned char*>(&params[which[k]]);
      for (std::size_t f = 0; f < kFields; ++f) std::memcpy(&col[f][k], src + f * sizeof(PairReal), sizeof(PairReal));
    }
    for (std::size_t k = 0; k < c; ++k) {
      PairReal v[kFields];
      for (std::size_t f = 0; f < kFields; ++f) v[f] = col[f][k];
      Params pp;
      std::memcpy(&pp, v, sizeof(Params));
      pair(pp, k0 + k);
    }
  }
}

// What one kind of pair computation evaluates, on top of the shared traversal:
//   kComponents   integers accumulated per particle (3 for a force, 1 for a density)
//   kSymmetric    the pair adds the same value to i and j (density) instead of opposite ones (force)
//   kVelocity, kNoise, kDirection   which per-pair inputs the geometry and noise passes compute
//   evaluate(b, m, local)  fills b.qx (.qy, .qz) for batch entries [0, m) and adds to the sums.

// A force law `Eval` of law `Law` (physics/*.hpp).
// A law with per-particle scalars (kScalars: eDPD's temperature, tDPD's concentrations) adds a component
// per scalar, its rate, which is not antisymmetric in general: the pair's contributions to i and j come
// separately (qhi, qhj). Only the first n_scalars are held in a run; the others are zeros throughout.
template <class Law, class Eval, bool kSums>
struct ForcePass {
  static constexpr int kScalars = law_scalars<Law>;
  static constexpr int kComponents = 3 + kScalars;
  static constexpr bool kSymmetric = false;
  static constexpr bool kVelocity = Law::kVelocity;
  static constexpr bool kNoise = Law::kNoise;
  static constexpr bool kDirection = true;
  static constexpr bool kNonCentral = law_non_central<Law>;
  static constexpr int kNoiseWords = law_noise_words<Law>;
  using Params = typename Law::template Params<PairReal>;

  Eval eval;
  const Params* params = nullptr;  // the table in the pair arithmetic type (LawTable::params_real)
  int ns = 1;
  PairReal inv_sqrt_dt = 1;
  const std::int32_t* species = nullptr;
  const double* rho = nullptr;
  double fixed_limit = kPairFixedLimit;  // PairJob::fixed_limit
  const std::uint32_t* ids = nullptr;    // global ids of the stored particles, for overflow reports
  int n_scalars = 0;                     // PairJob::n_scalars

  void evaluate(PairBatch& b, std::size_t m, std::int64_t* local) const {
    // Pair k with the parameters pp of its species pair.
    auto pair = [&](const Params& pp, std::size_t k) __attribute__((always_inline)) {
      PairInput<PairReal> in;
      in.r = b.r[k];
      if constexpr (kVelocity) in.rv = b.rv[k];
      if constexpr (kNoise) in.xi = b.xi[k];
      in.inv_sqrt_dt = inv_sqrt_dt;
      if constexpr (Law::kDensity) {
        in.rho_i = static_cast<PairReal>(rho[b.i[k]]);
        in.rho_j = static_cast<PairReal>(rho[b.j[k]]);
      }
      for (int c = 0; c < kScalars; ++c) {
        in.si[c] = static_cast<PairReal>(b.si[c][k]);
        in.sj[c] = static_cast<PairReal>(b.sj[c][k]);
        in.xs[c] = b.xs[c][k];
      }
      if constexpr (kNonCentral) {
        in.d[0] = b.dx[k];
        in.d[1] = b.dy[k];
        in.d[2] = b.dz[k];
        in.dv[0] = b.dvx[k];
        in.dv[1] = b.dvy[k];
        in.dv[2] = b.dvz[k];
      }
      for (int c = 0; c < kNoiseWords; ++c) in.xm[c] = b.xm[c][k];
      const PairForceT<PairReal> f = eval(pp, in);
      for (int c = 0; c < kScalars; ++c) {
        b.hi[c][k] = f.qi[c];
        b.hj[c][k] = f.qj[c];
      }
      const PairForceVector fv = pair_force_vector<kNonCentral>(f, b.inv_r[k], b.dx[k], b.dy[k], b.dz[k]);
      if constexpr (!kSums) {
        // Converted below, a vector at a time; this loop then has no int64 conversion, which AVX2
        // lacks and which would keep the compiler from vectorising the law.
        b.fx[k] = fv.x;
        b.fy[k] = fv.y;
        b.fz[k] = fv.z;
      } else {
        const PairForceFixed q = to_fixed(fv);
        b.qx[k] = q.x;
        b.qy[k] = q.y;
        b.qz[k] = q.z;
        for (const double c : {fv.x, fv.y, fv.z})
          if (!in_fixed_range(c, kForceScale, fixed_limit))
            b.note_overflow(ids[b.i[k]], ids[b.j[k]], c, FixedPointOverflow::What::PairForce);
        // The pair's terms, then their sums with a check (thermo steps only): a term at the clamp or a
        // total past the int64 range would be a wrong pressure or energy without a word.
        std::int64_t terms[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
        add_pair_sums<kNonCentral>(terms, f, fv, b.r[k], b.dx[k], b.dy[k], b.dz[k], pp.rcut2);
        bool bad = false;
        for (int c = 0; c < 9; ++c) {
          bad |= terms[c] >= kPairSumLimit || terms[c] <= -kPairSumLimit;
          bad |= __builtin_add_overflow(local[c], terms[c], &local[c]);
        }
        if (bad)
          b.note_overflow(ids[b.i[k]], ids[b.j[k]], static_cast<double>(f.fc) * static_cast<double>(b.r[k]),
                          FixedPointOverflow::What::PairVirial);
      }
    };
    for_each_pair_params(b, m, params, ns, species, pair);
    for (int c = 0; c < n_scalars; ++c) {
      bool out = to_fixed_array(b.hi[c], b.qhi[c], m, kForceScale, fixed_limit);
      out |= to_fixed_array(b.hj[c], b.qhj[c], m, kForceScale, fixed_limit);
      if (out) [[unlikely]]
        note_overflow_in(b, m, kForceScale, fixed_limit, ids, b.hi[c], b.hj[c], nullptr,
                         FixedPointOverflow::What::ScalarRate);
    }
    if constexpr (!kSums) {
      bool out = to_fixed_array(b.fx, b.qx, m, kForceScale, fixed_limit);
      out |= to_fixed_array(b.fy, b.qy, m, kForceScale, fixed_limit);
      out |= to_fixed_array(b.fz, b.qz, m, kForceScale, fixed_limit);
      if (out) [[unlikely]]
        note_overflow_in(b, m, kForceScale, fixed_limit, ids, b.fx, b.fy, b.fz, FixedPointOverflow::What::PairForce);
    }
  }
};

// A density kernel (physics/density_kernel.hpp): rho_i += w(r_ij), rho_j += w(r_ij).
template <class Kernel>
struct DensityPass {
  static constexpr int kComponents = 1;
  static constexpr int kScalars = 0;
  static constexpr bool kSymmetric = true;
  static constexpr bool kVelocity = false;
  static constexpr bool kNoise = false;
  static constexpr bool kDirection = false;
  static constexpr bool kNonCentral = false;
  static constexpr int kNoiseWords = 0;
  using Params = DensityParamsT<PairReal>;

  Kernel kernel;
  std::vector<Params> params;
  int ns = 1;
  const std::int32_t* species = nullptr;

  double fixed_limit = kPairFixedLimit;
  const std::uint32_t* ids = nullptr;

  void evaluate(PairBatch& b, std::size_t m, std::int64_t*) const {
    for_each_pair_params(b, m, params.data(), ns, species,
                         [&](const Params& pp, std::size_t k) { b.fx[k] = kernel(pp, b.r[k]); });
    if (to_fixed_array(b.fx, b.qx, m, kForceScale, fixed_limit)) [[unlikely]]
      note_overflow_in(b, m, kForceScale, fixed_limit, ids, b.fx, nullptr, nullptr, FixedPointOverflow::What::Density);
  }
};

// What the evaluation passes read besides the batch: positions, velocities and ids of every stored
// particle, the periodic images and the noise key.
struct BatchGeometry {
  const double* x;
  const double* y;
  const double* z;
  const double* vx;
  const double* vy;
  const double* vz;
  const std::uint32_t* id;
  double ilx, ily, ilz, hlx, hly, hlz;
  std::uint64_t seed;
  NoiseKind kind;
  std::uint64_t step;
  // Passes with kScalars: the held scalars (PairJob::scalar), n_scalars of them.
  int n_scalars = 0;
  const double* const* scalar = nullptr;
  // Lees-Edwards images (Box::shear): per image count n along the gradient axis, j's image is shifted
  // by n offset and moves n velocity faster along the flow axis. gradient < 0: none.
  int gradient = -1, flow = -1;
  double offset = 0, velocity = 0;
};

// The BatchGeometry of a box and particles: minimum image on periodic axes, the plain difference on
// bounded ones (Box::image_len), and the box's Lees-Edwards images.
inline BatchGeometry batch_geometry(const ParticleData& p, const Box& box, const NoiseSettings& noise, std::uint64_t step,
                                    int n_scalars, const double* const* scalar) {
  BatchGeometry g{p.x.data(),       p.y.data(),       p.z.data(),       p.vx.data(),
                  p.vy.data(),      p.vz.data(),      p.id.data(),      box.image_len(0),
                  box.image_len(1), box.image_len(2), box.half_image_len(0), box.half_image_len(1),
                  box.half_image_len(2), noise.seed, noise.kind, step, n_scalars, scalar};
  if (box.sheared()) {
    g.gradient = box.shear.gradient;
    g.flow = box.shear.flow;
    g.offset = box.shear.offset;
    g.velocity = box.shear.velocity;
  }
  return g;
}

// Moves the batch's out-of-range pair (PairBatch::overflow) into `found`, which keeps the pair with the
// smallest ids so that the report depends neither on threads nor on batches; clears the batch's.
inline void take_batch_overflow(PairBatch& b, double limit, std::optional<FixedPointOverflow>& found) {
  if (!b.overflow) return;
  FixedPointOverflow o = *b.overflow;
  o.limit = o.what == FixedPointOverflow::What::PairVirial ? static_cast<double>(kPairSumLimit) * kVirialUnscale
                                                           : limit * kForceUnscale;
  if (!found || o.id_a < found->id_a || (o.id_a == found->id_a && o.id_b < found->id_b)) found = o;
  b.overflow.reset();
}

// Adds a thread's nine sums to the rank's, reporting a total that leaves the int64 range.
inline void add_sums_checked(std::int64_t* totals, const std::int64_t* local, std::optional<FixedPointOverflow>& found) {
  bool bad = false;
  for (int q = 0; q < 9; ++q) bad |= __builtin_add_overflow(totals[q], local[q], &totals[q]);
  if (bad && !found) {
    FixedPointOverflow o;
    o.what = FixedPointOverflow::What::PairVirial;
    o.value = std::numeric_limits<double>::infinity();
    o.limit = 9.2e18 * kVirialUnscale;
    found = o;
  }
}

// Passes 1-3 over batch entries [0, m): exact geometry, the pair noise, the law or kernel with the
// fixed-point conversion (into b.qx, .qy, .qz; sums into `local`). Shared by the pair loop and by the
// evaluation of listed pairs (excluded bonded pairs), so both give the same bits for a pair.
template <class Pass>
HWY_INLINE void evaluate_batch(PairBatch& b, std::size_t m, const Pass& pass, const BatchGeometry& g,
                               std::int64_t* local) {
  const double* __restrict x = g.x;
  const double* __restrict y = g.y;
  const double* __restrict z = g.z;
  const double* __restrict vx = g.vx;
  const double* __restrict vy = g.vy;
  const double* __restrict vz = g.vz;
  const std::uint32_t* __restrict id = g.id;
  const double ilx = g.ilx, ily = g.ily, ilz = g.ilz, hlx = g.hlx, hly = g.hly, hlz = g.hlz;
  const std::uint64_t seed = g.seed;
  const NoiseKind kind = g.kind;
  const std::uint64_t step = g.step;
  // Pass 0: particle j's data into contiguous arrays (the only gathers of the evaluation).
  for (std::size_t k = 0; k < m; ++k) {
    const std::uint32_t j = b.j[k];
    b.jx[k] = x[j];
    b.jy[k] = y[j];
    b.jz[k] = z[j];
    if constexpr (Pass::kVelocity) {
      b.jvx[k] = vx[j];
      b.jvy[k] = vy[j];
      b.jvz[k] = vz[j];
    }
    if constexpr (Pass::kNoise || Pass::kNoiseWords > 0) b.jid[k] = id[j];
  }
  // The scalars of j; a channel the run does not hold is zero for the law (and its noise too).
  for (int c = 0; c < Pass::kScalars; ++c) {
    if (c < g.n_scalars) {
      const double* __restrict sc = g.scalar[c];
      for (std::size_t k = 0; k < m; ++k) b.sj[c][k] = sc[b.j[k]];
    } else {
      std::fill_n(b.si[c], m, 0.0);
      std::fill_n(b.sj[c], m, 0.0);
      std::fill_n(b.xs[c], m, PairReal(0));
    }
  }
  // Pass 1: exact geometry. minimum_image() gives the same bits whichever side finds the pair.
  // With Lees-Edwards images the image count n along the gradient axis shifts j's image along the flow
  // axis and adds to its velocity there (box_displacement(), written out so that it vectorises; n is
  // odd in (i, j), so the shifted difference is too).
  const auto store_geometry = [&](std::size_t k, PairReal dx, PairReal dy, PairReal dz, double dvx, double dvy,
                                  double dvz) {
    const PairReal r = std::sqrt(dx * dx + dy * dy + dz * dz);
    b.r[k] = r;
    if constexpr (Pass::kDirection) {
      // Divides by 1 where r = 0 and then selects 0: a division that cannot fault is one the compiler
      // may compute for every lane, so the loop vectorises without masked division (AVX2).
      const bool apart = r > PairReal(0);
      const PairReal inv_r = apart ? PairReal(1) / (apart ? r : PairReal(1)) : PairReal(0);
      b.dx[k] = dx;
      b.dy[k] = dy;
      b.dz[k] = dz;
      b.inv_r[k] = inv_r;
      if constexpr (Pass::kVelocity)
        b.rv[k] = (dx * static_cast<PairReal>(dvx) + dy * static_cast<PairReal>(dvy) + dz * static_cast<PairReal>(dvz)) *
                  inv_r;
      if constexpr (Pass::kNonCentral) {
        b.dvx[k] = static_cast<PairReal>(dvx);
        b.dvy[k] = static_cast<PairReal>(dvy);
        b.dvz[k] = static_cast<PairReal>(dvz);
      }
    }
    (void)dvx, (void)dvy, (void)dvz;
  };
  if (g.gradient < 0) {
    for (std::size_t k = 0; k < m; ++k) {
      const PairReal dx = static_cast<PairReal>(minimum_image(b.ix[k] - b.jx[k], ilx, hlx));
      const PairReal dy = static_cast<PairReal>(minimum_image(b.iy[k] - b.jy[k], ily, hly));
      const PairReal dz = static_cast<PairReal>(minimum_image(b.iz[k] - b.jz[k], ilz, hlz));
      if constexpr (Pass::kVelocity)
        store_geometry(k, dx, dy, dz, b.ivx[k] - b.jvx[k], b.ivy[k] - b.jvy[k], b.ivz[k] - b.jvz[k]);
      else
        store_geometry(k, dx, dy, dz, 0.0, 0.0, 0.0);
    }
  } else {
    // The planes as compile-time axes (flow F before gradient G), so that the loop has no branch and
    // vectorises like the plain one.
    const auto sheared = [&](auto flow_axis, auto gradient_axis) {
      constexpr int F = decltype(flow_axis)::value, G = decltype(gradient_axis)::value;
      const double hg = G == 1 ? hly : hlz;
      const double off = g.offset, du = g.velocity;
      for (std::size_t k = 0; k < m; ++k) {
        const double rx = b.ix[k] - b.jx[k], ry = b.iy[k] - b.jy[k], rz = b.iz[k] - b.jz[k];
        const double rg = G == 1 ? ry : rz;
        const double n = (rg > hg ? 1.0 : 0.0) - (rg < -hg ? 1.0 : 0.0);  // image_count()
        const PairReal dx = static_cast<PairReal>(minimum_image(F == 0 ? rx - n * off : rx, ilx, hlx));
        const PairReal dy = static_cast<PairReal>(minimum_image(F == 1 ? ry - n * off : ry, ily, hly));
        const PairReal dz = static_cast<PairReal>(minimum_image(rz, ilz, hlz));
        if constexpr (Pass::kVelocity)
          store_geometry(k, dx, dy, dz, b.ivx[k] - b.jvx[k] - (F == 0 ? n * du : 0.0),
                         b.ivy[k] - b.jvy[k] - (F == 1 ? n * du : 0.0), b.ivz[k] - b.jvz[k]);
        else
          store_geometry(k, dx, dy, dz, 0.0, 0.0, 0.0);
      }
    };
    using A0 = std::integral_constant<int, 0>;
    using A1 = std::integral_constant<int, 1>;
    using A2 = std::integral_constant<int, 2>;
    if (g.gradient == 1)
      sheared(A0{}, A1{});
    else if (g.flow == 0)
      sheared(A0{}, A2{});
    else
      sheared(A1{}, A2{});
  }
  // Pass 2: the symmetric pair noise (seed 000 Eq. 5), one loop per distribution; with scalars also
  // their antisymmetric noises (the first from the same draw).
  if constexpr (Pass::kScalars > 0) {
    const int ns = g.n_scalars;
#if MESODPD_VECTOR_NOISE  // the layout of pair_noise_with_scalars, a vector at a time
    PairReal* const none = nullptr;
    noise_array(kind, b.iid, b.jid, b.xi, false, ns > 0 ? b.xs[0] : none, true, m, seed, step, RngStream::PairNoise);
    if (ns > 1)
      noise_array(kind, b.iid, b.jid, b.xs[1], true, ns > 2 ? b.xs[2] : none, true, m, seed, step, RngStream::ScalarNoise);
    if (ns > 3) noise_array(kind, b.iid, b.jid, b.xs[3], true, none, true, m, seed, step, RngStream::ScalarNoise2);
#else
    for (std::size_t k = 0; k < m; ++k) {
      double xi, xs[kMaxScalars];
      pair_noise_with_scalars(seed, step, b.iid[k], b.jid[k], kind, xi, xs, ns);
      b.xi[k] = static_cast<PairReal>(xi);
      for (int c = 0; c < ns; ++c) b.xs[c][k] = static_cast<PairReal>(xs[c]);
    }
#endif
  } else if constexpr (Pass::kNoise) {
#if MESODPD_VECTOR_NOISE
    noise_array(kind, b.iid, b.jid, b.xi, false, static_cast<PairReal*>(nullptr), false, m, seed, step, RngStream::PairNoise);
#else
    for (std::size_t k = 0; k < m; ++k) b.xi[k] = static_cast<PairReal>(pair_noise(seed, step, b.iid[k], b.jid[k], kind));
#endif
  }
  // The symmetric noise words of a law that draws its own (pair_noise_words, the same bits).
  if constexpr (Pass::kNoiseWords > 0) {
    constexpr int nw = Pass::kNoiseWords;
#if MESODPD_VECTOR_NOISE
    for (int w = 0; w < nw; w += 2)
      noise_array(kind, b.iid, b.jid, b.xm[w], false, w + 1 < nw ? b.xm[w + 1] : static_cast<PairReal*>(nullptr), false,
                  m, seed, step,
                  static_cast<RngStream>(static_cast<std::uint32_t>(RngStream::PairMatrix) + static_cast<std::uint32_t>(w / 2)));
#else
    for (std::size_t k = 0; k < m; ++k) {
      double xm[kMaxNoiseWords];
      pair_noise_words(seed, step, b.iid[k], b.jid[k], kind, xm, nw);
      for (int w = 0; w < nw; ++w) b.xm[w][k] = static_cast<PairReal>(xm[w]);
    }
#endif
  }
  // Pass 3: the law or kernel and the fixed-point conversion.
  pass.evaluate(b, m, local);
}

// ---- The pair loop in four parts: workspace, accumulation, candidate filter, traversals. ----------
// run_loop() at the end puts them together; each part reads on its own.

// Workspace growth before the parallel region: the ghost totals (C integers per stored particle), one
// integer buffer and one batch per thread. Returns the thread count the region runs with.
inline int prepare_workspace(PairWorkspace& ws, int components, std::size_t ntot, bool ghosts) {
  const std::size_t need = static_cast<std::size_t>(components) * ntot;
  if (ghosts) {
    if (need > ws.fixed.capacity()) ws.fixed.reserve(need + need / 8);  // not the usual doubling
    ws.fixed.resize(need);
  }
  const int nthreads = omp_get_max_threads();
  ws.buffers.resize(static_cast<std::size_t>(nthreads));
  while (ws.batches.size() < static_cast<std::size_t>(nthreads)) ws.batches.push_back(std::make_unique<PairBatch>());
  return nthreads;
}

// Whether any stored particle is frozen (body != 0). Frozen wall particles do not interact with each
// other: force passes skip such pairs when the system holds any. Density passes keep them (a wall
// particle's density counts its neighbours in the wall too), so they never ask.
inline bool any_frozen_particle(const ParticleData& p) {
  const std::int32_t* bd = p.body.data();
  const std::size_t ntot = p.size();
  for (std::size_t k = 0; k < ntot; ++k)
    if (bd[k] != 0) return true;
  return false;
}

// Accumulation, one per thread: owns the thread's batch of pairs, evaluates it (evaluate_batch) when
// it is full or the traversal ends, and scatters the integer results into the thread's buffer (C
// integers per stored particle) and its share of the sums. Integer adds, so neither the order of the
// pairs nor the split over threads reaches the totals.
template <class Pass, bool kSums>
class BatchAccumulator {
 public:
  static constexpr int C = Pass::kComponents;

  BatchAccumulator(PairBatch& b, std::int64_t* buf, const Pass& pass, const BatchGeometry& geo)
      : b_(b), buf_(buf), pass_(pass), geo_(geo) {
    b_.m = 0;
  }

  PairBatch& batch() { return b_; }

  // Marks batch entries [m0, m) as pairs of particle i: copies i's position, velocity and id into
  // them a vector at a time (see PairBatch::ix), so that the passes read them contiguously.
  void mark_pairs_of(std::uint32_t i, std::size_t m0, std::size_t m) {
    const hn::ScalableTag<double> dd;
    const hn::Rebind<std::uint32_t, decltype(dd)> du;
    const std::size_t nd = hn::Lanes(dd);
    PairBatch& b = b_;
    const auto px = hn::Set(dd, geo_.x[i]), py = hn::Set(dd, geo_.y[i]), pz = hn::Set(dd, geo_.z[i]);
    const auto pvx = hn::Set(dd, geo_.vx[i]), pvy = hn::Set(dd, geo_.vy[i]), pvz = hn::Set(dd, geo_.vz[i]);
    const auto pi = hn::Set(du, i), pid = hn::Set(du, geo_.id[i]);
    for (int c = 0; c < Pass::kScalars && c < geo_.n_scalars; ++c) {
      const auto pt = hn::Set(dd, geo_.scalar[c][i]);
      for (std::size_t k = m0; k < m; k += nd) hn::StoreU(pt, dd, b.si[c] + k);
    }
    for (std::size_t k = m0; k < m; k += nd) {
      hn::StoreU(px, dd, b.ix + k);
      hn::StoreU(py, dd, b.iy + k);
      hn::StoreU(pz, dd, b.iz + k);
      if constexpr (Pass::kVelocity) {
        hn::StoreU(pvx, dd, b.ivx + k);
        hn::StoreU(pvy, dd, b.ivy + k);
        hn::StoreU(pvz, dd, b.ivz + k);
      }
      hn::StoreU(pi, du, b.i + k);
      hn::StoreU(pid, du, b.iid + k);
    }
  }

  // Evaluates every pair in the batch and scatters the results; the batch is then empty.
  void flush() {
    PairBatch& b = b_;
    std::int64_t* buf = buf_;
    const std::size_t m = b.m;
    evaluate_batch(b, m, pass_, geo_, local_);
    if (b.overflow) [[unlikely]]
      take_batch_overflow(b, pass_.fixed_limit, overflow_);
    // Pass 4: scatter. The pairs of one particle i are consecutive in the batch, so i's share is
    // summed in registers and added once per run.
    if constexpr (C >= 3) {
      // Forces (antisymmetric), and with scalars their rates at i and j, each to its own particle.
      constexpr int S = C - 3;
      const int ns = geo_.n_scalars;
      for (std::size_t k = 0; k < m;) {
        const std::size_t i = b.i[k];
        std::int64_t sx = 0, sy = 0, sz = 0, sh[S > 0 ? S : 1] = {};
        for (; k < m && b.i[k] == i; ++k) {
          const std::size_t j = b.j[k];
          sx += b.qx[k];
          sy += b.qy[k];
          sz += b.qz[k];
          buf[C * j] -= b.qx[k];
          buf[C * j + 1] -= b.qy[k];
          buf[C * j + 2] -= b.qz[k];
          for (int c = 0; c < S && c < ns; ++c) {
            sh[c] += b.qhi[c][k];
            buf[C * j + 3 + c] += b.qhj[c][k];
          }
        }
        buf[C * i] += sx;
        buf[C * i + 1] += sy;
        buf[C * i + 2] += sz;
        for (int c = 0; c < S && c < ns; ++c) buf[C * i + 3 + c] += sh[c];
      }
    } else {
      for (std::size_t k = 0; k < m; ++k) {
        const std::size_t i = b.i[k], j = b.j[k];
        buf[i] += b.qx[k];
        buf[j] += Pass::kSymmetric ? b.qx[k] : -b.qx[k];
      }
    }
    b.m = 0;
  }

  // The last batch, then this thread's sums into the rank's (integers: the order does not matter).
  void finish(std::int64_t* totals, std::optional<FixedPointOverflow>& overflow) {
    flush();
#pragma omp critical
    {
      if constexpr (kSums) add_sums_checked(totals, local_, overflow_);
      if (overflow_ && (!overflow || overflow_->id_a < overflow->id_a ||
                        (overflow_->id_a == overflow->id_a && overflow_->id_b < overflow->id_b)))
        overflow = overflow_;
    }
  }

 private:
  PairBatch& b_;
  std::int64_t* buf_;
  const Pass& pass_;
  const BatchGeometry& geo_;
  std::int64_t local_[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};  // this thread's sums (PairJob::totals)
  std::optional<FixedPointOverflow> overflow_;            // this thread's first pair out of range
};

// Where the instruction set has no compress instruction and a vector holds 4 candidates (AVX2, double
// precision), the filter's compress is a table-driven byte shuffle (kCompress4).
#undef MESODPD_TABLE_COMPRESS
#if HWY_TARGET == HWY_AVX2 && !defined(MESODPD_SINGLE_PRECISION)
#define MESODPD_TABLE_COMPRESS 1
#else
#define MESODPD_TABLE_COMPRESS 0
#endif

// The candidate filter: particle i against candidates [k0, k1) of the batch's candidate arrays
// (PairBatch::cand_*), which hold nearest-image coordinates relative to (ox, oy, oz). Survivors are
// appended to the accumulator's batch without branches: a vector of candidates per step, squared
// distance, compare, and the survivors' indices packed by a compressing store; the last, partial
// vector is masked. The filter only selects (a superset of the pairs in range: `filter2` carries a
// margin), so its rounding never reaches the result.
template <class Acc>
class CandidateFilter {
 public:
  CandidateFilter(Acc& acc, const ParticleData& p, PairReal filter2, bool any_frozen)
      : acc_(acc), x_(p.x.data()), y_(p.y.data()), z_(p.z.data()),
        body_(reinterpret_cast<const std::uint32_t*>(p.body.data())), filter2_(filter2), any_frozen_(any_frozen) {}

  void operator()(std::uint32_t i, std::size_t k0, std::size_t k1, double ox, double oy, double oz) {
    const hn::ScalableTag<PairReal> dr;
    const hn::Rebind<std::uint32_t, decltype(dr)> dru;
    const std::size_t nr_lanes = hn::Lanes(dr);
#if MESODPD_TABLE_COMPRESS
    const hn::Repartition<std::uint8_t, decltype(dru)> du8;
#endif
    PairBatch& b = acc_.batch();
    const std::uint32_t* __restrict body = body_;
    constexpr std::size_t kChunk = PairBatch::kCapacity / 2;  // dense cells are taken in chunks
    const auto lim = hn::Set(dr, filter2_);
    const auto xi = hn::Set(dr, static_cast<PairReal>(x_[i] - ox));
    const auto yi = hn::Set(dr, static_cast<PairReal>(y_[i] - oy));
    const auto zi = hn::Set(dr, static_cast<PairReal>(z_[i] - oz));
    for (std::size_t a = k0; a < k1; a += kChunk) {
      const std::size_t cnt = std::min(k1, a + kChunk) - a;
      const PairReal* __restrict cx = b.cand_x.data() + a;
      const PairReal* __restrict cy = b.cand_y.data() + a;
      const PairReal* __restrict cz = b.cand_z.data() + a;
      const std::uint32_t* __restrict cj = b.cand_j.data() + a;
      const std::uint32_t* __restrict cb = b.cand_body.data() + a;
      // A frozen i keeps only mobile candidates.
      const bool frozen_i = any_frozen_ && body[i] != 0;
      if (b.m + cnt > PairBatch::kCapacity) acc_.flush();
      const std::size_t m0 = b.m;
      std::size_t m = m0;
      // The candidate arrays carry a vector of slack, so whole-vector loads stay inside them.
      for (std::size_t k = 0; k < cnt; k += nr_lanes) {
        const auto valid = hn::FirstN(dr, cnt - k);
        const auto dx = hn::Sub(xi, hn::LoadU(dr, cx + k));
        const auto dy = hn::Sub(yi, hn::LoadU(dr, cy + k));
        const auto dz = hn::Sub(zi, hn::LoadU(dr, cz + k));
        const auto r2 = hn::MulAdd(dz, dz, hn::MulAdd(dy, dy, hn::Mul(dx, dx)));
        const auto keep = hn::And(valid, hn::Lt(r2, lim));
#if MESODPD_TABLE_COMPRESS
        {
          // 4 candidates: the keep bits select a byte shuffle that packs the kept indices; the whole
          // vector is stored (b.j has slack) and m advances by the count.
          alignas(8) std::uint8_t bits[8] = {};
          hn::StoreMaskBits(dr, keep, bits);
          unsigned mask = bits[0];
          if (frozen_i) {
            alignas(8) std::uint8_t mobile[8] = {};
            hn::StoreMaskBits(dru, hn::Eq(hn::LoadU(dru, cb + k), hn::Zero(dru)), mobile);
            mask &= mobile[0];
          }
          const auto shuffle = hn::Load(du8, kCompress4.idx[mask]);
          hn::StoreU(hn::BitCast(dru, hn::TableLookupBytes(hn::BitCast(du8, hn::LoadU(dru, cj + k)), shuffle)), dru,
                     b.j + m);
          m += static_cast<std::size_t>(hwy::PopCount(mask));
        }
#else
        auto keep_j = index_mask(dr, dru, keep);
        if (frozen_i) keep_j = hn::And(keep_j, hn::Eq(hn::LoadU(dru, cb + k), hn::Zero(dru)));
        m += hn::CompressStore(hn::LoadU(dru, cj + k), keep_j, dru, b.j + m);
#endif
      }
      acc_.mark_pairs_of(i, m0, m);
      b.m = m;
    }
  }

 private:
  // The keep mask of a vector of coordinates as a mask of the 32-bit indices of the same lanes (lane
  // sizes differ in double precision, so it goes through its bits).
  template <class DR, class DRU, class M>
  static auto index_mask(DR dr, DRU dru, M keep) {
    if constexpr (sizeof(PairReal) == sizeof(std::uint32_t)) {
      (void)dr;
      return hn::RebindMask(dru, keep);
    } else {
      alignas(8) std::uint8_t bits[8] = {};
      hn::StoreMaskBits(dr, keep, bits);
      return hn::LoadMaskBits(dru, bits);
    }
  }

  Acc& acc_;
  const double* x_;
  const double* y_;
  const double* z_;
  const std::uint32_t* body_;
  PairReal filter2_;
  bool any_frozen_;
};

// Traversal by cell pairs (this thread's share of the owned cells): particle i against the rest of
// its own cell and the 13 forward neighbour cells. The candidates of a cell are gathered once into
// the batch's candidate arrays, with periodic shifts applied, own cell first; the q-th particle of the
// cell then scans candidates q+1 onwards with the filter.
template <class Filter>
void traverse_cell_pairs(const NeighborList& list, const ParticleData& p, const Box& box, bool any_frozen,
                         PairBatch& b, Filter& filter) {
  const hn::ScalableTag<double> dd;                 // particle coordinates
  const hn::Rebind<std::uint32_t, decltype(dd)> du;  // indices, one per coordinate lane
  const std::size_t nd = hn::Lanes(dd);
  const double* __restrict x = p.x.data();
  const double* __restrict y = p.y.data();
  const double* __restrict z = p.z.data();
  const std::uint32_t* __restrict body = reinterpret_cast<const std::uint32_t*>(p.body.data());
  const double lx = box.len.x, ly = box.len.y, lz = box.len.z;  // shifts of wrapped cell runs
  const bool sheared = box.sheared();
  const int flow = box.shear.flow, gradient = box.shear.gradient;
  const CellGrid& grid = list.grid();
  const std::uint32_t* start = list.cell_start().data();
  const std::size_t ncells = grid.num_owned_cells();  // ghost cells are only partners
  // Stores a vector of coordinates in the candidate arrays' type.
  auto store_candidates = [&](auto v, PairReal* dst) {
    if constexpr (std::is_same_v<PairReal, double>) {
      hn::StoreU(v, dd, dst);
    } else {
      const hn::Rebind<PairReal, decltype(dd)> dc;
      hn::StoreU(hn::DemoteTo(dc, v), dc, dst);
    }
  };
#pragma omp for schedule(static)
  for (std::size_t c = 0; c < ncells; ++c) {
    if (start[c] == start[c + 1]) continue;
    CellRun runs[CellGrid::kMaxHalfRuns];
    const int nr = grid.half_runs(static_cast<int>(c), runs, box.shear.offset);
    std::size_t total_c = 0;
    for (int r = 0; r < nr; ++r) total_c += start[runs[r].last + 1] - start[runs[r].first];
    if (b.cand_x.size() < total_c + PairBatch::kSlack) {  // slack for whole-vector loads and stores
      b.cand_x.resize(2 * total_c + PairBatch::kSlack);
      b.cand_y.resize(2 * total_c + PairBatch::kSlack);
      b.cand_z.resize(2 * total_c + PairBatch::kSlack);
      b.cand_j.resize(2 * total_c + PairBatch::kSlack);
      if (any_frozen) b.cand_body.resize(2 * total_c + PairBatch::kSlack);
    }
    if (any_frozen && b.cand_body.size() < b.cand_j.size()) b.cand_body.resize(b.cand_j.size());
    // Candidate coordinates are taken relative to a particle of the cell, so that they are small
    // numbers whose float rounding (single-precision build) stays far below the filter's margin
    // however large the box.
    const double ox = x[start[c]], oy = y[start[c]], oz = z[start[c]];
    std::size_t mc = 0;
    for (int r = 0; r < nr; ++r) {
      const CellRun& e = runs[r];
      double sx = e.wx * lx - ox, sy = e.wy * ly - oy, sz = e.wz * lz - oz;
      if (sheared) {  // the Lees-Edwards image of a run across the gradient faces (CellGrid::half_runs)
        const double w = gradient == 0 ? e.wx : (gradient == 1 ? e.wy : e.wz);
        (flow == 0 ? sx : (flow == 1 ? sy : sz)) += w * box.shear.offset;
      }
      const std::uint32_t j0 = start[e.first], j1 = start[e.last + 1];
      const auto vsx = hn::Set(dd, sx), vsy = hn::Set(dd, sy), vsz = hn::Set(dd, sz);
      std::uint32_t j = j0;
      // A vector at a time into the slack-padded arrays; the (short) run's last partial vector with
      // a masked load where loads cannot fault, by a scalar loop elsewhere.
      for (; j + nd <= j1 || (kFaultFreeMaskedLoad && j < j1); j += static_cast<std::uint32_t>(nd)) {
        const auto valid = hn::FirstN(dd, j1 - j);
        // (hwy's MaskedLoad wants aligned memory where it is not a fault-free instruction.)
        auto load = [&](const double* src) {
          if constexpr (kFaultFreeMaskedLoad)
            return hn::MaskedLoad(valid, dd, src);
          else
            return hn::LoadU(dd, src);
        };
        store_candidates(hn::Add(load(x + j), vsx), b.cand_x.data() + mc);
        store_candidates(hn::Add(load(y + j), vsy), b.cand_y.data() + mc);
        store_candidates(hn::Add(load(z + j), vsz), b.cand_z.data() + mc);
        hn::StoreU(hn::Iota(du, j), du, b.cand_j.data() + mc);
        if (any_frozen) {
          const auto valid_u = hn::FirstN(du, j1 - j);
          if constexpr (kFaultFreeMaskedLoad)
            hn::StoreU(hn::MaskedLoad(valid_u, du, body + j), du, b.cand_body.data() + mc);
          else
            hn::StoreU(hn::LoadU(du, body + j), du, b.cand_body.data() + mc);
        }
        mc += std::min<std::size_t>(nd, j1 - j);
      }
      for (; j < j1; ++j, ++mc) {
        if (any_frozen) b.cand_body[mc] = body[j];
        b.cand_x[mc] = static_cast<PairReal>(x[j] + sx);
        b.cand_y[mc] = static_cast<PairReal>(y[j] + sy);
        b.cand_z[mc] = static_cast<PairReal>(z[j] + sz);
        b.cand_j[mc] = j;
      }
    }
    for (std::uint32_t i = start[c]; i < start[c + 1]; ++i) filter(i, i - start[c] + 1, mc, ox, oy, oz);
  }
}

// Traversal of a half Verlet list (this thread's share of the local particles): the listed partners
// of i go into the batch as they are (the list holds only pairs within cutoff + skin), less the
// frozen partners of a frozen i.
template <class Acc>
void traverse_verlet(const NeighborList& list, std::size_t n, const std::uint32_t* body, bool any_frozen, Acc& acc) {
  PairBatch& b = acc.batch();
  const std::uint32_t* off = list.offsets().data();
  const std::uint32_t* nbr = list.neighbors().data();
#pragma omp for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t k = off[i]; k < off[i + 1];) {
      if (b.m == PairBatch::kCapacity) acc.flush();
      const std::size_t m0 = b.m;
      const std::size_t take = std::min<std::size_t>(off[i + 1] - k, PairBatch::kCapacity - m0);
      std::size_t m = m0;
      if (any_frozen && body[i] != 0) {
        for (std::size_t q = 0; q < take; ++q) {
          b.j[m] = nbr[k + q];
          m += body[nbr[k + q]] == 0 ? 1 : 0;
        }
      } else {
        for (std::size_t q = 0; q < take; ++q) b.j[m0 + q] = nbr[k + q];
        m = m0 + take;
      }
      k += static_cast<std::uint32_t>(take);
      b.m = m;
      acc.mark_pairs_of(static_cast<std::uint32_t>(i), m0, b.m);
    }
  }
}

// Reduction of the per-thread buffers (inside the parallel region, after every thread's last flush):
// integer addition, so the result does not depend on the thread count. Each entry is cleared as it is
// read (its cache line is already there), which leaves the buffers all zero for the next call. Without
// ghosts the sums go straight to the outputs (forces, or the density array); with ghosts their
// integers go to ws.fixed, and the caller returns the ghost totals to their owners before converting.
template <int C>
void reduce_thread_buffers(PairWorkspace& ws, int nthreads, std::size_t n, std::size_t ntot, bool ghosts,
                           ParticleData& p, double* out, double* const* rate, int n_scalars) {
  if (!ghosts) {
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      std::int64_t s[C] = {};
      for (int u = 0; u < nthreads; ++u) {
        std::int64_t* bu = ws.buffers[static_cast<std::size_t>(u)].data();
        for (int q = 0; q < C; ++q) {
          s[q] += bu[C * i + q];
          bu[C * i + q] = 0;
        }
      }
      if constexpr (C >= 3) {
        p.fx[i] = static_cast<double>(s[0]) * kForceUnscale;
        p.fy[i] = static_cast<double>(s[1]) * kForceUnscale;
        p.fz[i] = static_cast<double>(s[2]) * kForceUnscale;
        for (int c = 0; c < C - 3 && c < n_scalars; ++c) rate[c][i] = static_cast<double>(s[3 + c]) * kForceUnscale;
      } else {
        out[i] = static_cast<double>(s[0]) * kForceUnscale;
      }
    }
  } else {
#pragma omp for schedule(static)
    for (std::size_t k = 0; k < C * ntot; ++k) {
      std::int64_t s = 0;
      for (int u = 0; u < nthreads; ++u) {
        s += ws.buffers[static_cast<std::size_t>(u)][k];
        ws.buffers[static_cast<std::size_t>(u)][k] = 0;
      }
      ws.fixed[k] = s;
    }
  }
}

// The shared loop: traverses every pair within the largest cutoff once (cell pairs or a half Verlet
// list), filters and batches them, evaluates `pass` on the batches and accumulates the per-particle
// integer totals (summed over threads) in job.out / p.f (no ghosts) or job.ws->fixed (with ghosts; the
// caller returns ghost totals first).
template <class Pass, bool kSums>
void run_loop(PairJob& job, const Pass& pass, double cutoff) {
  constexpr int C = Pass::kComponents;
  ParticleData& p = *job.p;
  const Box& box = *job.box;
  const NeighborList& list = *job.list;
  PairWorkspace& ws = *job.ws;
  const std::size_t n = p.n_local;
  const std::size_t ntot = p.size();  // local particles, then ghosts
  const bool ghosts = p.n_ghost > 0 || job.exchange;
  const int nthreads = prepare_workspace(ws, C, ntot, ghosts);
  const BatchGeometry geo = batch_geometry(p, box, job.noise, job.step, Pass::kScalars > 0 ? job.n_scalars : 0, job.scalar);
  // The filter keeps a relative margin so that no pair the exact evaluation would count is dropped
  // because the filter's displacement was rounded differently.
  const PairReal filter2 = static_cast<PairReal>(cutoff * cutoff * (1.0 + kFilterMargin));
  const bool any_frozen = !Pass::kSymmetric && any_frozen_particle(p);

#pragma omp parallel num_threads(nthreads)
  {
    const int t = omp_get_thread_num();
    std::vector<std::int64_t>& bufv = ws.buffers[static_cast<std::size_t>(t)];
    // Buffers are left all zero by the reduction, so only entries added by growth need zeroing here.
    // A buffer only grows: entries past C * ntot stay zero too (passes with 1 and 3 components alternate).
    if (bufv.size() < C * ntot) bufv.resize(C * ntot, 0);
    BatchAccumulator<Pass, kSums> acc(*ws.batches[static_cast<std::size_t>(t)], bufv.data(), pass, geo);
    if (list.cells_only()) {
      CandidateFilter filter(acc, p, filter2, any_frozen);
      traverse_cell_pairs(list, p, box, any_frozen, acc.batch(), filter);
    } else {
      traverse_verlet(list, n, reinterpret_cast<const std::uint32_t*>(p.body.data()), any_frozen, acc);
    }
    acc.finish(job.totals, job.overflow);
#pragma omp barrier
    reduce_thread_buffers<C>(ws, nthreads, n, ntot, ghosts, p, job.out, job.rate, job.n_scalars);
  }
}

// Listed pairs (job.pairs): the same passes as the loop's on a batch filled from the list, with the
// results subtracted. Serial; the lists are short (bonded pairs).
template <class Pass, bool kSums>
void run_listed(PairJob& job, const Pass& pass) {
  // Listed pairs subtract forces only (3 integers per particle); laws with scalars are refused with
  // bonds.exclude by their installers.
  if constexpr (Pass::kScalars > 0) throw std::logic_error("ForceCompute::subtract_pairs: not for a law with scalars");
  const ParticleData& p = *job.p;
  const Box& box = *job.box;
  PairWorkspace& ws = *job.ws;
  if (ws.batches.empty()) ws.batches.push_back(std::make_unique<PairBatch>());
  PairBatch& b = *ws.batches[0];
  const BatchGeometry geo = batch_geometry(p, box, job.noise, job.step, Pass::kScalars > 0 ? job.n_scalars : 0, job.scalar);
  std::int64_t local[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  std::int64_t* f = job.subtract_into;
  for (std::size_t k0 = 0; k0 < job.n_pairs; k0 += PairBatch::kCapacity) {
    const std::size_t m = std::min(PairBatch::kCapacity, job.n_pairs - k0);
    for (std::size_t k = 0; k < m; ++k) {
      const std::uint32_t i = job.pairs[2 * (k0 + k)], j = job.pairs[2 * (k0 + k) + 1];
      b.i[k] = i;
      b.j[k] = j;
      b.ix[k] = p.x[i];
      b.iy[k] = p.y[i];
      b.iz[k] = p.z[i];
      b.ivx[k] = p.vx[i];
      b.ivy[k] = p.vy[i];
      b.ivz[k] = p.vz[i];
      b.iid[k] = p.id[i];
    }
    evaluate_batch(b, m, pass, geo, local);
    take_batch_overflow(b, pass.fixed_limit, job.overflow);
    for (std::size_t k = 0; k < m; ++k) {
      const std::size_t i = b.i[k], j = b.j[k];
      f[3 * i] -= b.qx[k];
      f[3 * i + 1] -= b.qy[k];
      f[3 * i + 2] -= b.qz[k];
      f[3 * j] += b.qx[k];
      f[3 * j + 1] += b.qy[k];
      f[3 * j + 2] += b.qz[k];
    }
  }
  if constexpr (kSums)
    for (int q = 0; q < 9; ++q) job.totals[q] -= local[q];
}

template <class Pass>
void run_pass(PairJob& job, const Pass& pass, double cutoff) {
  if (job.with_sums)
    run_loop<Pass, true>(job, pass, cutoff);
  else
    run_loop<Pass, false>(job, pass, cutoff);
}

// Converts a double parameter table to the pair arithmetic type.
template <class Params, class Table>
std::vector<Params> converted(const Table& table) {
  std::vector<Params> out;
  out.reserve(table.params.size());
  for (const auto& q : table.params) out.push_back(q.template as<PairReal>());
  return out;
}

// Entry point of this target: one pair computation, dispatched over the compile-time list of laws.
void run_pair_job(PairJob& job) {
  if (job.laws != nullptr) {
    std::visit(
        [&](const auto& lt) {
          using Law = typename std::decay_t<decltype(lt)>::LawType;
          Law::with_evaluator(lt.table.params, [&](auto eval) {
            auto run = [&]<bool kSums>() {
              ForcePass<Law, decltype(eval), kSums> pass;
              pass.eval = eval;
              pass.params = lt.params_real.data();
              pass.ns = lt.loop_species;
              pass.inv_sqrt_dt = static_cast<PairReal>(1.0 / std::sqrt(job.dt));
              pass.species = job.p->species.data();
              pass.rho = job.rho;
              pass.fixed_limit = job.fixed_limit;
              pass.ids = job.p->id.data();
              pass.n_scalars = job.n_scalars;
              if (job.pairs != nullptr)
                run_listed<decltype(pass), kSums>(job, pass);
              else
                run_loop<decltype(pass), kSums>(job, pass, lt.table.max_cutoff);
            };
            if (job.with_sums)
              run.template operator()<true>();
            else
              run.template operator()<false>();
          });
        },
        *job.laws);
    return;
  }
  const DensitySettings& ds = *job.density;
  auto run = [&](auto kernel) {
    DensityPass<decltype(kernel)> pass;
    pass.kernel = kernel;
    pass.params = converted<DensityParamsT<PairReal>>(ds.table);
    pass.ns = distinct_species(pass.params, ds.table.n_species);
    pass.species = job.p->species.data();
    pass.fixed_limit = job.fixed_limit;
    pass.ids = job.p->id.data();
    run_pass(job, pass, ds.table.max_cutoff);
  };
  with_density_kernel(ds.kernel, run);
}

// The target this copy was compiled for (hwy's bit for it).
std::int64_t compiled_target() { return HWY_TARGET; }

}  // namespace HWY_NAMESPACE
}  // namespace mesodpd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace mesodpd {

HWY_EXPORT(run_pair_job);
HWY_EXPORT(compiled_target);

namespace {
// Applies MESODPD_SIMD (a cap on the instruction set) once, before the first dispatch.
void apply_simd_cap() {
  static const bool once = [] {
    const char* cap = std::getenv("MESODPD_SIMD");
    if (cap == nullptr) return true;
    const std::string c(cap);
    std::int64_t disable = 0;
    if (c == "avx2") disable = HWY_AVX3 | HWY_AVX3_DL;
    else if (c == "sse4") disable = HWY_AVX3 | HWY_AVX3_DL | HWY_AVX2;
    else if (c == "scalar") disable = HWY_AVX3 | HWY_AVX3_DL | HWY_AVX2 | HWY_SSE4 | HWY_SSSE3;
    else if (c != "avx512" && c != "best")
      throw ConfigError("MESODPD_SIMD = " + c + " (environment): expected avx512, avx2, sse4, scalar or best");
    hwy::DisableTargets(disable);
    return true;
  }();
  (void)once;
}
}  // namespace

std::string ForceCompute::simd_target() {
  apply_simd_cap();
  return hwy::TargetName(HWY_DYNAMIC_DISPATCH(compiled_target)());
}

std::vector<std::int64_t> ForceCompute::simd_targets() {
  std::vector<std::int64_t> out;
  for (std::int64_t t = hwy::SupportedTargets() & HWY_TARGETS; t != 0; t &= t - 1) out.push_back(t & -t);
  return out;
}

std::unique_ptr<PairBackend> make_pair_backend(PairLawTables laws, NoiseSettings noise) {
  return std::make_unique<ForceCompute>(std::move(laws), noise);
}

ForceCompute::ForceCompute(PairLawTables laws, NoiseSettings noise)
    : laws_(std::move(laws)), noise_(noise), ws_(std::make_unique<PairWorkspace>()) {}
ForceCompute::~ForceCompute() = default;
namespace {

// The per-pair limit of a loop over `list`: 2^51 (kPairFixedLimit), lowered where a particle may have
// more than 4096 partners so that the sum of its contributions cannot leave int64. Cells are at least
// a cutoff (plus skin) wide, so 27 times the fullest cell of the last build bounds any particle's
// candidates; counting costs one pass over the cells, nothing next to the pairs.
double pair_fixed_limit(const NeighborList& list, const ParticleData& p) {
  const std::vector<std::uint32_t>& cs = list.cell_start();
  std::uint64_t partners = p.size();
  if (cs.size() >= 2) {
    std::uint32_t fullest = 0;
    for (std::size_t c = 0; c + 1 < cs.size(); ++c)
      if (cs[c + 1] > cs[c]) fullest = std::max(fullest, cs[c + 1] - cs[c]);
    partners = std::min<std::uint64_t>(partners, 27 * static_cast<std::uint64_t>(fullest));
  }
  if (partners <= 4096) return kPairFixedLimit;
  return std::floor(9223372036854775808.0 / static_cast<double>(partners));  // 2^63 / partners
}

}  // namespace

ForceCompute::ForceCompute(ForceCompute&&) noexcept = default;
ForceCompute& ForceCompute::operator=(ForceCompute&&) noexcept = default;

void ForceCompute::compute(ParticleData& p, const Box& box, const NeighborList& list, std::uint64_t step,
                           double dt, bool with_sums, PairSums& sums, Halo* halo, const double* density) {
  apply_simd_cap();
  if (density == nullptr && std::visit([](const auto& t) { return std::decay_t<decltype(t)>::LawType::kDensity; }, laws_))
    throw std::logic_error("ForceCompute::compute: this pair law reads local densities; run compute_density first");
  PairJob job;
  job.p = &p;
  job.box = &box;
  job.list = &list;
  job.laws = &laws_;
  job.rho = density;
  job.step = step;
  job.dt = dt;
  job.noise = noise_;
  job.with_sums = with_sums;
  job.ws = ws_.get();
  job.fixed_limit = fixed_limit_ = pair_fixed_limit(list, p);
  job.exchange = halo != nullptr && halo->active();
  // A law with scalars: the leading ones of its fields that the particles hold (a model enables them).
  std::visit(
      [&](const auto& t) {
        using Law = typename std::decay_t<decltype(t)>::LawType;
        if constexpr (law_scalars<Law> > 0) {
          for (int c = 0; c < law_scalars<Law>; ++c) {
            std::vector<double>* v = p.doubles(Law::kScalarFields[static_cast<std::size_t>(c)]);
            std::vector<double>* r = p.doubles(Law::kScalarRates[static_cast<std::size_t>(c)]);
            if (v == nullptr || r == nullptr) break;
            job.scalar[c] = v->data();
            job.rate[c] = r->data();
            job.n_scalars = c + 1;
          }
          if (job.n_scalars == 0)
            throw std::logic_error("ForceCompute::compute: this pair law transports particle scalars; enable p." +
                                   std::string(Law::kScalarFields[0]) + " and p." + std::string(Law::kScalarRates[0]));
        }
      },
      laws_);
  HWY_DYNAMIC_DISPATCH(run_pair_job)(job);
  note(job.overflow);
  const std::size_t n = p.n_local;
  if (p.n_ghost > 0 || job.exchange) {
    std::int64_t* fixed = ws_->fixed.data();
    const int c = 3 + std::visit([](const auto& t) { return law_scalars<typename std::decay_t<decltype(t)>::LawType>; }, laws_);
    if (halo != nullptr) halo->reverse_sums(fixed, c, p);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      p.fx[i] = static_cast<double>(fixed[c * i]) * kForceUnscale;
      p.fy[i] = static_cast<double>(fixed[c * i + 1]) * kForceUnscale;
      p.fz[i] = static_cast<double>(fixed[c * i + 2]) * kForceUnscale;
      for (int q = 0; q < job.n_scalars; ++q) job.rate[q][i] = static_cast<double>(fixed[c * i + 3 + q]) * kForceUnscale;
    }
  }
  if (with_sums) {
    // Each pair was evaluated on exactly one rank: the integer totals add up to the single-rank ones.
    if (halo != nullptr) halo->comm().sum(std::span<std::int64_t>(job.totals, 9));
    for (int q = 0; q < 6; ++q) sums.virial[static_cast<std::size_t>(q)] = static_cast<double>(job.totals[q]) * kVirialUnscale;
    sums.virial_conservative = static_cast<double>(job.totals[6]) * kVirialUnscale;
    sums.potential_energy = static_cast<double>(job.totals[7]) * kVirialUnscale;
    sums.pairs_in_range = static_cast<std::uint64_t>(job.totals[8]);
  }
}

void ForceCompute::subtract_pairs(ParticleData& p, const Box& box, std::span<const std::uint32_t> pairs,
                                  std::uint64_t step, double dt, bool with_sums, std::int64_t* fixed,
                                  std::int64_t* totals, const double* density) {
  if (pairs.empty()) return;
  apply_simd_cap();
  PairJob job;
  job.p = &p;
  job.box = &box;
  job.laws = &laws_;
  job.rho = density;
  job.step = step;
  job.dt = dt;
  job.noise = noise_;
  job.with_sums = with_sums;
  job.ws = ws_.get();
  job.pairs = pairs.data();
  job.n_pairs = pairs.size() / 2;
  job.subtract_into = fixed;
  job.fixed_limit = fixed_limit_;
  HWY_DYNAMIC_DISPATCH(run_pair_job)(job);
  note(job.overflow);
  if (with_sums) {
    bool bad = false;
    for (int q = 0; q < 9; ++q) bad |= __builtin_add_overflow(totals[q], job.totals[q], &totals[q]);
    if (bad) {
      FixedPointOverflow o;
      o.what = FixedPointOverflow::What::PairVirial;
      o.value = std::numeric_limits<double>::infinity();
      o.limit = 9.2e18 * kVirialUnscale;
      note(o);
    }
  }
}

void ForceCompute::note(const std::optional<FixedPointOverflow>& found) {
  if (found && (!overflow_ || found->id_a < overflow_->id_a ||
                (found->id_a == overflow_->id_a && found->id_b < overflow_->id_b)))
    overflow_ = found;
}

void ForceCompute::compute_density(ParticleData& p, const Box& box, const NeighborList& list,
                                   const DensitySettings& density, std::span<double> rho, Halo* halo) {
  apply_simd_cap();
  if (rho.size() < p.size())
    throw std::invalid_argument("ForceCompute::compute_density: rho has " + std::to_string(rho.size()) +
                                " entries for " + std::to_string(p.size()) + " stored particles");
  PairJob job;
  job.p = &p;
  job.box = &box;
  job.list = &list;
  job.density = &density;
  job.out = rho.data();
  job.ws = ws_.get();
  job.fixed_limit = fixed_limit_ = pair_fixed_limit(list, p);
  job.exchange = halo != nullptr && halo->active();
  HWY_DYNAMIC_DISPATCH(run_pair_job)(job);
  note(job.overflow);
  if (p.n_ghost > 0 || job.exchange) {
    std::int64_t* fixed = ws_->fixed.data();
    if (halo != nullptr) halo->reverse_sums(fixed, 1, p);
    const std::size_t n = p.n_local;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) rho[i] = static_cast<double>(fixed[i]) * kForceUnscale;
    if (halo != nullptr) halo->forward_field(p, rho);
  }
}

}  // namespace mesodpd
#endif  // HWY_ONCE
