// [analysis.flux] (analysis/scalar_flux.hpp, engine/install_flux.cpp): the pair part of the flux through
// two planes against the rates of the particles between them (an exact balance), the steady flux between
// solute walls against what the walls give and take and the diffusivity it implies, the same for eDPD's
// heat, a restart that continues the analysis byte for byte, and bad input named by its key.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analysis/kinetic_theory.hpp"
#include "analysis/scalar_flux.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "schema/declared_tables.hpp"
#include "test_support.hpp"
#include "transport_configs.hpp"

using namespace mesodpd;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(test::read_file(path)); }

}  // namespace

// The pair part of the flux is each straddling pair's exchange, so for two planes P1 < P2 the amount
// flowing in through P1 less that flowing out through P2 is the summed rate of the particles between
// them, and the rest of the periodic box gets the opposite: checked on one configuration of a tDPD fluid
// with a concentration wave and no random flux (its rates are then the Fick terms alone), with planes
// placed so that the second slab wraps around the box, on every axis.
TEST(Flux, PairFluxesThroughTwoPlanesBalanceTheRatesBetweenThem) {
  const double l = 7.0;
  const std::string text = test::periodic_fluid_config("style = \"tdpd\"\nkappa1 = 2.0\nrcc = 1.3", "conc1 = 1.0",
                                                       "\n[tdpd]\nsolutes = 1\n", l, 0.01, 5);
  const SimulationSpec spec = parse_config(text, "f.toml");
  Simulation sim(spec, RunOptions{});
  ParticleData p = sim.particles();
  for (std::size_t i = 0; i < p.n_local; ++i)
    p.conc1[i] = 1.0 + 0.4 * std::sin(2 * kPi * p.z[i] / l) + 0.3 * std::cos(2 * kPi * (p.x[i] + 2 * p.y[i]) / l) +
                 0.1 * std::sin(static_cast<double>(p.id[i]));
  const PairLawTables laws = make_pair_laws(spec);
  std::vector<std::array<double, 3>> f;
  PairSums sums;
  std::vector<double> rate;
  reference_forces(p, sim.box(), laws, NoiseSettings{1, NoiseKind::Uniform}, 1, 0.01, f, sums, nullptr, &rate);
  const std::vector<double> capacity{1.0};
  const ScalarExchangeOf exchange = [&](const ParticleData& all, const Box& box, const auto& want, const auto& visit) {
    reference_scalar_exchange(all, box, laws, 0, capacity, want, visit);
  };
  for (int axis = 0; axis < 3; ++axis) {
    const double p1 = 1.7, p2 = 4.9;
    FluxSpec fs;
    fs.field = "conc1";
    fs.axis = axis;
    fs.position = p1;
    fs.planes = 2;
    fs.spacing = p2 - p1;
    ScalarFlux flux(fs, {l, l, l}, {true, true, true}, capacity, {0}, {"A"});
    flux.sample(p, sim.box(), exchange, {});
    const FluxResult r = flux.result();
    const std::vector<double>& pos = axis == 0 ? p.x : (axis == 1 ? p.y : p.z);
    double inside = 0, outside = 0, scale = 0;
    for (std::size_t i = 0; i < p.n_local; ++i) {
      (pos[i] > p1 && pos[i] < p2 ? inside : outside) += rate[i];
      scale += std::fabs(rate[i]);
    }
    const double area = l * l;
    const double through = area * (r.planes[0].pair.value - r.planes[1].pair.value);
    std::printf("axis %c: in through P1 less out through P2 %.12g, rates inside %.12g, outside %.12g (sum |rate| %.4g)\n",
                "xyz"[axis], through, inside, outside, scale);
    EXPECT_GT(std::fabs(through), 1e-3 * scale);  // a real flux, not two zeros
    EXPECT_NEAR(through, inside, 1e-10 * scale);
    EXPECT_NEAR(-through, outside, 1e-10 * scale);
  }
}

namespace {

// The channel of transport_configs.hpp (walls at z < 1 and z > 11, 6 x 6 across) with [analysis.flux]
// planes at z = 3, 6 and 9, sampled from step `start` on.
std::string flux_channel(const std::string& fluid, const std::string& bottom, const std::string& top,
                         const std::string& pair, const std::string& field, std::uint64_t start, std::uint64_t steps) {
  std::string text = test::plate_channel_config(fluid, bottom, top, pair);
  text.replace(text.find("steps = 100000"), 14, fmt::format("steps = {}", steps));
  return text + fmt::format("\n[analysis.flux]\nfield = \"{}\"\naxis = \"z\"\nposition = 3.0\nplanes = 3\nspacing = 3.0\n"
                            "start = {}\nevery = 5\nblocks = 8\n",
                            field, start);
}

}  // namespace

// Solute walls held at C = 1 (bottom) and 0 (top), kappa = 20: in the steady state the same flux crosses
// every plane and the bottom wall gives what the top wall takes (tDPD conserves the solute, so without
// sources nothing else can), each within 4 block errors; the fluid's diffusivity J / (n |dC/dz|) lies
// between the particles' self-diffusion plus 0.4 of the mean-field exchange (2 pi n kappa r_cc^5 / 315 =
// 1.20) and the two together (docs/validation.md 8b: the exchange part is 0.4-0.8 of the mean field).
TEST(Flux, SoluteWallsSteadyFluxMatchesTheWallsAndGivesTheDiffusivity) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_flux_solute";
  fs::remove_all(dir);
  Simulation sim(parse_config(flux_channel("conc1 = 0.5", "conc1 = 1.0\nsolute_wall = 1", "conc1 = 0.0\nsolute_wall = 1",
                                           "style = \"tdpd\"\nkappa1 = 20.0\n[tdpd]\nsolutes = 1", "conc1", 1500, 7500),
                              "f.toml"),
                 RunOptions{dir, {}, {}, false, false});
  sim.run();
  const nlohmann::json j = read_json(dir / "flux.json");
  ASSERT_EQ(j["walls"].size(), 2u);
  const double bottom = j["walls"][0]["per_area"], bottom_err = j["walls"][0]["per_area_err"];
  const double top = j["walls"][1]["per_area"], top_err = j["walls"][1]["per_area_err"];
  std::printf("walls give %.5f +- %.5f (bottom) and %.5f +- %.5f (top) per unit area\n", bottom, bottom_err, top, top_err);
  EXPECT_GT(bottom, 0.02);
  EXPECT_NEAR(bottom, -top, 4 * std::hypot(bottom_err, top_err));
  const double d_kin = 2 * kPi * 3.0 * 20.0 / 315.0, d_self = 0.30;
  for (const auto& plane : j["planes"]) {
    const double flux = plane["flux"], err = plane["flux_err"], d = plane["diffusivity"];
    std::printf("plane z = %.1f: J = %.5f +- %.5f (pairs %.5f, convection %.5f), gradient %.5f, D = %.4f +- %.4f\n",
                static_cast<double>(plane["position"]), flux, err, static_cast<double>(plane["pair"]),
                static_cast<double>(plane["convection"]), static_cast<double>(plane["gradient"]), d,
                static_cast<double>(plane["diffusivity_err"]));
    EXPECT_NEAR(flux, bottom, 4 * std::hypot(err, bottom_err));
    EXPECT_GT(static_cast<double>(plane["convection"]), 0.0);  // the particles carry solute down the gradient too
    EXPECT_GT(d, d_self + 0.4 * d_kin);
    EXPECT_LT(d, d_self + d_kin);
  }
  EXPECT_FALSE(test::read_file(dir / "flux_profile.csv").empty());
  fs::remove_all(dir);
}

// eDPD between walls held at 1.1 and 0.9 (C_v = 1000, C_v kappa = 10): heat flows from the hot wall into
// the fluid and out through the cold one, and crosses the middle plane. The fluid also makes heat of its
// own (viscous heating and the time step's drift, docs/physics.md "eDPD"), so the flux grows from the hot
// wall to the cold one: the middle plane's lies between the two walls' (within 4 block errors each way).
// Its thermal diffusivity k / (n C_v) lies in the band the kinetic theory allows as for the solute above
// (self-diffusion plus 0.4 to 1 of the mean-field 2 pi n C_v kappa / 315 = 0.60).
TEST(Flux, HeatBetweenThermalWallsFlowsFromHotToColdWithTheFluidsOwnHeating) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_flux_heat";
  fs::remove_all(dir);
  Simulation sim(parse_config(flux_channel("cv = 1000.0", "cv = 1000.0\ntemperature = 1.1", "cv = 1000.0\ntemperature = 0.9",
                                           "style = \"edpd\"\nkappa = 0.01", "temp", 1500, 5500),
                              "f.toml"),
                 RunOptions{dir, {}, {}, false, false});
  sim.run();
  const nlohmann::json j = read_json(dir / "flux.json");
  const double hot = j["walls"][0]["per_area"], hot_err = j["walls"][0]["per_area_err"];
  const double cold = j["walls"][1]["per_area"], cold_err = j["walls"][1]["per_area_err"];
  const double mid = j["planes"][1]["flux"], mid_err = j["planes"][1]["flux_err"];
  std::printf("hot wall gives %.4f +- %.4f, cold wall %.4f +- %.4f per unit area; middle plane %.4f +- %.4f, "
              "thermal diffusivity %.4f +- %.4f\n",
              hot, hot_err, cold, cold_err, mid, mid_err, static_cast<double>(j["planes"][1]["diffusivity"]),
              static_cast<double>(j["planes"][1]["diffusivity_err"]));
  EXPECT_GT(hot, 4 * hot_err);
  EXPECT_LT(cold, -4 * cold_err);
  EXPECT_GT(mid, hot - 4 * std::hypot(mid_err, hot_err));
  EXPECT_LT(mid, -cold + 4 * std::hypot(mid_err, cold_err));
  const double d = j["planes"][1]["diffusivity"], d_kin = 2 * kPi * 3.0 * 10.0 / 315.0;
  EXPECT_GT(d, 0.30 + 0.4 * d_kin);
  EXPECT_LT(d, 0.30 + d_kin);
  fs::remove_all(dir);
}

// Interrupted between samples and restarted on two threads, the run writes the files of the whole run
// on one thread byte for byte.
TEST(Flux, RestartContinuesTheAnalysisByteForByte) {
  const fs::path dir = fs::temp_directory_path() / "mesodpd_test_flux_restart";
  fs::remove_all(dir);
  const std::string cfg = flux_channel("cv = 100.0", "cv = 100.0\ntemperature = 1.1", "cv = 100.0\ntemperature = 0.9",
                                       "style = \"edpd\"\nkappa = 0.1", "temp", 20, 200);
  {
    Simulation a(parse_config(cfg, "f.toml"), RunOptions{dir / "whole", {}, {}, false, false});
    a.run();
  }
  {
    Simulation b(parse_config(cfg, "f.toml"), RunOptions{dir / "split", 123, {}, false, false});
    b.run();
  }
  omp_set_num_threads(2);
  Simulation c(parse_config(cfg, "f.toml"), RunOptions{dir / "split", {}, dir / "split" / "checkpoint.mdpd", false, false});
  c.run();
  omp_set_num_threads(1);
  for (const char* file : {"flux.csv", "flux.json", "flux_profile.csv"}) {
    const std::string whole = test::read_file(dir / "whole" / file);
    EXPECT_FALSE(whole.empty()) << file;
    EXPECT_EQ(test::read_file(dir / "split" / file), whole) << file;
  }
  fs::remove_all(dir);
}

namespace {
void expect_refused(const std::string& cfg, const std::string& key) {
  try {
    parse_config(cfg, "f.toml");
    FAIL() << "accepted: " << key;
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(Flux, RefusesBadInputNamingTheKey) {
  const std::string edpd = "style = \"edpd\"\nkappa = 0.1";
  const auto with = [&](const std::string& flux) {
    std::string text = test::plate_channel_config("cv = 100.0", "cv = 100.0\ntemperature = 1.1",
                                                  "cv = 100.0\ntemperature = 0.9", edpd);
    return text + "\n[analysis.flux]\naxis = \"z\"\n" + flux;
  };
  expect_refused(with("position = 12.5\n"), "analysis.flux.position");           // outside the box
  expect_refused(with("position = 3\nplanes = 4\nspacing = 3\n"), "analysis.flux.spacing");  // plane 3 at 12
  expect_refused(with("position = 3\nfield = \"conc1\"\n"), "analysis.flux.field");  // not a tDPD run
  expect_refused(with("position = 3\nfield = \"pressure\"\n"), "analysis.flux.field");
  expect_refused(with("position = 3\nslab = 6\n"), "analysis.flux.slab");
  expect_refused(with("position = 3\nbin = 3\n"), "analysis.flux.bin");
  expect_refused(with("planes = 2\n"), "analysis.flux.position");  // required
  expect_refused(with("position = 3\nblocks = 1\n"), "analysis.flux.blocks");
}

// `mesodpd check` prints the Rayleigh number of a buoyant layer between two walls held at two
// temperatures: g beta dT L^3 / (nu D) with L the distance between the plane walls normal to g and the
// kinetic-theory nu and D (self-diffusion plus the mean-field exchange).
TEST(Flux, CheckPrintsTheRayleighNumberOfAHeatedLayer) {
  const std::string text =
      test::plate_channel_config("cv = 100.0", "cv = 100.0\ntemperature = 1.1", "cv = 100.0\ntemperature = 0.9",
                                 "style = \"edpd\"\nkappa = 0.05") +
      "\n[buoyancy]\nbeta = 1.0\nreference = 1.0\ngravity = [0.0, 0.0, -0.5]\n";
  const std::string lines = model_numbers_summary(parse_config(text, "n.toml"));
  std::printf("%s", lines.c_str());
  const double n = 3.0, nu = kinetic_viscosity(n, 4.5, 1.0, 1.0, 2.0) / n;
  const double d = kinetic_diffusivity(n, 4.5, 1.0, 1.0, 2.0) + 2 * kPi * n * 100.0 * 0.05 / 315.0;
  const double ra = 0.5 * 0.2 * 1000.0 / (nu * d);
  EXPECT_NE(lines.find(fmt::format("Rayleigh number g beta dX L^3 / (nu D) = {:.4g} (dX = 0.2 between the walls, L = 10 "
                                   "between the plane walls",
                                   ra)),
            std::string::npos);
}
