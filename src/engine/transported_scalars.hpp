// The transported scalars that [[source]], [[reaction]] and [buoyancy] name by their particle field:
// eDPD's "temp", tDPD's "conc1" .. "conc4". Checks shared by those modules.
#pragma once
#include <string>

#include "core/particle_data.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

// Refuses (a SpecError naming `key`) a field that is neither "temp" nor "conc<k>", k <= 4, or one the
// run's pair style does not transport ("temp" needs edpd, "conc<k>" tdpd).
void check_scalar_field(const std::string& field, const SimulationSpec& spec, const std::string& key);

// Refuses a field the particles do not hold (a solute beyond [tdpd] solutes), naming `key` = `value`.
void require_held(const ParticleData& p, const std::string& field, const std::string& key, const std::string& value);

}  // namespace mesodpd
