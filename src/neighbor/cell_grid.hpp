// Regular periodic grid of cells at least `min_size` wide, with neighbour-cell stencils computed on the
// fly (a stored stencil per cell would cost more memory than the particles at rho = 3).
#pragma once
#include <array>
#include <cstdint>

#include "core/box.hpp"

namespace mesodpd {

// Consecutive cells [first, last] (in storage order) that share one periodic wrap: their particles
// form one contiguous range once particles are sorted by cell. The nearest images of those particles
// lie at x_j + wrap * L, so the displacement is d = (x_i - x_j) - wrap * L.
struct CellRun {
  int first, last;
  std::int8_t wx, wy, wz;
};

class CellGrid {
 public:
  // Upper bound on the runs of one half stencil: the own cell plus 13 forward cells.
  static constexpr int kMaxHalfRuns = 14;

  CellGrid() = default;
  CellGrid(const Box& box, double min_size);

  int cell_of(double x, double y, double z) const;
  std::size_t num_cells() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
  const std::array<int, 3>& dims() const { return n_; }

  // Calls f(cell) once for every distinct cell within one cell of `c` (c included), for periodic grids
  // of any size: a dimension with fewer than three cells must not visit a cell twice.
  template <class F>
  void for_each_neighbor_cell(int c, F&& f) const;

  // With at least three cells in every direction, visiting the own cell (pairs j > i) plus the 13
  // "forward" neighbour cells (half of the 26) finds every pair exactly once.
  bool has_half_stencil() const { return n_[0] >= 3 && n_[1] >= 3 && n_[2] >= 3; }
  // Writes the own cell followed by the forward cells of `c`, merged into runs of storage-adjacent
  // cells with a common wrap, into out[0..return). out[0] starts at c itself. Usually 5 runs.
  int half_runs(int c, CellRun* out) const;

 private:
  int half_runs_general(int c, CellRun* out) const;

  // Runs of an interior cell (no wrap), relative to the cell's own index: the same for all of them.
  CellRun interior_runs_[kMaxHalfRuns]{};
  int interior_count_ = 0;
  std::array<int, 3> n_{1, 1, 1};
  std::array<double, 3> inv_size_{1, 1, 1};
};

template <class F>
void CellGrid::for_each_neighbor_cell(int c, F&& f) const {
  const int cx = c % n_[0], cy = (c / n_[0]) % n_[1], cz = c / (n_[0] * n_[1]);
  // Offsets per dimension that reach distinct cells: {0} for 1 cell, {0,1} for 2, {-1,0,1} otherwise.
  auto lo = [](int n) { return n >= 3 ? -1 : 0; };
  auto hi = [](int n) { return n >= 2 ? 1 : 0; };
  for (int dz = lo(n_[2]); dz <= hi(n_[2]); ++dz)
    for (int dy = lo(n_[1]); dy <= hi(n_[1]); ++dy)
      for (int dx = lo(n_[0]); dx <= hi(n_[0]); ++dx) {
        const int nx = (cx + dx + n_[0]) % n_[0], ny = (cy + dy + n_[1]) % n_[1];
        const int nz = (cz + dz + n_[2]) % n_[2];
        f((nz * n_[1] + ny) * n_[0] + nx);
      }
}

}  // namespace mesodpd
