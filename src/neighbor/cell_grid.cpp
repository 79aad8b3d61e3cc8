// Cell grid geometry, the numbering of owned and ghost cells, and half stencils (periodic or bounded).
#include "neighbor/cell_grid.hpp"

#include <algorithm>
#include <cmath>

namespace mesodpd {

std::array<int, 3> CellGrid::dims_for(const Box& box, double min_size) {
  const double len[3] = {box.len.x, box.len.y, box.len.z};
  std::array<int, 3> n{};
  for (std::size_t d = 0; d < 3; ++d) n[d] = std::max(1, static_cast<int>(std::floor(len[d] / min_size)));
  return n;
}

CellGrid::CellGrid(const Box& box, double min_size, const CellDomain& domain) {
  n_ = dims_for(box, min_size);
  const double len[3] = {box.len.x, box.len.y, box.len.z};
  bool any_ghost = false;
  for (std::size_t d = 0; d < 3; ++d) {
    inv_size_[d] = n_[d] / len[d];
    periodic_[d] = box.periodic[d];
    const bool split = domain.count[d] > 0 && domain.count[d] < n_[d];
    lo_[d] = split ? domain.lo[d] : 0;
    own_[d] = split ? domain.count[d] : n_[d];
    ghost_[d] = split && domain.ghost[d] ? 1 : 0;
    any_ghost = any_ghost || ghost_[d] != 0;
  }
  if (box.sheared()) {
    flow_ = box.shear.flow;
    gradient_ = box.shear.gradient;
    flow_len_ = box.length(flow_);
  }
  num_owned_ = static_cast<std::size_t>(own_[0]) * static_cast<std::size_t>(own_[1]) * static_cast<std::size_t>(own_[2]);
  num_cells_ = num_owned_;
  if (any_ghost) {
    // Ghost cells are numbered after the owned ones, in (z, y, x) order of the extended grid.
    const int ex = own_[0] + 2 * ghost_[0], ey = own_[1] + 2 * ghost_[1], ez = own_[2] + 2 * ghost_[2];
    ghost_index_.assign(static_cast<std::size_t>(ex) * static_cast<std::size_t>(ey) * static_cast<std::size_t>(ez), -1);
    int next = static_cast<int>(num_owned_);
    for (int z = 0; z < ez; ++z)
      for (int y = 0; y < ey; ++y)
        for (int x = 0; x < ex; ++x) {
          const int lx = x - ghost_[0], ly = y - ghost_[1], lz = z - ghost_[2];
          const bool owned = lx >= 0 && lx < own_[0] && ly >= 0 && ly < own_[1] && lz >= 0 && lz < own_[2];
          ghost_index_[static_cast<std::size_t>((z * ey + y) * ex + x)] =
              owned ? (lz * own_[1] + ly) * own_[0] + lx : next++;
        }
    num_cells_ = static_cast<std::size_t>(next);
  }
  if (has_half_stencil() && own_[0] >= 3 && own_[1] >= 3 && own_[2] >= 2) {
    // Any interior cell serves as the template; store its runs relative to its index.
    const int c = (0 * own_[1] + 1) * own_[0] + 1;
    interior_count_ = half_runs_general(c, interior_runs_, 0.0);
    for (int r = 0; r < interior_count_; ++r) {
      interior_runs_[r].first -= c;
      interior_runs_[r].last -= c;
    }
  }
}

int CellGrid::index_of(int lx, int ly, int lz) const {
  if (ghost_index_.empty()) return (lz * own_[1] + ly) * own_[0] + lx;
  const int ex = own_[0] + 2 * ghost_[0], ey = own_[1] + 2 * ghost_[1];
  return ghost_index_[static_cast<std::size_t>(((lz + ghost_[2]) * ey + (ly + ghost_[1])) * ex + (lx + ghost_[0]))];
}

int CellGrid::half_runs(int c, CellRun* out, double shear_offset) const {
  const int cx = c % own_[0], cy = (c / own_[0]) % own_[1], cz = c / (own_[0] * own_[1]);
  const bool interior = interior_count_ > 0 && cx > 0 && cx < own_[0] - 1 && cy > 0 && cy < own_[1] - 1 &&
                        cz < own_[2] - 1;
  if (!interior) return half_runs_general(c, out, shear_offset);
  for (int r = 0; r < interior_count_; ++r) {
    out[r] = interior_runs_[r];
    out[r].first += c;
    out[r].last += c;
  }
  return interior_count_;
}

int CellGrid::half_runs_general(int c, CellRun* out, double shear_offset) const {
  const int q[3] = {c % own_[0], (c / own_[0]) % own_[1], c / (own_[0] * own_[1])};
  int count = 0;
  out[count++] = CellRun{c, c, 0, 0, 0};
  // Neighbour coordinate along axis d and its wrap: -1 when the step leaves the global grid below (the
  // neighbour sits at the top, one box length too high), +1 when it leaves above. Axes with ghost
  // layers do not wrap their local coordinate; the ghost cell holds the periodic image. On a bounded
  // axis there is nothing beyond the faces: `absent` is set instead.
  bool absent = false;
  auto step = [&](int d, int delta, int& local) -> std::int8_t {
    const int g = lo_[d] + q[d] + delta;
    const std::int8_t wrap = static_cast<std::int8_t>(g < 0 ? -1 : (g >= n_[d] ? 1 : 0));
    if (wrap != 0 && !periodic_[d]) absent = true;
    local = ghost_[d] ? q[d] + delta : (q[d] + delta + own_[d]) % own_[d];
    return wrap;
  };
  // Forward half: offsets lexicographically positive in (dz, dy, dx). Enumerated in that order, interior
  // cells come out in increasing storage order, so adjacent ones merge into runs. With shear, a row
  // whose gradient step leaves the global grid (wrap w != 0 along the gradient axis) has its image
  // shifted by w * shear_offset along the flow axis, s cells: the partners of the shifted image of cells
  // q-1 .. q+1 lie in the four cells from floor(q - 1 - s) on. The flow axis comes after the gradient
  // axis in the loops (flow < gradient), so the row's wrap is known when its flow cells are chosen.
  const double cells_per_offset = flow_ >= 0 ? n_[static_cast<std::size_t>(flow_)] / flow_len_ : 0.0;
  int delta[3] = {0, 0, 0};
  std::int8_t wrap[3] = {0, 0, 0};
  auto emit = [&]() {
    const bool forward = delta[2] > 0 || (delta[2] == 0 && (delta[1] > 0 || (delta[1] == 0 && delta[0] > 0)));
    if (!forward) return;
    int local[3];
    absent = false;
    for (int d = 0; d < 3; ++d) wrap[d] = step(d, delta[d], local[d]);
    if (absent) return;
    const int cell = index_of(local[0], local[1], local[2]);
    CellRun& last = out[count - 1];
    if (cell == last.last + 1 && wrap[0] == last.wx && wrap[1] == last.wy && wrap[2] == last.wz)
      last.last = cell;
    else
      out[count++] = CellRun{cell, cell, wrap[0], wrap[1], wrap[2]};
  };
  // The flow-axis offsets of a row: -1 .. 1, or the four shifted ones of a crossing row.
  auto flow_range = [&](int& a, int& b) {
    a = -1;
    b = 1;
    if (flow_ < 0) return;
    const auto ga = static_cast<std::size_t>(gradient_);
    const int g = lo_[ga] + q[ga] + delta[ga];
    const int w = g < 0 ? -1 : (g >= n_[ga] ? 1 : 0);
    if (w == 0) return;
    a = static_cast<int>(std::floor(-1.0 - w * shear_offset * cells_per_offset));
    b = a + 3;
  };
  for (delta[2] = 0; delta[2] <= 1; ++delta[2]) {
    int y0 = -1, y1 = 1;
    if (flow_ == 1) flow_range(y0, y1);
    for (delta[1] = y0; delta[1] <= y1; ++delta[1]) {
      int x0 = -1, x1 = 1;
      if (flow_ == 0) flow_range(x0, x1);
      for (delta[0] = x0; delta[0] <= x1; ++delta[0]) emit();
    }
  }
  return count;
}

}  // namespace mesodpd
