// Building the particles of a new run: lattice or random placement, or a LAMMPS data file, and
// Maxwell-Boltzmann velocities with zero total momentum (seed 000 Sect. 2.6).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "core/box.hpp"
#include "core/particle_data.hpp"
#include "core/topology.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// Which generated particles to store (by wrapped position): a rank keeps those of its own domain.
using KeepPredicate = std::function<bool(double x, double y, double z)>;

// Fills `p` and sets `box` from the spec (and the data file, if one is named). Placement and
// velocities are pure functions of (seed, particle id) and of sums over the whole system in id order,
// so they do not depend on thread or rank count. With `keep`, a generated system (no data file)
// stores only the particles it accepts, so a rank never holds the whole system; a data file is
// always read whole. With [[solid]] blocks, the generated fluid fills the whole box and the particles
// inside a solid become that solid's frozen species (body = solid index + 1, velocity = the solid's) if
// they lie within walls.depth of its surface and are left out otherwise; ids stay consecutive (seed 000
// Sect. 3.2.2). Returns the particle count of the whole system.
// With `topology`, also returns the bonds and angles (by global id) of the generated molecules or of
// the data file.
// With `placed` (x, y, z of every free particle by draw number, 3 values each: the fluid equilibrated
// before freezing, walls.equilibrate), those positions replace the drawn ones.
std::uint64_t make_initial_state(const SimulationSpec& spec, Box& box, ParticleData& p, const KeepPredicate& keep = {},
                                 Topology* topology = nullptr, const std::vector<double>* placed = nullptr);

// The pre-flight check of an initial state, shared by `mesodpd check` and the public API: with
// init.lammps_data, reads the file and checks it against the spec by the same code make_initial_state
// runs (atom types, box, masses, velocities), so a run refuses nothing here that this accepted. Returns
// the number of particles the run will start with. The spec must be validated (validate(spec)).
// Also checks the bonds of a data file (check_initial_bonds).
std::uint64_t check_initial_state(const SimulationSpec& spec);

// Throws BlowUpError (step 0, the exit code of a blow-up) naming the first FENE or worm-like-chain bond
// of `topology` whose minimum-image length in `box` is at or past its maximum (bond_type[k].rmax), its
// particle ids and its length: such a bond has an infinite force from the first step. `p` holds every
// particle (n_local); make_initial_state runs this on a data file's bonds.
void check_initial_bonds(const SimulationSpec& spec, const Box& box, const ParticleData& p, const Topology& topology);

// The id of the first particle that model `name` places (Model::place, engine/installer.hpp): after the
// molecules' beads and the particles of the models before it in the list.
std::uint32_t first_placed_id(const SimulationSpec& spec, const std::string& name);

// Draws Maxwell-Boltzmann velocities at kT, removes the centre-of-mass velocity and rescales so the
// kinetic temperature (3N - 3 degrees of freedom) is exactly kT.
void assign_maxwell_velocities(const SimulationSpec& spec, ParticleData& p);

}  // namespace mesodpd
