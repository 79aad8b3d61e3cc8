// Domain decomposition without MPI: the rank grid choice, its error messages, and the decomposed cell
// grids, whose half stencils must together visit every pair of neighbouring cells exactly once with the
// same periodic wrap as a single-domain grid, with periodic and with bounded axes.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <tuple>

#include "mesodpd/spec.hpp"
#include "neighbor/cell_grid.hpp"
#include "parallel/decomposition.hpp"

namespace mesodpd {
namespace {

// The automatic grid minimises the ghost volume per rank: unsplit axes need no ghosts, so few ranks
// prefer slabs and pencils, many ranks cubes.
TEST(Decomposition, AutomaticGridMinimisesTheGhostVolume) {
  const Decomposition d = Decomposition::make(2, 0, {8, 8, 16}, {8, 8, 16}, {0, 0, 0}, 1.0);
  EXPECT_EQ(d.grid, (std::array<int, 3>{1, 1, 2}));  // split the long axis: 8 x 8 faces
  // 8 ranks on a 10^3 box: 10 x 5 x 2.5 domains grow to 10 x 7 x 4.5 (ghost volume 190), less than
  // 2 x 2 x 2's 7^3 - 5^3 = 218.
  const Decomposition c = Decomposition::make(8, 5, {10, 10, 10}, {10, 10, 10}, {0, 0, 0}, 1.0);
  EXPECT_EQ(c.grid, (std::array<int, 3>{1, 2, 4}));
  EXPECT_EQ(c.coord, (std::array<int, 3>{0, 1, 2}));
  // 64 ranks on a 40^3 box: 4 x 4 x 4 (ghost volume 12^3 - 10^3 = 728) beats 2 x 4 x 8 (848).
  EXPECT_EQ(Decomposition::make(64, 0, {40, 40, 40}, {40, 40, 40}, {0, 0, 0}, 1.0).grid, (std::array<int, 3>{4, 4, 4}));
}

TEST(Decomposition, CellRangesTileTheGrid) {
  for (int nr : {1, 2, 3, 4, 5, 7}) {
    const std::array<int, 3> req{nr, 1, 1};
    std::vector<int> owner_count(11, 0);
    for (int r = 0; r < nr; ++r) {
      const Decomposition d = Decomposition::make(nr, r, {11, 4, 4}, {11, 4, 4}, req, 1.0);
      ASSERT_GE(d.cell_count[0], 1);
      for (int g = d.cell_lo[0]; g < d.cell_lo[0] + d.cell_count[0]; ++g) {
        ++owner_count[static_cast<std::size_t>(g)];
        EXPECT_EQ(d.owner_of_cell(0, g), d.coord[0]);
      }
    }
    for (int c : owner_count) EXPECT_EQ(c, 1) << nr << " ranks";
  }
}

TEST(Decomposition, RefusesDomainsThinnerThanTheGhostWidth) {
  try {
    Decomposition::make(8, 0, {6, 6, 6}, {8, 8, 8}, {8, 1, 1}, 1.3);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("parallel.grid"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("thinner than the ghost width"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Decomposition::make(4, 0, {6, 6, 6}, {8, 8, 8}, {2, 1, 1}, 1.3), ConfigError);  // 2 != 4 ranks
  EXPECT_THROW(Decomposition::make(3, 0, {6, 6, 6}, {8, 8, 8}, {0, 0, 2}, 1.3), ConfigError);  // 2 does not divide 3
  EXPECT_THROW(Decomposition::make(64, 0, {3, 3, 3}, {3, 3, 3}, {0, 0, 0}, 1.0), ConfigError);  // no grid fits
  EXPECT_THROW(Decomposition::make(2, 0, {2, 8, 8}, {2, 8, 8}, {0, 0, 0}, 1.0), ConfigError);   // < 3 cells
  EXPECT_THROW(Decomposition::make(2, 0, {40000, 8, 8}, {40000, 8, 8}, {0, 0, 0}, 1.0), ConfigError);  // 16-bit cells
}

// Every (cell, neighbour cell, wrap) triple the half stencils produce, in global cell coordinates.
using Visit = std::tuple<int, int, int, int, int, int, int, int, int>;

std::multiset<Visit> visits(const CellGrid& g, const std::array<int, 3>& lo) {
  const auto& own = g.owned_dims();
  const auto& n = g.dims();
  // Cell index -> global coordinates, by probing every local coordinate of the extended grid.
  std::map<int, std::array<int, 3>> global;
  for (int z = -1; z <= own[2]; ++z)
    for (int y = -1; y <= own[1]; ++y)
      for (int x = -1; x <= own[0]; ++x) {
        const bool inside = x >= 0 && x < own[0] && y >= 0 && y < own[1] && z >= 0 && z < own[2];
        const std::array<int, 3> l{x, y, z};
        bool valid = true;
        for (std::size_t d = 0; d < 3; ++d)
          if ((l[d] < 0 || l[d] >= own[d]) && own[d] == n[d]) valid = false;  // unsplit axes have no ghosts
        if (!valid && !inside) continue;
        const int idx = g.index_of(x, y, z);
        std::array<int, 3> gc{};
        for (std::size_t d = 0; d < 3; ++d) gc[d] = ((lo[d] + l[d]) % n[d] + n[d]) % n[d];
        global[idx] = gc;
      }
  std::multiset<Visit> out;
  CellRun runs[CellGrid::kMaxHalfRuns];
  for (int c = 0; c < static_cast<int>(g.num_owned_cells()); ++c) {
    const int nr = g.half_runs(c, runs);
    for (int r = 0; r < nr; ++r)
      for (int k = runs[r].first; k <= runs[r].last; ++k) {
        const auto a = global.at(c), b = global.at(k);
        out.insert({a[0], a[1], a[2], b[0], b[1], b[2], runs[r].wx, runs[r].wy, runs[r].wz});
      }
  }
  return out;
}

// The cell block and ghost layers of rank `d` (as Halo::cell_domain gives them).
CellDomain domain_of(const Decomposition& d) {
  CellDomain dom;
  for (std::size_t a = 0; a < 3; ++a) {
    dom.lo[a] = d.cell_lo[a];
    dom.count[a] = d.grid[a] > 1 ? d.cell_count[a] : 0;
    dom.ghost[a] = d.grid[a] > 1;
  }
  return dom;
}

TEST(Decomposition, BoundedAxesHaveNoNeighbourPastTheirEnds) {
  const std::array<bool, 3> per{true, false, true};
  for (int r = 0; r < 6; ++r) {
    const Decomposition d = Decomposition::make(6, r, {6, 9, 6}, {6, 9, 6}, {2, 3, 1}, 1.0, per);
    EXPECT_NE(d.neighbor(0, 0), Decomposition::kNoRank);  // periodic: always a neighbour
    EXPECT_NE(d.neighbor(0, 1), Decomposition::kNoRank);
    EXPECT_EQ(d.neighbor(1, 0) == Decomposition::kNoRank, d.coord[1] == 0) << "rank " << r;
    EXPECT_EQ(d.neighbor(1, 1) == Decomposition::kNoRank, d.coord[1] == 2) << "rank " << r;
    if (d.coord[1] > 0) {
      EXPECT_EQ(d.neighbor(1, 0), r - 2);
    }
  }
  // Fewer than 3 cells are allowed along a bounded axis, even split: nothing wraps there.
  EXPECT_THROW(Decomposition::make(2, 0, {2, 8, 8}, {2, 8, 8}, {2, 1, 1}, 1.0), ConfigError);
  EXPECT_EQ(Decomposition::make(2, 0, {2, 8, 8}, {2, 8, 8}, {2, 1, 1}, 1.0, {false, true, true}).grid,
            (std::array<int, 3>{2, 1, 1}));
  EXPECT_EQ(Decomposition::make(2, 1, {1, 8, 8}, {1.5, 8, 8}, {0, 0, 0}, 1.0, {false, true, true}).grid,
            (std::array<int, 3>{1, 1, 2}));
}

// Two ranks along a bounded axis need one ghost layer each instead of two, so the automatic choice
// splits a bounded axis of a cube where a periodic box would split z.
TEST(Decomposition, AutomaticGridPrefersSplittingABoundedAxis) {
  EXPECT_EQ(Decomposition::make(2, 0, {8, 8, 8}, {8, 8, 8}, {0, 0, 0}, 1.0).grid, (std::array<int, 3>{1, 1, 2}));
  EXPECT_EQ(Decomposition::make(2, 0, {8, 8, 8}, {8, 8, 8}, {0, 0, 0}, 1.0, {false, true, true}).grid,
            (std::array<int, 3>{2, 1, 1}));
  EXPECT_EQ(Decomposition::make(2, 0, {8, 8, 8}, {8, 8, 8}, {0, 0, 0}, 1.0, {true, false, true}).grid,
            (std::array<int, 3>{1, 2, 1}));
  // Three ranks: the middle one has two layers either way, so the bounded axis brings no gain, and a
  // bounded axis shorter than the others is not split before a longer periodic one.
  EXPECT_EQ(Decomposition::make(3, 0, {6, 12, 12}, {6, 12, 12}, {0, 0, 0}, 1.0, {false, true, true}).grid[0], 1);
}

TEST(Decomposition, DecomposedStencilsVisitTheSameCellPairsAsOneDomain) {
  const Box box{{7.0, 6.0, 9.0}};
  const std::array<int, 3> cells = CellGrid::dims_for(box, 1.0);
  const CellGrid single(box, 1.0);
  const std::multiset<Visit> expected = visits(single, {0, 0, 0});
  for (const std::array<int, 3> req : {std::array<int, 3>{2, 1, 1}, {1, 3, 1}, {2, 2, 2}, {3, 1, 4}, {7, 2, 1}}) {
    const int nr = req[0] * req[1] * req[2];
    std::multiset<Visit> all;
    for (int r = 0; r < nr; ++r) {
      const Decomposition d = Decomposition::make(nr, r, cells, {7.0, 6.0, 9.0}, req, 1.0);
      CellDomain dom;
      for (std::size_t a = 0; a < 3; ++a) {
        dom.lo[a] = d.cell_lo[a];
        dom.count[a] = d.grid[a] > 1 ? d.cell_count[a] : 0;
        dom.ghost[a] = d.grid[a] > 1;
      }
      const CellGrid g(box, 1.0, dom);
      EXPECT_EQ(g.num_owned_cells(), static_cast<std::size_t>(d.cell_count[0] * d.cell_count[1] * d.cell_count[2]));
      const auto v = visits(g, d.cell_lo);
      all.insert(v.begin(), v.end());
    }
    EXPECT_EQ(all, expected) << "grid " << format_grid(req);
  }
}

// The same with bounded axes: ghost layers past a bounded end stay empty and unvisited, and the
// decomposed stencils still give exactly the single-domain cell pairs, with no wrap along a bounded axis.
TEST(Decomposition, DecomposedStencilsWithBoundedAxes) {
  for (const std::array<bool, 3> per : {std::array<bool, 3>{true, true, false}, {false, true, false}, {false, false, true}}) {
    Box box{{7.0, 6.0, 9.0}};
    box.periodic = per;
    const std::array<int, 3> cells = CellGrid::dims_for(box, 1.0);
    const CellGrid single(box, 1.0);
    ASSERT_TRUE(single.has_half_stencil());
    const std::multiset<Visit> expected = visits(single, {0, 0, 0});
    for (const Visit& v : expected) {
      EXPECT_TRUE(per[0] || std::get<6>(v) == 0);
      EXPECT_TRUE(per[1] || std::get<7>(v) == 0);
      EXPECT_TRUE(per[2] || std::get<8>(v) == 0);
    }
    for (const std::array<int, 3> req : {std::array<int, 3>{2, 1, 1}, {1, 3, 1}, {2, 2, 2}, {3, 1, 4}, {7, 2, 1}, {1, 1, 9}}) {
      const int nr = req[0] * req[1] * req[2];
      std::multiset<Visit> all;
      for (int r = 0; r < nr; ++r) {
        const Decomposition d = Decomposition::make(nr, r, cells, {7.0, 6.0, 9.0}, req, 1.0, per);
        const CellGrid g(box, 1.0, domain_of(d));
        const auto v = visits(g, d.cell_lo);
        all.insert(v.begin(), v.end());
      }
      EXPECT_EQ(all, expected) << "grid " << format_grid(req);
    }
  }
  // A bounded axis of two cells split over two ranks: one cell each, every pair of cells once.
  Box thin{{2.5, 6.0, 6.0}};
  thin.periodic = {false, true, true};
  const std::array<int, 3> cells = CellGrid::dims_for(thin, 1.0);
  ASSERT_EQ(cells[0], 2);
  const std::multiset<Visit> expected = visits(CellGrid(thin, 1.0), {0, 0, 0});
  std::multiset<Visit> all;
  for (int r = 0; r < 2; ++r) {
    const Decomposition d = Decomposition::make(2, r, cells, {2.5, 6.0, 6.0}, {2, 1, 1}, 1.0, thin.periodic);
    const auto v = visits(CellGrid(thin, 1.0, domain_of(d)), d.cell_lo);
    all.insert(v.begin(), v.end());
  }
  EXPECT_EQ(all, expected);
}

}  // namespace
}  // namespace mesodpd
