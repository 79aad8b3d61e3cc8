// The recipes of docs/architecture.md, proved: a thermostat (rescale_thermostat.cpp) and an analysis
// (velocity_moments.*) that live outside src/ and join the engine through register_model() alone, with
// their own config sections, stages, thermo column, checkpoint part and summary.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/installer.hpp"
#include "engine/simulation.hpp"
#include "mesodpd/config.hpp"
#include "modules/velocity_moments.hpp"
#include "schema/declared_tables.hpp"
#include "test_support.hpp"

namespace mesodpd::test_models {
Model rescale_model();
}

namespace mesodpd {
namespace {

struct LateSpec {
  bool on = true;
};
const keys::KeyTable<LateSpec>& late_keys() {
  static const keys::KeyTable<LateSpec> table = [] {
    keys::KeyTable<LateSpec> t("test_late");
    t.boolean("on", &LateSpec::on, "Adds a thermo column.");
    return t;
  }();
  return table;
}

// The models join once per test program, before any spec is read. The third is misplaced on purpose:
// after the thermo rows, where its thermo column could not reach them.
const bool kRegistered = [] {
  register_model(test_models::rescale_model());
  register_model(test_models::moments_model());
  register_model({"test_late",
                  [](Installation& in) {
                    if (in.spec.model<LateSpec>("test_late"))
                      in.thermo_columns.push_back({"late", [](const StepContext&) { return 0.0; }});
                  },
                  [] { return model_section(late_keys()); }},
                 "checkpoints");
  return true;
}();

std::string fluid(double box, double gamma, const std::string& extra) {
  return "[system]\nbox = [" + std::to_string(box) + ", " + std::to_string(box) + ", " + std::to_string(box) +
         "]\nkT = 1.0\nseed = 7\n[[species]]\nname = \"A\"\ndensity = 3.0\n[pair]\na = 25.0\ngamma = " +
         std::to_string(gamma) + "\nrc = 1.0\n[integrator]\ndt = 0.04\n[run]\nsteps = 300\n[output]\nthermo_every = 50\n" +
         extra;
}

double temperature(const Simulation& sim) {
  const ParticleData& p = sim.particles();
  double twice_ke = 0;
  for (std::size_t i = 0; i < p.n_local; ++i) twice_ke += p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
  return twice_ke / (3.0 * static_cast<double>(p.n_local) - 3.0);
}

// The mean kinetic temperature over the steps after `from` of a run of `steps`.
double mean_temperature(const std::string& toml, std::uint64_t from, std::uint64_t steps) {
  Simulation sim(parse_config(toml, "recipe.toml"), RunOptions{});
  double sum = 0;
  std::uint64_t n = 0;
  while (sim.current_step() < steps) {
    sim.step();
    if (sim.current_step() > from) {
      sum += temperature(sim);
      ++n;
    }
  }
  return sum / static_cast<double>(n);
}

TEST(ModelRecipes, ARegisteredThermostatHoldsItsTarget) {
  ASSERT_TRUE(kRegistered);
  // No DPD thermostat (gamma = 0): alone, the conservative forces of the random start heat the fluid
  // (to about kT = 2.6); the rescale holds it at its own target instead, with tau = 0.4 (10 steps).
  for (const double target : {0.7, 1.5}) {
    const std::string section = "[test_rescale]\nkT = " + std::to_string(target) + "\ntau = 0.4\n";
    EXPECT_NEAR(mean_temperature(fluid(5, 0.0, section), 100, 200), target, 0.01 * target) << target;
  }
}

TEST(ModelRecipes, AModelSectionIsReadCheckedAndDocumentedLikeTheSchemasOwn) {
  ASSERT_TRUE(kRegistered);
  try {
    parse_config(fluid(6, 4.5, "[test_rescale]\nkT = 2.0\ntau = 0.01\n"), "recipe.toml");
    FAIL() << "tau < dt accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "test_rescale.tau") << e.what();
    EXPECT_NE(std::string(e.what()).find("recipe.toml:"), std::string::npos) << e.what();
  }
  try {
    parse_config(fluid(6, 4.5, "[test_rescale]\nkT = -1.0\n"), "recipe.toml");
    FAIL() << "negative kT accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "test_rescale.kT") << e.what();
  }
  try {
    parse_config(fluid(6, 4.5, "[test_rescale]\ntua = 1.0\n"), "recipe.toml");
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("tua"), std::string::npos) << e.what();
  }
  try {
    parse_config(fluid(6, 4.5, "[analysis.test_moments]\nevery = \"often\"\n"), "recipe.toml");
    FAIL() << "a string for an integer accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), "analysis.test_moments.every") << e.what();
  }
  const SimulationSpec spec = parse_config(fluid(6, 4.5, "[analysis.test_moments]\n"), "recipe.toml");
  ASSERT_NE(spec.model<test_models::MomentsSpec>("analysis.test_moments"), nullptr);
  EXPECT_EQ(spec.model<test_models::MomentsSpec>("analysis.test_moments")->every, 10u);  // the declared default
  EXPECT_EQ(spec.model<test_models::MomentsSpec>("test_rescale"), nullptr);
  bool documented = false;
  for (const DeclaredTable& t : declared_tables())
    if (t.path == "test_rescale") documented = t.rows.size() == 2 && t.rows[1].name == "tau";
  EXPECT_TRUE(documented);
}

// `mesodpd check` lists the settings from the declarations: a key a model declares appears there with no
// edit to the summary, as do the schema's own tables (with units where declared); a section the file
// leaves out does not.
TEST(ModelRecipes, ADeclaredKeyAppearsInTheCheckSummary) {
  ASSERT_TRUE(kRegistered);
  const SimulationSpec spec =
      parse_config(fluid(6, 4.5, "[test_rescale]\nkT = 1.5\ntau = 0.4\n[analysis.test_moments]\n"), "recipe.toml");
  const std::string summary = declared_values_summary(spec);
  EXPECT_NE(summary.find("\n  test_rescale: kT = 1.5, tau = 0.4\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\n  analysis.test_moments: defaults\n"), std::string::npos) << summary;
  EXPECT_EQ(summary.find("test_late"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\n  system: box = [6, 6, 6] r_c, seed = 7\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\n  species[0]: name = \"A\", density = 3, count = 648\n"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\n  run: steps = 300\n"), std::string::npos) << summary;
}

std::string summary_line(const std::string& summary) {
  std::istringstream in(summary);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("velocity moments:", 0) == 0) return line;
  return {};
}

TEST(ModelRecipes, ARegisteredAnalysisMeasuresMaxwellBoltzmannAndRestarts) {
  ASSERT_TRUE(kRegistered);
  const auto dir = std::filesystem::temp_directory_path() / "mesodpd_test_model_recipes";
  std::filesystem::remove_all(dir);
  const std::string cfg = fluid(8, 4.5, "[analysis.test_moments]\nevery = 5\n");
  RunOptions whole{dir / "whole", {}, {}, false, false};
  Simulation a(parse_config(cfg, "recipe.toml"), whole);
  const std::string full = summary_line(a.run());
  ASSERT_FALSE(full.empty());
  // <v^4>/<v^2>^2 = 5/3 for Maxwell-Boltzmann; 60 samples of 1536 particles: about 0.4% noise.
  const double ratio = std::stod(full.substr(full.find('=') + 1));
  EXPECT_NEAR(ratio, 5.0 / 3.0, 0.03) << full;
  // Its thermo column is in thermo.csv.
  const std::string thermo = test::read_file(dir / "whole" / "thermo.csv");
  EXPECT_NE(thermo.substr(0, thermo.find('\n')).find("v4_ratio"), std::string::npos) << thermo;
  // Interrupted at step 150 and restarted: its running mean came through the checkpoint.
  {
    RunOptions first{dir / "split", 150, {}, false, false};
    Simulation b(parse_config(cfg, "recipe.toml"), first);
    b.run();
  }  // a run owns its output folder until it ends
  RunOptions second{dir / "split", {}, dir / "split" / "checkpoint.mdpd", false, false};
  Simulation c(parse_config(cfg, "recipe.toml"), second);
  EXPECT_EQ(summary_line(c.run()), full);
  std::filesystem::remove_all(dir);
}

TEST(ModelRecipes, AModelAfterTheObserversCannotAddColumnsInSilence) {
  ASSERT_TRUE(kRegistered);
  try {
    Simulation sim(parse_config(fluid(5, 4.5, "[test_late]\n"), "recipe.toml"), RunOptions{});
    FAIL() << "a column after the thermo rows was accepted";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("test_late"), std::string::npos) << e.what();
  }
  // Left out, the model does nothing and the run starts.
  Simulation sim(parse_config(fluid(5, 4.5, ""), "recipe.toml"), RunOptions{});
  EXPECT_GT(sim.total_particles(), 0u);
}

}  // namespace
}  // namespace mesodpd
