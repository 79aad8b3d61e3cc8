// A program built against an installed mesodpd (find_package(mesodpd), tests/install/test_install.py).
// It includes every public header, so one that needs anything outside include/mesodpd/ (a src/ header,
// a third-party one) fails to compile here. Then it runs a small fluid twice, once built in code and once
// from TOML text (which exercises the toml++ link dependency), and checks the physics.
#include <cmath>
#include <cstdio>
#include <exception>

#include "mesodpd/config.hpp"
#include "mesodpd/config_error.hpp"
#include "mesodpd/flow_numbers.hpp"
#include "mesodpd/key_table.hpp"
#include "mesodpd/simulation.hpp"
#include "mesodpd/spec.hpp"
#include "mesodpd/units.hpp"
#include "mesodpd/validate.hpp"

namespace {

int failures = 0;

void expect(bool ok, const char* what) {
  std::printf("%s: %s\n", ok ? "ok" : "FAILED", what);
  if (!ok) ++failures;
}

// Mean temperature over `rows` thermo samples, `every` steps apart, after the initial state.
double mean_temperature(mesodpd::api::Simulation& sim, int rows, int every) {
  double sum = 0.0;
  for (int i = 0; i < rows; ++i) {
    sim.step(static_cast<std::uint64_t>(every));
    sum += sim.thermo().temperature;
  }
  return sum / rows;
}

}  // namespace

int main() {
  try {
    // 5 x 5 x 5 at rho = 3: 375 particles; the standard fluid (a = 25, gamma = 4.5, dt = 0.04).
    mesodpd::SimulationSpec spec;
    spec.box = {5.0, 5.0, 5.0};
    spec.kT = 1.0;
    spec.seed = 11;
    mesodpd::SpeciesSpec water;
    water.name = "W";
    water.density = 3.0;
    spec.species.push_back(water);
    spec.pair_section.params.a = 25.0;
    spec.pair_section.params.gamma = 4.5;
    spec.dt = 0.04;
    spec.steps = 200;
    spec.progress = false;
    mesodpd::validate(spec);
    expect(spec.species[0].count == 375, "validate() turns density 3 into 375 particles");

    mesodpd::api::Simulation sim(spec);
    expect(sim.total_particles() == 375, "the simulation holds 375 particles");
    // Velocities start at kT; after 40 steps the thermostat holds the temperature there. The
    // instantaneous value of 375 particles scatters by about sqrt(2 / 1122) = 4%, less on average.
    sim.step(40);
    const double t = mean_temperature(sim, 16, 10);
    std::printf("mean temperature %.4f (kT = 1)\n", t);
    expect(std::abs(t - 1.0) < 0.08, "the temperature is within 8% of kT");
    const mesodpd::api::Thermo th = sim.thermo();
    const double p = std::sqrt(th.momentum[0] * th.momentum[0] + th.momentum[1] * th.momentum[1] +
                               th.momentum[2] * th.momentum[2]);
    expect(p < 1e-8, "total momentum stays zero (pairwise forces)");
    expect(th.pressure > 20.0 && th.pressure < 28.0, "pressure near the standard fluid's 23.6");

    const mesodpd::SimulationSpec from_toml = mesodpd::parse_config(R"(
[system]
box = [5.0, 5.0, 5.0]
kT = 1.0
seed = 11
[[species]]
name = "W"
density = 3.0
[pair]
a = 25.0
gamma = 4.5
[integrator]
dt = 0.04
[run]
steps = 200
)",
                                                                    "consumer.toml");
    expect(from_toml.species[0].count == 375, "the same fluid read from TOML text has 375 particles");
    const mesodpd::FlowNumbers numbers = mesodpd::flow_numbers(from_toml);
    expect(std::abs(numbers.density - 3.0) < 1e-12, "flow_numbers() sees density 3");
    expect(mesodpd::units::map_units(mesodpd::units::water_300k()).length > 0, "the units mapper answers");

    bool refused = false;
    try {
      mesodpd::SimulationSpec bad = spec;
      bad.dt = -1.0;
      mesodpd::validate(bad);
    } catch (const mesodpd::ConfigError&) {
      refused = true;
    }
    expect(refused, "validate() refuses a negative time step with a ConfigError");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  if (failures != 0) {
    std::printf("%d check(s) failed\n", failures);
    return 1;
  }
  std::printf("consumer: all checks passed\n");
  return 0;
}
