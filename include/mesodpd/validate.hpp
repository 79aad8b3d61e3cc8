// validate(spec): the one place where a SimulationSpec's ranges, cross-checks and derived defaults live,
// for a spec read from TOML (io/config calls it) and for one built in C++ alike.
#pragma once
#include <string>
#include <vector>

#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// Checks every value of `spec` against its allowed range and the others it depends on, and fills what
// follows from other values: species counts from densities, the resolved `pairs` table from
// `pair_section` (overrides, mixing, rd = rc), `init_velocities`, the default dump file name. Also
// refuses, before anything is built, what the engine would refuse at construction whatever the MPI
// rank count: more particles than 32-bit ids allow, a box shorter than twice the largest cutoff, a
// parallel.grid the cell grid cannot be split into. Idempotent: validating a validated spec changes
// nothing. Throws SpecError naming the key. Reading init.lammps_data itself is left to the engine
// (see check_initial_state in src/engine/initial_state.hpp); validate only checks the file exists.
void validate(SimulationSpec& spec);

// Legal but doubtful choices of a validated spec, one sentence each (the program prints them as
// "warning: ..."): a many-body DPD mixture whose B_ij or r_d differ between pairs has no potential
// (Warren 2003), so its "energy" column is only a diagnostic and its phase behaviour is not that of a
// free energy.
std::vector<std::string> spec_warnings(const SimulationSpec& spec);

}  // namespace mesodpd
