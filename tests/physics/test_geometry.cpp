// Tests of the solid geometry: signed distance and normal of every primitive against analytic values,
// unions and differences, pillar lattices, the voxel image readers (and their errors), the image's
// signed distance and normals, and the [[solid]] schema's refusals of bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "boundary/geometry.hpp"
#include "boundary/voxel_image.hpp"
#include "mesodpd/config.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

Box make_box(double lx, double ly, double lz, std::array<bool, 3> periodic = {true, true, true}) {
  Box b;
  b.len = {lx, ly, lz};
  b.periodic = periodic;
  return b;
}

void expect_vec(Vec3 a, Vec3 b, double tol = 1e-6) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

// Random points in the box, the same for every run.
std::vector<Vec3> points(const Box& box, int n, unsigned seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> out;
  for (int k = 0; k < n; ++k) out.push_back({u(rng) * box.len.x, u(rng) * box.len.y, u(rng) * box.len.z});
  return out;
}

ShapeSpec plane(std::array<double, 3> point, std::array<double, 3> normal) {
  ShapeSpec s;
  s.kind = ShapeKind::Plane;
  s.point = point;
  s.normal = normal;
  return s;
}

// With 8 or more solids Geometry looks only at the solids a grid cell lists as possibly nearest: at
// 200,000 random points of a box holding 40 spheres, 6 boxes and 2 planes (a bounded axis), one of them
// released, the distance and the nearest solid are bit for bit those of the plain minimum over all.
TEST(Geometry, ManySolidsGiveTheSameNearestSolidAsTheFullLoop) {
  Box box;
  box.len = {23.0, 17.0, 20.0};
  box.periodic = {true, true, false};
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<SolidSpec> solids;
  for (int k = 0; k < 40; ++k) {
    SolidSpec s;
    s.shape.kind = ShapeKind::Sphere;
    s.shape.center = {u(rng) * 23.0, u(rng) * 17.0, 2.0 + u(rng) * 16.0};
    s.shape.radius = 0.5 + 1.5 * u(rng);
    solids.push_back(s);
  }
  for (int k = 0; k < 6; ++k) {
    SolidSpec s;
    s.shape.kind = ShapeKind::Box;
    const double x = u(rng) * 20.0, y = u(rng) * 14.0, z = 2.0 + u(rng) * 14.0;
    s.shape.lo = {x, y, z};
    s.shape.hi = {x + 0.5 + 2.0 * u(rng), y + 0.5 + 2.0 * u(rng), z + 0.5 + 2.0 * u(rng)};
    solids.push_back(s);
  }
  SolidSpec floor;
  floor.shape.kind = ShapeKind::Plane;
  floor.shape.point = {0, 0, 1};
  floor.shape.normal = {0, 0, 1};
  solids.push_back(floor);
  floor.shape.point = {0, 0, 19};
  floor.shape.normal = {0, 0, -1};
  solids.push_back(floor);
  std::vector<std::uint8_t> released(solids.size(), 0);
  released[3] = 1;
  const Geometry g(solids, box, released);
  std::size_t checked = 0;
  for (int n = 0; n < 200000; ++n) {
    const Vec3 p{u(rng) * 23.0, u(rng) * 17.0, u(rng) * 20.0};
    int body = -2;
    const double d = g.sdf(p, body);
    double best = std::numeric_limits<double>::infinity();
    int nearest = -1;
    for (std::size_t k = 0; k < solids.size(); ++k)
      if (!g.released(k))
        if (const double dk = g.shape(k).sdf(p); dk < best) best = dk, nearest = static_cast<int>(k);
    ASSERT_EQ(d, best) << "at (" << p.x << ", " << p.y << ", " << p.z << ")";
    ASSERT_EQ(body, nearest);
    ++checked;
  }
  EXPECT_EQ(checked, 200000u);
}

TEST(Geometry, PlaneIsTheSignedHeightAboveIt) {
  const Box box = make_box(10, 10, 10, {true, true, false});
  const auto s = make_shape(plane({0, 0, 2}, {0, 0, 3}), box, "solid[0]");  // normal is normalised
  for (const Vec3& p : points(box, 50)) {
    EXPECT_NEAR(s->sdf(p), p.z - 2.0, 1e-12);
    expect_vec(s->normal(p), {0, 0, 1}, 1e-12);
  }
  const auto top = make_shape(plane({0, 0, 8}, {0, 0, -1}), box, "solid[1]");
  EXPECT_NEAR(top->sdf({1, 1, 9}), -1.0, 1e-12);
  EXPECT_NEAR(top->sdf({1, 1, 5}), 3.0, 1e-12);
}

TEST(Geometry, CylinderAlongAnyAxisIsDistanceFromTheAxisMinusRadius) {
  const Box box = make_box(20, 20, 20, {false, false, false});  // bounded: no periodic images
  const Vec3 c{10, 10, 10};
  for (const Vec3 dir : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1, 2, -2}}) {
    ShapeSpec s;
    s.kind = ShapeKind::Cylinder;
    s.center = {c.x, c.y, c.z};
    s.direction = {dir.x, dir.y, dir.z};
    s.radius = 3;
    const auto cyl = make_shape(s, box, "solid[0]");
    const double l = std::sqrt(dot(dir, dir));
    const Vec3 u = (1.0 / l) * dir;
    for (const Vec3& p : points(box, 100)) {
      const Vec3 d = p - c;
      const Vec3 radial = d - dot(d, u) * u;
      const double r = std::sqrt(dot(radial, radial));
      EXPECT_NEAR(cyl->sdf(p), r - 3.0, 1e-12);
      expect_vec(cyl->normal(p), (1.0 / r) * radial, 1e-12);
      // The normal agrees with the gradient of the distance (the generic finite-difference normal).
      expect_vec(cyl->normal(p), cyl->Shape::normal(p), 1e-6);
    }
  }
}

TEST(Geometry, SphereAndBoxAgainstAnalyticDistancesAndPeriodicImages) {
  const Box box = make_box(10, 10, 10);
  ShapeSpec sp;
  sp.kind = ShapeKind::Sphere;
  sp.center = {1, 5, 5};
  sp.radius = 2;
  const auto sphere = make_shape(sp, box, "solid[0]");
  EXPECT_NEAR(sphere->sdf({1, 5, 5}), -2.0, 1e-12);
  EXPECT_NEAR(sphere->sdf({4, 5, 5}), 1.0, 1e-12);
  EXPECT_NEAR(sphere->sdf({9.5, 5, 5}), -0.5, 1e-12);  // 1.5 away through the periodic face
  expect_vec(sphere->normal({9.5, 5, 5}), {-1, 0, 0}, 1e-12);
  expect_vec(sphere->normal({1, 8, 9}), {0, 0.6, 0.8}, 1e-12);

  ShapeSpec bx;
  bx.kind = ShapeKind::Box;
  bx.lo = {2, 3, 4};
  bx.hi = {6, 5, 8};
  const auto b = make_shape(bx, box, "solid[0]");
  EXPECT_NEAR(b->sdf({4, 4, 6}), -1.0, 1e-12);          // centre: 1 from the y faces
  EXPECT_NEAR(b->sdf({2.5, 4, 6}), -0.5, 1e-12);        // 0.5 inside the x = 2 face
  EXPECT_NEAR(b->sdf({1, 4, 6}), 1.0, 1e-12);           // 1 outside the x = 2 face
  EXPECT_NEAR(b->sdf({1, 2, 6}), std::sqrt(2.0), 1e-12);  // beyond an edge
  EXPECT_NEAR(b->sdf({7, 6, 9}), std::sqrt(3.0), 1e-12);  // beyond a corner
  expect_vec(b->normal({1, 4, 6}), {-1, 0, 0}, 1e-6);
  expect_vec(b->normal({4, 4, 8.5}), {0, 0, 1}, 1e-6);
}

TEST(Geometry, UnionIsTheMinimumAndDifferenceCarves) {
  const Box box = make_box(20, 20, 20, {false, false, false});
  ShapeSpec a;
  a.kind = ShapeKind::Sphere;
  a.center = {8, 10, 10};
  a.radius = 3;
  ShapeSpec b = a;
  b.center = {12, 10, 10};
  ShapeSpec u;
  u.kind = ShapeKind::Union;
  u.parts = {a, b};
  ShapeSpec d;
  d.kind = ShapeKind::Difference;
  d.parts = {a, b};
  const auto su = make_shape(u, box, "solid[0]"), sd = make_shape(d, box, "solid[1]");
  const auto sa = make_shape(a, box, "a"), sb = make_shape(b, box, "b");
  for (const Vec3& p : points(box, 200)) {
    EXPECT_DOUBLE_EQ(su->sdf(p), std::min(sa->sdf(p), sb->sdf(p)));
    EXPECT_DOUBLE_EQ(sd->sdf(p), std::max(sa->sdf(p), -sb->sdf(p)));
  }
  EXPECT_LT(sd->sdf({6, 10, 10}), 0);   // in a, outside b
  EXPECT_GT(sd->sdf({10, 10, 10}), 0);  // in both: carved away
  // Inside the carved region, next to b's surface, the normal points into b (into the carved fluid).
  expect_vec(sd->normal({9.2, 10, 10}), {1, 0, 0}, 1e-9);
}

TEST(Geometry, SquareAndHexagonalPillarLattices) {
  const double L = 5, r = 1;
  ShapeSpec s;
  s.kind = ShapeKind::Pillars;
  s.axis = 1;  // pillars along y: lattice in x (first) and z (second)
  s.spacing = L;
  s.radius = r;
  s.point = {0, 0, 0};
  const Box box = make_box(20, 7, 20);
  const auto sq = make_shape(s, box, "solid[0]");
  EXPECT_NEAR(sq->sdf({0, 3, 0}), -1.0, 1e-12);
  EXPECT_NEAR(sq->sdf({15, 1, 10}), -1.0, 1e-12);
  EXPECT_NEAR(sq->sdf({2.5, 3, 2.5}), std::hypot(2.5, 2.5) - 1, 1e-12);  // cell centre
  EXPECT_NEAR(sq->sdf({7, 3, 5}), 1.0, 1e-12);
  expect_vec(sq->normal({7, 3, 5}), {1, 0, 0}, 1e-12);
  s.lattice = Lattice::Hexagonal;
  const auto hex = make_shape(s, box, "solid[1]");
  const double h = L * std::sqrt(3.0) / 2;  // row distance
  EXPECT_NEAR(hex->sdf({2.5, 0, h}), -1.0, 1e-12);  // second row shifted by L/2
  EXPECT_NEAR(hex->sdf({5, 0, 2 * h}), -1.0, 1e-12);
  // Every lattice point has six nearest neighbours at distance L: the midpoint of any two is L/2 - r away.
  EXPECT_NEAR(hex->sdf({1.25, 0, h / 2}), L / 2 - r, 1e-12);
  EXPECT_NEAR(hex->sdf({2.5, 0, 0}), L / 2 - r, 1e-12);
  // The centroid of a lattice triangle is L / sqrt(3) from its three corners.
  EXPECT_NEAR(hex->sdf({2.5, 0, h / 3}), L / std::sqrt(3.0) - r, 1e-12);
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("mesodpd_test_geometry_" +
                                                   std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& f, const std::string& text) {
  std::ofstream out(f, std::ios::binary);
  out << text;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a ConfigError";
  return {};
}

TEST(VoxelImage, PgmTextAndBinaryGiveTheSameGridBottomRowFirst) {
  const fs::path d = temp_dir();
  write(d / "a.pgm", "P2\n# a comment\n3 2\n255\n0 0 255\n7 0 0\n");
  std::string bin = "P5\n3 2\n255\n";
  for (const unsigned char c : {0, 0, 255, 7, 0, 0}) bin.push_back(static_cast<char>(c));
  write(d / "b.pgm", bin);
  const VoxelGrid a = read_pgm((d / "a.pgm").string()), b = read_pgm((d / "b.pgm").string());
  EXPECT_EQ(a.n, (std::array<int, 3>{3, 2, 1}));
  EXPECT_EQ(a.solid, b.solid);
  // Grid row 0 is the picture's bottom row ("7 0 0").
  EXPECT_EQ(a.solid, (std::vector<std::uint8_t>{1, 0, 0, 0, 0, 1}));
}

TEST(VoxelImage, VoxelFileAsciiAndBinary) {
  const fs::path d = temp_dir();
  write(d / "a.vox", "MESODPD-VOXELS 1\nsize 2 2 2\nencoding ascii\ndata\n01\n10\n\n11 00\n");
  std::string bin = "MESODPD-VOXELS 1\nsize 2 2 2\nencoding binary\ndata\n";
  for (const char c : {0, 1, 1, 0, 1, 1, 0, 0}) bin.push_back(c);
  write(d / "b.vox", bin);
  const VoxelGrid a = read_voxels((d / "a.vox").string()), b = read_voxels((d / "b.vox").string());
  EXPECT_EQ(a.n, (std::array<int, 3>{2, 2, 2}));
  EXPECT_EQ(a.solid, (std::vector<std::uint8_t>{0, 1, 1, 0, 1, 1, 0, 0}));
  EXPECT_EQ(a.solid, b.solid);
}

TEST(VoxelImage, BadFilesAreRefusedNamingFileAndProblem) {
  const fs::path d = temp_dir();
  const std::string f = (d / "x.pgm").string();
  write(f, "P3\n1 1\n1\n0\n");
  EXPECT_NE(error_of([&] { read_pgm(f); }).find("not a PGM image"), std::string::npos);
  write(f, "P2\n2 2\n1\n0 1 0\n");
  EXPECT_NE(error_of([&] { read_pgm(f); }).find("3 pixels, 2 x 2 = 4 expected"), std::string::npos);
  write(f, "P2\n1 1\n1\n5\n");
  EXPECT_NE(error_of([&] { read_pgm(f); }).find("outside [0, 1]"), std::string::npos);
  EXPECT_NE(error_of([&] { read_pgm((d / "missing.pgm").string()); }).find("cannot open"), std::string::npos);
  const std::string v = (d / "x.vox").string();
  write(v, "MESODPD-VOXELS 1\nsize 2 2 1\nencoding ascii\ndata\n012\n");
  const std::string m = error_of([&] { read_voxels(v); });
  EXPECT_NE(m.find(v), std::string::npos) << m;
  EXPECT_NE(m.find("cell 2 is '2'"), std::string::npos) << m;
  write(v, "MESODPD-VOXELS 1\nsize 2 2 1\nencoding ascii\ndata\n010\n");
  EXPECT_NE(error_of([&] { read_voxels(v); }).find("3 cells, 2 x 2 x 1 = 4 expected"), std::string::npos);
  write(v, "MESODPD-VOXELS 2\n");
  EXPECT_NE(error_of([&] { read_voxels(v); }).find("version"), std::string::npos);
  // Size mismatch with the box.
  write(v, "MESODPD-VOXELS 1\nsize 4 4 4\nencoding ascii\ndata\n" + std::string(64, '0'));
  ShapeSpec s;
  s.kind = ShapeKind::Image;
  s.file = v;
  s.voxel_size = 2;
  const std::string mm = error_of([&] { load_image(s, make_box(8, 8, 10), "solid[3]"); });
  EXPECT_NE(mm.find("solid[3].file"), std::string::npos) << mm;
  EXPECT_NE(mm.find("4 cells along z"), std::string::npos) << mm;
}

TEST(VoxelImage, ImageOfASlabHasTheSlabsDistanceAndNormals) {
  // A 2-D image (extruded along y) of a wall filling z < 2 of a 10 x 4 x 10 box with 0.5 pixels, plus
  // a square block; its distance and normals must match the exact shapes away from corners.
  const fs::path d = temp_dir();
  const int w = 20, h = 20;  // x columns, z rows
  std::string text = "P2\n" + std::to_string(w) + " " + std::to_string(h) + "\n1\n";
  for (int r = 0; r < h; ++r) {
    const int row = h - 1 - r;  // grid row from the bottom; cell centre z = (row + 0.5) * 0.5
    for (int c = 0; c < w; ++c) text += (row < 4 ? "1 " : "0 ");
    text += "\n";
  }
  write(d / "slab.pgm", text);
  ShapeSpec s;
  s.kind = ShapeKind::Image;
  s.file = (d / "slab.pgm").string();
  s.voxel_size = 0.5;
  s.axis = 1;
  const Box box = make_box(10, 4, 10, {true, true, false});
  const auto img = make_shape(s, box, "solid[0]");
  for (const double z : {0.8, 1.6, 2.1, 2.5, 3.3, 4.0}) {
    for (const double x : {0.3, 4.1, 9.9}) {
      const Vec3 p{x, 1.7, z};
      EXPECT_NEAR(img->sdf(p), z - 2.0, 1e-5) << "z " << z;
      expect_vec(img->normal(p), {0, 0, 1}, 1e-6);
    }
  }
  // Far from the wall the distance grows linearly (the distance transform, not a clipped indicator).
  EXPECT_NEAR(img->sdf({5, 1, 8.75}), 6.75, 1e-5);
}

TEST(VoxelImage, ThreeDimensionalSphereImageApproximatesTheSphere) {
  const fs::path d = temp_dir();
  const int n = 24;
  const double hcell = 0.5, R = 3.2;
  std::string data;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double x = (i + 0.5) * hcell - 6, y = (j + 0.5) * hcell - 6, z = (k + 0.5) * hcell - 6;
        data += (x * x + y * y + z * z < R * R) ? '1' : '0';
      }
  write(d / "s.vox", "MESODPD-VOXELS 1\nsize 24 24 24\nencoding ascii\ndata\n" + data);
  ShapeSpec s;
  s.kind = ShapeKind::Image;
  s.file = (d / "s.vox").string();
  s.voxel_size = hcell;
  const auto img = make_shape(s, make_box(12, 12, 12), "solid[0]");
  for (const Vec3& p : points(make_box(12, 12, 12), 300)) {
    const Vec3 q = p - Vec3{6, 6, 6};
    const double r = std::sqrt(dot(q, q));
    if (r < 1.0) continue;
    // Staircase surface: within about one cell of the exact distance.
    EXPECT_NEAR(img->sdf(p), r - R, 0.5) << "r " << r;
    if (std::abs(r - R) < 0.5) {
      // Normals from the smoothed indicator near the surface: within ~18 degrees of the radial direction.
      EXPECT_GT(dot(img->normal(p), (1.0 / r) * q), 0.95) << "r " << r;
    }
  }
}

// ------------------------------------------------------------------------------------------------
// The [[solid]] schema

const char* kChannel = R"(
[system]
box = [6, 5, 8]
periodic = [true, true, false]
[[species]]
name = "fluid"
density = 3
[[species]]
name = "wall"
frozen = true
[[solid]]
name = "bottom"
species = "wall"
shape = "plane"
point = [0, 0, 1]
normal = [0, 0, 1]
[[solid]]
name = "top"
species = "wall"
shape = "plane"
point = [0, 0, 7]
normal = [0, 0, -1]
velocity = [0.5, 0, 0]
)";

std::string config_error(const std::string& text) {
  return error_of([&] { parse_config(text, "walls.toml"); });
}

// Two chains of harmonic bonds with the given bead sequence, appended to a channel config.
std::string with_chains(const std::string& sequence) {
  return std::string(kChannel) + R"(
[[bond_type]]
name = "spring"
style = "harmonic"
k = 4
[[molecule]]
name = "chain"
sequence = ")" + sequence + R"("
bond_type = "spring"
count = 2
)";
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(SolidConfig, AChannelParsesAndResolvesSpeciesAndDepth) {
  const SimulationSpec spec = parse_config(kChannel, "walls.toml");
  ASSERT_EQ(spec.solids.size(), 2u);
  EXPECT_EQ(spec.solids[1].species_index, 1);
  EXPECT_EQ(spec.solids[1].velocity[0], 0.5);
  EXPECT_EQ(spec.walls.depth, 1.0);
  EXPECT_EQ(spec.walls.layer, 0.1);
  EXPECT_EQ(spec.walls.reflection, ReflectionKind::BounceBack);
  EXPECT_TRUE(spec.species[1].frozen);
  EXPECT_EQ(spec.species[1].count, 0u);
}

TEST(SolidConfig, BadGeometryIsRefusedNamingTheKey) {
  // A wall thinner than the cutoff at a bounded face.
  auto m = config_error(replaced(kChannel, "point = [0, 0, 1]", "point = [0, 0, 0.5]"));
  EXPECT_NE(m.find("system.periodic"), std::string::npos) << m;
  EXPECT_NE(m.find("only 0.5 thick"), std::string::npos) << m;
  // A bounded face that no solid closes.
  m = config_error(replaced(kChannel, "periodic = [true, true, false]", "periodic = [false, true, false]"));
  EXPECT_NE(m.find("no [[solid]] closes its face x = 0"), std::string::npos) << m;
  // Solids that leave no fluid.
  m = config_error(replaced(kChannel, "point = [0, 0, 1]", "point = [0, 0, 9]"));
  EXPECT_NE(m.find("no fluid is left"), std::string::npos) << m;
  // A plane across a periodic axis.
  m = config_error(replaced(kChannel, "normal = [0, 0, 1]", "normal = [1, 0, 1]"));
  EXPECT_NE(m.find("solid[0].normal"), std::string::npos) << m;
  // A solid species that is not frozen, a missing shape key, a key the shape does not use.
  m = config_error(replaced(kChannel, "frozen = true", "frozen = false\ndensity = 1"));
  EXPECT_NE(m.find("solid[0].species"), std::string::npos) << m;
  m = config_error(replaced(kChannel, "normal = [0, 0, -1]", "normal = [0, 0, -1]\nradius = 2"));
  EXPECT_NE(m.find("solid[1].radius"), std::string::npos) << m;
  // A moving wall that would not slide along itself.
  m = config_error(replaced(kChannel, "velocity = [0.5, 0, 0]", "velocity = [0, 0, 0.5]"));
  EXPECT_NE(m.find("solid[1].velocity"), std::string::npos) << m;
  // A thin plate inside the fluid.
  m = config_error(std::string(kChannel) + R"(
[[solid]]
name = "plate"
species = "wall"
shape = "box"
lo = [0, 0, 3]
hi = [6, 5, 3.5]
)");
  EXPECT_NE(m.find("solid[2].hi[2]"), std::string::npos) << m;
  EXPECT_NE(m.find("thinner than walls.depth"), std::string::npos) << m;
  // Pillars that do not repeat with the box.
  m = config_error(replaced(kChannel, "box = [6, 5, 8]", "box = [6, 5, 8]") + R"(
[[solid]]
name = "pillars"
species = "wall"
shape = "pillars"
axis = "z"
lattice = "square"
spacing = 4
radius = 1
)");
  EXPECT_NE(m.find("system.box[0]"), std::string::npos) << m;
  // Molecule beads of a frozen (wall) species: refused, naming the sequence.
  m = config_error(with_chains("fluid2wall3"));
  EXPECT_NE(m.find("molecule[0].sequence"), std::string::npos) << m;
  EXPECT_NE(m.find("frozen"), std::string::npos) << m;
  // Equilibration before freezing with molecules (placed clear of the solids, not cut from a fluid).
  m = config_error(with_chains("fluid4") + "[walls]\nequilibrate = 100\n");
  EXPECT_NE(m.find("walls.equilibrate"), std::string::npos) << m;
  EXPECT_NE(m.find("[[molecule]]"), std::string::npos) << m;
}

TEST(SolidConfig, EquilibrationWithoutSolidsIsRefused) {
  const auto m = config_error(R"(
[system]
box = [6, 6, 6]
[[species]]
name = "fluid"
density = 3
[pair]
a = 25
gamma = 4.5
[walls]
equilibrate = 100
)");
  EXPECT_NE(m.find("walls.equilibrate"), std::string::npos) << m;
  EXPECT_NE(m.find("needs [[solid]] walls"), std::string::npos) << m;
}

TEST(SolidConfig, BodyForceAlongABoundedAxisWithoutWallsIsRefused) {
  const auto m = config_error(R"(
[system]
box = [6, 6, 6]
periodic = [true, true, false]
[[species]]
name = "fluid"
density = 3
body_force = [0, 0, 0.1]
)");
  EXPECT_NE(m.find("species[0].body_force"), std::string::npos) << m;
  EXPECT_NE(m.find("bounded"), std::string::npos) << m;
}

TEST(SolidConfig, ImageSizeMismatchNamesTheKeyAndFile) {
  const fs::path d = temp_dir();
  write(d / "img.pgm", "P2\n4 4\n1\n1 1 1 1\n0 0 0 0\n0 0 0 0\n1 1 1 1\n");
  const std::string text = std::string(R"(
[system]
box = [6, 5, 8]
periodic = [true, true, false]
[[species]]
name = "fluid"
density = 3
[[species]]
name = "wall"
frozen = true
[[solid]]
name = "walls"
species = "wall"
shape = "image"
axis = "y"
voxel_size = 1.5
file = ")") + (d / "img.pgm").string() + "\"\n";
  const auto m = config_error(text);
  EXPECT_NE(m.find("solid[0].file"), std::string::npos) << m;
  EXPECT_NE(m.find("img.pgm"), std::string::npos) << m;
  EXPECT_NE(m.find("4 cells along z"), std::string::npos) << m;
}

}  // namespace
}  // namespace mesodpd
