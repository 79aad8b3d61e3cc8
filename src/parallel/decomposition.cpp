// Choice of the rank grid and the cell ranges of each rank.
#include "parallel/decomposition.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "mesodpd/config_error.hpp"

namespace mesodpd {

std::string format_grid(const std::array<int, 3>& g) { return fmt::format("[{}, {}, {}]", g[0], g[1], g[2]); }

int Decomposition::rank_at(std::array<int, 3> c) const {
  for (std::size_t d = 0; d < 3; ++d) c[d] = ((c[d] % grid[d]) + grid[d]) % grid[d];
  return (c[2] * grid[1] + c[1]) * grid[0] + c[0];
}

int Decomposition::neighbor(int d, int dir) const {
  const auto u = static_cast<std::size_t>(d);
  std::array<int, 3> c = coord;
  c[u] += dir == 0 ? -1 : 1;
  if (!periodic[u] && (c[u] < 0 || c[u] >= grid[u])) return kNoRank;
  return rank_at(c);
}

int Decomposition::first_cell(int d, int k) const {
  const auto u = static_cast<std::size_t>(d);
  return static_cast<int>(static_cast<std::int64_t>(k) * cells[u] / grid[u]);
}

int Decomposition::owner_of_cell(int d, int g) const {
  const auto u = static_cast<std::size_t>(d);
  // first_cell is monotone: the owner is the largest k with first_cell(k) <= g.
  int k = static_cast<int>((static_cast<std::int64_t>(g) * grid[u]) / cells[u]);
  while (k + 1 < grid[u] && first_cell(d, k + 1) <= g) ++k;
  while (k > 0 && first_cell(d, k) > g) --k;
  return k;
}

Decomposition Decomposition::make(int nranks, int rank, std::array<int, 3> cells, std::array<double, 3> len,
                                  std::array<int, 3> requested, double range, std::array<bool, 3> periodic) {
  const char* axes = "xyz";
  for (std::size_t d = 0; d < 3; ++d)
    if (requested[d] < 0) throw ConfigError(fmt::format("parallel.grid: {} is negative", format_grid(requested)));
  const bool all_given = requested[0] > 0 && requested[1] > 0 && requested[2] > 0;
  if (all_given && requested[0] * requested[1] * requested[2] != nranks)
    throw ConfigError(fmt::format("parallel.grid: {} needs {} ranks but the run has {} (mpirun -np)",
                                  format_grid(requested), requested[0] * requested[1] * requested[2], nranks));
  // A dimension split over several ranks needs at least one cell per rank and, if periodic, three cells
  // in all (the half stencil must not meet the same neighbour cell from both sides; a bounded axis
  // does not wrap, so there it cannot).
  auto refuse = [&](std::size_t d, int p) {
    return fmt::format(
        "parallel.grid: {} ranks along {} would make domains {:.4g} wide, thinner than the ghost width {:.4g} "
        "(largest cutoff + skin) or fewer than 3 cells ({} along {}); use fewer ranks along {} or a larger box",
        p, axes[d], len[d] / p, range, cells[d], axes[d], axes[d]);
  };
  for (std::size_t d = 0; d < 3; ++d)
    if (requested[d] > 1 && (requested[d] > cells[d] || (periodic[d] && cells[d] < 3)))
      throw ConfigError(refuse(d, requested[d]));
  const int fixed = std::max(1, requested[0]) * std::max(1, requested[1]) * std::max(1, requested[2]);
  if (nranks % fixed != 0)
    throw ConfigError(fmt::format("parallel.grid: {} fixes {} ranks, which does not divide the {} ranks of the run "
                                  "(mpirun -np); use 0 for the axes to choose",
                                  format_grid(requested), fixed, nranks));
  if (nranks > 1)
    for (std::size_t d = 0; d < 3; ++d)
      if (cells[d] > 32000)  // ghost records carry 16-bit cell coordinates
        throw ConfigError(fmt::format("system.box: {} cells along {} exceed the 32,000 a decomposed run supports",
                                      cells[d], axes[d]));
  if (nranks > 1)
    for (std::size_t d = 0; d < 3; ++d)
      if (periodic[d] && cells[d] < 3)
        throw ConfigError(fmt::format(
            "system.box: under MPI every periodic box length must hold at least 3 cells of width {:.4g} (largest "
            "cutoff + skin); the box is {:.4g} long along {}",
            range, len[d], axes[d]));

  Decomposition best;
  double best_cost = std::numeric_limits<double>::infinity();
  bool found = false;
  for (int px = 1; px <= nranks; ++px) {
    if (nranks % px) continue;
    for (int py = 1; py <= nranks / px; ++py) {
      if ((nranks / px) % py) continue;
      const int pz = nranks / (px * py);
      const std::array<int, 3> g{px, py, pz};
      bool ok = true;
      for (std::size_t d = 0; d < 3; ++d) {
        if (requested[d] > 0 && g[d] != requested[d]) ok = false;
        if (g[d] > cells[d]) ok = false;
      }
      if (!ok) continue;
      // Ghost volume of the busiest rank: the domain grown by one ghost width on both sides of each
      // split axis, minus the domain. An unsplit axis needs no ghosts at all; along a bounded axis the
      // end ranks have a neighbour on one side only, so with two ranks there each has one layer.
      double grown = 1, own = 1;
      for (std::size_t d = 0; d < 3; ++d) {
        const int layers = g[d] == 1 ? 0 : (periodic[d] ? 2 : std::min(2, g[d] - 1));
        own *= len[d] / g[d];
        grown *= len[d] / g[d] + layers * range;
      }
      const double cost = grown - own;
      if (cost < best_cost - 1e-9) {
        best_cost = cost;
        best.grid = g;
        found = true;
      }
    }
  }
  if (!found) {
    std::size_t worst = 0;
    for (std::size_t d = 1; d < 3; ++d)
      if (cells[d] > cells[worst]) worst = d;
    throw ConfigError(fmt::format(
        "parallel.grid: cannot split the box ({:.4g} x {:.4g} x {:.4g}, {} x {} x {} cells of width >= {:.4g}) "
        "over {} ranks{} with every domain at least one cell thick; use fewer ranks",
        len[0], len[1], len[2], cells[0], cells[1], cells[2], range, nranks,
        all_given || requested == std::array<int, 3>{0, 0, 0} ? "" : fmt::format(" with grid {}", format_grid(requested))));
  }
  best.cells = cells;
  best.periodic = periodic;
  best.coord = {rank % best.grid[0], (rank / best.grid[0]) % best.grid[1], rank / (best.grid[0] * best.grid[1])};
  for (int d = 0; d < 3; ++d) {
    const auto u = static_cast<std::size_t>(d);
    best.cell_lo[u] = best.first_cell(d, best.coord[u]);
    best.cell_count[u] = best.first_cell(d, best.coord[u] + 1) - best.cell_lo[u];
  }
  return best;
}

}  // namespace mesodpd
