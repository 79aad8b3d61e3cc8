// Regular periodic grid of cells at least `min_size` wide, with the distinct neighbour-cell stencil.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/box.hpp"

namespace mesodpd {

// A neighbour cell seen from some cell, with the periodic wrap crossed to reach it: the neighbour's
// particles' nearest images lie at x_j + wrap * L, so d = (x_i - x_j) - wrap * L.
struct StencilEntry {
  int cell;
  std::int8_t wx, wy, wz;
};

// Consecutive cells [first, last] (in storage order) that share one periodic wrap: their particles
// form one contiguous range once particles are sorted by cell.
struct CellRun {
  int first, last;
  std::int8_t wx, wy, wz;
};

class CellGrid {
 public:
  CellGrid() = default;
  CellGrid(const Box& box, double min_size);

  int cell_of(double x, double y, double z) const;
  std::size_t num_cells() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }
  const std::array<int, 3>& dims() const { return n_; }

  // Cells whose particles may lie within min_size of cell `c`, each listed once (c included), for
  // periodic grids of any size: a dimension with fewer than three cells must not visit a cell twice.
  const std::vector<int>& stencil(int c) const { return stencils_[static_cast<std::size_t>(c)]; }

  // With at least three cells in every direction, the 13 "forward" neighbour cells of `c` (half of the
  // 26): visiting the own cell (pairs j > i) plus these finds every pair exactly once. Empty otherwise.
  bool has_half_stencil() const { return !half_stencils_.empty(); }
  const std::vector<StencilEntry>& half_stencil(int c) const { return half_stencils_[static_cast<std::size_t>(c)]; }
  // The own cell followed by the half stencil, merged into runs of storage-adjacent cells. The first run
  // starts at cell c itself (pairs within it need j > i); the 14 cells usually form 5 runs.
  const std::vector<CellRun>& half_runs(int c) const { return half_runs_[static_cast<std::size_t>(c)]; }


 private:
  std::array<int, 3> n_{1, 1, 1};
  std::array<double, 3> inv_size_{1, 1, 1};
  std::vector<std::vector<int>> stencils_;
  std::vector<std::vector<StencilEntry>> half_stencils_;
  std::vector<std::vector<CellRun>> half_runs_;
};

}  // namespace mesodpd
