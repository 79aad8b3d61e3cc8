// Bounded axes (Box::periodic false) below the config level, which refuses them until walls exist: the
// minimum image, the cell stencils (half stencil, its interior fast path and the small-grid fallback)
// against O(N^2) pair lists, engine forces against an O(N^2) reference, and a particle that leaves
// through a bounded face.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>

#include "core/philox.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/validate.hpp"
#include "neighbor/cell_grid.hpp"
#include "neighbor/neighbor_list.hpp"
#include "physics/dpd_pair.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"

using namespace mesodpd;

namespace {

using Periodic = std::array<bool, 3>;

std::string name_of(const Vec3& len, const Periodic& per) {
  std::string s = std::to_string(len.x) + " x " + std::to_string(len.y) + " x " + std::to_string(len.z) + " periodic ";
  for (bool b : per) s += b ? 't' : 'f';
  return s;
}

// Displacement i - j as the engine must see it: nearest image along periodic axes, straight along
// bounded ones. Written out here, not through Box::image_len, so that it checks those too.
std::array<double, 3> displacement(const Box& box, double xi, double yi, double zi, double xj, double yj, double zj) {
  const double d[3] = {xi - xj, yi - yj, zi - zj};
  std::array<double, 3> out{};
  for (int a = 0; a < 3; ++a) {
    const double len = box.length(a);
    out[static_cast<std::size_t>(a)] = box.periodic[static_cast<std::size_t>(a)] ? d[a] - len * std::nearbyint(d[a] / len) : d[a];
  }
  return out;
}

using PairSet = std::set<std::pair<std::uint32_t, std::uint32_t>>;

PairSet brute_force_pairs(const ParticleData& p, const Box& box, double range) {
  PairSet out;
  for (std::size_t i = 0; i < p.n_local; ++i)
    for (std::size_t j = i + 1; j < p.n_local; ++j) {
      const auto d = displacement(box, p.x[i], p.y[i], p.z[i], p.x[j], p.y[j], p.z[j]);
      if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < range * range)
        out.insert({std::min(p.id[i], p.id[j]), std::max(p.id[i], p.id[j])});
    }
  return out;
}

// Box shapes with 1, 2 and many cells of width 1.3 along bounded and periodic axes, and the patterns
// with one and two bounded axes.
const std::vector<Vec3> kShapes = {{5, 5, 5}, {2.6, 7, 4.1}, {4.2, 2.7, 6.5}, {8, 4, 2.05}, {6.5, 6.5, 2.9}};
const std::vector<Periodic> kPatterns = {{true, true, false}, {false, true, true}, {true, false, false}, {false, false, true}};

}  // namespace

TEST(Boundaries, MinimumImageLeavesABoundedAxisUnwrapped) {
  Box box;
  box.len = {10.0, 4.0, 6.0};
  box.periodic = {true, false, true};
  EXPECT_EQ(box.image_len(0), 10.0);
  EXPECT_EQ(box.half_image_len(0), 5.0);
  EXPECT_EQ(box.image_len(1), std::numeric_limits<double>::infinity());
  EXPECT_EQ(box.half_image_len(1), std::numeric_limits<double>::infinity());
  EXPECT_EQ(box.half_image_len(2), 3.0);
  EXPECT_FALSE(box.all_periodic());
  // 0.9 L apart: the nearest image is 0.1 L the other way on a periodic axis, the plain distance on a
  // bounded one; both exactly odd in the sign.
  for (int d = 0; d < 3; ++d) {
    const double len = box.length(d), far = 0.9 * len;
    const double m = minimum_image(far, box.image_len(d), box.half_image_len(d));
    EXPECT_EQ(m, box.periodic[static_cast<std::size_t>(d)] ? far - len : far) << "axis " << d;
    EXPECT_EQ(minimum_image(-far, box.image_len(d), box.half_image_len(d)), -m) << "axis " << d;
    EXPECT_EQ(minimum_image(0.3, box.image_len(d), box.half_image_len(d)), 0.3);
  }
}

// Every (cell, neighbour cell) pair the half stencils give, checked against the neighbouring cell pairs
// found by brute force over all pairs of cells: each unordered pair once, none across a bounded face, and
// the wrap of each run equal to the periodic crossing. Grids of at least 3 x 3 x 2 cells also exercise
// the interior fast path.
TEST(Boundaries, HalfStencilVisitsEveryNeighbourCellPairOnce) {
  const std::vector<Vec3> shapes = {{5, 5, 5}, {3, 4, 5}, {5, 4, 2}, {4, 1, 6}, {6, 5, 3}};
  for (const Vec3& len : shapes)
    for (const Periodic& per : kPatterns) {
      Box box;
      box.len = len;
      box.periodic = per;
      const CellGrid g(box, 1.0);
      const auto& n = g.dims();
      bool expect_half = true;
      for (std::size_t d = 0; d < 3; ++d) expect_half = expect_half && (!per[d] || n[d] >= 3);
      ASSERT_EQ(g.has_half_stencil(), expect_half) << name_of(len, per);
      if (!expect_half) continue;
      auto coords = [&](int c) { return std::array<int, 3>{c % n[0], (c / n[0]) % n[1], c / (n[0] * n[1])}; };
      std::map<std::pair<int, int>, int> seen;
      CellRun runs[CellGrid::kMaxHalfRuns];
      for (int c = 0; c < static_cast<int>(g.num_cells()); ++c) {
        const int nr = g.half_runs(c, runs);
        ASSERT_EQ(runs[0].first, c);
        for (int r = 0; r < nr; ++r)
          for (int k = runs[r].first; k <= runs[r].last; ++k) {
            const auto a = coords(c), b = coords(k);
            const std::int8_t wrap[3] = {runs[r].wx, runs[r].wy, runs[r].wz};
            for (std::size_t d = 0; d < 3; ++d) {
              // Unwrapped neighbour coordinate b + wrap * n must lie within one cell of a.
              const int step = b[d] + wrap[d] * n[d] - a[d];
              EXPECT_LE(std::abs(step), 1) << name_of(len, per) << " cell " << c << " -> " << k;
              if (!per[d]) {
                EXPECT_EQ(wrap[d], 0) << name_of(len, per) << " wraps a bounded axis";
              }
            }
            ++seen[{std::min(c, k), std::max(c, k)}];
          }
      }
      std::map<std::pair<int, int>, int> expected;
      for (int c = 0; c < static_cast<int>(g.num_cells()); ++c)
        for (int k = c; k < static_cast<int>(g.num_cells()); ++k) {
          const auto a = coords(c), b = coords(k);
          bool near = true;
          for (std::size_t d = 0; d < 3; ++d) {
            const int dist = std::abs(a[d] - b[d]);
            near = near && (per[d] ? std::min(dist, n[d] - dist) <= 1 : dist <= 1);
          }
          if (near) expected[{c, k}] = 1;
        }
      EXPECT_EQ(seen, expected) << name_of(len, per);
    }
}

TEST(Boundaries, NeighborListEqualsBruteForceWithBoundedAxes) {
  std::uint64_t seed = 7;
  int half_runs = 0, fallback_runs = 0;
  for (const Vec3& len : kShapes)
    for (const Periodic& per : kPatterns)
      for (bool sort : {false, true}) {
        Box box;
        box.len = len;
        box.periodic = per;
        ParticleData p = test::random_particles(box, static_cast<std::size_t>(3 * box.volume()), seed++);
        NeighborList list(NeighborSettings{1.0, 0.3, sort});
        list.build(p, box);
        (sort && list.grid().has_half_stencil() ? half_runs : fallback_runs)++;
        PairSet got;
        std::size_t entries = 0;
        for (std::size_t i = 0; i < p.n_local; ++i)
          for (std::uint32_t k = list.offsets()[i]; k < list.offsets()[i + 1]; ++k) {
            const std::uint32_t j = list.neighbors()[k];
            got.insert({std::min(p.id[i], p.id[j]), std::max(p.id[i], p.id[j])});
            ++entries;
          }
        EXPECT_EQ(entries, got.size()) << "a pair listed twice: " << name_of(len, per) << " sort " << sort;
        EXPECT_EQ(got, brute_force_pairs(p, box, 1.3)) << name_of(len, per) << " sort " << sort;
      }
  // Both traversals were exercised: bounded axes with 1 or 2 cells keep the half stencil.
  EXPECT_GT(half_runs, 10);
  EXPECT_GT(fallback_runs, 20);
}

// Engine forces at step 0 against an O(N^2) reference, in cell-pair mode and with Verlet lists. The
// bounded axes are 2.5 long: two cells, so candidate pairs up to 2.5 apart are examined, and a minimum
// image taken with the box length would bring pairs across the face into range.
TEST(Boundaries, EngineForcesEqualTheReferenceWithBoundedAxes) {
  for (const Periodic& per : kPatterns)
    for (NeighborMethod method : {NeighborMethod::Cells, NeighborMethod::Verlet}) {
      SimulationSpec spec = test::fluid_spec(per[0] ? 4.0 : 2.5, per[1] ? 5.0 : 2.5, per[2] ? 4.5 : 2.5, 3.0);
      spec.periodic = per;
      spec.neighbor = method;
      Simulation sim(spec, RunOptions{});
      const ParticleData& p = sim.particles();
      const Box& box = sim.box();
      ASSERT_EQ(box.periodic, per);
      EXPECT_EQ(sim.neighbor_list().cells_only(), method == NeighborMethod::Cells) << name_of(box.len, per);
      const DpdPairParams pp = make_pair_table(spec)(0, 0);
      double max_err = 0, max_f = 0;
      std::size_t across = 0;  // pairs in range only through a bounded face (must get no force)
      for (std::size_t i = 0; i < p.n_local; ++i) {
        double f[3] = {0, 0, 0};
        for (std::size_t j = 0; j < p.n_local; ++j) {
          if (i == j) continue;
          const auto d = displacement(box, p.x[i], p.y[i], p.z[i], p.x[j], p.y[j], p.z[j]);
          const double r = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          Box all = box;
          all.periodic = {true, true, true};
          const auto dp = displacement(all, p.x[i], p.y[i], p.z[i], p.x[j], p.y[j], p.z[j]);
          if (r >= 1.0 && dp[0] * dp[0] + dp[1] * dp[1] + dp[2] * dp[2] < 1.0) ++across;
          if (r >= 1.0 || r == 0) continue;
          const double rv = (d[0] * (p.vx[i] - p.vx[j]) + d[1] * (p.vy[i] - p.vy[j]) + d[2] * (p.vz[i] - p.vz[j])) / r;
          const double xi = pair_noise(spec.seed, 0, p.id[i], p.id[j], NoiseKind::Uniform);
          const DpdPairForce pf = dpd_pair_force(pp, r, rv, xi, 1 / std::sqrt(spec.dt));
          for (std::size_t c = 0; c < 3; ++c) f[c] += (pf.fc + pf.fd + pf.fr) * d[c] / r;
        }
        max_err = std::max({max_err, std::abs(f[0] - p.fx[i]), std::abs(f[1] - p.fy[i]), std::abs(f[2] - p.fz[i])});
        max_f = std::max({max_f, std::abs(f[0]), std::abs(f[1]), std::abs(f[2])});
      }
      EXPECT_GT(across, 50u) << name_of(box.len, per);
      EXPECT_GT(max_f, 10.0);
#ifdef MESODPD_SINGLE_PRECISION
      EXPECT_LT(max_err, 5e-4) << name_of(box.len, per);
#else
      EXPECT_LT(max_err, 1e-8) << name_of(box.len, per);
#endif
    }
}

// Nothing keeps a particle in along a bounded axis yet: leaving is an error naming the step and the id.
// Periodic axes of the same box still wrap, counting the crossing in the image counter.
TEST(Boundaries, LeavingThroughABoundedFaceStopsTheRun) {
  SimulationSpec spec = test::fluid_spec(5.0, 5.0, 5.0, 3.0);
  spec.periodic = {true, true, false};
  spec.species[0].placement = Placement::Lattice;  // sites half a spacing inside every face
  spec.kT = 0.01;                                  // slow thermal motion: only the pushed particles move far
  Simulation sim(spec, RunOptions{});
  ParticleData& p = sim.particles();
  // Push two particles out: one across the periodic x face from the middle of the box, one down through
  // the bounded z face from the middle of the lowest layer (away from each other).
  auto middle = [](double v) { return std::abs(v - 2.5) < 0.4; };
  std::size_t out_x = p.n_local, out_z = p.n_local;
  for (std::size_t i = 0; i < p.n_local; ++i) {
    if (middle(p.y[i]) && middle(p.z[i]) && (out_x == p.n_local || p.x[i] > p.x[out_x])) out_x = i;
    if (middle(p.x[i]) && middle(p.y[i]) && (out_z == p.n_local || p.z[i] < p.z[out_z])) out_z = i;
  }
  ASSERT_LT(out_x, p.n_local);
  ASSERT_LT(out_z, p.n_local);
  ASSERT_LT(p.z[out_z], 0.5);
  const std::uint32_t id_x = p.id[out_x], id_z = p.id[out_z];
  p.vx[out_x] = 0.8 / spec.dt;  // 0.8 in one step: past x = 5 from the last lattice layer
  sim.step();
  const auto at = std::find(p.id.begin(), p.id.begin() + static_cast<std::ptrdiff_t>(p.n_local), id_x) - p.id.begin();
  EXPECT_EQ(p.ix[static_cast<std::size_t>(at)], 1);
  EXPECT_LT(p.x[static_cast<std::size_t>(at)], 1.0);
  const auto az = std::find(p.id.begin(), p.id.begin() + static_cast<std::ptrdiff_t>(p.n_local), id_z) - p.id.begin();
  p.vz[static_cast<std::size_t>(az)] = -1.0 / spec.dt;
  try {
    sim.step();
    FAIL() << "expected a BlowUpError";
  } catch (const BlowUpError& e) {
    EXPECT_EQ(e.step(), 2u);
    EXPECT_EQ(e.particle_id(), id_z);
    const std::string what = e.what();
    for (const std::string& needle : std::vector<std::string>{"left the box at step 2", "particle id " + std::to_string(id_z), "along z",
                                     "system.periodic"})
      EXPECT_NE(what.find(needle), std::string::npos) << what << "\nlacks: " << needle;
  }
}

// The engine runs bounded axes; validate(spec), which the config reader and the public API call,
// refuses them until walls exist, naming the key and saying why.
TEST(Boundaries, ValidateRefusesBoundedAxesUntilWallsExist) {
  SimulationSpec spec = test::fluid_spec(5.0, 5.0, 5.0, 3.0);
  spec.species[0].count = 0;
  spec.species[0].density = 3.0;
  SimulationSpec periodic = spec;
  EXPECT_NO_THROW(validate(periodic));
  spec.periodic = {true, true, false};
  try {
    validate(spec);
    FAIL() << "expected a SpecError";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.key(), "system.periodic");
    EXPECT_EQ(e.value(), "[true, true, false]");
    EXPECT_NE(e.why().find("walls"), std::string::npos) << e.what();
  }
}
