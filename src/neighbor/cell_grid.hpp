// Regular grid of cells at least `min_size` wide over the box, with neighbour-cell stencils computed on
// the fly (a stored stencil per cell would cost more memory than the particles at rho = 3). Along a
// periodic axis the stencil wraps around; along a bounded axis (Box::periodic) the cells beyond either
// face are absent and the stencil leaves them out.
//
// With Lees-Edwards images (Box::shear) the cells one box length up the gradient axis sit `offset`
// further along the flow axis: a stencil row that crosses the gradient faces takes the four flow-axis
// cells that the shifted image of the three neighbours overlaps (half_runs), or the whole flow row
// (for_each_neighbor_cell). Since the flow axis precedes the gradient axis in the (z, y, x) order, such
// a row is wholly forward or wholly backward, and the half stencil still finds every pair once.
//
// Under domain decomposition a grid covers one rank's block of whole cells plus, along each split axis,
// one layer of ghost cells on either side. Owned cells are numbered first, (z, y, x) lexicographically,
// ghost cells after them, so local particles sorted by cell come before ghosts. Along an axis that is not
// split the grid wraps periodically (if the axis is periodic), exactly as a single-domain grid does.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "core/box.hpp"

namespace mesodpd {

// Consecutive cells [first, last] (in storage order) that share one periodic wrap: their particles
// form one contiguous range once particles are sorted by cell. The nearest images of those particles
// lie at x_j + wrap * L, so the displacement is d = (x_i - x_j) - wrap * L. The wrap is always 0 along
// a bounded axis.
struct CellRun {
  int first, last;
  std::int8_t wx, wy, wz;
};

// The block of global cells one rank owns, and which axes carry ghost layers.
struct CellDomain {
  std::array<int, 3> lo{0, 0, 0};
  std::array<int, 3> count{0, 0, 0};  // 0: the whole axis
  std::array<bool, 3> ghost{false, false, false};

  bool operator==(const CellDomain&) const = default;
};

class CellGrid {
 public:
  // Upper bound on the runs of one half stencil: the own cell plus 13 forward cells, and with shear one
  // more cell in each of the (at most three) forward rows that cross the gradient faces.
  static constexpr int kMaxHalfRuns = 17;

  CellGrid() = default;
  CellGrid(const Box& box, double min_size, const CellDomain& domain = {});

  // Global cells along each axis for a box and minimum cell size.
  static std::array<int, 3> dims_for(const Box& box, double min_size);

  // Owned cell holding a position, or -1 if the position lies outside this grid's owned block.
  int cell_of(double x, double y, double z) const {
    const int gx = global_coord(x, 0), gy = global_coord(y, 1), gz = global_coord(z, 2);
    const int lx = gx - lo_[0], ly = gy - lo_[1], lz = gz - lo_[2];
    if (static_cast<unsigned>(lx) >= static_cast<unsigned>(own_[0]) ||
        static_cast<unsigned>(ly) >= static_cast<unsigned>(own_[1]) ||
        static_cast<unsigned>(lz) >= static_cast<unsigned>(own_[2]))
      return -1;
    return (lz * own_[1] + ly) * own_[0] + lx;
  }
  // Global cell coordinate along axis d of a wrapped coordinate (NaN maps to 0; the health check
  // reports it).
  int global_coord(double v, int d) const {
    const double s = v * inv_size_[static_cast<std::size_t>(d)];
    const int c = s >= 0 ? static_cast<int>(s) : 0;  // false for NaN
    const int n = n_[static_cast<std::size_t>(d)];
    return c < n ? c : n - 1;
  }
  // Cells in storage order: owned first, then ghosts.
  std::size_t num_cells() const { return num_cells_; }
  std::size_t num_owned_cells() const { return num_owned_; }
  // Global cells along x, y, z.
  const std::array<int, 3>& dims() const { return n_; }
  const std::array<int, 3>& owned_dims() const { return own_; }
  const std::array<int, 3>& owned_lo() const { return lo_; }
  // Index of the cell at local coordinates (lx, ly, lz); ghost layers are at -1 and owned_dims()[d].
  int index_of(int lx, int ly, int lz) const;

  // Calls f(cell) once for every distinct cell within one cell of `c` (c included), for grids of any
  // size: a periodic dimension with fewer than three cells must not visit a cell twice, and a bounded
  // one has no cells beyond its faces. Single domain only.
  template <class F>
  void for_each_neighbor_cell(int c, F&& f) const;

  // With at least three cells along every periodic axis (any number along a bounded one, which does
  // not wrap), visiting the own cell (pairs j > i) plus the 13 "forward" neighbour cells (half of the
  // 26, less those beyond a bounded face) finds every pair exactly once.
  // With shear also four cells along the flow axis (the four shifted cells of a crossing row).
  bool has_half_stencil() const {
    for (std::size_t d = 0; d < 3; ++d)
      if (periodic_[d] && n_[d] < 3) return false;
    return !(flow_ >= 0 && n_[static_cast<std::size_t>(flow_)] < 4);
  }
  const std::array<bool, 3>& periodic() const { return periodic_; }
  // Writes the own cell followed by the forward cells of owned cell `c`, merged into runs of
  // storage-adjacent cells with a common wrap, into out[0..return). out[0] starts at c itself.
  // `shear_offset` is the box's current image offset (Box::shear.offset; ignored without shear): the
  // image of a run whose wrap along the gradient axis is w lies w * shear_offset further along the flow
  // axis, which the caller adds to the run's shift.
  int half_runs(int c, CellRun* out, double shear_offset = 0.0) const;
  // Lees-Edwards axes of the box the grid was made for (-1: no shear).
  int flow_axis() const { return flow_; }
  int gradient_axis() const { return gradient_; }

 private:
  int half_runs_general(int c, CellRun* out, double shear_offset) const;

  // Runs of an interior cell (no wrap, all neighbours owned), relative to the cell's own index.
  CellRun interior_runs_[kMaxHalfRuns]{};
  int interior_count_ = 0;
  std::array<int, 3> n_{1, 1, 1};
  std::array<int, 3> lo_{0, 0, 0}, own_{1, 1, 1}, ghost_{0, 0, 0};
  std::array<double, 3> inv_size_{1, 1, 1};
  std::array<bool, 3> periodic_{true, true, true};
  std::size_t num_cells_ = 1, num_owned_ = 1;
  std::vector<int> ghost_index_;  // extended grid -> cell index, when there are ghost layers
  int flow_ = -1, gradient_ = -1;  // Lees-Edwards axes (Box::shear), -1 without shear
  double flow_len_ = 1.0;          // the box length along the flow axis
};

template <class F>
void CellGrid::for_each_neighbor_cell(int c, F&& f) const {
  const int cx = c % n_[0], cy = (c / n_[0]) % n_[1], cz = c / (n_[0] * n_[1]);
  // Offsets per dimension that reach distinct cells. Periodic: {0} for 1 cell, {0,1} for 2, {-1,0,1}
  // otherwise. Bounded: those of {-1,0,1} that stay inside [0, n).
  const int q[3] = {cx, cy, cz};
  // With shear a row that crosses the gradient faces takes the whole flow axis (the shifted image may
  // overlap any of its cells); the gradient axis then has at least three cells (validated), so a
  // crossing is told apart from a step inside the grid.
  auto lo = [&](std::size_t d) { return periodic_[d] ? (n_[d] >= 3 ? -1 : 0) : (q[d] > 0 ? -1 : 0); };
  auto hi = [&](std::size_t d) { return periodic_[d] ? (n_[d] >= 2 ? 1 : 0) : (q[d] < n_[d] - 1 ? 1 : 0); };
  auto crossing = [&](int dg) {
    if (gradient_ < 0) return false;
    const int k = q[static_cast<std::size_t>(gradient_)] + dg;
    return k < 0 || k >= n_[static_cast<std::size_t>(gradient_)];
  };
  int d_of[3] = {0, 0, 0};
  auto range = [&](std::size_t d, int& a, int& b) {
    a = lo(d);
    b = hi(d);
    if (static_cast<int>(d) == flow_ && crossing(d_of[static_cast<std::size_t>(gradient_)])) {
      a = -q[d];
      b = n_[d] - 1 - q[d];
    }
  };
  int z0, z1;
  range(2, z0, z1);
  for (int dz = z0; dz <= z1; ++dz) {
    d_of[2] = dz;
    int y0, y1;
    range(1, y0, y1);
    for (int dy = y0; dy <= y1; ++dy) {
      d_of[1] = dy;
      int x0, x1;
      range(0, x0, x1);
      for (int dx = x0; dx <= x1; ++dx) {
        const int nx = (cx + dx + n_[0]) % n_[0], ny = (cy + dy + n_[1]) % n_[1], nz = (cz + dz + n_[2]) % n_[2];
        f((nz * n_[1] + ny) * n_[0] + nx);
      }
    }
  }
}

}  // namespace mesodpd
