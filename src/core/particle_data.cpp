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

void ParticleData::permute(const std::vector<std::uint32_t>& order, std::size_t capacity) {
  std::vector<double> sd;
  for (auto* v : {&x, &y, &z, &vx, &vy, &vz, &fx, &fy, &fz, &hx, &hy, &hz}) apply_order(*v, order, sd, capacity);
  std::vector<std::int32_t> si;
  for (auto* v : {&species, &ix, &iy, &iz}) apply_order(*v, order, si, capacity);
  std::vector<std::uint32_t> su;
  apply_order(id, order, su, capacity);
  n_local = order.size();
  n_ghost = 0;
}

}  // namespace mesodpd
