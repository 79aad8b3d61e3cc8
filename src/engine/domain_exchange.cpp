// The order of migration, cell sort, ghost construction and list building, for one rank or many.
#include "engine/domain_exchange.hpp"

#include <algorithm>
#include <limits>

namespace mesodpd {

std::optional<EscapedParticle> apply_box_boundaries(ParticleData& p, const Box& box, const Comm& comm) {
  const std::size_t n = p.n_local;
  if (box.sheared()) {
    // Lees-Edwards: a crossing of the gradient axis first, which moves the particle along the flow axis
    // by the image offset and changes its flow velocity (both the current one and the half-step one of
    // velocity Verlet) by the image velocity; then the plain wrap of every axis.
    const int g = box.shear.gradient, f = box.shear.flow;
    std::vector<double>* r[3] = {&p.x, &p.y, &p.z};
    std::vector<double>* v[2][3] = {{&p.vx, &p.vy, &p.vz}, {&p.hx, &p.hy, &p.hz}};
    std::vector<std::int32_t>* image[3] = {&p.ix, &p.iy, &p.iz};
    double* rg = r[g]->data();
    double* rf = r[f]->data();
    std::int32_t* ig = image[g]->data();
    double* vf = v[0][f]->data();
    double* hf = v[1][f]->data();
    const bool half = p.hx.size() >= n;
    const double du = box.shear.velocity;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double k = wrap_sheared_gradient(box, rg[i], ig[i], rf[i]);
      if (k != 0.0) {
        vf[i] -= k * du;
        if (half) hf[i] -= k * du;
      }
    }
  }
  if (box.all_periodic()) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      wrap_coordinate(p.x[i], p.ix[i], box.len.x);
      wrap_coordinate(p.y[i], p.iy[i], box.len.y);
      wrap_coordinate(p.z[i], p.iz[i], box.len.z);
    }
    return std::nullopt;
  }
  std::vector<double>* r[3] = {&p.x, &p.y, &p.z};
  std::vector<std::int32_t>* image[3] = {&p.ix, &p.iy, &p.iz};
  // Index of the escaped particle with the smallest id on this rank (n: none). NaN is not "outside":
  // the health check reports it as a blow-up.
  auto outside = [&](std::size_t i, int d) {
    const double v = (*r[d])[i];
    return v < 0.0 || v >= box.length(d);
  };
  std::size_t first = n;
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    if (box.periodic[u]) {
      const double len = box.length(d);
      double* v = r[d]->data();
      std::int32_t* im = image[d]->data();
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i) wrap_coordinate(v[i], im[i], len);
      continue;
    }
    std::size_t bad = n;
#pragma omp parallel for reduction(min : bad) schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      if (outside(i, d)) bad = std::min(bad, i);
    for (std::size_t i = bad; i < n; ++i)
      if (outside(i, d) && (first == n || p.id[i] < p.id[first])) first = i;
  }
  std::uint64_t id = first == n ? std::numeric_limits<std::uint64_t>::max() : p.id[first];
  if (comm.distributed()) id = comm.min(id);
  if (id == std::numeric_limits<std::uint64_t>::max()) return std::nullopt;
  // The owner contributes the particle's position and axis; the others add zeros.
  double state[4] = {0, 0, 0, 0};
  if (first != n && p.id[first] == id) {
    int axis = 0;
    while (axis < 2 && !(!box.periodic[static_cast<std::size_t>(axis)] && outside(first, axis))) ++axis;
    state[0] = p.x[first];
    state[1] = p.y[first];
    state[2] = p.z[first];
    state[3] = axis;
  }
  if (comm.distributed()) comm.sum(std::span<double>(state, 4));
  return EscapedParticle{static_cast<std::uint32_t>(id), static_cast<int>(state[3]), state[0], state[1], state[2]};
}

void rebuild_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo, ParticleData::Forces forces) {
  if (!halo.active()) {
    list.build(p, box, forces);
    return;
  }
  list.set_grid(box, halo.cell_domain());
  halo.migrate(p, list.grid());  // drops the old ghosts; particles change ranks only here
  list.sort_locals(p, forces);
  halo.build_ghosts(p, list.grid(), list.cell_start());
  list.finish(p, box, halo.ghost_counts());
}

bool update_neighbors(NeighborList& list, ParticleData& p, const Box& box, Halo& halo) {
  bool rebuild = list.needs_rebuild(p, box);
  // With a skin the answer differs between ranks; all rebuild together (migration and ghosts are
  // collective), exactly when a single rank holding every particle would.
  if (list.settings().skin > 0.0 && halo.comm().distributed())
    rebuild = halo.comm().max(rebuild ? std::uint64_t{1} : std::uint64_t{0}) != 0;
  if (rebuild)
    rebuild_neighbors(list, p, box, halo);
  else
    halo.update_ghosts(p);
  return rebuild;
}

}  // namespace mesodpd
