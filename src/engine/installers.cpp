// The list of installers: which models join a simulation, in what order they are set up, and so in what
// order their stages run at each point of the step (engine/installer.hpp). An installer looks at the spec and does nothing when its
// model is not configured. A new model adds its installer file and one line here.
#include <array>

#include "engine/installer.hpp"

namespace mesodpd {

void install_external_fields(Installation& in);  // species body forces, reverse Poiseuille (Forces)
void install_initial_forces(Installation& in);   // the forces of the initial state (after the fields)
void install_walls(Installation& in);            // [[solid]]: reflections, adaptive force, drag
void install_observers(Installation& in);        // thermo, analyses, trajectories, progress (EndOfStep)
void install_checkpoints(Installation& in);      // output.checkpoint_every (EndOfStep, after the observers)

std::span<const Installer> installers() {
  static constexpr std::array<Installer, 5> list{install_external_fields, install_initial_forces, install_walls,
                                                 install_observers, install_checkpoints};
  return list;
}

}  // namespace mesodpd
