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

void install_external_fields(Installation& in);  // species body forces, reverse Poiseuille (Forces)
void install_initial_forces(Installation& in);   // the forces of the initial state (after the fields)
void install_walls(Installation& in);            // [[solid]]: reflections, adaptive force, drag
void install_observers(Installation& in);        // thermo, analyses, trajectories, progress (EndOfStep)
void install_checkpoints(Installation& in);      // output.checkpoint_every (EndOfStep, after the observers)

namespace {

// The models registered at run time, each with the listed model it goes before.
std::vector<std::pair<Model, std::string>>& registered() {
  static std::vector<std::pair<Model, std::string>> list;
  return list;
}

}  // namespace

std::vector<Model> models() {
  std::vector<Model> list{{"external_fields", install_external_fields, {}},
                          {"initial_forces", install_initial_forces, {}},
                          {"walls", install_walls, {}},
                          {"observers", install_observers, {}},
                          {"checkpoints", install_checkpoints, {}}};
  for (const auto& [model, before] : registered()) {
    auto at = std::find_if(list.begin(), list.end(), [&](const Model& m) { return m.name == before; });
    list.insert(at, model);
  }
  return list;
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
