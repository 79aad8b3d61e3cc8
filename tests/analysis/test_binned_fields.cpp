// Binned fields (analysis/binned_fields.hpp): mass conservation, exact velocities and zero temperature of
// a uniform flow, the N - 1 degrees of freedom of the bin temperature, centring, the slab fit, the VTK
// file and the checkpoint state.
#include "analysis/binned_fields.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "core/box.hpp"
#include "mesodpd/config_error.hpp"
#include "parallel/comm.hpp"
#include "random_particles.hpp"
#include "test_support.hpp"

namespace mesodpd {
namespace {

namespace fs = std::filesystem;

// A FieldsSpec as validate() leaves it: region = whole box unless given, every species selected.
FieldsSpec grid(std::array<int, 3> bins, std::array<double, 3> box, int species = 1) {
  FieldsSpec f;
  f.bins = bins;
  f.region_hi = box;
  for (int s = 0; s < species; ++s) f.selected.push_back(s);
  return f;
}

std::vector<std::string> names(int n) {
  std::vector<std::string> out;
  for (int s = 0; s < n; ++s) out.push_back(fmt::format("S{}", s));
  return out;
}

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_binned_fields" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(BinnedFields, DensityTimesBinVolumeCountsEveryParticle) {
  // Sum over bins of density x bin volume = particles per sample, per species and for the selection,
  // including particles exactly on the upper box face and slightly outside it (wrapped).
  Box box;
  box.len = {6.0, 5.0, 7.0};
  ParticleData p = test::random_particles(box, 3000, 7, 3);
  p.x[0] = 6.0;      // on the face: wraps to 0
  p.z[1] = -1e-17;   // wraps to just below 7
  p.y[2] = 12.5;     // one period out
  FieldsSpec f = grid({5, 4, 3}, {6, 5, 7}, 3);
  f.selected = {0, 2};
  BinnedFields fields(f, {1.0, 2.0, 0.5}, names(3), {6, 5, 7});
  const Comm comm = Comm::serial();
  for (int k = 0; k < 3; ++k) fields.sample(p, comm, static_cast<std::uint64_t>(k));
  std::array<int, 3> count{};
  for (std::size_t i = 0; i < p.n_local; ++i) ++count[static_cast<std::size_t>(p.species[i])];
  const double v = fields.cell_volume();
  EXPECT_DOUBLE_EQ(v, 6.0 / 5 * 5.0 / 4 * 7.0 / 3);
  for (int s = 0; s < 3; ++s) {
    double total = 0;
    for (double r : fields.species_density(s)) total += r * v;
    EXPECT_NEAR(total, count[static_cast<std::size_t>(s)], 1e-9) << "species " << s;
  }
  double selected = 0;
  for (double r : fields.density()) selected += r * v;
  EXPECT_NEAR(selected, count[0] + count[2], 1e-9);
}

// FieldsSpec::means: the mean of a per-particle field over the selected species' particles in each bin
// (eDPD's internal temperature), over the samples; a field the particles do not hold is an error naming
// the key; the CSV and VTK files carry it as mean_<field>.
TEST(BinnedFields, MeansOfAParticleFieldPerBin) {
  Box box;
  box.len = {4.0, 4.0, 8.0};
  ParticleData p = test::random_particles(box, 2000, 11, 2);
  p.enable("temp");
  for (std::size_t i = 0; i < p.n_local; ++i) p.temp[i] = 1.0 + 0.1 * p.z[i] + (p.species[i] == 1 ? 5.0 : 0.0);
  FieldsSpec f = grid({1, 1, 4}, {4, 4, 8}, 2);
  f.selected = {0};  // species 1 (5 hotter) is left out of the means
  f.means = {"temp"};
  BinnedFields fields(f, {1.0, 1.0}, names(2), {4, 4, 8});
  const Comm comm = Comm::serial();
  fields.sample(p, comm, 0);
  for (std::size_t i = 0; i < p.n_local; ++i) p.temp[i] += 1.0;  // a second sample, one hotter
  fields.sample(p, comm, 1);
  const std::vector<double> mean = fields.mean(0);
  for (std::size_t b = 0; b < 4; ++b) {
    double sum = 0, n = 0;
    for (std::size_t i = 0; i < p.n_local; ++i)
      if (p.species[i] == 0 && static_cast<std::size_t>(p.z[i] / 2.0) == b) sum += p.temp[i] - 0.5, n += 1;
    EXPECT_NEAR(mean[b], sum / n, 1e-9) << "bin " << b;
  }
  EXPECT_NEAR(mean[3] - mean[0], 0.6, 0.05);  // 0.1 per unit of z, bins 2 apart
  const fs::path dir = fresh_dir("means");
  fields.write(dir);
  const std::string csv = test::read_file(dir / "fields.csv");
  EXPECT_NE(csv.find(",mean_temp\n"), std::string::npos);
  EXPECT_NE(test::read_file(dir / "fields.vti").find("mean_temp"), std::string::npos);
  ParticleData plain = test::random_particles(box, 100, 12, 2);
  BinnedFields missing(f, {1.0, 1.0}, names(2), {4, 4, 8});
  try {
    missing.sample(plain, comm, 0);
    ADD_FAILURE() << "no error for a field the particles do not hold";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("analysis.fields.means"), std::string::npos) << e.what();
  }
}

TEST(BinnedFields, SubRegionCountsOnlyTheParticlesInside) {
  Box box;
  box.len = {8.0, 8.0, 8.0};
  const ParticleData p = test::random_particles(box, 4000, 11);
  FieldsSpec f = grid({4, 1, 2}, {8, 8, 8});
  f.region_lo = {1.0, 0.0, 2.5};
  f.region_hi = {5.0, 8.0, 6.5};
  BinnedFields fields(f, {1.0}, names(1), {8, 8, 8});
  fields.sample(p, Comm::serial(), 0);
  std::size_t inside = 0;
  for (std::size_t i = 0; i < p.n_local; ++i)
    inside += p.x[i] >= 1.0 && p.x[i] < 5.0 && p.z[i] >= 2.5 && p.z[i] < 6.5;
  double total = 0;
  for (double r : fields.density()) total += r * fields.cell_volume();
  EXPECT_NEAR(total, static_cast<double>(inside), 1e-9);
  EXPECT_DOUBLE_EQ(fields.centre(0)[0], 1.5);
  EXPECT_DOUBLE_EQ(fields.centre(0)[2], 3.5);
  EXPECT_DOUBLE_EQ(fields.centre(7)[0], 4.5);  // ix = 3, iz = 1
  EXPECT_DOUBLE_EQ(fields.centre(7)[2], 5.5);
}

TEST(BinnedFields, UniformFlowGivesExactVelocityAndZeroTemperature) {
  // Two species of different masses moving together: every bin's mass-weighted velocity is exactly the
  // common velocity (values exact in binary) and the peculiar velocity, hence the temperature, is zero.
  Box box;
  box.len = {5.0, 5.0, 5.0};
  ParticleData p = test::random_particles(box, 2000, 3, 2);
  for (std::size_t i = 0; i < p.n_local; ++i) p.vx[i] = 0.5, p.vy[i] = -0.25, p.vz[i] = 1.5;
  BinnedFields fields(grid({5, 5, 2}, {5, 5, 5}, 2), {1.0, 3.0}, names(2), {5, 5, 5});
  for (int k = 0; k < 4; ++k) fields.sample(p, Comm::serial(), static_cast<std::uint64_t>(k));
  const double expect[3] = {0.5, -0.25, 1.5};
  for (int d = 0; d < 3; ++d)
    for (double v : fields.velocity(d)) EXPECT_EQ(v, expect[d]);
  for (int d = -1; d < 3; ++d)
    for (double t : fields.temperature(d)) EXPECT_EQ(t, 0.0);
}

TEST(BinnedFields, TemperatureCountsNMinusOneDegreesOfFreedom) {
  // 3 particle-samples per bin: subtracting the bin's own mean velocity leaves 2 degrees of freedom per
  // component, so sum m (v - u)^2 / 2 is unbiased while dividing by 3 would read kT as 2/3 kT. Masses
  // 1 and 4 (velocity variance kT/m each) and a streaming velocity that differs between bins.
  const double kT = 1.7;
  const int bins = 4000;
  Box box;
  box.len = {static_cast<double>(bins), 1.0, 1.0};
  ParticleData p;
  p.resize(3 * bins);
  p.n_local = 3 * bins;
  std::mt19937_64 rng(99);
  std::normal_distribution<double> g(0.0, 1.0);
  for (std::size_t i = 0; i < p.n_local; ++i) {
    const std::size_t b = i / 3;
    p.species[i] = static_cast<std::int32_t>(i % 2);
    const double sd = std::sqrt(kT / (i % 2 ? 4.0 : 1.0));
    p.x[i] = static_cast<double>(b) + 0.5;
    p.y[i] = p.z[i] = 0.5;
    p.vx[i] = 0.001 * static_cast<double>(b) + sd * g(rng);
    p.vy[i] = std::sin(0.01 * static_cast<double>(b)) + sd * g(rng);
    p.vz[i] = sd * g(rng);
  }
  BinnedFields fields(grid({bins, 1, 1}, {box.len.x, 1.0, 1.0}, 2), {1.0, 4.0}, names(2), {box.len.x, 1.0, 1.0});
  fields.sample(p, Comm::serial(), 0);
  const std::vector<double> t = fields.temperature(-1);
  double mean = 0;
  for (double x : t) mean += x / bins;
  // Each bin's T has 6 degrees of freedom (chi-squared): relative standard deviation sqrt(2/6) per bin,
  // sqrt(2/6/4000) = 0.9% for the mean over bins; 4 sigma = 3.7%.
  EXPECT_NEAR(mean / kT, 1.0, 4 * std::sqrt(2.0 / 6.0 / bins)) << "mean bin temperature " << mean;
  EXPECT_GT(std::fabs(mean / kT - 2.0 / 3.0), 0.2) << "reads like the N (not N - 1) normalisation";
}

TEST(BinnedFields, CentringRemovesADriftOfTheSlab) {
  // A slab of particles |z - c| < 2 in a box of 10: wherever its centre c is (also across the periodic
  // boundary), the centred profile puts it in the middle and matches the profile at c = 5.
  Box box;
  box.len = {4.0, 4.0, 10.0};
  auto slab_at = [&](double c) {
    ParticleData p = test::random_particles(box, 3000, 5);
    for (std::size_t i = 0; i < p.n_local; ++i) {
      const double z = c + 4.0 * (p.z[i] / 10.0 - 0.5);
      p.z[i] = z - 10.0 * std::floor(z / 10.0);
    }
    return p;
  };
  FieldsSpec f = grid({1, 1, 20}, {4, 4, 10});
  f.centre_axis = 2;
  auto profile = [&](double c) {
    BinnedFields fields(f, {1.0}, names(1), {4, 4, 10});
    fields.sample(slab_at(c), Comm::serial(), 0);
    return fields.density();
  };
  const std::vector<double> ref = profile(5.0);
  for (double c : {1.0, 3.3, 9.2}) {
    const std::vector<double> got = profile(c);
    double diff = 0;
    for (std::size_t k = 0; k < got.size(); ++k) diff += std::fabs(got[k] - ref[k]);
    // Particles within round-off of a bin edge may change bins: allow a handful out of 3000.
    EXPECT_LT(diff * 4.0 * 4.0 * 0.5, 5.0) << "slab centred at " << c;  // x bin volume: particles
    EXPECT_EQ(got[0], 0.0) << "slab at " << c << " not centred";
    EXPECT_EQ(got[19], 0.0) << "slab at " << c << " not centred";
  }
}

TEST(SlabFit, RecoversKnownParametersFromASyntheticProfile) {
  // rho_l = 6.1, rho_v = 0.05, h = 4, w = 0.6 on a periodic axis of 20, with small noise, centred at 10
  // and wrapped across the boundary (centre 1.5).
  for (double z0 : {10.0, 1.5}) {
    std::mt19937_64 rng(4);
    std::normal_distribution<double> noise(0.0, 0.01);
    std::vector<double> z, rho;
    for (int k = 0; k < 100; ++k) {
      const double zz = 0.1 + 0.2 * k;
      double d = zz - z0;
      d -= 20.0 * std::round(d / 20.0);
      z.push_back(zz);
      rho.push_back(0.5 * (6.1 + 0.05) - 0.5 * (6.1 - 0.05) * std::tanh((std::fabs(d) - 4.0) / 0.6) + noise(rng));
    }
    const SlabFit fit = fit_slab_profile(z, rho, 20.0);
    ASSERT_TRUE(fit.converged) << "z0 = " << z0;
    EXPECT_NEAR(fit.rho_l, 6.1, 0.01);
    EXPECT_NEAR(fit.rho_v, 0.05, 0.01);
    EXPECT_NEAR(fit.half_width, 4.0, 0.01);
    EXPECT_NEAR(fit.width, 0.6, 0.01);
    EXPECT_NEAR(fit.z0, z0, 0.01);
    EXPECT_NEAR(fit.rms, 0.01, 0.003);
  }
  // Noise-free: recovered to round-off.
  std::vector<double> z, rho;
  for (int k = 0; k < 60; ++k) {
    z.push_back(0.25 + 0.5 * k);
    rho.push_back(0.5 * 3.3 - 0.5 * 2.7 * std::tanh((std::fabs(z.back() - 14.0) - 6.0) / 1.3));
  }
  const SlabFit exact = fit_slab_profile(z, rho, 0.0);
  ASSERT_TRUE(exact.converged);
  EXPECT_NEAR(exact.rho_l, 3.0, 1e-8);
  EXPECT_NEAR(exact.rho_v, 0.3, 1e-8);
  EXPECT_NEAR(exact.z0, 14.0, 1e-8);
  EXPECT_NEAR(exact.half_width, 6.0, 1e-8);
  EXPECT_NEAR(exact.width, 1.3, 1e-8);
  // A flat profile has no slab.
  EXPECT_FALSE(fit_slab_profile(z, std::vector<double>(z.size(), 3.0), 0.0).converged);
}

TEST(BinnedFields, SlabFitOfSampledParticlesHasCalibratedErrorBars) {
  // Particles drawn from a known slab profile (rho_l = 3, rho_v = 0.3, h = 5, w = 0.8 in a periodic box
  // of 20 along z, centre 10; 2112 particles, the profile's integral over an 8 x 8 cross-section),
  // 160 independent samples binned at 0.25, centred, fitted with 10 blocks. The block errors must be
  // the size of the true scatter of such fits -- a Monte Carlo of 40 realisations with numpy/scipy
  // (unweighted least squares, like fit_slab_profile) gave, scaled to 160 samples, 0.0043 (rho_l),
  // 0.0023 (rho_v), 0.0068 (h), 0.011 (w) -- within a factor 2.5 either way, and the fit must lie
  // within 4 of its errors of the truth.
  const double rho_l = 3.0, rho_v = 0.3, h = 5.0, w = 0.8, lz = 20.0;
  auto profile = [&](double z) { return 0.5 * (rho_l + rho_v) - 0.5 * (rho_l - rho_v) * std::tanh((std::fabs(z - 10.0) - h) / w); };
  FieldsSpec f = grid({1, 1, 80}, {8, 8, lz});
  f.centre_axis = 2;
  f.fit = FieldsFit::Slab;
  f.blocks = 10;
  BinnedFields fields(f, {1.0}, names(1), {8, 8, lz});
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 2112;
  ParticleData p;
  p.resize(n);
  p.n_local = n;
  for (int sample = 0; sample < 160; ++sample) {
    for (std::size_t i = 0; i < n; ++i) {
      double z;
      do z = u(rng) * lz;
      while (u(rng) * rho_l > profile(z));
      p.x[i] = 8.0 * u(rng);
      p.y[i] = 8.0 * u(rng);
      p.z[i] = z;
    }
    fields.sample(p, Comm::serial(), static_cast<std::uint64_t>(sample));
  }
  const SlabFit fit = fields.slab_fit();
  ASSERT_TRUE(fit.converged);
  EXPECT_EQ(fit.blocks_used, 10);
  std::printf("rho_l %.4f +- %.4f, rho_v %.4f +- %.4f, h %.4f +- %.4f, w %.4f +- %.4f\n", fit.rho_l, fit.rho_l_err,
              fit.rho_v, fit.rho_v_err, fit.half_width, fit.half_width_err, fit.width, fit.width_err);
  const double truth[4] = {rho_l, rho_v, h, w};
  const double got[4] = {fit.rho_l, fit.rho_v, fit.half_width, fit.width};
  const double err[4] = {fit.rho_l_err, fit.rho_v_err, fit.half_width_err, fit.width_err};
  const double expected_err[4] = {0.0043, 0.0023, 0.0068, 0.011};
  for (int q = 0; q < 4; ++q) {
    EXPECT_NEAR(got[q], truth[q], 4 * err[q]) << "parameter " << q;
    EXPECT_GT(err[q], expected_err[q] / 2.5) << "parameter " << q;
    EXPECT_LT(err[q], expected_err[q] * 2.5) << "parameter " << q;
  }
  EXPECT_NEAR(fit.z0, 10.0, 0.05);  // centred
}

// Decodes standard base64 (with padding).
std::vector<unsigned char> unbase64(const std::string& s) {
  std::vector<unsigned char> out;
  unsigned v = 0;
  int bits = 0;
  for (char c : s) {
    int d;
    if (c >= 'A' && c <= 'Z') d = c - 'A';
    else if (c >= 'a' && c <= 'z') d = c - 'a' + 26;
    else if (c >= '0' && c <= '9') d = c - '0' + 52;
    else if (c == '+') d = 62;
    else if (c == '/') d = 63;
    else continue;  // '=' padding
    v = (v << 6) | static_cast<unsigned>(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((v >> bits) & 0xff));
    }
  }
  return out;
}

TEST(BinnedFields, VtiFileHoldsTheGridAndTheArrays) {
  Box box;
  box.len = {6.0, 4.0, 8.0};
  const ParticleData p = test::random_particles(box, 500, 21, 2);
  FieldsSpec f = grid({3, 1, 4}, {6, 4, 8}, 2);
  f.name = "map";
  f.selected = {1};
  f.region_lo = {0.0, 0.0, 2.0};
  BinnedFields fields(f, {1.0, 1.0}, {"W", "F"}, {6, 4, 8});
  fields.sample(p, Comm::serial(), 40);
  const fs::path dir = fresh_dir("vti");
  fields.write(dir);
  const std::string text = test::read_file(dir / "map.vti");
  EXPECT_EQ(text.rfind("<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" "
                       "header_type=\"UInt64\">", 0), 0u);
  EXPECT_NE(text.find("<ImageData WholeExtent=\"0 3 0 1 0 4\" Origin=\"0 0 2\" Spacing=\"2 4 1.5\">"), std::string::npos);
  EXPECT_NE(text.find("<Piece Extent=\"0 3 0 1 0 4\">"), std::string::npos);
  EXPECT_NE(text.find("<CellData Scalars=\"density\" Vectors=\"velocity\">"), std::string::npos);
  // Each array: the 8-byte length, then the values, each base64-encoded on its own.
  auto array = [&](const std::string& name) {
    const std::string open = "Name=\"" + name + "\"";
    const std::size_t at = text.find(open);
    EXPECT_NE(at, std::string::npos) << name;
    const std::size_t begin = text.find('>', at) + 1, end = text.find("</DataArray>", at);
    const std::string body = text.substr(begin, end - begin);
    const std::vector<unsigned char> head = unbase64(body.substr(0, 12));
    std::uint64_t bytes = 0;
    std::memcpy(&bytes, head.data(), 8);
    const std::vector<unsigned char> data = unbase64(body.substr(12));
    EXPECT_EQ(data.size(), bytes) << name;
    std::vector<double> values(bytes / 8);
    std::memcpy(values.data(), data.data(), bytes);
    return values;
  };
  const std::vector<double> rho = array("density");
  ASSERT_EQ(rho.size(), 12u);
  const std::vector<double> expect = fields.density();
  for (std::size_t c = 0; c < 12; ++c) EXPECT_EQ(rho[c], expect[c]);
  EXPECT_EQ(array("density_W").size(), 12u);
  const std::vector<double> vel = array("velocity");
  ASSERT_EQ(vel.size(), 36u);
  const std::vector<double> vy = fields.velocity(1);
  for (std::size_t c = 0; c < 12; ++c) EXPECT_EQ(std::isnan(vel[3 * c + 1]) ? 0.0 : vel[3 * c + 1], std::isnan(vy[c]) ? 0.0 : vy[c]);
  EXPECT_EQ(array("temperature").size(), 12u);
  EXPECT_NE(text.find("Name=\"samples\" NumberOfTuples=\"1\" format=\"ascii\">1<"), std::string::npos);
  // CSV: header and one row per bin.
  const std::string csv = test::read_file(dir / "map.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "ix,iy,iz,x,y,z,density,density_W,density_F,vx,vy,vz,temperature,temperature_x,temperature_y,temperature_z");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);
  EXPECT_TRUE(fs::exists(dir / "map.json"));
  EXPECT_FALSE(fs::exists(dir / "map_profile.svg")) << "only 1-D grids get a profile plot";
  for (const char* svg : {"map_density.svg", "map_vx.svg", "map_vz.svg"}) EXPECT_TRUE(fs::exists(dir / svg)) << svg;
  EXPECT_FALSE(fs::exists(dir / "map_vy.svg")) << "only the in-plane components are drawn";
}

TEST(BinnedFields, CheckpointStateRoundTripsAndRefusesAnotherGrid) {
  Box box;
  box.len = {5.0, 5.0, 5.0};
  const ParticleData p = test::random_particles(box, 800, 8);
  const FieldsSpec f = grid({2, 3, 4}, {5, 5, 5});
  BinnedFields a(f, {1.0}, names(1), {5, 5, 5});
  a.sample(p, Comm::serial(), 10);
  a.sample(p, Comm::serial(), 20);
  ByteWriter w;
  a.save(w);
  BinnedFields b(f, {1.0}, names(1), {5, 5, 5});
  ByteReader r(w.bytes(), "test");
  b.load(r, "test");
  EXPECT_EQ(b.samples(), 2u);
  EXPECT_EQ(b.temperature(-1), a.temperature(-1));
  EXPECT_EQ(b.density(), a.density());
  FieldsSpec other = f;
  other.bins[2] = 5;
  BinnedFields c(other, {1.0}, names(1), {5, 5, 5});
  ByteReader r2(w.bytes(), "test");
  EXPECT_THROW(c.load(r2, "test"), ConfigError);
}

}  // namespace
}  // namespace mesodpd
