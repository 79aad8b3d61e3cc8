// The keys of [bonds], declared next to the bonded forces they configure.
#pragma once
#include "mesodpd/key_table.hpp"
#include "mesodpd/spec.hpp"

namespace mesodpd {

const keys::KeyTable<SimulationSpec>& bonds_keys();

}  // namespace mesodpd
