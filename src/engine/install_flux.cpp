// [analysis.flux]: the flux of eDPD's heat or a tDPD solute through planes and out of walls, with the
// conductivity and diffusivity of a steady state (analysis/scalar_flux.hpp). The pair part of the flux
// is the run's own law, evaluated noise-free by the reference loop over the snapshot (serial and in
// index order, so the result depends on neither threads nor ranks).
#include <memory>
#include <string>
#include <vector>

#include "analysis/scalar_flux.hpp"
#include "engine/analysis_installer.hpp"
#include "engine/installer.hpp"
#include "engine/reference_pair_loop.hpp"
#include "engine/simulation.hpp"
#include "engine/transported_scalars.hpp"
#include "mesodpd/model_section.hpp"

namespace mesodpd {

namespace {

void check_flux_spec(const FluxSpec& f, const SimulationSpec& spec) {
  check_scalar_field(f.field, spec, "analysis.flux.field");
  check_flux(f, spec.box);
}

// The amount of the scalar one particle of each species holds per unit of it: C_v for heat, 1 for a solute.
std::vector<double> capacities(const FluxSpec& f, const SimulationSpec& spec) {
  std::vector<double> c;
  for (const SpeciesSpec& sp : spec.species) c.push_back(f.field == "temp" ? sp.own.at("cv") : 1.0);
  return c;
}

}  // namespace

ModelSection flux_section() { return model_section(flux_keys(), check_flux_spec, "axis = \"z\"\nposition = 5.0"); }

void install_flux(Installation& in) {
  const FluxSpec* f = in.spec.model<FluxSpec>("analysis.flux");
  if (!measuring(in) || !f) return;
  check_flux_spec(*f, in.spec);  // again, for specs built in code
  require_held(in.sim.particles(), f->field, "analysis.flux.field", "\"" + f->field + "\"");
  const bool heat = f->field == "temp";
  const int channel = heat ? 0 : f->field[4] - '1';
  const std::string rate = heat ? "temp_rate" : "conc_rate" + f->field.substr(4);
  std::vector<double> capacity = capacities(*f, in.spec);
  std::vector<std::uint8_t> frozen;
  std::vector<std::string> names;
  for (const SpeciesSpec& sp : in.spec.species) {
    frozen.push_back(sp.frozen ? 1 : 0);
    names.push_back(sp.name);
  }
  const Simulation& sim = in.sim;
  ScalarExchangeOf exchange = [&sim, channel, capacity](const ParticleData& all, const Box& box, const auto& want,
                                                        const auto& visit) {
    reference_scalar_exchange(all, box, sim.pair_backend().laws(), channel, capacity, want, visit);
  };
  const Box& box = in.sim.box();
  add_analysis(in,
               std::make_unique<ScalarFluxStage>(*f, std::array<double, 3>{box.len.x, box.len.y, box.len.z},
                                                 box.periodic, capacity, std::move(frozen), std::move(names), rate,
                                                 std::move(exchange), snapshot(in), in.sim.halo().comm(), output(in)),
               "flux");
}

}  // namespace mesodpd
