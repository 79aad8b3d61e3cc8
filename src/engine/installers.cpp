// The list of models: which join a simulation, in what order they are set up, and so in what order their
// stages run at each point of the step (engine/installer.hpp). An installer looks at the spec and does
// nothing when its model is not configured. A new model adds its installer file and one line here.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "engine/installer.hpp"

namespace mesodpd {

void install_edpd(Installation& in);             // pair.style = "edpd": internal temperatures
std::string edpd_numbers(const SimulationSpec&); // its estimates for `mesodpd check`
void install_tdpd(Installation& in);             // pair.style = "tdpd": solute concentrations
ModelSection tdpd_section();                     // [tdpd]
std::string tdpd_numbers(const SimulationSpec&);
void install_sources(Installation& in);          // [[source]], [[reaction]]: rates of temperatures, solutes
ModelSection source_section();                   // [[source]]
ModelSection reaction_section();                 // [[reaction]]
void install_buoyancy(Installation& in);         // [buoyancy]: Boussinesq body force (Forces)
ModelSection buoyancy_section();
std::string buoyancy_numbers(const SimulationSpec&);  // its Rayleigh number for `mesodpd check`
void install_lees_edwards(Installation& in);     // [lees_edwards]: shear images, profile, stress (EndOfStep)
ModelSection lees_edwards_section();
std::string lees_edwards_numbers(const SimulationSpec&);
std::optional<ShearImages> lees_edwards_images(const SimulationSpec&);
void install_sdpd(Installation& in);             // pair.style = "sdpd": refusals only (its law does the rest)
std::string sdpd_numbers(const SimulationSpec&); // its limits and numbers for `mesodpd check`
void install_spdpd(Installation& in);            // pair.style = "spdpd": angular velocities and their step
std::string spdpd_numbers(const SimulationSpec&); // lambda, inertias, spin relaxation rates for `mesodpd check`
void install_membrane(Installation& in);          // [[membrane]]: cells' vertices (placed) and forces (Forces)
ModelSection membrane_section();
std::vector<PlacedParticle> membrane_particles(const SimulationSpec&);
void install_bodies(Installation& in);            // [[body]]: rigid bodies of frozen particles (before the walls)
ModelSection body_section();
void install_external_fields(Installation& in);  // species body forces, reverse Poiseuille (Forces)
void install_initial_forces(Installation& in);   // the forces of the initial state (after the fields)
void install_walls(Installation& in);            // [[solid]]: reflections, adaptive force, drag
void install_thermostat(Installation& in);       // [thermostat]: pair sweep after the velocities (AfterSecondHalf)
ModelSection thermostat_section();               // its keys (integrate/thermostat_keys.hpp)
// The analyses (engine/install_analyses.cpp), each its own EndOfStep stage, in the order they ran in
// when they were one stage (Observers) so that every output stays byte for byte the same.
void install_thermo(Installation& in);            // thermo.csv rows and means (+ the columns above)
void install_surface_tension(Installation& in);   // [analysis.surface_tension] (reads the thermo rows)
void install_velocity_profile(Installation& in);  // [poiseuille] profile and viscosity
void install_fields(Installation& in);            // [analysis.fields], one stage per grid
void install_snapshot(Installation& in);          // the whole system in id order, for the stages below
void install_trajectory(Installation& in);        // [output.dump] frames
void install_rdf(Installation& in);               // [analysis.rdf]
void install_msd(Installation& in);               // [analysis.msd]
void install_transport(Installation& in);         // [analysis.transport]: D, eta and Sc by Green-Kubo
ModelSection transport_section();                 // its keys (analysis/transport.hpp)
void install_flux(Installation& in);              // [analysis.flux]: heat or solute flux, conductivity
ModelSection flux_section();                      // its keys (analysis/scalar_flux.hpp)
void install_droplet(Installation& in);           // [analysis.droplet]
void install_stress_profile(Installation& in);    // [analysis.stress_profile]
void install_progress(Installation& in);          // the progress bar
void install_checkpoints(Installation& in);       // output.checkpoint_every (EndOfStep, after the analyses)

namespace {

// The models registered at run time, each with the listed model it goes before.
std::vector<std::pair<Model, std::string>>& registered() {
  static std::vector<std::pair<Model, std::string>> list;
  return list;
}

}  // namespace

std::vector<Model> models() {
  std::vector<Model> list{{"edpd", install_edpd, {}, edpd_numbers},
                          {"tdpd", install_tdpd, tdpd_section, tdpd_numbers},
                          {"sources", install_sources, source_section},
                          // [[reaction]]'s keys; the sources' installer runs its stages too.
                          {"reactions", +[](Installation&) {}, reaction_section},
                          {"buoyancy", install_buoyancy, buoyancy_section, buoyancy_numbers},
                          {"lees_edwards", install_lees_edwards, lees_edwards_section, lees_edwards_numbers,
                           lees_edwards_images},
                          {"sdpd", install_sdpd, {}, sdpd_numbers},
                          {"spdpd", install_spdpd, {}, spdpd_numbers},
                          {"membrane", install_membrane, membrane_section, {}, {}, membrane_particles},
                          {"bodies", install_bodies, body_section},
                          {"external_fields", install_external_fields, {}},
                          {"initial_forces", install_initial_forces, {}},
                          {"walls", install_walls, {}},
                          {"thermostat", install_thermostat, thermostat_section},
                          {"thermo", install_thermo, {}},
                          {"surface_tension", install_surface_tension, {}},
                          {"velocity_profile", install_velocity_profile, {}},
                          {"fields", install_fields, {}},
                          {"snapshot", install_snapshot, {}},
                          {"trajectory", install_trajectory, {}},
                          {"rdf", install_rdf, {}},
                          {"msd", install_msd, {}},
                          {"transport", install_transport, transport_section},
                          {"flux", install_flux, flux_section},
                          {"droplet", install_droplet, {}},
                          {"stress_profile", install_stress_profile, {}},
                          {"progress", install_progress, {}},
                          {"checkpoints", install_checkpoints, {}}};
  for (const auto& [model, before] : registered()) {
    auto at = std::find_if(list.begin(), list.end(), [&](const Model& m) { return m.name == before; });
    list.insert(at, model);
  }
  return list;
}

const std::vector<std::string>& summary_order() {
  static const std::vector<std::string> order{"thermo",  "velocity_profile", "fields",         "rdf",
                                              "surface_tension", "droplet", "stress_profile", "msd",
                                              "progress"};
  return order;
}

void register_model(Model model, std::string before) {
  const std::vector<Model> list = models();
  for (const Model& m : list)
    if (m.name == model.name) throw std::invalid_argument("register_model: a model named " + model.name + " exists");
  if (std::none_of(list.begin(), list.end(), [&](const Model& m) { return m.name == before; }))
    throw std::invalid_argument("register_model: no model named " + before + " to go before");
  registered().emplace_back(std::move(model), std::move(before));
}

}  // namespace mesodpd
