// Global particle id -> local storage index (owned and ghost), rebuilt only when asked for after the
// particles were reordered: bonded forces and other code that looks particles up by id use it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/particle_data.hpp"

namespace mesodpd {

// Which copy is found when an id is stored several times (an owned particle that is also a ghost of
// itself across a periodic boundary, or a ghost received twice along an axis with two ranks): the
// owned copy if this rank owns the particle, otherwise the ghost with the lowest storage index (ghosts
// are stored by ghost cell, so this is the copy in the lowest-numbered ghost cell, which depends only
// on the positions and the decomposition). Every copy holds the owner's wrapped position, so pair
// geometry through the minimum image is the same from any of them.
//
// Storage: a flat array over [smallest id, largest id] when the ids held are dense (span at most
// twice the count plus 1024: one rank, or ids in a compact range), 4 bytes per id of the span;
// otherwise an open-addressing hash table of (id, index) pairs with a load factor of at most 1/2,
// 16-32 bytes per particle held. Under MPI a rank holds ids scattered over the whole system, so a
// flat array would cost 4 bytes per particle of the whole system on every rank; the hash keeps the
// cost proportional to what the rank holds.
//
// Cost when nobody asks: none. ParticleData bumps its generation on every resize and permute (sort,
// migration, ghost construction); refresh() rebuilds only when the generation differs.
class IdMap {
 public:
  static constexpr std::uint32_t kNotHere = std::numeric_limits<std::uint32_t>::max();

  // Rebuilds the map for `p` if p changed since the last refresh (serial; call it outside parallel
  // regions, before lookups from several threads).
  void refresh(const ParticleData& p);
  // True when the map describes `p` as it is now.
  bool fresh(const ParticleData& p) const { return source_ == &p && generation_ == p.generation(); }
  // Storage index of `id` (see above for duplicates), or kNotHere if this rank holds no copy. Valid
  // only while fresh(p); safe to call from several threads.
  std::uint32_t find(std::uint32_t id) const;
  // refresh(p) then find(id).
  std::uint32_t find(const ParticleData& p, std::uint32_t id) {
    refresh(p);
    return find(id);
  }
  // Asks the CPU to fetch the table entry of `id` into cache ahead of a find() (a hint; no effect on results).
  void prefetch(std::uint32_t id) const {
    if (!hashed_) {
      const std::uint64_t k = std::uint64_t{id} - min_id_;
      if (id >= min_id_ && k < flat_.size()) __builtin_prefetch(flat_.data() + k);
    } else if (!keys_.empty()) {
      __builtin_prefetch(keys_.data() + slot_of(id, keys_.size() - 1));
    }
  }
  // Whether the last rebuild chose the hash table (for tests and the memory note above).
  bool hashed() const { return hashed_; }
  // Bytes of the map's tables.
  std::size_t memory_bytes() const {
    return flat_.capacity() * sizeof(std::uint32_t) + keys_.capacity() * sizeof(std::uint32_t) +
           values_.capacity() * sizeof(std::uint32_t);
  }
  // Rebuilds since construction (tests: checks that nothing is rebuilt without a reorder).
  std::uint64_t rebuilds() const { return rebuilds_; }

 private:
  static std::size_t slot_of(std::uint32_t id, std::size_t mask) {
    return static_cast<std::size_t>((static_cast<std::uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> 32) & mask;
  }

  const ParticleData* source_ = nullptr;
  bool hashed_ = false;
  std::uint64_t generation_ = 0;
  std::uint64_t rebuilds_ = 0;
  std::uint32_t min_id_ = 0;
  std::vector<std::uint32_t> flat_;          // flat_[id - min_id_]: storage index or kNotHere
  std::vector<std::uint32_t> keys_, values_;  // hash table; keys_ slot kEmpty when free
};

}  // namespace mesodpd
