// Cell-binned construction of the half Verlet list, with optional spatial sorting.
#include "neighbor/neighbor_list.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mesodpd {

bool NeighborList::needs_rebuild(const ParticleData& p, const Box& box) const {
  if (settings_.skin <= 0.0) return true;
  int moved = (builds_ == 0 || x0_.size() != p.n_local) ? 1 : 0;
  if (!moved) {
    // With Lees-Edwards images a pair across the gradient faces also moves apart by the change of the
    // image offset since the build, drift; and a particle that crossed those faces was moved by the
    // offset of its crossing, which the displacement below measures with today's offset, off by at most
    // drift. The list stays valid while 2 (max displacement + drift) + drift <= skin.
    double drift = 0.0;
    if (box.sheared()) {
      const int f = box.shear.flow;
      drift = std::abs(minimum_image(box.shear.offset - offset0_, box.image_len(f), box.half_image_len(f)));
    }
    const double reach = 0.5 * (settings_.skin - 3.0 * drift);
    if (reach <= 0.0) return true;
    const double limit2 = reach * reach;
    const std::size_t n = p.n_local;
    if (box.sheared()) {
#pragma omp parallel for reduction(| : moved) schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        double d[3] = {p.x[i] - x0_[i], p.y[i] - y0_[i], p.z[i] - z0_[i]};
        box_displacement(box, d);
        moved |= (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > limit2) ? 1 : 0;
      }
      return moved != 0;
    }
    const double lx = box.image_len(0), ly = box.image_len(1), lz = box.image_len(2);
    const double hlx = box.half_image_len(0), hly = box.half_image_len(1), hlz = box.half_image_len(2);
#pragma omp parallel for reduction(| : moved) schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = minimum_image(p.x[i] - x0_[i], lx, hlx);
      const double dy = minimum_image(p.y[i] - y0_[i], ly, hly);
      const double dz = minimum_image(p.z[i] - z0_[i], lz, hlz);
      moved |= (dx * dx + dy * dy + dz * dz > limit2) ? 1 : 0;
    }
  }
  return moved != 0;
}

void NeighborList::build(ParticleData& p, const Box& box, ParticleData::Forces forces) {
  set_grid(box);
  sort_locals(p, forces);
  finish(p, box);
}

void NeighborList::set_grid(const Box& box, const CellDomain& domain) {
  const bool same = has_grid_ && box.len.x == grid_box_.len.x && box.len.y == grid_box_.len.y &&
                    box.len.z == grid_box_.len.z && domain == grid_domain_ &&
                    box.shear.flow == grid_box_.shear.flow && box.shear.gradient == grid_box_.shear.gradient;
  if (same) return;
  grid_ = CellGrid(box, settings_.cutoff + settings_.skin, domain);
  grid_box_ = box;
  grid_domain_ = domain;
  has_grid_ = true;
  decomposed_ = grid_.owned_dims() != grid_.dims();
}

void NeighborList::sort_locals(ParticleData& p, ParticleData::Forces forces) {
  if (!has_grid_) throw std::logic_error("NeighborList::sort_locals before set_grid");
  if (decomposed_ && !grid_.has_half_stencil())
    throw std::logic_error("NeighborList: a decomposed box needs the half stencil");
  const bool decomposed = decomposed_;
  const std::size_t n = p.n_local;
  const std::size_t nc = grid_.num_cells();
  const std::size_t owned = grid_.num_owned_cells();

  // Counting sort of local particles by cell. Stable, so the order is a function of positions alone
  // (not of the thread count). Each thread counts its block of particles per cell; a prefix over
  // (cell, thread) gives each thread's first slot in each cell; each thread then places its block.
  cell_index_.resize(n);
  cell_start_.resize(nc + 1);
  order_.resize(n);
  const std::size_t max_threads = static_cast<std::size_t>(omp_get_max_threads());
  thread_cell_slots_.resize(max_threads * owned);
  thread_block_sums_.resize(max_threads);
  int outside = 0;
#pragma omp parallel reduction(| : outside)
  {
    const std::size_t nt = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
    const std::size_t lo = n * t / nt, hi = n * (t + 1) / nt;               // this thread's particles
    const std::size_t clo = owned * t / nt, chi = owned * (t + 1) / nt;     // and cells
    std::uint32_t* slots = thread_cell_slots_.data() + t * owned;
    std::fill(slots, slots + owned, 0u);
    for (std::size_t i = lo; i < hi; ++i) {
      const int c = grid_.cell_of(p.x[i], p.y[i], p.z[i]);
      outside |= c < 0 ? 1 : 0;
      cell_index_[i] = static_cast<std::uint32_t>(c < 0 ? 0 : c);
      ++slots[cell_index_[i]];
    }
#pragma omp barrier
    std::uint64_t sum = 0;
    for (std::size_t c = clo; c < chi; ++c)
      for (std::size_t u = 0; u < nt; ++u) sum += thread_cell_slots_[u * owned + c];
    thread_block_sums_[t] = sum;
#pragma omp barrier
    std::uint64_t base = 0;
    for (std::size_t u = 0; u < t; ++u) base += thread_block_sums_[u];
    for (std::size_t c = clo; c < chi; ++c) {
      cell_start_[c] = static_cast<std::uint32_t>(base);
      for (std::size_t u = 0; u < nt; ++u) {
        const std::uint32_t count = thread_cell_slots_[u * owned + c];
        thread_cell_slots_[u * owned + c] = static_cast<std::uint32_t>(base);
        base += count;
      }
    }
#pragma omp barrier
    for (std::size_t i = lo; i < hi; ++i) order_[slots[cell_index_[i]]++] = static_cast<std::uint32_t>(i);
  }
  if (outside) throw std::logic_error("NeighborList: a local particle lies outside this rank's cells");
  cell_start_[owned] = static_cast<std::uint32_t>(n);
  // Forces are not carried by default: the step computes every force after a build, before reading
  // any (Simulation::step; at start-up the first build is followed by a force computation).
  if (settings_.sort || decomposed) p.permute(order_, decomposed ? n + n / 8 : 0, forces);  // room for the ghosts
}

void NeighborList::finish(ParticleData& p, const Box& box, std::span<const std::uint32_t> ghost_count) {
  const bool decomposed = decomposed_;
  const std::size_t n = p.n_local;
  const std::size_t nc = grid_.num_cells();
  const std::size_t owned = grid_.num_owned_cells();
  if (ghost_count.size() != (decomposed ? nc - owned : 0))
    throw std::logic_error("NeighborList::finish: ghost counts do not match the ghost cells");
  // Ghost cells follow the owned ones in storage and in cell_start_.
  for (std::size_t c = owned; c < nc; ++c) cell_start_[c + 1] = cell_start_[c] + ghost_count[c - owned];
  if (cell_start_[nc] != p.size()) throw std::logic_error("NeighborList::finish: ghost counts do not add up");
  sorted_generation_ = settings_.sort || decomposed ? p.generation() : 0;
  cells_only_ = settings_.skin <= 0.0 && (settings_.sort || decomposed) && grid_.has_half_stencil();
  if (cells_only_) {
    // The force loop walks cell_start_ over the sorted storage; no list, order or per-particle cell.
    offsets_.clear();
    neighbors_.clear();
    ++builds_;
    return;
  }
  if (settings_.sort || decomposed) {
    // Storage is now in cell order: the k-th particle of the cell order is particle k.
#pragma omp parallel for schedule(static)
    for (std::size_t c = 0; c < owned; ++c)
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        order_[k] = k;
        cell_index_[k] = static_cast<std::uint32_t>(c);
      }
    order_.resize(p.size());  // ghosts, too, sit in cell order
    for (std::size_t k = n; k < p.size(); ++k) order_[k] = static_cast<std::uint32_t>(k);
  }
  // order_[k] is the storage index of the k-th particle in cell order.

  // Minimum image on periodic axes, the plain difference on bounded ones (Box::image_len).
  const double lx = box.image_len(0), ly = box.image_len(1), lz = box.image_len(2);
  const double hlx = box.half_image_len(0), hly = box.half_image_len(1), hlz = box.half_image_len(2);
  const double range = settings_.cutoff + settings_.skin;
  const double range2 = range * range;

  // Grids with three or more cells per direction use the half stencil (own cell with j > i, plus 13
  // forward cells); smaller grids visit each distinct neighbour cell and keep pairs with j > i.
  const bool half = grid_.has_half_stencil() && (settings_.sort || decomposed);
  const bool sheared = box.sheared();
  // The squared pair distance under the box's images (Lees-Edwards or plain).
  auto dist2 = [&](double xi, double yi, double zi, std::uint32_t j) {
    if (sheared) {
      double d[3] = {xi - p.x[j], yi - p.y[j], zi - p.z[j]};
      box_displacement(box, d);
      return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    }
    const double dx = minimum_image(xi - p.x[j], lx, hlx);
    const double dy = minimum_image(yi - p.y[j], ly, hly);
    const double dz = minimum_image(zi - p.z[j], lz, hlz);
    return dx * dx + dy * dy + dz * dz;
  };
  auto visit = [&](std::size_t i, auto&& emit) {
    const double xi = p.x[i], yi = p.y[i], zi = p.z[i];
    auto scan = [&](std::uint32_t k0, std::uint32_t k1) {
      for (std::uint32_t k = k0; k < k1; ++k) {
        const std::uint32_t j = order_[k];
        if (dist2(xi, yi, zi, j) < range2) emit(j);
      }
    };
    const int c = static_cast<int>(cell_index_[i]);
    if (half) {
      // Sorted storage: particle i sits at position i of the cell order.
      CellRun runs[CellGrid::kMaxHalfRuns];
      const int nr = grid_.half_runs(c, runs, box.shear.offset);
      // The first run starts with the own cell: partners after i only.
      scan(static_cast<std::uint32_t>(i) + 1, cell_start_[static_cast<std::size_t>(runs[0].last) + 1]);
      for (int r = 1; r < nr; ++r)
        scan(cell_start_[static_cast<std::size_t>(runs[r].first)], cell_start_[static_cast<std::size_t>(runs[r].last) + 1]);
      return;
    }
    grid_.for_each_neighbor_cell(c, [&](int nc2) {
      for (std::uint32_t k = cell_start_[static_cast<std::size_t>(nc2)]; k < cell_start_[static_cast<std::size_t>(nc2) + 1]; ++k) {
        const std::uint32_t j = order_[k];
        if (j <= i) continue;
        if (dist2(xi, yi, zi, j) < range2) emit(j);
      }
    });
  };
  // One pass: each thread lists its contiguous block of rows into its own buffer, then the blocks are
  // concatenated in thread order, so the list is the same whatever the thread count.
  offsets_.assign(n + 1, 0);
#pragma omp parallel
  {
    const int nt = omp_get_num_threads(), t = omp_get_thread_num();
    const std::size_t lo = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(nt);
    const std::size_t hi = n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(nt);
#pragma omp single
    thread_rows_.resize(static_cast<std::size_t>(nt));
    std::vector<std::uint32_t>& rows = thread_rows_[static_cast<std::size_t>(t)];
    rows.clear();
    for (std::size_t i = lo; i < hi; ++i) {
      visit(i, [&](std::uint32_t j) { rows.push_back(j); });
      offsets_[i + 1] = static_cast<std::uint32_t>(rows.size());
    }
#pragma omp barrier
#pragma omp single
    {
      std::uint32_t base = 0;
      for (int u = 0; u < nt; ++u) {
        const std::size_t ulo = n * static_cast<std::size_t>(u) / static_cast<std::size_t>(nt);
        const std::size_t uhi = n * static_cast<std::size_t>(u + 1) / static_cast<std::size_t>(nt);
        for (std::size_t i = ulo; i < uhi; ++i) offsets_[i + 1] += base;
        base += static_cast<std::uint32_t>(thread_rows_[static_cast<std::size_t>(u)].size());
      }
      neighbors_.resize(base);
    }
    if (!rows.empty()) std::copy(rows.begin(), rows.end(), neighbors_.begin() + offsets_[lo]);
  }

  x0_.assign(p.x.begin(), p.x.begin() + static_cast<std::ptrdiff_t>(n));
  y0_.assign(p.y.begin(), p.y.begin() + static_cast<std::ptrdiff_t>(n));
  z0_.assign(p.z.begin(), p.z.begin() + static_cast<std::ptrdiff_t>(n));
  offset0_ = box.shear.offset;
  ++builds_;
}

}  // namespace mesodpd
