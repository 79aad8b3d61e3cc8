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
                s.push_back((nz * n_[1] + ny) * n_[0] + nx);
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
