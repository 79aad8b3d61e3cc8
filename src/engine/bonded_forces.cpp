// Bonded forces over the topology: lookup by id, fixed-point accumulation, ghost forces to owners.
#include "engine/bonded_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "engine/fixed_point.hpp"

namespace mesodpd {

namespace {

// CSR lists: entries of `owners` (one owner id per item) grouped by owner id.
void group_by_owner(const std::vector<std::uint32_t>& owners, std::uint32_t max_id, std::vector<std::uint32_t>& start,
                    std::vector<std::uint32_t>& items) {
  start.assign(static_cast<std::size_t>(max_id) + 2, 0);
  for (const std::uint32_t u : owners) ++start[static_cast<std::size_t>(u) + 1];
  for (std::size_t u = 1; u < start.size(); ++u) start[u] += start[u - 1];
  items.assign(owners.size(), 0);
  std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < owners.size(); ++k) items[next[owners[k]]++] = static_cast<std::uint32_t>(k);
}

// Integer adds: atomic when several threads may add to one particle (the result does not depend on
// their order), plain on one thread.
template <bool kAtomic>
inline void add(std::int64_t* f, std::size_t i, std::int64_t qx, std::int64_t qy, std::int64_t qz) {
  if constexpr (kAtomic) {
    std::atomic_ref<std::int64_t>(f[3 * i]).fetch_add(qx, std::memory_order_relaxed);
    std::atomic_ref<std::int64_t>(f[3 * i + 1]).fetch_add(qy, std::memory_order_relaxed);
    std::atomic_ref<std::int64_t>(f[3 * i + 2]).fetch_add(qz, std::memory_order_relaxed);
  } else {
    f[3 * i] += qx;
    f[3 * i + 1] += qy;
    f[3 * i + 2] += qz;
  }
}

constexpr std::uint64_t kNoProblem = std::numeric_limits<std::uint64_t>::max();
std::uint64_t problem_key(BondProblem::Kind kind, std::uint64_t index) {
  return (static_cast<std::uint64_t>(kind) << 40) | index;
}

}  // namespace

BondedForces::BondedForces(Topology topology, std::vector<BondParams> bond_types, std::vector<AngleParams> angle_types,
                           double reach, std::uint32_t max_id, BondExclusion exclude,
                           std::vector<DihedralParams> dihedral_types)
    : topo_(std::move(topology)),
      bond_types_(std::move(bond_types)),
      angle_types_(std::move(angle_types)),
      dihedral_types_(std::move(dihedral_types)),
      reach_(reach) {
  std::vector<std::uint32_t> owner, items;
  owner.reserve(topo_.bonds.size());
  for (const Bond& b : topo_.bonds) owner.push_back(std::min(b.a, b.b));
  group_by_owner(owner, max_id, bond_start_, items);
  for (const std::uint32_t k : items) {
    const Bond& b = topo_.bonds[k];
    owned_bonds_.push_back({b.a < b.b ? b.b : b.a, k, b.type, b.a < b.b ? 1 : 0});
  }
  owner.clear();
  for (const Angle& a : topo_.angles) owner.push_back(a.b);
  group_by_owner(owner, max_id, angle_start_, items);
  for (const std::uint32_t k : items) {
    const Angle& a = topo_.angles[k];
    owned_angles_.push_back({a.a, a.c, k, a.type});
  }
  owner.clear();
  for (const Dihedral& d : topo_.dihedrals) owner.push_back(d.b);
  group_by_owner(owner, max_id, dihedral_start_, items);
  for (const std::uint32_t k : items) {
    const Dihedral& d = topo_.dihedrals[k];
    owned_dihedrals_.push_back({d.a, d.c, d.d, k, d.type});
  }
  // Excluded pairs from the bond graph: bonded (1-2), and with 1-3 also two bonds apart.
  std::vector<std::uint64_t> pairs;
  auto key = [](std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t{a} << 32) | b : (std::uint64_t{b} << 32) | a;
  };
  if (exclude != BondExclusion::None) {
    for (const Bond& b : topo_.bonds) pairs.push_back(key(b.a, b.b));
    if (exclude == BondExclusion::OneThree) {
      std::vector<std::uint32_t> start, of;
      std::vector<std::uint32_t> ends;
      for (const Bond& b : topo_.bonds) {
        ends.push_back(b.a);
        ends.push_back(b.b);
      }
      group_by_owner(ends, max_id, start, of);  // of[] indexes ends: bond k is entries 2k, 2k + 1
      for (std::uint32_t c = 0; c <= max_id; ++c)
        for (std::uint32_t x = start[c]; x < start[c + 1]; ++x)
          for (std::uint32_t y = x + 1; y < start[c + 1]; ++y) {
            const std::uint32_t u = ends[of[x] ^ 1u], v = ends[of[y] ^ 1u];  // the other end of each bond
            if (u != v) pairs.push_back(key(u, v));
          }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  }
  owner.clear();
  for (const std::uint64_t k : pairs) owner.push_back(static_cast<std::uint32_t>(k >> 32));
  items.clear();
  group_by_owner(owner, max_id, excl_start_, items);
  excl_of_.resize(items.size());
  for (std::size_t k = 0; k < items.size(); ++k) excl_of_[k] = static_cast<std::uint32_t>(pairs[items[k]]);
}

namespace {

// CSR over n owners: start[i + 1] - start[i] = count(i), and fill(i, first) writes owner i's items from
// `first` and returns the end. On several threads counting and filling run in parallel; on one thread,
// when the number of items is known (`total`), a single pass does both. The layout depends on n and the
// counts alone.
constexpr std::size_t kUnknown = std::numeric_limits<std::size_t>::max();
template <class T, class Count, class Fill>
void build_grouped(std::size_t n, std::vector<std::uint32_t>& start, std::vector<T>& items, const Count& count,
                   const Fill& fill, std::size_t total = kUnknown) {
  start.resize(n + 1);
  start[0] = 0;
  if (total != kUnknown && omp_get_max_threads() == 1) {
    items.resize(total);
    T* out = items.data();
    for (std::size_t i = 0; i < n; ++i) {
      start[i] = static_cast<std::uint32_t>(out - items.data());
      out = fill(i, out);
    }
    start[n] = static_cast<std::uint32_t>(out - items.data());
    if (start[n] != total) throw std::logic_error("BondedForces: the lists lost or gained terms");
    return;
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) start[i + 1] = count(i);
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  items.resize(start[n]);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) fill(i, items.data() + start[i]);
}

}  // namespace

void BondedForces::lists_from_ids(const ParticleData& p) {
  ++list_rebuilds_;
  ids_.refresh(p);
  const std::size_t n = p.n_local;
  const std::size_t max_owner = bond_start_.size() - 2;
  auto range = [&](const std::vector<std::uint32_t>& start, std::size_t i) {
    const std::uint32_t u = p.id[i];
    return u > max_owner ? std::pair<std::uint32_t, std::uint32_t>{0, 0}
                         : std::pair<std::uint32_t, std::uint32_t>{start[u], start[u + 1]};
  };
  auto count_in = [&](const std::vector<std::uint32_t>& start) {
    return [&](std::size_t i) {
      const auto [lo, hi] = range(start, i);
      return hi - lo;
    };
  };
  build_grouped(
      p.n_local, lb_start_, lbonds_, count_in(bond_start_),
      [&](std::size_t i, LocalBond* out) {
        // Owners come in storage order, their ids at random: each lookup is a chain of dependent cache
        // misses (the owner's range, its first bond, the partner's id-map entry), so each link is
        // prefetched a few owners ahead, the next once the previous has arrived. Hints only.
        if (i + 16 < n && p.id[i + 16] <= max_owner) __builtin_prefetch(bond_start_.data() + p.id[i + 16]);
        if (i + 8 < n && p.id[i + 8] <= max_owner) __builtin_prefetch(owned_bonds_.data() + bond_start_[p.id[i + 8]]);
        if (i + 4 < n && p.id[i + 4] <= max_owner) {
          const std::uint32_t v = p.id[i + 4];
          if (bond_start_[v] < bond_start_[v + 1]) ids_.prefetch(owned_bonds_[bond_start_[v]].partner);
        }
        const auto [lo, hi] = range(bond_start_, i);
        for (std::uint32_t k = lo; k < hi; ++k) {
          const OwnedBond& b = owned_bonds_[k];
          *out++ = {ids_.find(b.partner), static_cast<std::uint32_t>(b.type) << 1 | static_cast<std::uint32_t>(b.owner_first)};
        }
        return out;
      });
  if (owned_angles_.empty()) {
    la_start_.assign(p.n_local + 1, 0);
  } else {
    build_grouped(
        p.n_local, la_start_, langles_, count_in(angle_start_),
        [&](std::size_t i, LocalAngle* out) {
          const auto [lo, hi] = range(angle_start_, i);
          for (std::uint32_t k = lo; k < hi; ++k) {
            const OwnedAngle& t = owned_angles_[k];
            *out++ = {ids_.find(t.a), ids_.find(t.c), t.index, t.type};
          }
          return out;
        });
  }
  if (owned_dihedrals_.empty()) {
    ld_start_.assign(p.n_local + 1, 0);
    return;
  }
  build_grouped(
      p.n_local, ld_start_, ldihedrals_, count_in(dihedral_start_),
      [&](std::size_t i, LocalDihedral* out) {
        const auto [lo, hi] = range(dihedral_start_, i);
        for (std::uint32_t k = lo; k < hi; ++k) {
          const OwnedDihedral& t = owned_dihedrals_[k];
          *out++ = {ids_.find(t.a), ids_.find(t.c), ids_.find(t.d), t.index, t.type};
        }
        return out;
      });
}

void BondedForces::lists_through(const std::vector<std::uint32_t>& order) {
  const std::size_t n = order.size();
  new_of_old_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) new_of_old_[order[k]] = static_cast<std::uint32_t>(k);
  auto moved = [&](std::uint32_t j) { return j == IdMap::kNotHere ? j : new_of_old_[j]; };
  // One kind of term: its groups taken in the new order of their owners, partners renumbered by `move`.
  auto follow = [&](std::vector<std::uint32_t>& start, auto& items, auto& spare, const auto& move) {
    using Item = typename std::remove_reference_t<decltype(items)>::value_type;
    build_grouped(
        n, spare_start_, spare, [&](std::size_t k) { return start[order[k] + 1] - start[order[k]]; },
        [&](std::size_t k, Item* out) {
          for (std::uint32_t e = start[order[k]]; e < start[order[k] + 1]; ++e) {
            Item t = items[e];
            move(t);
            *out++ = t;
          }
          return out;
        },
        items.size());
    start.swap(spare_start_);
    items.swap(spare);
  };
  follow(lb_start_, lbonds_, spare_bonds_, [&](LocalBond& b) { b.j = moved(b.j); });
  // Without angles or dihedrals their starts are n + 1 zeros already.
  if (!owned_angles_.empty())
    follow(la_start_, langles_, spare_angles_, [&](LocalAngle& t) {
      t.ja = moved(t.ja);
      t.jc = moved(t.jc);
    });
  if (!owned_dihedrals_.empty())
    follow(ld_start_, ldihedrals_, spare_dihedrals_, [&](LocalDihedral& t) {
      t.ja = moved(t.ja);
      t.jc = moved(t.jc);
      t.jd = moved(t.jd);
    });
}

void BondedForces::prepare_lists(const ParticleData& p) {
  if (list_source_ == &p && list_generation_ == p.generation()) return;
  const std::vector<std::uint32_t>* order =
      list_source_ == &p && !list_has_ghosts_ && p.n_ghost == 0 ? p.permutation_since(list_generation_) : nullptr;
  if (order != nullptr && order->size() + 1 == lb_start_.size() && order->size() + 1 == la_start_.size() &&
      order->size() + 1 == ld_start_.size())
    lists_through(*order);
  else
    lists_from_ids(p);
  list_source_ = &p;
  list_generation_ = p.generation();
  list_has_ghosts_ = p.n_ghost > 0;
}

std::optional<BondProblem> BondedForces::compute(ParticleData& p, const Box& box, Halo& halo, bool with_sums,
                                                 PairSums& sums, const PairSubtractor& subtract,
                                                 std::vector<double>* fast, bool only_fast) {
  if (topo_.empty()) return std::nullopt;
  prepare_lists(p);
  const std::size_t n = p.n_local;
  const std::size_t ntot = p.size();
  // The integer forces start at zero: the conversion at the end zeroes what it reads (one pass over
  // the buffer fewer than clearing it here); after an early return it is cleared here.
  if (!fixed_zero_) std::fill(fixed_.begin(), fixed_.end(), 0);
  if (fixed_.size() < 3 * ntot) fixed_.resize(3 * ntot, 0);
  fixed_zero_ = false;
  std::int64_t* f = fixed_.data();
  const double ilx = box.image_len(0), ily = box.image_len(1), ilz = box.image_len(2);
  const double hlx = box.half_image_len(0), hly = box.half_image_len(1), hlz = box.half_image_len(2);
  const std::size_t max_owner = bond_start_.size() - 2;
  // Integer sums: [0..5] virial tensor, [6] virial trace, [7] energy.
  std::int64_t acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::uint64_t problem = kNoProblem;

  const bool sheared = box.sheared();
  auto displacement = [&](std::size_t i, std::size_t j, double d[3]) {
    if (sheared) {  // Lees-Edwards images
      d[0] = p.x[i] - p.x[j];
      d[1] = p.y[i] - p.y[j];
      d[2] = p.z[i] - p.z[j];
      box_displacement(box, d);
    } else {
      d[0] = minimum_image(p.x[i] - p.x[j], ilx, hlx);
      d[1] = minimum_image(p.y[i] - p.y[j], ily, hly);
      d[2] = minimum_image(p.z[i] - p.z[j], ilz, hlz);
    }
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  };
  auto virial = [](std::int64_t* a, const double d[3], const double F[3]) {
    a[0] += to_fixed(d[0] * F[0], kVirialScale);
    a[1] += to_fixed(d[1] * F[1], kVirialScale);
    a[2] += to_fixed(d[2] * F[2], kVirialScale);
    a[3] += to_fixed(d[0] * F[1], kVirialScale);
    a[4] += to_fixed(d[0] * F[2], kVirialScale);
    a[5] += to_fixed(d[1] * F[2], kVirialScale);
    a[6] += to_fixed(d[0] * F[0] + d[1] * F[1] + d[2] * F[2], kVirialScale);
  };

  constexpr std::uint32_t kAhead = 8;
  // The terms owned by local particle i.
  // `a`: the thread's integer sums ([0..5] virial tensor, [6] its trace, [7] energy).
  auto terms = [&]<bool kAtomic>(std::size_t i, std::int64_t* a, std::uint64_t& problem) {
    for (std::uint32_t k = lb_start_[i]; k < lb_start_[i + 1]; ++k) {
      // Partners a sort layer away in storage are often not in cache yet: fetch them a few bonds ahead
      // (a hint; results do not depend on it).
      if (k + kAhead < lbonds_.size()) {
        const std::uint32_t jn = lbonds_[k + kAhead].j;
        if (jn < ntot) {
          __builtin_prefetch(p.x.data() + jn);
          __builtin_prefetch(p.y.data() + jn);
          __builtin_prefetch(p.z.data() + jn);
          __builtin_prefetch(f + 3 * static_cast<std::size_t>(jn), 1);
        }
      }
      const LocalBond& b = lbonds_[k];
      const std::uint32_t j = b.j;
      auto index = [&] { return owned_bonds_[bond_start_[p.id[i]] + (k - lb_start_[i])].index; };
      if (j == IdMap::kNotHere) {
        problem = std::min(problem, problem_key(BondProblem::TooLong, index()));
        continue;
      }
      // d = r_a - r_b, the force on a is f_over_r d (the stored order of the bond, whichever atom owns it).
      const bool owner_first = (b.meta & 1u) != 0;
      const std::size_t ia = owner_first ? i : j, ib = owner_first ? j : i;
      double d[3];
      const double r2 = displacement(ia, ib, d);
      const BondForce bf = bond_force(bond_types_[b.meta >> 1], std::sqrt(r2));
      if (bf.broken) {
        problem = std::min(problem, problem_key(BondProblem::Broken, index()));
        continue;
      }
      const double F[3] = {bf.f_over_r * d[0], bf.f_over_r * d[1], bf.f_over_r * d[2]};
      const std::int64_t qx = to_fixed(F[0], kForceScale), qy = to_fixed(F[1], kForceScale),
                         qz = to_fixed(F[2], kForceScale);
      add<kAtomic>(f, ia, qx, qy, qz);
      add<kAtomic>(f, ib, -qx, -qy, -qz);
      if (with_sums) {
        virial(a, d, F);
        a[7] += to_fixed(bf.energy, kVirialScale);
      }
    }
    // (Without angles or dihedrals their starts are n + 1 zeros: the loops are empty.)
    for (std::uint32_t k = la_start_[i]; k < la_start_[i + 1]; ++k) {
      const LocalAngle& t = langles_[k];
      const std::uint32_t ja = t.ja, jc = t.jc;
      if (ja == IdMap::kNotHere || jc == IdMap::kNotHere) {
        problem = std::min(problem, problem_key(BondProblem::AngleTooLong, t.index));
        continue;
      }
      double b1[3], b2[3];  // b1 = r_b - r_a, b2 = r_c - r_b
      displacement(i, ja, b1);
      displacement(jc, i, b2);
      const AngleForce af = angle_force(angle_types_[static_cast<std::size_t>(t.type)], b1, b2);
      const std::int64_t q1[3] = {to_fixed(af.f1[0], kForceScale), to_fixed(af.f1[1], kForceScale),
                                  to_fixed(af.f1[2], kForceScale)};
      const std::int64_t q3[3] = {to_fixed(af.f3[0], kForceScale), to_fixed(af.f3[1], kForceScale),
                                  to_fixed(af.f3[2], kForceScale)};
      add<kAtomic>(f, ja, q1[0], q1[1], q1[2]);
      add<kAtomic>(f, jc, q3[0], q3[1], q3[2]);
      add<kAtomic>(f, i, -(q1[0] + q3[0]), -(q1[1] + q3[1]), -(q1[2] + q3[2]));
      if (with_sums) {
        // sum over atoms of r (x) F with r_a = r_b - b1, r_c = r_b + b2: -b1 (x) F1 + b2 (x) F3.
        const double m1[3] = {-b1[0], -b1[1], -b1[2]};
        virial(a, m1, af.f1);
        virial(a, b2, af.f3);
        a[7] += to_fixed(af.energy, kVirialScale);
      }
    }
    for (std::uint32_t k = ld_start_[i]; k < ld_start_[i + 1]; ++k) {
      const LocalDihedral& t = ldihedrals_[k];
      const std::uint32_t ja = t.ja, jc = t.jc, jd = t.jd;
      if (ja == IdMap::kNotHere || jc == IdMap::kNotHere || jd == IdMap::kNotHere) {
        problem = std::min(problem, problem_key(BondProblem::DihedralTooLong, t.index));
        continue;
      }
      double ra[3], rc[3], rd[3];  // a, c and d relative to b (the owner i), nearest images
      displacement(ja, i, ra);
      displacement(jc, i, rc);
      displacement(jd, i, rd);
      const DihedralForce df = dihedral_force(dihedral_types_[static_cast<std::size_t>(t.type)], ra, rc, rd);
      const std::int64_t qa[3] = {to_fixed(df.fa[0], kForceScale), to_fixed(df.fa[1], kForceScale),
                                  to_fixed(df.fa[2], kForceScale)};
      const std::int64_t qc[3] = {to_fixed(df.fc[0], kForceScale), to_fixed(df.fc[1], kForceScale),
                                  to_fixed(df.fc[2], kForceScale)};
      const std::int64_t qd[3] = {to_fixed(df.fd[0], kForceScale), to_fixed(df.fd[1], kForceScale),
                                  to_fixed(df.fd[2], kForceScale)};
      add<kAtomic>(f, ja, qa[0], qa[1], qa[2]);
      add<kAtomic>(f, jc, qc[0], qc[1], qc[2]);
      add<kAtomic>(f, jd, qd[0], qd[1], qd[2]);
      // b gets minus the others' integers, so the four sum to zero exactly (momentum to the last bit).
      add<kAtomic>(f, i, -(qa[0] + qc[0] + qd[0]), -(qa[1] + qc[1] + qd[1]), -(qa[2] + qc[2] + qd[2]));
      if (with_sums) {
        // sum over atoms of r (x) F, relative to b (the forces sum to zero).
        virial(a, ra, df.fa);
        virial(a, rc, df.fc);
        virial(a, rd, df.fd);
        a[7] += to_fixed(df.energy, kVirialScale);
      }
    }
  };
  // Owners in storage order: their positions and forces are read in order, and bonded partners are
  // near in space, hence near in the cell-sorted storage, so the partners' data is mostly in cache.
  const bool atomic = omp_get_max_threads() > 1;
  auto run = [&]<bool kAtomic>() {
#pragma omp parallel for schedule(static) reduction(+ : acc[:8]) reduction(min : problem)
    for (std::size_t i = 0; i < n; ++i) terms.template operator()<kAtomic>(i, acc, problem);
  };
  if (atomic)
    run.template operator()<true>();
  else
    run.template operator()<false>();

  const Comm& comm = halo.comm();
  if (comm.distributed()) problem = comm.min(problem);
  if (problem != kNoProblem) {
    BondProblem out;
    out.kind = static_cast<BondProblem::Kind>(problem >> 40);
    out.index = problem & ((std::uint64_t{1} << 40) - 1);
    // The length, from whichever rank holds both atoms (others add zero).
    double len = 0;
    ids_.refresh(p);
    if (out.kind == BondProblem::Broken || out.kind == BondProblem::TooLong) {
      const Bond& b = topo_.bonds[out.index];
      const std::uint32_t ia = ids_.find(b.a), ib = ids_.find(b.b);
      const std::uint32_t owner = b.a < b.b ? ia : ib;  // the rank that evaluates the bond reports it
      if (ia != IdMap::kNotHere && ib != IdMap::kNotHere && owner < n) {
        double d[3];
        len = std::sqrt(displacement(ia, ib, d));
      }
    }
    if (comm.distributed()) {
      double v[1] = {len};
      comm.sum(std::span<double>(v, 1));
      len = v[0];
    }
    out.length = len;
    return out;
  }
  // Multiple time stepping: the bonded force alone, per local particle, for the inner steps.
  if (fast != nullptr) {
    if (halo.active()) halo.reverse_forces(f, p);
    fast->resize(3 * n);
    double* out = fast->data();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < 3 * n; ++i) out[i] = static_cast<double>(f[i]) * kForceUnscale;
    if (only_fast) return std::nullopt;
    std::fill(fixed_.begin(), fixed_.end(), 0);  // what follows adds the exclusions alone to p
  }
  // Excluded pairs: the pair loop's integers for them, subtracted (before ghost forces go home).
  std::int64_t excl_totals[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  if (!excl_of_.empty() && subtract) {
    ids_.refresh(p);
    excl_pairs_.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t u = p.id[i];
      if (u > max_owner) continue;
      for (std::uint32_t k = excl_start_[u]; k < excl_start_[u + 1]; ++k) {
        const std::uint32_t j = ids_.find(excl_of_[k]);
        if (j == IdMap::kNotHere) continue;  // farther than the ghost layer: no pair force to remove
        excl_pairs_.push_back(static_cast<std::uint32_t>(i));
        excl_pairs_.push_back(j);
      }
    }
    subtract(excl_pairs_, f, excl_totals);
  }
  // (Collective: the condition is the same on every rank, the topology being known to all.)
  if (halo.active() && (fast == nullptr || (!excl_of_.empty() && subtract))) halo.reverse_forces(f, p);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    p.fx[i] += static_cast<double>(f[3 * i]) * kForceUnscale;
    p.fy[i] += static_cast<double>(f[3 * i + 1]) * kForceUnscale;
    p.fz[i] += static_cast<double>(f[3 * i + 2]) * kForceUnscale;
    f[3 * i] = f[3 * i + 1] = f[3 * i + 2] = 0;
  }
  std::fill(fixed_.begin() + static_cast<std::ptrdiff_t>(3 * n), fixed_.end(), 0);  // the ghosts' entries
  fixed_zero_ = true;
  if (with_sums) {
    std::int64_t t[9];
    for (int q = 0; q < 8; ++q) t[q] = acc[q] + excl_totals[q];
    t[8] = excl_totals[8];
    if (comm.distributed()) comm.sum(std::span<std::int64_t>(t, 9));
    for (int q = 0; q < 6; ++q) sums.virial[static_cast<std::size_t>(q)] += static_cast<double>(t[q]) * kVirialUnscale;
    sums.virial_conservative += static_cast<double>(t[6]) * kVirialUnscale;
    sums.potential_energy += static_cast<double>(t[7]) * kVirialUnscale;
    sums.pairs_in_range = static_cast<std::uint64_t>(static_cast<std::int64_t>(sums.pairs_in_range) + t[8]);
  }
  return std::nullopt;
}

bool BondedForces::excluded(std::uint32_t a, std::uint32_t b) const {
  const std::uint32_t u = std::min(a, b), v = std::max(a, b);
  if (excl_start_.empty() || static_cast<std::size_t>(u) + 1 >= excl_start_.size()) return false;
  const auto first = excl_of_.begin() + excl_start_[u], last = excl_of_.begin() + excl_start_[u + 1];
  return std::find(first, last, v) != last;
}

void BondedForces::virial_terms(const ParticleData& p, const Box& box, VirialTerms& out) const {
  if (topo_.empty()) return;
  // Storage index by id over the locals.
  std::vector<std::uint32_t> at(bond_start_.size(), IdMap::kNotHere);
  for (std::size_t i = 0; i < p.n_local; ++i)
    if (p.id[i] < at.size()) at[p.id[i]] = static_cast<std::uint32_t>(i);
  auto index = [&](std::uint32_t id) {
    const std::uint32_t k = id < at.size() ? at[id] : IdMap::kNotHere;
    if (k == IdMap::kNotHere) throw std::logic_error("BondedForces::virial_terms: a bonded atom is missing");
    return k;
  };
  auto displacement = [&](std::uint32_t i, std::uint32_t j, double d[3]) {
    d[0] = p.x[i] - p.x[j];
    d[1] = p.y[i] - p.y[j];
    d[2] = p.z[i] - p.z[j];
    box_displacement(box, d);  // minimum image, with the Lees-Edwards images if any
  };
  for (const Bond& b : topo_.bonds) {
    VirialTerm t;
    t.i = index(b.a);
    t.j = index(b.b);
    displacement(t.i, t.j, t.d);
    const BondForce bf = bond_force(bond_types_[static_cast<std::size_t>(b.type)],
                                    std::sqrt(t.d[0] * t.d[0] + t.d[1] * t.d[1] + t.d[2] * t.d[2]));
    for (int c = 0; c < 3; ++c) t.f[c] = bf.f_over_r * t.d[c];  // zero for a broken bond, which stops a run
    out.push_back(t);
  }
  for (const Angle& a : topo_.angles) {
    const std::uint32_t ia = index(a.a), ib = index(a.b), ic = index(a.c);
    double b1[3], b2[3];  // b1 = r_b - r_a, b2 = r_c - r_b, as compute() takes them
    displacement(ib, ia, b1);
    displacement(ic, ib, b2);
    const AngleForce af = angle_force(angle_types_[static_cast<std::size_t>(a.type)], b1, b2);
    VirialTerm ta, tc;
    ta.i = ia, ta.j = ib, tc.i = ic, tc.j = ib;
    for (int c = 0; c < 3; ++c) {
      ta.d[c] = -b1[c];
      ta.f[c] = af.f1[c];
      tc.d[c] = b2[c];
      tc.f[c] = af.f3[c];
    }
    out.push_back(ta);
    out.push_back(tc);
  }
  for (const Dihedral& h : topo_.dihedrals) {
    const std::uint32_t ia = index(h.a), ib = index(h.b), ic = index(h.c), id = index(h.d);
    double ra[3], rc[3], rd[3];
    displacement(ia, ib, ra);
    displacement(ic, ib, rc);
    displacement(id, ib, rd);
    const DihedralForce df = dihedral_force(dihedral_types_[static_cast<std::size_t>(h.type)], ra, rc, rd);
    const std::uint32_t who[3] = {ia, ic, id};
    const double* d[3] = {ra, rc, rd};
    const double* fo[3] = {df.fa, df.fc, df.fd};
    for (int q = 0; q < 3; ++q) {
      VirialTerm t;
      t.i = who[q];
      t.j = ib;
      for (int c = 0; c < 3; ++c) {
        t.d[c] = d[q][c];
        t.f[c] = fo[q][c];
      }
      out.push_back(t);
    }
  }
}

}  // namespace mesodpd
