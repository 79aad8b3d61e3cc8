// Building and querying the global id -> storage index map.
#include "core/id_map.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace mesodpd {

namespace {
// An id that no particle has: ids are 32-bit and start at 1, and kNotHere is the largest value.
constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
}  // namespace

void IdMap::refresh(const ParticleData& p) {
  if (fresh(p)) return;
  const std::size_t n = p.size();
  if (n >= kNotHere) throw std::length_error("IdMap: more particles than 32-bit indices");
  std::uint32_t lo = std::numeric_limits<std::uint32_t>::max(), hi = 0;
  for (std::size_t i = 0; i < n; ++i) {
    lo = std::min(lo, p.id[i]);
    hi = std::max(hi, p.id[i]);
  }
  const std::uint64_t span = n == 0 ? 0 : std::uint64_t{hi} - lo + 1;
  hashed_ = span > 2 * static_cast<std::uint64_t>(n) + 1024;
  // Storage order ascending, first copy kept: locals (owned) before ghosts, ghosts by storage index.
  if (!hashed_) {
    keys_.clear();
    values_.clear();
    min_id_ = lo;
    flat_.assign(static_cast<std::size_t>(span), kNotHere);
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t& slot = flat_[p.id[i] - lo];
      if (slot == kNotHere) slot = static_cast<std::uint32_t>(i);
    }
  } else {
    flat_.clear();
    const std::size_t capacity = std::bit_ceil(std::max<std::size_t>(16, 2 * n));
    keys_.assign(capacity, kEmpty);
    values_.resize(capacity);
    const std::size_t mask = capacity - 1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t id = p.id[i];
      std::size_t s = slot_of(id, mask);
      while (keys_[s] != kEmpty && keys_[s] != id) s = (s + 1) & mask;
      if (keys_[s] == kEmpty) {
        keys_[s] = id;
        values_[s] = static_cast<std::uint32_t>(i);
      }
    }
  }
  generation_ = p.generation();
  source_ = &p;
  ++rebuilds_;
}

std::uint32_t IdMap::find(std::uint32_t id) const {
  if (!hashed_) {
    const std::uint64_t k = std::uint64_t{id} - min_id_;
    return id >= min_id_ && k < flat_.size() ? flat_[static_cast<std::size_t>(k)] : kNotHere;
  }
  if (id == kEmpty || keys_.empty()) return kNotHere;
  const std::size_t mask = keys_.size() - 1;
  for (std::size_t s = slot_of(id, mask);; s = (s + 1) & mask) {
    if (keys_[s] == id) return values_[s];
    if (keys_[s] == kEmpty) return kNotHere;
  }
}

}  // namespace mesodpd
