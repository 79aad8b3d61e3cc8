// How a model joins a simulation. Simulation's constructor makes the particles, the pair forces and the
// integrator, then hands one Installation to each model's installer (the list in engine/installers.cpp,
// then the models registered at run time), in that order. Through it a model adds its stages at named points of the step, its thermo columns, its
// checkpoint section, its end-of-run summary and the objects other models may look up by type. Stages
// at one point run in registration order, so the list's order is the order of the step's stages.
#pragma once
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "analysis/observers.hpp"
#include "core/stage.hpp"
#include "mesodpd/model_section.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class Simulation;
struct RunOptions;

// Objects shared between models, one per type (the walls, the observers).
class Components {
 public:
  template <class T>
  T& add(std::shared_ptr<T> object) {
    T& ref = *object;
    objects_[key<T>()] = std::move(object);
    return ref;
  }
  // An object owned elsewhere (a stage the stage list owns), shared by reference.
  template <class T>
  T& share(T& object) {
    return add(std::shared_ptr<T>(&object, [](T*) {}));
  }
  template <class T>
  T* find() const {
    auto it = objects_.find(key<T>());
    return it == objects_.end() ? nullptr : static_cast<T*>(it->second.get());
  }

 private:
  // One address per type, as its key (typeid would need the type complete where find() is called).
  template <class T>
  static const void* key() {
    static const char tag = 0;
    return &tag;
  }
  std::unordered_map<const void*, std::shared_ptr<void>> objects_;
};

// An end-of-run summary: files on the root (with an output directory) and text (on the root).
using Summary = std::function<std::string(const StepContext&)>;

struct Installation {
  Simulation& sim;            // the state so far: particles, box, halo, pair forces, bonds
  const SimulationSpec& spec;
  const RunOptions& options;
  bool restarted;             // continuing from a checkpoint
  StageList& stages;
  Components& components;
  std::vector<Summary>& summaries;  // after the observers' own, in this order
  // What the observers are built with: thermo columns and checkpoint sections are added here.
  ObserverSettings observers;
  // The observers' state from the checkpoint (empty when not restarting or none was saved).
  std::vector<std::byte> observer_state;
  StepContext context() const;
  // The forces of the initial state: a new run's (neighbours, ghosts, pair and bonded forces, the Forces
  // stages installed so far), or the bonded forces a subcycled restart recomputes. Called by the
  // installer of that name, so the list says which stages they include.
  void initial_forces();
  // Rebuilds the neighbours and ghosts and recomputes the forces (pair sums too) at the current state,
  // for an installer that changed the initial velocities.
  void refresh();
};

using Installer = void (*)(Installation&);

// A model as the engine lists it: its installer and, if it declares one, its own config section
// (include/mesodpd/model_section.hpp), which the schema reads, checks and documents.
struct Model {
  std::string name;
  Installer install = nullptr;
  std::function<ModelSection()> section;  // empty: the model reads the shared spec only
};

// The models, in order: those of engine/installers.cpp with any registered at run time among them.
std::vector<Model> models();
// Adds a model at run time (tests, and programs that bring their own models), just before the listed
// model `before`: by default before the observers, so that its thermo columns and checkpoint section
// reach them; a model that adds Forces stages goes before "initial_forces". Call it before any spec is
// read or Simulation made. A second model of the same name is refused.
void register_model(Model model, std::string before = "observers");

}  // namespace mesodpd
