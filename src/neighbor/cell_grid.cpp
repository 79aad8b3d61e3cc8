// Cell grid geometry and periodic stencils.
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
  // Offsets per dimension that reach distinct cells: {0} for 1 cell, {0,1} for 2, {-1,0,1} otherwise.
  auto offsets = [](int n) {
    if (n == 1) return std::vector<int>{0};
    if (n == 2) return std::vector<int>{0, 1};
    return std::vector<int>{-1, 0, 1};
  };
  const auto ox = offsets(n_[0]), oy = offsets(n_[1]), oz = offsets(n_[2]);
  stencils_.resize(num_cells());
  for (int cz = 0; cz < n_[2]; ++cz)
    for (int cy = 0; cy < n_[1]; ++cy)
      for (int cx = 0; cx < n_[0]; ++cx) {
        auto& s = stencils_[static_cast<std::size_t>((cz * n_[1] + cy) * n_[0] + cx)];
        for (int dz : oz)
          for (int dy : oy)
            for (int dx : ox) {
              const int nx = (cx + dx + n_[0]) % n_[0], ny = (cy + dy + n_[1]) % n_[1];
              const int nz = (cz + dz + n_[2]) % n_[2];
              s.push_back((nz * n_[1] + ny) * n_[0] + nx);
            }
      }
  if (n_[0] >= 3 && n_[1] >= 3 && n_[2] >= 3) {
    half_stencils_.resize(num_cells());
    for (int cz = 0; cz < n_[2]; ++cz)
      for (int cy = 0; cy < n_[1]; ++cy)
        for (int cx = 0; cx < n_[0]; ++cx) {
          auto& s = half_stencils_[static_cast<std::size_t>((cz * n_[1] + cy) * n_[0] + cx)];
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                // Forward half: the offset is lexicographically positive in (dz, dy, dx).
                const bool forward = dz > 0 || (dz == 0 && (dy > 0 || (dy == 0 && dx > 0)));
                if (!forward) continue;
                const int nx = (cx + dx + n_[0]) % n_[0], ny = (cy + dy + n_[1]) % n_[1];
                const int nz = (cz + dz + n_[2]) % n_[2];
                // wrap = -1 when the step left the grid below (the neighbour sits at the top, one box
                // length too high), +1 when it left above.
                auto wrap = [](int c, int d, int n) { return static_cast<std::int8_t>(c + d < 0 ? -1 : (c + d >= n ? 1 : 0)); };
                s.push_back(StencilEntry{(nz * n_[1] + ny) * n_[0] + nx, wrap(cx, dx, n_[0]), wrap(cy, dy, n_[1]),
                                         wrap(cz, dz, n_[2])});
              }
        }
    half_runs_.resize(num_cells());
    for (std::size_t c = 0; c < num_cells(); ++c) {
      std::vector<StencilEntry> entries = half_stencils_[c];
      std::sort(entries.begin(), entries.end(), [](const StencilEntry& a, const StencilEntry& b) { return a.cell < b.cell; });
      auto& runs = half_runs_[c];
      runs.push_back(CellRun{static_cast<int>(c), static_cast<int>(c), 0, 0, 0});
      // The own cell must stay first (its run starts at i + 1); the others follow in storage order.
      for (const StencilEntry& e : entries) {
        CellRun& last = runs.back();
        if (e.cell == last.last + 1 && e.wx == last.wx && e.wy == last.wy && e.wz == last.wz)
          last.last = e.cell;
        else
          runs.push_back(CellRun{e.cell, e.cell, e.wx, e.wy, e.wz});
      }
    }
  }
}

int CellGrid::cell_of(double x, double y, double z) const {
  const int cx = std::min(n_[0] - 1, static_cast<int>(x * inv_size_[0]));
  const int cy = std::min(n_[1] - 1, static_cast<int>(y * inv_size_[1]));
  const int cz = std::min(n_[2] - 1, static_cast<int>(z * inv_size_[2]));
  return (cz * n_[1] + cy) * n_[0] + cx;
}

}  // namespace mesodpd
