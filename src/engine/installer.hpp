// How a model joins a simulation. Simulation's constructor makes the particles, the pair forces and the
// integrator, then hands one Installation to each model's installer (the list in engine/installers.cpp,
// with the models registered at run time among them), in that order. Through it a model adds its stages
// at named points of the step, its thermo columns, its checkpoint sections, its end-of-run summary and
// the objects other models may look up by type. Stages at one point run in registration order, so the
// list's order is the order of the step's stages.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "analysis/observers.hpp"
#include "analysis/thermo_output.hpp"
#include "core/box.hpp"
#include "core/stage.hpp"
#include "io/byte_buffer.hpp"
#include "mesodpd/model_section.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

class Simulation;
struct RunOptions;

// Objects shared between models, one per type (the walls, the thermo rows, the system snapshot).
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

// An end-of-run summary: files on the root (with an output directory) and text (on the root). Collective.
using Summary = std::function<std::string(const StepContext&)>;

// A model's state that travels in checkpoints, by name (io/state_checkpoint.hpp: CheckpointSection).
// save() runs on the root only, so the state must be the same on every rank or held by the root alone;
// load() runs on every rank, once every model is installed, when the checkpoint of a restart has a
// section of that name.
struct StateSection {
  std::string name;
  std::function<void(ByteWriter&)> save;
  std::function<void(ByteReader&, const std::string& context)> load;
};

struct Installation {
  Simulation& sim;            // the state so far: particles, box, halo, pair forces, bonds
  const SimulationSpec& spec;
  const RunOptions& options;
  bool restarted;             // continuing from a checkpoint
  StageList& stages;
  Components& components;
  // Printed in the order of summary_order() (engine/installers.cpp), then the rest in the order added.
  std::vector<Summary>& summaries;
  std::vector<StateSection>& sections;  // names unique (a second section of a name is refused)
  Observers& observers;                 // the index of the analyses for the API (analysis/observers.hpp)
  // Thermo columns, appended to every thermo row in this order, and the index among them of a
  // temperature that the run's means and its warning use instead of thermo's own (-1: none). The thermo
  // model takes them: a model installed after it that adds one is refused.
  std::vector<ThermoColumn> thermo_columns;
  int temperature_column = -1;
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

// A particle that a model places in a new run (a membrane's vertex): its species, its unwrapped position
// and its molecule number (0: none). engine/initial_state.cpp gives the models' particles the ids after
// the molecules' beads and before the free particles, model after model in the list's order.
struct PlacedParticle {
  std::int32_t species = 0;
  std::array<double, 3> r{0, 0, 0};
  std::int32_t mol = 0;
};

// A model as the engine lists it: its installer and, if it declares one, its own config section
// (include/mesodpd/model_section.hpp), which the schema reads, checks and documents.
struct Model {
  std::string name;
  Installer install = nullptr;
  std::function<ModelSection()> section = {};  // empty: the model reads the shared spec only
  // What `mesodpd check` prints for this model before a run (its estimates: diffusivities, Prandtl and
  // Schmidt numbers), lines ending in '\n'; empty, or returning "", when it has nothing to say.
  std::function<std::string(const SimulationSpec&)> numbers = {};
  // The box's moving periodic images (Lees-Edwards shear, core/box.hpp), for a model that imposes them:
  // read before the particles and the rank grid are made (the flow axis is then never split over
  // ranks), and advanced by Simulation to the time of each step's positions. At most one model.
  std::function<std::optional<ShearImages>(const SimulationSpec&)> shear = {};
  // The particles this model places in a new run (not with a data file), a pure function of the spec:
  // every rank computes the same list, and the installer finds their ids with first_placed_id().
  std::function<std::vector<PlacedParticle>(const SimulationSpec&)> place = {};
};

// The models, in order: those of engine/installers.cpp with any registered at run time among them.
std::vector<Model> models();
// The models whose end-of-run summaries come first, in this order (the order the analyses' summaries
// had when they were one stage; it is not the order of their stages). Every other model's follow, in
// the order of the list.
const std::vector<std::string>& summary_order();
// Adds a model at run time (tests, and programs that bring their own models), just before the listed
// model `before`: by default before the thermo rows (the first analysis), so that its thermo columns
// reach them; a model that adds Forces stages goes before "initial_forces". Call it before any spec is
// read or Simulation made. A second model of the same name is refused.
void register_model(Model model, std::string before = "thermo");

}  // namespace mesodpd
