// Reordering of the particle arrays (spatial sorting).
#include "core/particle_data.hpp"

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
  for (auto* v : {&x, &y, &z, &vx, &vy, &vz, &hx, &hy, &hz}) apply_order(*v, order, spare_real_, capacity);
  for (auto* v : {&fx, &fy, &fz}) {
    if (forces == Forces::Keep) {
      apply_order(*v, order, spare_real_, capacity);
    } else {
      if (v->capacity() < capacity) v->reserve(capacity);
      v->resize(order.size());
    }
  }
  for (auto* v : {&species, &ix, &iy, &iz}) apply_order(*v, order, spare_int_, capacity);
  apply_order(id, order, spare_id_, capacity);
  n_local = order.size();
  n_ghost = 0;
}

}  // namespace mesodpd
