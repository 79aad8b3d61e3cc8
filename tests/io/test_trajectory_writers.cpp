// Tests of the trajectory writers: the LAMMPS dump is parsed back and must reproduce every double
// bit for bit; the GSD file is read back by the reference `gsd` Python package (tests/io/check_gsd.py);
// both must not depend on the storage order of the particles.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "io/frame.hpp"
#include "io/gsd_writer.hpp"
#include "io/lammps_dump_writer.hpp"
#include "mesodpd/spec.hpp"

namespace fs = std::filesystem;
using namespace mesodpd;

namespace {

const std::vector<std::string> kAllFields = {"id", "species", "position", "velocity", "force", "image"};

// Particle arrays in some storage order, with values chosen to need all 17 significant digits.
struct System {
  std::array<double, 3> lo{-2.5, 0.0, 1.0 / 3.0}, len{5.0, 7.25, 3.0};
  std::vector<std::uint32_t> id;
  std::vector<std::int32_t> species;
  std::vector<double> x, y, z, vx, vy, vz, fx, fy, fz;
  std::vector<std::int32_t> ix, iy, iz;
  std::vector<std::string> names{"solvent", "polymer bead"};
  std::vector<double> mass{1.0, 2.5};

  static System make(std::size_t n, double shift) {
    System s;
    for (std::size_t k = 0; k < n; ++k) {
      // Storage order deliberately not id order.
      s.id.push_back(static_cast<std::uint32_t>((k * 7 + 3) % n));
      s.species.push_back(static_cast<std::int32_t>(k % 2));
      const double t = static_cast<double>(k) + shift;
      auto frac = [](double v) { return v - std::floor(v); };
      s.x.push_back(s.lo[0] + s.len[0] * frac(t * 0.1234567891234567 + 1.0 / 3.0));
      s.y.push_back(s.lo[1] + s.len[1] * frac(t * 0.7071067811865476 + 0.1));
      s.z.push_back(s.lo[2] + s.len[2] * frac(t * 0.5772156649015329 + 0.2));
      s.vx.push_back(std::sin(t) * 1.7);
      s.vy.push_back(std::cos(t) / 3.0);
      s.vz.push_back(0.1 + 0.2 * t);
      s.fx.push_back(std::exp(t) * 1e-3 * (k % 2 ? -1 : 1));
      s.fy.push_back(k == 1 ? 5e-324 : 1.0 / (t + 7.0));  // a subnormal must survive too
      s.fz.push_back(k == 2 ? 1.7976931348623157e308 : -t * 1e10);
      s.ix.push_back(static_cast<std::int32_t>(k) - 2);
      s.iy.push_back(static_cast<std::int32_t>(k * k));
      s.iz.push_back(-static_cast<std::int32_t>(k));
    }
    return s;
  }

  // The same particles stored in another order.
  System permuted(const std::vector<std::size_t>& p) const {
    System s = *this;
    auto apply = [&](auto& dst, const auto& src) {
      for (std::size_t k = 0; k < p.size(); ++k) dst[k] = src[p[k]];
    };
    apply(s.id, id);
    apply(s.species, species);
    apply(s.x, x);
    apply(s.y, y);
    apply(s.z, z);
    apply(s.vx, vx);
    apply(s.vy, vy);
    apply(s.vz, vz);
    apply(s.fx, fx);
    apply(s.fy, fy);
    apply(s.fz, fz);
    apply(s.ix, ix);
    apply(s.iy, iy);
    apply(s.iz, iz);
    return s;
  }

  FrameView view(std::uint64_t step, bool with_names = true) const {
    FrameView f;
    f.step = step;
    f.time = 0.01 * static_cast<double>(step);
    f.box_lo = lo;
    f.box_len = len;
    f.n = id.size();
    f.id = id.data();
    f.species = species.data();
    f.x = x.data(), f.y = y.data(), f.z = z.data();
    f.vx = vx.data(), f.vy = vy.data(), f.vz = vz.data();
    f.fx = fx.data(), f.fy = fy.data(), f.fz = fz.data();
    f.ix = ix.data(), f.iy = iy.data(), f.iz = iz.data();
    if (with_names) {
      f.species_names = &names;
      f.species_mass = &mass;
    }
    return f;
  }

  // Storage indices in id order: the order every writer must use.
  std::vector<std::size_t> by_id() const {
    std::vector<std::size_t> o(id.size());
    std::iota(o.begin(), o.end(), std::size_t{0});
    std::sort(o.begin(), o.end(), [&](std::size_t a, std::size_t b) { return id[a] < id[b]; });
    return o;
  }
};

class TrajectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("mesodpd_traj_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  fs::path dir_;
};

// ---------------------------------------------------------------------------------------------
// LAMMPS dump

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// Parses a token as a double and requires the exact bit pattern: "close" is not good enough.
void expect_same_double(const std::string& token, double expected, const std::string& what) {
  char* end = nullptr;
  const double got = std::strtod(token.c_str(), &end);
  ASSERT_EQ(*end, '\0') << what << ": trailing characters in '" << token << "'";
  EXPECT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(expected))
      << what << ": '" << token << "' reads as " << fmt::format("{}", got) << ", wrote "
      << fmt::format("{}", expected);
}

// Checks one dump frame starting at lines[at]; returns the index of the line after it.
std::size_t check_dump_frame(const std::vector<std::string>& lines, std::size_t at, const System& s,
                             std::uint64_t step) {
  EXPECT_EQ(lines.at(at), "ITEM: TIMESTEP");
  EXPECT_EQ(lines.at(at + 1), std::to_string(step));
  EXPECT_EQ(lines.at(at + 2), "ITEM: NUMBER OF ATOMS");
  EXPECT_EQ(lines.at(at + 3), std::to_string(s.id.size()));
  EXPECT_EQ(lines.at(at + 4), "ITEM: BOX BOUNDS pp pp pp");
  for (int d = 0; d < 3; ++d) {
    const auto w = words(lines.at(at + 5 + static_cast<std::size_t>(d)));
    EXPECT_EQ(w.size(), 2u);
    expect_same_double(w.at(0), s.lo[d], "box lo");
    expect_same_double(w.at(1), s.lo[d] + s.len[d], "box hi");
  }
  EXPECT_EQ(lines.at(at + 8), "ITEM: ATOMS id type x y z vx vy vz fx fy fz ix iy iz");
  std::size_t row = at + 9;
  for (const std::size_t i : s.by_id()) {
    const auto w = words(lines.at(row));
    const std::string where = "row " + std::to_string(row) + " (id " + std::to_string(s.id[i]) + ")";
    EXPECT_EQ(lines.at(row).back(), w.back().back()) << where << ": trailing whitespace";
    EXPECT_EQ(w.size(), 14u) << where;
    if (w.size() != 14u) return row + 1;
    EXPECT_EQ(w[0], std::to_string(s.id[i])) << where;
    EXPECT_EQ(w[1], std::to_string(s.species[i] + 1)) << where;
    const double expected[9] = {s.x[i], s.y[i], s.z[i], s.vx[i], s.vy[i], s.vz[i], s.fx[i], s.fy[i], s.fz[i]};
    for (int c = 0; c < 9; ++c) expect_same_double(w[2 + static_cast<std::size_t>(c)], expected[c], where);
    EXPECT_EQ(w[11], std::to_string(s.ix[i])) << where;
    EXPECT_EQ(w[12], std::to_string(s.iy[i])) << where;
    EXPECT_EQ(w[13], std::to_string(s.iz[i])) << where;
    ++row;
  }
  return row;
}

TEST_F(TrajectoryTest, DumpRoundTripsEveryValueAtFullPrecisionInIdOrder) {
  const auto p = dir_ / "traj.lammpstrj";
  const System a = System::make(9, 0.0), b = System::make(9, 0.37);
  {
    LammpsDumpWriter w(p, kAllFields);
    w.write_frame(a.view(0));
    w.write_frame(b.view(250));
    EXPECT_EQ(w.frames_written(), 2u);
  }
  const auto lines = lines_of(slurp(p));
  std::size_t next = check_dump_frame(lines, 0, a, 0);
  next = check_dump_frame(lines, next, b, 250);
  EXPECT_EQ(next, lines.size());
}

TEST_F(TrajectoryTest, DumpIsFlushedAfterEachFrame) {
  const auto p = dir_ / "live.lammpstrj";
  const System a = System::make(4, 0.0);
  LammpsDumpWriter w(p, kAllFields);
  w.write_frame(a.view(10));
  // The writer is still open: a reader (or a crash) must already see the whole frame.
  const auto lines = lines_of(slurp(p));
  EXPECT_EQ(check_dump_frame(lines, 0, a, 10), lines.size());
}

// A bounded axis is written as LAMMPS "ff" (fixed, non-periodic), each axis on its own.
TEST_F(TrajectoryTest, DumpBoxBoundsNameBoundedAxes) {
  const auto p = dir_ / "bounded.lammpstrj";
  const System a = System::make(3, 0.0);
  FrameView f = a.view(7);
  f.periodic = {true, false, true};
  LammpsDumpWriter(p, {"id"}).write_frame(f);
  f.periodic = {false, true, false};
  LammpsDumpWriter(p, {"id"}, /*append=*/true).write_frame(f);
  const auto lines = lines_of(slurp(p));
  ASSERT_GT(lines.size(), 4u + 12u);
  EXPECT_EQ(lines[4], "ITEM: BOX BOUNDS pp ff pp");
  EXPECT_EQ(lines[9 + 3 + 4], "ITEM: BOX BOUNDS ff pp ff");
}

TEST_F(TrajectoryTest, DumpColumnsFollowCanonicalOrderForAnySubset) {
  const auto p = dir_ / "subset.lammpstrj";
  const System a = System::make(3, 0.0);
  LammpsDumpWriter(p, {"image", "velocity", "id"}).write_frame(a.view(5));
  const auto lines = lines_of(slurp(p));
  ASSERT_EQ(lines.size(), 9u + 3u);
  EXPECT_EQ(lines[8], "ITEM: ATOMS id vx vy vz ix iy iz");
  const std::size_t first = a.by_id()[0];
  const auto w = words(lines[9]);
  ASSERT_EQ(w.size(), 7u);
  EXPECT_EQ(w[0], std::to_string(a.id[first]));
  expect_same_double(w[1], a.vx[first], "vx");
  EXPECT_EQ(w[6], std::to_string(a.iz[first]));
}

TEST_F(TrajectoryTest, DumpAppendKeepsEarlierFramesAndTruncateDiscardsThem) {
  const auto p = dir_ / "restart.lammpstrj";
  const System a = System::make(5, 0.0), b = System::make(5, 1.5);
  LammpsDumpWriter(p, kAllFields).write_frame(a.view(100));
  LammpsDumpWriter(p, kAllFields, /*append=*/true).write_frame(b.view(200));
  auto lines = lines_of(slurp(p));
  std::size_t next = check_dump_frame(lines, 0, a, 100);
  EXPECT_EQ(check_dump_frame(lines, next, b, 200), lines.size());

  LammpsDumpWriter(p, kAllFields, /*append=*/false).write_frame(b.view(300));
  lines = lines_of(slurp(p));
  EXPECT_EQ(check_dump_frame(lines, 0, b, 300), lines.size());
}

TEST_F(TrajectoryTest, OutputDoesNotDependOnStorageOrder) {
  const System a = System::make(11, 0.25);
  std::vector<std::size_t> reverse(a.id.size());
  std::iota(reverse.rbegin(), reverse.rend(), std::size_t{0});
  const System b = a.permuted(reverse);
  ASSERT_NE(a.id, b.id);

  LammpsDumpWriter(dir_ / "a.lammpstrj", kAllFields).write_frame(a.view(1));
  LammpsDumpWriter(dir_ / "b.lammpstrj", kAllFields).write_frame(b.view(1));
  EXPECT_EQ(slurp(dir_ / "a.lammpstrj"), slurp(dir_ / "b.lammpstrj"));

  GsdWriter(dir_ / "a.gsd", kAllFields).write_frame(a.view(1));
  GsdWriter(dir_ / "b.gsd", kAllFields).write_frame(b.view(1));
  EXPECT_EQ(slurp(dir_ / "a.gsd"), slurp(dir_ / "b.gsd"));
}

void expect_config_error(const std::function<void()>& action, const fs::path& file,
                         const std::string& needle) {
  try {
    action();
    FAIL() << "expected ConfigError containing '" << needle << "'";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  }
}

TEST_F(TrajectoryTest, BadFieldListsAreRejectedNamingTheFile) {
  const auto p = dir_ / "bad.lammpstrj";
  const auto g = dir_ / "bad.gsd";
  expect_config_error([&] { LammpsDumpWriter(p, {"id", "charge"}); }, p, "unknown field 'charge'");
  expect_config_error([&] { LammpsDumpWriter(p, {"id", "position", "id"}); }, p, "listed twice");
  expect_config_error([&] { LammpsDumpWriter(p, {}); }, p, "empty");
  expect_config_error([&] { GsdWriter(g, {"positions"}); }, g, "unknown field 'positions'");
}

TEST_F(TrajectoryTest, IncompleteFramesAreRejected) {
  const auto p = dir_ / "bad.lammpstrj";
  const auto g = dir_ / "bad.gsd";
  System a = System::make(4, 0.0);
  LammpsDumpWriter dump(p, kAllFields);
  GsdWriter gsd(g, kAllFields);

  FrameView no_force = a.view(3);
  no_force.fy = nullptr;
  expect_config_error([&] { dump.write_frame(no_force); }, p, "no force array");
  expect_config_error([&] { gsd.write_frame(no_force); }, g, "no force array");

  FrameView no_id = a.view(3);
  no_id.id = nullptr;
  expect_config_error([&] { dump.write_frame(no_id); }, p, "no id array");

  a.id[2] = a.id[0];
  expect_config_error([&] { dump.write_frame(a.view(3)); }, p, "appears twice");

  a = System::make(4, 0.0);
  a.species[1] = 2;  // only two species are named
  expect_config_error([&] { gsd.write_frame(a.view(3)); }, g, "not a valid species");
  EXPECT_EQ(gsd.frame_count(), 0u);
}

// ---------------------------------------------------------------------------------------------
// GSD

TEST_F(TrajectoryTest, GsdHeaderDeclaresFileVersionTwoAndHoomdSchema) {
  const auto p = dir_ / "header.gsd";
  GsdWriter(p, {"position"}).write_frame(System::make(3, 0).view(0));
  const std::string raw = slurp(p);
  ASSERT_GE(raw.size(), 256u);
  std::uint64_t magic = 0;
  std::uint32_t schema_version = 0, gsd_version = 0;
  std::memcpy(&magic, raw.data(), 8);
  std::memcpy(&schema_version, raw.data() + 40, 4);
  std::memcpy(&gsd_version, raw.data() + 44, 4);
  EXPECT_EQ(magic, 0x65DF65DF65DF65DFULL);
  EXPECT_EQ(gsd_version, 2u << 16);
  EXPECT_EQ(schema_version, (1u << 16) | 4u);
  EXPECT_EQ(std::string(raw.data() + 112), "hoomd");
  EXPECT_EQ(std::string(raw.data() + 48).rfind("mesodpd", 0), 0u);
}

bool python_gsd_available() {
  return std::system("/usr/bin/python3 -c 'import numpy, gsd.hoomd, gsd.pygsd' >/dev/null 2>&1") == 0;
}

fs::path checker_script() {
  if (const char* src = std::getenv("MESODPD_SOURCE")) return fs::path(src) / "tests" / "io" / "check_gsd.py";
  return fs::path(__FILE__).parent_path() / "check_gsd.py";
}

// Expected content of one frame, in the JSON layout check_gsd.py reads.
std::string expected_frame_json(const System& s, std::uint64_t step, const FieldSet& f, bool names) {
  const auto order = s.by_id();
  std::string j = fmt::format(R"({{"step": {}, "N": {}, "box": [{}, {}, {}])", step, order.size(), s.len[0],
                              s.len[1], s.len[2]);
  auto rows = [&](const char* key, auto value_of, int m) {
    j += fmt::format(R"(, "{}": [)", key);
    for (std::size_t r = 0; r < order.size(); ++r) {
      if (r) j += ", ";
      if (m > 1) j += "[";
      for (int c = 0; c < m; ++c) {
        if (c) j += ", ";
        j += fmt::format("{}", value_of(order[r], c));
      }
      if (m > 1) j += "]";
    }
    j += "]";
  };
  if (f.species) {
    if (names) {
      j += fmt::format(R"(, "types": ["{}", "{}"])", s.names[0], s.names[1]);
      rows(
          "mass", [&](std::size_t i, int) { return s.mass[static_cast<std::size_t>(s.species[i])]; }, 1);
    } else {
      j += R"(, "types": ["1", "2"])";
    }
    rows(
        "typeid", [&](std::size_t i, int) { return s.species[i]; }, 1);
  }
  if (f.position) {
    // The documented convention: relative to the box centre, rounded to float32, and kept below
    // +L/2 of the float32 box (a value that rounds up to L/2 becomes the next float down).
    const std::array<const std::vector<double>*, 3> xyz{&s.x, &s.y, &s.z};
    rows(
        "position",
        [&](std::size_t i, int d) {
          const float v = static_cast<float>((*xyz[d])[i] - (s.lo[d] + 0.5 * s.len[d]));
          const float half = 0.5f * static_cast<float>(s.len[d]);
          return static_cast<double>(v < half ? v : std::nextafter(half, 0.0f));
        },
        3);
  }
  if (f.velocity) {
    const std::array<const std::vector<double>*, 3> v{&s.vx, &s.vy, &s.vz};
    rows(
        "velocity", [&](std::size_t i, int d) { return (*v[d])[i]; }, 3);
  }
  if (f.image) {
    const std::array<const std::vector<std::int32_t>*, 3> im{&s.ix, &s.iy, &s.iz};
    rows(
        "image", [&](std::size_t i, int d) { return (*im[d])[i]; }, 3);
  }
  if (f.force) {
    // gsd_system() keeps forces inside float32 range, so the float32 conversion is exact to compare.
    const std::array<const std::vector<double>*, 3> fo{&s.fx, &s.fy, &s.fz};
    rows(
        "force", [&](std::size_t i, int d) { return (*fo[d])[i]; }, 3);
  }
  if (f.id)
    rows(
        "id", [&](std::size_t i, int) { return s.id[i]; }, 1);
  return j + "}";
}

// Runs check_gsd.py; fails the test with the script's output if it reports a mismatch.
void check_with_python(const fs::path& gsd, const std::vector<std::string>& frames_json) {
  const fs::path expected = gsd.string() + ".expected.json";
  {
    std::ofstream out(expected);
    out << "{\"frames\": [";
    for (std::size_t k = 0; k < frames_json.size(); ++k) out << (k ? ",\n" : "\n") << frames_json[k];
    out << "]}\n";
  }
  const std::string cmd = "/usr/bin/python3 '" + checker_script().string() + "' '" + gsd.string() + "' '" +
                          expected.string() + "' 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe)) output += buf;
  const int status = ::pclose(pipe);
  EXPECT_EQ(status, 0) << cmd << "\n" << output;
}

// Test systems for GSD keep forces within float32 range (the dump test covers extreme doubles).
System gsd_system(std::size_t n, double shift) {
  System s = System::make(n, shift);
  for (double& v : s.fz) v = std::max(-1e30, std::min(v, 1e30));
  return s;
}

TEST_F(TrajectoryTest, GsdThreeFramesReadBackByPythonGsd) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "traj.gsd";
  const FieldSet all = parse_trajectory_fields(kAllFields, p);
  const System a = gsd_system(8, 0.0), b = gsd_system(8, 0.61), c = gsd_system(8, 2.2);
  {
    GsdWriter w(p, kAllFields);
    w.write_frame(a.view(0));
    w.write_frame(b.view(100));
    w.write_frame(c.view(200));
    EXPECT_EQ(w.frame_count(), 3u);
  }
  check_with_python(p, {expected_frame_json(a, 0, all, true), expected_frame_json(b, 100, all, true),
                        expected_frame_json(c, 200, all, true)});
}

TEST_F(TrajectoryTest, GsdManyFramesGrowIndexAndUnnamedSpeciesGetNumbers) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "long.gsd";
  const std::vector<std::string> fields = {"species", "position"};
  const FieldSet set = parse_trajectory_fields(fields, p);
  std::vector<std::string> expected;
  {
    GsdWriter w(p, fields);
    // ~5 chunks per frame: 150 frames overflow the initial 128-entry index several times.
    for (std::uint64_t k = 0; k < 150; ++k) {
      const System s = gsd_system(5, 0.01 * static_cast<double>(k));
      w.write_frame(s.view(k * 10, /*with_names=*/false));
      expected.push_back(expected_frame_json(s, k * 10, set, false));
    }
  }
  check_with_python(p, expected);
}

TEST_F(TrajectoryTest, GsdAppendContinuesExistingFile) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "restart.gsd";
  const FieldSet all = parse_trajectory_fields(kAllFields, p);
  const System a = gsd_system(6, 0.0), b = gsd_system(6, 0.5), c = gsd_system(6, 1.0);
  {
    GsdWriter w(p, kAllFields, /*append=*/true);  // file absent: append creates it
    w.write_frame(a.view(0));
    w.write_frame(b.view(10));
  }
  {
    GsdWriter w(p, kAllFields, /*append=*/true);
    EXPECT_EQ(w.frame_count(), 2u);
    w.write_frame(c.view(20));
    EXPECT_EQ(w.frame_count(), 3u);
  }
  check_with_python(p, {expected_frame_json(a, 0, all, true), expected_frame_json(b, 10, all, true),
                        expected_frame_json(c, 20, all, true)});

  // Without append the file starts over.
  GsdWriter(p, kAllFields).write_frame(c.view(30));
  check_with_python(p, {expected_frame_json(c, 30, all, true)});
}

// A restart from a checkpoint at step K drops the frames after K before appending, and gives back
// their space; the python readers must see a valid file with no repeated step.
TEST_F(TrajectoryTest, GsdAppendKeepThroughStepDropsLaterFrames) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "restart.gsd";
  const FieldSet all = parse_trajectory_fields(kAllFields, p);
  std::vector<System> s;
  for (int k = 0; k < 5; ++k) s.push_back(gsd_system(6, 0.37 * k));
  std::uintmax_t size_after_two = 0;
  {
    GsdWriter w(p, kAllFields);
    w.write_frame(s[0].view(0));
    w.write_frame(s[1].view(10));
    size_after_two = fs::file_size(p);
    w.write_frame(s[2].view(20));
    w.write_frame(s[3].view(30));
  }
  {
    // K = 15 lies between frames: steps 20 and 30 go, and with them the data they owned.
    GsdWriter w(p, kAllFields, /*append=*/true, /*keep_through_step=*/15);
    EXPECT_EQ(w.frame_count(), 2u);
    EXPECT_EQ(fs::file_size(p), size_after_two);
  }
  check_with_python(p, {expected_frame_json(s[0], 0, all, true), expected_frame_json(s[1], 10, all, true)});
  {
    GsdWriter w(p, kAllFields, /*append=*/true, /*keep_through_step=*/10);  // nothing after 10 left
    EXPECT_EQ(w.frame_count(), 2u);
    w.write_frame(s[4].view(20));
  }
  check_with_python(p, {expected_frame_json(s[0], 0, all, true), expected_frame_json(s[1], 10, all, true),
                        expected_frame_json(s[4], 20, all, true)});

  // Without keep_through_step every frame is kept.
  GsdWriter(p, kAllFields, /*append=*/true).write_frame(s[2].view(20));
  check_with_python(p, {expected_frame_json(s[0], 0, all, true), expected_frame_json(s[1], 10, all, true),
                        expected_frame_json(s[4], 20, all, true), expected_frame_json(s[2], 20, all, true)});

  // K = 0 keeps only the frame of step 0.
  {
    GsdWriter w(p, kAllFields, /*append=*/true, /*keep_through_step=*/0);
    EXPECT_EQ(w.frame_count(), 1u);
    w.write_frame(s[3].view(1));
  }
  check_with_python(p, {expected_frame_json(s[0], 0, all, true), expected_frame_json(s[3], 1, all, true)});

  // K before the first frame drops them all; the new first frame gets configuration/dimensions again.
  const auto q = dir_ / "late.gsd";
  GsdWriter(q, kAllFields).write_frame(s[1].view(100));
  {
    GsdWriter w(q, kAllFields, /*append=*/true, /*keep_through_step=*/50);
    EXPECT_EQ(w.frame_count(), 0u);
    w.write_frame(s[2].view(60));
  }
  check_with_python(q, {expected_frame_json(s[2], 60, all, true)});
}

// Truncation after the index has moved to the end of the file (here: more than 128 entries) keeps
// the file valid; the dropped frames' data stays as unreferenced space before the index.
TEST_F(TrajectoryTest, GsdKeepThroughStepAfterIndexGrowth) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "grown.gsd";
  const std::vector<std::string> fields = {"species", "position"};
  const FieldSet set = parse_trajectory_fields(fields, p);
  std::vector<std::string> expected;
  {
    GsdWriter w(p, fields);
    for (std::uint64_t k = 0; k < 60; ++k) {
      const System s = gsd_system(5, 0.01 * static_cast<double>(k));
      w.write_frame(s.view(k * 10, /*with_names=*/false));
      if (k <= 45) expected.push_back(expected_frame_json(s, k * 10, set, false));
    }
  }
  {
    GsdWriter w(p, fields, /*append=*/true, /*keep_through_step=*/455);
    EXPECT_EQ(w.frame_count(), 46u);
    const System s = gsd_system(5, 9.0);
    w.write_frame(s.view(460, /*with_names=*/false));
    expected.push_back(expected_frame_json(s, 460, set, false));
  }
  check_with_python(p, expected);
}

TEST_F(TrajectoryTest, GsdAppendWithMoreFieldsAddsNamesToTheFile) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "more_fields.gsd";
  const std::vector<std::string> few = {"position"};
  const System a = gsd_system(4, 0.0), b = gsd_system(4, 0.3);
  GsdWriter(p, few).write_frame(a.view(0));
  // The second writer needs names the file does not have yet; their ids come after "position",
  // so this frame's chunks are only in id order if the writer sorts them.
  GsdWriter(p, kAllFields, /*append=*/true).write_frame(b.view(1));
  check_with_python(p, {expected_frame_json(a, 0, parse_trajectory_fields(few, p), true),
                        expected_frame_json(b, 1, parse_trajectory_fields(kAllFields, p), true)});
}

TEST_F(TrajectoryTest, GsdPositionsAtTheUpperFaceStayInsideTheHalfOpenBox) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "faces.gsd";
  System s = gsd_system(3, 0.0);
  // Wrapped coordinates just below lo + L: centred they are L/2 - tiny, which rounds to L/2 in float32.
  for (int d = 0; d < 3; ++d) {
    auto& c = d == 0 ? s.x : (d == 1 ? s.y : s.z);
    c[0] = std::nextafter(s.lo[d] + s.len[d], s.lo[d]);
    c[1] = s.lo[d];
  }
  GsdWriter(p, {"position", "id"}).write_frame(s.view(0));
  // check_gsd.py verifies -L/2 <= x < L/2 for every frame; positions are not compared exactly here.
  check_with_python(p, {expected_frame_json(s, 0, parse_trajectory_fields({"id"}, p), true)});
}

TEST_F(TrajectoryTest, GsdAppendRejectsForeignFile) {
  const auto p = dir_ / "not_gsd.gsd";
  std::ofstream(p) << std::string(300, 'x');
  expect_config_error([&] { GsdWriter(p, kAllFields, true); }, p, "not a GSD file");
  EXPECT_EQ(slurp(p), std::string(300, 'x'));  // left untouched
}

TEST_F(TrajectoryTest, GsdEmptyFrameHasZeroParticles) {
  if (!python_gsd_available()) GTEST_SKIP() << "/usr/bin/python3 with numpy and gsd is not available";
  const auto p = dir_ / "empty.gsd";
  FrameView f;
  f.step = 7;
  f.box_len = {2, 3, 4};
  GsdWriter(p, kAllFields).write_frame(f);
  check_with_python(p, {R"({"step": 7, "N": 0, "box": [2, 3, 4]})"});
}

}  // namespace
