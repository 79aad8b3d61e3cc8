// Bonded forces over the topology: lookup by id, fixed-point accumulation, ghost forces to owners.
#include "engine/bonded_forces.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

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
                           double reach, std::uint32_t max_id, BondExclusion exclude)
    : topo_(std::move(topology)),
      bond_types_(std::move(bond_types)),
      angle_types_(std::move(angle_types)),
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

std::optional<BondProblem> BondedForces::compute(ParticleData& p, const Box& box, Halo& halo, bool with_sums,
                                                 PairSums& sums, const PairSubtractor& subtract,
                                                 std::vector<double>* fast, bool only_fast) {
  if (topo_.empty()) return std::nullopt;
  ids_.refresh(p);
  const std::size_t n = p.n_local;
  const std::size_t ntot = p.size();
  fixed_.assign(3 * ntot, 0);
  std::int64_t* f = fixed_.data();
  const double ilx = box.image_len(0), ily = box.image_len(1), ilz = box.image_len(2);
  const double hlx = box.half_image_len(0), hly = box.half_image_len(1), hlz = box.half_image_len(2);
  const std::size_t max_owner = bond_start_.size() - 2;
  // Integer sums: [0..5] virial tensor, [6] virial trace, [7] energy.
  std::int64_t acc[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  std::uint64_t problem = kNoProblem;

  auto displacement = [&](std::size_t i, std::size_t j, double d[3]) {
    d[0] = minimum_image(p.x[i] - p.x[j], ilx, hlx);
    d[1] = minimum_image(p.y[i] - p.y[j], ily, hly);
    d[2] = minimum_image(p.z[i] - p.z[j], ilz, hlz);
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

  // The terms owned by local particle i (global id u).
  // `a`: the thread's integer sums ([0..5] virial tensor, [6] its trace, [7] energy).
  auto terms = [&]<bool kAtomic>(std::size_t i, std::uint32_t u, std::int64_t* a, std::uint64_t& problem) {
    for (std::uint32_t k = bond_start_[u]; k < bond_start_[u + 1]; ++k) {
      const OwnedBond& b = owned_bonds_[k];
      const std::uint32_t j = ids_.find(b.partner);
      if (j == IdMap::kNotHere) {
        problem = std::min(problem, problem_key(BondProblem::TooLong, b.index));
        continue;
      }
      // d = r_a - r_b, the force on a is f_over_r d (the stored order of the bond, whichever atom owns it).
      const std::size_t ia = b.owner_first ? i : j, ib = b.owner_first ? j : i;
      double d[3];
      const double r2 = displacement(ia, ib, d);
      const BondForce bf = bond_force(bond_types_[static_cast<std::size_t>(b.type)], std::sqrt(r2));
      if (bf.broken) {
        problem = std::min(problem, problem_key(BondProblem::Broken, b.index));
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
    for (std::uint32_t k = angle_start_[u]; k < angle_start_[u + 1]; ++k) {
      const OwnedAngle& t = owned_angles_[k];
      const std::uint32_t ja = ids_.find(t.a), jc = ids_.find(t.c);
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
  };
  // Owners in storage order: their positions and forces are read in order, and bonded partners are
  // near in space, hence near in the cell-sorted storage. (Visiting owners in id order instead reads the
  // topology in order but the particle arrays at random; it was slower.)
  const bool atomic = omp_get_max_threads() > 1;
  auto run = [&]<bool kAtomic>() {
#pragma omp parallel for schedule(static) reduction(+ : acc[:8]) reduction(min : problem)
    for (std::size_t i = 0; i < n; ++i) {
      // The loop is bound by cache misses on a chain of dependent loads (the owner's entry in
      // bond_start_, its first bond, the partner's id-map entry, the partner's position and force), so
      // each link is prefetched a few owners ahead, the next link once the previous one has arrived.
      // Hints only: the results do not depend on them.
      if (i + 24 < n && p.id[i + 24] <= max_owner) __builtin_prefetch(bond_start_.data() + p.id[i + 24]);
      if (i + 16 < n && p.id[i + 16] <= max_owner) {
        const std::uint32_t k = bond_start_[p.id[i + 16]];
        if (k < owned_bonds_.size()) __builtin_prefetch(owned_bonds_.data() + k);
      }
      if (i + 8 < n && p.id[i + 8] <= max_owner) {
        const std::uint32_t v = p.id[i + 8];
        if (bond_start_[v] < bond_start_[v + 1]) ids_.prefetch(owned_bonds_[bond_start_[v]].partner);
      }
      if (i + 4 < n && p.id[i + 4] <= max_owner) {
        const std::uint32_t v = p.id[i + 4];
        if (bond_start_[v] < bond_start_[v + 1]) {
          const std::uint32_t j = ids_.find(owned_bonds_[bond_start_[v]].partner);
          if (j != IdMap::kNotHere) {
            __builtin_prefetch(p.x.data() + j);
            __builtin_prefetch(p.y.data() + j);
            __builtin_prefetch(p.z.data() + j);
            __builtin_prefetch(f + 3 * static_cast<std::size_t>(j), 1);
          }
        }
      }
      const std::uint32_t u = p.id[i];
      if (u > max_owner) continue;
      terms.template operator()<kAtomic>(i, u, acc, problem);
    }
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
    if (out.kind != BondProblem::AngleTooLong) {
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
  }
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
  const double il[3] = {box.image_len(0), box.image_len(1), box.image_len(2)};
  const double hl[3] = {box.half_image_len(0), box.half_image_len(1), box.half_image_len(2)};
  auto displacement = [&](std::uint32_t i, std::uint32_t j, double d[3]) {
    d[0] = minimum_image(p.x[i] - p.x[j], il[0], hl[0]);
    d[1] = minimum_image(p.y[i] - p.y[j], il[1], hl[1]);
    d[2] = minimum_image(p.z[i] - p.z[j], il[2], hl[2]);
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
}

}  // namespace mesodpd
