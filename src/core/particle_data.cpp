// Reordering of the particle arrays (spatial sorting), driven by the field list.
#include "core/particle_data.hpp"

#include <stdexcept>
#include <type_traits>
#include <string>

namespace mesodpd {

namespace {
template <class T>
void apply_order(std::vector<T>& v, const std::vector<std::uint32_t>& order, std::vector<T>& scratch,
                 std::size_t capacity) {
  const std::size_t n = order.size();
  if (scratch.capacity() < capacity) scratch.reserve(capacity);
  scratch.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) scratch[k] = v[order[k]];
  v.swap(scratch);
  v.resize(order.size());
}
}  // namespace

void ParticleData::permute(const std::vector<std::uint32_t>& order, std::size_t capacity, Forces forces) {
  for_each_field([&](const FieldInfo& f, auto& v) {
    using T = typename std::remove_reference_t<decltype(v)>::value_type;
    if (forces == Forces::Discard && (f.flags & field::kForce)) {
      if (v.capacity() < capacity) v.reserve(capacity);
      v.resize(order.size());
    } else {
      apply_order(v, order, spare<T>(), capacity);
    }
  });
  n_local = order.size();
  n_ghost = 0;
  last_order_.assign(order.begin(), order.end());
  permuted_from_ = generation_;
  generation_ = next_generation();
  permuted_to_ = generation_;
}

void ParticleData::enable(std::string_view name) {
  const std::size_t k = field_index(name);
  if (k == kFieldCount) throw std::invalid_argument("ParticleData::enable: no particle field '" + std::string(name) + "'");
  if (!(fields()[k].flags & field::kOptional)) return;  // always held
  if (enabled(k)) return;
  optional_on_ |= std::uint64_t{1} << k;
  const std::size_t n = id.size();  // the length of the last resize(), which may exceed size()
  for_each_field([&](const FieldInfo&, auto& v) {
    if (v.size() != n) v.resize(n, 0);
  });
  generation_ = next_generation();
}

std::vector<double>* ParticleData::doubles(std::string_view name) {
  std::vector<double>* out = nullptr;
  for_each_field([&](const FieldInfo& f, auto& v) {
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::vector<double>>)
      if (name == f.name) out = &v;
  });
  return out;
}

void ParticleData::enable_mask(std::uint64_t mask) {
  for (std::size_t k = 0; k < kFieldCount; ++k)
    if ((mask >> k) & 1u) enable(fields()[k].name);
}

}  // namespace mesodpd
