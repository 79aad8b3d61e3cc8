// Cell grid geometry and periodic half stencils.
#include "neighbor/cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace mesodpd {

CellGrid::CellGrid(const Box& box, double min_size) {
  const double len[3] = {box.len.x, box.len.y, box.len.z};
  for (int d = 0; d < 3; ++d) {
    n_[d] = std::max(1, static_cast<int>(std::floor(len[d] / min_size)));
    inv_size_[d] = n_[d] / len[d];
  }
  if (has_half_stencil()) {
    // Any interior cell serves as the template; store its runs relative to its index.
    const int c = (1 * n_[1] + 1) * n_[0] + 1;
    interior_count_ = half_runs_general(c, interior_runs_);
    for (int r = 0; r < interior_count_; ++r) {
      interior_runs_[r].first -= c;
      interior_runs_[r].last -= c;
    }
  }
}

int CellGrid::cell_of(double x, double y, double z) const {
  const int cx = std::min(n_[0] - 1, static_cast<int>(x * inv_size_[0]));
  const int cy = std::min(n_[1] - 1, static_cast<int>(y * inv_size_[1]));
  const int cz = std::min(n_[2] - 1, static_cast<int>(z * inv_size_[2]));
  return (cz * n_[1] + cy) * n_[0] + cx;
}

int CellGrid::half_runs(int c, CellRun* out) const {
  const int cx = c % n_[0], cy = (c / n_[0]) % n_[1], cz = c / (n_[0] * n_[1]);
  const bool interior = cx > 0 && cx < n_[0] - 1 && cy > 0 && cy < n_[1] - 1 && cz < n_[2] - 1;
  if (!interior) return half_runs_general(c, out);
  for (int r = 0; r < interior_count_; ++r) {
    out[r] = interior_runs_[r];
    out[r].first += c;
    out[r].last += c;
  }
  return interior_count_;
}

int CellGrid::half_runs_general(int c, CellRun* out) const {
  const int cx = c % n_[0], cy = (c / n_[0]) % n_[1], cz = c / (n_[0] * n_[1]);
  int count = 0;
  out[count++] = CellRun{c, c, 0, 0, 0};
  // wrap = -1 when a step leaves the grid below (the neighbour sits at the top, one box length too
  // high), +1 when it leaves above.
  auto wrap = [](int q, int d, int n) { return static_cast<std::int8_t>(q + d < 0 ? -1 : (q + d >= n ? 1 : 0)); };
  // Forward half: offsets lexicographically positive in (dz, dy, dx). Enumerated in that order, interior
  // cells come out in increasing storage order, so adjacent ones merge into runs.
  for (int dz = 0; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const bool forward = dz > 0 || (dy > 0 || (dy == 0 && dx > 0));
        if (!forward) continue;
        const int nx = (cx + dx + n_[0]) % n_[0], ny = (cy + dy + n_[1]) % n_[1];
        const int nz = (cz + dz + n_[2]) % n_[2];
        const int cell = (nz * n_[1] + ny) * n_[0] + nx;
        const std::int8_t wx = wrap(cx, dx, n_[0]), wy = wrap(cy, dy, n_[1]), wz = wrap(cz, dz, n_[2]);
        CellRun& last = out[count - 1];
        if (cell == last.last + 1 && wx == last.wx && wy == last.wy && wz == last.wz)
          last.last = cell;
        else
          out[count++] = CellRun{cell, cell, wx, wy, wz};
      }
  return count;
}

}  // namespace mesodpd
