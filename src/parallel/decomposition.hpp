// Spatial domain decomposition: the global cell grid (cells at least cutoff + skin wide) is split into a
// 3-D grid of ranks, each owning a contiguous block of whole cells. Because domains are unions of the
// same cells a single rank uses, every rank count sees the same cell pairs (docs/architecture.md).
#pragma once
#include <array>
#include <cstdint>
#include <string>

namespace mesodpd {

struct Decomposition {
  std::array<int, 3> grid{1, 1, 1};        // ranks along x, y, z
  std::array<int, 3> coord{0, 0, 0};       // this rank's position in that grid
  std::array<int, 3> cells{1, 1, 1};       // global cells along x, y, z
  std::array<int, 3> cell_lo{0, 0, 0};     // first cell this rank owns along each axis
  std::array<int, 3> cell_count{1, 1, 1};  // cells this rank owns along each axis
  std::array<bool, 3> periodic{true, true, true};  // false: a bounded axis, no neighbour beyond its ends

  bool decomposed(int d) const { return grid[static_cast<std::size_t>(d)] > 1; }
  bool any_decomposed() const { return grid[0] > 1 || grid[1] > 1 || grid[2] > 1; }
  // Rank at grid position c (periodic).
  int rank_at(std::array<int, 3> c) const;
  // Neighbour rank along axis d: dir = 0 below, 1 above; periodic around a periodic axis, kNoRank past
  // either end of a bounded one.
  static constexpr int kNoRank = -1;
  int neighbor(int d, int dir) const;
  // First global cell owned by grid position k along axis d (k = grid[d] gives cells[d]).
  int first_cell(int d, int k) const;
  // Grid position along axis d that owns global cell g.
  int owner_of_cell(int d, int g) const;

  // Chooses the rank grid for `nranks` ranks over a global grid of `cells` cells spanning `len`, or
  // uses `requested` (0 entries are chosen automatically). Automatic choice minimises the largest ghost
  // volume of a rank (a rank at a bounded end has one ghost layer along that axis, not two). Throws
  // ConfigError naming parallel.grid when no grid keeps every domain at least one cell (the ghost
  // width `range`) thick.
  static Decomposition make(int nranks, int rank, std::array<int, 3> cells, std::array<double, 3> len,
                            std::array<int, 3> requested, double range,
                            std::array<bool, 3> periodic = {true, true, true});
};

std::string format_grid(const std::array<int, 3>& g);

}  // namespace mesodpd
